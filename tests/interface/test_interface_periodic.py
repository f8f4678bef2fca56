"""Coupled normal/tangential DLFT on many contact pairs: kernels, one-pair limits, the benchmark."""

import numpy as np
import pytest

import fretwear as fw
from fretwear.interface.contact import OPEN, SLIP, STICK, march_pair
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.kernels import walk_kernel
from fretwear.interface.paper import paper_interface
from fretwear.interface.periodic import InterfaceProblem, newton, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.model import ContactPairs, Model, NormalContact, craig_bampton


def _paper_equivalent(fex=10.0, mu=1.0, normal_load=10.0):
    """The paper's 2-DOF model and its one-pair interface form (:func:`paper_interface`), condensed."""
    pm = fw.paper_model(fex=fex, mu=mu, normal_load=normal_load)
    model = paper_interface(fex=fex, mu=mu, normal_load=normal_load)
    return pm, ContactCondensation(craig_bampton(model, 0.0))


@pytest.mark.parametrize("f_hz", [0.45, 0.6, 0.7, 0.9, 1.05])
def test_one_pair_reduces_to_the_single_contact_solver(f_hz):
    """Constant normal force: the coupled law gives fretwear's single friction contact, to round-off."""
    pm, cond = _paper_equivalent()
    w = 2 * np.pi * f_hz
    prob = InterfaceProblem(cond, w, harmonics=7)
    sol = solve_interface(prob)
    ref = fw.solve_periodic(pm, w, 7, half_wave=False, eps=prob.eps[0])
    assert sol.converged and ref.converged
    x1 = sol.dof_harmonics[0]
    assert np.abs(x1 - ref.dof_harmonics[0]).max() <= 1e-8 * np.abs(ref.dof_harmonics[0]).max()
    assert np.allclose(sol.normal_force, 10.0, rtol=1e-10)  # the pressed DOF stays closed at F_N
    assert sol.slip_distance[0] == pytest.approx(ref.sliding_distance[0], rel=1e-8, abs=1e-15)


def test_separation_matches_the_unilateral_contact_solver():
    """mu = 0, a mass pressed on the ground and shaken off it: fretwear's unilateral contact solver."""
    k, m, c, P, F1 = 100.0, 1.0, 0.2, 1.0, 2.0  # the excitation lifts the mass off the ground each cycle
    ground = (NormalContact(0, None, 0.0),)
    ref_model = Model(M=[[m]], C=[[c]], K=[[k]], force_cos=[F1], force_static=[P], normal=ground)
    pairs = ContactPairs(dofs_a=[[-1, -1]], dofs_b=[[1, 0]], normal=[[0.0, -1.0]], area=[1.0], mu=0.0)
    model = Model(M=np.diag([m, 1.0]), C=np.diag([c, 0.0]), K=np.diag([k, 1.0]), pairs=pairs,
                           force_static=[P, 0.0], force_cos=[F1, 0.0])  # fmt: skip
    cond = ContactCondensation(craig_bampton(model, 0.0))
    w = 0.3 * np.sqrt(k / m)
    prob = InterfaceProblem(cond, w, harmonics=9)
    sol = solve_interface(prob)
    ref = fw.solve_periodic(ref_model, w, 9, eps=prob.eps[1])
    assert sol.converged and ref.converged
    assert 0.3 < np.mean(sol.state == OPEN) < 0.6
    y = sol.dof_harmonics[0]
    assert np.abs(y - ref.dof_harmonics[0]).max() <= 1e-8 * np.abs(ref.dof_harmonics[0]).max()


def test_march_is_periodic_and_respects_the_laws():
    rng = np.random.default_rng(3)
    n = 64
    t = 2 * np.pi * np.arange(n) / n
    uT = 3.0 * np.cos(t) + 0.5 * np.sin(3 * t)
    uN = 1.0 + 1.5 * np.cos(t + 0.3) + 0.1 * rng.standard_normal(n)  # separates over part of the period
    out = [np.empty(n) for _ in range(3)]
    state = np.empty(n, np.int8)
    kind, src, sgn = np.empty(n, np.int64), np.zeros(n, np.int64), np.zeros(n)
    march_pair(uT, uN, 0.0, 0.8, 2.0, 5.0, 0.0, *out, state, kind, src, sgn)
    lamT, lamN, X = out
    closed = state != OPEN
    assert np.all(lamN[closed] > 0) and np.all(lamN[~closed] == 0) and np.all(lamT[~closed] == 0)
    assert np.all(np.abs(lamT) <= 0.8 * lamN + 1e-12)
    assert np.allclose(np.abs(lamT[state == SLIP]), 0.8 * lamN[state == SLIP])
    # periodic: marching again from the end state changes nothing
    pred = uT[0] - 2.0 * X[-1]
    if state[0] == STICK:
        assert lamT[0] == pytest.approx(pred)
    assert np.all(np.diff(X)[state[1:] == STICK] == 0)


@pytest.fixture(scope="module")
def bench():
    model = cylinder_on_flat(contact_nodes=16, q_ratio=0.6)
    cond = ContactCondensation(craig_bampton(model, 7 * 50.0))
    return model, cond


