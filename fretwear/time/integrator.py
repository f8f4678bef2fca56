"""Exact time-domain reference for structures with Coulomb friction contacts.

The equations of motion of a :class:`~fretwear.model.Model` (paper eq. 5, 30),

    M u'' + C u' + K u + B^T lambda(t) = F_s + F_c cos(omega t) + F_sn sin(omega t),

with ``B = model.relative_map(model.friction)`` and, for each friction contact
``j`` of slip force ``g_j = mu_j F_N,j(w_j)``, the Coulomb law

* stick: ``du_r,j/dt = 0`` and ``|lambda_j| <= g_j``,
* slip: ``lambda_j = g_j sign(du_r,j/dt)``,
* open (``g_j = 0``): ``lambda_j = 0``,

are piecewise linear: between two contact events every stuck contact is a
linear constraint ``B_S u = const`` and every slipping contact a constant force.
This module integrates them with an **event-driven, piecewise-exact** scheme:

1. in each phase (fixed stick pattern ``S`` and slip directions) the motion is
   written in the unconstrained coordinates ``u = N q + R c_S`` (``N`` an
   orthonormal basis of the null space of ``B_S``, ``c_S`` the stuck relative
   displacements) as an autonomous linear system ``X' = A X`` in an augmented
   state ``X = (q, q', c_S, lambda, 1, cos omega t, sin omega t)``, so that the
   constant and harmonic forcing are propagated exactly together with the
   structure;
2. ``X(t0 + tau) = exp(A tau) X(t0)`` is evaluated from a cached
   eigendecomposition of ``A`` (one per stick pattern), or with
   :func:`scipy.linalg.expm` when that decomposition is ill-conditioned
   (rigid-body motion, undamped resonance, defective matrices);
3. events are bracketed on a time grid (geometrically refined at the start of
   each phase) and located with :func:`scipy.optimize.brentq` to ``1e-14 T``:
   a stuck contact's force reaching ``+-g_j`` (stick to slip), a slipping
   contact's relative velocity crossing zero (stick if the force needed lies
   inside the friction cone, otherwise slip reversal);
4. at each event the new contact states are selected consistently for all
   contacts at zero relative velocity (a box-constrained quadratic problem on
   the Delassus matrix ``B M^-1 B^T``, whose solution is unique).

Sliding distance and friction energy are exact (the relative displacement is
monotone within a slip phase); input work and viscous dissipation are phase-wise
Gauss-Legendre quadratures of analytic integrands (exact to round-off). The
state-transition (monodromy) matrix is the product of the exact phase
transition matrices and the saltation matrices of the events.

Requirements: ``M`` positive definite (no massless DOF), no unilateral
:class:`~fretwear.model.NormalContact`, and linearly independent friction
contacts (``B`` of full row rank, otherwise stuck forces are indeterminate).
All quantities are in SI units.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from scipy import linalg
from scipy.optimize import brentq

from ..model import OPEN, SLIP, STICK, Model

__all__ = [
    "STICK",
    "SLIP",
    "OPEN",
    "ContactEvent",
    "Trajectory",
    "integrate",
    "period_map",
    "Engine",
    "engine",
    "check_state",
]


_GRID_PER_PERIOD = 64  # bracketing grid: at most T / 64 ...
_GRID_PER_CYCLE = 16  # ... and at most 1/16 of the fastest free cycle of the phase
_CHUNK = 64  # grid points evaluated at once
_GEOMETRIC = 2.0 ** -np.arange(40, 0, -1)  # refinement of the first grid cell of a phase
_EVENT_TOL = 1e-12  # an event function must fall below -tol * its scale to count
TIME_TOL = 1e-14  # event location tolerance, relative to the period
_MARGIN = 1e-8  # stuck force beyond the friction limit accepted at the start of a phase, relative
_COND_MAX = 1e6  # largest eigenvector condition number for the modal propagator
_MAX_NULL_PHASES = 50  # consecutive zero-length phases before giving up
_GAUSS_X, _GAUSS_W = np.polynomial.legendre.leggauss(12)


# ---------------------------------------------------------------------------
# results
# ---------------------------------------------------------------------------
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
class _Phase:
    """One interval of constant contact states: everything needed to re-evaluate it."""

    t_start: float
    t_end: float
    pattern: _Pattern
    X0: np.ndarray
    state: np.ndarray
    direction: np.ndarray


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Result of :func:`integrate` over ``[t0, t1]``.

    Attributes
    ----------
    t0, t1 : float
        Integration interval (s).
    y : ndarray, shape (2 n,)
        State ``(u, v)`` at ``t1``: displacements (m) and velocities (m/s).
    times : ndarray, shape (k,)
        Sample times requested with ``samples`` (s); empty if none.
    states : ndarray, shape (2 n, k)
        States at ``times``.
    contact_force : ndarray, shape (n_friction, k)
        Friction forces ``lambda`` at ``times`` (N).
    contact_state : ndarray of int8, shape (n_friction, k)
        :data:`STICK`, :data:`SLIP` or :data:`OPEN` at ``times``.
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
    jacobian : ndarray, shape (2 n, 2 n) or None
        State-transition matrix ``dy(t1)/dy(t0)`` including the saltation of
        every event, when requested. A perturbation of the relative velocity
        of a contact stuck at ``t0`` is absorbed at once (M-orthogonal
        projection, the first-order effect of the short slip it causes).
    fourier : complex ndarray, shape (n,)
        ``integral u(t) exp(-i omega t) dt`` of each DOF over ``[t0, t1]`` (m s), by
        phase-wise Gauss-Legendre quadrature of the exact solution.
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
    _phases: tuple[_Phase, ...] = field(repr=False)
    fourier: np.ndarray = field(repr=False)

    def evaluate(self, times) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Dense output: exact state, friction force and contact state at ``times``.

        Parameters
        ----------
        times : array_like, shape (k,)
            Times in ``[t0, t1]`` (s).

        Returns
        -------
        states : ndarray, shape (2 n, k)
        contact_force : ndarray, shape (n_friction, k)
        contact_state : ndarray of int8, shape (n_friction, k)
        """
        times = np.atleast_1d(np.asarray(times, dtype=float))
        if times.size and (times.min() < self.t0 or times.max() > self.t1):
            raise ValueError(f"times must lie in [t0, t1] = [{self.t0}, {self.t1}]")
        return _evaluate(self._phases, times)


