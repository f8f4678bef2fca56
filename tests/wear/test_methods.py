"""Slow-time wear: stepping and the exact load path against exact solutions, invariants and each other.

The polynomial method has its own tests (tests/wear/test_polynomial.py).
"""

import dataclasses

import numpy as np
import pytest

from fretwear import FrictionContact, Model, paper_model, solve_periodic
from fretwear.wear import dynamics as wear_module
from fretwear.wear.exact import wear_exact
from fretwear.wear.polynomial import wear_polynomial
from fretwear.wear.stepping import wear_stepping

TWO_PI = 2 * np.pi


def imposed_motion_model(normal_load: float = 10.0) -> Model:
    """A 1e6 kg mass sliding on ground with 1 m amplitude: friction (<= 10 N) cannot change its motion.

    The sliding distance per cycle is then 4 X whatever the normal load (to ~1e-5), the
    frozen-dynamics case where Archard's law integrates exactly.
    """
    m, w0 = 1e6, 1.0
    return Model(
        M=[[m]], C=[[1e3]], K=[[m * w0**2]], force_cos=[0.75 * m * w0**2],
        friction=(FrictionContact.from_normal_load(0, None, 1.0, normal_load, kn=1e7),),
    )  # fmt: skip


def frozen_exact(model: Model, omega: float, kw: float, cycles: np.ndarray) -> np.ndarray:
    s = solve_periodic(model, omega, 21).sliding_distance[0]
    c = model.friction[0]
    return c.u0 * (1 - np.exp(-kw * c.kn * s * cycles))


KW_FROZEN = 2e-13  # K_w kn s ~ 2e-6 * 4.5 m per cycle: 0.99 u0 after ~5e5 cycles


def test_frozen_dynamics_adaptive_stepping():
    model, omega = imposed_motion_model(), 0.45
    hist = wear_stepping(model, omega, kw=KW_FROZEN, cycles=3e5, harmonics=21, tol=1e-4)
    assert hist.converged and hist.status == "horizon"
    exact = frozen_exact(model, omega, KW_FROZEN, hist.cycles)
    assert np.abs(hist.wear[:, 0] - exact).max() < 2e-4 * model.friction[0].u0
    assert hist.solves < 200  # the adaptive pair takes large steps on a smooth exponential


def test_frozen_dynamics_per_period_rule_converges_at_first_order():
    """Explicit Euler in N (eq. 24 with dN cycles): the error halves with the step."""
    model, omega, kw = imposed_motion_model(), 0.45, 2e-10  # faster wear so that dN = 1 stays cheap
    errors = []
    for step in (4.0, 2.0, 1.0):
        hist = wear_stepping(model, omega, kw=kw, cycles=200.0, harmonics=7, fixed_step=step)
        exact = frozen_exact(model, omega, kw, hist.cycles)
        errors.append(np.abs(hist.wear[:, 0] - exact).max() / model.friction[0].u0)
    assert errors[2] < 2e-3
    np.testing.assert_allclose(errors[0] / errors[1], 2.0, rtol=0.1)
    np.testing.assert_allclose(errors[1] / errors[2], 2.0, rtol=0.1)


def test_full_stick_never_wears():
    hist = wear_stepping(paper_model(fex=6), TWO_PI * 0.3, kw=1e-9, cycles=1e5, harmonics=7)
    assert hist.status == "stuck" and hist.solves == 1
    np.testing.assert_array_equal(hist.wear, 0.0)
    poly = wear_polynomial(paper_model(fex=6), TWO_PI * 0.3, kw=1e-9, cycles=1e5, harmonics=3)
    np.testing.assert_array_equal(poly.wear, 0.0)


@pytest.mark.parametrize("f", [0.6, 0.7, 1.0])
def test_slipping_points_wear_monotonically_and_never_overshoot(f):
    hist = wear_stepping(paper_model(fex=10), TWO_PI * f, kw=1e-11, cycles=1e6, harmonics=7, tol=1e-3)
    u0 = hist.u0[0]
    w = hist.wear[:, 0]
    assert hist.converged and hist.status == "worn"
    assert np.all(np.diff(w) >= 0) and np.all(w >= 0) and np.all(w < u0)
    assert np.all(hist.normal_load >= 0)
    np.testing.assert_allclose(hist.normal_load[:, 0], 1e7 * (u0 - w), rtol=1e-12, atol=1e-12)
    dense = hist.at(np.linspace(0, hist.cycles[-1], 400))["wear"][:, 0]
    assert np.all(np.diff(dense) >= -1e-15 * u0)


