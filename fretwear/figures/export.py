"""Export of figures (PNG, SVG, standalone HTML) and tables (CSV)."""

from __future__ import annotations

import csv
import io
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .plots import holoviews, load_backend

if TYPE_CHECKING:
    import holoviews as hv

__all__ = ["FIGURE_FORMATS", "figure_bytes", "save_figure", "csv_text", "save_csv"]

#: formats of :func:`figure_bytes`
FIGURE_FORMATS = ("png", "svg", "html")
FigureFormat = Literal["png", "svg", "html"]


def figure_bytes(fig: hv.core.Dimensioned, fmt: FigureFormat, *, title: str = "fretwear figure") -> bytes:
    """Render ``fig`` as PNG or SVG (Matplotlib backend) or standalone HTML (Bokeh, inline resources).

    The HTML page, titled ``title``, embeds BokehJS and the data: it opens
    offline. Load the backend (:func:`load_backend`) before building ``fig``
    so that its options apply.
    """
    hv = holoviews()
    if fmt in ("png", "svg"):
        load_backend("matplotlib")
        data = hv.renderer("matplotlib").instance(dpi=120)(fig, fmt=fmt)[0]
        import matplotlib.pyplot as plt

        plt.close("all")
        return data.encode() if isinstance(data, str) else data
    if fmt == "html":
        load_backend("bokeh")
        from bokeh.document import Document
        from bokeh.embed import file_html

        # Bokeh alone, in a new document: Panel's ``save`` (behind ``hv.save``) would draw into a served
        # document and rewrite the stylesheet links it shares with it to CDN addresses
        plot = hv.renderer("bokeh").get_plot(fig, doc=Document())
        return file_html(plot.state, _inline_resources(), title=title).encode()
    raise ValueError(f"fmt must be one of {FIGURE_FORMATS}, got {fmt!r}")


def _inline_resources():
    """BokehJS inline, without the external scripts other imported models (Panel's) declare."""
    from bokeh.resources import Resources

    class Inline(Resources):
        def _collect_external_resources(self, resource_attr):
            return []

        def clone(self, *, components=None):
            return Inline(
                mode="inline", components=list(self.components if components is None else components)
            )

    return Inline(mode="inline")


def save_figure(fig: hv.core.Dimensioned, path: str | Path) -> Path:
    """Write ``fig`` to ``path``; the suffix (``.png``, ``.svg`` or ``.html``) sets the format."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in FIGURE_FORMATS:
        raise ValueError(f"the file name must end in one of {FIGURE_FORMATS}, got {path.name!r}")
    path.write_bytes(figure_bytes(fig, fmt, title=path.stem))  # type: ignore[arg-type]
    return path


def csv_text(columns: Mapping[str, Any]) -> str:
    """CSV text of equal-length ``columns`` (name -> values), header first; floats with 10 digits."""
    names = list(columns)
    values = [np.asarray(columns[n]).ravel() for n in names]
    lengths = {len(v) for v in values}
    if len(lengths) > 1:
        raise ValueError(
            f"columns must have equal lengths, got {dict(zip(names, map(len, values), strict=True))}"
        )

    def fmt(v):
        if isinstance(v, (float, np.floating)):
            return f"{v:.10g}"
        if isinstance(v, (np.bool_, bool)):
            return str(bool(v))
        return str(v)

    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(names)
    for row in zip(*values, strict=True):
        writer.writerow([fmt(v) for v in row])
    return buf.getvalue()


def save_csv(columns: Mapping[str, Any], path: str | Path) -> Path:
    """Write ``columns`` (see :func:`csv_text`) to ``path``."""
    path = Path(path)
    path.write_text(csv_text(columns))
    return path


# -- the paper's figure set ---------------------------------------------------------
