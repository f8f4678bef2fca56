"""The library calls of the dashboard, their shared cache and the worker threads.

Every number the dashboard shows comes from one :class:`Backend` method, a
thin wrapper of one :mod:`fretwear` front function held by its :class:`Library`
(the Interface tab's too: a model with contact pairs goes through the same
:func:`fretwear.wear_history` and :func:`fretwear.sweep`);
``Backend.calls`` counts the library calls by name (the tests use it to prove
what is recomputed, and a backend built with other functions replaces the
library in tests).

Results are kept in a :class:`ResultCache` keyed by the parameters they depend
on; one cache serves every session of the server process. A computation
asked for while another thread runs it is waited for, not repeated.

The wear map and the regime map are split into chunks (of frequencies, of
load levels) that run on the backend's thread pool: the compiled kernels
release the GIL, the chunks give a determinate progress, and a superseded run
stops at the next chunk (:class:`Cancelled`).
"""

from __future__ import annotations

import functools
import importlib
import logging
import operator
import os
import threading
from collections import Counter, OrderedDict
from collections.abc import Callable, Hashable, Sequence
from concurrent.futures import Future, ThreadPoolExecutor, as_completed
from dataclasses import dataclass, fields
from typing import Any

import numpy as np

import fretwear
from fretwear.model import Model
from fretwear.studies import CostStudy, WearMap
from fretwear.wear import WearHistory

__all__ = [
    "Backend",
    "Cancelled",
    "Failure",
    "Grid",
    "InterfaceModel",
    "ModelSpec",
    "ResultCache",
    "shared_backend",
    "shared_cache",
    "shared_executor",
]

log = logging.getLogger(__name__)

Progress = Callable[[float], None]
Check = Callable[[], bool]


def _lazy(module: str, name: str) -> Callable:
    """``module.name``, imported on its first call (the interface builders load scikit-fem)."""

    def call(*args: Any, **kwargs: Any) -> Any:
        return getattr(importlib.import_module(module), name)(*args, **kwargs)

    call.__name__ = call.__qualname__ = name
    return call


class Library:
    """The library functions the dashboard calls, one attribute each (the test seam).

    The defaults are :mod:`fretwear`'s front functions; keyword arguments replace
    some of them (tests inject slow, failing or counting versions).
    """

    paper_model = staticmethod(fretwear.paper_model)
    linear_frf = staticmethod(fretwear.linear_frf)
    sweep = staticmethod(fretwear.sweep)
    regime_map = staticmethod(fretwear.regime_map)
    wear_map = staticmethod(fretwear.wear_map)
    wear_history = staticmethod(fretwear.wear_history)
    solve_periodic = staticmethod(fretwear.solve_periodic)
    shooting = staticmethod(fretwear.shooting)
    cost_ladder = staticmethod(fretwear.cost_ladder)
    reduce = staticmethod(fretwear.reduce)
    cylinder_on_flat = staticmethod(_lazy("fretwear", "cylinder_on_flat"))
    paper_interface = staticmethod(_lazy("fretwear", "paper_interface"))
    sphere_dynamic_model = staticmethod(_lazy("fretwear.interface.sphere", "sphere_dynamic_model"))
    read_interface_model = staticmethod(_lazy("fretwear.interface", "read_interface_model"))
    open_study = staticmethod(_lazy("fretwear.studies.store", "open_study"))
    bladed_disk = staticmethod(fretwear.bladed_disk)
    draw_mistuning = staticmethod(_lazy("fretwear.disk", "draw_mistuning"))
    sweep_sector = staticmethod(_lazy("fretwear.disk", "sweep_sector"))

    def __init__(self, **replacements: Callable) -> None:
        unknown = sorted(set(replacements) - set(_LIBRARY_NAMES))
        if unknown:
            raise ValueError(f"unknown library functions {unknown}; known: {sorted(_LIBRARY_NAMES)}")
        for name, function in replacements.items():
            setattr(self, name, function)


_LIBRARY_NAMES = tuple(k for k, v in vars(Library).items() if isinstance(v, staticmethod))


