"""Interface model files: matrices exported from another finite-element code plus the contact pairs.

A small TOML file points at the matrices and lists the contact node pairs and
the loads. Everything is in SI units; DOFs are numbered **from 1**, as in
Matrix Market files and in fretwear's other model files, and ``0`` marks a
grounded (fixed) component of a contact node. Paths are relative to the TOML
file. Example (a plane model)::

    title = "my dovetail"                # optional

    [matrices]
    M = "M.mtx"                          # required: Matrix Market file,
    K = "K.mtx"                          # or "K.npz" (scipy.sparse.save_npz),
    C = "arrays.npz:C"                   # or "archive.npz:key" (a dense array); C optional

    [contact]
    a = [[11, 12], [13, 14]]             # DOFs (x, y) of node A of each pair (e.g. the disk)
    b = [[101, 102], [103, 104]]         # DOFs of node B (e.g. the blade); 0 = grounded
    normal = [[0.0, 1.0], [0.0, 1.0]]    # unit normal from A into B
    area = [2.5e-5, 2.5e-5]              # tributary area (m^2; m per unit thickness in 2-D), > 0
    mu = 0.6                             # one number, or one per pair
    gap = [0.0, 1e-7]                    # optional initial gaps (m)
    position = [-1e-4, 1e-4]             # optional coordinate along the interface (m)
    tangent = [[1.0, 0.0], [1.0, 0.0]]   # optional in 2-D (default (n_y, -n_x)), required in 3-D

    [load.static]                        # optional: static load (N)
    dofs = [200]
    values = [-1.0e3]

    [load.cos]                           # the cos(omega t) excitation amplitude (N); [load.sin] likewise
    dofs = [199]
    values = [300.0]

    [names]                              # optional named DOFs (from 1), e.g. for the FRF output
    holder_x = 199

Instead of the inline lists, ``[contact] pairs = "pairs.npz"`` reads the arrays
``a``, ``b``, ``normal``, ``area`` and optionally ``mu``, ``gap``, ``position``,
``tangent`` from an ``.npz`` archive (same conventions).

Errors raise :class:`~fretwear.model.modelfile.ModelFileError` with a
one-line message ``"<file>: <key>: <problem>"``: a missing or unreadable
matrix, a non-square or non-symmetric matrix, matrices of different sizes,
contact DOFs out of range, zero or negative areas, a zero normal, loads on
DOFs out of range.
"""

from __future__ import annotations

import os
import tomllib
from pathlib import Path
from typing import Any

import numpy as np
import scipy.io
import scipy.sparse as sp

from ..model import ContactPairs, Model
from ..model.modelfile import ModelFileError

__all__ = ["read_interface_model", "write_interface_model"]

_TOP = ("title", "matrices", "contact", "load", "names")
_CONTACT = ("pairs", "a", "b", "normal", "area", "mu", "gap", "position", "tangent")


def _matrix(spec: Any, key: str, base: Path, source: str) -> sp.csr_matrix:
    if not isinstance(spec, str) or not spec:
        raise ModelFileError(
            source, key, f"must be a file name (.mtx, .npz or archive.npz:key), got {spec!r}"
        )
    name, _, inner = (
        spec.partition(":") if spec.count(":") == 1 and not Path(spec).exists() else (spec, "", "")
    )
    path = base / name
    if not path.exists():
        raise ModelFileError(source, key, f"matrix file not found: {path}")
    try:
        if path.suffix == ".mtx":
            A = scipy.io.mmread(path)
        elif path.suffix == ".npz" and inner:
            with np.load(path) as arch:
                if inner not in arch:
                    raise ModelFileError(
                        source, key, f"{path} has no array {inner!r} (it has {sorted(arch)})"
                    )
                A = arch[inner]
        elif path.suffix == ".npz":
            A = sp.load_npz(path)
        else:
            raise ModelFileError(source, key, f"unknown matrix format {path.suffix!r}; use .mtx or .npz")
    except ModelFileError:
        raise
    except Exception as exc:  # noqa: BLE001 - any reader failure is a bad file
        raise ModelFileError(source, key, f"cannot read {path}: {exc}") from None
    A = sp.csr_matrix(A, dtype=float)
    if A.ndim != 2 or A.shape[0] != A.shape[1] or A.shape[0] == 0:
        raise ModelFileError(source, key, f"must be a non-empty square matrix, got shape {A.shape}")
    if not np.all(np.isfinite(A.data)):
        raise ModelFileError(source, key, "must contain finite numbers only")
    scale = abs(A).max() if A.nnz else 0.0
    asym = abs(A - A.T).max() if A.nnz else 0.0
    if asym > 1e-10 * scale:
        raise ModelFileError(
            source, key, f"must be symmetric: max |A - A^T| = {asym:.3g} (max |A| = {scale:.3g})"
        )
    return A


