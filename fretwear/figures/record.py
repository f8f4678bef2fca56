"""The parameter record of an export, and the settings file shared by the dashboard and the CLI.

A *settings record* is a flat mapping keyed like the command-line options
(``fex``, ``mu``, ``fn``, ``kw``, ``cycles``, ``harmonics``, ``method``, ``tol``,
``degree``, ``fmin``, ``fmax``, ``nf``, ``ncycles``, ``f``), plus what only the
dashboard has (``N``: the selected cycle count, ``scene``, and the accuracy
scene's ``quantity``, ``target``, ``ladder`` and ``rungs``). The dashboard
writes it to its address (URL query) and to a small JSON file; ``fretwear
COMMAND --settings FILE`` reads the same file, so that a figure of the
dashboard can be computed again without it.

Every exported figure carries :func:`caption` and every exported table
:func:`csv_header`: the model, ``F_ex``, ``mu``, ``F_N``, ``k_w``, ``Nh``, the
slow-time method, its tolerance and the fretwear version.
"""

from __future__ import annotations

import html
import json
import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from ..parameters import PARAMETERS, Parameter

__all__ = [
    "SETTINGS_KEYS",
    "MODEL",
    "version",
    "settings_json",
    "parse_settings",
    "read_settings",
    "parameter_record",
    "caption",
    "csv_header",
]

#: the model every dashboard figure is drawn for
MODEL = "paper 2-DOF (Salles et al., section 2.1), kn = 1e7 N/m"

#: the keys of a settings record, in its order: the numbers of :data:`fretwear.parameters.PARAMETERS` (type,
#: meaning and unit from there) and the choices below
_SETTINGS_ORDER = ("fex", "mu", "fn", "kw", "cycles", "harmonics", "method", "dynamics", "degree", "tol",
                   "fmin", "fmax", "nf", "ncycles", "f", "N", "scene", "quantity", "target", "ladder",
                   "rungs")  # fmt: skip
#: the keys that are no number of the table: (type, meaning with its unit)
_CHOICES: dict[str, tuple[type, str]] = {
    "method": (str, "slow-time method"),
    "dynamics": (str, "periodic dynamics of the exact and stepping methods: shooting (exact) or dlft"),
    "N": (float, "selected cycle count (cycles)"),
    "scene": (str, "dashboard scene"),
    "quantity": (str, "error measure of the accuracy scene"),
    "ladder": (str, "ladder of the accuracy scene"),
    "rungs": (bool, "wear rungs of the accuracy scene"),
}


def _setting(p: Parameter) -> tuple[type, str]:
    return (int if p.integer else float), f"{p.doc} ({p.unit or '-'})"


#: keys of a settings record: (type, meaning with its unit)
SETTINGS_KEYS: dict[str, tuple[type, str]] = {
    key: _CHOICES[key] if key in _CHOICES else _setting(PARAMETERS[key]) for key in _SETTINGS_ORDER
}

#: (key, name, unit) of the parameter record, in its order; names and units in ASCII (the table's
#: symbols), marked up by :data:`MARKUP` in captions
_RECORD = tuple(
    (key, PARAMETERS[key].symbol or PARAMETERS[key].label, PARAMETERS[key].unit)
    if key in PARAMETERS
    else (key, key, {"N": "cycles"}.get(key, ""))
    for key in (
        "fex",
        "mu",
        "fn",
        "kw",
        "harmonics",
        "method",
        "dynamics",
        "tol",
        "degree",
        "cycles",
        "f",
        "N",
    )  # fmt: skip
)
#: the symbols of the record in each markup: Unicode text, Matplotlib's mathtext, HTML
MARKUP = {
    "unicode": {"F_ex": "Fₑₓ", "mu": "μ", "F_N": "Fₙ", "k_w": "k_w", "Nh": "Nₕ", "u0": "u₀"},
    "mathtext": {
        "F_ex": r"$F_\mathrm{ex}$",
        "mu": r"$\mu$",
        "F_N": r"$F_\mathrm{N}$",
        "k_w": r"$k_\mathrm{w}$",
        "Nh": r"$N_\mathrm{h}$",
        "u0": r"$u_0$",
    },  # fmt: skip
    "html": {
        "F_ex": "F<sub>ex</sub>",
        "mu": "μ",
        "F_N": "F<sub>N</sub>",
        "k_w": "k<sub>w</sub>",
        "Nh": "N<sub>h</sub>",
        "u0": "u<sub>0</sub>",
    },  # fmt: skip
}


