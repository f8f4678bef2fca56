"""Model files: a :class:`~fretwear.model.Model` written as TOML.

Users bring their own systems to the command line and the dashboard as a small
TOML file (read with :mod:`tomllib`). All quantities are in SI units (kg, N/m,
N s/m, N, m). A complete example, the 2-DOF system of the paper (section 2.1)::

    title = "Salles et al., section 2.1"   # optional, free text

    [structure]
    dofs = ["x1", "x2"]          # optional DOF names
    mass = [1.0, 1.0]            # kg
    stiffness = [9.869604401089358, 69.0872308076255]   # N/m
    damping_ratio = 0.001        # -, or `damping = ...` (N s/m), or neither

    [excitation]
    cos = [10.0, 0.0]            # N, amplitude of cos(omega t)
    sin = [0.0, 0.0]             # N, amplitude of sin(omega t), optional
    static = [0.0, 0.0]          # N, static load, optional

    [[friction]]                 # one table per friction contact
    dof = "x1"
    other = "x2"                 # "ground" or omitted: contact with ground
    mu = 1.0                     # -
    kn = 1e7                     # N/m
    normal_load = 10.0           # N; or `u0 = 1e-6` (m), not both

    [[normal]]                   # one table per unilateral contact
    dof = 2
    gap = 1e-5                   # m, optional (default 0); negative = interference

Sections and keys
-----------------
``title`` (optional)
    A single-line string describing the model.
``[structure]`` (required)
    ``mass`` and ``stiffness`` (required) and ``damping`` (optional, default
    zero) are either ``n x n`` matrices written as a list of ``n`` rows, or the
    shorthand of a list of ``n`` numbers meaning a diagonal matrix. The length
    of ``mass`` sets the number of DOFs ``n``. Matrices must be symmetric and
    positive semi-definite. ``damping_ratio`` (-) replaces ``damping`` by the
    diagonal damping ``c_ii = 2 zeta_i sqrt(k_ii m_ii)``; it is one number for
    every DOF or a list of ``n`` numbers. ``dofs`` optionally names the DOFs:
    ``n`` distinct, printable, non-empty strings other than ``"ground"``.
``[excitation]`` (required)
    ``cos`` (required), ``sin`` and ``static`` (optional, default zero): lists of
    ``n`` forces (N).
``[[friction]]`` (any number)
    ``dof`` (required), ``other`` (optional), ``mu >= 0`` (-), ``kn > 0``
    (N/m), and exactly one of ``u0 >= 0`` (initial normal interference, m) and
    ``normal_load >= 0`` (initial normal load ``kn u0``, N); optionally
    ``kt > 0`` (N/m), a tangential stiffness in series (a Jenkins contact).
``[[normal]]`` (any number)
    ``dof`` (required), ``other`` (optional), ``gap`` (m, default 0).

Numbering
---------
DOFs are numbered **from 1** in the file, as engineers number them and as the
command line prints them (``x1``, ``x2``, ...): ``dof = 1`` is
``Model`` DOF index 0. When ``structure.dofs`` is given, a DOF may also be
referred to by its name. ``other`` omitted or ``"ground"`` means a contact with
ground. Every index in an error message counts from 1 too: ``friction[2].mu``
is the ``mu`` key of the second ``[[friction]]`` table, and
``structure.stiffness[2][1]`` is row 2, column 1.

Errors
------
Every problem (TOML syntax, missing key, unknown key, wrong type, wrong shape,
value out of range, a matrix rejected by :class:`~fretwear.model.Model`) raises
:class:`ModelFileError`, a :class:`ValueError` whose message reads
``"<file>: <key path>: <problem>"``.

:func:`dump_model` writes the same format; loading its output gives back a
model with exactly the same numbers (floats are written with :func:`repr`).
"""

from __future__ import annotations

import difflib
import os
import tomllib
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from .structure import FrictionContact, Model, NormalContact

__all__ = [
    "ModelFileError",
    "ModelFile",
    "read_model_file",
    "read_model",
    "model_file_from_dict",
    "model_from_dict",
    "dumps_model",
    "dump_model",
    "example_names",
    "example_path",
]

DATA_DIR = Path(__file__).parents[1] / "data"
GROUND = "ground"

_TOP_KEYS = ("title", "structure", "excitation", "friction", "normal")
_STRUCTURE_KEYS = ("dofs", "mass", "damping", "damping_ratio", "stiffness")
_EXCITATION_KEYS = ("cos", "sin", "static")
_FRICTION_KEYS = ("dof", "other", "mu", "kn", "u0", "normal_load", "kt")
_NORMAL_KEYS = ("dof", "other", "gap")