def _array(value: Any, key: str, source: str, dtype=float, ndim: int | None = None) -> np.ndarray:
    try:
        a = np.array(value, dtype=dtype)
    except (TypeError, ValueError, OverflowError):
        raise ModelFileError(  # noqa: B904 - the message says it all
            source, key, f"must be {'integers' if dtype is int else 'numbers'}, got {value!r}"
        )
    if ndim is not None and a.ndim != ndim:
        raise ModelFileError(
            source, key, f"must be a {ndim}-D array (list{' of lists' * (ndim - 1)}), got {a.ndim}-D"
        )
    if dtype is float and not np.all(np.isfinite(a)):
        raise ModelFileError(source, key, "must contain finite numbers only")
    return a


def _load(table: Any, key: str, n: int, source: str) -> np.ndarray:
    if not isinstance(table, dict) or set(table) - {"dofs", "values"} or not {"dofs", "values"} <= set(table):
        raise ModelFileError(
            source, key, "must be a table with exactly the keys dofs (from 1) and values (N)"
        )
    dofs = _array(table["dofs"], f"{key}.dofs", source, int, 1)
    values = _array(table["values"], f"{key}.values", source, float, 1)
    if dofs.shape != values.shape:
        raise ModelFileError(
            source, key, f"dofs and values must have the same length, got {len(dofs)} and {len(values)}"
        )
    bad = (dofs < 1) | (dofs > n)
    if np.any(bad):
        raise ModelFileError(source, f"{key}.dofs", f"DOF {int(dofs[bad][0])} is out of range [1, {n}]")
    f = np.zeros(n)
    np.add.at(f, dofs - 1, values)
    return f


