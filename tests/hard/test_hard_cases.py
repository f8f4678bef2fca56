"""Hard cases, each named after what makes it hard (issue 5).

Each must converge to the right answer (checked against an exact solution, a
limit or the shooting reference) or return a clean failure status: never NaN,
inf, a hang or an exception.
"""

import warnings

import numpy as np
import pytest

from fretwear import FrictionContact, Model, paper_model, solve_periodic
from fretwear.hbm.continuation import sweep
from fretwear.hbm.linear import linear_frf
from fretwear.hbm.periodic import Problem
from fretwear.time.shooting import shooting
from fretwear.wear.stepping import wear_stepping

TWO_PI = 2 * np.pi


def finite(sol) -> bool:
    return all(np.all(np.isfinite(a)) for a in (sol.displacement, sol.contact_force, sol.dof_harmonics))


def test_stuck_only_thanks_to_damping():
    """F_ex = 10 N at exactly 0.5 Hz: the stick force needed is 99.99997 % of mu F_N."""
    model, w = paper_model(fex=10), TWO_PI * 0.5
    assert 0.9999995 < Problem(model, w, 21).stick_ratio() < 1.0
    sol = solve_periodic(model, w, 21)
    assert sol.path == "linear-stuck" and sol.sliding_distance[0] == 0 and finite(sol)
    hist = wear_stepping(model, w, kw=1e-11, cycles=1e6, harmonics=21)
    assert hist.status == "stuck" and np.all(hist.wear == 0)


def test_gross_slip_at_a_free_resonance_with_q_500():
    """F_ex = 14 N, 0.48-0.52 Hz: x1 of order 60 m at the resonance of mass 1 sliding freely."""
    model = paper_model(fex=14)
    f = np.linspace(0.48, 0.52, 81)
    sw = sweep(model, TWO_PI * f, 7)
    assert sw.converged.all() and all(finite(s) for s in sw.solutions)
    amp = np.array([s.amplitude[0] for s in sw.solutions])
    k = int(np.argmax(amp))
    assert 0 < k < len(f) - 1  # the peak is inside the band, resolved by the sweep
    peak = shooting(model, TWO_PI * f[k])
    assert peak.amplitude[0] > 50
    assert amp[k] == pytest.approx(peak.amplitude[0], rel=0.02)


@pytest.mark.parametrize("f", [0.38, 0.40, 0.44])
def test_many_stick_slip_transitions_per_period(f):
    """F_ex = 14 N, 0.37-0.45 Hz: 4 to 8 stick/slip events per period; DLFT converges as Nh grows."""
    model, w = paper_model(fex=14), TWO_PI * f
    ref = shooting(model, w)
    assert ref.converged and 4 <= len(ref.events) <= 8
    errors = []
    for nh in (7, 41, 81):
        sol = solve_periodic(model, w, nh)
        assert sol.converged and finite(sol)
        errors.append(abs(sol.half_peak_to_peak[0] / ref.half_peak_to_peak[0] - 1))
    assert errors[2] < 0.02 and errors[2] <= errors[0]


@pytest.mark.slow
def test_slowest_convergence_in_the_band():
    """0.37 Hz, next to the change from 4 to 8 events: 15 % at Nh = 21, still converging (1.6 % at 121)."""
    model, w = paper_model(fex=14), TWO_PI * 0.37
    ref = shooting(model, w).half_peak_to_peak[0]
    errors = [abs(solve_periodic(model, w, nh).half_peak_to_peak[0] / ref - 1) for nh in (21, 81, 121)]
    assert errors[0] > errors[1] > errors[2] and errors[2] < 0.03


def test_full_stick_everywhere():
    model = paper_model(fex=0.5)
    freqs = np.linspace(0.1, 2.0, 40)
    for f in freqs:
        p = Problem(model, TWO_PI * f, 7, half_wave=False)
        R, J, *_ = p.evaluate(np.zeros(p.size))
        assert np.linalg.cond(J) < 1e8
        sol = solve_periodic(model, TWO_PI * f, 7, half_wave=False)
        assert sol.path == "linear-stuck" and abs(sol.dof_harmonics[:, 0]).max() < 1e-14  # symmetric
        np.testing.assert_allclose(
            sol.amplitude, np.abs(linear_frf(model, TWO_PI * f, "stuck")[0]), rtol=1e-9
        )


