"""``fretwear linear``: the linear frequency responses with every contact stuck or open, as CSV."""

from __future__ import annotations

import argparse
import sys
from collections.abc import Sequence

import numpy as np

from ..hbm.linear import linear_frf
from ..model import Model
from .shared import (
    EXIT_OK,
    Names,
    add_band_options,
    add_model_options,
    add_out_option,
    add_settings_option,
    model_and_names,
    write_csv,
)

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv",)


#: the line of ``fretwear --help``, and the description of ``fretwear linear --help``
HELP = "linear FRFs with every contact stuck or open (CSV)"
DESCRIPTION = "Linear frequency responses with every contact stuck (rigid) or open, written as CSV."


def add_arguments(linear: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear linear`` on ``linear``."""
    add_model_options(linear)
    add_band_options(linear)
    add_out_option(linear)
    linear.add_argument(
        "--state",
        choices=("stuck", "open", "both"),
        default="both",
        help="contact state; default both (stuck rows first)",
    )
    add_settings_option(linear)


def records(model: Model, names: Names, freqs: np.ndarray, states: Sequence[str]) -> list[dict]:
    """CSV rows of the linear FRFs at ``freqs`` (Hz), one block per contact state."""
    rows = []
    B = model.relative_map()
    for state in states:
        U = linear_frf(model, 2 * np.pi * freqs, state=state)
        dof_amp, rel_amp = np.abs(U), np.abs(U @ B.T)
        for f, u, r in zip(freqs, dof_amp, rel_amp, strict=True):
            row: dict = {"f_hz": float(f), "state": state}
            for stems, amps in ((names.dofs, u), (names.contacts, r)):
                for name, a in zip(stems, amps, strict=True):
                    row[f"{name}_h1"] = row[f"{name}_half_p2p"] = float(a)
            rows.append(row)
    return rows


def run(args: argparse.Namespace) -> int:
    """Stuck and/or open linear FRFs as CSV."""
    model, names = model_and_names(args)
    states = ("stuck", "open") if args.state == "both" else (args.state,)
    rows = records(model, names, np.linspace(args.fmin, args.fmax, args.n), states)
    write_csv(rows, args.out)
    print(f"fretwear linear: {len(rows)} rows ({', '.join(states)}); wrote {args.out}", file=sys.stderr)
    return EXIT_OK
