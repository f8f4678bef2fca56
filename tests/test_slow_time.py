"""Tests of fretwear.slow_time: the one adaptive slow-time integrator of Archard's law.

Oracles: a contact whose sliding distance does not depend on the load wears as
``w = u0 (1 - exp(-a N))`` (``dw/dN = a (u0 - w)``), and by the explicit
per-period rule as ``u0 (1 - (1 - a h)^n)``; the step bound and the horizon
independence are invariants of the records.
"""

import numpy as np
import pytest

from fretwear.slow_time import integrate

U0, A = 1e-6, 1e-3  # interference (m), wear rate constant (1/cycle)


def run(cycles, **options):
    records = []

    def rate(w, _c, _h):
        return A * (U0 - w), None

    def accept(N, w, _k, _payload):
        records.append((N, w.copy()))
        return None

    w0 = np.zeros(1)
    options = {"scale": U0, "atol": 1e-6 * U0, "project": lambda w: np.clip(w, 0.0, U0), **options}
    status, ok = integrate(rate, w0, A * (U0 - w0), cycles, accept, **options)
    N = np.array([0.0] + [r[0] for r in records])
    w = np.array([0.0] + [r[1][0] for r in records])
    return status, ok, N, w


def test_the_adaptive_pair_follows_the_exponential_approach_within_its_tolerance():
    status, ok, N, w = run(1e4)
    assert (status, ok) == ("horizon", True) and N[-1] == pytest.approx(1e4)
    exact = U0 * (1 - np.exp(-A * N))
    assert np.max(np.abs(w - exact)) < 1e-5 * U0  # local errors of 1e-6 u0, a few hundred steps


def test_the_fixed_step_is_the_papers_per_period_rule():
    status, ok, N, w = run(50, fixed_step=1.0)
    n = np.arange(51)
    np.testing.assert_allclose(N, n)
    np.testing.assert_allclose(w, U0 * (1 - (1 - A) ** n), rtol=1e-12, atol=1e-30)


def test_no_step_wears_more_than_its_bound_and_the_horizon_sets_no_scale():
    """A loose tolerance: the increment bound, not the error, limits the steps; a horizon of 1e30 takes
    the same steps as one of 1e4 up to 1e4 (a longer horizon only adds steps at the end)."""
    _, _, N, w = run(1e4, atol=0.5 * U0, max_increment=0.05)
    assert np.max(np.diff(w)) <= 0.05 * U0 * (1 + 1e-12)
    _, ok, N_long, w_long = run(1e30, atol=0.5 * U0, max_increment=0.05)
    assert ok and w_long[-1] <= U0
    k = len(N) - 1  # the last step of the short run is cut at its horizon
    np.testing.assert_array_equal(N_long[:k], N[:k])
    np.testing.assert_array_equal(w_long[:k], w[:k])


def test_a_failing_solve_retries_a_bounded_number_of_times_and_says_where():
    calls = []

    def rate(w, _c, _h):
        calls.append(w[0])
        return (None, "no equilibrium") if w[0] > 0.5 * U0 else (A * (U0 - w), None)

    status, ok = integrate(rate, np.zeros(1), np.array([A * U0]), 1e6, lambda *a: None, scale=U0,
                           atol=1e-3 * U0, max_retries=5)  # fmt: skip
    assert not ok and status.startswith("periodic solve failed near N = ") and "no equilibrium" in status
    assert len(calls) < 2000


def test_accept_ends_the_integration_with_its_status():
    def accept(N, w, _k, _payload):
        return "worn" if w[0] >= 0.5 * U0 else None

    status, ok = integrate(lambda w, c, h: (A * (U0 - w), None), np.zeros(1), np.array([A * U0]), 1e9,
                           accept, scale=U0, atol=1e-4 * U0)  # fmt: skip
    assert (status, ok) == ("worn", True)
