"""Craig-Bampton reduction: a step on a :class:`~fretwear.model.structure.Model` that returns a smaller one.

The DOFs split into boundary DOFs ``b`` (every DOF of the
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
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from .pairs import ContactPairs
from .structure import Model

__all__ = ["Reduction", "craig_bampton"]


@dataclass(frozen=True, eq=False)
class Reduction:
    """How the coordinates of a Craig-Bampton reduced model give the DOFs of its full model.

    Attributes
    ----------
    full : Model
        The full model.
    boundary : ndarray of int
        Full-model DOFs kept physical; reduced coordinate ``j < n_b`` is DOF ``boundary[j]``.
    interior : ndarray of int
        The other full-model DOFs.
    mode_frequencies : ndarray
        Natural frequencies of the kept fixed-interface modes (Hz).
    cutoff : float
        Frequency criterion (Hz): every fixed-interface mode below it is kept.
    psi, phi : ndarray
        Constraint modes (n_i, n_b) and fixed-interface modes (n_i, n_m).
    """

    full: Model
    boundary: np.ndarray
    interior: np.ndarray
    mode_frequencies: np.ndarray
    cutoff: float
    psi: np.ndarray = field(repr=False)
    phi: np.ndarray = field(repr=False)

    @property
    def size(self) -> int:
        """Reduced coordinates ``n_b + n_modes``."""
        return len(self.boundary) + self.n_modes

    @property
    def n_modes(self) -> int:
        """Kept fixed-interface modes."""
        return self.phi.shape[1]

    def expand(self, coords: np.ndarray) -> np.ndarray:
        """Full-model DOF values from reduced coordinates (..., n_r) (any real or complex dtype)."""
        coords = np.asarray(coords)
        nb = len(self.boundary)
        out = np.zeros(coords.shape[:-1] + (self.full.n_dofs,), dtype=coords.dtype)
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
    model: Model,
    f_max: float,
    factor: float = 2.0,
    outputs=(),
    max_modes: int = 400,
) -> Model:
    """Craig-Bampton reduction of ``model`` keeping the modes below ``factor * f_max``.

    Parameters
    ----------
    model : Model
        A model with contact pairs (dense or sparse matrices).
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
    Model
        The reduced model: dense matrices of size ``n_b + n_modes`` (boundary
        DOFs, then modal coordinates), reduced loads, the pairs renumbered in
        reduced coordinates, the names of boundary DOFs, the full model's
        ``info``, and its :class:`Reduction` (``model.reduction``) to recover
        the full model's DOFs.
    """
    if not (np.isfinite(f_max) and f_max >= 0):
        raise ValueError(f"f_max must be a finite frequency >= 0 Hz (0: statics, no modes), got {f_max!r}")
    if not (np.isfinite(factor) and factor >= 1):
        raise ValueError(f"factor must be >= 1, got {factor!r}")
    if not isinstance(model, Model) or model.pairs is None:
        raise ValueError(f"model must be a Model with contact pairs, got {model!r:.80}")
    n = model.n_dofs
    c = model.pairs
    keep = [c.dofs_a[c.dofs_a >= 0], c.dofs_b[c.dofs_b >= 0], model.loaded_dofs]
    keep.append(np.array([model.dof(o) for o in outputs], dtype=np.int64))
    boundary = np.unique(np.concatenate(keep).astype(np.int64))
    mask = np.ones(n, dtype=bool)
    mask[boundary] = False
    interior = np.flatnonzero(mask)
    K, M, C = (sp.csr_matrix(a) for a in (model.K, model.M, model.C))
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
    Cr = _project(C, boundary, interior, psi, phi)

    def load(f: np.ndarray) -> np.ndarray:
        return np.concatenate([f[boundary] + psi.T @ f[interior], phi.T @ f[interior]])

    index = np.full(n, -1)
    index[boundary] = np.arange(len(boundary))
    contact = ContactPairs(
        dofs_a=np.where(c.dofs_a >= 0, index[c.dofs_a], -1),
        dofs_b=np.where(c.dofs_b >= 0, index[c.dofs_b], -1), normal=c.normal, area=c.area, mu=c.mu,
        gap=c.gap, tangent=c.tangent, position=c.position,
    )  # fmt: skip
    reduction = Reduction(
        full=model, boundary=boundary, interior=interior, mode_frequencies=np.sqrt(w2) / (2 * np.pi),
        cutoff=cutoff, psi=psi, phi=phi,
    )  # fmt: skip
    names = {k: int(index[d]) for k, d in model.names.items() if index[d] >= 0}
    return Model(
        M=Mr, C=Cr, K=Kr, force_cos=load(model.force_cos), force_sin=load(model.force_sin),
        force_static=load(model.force_static), pairs=contact, names=names, info=model.info,
        reduction=reduction,
    )  # fmt: skip