def read_interface_model(path: str | os.PathLike[str]) -> Model:
    """Read an interface model file (format in the module docstring).

    Raises
    ------
    ModelFileError
        With a one-line message naming the file and the key.
    """
    source = os.fspath(path)
    base = Path(path).parent
    try:
        with open(path, "rb") as fh:
            data = tomllib.load(fh)
    except OSError as exc:
        raise ModelFileError(source, None, f"cannot read file: {exc.strerror or exc}") from None
    except (UnicodeDecodeError, tomllib.TOMLDecodeError) as exc:
        raise ModelFileError(source, None, f"not a valid TOML file: {exc}") from None
    for k in data:
        if k not in _TOP:
            raise ModelFileError(source, k, f"unknown key; valid keys are {', '.join(_TOP)}")
    for k in ("matrices", "contact"):
        if not isinstance(data.get(k), dict):
            raise ModelFileError(source, k, f"missing required table [{k}]")
    mats = data["matrices"]
    for k in mats:
        if k not in ("M", "K", "C"):
            raise ModelFileError(source, f"matrices.{k}", "unknown key; valid keys are M, K, C")
    for k in ("M", "K"):
        if k not in mats:
            raise ModelFileError(source, f"matrices.{k}", "missing required matrix")
    M = _matrix(mats["M"], "matrices.M", base, source)
    n = M.shape[0]
    K = _matrix(mats["K"], "matrices.K", base, source)
    C = _matrix(mats["C"], "matrices.C", base, source) if "C" in mats else None
    for k, A in (("K", K), ("C", C)):
        if A is not None and A.shape != (n, n):
            raise ModelFileError(
                source, f"matrices.{k}", f"must have the shape of M ({n}, {n}), got {A.shape}"
            )

    contact = dict(data["contact"])
    for k in contact:
        if k not in _CONTACT:
            raise ModelFileError(source, f"contact.{k}", f"unknown key; valid keys are {', '.join(_CONTACT)}")
    if "pairs" in contact:
        p = base / str(contact.pop("pairs"))
        try:
            with np.load(p) as arch:
                for k in arch.files:
                    if k not in _CONTACT:
                        raise ModelFileError(
                            source, f"contact.pairs[{k}]", f"unknown array; valid: {_CONTACT[1:]}"
                        )
                    contact.setdefault(k, arch[k])
        except OSError as exc:
            raise ModelFileError(source, "contact.pairs", f"cannot read {p}: {exc}") from None
    for k in ("a", "b", "normal", "area"):
        if k not in contact:
            raise ModelFileError(source, f"contact.{k}", "missing required key")
    a = _array(contact["a"], "contact.a", source, int, 2)
    b = _array(contact["b"], "contact.b", source, int, 2)
    if a.shape != b.shape or a.shape[1] not in (2, 3):
        raise ModelFileError(
            source, "contact.b", f"a and b must both be nc x 2 or nc x 3, got {a.shape} and {b.shape}"
        )
    for k, d in (("a", a), ("b", b)):
        bad = (d < 0) | (d > n)
        if np.any(bad):
            i = int(np.argwhere(bad)[0, 0])
            raise ModelFileError(
                source, f"contact.{k}[{i + 1}]", f"DOF {d[i].tolist()} out of range [1, {n}] (0 = ground)"
            )
    nc = a.shape[0]
    normal = _array(contact["normal"], "contact.normal", source, float, 2)
    area = _array(contact["area"], "contact.area", source, float, 1)
    if area.shape != (nc,):
        raise ModelFileError(
            source, "contact.area", f"must have {nc} entries (one per pair), got {area.shape[0]}"
        )
    if np.any(area <= 0):
        i = int(np.argmin(area))
        raise ModelFileError(
            source, f"contact.area[{i + 1}]", f"tributary areas must be > 0, got {area[i]!r}"
        )
    if normal.shape != a.shape:
        raise ModelFileError(
            source, "contact.normal", f"must have shape {a.shape} like a, got {normal.shape}"
        )
    zero = np.linalg.norm(normal, axis=1) == 0
    if np.any(zero):
        raise ModelFileError(source, f"contact.normal[{int(np.argmax(zero)) + 1}]", "normal must be non-zero")
    opt = {}
    for k in ("gap", "position", "tangent", "mu"):
        if k in contact:
            opt[k] = _array(contact[k], f"contact.{k}", source)
    loads = data.get("load", {})
    if not isinstance(loads, dict):
        raise ModelFileError(source, "load", "must be a table with sub-tables static, cos, sin")
    for k in loads:
        if k not in ("static", "cos", "sin"):
            raise ModelFileError(source, f"load.{k}", "unknown key; valid keys are static, cos, sin")
    forces = {k: _load(v, f"load.{k}", n, source) for k, v in loads.items()}
    names = {}
    for k, v in data.get("names", {}).items():
        if isinstance(v, bool) or not isinstance(v, int) or not 1 <= v <= n:
            raise ModelFileError(source, f"names.{k}", f"must be a DOF number in [1, {n}], got {v!r}")
        names[k] = v - 1
    try:
        pairs = ContactPairs(
            dofs_a=a - 1, dofs_b=b - 1, normal=normal, area=area, mu=opt.get("mu", 0.0), gap=opt.get("gap"),
            tangent=opt.get("tangent"), position=opt.get("position"),
        )  # fmt: skip
        model = Model(
            M=M, C=C, K=K, pairs=pairs, force_static=forces.get("static"), force_cos=forces.get("cos"),
            force_sin=forces.get("sin"), names=names,
        )  # fmt: skip
    except ValueError as exc:
        first = str(exc).split(" ", 1)[0]
        key = f"contact.{first}" if first in _CONTACT else "contact"
        raise ModelFileError(source, key, str(exc)) from None
    return model


def write_interface_model(model: Model, path: str | os.PathLike[str], title: str | None = None) -> None:
    """Write ``model`` as ``path`` (TOML) with its matrices beside it (``<stem>_M.mtx``, ...).

    Reading the result with :func:`read_interface_model` gives the same model.
    """
    path = Path(path)
    stem = path.stem
    lines = [f"title = {title!r}".replace("'", '"')] if title else []
    lines.append("[matrices]")
    for k in ("M", "K", "C"):
        A = sp.csr_matrix(getattr(model, k))  # a dense model (e.g. the paper's one-pair form) too
        if k == "C" and A.nnz == 0:
            continue
        scipy.io.mmwrite(path.parent / f"{stem}_{k}.mtx", A, precision=17, symmetry="symmetric")
        lines.append(f'{k} = "{stem}_{k}.mtx"')
    c = model.pairs
    np.savez(path.parent / f"{stem}_pairs.npz", a=c.dofs_a + 1, b=c.dofs_b + 1, normal=c.normal, area=c.area,
             mu=c.mu, gap=c.gap, position=c.position, tangent=c.tangent)  # fmt: skip
    lines += ["[contact]", f'pairs = "{stem}_pairs.npz"']
    for k in ("static", "cos", "sin"):
        f = getattr(model, f"force_{k}")
        idx = np.flatnonzero(f)
        if len(idx):
            lines += [
                f"[load.{k}]",
                f"dofs = {(idx + 1).tolist()}",
                f"values = {[repr(float(v)) for v in f[idx]]}".replace("'", ""),
            ]
    if model.names:
        lines.append("[names]")
        lines += [f"{k} = {v + 1}" for k, v in model.names.items()]
    path.write_text("\n".join(lines) + "\n")
