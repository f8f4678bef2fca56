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
"""

from __future__ import annotations

from functools import cached_property

import numpy as np
import scipy.linalg as sla

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


class ContactCondensation:
    """Reduced dynamic stiffness ``Z_k`` and force ``F_k`` on the contact coordinates (eq. 11).

    Parameters
    ----------
    model : Model
        A model with contact pairs and dense matrices: a reduced model
        (:func:`~fretwear.model.craig_bampton`) or a small dense one.

    Attributes
    ----------
    model : Model
        The condensed model.
    full : Model
        The model whose DOFs the solutions report: ``model.reduction.full`` for
        a reduced model, else ``model``.
    """

    def __init__(self, model: Model) -> None:
        if not isinstance(model, Model) or model.pairs is None:
            raise ValueError(f"model must be a Model with contact pairs, got {model!r:.80}")
        if model.sparse:
            raise ValueError(
                f"model has sparse matrices ({model.n_dofs} DOFs): reduce it first "
                "(fretwear.reduce, Craig-Bampton) to dense matrices on the contact and loaded DOFs"
            )
        self.model = model
        self.full = model if model.reduction is None else model.reduction.full
        T, self.n_q, self.has_binormal = _contact_coordinates(model.pairs, model.n_dofs)
        self.T = T
        self.K = T.T @ model.K @ T
        self.M = T.T @ model.M @ T
        self.C = T.T @ model.C @ T
        self.force_static = T.T @ model.force_static
        self.force_harmonic = T.T @ (model.force_cos - 1j * model.force_sin)  # complex amplitude

    @property
    def n_pairs(self) -> int:
        return self.n_q // 2

    def dynamic_stiffness(self, omega: float, order: int) -> np.ndarray:
        """``D_k`` in the contact coordinates ``z`` (complex, or real at ``k omega = 0``)."""
        w = order * omega
        if w == 0:
            return self.K
        return self.K - w**2 * self.M + 1j * w * self.C

    def forcing(self, order: int, scale: float = 1.0) -> np.ndarray:
        """Force amplitude of order ``k`` in ``z`` (static load for ``k = 0``, excitation for ``k = 1``)."""
        if order == 0:
            return self.force_static
        if order == 1:
            return scale * self.force_harmonic
        return np.zeros(len(self.force_static))

    def schur(
        self, omega: float, order: int, keep: int | None = None
    ) -> tuple[np.ndarray, np.ndarray, tuple]:
        """``(Z_k, F_k at unit excitation scale, factors)`` for one harmonic order (complex for ``k > 0``),
        on the first ``keep`` coordinates of ``z`` (default ``n_q``; ``n_q`` plus the binormals: all the
        relative ones)."""
        D = self.dynamic_stiffness(omega, order)
        q = self.n_q if keep is None else keep
        D_ss = D[q:, q:]
        if D_ss.size == 0:  # every coordinate is a contact coordinate
            return 0.5 * (D + D.T), self.forcing(order), (None, None)
        try:
            fac = sla.lu_factor(D_ss, check_finite=False)
        except (sla.LinAlgError, ValueError) as exc:
            raise ValueError(f"the structure with every contact pair glued is singular ({exc})") from None
        if not np.all(np.isfinite(fac[0])) or np.min(np.abs(np.diag(fac[0]))) == 0:
            raise ValueError(
                f"the structure with every contact pair glued is singular at omega = {omega!r} rad/s, "
                f"harmonic {order}: anchor it, or add damping"
            )
        X = sla.lu_solve(fac, np.column_stack([D[q:, :q], self.forcing(order)[q:]]), check_finite=False)
        Z = D[:q, :q] - D[:q, q:] @ X[:, :q]
        F = self.forcing(order)[:q] - D[:q, q:] @ X[:, q]
        return 0.5 * (Z + Z.T), F, (fac, X)

    @cached_property
    def static(self) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(Z_0, F_s, F_c)`` on the contact coordinates: static stiffness (N/m), static load and the
        static effect of the ``cos`` excitation pattern (N)."""
        Z, F, (fac, _) = self.schur(0.0, 0)
        q = self.n_q
        fc = self.force_harmonic.real
        if fac is None:
            return Z, F, fc
        Fc = fc[:q] - self.K[:q, q:] @ sla.lu_solve(fac, fc[q:], check_finite=False)
        return Z, F, Fc

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
            D = self.dynamic_stiffness(omega, k)
            qk = q[:, 0] if k == 0 else q[:, 2 * k - 1] - 1j * q[:, 2 * k]
            rhs = self.forcing(k)[nq:] - D[nq:, :nq] @ qk
            zs = sla.solve(D[nq:, nq:], rhs, check_finite=False) if len(rhs) else rhs
            z = np.concatenate([qk, zs])
            if k == 0:
                out_z[:, 0] = z.real
            else:
                out_z[:, 2 * k - 1] = z.real
                out_z[:, 2 * k] = -z.imag
        return self.T @ out_z