# ---------------------------------------------------------------------------
# linear dynamics of one stick pattern
# ---------------------------------------------------------------------------
class _Pattern:
    """Exact propagator of the motion with a fixed set of stuck contacts.

    The augmented state is ``X = (q, q', c_S, lambda, 1, cos omega t, sin omega t)``
    of size ``2 m + s + n_friction + 3``, with ``u = N q + R c_S`` and
    ``v = N q'``; ``lambda`` holds the (constant) forces of the contacts that
    are not stuck. ``X' = A X`` exactly.
    """

    def __init__(self, eng: Engine, stuck: tuple[int, ...]) -> None:
        n, nf, omega = eng.n, eng.nf, eng.omega
        M, C, K, B = eng.M, eng.C, eng.K, eng.B
        s = len(stuck)
        BS = B[list(stuck)]
        if s:
            N = linalg.null_space(BS)
            R = linalg.solve(BS @ BS.T, BS, assume_a="pos").T
            MiBt = eng.Minv @ BS.T
            W = BS @ MiBt
            L = linalg.solve(W, MiBt.T, assume_a="pos")  # W^-1 B_S M^-1
            PM = np.eye(n) - MiBt @ linalg.solve(W, BS, assume_a="pos")  # M-orthogonal, onto B_S v = 0
        else:
            N, R, L, PM = np.eye(n), np.zeros((n, 0)), np.zeros((0, n)), np.eye(n)
        m = N.shape[1]
        dim = 2 * m + s + nf + 3
        self.stuck, self.dim = stuck, dim
        self.k = 2 * m + s  # size of the state part (q, q', c_S)
        self.i_lam = 2 * m + s
        self.i_one = 2 * m + s + nf
        Y = np.zeros((2 * n, dim))  # X -> full state (u, v)
        Y[:n, :m], Y[:n, 2 * m : 2 * m + s], Y[n:, m : 2 * m] = N, R, N
        fext = np.zeros((n, dim))  # X -> f(t)
        fext[:, self.i_one : self.i_one + 3] = np.column_stack(
            [eng.model.force_static, eng.model.force_cos, eng.model.force_sin]
        )
        lam = np.zeros((nf, dim))  # X -> forces of the non-stuck contacts
        lam[:, self.i_lam : self.i_lam + nf] = np.eye(nf)
        net = fext - C @ Y[n:] - K @ Y[:n] - B.T @ lam  # all forces but the stuck ones
        A = np.zeros((dim, dim))
        A[:m, m : 2 * m] = np.eye(m)
        A[m : 2 * m] = linalg.solve(N.T @ M @ N, N.T @ net, assume_a="pos")
        A[self.i_one + 1, self.i_one + 2] = -omega
        A[self.i_one + 2, self.i_one + 1] = omega
        force = lam.copy()
        force[list(stuck)] = L @ net
        self.A, self.Y, self.fext = A, Y, fext
        self.force = force  # X -> friction forces of all contacts
        self.force_rate = force @ A
        self.rel_disp = B @ Y[:n]
        self.rel_vel = B @ Y[n:]
        self.field = Y @ A  # X -> dy/dt
        self.enter = np.zeros((self.k, 2 * n))  # (u, v) -> (q, q', c_S)
        self.enter[:m, :n], self.enter[m : 2 * m, n:], self.enter[2 * m :, :n] = N.T, N.T @ PM, BS
        self.exit = Y[:, : self.k]
        eig = linalg.eigvals(A[: 2 * m, : 2 * m]) if m else np.zeros(0)
        fastest = max(np.abs(eig).max(initial=0.0), omega)
        self.h = min(eng.period / _GRID_PER_PERIOD, 2 * np.pi / (_GRID_PER_CYCLE * fastest))
        lamA, V = linalg.eig(A)
        self.modal = bool(np.all(np.isfinite(V)) and np.linalg.cond(V) < _COND_MAX)
        if self.modal:
            self.lam, self.V, self.Vinv = lamA, V, linalg.inv(V)
        self._expm: dict[float, np.ndarray] = {}

    def coords(self, y: np.ndarray, t: float, lam: np.ndarray, omega: float) -> np.ndarray:
        """Augmented state at time ``t`` of full state ``y`` and non-stuck forces ``lam``."""
        X = np.empty(self.dim)
        X[: self.k] = self.enter @ y
        X[self.i_lam : self.i_one] = lam
        X[list(self.i_lam + j for j in self.stuck)] = 0.0
        X[self.i_one :] = 1.0, math.cos(omega * t), math.sin(omega * t)
        return X

    def _exp(self, tau: float) -> np.ndarray:
        E = self._expm.get(tau)
        if E is None:
            if len(self._expm) > 4096:
                self._expm.clear()
            E = self._expm[tau] = linalg.expm(self.A * tau)
        return E

    def evaluator(self, H: np.ndarray, X0: np.ndarray):
        """Function ``taus -> H X(t0 + taus)``, shape (rows, len(taus))."""
        if self.modal:
            WH = (H @ self.V) * (self.Vinv @ X0)
            lam = self.lam
            return lambda taus: (WH @ np.exp(np.outer(lam, taus))).real
        return lambda taus: np.column_stack([H @ (self._exp(float(t)) @ X0) for t in taus])

    def scalar(self, h: np.ndarray, X0: np.ndarray):
        """Function ``tau -> h . X(t0 + tau)`` for one row ``h``."""
        if self.modal:
            w = (h @ self.V) * (self.Vinv @ X0)
            lam = self.lam
            return lambda tau: float((w @ np.exp(lam * tau)).real)
        return lambda tau: float(h @ (self._exp(float(tau)) @ X0))

    def propagate(self, X0: np.ndarray, tau: float) -> np.ndarray:
        """Augmented state after ``tau`` seconds."""
        if self.modal:
            return (self.V @ (np.exp(self.lam * tau) * (self.Vinv @ X0))).real
        return self._exp(float(tau)) @ X0

    def transition(self, tau: float) -> np.ndarray:
        """``d(q, q', c_S)(t0 + tau) / d(q, q', c_S)(t0)``."""
        k = self.k
        if self.modal:
            return ((self.V[:k] * np.exp(self.lam * tau)) @ self.Vinv[:, :k]).real
        return self._exp(float(tau))[:k, :k]


