"""The Jenkins contact of issue 24: accuracy against the exact orbit, and the cost of a sweep.

The 1-DOF oscillator (m = 1, k = 1, c = 0.02, k_t = 1, slip force 0.1, F = 0.1):

* half peak-to-peak at W = 1.4 rad/s, Nh = 21, against the event-driven
  integration of ``tests/hbm/test_jenkins.py`` (exact return map, shooting),
  for the Jenkins contact (alternating frequency-time law) and for the older
  model with a massless slider DOF and a rigid DLFT contact; target 1e-4;
* a sweep of 101 frequencies over 0.5-2.5 rad/s at Nh = 21 with both models:
  wall time (after a warm-up) and Newton iterations.

    python benchmarks/bench_jenkins.py
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "tests" / "hbm"))
from test_jenkins import oscillator, reference_half_peak_to_peak  # noqa: E402

import fretwear as fw  # noqa: E402
from fretwear.model import jenkins_oscillator  # noqa: E402

TARGET = 1e-4  # relative error of the half peak-to-peak at W = 1.4, Nh = 21


def main() -> None:
    exact = reference_half_peak_to_peak(1.4)
    print(f"exact half peak-to-peak at W = 1.4: {exact:.12f} m")
    for name, model in (("Jenkins contact (AFT)", oscillator()), ("slider DOF (DLFT)", jenkins_oscillator())):
        sol = fw.solve_periodic(model, 1.4, 21)
        error = abs(sol.half_peak_to_peak[0] / exact - 1)
        print(f"{name:24s} error {error:.3g}  target {TARGET:g}  ratio {error / TARGET:.3g}  "
              f"({sol.iterations} Newton iterations from the stuck start, path {sol.path})")  # fmt: skip
    omegas = np.linspace(0.5, 2.5, 101)
    for name, model in (("Jenkins contact (AFT)", oscillator()), ("slider DOF (DLFT)", jenkins_oscillator())):
        fw.sweep(model, omegas[:3], 21)  # warm-up
        t = time.perf_counter()
        sweep = fw.sweep(model, omegas, 21)
        wall = time.perf_counter() - t
        its = [s.iterations for s in sweep.solutions]
        print(f"{name:24s} sweep of {len(omegas)} points: {wall:.3f} s, converged {sweep.converged.all()}, "
              f"Newton iterations mean {np.mean(its):.2f}, max {max(its)}")  # fmt: skip


if __name__ == "__main__":
    main()
