"""Direct time integration of fretting wear, with cycle jumps (the paper's reference, section 2.1.1).

This is the reference against which the slow-time methods of :mod:`fretwear.wear`
are judged. The full transient is integrated with the exact event-driven
integrator of ``fretwear.time.integrator`` (exact stick/slip), one
excitation period ``T = 2 pi / omega`` at a time, and Archard's law (paper
eq. 15, 30c) is applied at the end of every period:

    w_j <- w_j + K_w F_N,j(w_j) s_j,        F_N,j(w) = k_n,j (u0_j - w_j)  (eq. 30d),

with ``s_j`` the distance slid by contact ``j`` during the period (m): the
normal load only depends on wear, so it is constant within a period and the
integral of eq. 15 is ``F_N s``. The new load sets the slip force ``mu F_N``
of the next period; mass, damping and stiffness do not change. ``K_w`` is in
m per (N m slid), i.e. 1/N, and the slow variable is the number ``N`` of
physical cycles. This *per-period rule* (every period integrated, ``dN = 1``)
is available with ``max_jump=0``.

Cycle jumps
-----------
With ``z_j = -ln(1 - w_j / u0_j)`` the per-period rule reads
``z_j <- z_j - ln(1 - K_w k_n,j s_j)``: the rate ``dz/dN ~ K_w k_n s`` only
follows the slowly varying sliding distance (it is constant when the dynamics
do not depend on the load), and any extrapolated ``z >= 0`` maps back to
``0 <= w < u0``, so that ``F_N > 0``: a jump can never overshoot ``u0``. The run
alternates

1. a *block* of ``block`` periods integrated with the per-period rule; its mean
   increment of ``z`` per cycle is a rate sample at the block's midpoint;
2. a *jump* of ``dN`` cycles: ``z`` advances by the integral of the linear
   extrapolation of the last two rate samples (a variable-step Adams-Bashforth
   predictor, second order). The state moves with the periodic orbit,
   ``y <- y + y*(w_new) - y*(w_old)``, ``y*`` found by Newton on the period map
   (:func:`~fretwear.time.shooting.periodic_state`) from the current state:
   the deviation of the trajectory from the orbit (its lag behind the drifting
   orbit, or what is left of a transient) is kept, and no start-up transient
   is created;
3. the block after the jump gives a new rate sample; the integral over the
   jump of the quadratic through the last three samples (corrector) minus the
   predictor estimates the local error. The error is controlled *relative to
   the jump's own increment*: a jump is rejected (state restored, smaller
   ``dN``) when ``|corrector - predictor| > tol * corrector`` for some contact
   (in ``z``; errors below ``1e-3 tol u0`` on ``w`` always pass), otherwise
   accepted with the corrector's value. The next ``dN`` scales as
   ``(tol / error)^(1/2)``; a jump changes ``z`` by at most 0.5 (dense enough
   records for the cubic interpolation of :meth:`WearHistory.at`).

Why relative: an error ``delta w`` made where the wear rate is ``R`` shifts the
rest of the history ``w(N)`` by ``delta w / R`` cycles (for one contact the
slow dynamics are autonomous, so perturbations are time shifts). Bounding
each jump's error by ``tol`` times its increment ``R dN`` therefore bounds the
error on the cycle count at which any wear depth is reached by about ``tol N``,
even in the slow, strongly self-accelerating start of a sigmoidal wear curve
where an absolute bound ``tol u0`` lets errors of ``100 tol`` build up. It also
implies the absolute bound: each jump's error on ``w`` is below ``tol u0``.

The dynamics between jumps are never approximated: every integrated period is
exact, and the wear of every integrated period follows the per-period rule.
"""

from __future__ import annotations

import math
import time
import warnings
from typing import Literal

import numpy as np
from numpy.typing import ArrayLike

from ..model import Model
from ..time.integrator import integrate, period_map
from ..time.shooting import periodic_state, shooting
from .result import TWO_SCALE_LIMIT, WearHistory, check_wear_inputs

__all__ = ["integrate_wear"]

_GROWTH_MAX = 3.0  # largest growth of the jump between two jumps
_SHRINK_MIN = 0.2  # strongest reduction after a rejected jump
_SAFETY = 0.8
_FIRST_JUMP = 0.1  # first jump: z changes by about _FIRST_JUMP * sqrt(tol)
_FLOOR = 1e-3  # errors below _FLOOR * tol * u0 on w always pass
_MAX_DZ = 0.5  # largest change of z = -ln(1 - w / u0) over one jump
_NEWTON_TOL = 1e-10  # periodicity residual of the orbits that carry the state across a jump


