"""Polynomial slow-time DLFT: its three bases against exact solutions, the exact load path and each other."""

import numpy as np
import pytest

from fretwear import FrictionContact, Model, paper_model, solve_periodic
from fretwear.hbm.problem import Problem
from fretwear.wear import polynomial
from fretwear.wear.exact import wear_exact
from fretwear.wear.polynomial import BASES, MISFIT_LIMIT, wear_polynomial
from fretwear.wear.stepping import wear_stepping

TWO_PI = 2 * np.pi
KW = 1e-11


def imposed_motion_model() -> Model:
    """A 1e6 kg mass sliding on ground with 1 m amplitude: friction cannot change its motion (s constant)."""
    m = 1e6
    return Model(M=[[m]], C=[[1e3]], K=[[m]], force_cos=[0.75 * m],
                 friction=(FrictionContact.from_normal_load(0, None, 1.0, 10.0, kn=1e7),))  # fmt: skip


def exact(fex: float, f: float, harmonics: int = 3):
    return wear_exact(paper_model(fex=fex), TWO_PI * f, kw=KW, cycles=1e9, harmonics=harmonics)


def cycles_error(hist, ref, fraction: float) -> float:
    return hist.cycles_to(fraction) / ref.cycles_to(fraction) - 1


def test_saturating_basis_is_exact_at_degree_one_when_the_sliding_distance_does_not_change():
    """Archard's law with a load-independent s: w/u0 = 1 - exp(-K_w k_n s N), z linear in N (eq. 15)."""
    model, omega, kw = imposed_motion_model(), 0.45, 2e-13
    s = solve_periodic(model, omega, 3).sliding_distance[0]
    c = model.friction[0]
    hist = wear_polynomial(model, omega, kw=kw, cycles=1e6, degree=1)
    assert hist.converged and hist.status == "worn"  # 0.99 u0 after ~5e5 cycles
    np.testing.assert_allclose(
        hist.wear[:, 0], c.u0 * -np.expm1(-kw * c.kn * s * hist.cycles), atol=1e-6 * c.u0
    )
    assert hist.wear[-1, 0] == pytest.approx(0.99 * c.u0, rel=1e-9)
    assert not hist.info["poor_fit"]


@pytest.mark.parametrize(
    "fex,f,nh",
    [(10, 0.6, 3), (10, 0.7, 3), (14, 0.6, 3), (6, 0.9, 3), (10, 0.55, 7), (6, 0.85, 7), (14, 0.55, 21)],
)
def test_saturating_basis_follows_the_exact_load_path(fex, f, nh):
    """The paper's cases at degree 4, with the cases near the stick limit that a single map missed by 4-29 %:
    cycles to 0.5 and 0.9 u0 within 1 % (issue target 2 %; measured 0.7 % at worst on 6, 10, 14 N x 0.5-1 Hz,
    Nh = 3, 7, 21)."""
    ref = exact(fex, f, nh)
    horizon = 1.25 * ref.cycles_to(0.9)
    hist = wear_polynomial(paper_model(fex=fex), TWO_PI * f, kw=KW, harmonics=nh, cycles=horizon)
    assert hist.converged and hist.info["basis"] == "saturating"
    assert hist.status == ("worn" if ref.cycles_to(0.99) < horizon else "horizon")
    assert hist.info["settled"] and not hist.info["poor_fit"] and not hist.warnings
    for fraction in (0.5, 0.9):
        assert abs(cycles_error(hist, ref, fraction)) < 0.01


def test_the_papers_bases_miss_the_wear_curve_that_the_saturating_basis_follows():
    """10 N, 0.7 Hz: w(N) polynomials in N are 12-21 % off at degree 4, and say so."""
    ref = exact(10, 0.7)
    horizon = 1.25 * ref.cycles_to(0.9)
    sat = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=horizon)
    for basis in ("legendre", "monomial"):
        paper = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=horizon, basis=basis)
        assert abs(cycles_error(paper, ref, 0.5)) > 0.1 and abs(cycles_error(sat, ref, 0.5)) < 0.02
        assert paper.info["poor_fit"] or not paper.converged


def test_horizon_before_wear_out():
    ref = exact(10, 0.8)
    horizon = 0.5 * ref.cycles_to(0.5)
    hist = wear_polynomial(paper_model(fex=10), TWO_PI * 0.8, kw=KW, cycles=horizon)
    assert hist.status == "horizon" and hist.cycles[-1] == pytest.approx(horizon)
    assert hist.wear[-1, 0] == pytest.approx(ref.at([horizon])["wear"][0, 0], abs=0.01 * ref.u0[0])


