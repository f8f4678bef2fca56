"""Harmonic basis: DFT pair, layout, extrema."""

import numpy as np
import pytest

from fretwear.hbm.harmonics import HarmonicBasis, amplitude, default_samples, extrema, full_synthesis


@pytest.mark.parametrize("half_wave", [False, True])
@pytest.mark.parametrize("nh,n", [(1, 4), (7, 128), (21, 512), (5, 11 + 1)])
def test_analysis_inverts_synthesis(nh, n, half_wave):
    b = HarmonicBasis(nh, n, half_wave)
    np.testing.assert_allclose(b.analysis @ b.synthesis, np.eye(b.size), atol=1e-12)


def test_half_wave_basis_keeps_odd_harmonics_on_half_a_period():
    b = HarmonicBasis(5, 32, half_wave=True)
    np.testing.assert_array_equal(b.orders, [1, 1, 3, 3, 5, 5])
    assert b.marched_samples == 16
    full = np.arange(11.0)
    np.testing.assert_array_equal(
        b.to_full(b.from_full(full)), np.where(np.isin(np.arange(11), [1, 2, 5, 6, 9, 10]), full, 0)
    )


def test_synthesis_of_a_known_signal():
    nh, n = 3, 64
    c = np.array([0.5, 1.0, -2.0, 0.0, 0.0, 0.25, 0.1])
    t = 2 * np.pi * np.arange(n) / n
    u = 0.5 + np.cos(t) - 2 * np.sin(t) + 0.25 * np.cos(3 * t) + 0.1 * np.sin(3 * t)
    np.testing.assert_allclose(full_synthesis(nh, n) @ c, u, atol=1e-13)
    assert amplitude(c) == pytest.approx(np.sqrt(5))


def test_extrema_are_exact_whatever_the_grid():
    rng = np.random.default_rng(0)
    c = rng.normal(size=(5, 2 * 9 + 1)) / (1 + np.repeat(np.arange(10), 2)[:-1])
    fine = c @ full_synthesis(9, 200_000).T
    coarse = c @ full_synthesis(9, 32).T
    hi, lo = extrema(c, coarse)
    # values of the series itself, at least as extreme as a 200 000-point grid, and within its resolution
    assert np.all(hi >= fine.max(axis=1) - 1e-13) and np.all(lo <= fine.min(axis=1) + 1e-13)
    np.testing.assert_allclose(hi, fine.max(axis=1), rtol=1e-8)
    np.testing.assert_allclose(lo, fine.min(axis=1), rtol=1e-8)
    assert np.all(hi >= coarse.max(axis=1)) and np.any(hi > coarse.max(axis=1) + 1e-6)


def test_extrema_leave_round_off_rows_at_their_samples():
    """Rows whose harmonics sum to at most ``atol`` keep their sampled extremes; the others are refined."""
    rng = np.random.default_rng(1)
    c = rng.normal(size=(4, 2 * 5 + 1))
    c[1:3] *= 1e-17  # the relative motion of a stuck contact: round-off
    coarse = c @ full_synthesis(5, 24).T
    hi, lo = extrema(c, coarse, atol=1e-12)
    exact_hi, exact_lo = extrema(c, coarse)
    np.testing.assert_array_equal(hi[1:3], coarse[1:3].max(axis=1))
    np.testing.assert_array_equal(lo[1:3], coarse[1:3].min(axis=1))
    np.testing.assert_array_equal(hi[[0, 3]], exact_hi[[0, 3]])
    np.testing.assert_array_equal(lo[[0, 3]], exact_lo[[0, 3]])
    assert np.all(hi[[0, 3]] > coarse[[0, 3]].max(axis=1) + 1e-6)  # refined beyond the grid
    assert np.all(np.abs(hi[1:3] - exact_hi[1:3]) < 1e-16)  # what the refinement would have moved


def test_sizes():
    assert default_samples(7) == 128 and default_samples(21) == 512 and default_samples(1) == 16
    with pytest.raises(ValueError, match="harmonics"):
        HarmonicBasis(0, 16)
    with pytest.raises(ValueError, match="samples"):
        HarmonicBasis(7, 14)
    with pytest.raises(ValueError, match="even"):
        HarmonicBasis(3, 15, half_wave=True)


@pytest.mark.parametrize("nh", [3, 9, 13])
def test_extrema_are_the_series_optima_to_round_off(nh):
    """Independent optimiser (bounded Brent on the series, around the best of a 20 000-point grid):
    the refined extremes agree to round-off, whatever way the Newton steps are computed."""
    from scipy.optimize import minimize_scalar

    rng = np.random.default_rng(nh)
    c = rng.normal(size=(6, 2 * nh + 1)) / (1 + np.repeat(np.arange(nh + 1), 2)[:-1]) ** 1.5
    hi, lo = extrema(c, c @ full_synthesis(nh, 8 * nh + 8).T)
    k, grid = np.arange(1, nh + 1), 2 * np.pi * np.arange(20_000) / 20_000
    for row, top, bottom in zip(c, hi, lo, strict=True):
        f = lambda t, row=row: row[0] + row[1::2] @ np.cos(k * t) + row[2::2] @ np.sin(k * t)  # noqa: E731
        values = np.array([f(t) for t in grid])
        for sign, got in ((-1.0, top), (1.0, bottom)):
            t0 = grid[np.argmin(sign * values)]
            best = minimize_scalar(lambda t, s=sign, f=f: s * f(t), bounds=(t0 - 1e-3, t0 + 1e-3),
                                   method="bounded", options={"xatol": 1e-12})  # fmt: skip
            assert got == pytest.approx(sign * best.fun, rel=1e-13, abs=1e-15)