@pytest.mark.parametrize("model", [paper_model(mu=0.0), paper_model(normal_load=0.0)], ids=["mu=0", "FN=0"])
def test_open_contact(model):
    sol = solve_periodic(model, TWO_PI * 0.7, 21)
    assert sol.path == "linear-open" and finite(sol)
    np.testing.assert_allclose(sol.amplitude, np.abs(linear_frf(model, TWO_PI * 0.7, "open")[0]), rtol=1e-10)


def test_normal_load_vanishing_during_wear():
    """Worn to 0.99 u0 and beyond: F_N -> 0 smoothly, w never reaches u0, no NaN."""
    hist = wear_stepping(paper_model(fex=10), TWO_PI * 0.7, kw=1e-11, cycles=1e7, harmonics=7)
    assert hist.status == "worn" and np.all(hist.wear < hist.u0) and np.all(hist.normal_load > 0)
    worn = solve_periodic(paper_model(fex=10), TWO_PI * 0.7, 7, wear=[hist.u0[0] * (1 - 1e-9)])
    assert worn.converged and finite(worn)
    gone = solve_periodic(paper_model(fex=10), TWO_PI * 0.7, 7, wear=[2 * hist.u0[0]])  # clipped: open
    assert gone.path == "linear-open" and gone.normal_loads[0] == 0


def test_kw_so_large_the_contact_wears_through_within_one_step():
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        for step in (None, 1.0):
            hist = wear_stepping(
                paper_model(fex=10), TWO_PI * 0.7, kw=1e-5, cycles=50, harmonics=7, fixed_step=step
            )
            assert hist.warnings  # the two-scale assumption is flagged
            assert np.all(hist.wear < hist.u0) and np.all(hist.normal_load >= 0)
            assert np.all(np.isfinite(hist.wear)) and np.all(np.diff(hist.wear[:, 0]) >= 0)


def test_64_harmonics_with_many_samples():
    model, w = paper_model(fex=10), TWO_PI * 0.9
    sol = solve_periodic(model, w, 64, samples=2048)
    assert sol.converged and finite(sol) and sol.residual < 1e-10
    ref = shooting(model, w).half_peak_to_peak[0]
    assert abs(sol.half_peak_to_peak[0] / ref - 1) < 0.01


def test_damping_ratio_1e_minus_5():
    model, w = paper_model(fex=10, damping_ratio=1e-5), TWO_PI * 0.7
    sol = solve_periodic(model, w, 21)
    assert sol.converged and finite(sol)
    assert abs(sol.input_work - sol.viscous_dissipation - sol.contact_work) <= 1e-6 * sol.input_work
    ref = shooting(model, w).half_peak_to_peak[0]
    assert abs(sol.half_peak_to_peak[0] / ref - 1) < 0.1


@pytest.mark.parametrize("factor", [1e-3, 1e3])
def test_penalty_far_from_its_default(factor):
    model, w = paper_model(fex=10), TWO_PI * 0.9
    default = Problem(model, w, 21).eps
    sol = solve_periodic(model, w, 21, eps=default * factor)
    assert sol.converged and finite(sol)
    ref = shooting(model, w).half_peak_to_peak[0]
    assert abs(sol.half_peak_to_peak[0] / ref - 1) < 0.1  # within the truncation error at Nh = 21


@pytest.mark.parametrize("mass", [1e-3, 1e3])
@pytest.mark.parametrize("force", [1e-6, 1e4])
def test_units_scaled(mass, force):
    """Masses 1e-3 to 1e3 kg, forces 1e-6 to 1e4 N: the same dimensionless answer."""
    k1, k2 = np.pi**2 * mass, 7 * np.pi**2 * mass
    zeta = 1e-3
    model = Model(
        M=mass * np.eye(2), C=np.diag([2 * zeta * np.sqrt(k1 * mass), 2 * zeta * np.sqrt(k2 * mass)]),
        K=np.diag([k1, k2]), force_cos=[force, 0.0],
        friction=(FrictionContact.from_normal_load(0, 1, 1.0, force, kn=1e7 * force),),
    )  # fmt: skip
    base = solve_periodic(paper_model(fex=10), TWO_PI * 0.7, 7)
    sol = solve_periodic(model, TWO_PI * 0.7, 7)
    assert sol.converged and finite(sol)
    # x scales as F / k: the paper model has F = 10 N, unit mass
    np.testing.assert_allclose(sol.amplitude * (10 / force) * mass, base.amplitude, rtol=1e-6)
