"""Mesh and matrices of the sphere-on-flat fretting benchmark (3-D, half model), refined under the contact.

One body is meshed: the **flat**, the block ``[-W, W] x [0, W] x [-D, 0]`` of
trilinear hexahedra (scikit-fem ``MeshHex``) on a graded tensor grid, top
surface ``z = 0``. The plane ``y = 0`` is a symmetry plane: a tangential load
along ``x`` and the normal load keep the problem symmetric under ``y -> -y``,
so ``u_y = 0`` there and half the contact is modelled (a quarter model would
need the problem symmetric under ``x -> -x`` too, which the tangential load
breaks). The **pad** (the sphere) is the flat's mirror image ``z -> -z``: as
in Hertz's theory, both bodies are half-spaces near the contact, and the
sphere's shape enters through the initial gap of the node pairs,
``g(r) = R - sqrt(R^2 - r^2)``; the profile is ``g <= r_w^2 / R`` over the
window, small against the contact radius when ``a << R``.

In ``x`` and ``y`` the grid has ``2 m + 1`` and ``m + 1`` equally spaced lines
over the contact window ``|x|, y <= r_w`` (spacing ``h = r_w / m``), then
spacings growing by a constant ratio up to ``W``; in depth, spacing ``h`` over
``r_w / 4`` and then growing up to ``D``. The contact pairs are the surface
nodes within the disk ``x^2 + y^2 <= r_w^2``.

Assembly: every element is a box, so its stiffness is a sum of six fixed
matrices weighted by ``dy dz / dx``, ``dx dz / dy``, ``dx dy / dz``, ``dz``,
``dy``, ``dx`` (the derivatives of the shape functions scale as ``1 / h``);
scikit-fem computes the six matrices once on reference boxes and the mesh is
assembled by one vectorised sum (a direct ``asm`` on 20 000 hexahedra takes
~20 s, this ~1 s).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementHex1, ElementVector, MeshHex, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from .mesh import graded_axis

__all__ = ["SphereOnFlatMesh", "sphere_on_flat_mesh", "assemble_boxes", "nested_dissection"]


@dataclass(frozen=True, eq=False)
class SphereOnFlatMesh:
    """The flat's mesh (the pad is its mirror ``z -> -z``) and its contact and boundary nodes.

    Attributes
    ----------
    flat : skfem.MeshHex
        The flat block (m).
    axes : tuple of ndarray
        Grid lines ``(x, y, z)`` (m).
    contact : ndarray of int, shape (nc,)
        Surface nodes of the contact pairs (``z = 0``, ``x^2 + y^2 <= r_w^2``).
    bottom : ndarray of int
        Nodes of the face ``z = -D`` (clamped on the flat, tied to the holder on the pad).
    symmetry : ndarray of int
        Nodes of the symmetry plane ``y = 0`` (``u_y = 0``).
    points : ndarray, shape (nc, 2)
        ``(x, y)`` of each pair (m).
    tributary : ndarray, shape (nc,)
        Tributary area of each pair (m^2): the product of its half spacings;
        halved on ``y = 0``, the half model's share.
    gap : ndarray, shape (nc,)
        Initial gap ``R - sqrt(R^2 - r^2)`` (m).
    """

    flat: MeshHex
    axes: tuple[np.ndarray, np.ndarray, np.ndarray]
    contact: np.ndarray
    bottom: np.ndarray
    symmetry: np.ndarray
    points: np.ndarray
    tributary: np.ndarray
    gap: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Nodes of both bodies."""
        return 2 * self.flat.p.shape[1]


