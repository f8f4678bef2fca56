"""The 3-D sphere-on-flat benchmark: assembly, static condensation, Hertz and Mindlin anchors, CLI."""

import argparse
import dataclasses
import json

import numpy as np
import pytest
import scipy.sparse.linalg as spla
from skfem import Basis, BilinearForm, ElementHex1, ElementVector, MeshHex, asm
from skfem.helpers import dot
from skfem.models.elasticity import lame_parameters, linear_elasticity

from fretwear.cli.interface import add_arguments, run
from fretwear.interface.contact import SLIP, STICK
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import (
    SphereOnFlat,
    _contact_schur,
    mindlin_deresiewicz_dissipation,
    sphere_cyclic_dissipation,
    sphere_dynamic_model,
    sphere_fretting_loop,
    sphere_on_flat,
    sphere_periodic,
    sphere_static_benchmark,
    sphere_static_model,
    tangential_modulus,
)
from fretwear.interface.sphere_mesh import assemble_boxes, nested_dissection
from fretwear.interface.static import second_moment_half_width, second_moment_radius, solve_static
from fretwear.model import ContactPairs, craig_bampton

CHEAP = dict(divisions=6, size=4.0)  # 63 pairs, 7 000 DOFs a body: a second to build


@pytest.fixture(scope="module")
def cond():
    return ContactCondensation(sphere_static_model(**CHEAP))


def test_box_assembly_equals_scikit_fem():
    x = np.array([0.0, 0.1, 0.25, 0.5, 1.0])
    mesh = MeshHex.init_tensor(x, 2 * x[:4], -3 * x[::-1])
    basis = Basis(mesh, ElementVector(ElementHex1()), intorder=2)
    K0 = asm(linear_elasticity(*lame_parameters(2.0, 0.3)), basis)
    M0 = asm(BilinearForm(lambda u, v, w: dot(u, v)), basis)
    K, M, dofs = assemble_boxes(mesh, 2.0, 0.3, 1.0)
    assert abs(K - K0).max() < 1e-13 * abs(K0).max()
    assert abs(M - M0).max() < 1e-13 * abs(M0).max()
    assert np.array_equal(dofs, basis.nodal_dofs)


def test_contact_schur_is_the_dense_schur_complement():
    mesh = SphereOnFlat(divisions=3, size=2.5).mesh()
    order = nested_dissection(mesh.flat, mesh.axes)
    assert np.array_equal(np.sort(order), np.arange(mesh.flat.p.shape[1]))  # a permutation of the nodes
    K, _, _ = assemble_boxes(mesh.flat, 1.0, 0.3, 1.0)
    S = _contact_schur(mesh, K)
    b = np.concatenate([3 * mesh.contact, 3 * mesh.contact + 2])
    fixed = np.concatenate([(3 * mesh.bottom[:, None] + np.arange(3)).ravel(), 3 * mesh.symmetry + 1])
    i = np.setdiff1d(np.arange(K.shape[0]), np.concatenate([b, fixed]))
    Kd = K.toarray()
    ref = Kd[np.ix_(b, b)] - Kd[np.ix_(b, i)] @ np.linalg.solve(Kd[np.ix_(i, i)], Kd[np.ix_(i, b)])
    assert np.abs(S - ref).max() < 1e-10 * np.abs(ref).max()


def test_static_model_responds_as_the_full_model():
    """Holder held, equal and opposite forces at the pairs: the same relative displacements in both."""
    p = dict(divisions=3, size=2.5)
    full, static = sphere_on_flat(**p), sphere_static_model(**p)
    rng = np.random.default_rng(1)
    nc = full.pairs.count
    f_pairs = rng.normal(size=(nc, 2))  # (x, z) force on the sphere's node, the opposite on the flat's
    f = np.zeros(full.n_dofs)
    for k, comp in ((0, 0), (1, 2)):
        f[full.pairs.dofs_b[:, comp]] += f_pairs[:, k]
        f[full.pairs.dofs_a[:, comp]] -= f_pairs[:, k]
    keep = np.setdiff1d(np.arange(full.n_dofs), [full.names["pad_x"], full.names["pad_z"]])
    u = np.zeros(full.n_dofs)
    u[keep] = spla.spsolve(full.K[keep][:, keep].tocsc(), f[keep])
    rel_full = np.column_stack([u[full.pairs.dofs_b[:, c]] - u[full.pairs.dofs_a[:, c]] for c in (0, 2)])
    g = np.concatenate([-f_pairs[:, 0], -f_pairs[:, 1], f_pairs[:, 0], f_pairs[:, 1]])
    v = np.linalg.solve(static.K[: 4 * nc, : 4 * nc], g)
    rel_static = np.column_stack([v[2 * nc : 3 * nc] - v[:nc], v[3 * nc :] - v[nc : 2 * nc]])
    assert np.abs(rel_static - rel_full).max() < 1e-9 * np.abs(rel_full).max()
    assert static.pairs.count == nc and np.allclose(static.pairs.gap, full.pairs.gap)


