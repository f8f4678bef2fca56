"""The sliding tables' interpolant (fretwear/wear/sliding.py); the tables themselves: test_exact.py."""

import numpy as np
import pytest
from scipy.interpolate import PchipInterpolator

from fretwear.wear.sliding import _evaluate, kinks, pchip


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


def test_a_kink_piece_is_the_line_and_leaves_its_neighbours_alone():
    """With ``breaks``, each smooth run of knots is scipy's PCHIP of that run alone (one-sided end
    slopes), and the piece across the kink is the straight line: a kink bends no piece next to it."""
    rng = np.random.default_rng(7)
    for _ in range(50):
        x = np.cumsum(rng.random(11) + 0.1)
        y = rng.standard_normal((11, 2))
        i = int(rng.integers(0, 10))  # the kink's piece
        breaks = np.zeros(10, dtype=bool)
        breaks[i] = True
        c = pchip(x, y, breaks)
        for lo, hi in ((0, i), (i + 1, 10)):  # the runs of knots on either side
            if hi > lo:
                r, run = np.linspace(x[lo], x[hi], 23), slice(lo, hi + 1)
                expected = PchipInterpolator(x[run], y[run])(r)
                np.testing.assert_allclose(_evaluate(x, c, r), expected, atol=1e-12)
        r = np.linspace(x[i], x[i + 1], 9)
        line = y[i] + (r - x[i])[:, None] * (y[i + 1] - y[i]) / (x[i + 1] - x[i])
        np.testing.assert_allclose(_evaluate(x, c, r), line, atol=1e-12)


def test_kinks_flag_the_intervals_between_different_events():
    assert kinks(np.array([2, 2, 6, 6, 4]), 5).tolist() == [False, True, False, True]
    assert kinks(np.array([2, 6]), 3).tolist() == [False, True]  # a first knot at rho = 0 (no events)
    assert kinks(None, 4).tolist() == [False] * 3
