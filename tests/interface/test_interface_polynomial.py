"""Polynomial slow-time method on the benchmark interface, against the adaptive slow-time stepping."""

import argparse
import csv

import numpy as np
import pytest

from fretwear.cli.interface import add_arguments, run
from fretwear.interface.contact import STICK
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem
from fretwear.interface.polynomial import wear_polynomial_interface
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.wear import wear_interface
from fretwear.model import craig_bampton

F_HZ, NH, KW = 50.0, 5, 1e-14


def _problem(**changes):
    model = cylinder_on_flat(contact_nodes=16, **changes)
    cond = ContactCondensation(craig_bampton(model, NH * F_HZ))
    return model, InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH)


def _wear_at(hist, cycles):
    """The polynomial's worn depths (nc,) at cycle counts ``cycles`` (m)."""
    m = hist.info["degree"]
    V = np.polynomial.legendre.legvander(2 * np.asarray(cycles) / hist.cycles[-1] - 1, m)
    return V @ hist.info["coefficients"]


@pytest.fixture(scope="module", params=["partial", "gross"])
def case(request):
    if request.param == "partial":  # Q0 = 0.5 mu P: the slip annulus wears until it unloads
        model, prob = _problem(q_ratio=0.5)
        cycles = 3e5
    else:  # displacement control, arm force 3.3 mu P: the scar widens
        model, prob = _problem(window=3.0, arm_stiffness=2e10, drive_displacement=2e-5)
        cycles = 3e4
    ref = wear_interface(prob, KW, cycles, rtol=3e-4)  # local error 3e-4 of the depth per step
    poly = wear_interface(prob, KW, cycles, method="polynomial", degree=6)
    return request.param, model, ref, poly


def test_polynomial_matches_the_slow_time_stepping(case):
    """Wear and pressure profiles over the history and at the end, to a few 1e-3 of their largest values.

    Measured: partial slip 3.5e-4 (wear, end), 1.5e-4 (pressure, end); gross slip 2.4e-4 and 1.1e-3.
    """
    name, model, ref, poly = case
    assert ref.converged and poly.converged, poly.message
    assert poly.info["residual"] <= 1e-8 and poly.info["iterations"] >= 1
    wmax = ref.wear[-1].max()
    assert np.abs(poly.wear[-1] - ref.wear[-1]).max() <= 2e-3 * wmax
    assert np.abs(_wear_at(poly, ref.cycles) - ref.wear).max() <= 5e-3 * wmax
    pmax = ref.pressure[-1].max()
    assert np.abs(poly.pressure[-1] - ref.pressure[-1]).max() <= 5e-3 * pmax
    # the pressure integral stays the normal load at every record
    assert np.abs(poly.normal_force_sum / model.info["normal_load"] - 1).max() < 1e-6
    # the polynomial agrees with its own Archard law along the records (trapezoid over 20 intervals)
    assert poly.info["wear_defect"] < 1e-2
    if name == "partial":  # the stick zone stays unworn: zero rate at every node, exactly zero polynomial
        never = np.all(ref.state[0] == STICK, axis=1)  # pairs that never slip in the unworn contact
        assert never.sum() >= 4 and np.all(poly.wear[:, never] == 0)


def test_failure_is_reported_with_its_residual():
    _, prob = _problem(q_ratio=0.5)
    hist = wear_polynomial_interface(prob, KW, 3e5, degree=3, max_iter=0)
    assert not hist.converged and "Galerkin residual" in hist.message
    assert hist.info["residual"] > 1e-8
    with pytest.raises(ValueError, match="degree must be"):
        wear_polynomial_interface(prob, KW, 3e5, degree=0)
    with pytest.raises(ValueError, match="method must be"):
        wear_interface(prob, KW, 3e5, method="exact")


def test_cli_polynomial_method(tmp_path):
    parser = argparse.ArgumentParser(prog="fretwear interface")
    add_arguments(parser)
    f = tmp_path / "wear.csv"
    argv = ["--contact-nodes", "12", "--harmonics", "3", "--kw", "1e-14", "--cycles", "2e4", "--method",
            "polynomial", "--degree", "3", "--out", str(f)]  # fmt: skip
    assert run(parser.parse_args(argv)) == 0
    rows = list(csv.DictReader(f.open()))
    cycles = sorted({float(r["cycles"]) for r in rows})
    assert cycles[-1] == pytest.approx(2e4) and len(rows) == 12 * len(cycles)
    assert max(float(r["w"]) for r in rows) > 0
    with pytest.raises(SystemExit, match="2"):  # degree out of [1, 12]: refused by the parser
        parser.parse_args(argv[:-4] + ["--degree", "13"])
