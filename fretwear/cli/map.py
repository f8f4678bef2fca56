"""``fretwear map``: the wear map W(f, N) with the response, as a long CSV table, NPZ arrays or its
figure."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..arguments import atomic
from ..studies import WearMap, wear_map
from ..studies.maps import LazyHistories
from ..wear import cycle_grid
from .shared import (
    EXIT_NOT_CONVERGED,
    EXIT_OK,
    FIGURE_SUFFIXES,
    add_band_options,
    add_export_options,
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

#: the suffixes of --out ("-": stdout for CSV)
OUT_SUFFIXES = (".csv", ".npz", *FIGURE_SUFFIXES)


#: the line of ``fretwear --help``, and the description of ``fretwear map --help``
HELP = "wear map over frequency x cycles (CSV long format, NPZ, or the figure)"
DESCRIPTION = (
    "Wear map W(f, N) (paper Fig. 7) with the response, over linspace(fmin, fmax, nf) "
    "and the cycle counts 0 then ncycles - 1 log-spaced over the four decades up to --cycles (the "
    "dashboard's grid). CSV long format (f_hz, cycles, w, ...), NumPy NPZ arrays when --out ends in "
    ".npz, or the figure when it ends in .png, .svg, .pdf or .html (with its parameters as caption; "
    "--size column, page or slide)."
)


def add_arguments(wmap: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear map`` on ``wmap``."""
    add_model_options(wmap)
    add_band_options(wmap, "nf", 41, "number of frequencies (-)")
    option(wmap, "--ncycles", "number of log-spaced cycle counts (-); default 60", default=60)
    add_wear_options(wmap)
    add_out_option(wmap, "CSV (long format), .npz, or a figure: .png, .svg, .pdf, .html", "FILE")
    add_export_options(wmap, own=("7", "4"))
    add_settings_option(wmap)


def run(args: argparse.Namespace) -> int:
    """The wear map as a long CSV table, NPZ arrays or its figure."""
    model, _ = model_and_names(args)
    compile_notice(args.command, kernel_needs(args, model))
    freqs = np.linspace(args.fmin, args.fmax, args.nf)
    cycles = cycle_grid(args.cycles, args.ncycles)

    def compute(method: str, **options) -> WearMap:
        return wear_map(model, freqs, cycles, method=method, kw=args.kw, **options)

    def notes(wmap: WearMap) -> list[str]:
        if isinstance(wmap.histories, LazyHistories):
            return []
        return [f"{h.frequency:.4g} Hz: {w}" for h in wmap.histories for w in h.warnings]

    wmap, method, options = wear_result(args, model, compute, notes)
    if args.out.lower().endswith(FIGURE_SUFFIXES):
        from ..figures import load_backend, wear_map_figure

        load_backend("bokeh" if args.out.lower().endswith(".html") else "matplotlib")
        title = f"Wear map ({wmap.label}, wear coefficient {args.kw:.3g} 1/N)"
        fig = wear_map_figure(freqs, cycles, wmap.wear_fraction[:, :, 0], title=title)
        write_figure(fig, args, method, options)
    elif args.out.lower().endswith(".npz"):
        with atomic(args.out) as temp:
            np.savez_compressed(temp, frequency_hz=wmap.frequency, cycles=wmap.cycles, wear=wmap.wear,
                                wear_fraction=wmap.wear_fraction, amplitude=wmap.amplitude,
                                half_peak_to_peak=wmap.half_peak_to_peak,
                                relative_half_peak_to_peak=wmap.relative_half_peak_to_peak)  # fmt: skip
    else:
        table = wmap.long_table()
        keys = list(table)
        write_csv(({k: float(table[k][r]) for k in keys} for r in range(len(table["f_hz"]))), args.out)
    failed = int(np.sum(~wmap.converged))
    print(f"fretwear map: {wmap.label}, {args.nf} frequencies x {args.ncycles} cycle counts, "
          f"{failed} incomplete; wrote {args.out}", file=sys.stderr)  # fmt: skip
    return EXIT_OK if not failed else EXIT_NOT_CONVERGED
