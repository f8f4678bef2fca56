"""Mistuned bladed disks: modal response against the direct solve, peaks, magnification, Whitehead's bound."""

import numpy as np
import pytest

import fretwear as fw
from fretwear.disk import draw_mistuning, magnification, modal_basis, peak
from fretwear.model import DiskSector, Model

TIPS = 3 * np.arange(24) + 2
BAND = (165.0, 200.0)  # the blade-dominated family, 169-196 Hz


def test_the_modal_sum_is_the_direct_solve_of_a_mistuned_disk():
    model = fw.bladed_disk(mistuning=draw_mistuning(24, 0.03, 1, seed=4)[0], engine_order=3, contacts="none")
    omegas = 2 * np.pi * np.array([60.0, 170.0, 185.3, 193.0, 600.0, 2050.0])
    direct = fw.linear_frf(model, omegas, "open")[:, TIPS]
    modal = modal_basis(model, TIPS).response(omegas)
    assert np.abs(modal - direct).max() <= 1e-10 * np.abs(direct).max()  # measured 6e-13


def test_non_modal_damping_and_contacts_are_refused():
    M, K = np.eye(2), np.array([[2.0, -1.0], [-1.0, 2.0]])
    local = Model(M=M, C=np.diag([0.1, 0.0]), K=K, force_cos=np.array([1.0, 0.0]))
    with pytest.raises(ValueError, match="damping is not modal"):
        modal_basis(local, [0])
    with pytest.raises(ValueError, match="no contacts"):
        modal_basis(fw.paper_model(), [0])


def test_the_peak_is_the_maximum_of_a_fine_grid():
    basis = modal_basis(
        fw.bladed_disk(mistuning=draw_mistuning(24, 0.02, 1, seed=3)[0], engine_order=3, contacts="none"),
        TIPS,
    )
    amp, f, blade = peak(basis, BAND)
    fine = 2 * np.pi * np.linspace(f - 0.05, f + 0.05, 20001)  # 5e-6 Hz steps about the peak found
    brute = np.abs(basis.response(fine))
    assert amp >= brute.max() * (1 - 1e-9)  # the refined peak is not below any sample
    assert amp == pytest.approx(brute[:, blade].max(), rel=1e-8)
    coarse = 2 * np.pi * np.linspace(*BAND, 40001)  # and no higher peak elsewhere in the band
    assert np.abs(basis.response(coarse)).max() <= amp * (1 + 1e-12)


def test_a_tuned_disk_is_not_magnified_and_peaks_at_its_engine_order_mode():
    res = magnification(np.zeros((1, 24)), BAND, engine_order=3)
    assert res.factor[0] == pytest.approx(1.0, rel=1e-12)
    f_nd = DiskSector().frequencies(3)[0]  # the nd = 3 mode of the blade family
    assert res.tuned_frequency == pytest.approx(f_nd, rel=1e-5)


def test_magnification_does_not_depend_on_the_force_amplitude():
    patterns = draw_mistuning(24, 0.01, 3, seed=2)
    a = magnification(patterns, BAND, engine_order=3, fex=1.0)
    b = magnification(patterns, BAND, engine_order=3, fex=7.0)
    assert np.allclose(a.factor, b.factor, rtol=1e-12, atol=0)
    assert b.tuned == pytest.approx(7.0 * a.tuned, rel=1e-12)


@pytest.mark.parametrize("level", [0.002, 0.01, 0.03, 0.1])
def test_no_draw_exceeds_whitehead_in_the_blade_family(level):
    """One mode per blade in 169-196 Hz: Whitehead's (1 + sqrt(24)) / 2 = 2.95 bounds every pattern."""
    res = magnification(draw_mistuning(24, level, 40, seed=11), BAND, engine_order=3)
    assert res.whitehead == pytest.approx(2.9494897, rel=1e-7)
    assert res.factor.max() <= res.whitehead
    assert res.factor.max() > 1.05  # mistuning does localise (measured 1.3-2.1)


def test_draws_are_seeded_and_have_the_level_as_standard_deviation():
    a, b = draw_mistuning(24, 0.04, 500, seed=5), draw_mistuning(24, 0.04, 500, seed=5)
    assert np.array_equal(a, b) and a.shape == (500, 24)
    assert a.std() == pytest.approx(0.04, rel=0.03)
    assert np.all(draw_mistuning(24, 0.5, 200, seed=1) > -1)
    with pytest.raises(ValueError, match="level"):
        draw_mistuning(24, -0.1, 3)
    with pytest.raises(ValueError, match="draws"):
        draw_mistuning(24, 0.1, 0)
    with pytest.raises(ValueError, match="band"):
        magnification(a[:2], (200.0, 100.0))
