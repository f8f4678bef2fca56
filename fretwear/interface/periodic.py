"""Periodic response of an interface at one frequency: harmonic balance with the coupled DLFT law.

The reduced model (``fretwear.interface.reduction``) is condensed on the
contact coordinates of every pair at each harmonic (eq. 11) and eq. 12 is
solved for their harmonics with the coupled normal/tangential law of
``fretwear.interface.contact`` (Newton's method, compiled). The path:

1. the quasi-static state under the static load alone
   (:func:`~fretwear.interface.static.solve_static`) gives the reference slip
   variables ``X_ref`` (where pairs stuck when the normal load was applied)
   and the starting point (its mean harmonics, no oscillation);
2. the strategy of every periodic solve (``fretwear.hbm.strategy``) with
   this law's steps: Newton and the Newton homotopy from a ``guess`` (a
   neighbouring solution) when given; Newton from that start; the exact
   piecewise-linear continuation in the excitation amplitude from 0 (where the
   start is exact) to 1 (:func:`load_walk`).

**Linear algebra** (``linear``): ``"structured"`` (default) takes every
Newton step from ``Z``'s blocks by harmonic and the law's local blocks
(:mod:`fretwear.hbm.structured`: the fixed and open pairs eliminated, a
system on the mixed coordinates only, solved by GMRES with a preconditioner
that couples no two harmonics (:mod:`fretwear.hbm.krylov`) from
``krylov_min`` of its unknowns, by its dense LU below), never forming the dense Jacobian; and
it starts Newton by penalty continuation through softer penalties to a
loose residual (:data:`SOFT_STAGES`: 0.1 then 0.3 times ``eps``) before the problem's penalty: the default
``eps`` is stiff (10 times ``Z``'s diagonal), and full Newton steps then wander
through stick/slip patterns (39 iterations at 128 pairs against 11-12 this
way). The penalty changes the DLFT solution at the level of the harmonic
truncation (~1e-3), so the answer is always the one at the problem's ``eps``:
the soft stage is only a start. ``"dense"``: the dense Jacobian, factored by
LAPACK after the stuck pairs are eliminated (the reference). The walks are dense.

The full harmonic basis is used (static normal load: no half-wave symmetry).

**Friction** (``friction``): ``"line"`` (default for 2-D pairs), the coupled law
of ``fretwear.hbm.coupled``, friction along each pair's tangent (on 3-D pairs
the binormal slides freely); ``"cone"`` (default for 3-D pairs), the 2-D law of
``fretwear.hbm.cone``: each pair has the coordinates ``(u_T1, u_T2, u_N)``
(tangent, binormal ``n x t``, normal), the circular Coulomb cone ``|lambda_T| <=
mu lambda_N`` and the slip reference a (nc, 2) array. The 1-D law is its
special case: a motion along the tangents alone gives the same answer. Its
quasi-static start is the 1-D one (:func:`~fretwear.interface.static.solve_static`,
binormal free) with the binormal relative displacements of that state: the 3-D
start whenever the normal load raises no binormal traction (identical
materials, Dundurs' ``beta = 0``, as in the sphere-on-flat benchmark).
"""

from __future__ import annotations

import copy
from dataclasses import dataclass, field
from functools import cached_property, partial

import numpy as np
from numba import njit

from .._fields import item
from ..hbm import cone, strategy
from ..hbm.cone_problem import newton_kernel as cone_newton_kernel
from ..hbm.cone_problem import walk_kernel as cone_walk_kernel
from ..hbm.dense import FASTMATH
from ..hbm.harmonics import HarmonicBasis, default_samples
from ..hbm.krylov import COUNTERS, KRYLOV_MIN
from ..hbm.newton import SINGULAR, cone_law, coupled_law
from ..hbm.newton import newton as _newton_loop
from ..hbm.strategy import NewtonResult, Steps, newton_message
from ..hbm.structured import dense_from_blocks
from .contact import STICK, evaluate, slip_work
from .interrupt import check_interrupt
from .kernels import evaluate_kernel, newton_kernel, walk_kernel
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