class Cancelled(Exception):
    """A newer request superseded the run that was computing this result (or the server is stopping)."""


@dataclass(frozen=True)
class Failure:
    """A computation that raised: kept in the cache and shown as a message, never as a traceback.

    ``message`` names the exception's type; ``reason`` is its text alone (one line).
    """

    message: str
    reason: str = ""

    def __str__(self) -> str:
        return self.message


@dataclass(frozen=True)
class Grid:
    """Evenly spaced values ``np.linspace(start, stop, n)`` as a hashable argument (and cache key)."""

    start: float
    stop: float
    n: int

    @property
    def values(self) -> np.ndarray:
        """The grid's values."""
        return np.linspace(self.start, self.stop, self.n)


@dataclass(frozen=True)
class ModelSpec:
    """The paper's 2-DOF model as a hashable cache key: the arguments of :func:`fretwear.paper_model`
    (``fex`` in N, ``mu``, ``normal_load`` in N, ``kn`` in N/m; see there)."""

    fex: float
    mu: float
    normal_load: float
    kn: float = 1e7

    @property
    def r(self) -> float:
        """Load ratio ``r = F_ex / (mu F_N)`` (-), :attr:`fretwear.Model.load_ratio`."""
        return fretwear.paper_model(self.fex, self.mu, self.normal_load, self.kn).load_ratio

    def unit_forcing(self) -> ModelSpec:
        """The same contact under ``F_ex = 1 N``: the key of results drawn over ``r``, whatever ``F_ex``."""
        return ModelSpec(1.0, self.mu, self.normal_load, self.kn)

    def linear_part(self) -> ModelSpec:
        """The same structure and excitation with the friction coefficient and normal load at 1: the
        linear FRFs with the contact stuck (a constraint) or open depend on neither."""
        return ModelSpec(self.fex, 1.0, 1.0, self.kn)


#: the interface models the backend builds by name (:class:`InterfaceModel`)
BUILDERS = ("cylinder_on_flat", "sphere_dynamic_model", "paper_interface")


@dataclass(frozen=True)
class InterfaceModel:
    """A model with contact pairs as a hashable cache key: its builder and the builder's arguments.

    ``builder`` is one of :data:`BUILDERS` (``parameters``: its keyword arguments as ``(name, value)``
    pairs), or ``"file"`` (an interface model file at ``path``, whose
    modification time ``stamp`` makes a changed file another key).
    """

    builder: str
    parameters: tuple[tuple[str, Any], ...] = ()
    path: str | None = None
    stamp: float | None = None


@dataclass(frozen=True)
class DiskSpec:
    """The shrouded bladed disk as a hashable cache key: the arguments of :func:`fretwear.bladed_disk`
    (``fex`` in N), mistuned by the seeded pattern of :func:`fretwear.disk.draw_mistuning` at ``level``
    (0: tuned)."""

    sectors: int = 24
    engine_order: int = 3
    fex: float = 2.0
    mu: float = 0.3
    level: float = 0.0
    seed: int = 0


