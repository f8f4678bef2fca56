"""The front functions: one call per job for every model, the solver picked by the contact kind."""

from importlib import import_module

import numpy as np
import pytest

import fretwear as fw
from fretwear.front import SOLVERS
from fretwear.interface.periodic import InterfaceProblem, InterfaceSolution, solve_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.static import solve_static
from fretwear.interface.wear import frf, wear_interface
from fretwear.model import craig_bampton

F_HZ, NH = 50.0, 3


def test_every_solver_of_the_table_exists():
    for kind, jobs in SOLVERS.items():
        for job, target in jobs.items():
            if target is not None:
                module, name = target.split(":")
                assert callable(getattr(import_module(module), name)), (kind, job)


# -- the paper's 2-DOF model and its one-pair interface form through the same calls ----------------------


@pytest.mark.parametrize("f_hz", [0.45, 0.7, 1.05])
def test_paper_model_and_paper_interface_agree_through_solve_periodic(f_hz):
    """Constant normal load: the coupled law of the pair is the single friction contact, to round-off."""
    w = 2 * np.pi * f_hz
    pair = fw.solve_periodic(fw.paper_interface(), w, 7)
    ref = fw.solve_periodic(fw.paper_model(), w, 7, half_wave=False, eps=pair.problem.eps[0])
    assert isinstance(pair, InterfaceSolution) and pair.converged and ref.converged
    assert pair.omega == ref.omega and pair.frequency == pytest.approx(f_hz, rel=1e-15)
    # x1, x2 of the interface form (its third DOF presses the pair); measured 2e-14
    assert np.abs(pair.dof_harmonics[:2] - ref.dof_harmonics).max() <= 5e-13 * np.abs(ref.dof_harmonics).max()
    assert pair.amplitude[:2] == pytest.approx(ref.amplitude, rel=5e-13)


def test_paper_model_and_paper_interface_agree_through_sweep():
    omegas = 2 * np.pi * np.linspace(0.4, 1.2, 9)  # through the resonance, stick to gross slip
    pair = fw.sweep(fw.paper_interface(), omegas, 7, eps=3e3)
    ref = fw.sweep(fw.paper_model(), omegas, 7, half_wave=False, eps=3e3)
    assert pair.converged.all() and ref.converged.all()
    assert np.array_equal(pair.omega, ref.omega)
    a = np.array([s.dof_harmonics[:2] for s in pair.solutions])
    b = np.array([s.dof_harmonics for s in ref.solutions])
    assert np.abs(a - b).max() <= 5e-12 * np.abs(b).max()  # measured 2e-12 over the 9 points


def test_paper_model_and_paper_interface_wear_alike():
    """The nodal wear history of the pair follows the friction contact's ``w(N)`` on the same dynamics.

    Reference: the exact slow-time method on the DLFT dynamics (N to 0.5 u0: 4202.92; the adaptive
    stepping of either model converges to it, 4202.93 at rtol 1e-6). At rtol = 1e-4 the interface's
    stepping is 3.9e-4 early.
    """
    w = 2 * np.pi * 0.7
    pi = fw.paper_interface()
    u0 = pi.info["u0"]
    pair = fw.wear_history(pi, w, kw=1e-11, cycles=6000.0, rtol=1e-4)
    ref = fw.wear_history(fw.paper_model(), w, "exact", kw=1e-11, cycles=6000.0, harmonics=7, dynamics="dlft")
    assert pair.converged and ref.converged and pair.status == "horizon"
    assert pair.method == "stepping" and pair.frequency == pytest.approx(0.7)
    assert pair.wear_rate[0, 0] == pytest.approx(ref.rate[0, 0], rel=1e-12)  # the same dynamics at N = 0
    n_pair, n_ref = pair.cycles_to_depth(0.5 * u0), ref.cycles_to(0.5)
    assert n_pair == pytest.approx(n_ref, rel=1e-3)


# -- the cylinder-on-flat benchmark: the front calls are the interface functions ---------------------------


@pytest.fixture(scope="module")
def bench():
    model = fw.cylinder_on_flat(contact_nodes=8, q_ratio=0.5)
    cond = ContactCondensation(craig_bampton(model, NH * F_HZ))
    return model, cond


