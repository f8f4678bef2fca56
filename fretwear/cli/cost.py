"""``fretwear cost``: what accuracy costs, error against wall time over a ladder of settings (CSV), the
recommendation on stderr."""

from __future__ import annotations

import argparse
import sys

from ..studies.accuracy import QUANTITIES, cost_ladder
from .shared import (
    EXIT_OK,
    UsageError,
    add_model_options,
    add_out_option,
    add_settings_option,
    model_and_names,
    option,
    write_csv,
)

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv",)


#: the line of ``fretwear --help``, and the description of ``fretwear cost --help``
HELP = "what accuracy costs: error vs wall time over a ladder of settings (CSV)"
DESCRIPTION = (
    "Runs a ladder of discretisations (Nh, samples, slow-time tolerance, polynomial degree, "
    "methods) at one frequency against a converged reference (shooting; with --kw and --cycles also "
    "w(N) against stepping with shooting dynamics) and writes error vs wall time per rung."
)


def add_arguments(cost: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear cost`` on ``cost``."""
    option(cost, "--f", "excitation frequency (Hz)", required=True, metavar="HZ")
    add_model_options(cost)
    option(cost, "--kw", "Archard coefficient (1/N): adds wear rungs")
    option(cost, "--cycles", "wear horizon (cycles), with --kw")
    option(cost, "--target", "target relative error for the recommendation (-); default 1e-2", default=1e-2)
    cost.add_argument("--quick", action="store_true", help="a shorter ladder")
    add_out_option(cost)
    add_settings_option(cost)


def run(args: argparse.Namespace) -> int:
    """The cost ladder as CSV, the recommendation on stderr."""
    model, _ = model_and_names(args)
    if (args.kw is None) != (args.cycles is None):
        raise UsageError("arguments --kw and --cycles: give both (wear rungs) or neither")
    ladder = dict(harmonics=(1, 3, 7, 21, 41), sample_factors=(8, 16), tolerances=(1e-1, 1e-2),
                  degrees=(2, 4), wear_harmonics=(3, 21)) if args.quick else {}  # fmt: skip
    study = cost_ladder(model, args.f, kw=args.kw, cycles=args.cycles, **ladder)
    best = study.recommend(args.target)
    rows = []
    for r in study.rungs:
        row = {"method": r.method, "settings": r.label, "wall_time_s": r.wall_time}
        row.update({f"err_{q}": r.errors.get(q, float("nan")) for q in QUANTITIES})
        row.update(converged=r.converged, recommended=r is best)
        rows.append(row)
    write_csv(rows, args.out)
    for name, ref in study.reference.items():
        print(f"fretwear cost: reference ({name}): {ref}", file=sys.stderr)
    print(f"fretwear cost: {study.summary(args.target)}; wrote {args.out}", file=sys.stderr)
    return EXIT_OK
