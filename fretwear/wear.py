"""Fretting wear on the slow time scale (paper sections 1.3, 1.6; eq. 15, 24-30).

Wear changes the dynamics only through the normal loads
``F_N,j(w_j) = k_n,j (u0_j - w_j)`` clipped at zero (eq. 30d). Archard's law
(eq. 15, 30c) over one period of the steady response gives the slow-time
equation, with ``N`` the number of physical vibration cycles,

    dw_j / dN = K_w F_N,j(w) s_j(w),

where ``s_j`` is the distance slid by contact ``j`` per period (m) in the
periodic response at wear ``w``. ``K_w`` is Archard's coefficient in m per
(N m slid), i.e. 1/Pa.

**Normalised slow time.** For a contact whose sliding distance per cycle does
not depend on the load, ``w / u0 = 1 - exp(-K_w k_n s N)``; ``K_w k_n N`` (m^-1 per
metre slid) is therefore the natural slow time, and the histories expose
``w / u0`` against ``K_w k_n N`` (:attr:`WearHistory.normalised_time`).
Results depend on ``K_w`` and ``N`` only through ``K_w N``.

**Scale separation.** The method assumes that wear barely changes over one
cycle. A warning is raised when the wear per cycle at the start exceeds
``TWO_SCALE_LIMIT * u0`` (the paper's ``K_w = 1e-6`` wears the contact through in
less than a cycle; ``K_w = 1e-11`` is a realistic default).

Two methods live here, with one result type, :class:`WearHistory`:

* :func:`wear_stepping`: slow-time stepping (eq. 24 and its natural
  improvement): an embedded Runge-Kutta pair (Bogacki-Shampine 3(2)) with a
  local error estimate on ``w``, each stage a periodic solve warm-started from
  the previous one; or the explicit per-period rule of the paper with a fixed
  step (``fixed_step=1`` is eq. 24 exactly).
* :func:`wear_polynomial`: the polynomial slow-time DLFT (eq. 25-29).

Direct time integration with wear is :func:`fretwear.wear_time.integrate_wear`.
"""

from __future__ import annotations

import time
import warnings
from dataclasses import dataclass, field
from typing import Literal

import numpy as np

from . import dlft
from .condensation import recover
from .harmonics import amplitude, extrema, full_synthesis
from .model import Model
from .periodic import LOAD, Problem, _walk, follow_normal_load, newton, solve_problem
from .results import PeriodicSolution

__all__ = [
    "WearHistory",
    "wear_stepping",
    "wear_exact",
    "exact_path_applies",
    "wear_polynomial",
    "check_wear_inputs",
    "TWO_SCALE_LIMIT",
]

#: wear per cycle, as a fraction of u0, above which the two-scale assumption is flagged
TWO_SCALE_LIMIT = 1e-2


@dataclass
class WearHistory:
    """Evolution of wear and response over the slow time ``N`` (cycles) at one frequency.

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    method : str
        ``"stepping"``, ``"polynomial"`` or ``"time"``.
    cycles : ndarray, shape (K,)
        Cycle counts ``N`` of the records.
    wear, normal_load, rate, sliding_distance : ndarray, shape (K, n_friction)
        Wear depth (m), normal load (N), wear rate ``dw/dN`` (m/cycle) and
        distance slid per cycle (m) of each friction contact.
    amplitude, half_peak_to_peak : ndarray, shape (K, n)
        First-harmonic amplitude and half peak-to-peak displacement of every DOF (m).
    relative_half_peak_to_peak : ndarray, shape (K, n_contacts)
        Half peak-to-peak relative displacement of every contact (m).
    u0, kn : ndarray, shape (n_friction,)
        Initial interference (m) and normal stiffness (N/m) of each friction contact.
    kw : float
        Archard coefficient (1/Pa).
    converged : bool
        False when a periodic solve failed and the curve stops early.
    status : str
        Why the history ends: ``"horizon"``, ``"worn"`` (every contact at
        ``stop_fraction u0``), ``"stuck"`` (full stick: no wear), or a failure.
    solves : int
        Periodic solves performed.
    wall_time : float
        Seconds spent.
    warnings : list of str
    """

    omega: float
    method: str
    cycles: np.ndarray
    wear: np.ndarray
    normal_load: np.ndarray
    rate: np.ndarray
    sliding_distance: np.ndarray
    amplitude: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    u0: np.ndarray
    kn: np.ndarray
    kw: float
    converged: bool = True
    status: str = "horizon"
    solves: int = 0
    wall_time: float = 0.0
    warnings: list[str] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    @property
    def wear_fraction(self) -> np.ndarray:
        """``w / u0`` per friction contact, shape (K, n_friction)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.u0 > 0, self.wear / self.u0, 0.0)

    @property
    def normalised_time(self) -> np.ndarray:
        """Slow time ``K_w k_n N`` per friction contact (1/m), shape (K, n_friction)."""
        return self.kw * np.outer(self.cycles, self.kn)

    def at(self, cycles) -> dict[str, np.ndarray]:
        """Records interpolated at cycle counts ``cycles`` (held constant past the end).

        Wear uses cubic Hermite interpolation with the recorded rates (it is
        monotone and smooth); other fields are interpolated linearly.
        """
        cycles = np.clip(np.asarray(cycles, dtype=float), self.cycles[0], self.cycles[-1])
        out = {"cycles": cycles, "wear": _hermite(self.cycles, self.wear, self.rate, cycles)}
        for name in ("normal_load", "rate", "sliding_distance", "amplitude", "half_peak_to_peak",
                     "relative_half_peak_to_peak"):  # fmt: skip
            values = getattr(self, name)
            out[name] = np.stack([np.interp(cycles, self.cycles, v) for v in values.T], axis=-1)
        return out

    def cycles_to(self, fraction: float, contact: int = 0) -> float:
        """Cycles at which contact ``contact`` reaches ``fraction * u0`` (nan if it does not)."""
        w = self.wear[:, contact] / self.u0[contact]
        k = np.searchsorted(w, fraction)
        if k == 0:
            return 0.0 if w[0] >= fraction else np.nan
        if k >= len(w):
            return np.nan
        # invert the Hermite interpolant on [k-1, k] by bisection
        lo, hi = self.cycles[k - 1], self.cycles[k]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            wm = _hermite(self.cycles, self.wear[:, [contact]], self.rate[:, [contact]], np.array([mid]))[
                0, 0
            ]
            lo, hi = (mid, hi) if wm / self.u0[contact] < fraction else (lo, mid)
        return 0.5 * (lo + hi)


def _hermite(x: np.ndarray, y: np.ndarray, dy: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Cubic Hermite interpolation of columns ``y`` (K, m) with slopes ``dy`` at ``xi``."""
    if len(x) == 1:
        return np.repeat(y[:1], len(xi), axis=0)
    k = np.clip(np.searchsorted(x, xi, side="right") - 1, 0, len(x) - 2)
    h = (x[k + 1] - x[k])[:, None]
    t = ((xi - x[k])[:, None] / np.where(h > 0, h, 1.0)).clip(0, 1)
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    return h00 * y[k] + h10 * h * dy[k] + h01 * y[k + 1] + h11 * h * dy[k + 1]


