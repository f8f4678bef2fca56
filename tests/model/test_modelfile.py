"""Tests of fretwear.model.modelfile: the TOML model file format."""

import copy
import tomllib

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from fretwear.model import FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model
from fretwear.model.modelfile import (
    ModelFile,
    ModelFileError,
    dump_model,
    dumps_model,
    example_names,
    example_path,
    model_file_from_dict,
    model_from_dict,
    read_model,
    read_model_file,
)

SOURCE = "my_model.toml"


def assert_same_model(a: Model, b: Model) -> None:
    """Exact equality of every number of two models."""
    for name in ("M", "C", "K", "force_cos", "force_sin", "force_static"):
        np.testing.assert_array_equal(getattr(a, name), getattr(b, name), err_msg=name)
    assert a.friction == b.friction
    assert a.normal == b.normal


def base() -> dict:
    """A valid model description with DOF names, a friction and a normal contact."""
    return {
        "title": "three masses",
        "structure": {
            "dofs": ["a", "b", "c"],
            "mass": [1.0, 2.0, 0.0],
            "stiffness": [[2.0, -1.0, 0.0], [-1.0, 2.0, -1.0], [0.0, -1.0, 1.0]],
            "damping": [0.1, 0.1, 0.0],
        },
        "excitation": {"cos": [1.0, 0.0, 0.0], "sin": [0.0, 0.5, 0.0], "static": [0.0, 0.0, -1.0]},
        "friction": [
            {"dof": "a", "other": "b", "mu": 0.3, "kn": 1e6, "u0": 1e-6},
            {"dof": 3, "mu": 0.5, "kn": 2e6, "normal_load": 4.0},
        ],
        "normal": [{"dof": 2, "other": "ground", "gap": 1e-4}, {"dof": "c", "other": 1}],
    }


# -- reading ------------------------------------------------------------------------
def test_base_description():
    model_file = model_file_from_dict(base(), SOURCE)
    assert isinstance(model_file, ModelFile)
    assert model_file.dofs == ("a", "b", "c") == model_file.labels
    assert model_file.title == "three masses"
    assert model_file.source == SOURCE
    model = model_file.model
    np.testing.assert_array_equal(model.M, np.diag([1.0, 2.0, 0.0]))
    np.testing.assert_array_equal(model.C, np.diag([0.1, 0.1, 0.0]))
    np.testing.assert_array_equal(model.K, base()["structure"]["stiffness"])
    np.testing.assert_array_equal(model.force_sin, [0.0, 0.5, 0.0])
    np.testing.assert_array_equal(model.force_static, [0.0, 0.0, -1.0])
    assert model.friction == (
        FrictionContact(0, 1, 0.3, 1e6, 1e-6),
        FrictionContact.from_normal_load(2, None, 0.5, 4.0, 2e6),
    )
    assert model.normal == (NormalContact(1, None, 1e-4), NormalContact(2, 0, 0.0))


def test_minimal_description_defaults():
    model_file = model_file_from_dict(
        {"structure": {"mass": [1.0], "stiffness": [4]}, "excitation": {"cos": [1]}}
    )
    assert model_file.dofs is None and model_file.title is None
    assert model_file.labels == ("x1",)
    model = model_file.model
    np.testing.assert_array_equal(model.C, [[0.0]])
    np.testing.assert_array_equal(model.force_sin, [0.0])
    assert model.friction == () and model.normal == ()


@pytest.mark.parametrize(
    ("ratio", "expected"),
    [(0.01, [2 * 0.01 * np.sqrt(2.0), 2 * 0.01 * 2.0, 0.0]), ([0.0, 0.02, 0.5], [0.0, 0.08, 0.0])],
)
def test_damping_ratio(ratio, expected):
    data = base()
    del data["structure"]["damping"]
    data["structure"]["damping_ratio"] = ratio
    np.testing.assert_allclose(model_from_dict(data).C, np.diag(expected), rtol=1e-15)


