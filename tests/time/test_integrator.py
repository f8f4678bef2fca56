"""Tests of fretwear.time.shooting against independent (mostly analytic) oracles.

* linear limits: rigid (stuck) and open contact, complex FRF solves;
* Den Hartog's exact continuous-sliding solution of the Coulomb oscillator,
  with the no-stop condition checked on the exact half-cycle motion;
* energy balance over a period and over a transient (energy identity);
* exact monodromy vs finite differences of the period map;
* closed-form slip of a free mass (singular, rigid-body slip dynamics);
* steady-state marching vs shooting; input validation.
"""

import numpy as np
import pytest
from scipy.optimize import brentq

import fretwear as fw
import fretwear.time as ti
from fretwear import FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model
from fretwear.model import OPEN, SLIP, STICK

K1, K2 = np.pi**2, 7 * np.pi**2
ZETA = 1e-3
C1, C2 = 2 * ZETA * np.sqrt(K1), 2 * ZETA * np.sqrt(K2)


def rel(a, b) -> float:
    """Relative difference of two arrays (max norm)."""
    return float(np.abs(np.asarray(a) - np.asarray(b)).max() / np.abs(np.asarray(b)).max())


def harmonic_state(U: np.ndarray, w: float) -> np.ndarray:
    """State at t = 0 of u(t) = Re(U exp(i w t))."""
    return np.concatenate([U.real, (1j * w * U).real])


def coulomb_oscillator(ratio: float, F0: float = 1.0) -> Model:
    """m = k = 1, c = 0, friction to ground of slip force ``ratio * F0``, load ``F0 cos(omega t)``."""
    return Model(
        M=[[1.0]],
        C=[[0.0]],
        K=[[1.0]],
        force_cos=[F0],
        friction=(FrictionContact.from_normal_load(0, None, 1.0, ratio * F0),),
    )


def fd_jacobian(model: Model, w: float, y: np.ndarray, h: float) -> np.ndarray:
    """Central finite differences of the period map at ``y``."""
    cols = [
        (ti.period_map(model, w, y + e)[0] - ti.period_map(model, w, y - e)[0]) / (2 * h)
        for e in h * np.eye(len(y))
    ]
    return np.column_stack(cols)


def three_dof() -> Model:
    """Coupled 3-DOF chain, non-diagonal K, C and unequal masses, three friction contacts."""
    K = 10 * np.array([[3.0, -1, 0], [-1, 2, -1], [0, -1, 1.5]])
    M = np.diag([1.0, 2, 0.5])
    friction = (
        FrictionContact.from_normal_load(0, None, 0.5, 2.0),
        FrictionContact.from_normal_load(1, 2, 0.4, 3.0),
        FrictionContact.from_normal_load(2, None, 1.0, 0.5),
    )
    return Model(
        M=M, C=0.002 * K + 0.01 * M, K=K, force_cos=[3.0, 0, 1], force_sin=[0, 1.0, 0], friction=friction
    )


