"""Single-frequency HBM + DLFT solver against exact solutions, limits and invariants."""

import numpy as np
import pytest

from fretwear import FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model, solve_periodic
from fretwear.hbm.linear import linear_frf
from fretwear.hbm.periodic import Problem
from fretwear.time.shooting import shooting

TWO_PI = 2 * np.pi


def exact_stick_ratio(fex: float, f: float, zeta: float = 1e-3) -> float:
    """Required stick force over mu F_N for the paper model (mu F_N = 10 N), from the issue's formula."""
    w = TWO_PI * f
    k1, k2 = np.pi**2, 7 * np.pi**2
    c1, c2 = 2 * zeta * np.sqrt(k1), 2 * zeta * np.sqrt(k2)
    return fex * abs(k2 - w**2 + 1j * c2 * w) / abs(k1 + k2 - 2 * w**2 + 1j * (c1 + c2) * w) / 10.0


def coulomb_oscillator(ratio: float) -> Model:
    """1-DOF, m = k = 1, c = 0, friction to ground with slip force ``ratio`` under cos(omega t)."""
    return Model(
        M=[[1.0]], C=[[0.0]], K=[[1.0]], force_cos=[1.0],
        friction=(FrictionContact.from_normal_load(0, None, 1.0, ratio),),
    )  # fmt: skip


def den_hartog(beta: float, ratio: float) -> float:
    """Den Hartog's exact non-stop amplitude X / (F0 / k) for Coulomb friction (1931)."""
    theta = np.pi / beta
    V = np.sin(theta) / (beta * (1 + np.cos(theta)))
    return np.sqrt(1 / (1 - beta**2) ** 2 - (ratio * V) ** 2)


# -- limits -----------------------------------------------------------------------


@pytest.mark.parametrize("f", [0.3, 0.7, 0.9, 1.3])
def test_stuck_limit_equals_linear_stuck_frf(f):
    model = paper_model(fex=10, normal_load=1e6)
    sol = solve_periodic(model, TWO_PI * f, 7)
    U = linear_frf(model, TWO_PI * f, "stuck")[0]
    assert sol.path == "linear-stuck" and sol.converged
    np.testing.assert_allclose(sol.amplitude, np.abs(U), rtol=1e-8)
    np.testing.assert_allclose(sol.half_peak_to_peak, np.abs(U), rtol=1e-8)
    assert sol.sliding_distance[0] == 0.0


def test_stuck_limit_through_the_nonlinear_solver():
    """Forcing the DLFT iteration (no shortcut) on a stuck point gives the same exact answer."""
    model = paper_model(fex=10, normal_load=1e6)
    p = Problem(model, TWO_PI * 0.7, 7)
    R, J, *_ = p.evaluate(np.zeros(p.size))
    x = np.linalg.solve(J, -R)
    R2 = p.evaluate(x, jacobian=False)[0]
    assert np.abs(R2).max() < 1e-9 * p.residual_scale()
    assert np.abs(x).max() < 1e-12  # stuck: no relative motion


@pytest.mark.parametrize("f", [0.3, 0.6, 1.3])
def test_open_limit_equals_open_frf(f):
    model = paper_model(fex=10, normal_load=0.0)
    sol = solve_periodic(model, TWO_PI * f, 7)
    U = linear_frf(model, TWO_PI * f, "open")[0]
    assert sol.path == "linear-open"
    np.testing.assert_allclose(sol.amplitude, np.abs(U), rtol=1e-10)
    np.testing.assert_allclose(sol.contact_force, 0.0)


def test_zero_friction_coefficient_is_open():
    model = paper_model(fex=10, mu=0.0)
    sol = solve_periodic(model, TWO_PI * 0.8, 7)
    assert sol.path == "linear-open"
    np.testing.assert_allclose(sol.amplitude, np.abs(linear_frf(model, TWO_PI * 0.8, "open")[0]), rtol=1e-10)


def test_jenkins_massless_dof_limits():
    """Massless DOF: stuck = mass on k + kt, open = mass on k alone (the massless DOF follows)."""
    w = 1.3
    stuck = solve_periodic(jenkins_oscillator(slip_force=1e3), w, 7)
    assert stuck.path == "linear-stuck"
    np.testing.assert_allclose(stuck.amplitude[0], 0.1 / abs(2.0 - w**2 + 0.02j * w), rtol=1e-8)
    free = solve_periodic(jenkins_oscillator(slip_force=0.0), w, 7)
    np.testing.assert_allclose(free.amplitude[0], 0.1 / abs(1.0 - w**2 + 0.02j * w), rtol=1e-8)


# -- exact solutions ------------------------------------------------------------------


