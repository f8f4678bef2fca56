"""Finite-element matrices of the cylinder-on-flat fretting benchmark (scikit-fem, plane strain).

The classic fretting test in 2-D: an elastic cylindrical pad of radius ``R``
pressed on an elastic flat block by a constant normal load ``P`` per unit
length and loaded tangentially by ``Q(t) = Q0 cos(omega t)`` (force control),
or driven through a loading arm of stiffness ``k_a`` whose end moves by
``delta0 cos(omega t)`` (displacement control). Pad and flat are the same
isotropic material (``E``, ``nu``, ``rho``), so that the normal and tangential
contact problems uncouple (Dundurs' ``beta = 0``).

Boundary conditions: the flat's bottom face is clamped; the pad's top face is
tied to a rigid holder with two DOFs, ``pad_x`` and ``pad_y`` (translations,
no rotation), which carry the loads and an optional holder mass. Each body is
assembled with bilinear quadrilaterals by scikit-fem; the tie and the clamp
are applied by a sparse transformation ``u_full = T u``.

Material damping is stiffness-proportional, ``C = beta K`` with ``beta = 2 zeta
/ omega_ref``: the damping ratio ``zeta`` at ``f_ref``.

Everything is per unit thickness: forces in N/m, masses in kg/m, stiffnesses in
N/m per m.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import scipy.sparse as sp
from skfem import Basis, BilinearForm, ElementQuad1, ElementVector, MeshQuad, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from ..model import ContactPairs, Model
from .mesh import CylinderOnFlatMesh, cylinder_on_flat_mesh

__all__ = [
    "MAX_CONTACT_NODES",
    "CylinderOnFlat",
    "assemble_body",
    "cylinder_on_flat",
    "effective_modulus",
    "hertz_half_width",
    "hertz_peak_pressure",
]


#: largest ``contact_nodes`` of the benchmark. At 128 pairs the mesh has 66 282 DOFs, Craig-Bampton takes
#: 42 s and one periodic solve 42 s (``Nh = 7``, 2-core machine, 24 GB): a wear history of ~100 solves is
#: already an hour. At 256 pairs (200 000 DOFs, 0.85 GB for the matrices alone) the dense Newton on
#: ``2 nc (2 Nh + 1) = 7 680`` unknowns costs ~8x more per solve; at 100 000 the mesh does not fit in memory.
MAX_CONTACT_NODES = 128


@BilinearForm
def _mass(u, v, w):
    return dot(u, v)


def assemble_body(mesh: MeshQuad, young: float, poisson: float, density: float):
    """Plane-strain stiffness (N/m per m) and consistent mass (kg/m) of one body, bilinear quads.

    Returns ``(K, M, basis)``; DOF ``basis.nodal_dofs[k, i]`` is component ``k`` (x, y) of node ``i``.
    """
    basis = Basis(mesh, ElementVector(ElementQuad1()))
    K = asm(linear_elasticity(*lame_parameters(young, poisson)), basis)
    M = density * asm(_mass, basis)
    return K.tocsr(), M.tocsr(), basis


def effective_modulus(young: float, poisson: float) -> float:
    """Plane-strain contact modulus of two identical bodies, ``E* = E / (2 (1 - nu^2))`` (Pa)."""
    return young / (2.0 * (1.0 - poisson**2))


def hertz_half_width(normal_load: float, radius: float, e_star: float) -> float:
    """Hertz half-width of a cylinder on a flat, ``a = sqrt(4 P R / (pi E*))`` (m), ``P`` in N/m."""
    return float(np.sqrt(4.0 * normal_load * radius / (np.pi * e_star)))


def hertz_peak_pressure(normal_load: float, half_width: float) -> float:
    """Hertz peak pressure ``p0 = 2 P / (pi a)`` (Pa)."""
    return 2.0 * normal_load / (np.pi * half_width)


class FrettingTest:
    """What the fretting tests (:class:`CylinderOnFlat`, :class:`~.sphere.SphereOnFlat`) share: the checks
    of their load, material, damping and loading arm, ``E*`` and the tangential load on the holder."""

    #: lower bound of each shared parameter and whether it is strict
    BOUNDS = (
        ("radius", 0.0, True), ("normal_load", 0.0, True), ("q_ratio", 0.0, False),
        ("arm_stiffness", 0.0, False), ("young", 0.0, True), ("density", 0.0, True),
        ("mu", 0.0, False), ("holder_mass", 0.0, False), ("damping_ratio", 0.0, False),
        ("damping_frequency", 0.0, True), ("window", 1.0, True),
    )  # fmt: skip
    #: unit of the loading arm's stiffness (per unit thickness in 2-D)
    ARM_UNIT = "N/m"

    def check_common(self) -> None:
        """``ValueError`` naming the first shared parameter out of its range."""
        for name, low, strict in self.BOUNDS:
            v = getattr(self, name)
            if not (isinstance(v, (int, float, np.floating, np.integer)) and np.isfinite(v)) or (
                v <= low if strict else v < low
            ):
                raise ValueError(f"{name} must be a finite number {'>' if strict else '>='} {low}, got {v!r}")
        if not -1.0 < self.poisson < 0.5:
            raise ValueError(f"poisson must be in (-1, 0.5), got {self.poisson!r}")
        if self.drive_displacement is not None and not (
            np.isfinite(self.drive_displacement) and self.arm_stiffness > 0
        ):
            raise ValueError(
                f"drive_displacement (m) must be finite and needs arm_stiffness > 0 {self.ARM_UNIT}, "
                f"got drive_displacement={self.drive_displacement!r}, arm_stiffness={self.arm_stiffness!r}"
            )

    @property
    def effective_modulus(self) -> float:
        """``E*`` of the identical bodies (Pa)."""
        return effective_modulus(self.young, self.poisson)

    @property
    def tangential_load(self) -> float:
        """Tangential force amplitude on the holder, ``Q0 = q_ratio mu P`` or ``k_a delta0`` with the arm
        held (N, or N/m per unit thickness in 2-D)."""
        if self.drive_displacement is not None:
            return self.arm_stiffness * self.drive_displacement
        return self.q_ratio * self.mu * self.normal_load


@dataclass(frozen=True)
class CylinderOnFlat(FrettingTest):
    """Parameters of the cylinder-on-flat benchmark (SI, per unit thickness).

    Parameters
    ----------
    radius : float
        Pad radius ``R`` (m).
    normal_load : float
        Normal load ``P`` per unit length (N/m), > 0.
    q_ratio : float
        Tangential load amplitude ``Q0 / (mu P)`` (-), >= 0 (force control).
    drive_displacement : float or None
        With a loading arm (``arm_stiffness > 0``): amplitude ``delta0`` of the
        arm end's motion (m), which replaces the force ``Q0``.
    arm_stiffness : float
        Tangential stiffness ``k_a`` of the loading arm between the holder and
        ground (N/m per m), >= 0.
    young, poisson, density : float
        Material of pad and flat (Pa, -, kg/m^3).
    mu : float
        Friction coefficient (-).
    holder_mass : float
        Mass of the rigid pad holder (kg/m), >= 0.
    damping_ratio, damping_frequency : float
        Stiffness-proportional damping: ratio ``zeta`` (-) at ``f_ref`` (Hz).
    contact_nodes : int
        Node pairs across the contact window, in ``[3, MAX_CONTACT_NODES]``
        (32-128 in the benchmarks).
    window : float
        Half-width of the contact window as a multiple of the Hertz ``a`` (-), > 1.
    pad_half_width, pad_height, flat_half_width, flat_depth : float
        Body sizes (m).
    growth : float
        Element size ratio away from the contact (-).
    """

    radius: float = 0.05
    normal_load: float = 2.0e5
    q_ratio: float = 0.5
    drive_displacement: float | None = None
    arm_stiffness: float = 0.0
    young: float = 200e9
    poisson: float = 0.3
    density: float = 7800.0
    mu: float = 0.6
    holder_mass: float = 50.0
    damping_ratio: float = 0.01
    damping_frequency: float = 2000.0
    contact_nodes: int = 32
    window: float = 1.25
    pad_half_width: float = 0.01
    pad_height: float = 0.01
    flat_half_width: float = 0.02
    flat_depth: float = 0.02
    growth: float = 1.25

    ARM_UNIT = "N/m per m"

    def __post_init__(self) -> None:
        self.check_common()
        n = self.contact_nodes
        if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and 3 <= n <= MAX_CONTACT_NODES):
            raise ValueError(
                f"contact_nodes must be an integer in [3, {MAX_CONTACT_NODES}] (memory and time of the mesh "
                f"and the solves), got {n!r}"
            )

    @property
    def half_width(self) -> float:
        """Hertz half-width ``a`` (m)."""
        return hertz_half_width(self.normal_load, self.radius, self.effective_modulus)

    @property
    def peak_pressure(self) -> float:
        """Hertz peak pressure ``p0`` (Pa)."""
        return hertz_peak_pressure(self.normal_load, self.half_width)

    def mesh(self) -> CylinderOnFlatMesh:
        """The graded pad and flat meshes."""
        return cylinder_on_flat_mesh(
            self.radius, self.window * self.half_width, self.contact_nodes, self.pad_half_width,
            self.pad_height, self.flat_half_width, self.flat_depth, self.growth,
        )  # fmt: skip


def cylinder_on_flat(params: CylinderOnFlat | None = None, **changes) -> Model:
    """The cylinder-on-flat benchmark as a :class:`~fretwear.model.Model` with contact pairs.

    Parameters
    ----------
    params : CylinderOnFlat, optional
        Benchmark parameters; default :class:`~fretwear.interface.CylinderOnFlat`.
    **changes
        Parameters to change, e.g. ``contact_nodes=64, q_ratio=0.8``.

    Returns
    -------
    Model
        Sparse matrices (CSR).         DOFs: the free DOFs of the pad, then of the flat, then ``pad_x``,
        ``pad_y`` (the holder, named in ``names``). Static load ``-P`` on
        ``pad_y``, ``Q0 cos(omega t)`` on ``pad_x``. The pairs join the flat's
        surface nodes (``A``) to the pad's (``B``), normal ``+y``, tangent
        ``+x``, initial gap ``g(x)``, ordered by ``x``. ``info`` holds the
        benchmark's parameters and Hertz values (SI).
    """
    p = CylinderOnFlat(**changes) if params is None else CylinderOnFlat(**{**asdict(params), **changes})
    mesh = p.mesh()
    K_pad, M_pad, b_pad = assemble_body(mesh.pad, p.young, p.poisson, p.density)
    K_flat, M_flat, b_flat = assemble_body(mesh.flat, p.young, p.poisson, p.density)
    n_pad = K_pad.shape[0]
    dof_pad = b_pad.nodal_dofs  # (2, nodes)
    dof_flat = b_flat.nodal_dofs + n_pad
    n_full = n_pad + K_flat.shape[0]
    K_full = sp.block_diag([K_pad, K_flat], format="csr")
    M_full = sp.block_diag([M_pad, M_flat], format="csr")

    tied = dof_pad[:, mesh.pad_top]  # (2, top nodes): to pad_x, pad_y
    clamped = dof_flat[:, mesh.flat_bottom].ravel()
    removed = np.zeros(n_full, dtype=bool)
    removed[tied.ravel()] = True
    removed[clamped] = True
    kept = np.flatnonzero(~removed)
    n = len(kept) + 2
    new_index = np.full(n_full, -1)
    new_index[kept] = np.arange(len(kept))
    rows = np.concatenate([kept, tied[0], tied[1]])
    cols = np.concatenate(
        [np.arange(len(kept)), np.full(tied.shape[1], n - 2), np.full(tied.shape[1], n - 1)]
    )
    T = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(n_full, n))
    K = (T.T @ K_full @ T).tocsr()
    M = (T.T @ M_full @ T).tocsr()
    pad_x, pad_y = n - 2, n - 1
    extra = sp.csr_matrix(([p.holder_mass] * 2, ([pad_x, pad_y], [pad_x, pad_y])), shape=(n, n))
    M = (M + extra).tocsr()
    if p.arm_stiffness > 0:
        K = (K + sp.csr_matrix(([p.arm_stiffness], ([pad_x], [pad_x])), shape=(n, n))).tocsr()
    K = 0.5 * (K + K.T)
    M = 0.5 * (M + M.T)
    C = (2 * p.damping_ratio / (2 * np.pi * p.damping_frequency)) * K

    flat_nodes = new_index[dof_flat[:, mesh.flat_contact]].T  # (nc, 2)
    pad_nodes = new_index[dof_pad[:, mesh.pad_contact]].T
    nc = len(mesh.x)
    contact = ContactPairs(
        dofs_a=flat_nodes, dofs_b=pad_nodes, normal=np.tile([0.0, 1.0], (nc, 1)), area=mesh.tributary,
        mu=p.mu, gap=mesh.gap, position=mesh.x,
    )  # fmt: skip
    force_static = np.zeros(n)
    force_static[pad_y] = -p.normal_load
    force_cos = np.zeros(n)
    force_cos[pad_x] = p.tangential_load
    info = {k: float(v) for k, v in asdict(p).items() if v is not None}
    info.update(
        effective_modulus=p.effective_modulus, hertz_half_width=p.half_width,
        hertz_peak_pressure=p.peak_pressure, tangential_load=p.tangential_load, nodes=float(mesh.n_nodes),
    )  # fmt: skip
    return Model(
        M=M, C=C, K=K, pairs=contact, force_static=force_static, force_cos=force_cos,
        names={"pad_x": pad_x, "pad_y": pad_y}, info=info,
    )  # fmt: skip
