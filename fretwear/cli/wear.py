"""``fretwear wear``: one wear history w(N) at one frequency, as CSV (one row per record) or its figure."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..wear import WearHistory, cycle_grid, wear_history
from .shared import (
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    FIGURE_SUFFIXES,
    add_model_options,
    add_out_option,
    add_settings_option,
    add_wear_options,
    compile_notice,
    model_and_names,
    option,
    wear_result,
    write_csv,
    write_figure,
)
from .shared import wear_kernel_needs as kernel_needs

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv", *FIGURE_SUFFIXES)


#: the line of ``fretwear --help``, and the description of ``fretwear wear --help``
HELP = "wear evolution at one frequency (CSV)"
DESCRIPTION = (
    "Fretting wear w(N) over the cycle count N at one frequency, by slow-time stepping, "
    "the polynomial slow-time DLFT or direct time integration, written as CSV."
)


def add_arguments(wear: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear wear`` on ``wear``."""
    option(wear, "--f", "excitation frequency (Hz)", required=True, metavar="HZ")
    add_model_options(wear)
    add_wear_options(wear)
    add_out_option(wear, "CSV file to write ('-': stdout), or the figure of w(N): .png, .svg, .html")
    add_settings_option(wear)


def run(args: argparse.Namespace) -> int:
    """One wear history as CSV, one row per record (or its figure)."""
    model, names = model_and_names(args)
    compile_notice(args.command, kernel_needs(args, model))

    def compute(method: str, **options) -> WearHistory:
        return wear_history(model, 2 * np.pi * args.f, method, kw=args.kw, cycles=args.cycles, **options)

    hist, _, options = wear_result(args, model, compute, lambda hist: hist.warnings)
    if args.out.lower().endswith(FIGURE_SUFFIXES):
        from ..figures import line_figure, load_backend, wear_curve

        load_backend("bokeh" if args.out.lower().endswith(".html") else "matplotlib")
        curve = wear_curve(hist, cycle_grid(args.cycles))
        fig = line_figure(
            {"wear history": curve},
            xlabel="cycles N",
            ylabel="w / u₀",
            logx=True,
            padding=0.05,
            title=f"Wear history at {args.f:.4g} Hz ({hist.label})",
        )
        write_figure(fig, args, hist.method, options, f=args.f)
        print(f"fretwear wear: {hist.label}, status {hist.status}; wrote {args.out}", file=sys.stderr)
        return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED
    rows = []
    for k, N in enumerate(hist.cycles):
        row: dict = {"cycles": float(N)}
        for j, suffix in enumerate(names.friction):
            row[f"w{suffix}"] = float(hist.wear[k, j])
            row[f"w{suffix}_over_u0"] = float(hist.wear_fraction[k, j])
            row[f"fn{suffix}"] = float(hist.normal_load[k, j])
            row[f"dw_dn{suffix}"] = float(hist.rate[k, j])
            row[f"sliding_distance{suffix}"] = float(hist.sliding_distance[k, j])
        for i, name in enumerate(names.dofs):
            row[f"{name}_h1"] = float(hist.amplitude[k, i])
            row[f"{name}_half_p2p"] = float(hist.half_peak_to_peak[k, i])
        for j, name in enumerate(names.contacts):
            row[f"{name}_half_p2p"] = float(hist.relative_half_peak_to_peak[k, j])
        rows.append(row)
    write_csv(rows, args.out)
    print(f"fretwear wear: {hist.label}, {len(rows)} records to N = {hist.cycles[-1]:g}, "
          f"status {hist.status}, "
          f"{hist.solves} solves, {hist.wall_time:.2f} s; wrote {args.out}", file=sys.stderr)  # fmt: skip
    return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED
