"""The interface with the 2-D friction law (the circular Coulomb cone) on 3-D pairs (issue 25)."""

import numpy as np
import pytest

from fretwear.hbm.dlft import jacobian_from_blocks
from fretwear.hbm.structured import harmonic_blocks, structured_step
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.time_integration import initial_state, integrate_interface
from fretwear.model import ContactPairs, Model, craig_bampton

OMEGA, NH = 2 * np.pi * 50.0, 5


def _lifted(model2d: Model, held_every: int = 2, y_force: np.ndarray | None = None) -> Model:
    """The 2-D model made 3-D: each pair gains a ``y`` on both nodes (tangent ``+x``, normal ``+z``, binormal
    ``+y``), on its own springs and masses; every ``held_every``-th pair has none (held on both nodes: a
    symmetry plane). Without ``y_force`` the motion stays in the ``(x, z)`` plane; ``y_force`` (nc,) is a
    ``sin(omega t)`` load (N) on node B's ``y`` of the pairs that have one (with the ``cos`` load along ``x``:
    the tangential load turns)."""
    c = model2d.pairs
    n, nc = model2d.n_dofs, c.count
    has_y = np.arange(nc) % held_every != 0
    ny = 2 * int(has_y.sum())
    N = n + ny
    K, M, C = (np.zeros((N, N)) for _ in range(3))
    K[:n, :n], M[:n, :n], C[:n, :n] = model2d.K, model2d.M, model2d.C
    ya, yb = np.full(nc, -1), np.full(nc, -1)
    ya[has_y] = n + 2 * np.arange(has_y.sum())
    yb[has_y] = ya[has_y] + 1
    k = np.abs(np.diag(model2d.K)).max()
    for a, b in zip(ya[has_y], yb[has_y], strict=True):  # y_A grounded; y_B on y_A and on the ground
        K[np.ix_([a, b], [a, b])] += k * np.array([[1.5, -1.0], [-1.0, 1.2]])
        M[a, a] = M[b, b] = 1e-3 * np.abs(np.diag(model2d.M)).max()
        C[np.ix_([a, b], [a, b])] += 1e-5 * K[np.ix_([a, b], [a, b])]
    pad = lambda v: np.concatenate([v, np.zeros(ny)])  # noqa: E731
    f_sin = pad(model2d.force_sin if model2d.force_sin is not None else np.zeros(n))
    if y_force is not None:
        f_sin[yb[has_y]] = np.asarray(y_force)[has_y]
    pairs = ContactPairs(
        dofs_a=np.column_stack([c.dofs_a[:, 0], ya, c.dofs_a[:, 1]]),
        dofs_b=np.column_stack([c.dofs_b[:, 0], yb, c.dofs_b[:, 1]]),
        normal=np.column_stack([c.normal[:, 0], np.zeros(nc), c.normal[:, 1]]),
        tangent=np.column_stack([c.tangent[:, 0], np.zeros(nc), c.tangent[:, 1]]),
        area=c.area, mu=c.mu, gap=c.gap, position=c.position,
    )  # fmt: skip
    return Model(M=M, C=C, K=K, pairs=pairs, force_static=pad(model2d.force_static),
                 force_cos=pad(model2d.force_cos), force_sin=f_sin)  # fmt: skip


@pytest.fixture(scope="module")
def cylinder():
    """An 8-pair cylinder (reduced), its 1-D problem, and the same structure lifted to 3-D pairs."""
    reduced = craig_bampton(cylinder_on_flat(contact_nodes=8, q_ratio=0.7), NH * 50.0)
    line = InterfaceProblem(ContactCondensation(reduced), OMEGA, harmonics=NH)
    return line, ContactCondensation(_lifted(reduced))


def test_cone_is_the_default_of_3d_pairs_and_line_of_2d(cylinder):
    line, cond3 = cylinder
    assert line.friction == "line" and line.per_pair == 2
    cone = InterfaceProblem(cond3, OMEGA, harmonics=NH)
    assert cone.friction == "cone" and cone.size == 3 * 8 * (2 * NH + 1) and cone.xref.shape == (8, 2)
    with pytest.raises(ValueError, match="friction"):
        InterfaceProblem(line.condensation, OMEGA, harmonics=NH, friction="cone")
    with pytest.raises(ValueError, match="friction"):
        InterfaceProblem(cond3, OMEGA, harmonics=NH, friction="circle")
    with pytest.raises(ValueError, match="xref"):
        InterfaceProblem(cond3, OMEGA, harmonics=NH, xref=np.zeros(8))


