"""Exact event-driven dynamics of Jenkins contacts (fretwear.time with ``FrictionContact(..., kt=...)``).

Checked against the independent event-driven ``solve_ivp`` integration of
tests/hbm/test_jenkins.py (extrema refined on its dense output), the linear
limits (stuck: the springs ``k_t``; vanishing slip force: no contacts), the
energy balance of a period with the analytical hysteresis loop, the monodromy
against finite differences of the period map, and, on the bladed disk with its
closed ring of shroud contacts, the cyclic symmetry of the tuned disk and DLFT
converging towards it with the harmonics.
"""

import importlib.util
import warnings
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq, fsolve

import fretwear as fw
import fretwear.time as ti
from fretwear.model import STICK, FrictionContact, Model, jenkins_oscillator

_spec = importlib.util.spec_from_file_location(
    "_hbm_jenkins", Path(__file__).parents[1] / "hbm" / "test_jenkins.py"
)
hbm_jenkins = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(hbm_jenkins)
oscillator, SLIP, KT = hbm_jenkins.oscillator, hbm_jenkins.SLIP, hbm_jenkins.KT


def _reference_half_peak_to_peak(omega: float) -> float:
    """tests/hbm/test_jenkins.py's reference orbit, its extrema refined to round-off on the dense output.

    (Its own ``reference_half_peak_to_peak`` takes the extrema of 40001 samples: ~1e-9 off.)
    """
    z = np.zeros(3)
    for _ in range(40):
        z = hbm_jenkins._period(z, omega, 1e-9, 1e-12)[0]
    with warnings.catch_warnings():  # fsolve's progress warning near its xtol (the orbit is checked below)
        warnings.filterwarnings("ignore", "The iteration is not making good progress")
        z = fsolve(lambda z: hbm_jenkins._period(z, omega)[0] - z, z, xtol=1e-13)
    zT, pieces = hbm_jenkins._period(z, omega, record=True)
    assert np.abs(zT - z).max() < 1e-12
    x = []
    for p in pieces:
        t = np.linspace(p.t[0], p.t[-1], 2001)
        x += list(p.sol(t)[0])
        v = p.sol(t)[1]
        for i in np.flatnonzero(np.sign(v[:-1]) * np.sign(v[1:]) < 0):  # velocity zeros: the extrema
            x.append(p.sol(brentq(lambda s, p=p: p.sol(s)[1], t[i], t[i + 1], xtol=1e-15))[0])
    return (max(x) - min(x)) / 2


def _linear(model: Model, omega: float, springs: bool) -> np.ndarray:
    """First-harmonic ``[a1, b1]`` per DOF of the linear structure, with the springs ``k_t`` or none."""
    K = model.K
    if springs:
        B = model.relative_map(model.friction)
        K = K + B.T @ (np.array([c.kt for c in model.friction])[:, None] * B)
    U = np.linalg.solve(K - omega**2 * model.M + 1j * omega * model.C, model.force_cos - 1j * model.force_sin)
    return np.stack([U.real, -U.imag], axis=1)


def _jenkins_chain(slip: float = 0.05) -> Model:
    """tests/hbm/test_jenkins.py's 3-mass chain with its three contacts all Jenkins (k_t = 3)."""
    model = hbm_jenkins.chain()
    return Model(
        M=model.M, C=model.C, K=model.K, force_cos=model.force_cos,
        friction=tuple(FrictionContact.from_normal_load(c.dof, c.other, 1.0, slip, kt=3.0)
                       for c in model.friction),
    )  # fmt: skip


# -- 1. the 1-DOF oscillator against the independent integration --------------------------------------