def _integral(nodes: list[float], values: list[np.ndarray], a: float, b: float) -> np.ndarray:
    """Integral over ``[a, b]`` of the polynomial through ``(nodes, values)``, per column."""
    x = (np.asarray(nodes) - a) / (b - a)
    coef = np.linalg.solve(np.vander(x, increasing=True), np.asarray(values))
    return (b - a) * (coef.T @ (1.0 / np.arange(1, len(nodes) + 1)))


def _whole(name: str, value, low: int, allow_none: bool = False) -> int | None:
    """``value`` as an int ``>= low``; ``ValueError`` naming ``name`` otherwise."""
    if value is None and allow_none:
        return None
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < low:
        raise ValueError(
            f"{name} must be an integer >= {low}" + (" or None" if allow_none else "") + f", got {value!r}"
        )
    return int(value)


class _Run:
    """State of one run: trajectory, wear, records and counters."""

    def __init__(self, model: Model, omega: float, kw: float, y: np.ndarray, w: np.ndarray, samples: int):
        self.model, self.omega, self.kw = model, omega, kw
        self.period = 2 * np.pi / omega
        self.times = np.arange(samples) * (self.period / samples)
        self.phase = np.exp(-1j * omega * self.times)
        self.B = model.relative_map(model.friction)
        self.u0 = np.array([c.u0 for c in model.friction])
        self.y, self.w, self.N = y, w, 0
        self.periods = self.solves = 0
        self.rows: list[list] = []

    # -- wear coordinates ------------------------------------------------
    def z_of(self, w: np.ndarray) -> np.ndarray:
        """``-ln(1 - w / u0)`` per contact (``w = u0`` only after an absurd per-period wear)."""
        return -np.log1p(-np.minimum(w / self.u0, 1 - 1e-16))

    def z(self) -> np.ndarray:
        """``z`` of the current wear."""
        return self.z_of(self.w)

    def wear_of(self, z: np.ndarray) -> np.ndarray:
        """Wear depth (m) of ``z``: ``u0 (1 - exp(-z))``."""
        return -self.u0 * np.expm1(-z)

    # -- periods ---------------------------------------------------------
    def integrate_period(self, record: bool) -> tuple[np.ndarray, np.ndarray]:
        """One exact period at the current wear: ``(state at T, wear increment)``; optionally a record."""
        loads = self.model.normal_loads(self.w)
        if record:
            traj = integrate(
                self.model, self.omega, self.y, 0.0, self.period, wear=self.w, samples=self.times
            )
            y1, slid = traj.y, traj.sliding_distance
        else:
            y1, slid, _ = period_map(self.model, self.omega, self.y, wear=self.w)
        self.periods += 1
        increment = self.kw * loads * slid
        if record:
            u = traj.states[: self.model.n_dofs]
            rel = self.B @ u
            self.rows.append(
                [
                    float(self.N),
                    self.w.copy(),
                    loads,
                    increment,
                    slid,
                    2 / len(self.times) * np.abs(u @ self.phase),
                    (u.max(axis=1) - u.min(axis=1)) / 2,
                    (rel.max(axis=1) - rel.min(axis=1)) / 2,
                ]
            )
        return y1, increment

    def block(self, length: int) -> tuple[float, np.ndarray]:
        """``length`` periods with the per-period rule, the first one recorded.

        Returns the block's midpoint (cycles) and mean increment of ``z`` per cycle.
        """
        n0, z0 = self.N, self.z()
        for k in range(length):
            self.y, increment = self.integrate_period(record=k == 0)
            self.w = np.minimum(self.w + increment, self.u0)
            self.N += 1
        return n0 + length / 2, (self.z() - z0) / length

    def correct(self, delta_z: np.ndarray, row: int) -> None:
        """Add ``delta_z`` to the current ``z`` and to that of record ``row`` (jump correction)."""
        self.w = self.wear_of(self.z() + delta_z)
        rec = self.rows[row]
        rec[1] = self.wear_of(self.z_of(rec[1]) + delta_z)
        rec[2] = self.model.normal_loads(rec[1])
        rec[3] = self.kw * rec[2] * rec[4]

    def shift(self, w_new: np.ndarray) -> bool:
        """Move the state with the periodic orbit from the current wear to ``w_new``; False on failure."""
        y_old = self.orbit(self.y, self.w)
        y_new = None if y_old is None else self.orbit(y_old, w_new)
        if y_new is None:
            return False
        self.y, self.w = y_new + (self.y - y_old), w_new
        return True

    def orbit(self, y: np.ndarray, w: np.ndarray) -> np.ndarray | None:
        """Periodic state at wear ``w`` by Newton from ``y``; None if Newton fails."""
        self.solves += 1
        try:
            y_star, ok = periodic_state(self.model, self.omega, y, wear=w, tol=_NEWTON_TOL)
        except RuntimeError:  # a Newton trial state the integrator cannot resolve
            return None
        return y_star if ok else None

    def snapshot(self) -> tuple:
        """State, wear, cycle count and number of records, for :meth:`restore`."""
        return self.y.copy(), self.w.copy(), self.N, len(self.rows)

    def restore(self, snap: tuple) -> None:
        """Return to a :meth:`snapshot` (a rejected jump), dropping the later records."""
        self.y, self.w, self.N, rows = snap
        del self.rows[rows:]

    def history(
        self, status: str, converged: bool, start: float, notes: list[str], info: dict
    ) -> WearHistory:
        """The records as a :class:`~fretwear.wear.WearHistory` (``method="time"``)."""
        cols = [np.array(c) for c in zip(*self.rows, strict=True)]
        info = dict(info, periods=self.periods)
        return WearHistory(
            self.omega,
            "time",
            *cols,
            u0=self.u0,
            kn=np.array([c.kn for c in self.model.friction]),
            kw=self.kw,
            dynamics="time",
            converged=converged,
            status=status,
            solves=self.solves,
            wall_time=time.perf_counter() - start,
            warnings=notes,
            info=info,
        )