# Model constructor errors start with the name of the offending attribute.
_MODEL_ATTRIBUTE_KEYS = {
    "M": "structure.mass",
    "C": "structure.damping",
    "K": "structure.stiffness",
    "force_cos": "excitation.cos",
    "force_sin": "excitation.sin",
    "force_static": "excitation.static",
}


class ModelFileError(ValueError):
    """Invalid model file.

    Parameters
    ----------
    source : str
        File name (or ``"<dict>"``-like label) of the model description.
    key : str or None
        Key path of the offending entry, e.g. ``"friction[2].mu"``, or ``None``
        when the problem concerns the whole file.
    problem : str
        What is wrong, with the valid range where there is one.
    """

    def __init__(self, source: str, key: str | None, problem: str) -> None:
        self.source = source
        self.key = key
        self.problem = problem
        super().__init__(f"{source}: {key}: {problem}" if key else f"{source}: {problem}")


@dataclass(frozen=True, eq=False)
class ModelFile:
    """Contents of a model file.

    Parameters
    ----------
    model : Model
        The structure, excitation and contacts.
    dofs : tuple of str or None
        DOF names from ``structure.dofs``, or ``None`` when the file has none.
    title : str or None
        The file's ``title``, if any.
    source : str
        Where the description came from (file name).
    """

    model: Model
    dofs: tuple[str, ...] | None = None
    title: str | None = None
    source: str = "<dict>"

    @property
    def labels(self) -> tuple[str, ...]:
        """DOF names, or ``x1, x2, ...`` (numbered from 1) when the file has none."""
        if self.dofs is not None:
            return self.dofs
        return tuple(f"x{i + 1}" for i in range(self.model.n_dofs))


