"""Tests of fretwear.time.shooting: the periodic-response protocol, robustness, exact anchors.

* every orbit a test produces is checked against Coulomb's law densely inside
  every phase (stuck force within the slip limit, zero relative velocity when
  stuck, slip force along the relative velocity when slipping), for its
  periodicity residual and its energy balance per period (1e-10);
* the cases where the former Python integrator failed or broke Coulomb's law;
* the paper model over a frequency x force grid and random 2-DOF structures
  (hypothesis): converged, or reported as not converged with a message;
* exact anchors: the stick threshold, half-wave symmetry, agreement with
  harmonic balance within its O(1 / Nh) band, simultaneous events of a
  symmetric structure.
"""

import numpy as np
import pytest
from hypothesis import given
from hypothesis import strategies as st

import fretwear as fw
from fretwear.model import SLIP, STICK, FrictionContact, Model, paper_model
from fretwear.response import RESPONSE_ATTRIBUTES, PeriodicResponse
from fretwear.time import ShootingSolution, integrate, shooting, shooting_sweep

K1, K2 = np.pi**2, 7 * np.pi**2
TWO_PI = 2 * np.pi
COARSE_FREQUENCIES = np.linspace(0.05, 2.0, 60)
COARSE_FORCES = [1.0, 4.0, 6.0, 10.0, 14.0, 20.0, 30.0]


def check_orbit(sol: ShootingSolution, residual: float = 1e-10) -> None:
    """A converged periodic orbit that obeys Coulomb's law everywhere and balances its energy.

    The exact solution is evaluated at 33 points inside every phase of
    constant contact states (however short the phase), not only at the samples.
    """
    assert sol.converged and sol.residual <= residual, sol.message
    assert sol.message == ""
    traj, g = sol.trajectory, sol.slip_forces
    n = sol.model.n_dofs
    bounds = traj.segment_times
    inside = np.linspace(0.0, 1.0, 35)[1:-1]
    times = (bounds[:-1, None] + np.diff(bounds)[:, None] * inside).ravel()
    phase = np.repeat(np.arange(len(bounds) - 1), len(inside))
    states, force, codes = traj.evaluate(times)
    vr = sol.model.relative_map(sol.model.friction) @ states[n:]
    vscale = np.abs(states[n:]).max() + sol.omega * np.abs(states[:n]).max()
    for j, gj in enumerate(g):
        stick, slip = codes[j] == STICK, codes[j] == SLIP
        assert np.all(codes[j] == traj.segment_state[phase, j])
        assert np.all(np.abs(force[j, stick]) <= gj * (1 + 1e-9)), np.abs(force[j, stick]).max() / gj - 1
        assert np.all(np.abs(vr[j, stick]) <= 1e-9 * vscale)
        direction = traj.segment_direction[phase, j][slip]
        assert np.all(np.abs(direction) == 1)
        assert np.all(force[j, slip] == pytest.approx(gj * direction, rel=1e-12))
        assert np.all(direction * vr[j, slip] > -1e-9 * vscale)
    # energy balance over the period (with the round-off change of mechanical energy it leaves)
    M, K = sol.model.M, sol.model.K

    def energy(y):
        return 0.5 * y[n:] @ M @ y[n:] + 0.5 * y[:n] @ K @ y[:n]

    dissipated = sol.viscous_dissipation + sol.friction_energy.sum() + energy(traj.y) - energy(sol.y0)
    assert sol.input_work == pytest.approx(dissipated, rel=1e-10, abs=1e-14 * energy(sol.y0))
    assert sol.friction_energy == pytest.approx(g * sol.sliding_distance, rel=1e-14, abs=0)


def two_dof(
    fex: float, mu: float = 1.0, zeta: float = 1e-3, mass_ratio: float = 1.0, stiffness_ratio: float = 7.0
):
    """The paper's 2-DOF model with free mass and stiffness ratios (``m1 = 1 kg``, ``k1 = pi^2 N/m``)."""
    k2, m2 = stiffness_ratio * K1, mass_ratio
    return Model(
        M=np.diag([1.0, m2]),
        C=np.diag([2 * zeta * np.sqrt(K1), 2 * zeta * np.sqrt(k2 * m2)]),
        K=np.diag([K1, k2]),
        force_cos=[fex, 0.0],
        friction=(FrictionContact.from_normal_load(0, 1, mu, 10.0),),
    )


