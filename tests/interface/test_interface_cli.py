"""``fretwear interface`` (add_arguments / run, wired into the fretwear CLI elsewhere)."""

import argparse
import csv
import json

import numpy as np
import pytest

from fretwear.cli.interface import COLUMNS, add_arguments, run
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.modelfile import write_interface_model


def _run(argv):
    parser = argparse.ArgumentParser(prog="fretwear interface")
    add_arguments(parser)
    try:
        args = parser.parse_args(argv)
    except SystemExit as stop:  # a value out of the parameter table's range: argparse's exit 2
        return stop.code
    return run(args)


def test_static_prints_the_json_of_the_quasi_static_limit(capsys):
    assert _run(["--static", "--q-ratio", "0.5", "--contact-nodes", "16"]) == 0
    out = json.loads(capsys.readouterr().out)
    for key in ("contact_half_width", "stick_half_width", "peak_pressure", "normal_load_per_length",
                "tangential_load_per_length", "radius", "effective_modulus", "mu"):  # fmt: skip
        assert isinstance(out[key], float)
    assert out["tangential_load_per_length"] == pytest.approx(0.5 * out["mu"] * out["normal_load_per_length"])
    assert out["stick_half_width"] == pytest.approx(out["contact_half_width"] * np.sqrt(0.5), rel=0.05)


def test_wear_run_writes_one_row_per_record_and_pair(tmp_path, capsys):
    f = tmp_path / "wear.csv"
    code = _run(
        ["--contact-nodes", "12", "--harmonics", "3", "--kw", "1e-14", "--cycles", "2e4", "--out", str(f)]
    )
    assert code == 0
    rows = list(csv.DictReader(f.open()))
    assert tuple(rows[0]) == COLUMNS
    cycles = sorted({float(r["cycles"]) for r in rows})
    assert cycles[0] == 0 and cycles[-1] == pytest.approx(2e4) and len(rows) == 12 * len(cycles)
    last = [r for r in rows if float(r["cycles"]) == cycles[-1]]
    assert max(float(r["w"]) for r in last) > 0
    assert all(0 <= float(r["state_fraction_stick"]) <= 1 for r in rows)
    assert "records" in capsys.readouterr().err


def test_model_file_static_and_periodic(tmp_path, capsys):
    write_interface_model(cylinder_on_flat(contact_nodes=9), tmp_path / "m.toml")
    assert _run(["--model", str(tmp_path / "m.toml"), "--static"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["converged"] and out["regime"] == "partial slip"
    assert out["normal_force_sum"] == pytest.approx(2e5, rel=1e-8)
    assert (
        _run(["--model", str(tmp_path / "m.toml"), "--harmonics", "3", "--out", str(tmp_path / "p.csv")]) == 0
    )
    rows = list(csv.DictReader((tmp_path / "p.csv").open()))
    assert len(rows) == 9 and all(float(r["cycles"]) == 0 for r in rows)


def test_bad_model_file_is_a_one_line_usage_error(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text('[matrices]\nM = "M.mtx"\n[contact]\na = [[1, 2]]\n')
    assert _run(["--model", str(bad), "--static"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "bad.toml: matrices.K: missing required matrix" in err


def test_bad_option_values_are_rejected():
    assert _run(["--q-ratio", "-1"]) == 2
    assert _run(["--contact-nodes", "2"]) == 2


@pytest.mark.parametrize("q", ["1", "1.05", "5"])
def test_static_at_or_beyond_gross_slip_is_refused_up_front(q, tmp_path, capsys):
    """Q0 >= mu P has no static equilibrium: exit 2 before any work (it used to exit 0, converged = false)."""
    assert _run(["--static", "--q-ratio", q, "--out", str(tmp_path / "s.json")]) == 2
    err = capsys.readouterr().err.strip().splitlines()[-1]  # argparse's usage line first (fretwear: none)
    assert "--q-ratio" in err and ("[0, 1)" in err or "<= 2" in err)  # with --static; in any run
    assert not list(tmp_path.iterdir())


def test_model_file_static_without_equilibrium_exits_3(tmp_path, capsys):
    write_interface_model(cylinder_on_flat(contact_nodes=9, q_ratio=1.05), tmp_path / "m.toml")
    assert _run(["--model", str(tmp_path / "m.toml"), "--static", "--out", str(tmp_path / "s.json")]) == 3
    out = json.loads((tmp_path / "s.json").read_text())
    assert out["regime"] == "gross slip" and not out["converged"]
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "no static equilibrium" in err


def test_static_out_writes_json_or_csv_and_refuses_other_names(tmp_path, capsys):
    base = ["--static", "--q-ratio", "0.5", "--contact-nodes", "12"]
    assert _run([*base, "--out", str(tmp_path / "s.json")]) == 0
    assert _run([*base, "--out", str(tmp_path / "s.csv")]) == 0
    as_json = json.loads((tmp_path / "s.json").read_text())
    (row,) = list(csv.DictReader((tmp_path / "s.csv").open()))
    assert tuple(row) == tuple(as_json) and as_json["converged"] is True
    assert float(row["stick_half_width"]) == as_json["stick_half_width"]
    assert capsys.readouterr().out == ""  # nothing on stdout when --out is given
    assert _run([*base, "--out", str(tmp_path / "s.txt")]) == 2
    assert "--out" in capsys.readouterr().err and not (tmp_path / "s.txt").exists()


_INTERRUPTED_RUN = """
import sys
import fretwear.interface.wear as wear
rate = wear._rate
def marked(*args, **kwargs):  # tells the test that the wear history has started
    if not marked.seen:
        marked.seen = True
        print("history started", file=sys.stderr, flush=True)
    return rate(*args, **kwargs)
marked.seen = False
wear._rate = marked
from fretwear.cli import main
sys.exit(main(sys.argv[1:]))
"""


def test_ctrl_c_stops_a_wear_history_with_status_130_and_no_file(tmp_path):
    """Ctrl-C used to be swallowed inside a compiled Newton call: the history ran to its end and exited 0."""
    import signal
    import subprocess
    import sys
    import time

    out = tmp_path / "w.csv"
    # rtol 1e-7 to 1e30 cycles: several hundred steps, far longer than the wait below
    argv = ["interface", "--contact-nodes", "16", "--harmonics", "5", "--kw", "1e-14", "--cycles", "1e30",
            "--rtol", "1e-7", "--out", str(out)]  # fmt: skip
    proc = subprocess.Popen(
        [sys.executable, "-c", _INTERRUPTED_RUN, *argv], stderr=subprocess.PIPE, text=True, cwd=tmp_path
    )
    try:
        for line in proc.stderr:
            if "history started" in line:
                break
        time.sleep(1.0)  # well inside the loop of periodic solves
        proc.send_signal(signal.SIGINT)
        sent = time.perf_counter()
        code = proc.wait(timeout=60)
        elapsed = time.perf_counter() - sent
        err = proc.stderr.read().strip()
    finally:
        proc.kill()
    assert code == 130, err
    assert err.count("\n") == 0 and "interrupted" in err and "Traceback" not in err
    assert elapsed < 10  # one periodic solve of 16 pairs takes 0.03 s; generous for a loaded machine
    assert not out.exists() and not list(tmp_path.glob("*.part"))
