"""Frequency sweeps and branch continuation against independent single-point solves."""

import numpy as np
import pytest

from fretwear import jenkins_oscillator, paper_model, solve_periodic
from fretwear.hbm.continuation import continuation, sweep

TWO_PI = 2 * np.pi


@pytest.mark.parametrize("nh", [7, 21])
def test_sweep_agrees_with_cold_single_point_solves(nh):
    model = paper_model(fex=10)
    omegas = TWO_PI * np.linspace(0.3, 1.3, 26)
    sw = sweep(model, omegas, nh)
    assert sw.converged.all()
    for sol, w in zip(sw.solutions, omegas, strict=True):
        cold = solve_periodic(model, w, nh)
        np.testing.assert_allclose(sol.amplitude, cold.amplitude, rtol=1e-7, atol=1e-12)
        assert sol.residual < 1e-10


def test_sweep_computes_only_what_is_needed():
    sw = sweep(paper_model(fex=6), TWO_PI * np.linspace(0.2, 0.45, 6), 7)  # all stuck
    assert all(s.path == "linear-stuck" and s.iterations == 0 for s in sw.solutions)


def test_sweep_downwards_and_jenkins_element():
    omegas = np.linspace(2.5, 0.5, 41)  # the massless DOF of a Jenkins element, swept downwards
    sw = sweep(jenkins_oscillator(), omegas, 7)
    assert sw.converged.all()
    np.testing.assert_allclose(sw.omega, omegas)
    for s in sw.solutions:
        assert abs(s.input_work - s.viscous_dissipation - s.contact_work) <= 1e-6 * s.input_work


def test_sweep_rejects_bad_frequencies():
    with pytest.raises(ValueError, match="omegas"):
        sweep(paper_model(), [1.0, -2.0])
    with pytest.raises(ValueError, match="omegas"):
        sweep(paper_model(), [])


@pytest.mark.parametrize("fex", [10, 14])
def test_continuation_branch_is_a_chain_of_solutions(fex):
    model = paper_model(fex=fex)
    br = continuation(model, TWO_PI * 0.3, TWO_PI * 1.3, 7)
    assert br.converged
    assert br.omega[0] == pytest.approx(TWO_PI * 0.3) and br.omega[-1] == pytest.approx(TWO_PI * 1.3)
    assert all(s.residual < 1e-9 for s in br.solutions)
    # the branch is continuous: neighbours are close in amplitude
    amps = np.array([s.amplitude[0] for s in br.solutions])
    assert np.abs(np.diff(amps)).max() < 0.2 * amps.max()
    # with no fold, each branch point is the solution a single-point solve gives there
    for k in range(0, len(br.solutions), max(1, len(br.solutions) // 8)):
        ref = solve_periodic(model, br.omega[k], 7)
        np.testing.assert_allclose(br.solutions[k].amplitude, ref.amplitude, rtol=1e-7)


def test_continuation_never_loops_forever():
    model = jenkins_oscillator(k=0.1, c=0.001, force=0.12)
    br = continuation(model, 0.15, 1.4, 7, h_max=0.01, max_steps=300)
    assert len(br.solutions) <= 302
    assert br.converged or br.message