def stuck_force_ratio(fex: float, f: float) -> float:
    """Amplitude of the stuck force of the paper model, relative to ``mu F_N = 10 N`` (linear, exact)."""
    w = TWO_PI * f
    c1, c2 = 2e-3 * np.sqrt(K1), 2e-3 * np.sqrt(K2)
    return fex * abs(K2 - w**2 + 1j * c2 * w) / abs(K1 + K2 - 2 * w**2 + 1j * (c1 + c2) * w) / 10.0


# ---------------------------------------------------------------------------
# 1. the periodic-response protocol
# ---------------------------------------------------------------------------
def test_shooting_solution_is_a_periodic_response():
    model = paper_model(fex=10)
    sol = shooting(model, TWO_PI * 0.7, samples=64)
    check_orbit(sol)
    assert isinstance(sol, PeriodicResponse)
    for name in RESPONSE_ATTRIBUTES:
        value = getattr(sol, name)
        if isinstance(value, (float, int, np.ndarray)) and not isinstance(value, bool):
            assert np.all(np.isfinite(value)), name
    assert sol.path == "shooting" and sol.message == "" and sol.model is model
    assert sol.frequency == pytest.approx(0.7, rel=1e-15)
    n_contacts = len(model.contacts)
    for name in ("relative_displacement", "contact_force", "state"):
        assert getattr(sol, name).shape == (n_contacts, 64)
    assert sol.displacement.shape == (2, 64) and sol.time.shape == (64,)
    assert sol.relative_amplitude == pytest.approx(
        np.abs(np.fft.rfft(sol.relative_displacement[0])[1]) / 32, rel=1e-3
    )
    # the unknowns are the state at t = 0: a guess that is already periodic
    again = shooting(model, TWO_PI * 0.7, sol.unknowns)
    assert again.converged and again.iterations == 0
    assert np.array_equal(sol.unknowns, sol.y0)


def test_failure_is_reported_not_raised():
    sol = shooting(paper_model(fex=10), TWO_PI * 0.7, max_iter=0, transient_periods=0)
    assert not sol.converged and sol.residual > 1e-6
    assert "did not reach the tolerance" in sol.message
    assert isinstance(sol, PeriodicResponse)
    assert np.all(np.isfinite(sol.amplitude)) and np.all(np.isfinite(sol.contact_force))


# ---------------------------------------------------------------------------
# 2. the cases where the Python integrator failed or broke Coulomb's law
# ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    "fex, f",
    [(6, 0.795), (6, 0.82), (6, 0.825), (6, 0.985), (10, 0.47), (10, 0.495), (10, 1.015), (14, 1.045)],
)
def test_former_failures_converge_cold(fex, f):
    check_orbit(shooting(paper_model(fex=fex), TWO_PI * f))


def test_short_slip_is_not_missed():
    """14 N at 0.415 Hz: a slip of 1.5 % of the period inside each half of the stick phase."""
    sol = shooting(paper_model(fex=14), TWO_PI * 0.415)
    check_orbit(sol)
    assert len(sol.events) == 8
    slips = [
        (a.time / sol.period, b.time / sol.period)
        for a, b in zip(sol.events[:-1], sol.events[1:], strict=True)
        if a.kind == "slip"
    ]
    assert any(0.12 < a < 0.13 and 0.14 < b < 0.15 for a, b in slips)