def check_wear_inputs(model: Model, kw: float, cycles: float, degree: int | None = None) -> None:
    """Raise ``ValueError`` naming the parameter and its valid range for bad wear inputs."""
    if not np.isfinite(kw) or kw < 0:
        raise ValueError(f"kw (Archard coefficient, 1/Pa) must be finite and >= 0, got {kw!r}")
    if not np.isfinite(cycles) or cycles <= 0:
        raise ValueError(f"cycles (horizon) must be finite and > 0, got {cycles!r}")
    if not model.friction:
        raise ValueError("the model has no friction contact: nothing can wear")
    for j, c in enumerate(model.friction):
        if c.u0 <= 0:
            raise ValueError(f"friction[{j}].u0 must be > 0 m for a wearing contact, got {c.u0!r}")
        if c.kn <= 0:
            raise ValueError(f"friction[{j}].kn must be > 0 N/m, got {c.kn!r}")
    if degree is not None and not (isinstance(degree, (int, np.integer)) and 0 <= degree <= 12):
        raise ValueError(f"degree must be an integer in [0, 12], got {degree!r}")


# -- periodic dynamics at a wear state ---------------------------------------------


class _Dynamics:
    """Periodic response at a wear state, warm-started from the previous call (DLFT or shooting)."""

    def __init__(self, model, omega, harmonics, samples, kw, dynamics):
        self.model, self.omega, self.kw, self.kind = model, omega, kw, dynamics
        self.solves = 0
        self.guess = None
        if dynamics == "dlft":
            self.problem = Problem(model, omega, harmonics, samples)
        elif dynamics != "shooting":
            raise ValueError(f"dynamics must be 'dlft' or 'shooting', got {dynamics!r}")

    def _solve(self, problem: Problem) -> PeriodicSolution:
        """Warm start: Newton from the last solution, then the exact normal-load walk, then cold."""
        last = getattr(self, "last", None)
        if self.guess is None or last is None or self.guess.shape != (problem.size,):
            return solve_problem(problem)
        res = newton(problem, self.guess, 1e-10, 8)
        path = "dlft"
        if not res.converged and problem.n_active == 1 and last.n_active == 1:
            res, path = follow_normal_load(last, self.guess, problem), "dlft-load-walk"
        if not res.converged:
            return solve_problem(problem, self.guess)
        return PeriodicSolution.build(problem, res.x, res, path)

    def __call__(self, wear: np.ndarray, keep: bool = True):
        """Return ``(rate dw/dN, sliding distance, solution)`` or ``None`` if the solve fails."""
        self.solves += 1
        loads = self.model.normal_loads(wear)
        if self.kind == "dlft":
            problem = self.problem.with_wear(wear)
            sol = self._solve(problem)
            if not sol.converged:
                return None
            if keep:
                self.guess, self.last = sol.unknowns, problem
            slid = sol.sliding_distance
        else:
            from .time_integration import shooting

            sol = shooting(self.model, self.omega, self.guess, wear=wear)
            if not sol.converged:
                return None
            if keep:
                self.guess = sol.y0
            slid = np.asarray(sol.sliding_distance)
        return self.kw * loads * slid, slid, sol