@pytest.mark.parametrize("beta", [0.6, 0.8, 1.5, 2.0])
@pytest.mark.parametrize("ratio", [0.1, 0.3])
def test_den_hartog_continuous_sliding(beta, ratio):
    """Gross slip of a Coulomb oscillator: error O(1/Nh), 1e-3 (P0/F0 = 0.1) to 1e-2 (0.3) at Nh = 21.

    The friction force jumps at each reversal; the DLFT stick/slip decision sees
    the Gibbs ripple of the truncated acceleration there, which shifts the
    reversal by O(T / Nh): the error halves when Nh doubles.
    """
    exact = den_hartog(beta, ratio)
    errors = []
    for nh in (21, 41, 81):
        sol = solve_periodic(coulomb_oscillator(ratio), beta, nh)
        assert sol.converged
        assert np.all(sol.state[0] != 0) or np.mean(sol.state[0] == 1) > 0.95  # (almost) always sliding
        errors.append(abs(sol.half_peak_to_peak[0] / exact - 1))
    assert errors[0] < 0.04 * ratio  # 1.2e-3 at P0/F0 = 0.1, 1.2e-2 at 0.3
    assert errors[2] < 0.4 * errors[0] + 2e-4  # converges like 1/Nh
    assert errors[2] < 3e-3


# -- stick threshold ------------------------------------------------------------------


@pytest.mark.parametrize("fex", [6.0, 10.0, 14.0])
def test_stick_threshold_of_the_paper_model(fex):
    freqs = np.linspace(0.2, 1.6, 57)
    ratios = np.array([exact_stick_ratio(fex, f) for f in freqs])
    inside = freqs[ratios < 0.98]
    outside = freqs[(ratios > 1.02)]
    for f in inside:
        sol = solve_periodic(paper_model(fex=fex), TWO_PI * f, 7)
        assert sol.path == "linear-stuck" and sol.sliding_distance[0] == 0.0 and not sol.slipping[0]
    for f in outside[:12]:
        sol = solve_periodic(paper_model(fex=fex), TWO_PI * f, 7)
        assert sol.converged and sol.slipping[0] and sol.sliding_distance[0] > 0


def test_stick_threshold_just_outside():
    # boundary near 1.118 Hz at fex = 10: find it and step 1 % beyond in load
    f = 1.0
    ratio = exact_stick_ratio(10.0, f)
    inside = solve_periodic(paper_model(fex=10 / ratio * 0.999), TWO_PI * f, 21)
    outside = solve_periodic(paper_model(fex=10 / ratio * 1.01), TWO_PI * f, 21)
    assert inside.sliding_distance[0] == 0 and inside.path == "linear-stuck"
    assert outside.converged and outside.sliding_distance[0] > 0


# -- invariants -------------------------------------------------------------------------


@pytest.mark.parametrize("lam", [0.1, 3.0])
@pytest.mark.parametrize("f", [0.6, 0.85])
def test_homogeneity(lam, f):
    base = solve_periodic(paper_model(fex=10), TWO_PI * f, 7)
    scaled = solve_periodic(paper_model(fex=10 * lam, normal_load=10 * lam), TWO_PI * f, 7)
    assert base.converged and scaled.converged
    np.testing.assert_allclose(scaled.amplitude, lam * base.amplitude, rtol=1e-8)
    np.testing.assert_allclose(scaled.half_peak_to_peak, lam * base.half_peak_to_peak, rtol=1e-8)
    np.testing.assert_allclose(scaled.sliding_distance, lam * base.sliding_distance, rtol=1e-8)


@pytest.mark.parametrize(
    "model,omega",
    [
        (paper_model(fex=6), TWO_PI * 0.95),
        (paper_model(fex=10), TWO_PI * 0.7),
        (paper_model(fex=14), TWO_PI * 0.42),
        (jenkins_oscillator(), 1.5),
        (coulomb_oscillator(0.3), 0.8),
    ],
)
@pytest.mark.parametrize("nh", [7, 21])
def test_energy_balance_per_period(model, omega, nh):
    sol = solve_periodic(model, omega, nh)
    assert sol.converged
    balance = sol.input_work - sol.viscous_dissipation - sol.contact_work
    assert abs(balance) <= 1e-6 * sol.input_work
    assert sol.contact_work > 0
    # the time-domain friction dissipation tends to the Galerkin contact work
    assert abs(sol.friction_energy.sum() / sol.contact_work - 1) < 0.5