# ---------------------------------------------------------------------------
# the event-driven integrator
# ---------------------------------------------------------------------------
def _box_qp(W: np.ndarray, b: np.ndarray, g: np.ndarray) -> np.ndarray:
    """Solve ``min 1/2 x^T W x - b^T x`` subject to ``|x| <= g`` (``W`` positive definite)."""
    if len(b) == 1:
        return np.clip(b / W[0], -g, g)
    x = np.clip(linalg.solve(W, b, assume_a="pos"), -g, g)
    for _ in range(10_000):  # projected Gauss-Seidel: converges for positive definite W
        change = 0.0
        for i in range(len(b)):
            xi = min(max(x[i] + (b[i] - W[i] @ x) / W[i, i], -g[i]), g[i])
            change, x[i] = max(change, abs(xi - x[i])), xi
        if change <= 1e-15 * g.max():
            break
    bound = np.abs(x) >= g * (1 - 1e-9)  # polish: exact solve on the identified active set
    free = ~bound
    xp = np.where(bound, np.sign(x) * g, 0.0)
    if free.any():
        xp[free] = linalg.solve(W[np.ix_(free, free)], b[free] - W[np.ix_(free, bound)] @ xp[bound])
    a = b - W @ xp
    consistent = np.all(np.sign(xp[bound]) * a[bound] >= -1e-12 * np.abs(b).max())
    if consistent and np.all(np.abs(xp[free]) <= g[free]):
        return xp
    return x


