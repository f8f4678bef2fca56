"""Jenkins contacts in the receptance form (:mod:`fretwear.hbm.receptance`): dependent contact coordinates.

A closed ring of contacts has no condensed dynamic stiffness; the receptance
form solves it. Checked: on models where both forms exist they give the same
solution; on a ring, the stuck and sliding limits are the linear structures
with the springs ``k_t`` and without the contacts; a ring of rigid contacts is
refused with a message.
"""

import numpy as np
import pytest

import fretwear as fw
from fretwear.hbm.condensation import receptance as receptance_of
from fretwear.hbm.periodic import Problem, solve_problem
from fretwear.model import FrictionContact, Model


def ring(slip: float, kt: float | None = 3.0, n: int = 3) -> Model:
    """``n`` unit masses on ground springs, a Jenkins contact between each mass and the next (closed ring),
    forced by a travelling wave (engine order 1)."""
    K = np.diag(np.linspace(1.0, 1.6, n))
    model = Model(
        M=np.eye(n), C=0.03 * np.eye(n), K=K,
        friction=[FrictionContact.from_normal_load(i, (i + 1) % n, 1.0, slip, kt=kt) for i in range(n)],
    )  # fmt: skip
    return model.travelling_wave(np.arange(n), 1, 0.2)


def chain(slip: float) -> Model:
    """Three masses in a chain with Jenkins contacts 0-1 and 2-ground: independent coordinates."""
    K = np.array([[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]])
    return Model(
        M=np.eye(3), C=0.02 * K, K=K, force_cos=[0.0, 0.0, 0.1],
        friction=[FrictionContact.from_normal_load(0, 1, 1.0, slip, kt=2.0),
                  FrictionContact.from_normal_load(2, None, 1.0, slip, kt=1.0)],
    )  # fmt: skip


@pytest.mark.parametrize("omega", [0.8, 1.2, 1.6])
def test_both_forms_give_one_solution_where_both_exist(omega):
    """The chain in partial slip: receptance form (a given Receptance) = stiffness form to 1e-10."""
    model = chain(0.03)
    stiff = solve_problem(Problem(model, omega, 9))
    assert stiff.problem.form == "stiffness"
    p = Problem(model, omega, 9, condensed=lambda B, basis: receptance_of(model, B, omega, basis))
    rec = solve_problem(p)
    assert rec.problem.form == "receptance" and stiff.converged and rec.converged
    assert np.any(stiff.state == fw.model.SLIP) and np.any(stiff.state == fw.model.STICK)
    scale = np.abs(stiff.dof_harmonics).max()
    assert np.abs(rec.dof_harmonics - stiff.dof_harmonics).max() <= 1e-10 * scale
    assert np.abs(rec.contact_force - stiff.contact_force).max() <= 1e-10 * 0.03


def test_a_ring_is_solved_in_the_receptance_form():
    model = ring(0.02)
    B = model.relative_map()
    assert np.linalg.matrix_rank(B) == 2  # three contacts, two independent coordinates
    sol = fw.solve_periodic(model, 1.1, 7)
    assert sol.converged and sol.problem.form == "receptance"
    assert np.any(sol.state == fw.model.SLIP)
    # the relative displacements of the ring sum to zero at every instant
    assert np.abs(sol.relative_displacement.sum(axis=0)).max() <= 1e-12 * np.abs(sol.displacement).max()


def test_jacobian_matches_finite_differences_on_the_ring():
    p = Problem(ring(0.02), 1.1, 5)
    x = solve_problem(p).unknowns + 1e-3 * np.random.default_rng(1).standard_normal(p.size)
    R, J = p.evaluate(x)[:2]
    h = 1e-7
    Jfd = np.column_stack([(p.evaluate(x + h * e, False)[0] - R) / h for e in np.eye(p.size)])
    assert np.abs(J - Jfd).max() <= 1e-5 * np.abs(J).max()


@pytest.mark.parametrize("omega", [0.9, 1.3])
def test_ring_stuck_and_sliding_limits(omega, assert_linear):
    """Huge slip force: the linear ring with the springs k_t; vanishing: the masses without contacts."""
    for slip, springs in ((1e6, True), (1e-14, False)):
        model = ring(slip)
        sol = fw.solve_periodic(model, omega, 9)
        assert sol.converged
        B = model.relative_map()
        assert_linear(sol, model, omega, 3.0 * B.T @ B if springs else 0.0)


def test_a_ring_of_rigid_contacts_is_refused():
    with pytest.raises(ValueError, match="closed ring of contacts.*Jenkins contacts"):
        fw.solve_periodic(ring(0.02, kt=None), 1.1, 5)
