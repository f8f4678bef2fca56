"""The compiled sweep against the point-by-point solver, single-frequency solves and its own parts."""

import numpy as np
import pytest
from test_dlft import two_contact_model  # the same 3-DOF model with two friction contacts and a stop

from fretwear import jenkins_oscillator, paper_model, solve_periodic
from fretwear.hbm import compiled_sweep, dense, dlft
from fretwear.hbm.condensation import condense, condense_sweep
from fretwear.hbm.continuation import sweep
from fretwear.hbm.periodic import Problem, solve_problem

TWO_PI = 2 * np.pi

#: the benchmark's sweeps: 101 points over the paper model's band and the Jenkins oscillator's
CASES = {
    "paper": (paper_model(fex=10.0), TWO_PI * np.linspace(0.3, 1.3, 101)),
    "jenkins": (jenkins_oscillator(), np.linspace(0.5, 2.5, 101)),
}


def assert_same_solutions(a, b, rtol=1e-10):
    """Same unknowns (relative to the largest one), amplitudes and per-period quantities."""
    for sa, sb in zip(a, b, strict=True):
        assert sa.omega == sb.omega and sa.converged and sb.converged
        scale = max(np.abs(sb.unknowns).max(initial=0.0), 1e-300)
        assert np.abs(sa.unknowns - sb.unknowns).max(initial=0.0) <= rtol * scale
        np.testing.assert_allclose(
            sa.amplitude, sb.amplitude, rtol=rtol, atol=rtol * np.abs(sb.amplitude).max()
        )
        np.testing.assert_allclose(sa.sliding_distance, sb.sliding_distance, rtol=1e-8, atol=1e-8 * scale)
        np.testing.assert_allclose(
            sa.contact_force, sb.contact_force, rtol=0, atol=1e-8 * np.abs(sb.contact_force).max()
        )


@pytest.mark.parametrize("case", CASES)
@pytest.mark.parametrize("nh", [7, 21])
def test_compiled_sweep_gives_the_point_by_point_answers(case, nh):
    model, omegas = CASES[case]
    fast, ref = sweep(model, omegas, nh), sweep(model, omegas, nh, compiled=False)
    assert fast.converged.all()
    assert max(s.residual for s in fast.solutions) < 1e-10
    assert_same_solutions(fast.solutions, ref.solutions)
    assert {s.path for s in fast.solutions} <= {
        "linear-stuck",
        "dlft",
        "dlft-newton-homotopy",
        "dlft-homotopy",
    }


@pytest.mark.parametrize("case", CASES)
def test_compiled_sweep_gives_the_cold_single_frequency_answers(case):
    model, omegas = CASES[case]
    fast = sweep(model, omegas, 21).solutions[::8]
    cold = [
        solve_problem(Problem(model, s.omega, 21)) for s in fast
    ]  # the Python solver, from the stuck start
    assert_same_solutions(fast, cold)
    assert_same_solutions([solve_periodic(model, s.omega, 21) for s in fast], cold)  # the compiled one, cold


def test_several_contacts_unilateral_and_full_wave():
    """Two friction contacts and a unilateral stop, full wave. Between 1.3 and 1.65 rad/s this model has
    several periodic solutions (both solvers' answers there solve the equations and differ by up to 12 %):
    the sweep continues its neighbours, the point-by-point path may take another branch. Every answer
    must solve the equations (checked in ``x`` by the reference's own problem) and balance energy per
    cycle; outside that band the answers are the same."""
    model = two_contact_model()
    omegas = np.linspace(0.4, 2.0, 33)
    fast, ref = sweep(model, omegas, 5), sweep(model, omegas, 5, compiled=False)
    assert not fast.solutions[0].half_wave and fast.converged.all() and ref.converged.all()
    for sa, sb in zip(fast.solutions, ref.solutions, strict=True):
        R = sb.problem.evaluate(sa.unknowns, jacobian=False)[0]  # in x, by the reference's problem
        assert np.abs(R).max() <= 1e-9 * sb.problem.residual_scale()
        assert abs(sa.input_work - sa.viscous_dissipation - sa.contact_work) <= 1e-6 * sa.input_work
    unique = (omegas < 1.3) | (omegas > 1.65)
    assert_same_solutions(
        [s for s, u in zip(fast.solutions, unique, strict=True) if u],
        [s for s, u in zip(ref.solutions, unique, strict=True) if u],
    )


