"""Sphere-on-flat benchmark (issue 25, static part): cost and anchors of the 3-D half model.

Run ``OPENBLAS_NUM_THREADS=1 python benchmarks/bench_sphere.py`` (``--divisions 6 12 18 24`` for
the scaling rows; default 6 12 18). For each mesh it prints the pairs and DOFs, the wall time of the
build (mesh, assembly and the static condensation on the contact by one sparse LU), of the
condensation on the contact coordinates (``ContactCondensation.static``) and of the quasi-static
solves (Hertz, then Mindlin at ``Q / (mu P)`` = 0.3, 0.5, 0.8), the process's peak memory, and the
anchors' errors against their targets (3 % on ``a`` and ``p0``, 5 % on ``c``; ratio = error /
target, <= 1 meets it), then the friction work per cycle of tangential load ``+-Q*`` on the finest
mesh against Mindlin-Deresiewicz (5 %).

Then the dynamic sphere (``--dynamic``, default the finest mesh; :func:`sphere_dynamic_model`, the
2-D friction law): one periodic solve (``Nh`` = 5) at ``Q*/(mu P)`` = 0.5 and 1/20 of the holder's
mode (quasi-static: its dissipation per cycle against Mindlin-Deresiewicz, 5 %), and at 0.3 and 0.9
of it (near the mode); time against the issue's 10 s target, Newton iterations against 10, peak
memory; the dense path in the same run on the meshes of ``--dense`` (default the coarsest).

With ``--history``: the wear history of the dynamic sphere (finest mesh, ``Q*/(mu P)`` = 0.5, 1/20 of
the mode, ``Nh`` = 5, ``k_w`` = 1e-14 1/Pa, stepping) to a converged scar (``converge=1e-3``): wall
time against the issue's 5 min target, periodic solves, peak memory.

The machine's load and memory are printed first: timings on a shared machine scale with the load.
"""

from __future__ import annotations

import argparse
import os
import resource

import numpy as np
from timing import best_of as timed
from timing import table

from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import (
    SphereOnFlat,
    sphere_cyclic_dissipation,
    sphere_dynamic_model,
    sphere_periodic,
    sphere_static_benchmark,
    sphere_static_model,
)


def peak_memory_gb() -> float:
    """Peak resident memory of this process so far (GB)."""
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024**2


def total_memory_gb() -> float:
    with open("/proc/meminfo") as fh:
        return int(fh.readline().split()[1]) / 1024**2


def row(divisions: int) -> tuple[list, dict, ContactCondensation]:
    t_build, model = timed(lambda: sphere_static_model(divisions=divisions))
    t_cond, cond = timed(lambda: ContactCondensation(model))
    t_z, _ = timed(lambda: cond.static)
    solves, errors = [], {}
    for q in (0.0, 0.3, 0.5, 0.8):
        t, d = timed(lambda q=q: sphere_static_benchmark(q, condensation=cond))
        solves.append(t)
        if q == 0.0:
            errors.update(a=abs(d["error_contact_radius"]), p0=abs(d["error_peak_pressure"]))
        else:
            errors[f"c({q})"] = abs(d["error_stick_radius"])
    dofs = int(3 * model.info["nodes"])
    return [
        divisions, model.pairs.count, dofs, f"{t_build:.3g}", f"{t_cond + t_z:.3g}",
        f"{max(solves):.3g}", f"{peak_memory_gb():.2f}",
    ], errors, cond  # fmt: skip


def dynamic_rows(divisions: int, dense: bool) -> list[list]:
    """Periodic solves of the dynamic sphere (module text), structured and, with ``dense``, dense."""
    t_build, model = timed(lambda: sphere_dynamic_model(divisions=divisions))
    t_cond, cond = timed(lambda: ContactCondensation(model))
    print(f"dynamic, divisions {divisions}: {model.pairs.count} pairs, build {t_build:.3g} s, "
          f"condensation {t_cond:.3g} s", flush=True)  # fmt: skip
    rows = []
    for q, fr in ((0.5, 0.05), (0.3, 0.9)):
        for linear in ("structured", "dense") if dense else ("structured",):
            t, d = timed(lambda q=q, fr=fr, linear=linear: sphere_periodic(q, fr, 5, condensation=cond,
                                                                           linear=linear))  # fmt: skip
            e = d.get("error_dissipation")
            rows.append([
                divisions, d["pairs"], d["unknowns"], q, f"{d['frequency']:.4g}", fr, linear,
                f"{t:.3g} ({t / 10:.2f})", f"{d['iterations']} ({d['iterations'] / 10:.1f})",
                f"{d['dissipation']:.4g}", "-" if fr > 0.1 else f"{abs(e):.2e} ({abs(e) / 0.05:.2f})",
                f"{d['holder_amplitude']:.3g}", f"{peak_memory_gb():.2f}", d["converged"],
            ])  # fmt: skip
            print(rows[-1], flush=True)
    return rows