def test_a_motion_along_the_tangents_is_the_1d_interface_solution(cylinder):
    """The lifted structure (binormal springs unloaded, half the pairs on a symmetry plane) with the cone:
    the binormal stays at rest, and contact coordinates, forces, slip and friction energy are the 1-D
    interface's to round-off; the 1-D law on the lifted structure (binormal free) too."""
    line, cond3 = cylinder
    ref = solve_interface(line)
    assert ref.converged and np.any(ref.state_fraction(2) > 0)  # some pair slips: the test sees the law
    H = line.basis.size
    for friction in ("cone", "line"):
        eps = line.eps.reshape(8, 2)[:, [0, 0, 1]].ravel() if friction == "cone" else None  # the same penalty
        prob = InterfaceProblem(cond3, OMEGA, harmonics=NH, friction=friction, eps=eps)
        sol = solve_interface(prob)
        assert sol.converged
        x = sol.unknowns.reshape(8, prob.per_pair, H)
        x_ref = ref.unknowns.reshape(8, 2, H)
        scale = np.abs(x_ref).max()
        assert np.abs(x[:, [0, -1]] - x_ref).max() <= 1e-9 * scale
        lam = sol.tangential_force
        F = np.abs(ref.normal_force).max()
        if friction == "cone":
            assert np.abs(x[:, 1]).max() <= 1e-9 * scale and np.abs(lam[..., 1]).max() <= 1e-8 * F
            lam = lam[..., 0]
        assert np.abs(lam - ref.tangential_force).max() <= 1e-8 * F
        assert np.abs(sol.normal_force - ref.normal_force).max() <= 1e-8 * F
        assert sol.friction_energy == pytest.approx(ref.friction_energy, rel=1e-8)
        assert sol.contact_work == pytest.approx(ref.contact_work, rel=1e-6)
        coords = line.condensation.recover(OMEGA, NH, ref.contact_harmonics)  # the reduced model's DOFs
        full = sol.dof_harmonics[: coords.shape[0]]  # the lifted model is not reduced: its DOFs are those
        assert np.abs(full - coords).max() <= 1e-8 * np.abs(coords).max()


def test_structured_cone_step_is_the_dense_step(cylinder):
    """The Schur elimination with three coordinates a pair: the structured step equals LAPACK's solve of
    the dense Jacobian on Newton's iterates (fixed, open and mixed coordinates present), and the structured
    and dense solves agree."""
    _, cond3 = cylinder
    prob = InterfaceProblem(cond3, OMEGA, harmonics=NH)
    dense = InterfaceProblem(cond3, OMEGA, harmonics=NH, linear="dense", xref=prob.xref, eps=prob.eps)
    Zb = harmonic_blocks(prob.Z, 3 * prob.n_pairs, prob.basis.size)
    rng = np.random.default_rng(3)
    x = prob.start() + 1e-3 * np.abs(prob.start()).max() * rng.standard_normal(prob.size)
    for _ in range(4):
        R, A, *_ = prob.evaluate(x, jacobian=True)
        J = np.empty((prob.size, prob.size))
        jacobian_from_blocks(prob.Z, prob.eps, A, J)
        for rhs in (R, np.abs(R).max() * rng.standard_normal(prob.size)):
            ref = np.linalg.solve(J, -rhs)
            dx = np.empty(prob.size)
            structured_step(Zb, A, rhs, prob.eps, dx)
            assert np.abs(dx - ref).max() <= 1e-8 * np.abs(ref).max()
        x = x + np.linalg.solve(J, -R)
    a, b = solve_interface(prob), solve_interface(dense)
    assert a.converged and b.converged
    assert np.abs(a.unknowns - b.unknowns).max() <= 1e-10 * np.abs(b.unknowns).max()