def test_a_singular_penalty_map_falls_back_to_the_solver_in_x():
    """With eps equal to the static condensed stiffness, E - Z is singular on the mean slot."""
    model = paper_model(fex=10.0)
    omegas = TWO_PI * np.linspace(0.6, 0.8, 5)
    eps = Problem(model, omegas[0], 5, half_wave=False).Z[0, 0]
    assert eps > 0
    fast = sweep(model, omegas, 5, half_wave=False, eps=eps)
    ref = sweep(model, omegas, 5, half_wave=False, eps=eps, compiled=False)
    assert_same_solutions(fast.solutions, ref.solutions)


def test_failures_are_reported_with_the_solver_messages():
    model, omegas = paper_model(fex=10.0), TWO_PI * np.linspace(0.6, 0.8, 3)
    fast = sweep(model, omegas, 5, tol=0.0, max_iter=4)  # a tolerance no solve can meet
    for s in fast.solutions:
        assert not s.converged and np.isfinite(s.residual) and s.residual > 0
        assert s.path == "dlft-homotopy"
        assert s.message.startswith("load continuation ended at load factor 1 after ")
        assert s.message.endswith(("line search failed", "no convergence in 4 iterations"))


def test_guess_and_bad_guess():
    model = paper_model(fex=10.0)
    ref = solve_periodic(model, TWO_PI * 0.7, 7)
    near = solve_periodic(model, TWO_PI * 0.7, 7, guess=1.01 * ref.unknowns)
    assert near.converged and near.path == "dlft"
    np.testing.assert_allclose(near.unknowns, ref.unknowns, rtol=0, atol=1e-10 * np.abs(ref.unknowns).max())
    with pytest.raises(ValueError, match="guess must have shape"):
        solve_periodic(model, TWO_PI * 0.7, 7, guess=np.zeros(3))


def test_no_active_contact_is_the_linear_open_response():
    sw = sweep(paper_model(fex=10.0, normal_load=0.0), TWO_PI * np.array([0.4, 0.9]), 5)
    assert [s.path for s in sw.solutions] == ["linear-open"] * 2 and sw.converged.all()


# -- parts ---------------------------------------------------------------------------------------------------


def test_compiled_condensation_is_the_condensation():
    for model, nh in ((paper_model(), 7), (jenkins_oscillator(), 5), (two_contact_model(), 4)):
        p = Problem(model, 1.0, nh)
        omegas = np.linspace(0.3, 3.0, 7)
        a, b = condense(model, p.B, omegas, p.basis), condense_sweep(model, p.B, omegas, p.basis)
        np.testing.assert_allclose(b.Z, a.Z, rtol=0, atol=1e-14 * np.abs(a.Z).max())
        np.testing.assert_allclose(b.F, a.F, rtol=0, atol=1e-14 * np.abs(a.F).max())


def test_lu_solves_and_gives_the_determinant_sign():
    rng = np.random.default_rng(1)
    for n in (1, 4, 23):
        a = rng.normal(size=(n, n))
        b = rng.normal(size=n)
        f, piv, y = a.copy(), np.empty(n, dtype=np.int64), b.copy()
        sign = dense.lu_factor(f, piv)
        dense.lu_solve(f, piv, y)
        np.testing.assert_allclose(a @ y, b, atol=1e-10 * np.abs(b).max() * np.linalg.cond(a))
        assert sign == np.sign(np.linalg.det(a))
    singular = np.array([[1.0, 2.0], [0.5, 1.0]])
    assert dense.lu_factor(singular, np.empty(2, dtype=np.int64)) == 0


#: problems with every kind of march row (dep: >= 0 stick, -1 slip/open, -2 centred full stick, -4 closed)
ROWS = {
    "half-wave": (Problem(paper_model(), TWO_PI * 0.7, 5), {-1, 0}),
    "full": (Problem(paper_model(), TWO_PI * 0.7, 5, half_wave=False), {-1, 0}),
    "full-stick": (Problem(paper_model(normal_load=40.0), TWO_PI * 0.3, 5, half_wave=False), {-2}),
    "three-contacts": (Problem(two_contact_model(), 1.1, 4), {-4, -1, 0}),
}


