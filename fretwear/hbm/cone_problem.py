"""Periodic DLFT problem of node pairs with 2-D friction on a reduced dynamic stiffness (eq. 12).

A small front end of the law ``fretwear.hbm.cone`` for any structure
already condensed on the contact coordinates ``(u_T1, u_T2, u_N)`` of its pairs
(``Z``, ``F`` in the contact-major layout of a harmonic basis): the checks
against exact solutions use it, and so can a 3-D interface. It lives beside
the law rather than in :mod:`fretwear.interface` because it depends on no
mesh, reduction or condensation, and in a module of its own because the law
sits below the compiled solvers of ``fretwear.hbm.newton`` that this module
calls.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .cone import evaluate, slip_work
from .dense import FASTMATH
from .dlft import jacobian_from_blocks
from .harmonics import HarmonicBasis, default_samples
from .newton import SINGULAR, cone_law, newton, walk
from .strategy import newton_message

__all__ = ["ConeProblem", "ConeSolution", "newton_kernel", "walk_kernel"]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def newton_kernel(x0, Z, F, eps, gap, mu, xref, Phi, Psi, target, max_iter, blocks=None):
    """:func:`fretwear.hbm.newton.newton` with the 2-D friction law: ``(x, converged, iterations, max|R|,
    code)``; a singular Jacobian raises (LAPACK). ``blocks``: ``Z`` by harmonic
    (``fretwear.hbm.structured.harmonic_blocks()`` on ``3 nc`` coordinates) for the structured steps."""
    return newton(cone_law(gap, mu, xref, Phi, Psi), x0, Z, F, eps, target, max_iter, blocks)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def walk_kernel(x0, p0, Z, F0, F1, r0, eps, gap, mu, xref, Phi, Psi, max_pieces):
    """:func:`fretwear.hbm.newton.walk` with the 2-D friction law to ``p = 1``: ``(x, p, pieces,
    arrived)``."""
    none = np.empty((0, x0.shape[0]))
    x, p, pieces, arrived, _ = walk(
        cone_law(gap, mu, xref, Phi, Psi), x0, p0, 1.0, Z, F0, F1, r0, eps, max_pieces,
        none, np.empty(0), np.empty(0),
    )  # fmt: skip
    return x, p, pieces, arrived


@dataclass
class ConeProblem:
    """Node pairs with a normal and two tangential directions under ``Z x + Lambda(x) = F`` (eq. 12).

    Parameters
    ----------
    Z : ndarray, shape (3 nc H, 3 nc H)
        Real dynamic stiffness on the contact coordinates (N/m), contact-major
        (entry ``c H + j``: slot ``j`` of coordinate ``c``; ``c = 3 i``, ``3 i + 1``
        tangential, ``3 i + 2`` normal, of pair ``i``).
    F : ndarray, shape (3 nc H,)
        Force harmonics (N), same layout.
    basis : HarmonicBasis
        Full basis (``half_wave=False``) of ``H`` slots.
    mu : ndarray, shape (nc,)
        Friction coefficients, >= 0.
    gap : ndarray, shape (nc,), optional
        Gap plus wear of each pair (m); default 0.
    xref : ndarray, shape (nc, 2), optional
        Reference slip variables (m) of pairs that can stick all period; default 0.
    eps : ndarray, shape (3 nc,), optional
        Penalty per coordinate (N/m); default 10 times the coordinate's largest
        diagonal entry of ``Z`` (the two tangents of a pair: the larger of theirs).
    """

    Z: np.ndarray
    F: np.ndarray
    basis: HarmonicBasis
    mu: np.ndarray
    gap: np.ndarray | None = None
    xref: np.ndarray | None = None
    eps: np.ndarray | None = None

    def __post_init__(self) -> None:
        if self.basis.half_wave:
            raise ValueError("basis must be the full harmonic basis (half_wave=False), got a half-wave one")
        H = self.basis.size
        self.mu = np.atleast_1d(np.asarray(self.mu, dtype=float))
        nc = len(self.mu)
        n = 3 * nc * H
        self.Z = np.ascontiguousarray(self.Z, dtype=float)
        self.F = np.ascontiguousarray(self.F, dtype=float)
        if self.Z.shape != (n, n) or self.F.shape != (n,):
            raise ValueError(f"Z must be ({n}, {n}) and F ({n},) for {nc} pairs of 3 coordinates, H = {H}; "
                             f"got {self.Z.shape} and {self.F.shape}")  # fmt: skip
        if np.any(~np.isfinite(self.mu)) or np.any(self.mu < 0):
            raise ValueError(f"mu must be finite friction coefficients >= 0, got {self.mu}")
        self.gap = np.zeros(nc) if self.gap is None else np.asarray(self.gap, dtype=float)
        if self.gap.shape != (nc,) or np.any(~np.isfinite(self.gap)):
            raise ValueError(f"gap must be {nc} finite gaps (m), got {self.gap}")
        xref = np.zeros((nc, 2)) if self.xref is None else np.asarray(self.xref, dtype=float)
        if xref.shape != (nc, 2) or np.any(~np.isfinite(xref)):
            raise ValueError(f"xref must be ({nc}, 2) finite slip variables (m), got shape {xref.shape}")
        self.xref = np.ascontiguousarray(xref)
        if self.eps is None:
            diag = np.abs(np.diag(self.Z)).reshape(nc, 3, H).max(axis=2)
            diag[:, :2] = diag[:, :2].max(axis=1, keepdims=True)  # an isotropic tangential penalty
            self.eps = 10.0 * np.maximum(diag, 1e-300).ravel()
        self.eps = np.asarray(self.eps, dtype=float)
        if self.eps.shape != (3 * nc,) or np.any(~np.isfinite(self.eps)) or np.any(self.eps <= 0):
            raise ValueError(f"eps must be {3 * nc} finite penalties > 0 N/m, got {self.eps}")

    @classmethod
    def from_condensation(
        cls,
        condensation,
        omega: float,
        harmonics: int = 7,
        samples: int | None = None,
        wear: np.ndarray | None = None,
        xref: np.ndarray | None = None,
        eps: np.ndarray | None = None,
        force_scale: float = 1.0,
    ) -> ConeProblem:
        """The problem of a model with 3-D contact pairs at ``omega`` (rad/s), condensed on ``(u_T1, u_T2,
        u_N)`` of every pair: the pair's tangent, its binormal ``n x t`` and its normal coordinate.

        ``condensation`` is a :class:`fretwear.interface.ContactCondensation` (its model's pairs 3-D),
        whose Schur complement keeps only ``(u_T, u_N)``: here the binormal relative displacements, which
        it places right after them, are kept too (eq. 11 per harmonic, ``D_ss`` the structure with every
        pair glued). ``wear`` (nc,) opens the gaps (m); ``force_scale`` multiplies the harmonic excitation.
        """
        pairs = condensation.model.pairs
        if pairs.dim != 3:
            raise ValueError(f"condensation must be of a model with 3-D contact pairs, got dim = {pairs.dim}")
        held = np.flatnonzero(np.any((pairs.dofs_a < 0) & (pairs.dofs_b < 0), axis=1))
        if held.size:  # a symmetry plane through the pair: the condensation gives it no binormal coordinate
            raise ValueError(f"condensation: pairs {held[:5].tolist()} have a component fixed on both nodes "
                             "(no binormal coordinate); the 2-D law needs both tangents of each")  # fmt: skip
        if not (np.isfinite(omega) and omega > 0):
            raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {omega!r}")
        nc, nq = pairs.count, condensation.n_q
        basis = HarmonicBasis(harmonics, default_samples(harmonics) if samples is None else samples)
        q = np.column_stack([2 * np.arange(nc), nq + np.arange(nc), 2 * np.arange(nc) + 1]).ravel()
        rest = np.setdiff1d(np.arange(condensation.K.shape[0]), q)
        H = basis.size
        Zr, Fr = np.zeros((3 * nc, H, 3 * nc, H)), np.zeros((3 * nc, H))
        for k in range(harmonics + 1):
            w = k * omega
            D = condensation.K - w**2 * condensation.M + 1j * w * condensation.C
            f = condensation.force_static if k == 0 else force_scale * condensation.force_harmonic
            f = f if k <= 1 else np.zeros_like(f)
            Zk, Fk = D[np.ix_(q, q)], f[q]
            if rest.size:
                X = np.linalg.solve(D[np.ix_(rest, rest)], np.column_stack([D[np.ix_(rest, q)], f[rest]]))
                Zk, Fk = Zk - D[np.ix_(q, rest)] @ X[:, :-1], Fk - D[np.ix_(q, rest)] @ X[:, -1]
            if k == 0:
                Zr[:, 0, :, 0], Fr[:, 0] = Zk.real, Fk.real
                continue
            c, s = 2 * k - 1, 2 * k  # as ContactCondensation.harmonic: u = a cos + b sin, q_k = a - i b
            Zr[:, c, :, c] = Zr[:, s, :, s] = Zk.real
            Zr[:, c, :, s], Zr[:, s, :, c] = Zk.imag, -Zk.imag
            Fr[:, c], Fr[:, s] = Fk.real, -Fk.imag
        wear = np.zeros(nc) if wear is None else np.asarray(wear, dtype=float)
        if wear.shape != (nc,) or not np.all(np.isfinite(wear)) or np.any(wear < 0):
            raise ValueError(f"wear must be {nc} finite depths >= 0 m (one per pair), got {wear}")
        n = 3 * nc * H
        return cls(Zr.reshape(n, n), Fr.reshape(n), basis, pairs.mu, pairs.gap + wear, xref, eps)

    @property
    def n_pairs(self) -> int:
        return len(self.mu)

    @property
    def size(self) -> int:
        """Unknowns ``3 nc H``."""
        return self.F.shape[0]

    def _law_args(self):
        b = self.basis
        return self.gap, self.mu, self.xref, b.synthesis, b.analysis

    def evaluate(self, x: np.ndarray, jacobian: bool = False):
        """``(R, A, lamT, lamN, X, state)`` at unknowns ``x`` (m): residual (N), Jacobian blocks (nc, 3H, 3H)
        (filled with ``jacobian``), tangential forces (nc, Ns, 2) (N), normal forces (nc, Ns) (N), slip
        variables (nc, Ns, 2) (m) and states (nc, Ns)."""
        nc, H, Ns = self.n_pairs, self.basis.size, self.basis.marched_samples
        R = np.empty(self.size)
        A = np.empty((nc, 3 * H, 3 * H))
        lamT, X = np.empty((2 * nc, Ns)), np.empty((2 * nc, Ns))
        lamN, state = np.empty((nc, Ns)), np.empty((nc, Ns), dtype=np.int8)
        gap, mu, xref, Phi, Psi = self._law_args()
        evaluate(np.ascontiguousarray(x, dtype=float), self.Z, self.F, self.eps, gap, mu, xref, Phi, Psi,
                 jacobian, R, A, lamT, lamN, X, state)  # fmt: skip
        pairs = lambda v: v.reshape(nc, 2, Ns).transpose(0, 2, 1)  # noqa: E731
        return R, A, pairs(lamT), lamN, pairs(X), state

    def jacobian(self, x: np.ndarray) -> np.ndarray:
        """Exact ``dR / dx`` (N/m) at ``x`` (away from changes of state)."""
        A = self.evaluate(x, True)[1]
        J = np.empty((self.size, self.size))
        jacobian_from_blocks(self.Z, self.eps, A, J)
        return J

    def residual_scale(self) -> float:
        """Force scale (N) against which residuals are judged."""
        return max(float(np.abs(self.F).max()), 1e-300)

    def solve(self, x0: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 50) -> ConeSolution:
        """Periodic solution: Newton's method from ``x0`` (default 0), else the load walk from ``F = 0``
        (where ``x = 0`` is exact for gaps >= 0) polished by Newton. ``tol``: on ``max |R|`` relative to
        the largest force."""
        scale = self.residual_scale()
        gap, mu, xref, Phi, Psi = self._law_args()
        x0 = np.zeros(self.size) if x0 is None else np.asarray(x0, dtype=float).copy()
        target = tol * scale
        try:
            x, ok, it, r, code = newton_kernel(x0, self.Z, self.F, self.eps, gap, mu, xref, Phi, Psi, target,
                                               max_iter)  # fmt: skip
        except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
            x, ok, it, r, code = x0, False, 0, np.inf, SINGULAR
        path = "newton"
        if not ok and np.all(self.gap >= 0):
            zero = np.zeros(self.size)
            try:
                xw, _, pieces, _ = walk_kernel(zero, 0.0, self.Z, zero, self.F, zero, self.eps, gap, mu, xref,
                                               Phi, Psi, 20_000)  # fmt: skip
                x, ok, itn, r, code = newton_kernel(xw, self.Z, self.F, self.eps, gap, mu, xref, Phi, Psi,
                                                    target, max_iter)  # fmt: skip
                it += int(pieces) + int(itn)
                path = "newton, load walk"
            except Exception:  # noqa: BLE001
                code = SINGULAR
        message = newton_message(code, max_iter)
        return ConeSolution(self, x, bool(ok), int(it), float(r / scale), message, path)


@dataclass(eq=False)
class ConeSolution:
    """Periodic solution of a :class:`ConeProblem` on the DLFT grid ``t_n = n T / N``.

    Attributes
    ----------
    problem, unknowns, converged, iterations, residual, message, path
        As :class:`fretwear.interface.InterfaceSolution`'s.
    tangential_force : (nc, N, 2) ``lambda_T`` (N). normal_force : (nc, N) ``lambda_N`` (N).
    slip_variable : (nc, N, 2) ``X`` (m). state : (nc, N) STICK, SLIP, OPEN.
    """

    problem: ConeProblem
    unknowns: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str
    path: str

    def __post_init__(self) -> None:
        fields = self.problem.evaluate(self.unknowns)[2:]
        self.tangential_force, self.normal_force, self.slip_variable, self.state = fields

    @property
    def harmonics(self) -> np.ndarray:
        """Harmonics of the contact coordinates, shape (nc, 3, H) (m)."""
        return self.unknowns.reshape(self.problem.n_pairs, 3, self.problem.basis.size)

    @property
    def friction_energy(self) -> np.ndarray:
        """Energy dissipated by friction per period by each pair, ``mu sum_n lambda_N^n |dX^n|`` (J)."""
        nc, Ns = self.normal_force.shape
        X = np.ascontiguousarray(self.slip_variable.transpose(0, 2, 1).reshape(2 * nc, Ns))
        return self.problem.mu * slip_work(X, self.normal_force, self.state)[1]

    @property
    def contact_work(self) -> np.ndarray:
        """Work of the tangential contact forces per period from the harmonics, ``oint lambda_T . du_T`` (J),
        per pair: independent of the march's slip accounting."""
        b = self.problem.basis
        lam = self.tangential_force.transpose(0, 2, 1) @ b.analysis.T  # (nc, 2, H)
        a_l, a_q = b.to_full(lam), b.to_full(self.harmonics[:, :2])
        k = np.arange(1, b.harmonics + 1)
        # oint lambda du = pi sum_k k (a_k^lam b_k^u - b_k^lam a_k^u), summed over both tangents
        w = a_l[..., 1::2] * a_q[..., 2::2] - a_l[..., 2::2] * a_q[..., 1::2]
        return np.pi * np.sum(k * w, axis=(1, 2))
