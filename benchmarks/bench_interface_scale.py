"""The interface periodic solve at scale (issue 25): the structured path against the dense one, same run.

Run ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_interface_scale.py`` (``--pairs 32 64 128 256``
to choose the sizes; 256 pairs builds a 200 000-DOF mesh and its dense solve takes minutes). The
partial-slip cylinder (``Q0 / (mu P) = 0.5``, ``Nh = 7``, 50 Hz), one periodic solve from the
quasi-static start by :func:`fretwear.interface.periodic.solve_interface` with
``linear="dense"`` (the dense Jacobian, LAPACK) and ``linear="structured"`` (Newton steps from
``Z``'s harmonic blocks, the soft-penalty start): wall time (warm kernels, one solve each), Newton
iterations, the largest difference of the two solutions relative to their largest entry, and the
peak resident memory above the problem's during the solve. Targets at 128 pairs: one solve <= 1 s
and <= 10 Newton iterations, the same answer as the dense path.
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


def problems(pairs: int) -> tuple[InterfaceProblem, InterfaceProblem]:
    """The dense and the structured problem of the partial-slip cylinder with ``pairs`` pairs."""
    cond = ContactCondensation(craig_bampton(cylinder_on_flat(contact_nodes=pairs), NH * F_HZ))
    dense = InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH, linear="dense")
    structured = InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH, xref=dense.xref, eps=dense.eps)
    return dense, structured


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="+", default=[32, 64, 128], help="contact pairs per row")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}")  # fmt: skip
    for p in problems(8):  # warm-up: compiles or loads both kernels
        solve_interface(p)
    print("\n| pairs | unknowns | dense (s) | its | peak MB | structured (s) | its | peak MB | speed-up "
          "| max diff |")  # fmt: skip
    print("|---|---|---|---|---|---|---|---|---|---|")
    rows = {}
    for n in args.pairs:
        dense, structured = problems(n)
        td, md, sd = measured(lambda dense=dense: solve_interface(dense))
        ts, ms, ss = measured(lambda structured=structured: solve_interface(structured))
        diff = np.abs(ss.unknowns - sd.unknowns).max() / np.abs(sd.unknowns).max()
        ok = "" if sd.converged and ss.converged else " (not converged)"
        print(f"| {n} | {dense.size} | {td:.3f} | {sd.iterations} | {md / 1e6:.0f} | {ts:.3f} | "
              f"{ss.iterations} | {ms / 1e6:.0f} | {td / ts:.1f} | {diff:.1e}{ok} |", flush=True)  # fmt: skip
        rows[n] = (ts, ss.iterations, diff, sd.residual, ss.residual)
    if 128 in rows:
        ts, its, diff, rd, rs = rows[128]
        print(f"\n128 pairs, one periodic solve (structured): {ts:.3f} s (target <= {TIME_TARGET:g} s: ratio "
              f"{ts / TIME_TARGET:.2f}); {its} Newton iterations (target <= {ITER_TARGET}: ratio "
              f"{its / ITER_TARGET:.2f}); solutions differ by {diff:.1e} of the largest entry "
              f"(residuals {rd:.1e} dense, {rs:.1e} structured, tolerance 1e-10)")  # fmt: skip


if __name__ == "__main__":
    main()
