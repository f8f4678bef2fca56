"""Interface model files: matrices from another FE code plus contact pairs; one-line errors."""

import numpy as np
import pytest
import scipy.io
import scipy.sparse as sp

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.modelfile import read_interface_model, write_interface_model
from fretwear.interface.paper import paper_interface
from fretwear.model.modelfile import ModelFileError


def _write(tmp_path, text, K=None, n=4):
    K = sp.csr_matrix(np.diag([2.0, 2.0, 3.0, 3.0]) if K is None else K)
    scipy.io.mmwrite(tmp_path / "K.mtx", K)
    scipy.io.mmwrite(tmp_path / "M.mtx", sp.identity(n, format="csr"))
    np.savez(tmp_path / "arrays.npz", C=0.01 * np.eye(n))
    f = tmp_path / "model.toml"
    f.write_text(text)
    return f


GOOD = """
[matrices]
M = "M.mtx"
K = "K.mtx"
C = "arrays.npz:C"
[contact]
a = [[1, 2]]
b = [[3, 4]]
normal = [[0.0, 1.0]]
area = [1e-4]
mu = 0.5
[load.static]
dofs = [4]
values = [-10.0]
[load.cos]
dofs = [3]
values = [2.0]
[names]
pad_x = 3
"""


def test_reads_a_small_model(tmp_path):
    m = read_interface_model(_write(tmp_path, GOOD))
    assert m.n_dofs == 4 and m.n_pairs == 1
    assert m.pairs.dofs_a.tolist() == [[0, 1]] and m.pairs.dofs_b.tolist() == [[2, 3]]
    assert m.force_static.tolist() == [0, 0, 0, -10.0] and m.force_cos[2] == 2.0
    assert m.C.toarray()[0, 0] == 0.01 and m.names == {"pad_x": 2}


def test_round_trip_of_the_benchmark(tmp_path):
    m = cylinder_on_flat(contact_nodes=9)
    write_interface_model(m, tmp_path / "bench.toml", title="benchmark")
    m2 = read_interface_model(tmp_path / "bench.toml")
    for k in ("M", "K", "C"):
        assert abs(getattr(m2, k) - getattr(m, k)).max() == 0
    for k in ("dofs_a", "dofs_b", "normal", "area", "gap", "position", "mu"):
        assert np.array_equal(getattr(m2.pairs, k), getattr(m.pairs, k))
    assert np.array_equal(m2.force_static, m.force_static) and m2.names == m.names


def test_a_dense_model_with_pairs_is_written_too(tmp_path):
    """The paper's one-pair form has dense matrices; its file reads back as the same (sparse) model."""
    m = paper_interface()
    write_interface_model(m, tmp_path / "paper.toml")
    m2 = read_interface_model(tmp_path / "paper.toml")
    for k in ("M", "K", "C"):
        assert np.array_equal(getattr(m2, k).toarray(), getattr(m, k))
    assert np.array_equal(m2.force_static, m.force_static) and m2.names == m.names


@pytest.mark.parametrize(
    "change, key, problem",
    [
        (('K = "K.mtx"\n', ""), "matrices.K", "missing required matrix"),
        (('M = "M.mtx"', 'M = "nowhere.mtx"'), "matrices.M", "matrix file not found"),
        (("a = [[1, 2]]", "a = [[1, 9]]"), r"contact.a\[1\]", r"out of range \[1, 4\]"),
        (("area = [1e-4]", "area = [0.0]"), r"contact.area\[1\]", "must be > 0"),
        (("normal = [[0.0, 1.0]]", "normal = [[0.0, 0.0]]"), r"contact.normal\[1\]", "non-zero"),
        (("dofs = [4]", "dofs = [5]"), "load.static.dofs", "out of range"),
        (("[contact]", "[contacts]"), "contacts", "unknown key"),
        (('C = "arrays.npz:C"', 'C = "arrays.npz:D"'), "matrices.C", "has no array 'D'"),
    ],
)
def test_bad_files_get_one_line_errors_naming_file_and_key(tmp_path, change, key, problem):
    f = _write(tmp_path, GOOD.replace(*change))
    with pytest.raises(ModelFileError, match=rf"model.toml: {key}: .*{problem}") as info:
        read_interface_model(f)
    assert "\n" not in str(info.value)


def test_non_symmetric_stiffness_is_rejected(tmp_path):
    K = np.diag([2.0, 2.0, 3.0, 3.0])
    K[0, 2] = 0.5
    f = _write(tmp_path, GOOD, K=K)
    with pytest.raises(ModelFileError, match=r"model.toml: matrices.K: must be symmetric"):
        read_interface_model(f)


def test_contact_arrays_from_an_npz(tmp_path):
    np.savez(tmp_path / "pairs.npz", a=[[1, 2]], b=[[3, 4]], normal=[[0.0, 1.0]], area=[2e-4], gap=[1e-6])
    text = GOOD.split("[contact]")[0] + '[contact]\npairs = "pairs.npz"\nmu = 0.3\n'
    m = read_interface_model(_write(tmp_path, text))
    assert m.pairs.area.tolist() == [2e-4] and m.pairs.gap.tolist() == [1e-6] and m.pairs.mu[0] == 0.3
