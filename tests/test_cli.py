"""Tests of the command line interface (fretwear.cli).

Every command is run in-process through ``main`` and checked against the
library call it wraps, and the linear FRFs against the closed-form responses
of the paper's 2-DOF model.
"""

import csv
import json
import os
import re
import subprocess
import sys
import warnings
from pathlib import Path

import numpy as np
import pytest

from fretwear import cli, paper_model, solve_periodic, wear_history
from fretwear.hbm.continuation import sweep
from fretwear.hbm.linear import linear_frf
from fretwear.model import jenkins_oscillator

ROOT = Path(__file__).resolve().parents[1]
PAPER_FILE = str(ROOT / "fretwear" / "data" / "paper_2dof.toml")
PAPER_COLUMNS = [
    "f_hz", "x1_h1", "x1_half_p2p", "x2_h1", "x2_half_p2p", "xr_h1", "xr_half_p2p",
    "sliding_distance", "friction_energy", "converged", "residual", "iterations", "path",
]  # fmt: skip
FREQS = np.linspace(0.4, 1.1, 5)  # Hz: stuck, stick-slip and stuck points
BAND = ["--fmin", "0.4", "--fmax", "1.1", "--n", "5"]
RTOL = 1e-12


def read_csv(path: Path) -> tuple[list[str], list[dict[str, str]]]:
    with open(path, newline="") as fh:
        reader = csv.DictReader(fh)
        return list(reader.fieldnames or []), list(reader)


def column(rows: list[dict[str, str]], name: str) -> np.ndarray:
    return np.array([float(r[name]) for r in rows])


def run(capsys, *argv: str) -> tuple[int, str, str]:
    code = cli.main(list(argv))
    out, err = capsys.readouterr()
    return code, out, err


# -- help -------------------------------------------------------------------------
def test_console_help_in_a_subprocess():
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    for module in ("fretwear", "fretwear.cli"):
        done = subprocess.run(
            [sys.executable, "-m", module, "--help"], capture_output=True, text=True, env=env, timeout=60
        )
        assert done.returncode == 0, done.stderr
        assert all(name in done.stdout for name in ("frf", "linear", "point", "Exit status"))


@pytest.mark.parametrize("command", ["frf", "linear", "point"])
def test_help_documents_units(capsys, command):
    code, out, _ = run(capsys, command, "--help")
    assert code == 0
    text = " ".join(out.split())
    units = {"--fex": "N", "--mu": "-", "--fn": "N", "--u0": "m", "--kn": "N/m"}
    if command == "point":
        units |= {"--f": "Hz", "--harmonics": "-", "--samples": "-"}
    else:
        units |= {"--fmin": "Hz", "--fmax": "Hz", "--n": "-"}
    if command == "frf":
        units |= {"--harmonics": "-", "--samples": "-"}
    for option, unit in units.items():
        assert re.search(rf"{re.escape(option)} [A-Z0-9_]+ [^(]*\({re.escape(unit)}\)", text), option


