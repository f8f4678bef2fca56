"""Jenkins contacts (Coulomb friction with a tangential stiffness k_t in series) in harmonic balance.

The force is an alternating frequency-time law (:mod:`fretwear.hbm.dlft`, kind
``JENKINS``). Checked against an independent event-driven time integration
of the same ODE with the exact return map, against the linear limits (stuck:
the spring ``k_t``; sliding: no contact), against the energy balance of a
period with the analytical hysteresis loop, and its Jacobian against finite
differences.
"""

import tomllib

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import fsolve

import fretwear as fw
from fretwear.hbm import dlft
from fretwear.hbm.continuation import _frequency_evaluate
from fretwear.hbm.periodic import Problem, load_homotopy, newton
from fretwear.model import FrictionContact, Model, jenkins_oscillator
from fretwear.model.modelfile import dumps_model, model_from_dict

#: the 1-DOF oscillator of issue 24: m, c, k, k_t, slip force, forcing amplitude
M, C, K, KT, SLIP, FORCE = 1.0, 0.02, 1.0, 1.0, 0.1, 0.1
CHAIN_K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])


def oscillator(slip: float = SLIP) -> Model:
    """Mass on a spring ``k`` with a Jenkins contact (``k_t``, slip force ``slip``) to ground."""
    return Model(
        M=[[M]], C=[[C]], K=[[K]], force_cos=[FORCE],
        friction=(FrictionContact.from_normal_load(0, None, 1.0, slip, kt=KT),),
    )  # fmt: skip


def chain(slips=(0.05, 0.05, 0.05)) -> Model:
    """3 masses in a chain; Jenkins contacts 1-2 (k_t = 2) and 3-ground (k_t = 1), rigid friction 2-3."""
    return Model(
        M=np.eye(3), C=0.02 * CHAIN_K, K=CHAIN_K, force_cos=[0.1, 0.0, 0.0],
        friction=(
            FrictionContact.from_normal_load(0, 1, 1.0, slips[0], kt=2.0),
            FrictionContact.from_normal_load(2, None, 1.0, slips[1], kt=1.0),
            FrictionContact.from_normal_load(1, 2, 1.0, slips[2]),
        ),
    )  # fmt: skip


# -- the independent reference: event-driven integration with the exact return map -----------------


def _period(z, omega, rtol=1e-12, atol=1e-14, record=False):
    """State ``(x, v, f)`` after one period, ``f`` the Jenkins force; stick ``f' = k_t v``, slip ``f = +-L``.

    Events: stick -> slip when ``f`` reaches ``+-L``; slip -> stick when the
    velocity vanishes (DOP853 with event location on each smooth phase).
    """
    T = 2 * np.pi / omega
    x, v, f = z
    t, slip, pieces = 0.0, 0, []
    if abs(f) >= SLIP * (1 - 1e-13) and f * v > 0:
        slip = int(np.sign(f))
    while t < T:
        if slip == 0:

            def rhs(t, y):
                return [y[1], (FORCE * np.cos(omega * t) - C * y[1] - K * y[0] - y[2]) / M, KT * y[1]]

            def up(t, y):
                return y[2] - SLIP

            def down(t, y):
                return y[2] + SLIP

            up.terminal = down.terminal = True
            up.direction, down.direction = 1, -1
            events = [up, down]
        else:

            def rhs(t, y, sg=slip):
                return [y[1], (FORCE * np.cos(omega * t) - C * y[1] - K * y[0] - sg * SLIP) / M, 0.0]

            def stop(t, y, sg=slip):
                return sg * y[1]

            stop.terminal, stop.direction = True, -1
            events = [stop]
        sol = solve_ivp(rhs, (t, T), [x, v, f], "DOP853", rtol=rtol, atol=atol, events=events,
                        dense_output=record)  # fmt: skip
        pieces.append(sol)
        (x, v, f), t = sol.y[:, -1], sol.t[-1]
        if sol.status == 1:  # an event ended the phase
            if slip == 0:
                slip = 1 if sol.t_events[0].size else -1
                f = slip * SLIP
            else:
                slip, v = 0, 0.0
    return np.array([x, v, f]), pieces


def reference_half_peak_to_peak(omega: float) -> float:
    """Half peak-to-peak of the periodic orbit: transient marched out, then shooting on ``(x, v, f)``."""
    z = np.zeros(3)
    for _ in range(40):
        z = _period(z, omega, 1e-9, 1e-12)[0]
    z, info, ier, msg = fsolve(lambda z: _period(z, omega)[0] - z, z, xtol=1e-13, full_output=True)
    zT, pieces = _period(z, omega, record=True)
    assert np.abs(zT - z).max() < 1e-12, msg
    t = np.linspace(0, 2 * np.pi / omega, 40001)
    x = np.concatenate([p.sol(t[(t >= p.t[0]) & (t <= p.t[-1])])[0] for p in pieces])
    return (x.max() - x.min()) / 2