class Engine:
    """Pattern cache and event-driven integrator of one model at one frequency."""

    def __init__(self, model: Model, omega: float) -> None:
        if model.normal:
            raise ValueError(
                "time_integration supports friction contacts only: unilateral normal contacts "
                f"(model.normal, {len(model.normal)} given) are not implemented"
            )
        M = model.M
        if np.linalg.eigvalsh(M).min() <= 1e-12 * np.abs(M).max():
            raise ValueError(
                "time_integration requires a positive definite mass matrix M: "
                "massless DOFs (singular M) are not supported; condense them out first"
            )
        self.model, self.omega, self.period = model, omega, 2 * np.pi / omega
        self.M, self.C, self.K = model.M, model.C, model.K
        self.n, self.nf = model.n_dofs, len(model.friction)
        self.B = model.relative_map(model.friction)
        if self.nf and np.linalg.matrix_rank(self.B) < self.nf:
            raise ValueError(
                "friction contacts must be linearly independent (relative map B of full row rank): "
                "redundant contacts make the stuck forces indeterminate"
            )
        self.Minv = linalg.inv(M)
        self._patterns: dict[tuple[int, ...], _Pattern] = {}

    def pattern(self, stuck: tuple[int, ...]) -> _Pattern:
        pat = self._patterns.get(stuck)
        if pat is None:
            pat = self._patterns[stuck] = _Pattern(self, stuck)
        return pat

    def forcing(self, t: float) -> np.ndarray:
        m, phase = self.model, self.omega * t
        return m.force_static + m.force_cos * math.cos(phase) + m.force_sin * math.sin(phase)

    def select(self, t: float, y: np.ndarray, Z, g: np.ndarray, direction: np.ndarray):
        """Contact states at ``(t, y)`` for the contacts ``Z`` at zero relative velocity.

        Solves the Coulomb law at acceleration level for ``Z`` (the other
        contacts keep their slip force): a box-constrained QP on the Delassus
        matrix. Contacts at the friction limit with zero relative acceleration
        are decided by the rate of their stuck force. Returns the stuck set, the
        slip directions and ``y`` with the relative velocities of ``Z`` set to
        exactly zero (an M-orthogonal round-off correction).
        """
        direction = direction.copy()
        Z = sorted(Z)
        if not Z:
            return (), direction, y
        n = self.n
        MiBt = self.Minv @ self.B[Z].T
        W = self.B[Z] @ MiBt
        y = y.copy()  # put the contacts of Z exactly at zero relative velocity (round-off correction)
        y[n:] -= MiBt @ linalg.solve(W, self.B[Z] @ y[n:], assume_a="pos")
        lam = np.where(g > 0, g * direction, 0.0)
        lam[Z] = 0.0
        r = self.forcing(t) - self.C @ y[n:] - self.K @ y[:n] - self.B.T @ lam
        b, gz = MiBt.T @ r, g[Z]
        lz = _box_qp(W, b, gz)
        a = b - W @ lz
        tol_a = 1e-9 * max(np.abs(b).max(), np.abs(W).max() * gz.max())
        stuck, critical = [], []
        for k, j in enumerate(Z):
            sign = 1 if lz[k] > 0 else -1
            if abs(lz[k]) < gz[k] * (1 - 1e-10):
                stuck.append(j)
                direction[j] = 0
            elif sign * a[k] > tol_a:
                direction[j] = sign
            else:
                critical.append((j, sign))
        if critical:
            trial = tuple(sorted(stuck + [j for j, _ in critical]))
            pat = self.pattern(trial)
            rate = pat.force_rate @ pat.coords(y, t, np.where(g > 0, g * direction, 0.0), self.omega)
            for j, sign in critical:
                if sign * rate[j] > 0:
                    direction[j] = sign
                else:
                    stuck.append(j)
                    direction[j] = 0
        return tuple(sorted(stuck)), direction, y

    def advance(self, pat: _Pattern, X0: np.ndarray, t: float, t1: float, g: np.ndarray, direction):
        """End of the phase starting at ``(t, X0)``: ``(time, contact, kind, near)``.

        ``kind`` is ``"force"`` or ``"velocity"`` (the event function that
        vanished), ``None`` when ``t1`` is reached; ``near`` lists slipping
        contacts whose relative velocity also vanishes at the event.
        """
        rows, owner, floor = [], [], []
        e1 = np.zeros(pat.dim)
        e1[pat.i_one] = 1.0
        for j in range(self.nf):
            if g[j] <= 0:
                continue
            if j in pat.stuck:
                rows += [g[j] * e1 - pat.force[j], g[j] * e1 + pat.force[j]]
                owner += [(j, "force"), (j, "force")]
                floor += [g[j], g[j]]  # a stuck force held at the limit is not an event
            else:
                rows.append(direction[j] * pat.rel_vel[j])
                owner.append((j, "velocity"))
                floor.append(0.0)
        if not rows or t1 <= t:
            return t1, None, None, ()
        H = np.array(rows)
        floor = np.array(floor)
        # select() keeps a contact stuck when its force sits at the limit (within its round-off
        # tolerance) with no outward rate: measure the force event from that start, not from the limit
        beyond = np.minimum(H @ X0, 0.0)
        H[:, pat.i_one] -= np.where(-beyond <= _MARGIN * floor, beyond, 0.0)
        ev = pat.evaluator(H, X0)
        tau_stop = t1 - t
        start, prev = 0.0, H @ X0
        first = True
        while start < tau_stop:
            taus = start + pat.h * np.arange(1, _CHUNK + 1)
            if first:
                taus = np.concatenate([pat.h * _GEOMETRIC, taus])
            taus = np.append(taus[taus < tau_stop], tau_stop)
            E = ev(taus)
            scale = np.maximum(np.maximum(np.abs(E).max(axis=1), np.abs(prev)), floor)
            bad = E < -_EVENT_TOL * scale[:, None]
            if bad.any():
                col = int(np.argmax(bad.any(axis=0)))
                grid = np.concatenate([[start], taus[: col + 1]])
                vals = np.column_stack([prev, E[:, : col + 1]])
                best, who = math.inf, None
                for r in np.flatnonzero(bad[:, col]):
                    # bracket from the last clearly valid point, else from the last valid one
                    pos = np.flatnonzero(vals[r, :-1] > _EVENT_TOL * scale[r])
                    if pos.size == 0:
                        pos = np.flatnonzero(vals[r, :-1] > 0)
                    func = pat.scalar(H[r], X0)
                    if pos.size == 0 or func(grid[pos[-1]]) <= 0:
                        root = grid[pos[-1]] if pos.size else 0.0  # already on the boundary
                    else:
                        root = brentq(func, grid[pos[-1]], grid[-1], xtol=TIME_TOL * self.period)
                    if root < best:
                        best, who = root, owner[r]
                at = ev(np.array([best]))[:, 0]
                near = tuple(
                    owner[r][0]
                    for r in range(len(rows))
                    if owner[r][1] == "velocity" and at[r] <= 1e-11 * scale[r] and owner[r] != who
                )
                return t + best, who[0], who[1], near
            start, prev, first = taus[-1], E[:, -1], False
        return t1, None, None, ()

    def run(
        self,
        y0: np.ndarray,
        t0: float,
        t1: float,
        g: np.ndarray,
        *,
        sample_times: np.ndarray | None = None,
        jacobian: bool = False,
        quadrature: bool = False,
    ) -> Trajectory:
        n, nf, omega = self.n, self.nf, self.omega
        active = g > 0
        y, t = np.array(y0, dtype=float), float(t0)
        rel_v = self.B @ y[n:]
        vscale = 2 * np.abs(y[n:]).max(initial=0.0)
        Z = [j for j in range(nf) if active[j] and abs(rel_v[j]) <= 1e-13 * vscale]
        direction = np.where(active, np.sign(rel_v), 0).astype(int)
        stuck, direction, y = self.select(t, y, Z, g, direction)
        jac = np.eye(2 * n) if jacobian else None
        phases, events = [], []
        sliding = np.zeros(nf)
        work = visc = 0.0
        fourier = np.zeros(n, dtype=complex)
        null_phases = 0
        while True:
            pat = self.pattern(stuck)
            lam = np.where(active, g * direction, 0.0)
            X0 = pat.coords(y, t, lam, omega)
            t_end, j_event, kind, near = self.advance(pat, X0, t, t1, g, direction)
            tau = t_end - t
            X1 = pat.propagate(X0, tau)
            state = np.where(active, SLIP, OPEN).astype(np.int8)
            state[list(stuck)] = STICK
            phases.append(_Phase(t, t_end, pat, X0, state, direction.astype(np.int8)))
            slipping = active & (state == SLIP)
            sliding[slipping] += np.maximum(direction[slipping] * ((pat.rel_disp @ (X1 - X0))[slipping]), 0.0)
            if quadrature and tau > 0:
                w_, v_, f_ = _phase_quadrature(pat, X0, t, tau, n, omega, self.C)
                work, visc = work + w_, visc + v_
                fourier += f_
            if jacobian:
                jac = pat.exit @ pat.transition(tau) @ pat.enter @ jac
            y, t = pat.Y @ X1, t_end
            if j_event is None:
                break
            null_phases = null_phases + 1 if tau <= TIME_TOL * self.period else 0
            if null_phases > _MAX_NULL_PHASES:
                raise RuntimeError(
                    f"contact states could not be resolved at t = {t!r} s (degenerate stick/slip transition)"
                )
            Z = set(stuck) | set(near)
            if kind == "velocity":
                Z.add(j_event)
            new_stuck, new_direction, y_new = self.select(t, y, Z, g, direction)
            for j in range(nf):
                was, now = j in stuck, j in new_stuck
                if was and not now:
                    events.append(ContactEvent(t, j, "slip", int(new_direction[j])))
                elif now and not was:
                    events.append(ContactEvent(t, j, "stick", 0))
                elif not now and new_direction[j] != direction[j]:
                    events.append(ContactEvent(t, j, "reversal", int(new_direction[j])))
            if jacobian and kind == "velocity":
                f_minus = pat.field @ X1
                new = self.pattern(new_stuck)
                f_plus = new.field @ new.coords(y_new, t, np.where(active, g * new_direction, 0.0), omega)
                hy = self.B[j_event]
                jac = jac + np.outer((f_plus - f_minus) / (hy @ f_minus[n:]), hy @ jac[n:])
            stuck, direction, y = new_stuck, new_direction, y_new
        if sample_times is not None and sample_times.size:
            states, forces, codes = _evaluate(phases, sample_times)
        else:
            sample_times = np.zeros(0)
            states, forces, codes = np.zeros((2 * n, 0)), np.zeros((nf, 0)), np.zeros((nf, 0), np.int8)
        return Trajectory(
            t0=float(t0),
            t1=float(t1),
            y=y,
            times=sample_times,
            states=states,
            contact_force=forces,
            contact_state=codes,
            segment_times=np.array([p.t_start for p in phases] + [phases[-1].t_end]),
            segment_state=np.array([p.state for p in phases]),
            segment_direction=np.array([p.direction for p in phases]),
            events=tuple(events),
            sliding_distance=sliding,
            friction_energy=g * sliding,
            input_work=work,
            viscous_dissipation=visc,
            jacobian=jac,
            _phases=tuple(phases),
            fourier=fourier,
        )


