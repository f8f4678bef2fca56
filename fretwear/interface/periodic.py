"""Periodic response of an interface at one frequency: harmonic balance with the coupled DLFT law.

The reduced model (:mod:`~fretwear.interface.reduction`) is condensed on the
contact coordinates of every pair at each harmonic (eq. 11) and eq. 12 is
solved for their harmonics with the coupled normal/tangential law of
:mod:`~fretwear.interface.contact` (Newton's method, compiled). The path:

1. the quasi-static state under the static load alone
   (:func:`~fretwear.interface.static.solve_static`) gives the reference slip
   variables ``X_ref`` (where pairs stuck when the normal load was applied)
   and the starting point (its mean harmonics, no oscillation);
2. the strategy of every periodic solve (:mod:`fretwear.hbm.strategy`) with
   this law's steps: Newton and the Newton homotopy from a ``guess`` (a
   neighbouring solution) when given; Newton from that start; the exact
   piecewise-linear continuation in the excitation amplitude from 0 (where the
   start is exact) to 1 (:func:`load_walk`).

**Linear algebra** (``linear``): ``"structured"`` (default) takes every
Newton step from ``Z``'s blocks by harmonic and the law's local blocks
(:mod:`fretwear.hbm.structured`: the fixed and open pairs eliminated, a dense
system on the mixed coordinates only), never forming the dense Jacobian; and
it starts Newton at the softer penalty ``SOFT_PENALTY * eps`` to a loose
residual (:data:`SOFT_TARGET`) before the problem's penalty: the default
``eps`` is stiff (10 times ``Z``'s diagonal), and full Newton steps then wander
through stick/slip patterns (39 iterations at 128 pairs against 11-12 this
way). The penalty changes the DLFT solution at the level of the harmonic
truncation (~1e-3), so the answer is always the one at the problem's ``eps``:
the soft stage is only a start. ``"dense"``: the dense Jacobian, factored by
LAPACK after the stuck pairs are eliminated (the reference). The walks are dense.

The full harmonic basis is used (static normal load: no half-wave symmetry).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from functools import cached_property, partial

import numpy as np

from .._fields import item
from ..hbm import strategy
from ..hbm.harmonics import HarmonicBasis, default_samples
from ..hbm.newton import SINGULAR
from ..hbm.strategy import NewtonResult, Steps, newton_message
from ..hbm.structured import harmonic_blocks
from .contact import STICK, evaluate, slip_work
from .interrupt import check_interrupt
from .kernels import newton_kernel, walk_kernel
from .reduction import ContactCondensation
from .static import solve_static

__all__ = [
    "EPS_FACTOR",
    "InterfaceProblem",
    "InterfaceSolution",
    "solve_interface",
    "newton",
    "soft_start",
    "newton_homotopy",
    "load_walk",
]

#: default penalty, as a multiple of each coordinate's largest diagonal entry of Z (section 1.4)
EPS_FACTOR = 10.0

#: the structured path's first Newton stage: penalty ``SOFT_PENALTY * eps`` to ``SOFT_TARGET`` (relative)
#: in at most ``SOFT_STEPS`` iterations (measured on the cylinder, 32-128 pairs: 0.1 converges in 5-8
#: steps where 0.2 can wander; 1e-3 lets the stiff stage start from settled patterns)
SOFT_PENALTY, SOFT_TARGET, SOFT_STEPS = 0.1, 1e-3, 12

#: the linear algebra of the Newton steps (module text)
LINEAR = ("structured", "dense")


@dataclass
class InterfaceProblem:
    """Coupled DLFT problem of an interface at one frequency and one wear state.

    Parameters
    ----------
    condensation : ContactCondensation
    omega, harmonics, samples
        As :func:`fretwear.solve_periodic`.
    wear : ndarray, shape (nc,), optional
        Worn depth per pair (m), >= 0; opens the gaps (eq. 17b).
    xref : ndarray, shape (nc,), optional
        Reference slip variables of pairs that stick all period (m); default:
        those of the quasi-static state under the static load.
    eps : ndarray, shape (2 nc,), optional
        Penalty per contact coordinate (N/m); default ``EPS_FACTOR`` times the
        coordinate's largest diagonal entry of ``Z`` over the harmonics.
    force_scale : float
        Factor on the harmonic excitation (the static load is kept).
    linear : str
        The Newton steps' linear algebra, one of :data:`LINEAR` (module text); the answer is the same.
    """

    condensation: ContactCondensation
    omega: float
    harmonics: int = 7
    samples: int | None = None
    wear: np.ndarray | None = None
    xref: np.ndarray | None = None
    eps: np.ndarray | None = None
    force_scale: float = 1.0
    linear: str = "structured"
    basis: HarmonicBasis = field(init=False)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.omega) and self.omega > 0):
            raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {self.omega!r}")
        if self.linear not in LINEAR:
            raise ValueError(f"linear must be one of {LINEAR}, got {self.linear!r}")
        self.samples = default_samples(self.harmonics) if self.samples is None else self.samples
        self.basis = HarmonicBasis(self.harmonics, self.samples, False)
        contact = self.condensation.model.pairs
        nc = contact.count
        self.wear = np.zeros(nc) if self.wear is None else np.asarray(self.wear, dtype=float)
        if self.wear.shape != (nc,) or not np.all(np.isfinite(self.wear)) or np.any(self.wear < 0):
            raise ValueError(f"wear must be {nc} finite depths >= 0 m (one per pair)")
        self.Z, F = self.condensation.harmonic(self.omega, self.basis)
        H = self.basis.size
        static = np.zeros(F.shape, dtype=bool)
        static[::H] = True
        self.F_static = np.where(static, F, 0.0)
        self.F_exc = np.where(static, 0.0, F)
        if self.eps is None:
            diag = np.abs(np.diag(self.Z)).reshape(2 * nc, H)
            self.eps = EPS_FACTOR * diag.max(axis=1)
        self.eps = np.asarray(self.eps, dtype=float)
        if self.eps.shape != (2 * nc,) or np.any(~np.isfinite(self.eps)) or np.any(self.eps <= 0):
            raise ValueError(f"eps must be {2 * nc} finite penalties > 0 N/m (tangential, normal per pair)")
        self.gap = contact.gap + self.wear
        self.mu = contact.mu
        if self.xref is None:
            self.xref = self._static_state()[1]
        self.xref = np.ascontiguousarray(self.xref, dtype=float)  # a column of a history is strided

    @cached_property
    def blocks(self) -> np.ndarray | None:
        """``Z`` by harmonic (:func:`~fretwear.hbm.structured.harmonic_blocks`) for the structured steps, or
        None for the dense ones."""
        if self.linear == "dense":
            return None
        return harmonic_blocks(self.Z, 2 * self.n_pairs, self.basis.size)

    @property
    def n_pairs(self) -> int:
        return len(self.gap)

    @property
    def size(self) -> int:
        """Unknowns ``2 nc H``."""
        return 2 * self.n_pairs * self.basis.size

    @property
    def F(self) -> np.ndarray:
        """Reduced force at the current excitation scale (N)."""
        return self.F_static + self.force_scale * self.F_exc

    def _static_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact coordinates and slip variables of the quasi-static state under the static load."""
        res = solve_static(self.condensation, tangential_scale=0.0, wear=self.wear)
        if not res.converged:
            raise ValueError(f"no quasi-static state under the static load: {res.message}")
        return res.final.q, res.final.slip_variable

    def start(self) -> np.ndarray:
        """Unknowns of the quasi-static state: its contact coordinates as mean harmonics, exact at zero
        excitation."""
        x = np.zeros(self.size)
        x[:: self.basis.size] = self._static_state()[0]
        return x

    def with_wear(self, wear: np.ndarray, xref: np.ndarray | None = None) -> InterfaceProblem:
        """The same problem at worn depths ``wear`` (m): only the gaps change (``Z``, ``F``, ``eps`` reused).

        ``xref`` (m) replaces the reference slip variables (default: kept).
        """
        wear = np.asarray(wear, dtype=float)
        if wear.shape != self.wear.shape or not np.all(np.isfinite(wear)) or np.any(wear < 0):
            raise ValueError(f"wear must be {self.n_pairs} finite depths >= 0 m (one per pair)")
        new = copy.copy(self)
        new.wear = wear
        new.gap = self.condensation.model.pairs.gap + wear
        new.xref = self.xref if xref is None else np.ascontiguousarray(xref, dtype=float)  # one kernel build
        return new

    def evaluate(self, x: np.ndarray, jacobian: bool = False):
        """Residual (N) and the time fields ``(lamT, lamN, X, state)`` of the march at unknowns ``x``."""
        nc, H = self.n_pairs, self.basis.size
        Ns = self.basis.marched_samples
        R = np.empty(self.size)
        A = np.empty((nc, 2 * H, 2 * H))
        lamT, lamN, X = np.empty((nc, Ns)), np.empty((nc, Ns)), np.empty((nc, Ns))
        state = np.empty((nc, Ns), dtype=np.int8)
        evaluate(x, self.Z, self.F, self.eps, self.gap, self.mu, self.xref, self.basis.synthesis,
                 self.basis.analysis, jacobian, R, A, lamT, lamN, X, state)  # fmt: skip
        return R, A, lamT, lamN, X, state

    def residual_scale(self) -> float:
        """Force scale (N) against which residuals are judged."""
        return max(float(np.abs(self.F).max()), 1e-300)