def test_full_mass_matrix_and_integers():
    data = base()
    data["structure"]["mass"] = [[2, 1, 0], [1, 2, 0], [0, 0, 1]]
    np.testing.assert_array_equal(
        model_from_dict(data).M, [[2.0, 1.0, 0.0], [1.0, 2.0, 0.0], [0.0, 0.0, 1.0]]
    )


# -- examples -------------------------------------------------------------------------
def test_examples_equal_the_factories():
    assert set(example_names()) >= {"paper_2dof", "jenkins"}
    paper = read_model_file(example_path("paper_2dof"))
    assert_same_model(paper.model, paper_model())
    assert paper.labels == ("x1", "x2")
    assert_same_model(read_model(example_path("jenkins.toml")), jenkins_oscillator())


def test_example_path_rejects_unknown_names():
    with pytest.raises(ValueError, match="unknown example 'nope'.*paper_2dof"):
        example_path("nope")


# -- writing and round trips ------------------------------------------------------------
@pytest.mark.parametrize("dofs", [None, ("a", "b", "c")])
def test_round_trip_file(tmp_path, dofs):
    model = model_from_dict(base())
    path = tmp_path / "model.toml"
    dump_model(model, path, dofs=dofs, title='quote " and \\ backslash')
    model_file = read_model_file(path)
    assert_same_model(model_file.model, model)
    assert model_file.dofs == dofs
    assert model_file.title == 'quote " and \\ backslash'
    assert model_file.source == str(path)
    assert dumps_model(model_file.model, dofs=dofs, title=model_file.title) == path.read_text()


@pytest.mark.parametrize("factory", [paper_model, jenkins_oscillator])
def test_round_trip_factories(factory):
    model = factory()
    text = dumps_model(model)
    assert_same_model(model_from_dict(tomllib.loads(text)), model)
    assert "damping_ratio" not in text and "sin" not in text and "static" not in text


def test_dump_writes_diagonal_matrices_as_vectors():
    data = tomllib.loads(dumps_model(jenkins_oscillator()))
    assert data["structure"]["mass"] == [1.0, 0.0]
    assert data["structure"]["stiffness"] == [[2.0, -1.0], [-1.0, 1.0]]
    assert data["friction"] == [{"dof": 2, "mu": 1.0, "kn": 1e7, "u0": jenkins_oscillator().friction[0].u0}]


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        (dict(dofs=["x1"]), r"dofs: must be a list of 2 names"),
        (dict(dofs=["x1", "x1"]), r"dofs\[2\]: names must be distinct"),
        (dict(dofs=["x1", "ground"]), r"dofs\[2\]: names must be distinct, non-empty and not 'ground'"),
        (dict(dofs=["x1", ""]), r"dofs\[2\]"),
        (dict(title="two\nlines"), r"title: must be a single-line string"),
    ],
)
def test_dump_rejects_invalid_names(kwargs, match):
    with pytest.raises(ValueError, match=match):
        dumps_model(paper_model(), **kwargs)


positive = st.floats(0.0, 1e6)


@st.composite
def models(draw) -> tuple[Model, tuple[str, ...] | None]:
    n = draw(st.integers(1, 4))
    vec = st.lists(st.floats(-1e6, 1e6), min_size=n, max_size=n)

    def psd(diagonal: bool) -> np.ndarray:
        if diagonal:
            return np.diag(draw(st.lists(positive, min_size=n, max_size=n)))
        A = np.array(draw(st.lists(vec, min_size=n, max_size=n))) * 1e-3
        return A @ A.T

    def contact_dofs() -> tuple[int, int | None]:
        dof = draw(st.integers(0, n - 1))
        others = [None, *(j for j in range(n) if j != dof)]
        return dof, draw(st.sampled_from(others))

    friction = tuple(
        FrictionContact(
            *contact_dofs(), draw(positive), draw(st.floats(1e-3, 1e12)), draw(st.floats(0.0, 1e-3))
        )
        for _ in range(draw(st.integers(0, 2)))
    )
    normal = tuple(
        NormalContact(*contact_dofs(), draw(st.floats(-1e-3, 1e-3))) for _ in range(draw(st.integers(0, 2)))
    )
    model = Model(
        M=psd(draw(st.booleans())),
        C=psd(draw(st.booleans())),
        K=psd(draw(st.booleans())),
        force_cos=draw(vec),
        force_sin=draw(st.none() | vec),
        force_static=draw(st.none() | vec),
        friction=friction,
        normal=normal,
    )
    dofs = draw(st.none() | st.just(tuple(f"dof {i} \"'" for i in range(n))))
    return model, dofs


