"""The sphere-on-flat fretting benchmark in 3-D (scikit-fem hexahedra, half model): Hertz and Mindlin.

An elastic sphere of radius ``R`` pressed on an elastic flat by ``P`` and
loaded tangentially along ``x`` by ``Q`` through a rigid holder; the flat's
bottom is clamped. Sphere and flat are the same isotropic material, so that
the normal and tangential contact problems uncouple (Dundurs' ``beta = 0``)
and Hertz's and Mindlin's theories apply (Johnson, *Contact Mechanics*, 1985,
sec. 4.2 and 7.2):

* Hertz: ``a = (3 P R / (4 E*))^(1/3)``, ``p(r) = p0 sqrt(1 - r^2 / a^2)``,
  ``p0 = 3 P / (2 pi a^2)``, ``1 / E* = 2 (1 - nu^2) / E``;
* Mindlin: a central stick disk of radius ``c = a (1 - Q / (mu P))^(1/3)``,
  slip in the annulus ``c < r < a``; no static equilibrium for ``Q >= mu P``.

The model (``fretwear.interface.sphere_mesh``) is the half ``y >= 0``
(``y = 0`` is a symmetry plane for ``Q`` along ``x``); it carries half the
loads, ``P / 2`` and ``Q / 2``, and the results are reported for the whole
contact. Pairs: flat node ``A``, sphere node ``B``, normal ``+z``, tangent
``+x``; the 1-D friction law acts along ``x`` (for ``Q`` along ``x`` the slip is
along ``x`` to first order: Mindlin's own approximation, tractions along ``x``
only) and the binormal ``y`` is free (no traction), as in
:class:`~fretwear.interface.reduction.ContactCondensation`.

Two models:

* :func:`sphere_on_flat`: the full sparse model (both bodies, 3-D pairs), for
  the dynamic solves after a Craig-Bampton reduction;
* :func:`sphere_static_model`: its exact static condensation on the contact
  coordinates, dense, for :func:`~fretwear.interface.static.solve_static`:
  the pairs' ``x`` and ``z`` components and the holder's ``x`` and ``z``. The
  ``y`` components of the contact nodes carry no force and are condensed. The
  Schur complement is the trailing block of one sparse LU factorization of
  the flat, ordered by nested dissection with the contact DOFs last
  (``L_bb U_bb = K_bb - K_bi K_ii^-1 K_ib``); the sphere is its mirror image,
  its top tied to the holder by a rigid translation. No constraint modes are
  formed (Craig-Bampton's ``K_ii^-1 K_ib`` would be ``n_i x 6 nc`` dense, 4 GB at
  500 pairs).
"""

from __future__ import annotations

from dataclasses import asdict, dataclass

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
import scipy.sparse.linalg as spla

from ..model import ContactPairs, Model
from .fe import FrettingTest
from .reduction import ContactCondensation
from .sphere_mesh import SphereOnFlatMesh, assemble_boxes, nested_dissection, sphere_on_flat_mesh
from .static import check_q_ratio, solve_static, static_anchors

__all__ = [
    "MAX_DIVISIONS",
    "SphereOnFlat",
    "hertz_radius",
    "hertz_sphere_peak_pressure",
    "holder_frequency",
    "mindlin_deresiewicz_dissipation",
    "mindlin_stick_radius",
    "sphere_cyclic_dissipation",
    "sphere_dynamic_model",
    "sphere_fretting_loop",
    "sphere_on_flat",
    "sphere_periodic",
    "sphere_static_benchmark",
    "sphere_static_model",
    "tangential_modulus",
]

#: largest ``divisions``: 18 are 523 pairs, 103 428 DOFs, an 18-30 s build and 1.5 GB (measured); 40 would
#: be ~2 550 pairs and ~500 000 DOFs, a factorization ~25x longer (extrapolated: it grows like DOFs^2).
MAX_DIVISIONS = 40


def hertz_radius(normal_load: float, radius: float, e_star: float) -> float:
    """Hertz contact radius of a sphere on a flat, ``a = (3 P R / (4 E*))^(1/3)`` (m), ``P`` in N."""
    return float(np.cbrt(3.0 * normal_load * radius / (4.0 * e_star)))


def hertz_sphere_peak_pressure(normal_load: float, contact_radius: float) -> float:
    """Hertz peak pressure of a sphere, ``p0 = 3 P / (2 pi a^2)`` (Pa)."""
    return 3.0 * normal_load / (2.0 * np.pi * contact_radius**2)


def mindlin_stick_radius(contact_radius: float, q_ratio: float) -> float:
    """Mindlin's stick radius ``c = a (1 - Q / (mu P))^(1/3)`` (m); 0 at and beyond gross slip."""
    return float(contact_radius * np.cbrt(max(1.0 - q_ratio, 0.0)))


