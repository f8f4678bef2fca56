"""Pseudo-arc-length tracking on curves with known folds."""

import numpy as np

from fretwear.hbm.arclength import track


def cubic(x, p):
    """R = x^3 - x - p: an S-curve in p with folds at p = -+2 / (3 sqrt 3)."""
    R = np.array([x[0] ** 3 - x[0] - p])
    return R, np.array([[3 * x[0] ** 2 - 1]]), np.array([-1.0])


def test_track_passes_two_folds_of_an_s_curve():
    # start on the lower branch at p = -1 (x = -1.3247...), go to p = +1
    x0 = np.array([np.real(np.roots([1, 0, -1, 1])).min()])
    res = track(cubic, x0, -1.0, 1.0, x_scale=1.0, tol=1e-12, h_max=0.1, record=True)
    assert res.converged and res.p == 1.0
    assert abs(res.x[0] ** 3 - res.x[0] - 1.0) < 1e-12
    # the upper branch root at p = 1, not the continuation of the lower one beyond its fold
    np.testing.assert_allclose(res.x[0], np.real(np.roots([1, 0, -1, -1])).max(), rtol=1e-10)
    p = np.array([q[1] for q in res.points])
    turns = np.flatnonzero(np.diff(np.sign(np.diff(p))) != 0)
    assert len(turns) == 2  # p increases, decreases, increases: both folds passed
    fold = 2 / (3 * np.sqrt(3))
    np.testing.assert_allclose(sorted([p[turns[0] + 1], p[turns[1] + 1]]), [-fold, fold], atol=0.02)


def test_track_lands_exactly_and_stops_on_budget():
    res = track(cubic, np.array([2.0]), 6.0, 24.0, x_scale=1.0, tol=1e-12)
    assert res.converged and res.p == 24.0 and abs(res.x[0] - 3.0) < 1e-10
    res = track(cubic, np.array([2.0]), 6.0, 24.0, x_scale=1.0, tol=1e-12, h_max=1e-3, max_steps=5)
    assert not res.converged and res.steps == 5 and "5 steps" in res.message


def test_track_reports_failure_instead_of_looping():
    def nowhere(x, p):  # no solution curve beyond p = 0: R = x^2 + p
        return np.array([x[0] ** 2 + p]), np.array([[2 * x[0]]]), np.array([1.0])

    res = track(nowhere, np.array([1.0]), -1.0, 1.0, x_scale=1.0, tol=1e-12, max_steps=200)
    # the curve x^2 = -p turns back at p = 0 and never reaches p = 1
    assert not res.converged and res.steps <= 200