# ---------------------------------------------------------------------------
# 1. linear limits
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("f", [0.4, 0.7, 1.3])
def test_stuck_limit_matches_rigid_frf(f):
    w = 2 * np.pi * f
    fex = 10.0
    model = paper_model(fex=fex, normal_load=1e6)  # mu F_N = 1e6 N: never slips
    X = fex / (K1 + K2 - 2 * w**2 + 1j * (C1 + C2) * w)  # u1 = u2 = X
    exact = harmonic_state(np.array([X, X]), w)
    assert rel(ti.period_map(model, w, exact)[0], exact) <= 1e-10
    sol = ti.shooting(model, w)
    assert sol.converged and sol.residual <= 1e-10
    assert rel(sol.y0, exact) <= 1e-9
    assert rel(sol.amplitude, np.abs([X, X])) <= 1e-9
    assert rel(sol.half_peak_to_peak, np.abs([X, X])) <= 1e-9
    # from a perturbed guess Newton lands on another member of the family of stuck orbits:
    # the same motion up to a static offset
    guess = exact + 0.05 * np.abs(exact).max() * np.array([1.0, 1.0, -2.0, -2.0])
    other = ti.shooting(model, w, guess)
    assert other.converged and other.residual <= 1e-10
    assert rel(other.velocity, sol.velocity) <= 1e-9
    assert rel(other.half_peak_to_peak, sol.half_peak_to_peak) <= 1e-9
    assert rel(other.amplitude, sol.amplitude) <= 1e-9
    assert np.all(sol.state == STICK) and not sol.events
    lam = (K2 - w**2 + 1j * C2 * w) * X  # mass-2 equation: lambda = m2 u2'' + c2 u2' + k2 u2
    assert rel(sol.contact_force[0], (lam * np.exp(1j * w * sol.time)).real) <= 1e-9
    assert np.all(sol.sliding_distance == 0) and np.all(sol.friction_energy == 0)
    # stuck the whole period: the relative velocity is annihilated (multiplier 0), the
    # stuck offset is neutral (multiplier 1), the other multipliers are viscous decay
    mult = np.abs(sol.floquet_multipliers)
    assert mult[0] == pytest.approx(1.0, abs=1e-12) and mult[-1] <= 1e-12
    assert np.allclose(mult[1:3], np.exp(-(C1 + C2) / 2 / 2 * sol.period), rtol=1e-9)


@pytest.mark.parametrize("f", [0.3, 0.7, 1.3])
def test_open_limit_matches_free_frf(f):
    w = 2 * np.pi * f
    fex = 10.0
    model = paper_model(fex=fex, normal_load=0.0)
    X1 = fex / (K1 - w**2 + 1j * C1 * w)
    exact = harmonic_state(np.array([X1, 0.0]), w)
    sol = ti.shooting(model, w, np.zeros(4))
    assert sol.converged and sol.residual <= 1e-10
    assert rel(sol.y0, exact) <= 1e-9
    assert rel(sol.amplitude, np.abs([X1, 0.0])) <= 1e-9
    assert rel(sol.half_peak_to_peak, np.abs([X1, 0.0])) <= 1e-9
    assert np.all(sol.state == OPEN) and np.all(sol.contact_force == 0)
    assert sol.stable


# ---------------------------------------------------------------------------
# 2. Den Hartog's exact solution
# ---------------------------------------------------------------------------
def den_hartog_amplitude(beta: float, ratio: float) -> float:
    """X / (F0 / k) for continuous sliding (Den Hartog 1931)."""
    V = np.sin(np.pi / beta) / (beta * (1 + np.cos(np.pi / beta)))
    return float(np.sqrt(1 / (1 - beta**2) ** 2 - (ratio * V) ** 2))


