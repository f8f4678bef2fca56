"""The tuned shrouded disk on one sector (:mod:`fretwear.disk.cyclic`) against the full disk and limits."""

from dataclasses import replace

import numpy as np
import pytest

import fretwear as fw
from fretwear.disk.cyclic import samples_for, solve_sector, sweep_sector, tuned_disk
from fretwear.model import SLIP, STICK


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize(
    ("sectors", "eo", "fex", "band"),
    [(24, 1, 2.0, (166.0, 174.0)), (6, 1, 2.0, (210.0, 234.0)), (8, 3, 8.0, (170.0, 200.0))],
    ids=["24-EO1", "6-EO1", "8-EO3"],
)
def test_sector_equals_full_disk_across_the_resonance(sectors, eo, fex, band):
    """Issue 24: the cyclic sector solve equals the full-disk solve to 1e-8 at every frequency of a sweep
    through partial slip (same time grid: samples_for); measured 1e-12."""
    model = fw.bladed_disk(sectors, engine_order=eo, fex=fex)
    omegas = 2 * np.pi * np.linspace(*band, 9)
    full = fw.sweep(model, omegas, 5, samples=samples_for(sectors, eo, 5))
    cyc = sweep_sector(model, omegas, 5)
    assert all(full.converged) and all(cyc.converged)
    states = np.concatenate([s.state.ravel() for s in full.solutions])
    assert np.any(states == SLIP) and np.any(states == STICK)  # the sweep crosses partial slip
    for f, c in zip(full.solutions, cyc.solutions, strict=True):
        assert c.samples == f.samples and c.problem.n_active == 1
        assert _rel(c.dof_harmonics, f.dof_harmonics) <= 1e-8
        assert _rel(c.contact_force, f.contact_force) <= 1e-8
        assert np.array_equal(c.state, f.state)
        assert np.abs(c.slip - f.slip).max() <= 1e-8 * np.abs(f.relative_displacement).max()


@pytest.mark.parametrize("omega_hz", [150.0, 170.0, 190.0])
def test_sector_stuck_and_sliding_limits(omega_hz, assert_linear):
    """Stuck shroud: the linear disk with springs k_t between neighbouring tips; sliding (vanishing slip
    force): the disk without contacts. Both to 1e-10."""
    omega = 2 * np.pi * omega_hz
    for mu, springs in ((1e9, True), (1e-16, False)):
        model = fw.bladed_disk(12, engine_order=2, mu=mu)
        sol = solve_sector(model, omega, 7)
        assert sol.converged
        B = model.relative_map()
        assert_linear(sol, model, omega, 5e5 * B.T @ B if springs else 0.0)


def test_worn_through_shroud_is_the_open_disk():
    model = fw.bladed_disk(6)
    sol = solve_sector(model, 2 * np.pi * 165, 5, wear=2e-6)  # u0 = 1e-6: the load is clipped at zero
    lin = fw.solve_periodic(fw.bladed_disk(6, contacts="none"), 2 * np.pi * 165, 5)
    assert sol.path == "linear-open" and np.all(sol.normal_loads == 0)
    assert _rel(sol.dof_harmonics, lin.dof_harmonics) <= 1e-12


def test_the_delay_between_sectors_is_a_whole_number_of_samples():
    for sectors, eo, nh in [(24, 1, 7), (24, 5, 21), (7, 3, 3), (6, 2, 5)]:
        n = samples_for(sectors, eo, nh)
        assert n % 2 == 0 and n >= 16 * nh and (n * eo) % sectors == 0


@pytest.mark.parametrize(
    ("change", "match"),
    [
        (dict(contacts="none"), "contacts='shroud'"),
        (dict(mistuning=[0.01, 0, 0, 0, 0, 0]), "tuned disk"),
    ],
)
def test_only_the_tuned_shrouded_disk_is_solved_on_a_sector(change, match):
    with pytest.raises(ValueError, match=match):
        tuned_disk(fw.bladed_disk(6, **change))


def test_a_changed_disk_is_refused():
    model = fw.bladed_disk(6).scaled(2.0)
    with pytest.raises(ValueError, match="changed after bladed_disk built it"):
        solve_sector(model, 1000.0)


def test_tuned_disk_wears_alike_on_a_sector_as_on_the_full_disk():
    """fw.wear_history on the tuned disk runs on one sector; the full disk (the same model, not recognised
    as a bladed_disk) gives the same history on the same grid: every contact worn alike."""
    model = fw.bladed_disk(6, engine_order=1, fex=2.0)
    omega, samples = 2 * np.pi * 222.0, samples_for(6, 1, 7)
    options = dict(kw=3e-7, cycles=2e4, harmonics=7, samples=samples)
    sector = fw.wear_history(model, omega, "stepping", **options)
    full = fw.wear_history(replace(model, info={}), omega, "stepping", **options)
    assert sector.converged and full.converged and sector.wear[-1, 0] > 0.3 * model.friction[0].u0
    assert np.allclose(sector.cycles, full.cycles, rtol=1e-9, atol=0)
    assert np.abs(sector.wear - full.wear).max() <= 1e-9 * sector.wear.max()
    assert np.ptp(full.wear[-1]) <= 1e-9 * full.wear[-1, 0]  # the full disk wears alike too