@pytest.mark.parametrize("basis", BASES)
def test_wear_stays_in_zero_u0_and_grows(basis):
    """A horizon ten times the wear life: the polynomials in N overshoot, the records and at() do not."""
    hist = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=1e5, basis=basis)
    u0 = hist.u0[0]
    dense = hist.at(np.linspace(0, 1e5, 4001))["wear"][:, 0]
    assert np.all(hist.wear >= 0) and np.all(hist.wear < u0) and np.all(dense >= 0) and np.all(dense < u0)
    if basis == "saturating":
        assert hist.status == "worn" and np.all(np.diff(dense) >= 0)
        assert hist.cycles_to(0.99) == pytest.approx(exact(10, 0.7).cycles_to(0.99), rel=0.02)


def test_an_unresolved_fit_is_flagged_with_frequency_and_misfit(monkeypatch):
    """Without refinement (the first map's nodes and one Galerkin pass) the 10 N, 0.7 Hz history is several %
    off: flagged."""
    ref = exact(10, 0.7)
    horizon = 1.25 * ref.cycles_to(0.9)
    fractions = np.linspace(0.1, 0.9, 9)
    monkeypatch.setattr(polynomial, "MAX_ROUNDS", 0)
    monkeypatch.setattr(polynomial, "GALERKIN_PASSES", 1)
    low = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=horizon)
    assert not low.info["settled"] and low.info["misfit"] > MISFIT_LIMIT and low.info["poor_fit"]
    (note,) = [n for n in low.warnings if "Archard" in n]
    assert "0.7 Hz" in note and f"{low.info['misfit']:.1%}" in note and "exact method" in note
    # the misfit measures the error: cycles to 10-90 % of u0 off by about as much (measured 7.6 and 7.6 %)
    errors = [abs(cycles_error(low, ref, q)) for q in fractions]
    assert max(errors) > MISFIT_LIMIT and 0.3 < max(errors) / low.info["misfit"] < 3
    monkeypatch.undo()
    refined = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=horizon)
    assert refined.info["settled"] and not refined.info["poor_fit"] and not refined.warnings
    assert refined.info["rounds"] > 0 and refined.solves > low.solves
    assert max(abs(cycles_error(refined, ref, q)) for q in fractions) < 0.01


def test_near_the_stick_limit_the_refinement_follows_a_770_fold_growth_of_the_sliding_distance():
    """10 N at 0.55 Hz: s grows 770-fold along the history (x8 within z < 0.02, where 70 % of the life is
    spent, then jumps); a single map of the slow variable missed the cycles by 29 % at degree 4."""
    ref = exact(10, 0.55)
    hist = wear_polynomial(paper_model(fex=10), TWO_PI * 0.55, kw=KW, cycles=1e5)
    dense = hist.at(np.linspace(0, 1e5, 4001))["wear"][:, 0]
    assert hist.info["sliding_ratio"] > 100 and hist.info["settled"] and not hist.info["poor_fit"]
    assert np.all(np.diff(dense) >= 0) and np.all(dense < hist.u0[0]) and hist.status == "worn"
    for fraction in (0.1, 0.5, 0.9, 0.99):
        assert abs(cycles_error(hist, ref, fraction)) < 0.01


def test_many_harmonics_converge():
    """The case that failed at Nh = 21 (10 N, 0.7 Hz): node solves with the Newton homotopy fallback."""
    ref = exact(10, 0.7, harmonics=21)
    hist = wear_polynomial(paper_model(fex=10), TWO_PI * 0.7, kw=KW, cycles=1e4, harmonics=21)
    assert hist.converged and hist.status == "horizon"
    assert abs(cycles_error(hist, ref, 0.5)) < 0.03  # measured 2.1 %


def test_legendre_basis_on_frozen_dynamics():
    """The paper's polynomial in N for w = u0 (1 - exp(-K_w k_n s N)), not a polynomial: 1e-4 at degree 8."""
    model, omega, kw = imposed_motion_model(), 0.45, 2e-13
    s = solve_periodic(model, omega, 7).sliding_distance[0]
    c = model.friction[0]
    hist = wear_polynomial(model, omega, kw=kw, cycles=2e5, harmonics=7, degree=8, basis="legendre")
    assert hist.converged and not hist.info["poor_fit"]
    np.testing.assert_allclose(
        hist.wear[:, 0], c.u0 * -np.expm1(-kw * c.kn * s * hist.cycles), atol=1e-4 * c.u0
    )