@settings(max_examples=60, deadline=None)
@given(models())
def test_round_trip_property(model_and_dofs):
    model, dofs = model_and_dofs
    text = dumps_model(model, dofs=dofs)
    model_file = model_file_from_dict(tomllib.loads(text))
    assert_same_model(model_file.model, model)
    assert model_file.dofs == dofs
    assert dumps_model(model_file.model, dofs=dofs) == text


# -- errors ------------------------------------------------------------------------------
DEL = object()


def _set(data: dict, path: str, value) -> dict:
    """``data`` with the entry at dotted ``path`` set to ``value`` (deleted if ``DEL``).

    List indices in ``path`` are 0-based.
    """
    *parents, last = path.split(".")
    node = data
    for key in parents:
        node = node[int(key)] if isinstance(node, list) else node[key]
    if isinstance(node, list):
        last = int(last)
    if value is DEL:
        del node[last]
    else:
        node[last] = value
    return data


@pytest.mark.parametrize(
    ("path", "value", "key", "match"),
    [
        # missing keys
        ("structure", DEL, "structure", "missing required key"),
        ("excitation", DEL, "excitation", "missing required key"),
        ("structure.mass", DEL, "structure.mass", "missing required key"),
        ("structure.stiffness", DEL, "structure.stiffness", "missing required key"),
        ("excitation.cos", DEL, "excitation.cos", "missing required key"),
        ("friction.0.mu", DEL, "friction[1].mu", "missing required key"),
        ("friction.1.kn", DEL, "friction[2].kn", "missing required key"),
        ("normal.1.dof", DEL, "normal[2].dof", "missing required key"),
        ("friction.1.normal_load", DEL, "friction[2]", "exactly one of u0 .m. and normal_load .N."),
        # unknown keys
        ("titel", "x", "titel", r"unknown key \(did you mean 'title'\?\); valid keys are title, structure"),
        ("structure.stifness", [1.0], "structure.stifness", "did you mean 'stiffness'"),
        ("excitation.cosine", [1.0], "excitation.cosine", "unknown key"),
        ("friction.1.Mu", 0.1, "friction[2].Mu", "did you mean 'mu'"),
        ("normal.0.gap_m", 0.1, "normal[1].gap_m", "unknown key"),
        # wrong types
        ("title", 3, "title", "must be a single-line string, got int 3"),
        ("structure", [1, 2], "structure", r"must be a table \[structure\]"),
        ("friction", {"dof": 1}, "friction", r"must be an array of tables, each written \[\[friction\]\]"),
        ("friction.0.mu", "0.3", "friction[1].mu", "must be a number, got str '0.3'"),
        ("friction.0.kn", True, "friction[1].kn", "must be a number, got bool True"),
        ("friction.0.kn", -(10**400), "friction[1].kn", "must be a finite number, got -inf"),
        ("normal.0.gap", [0.1], "normal[1].gap", "must be a number"),
        ("excitation.cos", 1.0, "excitation.cos", "must be a list of 3 numbers"),
        ("excitation.sin", [0.0, "1", 0.0], "excitation.sin[2]", "must be a number"),
        ("structure.mass", 1.0, "structure.mass", r"must be a list of n numbers \(diagonal\) or of n rows"),
        ("structure.mass", [], "structure.mass", r"must be a list of n numbers"),
        ("structure.stiffness", [1.0, [1.0, 2.0, 3.0], 1.0], "structure.stiffness", "not a mix"),
        ("structure.dofs", "abc", "structure.dofs", "must be a list of 3 names"),
        ("structure.dofs", ["a", 2, "c"], "structure.dofs[2]", "must be a single-line string"),
        # wrong shapes
        (
            "structure.stiffness",
            [1.0, 2.0],
            "structure.stiffness",
            r"must have 3 entries \(one per DOF\), got 2",
        ),
        ("structure.damping", [[0.1, 0.0], [0.0, 0.1]], "structure.damping", "must have 3 rows"),
        ("structure.stiffness.1", [-1.0, 2.0], "structure.stiffness[2]", "must have 3 entries"),
        ("excitation.static", [0.0] * 4, "excitation.static", "must have 3 entries"),
        ("structure.dofs", ["a", "b"], "structure.dofs", "must be a list of 3 names"),
        # invalid values
        ("structure.mass", [1.0, -2.0, 0.0], "structure.mass[2]", r"must be >= 0.0, got -2.0"),
        ("structure.damping", [0.1, float("nan"), 0.0], "structure.damping[2]", "must be a finite number"),
        (
            "structure.stiffness.2",
            [0.0, -1.0, -1.0],
            "structure.stiffness[3][3]",
            "diagonal entries must be >= 0.0",
        ),
        ("excitation.cos", [float("inf"), 0.0, 0.0], "excitation.cos[1]", "must be a finite number, got inf"),
        ("friction.0.mu", -0.3, "friction[1].mu", r"must be >= 0.0, got -0.3"),
        ("friction.0.kn", 0, "friction[1].kn", r"must be > 0.0, got 0.0"),
        ("friction.0.u0", -1e-6, "friction[1].u0", "must be >= 0.0"),
        ("friction.1.normal_load", -4.0, "friction[2].normal_load", "must be >= 0.0"),
        ("friction.0.normal_load", 4.0, "friction[1]", "exactly one of u0"),
        (
            "friction.0.dof",
            0,
            "friction[1].dof",
            r"must be a DOF number in \[1, 3\] or a name in structure.dofs",
        ),
        ("friction.0.dof", 4, "friction[1].dof", r"must be a DOF number in \[1, 3\]"),
        ("friction.0.dof", 1.0, "friction[1].dof", "got 1.0"),
        ("friction.0.dof", "ground", "friction[1].dof", "got 'ground'"),
        (
            "friction.0.other",
            "d",
            "friction[1].other",
            r"or a name in structure.dofs \['a', 'b', 'c'\] or 'ground'",
        ),
        ("friction.0.other", "a", "friction[1].other", r"must differ from dof \(both are DOF 1\)"),
        ("normal.1.other", 3, "normal[2].other", "must differ from dof"),
        ("structure.dofs", ["a", "b", "a"], "structure.dofs[3]", "names must be distinct"),
        ("structure.dofs", ["a", "ground", "c"], "structure.dofs[2]", "not 'ground'"),
        ("structure.dofs", ["a", "b\tc", "c"], "structure.dofs[2]", "single-line string"),
    ],
)
def test_errors_name_the_key(path, value, key, match):
    data = _set(base(), path, value)
    with pytest.raises(ModelFileError, match=match) as info:
        model_from_dict(data, SOURCE)
    assert isinstance(info.value, ValueError)
    assert info.value.source == SOURCE
    assert info.value.key == key
    assert str(info.value).startswith(f"{SOURCE}: {key}: ")


