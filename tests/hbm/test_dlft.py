"""DLFT residual: exact derivatives and the piecewise-linear structure."""

import numpy as np
import pytest

from fretwear import FrictionContact, Model, NormalContact, paper_model
from fretwear.hbm import dlft
from fretwear.hbm.continuation import _frequency_evaluate
from fretwear.hbm.periodic import Problem

TWO_PI = 2 * np.pi


def two_contact_model():
    """3 DOFs, friction between 1-2 and 2-ground, a unilateral stop on DOF 3 (no half-wave symmetry)."""
    K = np.array([[3.0, -1.0, 0.0], [-1.0, 2.5, -1.0], [0.0, -1.0, 2.0]])
    return Model(
        M=np.diag([1.0, 0.5, 2.0]), C=0.02 * K, K=K, force_cos=[1.0, 0.0, 0.3], force_static=[0.0, 0.0, -0.1],
        friction=(
            FrictionContact.from_normal_load(0, 1, 0.5, 1.0),
            FrictionContact.from_normal_load(1, None, 0.3, 1.0),
        ),
        normal=(NormalContact(2, None, 0.2),),
    )  # fmt: skip


@pytest.mark.parametrize(
    "problem",
    [
        Problem(paper_model(), TWO_PI * 0.7, 5),
        Problem(paper_model(), TWO_PI * 0.7, 5, half_wave=False),
        Problem(two_contact_model(), 1.1, 4),
    ],
    ids=["half-wave", "full", "three-contacts"],
)
def test_jacobian_matches_finite_differences(problem):
    rng = np.random.default_rng(3)
    checked_mixed = 0
    for _ in range(20):
        x = rng.normal(size=problem.size) * rng.choice([0.03, 0.3, 1.0])
        R, J, _, _, _, state = problem.evaluate(x)
        checked_mixed += np.any(state == dlft.STICK) and np.any(state != dlft.STICK)
        h = 1e-7
        Jfd = np.empty_like(J)
        for j in range(problem.size):
            e = np.zeros(problem.size)
            e[j] = h
            Jfd[:, j] = (problem.evaluate(x + e, False)[0] - problem.evaluate(x - e, False)[0]) / (2 * h)
        # piecewise linear: exact unless a sample switches within +-h (then one column is off)
        bad = np.abs(J - Jfd).max(axis=0) > 1e-5 * np.abs(J).max()
        assert bad.sum() <= 1
    assert checked_mixed >= 5  # the draws exercise stick and slip together


def test_frequency_derivative_matches_finite_differences():
    model = paper_model(fex=10)
    settings = dict(harmonics=5, samples=None, wear=None, half_wave=None)
    evaluate = _frequency_evaluate(model, settings, None)
    x = np.random.default_rng(0).normal(size=Problem(model, 4.0, 5).size) * 0.1
    w, h = 4.0, 1e-6
    _, _, dR = evaluate(x, w)
    fd = (evaluate(x, w + h)[0] - evaluate(x, w - h)[0]) / (2 * h)
    np.testing.assert_allclose(dR, fd, rtol=1e-5, atol=1e-6 * np.abs(fd).max())


@pytest.mark.parametrize(
    "problem", [Problem(paper_model(), TWO_PI * 0.8, 7), Problem(two_contact_model(), 1.1, 4)]
)
def test_boundary_distance_is_the_first_state_change(problem):
    rng = np.random.default_rng(1)
    H = problem.basis.size
    eps_diag = np.repeat(problem.eps, H)
    for _ in range(40):
        x, d = rng.normal(size=problem.size) * 0.3, rng.normal(size=problem.size) * 0.3
        lu = problem.F - problem.Z @ x + eps_diag * x
        dlu = -problem.Z @ d + eps_diag * d
        tau = dlft.boundary_distance(
            lu, dlu, problem.eps, problem.kinds, problem.limits, problem.basis.synthesis,
            problem.basis.half_wave, 10.0,
        )  # fmt: skip
        states = [problem.evaluate(x + t * d, False)[5] for t in (1e-9 * tau, 0.5 * tau, (1 - 1e-9) * tau)]
        assert np.array_equal(states[0], states[1]) and np.array_equal(states[0], states[2])
        if tau < 10.0:  # just beyond it, some sample has changed
            assert not np.array_equal(states[0], problem.evaluate(x + 1.001 * tau * d, False)[5])
