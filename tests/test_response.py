"""The periodic-solution protocol: every solver's result exposes the same attributes."""

import numpy as np

import fretwear as fw
from fretwear.response import RESPONSE_ATTRIBUTES, PeriodicResponse


def check_protocol(sol) -> None:
    assert isinstance(sol, PeriodicResponse)
    for name in RESPONSE_ATTRIBUTES:
        value = getattr(sol, name)
        if isinstance(value, (float, np.ndarray)) and np.asarray(value).dtype.kind == "f":
            assert np.all(np.isfinite(value)), name


def test_harmonic_balance_solutions_follow_the_protocol():
    for fex in (6.0, 14.0):  # stuck (linear path) and slipping (DLFT)
        sol = fw.solve_periodic(fw.paper_model(fex=fex), 2 * np.pi * 0.7, 7)
        check_protocol(sol)
        assert sol.floquet_multipliers is None and sol.frequency == 0.7


def test_the_public_api_example_of_the_readme_runs():
    """The README's first library example, line for line."""
    import fretwear as fw

    model = fw.paper_model(fex=10, mu=1.0, normal_load=10.0)  # the paper's 2-DOF example (N)
    sol = fw.solve_periodic(model, 2 * np.pi * 0.7, harmonics=21)  # HBM + DLFT at 0.7 Hz
    frf = fw.sweep(model, 2 * np.pi * np.linspace(0.3, 1.3, 51), harmonics=7)
    hist = fw.wear_history(model, 2 * np.pi * 0.7, kw=1e-11, cycles=2e4)  # exact load path
    print(sol.amplitude, hist.cycles_to(0.5), max(s.amplitude[0] for s in frf.solutions))
    assert sol.converged and all(s.converged for s in frf.solutions)
    assert hist.method == "exact" and 3e3 < hist.cycles_to(0.5) < 1e4