@pytest.mark.parametrize(
    ("ratio", "key", "match"),
    [
        (-0.01, "structure.damping_ratio", r"must be >= 0.0, got -0.01"),
        ("0.01", "structure.damping_ratio", "must be a number"),
        ([0.1, 0.1], "structure.damping_ratio", r"must have 3 entries \(one per DOF\), got 2"),
        ([0.1, -0.1, 0.1], "structure.damping_ratio[2]", "must be >= 0.0"),
    ],
)
def test_damping_ratio_errors(ratio, key, match):
    data = base()
    del data["structure"]["damping"]
    data["structure"]["damping_ratio"] = ratio
    with pytest.raises(ModelFileError, match=match) as info:
        model_from_dict(data, SOURCE)
    assert info.value.key == key


def test_damping_and_damping_ratio_exclusive():
    data = _set(base(), "structure.damping_ratio", 0.01)
    with pytest.raises(
        ModelFileError, match=r"^my_model.toml: structure: give either damping or damping_ratio"
    ):
        model_from_dict(data, SOURCE)


def test_names_only_with_dofs():
    data = base()
    del data["structure"]["dofs"]
    with pytest.raises(
        ModelFileError, match=r"friction\[1\]\.dof: must be a DOF number in \[1, 3\], got 'a'"
    ):
        model_from_dict(data, SOURCE)


