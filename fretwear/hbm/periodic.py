"""Periodic response at one frequency: harmonic balance with DLFT contact forces.

:func:`solve_periodic` is the single-frequency solver (paper sections 1.3-1.5).
It computes only the effects present:

1. contacts with zero normal load are open and left out of the nonlinear system;
2. with no active contact left, the linear open solution is exact (path ``"linear-open"``);
3. with friction contacts only, the exact linear *stuck* solution is returned when
   it keeps every contact strictly inside its friction cone over the whole
   period (path ``"linear-stuck"``), with no nonlinear solve;
4. otherwise Newton's method with backtracking line search on the DLFT residual,
   from a guess or from the stuck solution (path ``"dlft"``); if that fails, a
   continuation in the load factor from the largest load that still sticks
   (path ``"dlft-homotopy"``), which is reliable at any harmonic count.

:class:`Problem` holds everything that depends on the frequency only
(condensation, DFT matrices, penalties) and is reused by the sweeps in
:mod:`fretwear.hbm.continuation`.
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field

import numpy as np

from ..model import Model
from . import dlft
from .condensation import Condensed, condense
from .harmonics import HarmonicBasis, default_samples
from .kernels import LOAD, NEWTON, newton_kernel, walk_kernel
from .solution import PeriodicSolution

__all__ = [
    "Problem",
    "NewtonResult",
    "solve_periodic",
    "solve_problem",
    "newton",
    "load_homotopy",
    "newton_homotopy",
    "follow_normal_load",
    "walk",
    "LOAD",
    "NEWTON",
]

#: default penalty, as a multiple of the condensed dynamic stiffness scale
EPS_FACTOR = 10.0


@dataclass
class NewtonResult:
    """Outcome of a Newton solve on the DLFT residual."""

    x: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str = ""


@dataclass
class Problem:
    """DLFT problem at one frequency, for a model in a given wear state.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s), > 0.
    harmonics : int
        Highest harmonic ``Nh >= 1``.
    samples : int, optional
        Samples per period ``N >= 2 Nh + 1``; default :func:`default_samples`.
    wear : array_like, optional
        Wear depth of each friction contact (m); default zero.
    eps : float or array_like, optional
        DLFT penalty per active contact (N/m). Default: ``EPS_FACTOR`` times the
        largest diagonal entry of the condensed dynamic stiffness over the
        retained harmonics (the paper's advice, section 1.4).
    half_wave : bool, optional
        Use odd harmonics and half a period; default: when the model allows it.
    force_scale : float
        Load factor applied to every external force (used by load continuation).
    condensed : Condensed, optional
        The condensation at ``omega`` on the active contacts, when already known
        (sweeps condense every frequency at once).
    """

    model: Model
    omega: float
    harmonics: int = 7
    samples: int | None = None
    wear: np.ndarray | None = None
    eps: float | np.ndarray | None = None
    half_wave: bool | None = None
    force_scale: float = 1.0
    derivative: bool = False
    condensed: Condensed | None = field(default=None, repr=False)
    basis: HarmonicBasis = field(init=False)

    def __post_init__(self) -> None:
        m = self.model
        if not np.isfinite(self.omega) or self.omega <= 0:
            raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {self.omega!r}")
        samples = default_samples(self.harmonics) if self.samples is None else self.samples
        if self.half_wave is None:
            self.half_wave = m.half_wave_symmetric and samples % 2 == 0
        elif self.half_wave and not m.half_wave_symmetric:
            raise ValueError(
                "half_wave=True needs a half-wave symmetric model (no static load, no unilateral contact)"
            )
        self.basis = HarmonicBasis(self.harmonics, samples, bool(self.half_wave))
        self.samples = samples
        self.normal_loads = m.normal_loads(self.wear)
        self.wear = np.zeros(len(m.friction)) if self.wear is None else np.asarray(self.wear, float)
        if np.any(self.wear < 0):
            raise ValueError(f"wear must be >= 0 m, got {self.wear}")
        active_f = [i for i, c in enumerate(m.friction) if c.mu * self.normal_loads[i] > 0]
        self.active_index = active_f + [len(m.friction) + j for j in range(len(m.normal))]
        self.active = [m.contacts[i] for i in self.active_index]
        self.kinds = np.array(
            [dlft.FRICTION] * len(active_f) + [dlft.UNILATERAL] * len(m.normal), dtype=np.int64
        )
        self.limits = np.array(
            [m.friction[i].mu * self.normal_loads[i] for i in active_f] + [c.gap for c in m.normal],
            dtype=float,
        )
        self.B = m.relative_map(self.active)
        if self.active:
            cond = self.condensed or condense(m, self.B, self.omega, self.basis, self.derivative)
            self.Z, self.F0, self.dZ, self.dF0 = cond.Z, cond.F, cond.dZ, cond.dF
            self.eps = self._penalty(self.eps)

    def with_wear(self, wear) -> Problem:
        """The same problem at wear depths ``wear`` (m): wear changes only the friction limits.

        Reuses the condensation and the penalty when the set of active contacts
        is unchanged (it changes only when a normal load reaches zero).
        """
        wear = np.asarray(wear, dtype=float)
        loads = self.model.normal_loads(wear)
        nf = len(self.model.friction)
        active_f = [i for i in range(nf) if self.model.friction[i].mu * loads[i] > 0]
        if active_f != [i for i in self.active_index if i < nf]:
            return Problem(
                self.model, self.omega, self.harmonics, self.samples, wear, None, self.basis.half_wave,
                self.force_scale,
            )  # fmt: skip
        new = copy.copy(self)
        new.wear, new.normal_loads = wear, loads
        new.limits = self.limits.copy()
        new.limits[: len(active_f)] = [self.model.friction[i].mu * loads[i] for i in active_f]
        return new

    def sliding_distance(self, x: np.ndarray) -> np.ndarray:
        """Distance slid per period by each active friction contact at unknowns ``x`` (m)."""
        X = self.evaluate(x, jacobian=False)[4]
        slid = np.abs(np.diff(X, axis=1, append=X[:, :1] * (-1 if self.basis.half_wave else 1))).sum(axis=1)
        return (2 * slid if self.basis.half_wave else slid)[self.kinds == dlft.FRICTION]

    # -- sizes ----------------------------------------------------------------
    @property
    def n_active(self) -> int:
        return len(self.active)

    @property
    def size(self) -> int:
        """Number of unknowns ``nc H``."""
        return self.n_active * self.basis.size

    @property
    def F(self) -> np.ndarray:
        """Reduced force at the current load factor (N)."""
        return self.force_scale * self.F0

    def _penalty(self, eps) -> np.ndarray:
        """Penalty per contact (N/m); sets ``deps``, its derivative in omega (N s/m)."""
        H, nc = self.basis.size, self.n_active
        self.deps = np.zeros(nc)
        if eps is None:
            diag = np.diag(self.Z).reshape(nc, H)
            j = np.argmax(np.abs(diag), axis=1)
            if self.dZ is not None:
                dd = np.diag(self.dZ).reshape(nc, H)[np.arange(nc), j]
                self.deps = EPS_FACTOR * np.sign(diag[np.arange(nc), j]) * dd
            return EPS_FACTOR * np.abs(diag[np.arange(nc), j])
        eps = np.broadcast_to(np.asarray(eps, dtype=float), (self.n_active,)).copy()
        if np.any(~np.isfinite(eps)) or np.any(eps <= 0):
            raise ValueError(f"eps must be finite and > 0 N/m, got {eps}")
        return eps

    # -- DLFT -------------------------------------------------------------------
    def evaluate(self, x: np.ndarray, jacobian: bool = True):
        """Residual (N), Jacobian (N/m) or None, and the time-domain fields of the march."""
        nc, H = self.n_active, self.basis.size
        Ns = self.basis.marched_samples
        R = np.empty(nc * H)
        A = np.empty((nc, H, H))
        lam = np.empty((nc, Ns))
        X = np.empty((nc, Ns))
        state = np.empty((nc, Ns), dtype=np.int8)
        dlft.evaluate(
            x, self.Z, self.F, self.eps, self.kinds, self.limits, self.basis.synthesis, self.basis.analysis,
            self.basis.half_wave, jacobian, R, A, lam, X, state,
        )  # fmt: skip
        J = None
        if jacobian:
            J = np.empty((nc * H, nc * H))
            dlft.jacobian_from_blocks(self.Z, self.eps, A, J)
        return R, J, A, lam, X, state

    def residual_scale(self) -> float:
        """Force scale (N) against which residuals are judged."""
        scale = max(
            np.abs(self.F).max(initial=0.0), np.abs(self.limits[self.kinds == dlft.FRICTION]).max(initial=0)
        )
        return scale if scale > 0 else 1.0

    # -- linear solutions -------------------------------------------------------
    def stuck_guess(self) -> np.ndarray:
        """Stuck friction contacts (x = 0) and unilateral contacts closed at their gap."""
        x = np.zeros(self.size)
        if not self.basis.half_wave:
            H = self.basis.size
            for c in np.flatnonzero(self.kinds == dlft.UNILATERAL):
                x[c * H] = self.limits[c]
        return x

    def stick_ratio(self) -> float:
        """Largest ratio ``(stick force half-range) / (mu F_N)`` of the exact stuck solution.

        Only for friction-only problems: the stuck solution has ``x = 0`` on
        every harmonic but the mean, chosen so that each stick force is centred
        in its cone, and its force is ``Lambda = F_r - Z_r x``. Values ``<= 1``
        mean the stuck solution is exact.
        """
        H = self.basis.size
        F = self.F.reshape(self.n_active, H)
        amp = np.sqrt(np.sum(F[:, self.basis.orders == 1] ** 2, axis=1))  # forcing is at the fundamental
        return float(np.max(amp / self.limits))

    def stuck_solution(self) -> np.ndarray:
        """Unknowns of the centred stuck solution (friction-only problems)."""
        x = np.zeros(self.size)
        if not self.basis.half_wave:
            H = self.basis.size
            means = np.arange(self.n_active) * H
            # centred stick: the mean stick force Lambda_0 = F_0 - Z_0 x_0 is zero
            x[means] = np.linalg.solve(self.Z[np.ix_(means, means)], self.F[means])
        return x


def _norm(v: np.ndarray) -> float:
    return float(np.abs(v).max(initial=0.0))


def newton(problem: Problem, x0: np.ndarray, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Newton's method on the DLFT residual, non-monotone, with a damped fallback.

    Converged when ``max |R| <= tol * scale`` with ``scale`` the largest
    external or friction force (N). The residual is piecewise linear: once the
    stick/slip pattern is right, a full Newton step lands on the solution. On
    the way, full steps must be allowed to raise the residual while the pattern
    settles (a monotone line search stalls at the kinks), so full steps are
    taken while the residual stays within a factor 1000 of the best one seen,
    for half the budget; then a backtracking line search restarts from the best
    iterate. The loop is compiled (:func:`fretwear.hbm.kernels.newton_kernel`).
    """
    scale = problem.residual_scale()
    b = problem.basis
    try:
        x, ok, it, r, code = newton_kernel(
            np.asarray(x0, dtype=float).copy(), problem.Z, problem.F, problem.eps, problem.kinds,
            problem.limits, b.synthesis, b.analysis, b.half_wave, tol * scale, max_iter,
        )  # fmt: skip
    except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
        return NewtonResult(np.asarray(x0, dtype=float), False, 0, np.inf, "singular Jacobian")
    messages = {0: "", 1: "non-finite Newton step", 2: "line search failed",
                3: f"no convergence in {max_iter} iterations"}  # fmt: skip
    return NewtonResult(x, bool(ok), int(it), float(r / scale), messages[code])


def walk(problem: Problem, x, p, p_end, mode, F, r0, max_pieces, record: int = 0):
    """Follow a piecewise-linear solution curve of the DLFT equations (compiled walk).

    Each step goes along the null vector of ``[dR/dx, dR/dp]`` to the next
    state change, computed exactly by :func:`fretwear.hbm.dlft.boundary_distance`,
    and just past it. The tangent keeps the sign of ``det [J dR/dp; t]``, the
    invariant of a regular curve across the kinks (a dot product with the
    previous tangent is not). Returns ``(x, p, pieces, arrived)``, and with
    ``record > 0`` also the path's breakpoints ``(x_k, p_k, slid_k)`` (at most ``record``).
    """
    b = problem.basis
    rec = np.empty((record, x.size)), np.empty(record), np.empty(record)
    try:
        x, p, pieces, arrived, k = walk_kernel(
            np.asarray(x, dtype=float).copy(), float(p), float(p_end), mode, problem.Z, F, r0, problem.eps,
            problem.kinds, problem.limits, b.synthesis, b.analysis, b.half_wave, max_pieces, *rec,
        )  # fmt: skip
    except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
        return (x, p, 0, False) + ((rec[0][:0], rec[1][:0], rec[2][:0]) if record else ())
    out = (x, p, int(pieces), bool(arrived))
    return out + ((rec[0][:k], rec[1][:k], rec[2][:k]) if record else ())


def load_homotopy(
    problem: Problem, tol: float = 1e-10, max_iter: int = 50, max_pieces: int = 100_000
) -> NewtonResult:
    """Solve ``problem`` by exact piecewise-linear continuation in the load factor.

    With the forces scaled by ``s``, the DLFT residual ``R(x, s)`` is piecewise
    linear in ``(x, s)`` jointly (linear while no sample changes state), so its
    solution curve is a polygon, followed piece by piece by :func:`walk`: no
    Newton iteration can fail on the way, and the cost is one linear solve per
    piece crossed.

    For friction-only problems the curve starts at the largest load factor for
    which the stuck solution is exact; otherwise at zero load.
    """
    full = problem.force_scale
    if np.all(problem.kinds == dlft.FRICTION):
        s = full * min(1.0, 1.0 / problem.stick_ratio())
        problem.force_scale = s
        x = problem.stuck_solution()
    else:
        s = 0.0
        problem.force_scale = s
        start = newton(problem, problem.stuck_guess(), tol, max_iter)
        if not start.converged:
            problem.force_scale = full
            return NewtonResult(start.x, False, start.iterations, start.residual, "no solution at zero load")
        x = start.x
    x, s, pieces, _ = walk(problem, x, s, full, LOAD, problem.F0, np.zeros(0), max_pieces)
    problem.force_scale = full
    final = newton(problem, x, tol, max_iter)  # polish the end point (exact up to round-off already)
    final.iterations += pieces
    if not final.converged:
        final.message = (
            f"load continuation ended at load factor {s / full:.6g} after {pieces} pieces; " + final.message
        )
    return final


def follow_normal_load(problem: Problem, x: np.ndarray, target: Problem, tol: float = 1e-10) -> NewtonResult:
    """Solve ``target`` from a solution ``x`` of ``problem`` that differs only by the normal load.

    With one friction contact and no unilateral contact, the DLFT equations are
    positively homogeneous in the forces and the friction limit: the response
    at limit ``L2`` equals ``L2 / L1`` times the response at limit ``L1`` under the
    forces scaled by ``L1 / L2``. The exact load walk from force scale 1 to
    ``L1 / L2`` therefore follows the physical path between the two normal loads
    (as wear relaxes the load) crossing only the stick/slip changes on the way.
    """
    if not (problem.n_active == target.n_active == 1 and problem.kinds[0] == dlft.FRICTION
            and problem.basis == target.basis):  # fmt: skip
        raise ValueError("follow_normal_load needs one active friction contact and the same basis")
    ratio = target.limits[0] / problem.limits[0]
    x_end, s, pieces, arrived = walk(problem, x, 1.0, 1.0 / ratio, LOAD, problem.F0 * problem.force_scale,
                                      np.zeros(0), 100_000)  # fmt: skip
    res = newton(target, ratio * x_end, tol, 20)
    res.iterations += pieces
    if not res.converged:
        res.message = f"normal-load walk ended at load ratio {s:.6g} ({pieces} pieces); " + res.message
    return res


def newton_homotopy(
    problem: Problem, x0: np.ndarray, tol: float = 1e-10, max_pieces: int = 500
) -> NewtonResult:
    """Solve ``problem`` from a nearby point ``x0`` by the global Newton homotopy.

    ``R(x) = (1 - sigma) R(x0)`` is piecewise linear in ``(x, sigma)``; its curve
    from ``(x0, 0)`` to ``sigma = 1`` is followed exactly by :func:`walk`. From
    the solution at a neighbouring frequency this crosses few pieces, and it
    does not fail where Newton's method jumps between stick/slip patterns.
    """
    r0 = problem.evaluate(x0, jacobian=False)[0]
    x, sigma, pieces, _ = walk(problem, x0, 0.0, 1.0, NEWTON, problem.F, r0, max_pieces)
    final = newton(problem, x, tol, 20)
    final.iterations += pieces
    if not final.converged:
        final.message = f"Newton homotopy ended at sigma {sigma:.6g} after {pieces} pieces; " + final.message
    return final


def solve_periodic(
    model: Model,
    omega: float,
    harmonics: int = 7,
    *,
    samples: int | None = None,
    wear=None,
    eps=None,
    half_wave: bool | None = None,
    guess: np.ndarray | None = None,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> PeriodicSolution:
    """Periodic response of ``model`` at ``omega`` by HBM + DLFT.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s), > 0.
    harmonics : int
        Highest harmonic ``Nh >= 1``.
    samples : int, optional
        Time samples per period ``N >= 2 Nh + 1`` (default: next power of 2 >= 16 Nh).
    wear : array_like, optional
        Wear depth of each friction contact (m).
    eps : float or array_like, optional
        DLFT penalty (N/m); changes the convergence, and at finite ``Nh`` the
        answer only within the truncation error.
    half_wave : bool, optional
        Force or forbid the half-wave (odd harmonics) reduction.
    guess : ndarray, optional
        Starting unknowns (harmonics of the active contact coordinates, in the
        layout of :class:`Problem`), e.g. ``solution.unknowns`` of a neighbour.
    tol : float
        Relative residual tolerance.
    max_iter : int
        Newton iterations per solve.

    Returns
    -------
    PeriodicSolution
        With ``converged``, ``residual``, ``iterations``, ``message`` and ``path``.
    """
    problem = Problem(model, omega, harmonics, samples, wear, eps, half_wave)
    return solve_problem(problem, guess, tol, max_iter)


def solve_problem(
    problem: Problem, guess: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 50
) -> PeriodicSolution:
    """Solve a prepared :class:`Problem`, computing only the effects present.

    Linear paths first (no active contact; exact stuck solution). Then, from a
    ``guess`` (a neighbour's solution): Newton, and if it fails the global
    Newton homotopy from the guess. Without a guess, or if those fail: Newton
    from the stuck solution and then the exact load continuation.
    """
    if problem.n_active == 0:
        return PeriodicSolution.build(problem, None, NewtonResult(np.zeros(0), True, 0, 0.0), "linear-open")
    friction_only = bool(np.all(problem.kinds == dlft.FRICTION))
    if friction_only and problem.stick_ratio() < 1.0:
        x = problem.stuck_solution()
        return PeriodicSolution.build(problem, x, NewtonResult(x, True, 0, 0.0), "linear-stuck")
    iterations = 0
    if guess is not None:
        guess = np.asarray(guess, dtype=float)
        if guess.shape != (problem.size,):
            raise ValueError(f"guess must have shape ({problem.size},), got {guess.shape}")
        res = newton(problem, guess, tol, min(max_iter, 12))
        if res.converged:
            return PeriodicSolution.build(problem, res.x, res, "dlft")
        res = newton_homotopy(problem, res.x, tol)  # from Newton's best iterate
        if res.converged:
            res.iterations += 12
            return PeriodicSolution.build(problem, res.x, res, "dlft-newton-homotopy")
        iterations = res.iterations + 12
    start = problem.stuck_solution() if friction_only else problem.stuck_guess()
    res = newton(problem, start, tol, min(max_iter, 16))
    path = "dlft"
    if not res.converged:
        res = load_homotopy(problem, tol, max_iter)
        path = "dlft-homotopy"
    res.iterations += iterations
    return PeriodicSolution.build(problem, res.x, res, path)
