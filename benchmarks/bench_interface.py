"""Interface benchmarks (issue 11): the cylinder-on-flat test with many contact pairs.

Run ``python benchmarks/bench_interface.py`` (``--quick`` skips the wear history
and the 128-pair row). Prints warm wall times next to their targets and the
ratio (time / target, <= 1 meets it):

* one periodic solve, 32 pairs, ``Nh = 7`` (partial slip, from the quasi-static
  start): target 1 s;
* a wear history to a converged profile, 32 pairs, ``Nh = 7``: target 2 min;
* Craig-Bampton reduction of a 20 000-DOF mesh (modes by the frequency
  criterion): target 10 s;
* the polynomial slow-time method next to the adaptive stepping, 32 pairs,
  ``Nh = 7``, the same wear period (no target: the ratio polynomial / stepping
  and their difference in the final wear profile);
* the time-integration check: 8 pairs, 4 periods at 2048 steps, against the
  DLFT at ``Nh = 31``; and a 100-cycle wear run of 12 pairs at 256 steps per
  period (no target: its cost next to the slow-time stepping's);
* cost against the number of contact pairs (16, 32, 64, 128): reduction,
  condensation, one periodic solve and its Newton iterations.

The machine's load is printed first: timings on a shared machine scale with it.
"""

from __future__ import annotations

import argparse
import os

import numpy as np
from timing import best_of as timed

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.time_integration import initial_state, integrate_interface
from fretwear.interface.wear import wear_interface
from fretwear.model import craig_bampton

F_HZ, NH = 50.0, 7


def report(label: str, seconds: float, target: float) -> None:
    print(f"{label}: {seconds:.3g} s (target <= {target:g} s: ratio {seconds / target:.2f})")


def setup(nodes: int, **changes):
    model = cylinder_on_flat(contact_nodes=nodes, **changes)
    t_red, reduced = timed(lambda: craig_bampton(model, NH * F_HZ))
    cond = ContactCondensation(reduced)
    t_cond, prob = timed(lambda: InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH))
    return model, reduced, prob, t_red, t_cond


def bench_solve() -> None:
    _, _, prob, _, _ = setup(32)
    solve_interface(prob)  # warm-up: compiles or loads the kernels
    t, sol = timed(lambda: solve_interface(prob), repeat=3)
    report(f"periodic solve, 32 pairs, Nh = {NH} ({sol.iterations} Newton iterations, {sol.path})", t, 1.0)


def bench_wear() -> None:
    model, _, prob, _, _ = setup(32)
    solve_interface(prob)
    t, hist = timed(lambda: wear_interface(prob, 1e-14, 1e8, converge=1e-3))
    print(f"  {hist.message}; {len(hist.cycles)} records, {hist.solves} periodic solves")
    report("wear history to a converged profile, 32 pairs, Nh = 7 (partial slip, Q0 = 0.5 mu P)", t, 120.0)


def bench_reduction() -> None:
    model = cylinder_on_flat(contact_nodes=32, growth=1.12)
    craig_bampton(model, 1e4)  # warm-up (imports, caches)
    t, red = timed(lambda: craig_bampton(model, 5e4))
    report(
        f"Craig-Bampton, {model.n_dofs} DOFs, {len(red.reduction.boundary)} boundary DOFs, "
        f"{red.reduction.n_modes} modes below {red.reduction.cutoff:.3g} Hz",
        t,
        10.0,
    )


def bench_polynomial(cycles: float = 1e6, degree: int = 6) -> None:
    _, _, prob, _, _ = setup(32)
    wear_interface(prob, 1e-14, 1e3, method="polynomial", degree=2)  # warm-up: compiles the kernels
    t_s, ref = timed(lambda: wear_interface(prob, 1e-14, cycles, rtol=1e-2))
    t_p, poly = timed(lambda: wear_interface(prob, 1e-14, cycles, method="polynomial", degree=degree))
    err = np.abs(poly.wear[-1] - ref.wear[-1]).max() / ref.wear[-1].max()
    perr = np.abs(poly.pressure[-1] - ref.pressure[-1]).max() / ref.pressure[-1].max()
    print(f"wear to N = {cycles:g}, 32 pairs, Nh = {NH} (partial slip): stepping {t_s:.3g} s "
          f"({ref.solves} solves), polynomial degree {degree} {t_p:.3g} s ({poly.solves} solves, "
          f"{poly.info['iterations']} Newton iterations, Galerkin residual {poly.info['residual']:.1e}); "
          f"ratio polynomial / stepping {t_p / t_s:.2f}; final wear differs by {err:.1e} of its largest "
          f"value, pressure by {perr:.1e}")  # fmt: skip


def bench_time_integration() -> None:
    omega = 2 * np.pi * F_HZ
    model = cylinder_on_flat(contact_nodes=8, q_ratio=0.5)
    cond = ContactCondensation(craig_bampton(model, 1000.0))
    sol = solve_interface(InterfaceProblem(cond, omega, harmonics=31))
    start = initial_state(sol)
    integrate_interface(cond, omega, *start, periods=1, steps_per_period=64)  # warm-up
    t, run = timed(lambda: integrate_interface(cond, omega, *start, periods=4, steps_per_period=2048))
    E = run.energy_per_period[-1].sum()
    print(
        f"time integration, 8 pairs, 4 periods x 2048 steps: {t:.3g} s; friction work per period "
        f"{E:.6g} J/m, DLFT Nh = 31: {sol.friction_energy:.6g} J/m ({E / sol.friction_energy - 1:+.1e})"
    )
    model = cylinder_on_flat(contact_nodes=12, q_ratio=0.5)
    cond = ContactCondensation(craig_bampton(model, 1000.0))
    prob = InterfaceProblem(cond, omega, harmonics=7)
    t_s, hist = timed(lambda: wear_interface(prob, 3e-11, 100, rtol=1e-2))
    start = initial_state(hist.solutions[0])
    t_i, run = timed(lambda: integrate_interface(cond, omega, *start, periods=100, steps_per_period=256,
                                                 kw=3e-11, samples_per_period=4))  # fmt: skip
    err = np.abs(run.wear[-1] - hist.wear[-1]).max() / hist.wear[-1].max()
    print(
        f"wear over 100 cycles, 12 pairs: time integration (256 steps per cycle) {t_i:.3g} s, slow-time "
        f"stepping (Nh = 7) {t_s:.3g} s; final wear differs by {err:.1e} of its largest value"
    )


def bench_scaling(counts: tuple[int, ...]) -> None:
    print("\n| pairs | DOFs | reduction (s) | condensation (s) | periodic solve (s) | Newton iterations |")
    print("|---|---|---|---|---|---|")
    for n in counts:
        model, _, prob, t_red, t_cond = setup(n)
        solve_interface(prob)
        t, sol = timed(lambda prob=prob: solve_interface(prob), repeat=2)
        print(f"| {n} | {model.n_dofs} | {t_red:.2f} | {t_cond:.2f} | {t:.3f} | {sol.iterations} |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true", help="no wear history, no 128-pair row")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs")
    bench_solve()
    bench_reduction()
    bench_time_integration()
    if not args.quick:
        bench_wear()
        bench_polynomial()
    bench_scaling((16, 32, 64) if args.quick else (16, 32, 64, 128))


if __name__ == "__main__":
    main()