# -- frf --------------------------------------------------------------------------
def test_frf_sweep_equals_library(tmp_path, capsys):
    out = tmp_path / "frf.csv"
    code, _, err = run(capsys, "frf", *BAND, "--harmonics", "5", "--out", str(out))
    assert code == cli.EXIT_OK
    assert "5 converged, 0 not converged" in err and len(err.strip().splitlines()) == 1
    names, rows = read_csv(out)
    assert names[: len(PAPER_COLUMNS)] == PAPER_COLUMNS
    assert len(rows) == len(FREQS)
    sols = sweep(paper_model(), 2 * np.pi * FREQS, 5).solutions
    assert {s.path for s in sols} >= {"linear-stuck"} and any(s.sliding_distance[0] > 0 for s in sols)
    np.testing.assert_allclose(column(rows, "f_hz"), FREQS, rtol=RTOL)
    for i, dof in enumerate(("x1", "x2")):
        np.testing.assert_allclose(column(rows, f"{dof}_h1"), [s.amplitude[i] for s in sols], rtol=RTOL)
        np.testing.assert_allclose(
            column(rows, f"{dof}_half_p2p"), [s.half_peak_to_peak[i] for s in sols], rtol=RTOL
        )
    for name, values in (
        ("xr_h1", [s.relative_amplitude[0] for s in sols]),
        ("xr_half_p2p", [s.relative_half_peak_to_peak[0] for s in sols]),
        ("sliding_distance", [s.sliding_distance[0] for s in sols]),
        ("friction_energy", [s.friction_energy[0] for s in sols]),
        ("residual", [s.residual for s in sols]),
    ):
        np.testing.assert_allclose(column(rows, name), values, rtol=RTOL, atol=1e-300, err_msg=name)
    assert [r["converged"] for r in rows] == ["True"] * len(FREQS)
    assert [r["path"] for r in rows] == [s.path for s in sols]
    assert [int(r["iterations"]) for r in rows] == [s.iterations for s in sols]


def test_frf_model_file_matches_paper_options(tmp_path, capsys):
    paper, fromfile = tmp_path / "paper.csv", tmp_path / "file.csv"
    assert run(capsys, "frf", *BAND, "--harmonics", "3", "--out", str(paper))[0] == 0
    assert (
        run(capsys, "frf", "--model", PAPER_FILE, *BAND, "--harmonics", "3", "--out", str(fromfile))[0] == 0
    )
    _, a = read_csv(paper)
    names, b = read_csv(fromfile)
    expected = ["x1_h1", "x1_half_p2p", "x2_h1", "x2_half_p2p", "xr1_h1", "xr1_half_p2p", "sliding_distance1"]
    assert set(expected) <= set(names) and "xr_h1" not in names
    renamed = {"xr1_h1": "xr_h1", "xr1_half_p2p": "xr_half_p2p", "sliding_distance1": "sliding_distance"}
    for name in ("f_hz", *expected):
        np.testing.assert_allclose(
            column(b, name), column(a, renamed.get(name, name)), rtol=1e-10, atol=1e-18
        )


def test_frf_continuation_rows_follow_the_branch(tmp_path, capsys):
    out = tmp_path / "branch.csv"
    code, _, err = run(capsys, "frf", *BAND, "--harmonics", "5", "--continuation", "--out", str(out))
    assert code == cli.EXIT_OK, err
    _, rows = read_csv(out)
    f = column(rows, "f_hz")
    assert len(rows) > len(FREQS)  # the branch points, not the --n grid
    assert f[0] == pytest.approx(0.4) and f[-1] == pytest.approx(1.1)
    assert all(r["converged"] == "True" for r in rows)
    assert column(rows, "sliding_distance").max() > 0


def test_frf_reports_non_converged_points(tmp_path, capsys, monkeypatch):
    def failing_sweep(*args, **kwargs):
        result = sweep(*args, **kwargs)
        result.solutions[1].converged, result.solutions[1].residual = False, 0.25
        return result

    monkeypatch.setattr(cli.frf, "sweep", failing_sweep)
    out = tmp_path / "frf.csv"
    code, _, err = run(capsys, "frf", *BAND, "--harmonics", "3", "--out", str(out))
    assert code == cli.EXIT_NOT_CONVERGED == 3
    assert "4 converged, 1 not converged" in err
    _, rows = read_csv(out)
    assert len(rows) == len(FREQS)
    assert rows[1]["converged"] == "False" and float(rows[1]["residual"]) == 0.25


