"""Tests of ``WearHistory.rescaled``: a history under another Archard coefficient, by Archard's law alone.

Oracle: the same method run directly at the other ``K_w`` (the exact load path on DLFT, whose records
are placed in wear): every record, rate, response and warning must agree to round-off.
"""

from __future__ import annotations

import warnings

import numpy as np
import pytest

import fretwear as fw

FIELDS = ("cycles", "wear", "normal_load", "rate", "sliding_distance", "amplitude", "half_peak_to_peak",
          "relative_half_peak_to_peak")  # fmt: skip


def _exact_dlft(f_hz: float, kw: float, cycles: float = 1e5) -> fw.WearHistory:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)  # the two-scale warning at a large K_w
        return fw.wear_history(fw.paper_model(fex=10.0), 2 * np.pi * f_hz, "exact", kw=kw, cycles=cycles,
                               dynamics="dlft", harmonics=5)  # fmt: skip


@pytest.mark.parametrize(("f_hz", "status"), [(0.55, "worn"), (1.05, "worn"), (1.25, "stuck")])
@pytest.mark.parametrize("kw", [2.7e-11, 4e-12, 1e-4])
def test_a_rescaled_history_is_the_history_computed_at_that_kw(f_hz, status, kw):
    base = _exact_dlft(f_hz, 1e-11)
    assert base.status == status
    direct = _exact_dlft(f_hz, kw, cycles=1e9)  # a horizon it does not reach at any of these K_w
    base = _exact_dlft(f_hz, 1e-11, cycles=1e9)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        got = base.rescaled(kw)
    assert (got.status, got.kw, got.warnings) == (direct.status, direct.kw, direct.warnings)
    assert bool(got.warnings) == (kw == 1e-4 and status == "worn")  # two-scale: from K_w, not the base
    for name in FIELDS:
        want = getattr(direct, name)
        np.testing.assert_allclose(getattr(got, name), want, rtol=1e-13, atol=1e-13 * np.abs(want).max(),
                                   err_msg=name)  # fmt: skip


def test_a_history_cut_by_its_horizon_does_not_rescale():
    cut = _exact_dlft(0.55, 1e-11, cycles=100.0)
    assert cut.status == "horizon"
    with pytest.raises(ValueError, match="ended 'horizon'"):
        cut.rescaled(2e-11)
    with pytest.raises(ValueError, match="kw must be > 0"):
        _exact_dlft(0.55, 1e-11).rescaled(0.0)


def test_a_history_whose_scaled_end_passes_the_horizon_does_not_rescale():
    """At a smaller K_w the worn end moves to larger N: past the horizon, the direct run would stop there."""
    base = _exact_dlft(0.55, 1e-11)
    end = base.cycles[-1]
    assert base.status == "worn" and end < 1e5
    assert base.rescaled(1e-11 * end / 0.9e5, horizon=1e5).cycles[-1] == pytest.approx(0.9e5)
    with pytest.raises(ValueError, match="beyond the horizon"):
        base.rescaled(1e-11 * end / 1.1e5, horizon=1e5)
    stuck = _exact_dlft(1.25, 1e-11)
    assert stuck.rescaled(1e-20, horizon=1e5).status == "stuck"  # never wears: any K_w
