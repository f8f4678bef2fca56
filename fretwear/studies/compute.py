"""What one task of a study computes: the points of a block, each a model, a sweep or a wear history.

Every point goes through the front functions (:func:`fretwear.sweep`, :func:`fretwear.solve_periodic`,
:func:`fretwear.wear_history`), whatever the model's contacts.

:func:`compute_block` is the Dask task; every failure of a point is recorded as a status code
(:data:`STATUS`) and a message, never raised, so that a study goes on past it.

A model with contact pairs is reduced once (:func:`prepared`, at
:attr:`~fretwear.studies.spec.StudySpec.reduce_hz`); each of its points is one
:func:`fretwear.solve_periodic` (``frf``) and one :func:`fretwear.wear_history`
(``wear``) on that reduced model, with the point's ``mu`` and ``force_scale``.

The bladed disk's mistuning study (``magnification``) draws a point's pattern in the task, from the
study's seed and the point's level and sample index (``fretwear.studies.spec``), and calls
:func:`fretwear.disk.magnification` once per level of the block.
"""

from __future__ import annotations

import math
import time
import warnings
from collections.abc import Mapping
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from scipy.interpolate import CubicHermiteSpline

from ..disk import draw_mistuning, magnification
from ..front import solve_periodic, sweep, wear_history
from ..model import craig_bampton, paper_model
from ..wear import METHODS, describe, resolve_dynamics, resolve_method
from ..wear.polynomial import DEFAULT_HARMONICS as POLYNOMIAL_HARMONICS
from .spec import FRF_HARMONICS, StudySpec

__all__ = [
    "FAILED",
    "STATUS",
    "Work",
    "compute_block",
    "method_label",
    "outputs",
    "VARIABLES",
    "pair_method",
    "point_method",
    "prepared",
    "reported_dofs",
]

#: status codes of a point, in increasing severity (a point's status is the worst of its quantities')
STATUS = ("not_computed", "ok", "stuck", "horizon", "not_converged", "invalid", "error")
NOT_COMPUTED, OK, STUCK, HORIZON, NOT_CONVERGED, INVALID, ERROR = range(len(STATUS))
FAILED = (NOT_CONVERGED, INVALID, ERROR)


@dataclass(frozen=True)
class Work:
    """What every task needs: the quantities, the base model and the fixed settings (and, for a model
    with contact pairs, ``reduce_hz``: the ``f_max`` of its reduction, Hz; for the mistuning study, the
    seed, the samples per level and the disk's parameters)."""

    quantities: tuple[str, ...]
    model_kind: str
    model: Any
    fixed: dict[str, Any]
    fractions: tuple[float, ...]
    cycle_grid: np.ndarray | None
    reduce_hz: float | None = None
    depths: tuple[float, ...] = ()
    seed: int | None = None
    samples: int = 0
    disk: dict[str, Any] = field(default_factory=dict)

    @classmethod
    def of(cls, spec: StudySpec) -> Work:
        return cls(
            spec.quantities,
            spec.model_kind,
            spec.model,
            spec.fixed,
            spec.fractions,
            spec.cycle_grid() if "wear" in spec.quantities else None,
            spec.reduce_hz,
            spec.depths,
            spec.seed,
            spec.samples,
            spec.model_parameters if spec.mistuning else {},
        )

    @property
    def pairs(self) -> bool:
        """Whether the model has contact pairs."""
        return self.model.pairs is not None


def prepared(work: Work) -> Work:
    """``work`` with its model with contact pairs reduced once, by :func:`fretwear.reduce` at
    ``work.reduce_hz`` (the tasks' model; unchanged for 1-D contacts or a model reduced already)."""
    if not work.pairs or work.model.reduction is not None:
        return work
    return replace(work, model=craig_bampton(work.model, work.reduce_hz))


def reported_dofs(model) -> dict[str, int]:
    """The DOFs of the full model a study of a model with contact pairs reports, by name: its named DOFs
    (e.g. the benchmark's holder ``pad_x``, ``pad_y``), or else its loaded DOFs (``x<k>``, from 1)."""
    full = model.reduction.full if model.reduction is not None else model
    if full.names:
        return dict(sorted(full.names.items(), key=lambda item: item[1]))
    return {f"x{d + 1}": int(d) for d in full.loaded_dofs}


#: per model kind (pairs or not) and quantity, the variables and their extra dimensions
VARIABLES: dict[bool, dict[str, dict[str, tuple[str, ...]]]] = {
    False: {
        "frf": {"amplitude": ("dof",), "relative_amplitude": ("contact",),
                "sliding_distance": ("friction_contact",), "friction_energy": ("friction_contact",)},
        "wear_life": {"cycles_to": ("fraction",)},
        "wear": {"wear_fraction": ("cycles",), "wear_amplitude": ("cycles", "dof")},
        "magnification": {"magnification": (), "peak_frequency": (), "peak_blade": (), "delta": ("blade",)},
    },
    True: {  # per reported DOF (:func:`reported_dofs`) and per pair
        "frf": {"amplitude": ("dof",), "slip_distance": ("pair",), "mean_pressure": ("pair",),
                "friction_energy": ()},
        "wear_life": {"cycles_to": ("depth",)},
        "wear": {"wear_depth": ("cycles", "pair"), "wear_pressure": ("cycles", "pair"),
                 "wear_amplitude": ("cycles", "dof")},
    },
}  # fmt: skip