def exact_half_cycle(beta: float, ratio: float):
    """Exact symmetric half cycle of x'' + x = cos(beta t) - ratio sign(x'), sliding down from x = X.

    With s the time since the upper reversal and theta the forcing phase there,
    x = ratio + A cos s + B sin s + D (p cos(beta s) - q sin(beta s)),
    D = 1 / (1 - beta^2), p = cos(theta), q = sin(theta). The four reversal
    conditions x(0) = X, x'(0) = 0, x(pi/beta) = -X, x'(pi/beta) = 0 are
    linear in (A, B, X, p, q); p^2 + q^2 = 1 closes them.

    Returns
    -------
    X, max_velocity, stick_margin
        Amplitude, largest velocity inside the half cycle (< 0 if it does not
        stop) and ``|F(0) - k X| - ratio`` at the reversal (> 0 if it does not stick).
    """
    D, h = 1 / (1 - beta**2), np.pi / beta

    def rows(s):
        x = [np.cos(s), np.sin(s), 0.0, D * np.cos(beta * s), -D * np.sin(beta * s)]
        v = [-np.sin(s), np.cos(s), 0.0, -D * beta * np.sin(beta * s), -D * beta * np.cos(beta * s)]
        return np.array(x), np.array(v)

    x0, v0 = rows(0.0)
    x1, v1 = rows(h)
    e3 = np.array([0, 0, 1.0, 0, 0])
    A = np.array([x0 - e3, v0, x1 + e3, v1])
    rhs = np.array([-ratio, 0.0, -ratio, 0.0])
    part = np.linalg.lstsq(A, rhs, rcond=None)[0]
    null = np.linalg.svd(A)[2][-1]
    pq, dpq = part[3:], null[3:]
    roots = np.roots([dpq @ dpq, 2 * pq @ dpq, pq @ pq - 1])
    sols = [part + r.real * null for r in roots if abs(r.imag) < 1e-12]
    a, b, X, p, q = max(sols, key=lambda z: z[2])
    s = np.linspace(0.0, h, 20001)[1:-1]
    v = -a * np.sin(s) + b * np.cos(s) - D * beta * (p * np.sin(beta * s) + q * np.cos(beta * s))
    return X, v.max(), abs(p - X) - ratio


@pytest.mark.parametrize("beta", [0.6, 0.8, 1.5, 2.0])
@pytest.mark.parametrize("ratio", [0.1, 0.3])
def test_den_hartog_continuous_sliding(beta, ratio):
    X_exact = den_hartog_amplitude(beta, ratio)
    X_half, v_max, margin = exact_half_cycle(beta, ratio)
    assert X_half == pytest.approx(X_exact, rel=1e-10)  # two independent exact expressions agree
    assert v_max < 0 and margin > 0  # the exact motion neither stops inside a half cycle nor sticks
    sol = ti.shooting(coulomb_oscillator(ratio), beta)
    assert sol.converged and sol.residual <= 1e-10
    assert sol.half_peak_to_peak[0] == pytest.approx(X_exact, rel=1e-10)
    assert sol.relative_half_peak_to_peak[0] == pytest.approx(X_exact, rel=1e-10)
    assert [e.kind for e in sol.events] == ["reversal", "reversal"]
    assert not np.any(sol.state == STICK)
    assert np.all(np.abs(sol.contact_force) == pytest.approx(ratio))
    # continuous sliding: the slid distance is 4 X per period
    assert sol.sliding_distance[0] == pytest.approx(4 * X_exact, rel=1e-10)
    assert sol.stable


@pytest.mark.parametrize("beta, bracket", [(0.6, (0.5, 0.55)), (1.5, (0.6, 0.65))])
def test_den_hartog_boundary_zero_velocity_at_the_friction_limit(beta, bracket):
    """At Den Hartog's stop boundary the velocity vanishes exactly when the stuck force is at the limit."""
    ratio = brentq(lambda r: exact_half_cycle(beta, r)[2], *bracket, xtol=1e-15)
    for r in (ratio, ratio * (1 + 1e-9)):  # on the boundary, and just inside the stop regime
        sol = ti.shooting(coulomb_oscillator(r), beta)
        assert sol.converged and sol.residual <= 1e-10
        assert sol.half_peak_to_peak[0] == pytest.approx(den_hartog_amplitude(beta, r), rel=1e-10)