def test_second_moment_radius_of_a_semi_ellipsoid():
    g = np.linspace(-2.0, 2.0, 801)
    x, y = (v.ravel() for v in np.meshgrid(g, g))
    w = np.sqrt(np.clip(1 - ((x - 0.3) ** 2 + y**2) / 1.5**2, 0, None))
    assert second_moment_radius(np.column_stack([x, y]), w) == pytest.approx(1.5, rel=1e-3)
    line = np.linspace(-2.0, 2.0, 4001)
    w1 = np.sqrt(np.clip(1 - line**2 / 1.5**2, 0, None))
    assert second_moment_half_width(line, w1) == pytest.approx(1.5, rel=1e-4)
    assert second_moment_radius(np.column_stack([x, y]), 0 * x) == 0.0


def test_hertz_radius_and_peak_pressure(cond):
    d = sphere_static_benchmark(0.0, condensation=cond)
    assert d["converged"] and d["regime"] == "stick"
    P, e_star, R = d["normal_load"], d["effective_modulus"], d["radius"]
    a = (3 * P * R / (4 * e_star)) ** (1 / 3)
    assert d["hertz_radius"] == pytest.approx(a) and d["hertz_peak_pressure"] == pytest.approx(
        3 * P / (2 * np.pi * a**2)
    )
    assert abs(d["error_contact_radius"]) < 0.03 and abs(d["error_peak_pressure"]) < 0.03
    assert d["normal_force_sum"] == pytest.approx(P, rel=1e-8)  # the half model carries P / 2


@pytest.mark.parametrize("q", [0.3, 0.5, 0.8])
def test_mindlin_stick_radius(cond, q):
    d = sphere_static_benchmark(q, condensation=cond)
    assert d["converged"] and d["regime"] == "partial slip"
    assert d["mindlin_stick_radius"] == pytest.approx(d["hertz_radius"] * (1 - q) ** (1 / 3))
    assert abs(d["error_stick_radius"]) < 0.05
    assert d["tangential_force_sum"] == pytest.approx(q * d["mu"] * d["normal_load"], rel=1e-8)
    assert abs(d["error_contact_radius"]) < 0.03  # beta = 0: Q leaves the pressure unchanged


def test_gross_slip_above_mu_p(cond):
    d = sphere_static_benchmark(1.05, condensation=cond)
    assert d["regime"] == "gross slip" and not d["converged"] and d["stick_radius"] == 0.0


@pytest.mark.parametrize(
    ("change", "name"),
    [
        (dict(divisions=1), "divisions"),
        (dict(divisions=6.0), "divisions"),
        (dict(normal_load=-1.0), "normal_load"),
        (dict(poisson=0.5), "poisson"),
        (dict(window=1.0), "window"),
        (dict(size=1.1), "size"),
        (dict(size=60.0), "size"),  # the block wider than the sphere
        (dict(growth=2.5), "growth"),
        (dict(mu=float("nan")), "mu"),
        (dict(drive_displacement=1e-6), "drive_displacement"),
    ],
)
def test_bad_parameters_are_refused_by_name(change, name):
    with pytest.raises(ValueError, match=name):
        SphereOnFlat(**change)


def test_full_model_has_3d_pairs_and_half_loads():
    m = sphere_on_flat(divisions=3, size=2.5)
    assert m.pairs.dim == 3 and m.sparse
    assert np.allclose(m.pairs.normal, [0, 0, 1]) and np.allclose(m.pairs.tangent, [1, 0, 0])
    on_plane = m.info["pair_points"][:, 1] == 0
    assert np.all(m.pairs.dofs_a[on_plane, 1] == -1) and np.all(m.pairs.dofs_a[~on_plane, 1] >= 0)
    assert m.force_static[m.names["pad_z"]] == -0.5 * m.info["normal_load"]


def _cli(argv):
    parser = argparse.ArgumentParser(prog="fretwear interface")
    add_arguments(parser)
    return run(parser.parse_args(argv))