def sphere_on_flat_mesh(
    radius: float, window: float, divisions: int, half_width: float, depth: float, growth: float
) -> SphereOnFlatMesh:
    """Graded hexahedral mesh of the flat of the sphere-on-flat benchmark (half model ``y >= 0``).

    Parameters
    ----------
    radius : float
        Sphere radius ``R`` (m), > 0.
    window : float
        Radius ``r_w`` of the contact window (m), ``0 < r_w < half_width``.
    divisions : int
        Grid spacings ``m`` across the window radius, ``>= 2``.
    half_width : float
        ``W`` (m), with ``sqrt(2) W < R`` (the gap is defined over the whole block).
    depth : float
        ``D`` (m), > ``r_w``.
    growth : float
        Ratio of consecutive element sizes away from the window, in ``[1, 2]``.
    """
    checks = {
        "radius": (radius > 0, "> 0 m"),
        "divisions": (isinstance(divisions, (int, np.integer)) and divisions >= 2, "an integer >= 2"),
        "window": (0 < window < half_width, "in (0, half_width) m"),
        "half_width": (0 < half_width < radius / np.sqrt(2), "in (0, radius / sqrt(2)) m"),
        "depth": (depth > window, "> window m"),
        "growth": (1 <= growth <= 2, "in [1, 2]"),
    }
    values = dict(radius=radius, divisions=divisions, window=window, half_width=half_width, depth=depth,
                  growth=growth)  # fmt: skip
    for name, (ok, valid) in checks.items():
        if not ok:
            raise ValueError(f"{name} must be {valid}, got {values[name]!r}")
    h = window / divisions
    uniform = np.linspace(0.0, window, divisions + 1)
    outer = window + graded_axis(h, 0.0, half_width - window, growth)[1:]
    y = np.concatenate([uniform, outer])
    x = np.concatenate([-y[:0:-1], y])
    z = -graded_axis(h, 0.25 * window, depth, growth)[::-1]
    flat = MeshHex.init_tensor(x, y, z)
    px, py, pz = flat.p
    tol = 1e-9 * h
    contact = np.flatnonzero((np.abs(pz) < tol) & (px**2 + py**2 <= window**2 * (1 + 1e-9)))
    contact = contact[np.lexsort((px[contact], py[contact]))]  # rows of y, each ordered by x

    def half_spacing(axis: np.ndarray, v: np.ndarray) -> np.ndarray:
        i = np.searchsorted(axis, v - tol)
        left = np.where(i > 0, axis[i] - axis[np.maximum(i - 1, 0)], 0.0)
        right = np.where(i < len(axis) - 1, axis[np.minimum(i + 1, len(axis) - 1)] - axis[i], 0.0)
        return 0.5 * (left + right)

    cx, cy = px[contact], py[contact]
    r2 = cx**2 + cy**2
    return SphereOnFlatMesh(
        flat=flat, axes=(x, y, z), contact=contact, bottom=np.flatnonzero(np.abs(pz - z[0]) < tol),
        symmetry=np.flatnonzero(np.abs(py) < tol), points=np.column_stack([cx, cy]),
        tributary=half_spacing(x, cx) * half_spacing(y, cy), gap=radius - np.sqrt(radius**2 - r2),
    )  # fmt: skip


@BilinearForm
def _mass(u, v, w):
    return dot(u, v)


#: box sizes whose element matrices determine the six reference matrices (a non-singular system)
_BOXES = np.array([[1, 1, 1], [2, 1, 1], [1, 2, 1], [1, 1, 2], [2, 3, 1], [3, 1, 2], [1, 3, 2], [2, 2, 3]])


def _box_coefficients(d: np.ndarray) -> np.ndarray:
    """Weights (..., 6) of the reference stiffness matrices for boxes of sides ``d`` (..., 3)."""
    dx, dy, dz = d[..., 0], d[..., 1], d[..., 2]
    return np.stack([dy * dz / dx, dx * dz / dy, dx * dy / dz, dz, dy, dx], axis=-1)


