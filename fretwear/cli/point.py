"""``fretwear point``: the periodic response at one frequency, JSON on stdout."""

from __future__ import annotations

import argparse
import json
import sys

import numpy as np

from ..hbm.periodic import solve_periodic
from ..model import Model
from ..time import shooting
from .shared import (
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    add_method_option,
    add_model_options,
    add_settings_option,
    add_solver_options,
    compile_notice,
    model_and_names,
    option,
    record,
)

#: the line of ``fretwear --help``, and the description of ``fretwear point --help``
HELP = "response at one frequency (JSON on stdout)"
DESCRIPTION = "Periodic response at one frequency, printed as JSON."


def add_arguments(point: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear point`` on ``point``."""
    option(point, "--f", "excitation frequency (Hz)", required=True, metavar="HZ")
    add_model_options(point)
    add_solver_options(point)
    add_method_option(point)
    add_settings_option(point)


def kernel_needs(args: argparse.Namespace, model: Model | None = None) -> tuple[str, ...]:
    """The computations of :data:`fretwear.compile.NEEDS` that the command runs."""
    return ("shooting",) if args.method == "shooting" else ("sweep",)


def run(args: argparse.Namespace) -> int:
    """One periodic solve, JSON on stdout."""
    model, names = model_and_names(args)
    compile_notice(args.command, kernel_needs(args, model))
    omega = 2 * np.pi * args.f
    if args.method == "shooting":
        sol = shooting(model, omega)
        row = record(sol, names, model)
        row.update(omega_rad_s=float(omega), input_work=float(sol.input_work),
                   viscous_dissipation=float(sol.viscous_dissipation),
                   floquet_max=float(np.abs(sol.floquet_multipliers).max()),
                   stable=bool(sol.stable))  # fmt: skip
    else:
        sol = solve_periodic(model, omega, args.harmonics, samples=args.samples)
        row = record(sol, names, model)
        row.update(
            omega_rad_s=float(sol.omega),
            harmonics=int(sol.harmonics),
            samples=int(sol.samples),
            half_wave=bool(sol.half_wave),
            input_work=float(sol.input_work),
            viscous_dissipation=float(sol.viscous_dissipation),
            contact_work=float(sol.contact_work),
        )
    json.dump(row, sys.stdout, indent=2)
    sys.stdout.write("\n")
    status = "converged" if sol.converged else f"NOT converged ({row['message']})"
    print(f"fretwear point: {status}, residual {sol.residual:.3g}, path {row['path']}", file=sys.stderr)
    return EXIT_OK if sol.converged else EXIT_NOT_CONVERGED