class ResultCache:
    """Bounded least-recently-used cache of results, shared by threads and sessions.

    Keys are tuples whose first item names the kind of result (``"wear_map"``,
    ``"history"``, ...); each kind has its own bound, so that the many small
    wear histories a wear map brings along do not push out the maps.

    Parameters
    ----------
    max_entries : int
        Results kept per kind; the least recently used go first.
    per_kind : mapping, optional
        Other bounds by kind.
    """

    def __init__(self, max_entries: int = 48, per_kind: dict[str, int] | None = None) -> None:
        self.max_entries = max_entries
        # a reduced interface model holds its full model (MBs): a few only
        bounds = {"history": 2048, "point": 256, "interface_model": 4}
        self.per_kind = bounds if per_kind is None else dict(per_kind)
        self._lock = threading.Lock()
        self._done: dict[Hashable, OrderedDict[Hashable, Any]] = {}
        self._running: dict[Hashable, Future] = {}

    @staticmethod
    def _kind(key: Hashable) -> Hashable:
        return key[0] if isinstance(key, tuple) and key else None

    def _shelf(self, key: Hashable) -> OrderedDict[Hashable, Any]:
        return self._done.setdefault(self._kind(key), OrderedDict())

    def __contains__(self, key: Hashable) -> bool:
        with self._lock:
            return key in self._shelf(key)

    def __len__(self) -> int:
        with self._lock:
            return sum(len(shelf) for shelf in self._done.values())

    def get(self, key: Hashable, default: Any = None) -> Any:
        """The cached result of ``key`` (marked as recently used), or ``default``."""
        with self._lock:
            shelf = self._shelf(key)
            if key not in shelf:
                return default
            shelf.move_to_end(key)
            return shelf[key]

    def put(self, key: Hashable, value: Any) -> None:
        """Store ``value`` under ``key``, dropping the least recently used results of its kind."""
        with self._lock:
            self._store(key, value)

    def _store(self, key: Hashable, value: Any) -> None:
        shelf = self._shelf(key)
        shelf[key] = value
        shelf.move_to_end(key)
        while len(shelf) > self.per_kind.get(self._kind(key), self.max_entries):
            shelf.popitem(last=False)

    def get_or_compute(self, key: Hashable, compute: Callable[[], Any]) -> Any:
        """The result of ``key``: cached, awaited from the thread computing it, or computed here.

        A computation that raises is not cached; when the thread computing it
        was cancelled, a waiting thread computes it itself.
        """
        while True:
            with self._lock:
                shelf = self._shelf(key)
                if key in shelf:
                    shelf.move_to_end(key)
                    return shelf[key]
                future = self._running.get(key)
                owner = future is None
                if owner:
                    future = self._running[key] = Future()
            if not owner:
                try:
                    return future.result()
                except Cancelled:
                    continue
            try:
                value = compute()
            except BaseException as exc:
                with self._lock:
                    del self._running[key]
                future.set_exception(exc)
                raise
            with self._lock:
                del self._running[key]
                self._store(key, value)
            future.set_result(value)
            return value


def _merge(parts: list, axis_length: Callable[[Any], int]) -> dict[str, Any]:
    """Join the fields of chunked results along their first axis.

    Arrays whose first axis has the chunk's length and sequences (lists, the
    lazy histories of exact maps) are joined; every other field (shared grids,
    ``u0``) comes from the first chunk.
    """
    first = parts[0]
    items = (
        first.items()
        if isinstance(first, dict)
        else ((f.name, getattr(first, f.name)) for f in fields(first))
    )
    merged = {}
    for name, value in items:
        values = [p[name] if isinstance(p, dict) else getattr(p, name) for p in parts]
        if isinstance(value, Sequence) and not isinstance(value, str):
            merged[name] = functools.reduce(operator.add, values)
        elif isinstance(value, np.ndarray) and value.ndim and len(value) == axis_length(first):
            merged[name] = np.concatenate(values, axis=0)
        else:
            merged[name] = value
    return merged


def _chunks(n: int, count: int) -> list[slice]:
    edges = np.linspace(0, n, min(count, n) + 1).round().astype(int)
    return [slice(a, b) for a, b in zip(edges[:-1], edges[1:], strict=True)]