def _phase_quadrature(pat: _Pattern, X0, t: float, tau: float, n: int, omega: float, C: np.ndarray):
    """Input work, viscous dissipation and ``integral u exp(-i omega t) dt`` over one phase."""
    cells = max(1, math.ceil(tau / pat.h))
    edges = np.linspace(0.0, tau, cells + 1)
    half = np.diff(edges) / 2
    nodes = ((edges[:-1] + half)[:, None] + half[:, None] * _GAUSS_X).ravel()
    weights = (half[:, None] * _GAUSS_W).ravel()
    H = np.vstack([pat.Y, pat.fext])
    work = visc = 0.0
    fourier = np.zeros(n, dtype=complex)
    ev = pat.evaluator(H, X0)
    for lo in range(0, nodes.size, 1024):
        sl = slice(lo, lo + 1024)
        Z = ev(nodes[sl])
        u, v, f = Z[:n], Z[n : 2 * n], Z[2 * n :]
        w = weights[sl]
        work += float(np.sum(f * v, axis=0) @ w)
        visc += float(np.einsum("it,ij,jt->t", v, C, v) @ w)
        fourier += u @ (w * np.exp(-1j * omega * (t + nodes[sl])))
    return work, visc, fourier


def _evaluate(phases, times: np.ndarray):
    """States, friction forces and contact states at ``times`` from the phase list."""
    starts = np.array([p.t_start for p in phases])
    idx = np.clip(np.searchsorted(starts, times, side="right") - 1, 0, len(phases) - 1)
    nf = len(phases[0].state)
    n2 = phases[0].pattern.Y.shape[0]
    states, forces = np.zeros((n2, times.size)), np.zeros((nf, times.size))
    codes = np.zeros((nf, times.size), dtype=np.int8)
    for i in np.unique(idx):
        sel = np.flatnonzero(idx == i)
        p = phases[i]
        Z = p.pattern.evaluator(np.vstack([p.pattern.Y, p.pattern.force]), p.X0)(times[sel] - p.t_start)
        states[:, sel], forces[:, sel] = Z[:n2], Z[n2:]
        codes[:, sel] = p.state[:, None]
    return states, forces, codes