@pytest.mark.parametrize("stride", [1, 3])
@pytest.mark.parametrize("case", ROWS)
def test_augmented_residual_and_jacobian_are_those_in_x(case, stride):
    """``R(v(x)) = R(x)`` and ``dR/dv W = dR/dx`` with ``v = F + W x``, ``W = E - Z``, on every row kind."""
    problem, expected_rows = ROWS[case]
    b, n, nc, H = problem.basis, problem.size, problem.n_active, problem.basis.size
    Ns = b.marched_samples
    W = np.diag(np.repeat(problem.eps, H)) - problem.Z
    M = problem.Z @ np.linalg.inv(W)
    P, Q = dlft.block_sums(b.synthesis, b.analysis, stride)
    PhiT, PsiT = np.ascontiguousarray(b.synthesis.T), np.ascontiguousarray(b.analysis.T)
    buf = (np.empty(n), np.empty((nc, Ns)), np.empty((nc, Ns)), np.empty((nc, Ns), dtype=np.int8),
           np.empty((nc, Ns), dtype=np.int64), np.ones((nc, Ns)), np.zeros((nc, 2), dtype=np.int64),
           np.empty((nc, Ns)))  # fmt: skip
    rng = np.random.default_rng(3)
    x0, scales = (
        (problem.stuck_solution(), [1e-12, 1e-8, 1e-7, 1e-6])
        if nc == 1
        else (problem.stuck_guess(), [0.01, 0.1])
    )
    rows = set()
    for _ in range(20):
        x = x0 + rng.normal(size=n) * rng.choice(scales)
        v = problem.F + W @ x
        r = dlft.augmented_residual(v, M, problem.F, problem.eps, problem.kinds, problem.limits, PhiT, PsiT,
                                    b.half_wave, *buf)  # fmt: skip
        J = np.empty((n, n))
        dlft.augmented_jacobian(M, buf[4], buf[5], buf[6], b.synthesis, b.analysis, P, Q, stride,
                                np.empty((H, H)), J)  # fmt: skip
        Rx, Jx, *_ = problem.evaluate(x)
        assert r == np.abs(buf[0]).max()
        np.testing.assert_allclose(buf[0], Rx, rtol=0, atol=1e-9 * max(np.abs(Rx).max(), 1.0))
        np.testing.assert_allclose(J @ W, Jx, rtol=0, atol=1e-10 * np.abs(Jx).max())
        rows.update(np.unique(buf[4]).clip(-6, 0).tolist())
    assert expected_rows <= rows  # each kind of row was exercised


def test_pattern_prediction_moves_the_runs_by_their_secant():
    """Runs shifted by 3 samples between two solutions are predicted 3 samples further; a new run is not."""
    Ns = 32
    code = np.zeros(Ns, dtype=np.int8)
    code[4:12], code[20:26] = 1, -1
    c0, c1, c2 = code, np.roll(code, 3), np.roll(code, 6)
    out = np.empty(Ns, dtype=np.int8)
    assert compiled_sweep._predict_pattern(c0, c1, 1.0, False, out)
    np.testing.assert_array_equal(out, c2)
    assert compiled_sweep._predict_pattern(c0, c1, 0.5, False, out)  # half the step: half the shift, rounded
    np.testing.assert_array_equal(out, np.roll(code, 5))
    extra = c1.copy()
    extra[18:20] = 1  # a new run
    assert not compiled_sweep._predict_pattern(c0, extra, 1.0, False, out)


@pytest.mark.parametrize("half_wave", [True, False])
@pytest.mark.parametrize("model", [paper_model(fex=10.0), two_contact_model()], ids=["paper", "two-contact"])
def test_penalty_map_by_harmonic_blocks_is_the_inverse(model, half_wave):
    """``W = E - Z`` inverted harmonic by harmonic, and as a whole where ``Z`` couples harmonics."""
    problem = Problem(model, TWO_PI * 0.7, 7, half_wave=half_wave if len(model.friction) == 1 else False)
    Z, eps, H = problem.Z, problem.eps, problem.basis.size
    n = len(Z)
    for coupled in (False, True):
        if coupled:  # a slot of the first harmonic coupled to the last slot: no longer by blocks
            Z = Z.copy()
            Z[1, H - 1] += 0.3 * np.abs(Z).max()
        Winv, M = np.empty((n, n)), np.empty((n, n))
        assert compiled_sweep._penalty_map(Z, eps, H, Winv, M)
        ref = np.linalg.inv(np.diag(np.repeat(eps, H)) - Z)
        np.testing.assert_allclose(Winv, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
        np.testing.assert_allclose(M, Z @ ref, rtol=0, atol=1e-10 * np.abs(Z @ ref).max())
