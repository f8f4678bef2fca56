"""Quasi-static anchors: Hertz, Cattaneo-Mindlin partial slip, gross slip, mesh convergence."""

import numpy as np
import pytest

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.static import second_moment_half_width, solve_static, static_benchmark
from fretwear.model import craig_bampton
from fretwear.model.structure import SLIP, STICK


def _condensation(nodes):
    return ContactCondensation(craig_bampton(cylinder_on_flat(contact_nodes=nodes), 0.0))


@pytest.fixture(scope="module")
def cond32():
    return _condensation(32)


def test_second_moment_half_width_of_an_ellipse():
    x = np.linspace(-2.0, 2.0, 4001)
    w = np.sqrt(np.clip(1 - (x - 0.3) ** 2 / 1.5**2, 0, None))
    assert second_moment_half_width(x, w) == pytest.approx(1.5, rel=1e-4)
    assert second_moment_half_width(x, 0 * x) == 0.0


def test_hertz_half_width_peak_pressure_and_profile(cond32):
    d = static_benchmark(0.0, condensation=cond32)
    assert d["regime"] == "stick" and d["converged"]
    assert abs(d["error_contact_half_width"]) < 0.03
    assert abs(d["error_peak_pressure"]) < 0.03
    assert d["normal_force_sum"] == pytest.approx(d["normal_load_per_length"], rel=1e-8)  # equilibrium
    # the whole pressure profile, node by node, follows p0 sqrt(1 - x^2 / a^2)
    res = solve_static(cond32, tangential_scale=0.0)
    c = cond32.model.pairs
    p = res.final.normal_force / c.area
    a, p0 = d["hertz_half_width"], d["hertz_peak_pressure"]
    hertz = p0 * np.sqrt(np.clip(1 - c.position**2 / a**2, 0, None))
    assert np.sqrt(np.mean((p - hertz) ** 2)) < 0.03 * p0


@pytest.mark.parametrize("q", [0.3, 0.5, 0.8])
def test_cattaneo_mindlin_stick_zone(cond32, q):
    d = static_benchmark(q, condensation=cond32)
    assert d["regime"] == "partial slip" and d["converged"]
    assert d["mindlin_stick_half_width"] == pytest.approx(d["hertz_half_width"] * np.sqrt(1 - q))
    assert abs(d["error_stick_half_width"]) < 0.05
    assert d["tangential_force_sum"] == pytest.approx(q * d["mu"] * d["normal_load_per_length"], rel=1e-8)
    # identical materials: the tangential load leaves the pressure (hence a) unchanged
    assert abs(d["error_contact_half_width"]) < 0.03


def test_stick_zone_is_central_and_slip_is_at_the_friction_limit(cond32):
    res = solve_static(cond32, tangential_scale=0.5 / 0.5)  # the model's q_ratio is 0.5
    s = res.final
    x = cond32.model.pairs.position
    a = cond32.full.info["hertz_half_width"]
    c = a * np.sqrt(0.5)
    stick, slip = s.state == STICK, s.state == SLIP
    assert np.all(np.abs(x[stick]) < 1.1 * c) and np.all(np.abs(x[slip]) > 0.9 * c)
    mu = cond32.model.pairs.mu
    assert np.allclose(s.tangential_force[slip], mu[slip] * s.normal_force[slip], rtol=1e-9)
    assert np.all(np.abs(s.tangential_force[stick]) < mu[stick] * s.normal_force[stick])


def test_gross_slip_above_mu_p(cond32):
    below = static_benchmark(0.95, condensation=cond32)
    assert below["regime"] == "partial slip" and below["stick_half_width"] > 0
    above = static_benchmark(1.05, condensation=cond32)
    assert above["regime"] == "gross slip" and above["stick_half_width"] == 0.0
    assert not above["converged"] and above["message"].startswith("gross slip")


def test_static_solution_does_not_depend_on_the_penalty(cond32):
    Z = cond32.static[0]
    base = solve_static(cond32, tangential_scale=1.0).final
    other = solve_static(cond32, tangential_scale=1.0, eps=30 * np.abs(np.diag(Z))).final
    scale = base.normal_force.max()
    assert np.abs(other.normal_force - base.normal_force).max() < 1e-8 * scale
    assert np.abs(other.tangential_force - base.tangential_force).max() < 1e-8 * scale


def test_mesh_convergence_of_the_half_widths(cond32):
    """Three meshes (8, 16, 32 pairs across the window): the errors on a and on c shrink."""
    err_a, err_c = [], []
    for cond in (_condensation(8), _condensation(16), cond32):
        err_a.append(abs(static_benchmark(0.0, condensation=cond)["error_contact_half_width"]))
        err_c.append(
            max(
                abs(static_benchmark(q, condensation=cond)["error_stick_half_width"]) for q in (0.3, 0.5, 0.8)
            )
        )
    assert err_a[0] > err_a[1] > err_a[2]
    assert err_c[0] > err_c[1] > err_c[2]


def test_benchmark_dictionary_has_the_cli_keys(cond32):
    d = static_benchmark(0.5, condensation=cond32)
    for key in ("contact_half_width", "stick_half_width", "peak_pressure", "normal_load_per_length",
                "tangential_load_per_length", "radius", "effective_modulus", "mu"):  # fmt: skip
        assert isinstance(d[key], float) and np.isfinite(d[key])
    with pytest.raises(ValueError, match="q_ratio must be"):
        static_benchmark(-0.1, condensation=cond32)


@pytest.mark.slow
def test_anchors_on_the_fine_mesh():
    """64 pairs across the window (a spacing of a / 25): Hertz and the three Mindlin cases."""
    cond = _condensation(64)
    hertz = static_benchmark(0.0, condensation=cond)
    assert abs(hertz["error_contact_half_width"]) < 0.03 and abs(hertz["error_peak_pressure"]) < 0.03
    for q in (0.3, 0.5, 0.8):
        assert abs(static_benchmark(q, condensation=cond)["error_stick_half_width"]) < 0.05