@pytest.mark.parametrize("omega", [0.7, 1.4, 2.0])
def test_oscillator_against_independent_integration(omega):
    """Half peak-to-peak to 1e-9 (measured 7e-13, 1e-13, 6e-13); stable orbit (multipliers inside)."""
    sol = ti.shooting(oscillator(), omega)
    assert sol.converged, sol.message
    exact = _reference_half_peak_to_peak(omega)
    assert sol.half_peak_to_peak[0] == pytest.approx(exact, rel=1e-9, abs=0)
    assert sol.stable
    rest = np.sort(np.abs(sol.floquet_multipliers))[: len(sol.y0) - sol.neutral_multipliers]
    assert rest.max() < 1.0
    slipping = bool(sol.events)
    assert sol.neutral_multipliers == (0 if slipping else 1)  # a stuck orbit: the slider's offset is free
    assert slipping == (omega == 1.4)
    force = sol.contact_force[0]
    assert np.abs(force).max() <= SLIP * (1 + 1e-12)
    if slipping:  # force and state: at the slip force exactly while slipping
        assert np.allclose(np.abs(force[sol.state[0] != STICK]), SLIP, rtol=1e-12)


def test_monodromy_matches_finite_differences():
    """The saltation of stick -> slip (I - e e^T) and slip -> stick (none) in the exact monodromy."""
    model, omega = oscillator(), 1.4
    sol = ti.shooting(model, omega)
    y0 = sol.y0
    J = ti.integrate(model, omega, y0, 0.0, sol.period, jacobian=True).jacobian
    FD = np.empty_like(J)
    for j in range(3):
        h = 1e-7 * max(abs(y0[j]), 1e-3)
        e = np.zeros(3)
        e[j] = h
        FD[:, j] = (ti.period_map(model, omega, y0 + e)[0] - ti.period_map(model, omega, y0 - e)[0]) / (2 * h)
    # the force at t = 0 is stuck (inside the cone): its perturbation matters, as u's and v's do
    assert np.abs(y0[2]) < SLIP
    assert np.abs(FD - J).max() <= 1e-6 * np.abs(J).max()
    assert np.allclose(sol.monodromy, J, rtol=0, atol=1e-12 * np.abs(J).max())
    # from a state in slip: the force's perturbation is lost (a zero column), the others propagate
    slipping = np.flatnonzero(sol.state[0] != STICK)
    t0 = sol.time[slipping[len(slipping) // 2]]
    ys = sol.trajectory.evaluate([t0])[0][:, 0]
    ys = np.append(ys, sol.contact_force[0, slipping[len(slipping) // 2]])
    assert abs(ys[2]) == pytest.approx(SLIP, rel=1e-14)

    def flow(y):
        return ti.integrate(model, omega, y, t0, t0 + sol.period).y

    J = ti.integrate(model, omega, ys, t0, t0 + sol.period, jacobian=True).jacobian
    for j in range(3):
        h = 1e-7 * max(abs(ys[j]), 1e-3)
        e = np.zeros(3)
        e[j] = h
        FD[:, j] = (flow(ys + e) - flow(ys - e)) / (2 * h)
    assert np.all(J[:, 2] == 0)
    assert np.abs(FD - J).max() <= 1e-6 * np.abs(J).max()


def test_steady_state_marches_to_the_shooting_orbit():
    """Plain time marching (no Newton, no monodromy) settles on the orbit shooting finds."""
    model, omega = oscillator(), 1.4
    sol = ti.shooting(model, omega)
    marched = ti.steady_state(model, omega, tol=1e-13)
    assert marched.converged, marched.message
    assert marched.half_peak_to_peak[0] == pytest.approx(sol.half_peak_to_peak[0], rel=1e-10)
    np.testing.assert_allclose(marched.y0, sol.y0, rtol=0, atol=1e-10 * np.abs(sol.y0).max())
    X = marched.relative_half_peak_to_peak[0]
    assert marched.friction_energy[0] == pytest.approx(4 * SLIP * (X - SLIP / KT), rel=1e-9)  # the loop


# -- 2. limits ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("make", [oscillator, _jenkins_chain], ids=["oscillator", "chain"])
@pytest.mark.parametrize("omega", [0.7, 1.4])
def test_stuck_and_sliding_limits(make, omega):
    """Huge slip force: the linear structure with the springs k_t; vanishing: without contacts (1e-10)."""
    for slip, springs in ((1e6, True), (1e-14, False)):
        model = make(slip)
        sol = ti.shooting(model, omega)
        assert sol.converged, sol.message
        lin = _linear(model, omega, springs)
        assert np.abs(sol.first_harmonic - lin).max() <= 1e-10 * np.abs(lin).max()
        amplitude = np.hypot(lin[:, 0], lin[:, 1])
        assert np.allclose(sol.half_peak_to_peak, amplitude, rtol=1e-10, atol=0)
    worn = make(SLIP)  # normal loads clipped at zero by wear: open contacts, no force
    sol = ti.shooting(worn, omega, wear=[2 * c.u0 for c in worn.friction])
    lin = _linear(worn, omega, False)
    assert np.abs(sol.first_harmonic - lin).max() <= 1e-10 * np.abs(lin).max()
    assert np.all(sol.contact_force == 0)


# -- 3. energy ----------------------------------------------------------------------------------------------


@pytest.mark.parametrize("omega", [1.2, 1.4, 1.7])
def test_energy_balance_and_hysteresis_loop(omega):
    """Input work = viscous + friction dissipation (1e-10 of the input); friction: the loop 4 L (X - L/kt)."""
    sol = ti.shooting(oscillator(), omega)
    assert sol.converged and sol.events
    assert abs(sol.input_work - sol.viscous_dissipation - sol.friction_energy.sum()) <= 1e-10 * sol.input_work
    X = sol.relative_half_peak_to_peak[0]
    loop = 4 * SLIP * (X - SLIP / KT)
    assert sol.friction_energy[0] == pytest.approx(loop, rel=1e-10)
    assert sol.sliding_distance[0] == pytest.approx(4 * (X - SLIP / KT), rel=1e-10)  # the slider's travel


def test_energy_balance_with_several_contacts():
    """Three Jenkins contacts, each in partial slip: the balance to 1e-10 of the input work; DLFT at
    Nh = 21 within 1e-4 of the orbit (measured 1.7e-5)."""
    sol = ti.shooting(_jenkins_chain(), 0.8)
    dlft = fw.solve_periodic(_jenkins_chain(), 0.8, 21, samples=4096)
    assert np.abs(dlft.half_peak_to_peak / sol.half_peak_to_peak - 1).max() <= 1e-4
    assert sol.converged, sol.message
    slip = (sol.state != STICK).mean(axis=1)
    assert np.all((slip > 0.05) & (slip < 0.95))
    assert abs(sol.input_work - sol.viscous_dissipation - sol.friction_energy.sum()) <= 1e-10 * sol.input_work
    assert sol.stable


# -- 4. the bladed disk: a closed ring of shroud contacts ---------------------------------------------------

#: sectors -> a frequency (Hz) where the shroud is in partial slip under EO 1, fex = 1 N (DLFT: 25 %, 52 %)
DISK_PARTIAL_SLIP = {3: 315.0, 6: 245.0}


@pytest.mark.parametrize("sectors", [3, 6])
def test_bladed_disk_shroud_ring(sectors):
    """Shooting converges on the ring (B of rank N - 1); tuned blades equal (1e-9); DLFT tends to it.

    Measured relative errors of the tip's half peak-to-peak, DLFT (4096 samples) against shooting:
    3 sectors at 315 Hz: 4.7e-4, 1.0e-5, 5.9e-8 at Nh = 5, 11, 21; 6 sectors at 245 Hz: 1.3e-4,
    1.2e-5, 5.4e-6. Blades equal to 4e-14, energy balance to 2e-13.
    """
    model = fw.bladed_disk(sectors, engine_order=1, fex=1.0)
    assert np.linalg.matrix_rank(model.relative_map(model.friction)) == sectors - 1
    omega = 2 * np.pi * DISK_PARTIAL_SLIP[sectors]
    sol = ti.shooting(model, omega)
    assert sol.converged, sol.message
    tips = sol.half_peak_to_peak[2::3]
    assert np.abs(tips / tips[0] - 1).max() <= 1e-9
    slip = (sol.state != STICK).mean(axis=1)
    assert np.all((slip > 0.05) & (slip < 0.95))  # partial slip at every contact
    assert abs(sol.input_work - sol.viscous_dissipation - sol.friction_energy.sum()) <= 1e-10 * sol.input_work
    assert sol.stable
    errors = []
    for harmonics in (5, 11, 21):
        dlft = fw.solve_periodic(model, omega, harmonics, samples=4096)
        assert dlft.converged
        errors.append(abs(dlft.half_peak_to_peak[2] / tips[0] - 1))
    assert errors[2] <= 2e-5
    assert errors[0] > errors[1] > errors[2]


def test_simultaneous_events_and_mistuned_disk():
    """Two identical oscillators: every event of the two contacts at one instant, each the 1-DOF orbit;
    a mistuned 6-sector disk (blades unequal): DLFT at Nh = 21 within 1e-4 of shooting (measured 7.6e-6)."""
    twins = Model(
        M=np.eye(2), C=0.02 * np.eye(2), K=np.eye(2), force_cos=[0.1, 0.1],
        friction=tuple(FrictionContact.from_normal_load(i, None, 1.0, SLIP, kt=KT) for i in range(2)),
    )  # fmt: skip
    sol = ti.shooting(twins, 1.4)
    assert sol.converged and sol.stable and len(sol.events) == 8
    exact = _reference_half_peak_to_peak(1.4)
    np.testing.assert_allclose(sol.half_peak_to_peak, exact, rtol=1e-9)
    disk = fw.bladed_disk(6, engine_order=1, fex=1.0, mistuning=[0.02, -0.01, 0.03, 0.0, -0.02, 0.01])
    omega = 2 * np.pi * 245.0
    sol = ti.shooting(disk, omega)
    assert sol.converged and sol.stable
    tips = sol.half_peak_to_peak[2::3]
    assert tips.max() / tips.min() > 1.2
    dlft = fw.solve_periodic(disk, omega, 21, samples=4096)
    assert np.abs(dlft.half_peak_to_peak[2::3] / tips - 1).max() <= 1e-4


# -- 5. bad input --------------------------------------------------------------------------------------------


def test_bad_input():
    mixed = hbm_jenkins.chain()  # two Jenkins contacts and a rigid one
    with pytest.raises(ValueError, match="all rigid or all Jenkins"):
        ti.shooting(mixed, 1.0)
    with pytest.raises(ValueError, match="massless DOFs"):  # the slider-DOF model: kt belongs in the contact
        ti.shooting(jenkins_oscillator(), 1.0)
    with pytest.raises(ValueError, match=r"\(u, v, lambda\) .* shape \(3,\)"):
        ti.integrate(oscillator(), 1.0, np.zeros(2), 0.0, 1.0)
    with pytest.raises(ValueError, match=r"shape \(3,\)"):
        ti.shooting(oscillator(), 1.0, np.zeros(2))
    for message in (str(e) for e in _errors(mixed)):
        assert "\n" not in message


def _errors(model):
    for call in (lambda: ti.shooting(model, 1.0), lambda: ti.integrate(model, 1.0, np.zeros(6), 0.0, 1.0)):
        try:
            call()
        except ValueError as exc:
            yield exc


def test_exact_wear_dynamics_still_refuse_jenkins_contacts():
    """The wear code's check (patterns.unsupported without ``jenkins``) names them: they wear on DLFT."""
    from fretwear.time.patterns import unsupported

    assert "Jenkins" in unsupported(oscillator())
    assert unsupported(oscillator(), jenkins=True) is None
    assert unsupported(fw.bladed_disk(3), jenkins=True) is None