def _largest_step(N: int, nodes: list[float], rates: list[np.ndarray], limit: float) -> int:
    """Whole jump <= ``limit`` over which the extrapolated rate of ``z`` stays above half its last value.

    ``z`` may change by at most ``_MAX_DZ``, so that the records stay dense
    enough for cubic interpolation of ``w`` in the final exponential approach.
    """
    top = rates[-1].max()
    if top > 0:
        limit = min(limit, _MAX_DZ / top)
    slope = (rates[-1] - rates[-2]) / (nodes[-1] - nodes[-2])
    falling = (slope < 0) & (rates[-1] > 0)
    if falling.any():
        limit = min(limit, float(np.min(rates[-1][falling] / (2 * -slope[falling]))) - (N - nodes[-1]))
    return max(math.floor(limit), 0)


def _jump(run: _Run, nodes: list[float], rates: list[np.ndarray], step: int, block: int, tol: float):
    """Jump ``step`` cycles, then integrate a block of ``block`` periods.

    Predictor: integral of the line through the last two rate samples;
    corrector: of the quadratic through them and the sample of the new block.
    Returns the error ratio ``max |corrector - predictor| / (tol corrector)`` (in ``z``):
    accepted (corrector kept, sample appended) when <= 1, otherwise the run is
    restored to its state before the jump. Returns None, with the run
    unchanged, when the periodic orbit could not be followed.
    """
    snap = run.snapshot()
    N0, z0 = run.N, run.z()
    predicted = np.maximum(_integral(nodes[-2:], rates[-2:], N0, N0 + step), 0.0)
    z1 = z0 + predicted
    if not run.shift(run.wear_of(z1)):
        return None
    run.N += step
    row = len(run.rows)
    mid, rate = run.block(block)
    corrected = np.maximum(_integral([*nodes[-2:], mid], [*rates[-2:], rate], N0, N0 + step), 0.0)
    scale = np.maximum(corrected, _FLOOR * np.exp(z1))  # the step's increment of z, floored
    ratio = float(np.max(np.abs(corrected - predicted) / scale)) / tol
    if ratio > 1:
        run.restore(snap)
    else:
        run.correct(corrected - predicted, row)
        nodes.append(mid)
        rates.append(rate)
    return ratio


