"""Studies: wear maps, regime maps and stick limits against single runs and exact formulas."""

import numpy as np
import pytest

import fretwear
from fretwear import (
    compare_methods,
    harmonic_convergence,
    paper_model,
    regime_map,
    wear_history,
    wear_map,
)
from fretwear.studies import stick_limit

TWO_PI = 2 * np.pi


def test_wear_map_matches_single_histories_and_stuck_frequencies_do_not_wear():
    model = paper_model(fex=10)
    freqs = np.array([0.3, 0.7, 0.9, 1.25])
    cycles = np.geomspace(1, 3e4, 12)
    wm = wear_map(model, freqs, cycles, kw=1e-11, harmonics=5, tol=1e-3)
    assert wm.wear.shape == (4, 12, 1) and wm.converged.all()
    np.testing.assert_array_equal(wm.wear[[0, 3]], 0.0)  # stuck at 0.3 and 1.25 Hz
    single = wear_history(model, TWO_PI * 0.7, kw=1e-11, cycles=3e4, harmonics=5, tol=1e-3)
    np.testing.assert_allclose(wm.wear[1, :, 0], single.at(cycles)["wear"][:, 0], rtol=1e-12)
    assert np.all(np.diff(wm.wear[1, :, 0]) >= 0) and wm.wear_fraction.max() < 1
    frf = wm.pseudo_frf([1.0, 3e4])
    assert frf.shape == (2, 4, 2) and frf[1, 1, 0] != frf[0, 1, 0]
    table = wm.long_table()
    assert len(table["f_hz"]) == 48 and {"cycles", "w", "w_over_u0", "x1_h1", "xr_half_p2p"} <= set(table)


def test_wear_map_threads_give_the_same_answer():
    model = paper_model(fex=10)
    args = (model, [0.6, 0.8], np.geomspace(1, 1e4, 5))
    a = wear_map(*args, kw=1e-11, harmonics=3, workers=1)
    b = wear_map(*args, kw=1e-11, harmonics=3, workers=2)
    np.testing.assert_array_equal(a.wear, b.wear)


def test_wear_map_bad_input():
    with pytest.raises(ValueError, match="frequencies"):
        wear_map(paper_model(), [0.0, 1.0], [1, 10])
    with pytest.raises(ValueError, match="cycles"):
        wear_map(paper_model(), [0.5], [10, 1])
    with pytest.raises(ValueError, match="kw"):
        wear_map(paper_model(), [0.5], [1, 10], kw=-1)
    with pytest.raises(ValueError, match="method"):
        wear_history(paper_model(), 4.0, "magic")


def test_stick_limit_is_the_exact_threshold():
    f = np.array([0.3, 0.7, 1.2])
    w = TWO_PI * f
    k1, k2, c1, c2 = np.pi**2, 7 * np.pi**2, 2e-3 * np.pi, 2e-3 * np.sqrt(7) * np.pi
    required = 10 * np.abs(k2 - w**2 + 1j * c2 * w) / np.abs(k1 + k2 - 2 * w**2 + 1j * (c1 + c2) * w)
    for fex in (5.0, 10.0):  # a ratio r = F_ex / (mu F_N): the model's own F_ex does not matter
        np.testing.assert_allclose(stick_limit(paper_model(fex=fex), f), 10 / required, rtol=1e-10)


def test_regime_map_slips_exactly_beyond_the_stick_limit():
    model, f = paper_model(fex=4), np.array([0.4, 0.7, 1.2])
    limit = stick_limit(model, f)
    ratios = np.array([0.5, 1.0, 2.0])
    r = regime_map(model, f, ratios, harmonics=5)
    slipping = r["slip_fraction"] > 0
    np.testing.assert_array_equal(slipping, ratios[:, None] > limit[None, :] * 1.001)
    one = fretwear.solve_periodic(paper_model(fex=20), TWO_PI * 0.7, 5)  # r = 2 at 0.7 Hz
    np.testing.assert_allclose(r["amplitude"][2, 1], one.amplitude[0], rtol=1e-9)


def test_harmonic_convergence_and_method_comparison_shapes():
    model = paper_model(fex=10)
    conv = harmonic_convergence(model, 0.7, harmonics=(1, 3), kw=1e-11, cycles=1e4, tol=1e-2)
    assert set(conv) == {1, 3} and all(h.converged for h in conv.values())
    comp = compare_methods(model, 0.7, methods=("stepping", "polynomial"), kw=1e-11, cycles=1e4,
                           harmonics=3)  # fmt: skip
    assert comp["stepping"].method == "stepping" and comp["polynomial"].method == "polynomial"