def test_wear_rate_rises_before_it_falls():
    """As F_N relaxes the contact slides more: dw/dN peaks inside the history (the paper's maximal slope)."""
    hist = wear_stepping(paper_model(fex=10), TWO_PI * 0.7, kw=1e-11, cycles=1e6, harmonics=7, tol=1e-3)
    rate = hist.rate[:, 0]
    k = int(np.argmax(rate))
    assert 0 < k < len(rate) - 1 and rate[k] > 2 * rate[0] and rate[-1] < 0.2 * rate[k]


def test_wear_depends_on_kw_times_cycles_only():
    model, omega = paper_model(fex=10), TWO_PI * 0.7
    a = wear_stepping(model, omega, kw=1e-11, cycles=2e4, harmonics=7, tol=1e-5)
    b = wear_stepping(model, omega, kw=2e-11, cycles=1e4, harmonics=7, tol=1e-5)
    N = np.linspace(0, 1e4, 50)
    np.testing.assert_allclose(b.at(N)["wear"], a.at(2 * N)["wear"], atol=2e-4 * a.u0[0])
    np.testing.assert_allclose(b.normalised_time[-1], a.normalised_time[-1])


def test_adaptive_stepping_agrees_with_fine_fixed_stepping():
    model, omega = paper_model(fex=10), TWO_PI * 0.7
    fine = wear_stepping(model, omega, kw=1e-11, cycles=1.2e4, harmonics=7, fixed_step=5.0)
    N = np.linspace(0, 1.2e4, 60)
    for tol in (1e-2, 1e-3):
        adaptive = wear_stepping(model, omega, kw=1e-11, cycles=1.2e4, harmonics=7, tol=tol)
        err = np.abs(adaptive.at(N)["wear"] - fine.at(N)["wear"]).max() / fine.u0[0]
        assert err < 10 * tol + 2e-3  # local tolerance, accumulated; plus the Euler error of the reference
        assert adaptive.solves < fine.solves / 10


def test_stepping_dlft_converges_to_stepping_with_shooting_dynamics():
    model, omega = paper_model(fex=10), TWO_PI * 0.7
    exact = wear_stepping(model, omega, kw=1e-11, cycles=2e4, dynamics="shooting", tol=1e-4)
    n50 = exact.cycles_to(0.5)
    errors = [
        abs(
            wear_stepping(model, omega, kw=1e-11, cycles=2e4, harmonics=nh, tol=1e-4).cycles_to(0.5) / n50 - 1
        )
        for nh in (3, 7, 21, 41)
    ]
    assert errors[-1] < 0.03 and errors[-1] < errors[0]
    assert errors[3] < errors[1]


def test_huge_horizon_steps_are_bounded_by_u0_and_end_on_the_exact_path():
    """Horizon 1e30 at the loosest tolerances: no step wears more than MAX_INCREMENT u0, so the history and
    its end follow the exact load path (before the bound, tol = 0.1 jumped from 0.2 to 1.0 u0 in one step:
    8.4e-2 u0 off the exact path, measured)."""
    from fretwear.wear.stepping import MAX_INCREMENT

    model, omega = paper_model(fex=10), TWO_PI * 1.0
    exact = wear_exact(
        model, omega, kw=1e-11, cycles=1e30, harmonics=7, stop_fraction=0.99999, max_records=2000
    )
    u0 = exact.u0[0]
    histories = {
        tol: wear_stepping(model, omega, kw=1e-11, cycles=1e30, harmonics=7, tol=tol) for tol in (0.1, 0.5)
    }
    for hist in histories.values():
        w = hist.wear[:, 0]
        assert hist.converged and hist.status == "worn" and np.all(w <= u0) and np.all(np.diff(w) >= 0)
        assert np.diff(w).max() <= MAX_INCREMENT * u0 * (1 + 1e-9)
        w_exact = exact.at(hist.cycles)["wear"][:, 0]
        assert np.abs(w - w_exact).max() < 1e-2 * u0  # measured 3.7e-3
        assert abs(w[-1] - w_exact[-1]) < 1e-2 * u0  # the end: measured 1.9e-3
    # the horizon sets no step: the same history to 1e5 cycles
    short = wear_stepping(model, omega, kw=1e-11, cycles=1e5, harmonics=7, tol=0.1)
    np.testing.assert_array_equal(short.wear, histories[0.1].wear)


