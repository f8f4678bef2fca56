"""The ``_repr_html_`` of the main result types: a small table of their key fields, for Jupyter.

One helper for every result (:func:`summary_html`): a field is shown when the
result has it (periodic solutions, wear histories, wear maps, interface
histories), so the tables read the same across types.
"""

from __future__ import annotations

from collections.abc import Callable
from html import escape
from typing import Any

import numpy as np

__all__ = ["summary_html", "summary_rows"]


def _get(obj: Any, name: str) -> Any:
    try:
        return getattr(obj, name)
    except Exception:  # noqa: BLE001 - a lazy field that cannot be computed is left out of a summary
        return None


def _method(obj: Any) -> str | None:
    if _get(obj, "path") == "shooting":
        return "shooting (exact event-driven dynamics)"
    if _get(obj, "path") is not None and _get(obj, "harmonics") is not None:
        return f"{obj.path}, Nh = {obj.harmonics}, N = {obj.samples}"
    return _get(obj, "label") or _get(obj, "method")


def _frequency(obj: Any) -> str | None:
    f = _get(obj, "frequency")
    if f is None:
        return None
    f = np.atleast_1d(f)
    return f"{f[0]:.6g} Hz" if f.size == 1 else f"{f.size} from {f.min():.6g} to {f.max():.6g} Hz"


def _converged(obj: Any) -> str | None:
    c = _get(obj, "converged")
    if c is None:
        return None
    c = np.atleast_1d(c)
    return ("yes" if c[0] else "no") if c.size == 1 else f"{int(c.sum())} of {c.size} frequencies"


def _cycles(obj: Any) -> str | None:
    n = _get(obj, "cycles")
    if n is None or not np.size(n):
        return None
    n = np.asarray(n)
    return f"{n.size} records, 0 to {n.max():.4g}" if n.size > 1 else f"{n.max():.4g}"


def _wear(obj: Any) -> str | None:
    if _get(obj, "cycles") is None:  # a periodic solution: its wear is an input
        return None
    if _get(obj, "u0") is not None:
        return f"{np.max(obj.wear_fraction):.4g} u0 (largest)"
    w = _get(obj, "wear")
    return None if w is None or not np.size(w) else f"{np.max(w):.4g} m (largest)"


def _error(obj: Any) -> str | None:
    """The error the result measured on itself (polynomial fits: misfit and wear defect)."""
    info = _get(obj, "info") or {}
    parts = [
        f"{key.replace('_', ' ')} {info[key]:.3g}"
        for key in ("misfit", "wear_defect")
        if np.ndim(info.get(key)) == 0 and info.get(key) is not None
    ]
    return ", ".join(parts) or None


def _number(name: str, fmt: str) -> Callable[[Any], str | None]:
    def get(obj: Any) -> str | None:
        value = _get(obj, name)
        return None if value is None or np.ndim(value) else format(value, fmt)

    return get


#: the rows of a summary: label, and how to read it (None: the result has no such field)
ROWS: tuple[tuple[str, Callable[[Any], str | None]], ...] = (
    ("method", _method),
    ("dynamics", lambda o: _get(o, "dynamics")),
    ("converged", _converged),
    ("status", lambda o: _get(o, "status")),
    ("message", lambda o: _get(o, "message") or None),
    ("residual", _number("residual", ".2e")),
    ("iterations", _number("iterations", "d")),
    ("frequency", _frequency),
    ("cycles", _cycles),
    ("wear", _wear),
    ("measured error", _error),
    ("periodic solves", _number("solves", "d")),
    ("wall time (s)", _number("wall_time", ".3g")),
)


def summary_rows(obj: Any) -> list[tuple[str, str]]:
    """The (label, text) rows of ``obj``'s summary: the fields of :data:`ROWS` it has."""
    rows = [(label, get(obj)) for label, get in ROWS]
    return [(label, str(text)) for label, text in rows if text is not None]


def summary_html(obj: Any) -> str:
    """A small HTML table of ``obj``'s key fields, titled by its type, ending with how to get all of it."""
    left = 'style="text-align:left"'
    body = "".join(
        f"<tr><th {left}>{escape(label)}</th><td {left}>{escape(text)}</td></tr>"
        for label, text in summary_rows(obj)
    )
    name = escape(type(obj).__name__)
    return (
        f"<table><caption {left}><b>{name}</b></caption>{body}</table>"
        "<small>all fields: <code>.to_xarray()</code></small>"
    )