def version() -> str:
    """The installed fretwear version."""
    from .. import __version__

    return __version__


def settings_json(values: Mapping[str, Any]) -> str:
    """``values`` (a settings record) as the text of a settings file, with the fretwear version."""
    record = parse_settings(json.dumps(dict(values)))
    return json.dumps({"fretwear": version(), **record}, indent=1) + "\n"


def _check(key: str, value: Any, source: str) -> Any:
    kind, meaning = SETTINGS_KEYS[key]
    if kind is bool:
        ok = isinstance(value, bool)
    elif kind is str:
        ok = isinstance(value, str)
    else:
        ok = isinstance(value, (int, float)) and not isinstance(value, bool) and math.isfinite(value)
        ok = ok and (kind is float or float(value).is_integer())
    if not ok:
        what = {bool: "true or false", str: "a string", int: "a whole number", float: "a finite number"}[kind]
        raise ValueError(f"{source}: {key!r} ({meaning}) must be {what}, got {value!r}")
    return int(value) if kind is int else value


def parse_settings(text: str, source: str = "settings", ranges: bool = False) -> dict[str, Any]:
    """The settings record in the JSON ``text`` (``ValueError`` naming every bad key and what it must be).

    The object may hold any of ``SETTINGS_KEYS`` and the ``"fretwear"``
    version that wrote it. With ``ranges``, the numbers of
    :data:`fretwear.parameters.PARAMETERS` are checked against their ranges
    too (the dashboard's loader: every problem of a file at once); without,
    by whoever applies them (the CLI's options name themselves).
    """
    try:
        data = json.loads(text)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{source}: not JSON ({exc.msg} at line {exc.lineno})") from None
    if not isinstance(data, dict):
        raise ValueError(f"{source}: must be a JSON object of settings, got {type(data).__name__}")
    data.pop("fretwear", None)
    problems, record = [], {}
    unknown = sorted(set(data) - set(SETTINGS_KEYS))
    if unknown:
        problems.append(f"{source}: unknown keys {unknown}; known: {', '.join(SETTINGS_KEYS)}")
    for key in SETTINGS_KEYS:
        if key in data:
            try:
                record[key] = _check(key, data[key], source)
                if ranges and key in PARAMETERS:
                    PARAMETERS[key].check(record[key], f"{source}: {key!r}")
            except ValueError as exc:  # every bad value is named, not only the first
                problems.append(str(exc))
    if problems:
        raise ValueError("; ".join(problems))
    return record


def read_settings(path: str | Path) -> dict[str, Any]:
    """The settings record of the JSON file ``path`` (see :func:`parse_settings`)."""
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise ValueError(f"settings file {str(path)!r}: {exc.strerror or exc}") from None
    return parse_settings(text, f"settings file {path.name!r}")


def _items(values: Mapping[str, Any], markup: str | None) -> list[str]:
    symbols = MARKUP[markup] if markup else {}
    out = []
    for key, name, unit in _RECORD:
        if values.get(key) is None:
            continue
        value = values[key]
        text = f"{value:.4g}" if isinstance(value, float) else str(value)
        unit = symbols.get(unit, unit)
        out.append(f"{symbols.get(name, name)} = {text}{' ' + unit if unit else ''}")
    return out


def parameter_record(values: Mapping[str, Any], model: str = MODEL) -> list[str]:
    """Lines of the record of an export: the model, each parameter of ``values`` given, the version.

    ``values`` is a settings record; parameters it lacks (``None`` or absent)
    are left out, e.g. the tolerance of a method that takes none.
    """
    return [f"model: {model}", *_items(values, None), f"fretwear {version()}"]


def caption(values: Mapping[str, Any], model: str = MODEL, markup: str = "unicode") -> str:
    """One-paragraph caption of a figure: :func:`parameter_record` with symbols (μ, subscripts).

    ``markup``: ``"unicode"`` (plain text), ``"mathtext"`` (Matplotlib) or ``"html"``.
    """
    if markup not in MARKUP:
        raise ValueError(f"markup must be one of {sorted(MARKUP)}, got {markup!r}")
    text = ", ".join(_items(values, markup))
    if markup == "html":
        model = html.escape(model)
    return "; ".join([model, text, f"fretwear {version()}"])


def csv_header(values: Mapping[str, Any], model: str = MODEL) -> str:
    """The record as a block of ``#`` comment lines (pandas: ``read_csv(..., comment="#")``)."""
    return "".join(f"# {line}\n" for line in parameter_record(values, model))