def _clip_wear(w: np.ndarray, u0: np.ndarray) -> np.ndarray:
    """Wear stays in [0, u0): the normal load relaxes to zero only asymptotically."""
    return np.clip(w, 0.0, u0 * (1 - 1e-12))


class _Recorder:
    def __init__(self):
        self.rows = []

    def add(self, N, w, rate, slid, sol, model):
        self.rows.append((N, w.copy(), model.normal_loads(w), rate.copy(), slid.copy(),
                          np.asarray(sol.amplitude), np.asarray(sol.half_peak_to_peak),
                          np.asarray(sol.relative_half_peak_to_peak)))  # fmt: skip

    def history(self, omega, method, model, kw, **status) -> WearHistory:
        cols = list(zip(*self.rows, strict=True))
        u0 = np.array([c.u0 for c in model.friction])
        kn = np.array([c.kn for c in model.friction])
        return WearHistory(omega, method, np.array(cols[0]), *(np.array(c) for c in cols[1:]),
                           u0=u0, kn=kn, kw=kw, **status)  # fmt: skip


def _two_scale_warning(rate0: np.ndarray, u0: np.ndarray) -> list[str]:
    per_cycle = float(np.max(rate0 / u0))
    if per_cycle > TWO_SCALE_LIMIT:
        msg = (
            f"wear per cycle at the start is {per_cycle:.3g} u0 > {TWO_SCALE_LIMIT:g} u0: the two-scale "
            "assumption (wear barely changes over a cycle) does not hold; lower kw"
        )
        warnings.warn(msg, RuntimeWarning, stacklevel=3)
        return [msg]
    return []


def wear_stepping(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 21,
    samples: int | None = None,
    tol: float = 1e-3,
    fixed_step: float | None = None,
    dynamics: Literal["dlft", "shooting"] = "dlft",
    stop_fraction: float = 0.99,
    max_steps: int = 100_000,
) -> WearHistory:
    """Wear evolution at one frequency by stepping on the slow time (eq. 24 and RK23).

    Parameters
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s).
    kw : float
        Archard coefficient (1/Pa), >= 0.
    cycles : float
        Horizon (cycles), > 0.
    harmonics, samples : int
        Harmonic balance settings of the DLFT periodic solves.
    tol : float
        Local error tolerance on ``w`` per step, as a fraction of ``u0``.
    fixed_step : float, optional
        Explicit Euler with this step (cycles) instead of the adaptive pair;
        ``fixed_step=1`` is the paper's per-period update (eq. 24).
    dynamics : {"dlft", "shooting"}
        Periodic solver: HBM + DLFT, or exact shooting in the time domain.
    stop_fraction : float
        Stop when every contact reaches ``stop_fraction * u0``.
    max_steps : int
        Step budget.
    """
    check_wear_inputs(model, kw, cycles)
    if not 0 < tol < 1:
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    if fixed_step is not None and not (np.isfinite(fixed_step) and fixed_step > 0):
        raise ValueError(f"fixed_step must be > 0 cycles, got {fixed_step!r}")
    start = time.perf_counter()
    u0 = np.array([c.u0 for c in model.friction])
    dyn = _Dynamics(model, omega, harmonics, samples, kw, dynamics)
    rec = _Recorder()
    w = np.zeros(len(model.friction))
    first = dyn(w)
    if first is None:
        raise RuntimeError("the periodic solve of the unworn structure failed")
    g, slid, sol = first
    rec.add(0.0, w, g, slid, sol, model)
    method = "stepping"

    def done(**kw_):
        return rec.history(omega, method, model, kw, solves=dyn.solves,
                           wall_time=time.perf_counter() - start, warnings=notes, **kw_)  # fmt: skip

    if not np.any(g > 0):
        notes = []
        rec.add(float(cycles), w, g, slid, sol, model)
        return done(status="stuck")
    notes = _two_scale_warning(g, u0)
    N = 0.0
    h = float(fixed_step) if fixed_step else min(cycles, tol * u0.max() / g.max())
    for _ in range(max_steps):
        if N >= cycles:
            return done(status="horizon")
        if np.all(w >= stop_fraction * u0):
            return done(status="worn")
        h = min(h, cycles - N)
        if fixed_step:
            w_new = _clip_wear(w + h * g, u0)
            nxt = dyn(w_new)
            if nxt is None:
                return done(converged=False, status=f"periodic solve failed at N = {N + h:g}")
        else:  # Bogacki-Shampine 3(2), first same as last
            stages = []
            for a in ((0.5,), (0.0, 0.75)):
                ws = _clip_wear(w + h * sum(c * k for c, k in zip(a, [g, *stages], strict=False)), u0)
                r = dyn(ws, keep=False)
                if r is None:
                    break
                stages.append(r[0])
            nxt = None
            if len(stages) == 2:
                k2, k3 = stages
                w_new = _clip_wear(w + h * (2 * g + 3 * k2 + 4 * k3) / 9, u0)
                nxt = dyn(w_new)
            if nxt is None:
                h *= 0.5  # a failed periodic solve: retry with a smaller step, then give up
                if h < 1e-6 * max(cycles, 1.0):
                    return done(converged=False, status=f"periodic solve failed near N = {N:g}")
                continue
            err = h * np.abs(-5 * g / 72 + k2 / 12 + k3 / 9 - nxt[0] / 8)
            ratio = float(np.max(err / (tol * u0)))
            h_next = h * min(5.0, max(0.2, 0.9 * ratio ** (-1 / 3) if ratio > 0 else 5.0))
            if ratio > 1:
                h = h_next
                continue
        w, N = w_new, N + h
        g, slid, sol = nxt
        rec.add(N, w, g, slid, sol, model)
        if not fixed_step:
            h = h_next
    return done(converged=False, status=f"step budget of {max_steps} exhausted at N = {N:g}")


