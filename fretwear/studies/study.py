"""Parameter studies on Dask, results in Zarr: ``fretwear study SPEC.toml --out RESULT.zarr``.

The spec (:mod:`fretwear.studies.spec`) defines the points of the study: the
outer product of its grid axes, times ``samples`` random draws when some
parameters are random. The points are cut into rectangular blocks, one Dask
task each (:func:`compute_block`); the tasks run on a local cluster (one
single-threaded worker process per core) or on an existing scheduler
(``--scheduler ADDRESS``), and the client writes each block into a Zarr store
as soon as it comes back.

Reading a result
----------------
``xarray.open_zarr(RESULT)`` gives the Dataset. Its dimensions are the study's
axes: ``sample`` (random draws; the drawn values are coordinates along it)
and the grid axes, by name (``frequency`` last), then the dimensions of the
quantities: ``fraction`` (``cycles_to``), ``cycles`` (the wear grid), ``dof``,
``contact`` and ``friction_contact``. Variables:

``cycles_to`` (``wear_life``)
    Cycles to ``w = fraction * u0``; ``inf`` where the contact sticks (no wear),
    NaN where the fraction is not reached within the horizon (status
    ``horizon``) or the point failed.
``wear_fraction``, ``wear_amplitude`` (``wear``)
    ``w / u0`` and first-harmonic amplitudes (m) at the cycle counts ``cycles``.
``amplitude``, ``relative_amplitude``, ``sliding_distance``, ``friction_energy`` (``frf``)
    Periodic response without wear: first-harmonic amplitude of each DOF and of
    each contact's relative displacement (m), distance slid (m) and energy
    dissipated (J) per period by each friction contact.
``status``
    Per point, the worst of its quantities' codes (:data:`STATUS`, also in the
    variable's ``flag_values`` and ``flag_meanings``): 0 not computed yet, 1 ok,
    2 stuck, 3 horizon, 4 not converged, 5 invalid parameters (e.g. a negative
    draw of ``mu``), 6 error. A point that fails is NaN with its status; the
    study goes on.
``task_seconds``
    Compute time of each task (s), NaN for a task not computed yet: the record
    of completed blocks that a rerun uses to resume.

Attributes: ``title``, ``quantities``, ``fretwear_version``, ``spec`` (the TOML
file as written), ``spec_resolved`` (JSON: every value, defaults included),
``study_key`` (its hash), ``wear_method`` (with the wear quantities and one method: what ran, the
slow-time scheme and the dynamics apart, e.g. ``"exact"`` for the exact answer, as
:func:`fretwear.wear.describe` says), ``units`` and ``long_name`` of every variable.

Resuming and failures
---------------------
Rerunning the same command after an interruption computes only the tasks
whose ``task_seconds`` is NaN (a block is marked done after its data is
written). A store made by another spec, another ``--samples`` or another
fretwear version is refused (``--overwrite`` replaces it). A worker process
that dies is replaced (by its nanny) and its tasks are rerun by the scheduler;
a task that raises is retried (``--retries``). Tasks are deterministic and the
draws seeded, so the result does not depend on the cluster, the interruptions
or the failures.
"""

from __future__ import annotations

import argparse
import json
import logging
import math
import os
import shutil
import signal
import sys
import threading
import time
import warnings
from collections.abc import Callable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..arguments import atomic, check_output, document, number
from ..hbm import sweep
from ..model import paper_model
from ..wear import METHODS, describe, resolve_dynamics, resolve_method, wear_history
from ..wear.polynomial import DEFAULT_HARMONICS as POLYNOMIAL_HARMONICS
from .spec import FRF_HARMONICS, PARAMETERS, SpecError, StudySpec, read_spec

__all__ = [
    "STATUS",
    "StudyRun",
    "Layout",
    "add_arguments",
    "compute_block",
    "open_study",
    "layout",
    "main",
    "run",
    "run_study",
    "wear_life_figure",
    "wear_life_summary",
]

EXIT_OK, EXIT_USAGE, EXIT_NOT_CONVERGED, EXIT_INTERRUPTED = 0, 2, 3, 130

#: status codes of a point, in increasing severity (a point's status is the worst of its quantities')
STATUS = ("not_computed", "ok", "stuck", "horizon", "not_converged", "invalid", "error")
NOT_COMPUTED, OK, STUCK, HORIZON, NOT_CONVERGED, INVALID, ERROR = range(len(STATUS))
FAILED = (NOT_CONVERGED, INVALID, ERROR)

#: estimated compute time of one point (s) by quantity and slow-time method, at Nh = 21 on the DLFT
#: dynamics, to size tasks; "-shooting": on the exact dynamics (exact: 1.5 ms a point once the sliding
#: table of the frequency is built, about 1 s, once per worker)
POINT_SECONDS = {"frf": 1e-3, "exact": 0.08, "exact-shooting": 0.01, "stepping": 1.0,
                 "stepping-shooting": 0.05, "polynomial": 2.0, "time": 10.0}  # fmt: skip
#: target compute time of one task (s): Dask's overhead is a few ms per task
TASK_SECONDS = 2.0
#: tasks a study is cut into at least (when it has that many points): load balance and progress
MIN_TASKS = 32


# -- layout: points -> blocks (tasks) -----------------------------------------------