# -- linear -----------------------------------------------------------------------
def test_linear_equals_closed_form_and_library(tmp_path, capsys):
    out = tmp_path / "linear.csv"
    code, _, _ = run(capsys, "linear", *BAND, "--fex", "3", "--out", str(out))
    assert code == 0
    names, rows = read_csv(out)
    assert names == ["f_hz", "state", "x1_h1", "x1_half_p2p", "x2_h1", "x2_half_p2p", "xr_h1", "xr_half_p2p"]
    assert [r["state"] for r in rows] == ["stuck"] * 5 + ["open"] * 5
    w = 2 * np.pi * FREQS
    k1, k2 = np.pi**2, 7 * np.pi**2
    c1, c2 = 2e-3 * np.sqrt(k1), 2e-3 * np.sqrt(k2)
    stuck = 3 / np.abs(k1 + k2 - 2 * w**2 + 1j * (c1 + c2) * w)
    free = 3 / np.abs(k1 - w**2 + 1j * c1 * w)
    expected = {
        "stuck": {"x1": stuck, "x2": stuck, "xr": 0 * w},
        "open": {"x1": free, "x2": 0 * w, "xr": free},
    }
    for state, block in (("stuck", rows[:5]), ("open", rows[5:])):
        np.testing.assert_allclose(column(block, "f_hz"), FREQS, rtol=RTOL)
        U = np.abs(linear_frf(paper_model(fex=3), w, state=state))
        for name, value in expected[state].items():
            for kind in ("h1", "half_p2p"):
                np.testing.assert_allclose(column(block, f"{name}_{kind}"), value, rtol=1e-9, atol=1e-12)
        np.testing.assert_allclose(column(block, "x1_h1"), U[:, 0], rtol=RTOL)
        np.testing.assert_allclose(column(block, "x2_h1"), U[:, 1], rtol=RTOL)


def test_linear_single_state_and_model_file(tmp_path, capsys):
    out = tmp_path / "linear.csv"
    code, _, _ = run(capsys, "linear", "--model", "jenkins", *BAND, "--state", "open", "--out", str(out))
    assert code == 0
    names, rows = read_csv(out)
    assert names == [
        "f_hz",
        "state",
        "x1_h1",
        "x1_half_p2p",
        "x2_h1",
        "x2_half_p2p",
        "xr1_h1",
        "xr1_half_p2p",
    ]
    assert {r["state"] for r in rows} == {"open"} and len(rows) == 5
    U = np.abs(linear_frf(jenkins_oscillator(), 2 * np.pi * FREQS, state="open"))
    np.testing.assert_allclose(column(rows, "x1_h1"), U[:, 0], rtol=RTOL)
    np.testing.assert_allclose(column(rows, "xr1_h1"), U[:, 1], rtol=RTOL)  # contact of DOF 2 to ground


# -- point -------------------------------------------------------------------------
def test_point_equals_solve_periodic(capsys):
    argv = ["--fex", "5", "--mu", "0.5", "--u0", "2e-6", "--kn", "5e6", "--harmonics", "5"]
    code, out, err = run(capsys, "point", "--f", "0.7", *argv)
    assert code == 0 and "converged" in err
    got = json.loads(out)
    sol = solve_periodic(paper_model(fex=5, mu=0.5, normal_load=5e6 * 2e-6, kn=5e6), 2 * np.pi * 0.7, 5)
    assert sol.path.startswith("dlft") and sol.sliding_distance[0] > 0
    expected = {
        "f_hz": sol.frequency,
        "x1_h1": sol.amplitude[0],
        "x1_half_p2p": sol.half_peak_to_peak[0],
        "x2_h1": sol.amplitude[1],
        "xr_h1": sol.relative_amplitude[0],
        "xr_half_p2p": sol.relative_half_peak_to_peak[0],
        "sliding_distance": sol.sliding_distance[0],
        "friction_energy": sol.friction_energy[0],
        "residual": sol.residual,
        "input_work": sol.input_work,
        "viscous_dissipation": sol.viscous_dissipation,
    }
    for key, value in expected.items():
        assert got[key] == pytest.approx(value, rel=RTOL, abs=1e-300), key
    assert (got["converged"], got["iterations"], got["path"]) == (True, sol.iterations, sol.path)
    assert got["half_wave"] is True and got["harmonics"] == 5