# ---------------------------------------------------------------------------
# public API
# ---------------------------------------------------------------------------
@lru_cache(maxsize=32)
def _engine(model: Model, omega: float) -> Engine:
    return Engine(model, omega)


def engine(model: Model, omega: float, wear) -> tuple[Engine, np.ndarray]:
    """The (cached) integrator of ``model`` at ``omega`` (rad/s) and the slip forces ``mu F_N(wear)`` (N)."""
    if not isinstance(model, Model):
        raise TypeError(f"model must be a fretwear.model.Model, got {type(model).__name__}")
    omega = float(omega)
    if not np.isfinite(omega) or omega <= 0:
        raise ValueError(f"omega must be a finite positive angular frequency (rad/s), got {omega!r}")
    eng = _engine(model, omega)
    return eng, np.array([c.mu for c in model.friction]) * model.normal_loads(wear)


def check_state(eng: Engine, y, name: str) -> np.ndarray:
    """``y`` as a finite state ``(u, v)`` of ``eng``'s model; ``ValueError`` naming ``name`` otherwise."""
    y = np.asarray(y, dtype=float)
    if y.shape != (2 * eng.n,) or not np.all(np.isfinite(y)):
        raise ValueError(f"{name} must be a finite state (u, v) of shape ({2 * eng.n},), got shape {y.shape}")
    return y


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
    y0 : array_like, shape (2 n,)
        Initial state ``(u, v)`` at ``t0`` (m, m/s). A contact with zero
        relative velocity starts stuck if its stuck force lies inside the
        friction cone.
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
    return eng.run(y0, t0, t1, g, sample_times=times, jacobian=jacobian, quadrature=True)


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
    """
    eng, g = engine(model, omega, wear)
    run = eng.run(check_state(eng, y0, "y0"), 0.0, eng.period, g)
    return run.y, run.sliding_distance, run.friction_energy
