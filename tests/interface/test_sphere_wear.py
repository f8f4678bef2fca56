"""Archard wear over the 3-D patch of the sphere on the flat (issue 25): the scar's shape by regime.

A coarse half model (``divisions=4``: 29 pairs on a grid of spacing ``0.31 a``), the 2-D friction law,
``Nh = 3``, at 1/20 of the holder's mode (quasi-static). Mindlin's partial slip wears an annulus around
the stick disk ``r < c`` (``c = a (1 - Q / (mu P))^(1/3)``), which stays unworn; gross slip (the holder
driven through a loading arm past ``mu P``) wears the whole contact disk ``r < a``, deepest at the centre
where the pressure peaks. The pressure integral stays the normal load ``P / 2`` of the half model at every
record while the pressure redistributes. Each history takes a few seconds.
"""

import numpy as np
import pytest

from fretwear.interface.history import fretting_loop
from fretwear.interface.periodic import InterfaceProblem
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import holder_frequency, mindlin_stick_radius, sphere_dynamic_model
from fretwear.interface.wear import wear_interface

COARSE = dict(divisions=4, size=4.0)
Q_RATIO = 0.6
#: the arm (N/m) and its end's amplitude (m): k_a delta0 = 300 N = 5 mu P, well past gross slip
GROSS = dict(arm_stiffness=2e7, drive_displacement=1.5e-5)


def history(cycles: float, **changes):
    cond = ContactCondensation(sphere_dynamic_model(**COARSE, **changes))
    problem = InterfaceProblem(cond, 2 * np.pi * 0.05 * holder_frequency(), harmonics=3)
    h = wear_interface(problem, 1e-14, cycles, rtol=3e-2)
    assert h.converged, h.message
    info = cond.full.info
    return h, info, np.hypot(*info["pair_points"].T) / info["hertz_radius"]


@pytest.fixture(scope="module")
def partial():
    return history(1e5, q_ratio=Q_RATIO)


@pytest.fixture(scope="module")
def gross():
    return history(1e3, **GROSS)  # a shallow scar: ~0.3 um, a tenth of Hertz's approach a^2 / R


def test_partial_slip_scar_is_an_annulus_around_the_unworn_stick_disk(partial):
    h, info, r = partial
    c = mindlin_stick_radius(1.0, Q_RATIO)  # in units of a: 0.74
    w = h.wear[-1]
    stick, annulus = r < 0.9 * c, (r > c) & (r < 1.0)
    assert stick.sum() >= 9 and annulus.sum() >= 8  # the mesh resolves both
    assert np.all(w[stick] == 0) and np.all(h.stick_fraction[:, stick] == 1)
    assert np.all(w[annulus] > 0.3 * w.max()) and w.max() > 0
    # the scar's inner edge: the worn pair nearest the centre lies beyond Mindlin's c
    assert r[w > 0].min() > c
    np.testing.assert_allclose(h.normal_force_sum, info["normal_load"] / 2, rtol=1e-9)


def test_gross_slip_scar_is_a_disk_deepest_at_the_centre(gross):
    h, info, r = gross
    w = h.wear[-1]
    contact = r < 1.0
    assert np.all(h.stick_fraction[-1, contact] < 0.5)  # the whole contact slides
    assert np.all(w[contact] > 0)  # the worn set covers the whole contact disk
    assert np.argmin(r) == np.argmax(w) and r[np.argmax(w)] == 0  # deepest at the centre
    # the depth falls off with r as the initial pressure does (Archard at uniform slip)
    ring = np.unique(np.round(r[contact], 6))
    depth = [w[np.isclose(r, q)].mean() for q in ring]
    assert np.all(np.diff(depth) < 0)
    np.testing.assert_allclose(h.normal_force_sum, info["normal_load"] / 2, rtol=1e-9)


def test_gross_slip_loop_is_a_parallelogram_at_mu_p(gross):
    """The fretting loop of the gross-slip record: its force plateaus at +-mu P (the whole contact slides),
    and its area is the energy the friction dissipates (the holder's damping, stiffness-proportional at
    1/20 of the mode, takes a few per mille)."""
    h, info, _ = gross
    sol = h.solutions[-1]
    delta, Q = fretting_loop(sol, "pad_x")
    mu_p = info["mu"] * info["normal_load"]
    assert np.abs(Q).max() == pytest.approx(mu_p, rel=1e-6)
    assert np.mean(np.abs(Q) > 0.99 * mu_p) > 0.5  # slides most of the period
    assert Q[np.argmax(delta)] > 0.99 * mu_p  # the load follows the holder (a clockwise loop)
    area = np.sum(0.5 * (Q + np.roll(Q, -1)) * (np.roll(delta, -1) - delta))  # oint Q d(delta), closed
    assert area == pytest.approx(2 * sol.friction_energy, rel=0.02)
    assert 0.5 < area / (2 * mu_p * np.ptp(delta)) < 1  # a parallelogram, its corners cut by the sticks