class Backend:
    """The library calls of the dashboard, counted.

    Parameters
    ----------
    workers : int, optional
        Threads for chunked maps; default the number of CPUs, at most 4.
    chunks : int
        Chunks of a wear map or regime map (progress steps).
    **replacements
        Replacements of library functions by name (attributes of :class:`Library`).
    """

    def __init__(self, workers: int | None = None, chunks: int = 8, **replacements: Callable) -> None:
        self.library = Library(**replacements)
        self.chunks = chunks
        self.calls: Counter[str] = Counter()
        self._calls_lock = threading.Lock()
        self.workers = workers or max(1, min(4, os.cpu_count() or 1))
        self._pool: ThreadPoolExecutor | None = None
        # the exact load path's histories on DLFT per frequency, whatever k_w (see wear_map)
        self._any_kw = ResultCache(per_kind={"any_kw": 512})

    @property
    def pool(self) -> ThreadPoolExecutor:
        """Worker threads of the chunked computations (created on first use)."""
        if self._pool is None:
            self._pool = ThreadPoolExecutor(self.workers, thread_name_prefix="fretwear-chunk")
        return self._pool

    def _tally(self, name: str) -> None:
        """Count one call of the library function ``name`` in :attr:`calls`."""
        with self._calls_lock:
            self.calls[name] += 1

    def _chunked(
        self, function: Callable, jobs: list[tuple[tuple, dict]], progress: Progress, cancelled: Check
    ) -> list:
        """Run ``function(*args, **kwargs)`` (a :class:`Library` function) for each job on the pool."""
        name = next(n for n in _LIBRARY_NAMES if getattr(self.library, n) is function)

        def run(args, kwargs):
            if cancelled():
                raise Cancelled
            self._tally(name)
            return function(*args, **kwargs)

        try:
            futures = [self.pool.submit(run, *job) for job in jobs]
        except RuntimeError as exc:  # "cannot schedule new futures after shutdown": the server is stopping
            if "shutdown" not in str(exc):
                raise
            raise Cancelled from None
        try:
            for done, future in enumerate(as_completed(futures), 1):
                future.result()
                progress(done / len(futures))
        except BaseException:
            for future in futures:
                future.cancel()
            raise
        return [future.result() for future in futures]

    # -- the computations -------------------------------------------------------------

    def model(self, spec: ModelSpec) -> Model:
        """The paper's 2-DOF model of ``spec``."""
        self._tally("paper_model")
        return self.library.paper_model(fex=spec.fex, mu=spec.mu, normal_load=spec.normal_load, kn=spec.kn)

    def linear(self, spec: ModelSpec, grid: Grid, state: str) -> dict[str, np.ndarray]:
        """Complex amplitudes (m) of every DOF over the frequency ``grid`` (Hz) with the contact ``state``
        ("stuck" or "open")."""
        self._tally("linear_frf")
        f_hz = grid.values
        u = self.library.linear_frf(self.model(spec), 2 * np.pi * f_hz, state)
        return {"f_hz": f_hz, "amplitude": u}

    def frf(self, spec: ModelSpec, grid: Grid, harmonics: int) -> dict[str, np.ndarray]:
        """Nonlinear FRF without wear (a sweep) over the frequency ``grid`` (Hz), as arrays.

        First-harmonic amplitudes only: the exact half peak-to-peak values cost
        three times the sweep.
        """
        model = self.model(spec)
        self._tally("sweep")
        f_hz = grid.values
        sols = self.library.sweep(model, 2 * np.pi * f_hz, harmonics).solutions
        return {
            "f_hz": f_hz,
            "amplitude": np.array([s.amplitude for s in sols]),
            "relative_amplitude": np.array([s.relative_amplitude for s in sols]),
            "sliding_distance": np.array([s.sliding_distance for s in sols]),
            "friction_energy": np.array([s.friction_energy for s in sols]),
            "converged": np.array([s.converged for s in sols]),
        }

    def regime(
        self,
        spec: ModelSpec,
        grid: Grid,
        ratio_grid: Grid,
        harmonics: int,
        progress: Progress = lambda _f: None,
        cancelled: Check = lambda: False,
    ) -> dict[str, np.ndarray]:
        """Stick/slip regime over the frequency ``grid`` (Hz) x the load ratios ``r`` of ``ratio_grid``
        (:func:`fretwear.studies.regime_map`).

        The result does not depend on ``F_ex``: callers pass ``spec.unit_forcing()``.
        """
        model = self.model(spec)
        f_hz, ratios = grid.values, ratio_grid.values
        jobs = [((model, f_hz, ratios[part], harmonics), {}) for part in _chunks(len(ratios), self.chunks)]
        parts = self._chunked(self.library.regime_map, jobs, progress, cancelled)
        return {
            "f_hz": np.asarray(f_hz),
            "ratios": np.asarray(ratios),
            **_merge(parts, lambda p: len(p["slip_fraction"])),
        }

    def wear_map(
        self,
        spec: ModelSpec,
        grid: Grid,
        horizon: float,
        n_cycles: int,
        method: str,
        kw: float,
        options: tuple[tuple[str, Any], ...],
        progress: Progress = lambda _f: None,
        cancelled: Check = lambda: False,
    ) -> WearMap:
        """Wear map over the frequency ``grid`` (Hz) x ``n_cycles`` cycle counts up to ``horizon``
        (:func:`fretwear.wear.cycle_grid`) by :func:`fretwear.studies.wear_map`, in frequency chunks;
        ``options``: the method's options as ``(name, value)`` pairs.

        The exact method on DLFT places its records in wear and integrates ``N`` in closed form, so a
        frequency whose history reached its end state (worn through, or stuck) within the horizon at
        one ``k_w`` is the same history at another, its cycle counts scaled
        (:meth:`fretwear.wear.WearHistory.rescaled`): a new ``k_w`` recomputes only the frequencies
        whose scaled end passes the horizon.
        """
        model = self.model(spec)
        f_hz, cycles = grid.values, fretwear.wear.cycle_grid(horizon, n_cycles)
        if method == "exact" and dict(options).get("dynamics") == "dlft":
            return self._exact_dlft_map(spec, f_hz, cycles, horizon, kw, options, progress, cancelled)
        jobs = [
            ((model, f_hz[part], cycles), {"method": method, "kw": kw, **dict(options)})
            for part in _chunks(len(f_hz), self.chunks)
        ]
        parts = self._chunked(self.library.wear_map, jobs, progress, cancelled)
        return WearMap(**_merge(parts, lambda p: len(p.frequency)))

    def _exact_dlft_map(self, spec, f_hz, cycles, horizon, kw, options, progress, cancelled) -> WearMap:
        """:meth:`wear_map` of the exact method on DLFT, reusing the histories of other ``k_w``."""
        model = self.model(spec)
        keys = [("any_kw", spec, float(f"{f:.12g}"), options, horizon) for f in f_hz]
        histories = [self._at_kw(self._any_kw.get(key), kw, horizon) for key in keys]
        todo = np.flatnonzero([h is None for h in histories])
        if len(todo):
            jobs = [((model, f_hz[todo[part]], cycles), {"method": "exact", "kw": kw, **dict(options)})
                    for part in _chunks(len(todo), self.chunks)]  # fmt: skip
            parts = self._chunked(self.library.wear_map, jobs, progress, cancelled)
            for i, h in zip(todo, (h for part in parts for h in part.histories), strict=True):
                histories[i] = h
                if h.status in ("worn", "stuck"):
                    self._any_kw.put(keys[i], h)
        progress(1.0)
        return fretwear.studies.maps.map_of_histories(model, f_hz, cycles, histories)

    @staticmethod
    def _at_kw(history: WearHistory | None, kw: float, horizon: float) -> WearHistory | None:
        """``history`` under ``kw`` when that is exact (:meth:`fretwear.wear.WearHistory.rescaled`), else
        None."""
        if history is None or history.kw == kw:
            return history
        try:
            return history.rescaled(kw, horizon)
        except ValueError:  # its scaled end passes the horizon: computed again
            return None

    def history(
        self,
        spec: ModelSpec,
        f_hz: float,
        method: str,
        kw: float,
        horizon: float,
        options: tuple[tuple[str, Any], ...],
    ) -> WearHistory:
        """Wear evolution at one frequency (:func:`fretwear.wear.wear_history`); ``options``: the
        method's options as ``(name, value)`` pairs."""
        model = self.model(spec)
        self._tally("wear_history")
        return self.library.wear_history(
            model, 2 * np.pi * f_hz, method, kw=kw, cycles=horizon, **dict(options)
        )

    def point(
        self, spec: ModelSpec, f_hz: float, harmonics: int, wear: np.ndarray | None
    ) -> fretwear.PeriodicSolution:
        """Periodic response at one frequency and wear (``None``: unworn), :func:`fretwear.solve_periodic`."""
        model = self.model(spec)
        self._tally("solve_periodic")
        return self.library.solve_periodic(model, 2 * np.pi * f_hz, harmonics, wear=wear)

    def exact_point(self, spec: ModelSpec, f_hz: float, wear: np.ndarray | None) -> fretwear.ShootingSolution:
        """Exact periodic orbit at one frequency and wear (:func:`fretwear.shooting`, event-driven)."""
        model = self.model(spec)
        self._tally("shooting")
        return self.library.shooting(model, 2 * np.pi * f_hz, wear=wear)

    def cost(
        self,
        spec: ModelSpec,
        f_hz: float,
        ladder: tuple[tuple[str, Any], ...],
        kw: float | None = None,
        cycles: float | None = None,
        progress: Progress = lambda _f: None,
        cancelled: Check = lambda: False,
    ) -> CostStudy:
        """Error against wall time over a ladder of settings (:func:`fretwear.studies.accuracy.cost_ladder`).

        ``ladder`` holds the ladder's keyword arguments as ``(name, value)`` pairs; ``kw`` and ``cycles``
        (both or neither) add the wear rungs. The run stops with
        :class:`Cancelled` at the first rung after ``cancelled()`` turns true.
        """

        def step(fraction: float) -> None:
            if cancelled():
                raise Cancelled
            progress(fraction)

        model = self.model(spec)
        self._tally("cost_ladder")
        return self.library.cost_ladder(model, f_hz, kw=kw, cycles=cycles, progress=step, **dict(ladder))

    # -- a model with contact pairs (the Interface tab) ------------------------------------

    def interface_model(self, spec: InterfaceModel, f_max: float) -> Model:
        """The model of ``spec`` reduced by :func:`fretwear.reduce` for frequencies up to ``f_max`` (Hz):
        what :meth:`interface_history` and :meth:`interface_frf` take (reduced once, used as it is)."""
        lib = self.library
        if spec.builder == "file":
            self._tally("read_interface_model")
            model = lib.read_interface_model(spec.path)
        elif spec.builder in BUILDERS:
            self._tally(spec.builder)
            model = getattr(lib, spec.builder)(**dict(spec.parameters))
        else:
            raise ValueError(
                f"builder must be one of {', '.join(map(repr, BUILDERS))} or 'file', got {spec.builder!r}"
            )
        self._tally("reduce")
        return lib.reduce(model, f_max)

    def interface_history(
        self, model: Model, f_hz: float, harmonics: int, kw: float, cycles: float, rtol: float
    ):
        """Nodal wear history of the reduced interface ``model`` at ``f_hz`` by slow-time stepping
        (:func:`fretwear.wear_history`: ``kw`` in 1/Pa, to ``cycles``; ``rtol`` its step tolerance)."""
        self._tally("wear_history")
        return self.library.wear_history(
            model, 2 * np.pi * f_hz, "stepping", kw=kw, cycles=cycles, harmonics=harmonics, rtol=rtol
        )

    def interface_frf(
        self, model: Model, grid: Grid, harmonics: int, dof: str, wear: np.ndarray | None
    ) -> dict[str, Any]:
        """First-harmonic amplitude (m) of DOF ``dof`` of the full model (its first DOF when it has no DOF
        of that name) over the frequency ``grid`` (Hz), at the worn depth per pair ``wear`` (m; ``None``:
        unworn): a sweep (:func:`fretwear.sweep`) of the reduced interface ``model``."""
        full = model.reduction.full if model.reduction is not None else model
        index = full.dof(dof) if dof in full.names else 0
        self._tally("sweep")
        sols = self.library.sweep(model, 2 * np.pi * grid.values, harmonics, wear=wear).solutions
        return {
            "f_hz": grid.values,
            "amplitude": np.array([np.hypot(*s.dof_harmonics[index, 1:3]) for s in sols]),
            "converged": np.array([s.converged for s in sols], dtype=bool),
            "dof": index,
            "dof_name": next((k for k, v in full.names.items() if v == index), str(index)),
        }

    # -- the bladed disk (the Bladed disk tab) ---------------------------------------------

    def disk_model(self, spec: DiskSpec) -> Model:
        """The shrouded disk of ``spec`` (:func:`fretwear.bladed_disk`), its blades mistuned by the
        pattern drawn at ``spec.level`` with ``spec.seed``."""
        lib = self.library
        self._tally("bladed_disk")
        delta = lib.draw_mistuning(spec.sectors, spec.level, 1, seed=spec.seed)[0] if spec.level else None
        return lib.bladed_disk(spec.sectors, engine_order=spec.engine_order, fex=spec.fex, mu=spec.mu,
                               mistuning=delta)  # fmt: skip

    def disk_frf(self, model: Model, grid: Grid, harmonics: int, wear: np.ndarray | None) -> dict[str, Any]:
        """First-harmonic amplitude and harmonics (m) of every blade tip over the frequency ``grid`` (Hz)
        at the worn depths ``wear`` (m, per shroud contact; ``None``: unworn): a tuned disk worn alike on
        one sector (:func:`fretwear.disk.sweep_sector`), else the full disk (:func:`fretwear.sweep`)."""
        from fretwear.disk.cyclic import is_tuned_disk

        omegas = 2 * np.pi * grid.values
        alike = wear is None or np.ptp(wear) <= 1e-12 * max(float(np.max(wear)), 1e-300)
        if is_tuned_disk(model) and alike:
            self._tally("sweep_sector")
            w0 = 0.0 if wear is None else float(wear[0])
            sols, how = self.library.sweep_sector(model, omegas, harmonics, wear=w0).solutions, "one sector"
        else:
            self._tally("sweep")
            sols, how = self.library.sweep(model, omegas, harmonics, wear=wear).solutions, "full disk"
        return {
            "f_hz": grid.values,
            "tips": np.array([s.amplitude[2::3] for s in sols]),
            "tip_harmonics": np.array([s.dof_harmonics[2::3] for s in sols]),
            "converged": np.array([s.converged for s in sols], dtype=bool),
            "solved_on": how,
        }

    def disk_history(
        self, model: Model, f_hz: float, harmonics: int, kw: float, cycles: float
    ) -> WearHistory:
        """Wear of every shroud contact at ``f_hz`` by slow-time stepping (:func:`fretwear.wear_history`,
        ``kw`` in 1/N, to ``cycles``), on DLFT at ``harmonics``."""
        self._tally("wear_history")
        return self.library.wear_history(model, 2 * np.pi * f_hz, "stepping", kw=kw, cycles=cycles,
                                         harmonics=harmonics)  # fmt: skip

    # -- a study written by ``fretwear study`` (the Study tab) ------------------------------

    def study(self, path: str, stamp: float):
        """The study stored at ``path`` (an ``xarray.Dataset`` in memory,
        :func:`fretwear.studies.store.open_study`): nothing is recomputed.

        ``stamp``, the store's modification time, makes a changed store another call (cache key).
        Raises ``ValueError`` (one line) for a missing path or a store that is not a study.
        """
        self._tally("open_study")
        return self.library.open_study(path)


_shared: dict[str, Any] = {}
_shared_lock = threading.Lock()


#: environment variable naming a module whose ``replacements()`` returns library functions by name
#: (:class:`Library`) for the server's backend: the browser tests' seam (e.g. a method that overshoots)
LIBRARY_VARIABLE = "FRETWEAR_APP_LIBRARY"


def shared_backend() -> Backend:
    """The backend of the server process (one thread pool for every session).

    With :data:`LIBRARY_VARIABLE` set, its module's ``replacements()`` replace
    some library functions (tests only).
    """
    with _shared_lock:
        if "backend" not in _shared:
            module = os.environ.get(LIBRARY_VARIABLE)
            replacements = importlib.import_module(module).replacements() if module else {}
            _shared["backend"] = Backend(**replacements)
        return _shared["backend"]


def shared_cache() -> ResultCache:
    """The result cache of the server process, shared by every session."""
    with _shared_lock:
        return _shared.setdefault("cache", ResultCache())


def shared_executor() -> ThreadPoolExecutor:
    """Threads running the sessions' requests, off the server's event loop."""
    with _shared_lock:
        if "executor" not in _shared:
            _shared["executor"] = ThreadPoolExecutor(4, thread_name_prefix="fretwear-run")
        return _shared["executor"]