def history(divisions: int) -> None:
    """The wear history to a converged scar (module text): time (ratio to 5 min), solves, memory."""
    from fretwear.interface.periodic import InterfaceProblem
    from fretwear.interface.sphere import holder_frequency
    from fretwear.interface.wear import wear_interface

    t_build, cond = timed(lambda: ContactCondensation(sphere_dynamic_model(divisions=divisions)))
    info = cond.full.info
    scale = 0.5 * info["mu"] * info["normal_load"] / info["tangential_load"]

    def run():
        omega = 2 * np.pi * 0.05 * holder_frequency()
        problem = InterfaceProblem(cond, omega, harmonics=5, force_scale=scale)
        return wear_interface(problem, 1e-14, 1e8, converge=1e-3)

    t, h = timed(run)
    print(f"wear history, {cond.n_pairs} pairs (build {t_build:.3g} s): {t:.4g} s (target 300 s: ratio "
          f"{t / 300:.2f}), {h.solves} periodic solves, {len(h.cycles)} records to N = {h.cycles[-1]:.3g}, "
          f"converged {h.converged} ({h.message}), peak memory {peak_memory_gb():.2f} GB")  # fmt: skip


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--divisions", type=int, nargs="+", default=[6, 12, 18])
    parser.add_argument("--dynamic", type=int, nargs="*", default=None,
                        help="meshes (divisions) of the periodic solves; default the finest")  # fmt: skip
    parser.add_argument("--dense", type=int, nargs="*", default=None,
                        help="meshes on which the dense path runs too; default the coarsest")  # fmt: skip
    parser.add_argument("--static", action=argparse.BooleanOptionalAction, default=True,
                        help="the static rows (--no-static: the dynamic ones only)")  # fmt: skip
    parser.add_argument("--history", action="store_true",
                        help="the wear history to a converged scar, finest mesh; nothing else")  # fmt: skip
    args = parser.parse_args()
    if args.history:
        print(f"load average {os.getloadavg()[0]:.2f}, OPENBLAS_NUM_THREADS="
              f"{os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}")  # fmt: skip
        return history(args.divisions[-1])
    dyn = [args.divisions[-1]] if args.dynamic is None else args.dynamic
    dense = [min(args.divisions)] if args.dense is None else args.dense
    if not args.static:
        print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, {total_memory_gb():.1f} GB "
              f"RAM, OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}\n")  # fmt: skip
        return dynamic(sorted(set(dyn) | set(dense)), dense)
    print(f"load average {os.getloadavg()[0]:.2f}, {os.cpu_count()} cores, {total_memory_gb():.1f} GB RAM, "
          f"OPENBLAS_NUM_THREADS={os.environ.get('OPENBLAS_NUM_THREADS', 'unset')}\n")  # fmt: skip
    rows, errs = [], []
    for d in args.divisions:
        r, e, cond = row(d)
        rows.append(r)
        errs.append(e)
        print(f"divisions {d}: pairs {r[1]}, build {r[3]} s, peak memory {r[6]} GB", flush=True)
    print()
    header = ["divisions", "pairs", "DOFs (both bodies)", "build (s)", "condense (s)",
              "static solve (s, max)", "peak memory (GB)"]  # fmt: skip
    table(header, rows)
    targets = dict(a=0.03, p0=0.03, **{f"c({q})": 0.05 for q in (0.3, 0.5, 0.8)})
    table(
        ["divisions", *[f"{k} err (ratio)" for k in targets]],
        [
            [d, *[f"{e[k]:.2e} ({e[k] / t:.2f})" for k, t in targets.items()]]
            for d, e in zip(args.divisions, errs, strict=True)
        ],
    )
    cyc = []
    for q in (0.3, 0.6, 0.9):
        t, d = timed(lambda q=q: sphere_cyclic_dissipation(q, condensation=cond))
        e = abs(d["error_dissipation"])
        w, w_md = d["dissipation"], d["mindlin_deresiewicz"]
        cyc.append([q, f"{w:.4g}", f"{w_md:.4g}", f"{e:.2e} ({e / 0.05:.2f})", f"{t:.3g}"])
    print(f"dissipation per cycle +-Q*, {args.divisions[-1]} divisions (target 5 %):")
    table(["Q* / (mu P)", "W (J)", "Mindlin-Deresiewicz (J)", "error (ratio)", "time (s)"], cyc)
    big = [r for r in rows if r[1] >= 500]
    if big:
        r = big[0]
        print(f">= 500 pairs ({r[1]}): static solve {r[5]} s next to the periodic target 10 s (ratio "
              f"{float(r[5]) / 10:.2f}); build {r[3]} s; peak memory {r[6]} GB of {total_memory_gb():.0f} GB "
              f"(ratio {float(r[6]) / total_memory_gb():.2f})")  # fmt: skip
    print(f"default SphereOnFlat: {SphereOnFlat().divisions} divisions")
    dynamic(sorted(set(dyn) | set(dense)), dense)


def dynamic(meshes: list[int], dense: list[int]) -> None:
    """The dynamic table: time (ratio to 10 s), Newton iterations (ratio to 10), dissipation error (ratio
    to 5 %), the holder's first-harmonic amplitude and the peak memory."""
    rows = [r for d in meshes for r in dynamic_rows(d, d in dense)]
    table(["divisions", "pairs", "unknowns", "Q*/(mu P)", "f (Hz)", "f / f1", "path", "solve s (ratio)",
           "its (ratio)", "W (J)", "W err (ratio)", "holder x (m)", "GB", "converged"], rows)  # fmt: skip


if __name__ == "__main__":
    main()
