"""``fretwear disk``: the ZZENF diagram and the magnification factors as CSV, the library's numbers."""

import csv

import numpy as np
import pytest

from fretwear.cli import EXIT_OK, EXIT_USAGE, main
from fretwear.disk import draw_mistuning, magnification
from fretwear.model import DiskSector


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
