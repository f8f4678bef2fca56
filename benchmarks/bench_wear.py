"""Wear benchmarks (issue 3): wear map, polynomial vs stepping, time integration vs stepping.

Run ``python benchmarks/bench_wear.py`` (add ``--quick`` for a coarser map). Prints
warm wall times (after a first run that compiles the kernels) and speed ratios
at matched accuracy, next to the targets.
"""

from __future__ import annotations

import argparse
import time
import warnings

import numpy as np

from fretwear import paper_model, wear_history, wear_map

warnings.filterwarnings("ignore", category=RuntimeWarning)
TWO_PI = 2 * np.pi


def timed(fn, repeat=1):
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t)
    return best, out


def max_error(hist, ref) -> float:
    """Largest |w - w_ref| over the reference's records, as a fraction of u0."""
    return float(np.max(np.abs(hist.at(ref.cycles)["wear"] - ref.wear)) / ref.u0[0])


def bench_map(nf: int, workers: int) -> None:
    model = paper_model(fex=10)
    freqs, cycles = np.linspace(0.3, 1.3, nf), np.geomspace(1, 1e5, 100)
    wear_map(model, freqs[:4], cycles, harmonics=21, tol=1e-2, workers=workers)  # warm-up
    for tol in (1e-2, 1e-3):
        t, wm = timed(lambda tol=tol: wear_map(model, freqs, cycles, harmonics=21, tol=tol, workers=workers))
        print(f"wear map {nf} f x 100 N, Nh = 21, tol {tol:g}, {workers} threads: {t:.2f} s "
              f"(target <= 1 s: x{t:.1f}); incomplete: {int(np.sum(~wm.converged))}")  # fmt: skip


def bench_matched(
    method: str, settings: list[dict], stepping: list[dict], reference: dict, label: str
) -> None:
    """Cheapest setting of ``method`` and of stepping within 2 % of ``reference``; their time ratio."""
    model, omega, horizon = paper_model(fex=10), TWO_PI * 0.7, 1.2e4
    ref = wear_history(model, omega, "stepping", kw=1e-11, cycles=horizon, **reference)

    def cheapest(name, options):
        for opts in options:
            t, hist = timed(
                lambda opts=opts: wear_history(model, omega, name, kw=1e-11, cycles=horizon, **opts)
            )
            err = max_error(hist, ref)
            print(f"  {name:10s} {opts}: {t * 1e3:8.1f} ms, error {err:.2%} of u0")
            if err <= 0.02:
                return t
        return np.nan

    print(label)
    t_method = cheapest(method, settings)
    t_step = cheapest("stepping", stepping)
    print(f"  -> stepping / {method} time ratio at <= 2 % error: {t_step / t_method:.2f}")
    if method == "polynomial":  # the paper's baseline: the per-period update of eq. 24
        t, hist = timed(lambda: wear_history(model, omega, "stepping", kw=1e-11, cycles=horizon,
                                             harmonics=reference["harmonics"], fixed_step=1.0))  # fmt: skip
        print(f"  per-period stepping (eq. 24, {len(hist.cycles) - 1} solves): {t * 1e3:.0f} ms, error "
              f"{max_error(hist, ref):.2%}; per-period / polynomial time: {t / t_method:.1f}")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--quick", action="store_true", help="26 frequencies instead of 101")
    args = parser.parse_args()
    nf = 26 if args.quick else 101
    bench_map(nf, workers=2)
    bench_map(nf, workers=1)
    bench_matched(
        "polynomial",
        [dict(harmonics=3, degree=d) for d in (4, 6, 8, 10, 12)],
        [dict(harmonics=3, tol=t) for t in (1e-1, 3e-2, 1e-2, 3e-3, 1e-3)],
        dict(harmonics=3, tol=1e-5),
        "polynomial vs stepping, paper model, Nh = 3, 0.7 Hz, K_w = 1e-11, 1.2e4 cycles (target >= 10x):",
    )
    try:
        bench_matched(
            "time",
            [dict(tol=t) for t in (1e-1, 3e-2, 1e-2, 3e-3)],
            [dict(dynamics="shooting", tol=t) for t in (1e-1, 3e-2, 1e-2, 3e-3, 1e-3)],
            dict(tol=1e-5, dynamics="shooting"),
            "time integration vs stepping (shooting dynamics as the reference), 0.7 Hz, 1.2e4 cycles:",
        )
    except ImportError as exc:
        print(f"time integration not available: {exc}")


if __name__ == "__main__":
    main()
