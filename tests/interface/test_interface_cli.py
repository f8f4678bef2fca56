"""``fretwear interface`` (add_arguments / run, wired into the fretwear CLI elsewhere)."""

import argparse
import csv
import json

import numpy as np
import pytest

from fretwear.interface.cli import COLUMNS, add_arguments, run
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.modelfile import write_interface_model


def _run(argv):
    parser = argparse.ArgumentParser(prog="fretwear interface")
    add_arguments(parser)
    return run(parser.parse_args(argv))


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
    with pytest.raises(SystemExit):
        _run(["--q-ratio", "-1"])
    with pytest.raises(SystemExit):
        _run(["--contact-nodes", "2"])
