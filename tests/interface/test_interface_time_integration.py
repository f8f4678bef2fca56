"""Direct time integration of the benchmark interface against the harmonic balance and the stepping."""

import numpy as np
import pytest

from fretwear.interface.contact import OPEN, SLIP
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.time_integration import initial_state, integrate_interface
from fretwear.interface.wear import wear_interface
from fretwear.model import craig_bampton

OMEGA = 2 * np.pi * 50.0
SAMPLES = 128  # records per period, a divisor of every DLFT grid used here


@pytest.fixture(scope="module")
def partial():
    """8 pairs, Q0 = 0.5 mu P; one reduction (fixed-interface modes to 1 kHz) shared by every Nh."""
    model = cylinder_on_flat(contact_nodes=8, q_ratio=0.5)
    cond = ContactCondensation(craig_bampton(model, 1000.0))
    sols = {nh: solve_interface(InterfaceProblem(cond, OMEGA, harmonics=nh)) for nh in (7, 15, 31)}
    z0, v0, X0, st0 = initial_state(sols[31])
    runs = {
        steps: integrate_interface(
            cond, OMEGA, z0, v0, X0, st0, periods=4, steps_per_period=steps, samples_per_period=SAMPLES
        )  # fmt: skip
        for steps in (128, 512, 2048)
    }
    return model, sols, runs


def _last_period_errors(run, sol):
    """Largest differences over the last period: lambda_T / (mu P_max), lambda_N / P_max, u_T / max u_T."""
    idx = (np.arange(SAMPLES) + 1) % SAMPLES * (sol.problem.basis.marched_samples // SAMPLES)
    lam, q = run.forces[-SAMPLES:], run.contact[-SAMPLES:]
    scale = sol.normal_force.max()
    nh = sol.problem.harmonics
    t = 2 * np.pi * idx / sol.problem.basis.marched_samples
    k = np.arange(1, nh + 1)
    h = sol.contact_harmonics[0::2]  # u_T harmonics per pair
    uT = h[:, :1] + h[:, 1::2] @ np.cos(np.outer(k, t)) + h[:, 2::2] @ np.sin(np.outer(k, t))
    return (
        np.abs(lam[:, 0::2] - sol.tangential_force[:, idx].T).max() / (0.6 * scale),
        np.abs(lam[:, 1::2] - sol.normal_force[:, idx].T).max() / scale,
        np.abs(q[:, 0::2] - uT.T).max() / np.abs(uT).max(),
    )


def test_time_integration_reaches_a_periodic_state(partial):
    _, _, runs = partial
    for run in runs.values():
        assert run.converged, run.message
        E = run.energy_per_period.sum(axis=1)
        assert E[-1] > 0 and abs(E[-1] / E[-2] - 1) < 1e-9  # periodic after the first periods
        closed = run.state != OPEN
        lamT, lamN = run.forces[:, 0::2], run.forces[:, 1::2]
        assert np.all(lamN[closed] > 0) and np.all(np.abs(lamT) <= 0.6 * lamN * (1 + 1e-9) + 1e-6)
        assert np.any(run.state == SLIP)


def test_time_integration_converges_to_first_order(partial):
    """Friction work per period: backward Euler's error falls with the step (measured 5e-6 -> 6e-7)."""
    _, _, runs = partial
    E = {s: r.energy_per_period[-1].sum() for s, r in runs.items()}
    e128, e512 = abs(E[128] / E[2048] - 1), abs(E[512] / E[2048] - 1)
    assert e512 < 0.5 * e128 and e128 < 1e-4


def test_harmonic_balance_converges_to_the_time_integration(partial):
    """DLFT at Nh = 7, 15, 31 against 2048 steps per period: every difference shrinks with Nh.

    Measured: tangential force 6.0e-2, 2.2e-2, 1.2e-2 of mu P_max; normal force 5e-6, 2e-6, 7e-7 of P_max;
    friction work per period 2.5e-3, 6.2e-3, 2.9e-4 (not monotone: the Gibbs ripple at the transitions).
    """
    model, sols, runs = partial
    run = runs[2048]
    errs = {nh: _last_period_errors(run, sol) for nh, sol in sols.items()}
    for j in range(3):  # tangential force, normal force, tangential displacement
        assert errs[31][j] < errs[15][j] < errs[7][j], (j, errs)
    assert errs[31][0] < 2e-2 and errs[31][1] < 1e-5 and errs[31][2] < 1e-2
    E = run.energy_per_period[-1].sum()
    for nh, sol in sols.items():
        assert E == pytest.approx(sol.friction_energy, rel=1e-2 if nh < 31 else 1e-3)
    # the pressure integral is the normal load at every step, but for the pad's vertical inertia (1e-8 P)
    assert np.abs(run.forces[:, 1::2].sum(axis=1) / model.info["normal_load"] - 1).max() < 1e-7


def test_short_wear_run_matches_the_slow_time_stepping():
    """100 cycles of direct integration with Archard's law at every step against wear_interface (Nh = 7).

    Measured: worn depths 1.5e-2 of the largest, worn area 1.3e-2 (Nh = 11: 9.5e-3, 9.5e-3); the
    difference is the DLFT's O(1/Nh) error on the slip, not the time step (256 and 1024 steps agree).
    """
    model = cylinder_on_flat(contact_nodes=12, q_ratio=0.5)
    cond = ContactCondensation(craig_bampton(model, 1000.0))
    kw, cycles = 3e-11, 100
    hist = wear_interface(InterfaceProblem(cond, OMEGA, harmonics=7), kw, cycles, rtol=1e-2)
    assert hist.converged
    run = integrate_interface(cond, OMEGA, *initial_state(hist.solutions[0]), periods=cycles,
                              steps_per_period=256, kw=kw, samples_per_period=4)  # fmt: skip
    assert run.converged, run.message
    w_ref, w = hist.wear[-1], run.wear[-1]
    assert w_ref.max() > 0 and np.abs(w - w_ref).max() <= 3e-2 * w_ref.max()
    assert w @ hist.area == pytest.approx(w_ref @ hist.area, rel=3e-2)
    assert np.all(w[w_ref == 0] == 0)  # the stick zone stays unworn in both


def test_input_checks(partial):
    model, sols, _ = partial
    cond = sols[7].problem.condensation
    z0, v0, X0, st0 = initial_state(sols[7])
    with pytest.raises(ValueError, match="steps_per_period"):
        integrate_interface(cond, OMEGA, z0, v0, X0, st0, periods=1, steps_per_period=4)
    with pytest.raises(ValueError, match="samples_per_period"):
        integrate_interface(
            cond, OMEGA, z0, v0, X0, st0, periods=1, steps_per_period=64, samples_per_period=7
        )
    with pytest.raises(ValueError, match="kw must be"):
        integrate_interface(cond, OMEGA, z0, v0, X0, st0, periods=1, kw=-1.0)