def _newton(problem: InterfaceProblem, x0, eps: np.ndarray, tol: float, max_iter: int) -> NewtonResult:
    """One compiled Newton solve (:func:`~.kernels.newton_kernel`) at penalty ``eps`` (N/m)."""
    scale = problem.residual_scale()
    b = problem.basis
    try:
        x, ok, it, r, code = newton_kernel(
            np.asarray(x0, dtype=float).copy(), problem.Z, problem.F, eps, problem.gap, problem.mu,
            problem.xref, b.synthesis, b.analysis, tol * scale, max_iter, problem.blocks,
        )  # fmt: skip
    except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
        return NewtonResult(np.asarray(x0, dtype=float), False, 0, np.inf, newton_message(SINGULAR, max_iter))
    return NewtonResult(x, bool(ok), int(it), float(r / scale), newton_message(code, max_iter))


def newton(problem: InterfaceProblem, x0: np.ndarray, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Newton's method on the coupled DLFT residual (compiled: :func:`~.kernels.newton_kernel`).

    Converged when ``max |R| <= tol * scale``, ``scale`` the largest reduced force (N).
    """
    return _newton(problem, x0, problem.eps, tol, max_iter)


def soft_start(problem: InterfaceProblem, tol: float = 1e-10) -> NewtonResult:
    """The structured path's start: Newton from the quasi-static state at the soft penalty (module text).

    Converged at ``max(SOFT_TARGET, tol)`` relative, at most ``SOFT_STEPS`` iterations; the result is a
    start for Newton at the problem's penalty, not a solution of the problem.
    """
    return _newton(problem, problem.start(), SOFT_PENALTY * problem.eps, max(SOFT_TARGET, tol), SOFT_STEPS)


def _walk(problem: InterfaceProblem, x0, F0, F1, r0, tol: float, max_pieces: int, what: str) -> NewtonResult:
    """Walk ``R(x; F0 + p F1) = (1 - p) r0`` from ``(x0, 0)`` to ``p = 1``, then polish by Newton."""
    check_interrupt()
    b = problem.basis
    try:
        x, p, pieces, _ = walk_kernel(
            np.array(x0, dtype=float), 0.0, problem.Z, F0, F1, r0, problem.eps, problem.gap, problem.mu,
            problem.xref, b.synthesis, b.analysis, max_pieces,
        )  # fmt: skip
    except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
        return NewtonResult(np.array(x0, dtype=float), False, 0, np.inf, f"{what}: singular system")
    final = newton(problem, x, tol, 20)  # the walk ends on the solution: no soft start
    final.iterations += int(pieces)
    if not final.converged:
        final.message = f"{what} ended at {p:.6g} after {pieces} pieces; " + final.message
    return final


def load_walk(problem: InterfaceProblem, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Solve ``problem`` by the exact piecewise-linear continuation in the excitation amplitude.

    From the quasi-static start (exact at zero excitation) the solution curve
    of ``R(x, p) = 0``, with forces ``F_static + p F_exc``, is a polygon followed
    piece by piece (:func:`~fretwear.interface.kernels.walk_kernel`): one
    linear solve per piece crossed, no Newton iteration that can fail on the
    way. The end point is polished by Newton's method (``max_iter`` is not used:
    the walk's budget is its pieces).
    """
    F_exc = problem.force_scale * problem.F_exc
    return _walk(problem, problem.start(), problem.F_static, F_exc, np.zeros(problem.size), tol, 20_000,
                 "load walk: excitation scale")  # fmt: skip


def newton_homotopy(problem: InterfaceProblem, x0: np.ndarray, tol: float = 1e-10) -> NewtonResult:
    """Solve ``problem`` from a nearby point ``x0`` by the global Newton homotopy ``R(x) = (1 - p) R(x0)``.

    Its curve from ``(x0, 0)`` to ``p = 1`` is piecewise linear and followed
    exactly; from a neighbour's solution it crosses few pieces.
    """
    r0 = problem.evaluate(x0)[0]
    return _walk(problem, x0, problem.F, np.zeros(problem.size), r0, tol, 500, "Newton homotopy: sigma")


def solve_interface(
    problem: InterfaceProblem, guess: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 50
) -> InterfaceSolution:
    """Periodic response of the interface ``problem`` by the strategy of :mod:`fretwear.hbm.strategy`.

    Newton and the Newton homotopy from the ``guess`` (e.g. ``solution.unknowns``
    at a neighbouring frequency or wear state), Newton from the quasi-static
    state, the exact load walk. ``tol`` is the relative residual tolerance,
    ``max_iter`` the Newton iterations per solve.
    """
    check_interrupt()  # between solves: Ctrl-C cannot stop a compiled kernel (:mod:`.interrupt`)
    soft = []

    def start() -> np.ndarray:
        if problem.linear == "dense":
            return problem.start()
        soft.append(soft_start(problem, tol))
        return soft[-1].x if np.all(np.isfinite(soft[-1].x)) else problem.start()

    # a walk piece costs a dense solve of all pairs' harmonics: Newton keeps its whole budget
    steps = Steps(problem.size, partial(newton, problem), partial(newton_homotopy, problem), start,
                  partial(load_walk, problem), guess_steps=max_iter, start_steps=max_iter)  # fmt: skip
    res, path = strategy.solve(steps, guess, tol, max_iter)
    res.iterations += sum(r.iterations for r in soft)  # the soft stage's steps count
    if res.converged:
        res.residual = float(np.abs(problem.evaluate(res.x)[0]).max() / problem.residual_scale())
    return InterfaceSolution(problem, res.x, res.converged, res.iterations, res.residual, res.message, path)


@dataclass(eq=False)
class InterfaceSolution:
    """Periodic response of an interface and its status.

    Attributes
    ----------
    problem : InterfaceProblem
    unknowns : ndarray
        Harmonics of the contact coordinates (solver layout), reusable as a ``guess``.
    converged, iterations, residual, message, path
        The solve's status, as :class:`fretwear.hbm.PeriodicSolution`'s (the
        residual relative to the largest reduced force).

    Time fields are sampled on the DLFT grid of one period, ``t_n = n T / N``.
    """

    problem: InterfaceProblem
    unknowns: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str
    path: str

    @cached_property
    def _fields(self):
        return self.problem.evaluate(self.unknowns)[2:]

    @property
    def position(self) -> np.ndarray:
        """Coordinate of each pair along the interface (m)."""
        return self.problem.condensation.model.pairs.position

    @property
    def area(self) -> np.ndarray:
        """Tributary area of each pair (m^2, or m per unit thickness)."""
        return self.problem.condensation.model.pairs.area

    tangential_force = item("_fields", 0, "``lambda_T`` per pair and sample, shape (nc, N) (N).")
    normal_force = item("_fields", 1, "``lambda_N >= 0`` per pair and sample, shape (nc, N) (N).")
    slip_variable = item("_fields", 2, "``X_T`` per pair and sample, shape (nc, N) (m).")
    state = item("_fields", 3, "STICK, SLIP or OPEN per pair and sample, shape (nc, N).")

    @property
    def pressure(self) -> np.ndarray:
        """Contact pressure per pair and sample ``lambda_N / area`` (Pa)."""
        return self.normal_force / self.area[:, None]

    @property
    def mean_pressure(self) -> np.ndarray:
        """Pressure averaged over the period, per pair (Pa)."""
        return self.pressure.mean(axis=1)

    @cached_property
    def _slip_work(self) -> tuple[np.ndarray, np.ndarray]:
        return slip_work(self.slip_variable, self.normal_force, self.state)

    @property
    def slip_distance(self) -> np.ndarray:
        """Distance slid per period by each pair, ``s_i`` (m)."""
        return self._slip_work[0]

    @property
    def pressure_slip(self) -> np.ndarray:
        """Archard integrand per period ``int p ds`` of each pair (Pa m): ``dw_i / dN = K_w`` times this."""
        return self._slip_work[1] / self.area

    @property
    def friction_energy(self) -> float:
        """Energy dissipated by friction per period, ``sum_i mu_i int lambda_N ds`` (J, or J/m)."""
        return float(np.sum(self.problem.mu * self._slip_work[1]))

    def state_fraction(self, which: int = STICK) -> np.ndarray:
        """Fraction of the period each pair spends in state ``which`` (STICK, SLIP, OPEN)."""
        return np.mean(self.state == which, axis=1)

    @property
    def contact_harmonics(self) -> np.ndarray:
        """Full harmonics of the contact coordinates ``(u_T, u_N)`` per pair, shape (2 nc, 2 Nh + 1) (m)."""
        b = self.problem.basis
        return b.to_full(self.unknowns.reshape(2 * self.problem.n_pairs, b.size))

    @cached_property
    def dof_harmonics(self) -> np.ndarray:
        """Full harmonics ``[a0, a1, b1, ...]`` of every DOF of the full model (m), shape (n, 2 Nh + 1).

        As :attr:`fretwear.hbm.PeriodicSolution.dof_harmonics`; a DOF by name is
        ``dof_harmonics[model.dof(name)]``.
        """
        p = self.problem
        return p.condensation.full_harmonics(p.omega, p.harmonics, self.contact_harmonics)

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude ``sqrt(a1^2 + b1^2)`` of every DOF of the full model (m), shape (n,)."""
        return np.hypot(self.dof_harmonics[:, 1], self.dof_harmonics[:, 2])

    @property
    def model(self):
        """The full model (:class:`~fretwear.model.Model`) whose DOFs the solution reports."""
        return self.problem.condensation.full

    @property
    def omega(self) -> float:
        """Excitation frequency (rad/s)."""
        return self.problem.omega

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.problem.omega / (2 * np.pi)

    @property
    def harmonics(self) -> int:
        """Highest harmonic ``Nh``."""
        return self.problem.harmonics

    @property
    def contact_work(self) -> float:
        """Work of the contact forces over the period from the harmonics, ``sum_i oint lambda_T du_T`` (J).

        Independent of the march's slip accounting: for a converged solution it
        equals :attr:`friction_energy` up to the time discretisation.
        """
        b = self.problem.basis
        H = b.size
        q = self.unknowns.reshape(2 * self.problem.n_pairs, H)[0::2]  # tangential coordinates
        a_l, a_q = b.to_full(self.tangential_force @ b.analysis.T), b.to_full(q)
        k = np.arange(1, self.problem.harmonics + 1)
        # oint lambda du = pi sum_k k (a_k^lam b_k^u - b_k^lam a_k^u)
        return float(np.pi * np.sum(k * (a_l[:, 1::2] * a_q[:, 2::2] - a_l[:, 2::2] * a_q[:, 1::2])))