#: the structured path's soft stages before the problem's penalty: (penalty as a multiple of ``eps``,
#: relative target, at most steps), each started from the last (penalty continuation). Measured: the
#: 523-pair sphere (18 divisions, cone, Nh = 5) converges in 12 iterations with 0.1 -> 0.3 -> 1 against
#: 38 with 0.1 -> 1; on the cylinder (32-128 pairs) 0.1 converges in 4-7 steps where 0.2 can wander. The
#: first stage's loose target (5e-2) and the second's 1e-2 save steps that only polish a start (total
#: iterations 8, 9, 10 on the cylinder at 32, 64, 128 pairs and 9 on the sphere, against 8, 11, 13 and 12
#: with 1e-3 at both); a second stage looser than 1e-2 can leave the last one to wander (33 on the sphere
#: at 3e-2)
SOFT_STAGES = ((0.1, 5e-2, 12), (0.3, 1e-2, 12))


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _block_newton(x0, F, eps, gap, mu, xref, Phi, Psi, target, max_iter, blocks, krylov_min, stats):
    """The compiled Newton of the structured path from ``Z``'s harmonic ``blocks`` alone (no dense ``Z``),
    either pair law (the cone for ``xref`` (nc, 2)): :func:`fretwear.hbm.newton.newton` with its steps by
    GMRES from ``krylov_min`` mixed unknowns, its counters accumulated in ``stats``."""
    law = cone_law(gap, mu, xref, Phi, Psi) if xref.ndim == 2 else coupled_law(gap, mu, xref, Phi, Psi)
    return _newton_loop(law, x0, np.zeros((0, 0)), F, eps, target, max_iter, blocks, krylov_min, stats)


#: the linear algebra of the Newton steps (module text)
LINEAR = ("structured", "dense")