# -- reading ------------------------------------------------------------------
def read_model_file(path: str | os.PathLike[str]) -> ModelFile:
    """Read a model file with its DOF names and title.

    Parameters
    ----------
    path : str or path-like
        TOML model file.

    Returns
    -------
    ModelFile

    Raises
    ------
    ModelFileError
        If the file cannot be read, is not valid TOML or does not describe a
        valid model.
    """
    source = os.fspath(path)
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ModelFileError(source, None, f"cannot read file: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise ModelFileError(source, None, f"not UTF-8 text: {exc}") from exc
    except tomllib.TOMLDecodeError as exc:
        raise ModelFileError(source, None, f"TOML syntax error: {exc}") from exc
    return model_file_from_dict(data, source)


def read_model(path: str | os.PathLike[str]) -> Model:
    """Read the :class:`~fretwear.model.Model` of a model file (see ``read_model_file()``)."""
    return read_model_file(path).model


def model_from_dict(data: Mapping[str, Any], source: str = "<dict>") -> Model:
    """Build the :class:`Model` described by parsed TOML ``data`` (see :func:`model_file_from_dict`)."""
    return model_file_from_dict(data, source).model


def model_file_from_dict(data: Mapping[str, Any], source: str = "<dict>") -> ModelFile:
    """Build a :class:`ModelFile` from parsed TOML ``data``.

    Parameters
    ----------
    data : mapping
        The model description, as returned by :func:`tomllib.load`.
    source : str
        Name of the description used in error messages.

    Returns a :class:`ModelFile`; raises :class:`ModelFileError` if ``data``
    does not follow the format of the module docstring.
    """
    r = _Reader(source)
    r.keys(data, None, _TOP_KEYS, required=("structure", "excitation"))
    title = None if "title" not in data else r.text(data["title"], "title")

    structure = r.table(data["structure"], "structure")
    r.keys(structure, "structure", _STRUCTURE_KEYS, required=("mass", "stiffness"))
    M, n = r.matrix(structure["mass"], "structure.mass", None)
    K, _ = r.matrix(structure["stiffness"], "structure.stiffness", n)
    dofs = None
    if "dofs" in structure:
        dofs = r.dof_names(structure["dofs"], "structure.dofs", n)
    if "damping" in structure and "damping_ratio" in structure:
        raise r.error("structure", "give either damping or damping_ratio, not both")
    if "damping_ratio" in structure:
        zeta = r.damping_ratio(structure["damping_ratio"], "structure.damping_ratio", n)
        C = np.diag(2.0 * zeta * np.sqrt(np.diag(K) * np.diag(M)))
    elif "damping" in structure:
        C, _ = r.matrix(structure["damping"], "structure.damping", n)
    else:
        C = np.zeros((n, n))

    excitation = r.table(data["excitation"], "excitation")
    r.keys(excitation, "excitation", _EXCITATION_KEYS, required=("cos",))
    forces = {
        name: None if name not in excitation else r.vector(excitation[name], f"excitation.{name}", n)
        for name in _EXCITATION_KEYS
    }

    friction = tuple(
        r.friction(table, f"friction[{i}]", n, dofs)
        for i, table in enumerate(r.tables(data.get("friction", []), "friction"), start=1)
    )
    normal = tuple(
        r.normal(table, f"normal[{i}]", n, dofs)
        for i, table in enumerate(r.tables(data.get("normal", []), "normal"), start=1)
    )
    try:
        model = Model(
            M=M,
            C=C,
            K=K,
            force_cos=forces["cos"],
            force_sin=forces["sin"],
            force_static=forces["static"],
            friction=friction,
            normal=normal,
        )
    except ValueError as exc:
        message = str(exc)
        raise r.error(_MODEL_ATTRIBUTE_KEYS.get(message.split(" ", 1)[0]), message) from exc
    return ModelFile(model=model, dofs=dofs, title=title, source=source)


class _Reader:
    """Validation helpers that raise :class:`ModelFileError` naming ``source``."""

    def __init__(self, source: str) -> None:
        self.source = source

    def error(self, key: str | None, problem: str) -> ModelFileError:
        return ModelFileError(self.source, key, problem)

    def table(self, value: Any, key: str) -> Mapping[str, Any]:
        if not isinstance(value, Mapping):
            raise self.error(key, f"must be a table [{key}], got {_kind(value)}")
        return value

    def tables(self, value: Any, key: str) -> list[Mapping[str, Any]]:
        if not isinstance(value, list) or not all(isinstance(t, Mapping) for t in value):
            raise self.error(key, f"must be an array of tables, each written [[{key}]], got {_kind(value)}")
        return value

    def keys(
        self, table: Mapping[str, Any], key: str | None, allowed: Sequence[str], required: Sequence[str]
    ) -> None:
        prefix = f"{key}." if key else ""
        for name in table:
            if name not in allowed:
                close = difflib.get_close_matches(name.lower(), allowed, n=1)
                hint = f" (did you mean {close[0]!r}?)" if close else ""
                raise self.error(f"{prefix}{name}", f"unknown key{hint}; valid keys are {', '.join(allowed)}")
        for name in required:
            if name not in table:
                raise self.error(f"{prefix}{name}", "missing required key")

    def text(self, value: Any, key: str) -> str:
        if not isinstance(value, str) or not value.isprintable():
            raise self.error(key, f"must be a single-line string, got {_kind(value)}")
        return value

    def number(self, value: Any, key: str, low: float | None = None, strict: bool = False) -> float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise self.error(key, f"must be a number, got {_kind(value)}")
        try:
            value = float(value)
        except OverflowError:
            value = float("inf") if value > 0 else float("-inf")
        if not np.isfinite(value):
            raise self.error(key, f"must be a finite number, got {value!r}")
        if low is not None and (value <= low if strict else value < low):
            raise self.error(key, f"must be {'>' if strict else '>='} {low!r}, got {value!r}")
        return value

    def vector(self, value: Any, key: str, n: int, low: float | None = None) -> np.ndarray:
        if not isinstance(value, list):
            raise self.error(key, f"must be a list of {n} numbers (one per DOF), got {_kind(value)}")
        if len(value) != n:
            raise self.error(key, f"must have {n} entries (one per DOF), got {len(value)}")
        return np.array([self.number(v, f"{key}[{i}]", low) for i, v in enumerate(value, start=1)])

    def matrix(self, value: Any, key: str, n: int | None) -> tuple[np.ndarray, int]:
        """``n x n`` matrix from rows or a diagonal vector; ``n=None`` takes ``len(value)``."""
        shapes = f"a list of {n or 'n'} numbers (diagonal) or of {n or 'n'} rows of {n or 'n'} numbers"
        if not isinstance(value, list) or not value:
            raise self.error(key, f"must be {shapes}, got {_kind(value)}")
        n = len(value) if n is None else n
        if not all(isinstance(row, list) for row in value):
            if any(isinstance(row, list) for row in value):
                raise self.error(key, f"must be {shapes}, not a mix of numbers and rows")
            return np.diag(self.vector(value, key, n, low=0.0)), n
        if len(value) != n:
            raise self.error(key, f"must have {n} rows (one per DOF), got {len(value)}")
        a = np.array([self.vector(row, f"{key}[{i}]", n) for i, row in enumerate(value, start=1)])
        for i in range(n):
            if a[i, i] < 0.0:
                raise self.error(
                    f"{key}[{i + 1}][{i + 1}]", f"diagonal entries must be >= 0.0, got {a[i, i]!r}"
                )
        return a, n

    def damping_ratio(self, value: Any, key: str, n: int) -> np.ndarray:
        if isinstance(value, list):
            return self.vector(value, key, n, low=0.0)
        return np.full(n, self.number(value, key, low=0.0))

    def dof_names(self, value: Any, key: str, n: int) -> tuple[str, ...]:
        if not isinstance(value, list) or len(value) != n:
            raise self.error(key, f"must be a list of {n} names (one per DOF), got {_kind(value)}")
        names = tuple(self.text(v, f"{key}[{i}]") for i, v in enumerate(value, start=1))
        for i, name in enumerate(names, start=1):
            if not name or name == GROUND or name in names[: i - 1]:
                raise self.error(
                    f"{key}[{i}]", f"names must be distinct, non-empty and not {GROUND!r}, got {name!r}"
                )
        return names

    def dof(self, value: Any, key: str, n: int, names: tuple[str, ...] | None, ground: bool = False) -> int:
        valid = f"a DOF number in [1, {n}]"
        if names is not None:
            valid += f" or a name in structure.dofs {list(names)}"
        if ground:
            valid += f" or {GROUND!r}"
        if isinstance(value, str) and names is not None and value in names:
            return names.index(value)
        if isinstance(value, bool) or not isinstance(value, int) or not 1 <= value <= n:
            raise self.error(key, f"must be {valid}, got {value!r}")
        return value - 1

    def contact_dofs(
        self, table: Mapping[str, Any], key: str, n: int, names: tuple[str, ...] | None
    ) -> tuple[int, int | None]:
        dof = self.dof(table["dof"], f"{key}.dof", n, names)
        other = table.get("other", GROUND)
        if other == GROUND:
            return dof, None
        other = self.dof(other, f"{key}.other", n, names, ground=True)
        if other == dof:
            raise self.error(f"{key}.other", f"must differ from dof (both are DOF {dof + 1})")
        return dof, other

    def friction(
        self, table: Mapping[str, Any], key: str, n: int, names: tuple[str, ...] | None
    ) -> FrictionContact:
        self.keys(table, key, _FRICTION_KEYS, required=("dof", "mu", "kn"))
        dof, other = self.contact_dofs(table, key, n, names)
        mu = self.number(table["mu"], f"{key}.mu", low=0.0)
        kn = self.number(table["kn"], f"{key}.kn", low=0.0, strict=True)
        if ("u0" in table) == ("normal_load" in table):
            raise self.error(key, "give exactly one of u0 (m) and normal_load (N)")
        kt = self.number(table["kt"], f"{key}.kt", low=0.0, strict=True) if "kt" in table else None
        if "u0" in table:
            return FrictionContact(dof, other, mu, kn, self.number(table["u0"], f"{key}.u0", low=0.0), kt)
        normal_load = self.number(table["normal_load"], f"{key}.normal_load", low=0.0)
        return FrictionContact.from_normal_load(dof, other, mu, normal_load, kn, kt)

    def normal(
        self, table: Mapping[str, Any], key: str, n: int, names: tuple[str, ...] | None
    ) -> NormalContact:
        self.keys(table, key, _NORMAL_KEYS, required=("dof",))
        dof, other = self.contact_dofs(table, key, n, names)
        return NormalContact(dof, other, self.number(table.get("gap", 0.0), f"{key}.gap"))


def _kind(value: Any) -> str:
    """Short description of a TOML value for error messages."""
    if isinstance(value, Mapping):
        return "a table"
    if isinstance(value, list):
        return f"a list of {len(value)} entries"
    return f"{type(value).__name__} {value!r}"


# -- writing ------------------------------------------------------------------
def dumps_model(model: Model, dofs: Sequence[str] | None = None, title: str | None = None) -> str:
    """Model file text describing ``model`` (the inverse of :func:`model_file_from_dict`).

    Diagonal matrices are written as vectors, damping always as ``damping``
    (never ``damping_ratio``), friction contacts with ``u0`` and zero ``sin``
    and ``static`` forces are left out. Floats are written with :func:`repr`,
    so reading the text back gives exactly the same numbers.

    Parameters
    ----------
    model : Model
        Model to describe.
    dofs : sequence of str, optional
        DOF names; contacts then refer to DOFs by name.
    title : str, optional
        Single-line description written as ``title``.

    Returns
    -------
    str
        TOML text.

    Raises
    ------
    ValueError
        If ``dofs`` or ``title`` would not be valid in a model file, or the
        model has contact pairs (written by
        :func:`fretwear.interface.modelfile.write_interface_model`).
    """
    if model.pairs is not None:
        raise ValueError(
            "model has contact pairs, which a model file of 1-D contacts cannot hold; write it with "
            "fretwear.interface.modelfile.write_interface_model"
        )
    r = _Reader("dumps_model")
    lines = ["# fretwear model file; format: see fretwear.model.modelfile. SI units (kg, N/m, N s/m, N, m)."]
    if title is not None:
        lines.append(f"title = {_toml_string(r.text(title, 'title'))}")
    names = None if dofs is None else r.dof_names(list(dofs), "dofs", model.n_dofs)

    lines += ["", "[structure]"]
    if names is not None:
        lines.append(f"dofs = [{', '.join(_toml_string(s) for s in names)}]")
    lines += _toml_matrix("mass", model.M)
    lines += _toml_matrix("stiffness", model.K)
    if np.any(model.C):
        lines += _toml_matrix("damping", model.C)

    lines += ["", "[excitation]", f"cos = {_toml_floats(model.force_cos)}"]
    if np.any(model.force_sin):
        lines.append(f"sin = {_toml_floats(model.force_sin)}")
    if np.any(model.force_static):
        lines.append(f"static = {_toml_floats(model.force_static)}")

    def dof_lines(c: FrictionContact | NormalContact) -> list[str]:
        out = [f"dof = {_toml_dof(c.dof, names)}"]
        if c.other is not None:
            out.append(f"other = {_toml_dof(c.other, names)}")
        return out

    for c in model.friction:
        lines += ["", "[[friction]]", *dof_lines(c)]
        lines += [f"mu = {float(c.mu)!r}", f"kn = {float(c.kn)!r}", f"u0 = {float(c.u0)!r}"]
        lines += [] if c.kt is None else [f"kt = {float(c.kt)!r}"]
    for c in model.normal:
        lines += ["", "[[normal]]", *dof_lines(c), f"gap = {float(c.gap)!r}"]
    return "\n".join(lines) + "\n"


def dump_model(
    model: Model,
    path: str | os.PathLike[str],
    dofs: Sequence[str] | None = None,
    title: str | None = None,
) -> None:
    """Write ``model`` to the model file ``path`` (UTF-8); see ``dumps_model()``."""
    Path(path).write_text(dumps_model(model, dofs=dofs, title=title), encoding="utf-8")


def _toml_string(s: str) -> str:
    return '"' + s.replace("\\", "\\\\").replace('"', '\\"') + '"'


def _toml_floats(v: np.ndarray) -> str:
    return "[" + ", ".join(repr(float(x)) for x in v) + "]"


def _toml_matrix(key: str, a: np.ndarray) -> list[str]:
    if np.array_equal(a, np.diag(np.diag(a))):
        return [f"{key} = {_toml_floats(np.diag(a))}"]
    return [f"{key} = [", *(f"    {_toml_floats(row)}," for row in a), "]"]


def _toml_dof(index: int, names: tuple[str, ...] | None) -> str:
    return str(int(index) + 1) if names is None else _toml_string(names[index])


# -- bundled examples -----------------------------------------------------------
def example_names() -> tuple[str, ...]:
    """Names of the bundled example model files (without ``.toml``), sorted (study specs left out)."""
    files = DATA_DIR.glob("*.toml")
    return tuple(sorted(p.stem for p in files if "[study]" not in p.read_text(encoding="utf-8")))


def example_path(name: str) -> Path:
    """Path of the bundled example model file ``name``.

    Parameters
    ----------
    name : str
        Example name with or without ``.toml``: ``"paper_2dof"`` (the model of
        :func:`~fretwear.model.paper_model`) or ``"jenkins"`` (the model of
        :func:`~fretwear.model.jenkins_oscillator`).

    Raises
    ------
    ValueError
        If there is no such example.
    """
    stem = name.removesuffix(".toml")
    if stem not in example_names():
        raise ValueError(f"unknown example {name!r}; available: {', '.join(example_names())}")
    return DATA_DIR / f"{stem}.toml"