def test_against_exact_time_integration():
    """Nh = 21 at W = 1.4: within 1e-4 of the exact orbit (measured 7e-6); DLFT with a slider DOF, 0.27 %."""
    exact = reference_half_peak_to_peak(1.4)
    sol = fw.solve_periodic(oscillator(), 1.4, 21)
    assert sol.converged
    error = abs(sol.half_peak_to_peak[0] / exact - 1)
    slider = fw.solve_periodic(jenkins_oscillator(M, C, K, KT, SLIP, FORCE), 1.4, 21)
    error_slider = abs(slider.half_peak_to_peak[0] / exact - 1)
    assert error <= 1e-4
    assert error_slider > 100 * error  # the kinks of the slider's own motion, truncated


# -- limits --------------------------------------------------------------------------------------------


def _linear(model: Model, omega: float, K_extra: np.ndarray) -> np.ndarray:
    """First-harmonic coefficients ``[a1, b1]`` per DOF of the linear structure ``K + K_extra``."""
    D = model.K + K_extra - omega**2 * model.M + 1j * omega * model.C
    U = np.linalg.solve(D, model.force_cos - 1j * model.force_sin)
    return np.stack([U.real, -U.imag], axis=1)


def _spring_matrix(model: Model) -> np.ndarray:
    B = model.relative_map(model.friction)
    kt = np.array([c.kt for c in model.friction])
    return B.T @ (kt[:, None] * B)


def _jenkins_chain(slip: float) -> Model:
    model = chain()
    return Model(
        M=model.M, C=model.C, K=model.K, force_cos=model.force_cos,
        friction=tuple(FrictionContact.from_normal_load(c.dof, c.other, 1.0, slip, kt=3.0)
                       for c in model.friction),
    )  # fmt: skip


@pytest.mark.parametrize("make", [oscillator, _jenkins_chain], ids=["oscillator", "chain"])
@pytest.mark.parametrize("omega", [0.7, 1.4])
def test_stuck_and_sliding_limits(make, omega, assert_linear):
    """Huge slip force: the linear structure with the springs k_t; vanishing: without the contacts."""
    for slip, springs in ((1e6, True), (1e-14, False)):
        model = make(slip)
        sol = fw.solve_periodic(model, omega, 9)
        assert sol.converged and np.abs(sol.dof_harmonics[:, 0]).max() == 0.0  # no mean: the half-wave basis
        assert_linear(sol, model, omega, _spring_matrix(model) if springs else 0.0)
    scale = np.abs(_linear(make(SLIP), omega, 0.0)).max()
    worn = make(SLIP)  # normal load clipped at zero by wear: no contact
    sol = fw.solve_periodic(worn, omega, 9, wear=[2 * c.u0 for c in worn.friction])
    assert np.abs(sol.dof_harmonics[:, 1:3] - _linear(worn, omega, 0.0)).max() <= 1e-10 * scale


def test_full_stick_force_is_spring_force_about_the_mean():
    """Full stick: f = k_t (x - mean x) on every sample (the centred slider of the module's text)."""
    model = oscillator(1e3)
    sol = fw.solve_periodic(model, 0.9, 5, half_wave=False)
    x = sol.relative_displacement[0]
    np.testing.assert_allclose(sol.contact_force[0], KT * (x - x.mean()), rtol=0, atol=1e-12)
    assert np.all(sol.state[0] == dlft.STICK)


# -- energy ---------------------------------------------------------------------------------------------


@pytest.mark.parametrize("omega", [1.2, 1.4, 1.7])
def test_energy_balance_with_the_hysteresis_loop(omega):
    """Input work = viscous dissipation + 4 L (X - L / k_t), the area of the loop of amplitude X.

    Judged against the friction dissipation (the loop), to 5e-4 of it at Nh = 21
    (measured 2e-5 to 1.5e-4, falling with Nh and the samples); leaving out the
    stick part ``L / k_t`` of the loop would be off 15-fold at W = 1.7.
    """
    sol = fw.solve_periodic(oscillator(), omega, 21)
    assert sol.slipping[0]
    X = sol.relative_half_peak_to_peak[0]
    loop = 4 * SLIP * (X - SLIP / KT)
    assert abs(sol.input_work - sol.viscous_dissipation - loop) <= 5e-4 * loop
    assert abs(sol.friction_energy[0] - loop) <= 5e-4 * loop  # sum f dX on the grid, X the slider


# -- the law's derivatives and solvers ----------------------------------------------------------------


