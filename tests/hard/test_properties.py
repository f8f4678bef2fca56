"""Property-based tests over random valid parameters (hypothesis).

The default run draws a dozen cases per property; ``pytest --slow`` draws
thousands (profile ``thorough`` in tests/conftest.py).
"""

import warnings

import numpy as np
from hypothesis import given
from hypothesis import strategies as st

from fretwear import paper_model, solve_periodic
from fretwear.wear.stepping import wear_stepping

TWO_PI = 2 * np.pi

cases = st.fixed_dictionaries(
    {
        "fex": st.floats(0.5, 20.0),
        "mu": st.floats(0.05, 2.0),
        "normal_load": st.floats(0.5, 20.0),
        "damping_ratio": st.floats(1e-4, 2e-2),
        "f": st.floats(0.15, 1.6),
        "nh": st.sampled_from([3, 7, 15]),
    }
)


@given(cases)
def test_converged_solutions_balance_energy_and_stay_finite(case):
    model = paper_model(case["fex"], case["mu"], case["normal_load"], damping_ratio=case["damping_ratio"])
    sol = solve_periodic(model, TWO_PI * case["f"], case["nh"])
    assert sol.converged, sol.message
    for a in (sol.displacement, sol.contact_force, sol.dof_harmonics):
        assert np.all(np.isfinite(a))
    scale = max(sol.input_work, sol.viscous_dissipation, 1e-300)
    assert abs(sol.input_work - sol.viscous_dissipation - sol.contact_work) <= 1e-6 * scale
    assert sol.sliding_distance[0] >= 0 and sol.contact_work >= -1e-6 * scale  # friction only dissipates
    assert np.all(np.abs(sol.contact_force) <= case["mu"] * case["normal_load"] * (1 + 1e-9))


@given(cases, st.floats(-12.0, -9.0))
def test_wear_stays_between_zero_and_u0_and_never_decreases(case, log_kw):
    model = paper_model(case["fex"], case["mu"], case["normal_load"], damping_ratio=case["damping_ratio"])
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # two-scale warnings for the largest kw
        hist = wear_stepping(model, TWO_PI * case["f"], kw=10**log_kw, cycles=2e4, harmonics=3, tol=1e-2)
    assert hist.converged, hist.status
    w = hist.wear[:, 0]
    assert np.all(np.isfinite(w)) and np.all(w >= 0) and np.all(w <= hist.u0[0])
    assert np.all(np.diff(w) >= 0) and np.all(hist.normal_load >= 0)
