"""The lumped bladed disk: natural frequencies against the published list, cyclic symmetry, mistuning,
modal damping and the travelling-wave excitation."""

import numpy as np
import pytest
import scipy.linalg as sl

import fretwear as fw
from fretwear.model import DiskSector

#: published natural frequencies of the 24-sector disk (Hz): the first seven and the last three, and the
#: sector's three at 0 and 12 nodal diameters (issue 24; pyHarm's tutorial 006 model)
FIRST = [88.26374399, 169.3441295, 169.3441295, 189.3018526, 189.3018526, 193.0496227, 193.0496227]
LAST = [2045.47055708, 2045.47055708, 2062.97567761]
ND0, ND12 = [88.2637, 249.3117, 619.3433], [195.6761, 617.3258, 2062.9757]


def frequencies(model) -> np.ndarray:
    return np.sqrt(sl.eigh(model.K, model.M, eigvals_only=True)) / (2 * np.pi)


def test_the_default_disk_has_the_published_natural_frequencies():
    f = frequencies(fw.bladed_disk())
    assert f.shape == (72,)
    assert np.allclose(f[:7], FIRST, rtol=1e-8, atol=0) and np.allclose(f[-3:], LAST, rtol=1e-8, atol=0)
    sector = DiskSector()
    assert np.allclose(sector.frequencies(0), ND0, rtol=0, atol=1e-4)
    assert np.allclose(sector.frequencies(12), ND12, rtol=0, atol=1e-4)


@pytest.mark.parametrize("sectors", [3, 7, 24])
def test_the_cyclic_sector_gives_every_frequency_of_the_full_disk(sectors):
    """Nodal diameters 0 .. N-1 of the sector: the full disk's spectrum, each frequency once."""
    sector = DiskSector(sectors)
    cyclic = np.sort(np.concatenate([sector.frequencies(nd) for nd in range(sectors)]))
    assert np.allclose(cyclic, frequencies(fw.bladed_disk(sectors)), rtol=1e-10, atol=0)
    zz = sector.zzenf()
    assert zz.shape == (sectors // 2 + 1, 3) and np.allclose(zz[1], sector.frequencies(sectors - 1))


def test_mistuning_scales_only_its_blades_springs_and_splits_the_double_modes():
    delta = np.zeros(24)
    delta[5] = 0.05
    tuned, mistuned = fw.bladed_disk(), fw.bladed_disk(mistuning=delta)
    dK = mistuned.K - tuned.K
    rows = np.flatnonzero(np.abs(dK).sum(axis=1))
    assert set(rows) == {15, 16, 17}  # sector 5: its disk (root spring), root and tip
    assert dK[16, 17] == pytest.approx(-0.05 * 2e6) and dK[15, 15] == pytest.approx(0.05 * 1e6)
    f_t, f_m = frequencies(tuned), frequencies(mistuned)
    assert abs(f_t[1] - f_t[2]) < 1e-6 * f_t[1] and abs(f_m[1] - f_m[2]) > 1e-4 * f_m[1]
    assert np.allclose(fw.bladed_disk(mistuning=np.zeros(24)).K, tuned.K, rtol=0, atol=0)


def test_every_mode_has_the_modal_damping_ratio():
    model = fw.bladed_disk(6, damping_ratio=2e-3)
    w2, phi = sl.eigh(model.K, model.M)
    modal = phi.T @ model.C @ phi
    assert np.allclose(modal, np.diag(2 * 2e-3 * np.sqrt(w2)), rtol=0, atol=1e-9 * np.abs(modal).max())


def test_the_excitation_is_a_travelling_wave_on_the_blade_tips():
    model = fw.bladed_disk(8, engine_order=3, fex=2.0)
    tips = [model.dof(f"tip{i}") for i in range(8)]
    force = model.force_cos - 1j * model.force_sin  # u(t) = Re(U e^{i omega t})
    assert np.allclose(force[tips], 2.0 * np.exp(-2j * np.pi * 3 * np.arange(8) / 8))
    assert np.count_nonzero(force) == 8 and model.info["engine_order"] == 3


def test_bad_disk_parameters_are_named():
    with pytest.raises(ValueError, match="sectors"):
        fw.bladed_disk(2)
    with pytest.raises(ValueError, match="kb1"):
        fw.bladed_disk(kb1=-1.0)
    with pytest.raises(ValueError, match="mistuning"):
        fw.bladed_disk(4, mistuning=[0.0, 0.0, -1.0, 0.0])
    with pytest.raises(ValueError, match="'m00' is not a parameter of bladed_disk; the sector has m0, mb1"):
        fw.bladed_disk(m00=1.0)
    with pytest.raises(ValueError, match="damping_ratio"):
        fw.bladed_disk(damping_ratio=1.0)
    with pytest.raises(ValueError, match="nodal_diameter"):
        DiskSector().frequencies(1.5)
