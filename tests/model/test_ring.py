"""The ring-damper disk (:mod:`fretwear.model.ring`): its linear modes against a cyclic-symmetry assembly and
the tutorial's numbers, and the stuck and sliding limits of a friction solve."""

import numpy as np
import pytest
import scipy.linalg as sl

import fretwear as fw
from fretwear.model import DiskSector
from fretwear.model.ring import ring_damper_disk, tutorial_rotation_speed

#: pyHarm tutorial 006's sorted natural frequencies of the disk (Hz), as printed by the notebook
TUTORIAL_DISK_HZ = [
    88.26374399, 169.3441295, 169.3441295, 189.3018526, 189.3018526, 193.0496227, 193.0496227,
    194.33310084, 194.33310084, 194.91823247, 194.91823247, 195.23065575, 195.23065575, 195.41408815,
    195.41408815, 195.52784525, 195.52784525, 195.59979933, 195.59979933, 195.64415084, 195.64415084,
    195.66835088, 195.66835088, 195.67605066, 249.31165161, 335.56537939, 335.56537939, 555.31017863,
    555.31017863, 615.15017797, 615.15017797, 616.585022, 616.585022, 616.96341859, 616.96341859,
    617.12696788, 617.12696788, 617.21324764, 617.21324764, 617.2635722, 617.2635722, 617.29423701,
    617.29423701, 617.31270821, 617.31270821, 617.32265229, 617.32265229, 617.32579659, 619.34330474,
    619.82021678, 619.82021678, 626.2025859, 626.2025859, 810.0067968, 810.0067968, 1044.51877441,
    1044.51877441, 1264.6832341, 1264.6832341, 1464.72871426, 1464.72871426, 1640.60424871, 1640.60424871,
    1789.01493852, 1789.01493852, 1907.27068187, 1907.27068187, 1993.2626374, 1993.2626374, 2045.47055708,
    2045.47055708, 2062.97567761,
]  # fmt: skip


def _hz(K: np.ndarray, M: np.ndarray) -> np.ndarray:
    return np.sqrt(sl.eigh(K, M, eigvals_only=True)) / (2 * np.pi)


def _cyclic_hz(sectors: int, kt: float, mr: float = 2e-3, kr: float = 1e7) -> np.ndarray:
    """All frequencies (Hz) from one 4-DOF sector (disk, root, tip, ring) per nodal diameter: an assembly
    independent of ring_damper_disk's."""
    sector = DiskSector(sectors)
    K0d, K1d = sector.stiffness()
    K0, K1 = np.zeros((4, 4)), np.zeros((4, 4))
    K0[:3, :3], K1[:3, :3] = K0d, K1d
    K0[3, 3] = 2 * kr + 1e-3 * kr
    K1[3, 3] = -kr
    K0[np.ix_([0, 3], [0, 3])] += kt * np.array([[1.0, -1.0], [-1.0, 1.0]])
    M = np.diag([sector.m0, sector.mb1, sector.mb2, mr])
    out = []
    for nd in range(sectors):
        e = np.exp(2j * np.pi * nd / sectors)
        out.extend(np.sqrt(sl.eigh(K0 + K1 * e + K1.T * np.conj(e), M, eigvals_only=True)))
    return np.sort(out) / (2 * np.pi)


def test_the_tutorial_parameters():
    """Tutorial 006: ring sector 2e-3 kg, R = 0.1 m, kr = 1e7 (link kr*1e1), mu = 0.1, Omega = pi f_1."""
    model = ring_damper_disk()
    info = model.info
    assert model.n_dofs == 96 and len(model.friction) == 24
    assert tutorial_rotation_speed() == pytest.approx(np.pi * 169.3441295, rel=1e-9)
    assert info["normal_load"] == pytest.approx(2e-3 * 0.1 * (np.pi * 169.3441295) ** 2, rel=1e-9)  # 56.61 N
    c = model.friction[5]
    assert (c.dof, c.other, c.kt, c.mu) == (model.dof("ring5"), model.dof("disk5"), 1e8, 0.1)
    assert model.slip_forces() == pytest.approx(np.full(24, 0.1 * info["normal_load"]), rel=1e-12)
    tips = 3 * np.arange(24) + 2
    phase = 2 * np.pi * np.arange(24) / 24  # EO 1, 1 N: cos(omega t - phase)
    assert np.allclose(model.force_cos[tips], np.cos(phase), atol=1e-15)
    assert np.allclose(model.force_sin[tips], np.sin(phase), atol=1e-15)