@pytest.mark.parametrize(
    ("path", "value", "key", "match"),
    [
        (
            "structure.stiffness",
            [[2.0, -1.0, 0.0], [-1.5, 2.0, -1.0], [0.0, -1.0, 1.0]],
            "structure.stiffness",
            "K must be symmetric",
        ),
        (
            "structure.mass",
            [[1.0, 2.0, 0.0], [2.0, 1.0, 0.0], [0.0, 0.0, 1.0]],
            "structure.mass",
            "M must be positive semi-definite",
        ),
        (
            "structure.damping",
            [[0.1, 0.2, 0.0], [0.2, 0.1, 0.0], [0.0, 0.0, 0.0]],
            "structure.damping",
            "C must be positive semi-definite",
        ),
    ],
)
def test_model_errors_are_reraised_with_the_file(path, value, key, match):
    with pytest.raises(ModelFileError, match=match) as info:
        model_from_dict(_set(base(), path, value), SOURCE)
    assert str(info.value).startswith(f"{SOURCE}: {key}: ")
    assert isinstance(info.value.__cause__, ValueError)


def test_toml_syntax_error(tmp_path):
    path = tmp_path / "broken.toml"
    path.write_text("[structure]\nmass = [1.0, 2.0\nstiffness = [1.0, 1.0]\n")
    with pytest.raises(ModelFileError, match=r"broken\.toml: TOML syntax error: .*line 3") as info:
        read_model(path)
    assert info.value.key is None
    assert isinstance(info.value.__cause__, tomllib.TOMLDecodeError)


def test_file_errors_name_the_file(tmp_path):
    path = tmp_path / "model.toml"
    path.write_text(dumps_model(paper_model()).replace("mu = 1.0", "mu = -1.0"))
    with pytest.raises(ModelFileError, match=rf"^{path}: friction\[1\]\.mu: must be >= 0.0, got -1.0$"):
        read_model(path)
    with pytest.raises(ModelFileError, match=r"missing\.toml: cannot read file"):
        read_model(tmp_path / "missing.toml")
    (tmp_path / "latin1.toml").write_bytes(b'title = "caf\xe9"\n')
    with pytest.raises(ModelFileError, match=r"latin1\.toml: not UTF-8 text"):
        read_model(tmp_path / "latin1.toml")


def test_base_is_not_mutated_by_reading():
    data = base()
    snapshot = copy.deepcopy(data)
    model_from_dict(data)
    assert data == snapshot


def test_a_model_with_contact_pairs_is_not_written_as_a_1d_model_file():
    import fretwear as fw

    with pytest.raises(ValueError, match="model has contact pairs, which a model file of 1-D contacts"):
        dumps_model(fw.paper_interface())