def test_point_model_file_keys(capsys):
    code, out, _ = run(capsys, "point", "--f", "0.7", "--model", PAPER_FILE, "--harmonics", "3")
    assert code == 0
    got = json.loads(out)
    assert {"x1_h1", "x2_half_p2p", "xr1_h1", "xr1_half_p2p", "sliding_distance1", "friction_energy1"} <= set(
        got
    )
    sol = solve_periodic(paper_model(), 2 * np.pi * 0.7, 3)
    assert got["xr1_h1"] == pytest.approx(sol.relative_amplitude[0], rel=1e-10)


def test_point_not_converged_exit_status(capsys, monkeypatch):
    def failing(*args, **kwargs):
        sol = solve_periodic(*args, **kwargs)
        sol.converged, sol.message = False, "no convergence in 50 iterations"
        return sol

    monkeypatch.setattr(cli.point, "solve_periodic", failing)
    code, out, err = run(capsys, "point", "--f", "0.7", "--harmonics", "3")
    assert code == cli.EXIT_NOT_CONVERGED
    assert json.loads(out)["converged"] is False and "NOT converged" in err


# -- bad input ------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("argv", "needle"),
    [
        (["frf", "--fmin", "0", "--fmax", "1", "--out", "x.csv"], "--fmin: must be a number > 0 and <= 1"),
        (["frf", "--fmin", "1", "--fmax", "0.5", "--out", "x.csv"], "--fmax: must be >= --fmin"),
        (["frf", *BAND[:4], "--n", "0", "--out", "x.csv"], "--n: must be an integer in [1, 10001]"),
        (["frf", *BAND, "--harmonics", "0", "--out", "x.csv"], "--harmonics: must be an integer in [1, 64]"),
        (
            ["frf", *BAND, "--harmonics", "5", "--samples", "10", "--out", "x.csv"],
            "--samples: must be >= 2 Nh + 1",
        ),
        (
            ["frf", "--fmin", "1", "--fmax", "1", "--continuation", "--out", "x.csv"],
            "--fmax: must be > --fmin",
        ),
        (["frf", *BAND, "--out", "no/such/dir/x.csv"], "--out:"),
        (["linear", *BAND, "--kn", "-1", "--out", "x.csv"], "--kn: must be a number > 0 and <= 1e+12 N/m"),
        (["linear", *BAND, "--state", "sliding", "--out", "x.csv"], "--state: invalid choice"),
        (["point", "--f", "abc"], "--f: must be a number > 0 and <= 100000 Hz"),
        (["point", "--f", "1", "--mu", "-1"], "--mu: must be a number > 0"),
        (["point", "--f", "1", "--fn", "-3"], "--fn: must be a number > 0 and <= 10000 N"),
        (["point", "--f", "1", "--u0", "-1e-6"], "--u0:"),
        (["point", "--f", "1", "--fn", "5", "--u0", "1e-6"], "--u0: not allowed with argument --fn"),
        (["point", "--f", "1", "--model", "missing.toml"], "--model: missing.toml: cannot read file"),
        (["point", "--f", "1", "--model", PAPER_FILE, "--fex", "2"], "--model: not allowed with"),
        (["point"], "--f"),
        ([], "COMMAND"),
    ],
)
def test_bad_input_is_one_line_and_exit_2(capsys, argv, needle):
    code, out, err = run(capsys, *argv)
    assert code == cli.EXIT_USAGE == 2
    assert out == ""
    assert len(err.strip().splitlines()) == 1 and "Traceback" not in err
    assert needle in err


def test_malformed_model_file_names_file_and_key(tmp_path, capsys):
    bad = tmp_path / "bad.toml"
    bad.write_text(Path(PAPER_FILE).read_text().replace("mu = 1.0", "mu = -1.0"))
    code, _, err = run(capsys, "point", "--f", "1", "--model", str(bad))
    assert code == 2 and len(err.strip().splitlines()) == 1
    assert str(bad) in err and "friction[1].mu" in err and ">= 0" in err