def test_two_scale_warning_for_the_papers_kw():
    with pytest.warns(RuntimeWarning, match="two-scale"):
        hist = wear_stepping(paper_model(fex=10), TWO_PI * 0.7, kw=1e-6, cycles=10, harmonics=3)
    assert hist.warnings and np.all(hist.wear[:, 0] < hist.u0[0])


def test_failed_periodic_solve_halves_the_step_then_stops_keeping_the_history(monkeypatch):
    calls = {"n": 0}
    original = wear_module.Dynamics._solve

    def flaky(self, problem):
        calls["n"] += 1
        sol = original(self, problem)
        return dataclasses.replace(sol, converged=False) if calls["n"] > 12 else sol

    monkeypatch.setattr(wear_module.Dynamics, "_solve", flaky)
    hist = wear_stepping(paper_model(fex=10), TWO_PI * 0.7, kw=1e-11, cycles=1e5, harmonics=7)
    assert not hist.converged and "failed" in hist.status
    assert len(hist.cycles) >= 2 and hist.cycles[-1] > 0  # what was computed is kept


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(kw=-1.0), "kw"),
        (dict(cycles=0.0), "cycles"),
        (dict(cycles=-5.0), "cycles"),
        (dict(tol=0.0), "tol"),
    ],
)
def test_bad_input_stepping(kwargs, match):
    with pytest.raises(ValueError, match=match):
        wear_stepping(paper_model(), 4.0, **kwargs)


@pytest.mark.parametrize("degree", [-1, 13, 2.5])
def test_bad_degree(degree):
    with pytest.raises(ValueError, match="degree"):
        wear_polynomial(paper_model(), 4.0, degree=degree)


def test_bad_u0_and_kn():
    with pytest.raises(ValueError, match="u0"):
        wear_stepping(paper_model(normal_load=0.0), 4.0)
    with pytest.raises(ValueError, match="kn"):
        paper_model(kn=0.0)


@pytest.mark.slow
def test_stepping_with_shooting_agrees_with_direct_time_integration():
    """The issue's reference case: cycles to 0.5 u0 and 0.9 u0 within 1 % (measured 0.01 % and 0.04 %)."""
    from fretwear.wear.time_integration import integrate_wear

    model, omega = paper_model(fex=10), TWO_PI * 0.7
    stepping = wear_stepping(model, omega, kw=1e-11, cycles=3e4, dynamics="shooting", tol=1e-4)
    direct = integrate_wear(model, omega, 3e4, kw=1e-11, tol=1e-3)
    for fraction in (0.5, 0.9):
        assert direct.cycles_to(fraction) == pytest.approx(stepping.cycles_to(fraction), rel=0.01)


# -- exact load-path integration -------------------------------------------------------------
def test_exact_path_is_the_zero_tolerance_limit_of_stepping():
    model, omega = paper_model(fex=10), TWO_PI * 0.7
    exact = wear_exact(model, omega, kw=1e-11, cycles=1e6, harmonics=7)
    fine = wear_stepping(model, omega, kw=1e-11, cycles=1e6, harmonics=7, tol=1e-6)
    assert exact.status == "worn" and exact.method == "exact"
    for fraction in (0.1, 0.5, 0.9, 0.98):
        assert exact.cycles_to(fraction) == pytest.approx(fine.cycles_to(fraction), rel=2e-4)
    N = np.linspace(0, exact.cycles[-1], 80)
    assert np.abs(exact.at(N)["wear"] - fine.at(N)["wear"]).max() < 2e-4 * exact.u0[0]
    assert np.all(np.diff(exact.wear[:, 0]) > 0) and np.all(exact.wear < exact.u0)


def test_exact_path_frozen_dynamics_and_horizon():
    model, omega = imposed_motion_model(), 0.45
    hist = wear_exact(model, omega, kw=KW_FROZEN, cycles=2e5, harmonics=21)
    assert hist.status == "horizon" and hist.cycles[-1] == pytest.approx(2e5)
    exact = frozen_exact(model, omega, KW_FROZEN, hist.cycles)
    assert np.abs(hist.wear[:, 0] - exact).max() < 1e-5 * model.friction[0].u0


def test_exact_path_stuck_and_applicability():
    hist = wear_exact(paper_model(fex=6), TWO_PI * 0.3, kw=1e-11, cycles=1e5)
    assert hist.status == "stuck" and np.all(hist.wear == 0)
    two = dataclasses.replace(paper_model(), friction=paper_model().friction * 2)
    with pytest.raises(ValueError, match="one friction contact"):
        wear_exact(two, 4.0)