# ---------------------------------------------------------------------------
# 3. energy balance
# ---------------------------------------------------------------------------
def test_energy_balance_per_period_in_stick_slip():
    fex, w = 10.0, 2 * np.pi * 0.7
    stick_limit = fex * abs(K2 - w**2 + 1j * C2 * w) / abs(K1 + K2 - 2 * w**2 + 1j * (C1 + C2) * w)
    assert stick_limit > 10.0  # mu F_N = 10 N: the linear stuck solution would violate Coulomb's law
    sol = ti.shooting(paper_model(fex=fex), w)
    assert sol.converged and sol.residual <= 1e-10
    assert np.any(sol.state == SLIP) and np.any(sol.state == STICK)
    assert [e.kind for e in sol.events] == ["stick", "slip", "stick", "slip"]
    assert np.abs(sol.contact_force).max() <= 10.0 * (1 + 1e-12)
    dissipated = sol.viscous_dissipation + sol.friction_energy.sum()
    assert sol.input_work == pytest.approx(dissipated, rel=1e-9)
    assert sol.friction_energy[0] == pytest.approx(10.0 * sol.sliding_distance[0], rel=1e-14)
    # half-wave symmetry of the (unique) stick-slip orbit: u(t + T/2) = -u(t)
    half = ti.integrate(paper_model(fex=fex), w, sol.y0, 0.0, sol.period / 2).y
    assert rel(half, -sol.y0) <= 1e-10
    # exact first harmonic and refined extrema against a dense sampling of the orbit
    grid = np.arange(8192) * sol.period / 8192
    traj = ti.integrate(paper_model(fex=fex), w, sol.y0, 0.0, sol.period, samples=grid)
    c1 = np.fft.rfft(traj.states[:2], axis=1)[:, 1] * 2 / 8192
    assert rel(np.column_stack([c1.real, -c1.imag]), sol.first_harmonic) <= 1e-8  # FFT aliasing ~ N^-3
    dense = np.ptp(traj.states[:2], axis=1) / 2
    assert np.all(sol.half_peak_to_peak >= dense) and rel(sol.half_peak_to_peak, dense) <= 1e-7


def test_energy_identity_over_a_transient_with_several_contacts():
    model = three_dof()
    traj = ti.integrate(model, 3.0, np.zeros(6), 0.0, 7.3)
    u, v = traj.y[:3], traj.y[3:]
    energy = 0.5 * v @ model.M @ v + 0.5 * u @ model.K @ u
    assert len(traj.events) > 10 and set(np.unique(traj.segment_state)) == {STICK, SLIP}
    balance = traj.input_work - traj.viscous_dissipation - traj.friction_energy.sum()
    assert balance == pytest.approx(energy, rel=1e-9)
    # dense output reproduces the end state and is continuous across events
    assert rel(traj.evaluate([7.3])[0][:, 0], traj.y) <= 1e-13
    t_event = traj.events[0].time
    before, after = traj.evaluate([t_event * (1 - 1e-12), t_event])[0].T
    assert rel(before, after) <= 1e-9


# ---------------------------------------------------------------------------
# 4. periodicity and Floquet multipliers of the paper model
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("fex", [6.0, 10.0, 14.0])
@pytest.mark.parametrize("f", [0.6, 0.7, 0.9])
def test_paper_model_periodicity_and_floquet(fex, f):
    w = 2 * np.pi * f
    sol = ti.shooting(paper_model(fex=fex), w)
    assert sol.converged and sol.residual <= 1e-10
    assert ti.period_map(paper_model(fex=fex), w, sol.y0)[0] == pytest.approx(sol.y0, rel=1e-10, abs=1e-12)
    mult = np.abs(sol.floquet_multipliers)
    stick_limit = fex * abs(K2 - w**2 + 1j * C2 * w) / abs(K1 + K2 - 2 * w**2 + 1j * (C1 + C2) * w)
    if stick_limit <= 10.0:  # stuck all along: neutral stuck offset, annihilated relative velocity
        assert not sol.events and np.all(sol.state == STICK)
        assert mult[0] == pytest.approx(1.0, abs=1e-12) and mult[-1] <= 1e-12
        assert np.all(mult[1:] < 1)
    else:
        assert len(sol.events) == 4 and sol.stable
        assert mult[-1] <= 1e-12  # each sticking annihilates the relative velocity