@pytest.mark.parametrize("fex, f", [(6, 1.085), (10, 1.12), (14, 1.145)])
def test_stuck_orbits_stay_within_the_limit(fex, f):
    """Where the stick-slip branch ends in stuck orbits, cold and swept up from the stick-slip side.

    Cold, the orbit is the linear stuck one (zero offset, exact force); so it
    is in a sweep. Newton from a slipping orbit reaches the member of the
    stuck family with the offset where the slip faded out: its peak force
    sits at the limit, and must not exceed it.
    """
    cold = shooting(paper_model(fex=fex), TWO_PI * f)
    check_orbit(cold)
    assert not cold.events and np.all(cold.state == STICK)
    dense = np.abs(cold.trajectory.evaluate(np.linspace(0.0, cold.period, 20001))[1]).max()
    assert dense == pytest.approx(10 * stuck_force_ratio(fex, f), rel=1e-7)  # sampling error 1.2e-8
    assert cold.neutral_multipliers == 1 and cold.stable
    swept = shooting_sweep(paper_model(fex=fex), TWO_PI * np.linspace(1.0, f, round((f - 1.0) / 0.005) + 1))
    for sol in swept:
        check_orbit(sol)
    assert swept[0].sliding_distance[0] > 0.1
    last = swept[-1]  # the sweep takes the stuck orbit without offset, as the cold solve
    assert not last.events and np.abs(last.y0 - cold.y0).max() <= 1e-12 * np.abs(cold.y0).max()
    # from the last slipping orbit of the sweep, Newton reaches the stuck orbit the slip leaves behind
    slipping = [sol for sol in swept if sol.events][-1]
    inherited = shooting(paper_model(fex=fex), TWO_PI * f, slipping.unknowns)
    check_orbit(inherited)
    assert inherited.relative_half_peak_to_peak[0] <= 1e-9 * swept[0].relative_half_peak_to_peak[0]
    assert np.abs(inherited.contact_force).max() == pytest.approx(10.0, rel=1e-4)
    assert np.abs(inherited.contact_force).max() <= 10.0 * (1 + 1e-9)


# ---------------------------------------------------------------------------
# 3. robustness: a frequency x force grid, random structures
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("fex", COARSE_FORCES)
def test_paper_model_coarse_grid(fex):
    """60 frequencies over 0.05-2 Hz, mu = 1, F_N = 10 N: every orbit exact and Coulomb-admissible."""
    for sol in shooting_sweep(paper_model(fex=fex), TWO_PI * COARSE_FREQUENCIES, samples=8):
        check_orbit(sol)


@pytest.mark.slow
def test_paper_model_full_grid():
    """The issue's grid: 400 frequencies over 0.05-2 Hz x 11 forces."""
    for fex in [1, 2, 4, 6, 8, 10, 12, 14, 16, 20, 30]:
        for sol in shooting_sweep(paper_model(fex=fex), TWO_PI * np.linspace(0.05, 2.0, 400), samples=8):
            check_orbit(sol)


@given(
    f=st.floats(0.05, 2.0),
    fex=st.floats(0.5, 40.0),
    mu=st.floats(0.05, 2.0),
    zeta=st.floats(-4.0, -1.0).map(lambda e: 10.0**e),
    mass_ratio=st.floats(-1.0, 1.0).map(lambda e: 10.0**e),
    stiffness_ratio=st.floats(-1.0, 1.3).map(lambda e: 10.0**e),
)
def test_random_structures_converge_or_say_why(f, fex, mu, zeta, mass_ratio, stiffness_ratio):
    sol = shooting(two_dof(fex, mu, zeta, mass_ratio, stiffness_ratio), TWO_PI * f, samples=8)
    if sol.converged:
        check_orbit(sol)
    else:
        assert sol.message


# ---------------------------------------------------------------------------
# 4. exact anchors
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("f", [0.3, 0.7, 1.3])
def test_exact_stick_threshold(f):
    """The stick threshold ``F* = mu F_N / |H(omega)|`` of the linear stuck response.

    Below it the orbit is stuck; at it the stuck force grazes the limit (not
    an event, by rule); above it, ``F = F* (1 + delta)``, the contact slips
    around each force peak, for a time ``~ sqrt(delta)`` with a velocity
    ``~ delta^(3/2)``: the slid distance grows as ``delta^2``.
    """
    threshold = 1.0 / stuck_force_ratio(1.0, f)
    for fex in (threshold * (1 - 1e-9), threshold):
        sol = shooting(paper_model(fex=fex), TWO_PI * f)
        check_orbit(sol)
        assert not sol.events and np.all(sol.sliding_distance == 0) and sol.neutral_multipliers == 1
    slid = []
    for delta in (1e-5, 1e-4):
        sol = shooting(paper_model(fex=threshold * (1 + delta)), TWO_PI * f)
        check_orbit(sol)
        assert [e.kind for e in sol.events] in (["stick", "slip"] * 2, ["slip", "stick"] * 2)
        assert sol.neutral_multipliers == 0 and sol.stable
        slid.append(sol.sliding_distance[0])
    assert slid[1] / slid[0] == pytest.approx(100.0, rel=1e-2)