@dataclass(frozen=True)
class SphereOnFlat(FrettingTest):
    """Parameters of the sphere-on-flat benchmark (SI; loads of the whole sphere).

    Parameters
    ----------
    radius : float
        Sphere radius ``R`` (m), > 0.
    normal_load : float
        Normal load ``P`` (N), > 0.
    q_ratio : float
        Tangential load ``Q / (mu P)`` (-), >= 0, along ``x`` (force control).
    drive_displacement : float or None
        With a loading arm (``arm_stiffness > 0``): amplitude ``delta0`` of the
        arm end's motion along ``x`` (m), which replaces the force ``Q``
        (displacement control: the contact may slip as a whole).
    arm_stiffness : float
        Stiffness ``k_a`` of the loading arm between the holder and its driven
        end (N/m), >= 0.
    young, poisson, density : float
        Material of sphere and flat (Pa, -, kg/m^3).
    mu : float
        Friction coefficient (-), >= 0.
    holder_mass : float
        Mass of the rigid holder of the sphere (kg), >= 0 (half of it in the half model).
    damping_ratio, damping_frequency : float
        Stiffness-proportional damping: ratio ``zeta`` (-) at ``f_ref`` (Hz).
    divisions : int
        Grid spacings across the contact window's radius, in ``[2, MAX_DIVISIONS]``;
        the pairs are the ~``pi divisions^2 / 2`` surface nodes of the half
        window (18: 523 pairs).
    window : float
        Radius of the contact window as a multiple of the Hertz ``a`` (-), > 1.
    size : float
        Half-width and depth of each body as a multiple of ``a`` (-), > ``window``.
    growth : float
        Element size ratio away from the contact (-), in ``[1, 2]``.
    """

    radius: float = 0.01
    normal_load: float = 100.0
    q_ratio: float = 0.5
    drive_displacement: float | None = None
    arm_stiffness: float = 0.0
    young: float = 200e9
    poisson: float = 0.3
    density: float = 7800.0
    mu: float = 0.6
    holder_mass: float = 0.1
    damping_ratio: float = 0.01
    damping_frequency: float = 20000.0
    divisions: int = 18
    window: float = 1.25
    size: float = 5.0
    growth: float = 1.5

    def __post_init__(self) -> None:
        self.check_common()
        n = self.divisions
        if not (isinstance(n, (int, np.integer)) and not isinstance(n, bool) and 2 <= n <= MAX_DIVISIONS):
            raise ValueError(
                f"divisions must be an integer in [2, {MAX_DIVISIONS}] (memory and time of the mesh and "
                f"its factorization), got {n!r}"
            )
        if not (np.isfinite(self.size) and self.size > self.window):
            raise ValueError(f"size must be a finite number > window = {self.window!r}, got {self.size!r}")
        if not (np.isfinite(self.growth) and 1 <= self.growth <= 2):
            raise ValueError(f"growth must be in [1, 2], got {self.growth!r}")
        if not np.sqrt(2) * self.size * self.contact_radius < self.radius:
            raise ValueError(
                f"size must be < radius / (sqrt(2) a) = {self.radius / np.sqrt(2) / self.contact_radius:.4g} "
                f"(the sphere's gap over the whole block), got {self.size!r}"
            )

    @property
    def contact_radius(self) -> float:
        """Hertz contact radius ``a`` (m)."""
        return hertz_radius(self.normal_load, self.radius, self.effective_modulus)

    @property
    def peak_pressure(self) -> float:
        """Hertz peak pressure ``p0`` (Pa)."""
        return hertz_sphere_peak_pressure(self.normal_load, self.contact_radius)

    def mesh(self) -> SphereOnFlatMesh:
        """The graded mesh of the flat (the sphere is its mirror)."""
        a = self.contact_radius
        return sphere_on_flat_mesh(
            self.radius, self.window * a, self.divisions, self.size * a, self.size * a, self.growth
        )

    def info(self, mesh: SphereOnFlatMesh) -> dict:
        """The model's ``info``: the parameters, Hertz's values and the pairs' ``(x, y)`` (SI)."""
        info = {k: float(v) for k, v in asdict(self).items() if v is not None}
        info.update(
            effective_modulus=self.effective_modulus, hertz_radius=self.contact_radius,
            hertz_peak_pressure=self.peak_pressure, tangential_load=self.tangential_load,
            nodes=float(mesh.n_nodes), symmetry_factor=2.0, pair_points=mesh.points,
        )  # fmt: skip
        return info


def _params(params: SphereOnFlat | None, changes: dict) -> SphereOnFlat:
    return SphereOnFlat(**changes) if params is None else SphereOnFlat(**{**asdict(params), **changes})


