"""Exact time-domain reference for structures with Coulomb friction contacts.

The equations of motion of a :class:`~fretwear.model.Model` (paper eq. 5, 30),

    M u'' + C u' + K u + B^T lambda(t) = F_s + F_c cos(omega t) + F_sn sin(omega t),

with ``B = model.relative_map(model.friction)`` and, for each friction contact
``j`` of slip force ``g_j = mu_j F_N,j(w_j)``, the Coulomb law

* stick: ``du_r,j/dt = 0`` and ``|lambda_j| <= g_j``,
* slip: ``lambda_j = g_j sign(du_r,j/dt)``,
* open (``g_j = 0``): ``lambda_j = 0``,

are piecewise linear: between two contact events every stuck contact is a
linear constraint and every slipping contact a constant force. This module
integrates them with a compiled **event-driven, piecewise-exact** scheme:

1. within a stick pattern the motion is the linear autonomous system
   ``X' = A_S X`` of :mod:`fretwear.time.patterns` in the augmented state
   ``X = (u, v, lambda, 1, cos omega t, sin omega t)``, propagated by its
   Taylor series over steps on which the neglected tail is below ``1e-20 |X|``;
2. on each step the guard functions (stuck force minus or plus the slip
   limit, relative velocity of a slipping contact) are polynomials: their first
   root is found with certified bounds (no event is missed, however short) and
   refined to round-off (:data:`TIME_TOL` of the period or better);
3. at each event the new contact states follow the Coulomb law at acceleration
   level (a box-constrained QP on the Delassus matrix ``B M^-1 B^T``), with a
   stated higher-order rule for contacts exactly at their limit
   (:mod:`fretwear.time.events`; the march: :mod:`fretwear.time.marching`).

Sliding distance and friction energy are exact (the relative displacement is
monotone within a slip phase); input work, viscous dissipation and the first
Fourier coefficient are Gauss-Legendre quadratures of the step polynomials,
exact to round-off. The state-transition (monodromy) matrix is the product of
the exact step propagators and the saltation matrices of the events.

**Jenkins contacts** (``FrictionContact(..., kt=...)``, a spring ``k_t`` in
series with the slider): the force ``lambda_j`` is a state, ``y = (u, v,
lambda)``; stuck, ``lambda_j' = k_t (B v)_j``; slipping, ``lambda_j = +-g_j``;
stick to slip when ``|lambda_j|`` reaches ``g_j``, slip to stick when the
relative velocity vanishes (:mod:`fretwear.time.patterns`,
:mod:`fretwear.time.marching`). No Delassus matrix and no rank condition:
the closed ring of a bladed disk's shroud is taken. The slider moves only in
slip, so the sliding distance is its travel and ``g_j`` times it the energy
dissipated.

Requirements: ``M`` positive definite (no massless DOF), no unilateral
:class:`~fretwear.model.NormalContact`, friction contacts all rigid or all
Jenkins, and linearly independent rigid contacts (``B`` of full row rank,
otherwise stuck forces are indeterminate). All quantities are in SI units.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from ..model import OPEN, SLIP, STICK, Model
from .codes import DEGENERATE, NEED_PATTERN, NEED_SPACE, OK
from .integrals import dense, orbit
from .marching import march as march_kernel
from .patterns import Engine

__all__ = [
    "STICK",
    "SLIP",
    "OPEN",
    "TIME_TOL",
    "ContactEvent",
    "Trajectory",
    "integrate",
    "period_map",
    "Engine",
    "engine",
    "engine_loads",
    "check_state",
    "march",
    "recorded",
    "make_trajectory",
    "Records",
    "clear_engines",
    "slip_forces",
]

#: event location tolerance, relative to the period (the refinement reaches round-off of a step)
TIME_TOL = 1e-14
_KINDS = ("stick", "slip", "reversal")
_PHASES_PER_PERIOD = 100_000  # more phases than this per period (or in all) is a degenerate cascade


@dataclass(frozen=True)
class ContactEvent:
    """Change of state of one friction contact.

    Attributes
    ----------
    time : float
        Event time (s).
    contact : int
        Index of the contact in ``model.friction``.
    kind : str
        ``"stick"`` (slip to stick), ``"slip"`` (stick to slip) or
        ``"reversal"`` (slip to slip in the opposite direction).
    direction : int
        Sign of the new relative velocity (+1 or -1), 0 for ``"stick"``.
    """

    time: float
    contact: int
    kind: str
    direction: int


@dataclass(frozen=True)
class _Record:
    """The recorded steps of a march: what dense output and the integrals need."""

    engine: Engine
    arrays: tuple  # the engine's pattern arrays when recorded (slots never change)
    t: np.ndarray
    length: np.ndarray
    pattern: np.ndarray
    phase: np.ndarray
    X: np.ndarray
    phase_state: np.ndarray


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Result of :func:`integrate` over ``[t0, t1]``.

    Attributes
    ----------
    t0, t1 : float
        Integration interval (s).
    y : ndarray, shape (2 n,) or (2 n + n_friction,)
        State ``(u, v)`` at ``t1``: displacements (m) and velocities (m/s);
        with Jenkins contacts ``(u, v, lambda)``, their forces (N) included.
    times : ndarray, shape (k,)
        Sample times requested with ``samples`` (s); empty if none.
    states : ndarray, shape (2 n, k)
        States at ``times``.
    contact_force : ndarray, shape (n_friction, k)
        Friction forces ``lambda`` at ``times`` (N).
    contact_state : ndarray of int8, shape (n_friction, k)
        :data:`~fretwear.model.STICK`, :data:`~fretwear.model.SLIP` or :data:`~fretwear.model.OPEN`
        at ``times``.
    segment_times : ndarray, shape (p + 1,)
        Boundaries of the ``p`` phases of constant contact states (s).
    segment_state : ndarray of int8, shape (p, n_friction)
        Contact state codes in each phase.
    segment_direction : ndarray of int8, shape (p, n_friction)
        Slip direction (+1/-1) in each phase, 0 when stuck or open.
    events : tuple of ContactEvent
        State changes inside ``(t0, t1]``, in time order.
    sliding_distance : ndarray, shape (n_friction,)
        ``integral |du_r/dt| dt`` of each contact over ``[t0, t1]`` (m).
    friction_energy : ndarray, shape (n_friction,)
        Energy dissipated by each contact, ``integral lambda du_r/dt dt`` (J).
    input_work : float
        Work of the external force, ``integral f(t) . v dt`` (J).
    viscous_dissipation : float
        ``integral v^T C v dt`` (J).
    jacobian : ndarray, shape (len(y), len(y)) or None
        State-transition matrix ``dy(t1)/dy(t0)`` including the saltation of
        every event, when requested. A perturbation of the relative velocity
        of a contact stuck at ``t0`` is absorbed at once (M-orthogonal
        projection, the first-order effect of the short slip it causes).
    fourier : complex ndarray, shape (n,)
        ``integral u(t) exp(-i omega t) dt`` of each DOF over ``[t0, t1]`` (m s),
        exact to round-off.
    """

    t0: float
    t1: float
    y: np.ndarray
    times: np.ndarray
    states: np.ndarray
    contact_force: np.ndarray
    contact_state: np.ndarray
    segment_times: np.ndarray
    segment_state: np.ndarray
    segment_direction: np.ndarray
    events: tuple[ContactEvent, ...]
    sliding_distance: np.ndarray
    friction_energy: np.ndarray
    input_work: float
    viscous_dissipation: float
    jacobian: np.ndarray | None
    _record: _Record = field(repr=False)
    fourier: np.ndarray = field(repr=False)

    def evaluate(self, times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense output: exact state, friction force and contact state at ``times``.

        Parameters
        ----------
        times : array_like, shape (k,)
            Times in ``[t0, t1]`` (s), in any order.

        Returns
        -------
        states : ndarray, shape (2 n, k)
        contact_force : ndarray, shape (n_friction, k)
        contact_state : ndarray of int8, shape (n_friction, k)
        """
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if times.ndim != 1 or not np.all(np.isfinite(times)):
            raise ValueError("times must be a finite one-dimensional array (s)")
        if times.size and (times.min() < self.t0 or times.max() > self.t1):
            raise ValueError(f"times must lie in [t0, t1] = [{self.t0}, {self.t1}]")
        order = np.argsort(times, kind="stable")
        states, forces, codes = _dense(self._record, times[order])
        out = [np.empty_like(a) for a in (states, forces, codes)]
        for o, a in zip(out, (states, forces, codes), strict=True):
            o[:, order] = a
        return out[0], out[1], out[2]


def _dense(rec: _Record, times: np.ndarray):
    steps = (rec.t, rec.length, rec.pattern, rec.phase, rec.X)
    return dense(rec.arrays, steps, rec.phase_state, len(rec.t), times)


# ---------------------------------------------------------------------------
# the engine and the march
# ---------------------------------------------------------------------------
@lru_cache(maxsize=64)
def _engine(model: Model, omega: float) -> Engine:
    return Engine(model, omega)


def clear_engines() -> None:
    """Forget the cached engines (benchmarks time the preparation of a new frequency)."""
    _engine.cache_clear()


def slip_forces(model: Model, wear) -> tuple[np.ndarray, np.ndarray]:
    """Slip forces ``mu F_N(wear)`` and normal loads ``F_N(wear)`` (N) of the friction contacts."""
    loads = model.normal_loads(wear)
    return np.array([c.mu for c in model.friction]) * loads, loads


def engine(model: Model, omega: float, wear) -> tuple[Engine, np.ndarray]:
    """The (cached) engine of ``model`` at ``omega`` (rad/s) and the slip forces ``mu F_N(wear)`` (N)."""
    eng, g, _ = engine_loads(model, omega, wear)
    return eng, g


def engine_loads(model: Model, omega: float, wear) -> tuple[Engine, np.ndarray, np.ndarray]:
    """:func:`engine` and the normal loads ``F_N(wear)`` (N)."""
    if not isinstance(model, Model):
        raise TypeError(f"model must be a fretwear.model.Model, got {type(model).__name__}")
    if isinstance(omega, bool) or not isinstance(omega, (int, float, np.integer, np.floating)):
        raise ValueError(f"omega must be a finite positive angular frequency (rad/s), got {omega!r}")
    omega = float(omega)
    if not np.isfinite(omega) or omega <= 0:
        raise ValueError(f"omega must be a finite positive angular frequency (rad/s), got {omega!r}")
    eng = _engine(model, omega)
    g, loads = slip_forces(model, wear)
    return eng, g, loads


def check_state(eng: Engine, y, name: str) -> np.ndarray:
    """``y`` as a finite state ``(u, v)`` of ``eng``'s model; ``ValueError`` naming ``name`` otherwise."""
    y = np.asarray(y, dtype=float)
    what = "(u, v, lambda) (Jenkins contacts)" if len(eng.kt) else "(u, v)"
    if y.shape != (eng.ny,) or not np.all(np.isfinite(y)):
        raise ValueError(f"{name} must be a finite state {what} of shape ({eng.ny},), got shape {y.shape}")
    return y


@dataclass(frozen=True)
class Records:
    """Buffers the compiled march records into: steps, phases and events (capacities are their lengths)."""

    st_t: np.ndarray
    st_len: np.ndarray
    st_pat: np.ndarray
    st_phase: np.ndarray
    st_X: np.ndarray
    ph_t: np.ndarray
    ph_state: np.ndarray
    ph_dir: np.ndarray
    ev_t: np.ndarray
    ev_c: np.ndarray
    ev_kind: np.ndarray
    ev_dir: np.ndarray

    @classmethod
    def empty(cls, steps: int, phases: int, dim: int, nf: int) -> Records:
        i8 = np.int64
        steps_ = (np.zeros(steps), np.zeros(steps), np.zeros(steps, i8), np.zeros(steps, i8))
        phases_ = (np.zeros(phases), np.zeros((phases, nf), np.int8), np.zeros((phases, nf), np.int8))
        events_ = (np.zeros(phases), np.zeros(phases, i8), np.zeros(phases, i8), np.zeros(phases, i8))
        return cls(*steps_, np.zeros((steps, dim)), *phases_, *events_)

    def grown(self, factor: int) -> Records:
        """Copy with ``factor`` times the capacities (the recorded content kept)."""
        out = Records.empty(factor * len(self.st_t), factor * len(self.ph_t), self.st_X.shape[1],
                            self.ph_state.shape[1])  # fmt: skip
        for name in self.__dataclass_fields__:
            a = getattr(self, name)
            getattr(out, name)[: len(a)] = a
        return out

    def packed(self) -> tuple:
        """The buffers as the kernels take them: ``(steps, phases, events)`` (:mod:`fretwear.time.codes`)."""
        return (
            (self.st_t, self.st_len, self.st_pat, self.st_phase, self.st_X),
            (self.ph_t, self.ph_state, self.ph_dir),
            (self.ev_t, self.ev_c, self.ev_kind, self.ev_dir),
        )


_NO_RECORD = Records.empty(0, 0, 0, 0)


def make_trajectory(table: Engine, i: int, rec: Records, steps: slice, phases: slice, events: slice, *,
                    t0: float, t1: float, times: np.ndarray | None, y: np.ndarray, J: np.ndarray | None,
                    sliding: np.ndarray, g: np.ndarray, work: float, viscous: float,
                    fourier: np.ndarray) -> Trajectory:  # fmt: skip
    """The :class:`Trajectory` over ``[t0, t1]`` recorded in ``rec`` for frequency ``i`` of ``table``.

    ``steps``, ``phases``, ``events``: its slices of the records (a step's
    phase index counts from ``phases.start``); ``times``: sorted sample times
    (s) of the dense output, or None.
    """
    record = _Record(table, table.table(i), rec.st_t[steps], rec.st_len[steps], rec.st_pat[steps],
                     rec.st_phase[steps], rec.st_X[steps], rec.ph_state[phases])  # fmt: skip
    n2, nf = 2 * table.n, table.nf
    times = np.zeros(0) if times is None else times
    if times.size:
        states, forces, codes = _dense(record, times)
    else:
        states, forces, codes = np.zeros((n2, 0)), np.zeros((nf, 0)), np.zeros((nf, 0), np.int8)
    return Trajectory(
        t0=float(t0),
        t1=float(t1),
        y=y,
        times=times,
        states=states,
        contact_force=forces,
        contact_state=codes,
        segment_times=np.append(rec.ph_t[phases], t1),
        segment_state=rec.ph_state[phases],
        segment_direction=rec.ph_dir[phases],
        events=tuple(
            ContactEvent(float(rec.ev_t[k]), int(rec.ev_c[k]), _KINDS[rec.ev_kind[k]], int(rec.ev_dir[k]))
            for k in range(events.start, events.stop)
        ),
        sliding_distance=sliding,
        friction_energy=g * sliding,
        input_work=float(work),
        viscous_dissipation=float(viscous),
        jacobian=J,
        _record=record,
        fourier=fourier,
    )


def _failure(status: int, t: float) -> str:
    if status == DEGENERATE:
        return f"contact states could not be resolved near t = {t!r} s (cascade of events at one instant)"
    return f"the state became non-finite near t = {t!r} s (unbounded motion)"


def _max_phases(eng: Engine, t0: float, t1: float) -> int:
    return int(_PHASES_PER_PERIOD * min(max((t1 - t0) / eng.period, 1.0), 1e4))


def march(eng: Engine, g: np.ndarray, y0: np.ndarray, t0: float, t1: float, *, jacobian: bool = False):
    """Run the compiled march (no records), building patterns on demand.

    Returns ``(status, y, J, sliding)``: ``status`` is
    :data:`~fretwear.time.codes.OK`, ``DEGENERATE`` or ``NONFINITE``.
    """
    while True:
        status, need, y, J, sliding, *_ = march_kernel(
            eng.model_arrays, eng.omega, eng.arrays(), g, y0, float(t0), float(t1), jacobian, False,
            _max_phases(eng, t0, t1), _NO_RECORD.packed(),
        )  # fmt: skip
        if status != NEED_PATTERN:
            return status, y, J, sliding
        eng.require(int(need))


_NO_ROWS = np.zeros((0, 0))


def recorded(eng: Engine, g: np.ndarray, y0: np.ndarray, t0: float, t1: float, times, *, jacobian: bool,
             rows: np.ndarray | None = None) -> tuple:  # fmt: skip
    """Recorded march from ``t0`` to ``t1`` (samples at the sorted ``times``) with its integrals.

    Returns ``(trajectory, maxima, minima)``: the extrema over
    ``[t0, t1]`` of ``rows @ u``. Raises ``RuntimeError`` when the march fails.
    """
    rows = _NO_ROWS if rows is None else rows
    steps = int(1.5 * (t1 - t0) / eng.step[0, : eng.count].min()) + 16
    buf = Records.empty(steps, 16, eng.dim, eng.nf)
    while True:
        out = orbit(eng.model_arrays, eng.omega, eng.arrays(), g, y0, float(t0), float(t1), jacobian,
                    _max_phases(eng, t0, t1), rows, buf.packed())  # fmt: skip
        status, need, y, J, sliding, ns, nph, nev, work, visc, fre, fim, hi, lo = out
        if status == NEED_PATTERN:
            eng.require(int(need))
        elif status == NEED_SPACE:
            steps = len(buf.st_t) * (4 if ns >= len(buf.st_t) else 1)
            phases = len(buf.ph_t) * (4 if max(nph, nev) >= len(buf.ph_t) else 1)
            buf = Records.empty(steps, phases, eng.dim, eng.nf)
        elif status != OK:
            raise RuntimeError(_failure(status, buf.st_t[ns - 1] if ns else t0))
        else:
            break
    traj = make_trajectory(eng, 0, buf, slice(0, ns), slice(0, nph), slice(0, nev), t0=t0, t1=t1, times=times,
                           y=y, J=J if jacobian else None, sliding=sliding, g=g, work=work, viscous=visc,
                           fourier=fre + 1j * fim)  # fmt: skip
    return traj, hi, lo


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------
def integrate(
    model: Model,
    omega: float,
    y0,
    t0: float,
    t1: float,
    *,
    wear=None,
    samples=None,
    jacobian: bool = False,
) -> Trajectory:
    """Integrate the motion exactly from ``t0`` to ``t1``.

    Parameters
    ----------
    model : Model
        Structure with friction contacts only; ``M`` positive definite.
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y0 : array_like, shape (2 n,) or (2 n + n_friction,)
        Initial state ``(u, v)`` at ``t0`` (m, m/s). A contact with zero
        relative velocity starts stuck if its stuck force lies inside the
        friction cone. With Jenkins contacts ``(u, v, lambda)``: their forces
        (N), clipped to ``+-mu F_N``; one at its limit slips if its relative
        velocity (at rest: acceleration) points along it.
    t0, t1 : float
        Start and end times (s), ``t1 >= t0``; the excitation phase is
        ``omega t``.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m); default zero.
    samples : array_like, optional
        Times in ``[t0, t1]`` (s) at which to return the state, friction
        forces and contact states (dense output).
    jacobian : bool
        Also compute the state-transition matrix ``dy(t1)/dy(t0)``.

    Returns
    -------
    Trajectory

    Raises
    ------
    RuntimeError
        When the motion becomes unbounded (non-finite state) or a cascade of
        events at one instant cannot be resolved.
    """
    eng, g = engine(model, omega, wear)
    y0 = check_state(eng, y0, "y0")
    t0, t1 = float(t0), float(t1)
    if not (np.isfinite(t0) and np.isfinite(t1) and t1 >= t0):
        raise ValueError(f"need finite times with t1 >= t0, got t0={t0!r}, t1={t1!r}")
    times = None
    if samples is not None:
        times = np.sort(np.atleast_1d(np.asarray(samples, dtype=float)))
        if times.size and (times[0] < t0 or times[-1] > t1):
            raise ValueError(f"samples must lie in [t0, t1] = [{t0}, {t1}]")
    return recorded(eng, g, y0, t0, t1, times, jacobian=jacobian)[0]


def period_map(model: Model, omega: float, y0, *, wear=None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """State after one excitation period ``T = 2 pi / omega``, starting at ``t = 0``.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y0 : array_like, shape (2 n,)
        State ``(u, v)`` at ``t = 0`` (m, m/s).
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).

    Returns
    -------
    y1 : ndarray, shape (2 n,)
        State at ``t = T``.
    sliding_distance : ndarray, shape (n_friction,)
        Distance slid by each contact over the period (m).
    friction_energy : ndarray, shape (n_friction,)
        Energy dissipated by each contact over the period (J).

    Raises
    ------
    RuntimeError
        As :func:`integrate`.
    """
    eng, g = engine(model, omega, wear)
    y0 = check_state(eng, y0, "y0")
    status, y, _, sliding = march(eng, g, y0, 0.0, eng.period)
    if status != OK:
        raise RuntimeError(_failure(status, 0.0))
    return y, sliding, g * sliding