def test_legendre_error_drops_with_degree_and_monomials_flag_a_low_degree():
    """The paper's setting (Nh = 3, degree 4) and higher degrees against fine stepping at Nh = 3."""
    model, omega, horizon = paper_model(fex=10), TWO_PI * 0.8, 8e3
    ref = wear_stepping(model, omega, kw=KW, cycles=horizon, harmonics=3, tol=1e-5)
    errors = {}
    for degree in (4, 8):
        hist = wear_polynomial(model, omega, kw=KW, cycles=horizon, degree=degree, basis="legendre")
        assert hist.converged
        errors[degree] = np.abs(hist.wear[:, 0] - ref.at(hist.cycles)["wear"][:, 0]).max() / ref.u0[0]
    assert errors[8] < errors[4] / 2 and errors[8] < 0.01
    low = wear_polynomial(model, omega, kw=KW, cycles=horizon, degree=2, basis="monomial")
    assert (
        low.info["basis"] == "monomial" and low.info["poor_fit"] and any("0.8 Hz" in n for n in low.warnings)
    )


def test_paper_galerkin_jacobian_is_the_derivative_of_its_residual():
    """The compiled Galerkin assembly (eq. 29 and Archard's law in N) against central differences."""
    problem = Problem(paper_model(fex=10), TWO_PI * 0.7, 3)
    sol = solve_periodic(paper_model(fex=10), TWO_PI * 0.7, 3)
    slow = polynomial._Slow(problem, KW, 3, "legendre")
    tau, wq, V, D, V0 = polynomial._quadrature("legendre", 3)
    Cx, a = slow._start(sol.unknowns, 5e3, tau, wq, V, V0, 0.99)
    Z, F, eps, kinds, Phi, Psi, half_wave = slow.dyn

    def residual(v):
        Cv, av = v[: Cx.size].reshape(Cx.shape), v[Cx.size :].reshape(a.shape)
        return polynomial._galerkin(Cv, av, 5e3, V, D, wq, V0, KW, slow.kn, slow.mu, slow.u0, Z, F, eps,
                                    kinds, Phi, Psi, half_wave, slow.scale, True)  # fmt: skip

    v = np.concatenate([Cx.ravel(), a.ravel()])
    _, J = residual(v)
    scales = np.concatenate([np.full(Cx.size, np.abs(Cx).max()), np.ones(a.size)])
    fd = np.empty_like(J)
    for i in range(v.size):
        h = 1e-7 * scales[i]
        fd[:, i] = (residual(v + h * np.eye(v.size)[i])[0] - residual(v - h * np.eye(v.size)[i])[0]) / (2 * h)
    np.testing.assert_allclose(J * scales, fd * scales, atol=1e-5 * np.abs(fd * scales).max())


def test_legendre_basis_with_two_contacts_agrees_with_stepping():
    """Two contacts wearing at different rates (the saturating basis takes one): the paper's basis in N."""
    model = Model(M=np.eye(2), K=[[30.0, -20.0], [-20.0, 40.0]], C=0.02 * np.eye(2), force_cos=[8.0, 0.0],
                  friction=(FrictionContact.from_normal_load(0, None, 1.0, 4.0, kn=1e7),
                            FrictionContact.from_normal_load(1, None, 1.0, 6.0, kn=1e7)))  # fmt: skip
    omega, horizon = 3.0, 3e3
    hist = wear_polynomial(model, omega, kw=KW, cycles=horizon, degree=6, basis="legendre")
    ref = wear_stepping(model, omega, kw=KW, cycles=horizon, harmonics=3, tol=1e-5)
    assert hist.converged
    assert np.all(hist.wear[-1] > 0.05 * hist.u0) and hist.info["misfit"] < 1e-3
    np.testing.assert_allclose(
        hist.wear, ref.at(hist.cycles)["wear"], atol=1e-3 * ref.u0.max()
    )  # measured 6e-5
    default = wear_polynomial(model, omega, kw=KW, cycles=horizon, degree=6)  # several contacts: legendre
    np.testing.assert_array_equal(default.wear, hist.wear)
    with pytest.raises(ValueError, match="one friction contact"):
        wear_polynomial(model, omega, kw=KW, cycles=horizon, basis="saturating")


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(basis="cubic"), "basis"),
        (dict(degree=0), "degree"),
        (dict(outputs=1), "outputs"),
        (dict(stop_fraction=1.0), "stop_fraction"),
        (dict(tol=0.0), "tol"),
    ],
)
def test_bad_input(kwargs, match):
    with pytest.raises(ValueError, match=match):
        wear_polynomial(paper_model(), 4.0, **kwargs)
