"""``fretwear study``: the parameter study of a TOML spec on Dask, results in Zarr. A thin adapter: the
options and the run are those of :mod:`fretwear.studies.study` (``add_arguments``, ``run``), which checks
the spec and the outputs itself."""

from __future__ import annotations

import argparse

from ..studies import study
from ..studies.study import add_arguments

__all__ = ["HELP", "DESCRIPTION", "add_arguments", "check_args", "run"]

#: the line of ``fretwear --help``, and the description of ``fretwear study --help``
HELP = "parameter study on Dask, results in Zarr"
DESCRIPTION = (
    "Runs the parameter study of a TOML spec on a Dask cluster (local by default) and "
    "writes an xarray Dataset to a Zarr store, chunk by chunk; rerun the same command to finish "
    "an interrupted study. Read the result with xarray.open_zarr(RESULT)."
)


def check_args(args: argparse.Namespace) -> None:
    """Nothing before the run: it checks the spec and ``--out`` / ``--figure`` itself."""


def run(args: argparse.Namespace) -> int:
    """Run the study; its exit status."""
    return study.run(args)