def test_cylinder_solve_periodic_is_solve_interface(bench):
    model, cond = bench
    w = 2 * np.pi * F_HZ
    sol = fw.solve_periodic(model, w, NH)
    ref = solve_interface(InterfaceProblem(cond, w, harmonics=NH))
    assert sol.converged and ref.converged
    assert np.array_equal(sol.unknowns, ref.unknowns)
    assert np.array_equal(sol.dof_harmonics, ref.dof_harmonics)
    assert sol.dof_harmonics.shape == (model.n_dofs, 2 * NH + 1)


def test_cylinder_sweep_is_the_interface_frf(bench):
    model, cond = bench
    freqs = np.array([40.0, 50.0, 60.0])
    sweep = fw.sweep(model, 2 * np.pi * freqs, NH)
    amp, ok = frf(lambda omega: InterfaceProblem(cond, omega, harmonics=NH), freqs, "pad_x")
    assert ok.all() and sweep.converged.all()
    pad_x = model.dof("pad_x")
    assert np.array_equal([s.amplitude[pad_x] for s in sweep.solutions], amp)


def test_cylinder_wear_history_is_wear_interface(bench):
    model, cond = bench
    w = 2 * np.pi * F_HZ
    hist = fw.wear_history(model, w, kw=1e-14, cycles=3e5, harmonics=NH, rtol=3e-2)
    ref = wear_interface(InterfaceProblem(cond, w, harmonics=NH), 1e-14, 3e5, rtol=3e-2)
    assert hist.converged and len(hist.cycles) > 2
    assert np.array_equal(hist.cycles, ref.cycles) and np.array_equal(hist.wear, ref.wear)
    assert hist.wear.shape == (len(hist.cycles), model.n_pairs)  # the nodal wear profile


def test_cylinder_static_contact_is_solve_static(bench):
    model, _ = bench
    res = fw.static_contact(model, 0.5)
    ref = solve_static(ContactCondensation(craig_bampton(model, 0.0)), 0.5)
    assert res.converged and np.array_equal(res.final.normal_force, ref.final.normal_force)


def test_a_reduced_model_is_used_as_it_is(bench):
    model, cond = bench
    w = 2 * np.pi * F_HZ
    reduced = fw.reduce(model, NH * F_HZ)
    assert np.array_equal(
        fw.solve_periodic(reduced, w, NH).unknowns, fw.solve_periodic(model, w, NH).unknowns
    )


# -- bad input names the parameter --------------------------------------------------------------------------


def test_bad_input_names_the_parameter():
    pi = fw.paper_interface()
    with pytest.raises(ValueError, match="model must be a fretwear Model, got str"):
        fw.solve_periodic("paper", 1.0)
    with pytest.raises(
        ValueError, match="static_contact applies to models with pairs; this model has contacts"
    ):
        fw.static_contact(fw.paper_model())
    with pytest.raises(ValueError, match="half_wave must be None or False .* got True"):
        fw.solve_periodic(pi, 4.0, half_wave=True)
    with pytest.raises(ValueError, match="omega must be a finite frequency > 0 rad/s, got -1.0"):
        fw.solve_periodic(pi, -1.0)
    with pytest.raises(ValueError, match="omegas must be a non-empty 1-D array"):
        fw.sweep(pi, [])
    with pytest.raises(
        ValueError, match="'dynamics' is not an option of wear_history .* valid options are rtol"
    ):
        fw.wear_history(pi, 4.0, dynamics="dlft")
    with pytest.raises(ValueError, match="method must be 'auto', 'stepping' or 'polynomial' .* got 'exact'"):
        fw.wear_history(pi, 4.0, "exact")


def test_the_1d_contact_solver_refuses_a_model_with_pairs():
    from fretwear.hbm import solve_periodic

    with pytest.raises(ValueError, match="model has contact pairs, which this solver of 1-D friction"):
        solve_periodic(fw.paper_interface(), 4.0)


@pytest.mark.parametrize("job", ["continuation", "linear_frf", "shooting", "shooting_sweep"])
def test_jobs_of_1d_contacts_refuse_a_model_with_pairs_and_pass_the_others_on(job):
    with pytest.raises(ValueError, match=f"{job} applies to models with contacts; this model has pairs"):
        getattr(fw, job)(fw.paper_interface(), 4.0)
    assert getattr(fw, job).__name__ == job


def test_linear_frf_through_the_front_is_the_hbm_one():
    from fretwear.hbm import linear_frf

    model, omegas = fw.paper_model(), 2 * np.pi * np.array([0.5, 1.0, 1.5])
    assert np.array_equal(fw.linear_frf(model, omegas), linear_frf(model, omegas))
