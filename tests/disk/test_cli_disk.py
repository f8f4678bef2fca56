"""``fretwear disk``: the ZZENF diagram and the magnification factors as CSV, the library's numbers."""

import csv

import numpy as np
import pytest

import fretwear as fw
from fretwear.cli import EXIT_OK, EXIT_USAGE, main
from fretwear.disk import draw_mistuning, magnification, sweep_sector
from fretwear.model import DiskSector, bladed_disk


def _rows(path):
    with open(path) as fh:
        return list(csv.DictReader(fh))


def test_modes_are_the_sectors_frequencies_per_nodal_diameter(tmp_path):
    out = tmp_path / "zz.csv"
    assert main(["disk", "modes", "--out", str(out)]) == EXIT_OK
    rows = _rows(out)
    table = np.array([[float(r[f"f{j}_hz"]) for j in (1, 2, 3)] for r in rows])
    assert [int(r["nodal_diameter"]) for r in rows] == list(range(13))
    assert np.array_equal(table, DiskSector().zzenf())
    assert table[0, 0] == pytest.approx(88.26374399, rel=1e-8)  # the published lowest frequency


def test_mistuning_writes_the_librarys_factors(tmp_path, capsys):
    out = tmp_path / "m.csv"
    argv = ["disk", "mistuning", "--level", "0.02", "--samples", "5", "--seed", "7", "--out", str(out)]
    assert main(argv) == EXIT_OK
    ref = magnification(draw_mistuning(24, 0.02, 5, seed=7), (165.0, 200.0), engine_order=3)
    rows = _rows(out)
    assert np.array_equal([float(r["magnification"]) for r in rows], ref.factor)
    assert [int(r["blade"]) for r in rows] == ref.blade.tolist()
    assert "Whitehead's bound 2.949" in capsys.readouterr().err


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--level", "0.9"], "--level: must be a number >= 0 and <= 0.5"),
        (["--sectors", "2"], "--sectors: must be an integer in [3, 1000]"),
        (["--fmin", "200", "--fmax", "150"], "--fmax: must be > --fmin"),
        (["--samples", "0"], "--samples"),
    ],
)
def test_bad_options_are_named(argv, message, tmp_path, capsys):
    assert main(["disk", "mistuning", *argv, "--out", str(tmp_path / "x.csv")]) == EXIT_USAGE
    assert message in capsys.readouterr().err


def test_frf_of_the_tuned_disk_is_the_sector_sweep(tmp_path, capsys):
    out = tmp_path / "frf.csv"
    argv = ["disk", "frf", "--sectors", "6", "--engine-order", "1", "--fmin", "216", "--fmax", "232",
            "--n", "5", "--harmonics", "3", "--out", str(out)]  # fmt: skip
    assert main(argv) == EXIT_OK
    model = bladed_disk(6, engine_order=1, fex=2.0)
    ref = sweep_sector(model, 2 * np.pi * np.linspace(216, 232, 5), 3)
    rows = _rows(out)
    tips = np.array([[float(r[f"tip{i}_m"]) for i in range(6)] for r in rows])
    assert np.array_equal(tips, [s.amplitude[2::3] for s in ref.solutions])
    assert "tuned, one sector, DLFT Nh = 3: an approximation" in capsys.readouterr().err


def test_wear_of_a_mistuned_disk_differs_between_blades(tmp_path, capsys):
    out = tmp_path / "w.csv"
    argv = ["disk", "wear", "--sectors", "6", "--engine-order", "1", "--f", "222", "--level", "0.02",
            "--kw", "3e-7", "--cycles", "2e4", "--harmonics", "3", "--out", str(out)]  # fmt: skip
    assert main(argv) == EXIT_OK
    model = bladed_disk(6, engine_order=1, fex=2.0, mistuning=draw_mistuning(6, 0.02, 1, seed=0)[0])
    ref = fw.wear_history(model, 2 * np.pi * 222, "stepping", kw=3e-7, cycles=2e4, harmonics=3)
    last = _rows(out)[-1]
    w = np.array([float(last[f"w{i}_m"]) for i in range(6)])
    assert np.array_equal(w, ref.wear[-1]) and np.ptp(w) > 0.01 * w.max()
    assert "mistuned, full disk" in capsys.readouterr().err
