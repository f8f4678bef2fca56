"""Benchmark: the exact wear answer (issue targets next to each figure).

    python benchmarks/bench_exact_wear.py [--quick]

1. the exact wear map 101 f x 100 N (paper model, 0.3-1.3 Hz, the map of ``fretwear map --method
   exact --dynamics shooting``) from scratch: no table in memory or on disk (``FRETWEAR_CACHE_DIR``
   empty), kernels compiled; target <= 1 s in-process (two threads, the library's default);
2. the same map from the cached tables: in memory, and in a new process that reads them from disk
   (kernels compiled, the process's start-up not counted);
3. the same map after a change of F_ex, mu, k_w or u0 (target <= 50 ms of compute each);
4. cycles to 0.5 and 0.9 u0 at 10 N / 0.7 Hz against direct time integration (target within 2e-3),
   and the time integration with wear to 0.99 u0 (target <= 0.2 s);
5. the map's tables against tables 30 times tighter: cycles to 0.1, 0.5, 0.9 and 0.99 u0 at every
   frequency (target within 1e-3).
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time

import numpy as np

import fretwear as fw
from fretwear.wear import integrate_wear, sliding


def timed(fn, repeats: int = 1):
    """Median wall time of ``repeats`` calls of ``fn`` and its last result."""
    times, out = [], None
    for _ in range(repeats):
        start = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - start)
    return float(np.median(times)), out


def line(name: str, value: float, target: float | None, unit: str = "s") -> None:
    ratio = "" if target is None else f"   target {target:g} {unit}, ratio {value / target:.2f}"
    print(f"{name:<58s} {value:10.4g} {unit}{ratio}", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="21 frequencies instead of 101")
    args = parser.parse_args()
    nf = 21 if args.quick else 101
    print(f"load average {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs (wall times grow with it)")
    freqs = np.linspace(0.3, 1.3, nf)
    cycles = fw.wear.cycle_grid(1e5, 100)
    base = dict(method="exact", dynamics="shooting", kw=1e-11, workers=1)

    os.environ["FRETWEAR_CACHE_DIR"] = ""  # from scratch: no table on disk
    fw.wear_history(fw.paper_model(), 2 * np.pi * 0.7, dynamics="shooting", cycles=1e3)  # compile

    def scratch():
        sliding._cache.clear()  # nor in memory
        return fw.wear_map(fw.paper_model(fex=10), freqs, cycles, **{**base, "workers": 2})

    cold, _ = timed(scratch, 3)
    solves = sum(t.solves for t in sliding._cache.values())
    sliding._cache.clear()
    single, _ = timed(lambda: fw.wear_map(fw.paper_model(fex=10), freqs, cycles, **base))
    warm, wm = timed(lambda: fw.wear_map(fw.paper_model(fex=10), freqs, cycles, **base), 3)
    os.environ["FRETWEAR_CACHE_DIR"] = tempfile.mkdtemp(prefix="fretwear-bench-")
    sliding._cache.clear()
    fw.wear_map(fw.paper_model(fex=10), freqs, cycles, **base)  # the tables on disk for the new process
    script = (
        "import time, numpy as np, fretwear as fw\n"
        "fw.wear_history(fw.paper_model(), 2 * np.pi * 0.7, 'exact', dynamics='shooting', cycles=10)\n"
        f"f, N = np.linspace(0.3, 1.3, {nf}), fw.wear.cycle_grid(1e5, 100)\n"
        "t = time.perf_counter()\n"
        "fw.wear_map(fw.paper_model(fex=10), f, N, method='exact', dynamics='shooting', kw=1e-11,\n"
        "            workers=1)\n"
        "print(time.perf_counter() - t)\n"
    )
    run = subprocess.run([sys.executable, "-c", script], capture_output=True, text=True, check=True)
    fresh = float(run.stdout)
    line(f"1. exact wear map {nf} f x {len(cycles)} N from scratch ({solves} solves)", cold, 1.0)
    line("1. the same from scratch in one thread", single, None)
    line("2. the same map, tables in memory", warm, 1.0)
    line("2. the same map in a new process, tables from disk", fresh, 1.0)
    for name, model, kw in (
        ("F_ex 10 -> 12 N", fw.paper_model(fex=12), 1e-11),
        ("mu 1 -> 0.9", fw.paper_model(fex=10, mu=0.9), 1e-11),
        ("k_w 1e-11 -> 3e-11", fw.paper_model(fex=10), 3e-11),
        ("u0: F_N 10 -> 11 N", fw.paper_model(fex=10, normal_load=11), 1e-11),
    ):
        fw.wear_map(model, freqs, cycles, **{**base, "kw": kw})  # extends the tables where needed
        t, _ = timed(lambda m=model, k=kw: fw.wear_map(m, freqs, cycles, **{**base, "kw": k}), 3)
        line(f"3. redraw after {name}", t, 0.05)

    omega = 2 * np.pi * 0.7
    exact = fw.wear_history(fw.paper_model(fex=10), omega, dynamics="shooting", kw=1e-11, cycles=2e4)
    t_int, ref = timed(lambda: integrate_wear(fw.paper_model(fex=10), omega, 2e4, kw=1e-11, tol=1e-4))
    for q in (0.5, 0.9):
        err = abs(exact.cycles_to(q) / ref.cycles_to(q) - 1)
        print(f"4. cycles to {q:g} u0: exact table {exact.cycles_to(q):.2f}, time integration "
              f"{ref.cycles_to(q):.2f}: relative difference {err:.2e} (target 2e-3)")  # fmt: skip
    t_int, _ = timed(lambda: integrate_wear(fw.paper_model(fex=10), omega, 2e4, kw=1e-11), 3)
    line("4. time integration with wear to 0.99 u0 (tol 1e-3)", t_int, 0.2)

    os.environ["FRETWEAR_CACHE_DIR"] = ""
    model, fractions = fw.paper_model(fex=10), (0.1, 0.5, 0.9, 0.99)

    def cycles_to(tight: bool) -> np.ndarray:
        """Cycles to each fraction at every frequency, on the map's own tables or on tighter ones."""
        sliding._cache.clear()
        if tight:
            rho0 = float(model.slip_forces()[0]) / sliding.unit_forcing(model)
            sliding.sliding_tables(
                model, 2 * np.pi * freqs, 1e-3 * rho0, rho0, tol=sliding.TOL / 30, workers=2
            )
        else:
            fw.wear_map(model, freqs, cycles, **{**base, "workers": 2})
        hs = [fw.wear_history(model, 2 * np.pi * f, kw=1e-11, cycles=1e9) for f in freqs]
        return np.array([[h.cycles_to(q) for q in fractions] for h in hs])

    err = np.abs(cycles_to(False) / cycles_to(True) - 1)
    k, j = np.unravel_index(np.nanargmax(err), err.shape)
    print(f"5. cycles to {', '.join(map(str, fractions))} u0, {nf} f, the map's tables (tol {sliding.TOL:g}) "
          f"against tables 30x tighter: worst {err[k, j]:.2e} ({fractions[j]:g} u0, {freqs[k]:.2f} Hz), "
          f"median {np.nanmedian(err):.1e} (target 1e-3)")  # fmt: skip


if __name__ == "__main__":
    main()
