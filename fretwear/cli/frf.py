"""``fretwear frf``: the nonlinear frequency response (sweep, continuation or shooting), one CSV row per
solution."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..hbm.continuation import continuation, sweep
from ..model import Model
from ..time import shooting_sweep
from .shared import (
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    UsageError,
    add_band_options,
    add_method_option,
    add_model_options,
    add_out_option,
    add_settings_option,
    add_solver_options,
    compile_notice,
    model_and_names,
    record,
    write_csv,
)

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv",)


#: the line of ``fretwear --help``, and the description of ``fretwear frf --help``
HELP = "nonlinear frequency response (CSV)"
DESCRIPTION = "Nonlinear frequency response by HBM + DLFT, written as CSV (one row per frequency)."


def add_arguments(frf: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear frf`` on ``frf``."""
    add_model_options(frf)
    add_band_options(frf)
    add_out_option(frf)
    add_solver_options(frf)
    add_method_option(frf)
    frf.add_argument(
        "--continuation",
        action="store_true",
        help="follow the branch by arc-length continuation from --fmin to --fmax, through folds: "
        "rows are the branch points in arc-length order (--n is then unused)",
    )
    add_settings_option(frf)


def kernel_needs(args: argparse.Namespace, model: Model | None = None) -> tuple[str, ...]:
    """The computations of :data:`fretwear.compile.NEEDS` that the command runs."""
    if args.method == "shooting":
        return ("shooting",)
    return ("solver",) if args.continuation else ("sweep",)


def run(args: argparse.Namespace) -> int:
    """Sweep or arc-length continuation over the band, one CSV row per solution."""
    model, names = model_and_names(args)
    compile_notice(args.command, kernel_needs(args, model))
    complete, note = True, ""
    if args.method == "shooting":
        if args.continuation:
            raise UsageError("argument --continuation: not available with --method shooting")
        omegas = 2 * np.pi * np.linspace(args.fmin, args.fmax, args.n)
        solutions = shooting_sweep(model, omegas)
    elif args.continuation:
        band = 2 * np.pi * args.fmin, 2 * np.pi * args.fmax
        branch = continuation(model, *band, args.harmonics, samples=args.samples)
        solutions, complete = branch.solutions, branch.converged
        if not complete:
            note = f"; continuation stopped at {solutions[-1].frequency:g} Hz: {branch.message}"
    else:
        omegas = 2 * np.pi * np.linspace(args.fmin, args.fmax, args.n)
        solutions = sweep(model, omegas, args.harmonics, samples=args.samples).solutions
    write_csv((record(s, names, model) for s in solutions), args.out)
    failed = sum(not s.converged for s in solutions)
    worst = max(s.residual for s in solutions)
    print(
        f"fretwear frf: {len(solutions)} points, {len(solutions) - failed} converged, {failed} not converged "
        f"(largest residual {worst:.3g}){note}; wrote {args.out}",
        file=sys.stderr,
    )
    return EXIT_OK if complete and not failed else EXIT_NOT_CONVERGED
