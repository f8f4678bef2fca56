"""Tests of ``WearHistory.cycles_to``: the inverse of the history's cubic Hermite interpolant (``at``).

Oracle: bisection of the vectorised interpolant ``_hermite`` (what ``at`` evaluates) on the record
interval that crosses the fraction; the scalar bisection of ``cycles_to`` must find the same cycle
count to round-off, and ``at`` must give back the fraction there.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretwear.wear import WearHistory
from fretwear.wear.result import _hermite


def _history(cycles: np.ndarray, wear: np.ndarray, rate: np.ndarray, u0: float = 1e-6) -> WearHistory:
    k = len(cycles)
    col = lambda a: np.asarray(a, dtype=float).reshape(k, 1)  # noqa: E731
    zeros = np.zeros((k, 1))
    return WearHistory(2 * np.pi, "stepping", np.asarray(cycles, dtype=float), col(wear), zeros, col(rate),
                       zeros, zeros, zeros, zeros, np.array([u0]), np.array([1e7]), 1e-11)  # fmt: skip


def _reference(h: WearHistory, fraction: float) -> float:
    """Bisection on the vectorised interpolant, as ``cycles_to`` did before it ran in scalars."""
    w = h.wear[:, 0] / h.u0[0]
    k = np.searchsorted(w, fraction)
    if k == 0:
        return 0.0 if w[0] >= fraction else np.nan
    if k >= len(w):
        return np.nan
    lo, hi = h.cycles[k - 1], h.cycles[k]
    for _ in range(60):
        mid = 0.5 * (lo + hi)
        wm = _hermite(h.cycles, h.wear, h.rate, np.array([mid]))[0, 0]
        lo, hi = (mid, hi) if wm / h.u0[0] < fraction else (lo, mid)
    return 0.5 * (lo + hi)


def _saturating(n: int, seed: int, repeat: bool = False) -> WearHistory:
    """``w / u0 = 1 - exp(-N / tau)`` on an uneven grid (optionally a repeated record), exact rates."""
    rng = np.random.default_rng(seed)
    cycles = np.concatenate([[0.0], np.sort(rng.uniform(0, 5e5, n - 1))])
    if repeat:
        cycles = np.sort(np.concatenate([cycles, cycles[n // 2 : n // 2 + 1]]))
    tau, u0 = 1e5, 1e-6
    return _history(cycles, u0 * (1 - np.exp(-cycles / tau)), u0 * np.exp(-cycles / tau) / tau, u0)


@pytest.mark.parametrize("h", [_saturating(12, 0), _saturating(40, 1), _saturating(25, 2, repeat=True)])
def test_cycles_to_is_the_bisection_of_the_interpolant(h):
    for fraction in (0.0, 1e-3, 0.1, 0.37, 0.5, 0.9, 0.99, 0.999999, 1.5):
        got, ref = h.cycles_to(fraction), _reference(h, fraction)
        assert got == pytest.approx(ref, rel=1e-14, abs=0.0, nan_ok=True)
        if np.isfinite(got) and got > 0:
            assert h.at([got])["wear"][0, 0] / h.u0[0] == pytest.approx(fraction, rel=1e-12)


def test_cycles_to_ends_and_records():
    h = _saturating(12, 3)
    w = h.wear[:, 0] / h.u0[0]
    assert h.cycles_to(0.0) == 0.0  # reached at the start
    assert np.isnan(h.cycles_to(w[-1] * 1.01))  # not reached within the records
    assert h.cycles_to(w[5]) == pytest.approx(h.cycles[5], rel=1e-14)  # a record's own wear