@lru_cache(maxsize=4)
def _reference_matrices(poisson: float) -> tuple[np.ndarray, np.ndarray]:
    """The six stiffness matrices (6, 24, 24) at ``E = 1`` and the mass matrix (24, 24) of the unit cube."""
    mats = []
    for d in _BOXES:
        mesh = MeshHex.init_tensor(*(np.array([0.0, s]) for s in d))
        basis = Basis(mesh, ElementVector(ElementHex1()), intorder=2)
        local = np.ix_(basis.element_dofs[:, 0], basis.element_dofs[:, 0])  # the element's own DOF order
        mats.append(asm(linear_elasticity(*lame_parameters(1.0, poisson)), basis).toarray()[local])
    coef = _box_coefficients(_BOXES.astype(float))
    ref = np.linalg.lstsq(coef, np.array(mats).reshape(len(_BOXES), -1), rcond=None)[0]
    unit = Basis(MeshHex.init_tensor(*(np.array([0.0, 1.0]),) * 3), ElementVector(ElementHex1()), intorder=2)
    local = np.ix_(unit.element_dofs[:, 0], unit.element_dofs[:, 0])
    return ref.reshape(6, 24, 24), asm(_mass, unit).toarray()[local]


def assemble_boxes(mesh: MeshHex, young: float, poisson: float, density: float):
    """Stiffness (N/m) and consistent mass (kg) of a tensor-grid hexahedral mesh, trilinear elements.

    Returns ``(K, M, nodal_dofs)`` (CSR); DOF ``nodal_dofs[k, i]`` is component
    ``k`` (x, y, z) of node ``i``, as scikit-fem's ``Basis.nodal_dofs``.
    """
    ref_k, ref_m = _reference_matrices(float(poisson))
    corners = mesh.p[:, mesh.t]  # (3, 8, nel)
    d = (corners.max(axis=1) - corners.min(axis=1)).T  # (nel, 3)
    dofs = np.vstack([3 * mesh.t + k for k in range(3)])  # (24, nel), skfem's ordering: see nodal_dofs
    dofs = dofs.reshape(3, 8, -1).transpose(1, 0, 2).reshape(24, -1)
    ke = young * (_box_coefficients(d) @ ref_k.reshape(6, -1))  # (nel, 576)
    me = density * np.prod(d, axis=1)[:, None] * ref_m.ravel()[None, :]
    rows = np.repeat(dofs.T, 24, axis=1).ravel()
    cols = np.tile(dofs.T, (1, 24)).ravel()
    n = 3 * mesh.p.shape[1]
    K = sp.csr_matrix((ke.ravel(), (rows, cols)), shape=(n, n))
    M = sp.csr_matrix((me.ravel(), (rows, cols)), shape=(n, n))
    return K, M, np.arange(n).reshape(-1, 3).T


def nested_dissection(mesh: MeshHex, axes: tuple[np.ndarray, ...], leaf: int = 64) -> np.ndarray:
    """Nodes of a tensor-grid mesh in nested-dissection order (separators last), for a sparse factorization.

    The grid's box of nodes is cut in two by the plane of nodes across its
    longest side, recursively; each half comes first, the cut plane after.
    On a 3-D grid this halves the fill of SuperLU's minimum-degree ordering.
    """
    index = np.stack([np.searchsorted(ax, mesh.p[k] - 1e-12 * np.ptp(ax)) for k, ax in enumerate(axes)])
    out: list[np.ndarray] = []
    stack = [(np.arange(mesh.p.shape[1]), np.zeros(3, int), np.array([len(ax) - 1 for ax in axes]), False)]
    while stack:  # depth first, a separator is emitted after both its halves
        nodes, lo, hi, emit = stack.pop()
        ext = hi - lo
        if emit or len(nodes) <= leaf or ext.max() < 2:
            out.append(nodes)
            continue
        k = int(np.argmax(ext))
        mid = (lo[k] + hi[k]) // 2
        c = index[k, nodes]
        hi_l, lo_r = hi.copy(), lo.copy()
        hi_l[k], lo_r[k] = mid - 1, mid + 1
        stack.append((nodes[c == mid], lo, hi, True))
        stack.append((nodes[c > mid], lo_r, hi, False))
        stack.append((nodes[c < mid], lo, hi_l, False))
    return np.concatenate(out)
