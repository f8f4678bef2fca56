"""Nodal Archard wear of the benchmark interface with pressure redistribution."""

import numpy as np
import pytest

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.wear import MAX_INCREMENT, frf, wear_interface, wear_scale
from fretwear.model import craig_bampton

F_HZ, NH, KW = 50.0, 5, 1e-14


def _problem(**changes):
    model = cylinder_on_flat(contact_nodes=16, **changes)
    cond = ContactCondensation(craig_bampton(model, NH * F_HZ))
    return model, InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH)


@pytest.fixture(scope="module")
def partial():
    model, prob = _problem(q_ratio=0.5)
    return model, wear_interface(prob, KW, 3e5, rtol=3e-2)


@pytest.fixture(scope="module")
def gross():
    model, prob = _problem(window=3.0, arm_stiffness=2e10, drive_displacement=2e-5)
    return model, wear_interface(prob, KW, 3e4, rtol=3e-2)


def test_partial_slip_wears_only_the_slip_annulus(partial):
    model, h = partial
    assert h.converged and h.cycles[-1] == pytest.approx(3e5)
    a = model.info["hertz_half_width"]
    c = a * np.sqrt(1 - 0.5)
    x, w = h.position, h.wear[-1]
    assert w.max() > 0
    assert np.all(w[np.abs(x) < 0.9 * c] <= 1e-3 * w.max())  # the stick zone stays unworn
    annulus = (np.abs(x) > c) & (np.abs(x) < a)
    assert annulus.sum() >= 4 and np.all(w[annulus] > 0.1 * w.max())
    # wear moves the load into the stick zone: its pressure rises, the annulus' falls
    p0, p1 = h.pressure[0], h.pressure[-1]
    assert np.all(p1[np.abs(x) < 0.9 * c] > p0[np.abs(x) < 0.9 * c])
    assert np.all(p1[annulus] < p0[annulus])


def test_pressure_integral_is_the_normal_load_at_every_step(partial, gross):
    for model, h in (partial, gross):
        assert np.abs(h.normal_force_sum / model.info["normal_load"] - 1).max() < 1e-6


def test_gross_slip_widens_the_scar_and_lowers_the_peak(gross):
    model, h = gross
    assert h.converged
    assert np.all(h.stick_fraction[0] < 1)  # every loaded pair slips in each cycle
    peak = h.peak_pressure.max(axis=1)
    assert np.all(np.diff(peak) < 0) and peak[-1] < 0.6 * peak[0]
    width = h.contact_width
    assert np.all(np.diff(width) >= 0) and width[-1] > 1.5 * width[0]
    assert width[-1] < 0.95 * 2 * 3.0 * model.info["hertz_half_width"]  # still inside the contact window


def test_archard_consistency(gross):
    """Worn area per cycle = K_w sum_i p_i s_i dx_i = (K_w / mu) friction work; it sums to the worn area."""
    model, h = gross
    N, A, rate = h.cycles, h.worn_area, h.worn_area_rate
    integrated = np.concatenate([[0.0], np.cumsum(0.5 * (rate[1:] + rate[:-1]) * np.diff(N))])
    assert np.abs(A - integrated).max() <= 2e-2 * A[-1]
    mu = model.info["mu"]
    for k, sol in enumerate(h.solutions):
        # nearly constant normal force (identical materials): int p ds = p s per pair; a lightly loaded pair
        # just come into contact at the scar's edge sees its force vary by a few % over the cycle, hence
        # the absolute part (measured differences: 2e-8 of the largest rate)
        r_k = h.wear_rate[k]
        assert np.allclose(KW * sol.mean_pressure * sol.slip_distance, r_k, rtol=1e-6, atol=1e-6 * r_k.max())
        # the contact work from the harmonics, independent of the march's slip accounting
        assert rate[k] == pytest.approx(KW / mu * sol.contact_work, rel=2e-3)


def test_saturated_scar_does_not_depend_on_the_horizon():
    """Partial slip: the annulus unloads and wear stops, so horizons 1e9 and 1e30 end on the same profile.

    Before the step control was tied to the wear scale, 1e16 cycles ended 600x deeper (2.3e-4 m against
    3.8e-7 m) and 1e30 cycles jumped to N = 5e22 in one step, 2.3e10 m deep.
    """
    _, prob = _problem(q_ratio=0.5)
    short = wear_interface(prob, KW, 1e9)
    long = wear_interface(prob, KW, 1e30)
    assert short.converged and long.converged and long.cycles[-1] == pytest.approx(1e30)
    w9, w30 = short.wear[-1], long.wear[-1]
    assert np.abs(w30 - w9).max() <= 1e-6 * w9.max()
    # saturated: the depth is of the order of the wear scale (measured 1.2 S), not of the horizon
    scale = wear_scale(short.solutions[0])
    assert 0.5 * scale < w9.max() < 3 * scale
    # no step wears any pair by more than MAX_INCREMENT S (plus the error-controlled part)
    assert np.abs(np.diff(long.wear, axis=0)).max() <= 1.5 * MAX_INCREMENT * scale


def test_wear_history_input_checks():
    _, prob = _problem(q_ratio=0.5)
    with pytest.raises(ValueError, match="kw must be"):
        wear_interface(prob, -1.0, 10.0)
    with pytest.raises(ValueError, match="cycles must be"):
        wear_interface(prob, KW, 0.0)
    with pytest.raises(ValueError, match="max_increment must be"):
        wear_interface(prob, KW, 10.0, max_increment=0.0)


def test_frf_before_and_after_wear(gross):
    model, h = gross
    cond = h.solutions[0].problem.condensation

    def make(omega):
        return InterfaceProblem(cond, omega, harmonics=NH)

    freqs = np.array([40.0, 50.0, 60.0])
    before, ok0 = frf(make, freqs, "pad_x")
    after, ok1 = frf(make, freqs, "pad_x", wear=h.wear[-1])
    assert ok0.all() and ok1.all()
    direct = solve_interface(make(2 * np.pi * 50.0)).dof_harmonics[model.dof("pad_x")]
    assert before[1] == pytest.approx(np.hypot(direct[1], direct[2]), rel=1e-9)
    # the worn, wider and flatter contact lowers the holder's amplitude: by 6.06e-4 at 40 Hz with a converged
    # history (rtol = 1e-5), far above the solves' 1e-10
    assert np.all(after < before) and np.abs(after / before - 1).max() > 3e-4
