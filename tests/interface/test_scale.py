"""The structured interface solve (issue 25, scale): the same steps and answers as the dense path."""

import numpy as np
import pytest

from fretwear.hbm.dlft import jacobian_from_blocks
from fretwear.hbm.krylov import EXACT, FALLBACKS, STEPS
from fretwear.hbm.structured import FIXED, FREE, MIXED, classify, harmonic_blocks, structured_step
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, newton, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import sphere_dynamic_model
from fretwear.model import craig_bampton

OMEGA, NH = 2 * np.pi * 50.0, 7


def _problems(pairs, **changes):
    """The dense and the structured problem of a cylinder (same penalty and reference slip variables)."""
    cond = ContactCondensation(craig_bampton(cylinder_on_flat(contact_nodes=pairs, **changes), NH * 50.0))
    dense = InterfaceProblem(cond, OMEGA, harmonics=NH, linear="dense")
    return dense, InterfaceProblem(cond, OMEGA, harmonics=NH, xref=dense.xref, eps=dense.eps)


@pytest.fixture(scope="module")
def cylinder32():
    return _problems(32)


def test_harmonic_blocks_hold_all_of_z(cylinder32):
    """Z couples no two harmonics: scattering the blocks back rebuilds Z exactly."""
    prob = cylinder32[1]
    H, q = prob.basis.size, 2 * prob.n_pairs
    Zb = harmonic_blocks(prob.Z, q, H)
    back = np.zeros_like(prob.Z)
    c = np.arange(q) * H
    back[np.ix_(c, c)] = Zb[0, :q, :q]
    for k in range(1, NH + 1):
        idx = np.concatenate([c + 2 * k - 1, c + 2 * k])
        back[np.ix_(idx, idx)] = Zb[k]
    assert np.array_equal(back, prob.Z)
    with pytest.raises(ValueError, match="H = 2 Nh"):
        harmonic_blocks(prob.Z, q, H + 1)


def test_structured_step_is_the_dense_step(cylinder32):
    """On Newton's iterates from the quasi-static start (fixed, open and mixed coordinates all present),
    the structured step equals LAPACK's solve of the dense Jacobian to rounding, for the residual and
    for a random right-hand side (the iterates' fixed rows have none)."""
    prob = cylinder32[1]
    Zb = harmonic_blocks(prob.Z, 2 * prob.n_pairs, prob.basis.size)
    rng = np.random.default_rng(5)
    x = prob.start()
    seen = set()
    for _ in range(6):
        R, A, *_ = prob.evaluate(x, jacobian=True)
        seen.update(classify(A).tolist())
        J = np.empty((prob.size, prob.size))
        jacobian_from_blocks(prob.Z, prob.eps, A, J)
        for rhs in (R, np.abs(R).max() * rng.standard_normal(prob.size)):
            ref = np.linalg.solve(J, -rhs)
            dx = np.empty(prob.size)
            structured_step(Zb, A, rhs, prob.eps, dx)
            assert np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()
        x = x + np.linalg.solve(J, -R)
    assert seen == {FIXED, FREE, MIXED}


@pytest.mark.parametrize(
    "pairs, changes",
    [
        (32, {}),  # partial slip, Q0 = 0.5 mu P
        (16, {"q_ratio": 0.8}),  # partial slip, a thin stick zone
        (12, {"arm_stiffness": 2e10, "drive_displacement": 2e-5}),  # gross slip, displacement control
    ],
)
def test_structured_solve_equals_the_dense_solve(pairs, changes, cylinder32):
    """The same periodic solution at the problem's penalty: the soft start changes convergence only."""
    dense, structured = cylinder32 if pairs == 32 else _problems(pairs, **changes)
    sd, ss = solve_interface(dense), solve_interface(structured)
    assert sd.converged and ss.converged and ss.residual <= 1e-10
    assert np.abs(ss.unknowns - sd.unknowns).max() <= 1e-9 * np.abs(sd.unknowns).max()
    assert np.array_equal(ss.state, sd.state)


def test_structured_newton_reports_a_failure(cylinder32):
    """Out of budget: not converged, the budget's message, and the residual of the point returned."""
    prob = cylinder32[1]
    res = newton(prob, prob.start(), 1e-10, 2)
    assert not res.converged and res.iterations == 2 and res.message == "no convergence in 2 iterations"
    R = prob.evaluate(res.x)[0]
    assert res.residual == pytest.approx(np.abs(R).max() / prob.residual_scale(), rel=1e-12)
    assert res.residual > 1e-10


def test_linear_is_checked(cylinder32):
    with pytest.raises(ValueError, match="linear must be one of"):
        InterfaceProblem(cylinder32[0].condensation, OMEGA, linear="krylov")


def test_gmres_steps_give_the_exact_steps_solution(cylinder32):
    """Coupled law: every step by GMRES (``krylov_min = 0``) against every step exact and against the dense
    path: the same converged solution within the Newton tolerance, with GMRES steps taken and none fallen
    back to the exact step."""
    dense, structured = cylinder32
    sd = solve_interface(dense)
    out = {}
    for kmin in (0, 2**62):
        structured.krylov_min = kmin
        structured.krylov_stats[:] = 0
        out[kmin] = (solve_interface(structured), structured.krylov_stats.copy())
    (sk, stk), (se, ste) = out[0], out[2**62]
    assert sk.converged and se.converged and sk.residual <= 1e-10 and se.residual <= 1e-10
    assert stk[STEPS] > 0 and stk[FALLBACKS] == 0 and ste[STEPS] == 0 and ste[EXACT] > 0
    for s in (sk, se):
        assert np.abs(s.unknowns - sd.unknowns).max() <= 1e-9 * np.abs(sd.unknowns).max()


def test_gmres_steps_give_the_exact_steps_solution_with_the_cone():
    """2-D friction law (63 pairs of the sphere, partial slip): GMRES steps and exact steps converge to the
    same solution within the Newton tolerance."""
    from fretwear.interface.sphere import sphere_periodic

    cond = ContactCondensation(sphere_dynamic_model(divisions=6, size=4.0))
    runs = {}
    for kmin in (0, 2**62):
        d = sphere_periodic(0.5, 0.05, harmonics=3, condensation=cond, krylov_min=kmin)
        runs[kmin] = d["solution"]
    a, b = runs[0], runs[2**62]
    assert a.converged and b.converged
    assert a.problem.krylov_stats[STEPS] > 0 and a.problem.krylov_stats[FALLBACKS] == 0
    assert b.problem.krylov_stats[STEPS] == 0
    assert np.abs(a.unknowns - b.unknowns).max() <= 1e-9 * np.abs(b.unknowns).max()


def test_gmres_newton_out_of_steps_says_so(cylinder32):
    """A Newton solve with GMRES steps stopped before convergence reports it: not converged, its residual
    (judged on the true residual, never on GMRES's) above the tolerance, a message that says why."""
    structured = cylinder32[1]
    structured.krylov_min = 0
    structured.krylov_stats[:] = 0
    res = newton(structured, structured.start(), tol=1e-10, max_iter=2)
    assert structured.krylov_stats[STEPS] > 0
    assert not res.converged and res.residual > 1e-10 and res.iterations <= 2
    assert res.message in ("no convergence in 2 iterations", "line search failed")