def outputs(work: Work) -> dict[str, tuple[tuple[str, ...], tuple[int, ...]]]:
    """Variables of the quantities (:data:`VARIABLES`): name -> (extra dimensions, extra shape)."""
    model = work.model
    if work.pairs:
        sizes = dict(dof=len(reported_dofs(model)), pair=model.n_pairs, depth=len(work.depths))
    else:
        sizes = dict(dof=model.n_dofs, contact=len(model.contacts), friction_contact=len(model.friction),
                     fraction=len(work.fractions), blade=model.n_dofs // 3)  # fmt: skip
    sizes["cycles"] = len(work.cycle_grid) if "wear" in work.quantities else 0
    return {
        name: (dims, tuple(sizes[d] for d in dims))
        for quantity, variables in VARIABLES[work.pairs].items()
        if quantity in work.quantities
        for name, dims in variables.items()
    }


def _model(work: Work, p: Mapping[str, Any]):
    """The model at one point (raises ``ValueError`` for invalid parameters)."""
    if work.pairs:  # the reduced model: a friction coefficient and a force scale change no mode
        model = work.model
        if "mu" in p:
            model = replace(model, pairs=replace(model.pairs, mu=float(p["mu"])))
        return model.scaled(p["force_scale"]) if "force_scale" in p else model
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


def point_method(model, p: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """The slow-time method that runs at a point and the options it takes, as :func:`~fretwear.wear_history`
    and ``fretwear wear`` resolve them (``auto``: the exact method where it applies)."""
    name = resolve_method(model, p["method"])
    taken = METHODS[name].options
    options = {k: p[k] for k in ("harmonics", "tol", "dynamics") if p.get(k) is not None and k in taken}
    if "dynamics" in taken:  # the dynamics that ran, not "auto"
        options["dynamics"] = resolve_dynamics(
            model, options.get("dynamics", "auto"), options.get("harmonics")
        )
    return name, options


def pair_method(p: Mapping[str, Any]) -> tuple[str, dict[str, Any]]:
    """The slow-time method that runs at a point of a model with contact pairs and its options
    (``auto`` is ``stepping``; the spec's ``tol`` is the stepping's ``rtol``)."""
    name = "stepping" if p["method"] == "auto" else p["method"]
    options = {"harmonics": int(p["harmonics"])} if "harmonics" in p else {}
    if name == "stepping" and p.get("tol") is not None:
        options["rtol"] = float(p["tol"])
    return name, options


def method_label(model, p: Mapping[str, Any]) -> str:
    """What :func:`point_method` runs, scheme and dynamics apart (:func:`fretwear.wear.describe`)."""
    name, options = point_method(model, p)
    dynamics = options.get("dynamics", "time" if name == "time" else "dlft")
    nh = options.get("harmonics", POLYNOMIAL_HARMONICS if name == "polynomial" else None)
    return describe(name, dynamics, nh)


def _wear_point(work: Work, p: Mapping[str, Any], out: dict[str, np.ndarray], i: int) -> int:
    """Wear quantities at point ``i``: fills ``out`` and returns the status code."""
    model = _model(work, p)
    name, options = point_method(model, p)
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


def _amplitudes(sol, dofs: np.ndarray) -> np.ndarray:
    """First-harmonic amplitudes (m) of the full model's DOFs ``dofs`` in the periodic solution ``sol``."""
    h = sol.dof_harmonics[dofs]
    return np.hypot(h[:, 1], h[:, 2])


def _pair_point(work: Work, p: Mapping[str, Any], out: dict[str, np.ndarray], i: int, messages) -> int:
    """Quantities of a model with contact pairs at point ``i``: fills ``out``, returns the status code."""
    model = _model(work, p)
    dofs = np.array(list(reported_dofs(model).values()), dtype=int)
    omega, code = 2 * np.pi * p["frequency"], OK
    if "frf" in work.quantities:
        sol = solve_periodic(model, omega, int(p["harmonics"]))
        if sol.converged:
            out["amplitude"][i] = _amplitudes(sol, dofs)
            out["slip_distance"][i] = sol.slip_distance
            out["mean_pressure"][i] = sol.mean_pressure
            out["friction_energy"][i] = sol.friction_energy
        else:
            code = NOT_CONVERGED
            messages.append((i, f"not converged: {sol.message} (residual {sol.residual:.3g})"))
    if "wear" in work.quantities or "wear_life" in work.quantities:
        name, options = pair_method(p)
        h = wear_history(model, omega, name, kw=p["kw"], cycles=p["cycles"], **options)
        stuck = not np.any(h.wear[-1] > 0)  # nothing slid under load: no wear, an infinite life
        if "cycles_to" in out:  # the deepest pair reaches a depth first
            life = np.array([[h.cycles_to_depth(d, k) for k in range(model.n_pairs)] for d in work.depths])
            reached = np.isfinite(life).any(axis=1)
            out["cycles_to"][i] = np.inf if stuck else np.where(reached, np.nanmin(np.where(
                np.isfinite(life), life, np.inf), axis=1), np.nan)  # fmt: skip
        if stuck:
            code = max(code, STUCK)
        elif "cycles_to" in out and np.isnan(out["cycles_to"][i]).any():
            code = max(code, HORIZON)
        grid = work.cycle_grid
        # held past the last record when the history reached its end (a converged profile), NaN if it failed
        at = None if grid is None else np.clip(grid, h.cycles[0], h.cycles[-1])
        if at is not None and len(h.cycles) > 1:
            # the depth is monotone and smooth in N: cubic Hermite with the recorded rates (WearHistory.at)
            out["wear_depth"][i] = CubicHermiteSpline(h.cycles, h.wear, h.wear_rate, axis=0)(at)
            out["wear_pressure"][i] = np.stack([np.interp(at, h.cycles, v) for v in h.pressure.T], axis=-1)
            amplitude = np.array([_amplitudes(s, dofs) for s in h.solutions])
            out["wear_amplitude"][i] = np.stack([np.interp(at, h.cycles, v) for v in amplitude.T], axis=-1)
        if not h.converged:
            for name in ("wear_depth", "wear_pressure", "wear_amplitude") if at is not None else ():
                out[name][i][grid > h.cycles[-1]] = np.nan
            messages.append((i, f"wear history stopped early: {h.status}"))
            code = max(code, NOT_CONVERGED)
    return code


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


#: integer variables and their value where not computed (the others are float, NaN there)
INTEGER_FILL = {"peak_blade": -1}


def _magnification_block(work: Work, params: Mapping[str, np.ndarray], n: int, out, status, messages) -> None:
    """The mistuning study's points (``level``, ``sample``): one :func:`fretwear.disk.magnification`
    per level of the block, on the rows ``sample`` of ``draw_mistuning(sectors, level, samples, seed)``."""
    levels = np.broadcast_to(np.asarray(params["level"], dtype=float), (n,))
    rows = np.broadcast_to(np.asarray(params["sample"], dtype=np.int64), (n,))
    sectors = work.model.n_dofs // 3
    for level in np.unique(levels):
        idx = np.flatnonzero(levels == level)
        try:
            delta = draw_mistuning(sectors, float(level), work.samples, seed=work.seed)[rows[idx]]
            res = magnification(delta, tuple(work.fixed["band"]), **work.disk)
        except Exception as exc:  # noqa: BLE001 - a failed point is recorded, never an aborted study
            status[idx] = INVALID if isinstance(exc, ValueError) else ERROR
            messages.extend((int(i), f"{type(exc).__name__}: {' '.join(str(exc).split())}") for i in idx)
            continue
        out["magnification"][idx], out["peak_frequency"][idx] = res.factor, res.frequency
        out["peak_blade"][idx], out["delta"][idx] = res.blade, delta
        status[idx] = OK


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
    out = {name: np.full((n, *shape), INTEGER_FILL.get(name, np.nan), dtype=np.int16 if name in INTEGER_FILL
                         else float) for name, (_, shape) in outputs(work).items()}  # fmt: skip
    status = np.zeros(n, dtype=np.int8)
    messages: list[tuple[int, str]] = []
    if "magnification" in work.quantities:  # the bladed disk's only quantity
        _magnification_block(work, params, n, out, status, messages)
        seconds, cpu = time.perf_counter() - start, time.process_time() - cpu
        return {**out, "status": status, "seconds": seconds, "cpu_seconds": cpu, "messages": messages}
    points = {k: np.broadcast_to(np.asarray(v), (n,)) for k, v in params.items()}
    points.update({k: np.full(n, v, dtype=object) for k, v in work.fixed.items() if k not in points})
    work = prepared(work)  # reduced once by the client already (run_study); here for a direct call
    if work.pairs:
        for i in range(n):
            try:
                status[i] = _pair_point(work, {k: v[i] for k, v in points.items()}, out, i, messages)
            except Exception as exc:  # noqa: BLE001 - a failed point is recorded, never an aborted study
                status[i] = INVALID if isinstance(exc, ValueError) else ERROR
                messages.append((i, f"{type(exc).__name__}: {' '.join(str(exc).split())}"))
    if "frf" in work.quantities and not work.pairs:
        others = [k for k in points if k != "frequency"]
        keys = [tuple(points[k][i] for k in others) for i in range(n)]
        groups: dict[tuple, list[int]] = {}
        for i, key in enumerate(keys):
            groups.setdefault(key, []).append(i)
        for idx in groups.values():
            _frf_points(work, points, np.array(idx), out, status, messages)
    if work.quantities != ("frf",) and not work.pairs:
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
