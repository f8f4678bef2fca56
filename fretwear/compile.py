"""The compiled numerical kernels: which there are, whether their machine code is cached, warming them up.

fretwear's hot loops are Numba functions, compiled to machine code the first
time they run and cached on disk (``__pycache__`` beside the modules, or under
``NUMBA_CACHE_DIR``): only the first run of a computation on a machine, with a
given Python, pays the compilation. The kernels are grouped by the
computations that need them, so that a command compiles only its own:

* ``"sweep"``: frequency sweeps and single-frequency solves
  (:func:`fretwear.sweep`, :func:`fretwear.solve_periodic`; ``fretwear frf``,
  ``fretwear point``, the dashboard's FRF scenes);
* ``"solver"``: the periodic solver's loops as the slow-time (wear) methods
  and the branch continuation use them (``fretwear.hbm.periodic.solve_problem()``,
  :func:`fretwear.hbm.periodic.walk`; ``fretwear wear``, ``fretwear map``,
  ``fretwear frf --continuation``);
* ``"polynomial"``: the polynomial slow-time method on DLFT dynamics
  (``wear_history(..., "polynomial")``, ``fretwear wear --method polynomial``);
* ``"exact"``: the exact event-driven dynamics: shooting, direct time
  integration and the exact wear tables (:func:`fretwear.shooting`,
  :func:`fretwear.shooting_sweep`, ``dynamics="shooting"``, ``method="time"``;
  ``--method shooting``, ``--dynamics shooting``);
* ``"interface"``: contact interfaces with many node pairs
  (:mod:`fretwear.interface`; ``fretwear interface``);
* ``"cone"``: 2-D friction, the circular Coulomb cone (:mod:`fretwear.hbm.cone_problem`).

A front end tells its user before a first run::

    message = fretwear.compile.notice("sweep")
    if message:
        print(message, file=sys.stderr)  # "compiling numerical kernels, first run only, about 20 s"

and can compile ahead of time with :func:`warm`, or on several cores with
:func:`warm_in_processes`.
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from pickle import dumps

import numpy as np

__all__ = [
    "Kernel", "KERNELS", "PARTS", "NEEDS", "cached", "pending", "notice", "notice_for", "warm",
    "warm_in_processes", "compile_ahead",
]  # fmt: skip


@dataclass(frozen=True)
class Kernel:
    """A group of compiled entry points that one kind of computation needs.

    Attributes
    ----------
    name : str
        Key in :data:`KERNELS`.
    purpose : str
        The computations that need it.
    entry_points : tuple of str
        ``"module:function"`` of its Numba entry points (their callees are
        compiled and cached with them).
    seconds : float
        Compile time measured in a new process on a 2-core machine, rounded up (s; the benchmark
        ``benchmarks/bench_solver.py`` measures it again); what :func:`notice` announces.
    run : callable
        A small computation that runs every entry point once (compiles them,
        or loads them from the cache).
    share : callable or None
        ``share(i)`` compiles the ``i``-th of two shares of the entry points'
        callees without running them (:func:`compile_ahead`); None: no split.
    """

    name: str
    purpose: str
    entry_points: tuple[str, ...]
    seconds: float
    run: Callable[[], object]
    share: Callable[[int], object] | None = None


def _run_sweep() -> None:
    from .hbm.continuation import sweep
    from .model import paper_model

    sweep(paper_model(), 2 * np.pi * np.array([0.3, 0.6, 0.7]), 3)


def _share_sweep(share: int) -> None:
    from .hbm.compiled_sweep import compile_callees

    compile_callees(share, 2)


def _run_solver() -> None:
    from .hbm.periodic import load_homotopy, newton, walk
    from .hbm.problem import Problem
    from .model import paper_model

    problem = Problem(paper_model(), 2 * np.pi * 0.7, 3)
    x = load_homotopy(problem).x  # walk_kernel, then newton_kernel
    newton(problem, x, 1e-10, 2)
    walk(problem, x, 1.0, 0.9, 0, problem.F0, np.zeros(0), 10, record=2)
    problem.evaluate(x)  # evaluate and jacobian_from_blocks, as Problem calls them


def _run_polynomial() -> None:
    from .model import paper_model
    from .wear.history import wear_history

    model, omega = paper_model(), 2 * np.pi * 0.7
    for basis in ("saturating", "legendre"):  # the default basis, and the paper's Galerkin system (_galerkin)
        wear_history(model, omega, "polynomial", kw=1e-11, cycles=20.0, harmonics=3, basis=basis)


def _run_exact() -> None:
    from .model import paper_model
    from .time.shooting import shooting, shooting_sweep
    from .wear.history import wear_history

    model, omega = paper_model(), 2 * np.pi * 0.7
    shooting(model, omega)
    shooting_sweep(model, omega * np.array([0.95, 1.0]))
    wear_history(model, omega, "exact", kw=1e-11, cycles=20.0, dynamics="shooting")
    wear_history(model, omega, "time", kw=1e-11, cycles=20.0)


def _run_interface() -> None:
    from .interface.paper import paper_interface
    from .interface.periodic import InterfaceProblem, load_walk, solve_interface
    from .interface.reduction import ContactCondensation
    from .interface.time_integration import initial_state, integrate_interface
    from .interface.wear import wear_interface
    from .model import craig_bampton

    condensation = ContactCondensation(craig_bampton(paper_interface(), 0.0))
    problem = InterfaceProblem(condensation, 2 * np.pi * 0.7, harmonics=3)
    load_walk(problem)  # the fallback of a Newton that fails (the structured Newton seldom does)
    integrate_interface(condensation, problem.omega, *initial_state(solve_interface(problem)), periods=1,
                        steps_per_period=64)  # fmt: skip
    for method in ("stepping", "polynomial"):
        wear_interface(problem, 1e-11, 100.0, method=method, degree=2 if method == "polynomial" else None)


def _run_cone() -> None:
    from .hbm.cone_problem import ConeProblem
    from .hbm.harmonics import HarmonicBasis

    # a point mass pressed on a flat, driven round a circle: one pair, stick and slip in the period
    basis = HarmonicBasis(1, 16)
    H = basis.size
    Z = np.zeros((3 * H, 3 * H))
    for o in (0, H):
        Z[o, o], Z[o + 1, o + 1], Z[o + 2, o + 2], Z[o + 1, o + 2], Z[o + 2, o + 1] = 1.0, 0.5, 0.5, 0.1, -0.1
    Z[2 * H :, 2 * H :] = 1e3 * np.eye(H)
    F = np.zeros(3 * H)
    F[1], F[H + 2], F[2 * H] = 2.0, 2.0, 1.0
    ConeProblem(Z, F, basis, np.array([1.0])).solve(max_iter=0)  # no Newton step: the load walk too
    # the 3-D interface with the cone law: the structured step of 3 coordinates a pair, the time integration
    from .interface.periodic import InterfaceProblem, solve_interface
    from .interface.reduction import ContactCondensation
    from .interface.sphere import sphere_dynamic_model
    from .interface.time_integration import initial_state, integrate_interface

    cond = ContactCondensation(sphere_dynamic_model(divisions=2, size=2.0, q_ratio=0.9))
    sol = solve_interface(InterfaceProblem(cond, 2 * np.pi * 100.0, harmonics=1))
    integrate_interface(cond, sol.problem.omega, *initial_state(sol), periods=1, steps_per_period=16)
    _ = sol.slip_distance  # the cone's slip work: the wear of the sphere in the dashboard's Interface tab


#: the kernel groups, by name
KERNELS: dict[str, Kernel] = {
    k.name: k
    for k in (
        Kernel(
            "sweep",
            "frequency sweeps and single-frequency solves (fretwear.sweep, fretwear.solve_periodic)",
            ("fretwear.hbm.compiled_sweep:sweep_kernel", "fretwear.hbm.condensation:condense_loop"),
            20.0,
            _run_sweep,
            _share_sweep,
        ),
        Kernel(
            "solver",
            "the periodic solver in Python loops: wear histories, branch continuation",
            (
                "fretwear.hbm.kernels:newton_kernel",
                "fretwear.hbm.kernels:walk_kernel",
                "fretwear.hbm.dlft:evaluate",
                "fretwear.hbm.dlft:jacobian_from_blocks",
                "fretwear.hbm.condensation:condense_loop",  # every Problem condenses with it
            ),  # fmt: skip
            20.0,
            _run_solver,
        ),
        Kernel(
            "polynomial",
            "the polynomial slow-time method on DLFT dynamics (wear_history(..., 'polynomial'))",
            ("fretwear.wear.polynomial:_chain", "fretwear.wear.polynomial:_galerkin"),
            30.0,
            _run_polynomial,
        ),
        Kernel(
            "exact",
            "the exact event-driven dynamics: shooting, time integration, exact wear tables",
            (
                "fretwear.time.periodic:solve",
                "fretwear.time.periodic:newton",
                "fretwear.time.marching:march",
                "fretwear.time.integrals:orbit",
                "fretwear.wear.sliding:_invert",
                "fretwear.wear.sliding:_pchip",
                "fretwear.wear.sliding:_lagrange",
            ),  # fmt: skip
            60.0,
            _run_exact,
        ),
        Kernel(
            "interface",
            "contact interfaces with many node pairs (fretwear.interface)",
            (
                "fretwear.interface.periodic:_block_newton",
                "fretwear.interface.kernels:walk_kernel",
                "fretwear.interface.polynomial:rate_sensitivity",
                "fretwear.interface.time_integration:integrate_kernel",
            ),  # fmt: skip
            30.0,
            _run_interface,
        ),
        Kernel(
            "cone",
            "2-D friction (the circular Coulomb cone) on node pairs (fretwear.hbm.cone_problem)",
            (
                "fretwear.hbm.cone_problem:newton_kernel",
                "fretwear.hbm.cone_problem:walk_kernel",
                "fretwear.interface.time_integration:integrate_cone_kernel",
            ),  # fmt: skip
            60.0,
            _run_cone,
        ),
    )
}


def _dispatcher(entry_point: str):
    module, name = entry_point.split(":")
    return getattr(__import__(module, fromlist=[name]), name)


def _in_cache(dispatcher) -> bool:
    """Whether the on-disk cache holds machine code of ``dispatcher`` for this machine and this source.

    Reads Numba's cache index as Numba itself does (its layout is not a public
    API: on any surprise the answer is False, so a front end announces a
    compilation that may not happen rather than miss one).
    """
    if dispatcher.overloads:  # compiled or loaded in this process
        return True
    try:
        cache = dispatcher._cache
        index = cache._cache_file._load_index()  # empty when missing or stale (source changed)
        py_func = dispatcher.py_func
        closure = b""
        if py_func.__closure__ is not None:
            closure = dumps(tuple(c.cell_contents for c in py_func.__closure__))
        code = (hashlib.sha256(py_func.__code__.co_code).hexdigest(), hashlib.sha256(closure).hexdigest())
        magic = dispatcher.targetctx.codegen().magic_tuple()
        return any(key[1] == magic and key[2] == code for key in index)
    except Exception:  # noqa: BLE001 - any change of Numba's internals: unknown, so not cached
        return False


def _check(names: tuple[str, ...]) -> tuple[str, ...]:
    names = names or tuple(KERNELS)
    unknown = [n for n in names if n not in KERNELS]
    if unknown:
        raise ValueError(f"kernel names must be among {sorted(KERNELS)}, got {unknown}")
    return names


def cached(name: str) -> bool:
    """Whether every entry point of kernel ``name`` is compiled for this interpreter (cache or memory)."""
    (name,) = _check((name,))
    return all(_in_cache(_dispatcher(e)) for e in KERNELS[name].entry_points)


def pending(*names: str) -> list[str]:
    """The kernels among ``names`` (default: all) that a first run would compile."""
    return [n for n in _check(names) if not cached(n)]


def notice(*names: str) -> str | None:
    """The line to show before a computation that needs kernels ``names``, or None if they are cached.

    ``"compiling numerical kernels, first run only, about N s"``, with ``N`` the
    sum of the pending kernels' measured compile times.
    """
    todo = pending(*names)
    if not todo:
        return None
    seconds = sum(KERNELS[n].seconds for n in todo)
    return f"compiling numerical kernels, first run only, about {seconds:.0f} s"


@dataclass(frozen=True)
class Need:
    """The entry points one computation of a front end calls, and their compile time.

    Attributes
    ----------
    entry_points : tuple of str
        ``"module:function"``: exactly those the computation runs (measured: the dispatchers with
        machine code after it), so that a cached computation is never announced.
    seconds : float
        Compile time in a new process with an empty cache, the needs listed before it in :data:`NEEDS`
        already compiled (measured on the project's 2-core machine).
    """

    entry_points: tuple[str, ...]
    seconds: float


_SHOOTING = (
    "fretwear.time.periodic:solve",
    "fretwear.wear.sliding:_invert",
    "fretwear.wear.sliding:_pchip",
    "fretwear.wear.sliding:_lagrange",
    "fretwear.hbm.condensation:condense_loop",
)

#: what each computation of the command line compiles on a first run, by name; the seconds were measured
#: on the project's 2-core machine with other jobs running (load 4-7, a quiet machine takes about a third)
NEEDS: dict[str, Need] = {
    "sweep": Need(KERNELS["sweep"].entry_points, 35.0),  # frf, point
    "solver": Need(KERNELS["solver"].entry_points, 60.0),  # continuation; wear and map on DLFT dynamics
    "polynomial": Need(("fretwear.wear.polynomial:_chain",), 60.0),  # with "solver": saturating basis
    "galerkin": Need(("fretwear.wear.polynomial:_galerkin",), 45.0),  # with "solver": legendre, monomial
    "shooting": Need(_SHOOTING, 220.0),  # --method shooting, --dynamics shooting (tables, the exact map)
    "time": Need(KERNELS["exact"].entry_points[:4], 25.0),  # with "shooting": --method time
    "interface": Need(KERNELS["interface"].entry_points, 175.0),
}


def notice_for(*needs: str) -> str | None:
    """The line to show before a computation with :data:`NEEDS` ``needs``, or None if nothing will compile.

    Asks Numba's on-disk cache whether each entry point the computation calls has machine code for this
    source (:func:`cached`); ``"compiling numerical kernels, first run only, about N s"`` with ``N`` the
    sum of the measured compile times of the needs with an entry point missing.
    """
    unknown = [n for n in needs if n not in NEEDS]
    if unknown:
        raise ValueError(f"needs must be among {sorted(NEEDS)}, got {unknown}")
    todo = [
        n for n in dict.fromkeys(needs) if not all(_in_cache(_dispatcher(e)) for e in NEEDS[n].entry_points)
    ]
    if not todo:
        return None
    seconds = sum(NEEDS[n].seconds for n in todo)
    return f"compiling numerical kernels, first run only, about {seconds:.0f} s"


def warm(*names: str, progress: Callable[[str, int, int], object] | None = None) -> dict[str, float]:
    """Compile (or load from the cache) kernels ``names`` (default: all); returns the wall time of each (s).

    ``progress(name, done, total)`` is called before each kernel and once at the end.
    Thread-safe (Numba compiles under a global lock); the kernels release the GIL once compiled.
    """
    names = _check(names)
    times = {}
    for k, name in enumerate(names):
        if progress is not None:
            progress(name, k, len(names))
        t0 = time.perf_counter()
        KERNELS[name].run()
        times[name] = time.perf_counter() - t0
    if progress is not None:
        progress("", len(names), len(names))
    return times


def _child_env(env: Mapping[str, str] | None = None) -> dict[str, str]:
    """``env`` (default: this process's environment) for a new Python process that imports this fretwear."""
    env = dict(os.environ if env is None else env)
    root = str(Path(__file__).resolve().parents[1])
    env["PYTHONPATH"] = os.pathsep.join(filter(None, [root, env.get("PYTHONPATH")]))
    return env


def compile_ahead(*names: str) -> None:
    """Before a first run, compile the pending groups ``names`` that split in two, on two cores at once.

    A second process compiles one share of a group's callees while this one
    compiles the other (:attr:`Kernel.share`); the group's entry points then
    load them from Numba's on-disk cache on first use. On two cores the cold
    ``fretwear frf`` takes about 14 s instead of 18 s (``benchmarks/bench_solver.py``).
    Groups without a split, and machines with one core, compile on first use
    as before; a failed process only costs time.
    """
    if (os.cpu_count() or 1) < 2:
        return
    for name in pending(*names):
        kernel = KERNELS[name]
        if kernel.share is None:
            continue
        code = "import sys, fretwear.compile as c; c.KERNELS[sys.argv[1]].share(1)"
        try:
            other = subprocess.Popen([sys.executable, "-W", "ignore", "-c", code, name], env=_child_env())
        except OSError:  # no second process: everything compiles on first use
            return
        try:
            kernel.share(0)
        except Exception:  # noqa: BLE001 - this share then compiles on first use, as without the split
            pass
        other.wait()


#: the kernel groups in two sets that share no kernel, for :func:`warm_in_processes`
PARTS: tuple[tuple[str, ...], ...] = (("sweep", "solver", "polynomial", "interface"), ("exact", "cone"))


def warm_in_processes(
    parts: tuple[tuple[str, ...], ...] = PARTS, env: Mapping[str, str] | None = None
) -> list[tuple[list[str], bool]]:
    """Compile the pending kernel groups of each of ``parts`` in a new Python process, all at once.

    Each process takes one core and writes the machine code to Numba's on-disk
    cache, from which this process and later ones load it: on a cold cache (a
    fresh install) two cores take about half the time of :func:`warm` (measured
    on the project's two cores, load 1-1.7: 177-191 s for all the groups, against
    220-250 s in turn on a quieter machine).
    Warnings of the tiny runs are not shown. A process that fails only costs
    time: the kernels then compile on first use. ``env``: the processes'
    environment (default: this one's). Returns ``(groups, ok)`` per process.
    """
    todo = [[name for name in part if name in pending(*part)] for part in parts]
    todo = [part for part in todo if part]
    env = _child_env(env)
    code = "import sys, fretwear.compile as c; c.warm(*sys.argv[1:])"
    runs = [subprocess.Popen([sys.executable, "-W", "ignore", "-c", code, *part], env=env) for part in todo]
    return [(part, run.wait() == 0) for part, run in zip(todo, runs, strict=True)]
