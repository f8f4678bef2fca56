"""The exact wear method on the exact dynamics: the sliding table and its quadrature."""

import numpy as np
import pytest
from scipy.integrate import quad

import fretwear as fw
from fretwear.wear.sliding import _piece_integral, cached_solves, sliding_table

OMEGA = 2 * np.pi * 0.7


@pytest.mark.parametrize(("s1", "s2"), [(1.0, 1.0), (1.0, 3.0), (2.0, 0.5), (0.3, 0.6)])
def test_piece_integral_is_the_closed_form_of_the_quadrature(s1, s2):
    r1, r2 = 0.2, 0.6
    s = lambda r: s1 + (s2 - s1) * (r - r1) / (r2 - r1)  # noqa: E731
    if s1 == 0.3:  # s proportional to r: the a = 0 branch
        r1, r2, s = 0.3, 0.6, lambda r: r  # noqa: E731
        s1, s2 = 0.3, 0.6
    ref = quad(lambda r: 1 / (r * s(r)), r1, r2, epsabs=0, epsrel=1e-13)[0]
    assert _piece_integral(r1, r2, s1, s2) == pytest.approx(ref, rel=1e-12)


def test_table_interpolates_the_exact_sliding_distance_and_is_reused():
    model = fw.paper_model(fex=10)
    table = sliding_table(model, OMEGA, 0.5, 0.9, tol=1e-2)
    assert 0.9 < table.rho_stick < 2 and np.all(np.diff(table.rho) > 0)
    # the stick threshold is exact: stuck just above it, slipping just below
    above = fw.shooting(model.scaled(1.0 / (table.rho_stick * 1.001)), OMEGA)  # F_ex = 10 / rho
    below = fw.shooting(model.scaled(1.0 / (table.rho_stick * 0.99)), OMEGA)
    assert above.converged and above.sliding_distance[0] < 1e-12
    assert below.converged and below.sliding_distance[0] > 1e-9
    # interpolation meets its tolerance where it was checked, against direct solves
    for rho in (0.55, 0.7, 0.85):
        sol = fw.shooting(model.scaled(1.0 / rho), OMEGA)  # mu F_N = 10 N, F_ex = 10 / rho: r = 1 / rho
        s_hat = sol.sliding_distance[0] / (10.0 / rho)
        assert table.interpolate(rho)["s_hat"][0] == pytest.approx(s_hat, rel=2e-2)
    # another F_ex, mu, u0 in the same range of rho: no new solve
    before = cached_solves(model, OMEGA)
    other = fw.paper_model(fex=20, mu=0.7, normal_load=20)  # rho = 0.7 ... in range
    sliding_table(other, OMEGA, 0.5, 0.7, tol=1e-2)
    assert cached_solves(model, OMEGA) == before
