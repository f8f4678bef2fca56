"""Condensation of a model with contact pairs on their contact coordinates (paper eq. 11).

**Condensation on the contact coordinates.** For each pair, the DOFs of node
``B`` are replaced by its contact coordinates relative to node ``A``
(``u_B = u_A + t u_T - n u_N``, plus the binormal component in 3-D), so that
the contact forces act on the coordinates ``q = (u_T, u_N)`` alone. Per
harmonic order ``k`` the reduced dynamic stiffness ``D_k = K - (k omega)^2 M +
i k omega C`` is condensed on ``q`` by its Schur complement,

    Z_k = D_qq - D_qs D_ss^{-1} D_sq,     F_k = F_q - D_qs D_ss^{-1} F_s,

so that ``Z_k q_k + Lambda_k = F_k`` (eq. 11). The Schur complement only needs
``D_ss`` regular: the structure with every pair glued. A body held by the
contact alone (the pad under a dead load) is thus fine even at ``k = 0``,
where ``Z_0`` is singular but finite.

**How** ``D_ss^-1`` **is applied.** With proportional damping (``C = alpha K +
beta M``, ``C = 0`` included: :attr:`ContactCondensation.proportional`), by one
Cholesky factorization of ``K_ss`` (positive definite: the glued structure is
anchored) and the glued structure's modes with mass (``_GluedModes``),
for every harmonic and frequency; otherwise, or when ``K_ss`` is singular, by a
complex LU of ``D_ss`` per harmonic. Both give the same ``Z_k`` and ``F_k`` to
rounding (``tests/interface/test_glued_modes.py``).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from functools import cached_property

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp

from ..hbm.harmonics import HarmonicBasis
from ..hbm.structured import dense_from_blocks
from ..model import ContactPairs, Model

__all__ = ["ContactCondensation"]


def _contact_coordinates(contact: ContactPairs, size: int) -> tuple[np.ndarray, int, np.ndarray]:
    """Transformation ``T`` (size, size) with ``coords = T z``, ``z = (q, slaves)``; returns ``(T, n_q,
    has_binormal)``, the last (nc,) bool: the pairs with a binormal coordinate.

    ``q`` holds ``(u_T, u_N)`` per pair (pair-major); in 3-D the binormal
    relative displacements come next; then every coordinate not replaced. A
    component fixed on both nodes of a 3-D pair (``-1`` in both: a symmetry
    plane through the pair) must be the binormal's; the pair then has no
    binormal coordinate.
    """
    nc, dim = contact.count, contact.dim
    replaced, rel = [], []  # replaced coordinate, and its sign convention (+1: node B, -1: node A)
    has_binormal = np.full(nc, dim == 3)
    for i in range(nc):
        a, b = contact.dofs_a[i], contact.dofs_b[i]
        held = (a < 0) & (b < 0)
        if held.any():
            in_plane = np.abs(contact.tangent[i, held]).max() + np.abs(contact.normal[i, held]).max()
            if dim < 3 or held.sum() > 1 or in_plane > 1e-12:
                raise ValueError(
                    f"contact pair {i}: only the binormal component of a 3-D pair may be fixed on both "
                    f"nodes, got dofs_a={a.tolist()}, dofs_b={b.tolist()}"
                )
            has_binormal[i] = False
        if np.all(b[~held] >= 0):
            replaced.append(b)
            rel.append((1.0, a))
        elif np.all(b < 0) and np.all(a >= 0):
            replaced.append(a)
            rel.append((-1.0, b))
        else:
            raise ValueError(
                f"contact pair {i}: node B must have every component free (or be fully grounded with node A "
                f"free), got dofs_a={a.tolist()}, dofs_b={b.tolist()}"
            )
    rep = np.concatenate(replaced)
    rep = rep[rep >= 0]
    if len(np.unique(rep)) != len(rep):
        raise ValueError("contact pairs share a node: each node B may belong to one pair only")
    others_ref = np.concatenate([r[1][r[1] >= 0] for r in rel])
    if np.intersect1d(rep, others_ref).size:
        raise ValueError("a node is node B of one pair and node A of another; pairs must not chain")
    binormal = np.cross(contact.normal, contact.tangent) if dim == 3 else None
    n_q = 2 * nc
    b_col = n_q + np.cumsum(has_binormal) - 1  # column of pair i's binormal coordinate
    n_rel = n_q + int(has_binormal.sum())
    rest = np.setdiff1d(np.arange(size), rep)
    pos = np.full(size, -1)
    pos[rest] = n_rel + np.arange(len(rest))
    T = np.zeros((size, size))
    T[rest, pos[rest]] = 1.0
    for i, ((sign, other), dofs) in enumerate(zip(rel, replaced, strict=True)):
        for k in range(dim):
            r = dofs[k]
            if r < 0:  # fixed on both nodes
                continue
            if other[k] >= 0:
                T[r, pos[other[k]]] = 1.0
            T[r, 2 * i] = sign * contact.tangent[i, k]
            T[r, 2 * i + 1] = -sign * contact.normal[i, k]
            if has_binormal[i]:
                T[r, b_col[i]] = sign * binormal[i, k]
    return T, n_q, has_binormal


#: relative (Frobenius) residual of ``C - alpha K - beta M`` below which ``C`` is proportional (and
#: relative asymmetry of ``K``, ``M`` below which they are symmetric): the modal path's condition
PROPORTIONAL_TOL = 1e-12

#: smallest Cholesky pivot of ``K_ss``, squared, relative to its largest diagonal entry, for the modal
#: path: a glued structure free to move statically (singular ``K_ss``) takes the LU path
PIVOT_TOL = 1e-14


@dataclass(frozen=True)
class _GluedModes:
    """``D_ss^-1`` of the glued structure at every frequency from one factorization and its modes.

    With proportional damping ``C = alpha K + beta M``, ``D = K - w^2 M + i w C = c1 K + c2 M`` with
    ``c1 = 1 + i w alpha`` and ``c2 = i w beta - w^2``. With ``K_ss = R^T R`` (Cholesky) and the glued
    structure's modes ``M_ss phi_j = mu_j K_ss phi_j`` (``mu_j = 1 / omega_j^2``), ``Phi^T K_ss Phi = I``,
    ``Phi^T M_ss Phi = diag(mu)``:

        D_ss^-1 = Phi diag(1 / (c1 + c2 mu)) Phi^T = K_ss^-1 / c1 - Phi diag(g) Phi^T,
        g_j = c2 mu_j / (c1 (c1 + c2 mu_j)),

    so only the modes with mass (``mu_j > 0``) enter the second term: ``Phi = R^-1 U``, ``U`` the left
    singular vectors of ``R^-T L`` (``L L^T = M_ss``, ``mu = sigma^2``), as many as ``M_ss``'s rank (two
    for the sphere's holder, every mode for a Craig-Bampton model). With ``Y = R^-T K_sq``, ``Y_M = R^-T
    M_sq``, ``P = c1 Y^T U + c2 Y_M^T U`` and ``f = R^-T f_s``, eq. 11 is, with ``D_qq = c1 K_qq + c2 M_qq``,

        Z = c1 (K_qq - Y^T Y) + c2 (M_qq - Y^T Y_M - Y_M^T Y) - (c2^2 / c1) Y_M^T Y_M + P diag(g) P^T,
        F = f_q - Y^T f - (c2 / c1) Y_M^T f + P diag(g) U^T f:

    three real matrices (``Z_K``, the static ``Z_0``; ``Z_M``; ``S_MM``) and the modes with mass.

    ``O(s^3)`` once (``s`` condensed coordinates), then ``O(q^2 r)`` per harmonic and frequency against
    an ``O(s^3 + s^2 q + s q^2)`` complex LU and solve each.
    """

    alpha: float
    beta: float
    R: np.ndarray  # (s, s) upper Cholesky factor of K_ss
    U: np.ndarray  # (s, r) the modes with mass, whitened
    mu: np.ndarray  # (r,) their 1 / omega_j^2 (s^2)
    Y: np.ndarray  # (s, q) R^-T K_sq
    Y_M: np.ndarray | None  # (s, q) R^-T M_sq, None where M_sq = 0
    Z_K: np.ndarray  # (q, q) K_qq - K_qs K_ss^-1 K_sq: Z_0
    Z_M: np.ndarray | None  # (q, q) M_qq - K_qs K_ss^-1 M_sq - its transpose, None where 0
    S_MM: np.ndarray | None  # (q, q) M_qs K_ss^-1 M_sq
    A: np.ndarray  # (q, r) K_qs Phi
    B: np.ndarray | None  # (q, r) M_qs Phi

    @classmethod
    def build(cls, cond: ContactCondensation, keep: int, alpha: float, beta: float) -> _GluedModes | None:
        """The modes of ``cond``'s glued structure on ``z[keep:]``, or None when ``K_ss`` is not positive
        definite or ``M_ss`` not positive semi-definite (the LU path then)."""
        K, M, q = cond.K, cond.M, keep
        K_ss = K[q:, q:]
        try:
            R = sla.cholesky(K_ss, lower=False, check_finite=False)
        except sla.LinAlgError:
            return None
        if np.min(np.diag(R)) ** 2 <= PIVOT_TOL * np.max(np.diag(K_ss)):
            return None
        s = K_ss.shape[0]
        M_ss = M[q:, q:]
        sup = np.flatnonzero(np.abs(M_ss).max(axis=1) > 0)  # the coordinates with mass
        lam, V = np.linalg.eigh(M_ss[np.ix_(sup, sup)])
        top = lam.max(initial=0.0)
        if lam.min(initial=0.0) < -PROPORTIONAL_TOL * len(sup) * top:
            return None
        pos = lam > np.finfo(float).eps * len(sup) * top  # M_ss = L L^T on its numerical rank
        L = np.zeros((s, int(pos.sum())))
        L[sup] = V[:, pos] * np.sqrt(lam[pos])
        U, sig = np.zeros((s, 0)), np.zeros(0)
        if L.shape[1]:
            U, sig, _ = sla.svd(cls._whiten(R, L), full_matrices=False, check_finite=False)
            rank = sig > np.finfo(float).eps * max(L.shape) * sig.max()
            U, sig = U[:, rank], sig[rank]
        Y = cls._whiten(R, K[q:, :q])
        Y_M = cls._whiten(R, M[q:, :q]) if np.any(M[q:, :q]) else None
        S_KM = 0.0 if Y_M is None else Y.T @ Y_M
        Z_K, Z_M = K[:q, :q] - Y.T @ Y, 0.5 * (M[:q, :q] + M[:q, :q].T) - (S_KM + np.transpose(S_KM))
        Z_M = Z_M if np.any(Z_M) else None
        return cls(
            alpha, beta, R, U, sig**2, Y, Y_M, 0.5 * (Z_K + Z_K.T), Z_M,
            None if Y_M is None else Y_M.T @ Y_M, Y.T @ U, None if Y_M is None else Y_M.T @ U,
        )  # fmt: skip

    @staticmethod
    def _whiten(R: np.ndarray, X: np.ndarray) -> np.ndarray:
        """``R^-T X`` (real ``R``, real or complex ``X``)."""
        if np.iscomplexobj(X):
            return sla.solve_triangular(R, X.real, trans="T", check_finite=False) + 1j * sla.solve_triangular(
                R, X.imag, trans="T", check_finite=False
            )
        return sla.solve_triangular(R, X, trans="T", check_finite=False)

    def _coefficients(self, w: float) -> tuple:
        """``(c1, c2, g)`` at the angular frequency ``w`` (rad/s): real at ``w = 0``."""
        if w == 0:
            return 1.0, 0.0, np.zeros(len(self.mu))
        c1, c2 = complex(1.0, w * self.alpha), complex(-(w**2), w * self.beta)
        den = c1 + c2 * self.mu
        if np.any(den == 0):
            raise ValueError(
                f"the structure with every contact pair glued is singular at {w!r} rad/s (an undamped mode "
                "of the glued structure): add damping"
            )
        return c1, c2, c2 * self.mu / (c1 * den)

    def terms(self, w: float) -> tuple[list, np.ndarray | None]:
        """``Z`` at the angular frequency ``w`` (rad/s) as ``sum_i c_i X_i`` (real ``X_i``, complex ``c_i``:
        the list of pairs) plus its modal part ``P diag(g) P^T`` (complex, symmetric to rounding; None at
        ``w = 0``) (class text)."""
        c1, c2, g = self._coefficients(w)
        out = [(c1, self.Z_K)]
        if c2 != 0 and self.Z_M is not None:
            out.append((c2, self.Z_M))
        if c2 != 0 and self.S_MM is not None:
            out.append((-(c2**2) / c1, self.S_MM))
        if c2 == 0 or not len(g):
            return out, None
        P = c1 * self.A if self.B is None else c1 * self.A + c2 * self.B
        return out, (P * g) @ P.T

    def force(self, f_q: np.ndarray, f_s: np.ndarray, w: float) -> np.ndarray:
        """``F`` of eq. 11 at the angular frequency ``w`` (rad/s) from the forces ``f_q`` and ``f_s`` (N) on
        the kept and the condensed coordinates (class text)."""
        c1, c2, g = self._coefficients(w)
        fw = self._whiten(self.R, f_s)
        F = f_q - self.Y.T @ fw
        if self.Y_M is not None and c2 != 0:
            F = F - (c2 / c1) * (self.Y_M.T @ fw)
        if c2 != 0 and len(g):
            P = c1 * self.A if self.B is None else c1 * self.A + c2 * self.B
            F = F + (P * g) @ (self.U.T @ fw)
        return F

    def schur(self, f: np.ndarray, w: float) -> tuple[np.ndarray, np.ndarray]:
        """``(Z, F)`` of eq. 11 at the angular frequency ``w`` (rad/s) from the force ``f`` (N) on every
        coordinate."""
        terms, W = self.terms(w)
        Z = sum(c * X for c, X in terms)
        q = self.Z_K.shape[0]
        return (Z if W is None else Z + W), self.force(f[:q], f[q:], w)

    def permuted(self, idx: np.ndarray) -> _GluedModes:
        """The same on the kept coordinates ``idx`` (a permutation, possibly repeating some)."""
        sub = {k: getattr(self, k) for k in ("Z_K", "Z_M", "S_MM")}
        sub = {k: None if v is None else v[np.ix_(idx, idx)] for k, v in sub.items()}
        return replace(
            self, **sub, A=self.A[idx], B=None if self.B is None else self.B[idx], Y=self.Y[:, idx],
            Y_M=None if self.Y_M is None else self.Y_M[:, idx],
        )  # fmt: skip

    def solve(self, w: float, rhs: np.ndarray) -> np.ndarray:
        """``D_ss^-1 rhs`` at the angular frequency ``w`` (rad/s) (class text)."""
        c1, c2, g = self._coefficients(w)
        y = self._whiten(self.R, rhs)
        if c2 != 0 and len(g):
            y = y / c1 - self.U @ ((g if y.ndim == 1 else g[:, None]) * (self.U.T @ y))
        else:
            y = y / c1
        if np.iscomplexobj(y):
            return sla.solve_triangular(self.R, y.real, check_finite=False) + 1j * sla.solve_triangular(
                self.R, y.imag, check_finite=False
            )
        return sla.solve_triangular(self.R, y, check_finite=False)


class ContactCondensation:
    """Reduced dynamic stiffness ``Z_k`` and force ``F_k`` on the contact coordinates (eq. 11).

    Parameters
    ----------
    model : Model
        A model with contact pairs and dense matrices: a reduced model
        (:func:`~fretwear.model.craig_bampton`) or a small dense one.
    modal : bool
        Apply ``D_ss^-1`` by the glued structure's modes when the damping is proportional
        (``_GluedModes``; same answer, a factorization for every harmonic and frequency less);
        False: always by a complex LU per harmonic (the reference).

    Attributes
    ----------
    model : Model
        The condensed model.
    full : Model
        The model whose DOFs the solutions report: ``model.reduction.full`` for
        a reduced model, else ``model``.
    """

    def __init__(self, model: Model, modal: bool = True) -> None:
        if not isinstance(model, Model) or model.pairs is None:
            raise ValueError(f"model must be a Model with contact pairs, got {model!r:.80}")
        if model.sparse:
            raise ValueError(
                f"model has sparse matrices ({model.n_dofs} DOFs): reduce it first "
                "(fretwear.reduce, Craig-Bampton) to dense matrices on the contact and loaded DOFs"
            )
        self.model = model
        self.modal = bool(modal)
        self.full = model if model.reduction is None else model.reduction.full
        T, self.n_q, self.has_binormal = _contact_coordinates(model.pairs, model.n_dofs)
        self.T = T
        Ts = sp.csr_matrix(T)  # a permutation and the pairs' couplings: sparse products, not n^3 dense ones
        self.K, self.M, self.C = (
            np.ascontiguousarray((Ts.T @ (Ts.T @ A).T).T) for A in (model.K, model.M, model.C)
        )
        self.force_static = T.T @ model.force_static
        self.force_harmonic = T.T @ (model.force_cos - 1j * model.force_sin)  # complex amplitude
        self._modes: dict[int, _GluedModes | None] = {}
        self._lu_cache: tuple = (None, None)
        self._permuted: dict = {}

    @property
    def n_pairs(self) -> int:
        return self.n_q // 2

    def dynamic_stiffness(self, omega: float, order: int) -> np.ndarray:
        """``D_k`` in the contact coordinates ``z`` (complex, or real at ``k omega = 0``)."""
        w = order * omega
        if w == 0:
            return self.K
        return self.K - w**2 * self.M + 1j * w * self.C

    def _block(self, omega: float, order: int, rows: slice, cols: slice) -> np.ndarray:
        """The block ``D_k[rows, cols]`` of :meth:`dynamic_stiffness`, formed alone."""
        w = order * omega
        if w == 0:
            return self.K[rows, cols]
        return self.K[rows, cols] - w**2 * self.M[rows, cols] + 1j * w * self.C[rows, cols]

    def forcing(self, order: int, scale: float = 1.0) -> np.ndarray:
        """Force amplitude of order ``k`` in ``z`` (static load for ``k = 0``, excitation for ``k = 1``)."""
        if order == 0:
            return self.force_static
        if order == 1:
            return scale * self.force_harmonic
        return np.zeros(len(self.force_static))

    @cached_property
    def proportional(self) -> tuple[float, float] | None:
        """``(alpha, beta)`` (s, s^-1) with ``C = alpha K + beta M`` (Rayleigh damping, ``C = 0`` included)
        to ``PROPORTIONAL_TOL`` relative (Frobenius), symmetric ``K`` and ``M``; else None."""
        K, M, C = self.K, self.M, self.C
        if any(np.abs(A - A.T).max(initial=0.0) > PROPORTIONAL_TOL * np.abs(A).max(initial=0.0)
               for A in (K, M)):  # fmt: skip
            return None
        norm_c = np.linalg.norm(C)
        if norm_c == 0:
            return 0.0, 0.0
        # least squares on the entries: the 2 x 2 normal equations of the Frobenius inner product
        G = np.array([[np.vdot(K, K), np.vdot(K, M)], [np.vdot(M, K), np.vdot(M, M)]])
        ab = np.linalg.lstsq(G, np.array([np.vdot(K, C), np.vdot(M, C)]), rcond=None)[0]
        if np.linalg.norm(C - ab[0] * K - ab[1] * M) > PROPORTIONAL_TOL * norm_c:
            return None
        return float(ab[0]), float(ab[1])

    def _modal(self, keep: int) -> _GluedModes | None:
        """The glued structure's modes on ``z[keep:]`` (``_GluedModes``, cached per ``keep``), or None
        when ``C`` is not proportional or ``K_ss`` not positive definite (then the LU path)."""
        if keep not in self._modes:
            ab = self.proportional if self.modal else None
            self._modes[keep] = None if ab is None else _GluedModes.build(self, keep, *ab)
        return self._modes[keep]

    def _lu(self, omega: float, order: int, keep: int) -> tuple:
        """LU factors of ``D_ss`` (the general path), the last one cached."""
        key = (omega * order, keep)
        if self._lu_cache[0] != key:
            D_ss = self._block(omega, order, slice(keep, None), slice(keep, None))
            try:
                fac = sla.lu_factor(D_ss, check_finite=False)
            except (sla.LinAlgError, ValueError) as exc:
                raise ValueError(f"the structure with every contact pair glued is singular ({exc})") from None
            if not np.all(np.isfinite(fac[0])) or np.min(np.abs(np.diag(fac[0]))) == 0:
                raise ValueError(
                    f"the structure with every contact pair glued is singular at omega = {omega!r} rad/s, "
                    f"harmonic {order}: anchor it, or add damping"
                )
            self._lu_cache = (key, fac)
        return self._lu_cache[1]

    def glued_solve(self, omega: float, order: int, rhs: np.ndarray, keep: int | None = None) -> np.ndarray:
        """``D_ss^-1 rhs`` at harmonic ``order``: the coordinates ``z[keep:]`` (default ``keep = n_q``) of the
        structure with the first ``keep`` ones held, under the forces ``rhs`` (N)."""
        q = self.n_q if keep is None else keep
        if rhs.shape[0] == 0:
            return rhs
        modes = self._modal(q)
        if modes is not None:
            return modes.solve(order * omega, rhs)
        return sla.lu_solve(self._lu(omega, order, q), rhs, check_finite=False)

    def schur(self, omega: float, order: int, keep: int | None = None) -> tuple[np.ndarray, np.ndarray, str]:
        """``(Z_k, F_k at unit excitation scale, path)`` for one harmonic order (complex for ``k > 0``),
        on the first ``keep`` coordinates of ``z`` (default ``n_q``; ``n_q`` plus the binormals: all the
        relative ones).

        ``path`` says how ``D_ss^-1`` was applied: ``"modal"``, by the glued structure's modes
        (``_GluedModes``, when ``C`` is proportional: every harmonic and frequency from one
        eigenproblem), ``"lu"``, by a complex LU of ``D_ss`` (the general path), or ``"none"`` (no
        coordinate to condense).
        """
        q = self.n_q if keep is None else keep
        f = self.forcing(order)
        if self.K.shape[0] == q:  # every coordinate is a contact coordinate
            D = self.dynamic_stiffness(omega, order)
            return 0.5 * (D + D.T), f, "none"
        modes = self._modal(q)
        if modes is not None:
            Z, F = modes.schur(f, order * omega)
            return Z, F, "modal"
        D = self.dynamic_stiffness(omega, order)
        X = sla.lu_solve(self._lu(omega, order, q), np.column_stack([D[q:, :q], f[q:]]), check_finite=False)
        Z = D[:q, :q] - D[:q, q:] @ X[:, :q]
        F = f[:q] - D[:q, q:] @ X[:, q]
        return 0.5 * (Z + Z.T), F, "lu"

    @cached_property
    def static(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(Z_0, F_s, F_c)`` on the contact coordinates: static stiffness (N/m), static load and the
        static effect of the ``cos`` excitation pattern (N)."""
        Z, F, _ = self.schur(0.0, 0)
        q = self.n_q
        fc = self.force_harmonic.real
        return Z, F, fc[:q] - self.K[:q, q:] @ self.glued_solve(0.0, 0, fc[q:])

    def cone_coordinates(self) -> np.ndarray:
        """Per pair the columns of ``z`` of its ``(u_T1, u_T2, u_N)``, shape (nc, 3): tangent, binormal
        (``-1`` for a pair without one: a symmetry plane through it) and normal."""
        nc = self.n_pairs
        b = np.full(nc, -1)
        b[self.has_binormal] = self.n_q + np.arange(int(self.has_binormal.sum()))
        return np.column_stack([2 * np.arange(nc), b, 2 * np.arange(nc) + 1])

    def harmonic(
        self, omega: float, basis: HarmonicBasis, binormal: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """Real ``Z`` (2 nc H, 2 nc H) and ``F`` (2 nc H,) in the contact-major layout of ``basis``.

        Entry ``c H + j`` is slot ``j`` of coordinate ``c`` (``c = 2 i`` tangential,
        ``2 i + 1`` normal, for pair ``i``). ``Z`` is the dense form of :meth:`harmonic_blocks`' blocks
        (it has no entry between two harmonics).

        With ``binormal`` (3-D pairs, the 2-D friction law): ``Z`` (3 nc H, 3 nc H) and ``F`` on
        ``(u_T1, u_T2, u_N)`` of every pair (``c = 3 i``, ``3 i + 1``, ``3 i + 2``), the binormal kept
        in the Schur complement instead of condensed. A pair without a binormal coordinate (both
        nodes held along it: a symmetry plane through the pair, where the binormal displacement and
        traction vanish) gets a decoupled one, ``Z`` its tangent's diagonal and no force: then ``u_T2
        = 0``, ``lambda_T2 = 0`` is the law's solution for it, as the symmetry requires.
        """
        Zb, F = self.harmonic_blocks(omega, basis, binormal)
        return dense_from_blocks(Zb), F

    def harmonic_blocks(
        self, omega: float, basis: HarmonicBasis, binormal: bool = False
    ) -> tuple[np.ndarray, np.ndarray]:
        """``Z`` by harmonic, shape (Nh + 1, 2 q, 2 q), and ``F`` (q H,) as :meth:`harmonic`'s (``q`` = 2 nc,
        or 3 nc with ``binormal``), never forming the dense ``Z`` (eq. 11 holds harmonic by harmonic).

        ``Zb[0, :q, :q]`` is the mean's block (real ``Z_0``); for ``k >= 1`` the block on the cosine slots
        then the sine slots of the coordinates, ``[[Re Z_k, Im Z_k], [-Im Z_k, Re Z_k]]`` (N/m): the
        layout of ``fretwear.hbm.structured.harmonic_blocks``, ``(Nh + 1) 4 q^2`` numbers against
        ``q^2 H^2`` for the dense ``Z``.
        """
        if basis.half_wave:
            raise ValueError("interfaces use the full harmonic basis (half_wave=False)")
        H = basis.size
        keep, order = self.n_q, None
        if binormal:
            if self.model.pairs.dim != 3:
                raise ValueError(f"binormal needs 3-D contact pairs, got dim = {self.model.pairs.dim}")
            cols = self.cone_coordinates()
            keep = self.n_q + int(self.has_binormal.sum())
            order = cols.ravel()
        nq = len(order) if binormal else self.n_q
        Zb = np.zeros((basis.harmonics + 1, 2 * nq, 2 * nq))
        Fr = np.zeros((nq, H))
        modes = self._modal(keep) if self.K.shape[0] > keep else None
        if modes is not None:  # the blocks from the modes' real terms, in the kept order
            return self._modal_blocks(modes, omega, basis, keep, order, Zb, Fr)
        for k in range(basis.harmonics + 1):
            Zk, Fk, _ = self.schur(omega, k, keep)
            if binormal:  # to the pair-major (t, b, n) order, a dummy binormal where the pair has none
                held = np.flatnonzero(order < 0)
                idx = np.where(order < 0, 0, order)
                Zk, Fk = Zk[np.ix_(idx, idx)], Fk[idx]
                Zk[held, :], Zk[:, held], Fk[held] = 0.0, 0.0, 0.0
                Zk[held, held] = np.abs(Zk[held - 1, held - 1])  # the pair's tangent, just before
            if k == 0:
                Zb[0, :nq, :nq] = Zk.real
                Fr[:, 0] = Fk.real
                continue
            X, Y = Zk.real, Zk.imag
            Zb[k, :nq, :nq] = Zb[k, nq:, nq:] = X
            Zb[k, :nq, nq:] = Y
            Zb[k, nq:, :nq] = -Y
            Fr[:, 2 * k - 1] = Fk.real
            Fr[:, 2 * k] = -Fk.imag
        return Zb, Fr.reshape(nq * H)

    def _modal_blocks(self, modes, omega, basis, keep, order, Zb, Fr) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`harmonic_blocks` by the glued structure's modes: per harmonic a few real ``q x q`` sums
        (:meth:`_GluedModes.terms`), permuted once to the pair-major order."""
        nq = Zb.shape[1] // 2
        idx = np.arange(nq) if order is None else np.where(order < 0, 0, order)
        held = np.flatnonzero(idx != (np.arange(nq) if order is None else order))
        key = (keep, idx.tobytes())
        if key not in self._permuted:
            self._permuted[key] = modes if order is None else modes.permuted(idx)
        perm = self._permuted[key]
        for k in range(basis.harmonics + 1):
            f = self.forcing(k)
            Fk = perm.force(f[:keep][idx], f[keep:], k * omega)
            terms, W = perm.terms(k * omega)
            X = np.zeros((nq, nq)) if W is None else W.real.copy()
            Y = np.zeros((nq, nq)) if W is None else W.imag.copy()
            for c, A in terms:
                X += np.real(c) * A
                if np.imag(c) != 0:
                    Y += np.imag(c) * A
            if held.size:  # a dummy binormal: decoupled, the pair's tangent's |Z_k| on its diagonal
                diag = np.abs(X[held - 1, held - 1] + 1j * Y[held - 1, held - 1])
                X[held, :], X[:, held], Y[held, :], Y[:, held], Fk[held] = 0.0, 0.0, 0.0, 0.0, 0.0
                X[held, held] = diag
            if k == 0:
                Zb[0, :nq, :nq] = X
                Fr[:, 0] = Fk.real
                continue
            Zb[k, :nq, :nq] = Zb[k, nq:, nq:] = X
            Zb[k, :nq, nq:] = Y
            Zb[k, nq:, :nq] = -Y
            Fr[:, 2 * k - 1] = Fk.real
            Fr[:, 2 * k] = -Fk.imag
        return Zb, Fr.reshape(nq * basis.size)

    def full_harmonics(
        self, omega: float, harmonics: int, q: np.ndarray, dofs: np.ndarray | None = None
    ) -> np.ndarray:
        """Full harmonics (n, 2 Nh + 1) of the DOFs of ``full`` (m) from those of the contact
        coordinates ``q`` (n_q, 2 Nh + 1), or with the binormals after them (``n_q`` plus their number:
        the 2-D friction law's); only the rows ``dofs`` (full-model indices) when given."""
        coords = self.recover(omega, harmonics, q)
        reduction = self.model.reduction
        if dofs is None:
            return coords if reduction is None else reduction.expand(coords.T).T
        if reduction is None:
            return coords[np.asarray(dofs)]
        return np.array([reduction.coordinate(d) @ coords for d in dofs])  # a row each: no full expansion

    def recover(self, omega: float, harmonics: int, q: np.ndarray) -> np.ndarray:
        """Reduced coordinates' full harmonics (n_r, 2 Nh + 1) from the contact coordinates' (n_q, 2 Nh + 1).

        ``z_s = D_ss^{-1} (F_s - D_sq q)`` per harmonic: the contact forces act on ``q`` only (``q`` with
        the binormals: the first ``len(q)`` coordinates of ``z``).
        """
        out_z = np.zeros((self.T.shape[0], 2 * harmonics + 1))
        nq = q.shape[0]
        for k in range(harmonics + 1):
            qk = q[:, 0] if k == 0 else q[:, 2 * k - 1] - 1j * q[:, 2 * k]
            D_sq = self._block(omega, k, slice(nq, None), slice(nq))
            zs = self.glued_solve(omega, k, self.forcing(k)[nq:] - D_sq @ qk, nq)
            z = np.concatenate([qk, zs])
            if k == 0:
                out_z[:, 0] = z.real
            else:
                out_z[:, 2 * k - 1] = z.real
                out_z[:, 2 * k] = -z.imag
        return self.T @ out_z
