"""Contact node pairs of an interface: the coupled normal/tangential contact of paper eq. 17-23.

Pair ``i`` joins node ``A_i`` (e.g. on the flat) and node ``B_i`` (on the pad);
``n_i`` is the unit normal pointing from ``A`` into ``B`` and ``t_i`` the unit
tangent. With ``d = u_B - u_A`` the relative displacement of the pair, its
contact coordinates are

    u_T = t . d          (tangential slip coordinate, m)
    u_N = -n . d         (normal approach, m; positive closes the gap)

and the pair is closed when ``u_N`` reaches the gap ``g0_i + w_i`` (initial gap
plus worn depth, paper eq. 17b). The contact forces ``lambda = (lambda_T,
lambda_N)`` act along ``B^T`` (``lambda_N >= 0`` is compressive, ``|lambda_T| <=
mu lambda_N``). Rows of ``B`` are ordered pair-major, ``(T, N)`` per pair.

Each pair carries its tributary area (m^2; in a plane model, m per unit
thickness), which turns nodal forces into pressures, and a position along the
interface (m) for the profiles ``w(x)``, ``p(x)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.sparse as sp

__all__ = ["ContactPairs"]


def finite_array(name: str, value, shape: tuple[int, ...]) -> np.ndarray:
    """``value`` as a read-only float array of ``shape``, finite (a ``ValueError`` names ``name``)."""
    a = np.array(value, dtype=float)
    if a.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} must contain finite numbers only")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class ContactPairs:
    """Contact node pairs of an interface (node-to-node, small sliding).

    Parameters
    ----------
    dofs_a, dofs_b : array_like of int, shape (nc, dim)
        DOF indices (0-based) of the ``dim`` displacement components of node
        ``A`` and node ``B`` of each pair; ``-1`` marks a grounded component
        (fixed, zero displacement). ``dim`` is 2 (plane models) or 3.
    normal : array_like, shape (nc, dim)
        Unit normal from ``A`` into ``B`` (normalised here).
    area : array_like, shape (nc,)
        Tributary area of each pair, > 0 (m^2; m per unit thickness in 2-D).
    mu : float or array_like, shape (nc,)
        Coulomb friction coefficient, >= 0.
    gap : array_like, shape (nc,), optional
        Initial normal gap ``g0`` (m); default zero. Negative is an interference.
    tangent : array_like, shape (nc, dim), optional
        Unit tangent (the slip direction), orthogonal to the normal. Default in
        2-D: the normal turned by -90 degrees, ``t = (n_y, -n_x)``; required in 3-D.
    position : array_like, shape (nc,), optional
        Coordinate of each pair along the interface (m), for profiles;
        default ``0, 1, 2, ...``.
    """

    dofs_a: np.ndarray
    dofs_b: np.ndarray
    normal: np.ndarray
    area: np.ndarray
    mu: np.ndarray | float
    gap: np.ndarray | None = None
    tangent: np.ndarray | None = None
    position: np.ndarray | None = None

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        a = np.array(self.dofs_a)
        b = np.array(self.dofs_b)
        if a.ndim != 2 or a.shape[1] not in (2, 3) or a.shape[0] == 0 or a.shape != b.shape:
            raise ValueError(
                "dofs_a and dofs_b must be integer arrays of the same shape (nc, 2) or (nc, 3), nc >= 1, "
                f"got {a.shape} and {b.shape}"
            )
        if not (np.issubdtype(a.dtype, np.integer) and np.issubdtype(b.dtype, np.integer)):
            raise ValueError("dofs_a and dofs_b must hold integer DOF indices (-1 = grounded component)")
        if np.any(a < -1) or np.any(b < -1):
            raise ValueError("dofs_a and dofs_b must be DOF indices >= 0, or -1 for a grounded component")
        nc, dim = a.shape
        for name, d in (("dofs_a", a), ("dofs_b", b)):
            d = d.astype(np.int64)
            d.setflags(write=False)
            set_(self, name, d)
        normal = finite_array("normal", self.normal, (nc, dim))
        length = np.linalg.norm(normal, axis=1)
        if np.any(length == 0):
            raise ValueError(f"normal of pair {int(np.argmin(length))} is zero; normals must be non-zero")
        normal = normal / length[:, None]
        normal.setflags(write=False)
        set_(self, "normal", normal)
        area = finite_array("area", self.area, (nc,))
        if np.any(area <= 0):
            i = int(np.argmin(area))
            raise ValueError(f"area must be > 0 for every pair, got {area[i]!r} for pair {i}")
        set_(self, "area", area)
        mu = finite_array("mu", np.broadcast_to(np.asarray(self.mu, dtype=float), (nc,)), (nc,))
        if np.any(mu < 0):
            raise ValueError(f"mu must be >= 0, got {mu.min()!r}")
        set_(self, "mu", mu)
        set_(self, "gap", finite_array("gap", np.zeros(nc) if self.gap is None else self.gap, (nc,)))
        if self.tangent is None:
            if dim == 3:
                raise ValueError("tangent (the slip direction) is required for 3-D pairs")
            tangent = np.column_stack([normal[:, 1], -normal[:, 0]])
        else:
            tangent = np.array(finite_array("tangent", self.tangent, (nc, dim)))
            tangent /= np.maximum(np.linalg.norm(tangent, axis=1), 1e-300)[:, None]
            if np.any(np.abs(np.sum(tangent * normal, axis=1)) > 1e-8):
                raise ValueError("tangent must be orthogonal to the normal for every pair")
        tangent.setflags(write=False)
        set_(self, "tangent", tangent)
        pos = np.arange(nc, dtype=float) if self.position is None else self.position
        set_(self, "position", finite_array("position", pos, (nc,)))

    @property
    def count(self) -> int:
        """Number of pairs ``nc``."""
        return self.dofs_a.shape[0]

    @property
    def dim(self) -> int:
        """Space dimension of the nodes (2 or 3)."""
        return self.dofs_a.shape[1]

    def relative_map(self, n_dofs: int) -> sp.csr_matrix:
        """Sparse ``B`` (2 nc, n): ``(u_T, u_N)`` of every pair from the DOFs, pair-major."""
        rows, cols, vals = [], [], []
        for side, dofs in ((1.0, self.dofs_b), (-1.0, self.dofs_a)):
            for k in range(self.dim):
                ok = dofs[:, k] >= 0
                idx = np.flatnonzero(ok)
                rows += [2 * idx, 2 * idx + 1]
                cols += [dofs[ok, k], dofs[ok, k]]
                vals += [side * self.tangent[ok, k], -side * self.normal[ok, k]]
        return sp.csr_matrix(
            (np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
            shape=(2 * self.count, n_dofs),
        )