@dataclass(frozen=True)
class Layout:
    """Blocks of points: the study's shape cut into chunks, one task (and one Zarr chunk) each."""

    shape: tuple[int, ...]
    chunks: tuple[int, ...]

    @property
    def grid(self) -> tuple[int, ...]:
        return tuple(-(-n // c) for n, c in zip(self.shape, self.chunks, strict=True))

    @property
    def n_tasks(self) -> int:
        return int(np.prod(self.grid, dtype=np.int64))

    def block(self, task: int) -> tuple[slice, ...]:
        """The slices of block ``task`` (C order over the chunk grid)."""
        index = np.unravel_index(task, self.grid) if self.shape else ()
        return tuple(
            slice(int(i) * c, min((int(i) + 1) * c, n))
            for i, c, n in zip(index, self.chunks, self.shape, strict=True)
        )


def _point_seconds(spec: StudySpec) -> float:
    """Estimated compute time of one point (s), from the quantities, methods and ``Nh``."""
    nh = np.max(spec.grid.get("harmonics", [spec.fixed.get("harmonics", FRF_HARMONICS)]))
    seconds = POINT_SECONDS["frf"] * max(1.0, nh / 7) if "frf" in spec.quantities else 0.0
    if spec.wear:
        methods = spec.grid["method"].tolist() if "method" in spec.grid else [spec.fixed["method"]]
        p = {**spec.fixed, "harmonics": spec.fixed.get("harmonics", spec.grid.get("harmonics", [None])[0])}
        runs = [_method(spec.model, {**p, "method": m}) for m in methods]
        seconds += np.mean([POINT_SECONDS[_cost_key(n, o)] * max(0.25, o.get("harmonics", 21) / 21)
                            for n, o in runs])  # fmt: skip
    return float(seconds)


def _cost_key(name: str, options: Mapping[str, Any]) -> str:
    """The key of :data:`POINT_SECONDS` of a method run with ``options``."""
    return f"{name}-shooting" if options.get("dynamics") == "shooting" else name


def layout(spec: StudySpec) -> Layout:
    """The study's blocks: about :data:`TASK_SECONDS` of estimated work each, and at least
    :data:`MIN_TASKS` of them; ``points_per_task`` of the spec overrides. The blocks fill the
    last axis first (``frequency``, along which an FRF is computed with warm starts).

    The layout depends on the spec only (not on the cluster), so that reruns find the same blocks.
    """
    shape, n = spec.shape, spec.n_points
    ppt = spec.points_per_task
    if ppt is None:
        ppt = min(max(1, round(TASK_SECONDS / _point_seconds(spec))), max(1, -(-n // MIN_TASKS)))
    chunks, left = [], ppt
    for size in reversed(shape):
        c = max(1, min(size, left))
        chunks.append(c)
        left = max(1, left // c)
    return Layout(tuple(shape), tuple(reversed(chunks)))


# -- what one task computes --------------------------------------------------------


@dataclass(frozen=True)
class Work:
    """What every task needs: the quantities, the base model and the fixed settings."""

    quantities: tuple[str, ...]
    model_kind: str
    model: Any
    fixed: dict[str, Any]
    fractions: tuple[float, ...]
    cycle_grid: np.ndarray | None

    @classmethod
    def of(cls, spec: StudySpec) -> Work:
        return cls(
            spec.quantities,
            spec.model_kind,
            spec.model,
            spec.fixed,
            spec.fractions,
            spec.cycle_grid() if "wear" in spec.quantities else None,
        )


def _outputs(work: Work) -> dict[str, tuple[tuple[str, ...], tuple[int, ...]]]:
    """Variables of the quantities: name -> (extra dimensions, extra shape)."""
    model = work.model
    n, nc, nf = model.n_dofs, len(model.contacts), len(model.friction)
    out: dict[str, tuple[tuple[str, ...], tuple[int, ...]]] = {}
    if "frf" in work.quantities:
        out.update(
            amplitude=(("dof",), (n,)),
            relative_amplitude=(("contact",), (nc,)),
            sliding_distance=(("friction_contact",), (nf,)),
            friction_energy=(("friction_contact",), (nf,)),
        )
    if "wear_life" in work.quantities:
        out["cycles_to"] = (("fraction",), (len(work.fractions),))
    if "wear" in work.quantities:
        nN = len(work.cycle_grid)
        out.update(wear_fraction=(("cycles",), (nN,)), wear_amplitude=(("cycles", "dof"), (nN, n)))
    return out


def _model(work: Work, p: Mapping[str, Any]):
    """The model at one point (raises ``ValueError`` for invalid parameters)."""
    if work.model_kind == "paper":
        kn = p["kn"]
        fn = p["normal_load"] if "normal_load" in p else kn * p["u0"]
        return paper_model(fex=p["fex"], mu=p["mu"], normal_load=fn, kn=kn)
    model = work.model
    changes = {k: p[k] for k in ("mu", "kn", "u0") if k in p}
    if changes:
        model = model.with_friction(**changes)
    if "normal_load" in p:  # the same initial load on every friction contact: u0 = F_N / kn per contact
        if not (math.isfinite(p["normal_load"]) and p["normal_load"] >= 0):
            raise ValueError(f"normal_load must be finite and >= 0 N, got {p['normal_load']!r}")
        friction = tuple(replace(c, u0=p["normal_load"] / c.kn) for c in model.friction)
        model = replace(model, friction=friction)
    if "force_scale" in p:
        model = model.scaled(p["force_scale"])
    return model


def _method(model, p: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """The slow-time method that runs at a point and the options it takes, as :func:`wear_history`
    and ``fretwear wear`` resolve them (``auto``: the exact method where it applies)."""
    name = resolve_method(model, p["method"])
    taken = METHODS[name].options
    options = {k: p[k] for k in ("harmonics", "tol", "dynamics") if p.get(k) is not None and k in taken}
    if "dynamics" in taken:  # the dynamics that ran, not "auto"
        options["dynamics"] = resolve_dynamics(
            model, options.get("dynamics", "auto"), options.get("harmonics")
        )
    return name, options


def _label(model, p: Mapping[str, Any]) -> str:
    """What :func:`_method` runs, scheme and dynamics apart (:func:`fretwear.wear.describe`)."""
    name, options = _method(model, p)
    dynamics = options.get("dynamics", "time" if name == "time" else "dlft")
    nh = options.get("harmonics", POLYNOMIAL_HARMONICS if name == "polynomial" else None)
    return describe(name, dynamics, nh)


def _wear_point(work: Work, p: Mapping[str, Any], out: dict[str, np.ndarray], i: int) -> int:
    """Wear quantities at point ``i``: fills ``out`` and returns the status code."""
    model = _model(work, p)
    name, options = _method(model, p)
    with warnings.catch_warnings():  # the two-scale warning: the spec chose kw and the horizon
        warnings.simplefilter("ignore")
        h = wear_history(model, 2 * np.pi * p["frequency"], name, kw=p["kw"], cycles=p["cycles"], **options)
    failed = not h.converged or h.status not in ("horizon", "worn", "stuck")
    stuck = h.status == "stuck"
    if "cycles_to" in out:
        out["cycles_to"][i] = np.inf if stuck else [h.cycles_to(f) for f in work.fractions]
    if "wear_fraction" in out:
        sampled = h.at(work.cycle_grid)
        fraction = sampled["wear"][:, 0] / h.u0[0]
        amplitude = sampled["amplitude"]
        if failed:  # the curve stops early: nothing past its end
            beyond = work.cycle_grid > h.cycles[-1]
            fraction[beyond], amplitude[beyond] = np.nan, np.nan
        out["wear_fraction"][i], out["wear_amplitude"][i] = fraction, amplitude
    if failed:
        return NOT_CONVERGED
    if stuck:
        return STUCK
    return HORIZON if "cycles_to" in out and np.isnan(out["cycles_to"][i]).any() else OK


def _frf_points(work: Work, params: Mapping[str, np.ndarray], idx: np.ndarray, out, status, messages) -> None:
    """Periodic responses at the points ``idx`` (same parameters but the frequency): one sweep."""
    p = {k: v[idx[0]] for k, v in params.items()}
    try:
        model = _model(work, p)
        swept = sweep(model, 2 * np.pi * params["frequency"][idx], int(p.get("harmonics", FRF_HARMONICS)))
    except Exception as exc:  # noqa: BLE001 - a failed point is recorded, never an aborted study
        code = INVALID if isinstance(exc, ValueError) else ERROR
        status[idx] = np.maximum(status[idx], code)
        messages.append((int(idx[0]), f"{type(exc).__name__}: {exc}"))
        return
    for i, sol in zip(idx, swept.solutions, strict=True):
        if not sol.converged:
            status[i] = max(status[i], NOT_CONVERGED)
            messages.append((int(i), f"not converged: {sol.message} (residual {sol.residual:.3g})"))
            continue
        out["amplitude"][i] = sol.amplitude
        out["relative_amplitude"][i] = sol.relative_amplitude
        out["sliding_distance"][i] = sol.sliding_distance
        out["friction_energy"][i] = sol.friction_energy
        status[i] = max(status[i], OK)


def compute_block(work: Work, params: Mapping[str, np.ndarray]) -> dict[str, Any]:
    """Compute the points of one block (a Dask task).

    Parameters
    ----------
    work : Work
        Quantities, base model and fixed settings.
    params : dict of ndarray
        The varying parameters at each point of the block (flattened, C order).

    Returns
    -------
    dict
        One array per variable (points first), ``status`` (codes of :data:`STATUS`),
        ``seconds`` (compute time), ``cpu_seconds`` (CPU time of the worker process: less than
        ``seconds`` when other processes take the core) and ``messages`` (point index, reason) of
        the failures.
    """
    start, cpu = time.perf_counter(), time.process_time()
    n = len(next(iter(params.values()))) if params else 1
    points = {k: np.broadcast_to(np.asarray(v), (n,)) for k, v in params.items()}
    points.update({k: np.full(n, v, dtype=object) for k, v in work.fixed.items() if k not in points})
    out = {name: np.full((n, *shape), np.nan) for name, (_, shape) in _outputs(work).items()}
    status = np.zeros(n, dtype=np.int8)
    messages: list[tuple[int, str]] = []
    if "frf" in work.quantities:
        others = [k for k in points if k != "frequency"]
        keys = [tuple(points[k][i] for k in others) for i in range(n)]
        groups: dict[tuple, list[int]] = {}
        for i, key in enumerate(keys):
            groups.setdefault(key, []).append(i)
        for idx in groups.values():
            _frf_points(work, points, np.array(idx), out, status, messages)
    if work.quantities != ("frf",):
        for i in range(n):
            p = {k: v[i] for k, v in points.items()}
            try:
                code = _wear_point(work, p, out, i)
            except Exception as exc:  # noqa: BLE001 - a failed point is recorded, never an aborted study
                code = INVALID if isinstance(exc, ValueError) else ERROR
                messages.append((i, f"{type(exc).__name__}: {' '.join(str(exc).split())}"))
            status[i] = max(status[i], code)
    seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
    return {**out, "status": status, "seconds": seconds, "cpu_seconds": cpu, "messages": messages}


# -- the store ------------------------------------------------------------------------


_UNITS = {
    "cycles_to": "cycles",
    "wear_fraction": "-",
    "wear_amplitude": "m",
    "amplitude": "m",
    "relative_amplitude": "m",
    "sliding_distance": "m",
    "friction_energy": "J",
}
_LONG_NAMES = {
    "cycles_to": "cycles to w = fraction * u0 (inf: the contact sticks; NaN: beyond the horizon or failed)",
    "wear_fraction": "wear depth over initial interference w / u0",
    "wear_amplitude": "first-harmonic amplitude of each DOF along the wear history",
    "amplitude": "first-harmonic amplitude of each DOF (no wear)",
    "relative_amplitude": "first-harmonic amplitude of each contact's relative displacement (no wear)",
    "sliding_distance": "distance slid per period by each friction contact (no wear)",
    "friction_energy": "energy dissipated per period by each friction contact (no wear)",
}


def _names(spec: StudySpec) -> dict[str, list[str]]:
    model = spec.model
    if spec.model_kind == "paper":
        return {"dof": ["x1", "x2"], "contact": ["xr"], "friction_contact": ["xr"]}
    return {
        "dof": [f"x{i + 1}" for i in range(model.n_dofs)],
        "contact": [f"xr{j + 1}" for j in range(len(model.contacts))],
        "friction_contact": [f"xr{j + 1}" for j in range(len(model.friction))],
    }


def _template(spec: StudySpec, lay: Layout):
    """The empty Dataset of the study (dask arrays: only metadata is written), and its encoding."""
    import dask.array as da
    import xarray as xr

    work = Work.of(spec)
    dims = spec.dims
    coords: dict[str, Any] = {}
    if spec.random:
        coords["sample"] = ("sample", np.arange(spec.samples), {"long_name": "random draw"})
        for name, values in spec.draws().items():
            p = PARAMETERS[name]
            coords[name] = (
                "sample",
                values,
                {"units": p.unit, "long_name": p.long_name, **spec.random[name].describe()},
            )
    for name, values in spec.grid.items():
        p = PARAMETERS[name]
        coords[name] = (name, values, {"units": p.unit, "long_name": p.long_name})
    outputs = _outputs(work)
    extra_dims = {d for d_, _ in outputs.values() for d in d_}
    if "fraction" in extra_dims:
        coords["fraction"] = ("fraction", np.array(spec.fractions), {"units": "-", "long_name": "w / u0"})
    if "cycles" in extra_dims:
        coords["cycles"] = (
            "cycles",
            spec.cycle_grid(),
            {"units": "cycles", "long_name": "vibration cycles N"},
        )
    for d, names in _names(spec).items():
        if d in extra_dims:
            coords[d] = (d, np.array(names))
    data_vars: dict[str, Any] = {}
    encoding: dict[str, Any] = {}
    for name, (extra, shape) in outputs.items():
        chunks = lay.chunks + shape
        data_vars[name] = (
            dims + extra,
            da.full(lay.shape + shape, np.nan, chunks=chunks),
            {"units": _UNITS[name], "long_name": _LONG_NAMES[name]},
        )
        encoding[name] = {"chunks": chunks}
    data_vars["status"] = (
        dims,
        np.zeros(lay.shape, dtype=np.int8),
        {
            "long_name": "status of the point",
            "flag_values": list(range(len(STATUS))),
            "flag_meanings": " ".join(STATUS),
        },
    )
    encoding["status"] = {"chunks": lay.chunks, "_FillValue": None}
    data_vars["task_seconds"] = (
        ("task",),
        np.full(lay.n_tasks, np.nan),
        {"units": "s", "long_name": "compute time of each task (NaN: not computed)"},
    )
    encoding["task_seconds"] = {"chunks": (1,)}
    resolved = spec.resolved()
    attrs = {
        "title": spec.title,
        "quantities": list(spec.quantities),
        "fretwear_version": __version__,
        "spec": spec.text,
        "spec_resolved": json.dumps(resolved, sort_keys=True),
        "study_key": spec.key(),
        "points_per_task": int(np.prod(lay.chunks, dtype=np.int64)),
        "fixed_parameters": json.dumps(spec.fixed, sort_keys=True),
        "created_by": "fretwear study",
    }
    if spec.wear and not {"method", "dynamics", "harmonics"} & set(spec.grid):
        attrs["wear_method"] = _label(spec.model, spec.fixed)
    ds = xr.Dataset(data_vars, coords=coords, attrs=attrs)
    return ds, encoding


def _create_store(spec: StudySpec, lay: Layout, out: Path) -> None:
    ds, encoding = _template(spec, lay)
    ds.to_zarr(out, mode="w", compute=False, encoding=encoding, zarr_format=2, consolidated=True)


def _open_store(spec: StudySpec, out: Path, overwrite: bool):
    """The Zarr group of the study at ``out`` (created if needed); :class:`SpecError` for another study."""
    import zarr

    if out.exists() and overwrite:
        shutil.rmtree(out) if out.is_dir() else out.unlink()
    if not out.exists():
        if not out.resolve().parent.is_dir():
            raise SpecError("--out", f"the folder of {str(out)!r} does not exist")
        _create_store(spec, layout(spec), out)
        return zarr.open_group(out, mode="r+"), False
    try:
        group = zarr.open_group(out, mode="r+")
        key = group.attrs.get("study_key")
    except Exception:  # noqa: BLE001 - anything that is not a readable store
        key = None
    if key is None:
        raise SpecError("--out", f"{str(out)!r} exists and is not a fretwear study store")
    if key != spec.key():
        old = json.loads(group.attrs["spec_resolved"])
        new = spec.resolved()
        diff = sorted(k for k in set(old) | set(new) if old.get(k) != new.get(k))
        raise SpecError(
            "--out",
            f"{str(out)!r} holds another study (differs in: {', '.join(diff)}); "
            "choose another --out, or --overwrite to replace it",
        )
    return group, True


# -- running ------------------------------------------------------------------------


@dataclass
class StudyRun:
    """What a run did.

    Attributes
    ----------
    path : Path
        The Zarr store.
    n_points, n_tasks : int
        Points and tasks of the study.
    computed : list of int
        Tasks computed by this run.
    resumed : int
        Tasks found done in the store.
    failed_tasks : dict of int -> str
        Tasks that failed at the Dask level (left to a rerun).
    workers : int
        Worker threads of the cluster.
    wall_time : float
        Seconds from the first task submitted to the last block written.
    compute_seconds : float
        Compute time of the tasks of this run, summed.
    cpu_seconds : float
        CPU time of the tasks of this run, summed (below ``compute_seconds`` on a busy machine).
    startup_seconds : float
        Time the workers took to import fretwear, before the clock of ``wall_time`` starts.
    status_counts : dict of str -> int
        Points per status over the whole store.
    messages : list of str
        The first failures of points (point, reason).
    """

    path: Path
    n_points: int
    n_tasks: int
    computed: list[int] = field(default_factory=list)
    resumed: int = 0
    failed_tasks: dict[int, str] = field(default_factory=dict)
    workers: int = 0
    wall_time: float = 0.0
    compute_seconds: float = 0.0
    cpu_seconds: float = 0.0
    startup_seconds: float = 0.0
    status_counts: dict[str, int] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)

    @property
    def overhead_per_task(self) -> float:
        """Worker time not spent computing, per task (s): ``(workers * wall - compute) / tasks``."""
        return (self.workers * self.wall_time - self.compute_seconds) / max(1, len(self.computed))

    @property
    def overhead_fraction(self) -> float:
        """``1 - compute / (workers * wall)``: the share of the workers' time lost to overhead and idling."""
        busy = self.workers * self.wall_time
        return 1.0 - self.compute_seconds / busy if busy > 0 else 0.0

    @property
    def complete(self) -> bool:
        return not self.failed_tasks and self.status_counts.get("not_computed", 0) == 0

    @property
    def failed_points(self) -> int:
        return sum(self.status_counts.get(STATUS[c], 0) for c in FAILED)


class Progress:
    """A progress bar on a terminal (``\\r`` updates), or a line per tenth on a file."""

    def __init__(self, total_points: int, tasks: int, stream=None, enabled: bool = True):
        self.stream = stream if stream is not None else sys.stderr
        self.total, self.tasks, self.enabled = total_points, tasks, enabled and tasks > 0
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.perf_counter()
        self.points = self.done = self.failed = self.tenth = 0

    def update(self, points: int, failed: int) -> None:
        self.done += 1
        self.points += points
        self.failed += failed
        if not self.enabled:
            return
        frac = self.done / self.tasks
        elapsed = time.perf_counter() - self.start
        eta = elapsed * (1 - frac) / frac if frac > 0 else math.nan
        bar = "#" * int(30 * frac)
        line = (
            f"[{bar:<30}] {self.done}/{self.tasks} tasks, {self.points}/{self.total} points, "
            f"{self.failed} failed, {elapsed:.1f} s, eta {eta:.0f} s"
        )
        if self.tty:
            self.stream.write("\r" + line + ("\n" if self.done == self.tasks else ""))
        elif int(10 * frac) > self.tenth or self.done == self.tasks:
            self.tenth = int(10 * frac)
            self.stream.write(line + "\n")
        self.stream.flush()


def _block_params(spec: StudySpec, lay: Layout, draws: Mapping[str, np.ndarray], task: int):
    """The varying parameters at the points of block ``task`` (flattened, C order) and the slices."""
    slices = lay.block(task)
    shape = tuple(s.stop - s.start for s in slices)
    params = {}
    for d, (dim, sl) in enumerate(zip(spec.dims, slices, strict=True)):
        axis = [1] * len(shape)
        axis[d] = shape[d]
        if dim == "sample":
            for name, values in draws.items():
                params[name] = np.broadcast_to(values[sl].reshape(axis), shape).ravel()
        else:
            params[dim] = np.broadcast_to(spec.grid[dim][sl].reshape(axis), shape).ravel()
    return params, slices, shape


@contextmanager
def _ctrl_c() -> Iterator[threading.Event]:
    """An event that Ctrl-C (SIGINT, main thread only) sets; the study stops where it checks it.

    The handler only sets the event, so that no interrupt can land inside the
    scheduler client's code (which may swallow it) or in the middle of a block's write.
    """
    pressed = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield pressed
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: pressed.set())
    try:
        yield pressed
    finally:
        signal.signal(signal.SIGINT, previous)


def _ready() -> int:
    """Nothing: run on every worker, it makes the worker import this module (and fretwear)."""
    return os.getpid()


def _start_client(scheduler: str | None, workers: int | None):
    """A Dask client: on ``scheduler``, or on a new local cluster of ``workers`` single-threaded processes."""
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            return Client(scheduler, timeout="20s", set_as_default=False), None
        except OSError as exc:
            raise SpecError("--scheduler", f"cannot reach a Dask scheduler at {scheduler!r}: {exc}") from None
    n = workers or len(os.sched_getaffinity(0))
    # Ctrl-C reaches the workers too: they start with SIGINT ignored, and the client closes them
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",  # the scheduler's HTTP server: local, a free port
            silence_logs=logging.ERROR,
        )
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    return Client(cluster, set_as_default=False), cluster


def run_study(
    spec: StudySpec,
    out: str | Path,
    *,
    client=None,
    scheduler: str | None = None,
    workers: int | None = None,
    retries: int = 2,
    overwrite: bool = False,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> StudyRun:
    """Run the study ``spec`` into the Zarr store ``out`` (created, or resumed when it holds the same study).

    Parameters
    ----------
    spec : StudySpec
        The study (:func:`fretwear.studies.spec.read_spec`).
    out : path
        Zarr store (a folder).
    client : distributed.Client, optional
        Use this client; else one on ``scheduler``, else a new local cluster of ``workers`` processes
        (default: one per core), closed at the end.
    retries : int
        Reruns of a task that raises, and resubmissions of a task the cluster loses (a worker that
        dies has its tasks rerun by the scheduler anyway, up to Dask's ``allowed-failures``).
    overwrite : bool
        Replace a store that holds another study.
    progress : bool
        Progress bar on stderr.
    log : callable, optional
        Receives the lines to print (the failures of points).

    Raises
    ------
    SpecError
        ``out`` holds another study, or is not a study store.
    KeyboardInterrupt
        Interrupted: the blocks written so far stay in the store; rerun to resume.
    """
    out = Path(out)
    connected = None
    if client is None and scheduler is not None:  # an unreachable scheduler must not leave a new store
        client, _ = connected = _start_client(scheduler, None)
    try:
        group, _ = _open_store(spec, out, overwrite)
        lay = layout(spec)
        seconds_done = np.asarray(group["task_seconds"][:])
        pending = [t for t in range(lay.n_tasks) if np.isnan(seconds_done[t])]
        result = StudyRun(out, spec.n_points, lay.n_tasks, resumed=lay.n_tasks - len(pending))
        if pending:
            _compute(spec, lay, group, pending, result, client, scheduler, workers, retries, progress, log)
    finally:
        if connected is not None:
            connected[0].close()
    status = np.asarray(group["status"][:]).ravel()
    counts = np.bincount(status.astype(np.int64), minlength=len(STATUS))
    result.status_counts = {STATUS[c]: int(counts[c]) for c in range(len(STATUS)) if counts[c]}
    return result


def _compute(spec, lay, group, pending, result, client, scheduler, workers, retries, progress, log) -> None:
    from distributed import as_completed

    own = client is None
    cluster = None
    if own:
        client, cluster = _start_client(scheduler, workers)
    futures = {}
    try:
        ready = time.perf_counter()
        client.run(_ready)  # the workers import this module (and fretwear) before the clock starts
        result.startup_seconds = time.perf_counter() - ready
        result.workers = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
        work = Work.of(spec)
        draws = spec.draws()
        bar = Progress(spec.n_points, len(pending), enabled=progress)
        start = time.perf_counter()
        blocks = {}
        lost = dict.fromkeys(pending, 0)  # resubmissions of each task after a failure outside it
        for task in pending:
            params, slices, shape = _block_params(spec, lay, draws, task)
            future = client.submit(compute_block, work, params, pure=False, retries=retries)
            futures[future] = task
            blocks[task] = (slices, shape, params)
        queue = as_completed(list(futures), loop=client.loop)
        with _ctrl_c() as pressed:
            for future in queue:
                if pressed.is_set():  # Ctrl-C: the blocks written so far are whole and marked done
                    raise KeyboardInterrupt
                task = futures.pop(future)
                slices, shape, params = blocks[task]
                if future.status != "finished":
                    # compute_block records every failure of a point, so an error here is the cluster's
                    # (a worker killed while it held the task more often than Dask allows, a lost
                    # connection): resubmit the task rather than leave a hole in the study.
                    reason = repr(future.exception()) if future.status == "error" else future.status
                    if lost[task] < retries:
                        lost[task] += 1
                        if log is not None:
                            log(f"task {task} lost ({reason}): resubmitted")
                        again = client.submit(compute_block, work, params, pure=False, retries=retries)
                        futures[again] = task
                        queue.add(again)
                        continue
                    result.failed_tasks[task] = reason
                    blocks.pop(task)
                    bar.update(0, int(np.prod(shape)))
                    continue
                blocks.pop(task)
                res = future.result()
                future.release()
                for name, values in res.items():  # Ctrl-C waits: a block is written whole, then marked done
                    if name in ("seconds", "cpu_seconds", "messages"):
                        continue
                    group[name][slices] = values.reshape(shape + values.shape[1:])
                group["task_seconds"][task : task + 1] = [res["seconds"]]
                result.computed.append(task)
                result.compute_seconds += res["seconds"]
                result.cpu_seconds += res["cpu_seconds"]
                failed = int(np.isin(res["status"], FAILED).sum())
                for i, message in res["messages"]:
                    if len(result.messages) < 20:
                        point = np.unravel_index(i, shape)
                        where = ", ".join(
                            f"{d}={s.start + int(j)}"
                            for d, s, j in zip(spec.dims, slices, point, strict=True)
                        )
                        result.messages.append(f"point ({where}): {message}")
                        if log is not None:
                            log(result.messages[-1])
                bar.update(int(np.prod(shape)), failed)
            if pressed.is_set():
                raise KeyboardInterrupt
        result.wall_time = time.perf_counter() - start
    finally:
        if futures:
            client.cancel(list(futures))
        if own:
            client.close()
            if cluster is not None:
                cluster.close()


# -- reading a result -----------------------------------------------------------------


def open_study(path: str | Path):
    """The study stored at ``path`` (a Zarr store written by ``fretwear study``), loaded into memory.

    Equivalent to ``xarray.open_zarr(path).load()`` with checks: the store
    exists, is readable, and was written by ``fretwear study`` (its
    ``created_by`` attribute and its ``status`` variable). Points not computed
    yet (status 0) are kept, NaN like failed ones.

    Raises
    ------
    ValueError
        One line naming ``path`` and what is wrong with it.
    """
    import xarray as xr

    path = Path(path)
    if not path.exists():
        raise ValueError(f"study {str(path)!r}: no such file or folder")
    try:
        ds = xr.open_zarr(path)
    except Exception as exc:  # noqa: BLE001 - anything that is not a readable Zarr store
        first = str(exc).splitlines()[0] if str(exc) else type(exc).__name__
        raise ValueError(f"study {str(path)!r}: not a readable Zarr store ({first})") from None
    if ds.attrs.get("created_by") != "fretwear study" or "status" not in ds:
        raise ValueError(
            f"study {str(path)!r}: a Zarr store but not a fretwear study (no 'created_by = fretwear study' "
            "attribute or no 'status' variable)"
        )
    return ds.load()


# -- wear life: summary and figure ---------------------------------------------------


def wear_life_summary(ds, fraction: float = 0.5) -> dict[str, float]:
    """Median and 5 / 95 % quantiles of the cycles to ``fraction * u0`` over the samples of a study.

    Points that stick count as an infinite life, points whose wear stays below
    ``fraction * u0`` at the horizon as a life beyond the horizon (``inf`` in
    the ranking too); failed or not computed points are left out. Quantiles are
    empirical (``inverted_cdf``): a quantile that falls among the infinite lives is ``inf``.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with the ``wear_life`` quantity (``xarray.open_zarr(RESULT)``), whose only
        point dimension is ``sample`` (select grid points first).

    Returns
    -------
    dict
        ``median``, ``q05``, ``q95`` (cycles), and counts ``n`` (points used), ``stuck``,
        ``beyond_horizon``, ``left_out``.
    """
    if "cycles_to" not in ds:
        raise ValueError("the study has no 'wear_life' quantity (no variable cycles_to)")
    fractions = ds["fraction"].values
    if not np.any(np.isclose(fractions, fraction)):
        raise ValueError(
            f"fraction must be one of the study's fractions {fractions.tolist()}, got {fraction!r}"
        )
    life = ds["cycles_to"].sel(fraction=fractions[np.isclose(fractions, fraction)][0])
    if set(life.dims) - {"sample"}:
        raise ValueError(f"select one point of the grid axes {sorted(set(life.dims) - {'sample'})} first")
    values = np.asarray(life.values, dtype=float).ravel()
    status = np.asarray(ds["status"].values).ravel()
    usable = np.isin(status, (OK, STUCK, HORIZON))
    ranked = np.where(np.isnan(values), np.inf, values)[usable]
    q = np.quantile(ranked, [0.5, 0.05, 0.95], method="inverted_cdf") if ranked.size else np.full(3, np.nan)
    return {
        "median": float(q[0]),
        "q05": float(q[1]),
        "q95": float(q[2]),
        "n": int(usable.sum()),
        "stuck": int((status == STUCK).sum()),
        "beyond_horizon": int((usable & (status != STUCK) & np.isnan(values)).sum()),
        "left_out": int((~usable).sum()),
    }


def wear_life_figure(ds, fraction: float = 0.5, bins: int = 40):
    """Histogram of the cycles to ``fraction * u0`` with its median and 5 / 95 % quantiles.

    Parameters
    ----------
    ds : xarray.Dataset
        As for :func:`wear_life_summary`.
    fraction : float
        Wear fraction of ``u0`` (one of the study's ``fraction`` coordinates).
    bins : int
        Log-spaced bins over the finite lives.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure  # plotting only here: the numerical core does not import it
    from matplotlib.ticker import NullFormatter

    summary = wear_life_summary(ds, fraction)
    life = ds["cycles_to"].sel(fraction=fraction, method="nearest").values.ravel()
    finite = life[np.isfinite(life)]
    fig = Figure(figsize=(7, 4.2), layout="constrained")
    ax = fig.add_subplot()
    if finite.size:
        edges = np.geomspace(finite.min(), finite.max() * 1.0001, bins + 1) if finite.min() > 0 else bins
        ax.hist(finite, bins=edges, color="#4c72b0", alpha=0.8, label=f"{finite.size} samples")
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
    styles = {"median": ("k", "-"), "q05": ("#c44e52", "--"), "q95": ("#c44e52", "--")}
    labels = {"median": "median", "q05": "5 %", "q95": "95 %"}
    for key, (color, style) in styles.items():
        value = summary[key]
        if np.isfinite(value):
            ax.axvline(value, color=color, linestyle=style, label=f"{labels[key]}: {value:.4g} cycles")
        else:
            ax.plot([], [], " ", label=f"{labels[key]}: no wear-through ({value})")
    notes = []
    if summary["stuck"]:
        notes.append(f"{summary['stuck']} stuck (no wear)")
    if summary["beyond_horizon"]:
        notes.append(f"{summary['beyond_horizon']} beyond the horizon")
    if summary["left_out"]:
        notes.append(f"{summary['left_out']} failed or not computed")
    if notes:
        ax.plot([], [], " ", label=", ".join(notes))
    ax.set_xlabel(f"cycles to w = {fraction:g} u0")
    ax.set_ylabel("samples")
    ax.set_title(str(ds.attrs.get("title", "wear life")))
    ax.legend(loc="best", fontsize="small")
    return fig


# -- command line ------------------------------------------------------------------


class _Parser(argparse.ArgumentParser):
    """Argument parser whose errors are one line on stderr and exit status 2."""

    def error(self, message: str) -> None:  # type: ignore[override]
        self.exit(EXIT_USAGE, f"{self.prog}: error: {message} (see '{self.prog} --help')\n")


def add_arguments(parser: argparse.ArgumentParser) -> None:
    """The options of ``fretwear study`` (see :func:`run`)."""
    parser.add_argument(
        "spec",
        metavar="SPEC.toml",
        help="study spec (format: fretwear.studies.spec), e.g. fretwear/data/wear_life.toml",
    )
    parser.add_argument(
        "--out",
        required=True,
        metavar="RESULT.zarr",
        help="Zarr store to write (read it with xarray.open_zarr); if it holds the same study, "
        "only what is missing is computed",
    )
    where = parser.add_mutually_exclusive_group()
    where.add_argument(
        "--scheduler",
        metavar="ADDRESS",
        help="address of a running Dask scheduler (e.g. tcp://host:8786); default: a local cluster",
    )
    where.add_argument(
        "--workers",
        type=number("workers"),
        metavar="N",
        help="worker processes of the local cluster; default: one per core",
    )
    parser.add_argument(
        "--samples",
        dest="draws",  # not "samples": the other commands' --samples is the time samples per period
        type=number("draws"),
        metavar="N",
        help="number of random draws (overrides study.samples)",
    )
    parser.add_argument(
        "--points-per-task",
        type=number("points_per_task"),
        metavar="N",
        help="points computed by one task; default: about 2 s of work, >= 32 tasks",
    )
    parser.add_argument(
        "--retries",
        type=number("retries"),
        default=2,
        metavar="N",
        help="reruns of a task that raises; default 2",
    )
    parser.add_argument("--overwrite", action="store_true", help="replace a store that holds another study")
    parser.add_argument(
        "--figure",
        metavar="FILE",
        help="wear_life: write the histogram of the cycles to 0.5 u0 (PNG, SVG or PDF)",
    )
    parser.add_argument("--quiet", action="store_true", help="no progress bar")


#: the formats of ``--figure`` (Matplotlib's, by suffix)
_FIGURE_SUFFIXES = (".png", ".svg", ".pdf")


def run(args: argparse.Namespace) -> int:
    """Run ``fretwear study`` with parsed ``args``.

    Returns
    -------
    int
        0 success; 2 bad input (one line on stderr names the key or option);
        3 some point did not converge or failed (NaN with its status in the store),
        or some task failed (rerun to complete); 130 interrupted (rerun to resume).
    """

    def say(message: str) -> None:
        print(f"fretwear study: {message}", file=sys.stderr, flush=True)

    try:
        for option, path, suffixes in (("--out", args.out, ()), ("--figure", args.figure, _FIGURE_SUFFIXES)):
            if path is not None:  # before any work: the study must not run to find it cannot be written
                try:
                    check_output(path, suffixes, folder=option == "--out")
                except ValueError as exc:
                    raise SpecError(option, str(exc)) from None
        spec = read_spec(args.spec, samples=args.draws, points_per_task=args.points_per_task)
        if args.figure is not None and "wear_life" not in spec.quantities:
            raise SpecError("--figure", "needs the quantity 'wear_life'")
        if args.figure is not None and (set(spec.dims) - {"sample"} or 0.5 not in spec.fractions):
            raise SpecError("--figure", "needs a study over random samples only, with fraction 0.5")
        lay = layout(spec)
        axes = " x ".join(f"{d} {n}" for d, n in zip(spec.dims, spec.shape, strict=True)) or "one point"
        per_task = int(np.prod(lay.chunks))
        say(
            f"{spec.title}: {spec.n_points} points ({axes}) in {lay.n_tasks} tasks of up to {per_task} points"
        )
        result = run_study(
            spec,
            args.out,
            scheduler=args.scheduler,
            workers=args.workers,
            retries=args.retries,
            overwrite=args.overwrite,
            progress=not args.quiet,
            log=say,
        )
    except SpecError as exc:
        say(f"error: {' '.join(str(exc).split())}")
        return EXIT_USAGE
    except KeyboardInterrupt:
        say(f"interrupted; the blocks computed so far are in {args.out}: rerun the same command to resume")
        return EXIT_INTERRUPTED
    counts = ", ".join(f"{k} {v}" for k, v in result.status_counts.items())
    if result.computed:
        say(
            f"computed {len(result.computed)} tasks ({result.resumed} already in the store) on "
            f"{result.workers} workers (ready in {result.startup_seconds:.1f} s) in {result.wall_time:.2f} s;"
            f" compute {result.compute_seconds:.2f} s, "
            f"overhead {result.overhead_per_task * 1e3:.1f} ms per task "
            f"({100 * result.overhead_fraction:.1f} % of the workers' time)"
        )
    else:
        say(f"all {result.n_tasks} tasks already in the store: nothing to compute")
    say(f"points: {counts}; wrote {args.out}")
    for task, reason in result.failed_tasks.items():
        say(f"task {task} failed: {reason} (rerun the same command to retry it)")
    if "wear_life" in spec.quantities and set(spec.dims) == {"sample"}:
        import xarray as xr

        ds = xr.open_zarr(args.out)
        for f in spec.fractions:
            s = wear_life_summary(ds, f)
            say(
                f"cycles to {f:g} u0: median {s['median']:.4g}, 5 % {s['q05']:.4g}, 95 % {s['q95']:.4g} "
                f"({s['n']} samples, {s['stuck']} stuck, {s['beyond_horizon']} beyond the horizon)"
            )
        if args.figure is not None:
            with atomic(args.figure) as temp:
                wear_life_figure(ds, 0.5).savefig(temp, dpi=150)
            say(f"wrote {args.figure}")
    return EXIT_OK if result.complete and not result.failed_points else EXIT_NOT_CONVERGED


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m fretwear.studies.study SPEC.toml --out RESULT.zarr [options]``; returns the exit status."""
    parser = _Parser(
        prog="fretwear study",
        description="Parameter study on Dask, results in Zarr "
        "(read with xarray.open_zarr). Exit status: 0 success, 2 bad input, 3 some point failed, "
        "130 interrupted (rerun to resume).",
    )
    add_arguments(parser)
    document(parser)
    try:
        args = parser.parse_args(argv)
    except SystemExit as exc:
        return exc.code if isinstance(exc.code, int) else EXIT_USAGE
    return run(args)


if __name__ == "__main__":  # the tasks must be this module's functions, not __main__'s
    from fretwear.studies.study import main as _main

    sys.exit(_main())
