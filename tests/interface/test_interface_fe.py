"""Benchmark mesh and finite-element matrices (scikit-fem, plane strain)."""

import numpy as np
import pytest

from fretwear.interface.fe import (
    MAX_CONTACT_NODES,
    CylinderOnFlat,
    assemble_body,
    cylinder_on_flat,
    effective_modulus,
)
from fretwear.interface.mesh import cylinder_on_flat_mesh, graded_axis
from fretwear.model import ContactPairs, Model


def test_graded_axis_is_uniform_then_geometric():
    x = graded_axis(0.1, 1.0, 20.0, 1.3)
    assert x[0] == 0 and x[-1] == 20.0
    d = np.diff(x)
    assert np.allclose(d[:10], 0.1)
    ratios = d[11:-2] / d[10:-3]
    assert np.allclose(ratios, 1.3)
    assert np.all(d > 0)


def test_graded_axis_rejects_bad_input():
    with pytest.raises(ValueError, match="growth >= 1"):
        graded_axis(0.1, 1.0, 2.0, 0.9)


def test_mesh_pairs_face_each_other_across_the_circular_gap():
    R = 0.05
    mesh = cylinder_on_flat_mesh(R, 5e-4, 17, 0.01, 0.01, 0.02, 0.02)
    xp, yp = mesh.pad.p[:, mesh.pad_contact]
    xf, yf = mesh.flat.p[:, mesh.flat_contact]
    assert np.allclose(xp, xf) and np.allclose(xf, mesh.x)
    assert np.allclose(yf, 0.0)
    assert np.allclose(yp, R - np.sqrt(R**2 - xp**2))
    assert np.allclose(mesh.gap, yp)
    # tributary lengths tile the window plus half a cell on each side
    h = np.diff(mesh.x)[0]
    assert np.allclose(mesh.tributary[1:-1], h)
    assert np.all(mesh.pad.p[1, mesh.pad_top] == pytest.approx(0.01))
    assert np.all(mesh.flat.p[1, mesh.flat_bottom] == pytest.approx(-0.02))


def test_mesh_rejects_a_window_wider_than_the_pad():
    with pytest.raises(ValueError, match="window must be in"):
        cylinder_on_flat_mesh(0.05, 0.02, 17, 0.01, 0.01, 0.02, 0.02)


def test_body_matrices_rigid_modes_and_mass():
    mesh = cylinder_on_flat_mesh(0.05, 5e-4, 9, 0.01, 0.01, 0.02, 0.02)
    rho = 7800.0
    K, M, basis = assemble_body(mesh.flat, 200e9, 0.3, rho)
    x, y = mesh.flat.p
    dx, dy = basis.nodal_dofs
    for mode in ("x", "y", "rot"):
        u = np.zeros(K.shape[0])
        u[dx], u[dy] = {"x": (1.0, 0.0), "y": (0.0, 1.0), "rot": (-y, x)}[mode]
        assert np.abs(K @ u).max() <= 1e-9 * abs(K).max() * np.abs(u).max()
    ux = np.zeros(K.shape[0])
    ux[dx] = 1.0
    assert ux @ M @ ux == pytest.approx(rho * 0.04 * 0.02, rel=1e-12)  # rho * area of the flat (kg/m)


def test_plane_strain_uniaxial_strain():
    # a uniform vertical strain of the flat needs sigma_yy = (lambda + 2 G) eps (plane strain)
    E, nu = 200e9, 0.3
    mesh = cylinder_on_flat_mesh(0.05, 5e-4, 9, 0.01, 0.01, 0.02, 0.02)
    K, _, basis = assemble_body(mesh.flat, E, nu, 1.0)
    x, y = mesh.flat.p
    u = np.zeros(K.shape[0])
    u[basis.nodal_dofs[1]] = 1e-4 * y
    f = K @ u
    top = np.abs(y) < 1e-12
    lam, G = E * nu / ((1 + nu) * (1 - 2 * nu)), E / (2 * (1 + nu))
    assert f[basis.nodal_dofs[1][top]].sum() == pytest.approx((lam + 2 * G) * 1e-4 * 0.04, rel=1e-10)


def test_benchmark_model_loads_pairs_and_info():
    p = CylinderOnFlat(contact_nodes=9, q_ratio=0.4)
    m = cylinder_on_flat(p)
    assert m.n_pairs == 9
    assert m.force_static[m.names["pad_y"]] == -p.normal_load
    assert m.force_cos[m.names["pad_x"]] == pytest.approx(0.4 * p.mu * p.normal_load)
    assert m.info["effective_modulus"] == effective_modulus(200e9, 0.3)
    assert m.info["hertz_half_width"] == pytest.approx(
        np.sqrt(4 * p.normal_load * p.radius / (np.pi * p.effective_modulus))
    )
    # the pad hangs on its holder: lifting the holder with the pad moves every pad DOF, strains nothing
    B = m.pairs.relative_map(m.n_dofs)
    assert B.shape == (18, m.n_dofs)
    assert abs(m.K - m.K.T).max() <= 1e-12 * abs(m.K).max()


def test_benchmark_parameters_are_checked():
    with pytest.raises(ValueError, match="normal_load must be"):
        CylinderOnFlat(normal_load=-1.0)
    with pytest.raises(ValueError, match="drive_displacement"):
        CylinderOnFlat(drive_displacement=1e-6)


def test_interface_model_validation_messages():
    pairs = ContactPairs(dofs_a=[[0, 1]], dofs_b=[[2, 3]], normal=[[0, 1]], area=[1.0], mu=0.5)
    I4 = np.eye(4)
    with pytest.raises(ValueError, match="K must be symmetric"):
        K = I4.copy()
        K[0, 1] = 1.0
        Model(M=I4, C=None, K=K, pairs=pairs)
    with pytest.raises(ValueError, match=r"dofs_b\[0\] = \[2, 7\] is out of range"):
        Model(M=I4, C=None, K=I4, pairs=ContactPairs([[0, 1]], [[2, 7]], [[0, 1]], [1.0], 0.5))
    with pytest.raises(ValueError, match="area must be > 0"):
        ContactPairs([[0, 1]], [[2, 3]], [[0, 1]], [0.0], 0.5)
    with pytest.raises(ValueError, match="tangent .* required"):
        ContactPairs([[0, 1, 2]], [[3, 4, 5]], [[0, 0, 1]], [1.0], 0.5)


def test_relative_map_gives_contact_coordinates():
    # node B displaced by (1, -2) relative to A with normal +y: slip u_T = 1, approach u_N = 2
    pairs = ContactPairs(dofs_a=[[0, 1]], dofs_b=[[2, 3]], normal=[[0.0, 2.0]], area=[1.0], mu=0.5)
    B = pairs.relative_map(4).toarray()
    u = np.array([0.5, 0.5, 1.5, -1.5])
    assert np.allclose(B @ u, [1.0, 2.0])


@pytest.mark.parametrize("n", [2, MAX_CONTACT_NODES + 1, 100_000, 32.5])
def test_contact_nodes_out_of_range_is_refused_before_meshing(n):
    """100 000 pairs used to raise MemoryError in the mesh; the bound is checked before any work."""
    match = rf"contact_nodes must be an integer in \[3, {MAX_CONTACT_NODES}\].*got {n}"
    with pytest.raises(ValueError, match=match):
        cylinder_on_flat(contact_nodes=n)