def _mirror(K: sp.csr_matrix) -> sp.csr_matrix:
    """The stiffness of the body mirrored by ``z -> -z``: the ``z`` components change sign."""
    s = np.tile([1.0, 1.0, -1.0], K.shape[0] // 3)
    return (sp.diags(s) @ K @ sp.diags(s)).tocsr()


def sphere_on_flat(params: SphereOnFlat | None = None, **changes) -> Model:
    """The sphere-on-flat benchmark (half model) as a sparse :class:`~fretwear.model.Model` with 3-D pairs.

    Parameters
    ----------
    params : SphereOnFlat, optional
        Benchmark parameters; default :class:`SphereOnFlat()`.
    **changes
        Parameters to change, e.g. ``divisions=8, q_ratio=0.8``.

    Returns
    -------
    Model
        Sparse matrices (CSR). DOFs: the free DOFs of the sphere, then of the
        flat, then the holder's ``pad_x``, ``pad_z`` (named). Static load ``-P /
        2`` on ``pad_z``, ``Q / 2 cos(omega t)`` on ``pad_x`` (with the arm: its
        stiffness ``k_a / 2`` on ``pad_x`` and ``Q = k_a delta0``). The pairs join
        the flat's surface nodes (``A``) to the sphere's (``B``), normal ``+z``,
        tangent ``+x``, initial gap ``R - sqrt(R^2 - r^2)``, ``position`` the
        ``x`` of each pair; a ``y`` component is ``-1`` (fixed) on the symmetry
        plane. ``info`` holds the parameters, Hertz's values and the pairs'
        ``(x, y)`` (``pair_points``).
    """
    p = _params(params, changes)
    mesh = p.mesh()
    K_flat, M_flat, dofs = assemble_boxes(mesh.flat, p.young, p.poisson, p.density)
    n1 = K_flat.shape[0]
    K_full = sp.block_diag([_mirror(K_flat), K_flat], format="csr")
    M_full = sp.block_diag([M_flat, M_flat], format="csr")  # a mass matrix is unchanged by a mirror
    pad_dofs, flat_dofs = dofs, dofs + n1
    tied = pad_dofs[:, mesh.bottom]  # the sphere's top face: x, z to the holder, y fixed (symmetric load)
    removed = np.zeros(2 * n1, dtype=bool)
    removed[tied.ravel()] = True
    removed[flat_dofs[:, mesh.bottom].ravel()] = True
    removed[pad_dofs[1, mesh.symmetry]] = True
    removed[flat_dofs[1, mesh.symmetry]] = True
    kept = np.flatnonzero(~removed)
    n = len(kept) + 2
    pad_x, pad_z = n - 2, n - 1
    new_index = np.full(2 * n1, -1)
    new_index[kept] = np.arange(len(kept))
    rows = np.concatenate([kept, tied[0], tied[2]])
    cols = np.concatenate(
        [np.arange(len(kept)), np.full(tied.shape[1], pad_x), np.full(tied.shape[1], pad_z)]
    )
    T = sp.csr_matrix((np.ones(len(rows)), (rows, cols)), shape=(2 * n1, n))
    K = (T.T @ K_full @ T).tocsr()
    M = (T.T @ M_full @ T).tocsr()
    half_mass = 0.5 * p.holder_mass
    M = (M + sp.csr_matrix(([half_mass] * 2, ([pad_x, pad_z], [pad_x, pad_z])), shape=(n, n))).tocsr()
    if p.arm_stiffness > 0:
        K = (K + sp.csr_matrix(([0.5 * p.arm_stiffness], ([pad_x], [pad_x])), shape=(n, n))).tocsr()
    K, M = 0.5 * (K + K.T), 0.5 * (M + M.T)
    C = (2 * p.damping_ratio / (2 * np.pi * p.damping_frequency)) * K
    nc = len(mesh.contact)
    contact = ContactPairs(
        dofs_a=new_index[flat_dofs[:, mesh.contact]].T, dofs_b=new_index[pad_dofs[:, mesh.contact]].T,
        normal=np.tile([0.0, 0.0, 1.0], (nc, 1)), tangent=np.tile([1.0, 0.0, 0.0], (nc, 1)),
        area=mesh.tributary, mu=p.mu, gap=mesh.gap, position=mesh.points[:, 0],
    )  # fmt: skip
    force_static, force_cos = np.zeros(n), np.zeros(n)
    force_static[pad_z] = -0.5 * p.normal_load
    force_cos[pad_x] = 0.5 * p.tangential_load
    return Model(
        M=M, C=C, K=K, pairs=contact, force_static=force_static, force_cos=force_cos,
        names={"pad_x": pad_x, "pad_z": pad_z}, info=p.info(mesh),
    )  # fmt: skip


def _contact_schur(mesh: SphereOnFlatMesh, K: sp.csr_matrix, with_y: bool = False) -> np.ndarray:
    """Schur complement (2 nc, 2 nc) of the clamped flat on its contact nodes' ``x``, then ``z`` (N/m);
    ``with_y``: on their ``x``, then ``y`` (the nodes off the symmetry plane), then ``z``.

    One LU factorization of ``K`` (bottom clamped, ``u_y = 0`` on the symmetry
    plane) ordered by nested dissection with the contact DOFs last, without
    pivoting (``K`` is positive definite): its trailing block is the Schur
    complement, ``L_bb U_bb = K_bb - K_bi K_ii^-1 K_ib``.
    """
    n = K.shape[0]
    y = 3 * mesh.contact[~np.isin(mesh.contact, mesh.symmetry)] + 1 if with_y else np.zeros(0, dtype=int)
    boundary = np.concatenate([3 * mesh.contact, y, 3 * mesh.contact + 2])
    removed = np.zeros(n, dtype=bool)
    removed[(3 * mesh.bottom[:, None] + np.arange(3)).ravel()] = True
    removed[3 * mesh.symmetry + 1] = True
    removed[boundary] = True
    order = (3 * nested_dissection(mesh.flat, mesh.axes)[:, None] + np.arange(3)).ravel()
    order = np.concatenate([order[~removed[order]], boundary])
    lu = spla.splu(
        K[order][:, order].tocsc(), permc_spec="NATURAL", diag_pivot_thresh=0.0,
        options={"SymmetricMode": True},
    )  # fmt: skip
    m = len(order)
    if not (np.array_equal(lu.perm_c, np.arange(m)) and np.array_equal(lu.perm_r, np.arange(m))):
        raise RuntimeError(
            "SuperLU permuted the ordered matrix: the trailing block is not the Schur complement"
        )
    nb = len(boundary)
    S = (lu.L[m - nb :, m - nb :] @ lu.U[m - nb :, m - nb :]).toarray()
    return 0.5 * (S + S.T)


def sphere_static_model(params: SphereOnFlat | None = None, **changes) -> Model:
    """The benchmark's exact static condensation on its contact coordinates (dense; statics only).

    Parameters
    ----------
    params : SphereOnFlat, optional
    **changes
        Parameters to change, e.g. ``divisions=8``.

    Returns
    -------
    Model
        Dense stiffness (N/m) on ``4 nc + 2`` DOFs: the flat's contact nodes
        (``x`` of every pair, then ``z``), the sphere's (likewise), then the
        holder's ``pad_x``, ``pad_z``; the same static response as
        :func:`sphere_on_flat` under loads on these DOFs. No mass nor damping
        (a static model: ``omega = 0`` only). Its pairs are 2-D in the
        ``(x, z)`` plane (normal ``(0, 1)``: ``+z``, tangent ``+x``): the
        ``y`` components, free of contact force, are condensed. Loads and
        ``info`` as :func:`sphere_on_flat`'s.
    """
    p = _params(params, changes)
    mesh = p.mesh()
    K_flat, _, _ = assemble_boxes(mesh.flat, p.young, p.poisson, p.density)
    S = _contact_schur(mesh, K_flat)
    nc = len(mesh.contact)
    flip = np.concatenate([np.ones(nc), -np.ones(nc)])
    S_pad = flip[:, None] * S * flip[None, :]  # the mirror image, top clamped
    R = np.zeros((2 * nc, 2))  # the holder's translation at the sphere's contact nodes
    R[:nc, 0] = R[nc:, 1] = 1.0
    n = 4 * nc + 2
    K = np.zeros((n, n))
    K[: 2 * nc, : 2 * nc] = S
    pad = slice(2 * nc, 4 * nc)
    K[pad, pad] = S_pad
    K[pad, 4 * nc :] = -S_pad @ R
    K[4 * nc :, pad] = -R.T @ S_pad
    K[4 * nc :, 4 * nc :] = R.T @ S_pad @ R
    K[n - 2, n - 2] += 0.5 * p.arm_stiffness  # the half model's share of the loading arm
    idx = np.arange(nc)
    contact = ContactPairs(
        dofs_a=np.column_stack([idx, nc + idx]), dofs_b=np.column_stack([2 * nc + idx, 3 * nc + idx]),
        normal=np.tile([0.0, 1.0], (nc, 1)), tangent=np.tile([1.0, 0.0], (nc, 1)), area=mesh.tributary,
        mu=p.mu, gap=mesh.gap, position=mesh.points[:, 0],
    )  # fmt: skip
    force_static, force_cos = np.zeros(n), np.zeros(n)
    force_static[n - 1] = -0.5 * p.normal_load
    force_cos[n - 2] = 0.5 * p.tangential_load
    return Model(
        M=np.zeros((n, n)), C=None, K=K, pairs=contact, force_static=force_static, force_cos=force_cos,
        names={"pad_x": n - 2, "pad_z": n - 1}, info=p.info(mesh),
    )  # fmt: skip


def sphere_dynamic_model(params: SphereOnFlat | None = None, **changes) -> Model:
    """The benchmark condensed exactly on its contact nodes and holder, with the holder's mass: 3-D pairs.

    The flat's and the sphere's stiffness are condensed on every component of
    their contact nodes (``x``, ``y`` off the symmetry plane, ``z``) by the
    sparse LU of :func:`sphere_static_model`; the holder keeps its mass
    (half of ``holder_mass`` on ``pad_x`` and ``pad_z``) and the damping is
    the stiffness-proportional one of :func:`sphere_on_flat` (``C = beta K``,
    condensed exactly with ``K``). The bodies' own inertia is left out: this is
    the Craig-Bampton reduction with no fixed-interface mode (Guyan), exact up
    to the bodies' first fixed-interface mode, of order ``c / (size a)`` (the
    default's blocks are about 1 mm: ~MHz), far above the holder's mode on the
    contact's tangential stiffness (a few kHz) that the fretting dynamics
    excite. For the 2-D friction law of :class:`~fretwear.interface.periodic.InterfaceProblem`.

    Returns
    -------
    Model
        Dense, ``2 (2 nc + ny) + 2`` DOFs: the flat's contact nodes (``x`` of every pair, ``y`` of the
        ``ny`` pairs off the symmetry plane, ``z``), the sphere's likewise, ``pad_x``, ``pad_z``; pairs
        3-D (normal ``+z``, tangent ``+x``, the ``y`` of a pair on the symmetry plane fixed: ``-1``).
        Loads and ``info`` as :func:`sphere_on_flat`'s.
    """
    p = _params(params, changes)
    mesh = p.mesh()
    K_flat, _, _ = assemble_boxes(mesh.flat, p.young, p.poisson, p.density)
    S = _contact_schur(mesh, K_flat, with_y=True)
    nc = len(mesh.contact)
    has_y = ~np.isin(mesh.contact, mesh.symmetry)
    ny = int(has_y.sum())
    m = 2 * nc + ny  # DOFs of one body
    flip = np.concatenate([np.ones(nc + ny), -np.ones(nc)])
    S_pad = flip[:, None] * S * flip[None, :]  # the mirror image, top clamped
    R = np.zeros((m, 2))  # the holder's translation at the sphere's contact nodes (x, z; y held)
    R[:nc, 0] = R[nc + ny :, 1] = 1.0
    n = 2 * m + 2
    K = np.zeros((n, n))
    K[:m, :m] = S
    pad = slice(m, 2 * m)
    K[pad, pad] = S_pad
    K[pad, 2 * m :] = -S_pad @ R
    K[2 * m :, pad] = -R.T @ S_pad
    K[2 * m :, 2 * m :] = R.T @ S_pad @ R
    K[n - 2, n - 2] += 0.5 * p.arm_stiffness
    K = 0.5 * (K + K.T)
    M = np.zeros((n, n))
    M[n - 2, n - 2] = M[n - 1, n - 1] = 0.5 * p.holder_mass
    C = (2 * p.damping_ratio / (2 * np.pi * p.damping_frequency)) * K
    idx = np.arange(nc)
    y_of = np.full(nc, -1)
    y_of[has_y] = nc + np.arange(ny)
    dofs_a = np.column_stack([idx, y_of, nc + ny + idx])
    dofs_b = np.where(dofs_a >= 0, dofs_a + m, -1)
    contact = ContactPairs(
        dofs_a=dofs_a, dofs_b=dofs_b, normal=np.tile([0.0, 0.0, 1.0], (nc, 1)),
        tangent=np.tile([1.0, 0.0, 0.0], (nc, 1)), area=mesh.tributary, mu=p.mu, gap=mesh.gap,
        position=mesh.points[:, 0],
    )  # fmt: skip
    force_static, force_cos = np.zeros(n), np.zeros(n)
    force_static[n - 1] = -0.5 * p.normal_load
    force_cos[n - 2] = 0.5 * p.tangential_load
    return Model(
        M=M, C=C, K=K, pairs=contact, force_static=force_static, force_cos=force_cos,
        names={"pad_x": n - 2, "pad_z": n - 1}, info=p.info(mesh),
    )  # fmt: skip


def holder_frequency(params: SphereOnFlat | None = None, **changes) -> float:
    """First natural frequency (Hz) of the holder along ``x`` on the stuck contact, Mindlin's closed form.

    ``sqrt(k_t / m) / (2 pi)`` with Mindlin's initial tangential stiffness ``k_t = 8 a G*`` (Johnson, sec.
    7.2; :func:`tangential_modulus`) and the holder's mass ``m``: the first mode of
    :func:`sphere_dynamic_model` (whose bodies have no mass) while no pair slips.
    """
    p = _params(params, changes)
    k_t = 8.0 * p.contact_radius * tangential_modulus(p.young, p.poisson)
    return float(np.sqrt(k_t / p.holder_mass) / (2 * np.pi))


def sphere_static_benchmark(
    q_ratio: float = 0.5,
    params: SphereOnFlat | None = None,
    condensation: ContactCondensation | None = None,
    **changes,
) -> dict:
    """Quasi-static sphere-on-flat test at ``Q / (mu P) = q_ratio`` against Hertz and Mindlin.

    Radii are measured from the nodal forces by their second moments over the
    whole contact (the half model mirrored), exact for the semi-ellipsoidal
    distributions of the theory: ``a^2 = 5 <r^2> / 2`` weighted by the normal
    forces, ``c`` the same on the stick-zone deficit ``mu F_N - F_T`` (zero in
    the slip annulus, ``mu p0 (c / a) sqrt(1 - r^2 / c^2)`` in the stick disk).

    Parameters
    ----------
    q_ratio : float
        Tangential load ``Q / (mu P)`` (-), >= 0.
    params : SphereOnFlat, optional
        Benchmark parameters (``q_ratio`` here overrides theirs).
    condensation : ContactCondensation, optional
        The condensation of a :func:`sphere_static_model` (or of a reduced
        :func:`sphere_on_flat`), to reuse over several ``q_ratio``.
    **changes
        Parameters to change, e.g. ``divisions=8``.

    Returns
    -------
    dict
        SI values: ``contact_radius``, ``stick_radius`` (m), ``peak_pressure``
        (Pa), ``normal_load``, ``tangential_load`` (N, whole sphere),
        ``radius`` (m), ``effective_modulus`` (Pa), ``mu``, ``q_ratio``,
        ``pairs`` (of the half model), ``node_spacing`` (m), the theory
        (``hertz_radius``, ``hertz_peak_pressure``, ``mindlin_stick_radius``),
        the relative errors ``error_contact_radius``, ``error_peak_pressure``,
        ``error_stick_radius``, ``regime``, the whole contact's force sums,
        ``converged`` and ``message``.
    """
    check_q_ratio(q_ratio)
    if condensation is None:
        condensation = ContactCondensation(
            sphere_static_model(params, **{**changes, "q_ratio": max(q_ratio, 1e-3)})
        )
    info = condensation.full.info
    if "pair_points" not in info:
        raise ValueError(
            "sphere_static_benchmark needs a sphere-on-flat model (its info names the pair points)"
        )
    P, R, e_star, mu = info["normal_load"], info["radius"], info["effective_modulus"], info["mu"]
    a_h = hertz_radius(P, R, e_star)
    p0_h = hertz_sphere_peak_pressure(P, a_h)
    c_h = mindlin_stick_radius(a_h, q_ratio)
    pts = info["pair_points"]
    out = dict(
        normal_load=P, tangential_load=q_ratio * mu * P, radius=R, effective_modulus=e_star, mu=mu,
        q_ratio=q_ratio, hertz_radius=a_h, hertz_peak_pressure=p0_h, mindlin_stick_radius=c_h,
        pairs=condensation.model.pairs.count, node_spacing=info["window"] * a_h / info["divisions"],
    )  # fmt: skip
    mirrored = np.vstack([pts, pts * [1.0, -1.0]])
    scale = q_ratio * mu * P / info["tangential_load"] if q_ratio else 0.0
    theory = dict(contact=a_h, peak=p0_h, stick=c_h)
    out.update(
        static_anchors(condensation, q_ratio, mirrored, theory, "radius", scale, info["symmetry_factor"])
    )
    return out


def tangential_modulus(young: float, poisson: float) -> float:
    """``G*`` of Mindlin's compliance for two identical bodies (Pa).

    ``1 / G* = (2 - nu1) / G1 + (2 - nu2) / G2`` (Johnson, sec. 7.2), so ``G* = G /
    (2 (2 - nu))`` with ``G = E / (2 (1 + nu))``: the tangential displacement of
    the holder is ``delta = 3 mu P / (16 a G*) [1 - (1 - Q / (mu P))^(2/3)]``.
    """
    return young / (2.0 * (1.0 + poisson)) / (2.0 * (2.0 - poisson))


def mindlin_deresiewicz_dissipation(
    normal_load: float, mu: float, contact_radius: float, g_star: float, q_amplitude: float
) -> float:
    """Energy dissipated per cycle of tangential load ``+-Q*`` at constant ``P`` (J; Johnson, sec. 7.4).

    ``W = 9 mu^2 P^2 / (10 a G*) [1 - (1 - x)^(5/3) - 5 x / 6 (1 + (1 - x)^(2/3))]``, ``x = Q* / (mu P)
    < 1``: the area of the Masing loop ``4 Q* d(Q*) - 8 int_0^Q* d(u) du`` of the compliance ``d(Q) = 3 mu
    P / (16 a G*) [1 - (1 - Q / (mu P))^(2/3)]`` (:func:`tangential_modulus`).
    """
    x = q_amplitude / (mu * normal_load)
    if not 0 <= x < 1:
        raise ValueError(f"q_amplitude / (mu P) must be in [0, 1) (partial slip), got {x!r}")
    bracket = 1 - (1 - x) ** (5 / 3) - 5 * x / 6 * (1 + (1 - x) ** (2 / 3))
    return float(9 * mu**2 * normal_load**2 / (10 * contact_radius * g_star) * bracket)


def sphere_fretting_loop(condensation: ContactCondensation, scale: float, steps: int = 12) -> dict:
    """The fretting loop of a quasi-static load cycle ``0 -> s -> -s -> s`` of the ``cos`` pattern.

    Parameters
    ----------
    condensation : ContactCondensation
        Of a :func:`sphere_static_model` (force or, with an arm, displacement control).
    scale : float
        Amplitude ``s`` as a multiple of the model's ``cos`` pattern (-).
    steps : int
        Increments per leg of the path.

    Returns
    -------
    dict
        Over the closed cycle (the last two legs, from the first ``+s``):
        ``tangential_force`` (N, the whole contact's ``sum lambda_T``, which
        the holder transmits), ``displacement`` (m, the holder's ``x``),
        ``drive`` (the load factors), ``loop_work = oint Q d(delta)`` (J) and
        ``friction_work`` (J, the contact forces' work on the pairs'
        tangential displacements, trapezoidal); ``converged``, ``message``.
        The two works agree: over a closed cycle the elastic energy returns
        (the arm's too).
    """
    res = solve_static(condensation, tangential_scale=(scale, -scale, scale), tangential_steps=steps)
    out = dict(converged=res.converged, message=res.message)
    if not res.converged:
        return out
    c, nq = condensation, condensation.n_q
    info = c.full.info
    first = next(k for k, st in enumerate(res.states) if st.load[1] == scale)
    cycle = res.states[first:]
    K_ss = sla.lu_factor(c.K[nq:, nq:])
    pad_x = c.model.names["pad_x"]

    def holder(st) -> float:
        F = st.load[0] * c.force_static + st.load[1] * c.force_harmonic.real
        z_s = sla.lu_solve(K_ss, F[nq:] - c.K[nq:, :nq] @ st.q)
        return float(c.T[pad_x] @ np.concatenate([st.q, z_s]))

    sym = info["symmetry_factor"]
    Q = sym * np.array([st.tangential_force.sum() for st in cycle])
    delta = np.array([holder(st) for st in cycle])
    friction = sum(
        0.5 * (b.tangential_force + a.tangential_force) @ (b.q[0::2] - a.q[0::2])
        for a, b in zip(cycle[:-1], cycle[1:], strict=True)
    )
    out.update(
        tangential_force=Q, displacement=delta, drive=np.array([st.load[1] for st in cycle]),
        loop_work=float(np.sum(0.5 * (Q[1:] + Q[:-1]) * np.diff(delta))), friction_work=sym * float(friction),
    )  # fmt: skip
    return out


def sphere_cyclic_dissipation(
    q_ratio: float,
    params: SphereOnFlat | None = None,
    condensation: ContactCondensation | None = None,
    steps: int = 12,
    **changes,
) -> dict:
    """Friction work per cycle of the tangential load ``0 -> Q* -> -Q* -> Q*`` against Mindlin-Deresiewicz.

    The quasi-static path of ``sphere_fretting_loop()`` (force control) with
    ``steps`` increments a leg; the work of the contact forces on the pairs'
    tangential displacements over the closed cycle, ``W = sum_k sum_i
    (lambda_T,i^k + lambda_T,i^(k-1)) / 2 (u_T,i^k - u_T,i^(k-1))``, twice the
    half model's.

    Returns
    -------
    dict
        ``dissipation`` (J), ``mindlin_deresiewicz`` (J), ``error_dissipation``
        (-), ``q_ratio``, ``converged``, ``message``.
    """
    check_q_ratio(q_ratio)
    if condensation is None:
        condensation = ContactCondensation(
            sphere_static_model(params, **{**changes, "q_ratio": max(q_ratio, 1e-3)})
        )
    info = condensation.full.info
    if info.get("arm_stiffness", 0.0) > 0:
        raise ValueError("sphere_cyclic_dissipation needs force control (a model without a loading arm)")
    P, mu = info["normal_load"], info["mu"]
    loop = sphere_fretting_loop(condensation, q_ratio * mu * P / info["tangential_load"], steps)
    theory = mindlin_deresiewicz_dissipation(
        P, mu, hertz_radius(P, info["radius"], info["effective_modulus"]),
        tangential_modulus(info["young"], info["poisson"]), q_ratio * mu * P,
    )  # fmt: skip
    out = dict(
        q_ratio=q_ratio, mindlin_deresiewicz=theory, converged=loop["converged"], message=loop["message"]
    )
    if not loop["converged"]:
        return dict(out, dissipation=None, error_dissipation=None)
    w = loop["friction_work"]
    return dict(out, dissipation=w, error_dissipation=(w - theory) / theory)


def sphere_periodic(
    q_ratio: float,
    frequency_ratio: float,
    harmonics: int = 3,
    params: SphereOnFlat | None = None,
    condensation: ContactCondensation | None = None,
    linear: str = "structured",
    krylov_min: int | None = None,
    **changes,
) -> dict:
    """Periodic response of the sphere on the flat under ``Q* cos(omega t)`` with the 2-D friction law.

    Parameters
    ----------
    q_ratio : float
        Load amplitude ``Q* / (mu P)`` (-), >= 0.
    frequency_ratio : float
        ``omega`` over the holder's first mode (:func:`holder_frequency`) (-), > 0: well below 1 the
        response is quasi-static, and its dissipation per cycle is Mindlin-Deresiewicz's.
    harmonics : int
        ``Nh`` of the harmonic balance.
    params, condensation, **changes
        As :func:`sphere_static_benchmark`'s; ``condensation`` of a :func:`sphere_dynamic_model` to reuse.
    linear : str
        The Newton steps' linear algebra (:class:`~fretwear.interface.periodic.InterfaceProblem`).
    krylov_min : int, optional
        The problem's ``krylov_min`` (:class:`~fretwear.interface.periodic.InterfaceProblem`); default its.

    Returns
    -------
    dict
        ``solution`` (:class:`~fretwear.interface.periodic.InterfaceSolution`, half model), ``frequency``
        (Hz), ``holder_frequency`` (Hz), ``dissipation`` (J per cycle, whole contact: twice the half
        model's friction energy), ``mindlin_deresiewicz`` (J, for ``q_ratio < 1``) and
        ``error_dissipation`` (-), ``holder_amplitude`` (m, first harmonic of ``pad_x``), ``pairs``,
        ``unknowns``, ``converged``, ``iterations``.
    """
    from .periodic import InterfaceProblem, solve_interface

    check_q_ratio(q_ratio)
    if not (np.isfinite(frequency_ratio) and frequency_ratio > 0):
        raise ValueError(f"frequency_ratio must be a finite ratio > 0, got {frequency_ratio!r}")
    if condensation is None:
        condensation = ContactCondensation(sphere_dynamic_model(params, **{**changes, "q_ratio": 0.5}))
    info = condensation.full.info
    p = SphereOnFlat(
        **{k: info[k] for k in ("radius", "normal_load", "young", "poisson", "mu", "holder_mass")}
    )
    f1 = holder_frequency(p)
    P, mu = info["normal_load"], info["mu"]
    problem = InterfaceProblem(
        condensation, 2 * np.pi * frequency_ratio * f1, harmonics=harmonics, linear=linear, friction="cone",
        force_scale=q_ratio * mu * P / info["tangential_load"],
    )  # fmt: skip
    if krylov_min is not None:
        problem.krylov_min = krylov_min
    sol = solve_interface(problem)
    sym = info["symmetry_factor"]
    out = dict(
        solution=sol, frequency=frequency_ratio * f1, holder_frequency=f1, pairs=problem.n_pairs,
        unknowns=problem.size, converged=sol.converged, iterations=sol.iterations,
        dissipation=sym * sol.friction_energy,
    )  # fmt: skip
    pad = condensation.full_harmonics(problem.omega, harmonics, sol.condensation_harmonics,
                                      dofs=[condensation.model.names["pad_x"]])[0]  # fmt: skip
    out["holder_amplitude"] = float(np.hypot(pad[1], pad[2]))
    if q_ratio < 1:
        a = hertz_radius(P, info["radius"], info["effective_modulus"])
        md = mindlin_deresiewicz_dissipation(P, mu, a, tangential_modulus(info["young"], info["poisson"]),
                                             q_ratio * mu * P)  # fmt: skip
        out.update(mindlin_deresiewicz=md, error_dissipation=(out["dissipation"] - md) / md)
    return out