def test_open_contacts_give_the_tutorial_disk_and_a_free_ring():
    """Contacts open: the disk's frequencies are the tutorial's printed ones (to their 10 digits, measured
    4e-11) and the ring's are sqrt((1e-3 kr + 2 kr (1 - cos theta)) / mr)."""
    model = ring_damper_disk()
    disk = _hz(model.K[:72, :72], model.M[:72, :72])
    assert np.abs(disk / TUTORIAL_DISK_HZ - 1).max() <= 1e-9
    theta = 2 * np.pi * np.arange(24) / 24
    ring = np.sqrt((1e4 + 2e7 * (1 - np.cos(theta))) / 2e-3) / (2 * np.pi)
    both = np.sort(np.concatenate([disk, ring]))
    assert np.abs(_hz(model.K, model.M) / both - 1).max() <= 1e-12


@pytest.mark.parametrize("sectors", [24, 7])
def test_stuck_contacts_against_a_cyclic_assembly(sectors):
    """Contacts stuck (the springs kt = 1e8): the full model's frequencies equal those of the 4-DOF sector
    per nodal diameter (measured 3e-12 relative); the ring stiffens the 1-ND mode from 169.34 to 173.57 Hz."""
    model = ring_damper_disk(sectors)
    B = model.relative_map()
    full = _hz(model.K + model.info["kt"] * B.T @ B, model.M)
    assert np.abs(full / _cyclic_hz(sectors, 1e8) - 1).max() <= 1e-10
    if sectors == 24:
        assert full[1] == pytest.approx(173.56785315, rel=1e-9)


@pytest.mark.parametrize("omega_hz", [160.0, 173.5, 185.0])
def test_stuck_and_sliding_limits_of_a_solve(omega_hz):
    """Never slipping (slip force 5.7e4 N, and 5.7e10 N: a Jenkins slip force beyond the spring's force
    does not set the residual's scale): the linear disk with the springs kt; vanishing slip force: the disk
    with the ring free. Both to 1e-10 (the shroud's check of tests/disk/test_cyclic.py; measured 1e-14)."""
    omega = 2 * np.pi * omega_hz
    for mu, springs in ((1e3, True), (1e9, True), (1e-16, False)):
        model = ring_damper_disk(8, mu=mu)
        sol = fw.solve_periodic(model, omega, 5)
        assert sol.converged and np.all(sol.state == (fw.model.STICK if springs else fw.model.SLIP))
        B = model.relative_map()
        extra = model.info["kt"] * B.T @ B if springs else 0.0
        D = model.K + extra - omega**2 * model.M + 1j * omega * model.C
        U = np.linalg.solve(D, model.force_cos - 1j * model.force_sin)
        h = sol.dof_harmonics
        scale = np.abs(U).max()
        assert np.abs(h[:, 1] - U.real).max() <= 1e-10 * scale
        assert np.abs(h[:, 2] + U.imag).max() <= 1e-10 * scale
        assert np.abs(h[:, 3:]).max() <= 1e-10 * scale


def test_partial_slip_lies_between_the_limits():
    """At the stuck resonance (173.57 Hz) the tutorial's contacts slip: the tip amplitude is below the stuck
    peak (measured 0.09 of it) and the contacts pass through both states."""
    model = ring_damper_disk()
    omega = 2 * np.pi * 173.56785315
    sol = fw.solve_periodic(model, omega, 5)
    B = model.relative_map()
    D = model.K + 1e8 * B.T @ B - omega**2 * model.M + 1j * omega * model.C
    stuck = np.abs(np.linalg.solve(D, model.force_cos - 1j * model.force_sin))[2]
    assert sol.converged
    assert np.any(sol.state == fw.model.SLIP) and np.any(sol.state == fw.model.STICK)
    assert np.linalg.norm(sol.dof_harmonics[2, 1:]) < 0.2 * stuck


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (dict(mr=0.0), "mr must be > 0"),
        (dict(radius=-1.0), "radius must be > 0"),
        (dict(kr=np.inf), "kr must be a finite number"),
        (dict(mu=-0.1), "mu must be >= 0"),
        (dict(rotation_speed=-5.0), "rotation_speed must be >= 0"),
        (dict(damping_ratio=1.0), r"damping_ratio must lie in \[0, 1\)"),
        (dict(kb3=1.0), "'kb3' is not a parameter of ring_damper_disk"),
        (dict(sectors=2), "sectors must be an integer >= 3"),
    ],
)
def test_bad_input_is_refused(change, match):
    with pytest.raises(ValueError, match=match):
        ring_damper_disk(**change)


def test_bladed_disk_builds_the_ring_layout():
    a = fw.bladed_disk(8, contacts="ring", engine_order=2, kr=2e7)
    b = ring_damper_disk(8, engine_order=2, kr=2e7)
    assert all(
        np.array_equal(getattr(a, k), getattr(b, k)) for k in ("M", "C", "K", "force_cos", "force_sin")
    )
    assert a.friction == b.friction and a.info["contacts"] == "ring" and a.friction[0].mu == 0.1
    with pytest.raises(ValueError, match="ring damper's disk is tuned"):
        fw.bladed_disk(8, contacts="ring", mistuning=np.zeros(8))
