"""Tests of fretwear.wear.history and the defaults of every slow-time entry point: exact by default.

Oracle: direct time integration with wear (``method="time"``: the event-driven
dynamics marched period after period, Archard's law integrated along them, with
cycle jumps), independent of the sliding tables, the load walk and every
periodic solver. With no options, ``fw.wear_history``, ``fw.wear_map`` and
``fretwear wear`` must agree with it within 1e-3 on the cycles to 0.5 u0, where
the two-scale assumption holds (wear per cycle times the relaxation time of
the structure small against u0: the cases below; the gap grows with ``K_w``).
"""

from __future__ import annotations

import csv
import warnings

import numpy as np
import pytest

import fretwear as fw
from fretwear import cli
from fretwear.model import FrictionContact, Model, NormalContact
from fretwear.wear import describe, resolve_dynamics

TWO_PI = 2 * np.pi
#: (F_ex N, f Hz, K_w 1/N): two-scale cases, stick-slip near the paper's resonances
CASES = [(10.0, 0.7, 1e-11), (6.0, 1.05, 1e-11), (14.0, 0.45, 1e-12)]


def _time_integration(fex: float, f: float, kw: float) -> fw.WearHistory:
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        return fw.wear_history(fw.paper_model(fex=fex), TWO_PI * f, "time", kw=kw, cycles=1e9, tol=1e-4)


@pytest.fixture(scope="module")
def references() -> dict:
    return {case: _time_integration(*case) for case in CASES}


@pytest.mark.parametrize("case", CASES)
def test_the_default_history_is_the_exact_answer(case, references):
    fex, f, kw = case
    hist = fw.wear_history(fw.paper_model(fex=fex), TWO_PI * f, kw=kw, cycles=1e9)
    assert (hist.method, hist.dynamics, hist.label) == ("exact", "shooting", "exact")
    ref = references[case]
    for fraction in (0.5, 0.9):
        assert abs(hist.cycles_to(fraction) / ref.cycles_to(fraction) - 1) < 1e-3


def test_the_default_map_is_the_exact_answer(references):
    fex, f, kw = CASES[0]
    ref = references[CASES[0]]
    cycles = np.array([0.0, ref.cycles_to(0.5)])
    wm = fw.wear_map(fw.paper_model(fex=fex), [0.5, f], cycles, kw=kw)
    assert wm.label == "exact"
    assert abs(wm.wear_fraction[1, 1, 0] - 0.5) < 1e-3  # w(N_0.5) = 0.5 u0 by the independent method


def test_the_cli_default_is_the_exact_answer(tmp_path, capsys, references):
    fex, f, kw = CASES[0]
    out = tmp_path / "w.csv"
    assert cli.main(["wear", "--f", str(f), "--kw", str(kw), "--cycles", "1e9", "--out", str(out)]) == 0
    assert capsys.readouterr().err.startswith("fretwear wear: exact, ")
    rows = list(csv.DictReader(out.open()))
    N = np.array([float(r["cycles"]) for r in rows])
    w = np.array([float(r["w_over_u0"]) for r in rows])
    n50 = np.interp(0.5, w, N)  # records are dense in wear: linear interpolation is within 1e-4
    assert abs(n50 / references[CASES[0]].cycles_to(0.5) - 1) < 1e-3


def test_the_cli_map_default_is_the_exact_answer(tmp_path, capsys, references):
    """``fretwear map`` with no method options: at the cycles time integration takes to 0.5 u0, the map
    reads 0.5 u0 (within 1e-3 of u0, a cycle error well under 1e-3 at this slope)."""
    fex, f, kw = CASES[0]
    n50 = references[CASES[0]].cycles_to(0.5)
    out = tmp_path / "m.csv"
    argv = ["map", "--fmin", "0.6", "--fmax", str(f), "--nf", "2", "--ncycles", "3", "--kw", str(kw),
            "--cycles", repr(float(n50)), "--out", str(out)]  # fmt: skip
    assert cli.main(argv) == 0
    assert capsys.readouterr().err.startswith("fretwear map: exact, ")
    rows = [r for r in csv.DictReader(out.open()) if float(r["f_hz"]) == f]
    assert abs(float(rows[-1]["cycles"]) / n50 - 1) < 1e-12 and abs(float(rows[-1]["w_over_u0"]) - 0.5) < 1e-3


