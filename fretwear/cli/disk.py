"""``fretwear disk``: the lumped bladed disk, its modes per nodal diameter and linear mistuning, as CSV."""

from __future__ import annotations

import argparse
import sys

from ..disk import draw_mistuning, magnification
from ..model import DiskSector
from .shared import EXIT_OK, add_out_option, check, option, write_csv

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv",)

#: the line of ``fretwear --help``, and the description of ``fretwear disk --help``
HELP = "bladed disk: modes per nodal diameter (ZZENF) or linear mistuning (CSV)"
DESCRIPTION = (
    "The lumped 24-sector bladed disk of Laxalde et al. (fretwear.bladed_disk). 'modes': its natural "
    "frequencies per nodal diameter, the ZZENF diagram (one row per nodal diameter, the three mode "
    "families). 'mistuning': the amplitude magnification factor (largest blade-tip amplitude over the tuned "
    "peak, in the band --fmin..--fmax) of --samples seeded random patterns of the blade stiffnesses at "
    "standard deviation --level, under an engine-order --engine-order excitation, with Whitehead's bound "
    "(1 + sqrt(N)) / 2 (linear: no contacts)."
)


def add_arguments(disk: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear disk`` on ``disk``."""
    disk.add_argument("what", choices=("modes", "mistuning"), help="what to compute")
    option(disk, "--sectors", "number of sectors N; default 24", default=24)
    group = disk.add_argument_group("mistuning")
    option(group, "--level", "standard deviation of the deviations delta_i (-); default 0.01", default=0.01)
    option(group, "--samples", "random patterns; default 100", name="draws", dest="draws", default=100)
    option(group, "--seed", "seed of the patterns; default 0", default=0)
    option(group, "--engine-order", "engine order EO; default 3", default=3)
    option(group, "--fmin", "band's lowest frequency (Hz); default 165", default=165.0)
    option(group, "--fmax", "band's highest frequency (Hz); default 200 (the blade family)", default=200.0)
    add_out_option(disk)


def check_args(args: argparse.Namespace) -> None:
    """Cross-option checks, before any work."""
    check(args, OUT_SUFFIXES, strict=True)


def run(args: argparse.Namespace) -> int:
    """The ZZENF diagram or the magnification factors, as CSV."""
    if args.what == "modes":
        zz = DiskSector(args.sectors).zzenf()
        rows = [{"nodal_diameter": nd, **{f"f{j + 1}_hz": float(f) for j, f in enumerate(fs)}}
                for nd, fs in enumerate(zz)]  # fmt: skip
        write_csv(rows, args.out)
        print(f"fretwear disk modes: {len(rows)} nodal diameters; wrote {args.out}", file=sys.stderr)
        return EXIT_OK
    patterns = draw_mistuning(args.sectors, args.level, args.draws, seed=args.seed)
    res = magnification(
        patterns, (args.fmin, args.fmax), sectors=args.sectors, engine_order=args.engine_order
    )
    rows = [
        {"draw": i, "level": args.level, "magnification": float(a), "f_hz": float(f), "blade": int(b)}
        for i, (a, f, b) in enumerate(zip(res.factor, res.frequency, res.blade, strict=True))
    ]
    write_csv(rows, args.out)
    print(
        f"fretwear disk mistuning: {len(rows)} patterns at level {args.level:g}: magnification mean "
        f"{res.factor.mean():.3f}, largest {res.factor.max():.3f} (Whitehead's bound {res.whitehead:.3f}); "
        f"tuned peak {res.tuned:.4g} m at {res.tuned_frequency:.3f} Hz; wrote {args.out}",
        file=sys.stderr,
    )
    return EXIT_OK