def integrate_wear(
    model: Model,
    omega: float,
    cycles: float,
    *,
    kw: float,
    wear0: ArrayLike | None = None,
    tol: float = 1e-3,
    max_jump: int | None = None,
    block: int = 3,
    start: Literal["periodic", "rest"] = "periodic",
    settle_periods: int | None = None,
    stop_fraction: float = 0.99,
    record_every: int | None = None,
    samples: int = 256,
) -> WearHistory:
    """Wear evolution at one frequency by direct time integration with cycle jumps.

    See the module docstring for the method. Records are taken at the first
    period of every block: a record at ``N`` holds the wear after ``N``
    cycles and the sliding distance, wear increment and response amplitudes
    of cycle ``N + 1`` (from ``samples`` uniform samples of that period). The
    first record is at ``N = 0`` and the last one at the end of the run.

    Parameters
    ----------
    model : Model
        Structure with friction contacts only (``M`` positive definite), each
        with ``u0 > 0`` and ``mu > 0``.
    omega : float
        Excitation angular frequency (rad/s), > 0.
    cycles : float
        Horizon: number of cycles, a whole number >= 1.
    kw : float
        Archard coefficient ``K_w`` (m per N per m slid, i.e. 1/N), >= 0.
    wear0 : array_like, shape (n_friction,), optional
        Initial wear depths (m), ``0 <= wear0 < u0``; default zero.
    tol : float
        Relative local error of a cycle jump: its error on the increment of
        ``z = -ln(1 - w / u0)`` over the jump is below ``tol`` times that
        increment, in (0, 1). The cycle counts at which given wear depths are
        reached then carry a relative error of about ``tol`` or less (on the
        paper model, ``tol = 1e-3`` gives about ``1e-4``).
    max_jump : int, optional
        Largest cycle jump (cycles); default unlimited. ``max_jump=0``
        disables the jumps: every period is integrated (the per-period rule,
        ``dN = 1``).
    block : int
        Periods integrated between two jumps (>= 1).
    start : {"periodic", "rest"}
        Start from the periodic orbit of the initial wear state (shooting; no
        start-up transient), or from rest (``u = v = 0`` at ``t = 0``).
    settle_periods : int, optional
        No jump before this many cycles. Default 0 from the periodic orbit;
        from rest, the periods the slowest decaying Floquet mode of the
        initial periodic orbit needs to fall below ``tol`` (the start-up
        transient is integrated in full; no jump if that orbit has no
        multiplier inside the unit circle).
    stop_fraction : float
        Stop once every contact has ``w >= stop_fraction * u0``, in (0, 1].
    record_every : int, optional
        Periods between records when ``max_jump=0``; default about 200 records
        over the horizon or over ``u0 / (initial wear per cycle)`` cycles if
        shorter. With jumps every block is recorded.
    samples : int
        Uniform samples per recorded period (>= 4) for the amplitudes.

    Returns
    -------
    WearHistory
        ``method="time"``. ``status`` is ``"horizon"``, ``"worn"``, ``"stuck"``
        (the initial periodic orbit never slides: ``w = 0`` for all ``N``,
        returned at once) or ``"failed: ..."`` (an integration failed; records
        up to there are kept, ``converged=False``). ``solves`` counts the
        Newton solves on the period map; ``info`` holds ``periods``
        (integrated periods, recorded ones included), ``jumps``,
        ``rejected_jumps``, ``largest_jump`` (cycles), ``settle_periods`` and
        ``initial_orbit_converged``.
    """
    clock = time.perf_counter()
    if isinstance(omega, bool) or not isinstance(omega, (int, float, np.integer, np.floating)):
        raise ValueError(f"omega must be a finite angular frequency > 0 rad/s, got {omega!r}")
    if not (np.isfinite(omega) and omega > 0):
        raise ValueError(f"omega must be a finite angular frequency > 0 rad/s, got {omega!r}")
    check_wear_inputs(model, kw, cycles)
    if cycles != math.floor(cycles):
        raise ValueError(f"cycles (horizon) must be a whole number of cycles >= 1, got {cycles!r}")
    if not 0 < tol < 1:
        raise ValueError(f"tol (relative error of a cycle jump) must be in (0, 1), got {tol!r}")
    if not 0 < stop_fraction <= 1:
        raise ValueError(f"stop_fraction must be in (0, 1], got {stop_fraction!r}")
    if start not in ("periodic", "rest"):
        raise ValueError(f"start must be 'periodic' or 'rest', got {start!r}")
    max_jump = _whole("max_jump", max_jump, 0, allow_none=True)
    block = _whole("block", block, 1)
    settle_periods = _whole("settle_periods", settle_periods, 0, allow_none=True)
    record_every = _whole("record_every", record_every, 1, allow_none=True)
    samples = _whole("samples", samples, 4)
    for j, c in enumerate(model.friction):
        if c.mu <= 0:
            raise ValueError(
                f"friction[{j}].mu must be > 0 for wear: the integrator does not track the sliding "
                f"of a contact without slip force, got {c.mu!r}"
            )
    u0 = np.array([c.u0 for c in model.friction])
    w = np.zeros(len(u0)) if wear0 is None else np.array(wear0, dtype=float)
    if w.shape != u0.shape or not np.all(np.isfinite(w)) or np.any(w < 0) or np.any(w >= u0):
        raise ValueError(
            f"wear0 must hold one depth per friction contact with 0 <= wear0 < u0 (m), got {wear0!r}"
        )
    cycles = int(cycles)
    omega = float(omega)

    orbit = shooting(model, omega, wear=w, samples=4)
    notes = [] if orbit.converged else ["the shooting of the initial periodic orbit did not converge"]
    per_cycle = float(np.max(kw * orbit.normal_loads * orbit.sliding_distance / u0))
    if per_cycle > TWO_SCALE_LIMIT:
        notes.append(
            f"wear per cycle at the start is {per_cycle:.3g} u0 > {TWO_SCALE_LIMIT:g} u0: the normal load "
            "changes noticeably within a cycle and the per-period Archard rule is coarse; lower kw"
        )
        warnings.warn(notes[-1], RuntimeWarning, stacklevel=2)
    if settle_periods is None:
        settle_periods = 0
        if start == "rest":
            inside = np.abs(orbit.floquet_multipliers)
            inside = inside[inside < 1 - 1e-9]
            slowest = inside.max(initial=0.0)
            settle_periods = (
                cycles if inside.size == 0 else math.ceil(math.log(tol) / math.log(max(slowest, tol)))
            )
    run = _Run(model, omega, kw, orbit.y0 if start == "periodic" else np.zeros(2 * model.n_dofs), w, samples)
    info = {
        "jumps": 0,
        "rejected_jumps": 0,
        "largest_jump": 0,
        "settle_periods": settle_periods,
        "initial_orbit_converged": orbit.converged,
    }

    if start == "periodic" and not np.any(orbit.sliding_distance > 0):
        run.integrate_period(record=True)
        run.rows.append([float(cycles), *run.rows[0][1:]])
        return run.history("stuck", True, clock, notes, info)

    jumps = max_jump is None or max_jump > 0
    if record_every is None:  # about 200 records over the horizon or the time to wear u0 at the initial rate
        record_every = max(1, round(min(cycles, 1 / per_cycle if per_cycle > 0 else cycles) / 200))
    length = block if jumps else record_every
    nodes: list[float] = []
    rates: list[np.ndarray] = []
    dN: float | None = None
    status, converged = "horizon", True
    try:
        while run.N < cycles and not np.all(run.w >= stop_fraction * u0):
            room = cycles - run.N - block  # a full block must follow a jump
            step = 0
            if jumps and len(rates) >= 2 and run.N >= settle_periods and room >= 1:
                if dN is None:
                    top = rates[-1].max()
                    dN = _FIRST_JUMP * math.sqrt(tol) / top if top > 0 else room
                step = _largest_step(run.N, nodes, rates, min(dN, room, max_jump or room))
            if step >= 1:
                ratio = _jump(run, nodes, rates, step, block, tol)
                if ratio is not None:
                    factor = _GROWTH_MAX if ratio == 0 else _SAFETY / math.sqrt(ratio)
                    if ratio > 1:
                        info["rejected_jumps"] += 1
                        dN = step * max(factor, _SHRINK_MIN)
                    else:
                        info["jumps"] += 1
                        info["largest_jump"] = max(info["largest_jump"], step)
                        dN = step * min(factor, _GROWTH_MAX)
                    continue
                dN = step / 2  # the orbit could not be followed: shorter jumps, after a plain block
            mid, rate = run.block(min(length, cycles - run.N))
            nodes.append(mid)
            rates.append(rate)
            if dN is not None:
                dN = max(dN, 1.0)
        if np.all(run.w >= stop_fraction * u0):
            status = "worn"
        if not run.rows or run.rows[-1][0] < run.N:
            run.integrate_period(record=True)
    except RuntimeError as exc:
        if not run.rows:
            raise
        status, converged = f"failed: {exc} (after {run.N} cycles)", False
    return run.history(status, converged, clock, notes, info)