#: the friction laws (module text): along the tangent, or the circular cone in the tangential plane
FRICTION = ("line", "cone")


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
    xref : ndarray, shape (nc,) or (nc, 2) with the cone, optional
        Reference slip variables of pairs that stick all period (m); default:
        those of the quasi-static state under the static load.
    eps : ndarray, shape (2 nc,) or (3 nc,) with the cone, optional
        Penalty per contact coordinate (N/m); default ``EPS_FACTOR`` times the
        coordinate's largest diagonal entry of ``Z`` over the harmonics (with
        the cone, the larger of the two tangents' for both: an isotropic law).
    force_scale : float
        Factor on the harmonic excitation (the static load is kept).
    linear : str
        The Newton steps' linear algebra, one of ``LINEAR`` (module text); the answer is the same.
    krylov_min : int
        The structured path's mixed unknowns (``nM H``) from which its steps solve the mixed system by
        GMRES (``fretwear.hbm.krylov``; 0: always) rather than its dense LU (the exact step; a number
        above the problem's ``size``: never).
    friction : str, optional
        One of ``FRICTION`` (module text); default ``"cone"`` for 3-D pairs, ``"line"`` for 2-D.
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
    friction: str | None = None
    krylov_min: int = KRYLOV_MIN
    basis: HarmonicBasis = field(init=False)
    #: counters of the structured path's steps, accumulated over its solves (``fretwear.hbm.krylov.STEPS``
    #: ...): GMRES steps, their products, fallbacks to the exact step, exact steps, reused eliminations
    krylov_stats: np.ndarray = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not (np.isfinite(self.omega) and self.omega > 0):
            raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {self.omega!r}")
        if self.linear not in LINEAR:
            raise ValueError(f"linear must be one of {LINEAR}, got {self.linear!r}")
        contact = self.condensation.model.pairs
        if self.friction is None:
            self.friction = "cone" if contact.dim == 3 else "line"
        if self.friction not in FRICTION:
            raise ValueError(f"friction must be one of {FRICTION}, got {self.friction!r}")
        if self.friction == "cone" and contact.dim != 3:
            raise ValueError(f"friction='cone' needs 3-D contact pairs, got dim = {contact.dim}")
        self.samples = default_samples(self.harmonics) if self.samples is None else self.samples
        self.krylov_stats = np.zeros(COUNTERS, dtype=np.int64)
        self.basis = HarmonicBasis(self.harmonics, self.samples, False)
        nc = contact.count
        d = self.per_pair
        self.wear = np.zeros(nc) if self.wear is None else np.asarray(self.wear, dtype=float)
        if self.wear.shape != (nc,) or not np.all(np.isfinite(self.wear)) or np.any(self.wear < 0):
            raise ValueError(f"wear must be {nc} finite depths >= 0 m (one per pair)")
        self._blocks, F = self.condensation.harmonic_blocks(self.omega, self.basis, binormal=self.cone)
        H = self.basis.size
        static = np.zeros(F.shape, dtype=bool)
        static[::H] = True
        self.F_static = np.where(static, F, 0.0)
        self.F_exc = np.where(static, 0.0, F)
        if self.eps is None:
            q = d * nc  # each coordinate's largest diagonal entry of Z over the harmonics' blocks
            diag = np.abs(np.diagonal(self._blocks[:, :q, :q], axis1=1, axis2=2)).max(axis=0).reshape(nc, d)
            diag[:, : d - 1] = diag[:, : d - 1].max(axis=1, keepdims=True)  # an isotropic tangential penalty
            self.eps = EPS_FACTOR * diag.ravel()
        self.eps = np.asarray(self.eps, dtype=float)
        if self.eps.shape != (d * nc,) or np.any(~np.isfinite(self.eps)) or np.any(self.eps <= 0):
            raise ValueError(
                f"eps must be {d * nc} finite penalties > 0 N/m ({d} per pair: tangential, normal)"
            )
        self.gap = contact.gap + self.wear
        self.mu = contact.mu
        if self.xref is None:
            self.xref = self._static_state()[1]
        self.xref = np.ascontiguousarray(self.xref, dtype=float)  # a column of a history is strided
        shape = (nc, 2) if self.cone else (nc,)
        if self.xref.shape != shape or not np.all(np.isfinite(self.xref)):
            raise ValueError(f"xref must be finite reference slip variables (m) of shape {shape}, "
                             f"got {self.xref.shape}")  # fmt: skip

    @property
    def cone(self) -> bool:
        """Whether the law is the 2-D friction law (``friction == "cone"``)."""
        return self.friction == "cone"

    @property
    def per_pair(self) -> int:
        """Contact coordinates per pair: 2 ``(u_T, u_N)``, or 3 ``(u_T1, u_T2, u_N)`` with the cone."""
        return 3 if self.cone else 2

    @property
    def blocks(self) -> np.ndarray | None:
        """``Z`` by harmonic (``ContactCondensation.harmonic_blocks()``) for the structured
        path, or None for the dense one."""
        return None if self.linear == "dense" else self._blocks

    @cached_property
    def Z(self) -> np.ndarray:
        """The dense reduced dynamic stiffness (size, size) (N/m), formed from the blocks on first use: the
        dense path and the walks need it, the structured Newton steps do not."""
        return dense_from_blocks(self._blocks)

    @property
    def n_pairs(self) -> int:
        return len(self.gap)

    @property
    def size(self) -> int:
        """Unknowns ``2 nc H`` (``3 nc H`` with the cone)."""
        return self.per_pair * self.n_pairs * self.basis.size

    @property
    def F(self) -> np.ndarray:
        """Reduced force at the current excitation scale (N)."""
        return self.F_static + self.force_scale * self.F_exc

    def _static_state(self) -> tuple[np.ndarray, np.ndarray]:
        """Contact coordinates and slip variables of the quasi-static state under the static load.

        With the cone (module text): the coordinates ``(u_T1, u_T2, u_N)`` per pair and the slip
        variables (nc, 2), the binormal's its displacement in that state.
        """
        # once per condensation, wear state and law: xref and start() need it, every frequency has the same
        key = (self.wear.tobytes(), self.cone)
        cached = self.condensation.__dict__.get("_static_state")
        if cached is not None and cached[0] == key:
            return cached[1][0].copy(), cached[1][1].copy()
        res = solve_static(self.condensation, tangential_scale=0.0, wear=self.wear)
        if not res.converged:
            raise ValueError(f"no quasi-static state under the static load: {res.message}")
        q, X = res.final.q, res.final.slip_variable
        if self.cone:
            c = self.condensation
            nq = c.n_q  # z_s = D_ss^-1 (F_s - D_sq q)
            zs = c.glued_solve(0.0, 0, c.force_static[nq:] - c.K[nq:, :nq] @ q)
            b = np.zeros(self.n_pairs)
            b[c.has_binormal] = zs[: int(c.has_binormal.sum())]
            q, X = np.column_stack([q[0::2], b, q[1::2]]).ravel(), np.column_stack([X, b])
        self.condensation._static_state = (key, (q.copy(), X.copy()))
        return q, X

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
        """Residual (N), Jacobian blocks (nc, d H, d H) and the time fields ``(lamT, lamN, X, state)`` of the
        march at unknowns ``x``; ``lamT`` and ``X`` (nc, Ns), or (nc, Ns, 2) with the cone."""
        nc, H, d = self.n_pairs, self.basis.size, self.per_pair
        Ns = self.basis.marched_samples
        R = np.empty(self.size)
        A = np.empty((nc, d * H, d * H))
        lamT, lamN, X = np.empty(((d - 1) * nc, Ns)), np.empty((nc, Ns)), np.empty(((d - 1) * nc, Ns))
        state = np.empty((nc, Ns), dtype=np.int8)
        x = np.ascontiguousarray(x, dtype=float)
        if self.blocks is not None:  # Z x by harmonic: the dense Z is never formed
            b = self.basis
            evaluate_kernel(x, self.blocks, self.F, self.eps, self.gap, self.mu, self.xref, b.synthesis,
                            b.analysis, jacobian, R, A, lamT, lamN, X, state)  # fmt: skip
        else:
            law = cone.evaluate if self.cone else evaluate
            law(x, self.Z, self.F, self.eps, self.gap, self.mu, self.xref, self.basis.synthesis,
                self.basis.analysis, jacobian, R, A, lamT, lamN, X, state)  # fmt: skip
        if self.cone:
            lamT, X = (v.reshape(nc, 2, Ns).transpose(0, 2, 1) for v in (lamT, X))
        return R, A, lamT, lamN, X, state

    @property
    def _kernels(self):
        """The compiled Newton and walk of the problem's law (same signatures)."""
        return (cone_newton_kernel, cone_walk_kernel) if self.cone else (newton_kernel, walk_kernel)

    def residual_scale(self) -> float:
        """Force scale (N) against which residuals are judged."""
        return max(float(np.abs(self.F).max()), 1e-300)


def _newton(problem: InterfaceProblem, x0, eps: np.ndarray, tol: float, max_iter: int) -> NewtonResult:
    """One compiled Newton solve (:func:`~.kernels.newton_kernel`) at penalty ``eps`` (N/m)."""
    scale = problem.residual_scale()
    b = problem.basis
    x0 = np.asarray(x0, dtype=float).copy()
    args = (problem.F, eps, problem.gap, problem.mu, problem.xref, b.synthesis, b.analysis, tol * scale,
            max_iter)  # fmt: skip
    try:
        if problem.blocks is None:
            x, ok, it, r, code = problem._kernels[0](x0, problem.Z, *args)
        else:
            x, ok, it, r, code = _block_newton(x0, *args, problem.blocks, problem.krylov_min,
                                               problem.krylov_stats)  # fmt: skip
    except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
        return NewtonResult(np.asarray(x0, dtype=float), False, 0, np.inf, newton_message(SINGULAR, max_iter))
    return NewtonResult(x, bool(ok), int(it), float(r / scale), newton_message(code, max_iter))


def newton(problem: InterfaceProblem, x0: np.ndarray, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Newton's method on the coupled DLFT residual (compiled: :func:`~.kernels.newton_kernel`).

    Converged when ``max |R| <= tol * scale``, ``scale`` the largest reduced force (N).
    """
    return _newton(problem, x0, problem.eps, tol, max_iter)


def soft_start(problem: InterfaceProblem, tol: float = 1e-10) -> NewtonResult:
    """The structured path's start: Newton from the quasi-static state through the soft penalties of
    :data:`SOFT_STAGES` in turn, each from the last one's point (module text).

    Each stage converges at ``max(target, tol)`` relative; a stage that fails (near resonance) ends the
    continuation at the last converged stage's point (the first stage's, converged or not). The result
    is a start for Newton at the problem's penalty, not a solution of the problem; its ``iterations``
    are all stages'.
    """
    res, steps = None, 0
    for factor, target, max_steps in SOFT_STAGES:
        stage = _newton(problem, problem.start() if res is None else res.x, factor * problem.eps,
                        max(target, tol), max_steps)  # fmt: skip
        steps += stage.iterations
        if res is not None and not (stage.converged and np.all(np.isfinite(stage.x))):
            break
        res = stage
    res.iterations = steps
    return res


def _walk(problem: InterfaceProblem, x0, F0, F1, r0, tol: float, max_pieces: int, what: str) -> NewtonResult:
    """Walk ``R(x; F0 + p F1) = (1 - p) r0`` from ``(x0, 0)`` to ``p = 1``, then polish by Newton."""
    check_interrupt()
    b = problem.basis
    try:
        x, p, pieces, _ = problem._kernels[1](
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
    """Periodic response of the interface ``problem`` by the strategy of ``fretwear.hbm.strategy``.

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

    tangential_force = item("_fields", 0, "``lambda_T`` per pair and sample, shape (nc, N), (nc, N, 2) with "
                            "the cone (N).")  # fmt: skip
    normal_force = item("_fields", 1, "``lambda_N >= 0`` per pair and sample, shape (nc, N) (N).")
    slip_variable = item("_fields", 2, "``X_T`` per pair and sample, shape (nc, N), (nc, N, 2) with the cone "
                         "(m).")  # fmt: skip
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
        if self.problem.cone:  # the law's rows: the two tangents of pair i at 2 i, 2 i + 1
            nc, Ns = self.normal_force.shape
            X = np.ascontiguousarray(self.slip_variable.transpose(0, 2, 1).reshape(2 * nc, Ns))
            return cone.slip_work(X, self.normal_force, self.state)
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

    def to_xarray(self):
        """The solution as an ``xarray.Dataset`` (units, long names): signals per ``pair`` on ``time``."""
        from .._xarray import interface_solution_dataset

        return interface_solution_dataset(self)

    @property
    def contact_harmonics(self) -> np.ndarray:
        """Full harmonics of the contact coordinates ``(u_T, u_N)`` per pair, shape (2 nc, 2 Nh + 1), or
        ``(u_T1, u_T2, u_N)``, (3 nc, 2 Nh + 1) with the cone (m)."""
        b = self.problem.basis
        return b.to_full(self.unknowns.reshape(self.problem.per_pair * self.problem.n_pairs, b.size))

    @cached_property
    def dof_harmonics(self) -> np.ndarray:
        """Full harmonics ``[a0, a1, b1, ...]`` of every DOF of the full model (m), shape (n, 2 Nh + 1).

        As :attr:`fretwear.hbm.PeriodicSolution.dof_harmonics`; a DOF by name is
        ``dof_harmonics[model.dof(name)]``.
        """
        p = self.problem
        return p.condensation.full_harmonics(p.omega, p.harmonics, self.condensation_harmonics)

    @property
    def condensation_harmonics(self) -> np.ndarray:
        """:attr:`contact_harmonics` in the condensation's order (m): ``(u_T, u_N)`` per pair, then (with
        the cone) the binormals of the pairs that have one, shape (2 nc + nb, 2 Nh + 1)."""
        p = self.problem
        q = self.contact_harmonics
        if not p.cone:
            return q
        q = q.reshape(p.n_pairs, 3, -1)
        return np.vstack([q[:, [0, 2]].reshape(2 * p.n_pairs, -1), q[p.condensation.has_binormal, 1]])

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
        p = self.problem
        b, d = p.basis, p.per_pair
        q = self.unknowns.reshape(p.n_pairs, d, b.size)[:, : d - 1]  # tangential coordinates
        lam = self.tangential_force.transpose(0, 2, 1) if p.cone else self.tangential_force[:, None]
        a_l, a_q = b.to_full(lam @ b.analysis.T), b.to_full(q)
        k = np.arange(1, self.problem.harmonics + 1)
        # oint lambda du = pi sum_k k (a_k^lam b_k^u - b_k^lam a_k^u)
        return float(np.pi * np.sum(k * (a_l[..., 1::2] * a_q[..., 2::2] - a_l[..., 2::2] * a_q[..., 1::2])))