@pytest.mark.parametrize("fex, f", [(6, 0.9), (10, 0.7), (14, 0.415), (30, 0.2)])
def test_half_wave_symmetry(fex, f):
    """No static load: the slipping orbit satisfies ``y(t + T/2) = -y(t)``."""
    model = paper_model(fex=fex)
    sol = shooting(model, TWO_PI * f, samples=64)
    check_orbit(sol)
    assert sol.sliding_distance[0] > 0
    half = integrate(model, TWO_PI * f, sol.y0, 0.0, sol.period / 2).y
    scale = np.abs(sol.y0).max()
    assert np.abs(half + sol.y0).max() <= 1e-10 * scale
    u = sol.displacement
    assert np.abs(u[:, 32:] + u[:, :32]).max() <= 1e-10 * np.abs(u).max()


@pytest.mark.parametrize("fex, f", [(10, 0.7), (14, 0.9), (6, 0.95)])
def test_harmonic_balance_converges_to_the_exact_orbit(fex, f):
    """DLFT's error on amplitudes and sliding distance stays within ``2 / Nh`` and falls with ``Nh``."""
    model = paper_model(fex=fex)
    exact = shooting(model, TWO_PI * f)
    check_orbit(exact)
    errors = []
    for nh in (21, 41):
        approx = fw.solve_periodic(model, TWO_PI * f, nh)
        assert approx.converged
        err = max(
            abs(approx.amplitude[0] / exact.amplitude[0] - 1),
            abs(approx.relative_half_peak_to_peak[0] / exact.relative_half_peak_to_peak[0] - 1),
            abs(approx.sliding_distance[0] / exact.sliding_distance[0] - 1),
        )
        assert err <= 2.0 / nh
        errors.append(err)
    assert errors[1] < errors[0]


def test_simultaneous_events_of_a_symmetric_structure():
    """Two identical contacts driven in phase reach their limits and zero velocity at the same instants."""
    K = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]]) * 10
    model = Model(
        M=np.eye(3),
        C=0.01 * K,
        K=K,
        force_cos=[3.0, 0.0, 3.0],
        friction=(
            FrictionContact.from_normal_load(0, None, 1.0, 1.0),
            FrictionContact.from_normal_load(2, None, 1.0, 1.0),
        ),
    )
    sol = shooting(model, 2.5)
    check_orbit(sol)
    times = np.array([e.time for e in sol.events]).reshape(-1, 2)
    contacts = np.array([e.contact for e in sol.events]).reshape(-1, 2)
    assert len(sol.events) >= 4
    assert np.all(np.abs(np.diff(times, axis=1)) <= 1e-12 * sol.period)
    assert np.all(np.sort(contacts, axis=1) == [0, 1])
    assert np.abs(sol.displacement[0] - sol.displacement[2]).max() <= 1e-10 * np.abs(sol.displacement).max()


def test_sweep_is_seeded_by_the_previous_unknowns():
    model = paper_model(fex=10)
    omegas = TWO_PI * np.linspace(0.6, 0.8, 9)
    swept = shooting_sweep(model, omegas, samples=8)
    cold = [shooting(model, w, samples=8) for w in omegas]
    for a, b in zip(swept, cold, strict=True):
        check_orbit(a)
        assert np.abs(a.y0 - b.y0).max() <= 1e-9 * np.abs(b.y0).max()
    assert sum(s.iterations for s in swept[1:]) < sum(s.iterations for s in cold[1:])
