"""The sliding tables' interpolant (fretwear/wear/sliding.py); the tables themselves: test_exact.py."""

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from fretwear.wear.sliding import _evaluate, pchip


@pytest.mark.parametrize("knots", [2, 3, 5, 12])
def test_pchip_is_scipys_monotone_cubic(knots):
    """The compiled Fritsch-Carlson cubic equals scipy's PchipInterpolator (an independent code),
    flat secants and sign changes included, on every column of a 2-D ``y`` and on a 1-D one."""
    rng = np.random.default_rng(knots)
    for _ in range(50):
        x = np.cumsum(rng.random(knots) + 0.1)
        y = rng.standard_normal((knots, 3))
        y[min(1, knots - 1)] = y[0]  # a flat secant
        r = np.linspace(x[0], x[-1], 57)
        np.testing.assert_allclose(_evaluate(x, pchip(x, y), r), PchipInterpolator(x, y)(r), atol=1e-12)
        np.testing.assert_allclose(_evaluate(x, pchip(x, y[:, 0]), r), PchipInterpolator(x, y[:, 0])(r),
                                   atol=1e-12)  # fmt: skip