def test_time_integration_with_2d_friction_along_a_line_is_the_1d_one(cylinder):
    """The backward-Euler check with the cone law (semi-smooth Newton per step) on the lifted structure,
    started from the same state: the 1-D active-set integration of the 2-D structure to round-off."""
    line, cond3 = cylinder
    cone = InterfaceProblem(cond3, OMEGA, harmonics=NH, eps=line.eps.reshape(8, 2)[:, [0, 0, 1]].ravel())
    z3, v3, X3, st3 = initial_state(solve_interface(cone))
    z, v, X, st = initial_state(solve_interface(line))
    assert X3.shape == (8, 2) and np.abs(X3[:, 1]).max() <= 1e-9 * np.abs(X3).max()
    a = integrate_interface(line.condensation, OMEGA, z, v, X, st, periods=2, steps_per_period=128)
    b = integrate_interface(cond3, OMEGA, z3, v3, X3, st3, periods=2, steps_per_period=128)
    assert a.converged and b.converged, b.message
    nq = 16
    F = np.abs(a.forces).max()
    assert np.abs(b.forces[:, :nq] - a.forces).max() <= 1e-8 * F
    assert np.abs(b.forces[:, nq:]).max() <= 1e-8 * F  # no binormal force
    assert np.abs(b.contact[:, :nq] - a.contact).max() <= 1e-8 * np.abs(a.contact).max()
    assert np.array_equal(a.state, b.state)
    assert b.energy_per_period.sum() == pytest.approx(a.energy_per_period.sum(), rel=1e-8)


@pytest.fixture(scope="module")
def turning():
    """8 pairs (every pair with a binormal), the tangential load turning (x cos, y sin): 2-D slip."""
    reduced = craig_bampton(cylinder_on_flat(contact_nodes=8, q_ratio=0.7), 31 * 50.0)
    line = InterfaceProblem(ContactCondensation(reduced), OMEGA, harmonics=3)
    pn = solve_interface(line).normal_force.mean(axis=1)
    cond = ContactCondensation(_lifted(reduced, held_every=10**6, y_force=0.4 * 0.6 * pn))
    sols = {nh: solve_interface(InterfaceProblem(cond, OMEGA, harmonics=nh)) for nh in (5, 11, 23)}
    run = integrate_interface(cond, OMEGA, *initial_state(sols[23]), periods=3, steps_per_period=1024,
                              samples_per_period=64)  # fmt: skip
    return cond, sols, run


def test_cone_dlft_converges_to_the_time_integration(turning):
    """DLFT with the cone law at Nh = 5, 11, 23 against backward Euler (1024 steps a period, periodic after
    3 periods): the tangential force (both components) approaches it at first order (measured 0.127, 0.056,
    0.027 of mu P_max); the friction work per period within 2 % (1.1e-4, 9.3e-3, 8.0e-4)."""
    cond, sols, run = turning
    assert run.converged, run.message
    E = run.energy_per_period.sum(axis=1)
    assert abs(E[-1] / E[-2] - 1) < 1e-6
    cols = cond.cone_coordinates()
    lam_t = run.forces[-64:][:, cols[:, :2]]  # (64, nc, 2)
    lam_n = run.forces[-64:][:, cols[:, 2]]
    assert np.all(np.hypot(lam_t[..., 0], lam_t[..., 1]) <= 0.6 * lam_n * (1 + 1e-9) + 1e-9 * lam_n.max())
    errs = []
    for sol in sols.values():
        assert sol.converged
        Ns = sol.problem.basis.marched_samples
        idx = (np.arange(64) + 1) % 64 * (Ns // 64)
        ref = sol.tangential_force[:, idx].transpose(1, 0, 2)  # (64, nc, 2)
        assert np.abs(ref[..., 1]).max() > 0.2 * np.abs(ref[..., 0]).max()  # a genuinely 2-D motion
        scale = 0.6 * sol.normal_force.max()
        errs.append((np.abs(lam_t - ref).max() / scale, abs(sol.friction_energy / E[-1] - 1)))
    errs = np.array(errs)
    assert np.all(np.diff(errs[:, 0]) < 0) and errs[-1, 0] < 0.05
    assert errs[:, 1].max() < 0.02  # not monotone: the Gibbs ripple at the transitions (as in 1-D)