def test_jacobian_is_the_exact_derivative(bench):
    model, cond = bench
    prob = InterfaceProblem(cond, 2 * np.pi * 50.0, harmonics=3)
    sol = solve_interface(prob)
    rng = np.random.default_rng(0)
    x = sol.unknowns * (1 + 0.05 * rng.standard_normal(sol.unknowns.size))
    from fretwear.interface.contact import jacobian

    R, A = prob.evaluate(x, jacobian=True)[:2]
    J = np.empty((x.size, x.size))
    jacobian(prob.Z, prob.eps, A, J)
    h = 1e-9 * np.abs(x).max()
    for j in rng.choice(x.size, 12, replace=False):
        d = np.zeros_like(x)
        d[j] = h
        fd = (prob.evaluate(x + d)[0] - prob.evaluate(x - d)[0]) / (2 * h)
        assert np.abs(fd - J[:, j]).max() <= 1e-5 * np.abs(J).max()


def test_quasi_static_benchmark_partial_slip(bench):
    """Far below the first mode: pressure integral P, Mindlin's stick zone to a spacing, energy balance."""
    model, cond = bench
    prob = InterfaceProblem(cond, 2 * np.pi * 50.0, harmonics=7)
    sol = solve_interface(prob)
    assert sol.converged and sol.residual < 1e-9
    P = model.info["normal_load"]
    assert sol.normal_force.mean(axis=1).sum() == pytest.approx(P, rel=1e-9)
    a = model.info["hertz_half_width"]
    x = sol.position
    never = np.all(sol.state == STICK, axis=1)
    c = a * np.sqrt(1 - 0.6)
    h = np.diff(x)[0]
    assert never.any() and np.abs(x[never]).max() == pytest.approx(c, abs=1.01 * h)
    assert np.all(sol.slip_distance[never] == 0) and np.all(sol.slip_distance[np.abs(x) > c + h][:-1] >= 0)
    # friction work from the harmonics (oint lambda_T du_T) = mu int lambda_N ds of the march
    assert sol.contact_work == pytest.approx(sol.friction_energy, rel=2e-3)


def test_gross_slip_under_displacement_control():
    model = cylinder_on_flat(
        contact_nodes=12, arm_stiffness=2e10, drive_displacement=2e-5
    )  # arm force 3.3 mu P
    cond = ContactCondensation(craig_bampton(model, 7 * 50.0))
    sol = solve_interface(InterfaceProblem(cond, 2 * np.pi * 50.0, harmonics=7))
    assert sol.converged
    closed = np.any(sol.state != OPEN, axis=1)
    assert np.all(np.any(sol.state[closed] == SLIP, axis=1))  # every closed pair slips
    Q = model.info["mu"] * model.info["normal_load"]
    assert np.abs(sol.tangential_force.sum(axis=0)).max() == pytest.approx(Q, rel=1e-6)  # saturated at mu P


def test_one_pair_wears_as_the_single_contact_exact_load_path():
    """The paper's normal-load relaxation through the pressing spring: F_N = k_n (u0 - w)."""
    from fretwear.interface.wear import wear_interface

    pm, cond = _paper_equivalent()
    omega = 2 * np.pi * 0.7
    ref = fw.wear_history(pm, omega, "exact", harmonics=7, kw=1e-11, cycles=2e4)
    errors = []
    for rtol in (1e-2, 1e-5):  # the slow-time error of the interface's stepping falls with its tolerance
        h = wear_interface(InterfaceProblem(cond, omega, harmonics=7), 1e-11, 2e4, rtol=rtol)
        load = np.maximum(10.0 - 1e7 * h.wear[:, 0], 0.0)  # clipped at zero once worn through
        assert h.converged and np.allclose(h.normal_force_sum, load, rtol=1e-9, atol=1e-9)
        inside = ref.at(h.cycles)["wear"][:, 0] < 0.98 * ref.u0[0]  # the reference stops at 0.99 u0
        errors.append(np.abs(ref.at(h.cycles)["wear"][inside, 0] - h.wear[inside, 0]).max() / ref.u0[0])
    assert errors[0] < 1e-2 and errors[1] < 2e-4 and errors[1] < errors[0] / 10  # measured 3.3e-3, 7.7e-5


def test_the_load_walk_passes_a_vertex_where_several_samples_change_state(bench):
    """At 70 Hz (Nh = 3) the walk meets a vertex where it went back and forth between pieces without
    progress (it stalled at p = 0.3428 for 20 000 pieces); it now arrives, on Newton's solution."""
    model, cond = bench
    prob = InterfaceProblem(cond, 2 * np.pi * 70.0, harmonics=3)
    b = prob.basis
    x, p, pieces, arrived = walk_kernel(
        prob.start(), 0.0, prob.Z, prob.F_static, prob.force_scale * prob.F_exc, np.zeros(prob.size),
        prob.eps, prob.gap, prob.mu, prob.xref, b.synthesis, b.analysis, 8000,
    )  # fmt: skip
    ref = solve_interface(prob)
    assert arrived and p == 1.0 and ref.converged
    R = prob.evaluate(x)[0]
    assert np.abs(R).max() <= 1e-5 * prob.residual_scale()  # near the path: nudged past the vertices
    polished = newton(prob, x)  # as load_walk ends
    assert polished.converged and polished.iterations <= 3
    assert np.abs(polished.x - ref.unknowns).max() <= 1e-10 * np.abs(ref.unknowns).max()