def test_asking_for_harmonics_asks_for_dlft_and_says_so():
    model = fw.paper_model()
    assert resolve_dynamics(model) == "shooting"
    assert resolve_dynamics(model, harmonics=7) == "dlft"
    assert resolve_dynamics(model, "dlft") == "dlft"
    with pytest.raises(ValueError, match="dynamics='shooting' .* takes neither"):
        resolve_dynamics(model, "shooting", harmonics=7)
    with pytest.raises(ValueError, match="dynamics must be one of 'auto', 'shooting', 'dlft', got 'exact'"):
        resolve_dynamics(model, "exact")
    hist = fw.wear_history(model, TWO_PI * 0.7, "exact", kw=1e-11, cycles=2e4, harmonics=7)
    assert (hist.dynamics, hist.harmonics) == ("dlft", 7)
    assert hist.label == "exact slow time on DLFT, Nh = 7"


def test_where_the_exact_dynamics_do_not_apply_dlft_runs_and_the_label_says_so():
    """A unilateral contact: the event-driven integrator does not take it, auto falls back to DLFT."""
    base = fw.paper_model()
    model = Model(M=base.M, C=base.C, K=base.K, force_cos=base.force_cos, friction=base.friction,
                  normal=(NormalContact(1, None, 1.0),))  # fmt: skip
    assert resolve_dynamics(model) == "dlft"
    with pytest.raises(ValueError, match="unilateral normal contacts"):
        resolve_dynamics(model, "shooting")
    hist = fw.wear_history(model, TWO_PI * 0.7, kw=1e-11, cycles=1e3)
    assert hist.label == "stepping on DLFT, Nh = 21"  # several contacts: stepping; no exact dynamics: DLFT
    assert any("an approximation: the exact dynamics do not apply" in w for w in hist.warnings)
    pair, ground = FrictionContact(0, 1, 1.0, 1e7, 1e-6), FrictionContact(0, None, 1.0, 1e7, 1e-6)
    two = Model(M=base.M, C=base.C, K=base.K, force_cos=base.force_cos, friction=(pair, ground))
    assert resolve_dynamics(two) == "shooting"  # several friction contacts: stepping on the exact dynamics
    hist = fw.wear_history(two, TWO_PI * 0.7, kw=1e-11, cycles=1e3)
    assert hist.label == "stepping on the exact dynamics"


@pytest.mark.parametrize(
    ("method", "dynamics", "nh", "label"),
    [
        ("exact", "shooting", None, "exact"),
        ("exact", "dlft", 21, "exact slow time on DLFT, Nh = 21"),
        ("stepping", "shooting", None, "stepping on the exact dynamics"),
        ("polynomial", "dlft", 3, "polynomial on DLFT, Nh = 3"),
        ("time", "time", None, "time integration (event-driven, cycle jumps)"),
    ],
)
def test_only_the_exact_answer_is_called_exact(method, dynamics, nh, label):
    assert describe(method, dynamics, nh) == label
    assert (label == "exact") == (method == "exact" and dynamics == "shooting")


def test_a_sliding_table_extended_to_higher_loads_keeps_the_exact_answers_accuracy(monkeypatch, references):
    """A table first built for a low load ratio (F_ex = 14 N, mu = 0.8: rho up to 0.57) and then extended
    up to the 6 N case's (rho 1.67) gave cycles to 0.5 u0 2.5e-3 off direct time integration (18
    samples), where a table built for the 6 N case alone is within 1e-4: the extension must refine as a
    new table does."""
    from fretwear.wear import sliding

    monkeypatch.setenv("FRETWEAR_CACHE_DIR", "")  # no table from disk: the order of the builds matters
    monkeypatch.setattr(sliding, "_cache", {})
    fex, f, kw = CASES[1]
    fw.wear_history(fw.paper_model(fex=14.0, mu=0.8), TWO_PI * f, kw=kw, cycles=1e3)
    hist = fw.wear_history(fw.paper_model(fex=fex), TWO_PI * f, kw=kw, cycles=1e9)
    assert abs(hist.cycles_to(0.5) / references[CASES[1]].cycles_to(0.5) - 1) < 1e-3