def test_monodromy_matches_finite_differences():
    model, w = paper_model(fex=10.0), 2 * np.pi * 0.7
    sol = ti.shooting(model, w)
    y = sol.y0 + 1e-3 * np.array([0.1, -0.2, 0.3, 0.1])
    J = ti.integrate(model, w, y, 0.0, sol.period, jacobian=True).jacobian
    assert rel(J, fd_jacobian(model, w, y, 1e-6)) <= 1e-6


def test_several_contacts_jacobian_and_symmetry():
    model, w = three_dof(), 6.0
    sol = ti.shooting(model, w)
    assert sol.converged and sol.residual <= 1e-10 and sol.stable
    assert len(sol.events) >= 4
    assert sol.input_work == pytest.approx(sol.viscous_dissipation + sol.friction_energy.sum(), rel=1e-9)
    half = ti.integrate(model, w, sol.y0, 0.0, sol.period / 2).y
    assert rel(half, -sol.y0) <= 1e-10
    y = sol.y0 + 1e-3
    J = ti.integrate(model, w, y, 0.0, sol.period, jacobian=True).jacobian
    assert rel(J, fd_jacobian(model, w, y, 1e-7)) <= 1e-6


def test_free_mass_slip_closed_form():
    """Free mass (k = c = 0) on a Coulomb contact: singular (rigid-body) slip dynamics."""
    F, P, w = 1.0, 0.6, 2.0
    model = Model(
        M=[[1.0]],
        C=[[0.0]],
        K=[[0.0]],
        force_cos=[F],
        friction=(FrictionContact.from_normal_load(0, None, 1.0, P),),
    )
    # from rest at t = 0, F > P: slips forward with v = F sin(w t) / w - P t until v = 0 ...
    t_stop = brentq(lambda t: F * np.sin(w * t) / w - P * t, 0.5, np.pi / w, xtol=1e-15)
    x_stop = F * (1 - np.cos(w * t_stop)) / w**2 - P * t_stop**2 / 2
    assert abs(F * np.cos(w * t_stop)) < P  # ... then sticks ...
    t_slip = np.arccos(-P / F) / w  # ... until F cos(w t) = -P
    traj = ti.integrate(model, w, np.zeros(2), 0.0, 1.2 * t_slip)
    assert [(e.kind, e.direction) for e in traj.events] == [("stick", 0), ("slip", -1)]
    assert traj.events[0].time == pytest.approx(t_stop, rel=1e-13)
    assert traj.events[1].time == pytest.approx(t_slip, rel=1e-13)
    assert traj.evaluate([t_stop])[0][0, 0] == pytest.approx(x_stop, rel=1e-12)
    assert traj.evaluate([t_slip])[0][0, 0] == pytest.approx(x_stop, rel=1e-12)
    t_end = 1.2 * t_slip
    v_end = F * (np.sin(w * t_end) - np.sin(w * t_slip)) / w + P * (t_end - t_slip)
    assert traj.y[1] == pytest.approx(v_end, rel=1e-12)
    dt = t_end - t_slip
    dx_back = (
        F * (np.cos(w * t_slip) - np.cos(w * t_end)) / w**2 - F * np.sin(w * t_slip) / w * dt + P * dt**2 / 2
    )
    assert traj.sliding_distance[0] == pytest.approx(x_stop - dx_back, rel=1e-12)


# ---------------------------------------------------------------------------
# 5. time marching vs shooting
# ---------------------------------------------------------------------------
def test_steady_state_agrees_with_shooting():
    model, w = paper_model(fex=10.0), 2 * np.pi * 0.9
    shot = ti.shooting(model, w)
    marched = ti.steady_state(model, w, tol=1e-12)  # from the rigid linear solution
    assert marched.converged and marched.iterations > 50
    # |mu_max| = 0.87: the marched state is within ~ 1e-12 / (1 - 0.87) of the orbit
    assert rel(marched.y0, shot.y0) <= 1e-9
    assert rel(marched.half_peak_to_peak, shot.half_peak_to_peak) <= 1e-9
    assert rel(marched.sliding_distance, shot.sliding_distance) <= 1e-9


