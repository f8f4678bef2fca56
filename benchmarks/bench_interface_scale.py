"""The interface periodic solve at scale (issue 25): the structured path against the dense one, same run.

Run ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_interface_scale.py`` (``--pairs 32 64 128`` to
choose the sizes, at most 128: the cylinder's mesh limit; the 3-D sphere's 523 pairs are
``bench_sphere.py --dynamic``'s). The
partial-slip cylinder (``Q0 / (mu P) = 0.5``, ``Nh = 7``, 50 Hz), one periodic solve from the
quasi-static start by :func:`fretwear.interface.periodic.solve_interface` with
``linear="dense"`` (the dense Jacobian, LAPACK; ``Z`` by a complex LU per harmonic,
``ContactCondensation(modal=False)``) and ``linear="structured"`` (Newton steps from ``Z``'s harmonic
blocks, the soft-penalty start; ``Z`` by the glued structure's modes): the setup (condensation, ``Z``'s
blocks and the quasi-static start) and the solve's wall time (warm kernels, one solve each), Newton
iterations, the largest difference of the two solutions relative to their largest entry, and the
peak resident memory above the problem's during the solve. Targets at 128 pairs: one solve <= 1 s
and <= 10 Newton iterations, the same answer as the dense path. Above ``--dense-max`` pairs (default
128: a minute a solve there on a loaded machine) the dense path is left out and only the structured one
is timed.
"""

from __future__ import annotations

import argparse
import os
import threading
import time

import numpy as np

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.model import craig_bampton

F_HZ, NH = 50.0, 7
TIME_TARGET, ITER_TARGET = 1.0, 10


def _rss() -> int:
    """Resident memory of this process (bytes)."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def measured(fn):
    """``(seconds, peak RSS above the start in bytes, result)`` of ``fn()``, RSS sampled every 2 ms."""
    base, peak, done = _rss(), [0], threading.Event()

    def poll() -> None:
        while not done.is_set():
            peak[0] = max(peak[0], _rss())
            time.sleep(0.002)

    thread = threading.Thread(target=poll, daemon=True)
    thread.start()
    t = time.perf_counter()
    out = fn()
    t = time.perf_counter() - t
    done.set()
    thread.join()
    return t, max(peak[0], _rss()) - base, out


def problems(pairs: int, dense: bool = True) -> tuple:
    """``(dense, structured, setup of dense (s), of structured (s))``: the problems of the partial-slip
    cylinder with ``pairs`` pairs (the dense one None without ``dense``); setup: condensation, ``Z``'s
    blocks, the quasi-static state."""
    model = craig_bampton(cylinder_on_flat(contact_nodes=pairs), NH * F_HZ)
    omega = 2 * np.pi * F_HZ
    t = time.perf_counter()
    structured = InterfaceProblem(ContactCondensation(model), omega, harmonics=NH)
    t_struct = time.perf_counter() - t
    if not dense:
        return None, structured, np.nan, t_struct
    t = time.perf_counter()
    ref = InterfaceProblem(ContactCondensation(model, modal=False), omega, harmonics=NH, linear="dense")
    t_dense = time.perf_counter() - t
    same = dict(harmonics=NH, xref=ref.xref, eps=ref.eps)  # the same problem to the last bit
    return ref, InterfaceProblem(structured.condensation, omega, **same), t_dense, t_struct


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[32, 64, 128], help="contact pairs per row")
    parser.add_argument("--dense-max", type=int, default=128, help="largest row with the dense path")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}")  # fmt: skip
    for p in problems(8)[:2]:  # warm-up: compiles or loads both kernels
        solve_interface(p)
    print("\n| pairs | unknowns | dense setup (s) | dense (s) | its | peak MB | structured setup (s) | "
          "structured (s) | its | peak MB | speed-up (solve) | max diff |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|---|---|")
    rows = {}
    for n in args.pairs:
        with_dense = n <= args.dense_max
        dense, structured, t_setup_d, t_setup_s = problems(n, with_dense)
        ts, ms, ss = measured(lambda structured=structured: solve_interface(structured))
        if with_dense:
            td, md, sd = measured(lambda dense=dense: solve_interface(dense))
            diff = np.abs(ss.unknowns - sd.unknowns).max() / np.abs(sd.unknowns).max()
            ok = "" if sd.converged and ss.converged else " (not converged)"
            d_cols = f"{t_setup_d:.3f} | {td:.3f} | {sd.iterations} | {md / 1e6:.0f}"
            tail = f"{td / ts:.1f} | {diff:.1e}{ok}"
            rows[n] = (ts, ss.iterations, diff, sd.residual, ss.residual)
        else:
            d_cols, tail = "- | - | - | -", f"- | - {'' if ss.converged else '(not converged)'}"
        print(f"| {n} | {structured.size} | {d_cols} | {t_setup_s:.3f} | {ts:.3f} | {ss.iterations} | "
              f"{ms / 1e6:.0f} | {tail} |", flush=True)  # fmt: skip
    if 128 in rows:
        ts, its, diff, rd, rs = rows[128]
        print(f"\n128 pairs, one periodic solve (structured): {ts:.3f} s (target <= {TIME_TARGET:g} s: ratio "
              f"{ts / TIME_TARGET:.2f}); {its} Newton iterations (target <= {ITER_TARGET}: ratio "
              f"{its / ITER_TARGET:.2f}); solutions differ by {diff:.1e} of the largest entry "
              f"(residuals {rd:.1e} dense, {rs:.1e} structured, tolerance 1e-10)")  # fmt: skip


if __name__ == "__main__":
    main()
