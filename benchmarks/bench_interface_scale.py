"""The interface periodic solve at scale (issue 25): GMRES steps, exact steps and the dense path, same run.

Run ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_interface_scale.py``. Rows: the partial-slip cylinder
(``--pairs``, default 32 64 128, at most 128: the cylinder's mesh limit; line friction, ``Q0 / (mu P) =
0.5``, ``Nh = 7``, 50 Hz) and, above that, the 3-D sphere on the flat (``--divisions``, default 13 18 25:
278, 523 and 1 006 pairs; the 2-D friction law, ``Q* / (mu P) = 0.5`` at 1/20 of the holder's mode,
``Nh = 5``, as ``bench_sphere.py --dynamic``). Each row: one periodic solve from the quasi-static start by
:func:`fretwear.interface.periodic.solve_interface`, warm kernels, with

* ``auto``: the default structured path (``krylov_min = KRYLOV_MIN``: GMRES on the mixed coordinates
  from that many mixed unknowns, the exact step below);
* ``gmres``: GMRES at every step (``krylov_min = 0``);
* ``schur``: the exact structured step at every step (the dense LU of the mixed system: the path before
  GMRES);
* ``dense``: the dense Jacobian (``linear="dense"``, LAPACK; ``Z`` by a complex LU per harmonic,
  ``ContactCondensation(modal=False)``), cylinder rows up to ``--dense-max`` pairs only (default 128,
  about a minute there).

Printed: the setup (condensation, ``Z``'s blocks, quasi-static state), then per path the solve's wall
time (the best of ``--repeat`` solves below 500 pairs; the dense path once), its Newton iterations,
GMRES products per GMRES step and fallbacks to the exact step, the peak resident memory above the
problem's during the solve, and the largest difference of its solution from the ``schur`` one relative
to their largest entry; the mixed unknowns ``nM H`` at the solution.
Targets: cylinder at 128 pairs one solve <= 1 s and <= 10 Newton iterations; sphere at 523 pairs one
solve <= 10 s and <= 10 iterations; the same answer on every path (within the Newton tolerance, 1e-10
of the largest force).
"""

from __future__ import annotations

import argparse
import os
import threading
import time

import numpy as np

from fretwear.hbm.krylov import EXACT, FALLBACKS, ITERATIONS, KRYLOV_MIN, STEPS
from fretwear.hbm.structured import classify
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import SphereOnFlat, holder_frequency, sphere_dynamic_model
from fretwear.model import craig_bampton

F_HZ, NH, NH_SPHERE = 50.0, 7, 5
#: targets (time s, Newton iterations) of one solve: the cylinder at 128 pairs, the sphere at 523
TARGETS = {128: (1.0, 10), 523: (10.0, 10)}
#: the paths: name, linear, krylov_min
PATHS = (("auto", "structured", KRYLOV_MIN), ("gmres", "structured", 0), ("schur", "structured", 2**62))


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


def cylinder(pairs: int, dense: bool) -> tuple:
    """``(structured problem, dense problem or None, setup s)`` of the partial-slip cylinder."""
    model = craig_bampton(cylinder_on_flat(contact_nodes=pairs), NH * F_HZ)
    omega = 2 * np.pi * F_HZ
    t = time.perf_counter()
    structured = InterfaceProblem(ContactCondensation(model), omega, harmonics=NH)
    setup = time.perf_counter() - t
    if not dense:
        return structured, None, setup
    ref = InterfaceProblem(ContactCondensation(model, modal=False), omega, harmonics=NH, linear="dense")
    same = dict(harmonics=NH, xref=ref.xref, eps=ref.eps)  # the same problem to the last bit
    return InterfaceProblem(structured.condensation, omega, **same), ref, setup


def sphere(divisions: int) -> tuple:
    """``(problem, None, setup s)`` of the dynamic sphere at ``Q* / (mu P) = 0.5``, 1/20 of the holder's
    mode (``bench_sphere.py --dynamic``'s first row); setup without the mesh and its static condensation."""
    model = sphere_dynamic_model(divisions=divisions)
    t = time.perf_counter()
    cond = ContactCondensation(model)
    info = cond.full.info
    keys = ("radius", "normal_load", "young", "poisson", "mu", "holder_mass")
    p = SphereOnFlat(**{k: info[k] for k in keys})
    scale = 0.5 * info["mu"] * info["normal_load"] / info["tangential_load"]
    prob = InterfaceProblem(cond, 2 * np.pi * 0.05 * holder_frequency(p), harmonics=NH_SPHERE,
                            friction="cone", force_scale=scale)  # fmt: skip
    return prob, None, time.perf_counter() - t


