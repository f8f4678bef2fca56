"""Wall-time benchmarks of the exact periodic solver (shooting on the event-driven integrator; not a test).

Run from the repository root::

    python benchmarks/bench_shooting.py            # about half a minute on 2 cores
    python benchmarks/bench_shooting.py --quick    # fewer repeats

Warm timings (a first pass compiles and loads the kernels) of the paper model
(mu = 1, F_N = 10 N) over 201 frequencies in 0.3-1.3 Hz, for F_ex = 6, 10 and
14 N. The engine cache (per model and frequency) is cleared before every
timed call, so that each solve pays for its stick-pattern propagators as a
new frequency of a sweep does:

1. one exact periodic solve seeded by its neighbour on the sweep (the
   previous frequency's ``unknowns``): median over the 201 points;
2. one cold solve (no guess): median over 41 of the frequencies;
3. the 201-point exact FRF (:func:`fretwear.time.shooting_sweep`) and the
   DLFT sweep at ``Nh = 21`` (:func:`fretwear.sweep`) over the same
   frequencies, timed in turn (median of repeats), and their ratio.

Each figure is printed next to its target and the ratio measured / target.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from timing import fmt_time, table  # noqa: E402

from fretwear import paper_model, sweep  # noqa: E402
from fretwear.time import integrator, shooting, shooting_sweep  # noqa: E402

SEEDED_TARGET, COLD_TARGET = 1e-3, 5e-3  # s per solve
FRF_TARGET, DLFT_RATIO_TARGET = 0.3, 2.0  # s per 201-point FRF; exact FRF time / DLFT Nh = 21 sweep time
FORCES = (6.0, 10.0, 14.0)
OMEGAS = 2 * np.pi * np.linspace(0.3, 1.3, 201)


def timed(fn: Callable[[], object]) -> tuple[float, object]:
    """Wall time (s) of ``fn()`` with a fresh engine cache, and its result."""
    integrator.clear_engines()
    t0 = time.perf_counter()
    out = fn()
    return time.perf_counter() - t0, out


def single_solves(quick: bool) -> None:
    """Table 1: seeded and cold single solves."""
    print("1. One exact periodic solve (median wall time; fresh engine per call)", flush=True)
    rows = []
    repeats = 1 if quick else 3
    for fex in FORCES:
        model = paper_model(fex=fex)
        reference = shooting_sweep(model, OMEGAS, samples=8)
        seeded, cold, failures = [], [], 0
        for _ in range(repeats):
            for k in range(1, len(OMEGAS)):
                guess = reference[k - 1].unknowns
                t, sol = timed(lambda m=model, w=OMEGAS[k], y=guess: shooting(m, w, y))
                seeded.append(t)
                failures += not sol.converged
            for w in OMEGAS[::5]:
                t, sol = timed(lambda m=model, w=w: shooting(m, w))
                cold.append(t)
                failures += not sol.converged
        for label, times, target in (("seeded by its neighbour", seeded, SEEDED_TARGET),
                                     ("cold (no guess)", cold, COLD_TARGET)):  # fmt: skip
            median = statistics.median(times)
            rows.append([f"{fex:g} N", label, fmt_time(median), fmt_time(max(times)), fmt_time(target),
                         f"{median / target:.3g}", failures])  # fmt: skip
    table(["F_ex", "solve", "median", "max", "target", "measured/target", "not converged"], rows)


def frf(quick: bool) -> None:
    """Table 2: the 201-point exact FRF against its target and against the DLFT Nh = 21 sweep."""
    print("2. 201-point FRF over 0.3-1.3 Hz (median of repeats, timed in turn)", flush=True)
    rows = []
    repeats = 3 if quick else 7
    for fex in FORCES:
        model = paper_model(fex=fex)
        sweep(model, OMEGAS, 21)
        exact_times, dlft_times = [], []
        for _ in range(repeats):
            t, sols = timed(lambda m=model: shooting_sweep(m, OMEGAS))
            exact_times.append(t)
            t0 = time.perf_counter()
            sweep(model, OMEGAS, 21)
            dlft_times.append(time.perf_counter() - t0)
        exact, dlft = statistics.median(exact_times), statistics.median(dlft_times)
        converged = sum(s.converged for s in sols)
        rows.append([f"{fex:g} N", fmt_time(exact), fmt_time(FRF_TARGET), f"{exact / FRF_TARGET:.3g}",
                     fmt_time(dlft), f"{exact / dlft:.3g}", f"{DLFT_RATIO_TARGET:g}",
                     f"{exact / dlft / DLFT_RATIO_TARGET:.3g}", f"{converged}/{len(OMEGAS)}"])  # fmt: skip
    table(["F_ex", "exact FRF", "target", "measured/target", "DLFT Nh=21", "exact/DLFT", "target",
           "ratio/target", "converged"], rows)  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--quick", action="store_true", help="fewer repeats")
    quick = parser.parse_args().quick
    for fex in FORCES:  # compile and load every kernel once
        shooting_sweep(paper_model(fex=fex), OMEGAS[::20])
        sweep(paper_model(fex=fex), OMEGAS[::20], 21)
    single_solves(quick)
    frf(quick)


if __name__ == "__main__":
    main()