# -- exact slow-time integration along the load path (one friction contact) ----------------


def exact_path_applies(model: Model) -> bool:
    """True when :func:`wear_exact` applies: one friction contact, no unilateral contact."""
    return len(model.friction) == 1 and not model.normal


def wear_exact(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 21,
    samples: int | None = None,
    stop_fraction: float = 0.99,
    max_records: int = 100,
) -> WearHistory:
    """Wear evolution with no slow-time discretisation error, for one friction contact.

    With one friction contact and no unilateral contact the DLFT equations are
    positively homogeneous in the forces and the friction limit, so the
    response at normal load ``F_N = F_N0 / sigma`` is ``1 / sigma`` times the
    response at ``F_N0`` under the forces scaled by ``sigma``. Wear relaxes the
    load along ``sigma = u0 / (u0 - w)``, and Archard's law becomes

        dN = d sigma / (K_w k_n s(sigma)),

    with ``s(sigma)`` the distance slid per cycle at load factor ``sigma`` and
    ``F_N0``. The exact piecewise-linear load walk gives the whole path from
    ``sigma = 1`` to ``1 / (1 - stop_fraction)`` in one pass; ``s`` is linear on
    each piece, so ``N(sigma)`` integrates in closed form (a logarithm per
    piece). This is stepping in the limit of zero tolerance, at the cost of one
    walk. Records are ``max_records`` points evenly spread in wear plus up to
    as many of the path's breakpoints (where the stick/slip pattern changes);
    ``x`` being linear in ``sigma`` on each piece, every record is exact.

    Parameters are those of :func:`wear_stepping`.
    """
    check_wear_inputs(model, kw, cycles)
    if not exact_path_applies(model):
        raise ValueError("wear_exact needs exactly one friction contact and no unilateral contact")
    if not 0 < stop_fraction < 1:
        raise ValueError(f"stop_fraction must be in (0, 1), got {stop_fraction!r}")
    start = time.perf_counter()
    contact = model.friction[0]
    u0, kn = contact.u0, contact.kn
    problem = Problem(model, omega, harmonics, samples)
    sol0 = solve_problem(problem)
    if not sol0.converged:
        raise RuntimeError(f"the periodic solve of the unworn structure failed: {sol0.message}")
    arrays = dict(u0=np.array([u0]), kn=np.array([kn]), kw=kw)
    if sol0.path in ("linear-stuck", "linear-open") or sol0.sliding_distance[0] == 0:
        rows = _observables(problem, np.repeat(sol0.unknowns[None], 2, axis=0), np.ones(2))
        load0 = np.full((2, 1), contact.normal_load())
        return WearHistory(omega, "exact", np.array([0.0, cycles]), np.zeros((2, 1)), load0,
                           np.zeros((2, 1)), np.zeros((2, 1)), *rows, **arrays, status="stuck", solves=1,
                           wall_time=time.perf_counter() - start)  # fmt: skip
    sigma_end = 1.0 / (1.0 - stop_fraction)
    _, _, pieces, arrived, xs, sig, slid = _walk(problem, sol0.unknowns, 1.0, sigma_end, LOAD, problem.F0,
                                                  np.zeros(0), 200_000, record=200_001)  # fmt: skip
    if len(sig) < 2:
        raise RuntimeError("the load walk of the wearing contact failed at its start")
    # N(sigma): exact integral of d sigma / (kw kn s) with s linear between breakpoints
    ds, dslid = np.diff(sig), np.diff(slid)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = slid[1:] / slid[:-1]
        dn = np.where(np.abs(dslid) > 1e-12 * slid[:-1], ds * np.log(ratio) / dslid, ds / slid[:-1])
    N = np.concatenate([[0.0], np.cumsum(dn)]) / (kw * kn)
    status = "worn" if arrived else f"load walk stopped after {pieces} pieces"
    sigma_stop = sig[-1]
    if N[-1] > cycles:  # the horizon comes first: sigma at N = cycles, by bisection on the piece's law
        k = int(np.searchsorted(N, cycles))
        a, b = sig[k - 1], sig[k]
        for _ in range(60):
            m = 0.5 * (a + b)
            n_m = N[k - 1] + _piece_cycles(sig[k - 1], m, slid[k - 1], _lerp(sig, slid, k - 1, m)) / (kw * kn)
            a, b = (m, b) if n_m < cycles else (a, m)
        sigma_stop, status = 0.5 * (a + b), "horizon"
    # records: evenly spread in wear, plus the breakpoints where the stick/slip pattern changes
    w_stop = 1.0 - 1.0 / sigma_stop
    targets = 1.0 / (1.0 - np.linspace(0.0, w_stop, max_records))
    breaks = sig[sig <= sigma_stop]
    targets = np.unique(np.concatenate([targets, breaks[_spread(1.0 - 1.0 / breaks, max_records)]]))
    k = np.clip(np.searchsorted(sig, targets, side="right") - 1, 0, len(sig) - 2)
    t = ((targets - sig[k]) / (sig[k + 1] - sig[k]))[:, None]
    xs = (1 - t) * xs[k] + t * xs[k + 1]  # exact: x is linear in sigma on each piece
    slid_t = (1 - t[:, 0]) * slid[k] + t[:, 0] * slid[k + 1]
    N = N[k] + np.array(
        [_piece_cycles(sig[j], s, slid[j], st) for j, s, st in zip(k, targets, slid_t, strict=True)]
    ) / (kw * kn)
    sig, slid = targets, slid_t
    wear = u0 * (1.0 - 1.0 / sig)
    load = kn * (u0 - wear)
    s_w = slid / sig  # homogeneity: distance slid at the actual load
    rate = kw * load * s_w
    notes = _two_scale_warning(rate[:1], np.array([u0]))
    rows = _observables(problem, xs, sig)
    return WearHistory(omega, "exact", N, wear[:, None], load[:, None], rate[:, None], s_w[:, None], *rows,
                       **arrays, status=status, solves=1, wall_time=time.perf_counter() - start,
                       warnings=notes,
                       info={"pieces": pieces})  # fmt: skip