def mixed_unknowns(problem: InterfaceProblem, x: np.ndarray) -> int:
    """``nM H`` of the Newton step at ``x``: the size of the mixed system."""
    A = problem.evaluate(x, jacobian=True)[1]
    return int(np.sum(classify(A, problem.per_pair) == 2)) * problem.basis.size


def best(fn, repeat: int) -> tuple:
    """:func:`measured` of ``fn`` ``repeat`` times: the shortest time (the least disturbed by the shared
    machine's other load), the last run's peak (warm: a first run may compile kernels), the last result."""
    runs = [measured(fn) for _ in range(repeat)]
    return min(r[0] for r in runs), runs[-1][1], runs[-1][2]


def run_row(label: str, structured: InterfaceProblem, dense: InterfaceProblem | None, setup: float,
            repeat: int = 1) -> dict:  # fmt: skip
    """Solve ``structured`` on every path of :data:`PATHS` (and ``dense``, once), best of ``repeat``, print
    the row, return its figures."""
    out = {}
    for name, _, kmin in PATHS:
        structured.krylov_min = kmin
        structured.krylov_stats[:] = 0
        t, mem, sol = best(lambda: solve_interface(structured), repeat)
        st = structured.krylov_stats // repeat
        out[name] = dict(time=t, its=sol.iterations, mem=mem, sol=sol, stats=st)
    if dense is not None:
        t, mem, sol = measured(lambda: solve_interface(dense))
        out["dense"] = dict(time=t, its=sol.iterations, mem=mem, sol=sol, stats=None)
    ref = out["schur"]["sol"].unknowns
    for v in out.values():
        v["diff"] = np.abs(v["sol"].unknowns - ref).max() / np.abs(ref).max()
    nm = mixed_unknowns(structured, ref)
    cols = []
    for name in [p[0] for p in PATHS] + ["dense"]:
        if name not in out:
            cols.append("-")
            continue
        v = out[name]
        st = v["stats"]
        gm = ""
        if st is not None and st[STEPS] > 0:
            gm = f", {st[ITERATIONS] / st[STEPS]:.0f} products/step, {st[FALLBACKS]} fallbacks"
        elif st is not None:
            gm = f", {st[EXACT]} exact"
        ok = "" if v["sol"].converged else " NOT CONVERGED"
        cols.append(f"{v['time']:.3g} s, {v['its']} its{gm}, {v['mem'] / 1e6:.0f} MB, {v['diff']:.0e}{ok}")
    speed = out["schur"]["time"] / out["auto"]["time"]
    print(f"| {label} | {structured.n_pairs} | {structured.size} | {nm} | {setup:.3g} | " + " | ".join(cols)
          + f" | {speed:.2f} |", flush=True)  # fmt: skip
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--pairs", type=int, nargs="*", default=[32, 64, 128], help="cylinder rows: pairs")
    parser.add_argument("--divisions", type=int, nargs="*", default=[13, 18, 25], help="sphere rows")
    parser.add_argument("--repeat", type=int, default=3, help="solves per path (best time), rows < 500 pairs")
    parser.add_argument("--dense-max", type=int, default=128, help="largest cylinder row with the dense path")
    args = parser.parse_args()
    print(f"load average {os.getloadavg()[0]:.2f} on {os.cpu_count()} CPUs, OPENBLAS_NUM_THREADS="
          f"{os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}, KRYLOV_MIN = {KRYLOV_MIN}")  # fmt: skip
    for p in cylinder(8, True)[:2]:  # warm-up: compiles or loads the kernels
        solve_interface(p)
        p.krylov_min = 0
        solve_interface(p)
    heads = [f"{name} (s, its, GMRES, peak, diff)" for name, _, _ in PATHS] + ["dense (s, its, peak, diff)"]
    print("\n| geometry | pairs | unknowns | mixed nM H | setup (s) | " + " | ".join(heads)
          + " | schur / auto |")  # fmt: skip
    print("|" + "---|" * (6 + len(heads)))
    rows = {}
    for n in args.pairs:
        rows[n] = run_row("cylinder", *cylinder(n, n <= args.dense_max), repeat=args.repeat)
    for d in args.divisions:
        prob, _, setup = sphere(d)
        rows[prob.n_pairs] = run_row(f"sphere ({d} div.)", prob, None, setup, args.repeat if d < 18 else 1)
    print(f"\nload average {os.getloadavg()[0]:.2f} at the end")
    for n, (t_target, it_target) in TARGETS.items():
        if n in rows:
            a = rows[n]["auto"]
            t, its = a["time"], a["its"]
            print(f"{n} pairs, one periodic solve (default path): {t:.3g} s (target <= {t_target:g} s: ratio "
                  f"{t / t_target:.2f}), {its} Newton iterations (target <= {it_target}: ratio "
                  f"{its / it_target:.2f}); exact steps {rows[n]['schur']['time']:.3g} s")  # fmt: skip


if __name__ == "__main__":
    main()
