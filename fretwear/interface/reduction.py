"""Craig-Bampton reduction and condensation on the contact coordinates (paper eq. 11).

**Craig-Bampton.** The DOFs split into boundary DOFs ``b`` (every DOF of the
contact pairs and every loaded DOF, plus any requested output DOF) kept
physical, and interior DOFs ``i``. The interior displacement is
``u_i = Psi u_b + Phi eta`` with the static constraint modes ``Psi = -K_ii^{-1}
K_ib`` (exact in statics) and the fixed-interface modes ``Phi`` (``K_ii phi =
omega^2 M_ii phi``, mass-normalised). **Mode count criterion:** every
fixed-interface mode with natural frequency up to ``factor * f_max`` is kept,
where ``f_max`` is the highest frequency the harmonic balance will see
(``Nh`` times the highest excitation frequency) and ``factor = 2`` by default
(the usual 1.5-2 rule). Everything is sparse up to the reduced matrices,
which are dense and of size ``n_b + n_modes``.

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

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..hbm.harmonics import HarmonicBasis
from .structure import ContactPairs, InterfaceModel

__all__ = ["ReducedModel", "craig_bampton", "ContactCondensation"]


@dataclass(frozen=True, eq=False)
class ReducedModel:
    """A Craig-Bampton reduced model.

    Attributes
    ----------
    model : InterfaceModel
        The full model.
    boundary : ndarray of int
        Full-model DOFs kept physical; reduced coordinate ``j < n_b`` is DOF ``boundary[j]``.
    interior : ndarray of int
        The other full-model DOFs.
    mode_frequencies : ndarray
        Natural frequencies of the kept fixed-interface modes (Hz).
    cutoff : float
        Frequency criterion (Hz): every fixed-interface mode below it is kept.
    K, M, C : ndarray, shape (n_r, n_r)
        Reduced matrices (boundary DOFs, then modal coordinates).
    force_static, force_cos, force_sin : ndarray, shape (n_r,)
        Reduced loads (N).
    contact : ContactPairs
        The pairs with their DOFs numbered in reduced coordinates.
    psi, phi : ndarray
        Constraint modes (n_i, n_b) and fixed-interface modes (n_i, n_m).
    """

    model: InterfaceModel
    boundary: np.ndarray
    interior: np.ndarray
    mode_frequencies: np.ndarray
    cutoff: float
    K: np.ndarray
    M: np.ndarray
    C: np.ndarray
    force_static: np.ndarray
    force_cos: np.ndarray
    force_sin: np.ndarray
    contact: ContactPairs
    psi: np.ndarray = field(repr=False)
    phi: np.ndarray = field(repr=False)

    @property
    def size(self) -> int:
        """Reduced coordinates ``n_b + n_modes``."""
        return self.K.shape[0]

    @property
    def n_modes(self) -> int:
        return self.phi.shape[1]

    def expand(self, coords: np.ndarray) -> np.ndarray:
        """Full-model DOF values from reduced coordinates (..., n_r) (any real or complex dtype)."""
        coords = np.asarray(coords)
        nb = len(self.boundary)
        out = np.zeros(coords.shape[:-1] + (self.model.n_dofs,), dtype=coords.dtype)
        out[..., self.boundary] = coords[..., :nb]
        out[..., self.interior] = coords[..., :nb] @ self.psi.T + coords[..., nb:] @ self.phi.T
        return out

    def coordinate(self, dof: int) -> np.ndarray:
        """Row vector ``r`` with ``u[dof] = r @ coords`` (full-model DOF from reduced coordinates)."""
        r = np.zeros(self.size)
        nb = len(self.boundary)
        where = np.flatnonzero(self.boundary == dof)
        if len(where):
            r[where[0]] = 1.0
        else:
            j = int(np.flatnonzero(self.interior == dof)[0])
            r[:nb] = self.psi[j]
            r[nb:] = self.phi[j]
        return r


def _project(A: sp.csr_matrix, b: np.ndarray, i: np.ndarray, psi: np.ndarray, phi: np.ndarray) -> np.ndarray:
    """``T^T A T`` for ``T = [[I, 0], [Psi, Phi]]`` (boundary, interior), dense result."""
    A_bb = A[b][:, b].toarray()
    A_bi = A[b][:, i]
    A_ii = A[i][:, i]
    Aii_psi = A_ii @ psi
    Aii_phi = A_ii @ phi
    bb = A_bb + A_bi @ psi
    bb = bb + bb.T - A_bb + psi.T @ Aii_psi
    bm = A_bi @ phi + psi.T @ Aii_phi
    mm = phi.T @ Aii_phi
    out = np.block([[bb, bm], [bm.T, mm]])
    return 0.5 * (out + out.T)


def craig_bampton(
    model: InterfaceModel,
    f_max: float,
    factor: float = 2.0,
    outputs=(),
    max_modes: int = 400,
) -> ReducedModel:
    """Craig-Bampton reduction of ``model`` keeping the modes below ``factor * f_max``.

    Parameters
    ----------
    model : InterfaceModel
    f_max : float
        Highest frequency of interest (Hz), >= 0: ``Nh`` times the highest
        excitation frequency for a harmonic balance; 0 keeps no mode (statics,
        Guyan reduction).
    factor : float
        Mode count criterion, ``>= 1``: fixed-interface modes up to ``factor *
        f_max`` are kept (default 2).
    outputs : sequence of int or str
        Further DOFs to keep physical (names or indices).
    max_modes : int
        Upper bound on the kept modes; exceeding it raises ``ValueError``.

    Returns
    -------
    ReducedModel
    """
    if not (np.isfinite(f_max) and f_max >= 0):
        raise ValueError(f"f_max must be a finite frequency >= 0 Hz (0: statics, no modes), got {f_max!r}")
    if not (np.isfinite(factor) and factor >= 1):
        raise ValueError(f"factor must be >= 1, got {factor!r}")
    n = model.n_dofs
    c = model.contact
    keep = [c.dofs_a[c.dofs_a >= 0], c.dofs_b[c.dofs_b >= 0], model.loaded_dofs]
    keep.append(np.array([model.dof(o) for o in outputs], dtype=np.int64))
    boundary = np.unique(np.concatenate(keep).astype(np.int64))
    mask = np.ones(n, dtype=bool)
    mask[boundary] = False
    interior = np.flatnonzero(mask)
    K, M = model.K, model.M
    K_ii = K[interior][:, interior].tocsc()
    K_ib = K[interior][:, boundary]
    lu = None
    psi = np.zeros((0, len(boundary)))
    if len(interior):
        try:
            # symmetric positive definite: symmetric ordering, no pivoting (half the fill of the default)
            lu = spla.splu(
                K_ii, permc_spec="MMD_AT_PLUS_A", diag_pivot_thresh=0.0, options={"SymmetricMode": True}
            )
        except RuntimeError as exc:
            raise ValueError(
                "the interior stiffness K_ii (every contact and loaded DOF fixed) is singular: some part of "
                f"the structure is not held by the boundary DOFs ({exc})"
            ) from None
        psi = -lu.solve(K_ib.toarray())
    cutoff = factor * f_max
    omega_c = 2 * np.pi * cutoff
    M_ii = M[interior][:, interior].tocsc()
    phi, w2 = np.zeros((len(interior), 0)), np.zeros(0)
    if lu is not None and cutoff > 0:
        op = spla.LinearOperator(K_ii.shape, matvec=lu.solve, dtype=float)
        k = min(12, len(interior) - 1)
        while k > 0:
            vals, vecs = spla.eigsh(K_ii, k=k, M=M_ii, sigma=0.0, OPinv=op, which="LM", tol=1e-10)
            order = np.argsort(vals)
            vals, vecs = vals[order], vecs[:, order]
            if vals[-1] > omega_c**2 or k >= len(interior) - 1:
                sel = vals <= omega_c**2
                w2, phi = vals[sel], vecs[:, sel]
                break
            if k >= max_modes:
                raise ValueError(
                    f"more than max_modes = {max_modes} fixed-interface modes lie below the cutoff "
                    f"{cutoff:.6g} Hz; lower f_max or factor, or raise max_modes"
                )
            # Weyl's law in 2-D: the mode count grows like omega^2; ask for a margin more
            guess = int(np.ceil(1.25 * k * omega_c**2 / vals[-1])) + 4
            k = min(max(2 * k, guess), len(interior) - 1, max_modes)
        phi = phi / np.sqrt(np.einsum("ij,ij->j", phi, M_ii @ phi))
    Kr = _project(K, boundary, interior, psi, phi)
    Mr = _project(M, boundary, interior, psi, phi)
    Cr = _project(model.C, boundary, interior, psi, phi)

    def load(f: np.ndarray) -> np.ndarray:
        return np.concatenate([f[boundary] + psi.T @ f[interior], phi.T @ f[interior]])

    index = np.full(n, -1)
    index[boundary] = np.arange(len(boundary))
    contact = ContactPairs(
        dofs_a=np.where(c.dofs_a >= 0, index[c.dofs_a], -1),
        dofs_b=np.where(c.dofs_b >= 0, index[c.dofs_b], -1), normal=c.normal, area=c.area, mu=c.mu,
        gap=c.gap, tangent=c.tangent, position=c.position,
    )  # fmt: skip
    return ReducedModel(
        model=model, boundary=boundary, interior=interior, mode_frequencies=np.sqrt(w2) / (2 * np.pi),
        cutoff=cutoff, K=Kr, M=Mr, C=Cr, force_static=load(model.force_static),
        force_cos=load(model.force_cos), force_sin=load(model.force_sin), contact=contact, psi=psi, phi=phi,
    )  # fmt: skip


def _contact_coordinates(contact: ContactPairs, size: int) -> tuple[np.ndarray, int]:
    """Transformation ``T`` (size, size) with ``coords = T z``, ``z = (q, slaves)``; returns ``(T, n_q)``.

    ``q`` holds ``(u_T, u_N)`` per pair (pair-major); in 3-D the binormal
    relative displacements come next; then every coordinate not replaced.
    """
    nc, dim = contact.count, contact.dim
    replaced, rel = [], []  # replaced coordinate, and its sign convention (+1: node B, -1: node A)
    for i in range(nc):
        a, b = contact.dofs_a[i], contact.dofs_b[i]
        if np.all(b >= 0):
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
    if len(np.unique(rep)) != len(rep):
        raise ValueError("contact pairs share a node: each node B may belong to one pair only")
    others_ref = np.concatenate([r[1][r[1] >= 0] for r in rel])
    if np.intersect1d(rep, others_ref).size:
        raise ValueError("a node is node B of one pair and node A of another; pairs must not chain")
    binormal = np.cross(contact.normal, contact.tangent) if dim == 3 else None
    n_q = 2 * nc
    n_rel = n_q + (nc if dim == 3 else 0)
    rest = np.setdiff1d(np.arange(size), rep)
    pos = np.full(size, -1)
    pos[rest] = n_rel + np.arange(len(rest))
    T = np.zeros((size, size))
    T[rest, pos[rest]] = 1.0
    for i, ((sign, other), dofs) in enumerate(zip(rel, replaced, strict=True)):
        for k in range(dim):
            r = dofs[k]
            if other[k] >= 0:
                T[r, pos[other[k]]] = 1.0
            T[r, 2 * i] = sign * contact.tangent[i, k]
            T[r, 2 * i + 1] = -sign * contact.normal[i, k]
            if binormal is not None:
                T[r, n_q + i] = sign * binormal[i, k]
    return T, n_q


class ContactCondensation:
    """Reduced dynamic stiffness ``Z_k`` and force ``F_k`` on the contact coordinates (eq. 11).

    Parameters
    ----------
    reduced : ReducedModel
    """

    def __init__(self, reduced: ReducedModel) -> None:
        self.reduced = reduced
        T, self.n_q = _contact_coordinates(reduced.contact, reduced.size)
        self.T = T
        self.K = T.T @ reduced.K @ T
        self.M = T.T @ reduced.M @ T
        self.C = T.T @ reduced.C @ T
        self.force_static = T.T @ reduced.force_static
        self.force_harmonic = T.T @ (reduced.force_cos - 1j * reduced.force_sin)  # complex amplitude

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

    def schur(self, omega: float, order: int) -> tuple[np.ndarray, np.ndarray, tuple]:
        """``(Z_k, F_k at unit excitation scale, factors)`` for one harmonic order (complex for ``k > 0``)."""
        D = self.dynamic_stiffness(omega, order)
        q = self.n_q
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

    def harmonic(self, omega: float, basis: HarmonicBasis) -> tuple[np.ndarray, np.ndarray]:
        """Real ``Z`` (2 nc H, 2 nc H) and ``F`` (2 nc H,) in the contact-major layout of ``basis``.

        Entry ``c H + j`` is slot ``j`` of coordinate ``c`` (``c = 2 i`` tangential,
        ``2 i + 1`` normal, for pair ``i``).
        """
        if basis.half_wave:
            raise ValueError("interfaces use the full harmonic basis (half_wave=False)")
        nq, H = self.n_q, basis.size
        Zr = np.zeros((nq, H, nq, H))
        Fr = np.zeros((nq, H))
        for k in range(basis.harmonics + 1):
            Zk, Fk, _ = self.schur(omega, k)
            if k == 0:
                Zr[:, 0, :, 0] = Zk.real
                Fr[:, 0] = Fk.real
                continue
            c, s = 2 * k - 1, 2 * k
            X, Y = Zk.real, Zk.imag
            Zr[:, c, :, c] = X
            Zr[:, s, :, s] = X
            Zr[:, c, :, s] = Y
            Zr[:, s, :, c] = -Y
            Fr[:, c] = Fk.real
            Fr[:, s] = -Fk.imag
        return Zr.reshape(nq * H, nq * H), Fr.reshape(nq * H)

    def recover(self, omega: float, harmonics: int, q: np.ndarray) -> np.ndarray:
        """Reduced coordinates' full harmonics (n_r, 2 Nh + 1) from the contact coordinates' (n_q, 2 Nh + 1).

        ``z_s = D_ss^{-1} (F_s - D_sq q)`` per harmonic: the contact forces act on ``q`` only.
        """
        out_z = np.zeros((self.T.shape[0], 2 * harmonics + 1))
        for k in range(harmonics + 1):
            D = self.dynamic_stiffness(omega, k)
            qk = q[:, 0] if k == 0 else q[:, 2 * k - 1] - 1j * q[:, 2 * k]
            rhs = self.forcing(k)[self.n_q :] - D[self.n_q :, : self.n_q] @ qk
            zs = sla.solve(D[self.n_q :, self.n_q :], rhs, check_finite=False) if len(rhs) else rhs
            z = np.concatenate([qk, zs])
            if k == 0:
                out_z[:, 0] = z.real
            else:
                out_z[:, 2 * k - 1] = z.real
                out_z[:, 2 * k] = -z.imag
        return self.T @ out_z