def _piece_cycles(s1: float, s2: float, slid1: float, slid2: float) -> float:
    """``integral d sigma / s`` over one piece where ``s`` is linear (times kw kn)."""
    if abs(slid2 - slid1) <= 1e-12 * slid1:
        return (s2 - s1) / slid1
    return (s2 - s1) * np.log(slid2 / slid1) / (slid2 - slid1)


def _lerp(x: np.ndarray, y: np.ndarray, k: int, xi: float) -> float:
    """Linear interpolation of ``y`` on ``[x[k], x[k + 1]]`` at ``xi``."""
    return y[k] + (y[k + 1] - y[k]) * (xi - x[k]) / (x[k + 1] - x[k])


def _spread(w: np.ndarray, count: int) -> np.ndarray:
    """Indices of about ``count`` points spread evenly in ``w``, always keeping both ends."""
    if len(w) <= count:
        return np.arange(len(w))
    targets = np.linspace(w[0], w[-1], count)
    idx = np.unique(np.clip(np.searchsorted(w, targets), 0, len(w) - 1))
    return np.unique(np.concatenate([[0], idx, [len(w) - 1]]))


def _observables(problem: Problem, xs: np.ndarray, sigma: np.ndarray):
    """Amplitudes of every DOF and relative displacements at path points ``xs`` (load factors ``sigma``).

    The actual response is ``xs / sigma`` under the unscaled forces; the DOF
    harmonics are affine in the contact-force harmonics ``Lambda = F_r - Z_r x``,
    so one linear map recovers all points at once.
    """
    model, b = problem.model, problem.basis
    nh, n_slots = b.harmonics, b.size
    x = xs / sigma[:, None]
    lam = problem.F[None, :] - x @ problem.Z.T  # (K, nc H)
    zero = np.zeros((problem.n_active, 2 * nh + 1))
    base = recover(model, problem.B, problem.omega, nh, zero)
    unit = np.stack([recover(model, problem.B, problem.omega, nh, b.to_full(e.reshape(-1, n_slots))) - base
                     for e in np.eye(problem.size)])  # fmt: skip
    U = base[None] + np.einsum("kj,jnm->knm", lam, unit)  # (K, n, 2 Nh + 1)
    K = len(sigma)
    grid = full_synthesis(nh, 8 * nh + 8)  # a start for the exact extrema: 4 samples per shortest period
    dof = U.reshape(-1, U.shape[-1])
    hi, lo = extrema(dof, dof @ grid.T)
    rel = np.einsum("cn,knm->kcm", model.relative_map(), U).reshape(-1, U.shape[-1])
    rhi, rlo = extrema(rel, rel @ grid.T)
    return (
        amplitude(U),
        ((hi - lo) / 2).reshape(K, -1),
        ((rhi - rlo) / 2).reshape(K, -1),
    )


# -- polynomial slow-time DLFT (eq. 25-29) ---------------------------------------------