def test_half_wave_symmetry_even_harmonics_vanish():
    model = paper_model(fex=10)
    full = solve_periodic(model, TWO_PI * 0.7, 7, half_wave=False)
    half = solve_periodic(model, TWO_PI * 0.7, 7)
    assert full.converged and not full.half_wave and half.half_wave
    scale = np.abs(full.dof_harmonics).max()
    even = full.dof_harmonics[:, [0, 3, 4, 7, 8, 11, 12]]
    assert np.abs(even).max() < 1e-9 * scale
    np.testing.assert_allclose(half.dof_harmonics, full.dof_harmonics, atol=1e-9 * scale)
    u = full.displacement
    np.testing.assert_allclose(u[:, full.samples // 2 :], -u[:, : full.samples // 2], atol=1e-9 * scale)


def test_full_stick_is_symmetric_with_a_regular_jacobian():
    model = paper_model(fex=2)  # full stick everywhere here
    p = Problem(model, TWO_PI * 0.7, 7, half_wave=False)
    x = np.zeros(p.size)
    x[0] = 0.3  # an arbitrary frozen offset: also a valid stuck state, but not the symmetric one
    R, J, *_ = p.evaluate(x)
    assert np.linalg.cond(J) < 1e6
    x = x + np.linalg.solve(J, -R)
    R, J, _, lam, _, state = p.evaluate(x)
    assert np.abs(R).max() < 1e-10 and np.all(state == 0)
    assert abs(x[0]) < 1e-12 and abs(lam.mean()) < 1e-10  # zero mean offset and mean stick force


# -- accuracy and penalty --------------------------------------------------------------------


@pytest.mark.slow
def test_truncation_error_against_shooting():
    """HBM with rigid Coulomb stick converges slowly in Nh; shooting is exact (docs: periodic solutions)."""
    model = paper_model(fex=10)
    for f in (0.6, 0.9):
        ref = shooting(model, TWO_PI * f)
        errors = [
            abs(solve_periodic(model, TWO_PI * f, nh).half_peak_to_peak[0] / ref.half_peak_to_peak[0] - 1)
            for nh in (7, 21, 81)
        ]
        assert errors[0] > errors[1] > errors[2]
        assert errors[1] < 0.05 and errors[2] < 0.01


@pytest.mark.slow
def test_penalty_changes_the_answer_only_within_the_truncation_error():
    model, w = paper_model(fex=10), TWO_PI * 0.9
    ref = shooting(model, w).half_peak_to_peak[0]
    spread = []
    for nh in (7, 21, 41):
        default = Problem(model, w, nh).eps
        values = [
            solve_periodic(model, w, nh, eps=default * k).half_peak_to_peak[0] for k in (0.1, 1.0, 10.0)
        ]
        spread.append((max(values) - min(values)) / ref)
        assert max(abs(v / ref - 1) for v in values) < 0.2 * 21 / nh
    assert spread[2] < spread[0]


# -- cold-start reliability ------------------------------------------------------------------


@pytest.mark.parametrize("nh", [7, 21, 41])
def test_cold_solves_on_a_grid(nh):
    freqs = np.linspace(0.3, 1.3, 11 if nh == 41 else 21)
    for fex in (6, 10, 14):
        model = paper_model(fex=fex)
        for f in freqs:
            sol = solve_periodic(model, TWO_PI * f, nh)
            assert sol.converged, (fex, f, sol.message)
            assert sol.residual < 1e-10
            assert np.all(np.isfinite(sol.displacement))


# -- unilateral contact ------------------------------------------------------------------------


def oscillator_with_stop(gap: float, force: float = 1.0) -> Model:
    return Model(
        M=[[1.0]], C=[[0.05]], K=[[1.0]], force_cos=[force], normal=(NormalContact(0, None, gap),)
    )  # fmt: skip


def test_unilateral_contact_far_away_is_linear():
    model = oscillator_with_stop(gap=100.0)
    sol = solve_periodic(model, 0.7, 7)
    assert sol.converged and not sol.half_wave
    np.testing.assert_allclose(sol.amplitude[0], 1 / abs(1 - 0.49 + 0.05j * 0.7), rtol=1e-9)
    assert np.all(sol.contact_force == 0)


def test_unilateral_contact_limits_the_motion_and_balances_energy():
    model = oscillator_with_stop(gap=0.5)
    sol = solve_periodic(model, 0.9, 21)
    assert sol.converged
    assert np.all(sol.contact_force >= -1e-12)
    assert sol.displacement.max() < 0.5 + 0.05  # the stop holds, up to the truncation ripple
    assert np.any(sol.state[0] == 2) and np.any(sol.contact_force > 0)
    assert abs(sol.input_work - sol.viscous_dissipation - sol.contact_work) <= 1e-6 * sol.input_work


def test_preloaded_unilateral_contact_stays_closed_under_small_forcing():
    model = Model(
        M=[[1.0]], C=[[0.05]], K=[[1.0]], force_cos=[0.1], normal=(NormalContact(0, None, -1.0),)
    )  # fmt: skip
    sol = solve_periodic(model, 0.7, 7)
    assert sol.converged
    np.testing.assert_allclose(sol.displacement, -1.0, atol=1e-9)  # held at the stop
    np.testing.assert_allclose(sol.contact_force.mean(), 1.0, rtol=1e-9)  # the preload force k * 1


# -- bad input ---------------------------------------------------------------------------------


@pytest.mark.parametrize(
    "kwargs,match",
    [
        (dict(omega=0.0), "omega"),
        (dict(omega=-1.0), "omega"),
        (dict(harmonics=0), "harmonics"),
        (dict(samples=8, harmonics=7), "samples"),
        (dict(eps=-1.0), "eps"),
        (dict(wear=[-1e-7]), "wear"),
        (dict(wear=[0.0, 0.0]), "wear"),
    ],
)
def test_bad_input(kwargs, match):
    args = dict(model=paper_model(), omega=4.0, harmonics=7)
    args.update(kwargs)
    with pytest.raises(ValueError, match=match):
        solve_periodic(**args)


def test_half_wave_requested_on_an_asymmetric_model():
    with pytest.raises(ValueError, match="half_wave"):
        solve_periodic(oscillator_with_stop(0.5), 0.7, 7, half_wave=True)