def test_jacobian_matches_finite_differences_in_partial_slip():
    """Jenkins rows ``Z + k_t A``, rigid rows ``Z + A (E - Z)``: every contact in partial slip."""
    problem = Problem(chain(), 0.8, 7, samples=256)
    x = fw.solve_periodic(chain(), 0.8, 7, samples=256).unknowns
    R, J, _, _, _, state = problem.evaluate(x)
    slip = (state == dlft.SLIP).mean(axis=1)
    assert np.all((slip > 0.2) & (slip < 0.8))
    assert list(problem.kinds) == [dlft.JENKINS, dlft.JENKINS, dlft.FRICTION]
    h = 1e-7 * np.abs(x).max()
    FD = np.empty_like(J)
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h
        FD[:, j] = (problem.evaluate(x + e, False)[0] - problem.evaluate(x - e, False)[0]) / (2 * h)
    assert np.abs(FD - J).max() <= 1e-6 * np.abs(J).max()


def test_newton_lands_in_one_step_near_the_solution():
    """Piecewise-linear residual, exact Jacobian: from a close start, one step, then done."""
    sol = fw.solve_periodic(chain(), 0.8, 7, samples=256)
    problem = Problem(chain(), 0.8, 7, samples=256)
    rng = np.random.default_rng(1)
    start = sol.unknowns * (1 + 1e-6 * rng.standard_normal(sol.unknowns.size))
    res = newton(problem, start, tol=1e-12)
    assert res.converged and res.iterations <= 2
    assert np.abs(res.x - sol.unknowns).max() <= 1e-10 * np.abs(sol.unknowns).max()


def test_load_walk_reaches_the_newton_solution():
    """The exact load continuation (Jenkins dR/dp and state boundaries on k_t x) ends at the solution."""
    problem = Problem(chain(), 0.8, 7, samples=256)
    walked = load_homotopy(problem, tol=1e-12)
    assert walked.converged and walked.iterations > 10  # pieces crossed
    direct = fw.solve_periodic(chain(), 0.8, 7, samples=256)
    assert np.abs(walked.x - direct.unknowns).max() <= 1e-9 * np.abs(direct.unknowns).max()


def test_sweep_and_single_solves_equal_the_point_by_point_solves():
    """fw.sweep and fw.solve_periodic route Jenkins models to the solves in x (the compiled sweep's
    augmented unknowns do not carry the law): the point-by-point sweep (``compiled=False``)."""
    omegas = np.linspace(0.5, 2.5, 21)
    sweep = fw.sweep(oscillator(), omegas, 11)
    reference = fw.sweep(oscillator(), omegas, 11, compiled=False)
    assert sweep.converged.all() and reference.converged.all()
    assert sum(s.slipping[0] for s in sweep.solutions) > 5
    for sol, ref in zip(sweep.solutions, reference.solutions, strict=True):
        np.testing.assert_allclose(sol.dof_harmonics, ref.dof_harmonics, rtol=0, atol=1e-10 * FORCE)
    single = fw.solve_periodic(oscillator(), 1.4, 11)
    np.testing.assert_allclose(single.dof_harmonics, reference.solutions[9].dof_harmonics, atol=1e-10 * FORCE)


def test_frequency_derivative_for_continuation():
    """d R / d omega of the arc-length continuation: Jenkins rows ``dZ x - dF`` (their force has no omega)."""
    evaluate = _frequency_evaluate(chain(), dict(harmonics=5, samples=128, wear=None, half_wave=None), None)
    x = fw.solve_periodic(chain(), 0.8, 5, samples=128).unknowns
    w, h = 0.8, 1e-7
    fd = (evaluate(x, w + h)[0] - evaluate(x, w - h)[0]) / (2 * h)
    np.testing.assert_allclose(evaluate(x, w)[2], fd, rtol=0, atol=1e-6 * np.abs(fd).max())


# -- input ------------------------------------------------------------------------------------------------


@pytest.mark.parametrize("kt", [0.0, -1.0, np.nan, np.inf])
def test_bad_stiffness_is_refused(kt):
    with pytest.raises(ValueError, match="kt"):
        FrictionContact(0, None, 1.0, 1e7, 1e-8, kt)


def test_model_file_reads_and_writes_kt():
    data = {
        "structure": {"mass": [1.0], "stiffness": [[1.0]]},
        "excitation": {"cos": [0.1]},
        "friction": [{"dof": 1, "mu": 1.0, "kn": 1e7, "normal_load": 0.1, "kt": 2.5}],
    }
    model = model_from_dict(data)
    assert model.friction[0].kt == 2.5
    again = model_from_dict(tomllib.loads(dumps_model(model)))
    assert again.friction[0] == model.friction[0]
    with pytest.raises(ValueError, match="kt"):
        model_from_dict({**data, "friction": [{**data["friction"][0], "kt": 0.0}]})