def _basis(kind: str, degree: int, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and d/dxi of the slow-time basis at ``xi`` in [-1, 1], shape (len(xi), degree + 1)."""
    if kind == "legendre":
        V = np.polynomial.legendre.legvander(xi, degree)
        D = np.stack([np.polynomial.legendre.legval(xi, np.polynomial.legendre.legder(np.eye(degree + 1)[q]))
                      for q in range(degree + 1)], axis=1)  # fmt: skip
    elif kind == "monomial":  # powers of the normalised slow time eta / N_end = (xi + 1) / 2
        s = (xi + 1) / 2
        q = np.arange(degree + 1)
        V = s[:, None] ** q
        D = np.where(q > 0, 0.5 * q * s[:, None] ** np.maximum(q - 1, 0), 0.0)
    else:
        raise ValueError(f"basis must be 'legendre' or 'monomial', got {kind!r}")
    return V, D


def wear_polynomial(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 3,
    samples: int | None = None,
    degree: int = 4,
    basis: Literal["legendre", "monomial"] = "legendre",
    tol: float = 1e-9,
    max_iter: int = 60,
    outputs: int = 101,
) -> WearHistory:
    """Wear evolution at one frequency by the polynomial slow-time DLFT (eq. 25-29).

    The harmonics ``x`` of the contact coordinates and the wear ``w`` are
    polynomials of degree ``m`` in the slow time ``eta`` in [0, cycles] (eq.
    25-27). Galerkin projection on the polynomial basis, with Gauss-Legendre
    quadrature in ``eta``, of the DLFT equations (eq. 29) and of the Archard law
    ``dw/deta = K_w F_N(w) s``, with ``w(0) = 0``, gives one nonlinear system of
    ``(m + 1) (n_c H + n_f)`` unknowns per frequency (``H = 2 Nh + 1`` slots per
    contact, fewer with half-wave symmetry), solved by Newton's method with the
    exact derivatives of the DLFT march. When Newton fails from the frozen-
    dynamics start, the horizon is grown from a short one.

    The fit is checked afterwards at ``outputs`` points: ``info["wear_defect"]``
    is the largest misfit of the Archard law integrated over the horizon, as a
    fraction of ``u0``, and ``info["poor_fit"]`` flags misfits above 2 % (the
    paper notes that polynomials cannot follow abrupt changes of the wear rate).

    Parameters
    ----------
    degree : int
        Polynomial degree ``m`` in [0, 12] (the paper uses 4).
    basis : {"legendre", "monomial"}
        Legendre polynomials on the slow interval (well conditioned, default) or
        the paper's monomials (in normalised slow time).
    Other parameters as in :func:`wear_stepping`.
    """
    check_wear_inputs(model, kw, cycles, degree)
    start = time.perf_counter()
    dyn = _Dynamics(model, omega, harmonics, samples, kw, "dlft")
    first = dyn(np.zeros(len(model.friction)))
    if first is None:
        raise RuntimeError("the periodic solve of the unworn structure failed")
    g0, slid0, sol0 = first
    u0 = np.array([c.u0 for c in model.friction])
    rec = _Recorder()
    if not np.any(g0 > 0):
        for N in (0.0, float(cycles)):
            rec.add(N, np.zeros_like(u0), g0, slid0, sol0, model)
        return rec.history(omega, "polynomial", model, kw, status="stuck", solves=1,
                           wall_time=time.perf_counter() - start)  # fmt: skip
    notes = _two_scale_warning(g0, u0)
    problem = dyn.problem
    if problem.n_active != len(model.friction) or np.any(problem.kinds != dlft.FRICTION):
        raise ValueError("wear_polynomial needs every contact to be a loaded friction contact")
    system = _PolySystem(problem, kw, degree, basis)
    x0 = sol0.unknowns
    # frozen dynamics start: x constant, w = u0 (1 - exp(-kw kn s0 eta)) projected on the basis
    result, start_kind = None, "frozen dynamics, growing horizon"
    for horizon in _horizons(cycles, g0, u0):
        guess = system.initial(x0, slid0, horizon) if result is None else system.rescale(result, horizon)
        result, ok, its, res = system.solve(guess, horizon, tol, max_iter)
        if not ok:
            break
    if not ok:  # start again from a coarse stepping solution sampled at the quadrature nodes
        coarse = wear_stepping(
            model, omega, kw=kw, cycles=cycles, harmonics=harmonics, samples=samples, tol=1e-2
        )
        result, ok, more, res = system.solve(system.from_history(coarse, cycles), cycles, tol, max_iter)
        its += more
        start_kind = "coarse stepping"
    status = "horizon" if ok else f"Newton did not converge (residual {res:.2e})"
    etas = np.linspace(0.0, cycles, outputs)
    defect = 0.0
    prev_w = None
    for eta in etas:
        x, w = system.evaluate_at(result, eta, cycles)
        p = problem.with_wear(_clip_wear(w, u0))
        sol = PeriodicSolution.build(p, x, _newton_stub(p, x), "polynomial")
        slid = sol.sliding_distance
        rate = kw * model.normal_loads(_clip_wear(w, u0)) * slid
        rec.add(eta, _clip_wear(w, u0), rate, slid, sol, model)
        if prev_w is not None:  # trapezoidal Archard integral between records vs the polynomial's increment
            prev_eta, prev_w_val, prev_rate, acc = prev_w
            acc = acc + 0.5 * (eta - prev_eta) * (rate + prev_rate)
            defect = max(defect, float(np.max(np.abs(acc - w) / u0)))
            prev_w = (eta, w, rate, acc)
        else:
            prev_w = (eta, w, rate, np.zeros_like(w))
    info = {"wear_defect": defect, "poor_fit": defect > 0.02, "iterations": its, "degree": degree,
            "basis": basis, "start": start_kind}  # fmt: skip
    if info["poor_fit"]:
        notes.append(f"polynomial fit is poor: Archard-law misfit {defect:.1%} of u0 (raise the degree)")
    hist = rec.history(omega, "polynomial", model, kw, converged=ok, status=status, solves=its,
                       wall_time=time.perf_counter() - start, warnings=notes, info=info)  # fmt: skip
    if ok and np.all(hist.wear[-1] >= 0.99 * u0):
        hist.status = "worn"
    return hist


def _horizons(cycles: float, g0: np.ndarray, u0: np.ndarray) -> list[float]:
    """Horizons for the continuation in the slow interval: from ~5 % wear up to ``cycles``."""
    short = float(np.min(0.05 * u0[g0 > 0] / g0[g0 > 0]))
    if short >= cycles:
        return [cycles]
    return list(np.geomspace(short, cycles, max(2, int(np.ceil(np.log(cycles / short) / np.log(4))) + 1)))


def _newton_stub(problem: Problem, x: np.ndarray):
    from .periodic import NewtonResult

    R = problem.evaluate(x, jacobian=False)[0]
    return NewtonResult(x, True, 0, float(np.abs(R).max() / problem.residual_scale()))


class _PolySystem:
    """Galerkin system of the polynomial slow-time DLFT for friction-only problems."""

    def __init__(self, problem: Problem, kw: float, degree: int, basis: str):
        self.p, self.kw, self.m, self.kind = problem, kw, degree, basis
        self.nq = degree + 1
        nodes, weights = np.polynomial.legendre.leggauss(max(2 * degree + 2, 4))
        self.xi, self.wq = nodes, weights
        self.V, self.D = _basis(basis, degree, nodes)  # (K, m+1)
        self.nc, self.H = problem.n_active, problem.basis.size
        self.nx = self.nc * self.H
        self.mu = np.array([c.mu for c in problem.model.friction])
        self.kn = np.array([c.kn for c in problem.model.friction])
        self.u0 = np.array([c.u0 for c in problem.model.friction])
        self.eps_diag = np.repeat(problem.eps, self.H)

    # unknowns: Cx (m+1, nx) then Cw (m+1, nc), flattened
    def split(self, y):
        return y[: self.nq * self.nx].reshape(self.nq, self.nx), y[self.nq * self.nx :].reshape(
            self.nq, self.nc
        )

    def initial(self, x0, s0, horizon):
        eta = (self.xi + 1) / 2 * horizon
        w = self.u0 * (1 - np.exp(-self.kw * self.kn * s0 * eta[:, None]))
        fit = np.linalg.lstsq(self.V, w, rcond=None)[0]
        Cx = np.zeros((self.nq, self.nx))
        Cx[:] = np.linalg.lstsq(self.V, np.tile(x0, (len(eta), 1)), rcond=None)[0]
        return np.concatenate([Cx.ravel(), fit.ravel()])

    def from_history(self, history: WearHistory, horizon: float):
        """Coefficients fitted to a stepping history at the quadrature nodes (x from fresh solves)."""
        eta = (self.xi + 1) / 2 * horizon
        w = history.at(eta)["wear"]
        xs, guess = [], None
        for wk in w:
            sol = solve_problem(self.p.with_wear(_clip_wear(wk, self.u0)), guess)
            guess = sol.unknowns
            xs.append(sol.unknowns)
        self._horizon = horizon
        return np.concatenate([np.linalg.lstsq(self.V, np.array(xs), rcond=None)[0].ravel(),
                               np.linalg.lstsq(self.V, w, rcond=None)[0].ravel()])  # fmt: skip

    def evaluate_at(self, y, eta, horizon):
        Cx, Cw = self.split(y)
        V, _ = _basis(self.kind, self.m, np.array([2 * eta / horizon - 1]))
        return V[0] @ Cx, V[0] @ Cw

    def rescale(self, y, horizon_new):
        """Re-fit a solution on a longer horizon: reuse its values at the new nodes (held past its end)."""
        Cx, Cw = self.split(y)
        eta_new = (self.xi + 1) / 2 * horizon_new
        old = self._horizon
        xi_old = np.clip(2 * eta_new / old - 1, -1, 1)
        V_old, _ = _basis(self.kind, self.m, xi_old)
        xs, ws = V_old @ Cx, V_old @ Cw
        beyond = eta_new > old
        ws[beyond] = self.u0 - (self.u0 - ws[beyond]) * np.exp(-(eta_new[beyond, None] - old) * 1e-3 / old)
        ws = np.minimum(ws, self.u0 * 0.999)
        return np.concatenate([np.linalg.lstsq(self.V, xs, rcond=None)[0].ravel(),
                               np.linalg.lstsq(self.V, ws, rcond=None)[0].ravel()])  # fmt: skip

    def residual(self, y, horizon, jacobian=True):
        p, nq, nx, nc, H = self.p, self.nq, self.nx, self.nc, self.H
        Cx, Cw = self.split(y)
        X, W = self.V @ Cx, self.V @ Cw  # values at the quadrature nodes
        dW = self.D @ Cw * (2.0 / horizon)  # d w / d eta
        K = len(self.xi)
        Rx = np.zeros((K, nx))
        Rw = np.zeros((K, nc))
        if jacobian:
            Jxx = np.zeros((K, nx, nx))
            Jxw = np.zeros((K, nx, nc))
            Jwx = np.zeros((K, nc, nx))
            Jww = np.zeros((K, nc, nc))
        phi, psi = p.basis.synthesis, p.basis.analysis
        Ns = phi.shape[0]
        lam, Xs, st = np.empty(Ns), np.empty(Ns), np.empty(Ns, dtype=np.int8)
        dlam, dsu = np.empty(Ns), np.empty(Ns)
        for k in range(K):
            wk = _clip_wear(W[k], self.u0)
            fn = np.maximum(self.kn * (self.u0 - W[k]), 0.0)
            q = p.with_wear(wk)
            R, J, *_ = q.evaluate(X[k], jacobian=jacobian)
            Rx[k] = R
            lu = q.F - q.Z @ X[k] + self.eps_diag * X[k]
            for c in range(nc):
                u = phi @ lu[c * H : (c + 1) * H]
                s, ds_dL = dlft.friction_sensitivity(u, q.limits[c], q.eps[c], p.basis.half_wave,
                                                     lam, Xs, st, dlam, dsu)  # fmt: skip
                Rw[k, c] = dW[k, c] - self.kw * fn[c] * s
                if jacobian:
                    dL_dw = -self.mu[c] * self.kn[c] if fn[c] > 0 else 0.0
                    dfn_dw = -self.kn[c] if fn[c] > 0 else 0.0
                    Jxw[k, c * H : (c + 1) * H, c] = (psi @ dlam) * dL_dw
                    # d s / d x = (d lambda_u / d x)^T Phi^T ds/du, lambda_u = F + (E - Z) x
                    ds_dlu = phi.T @ dsu
                    dlu_dx = -q.Z[c * H : (c + 1) * H, :].copy()
                    dlu_dx[:, c * H : (c + 1) * H] += q.eps[c] * np.eye(H)
                    Jwx[k, c] = -self.kw * fn[c] * (ds_dlu @ dlu_dx)
                    Jww[k, c, c] = -self.kw * (dfn_dw * s + fn[c] * ds_dL * dL_dw)
            if jacobian:
                Jxx[k] = J
        wV = self.wq[:, None] * self.V  # (K, m+1) quadrature-weighted test functions
        # dynamics: Galerkin on all m+1 test functions; wear: initial condition + m test functions
        G = np.concatenate([(wV.T @ Rx).ravel(), (self.V0 @ Cw).ravel(),
                            (wV[:, :-1].T @ Rw).ravel()])  # fmt: skip
        if not jacobian:
            return G, None
        n = y.size
        Jac = np.zeros((n, n))
        # rows: dyn (q, i) ; cols: Cx (r, j) -> sum_k wV[k,q] V[k,r] Jxx[k,i,j]
        Jac[: nq * nx, : nq * nx] = np.einsum("kq,kr,kij->qirj", wV, self.V, Jxx).reshape(nq * nx, nq * nx)
        Jac[: nq * nx, nq * nx :] = np.einsum("kq,kr,kij->qirj", wV, self.V, Jxw).reshape(nq * nx, nq * nc)
        r0 = nq * nx
        Jac[r0 : r0 + nc, nq * nx :] = np.kron(self.V0, np.eye(nc))
        r1 = r0 + nc
        Jac[r1:, : nq * nx] = np.einsum("kq,kr,kij->qirj", wV[:, :-1], self.V, Jwx).reshape(
            (nq - 1) * nc, nq * nx
        )
        dWdC = self.D * (2.0 / horizon)
        Jww_full = np.einsum("kq,kr,kij->qirj", wV[:, :-1], self.V, Jww) + np.einsum(
            "kq,kr,ij->qirj", wV[:, :-1], dWdC, np.eye(nc)
        )
        Jac[r1:, nq * nx :] = Jww_full.reshape((nq - 1) * nc, nq * nc)
        return G, Jac

    @property
    def V0(self):
        return _basis(self.kind, self.m, np.array([-1.0]))[0]  # basis at eta = 0, shape (1, m+1)

    def solve(self, y, horizon, tol, max_iter):
        self._horizon = horizon
        scale = max(self.p.residual_scale(), 1e-300)
        wscale = float(np.max(self.u0)) / horizon
        weights = np.concatenate([np.full(self.nq * self.nx, 1 / scale), np.full(self.nc, 1 / self.u0.max()),
                                  np.full((self.nq - 1) * self.nc, 1 / wscale)])  # fmt: skip
        G, Jac = self.residual(y, horizon)
        r = np.abs(G * weights).max()
        its = 0
        for its in range(1, max_iter + 1):
            if r <= tol:
                return y, True, its - 1, r
            try:
                dy = np.linalg.lstsq(Jac * weights[:, None], -G * weights, rcond=None)[0]
            except np.linalg.LinAlgError:
                return y, False, its, r
            step = 1.0
            for _ in range(20):
                yt = y + step * dy
                Gt, Jt = self.residual(yt, horizon)
                rt = np.abs(Gt * weights).max()
                if rt < r or step < 1e-3:
                    break
                step *= 0.5
            y, G, Jac, r = yt, Gt, Jt, rt
        return y, r <= tol, its, r