def test_library_value_error_becomes_a_message(capsys, monkeypatch):
    def reject(*args, **kwargs):
        raise ValueError("eps must be finite and > 0 N/m,\n got -1")

    monkeypatch.setattr(cli.point, "solve_periodic", reject)
    code, out, err = run(capsys, "point", "--f", "1")
    assert (code, out) == (2, "")
    assert err == "fretwear point: error: eps must be finite and > 0 N/m, got -1\n"


# -- wear, map and cost ---------------------------------------------------------------
def test_wear_command_writes_the_history(tmp_path, capsys):
    out = tmp_path / "wear.csv"
    assert cli.main(["wear", "--f", "0.7", "--cycles", "2e4", "--harmonics", "3", "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    assert {"cycles", "w", "w_over_u0", "fn", "dw_dn", "x1_h1", "xr_half_p2p", "sliding_distance"} <= set(
        rows[0]
    )
    w = np.array([float(r["w"]) for r in rows])
    assert w[0] == 0 and np.all(np.diff(w) >= 0) and w[-1] < 1e-6
    np.testing.assert_allclose([float(r["fn"]) for r in rows], 1e7 * (1e-6 - w), rtol=1e-9)


def test_map_command_long_format_and_npz(tmp_path):
    out = tmp_path / "map.csv"
    args = ["map", "--fmin", "0.5", "--fmax", "0.9", "--nf", "3", "--ncycles", "4", "--cycles", "1e4",
            "--harmonics", "3"]  # fmt: skip
    assert cli.main([*args, "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    assert len(rows) == 12 and {"f_hz", "cycles", "w", "w_over_u0"} <= set(rows[0])
    npz = tmp_path / "map.npz"
    assert cli.main([*args, "--out", str(npz)]) == 0
    data = np.load(npz)
    assert data["wear"].shape == (3, 4, 1)
    np.testing.assert_allclose(data["wear"].ravel(), [float(r["w"]) for r in rows])


def test_cost_command(tmp_path, capsys):
    out = tmp_path / "cost.csv"
    assert cli.main(["cost", "--f", "0.7", "--quick", "--target", "0.05", "--out", str(out)]) == 0
    rows = list(csv.DictReader(out.open()))
    assert rows[0]["method"] == "shooting" and any(r["method"] == "dlft" for r in rows)
    assert sum(r["recommended"] == "True" for r in rows) == 1
    assert "reference" in capsys.readouterr().err


@pytest.mark.parametrize(
    "argv,fragment",
    [
        (["wear", "--f", "0.7", "--kw", "-1", "--out", "x.csv"], "--kw"),
        (["wear", "--f", "0.7", "--cycles", "0", "--out", "x.csv"], "--cycles"),
        (["wear", "--f", "0.7", "--method", "polynomial", "--degree", "13", "--out", "x.csv"], "--degree"),
        (["wear", "--f", "0.7", "--method", "polynomial", "--degree", "0", "--out", "x.csv"], "--degree"),
        (["wear", "--f", "0.7", "--method", "polynomial", "--basis", "cubic", "--out", "x.csv"], "--basis"),
        (["wear", "--f", "0.7", "--tol", "2", "--out", "x.csv"], "--tol"),
        (["map", "--fmin", "1", "--fmax", "0.5", "--out", "x.csv"], "--fmax"),
        (["cost", "--f", "0.7", "--kw", "1e-11", "--out", "x.csv"], "--kw and --cycles"),
        (["wear", "--f", "0.7", "--fn", "0", "--out", "x.csv"], "--fn: must be a number > 0"),
    ],
)
def test_wear_bad_input(tmp_path, monkeypatch, capsys, argv, fragment):
    monkeypatch.chdir(tmp_path)
    assert cli.main(argv) == 2
    err = capsys.readouterr().err
    assert fragment in err and "Traceback" not in err


def test_figures_command_writes_the_paper_set(tmp_path, capsys):
    """The paper's set at the size asked; a wear coefficient that breaks the two-scale assumption is
    reported in lines of the command (as ``wear`` does), never as Python's ``RuntimeWarning`` with its
    source line."""
    out = tmp_path / "figs"
    argv = ["figures", "--out", str(out), "--harmonics", "3", "--nf", "4", "--ncycles", "5",
            "--cycles", "1e4", "--kw", "1e-9", "--formats", "png,csv", "--width", "4", "--height", "3",
            "--dpi", "50"]  # fmt: skip
    with warnings.catch_warnings(record=True) as leaked:  # what Python would print with its source line
        warnings.simplefilter("always")
        assert cli.main(argv) == 0
    assert [str(w.message) for w in leaked] == []
    names = sorted(p.name for p in out.iterdir())
    assert [n for n in names if n.endswith(".png")] == [f"fig{k:02d}.png" for k in range(5, 15)]
    assert {png_size((out / n).read_bytes()) for n in names if n.endswith(".png")} == {(200, 150)}
    err = capsys.readouterr().err
    assert "RuntimeWarning" not in err and all(
        line.startswith("fretwear figures: ") for line in err.splitlines()
    )
    assert "fretwear figures: warning: fig07, 14 N, 0.3 Hz: " in err and "two-scale assumption" in err
    header = [line for line in (out / "fig07.csv").read_text().splitlines() if line.startswith("#")]
    assert "# k_w = 1e-09 1/N" in header and "# Nh = 3" in header


def png_size(data: bytes) -> tuple[int, int]:
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return int.from_bytes(data[16:20], "big"), int.from_bytes(data[20:24], "big")


def test_wear_reports_the_method_it_ran(tmp_path, capsys):
    """``auto`` is not a method: the message names the scheme and the dynamics that ran; with no
    options they are the exact ones, and an approximation comes with its error against them."""
    code, _, err = run(capsys, "wear", "--f", "0.7", "--cycles", "1e4", "--out", str(tmp_path / "w.csv"))
    assert code == 0 and err.startswith("fretwear wear: exact, ") and "auto" not in err
    assert "warning" not in err and "DLFT" not in err
    code, _, err = run(capsys, "wear", "--f", "0.7", "--cycles", "1e4", "--harmonics", "3", "--out",
                       str(tmp_path / "w3.csv"))  # fmt: skip
    assert code == 0 and "fretwear wear: exact slow time on DLFT, Nh = 3, " in err
    assert "against the exact answer: cycles to 50% of u₀ are " in err


def test_polynomial_bases_from_the_command_line(tmp_path, capsys):
    """``--basis`` offers the saturating basis, the library's default for one contact."""
    runs = {}
    for basis in ("saturating", "legendre", None):
        out = tmp_path / f"{basis}.csv"
        extra = [] if basis is None else ["--basis", basis]
        code, _, _ = run(capsys, "wear", "--f", "0.7", "--method", "polynomial", "--harmonics", "3",
                         "--cycles", "2e4", *extra, "--out", str(out))  # fmt: skip
        assert code == 0
        runs[basis] = column(read_csv(out)[1], "w")
    np.testing.assert_array_equal(runs[None], runs["saturating"])
    assert not np.array_equal(runs["legendre"], runs["saturating"])


@pytest.mark.parametrize(
    "argv,method",
    [
        (["wear", "--f", "0.7", "--method", "polynomial"], "polynomial"),
        (["wear", "--f", "0.7", "--method", "time"], "time"),
        (["map", "--fmin", "0.5", "--fmax", "0.9", "--nf", "3", "--method", "polynomial"], "polynomial"),
    ],
)
def test_dynamics_where_it_does_not_apply_is_an_error(tmp_path, capsys, argv, method):
    code, _, err = run(capsys, *argv, "--dynamics", "shooting", "--out", str(tmp_path / "x.csv"))
    assert code == 2 and f"argument --dynamics: not taken by method '{method}'" in err
    assert not (tmp_path / "x.csv").exists()


def test_settings_file_of_the_dashboard(tmp_path, capsys):
    """``--settings FILE``: the dashboard's settings file sets the options; the command line wins; keys
    another command takes (the scene, the map's grid) are ignored; bad values name the option and file."""
    from fretwear.figures.record import settings_json

    path = tmp_path / "view.json"
    path.write_text(settings_json({"fex": 14, "mu": 0.8, "kw": 1e-10, "cycles": 2000, "harmonics": 3,
                                   "f": 0.6, "nf": 11, "scene": "wearmap", "method": "exact"}))  # fmt: skip
    out = tmp_path / "w.csv"
    assert cli.main(["wear", "--settings", str(path), "--out", str(out)]) == 0
    model = paper_model(fex=14, mu=0.8)
    ref = wear_history(model, 2 * np.pi * 0.6, "exact", kw=1e-10, cycles=2000, harmonics=3)
    _, rows = read_csv(out)
    np.testing.assert_allclose(column(rows, "w"), ref.wear[:, 0], rtol=1e-12)
    assert cli.main(["wear", "--settings", str(path), "--f", "0.9", "--out", str(out)]) == 0
    ref = wear_history(model, 2 * np.pi * 0.9, "exact", kw=1e-10, cycles=2000, harmonics=3)
    np.testing.assert_allclose(column(read_csv(out)[1], "w"), ref.wear[:, 0], rtol=1e-12)
    capsys.readouterr()
    path.write_text('{"mu": -1}')
    code, _, err = run(capsys, "wear", "--settings", str(path), "--f", "0.7", "--out", str(out))
    assert code == 2 and err.startswith("fretwear wear: error: argument --mu (from --settings view.json):")
    path.write_text('{"fex": 10, "colour": "red"}')
    code, _, err = run(capsys, "point", "--settings", str(path), "--f", "0.7")
    assert code == 2 and "unknown keys ['colour']" in err and "Traceback" not in err
    code, _, err = run(capsys, "point", "--settings", str(tmp_path / "missing.json"), "--f", "0.7")
    assert code == 2 and "settings file" in err and "missing.json" in err


def test_map_and_wear_figures_carry_their_parameters(tmp_path, capsys):
    import xml.etree.ElementTree as ET

    out = tmp_path / "map.svg"
    argv = ["map", "--fmin", "0.5", "--fmax", "0.9", "--nf", "3", "--ncycles", "4", "--cycles", "1e4",
            "--harmonics", "3", "--fex", "12", "--out", str(out)]  # fmt: skip
    assert cli.main(argv) == 0
    text = "".join(ET.fromstring(out.read_text()).itertext())
    assert "Fₑₓ = 12 N" in text and "k_w = 1e-11 1/N" in text and "method = exact" in text
    out = tmp_path / "wear.png"
    assert cli.main(["wear", "--f", "0.7", "--cycles", "1e3", "--harmonics", "3", "--out", str(out)]) == 0
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n" and b"method = exact" in out.read_bytes()


def test_figures_bad_format(tmp_path, capsys):
    assert cli.main(["figures", "--out", str(tmp_path), "--formats", "gif"]) == 2
    assert "gif" in capsys.readouterr().err


def test_wear_warnings_are_lines_that_say_where(tmp_path, capsys):
    """The two-scale warning of a wear map names its frequency, in the command's format (and no Python
    warning is left for Python to print with its source line)."""
    with warnings.catch_warnings(record=True) as leaked:
        warnings.simplefilter("always")
        code, _, err = run(capsys, "map", "--fmin", "0.5", "--fmax", "0.7", "--nf", "2", "--ncycles", "4",
                           "--cycles", "1e3", "--harmonics", "3", "--fex", "14", "--mu", "0.8", "--kw",
                           "1e-10", "--out", str(tmp_path / "m.csv"))  # fmt: skip
        assert code == 0 and all(line.startswith("fretwear map: ") for line in err.splitlines())
        assert "fretwear map: warning: 0.5 Hz: wear per cycle at the start is" in err
        code, _, err = run(capsys, "wear", "--f", "0.5", "--cycles", "1e3", "--harmonics", "3",
                           "--fex", "14", "--mu", "0.8", "--kw", "1e-10",
                           "--out", str(tmp_path / "w.csv"))  # fmt: skip
        assert code == 0 and err.count("two-scale assumption") == 1
    assert [str(w.message) for w in leaked] == []


# -- compile notice ------------------------------------------------------------------
USED = """
import json, sys
import fretwear.compile as c
from fretwear import cli
from fretwear.cli.shared import model_and_names
args = cli.build_parser().parse_args(sys.argv[1:])
needs = cli.COMMANDS[args.command].kernel_needs(args, model_and_names(args)[0])
cli.main(sys.argv[1:])
used = {e for k in c.KERNELS.values() for e in k.entry_points if c._dispatcher(e).overloads}
print(json.dumps([sorted(used), sorted({e for n in needs for e in c.NEEDS[n].entry_points})]))
"""


@pytest.mark.parametrize(
    "argv",
    [
        ["map", "--nf", "3", "--ncycles", "4", "--method", "exact", "--dynamics", "shooting"],
        ["wear", "--f", "0.7", "--cycles", "2e4", "--method", "polynomial", "--harmonics", "3"],
        ["wear", "--f", "0.7", "--cycles", "2e4", "--harmonics", "3"],
    ],
)
def test_the_compile_notice_asks_for_exactly_the_kernels_the_command_runs(tmp_path, argv):
    """Issue 22: `map --method exact --dynamics shooting` and `wear --method polynomial` announced kernels
    they never run, so the notice showed on every run. In a new process (no kernel loaded, no sliding
    table on disk), the kernels the command loads are exactly those its notice asks the cache about."""
    env = {**os.environ, "PYTHONPATH": str(ROOT), "FRETWEAR_CACHE_DIR": ""}
    argv = [*argv, "--out", str(tmp_path / "x.csv")]
    done = subprocess.run([sys.executable, "-c", USED, *argv], capture_output=True, text=True, env=env,
                          timeout=300)  # fmt: skip
    assert done.returncode == 0, done.stderr
    used, asked = json.loads(done.stdout.splitlines()[-1])
    assert used == asked


def test_a_settings_file_written_as_the_help_suggests_runs(tmp_path, capsys):
    """Issue 22: {"fex": 14, "mu": 0.8, "kw": 1e-10} (the --help example) failed with "--fmin, --fmax
    required"; without --model the band defaults to the paper model's, 0.3-1.3 Hz."""
    settings = tmp_path / "s.json"
    settings.write_text('{"fex": 14, "mu": 0.8, "kw": 1e-10}')
    out = tmp_path / "m.csv"
    argv = ["map", "--settings", str(settings), "--nf", "3", "--ncycles", "4", "--out", str(out)]
    code, _, err = run(capsys, *argv)
    assert code == 0, err
    f = column(read_csv(out)[1], "f_hz")
    assert (f.min(), f.max()) == (0.3, 1.3)


def test_outputs_are_written_whole_with_the_usual_mode(tmp_path, capsys):
    """Files are written under a temporary name and renamed: none is left beside, and the mode is a new
    file's (not mkstemp's 0600)."""
    out = tmp_path / "x.csv"
    assert run(capsys, "linear", *BAND, "--out", str(out))[0] == 0
    assert [p.name for p in tmp_path.iterdir()] == ["x.csv"]
    mask = os.umask(0)
    os.umask(mask)
    assert out.stat().st_mode & 0o777 == 0o666 & ~mask