def test_cli_sphere_static_json(capsys):
    assert _cli(["--static", "--geometry", "sphere", "--q-ratio", "0.5", "--divisions", "6"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("contact_radius", "stick_radius", "peak_pressure", "normal_load", "tangential_load", "radius",
                "effective_modulus", "mu", "error_contact_radius", "error_stick_radius"):  # fmt: skip
        assert isinstance(out[key], float) and np.isfinite(out[key])
    assert out["pairs"] == 63 and out["normal_load"] == 100.0
    assert out["stick_radius"] == pytest.approx(out["contact_radius"] * 0.5 ** (1 / 3), rel=0.05)
    assert _cli(["--geometry", "sphere", "--divisions", "6"]) == 2  # periodic solves: not yet
    assert _cli(["--static", "--divisions", "6"]) == 2  # --divisions is the sphere's
    assert "--divisions" in capsys.readouterr().err
    assert _cli(["--static", "--geometry", "sphere", "--divisions", "6", "--contact-nodes", "64"]) == 2
    assert "--contact-nodes" in capsys.readouterr().err  # the cylinder's: refused, not ignored


@pytest.mark.slow
def test_anchors_on_the_default_mesh_of_500_pairs():
    """The default (18 divisions, 523 pairs): Hertz, the three Mindlin cases and the dissipation per cycle
    at Q* / (mu P) = 0.3, 0.6, 0.9 (0.3 fails on the cheap mesh: its slip annulus, 0.11 a wide, is one
    spacing there)."""
    cond = ContactCondensation(sphere_static_model())
    assert cond.model.pairs.count >= 500
    hertz = sphere_static_benchmark(0.0, condensation=cond)
    assert abs(hertz["error_contact_radius"]) < 0.03 and abs(hertz["error_peak_pressure"]) < 0.03
    for q in (0.3, 0.5, 0.8):
        assert abs(sphere_static_benchmark(q, condensation=cond)["error_stick_radius"]) < 0.05
    for q in (0.3, 0.6, 0.9):
        assert abs(sphere_cyclic_dissipation(q, condensation=cond)["error_dissipation"]) < 0.05


def test_mindlin_deresiewicz_formula_is_the_masing_loop_area():
    """The closed form against the loop integrated from Mindlin's compliance (Masing's rule)."""
    P, mu, a, g = 100.0, 0.6, 2e-4, 30e9
    for x in (0.3, 0.6, 0.9):
        q_star = x * mu * P

        def d(u):
            return 3 * mu * P / (16 * a * g) * (1 - (1 - u / (mu * P)) ** (2 / 3))

        u = np.linspace(0.0, q_star, 20001)
        area = 4 * q_star * d(q_star) - 8 * np.trapezoid(d(u), u)
        assert mindlin_deresiewicz_dissipation(P, mu, a, g, q_star) == pytest.approx(area, rel=1e-6)
    assert tangential_modulus(200e9, 0.3) == pytest.approx(200e9 / 2.6 / 3.4)
    with pytest.raises(ValueError, match="q_amplitude"):
        mindlin_deresiewicz_dissipation(P, mu, a, g, mu * P)


@pytest.mark.parametrize("q", [0.6, 0.9])
def test_dissipation_per_cycle(cond, q):
    """Friction work of a cycle +-Q* on the cheap mesh (0.3 needs the default mesh: the slow test)."""
    d = sphere_cyclic_dissipation(q, condensation=cond)
    assert d["converged"] and abs(d["error_dissipation"]) < 0.05


def test_a_load_cycle_returns_to_the_state_of_first_loading(cond):
    """Masing: unloading to -Q* and reloading to Q* gives back the tractions of the first loading."""
    s = 0.7 / 0.5  # the model's q_ratio is 0.5
    first = solve_static(cond, tangential_scale=s, tangential_steps=12).final
    cycled = solve_static(cond, tangential_scale=(s, -s, s), tangential_steps=12).final
    scale = first.normal_force.max()
    assert np.abs(cycled.tangential_force - first.tangential_force).max() < 1e-6 * scale
    with pytest.raises(ValueError, match="tangential_scale"):
        solve_static(cond, tangential_scale=(s, np.nan))


def test_craig_bampton_of_the_3d_pairs_equals_the_static_model():
    """The full model (3-D pairs, binormal free, none on the symmetry plane) reduced by Craig-Bampton and
    condensed on its contact coordinates has the static stiffness and loads of the static model."""
    p = dict(divisions=3, size=2.5)
    via_cb = ContactCondensation(craig_bampton(sphere_on_flat(**p), 0.0)).static
    direct = ContactCondensation(sphere_static_model(**p)).static
    for x, y in zip(via_cb, direct, strict=True):
        assert np.abs(x - y).max() < 1e-11 * np.abs(y).max()


def test_a_pair_fixed_on_both_nodes_only_along_its_binormal():
    m = sphere_on_flat(divisions=3, size=2.5)
    c = m.pairs
    bad = ContactPairs(dofs_a=c.dofs_a, dofs_b=c.dofs_b, normal=c.normal, area=c.area, mu=c.mu,
                       tangent=np.tile([0.0, 1.0, 0.0], (c.count, 1)))  # fmt: skip
    with pytest.raises(ValueError, match="binormal component"):
        ContactCondensation(craig_bampton(dataclasses.replace(m, pairs=bad), 0.0))


def test_gross_slip_loop_is_a_parallelogram_with_mindlin_corners():
    """Displacement control through an arm beyond gross slip: the loop's long sides lie at Q = +-mu P exactly
    (every pair slips), the loop is point-symmetric, and its area is the friction work."""
    m = sphere_static_model(**CHEAP, arm_stiffness=2e7, drive_displacement=1.0)
    loop = sphere_fretting_loop(ContactCondensation(m), 1.5e-5)  # the arm's end moves +-15 um
    assert loop["converged"]
    Q, d = loop["tangential_force"], loop["displacement"]
    mu_p = m.info["mu"] * m.info["normal_load"]
    plateau = np.abs(np.abs(Q) - mu_p) < 1e-9 * mu_p
    assert plateau.sum() > len(Q) / 2 and np.any(Q[plateau] > 0) and np.any(Q[plateau] < 0)
    assert np.all(np.abs(Q) <= mu_p * (1 + 1e-9))
    half = len(Q) // 2
    assert np.allclose(Q[half:], -Q[: half + 1], atol=1e-9 * mu_p)
    assert np.allclose(d[half:], -d[: half + 1], atol=1e-9 * np.abs(d).max())
    assert loop["loop_work"] == pytest.approx(loop["friction_work"], rel=1e-9)
    assert 0.5 < loop["loop_work"] / (4 * mu_p * np.abs(d).max()) < 1  # a parallelogram's area, corners cut


@pytest.fixture(scope="module")
def dynamic():
    return ContactCondensation(sphere_dynamic_model(**CHEAP))


def test_dynamic_model_is_the_static_one_in_x_and_z(dynamic, cond):
    """Condensed with the binormal free, the dynamic model (contact nodes' x, y, z kept) has the static
    model's stiffness and loads on (u_T, u_N): the y components condensed either way."""
    for x, y in zip(dynamic.static, cond.static, strict=True):
        assert np.abs(x - y).max() < 1e-9 * np.abs(y).max()
    assert dynamic.model.pairs.dim == 3 and dynamic.has_binormal.sum() < dynamic.n_pairs  # a symmetry plane


def test_periodic_dissipation_far_below_the_holder_mode_is_mindlin_deresiewicz(dynamic):
    """The 2-D friction law on the 3-D patch (63 pairs) at 1/20 of the holder's mode (quasi-static): the
    dissipation per cycle of the periodic solution (Nh = 7) is Mindlin-Deresiewicz's within 5 % (measured
    3.4e-3; 4.4e-2 at Nh = 5, 1.2e-1 at Nh = 3), every traction inside the cone."""
    d = sphere_periodic(0.6, 0.05, harmonics=7, condensation=dynamic)
    assert d["converged"] and abs(d["error_dissipation"]) < 0.05, d["error_dissipation"]
    sol = d["solution"]
    lam = np.hypot(sol.tangential_force[..., 0], sol.tangential_force[..., 1])
    assert np.all(lam <= 0.6 * sol.normal_force * (1 + 1e-9) + 1e-12)
    assert np.any(sol.state == SLIP) and np.any(sol.state_fraction(STICK) == 1)  # partial slip


@pytest.mark.slow
def test_partial_slip_wears_an_annulus_of_the_3d_patch(dynamic):
    """Archard wear over the 3-D patch (63 pairs, cone law, Nh = 3, 1e5 cycles at Q* = 0.6 mu P, quasi-
    static): no wear inside 0.9 of Mindlin's stick radius, wear in the slip annulus, the normal load
    integral P / 2 (half model) kept at every step (measured ~20 s)."""
    from fretwear.interface.periodic import InterfaceProblem
    from fretwear.interface.sphere import holder_frequency, mindlin_stick_radius
    from fretwear.interface.wear import wear_interface

    info = dynamic.full.info
    scale = 0.6 / info["q_ratio"]
    prob = InterfaceProblem(dynamic, 2 * np.pi * 0.05 * holder_frequency(), harmonics=3, force_scale=scale)
    h = wear_interface(prob, 1e-14, 1e5)
    assert h.converged
    a = info["hertz_radius"]
    c = mindlin_stick_radius(a, 0.6)
    r = np.hypot(*info["pair_points"].T)
    w = h.wear[-1]
    assert w.max() > 0 and np.all(w[r < 0.9 * c] == 0)
    assert w[(r > c) & (r < a)].max() > 0.5 * w.max()
    assert np.allclose(h.normal_force_sum, info["normal_load"] / 2, rtol=1e-9)