# ---------------------------------------------------------------------------
# 6. bad input
# ---------------------------------------------------------------------------
def test_bad_input():
    model = paper_model()
    for w in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="omega"):
            ti.period_map(model, w, np.zeros(4))
    with pytest.raises(ValueError, match="positive definite mass"):
        ti.shooting(jenkins_oscillator(), 1.0)
    normal = Model(
        M=np.eye(2), C=np.zeros((2, 2)), K=np.eye(2), force_cos=[1.0, 0], normal=(NormalContact(0, 1),)
    )
    with pytest.raises(ValueError, match="normal contacts"):
        ti.integrate(normal, 1.0, np.zeros(4), 0.0, 1.0)
    with pytest.raises(ValueError, match="contact node pairs"):  # not solved without its contacts
        ti.shooting(fw.paper_interface(), 1.0)
    with pytest.raises(ValueError, match="shape"):
        ti.integrate(model, 1.0, np.zeros(3), 0.0, 1.0)
    with pytest.raises(ValueError, match="shape"):
        ti.period_map(model, 1.0, np.zeros((2, 2)))
    with pytest.raises(ValueError, match="shape"):
        ti.shooting(model, 1.0, np.zeros(5))
    with pytest.raises(ValueError, match="t1 >= t0"):
        ti.integrate(model, 1.0, np.zeros(4), 1.0, 0.0)
    with pytest.raises(ValueError, match="samples"):
        ti.integrate(model, 1.0, np.zeros(4), 0.0, 1.0, samples=[2.0])
    redundant = Model(
        M=np.eye(2),
        C=np.zeros((2, 2)),
        K=np.eye(2),
        force_cos=[1.0, 0],
        friction=(FrictionContact.from_normal_load(0, 1, 1, 1), FrictionContact.from_normal_load(1, 0, 1, 1)),
    )
    with pytest.raises(ValueError, match="linearly independent"):
        ti.period_map(redundant, 1.0, np.zeros(4))


# ---------------------------------------------------------------------------
# 6. additions for the wear reference (fretwear.wear.time_integration)
# ---------------------------------------------------------------------------
def test_periodic_state_is_the_shooting_orbit():
    model, w = paper_model(fex=10), 2 * np.pi * 0.7
    sol = ti.shooting(model, w, wear=[3e-7])
    y, converged = ti.periodic_state(model, w, sol.y0 * 1.01, wear=[3e-7])
    assert converged
    assert rel(y, sol.y0) < 1e-9


@pytest.mark.parametrize("excess", [8.0, 12.0])
def test_stuck_force_held_at_the_friction_limit(excess):
    """A stuck contact whose force sits at the limit with zero rate is not an event (regression).

    Mass 2 at rest is held by contact 1 (to ground, slip force 2 N) against its
    spring and the constant slip force (10 N) of contact 0: its stuck force
    ``10 - k2 x2`` is at ``+-2 N`` up to ``2e-9`` relative and stays constant
    while contact 0 slips. Before the fix, an excess beyond the limit small
    enough for the state selection to keep the contact stuck triggered an
    event at once, forever (RuntimeError for about half of these states).
    """
    base = paper_model(fex=10)
    model = Model(
        M=base.M, C=base.C, K=base.K, force_cos=base.force_cos,
        friction=base.friction + (FrictionContact.from_normal_load(1, None, 1.0, 2.0),),
    )  # fmt: skip
    w = 2 * np.pi * 0.7
    for k in range(-20, 21):
        y0 = np.array([-0.4, excess / K2 * (1 + k * 1e-11), 0.3, 0.0])
        run = ti.integrate(model, w, y0, 0.0, 2 * np.pi / w)
        if abs(k) <= 5:  # within round-off of the limit: contact 1 stays stuck until contact 0 changes
            assert run.segment_state[0, 1] == STICK and run.events[0].contact == 0
