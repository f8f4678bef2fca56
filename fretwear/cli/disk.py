"""``fretwear disk``: the lumped bladed disk: modes per nodal diameter, linear mistuning, the forced response
with the shroud's friction and its wear at every blade, as CSV."""

from __future__ import annotations

import argparse
import sys

import numpy as np

from ..disk import draw_mistuning, magnification, sweep_sector
from ..model import DiskSector, bladed_disk
from .shared import EXIT_NOT_CONVERGED, EXIT_OK, add_out_option, check, option, write_csv

#: the suffixes of --out ("-": stdout)
OUT_SUFFIXES = (".csv",)

#: the line of ``fretwear --help``, and the description of ``fretwear disk --help``
HELP = "bladed disk: modes (ZZENF), linear mistuning, shroud friction FRF and wear per blade (CSV)"
DESCRIPTION = (
    "The lumped 24-sector bladed disk of Laxalde et al. (fretwear.bladed_disk). 'modes': its natural "
    "frequencies per nodal diameter, the ZZENF diagram (one row per nodal diameter, the three mode "
    "families). 'mistuning': the amplitude magnification factor (largest blade-tip amplitude over the tuned "
    "peak, in the band --fmin..--fmax) of --samples seeded random patterns of the blade stiffnesses at "
    "standard deviation --level, under an engine-order --engine-order excitation, with Whitehead's bound "
    "(1 + sqrt(N)) / 2 (linear: no contacts). 'frf': the blade-tip amplitudes over --fmin..--fmax with the "
    "shroud's Jenkins contacts (HBM + DLFT with --harmonics, an approximation): a tuned disk (--level 0) "
    "is solved on one sector (cyclic symmetry), a mistuned one (pattern --seed at --level) as a whole. "
    "'wear': the wear history of every shroud contact at --f (Archard, --kw, --cycles)."
)


def add_arguments(disk: argparse.ArgumentParser) -> None:
    """Declare the options of ``fretwear disk`` on ``disk``."""
    disk.add_argument("what", choices=("modes", "mistuning", "frf", "wear"), help="what to compute")
    option(disk, "--sectors", "number of sectors N; default 24", default=24)
    shroud = disk.add_argument_group("frf and wear: the shroud's friction")
    option(shroud, "--fex", "force amplitude on every blade tip (N); default 2", default=2.0)
    option(shroud, "--mu", "friction coefficient of the shroud contacts (-); default 0.3", default=0.3)
    option(shroud, "--harmonics", "highest harmonic Nh (-); default 7", default=7)
    option(shroud, "--n", "frequencies of the FRF; default 41", default=41)
    option(shroud, "--f", "frequency of the wear history (Hz); default 205", default=205.0)
    option(shroud, "--kw", "Archard coefficient (1/N); default 1e-8", default=1e-8)
    option(shroud, "--cycles", "wear horizon (cycles); default 1e6", default=1e6)
    group = disk.add_argument_group("mistuning (and a mistuned frf or wear with --level > 0)")
    option(group, "--level", "standard deviation of the deviations delta_i (-); default 0.01 for "
           "'mistuning', 0 (tuned) for 'frf' and 'wear'")  # fmt: skip
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
    if args.what in ("frf", "wear"):
        return _nonlinear(args)
    level = 0.01 if args.level is None else args.level
    patterns = draw_mistuning(args.sectors, level, args.draws, seed=args.seed)
    res = magnification(
        patterns, (args.fmin, args.fmax), sectors=args.sectors, engine_order=args.engine_order
    )
    rows = [
        {"draw": i, "level": level, "magnification": float(a), "f_hz": float(f), "blade": int(b)}
        for i, (a, f, b) in enumerate(zip(res.factor, res.frequency, res.blade, strict=True))
    ]
    write_csv(rows, args.out)
    print(
        f"fretwear disk mistuning: {len(rows)} patterns at level {level:g}: magnification mean "
        f"{res.factor.mean():.3f}, largest {res.factor.max():.3f} (Whitehead's bound {res.whitehead:.3f}); "
        f"tuned peak {res.tuned:.4g} m at {res.tuned_frequency:.3f} Hz; wrote {args.out}",
        file=sys.stderr,
    )
    return EXIT_OK


def _nonlinear(args: argparse.Namespace) -> int:
    """The FRF or the wear history of the shrouded disk, tuned (--level 0) or mistuned (one pattern)."""
    import fretwear as fw

    mistuned = bool(args.level)
    delta = draw_mistuning(args.sectors, args.level, 1, seed=args.seed)[0] if mistuned else None
    model = bladed_disk(
        args.sectors, engine_order=args.engine_order, fex=args.fex, mu=args.mu, mistuning=delta
    )
    n_sec, label = args.sectors, "mistuned, full disk" if mistuned else "tuned, one sector"
    if args.what == "frf":
        omegas = 2 * np.pi * np.linspace(args.fmin, args.fmax, args.n)
        run_sweep = fw.sweep if mistuned else sweep_sector
        sols = run_sweep(model, omegas, args.harmonics).solutions
        rows = []
        for s in sols:
            tips = s.amplitude[2::3] if s.converged else np.full(n_sec, np.nan)
            per_blade = {f"tip{i}_m": float(a) for i, a in enumerate(tips)}
            rows.append({"f_hz": s.frequency, "converged": s.converged, "worst_blade": int(np.argmax(tips)),
                         "worst_tip_m": float(tips.max()), **per_blade})  # fmt: skip
        write_csv(rows, args.out)
        best = max(rows, key=lambda r: r["worst_tip_m"])
        ok = all(r["converged"] for r in rows)
        failed = "" if ok else "; some points did not converge"
        print(f"fretwear disk frf ({label}, DLFT Nh = {args.harmonics}: an approximation): largest tip "
              f"amplitude {best['worst_tip_m']:.4g} m at {best['f_hz']:.3f} Hz (blade {best['worst_blade']})"
              f"{failed}; wrote {args.out}", file=sys.stderr)  # fmt: skip
        return EXIT_OK if ok else EXIT_NOT_CONVERGED
    hist = fw.wear_history(model, 2 * np.pi * args.f, "stepping", kw=args.kw, cycles=args.cycles,
                           harmonics=args.harmonics)  # fmt: skip
    rows = [{"cycles": float(N), **{f"w{i}_m": float(x) for i, x in enumerate(w)},
             "worst_tip_m": float(a[2::3].max())}
            for N, w, a in zip(hist.cycles, hist.wear, hist.amplitude, strict=True)]  # fmt: skip
    write_csv(rows, args.out)
    w = hist.wear[-1]
    print(f"fretwear disk wear ({label}; {hist.label}): status {hist.status} after {hist.cycles[-1]:.4g} "
          f"cycles; worn depth {w.min():.4g} to {w.max():.4g} m over the {n_sec} contacts (u0 "
          f"{model.friction[0].u0:.3g} m); wrote {args.out}", file=sys.stderr)  # fmt: skip
    return EXIT_OK if hist.converged else EXIT_NOT_CONVERGED
