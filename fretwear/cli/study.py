"""``fretwear study``: the parameter study of a TOML spec on Dask, results in Zarr. A thin adapter: the
command's options and run are :func:`fretwear.studies.study.add_arguments` and
:func:`~fretwear.studies.study.run` (which check the spec and the outputs themselves)."""

from __future__ import annotations

import argparse

from ..studies import study


def add_parser(commands: argparse._SubParsersAction) -> None:
    """Declare ``study`` and its options among the ``commands``."""
    study.add_arguments(
        commands.add_parser(
            "study",
            help="parameter study on Dask, results in Zarr",
            description="Runs the parameter study of a TOML spec on a Dask cluster (local by default) and "
            "writes an xarray Dataset to a Zarr store, chunk by chunk; rerun the same command to finish "
            "an interrupted study. Read the result with xarray.open_zarr(RESULT).",
        )
    )


def check_args(args: argparse.Namespace) -> None:
    """Nothing before the run: it checks the spec and ``--out`` / ``--figure`` itself."""


def run(args: argparse.Namespace) -> int:
    """Run the study; its exit status."""
    return study.run(args)
