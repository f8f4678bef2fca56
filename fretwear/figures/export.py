"""Export of figures (PNG, SVG, standalone HTML) and tables (CSV), with their parameter record.

:class:`ExportOptions` sets the size, resolution and font size of a figure;
a caption (:func:`fretwear.figures.record.caption`) goes under the figure and a
comment block (:func:`fretwear.figures.record.csv_header`) above a table.
"""

from __future__ import annotations

import csv
import html
import io
import math
import re
import threading
import warnings
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .plots import holoviews, load_backend

#: a figure's caption: its text, or ``markup -> text`` (``"mathtext"`` for Matplotlib, ``"html"``)
Caption = str | Callable[[str], str] | None

if TYPE_CHECKING:
    import holoviews as hv

__all__ = [
    "FIGURE_FORMATS",
    "ExportOptions",
    "figure_bytes",
    "render_figure",
    "save_figure",
    "save_figures",
    "csv_text",
    "save_csv",
]

#: formats of :func:`figure_bytes`
FIGURE_FORMATS = ("png", "svg", "html")
FigureFormat = Literal["png", "svg", "html"]
#: CSS pixels per inch: the size of an HTML figure
CSS_DPI = 96


@dataclass(frozen=True)
class ExportOptions:
    """Size, resolution and font size of an exported figure.

    Attributes
    ----------
    width, height : float
        Size of the whole figure, caption included (inches), in [2, 30]; ``None``
        keeps the figure's own size.
    dpi : int
        Resolution of PNG files (dots per inch), in [50, 600]; SVG and HTML are
        vector or screen formats and ignore it (HTML is sized at 96 px per inch).
    fontsize : float
        Font size of the axis labels (pt), in [4, 40]; titles are 1.2 times,
        ticks and legends 0.9 times as large; ``None`` keeps the defaults.
    """

    width: float | None = None
    height: float | None = None
    dpi: int = 120
    fontsize: float | None = None

    #: valid ranges: name -> (low, high, unit)
    RANGES = {"width": (2.0, 30.0, "in"), "height": (2.0, 30.0, "in"), "dpi": (50, 600, ""),
              "fontsize": (4.0, 40.0, "pt")}  # fmt: skip

    def __post_init__(self) -> None:
        for name, (low, high, unit) in self.RANGES.items():
            value = getattr(self, name)
            if value is None and name != "dpi":
                continue
            ok = isinstance(value, (int, float, np.integer, np.floating)) and not isinstance(value, bool)
            ok = ok and math.isfinite(value) and low <= value <= high
            if not ok or (name == "dpi" and not float(value).is_integer()):
                kind = "a whole number" if name == "dpi" else "a number"
                unit = f" {unit}" if unit else ""
                raise ValueError(f"{name} must be {kind} in [{low:g}, {high:g}]{unit}, got {value!r}")

    def fonts(self) -> dict[str, float]:
        """HoloViews ``fontsize`` option of :attr:`fontsize` (pt)."""
        f = self.fontsize
        return {"title": 1.2 * f, "labels": f, "xticks": 0.9 * f, "yticks": 0.9 * f, "legend": 0.9 * f,
                "cticks": 0.9 * f, "clabel": f}  # fmt: skip


def figure_bytes(
    fig: hv.core.Dimensioned,
    fmt: FigureFormat,
    *,
    title: str = "fretwear figure",
    options: ExportOptions | None = None,
    caption: Caption = None,
) -> bytes:
    """Render ``fig`` as PNG or SVG (Matplotlib backend) or standalone HTML (Bokeh, inline resources).

    ``options`` sets the size, the resolution and the font size; ``caption``
    (the parameter record: its text, or a function of the markup, see
    :func:`fretwear.figures.record.caption`) is written under the figure. The HTML page, titled
    ``title``, embeds BokehJS and the data: it opens offline. Load the backend
    (:func:`load_backend`) before building ``fig`` so that its options apply.
    """
    return render_figure(fig, (fmt,), title=title, options=options, caption=caption)[fmt]


#: one render at a time (Matplotlib's figure manager and HoloViews' renderers are process-wide)
_RENDERING = threading.Lock()


def render_figure(
    fig: hv.core.Dimensioned,
    formats: tuple[str, ...],
    *,
    title: str = "fretwear figure",
    options: ExportOptions | None = None,
    caption: Caption = None,
) -> dict[str, bytes]:
    """``fig`` in each of ``formats`` (see :func:`figure_bytes`), drawn once for PNG and SVG together."""
    bad = sorted(set(formats) - set(FIGURE_FORMATS))
    if bad:
        raise ValueError(f"fmt must be one of {FIGURE_FORMATS}, got {bad[0]!r}")
    options = options or ExportOptions()
    out = {}
    raster = tuple(f for f in formats if f in ("png", "svg"))
    with _RENDERING:  # the renderers keep process-wide state: renders from a server's threads take turns
        if raster:
            out |= _matplotlib_bytes(fig, raster, options, caption)
        if "html" in formats:
            out["html"] = _html_bytes(fig, title, options, caption)
    return out


def _text(caption: Caption, markup: str) -> str:
    return caption(markup) if callable(caption) else (caption or "")


def _wrapped(figure, canvas, text: str, size: float) -> str:
    """``text`` in lines as wide as the figure (less 2 %), broken after its ``", "`` and ``"; "``.

    Each piece is measured once: Matplotlib's own wrapping measures every
    growing line, each a new mathtext parse (about 1.4 s per exported figure).
    """
    renderer = canvas.get_renderer()
    probe = figure.text(0, 0, "", fontsize=size)

    def width(piece: str) -> float:
        probe.set_text(piece)
        return probe.get_window_extent(renderer).width

    space = width("a a") - width("aa")
    room = 0.98 * figure.get_figwidth() * figure.dpi
    lines: list[list[str]] = [[]]
    used = 0.0
    for piece in re.split(r"(?<=[,;]) ", text):
        w = width(piece)
        if lines[-1] and used + space + w > room:
            lines.append([])
            used = 0.0
        used += (space if lines[-1] else 0.0) + w
        lines[-1].append(piece)
    probe.remove()
    return "\n".join(" ".join(line) for line in lines)


def _matplotlib_bytes(fig, formats: tuple[str, ...], options: ExportOptions, caption: Caption) -> dict:
    hv = holoviews()
    load_backend("matplotlib")
    opts: dict[str, Any] = {}
    if options.width is not None or options.height is not None:
        opts["fig_inches"] = (options.width or 7.0, options.height or 4.0)
    if options.fontsize is not None:
        opts["fontsize"] = options.fonts()
    if opts:
        fig = fig.opts(backend="matplotlib", **opts)
    import matplotlib
    import matplotlib.pyplot as plt
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    plot = hv.renderer("matplotlib").get_plot(fig)
    figure = plot.state
    try:
        if options.width is not None or options.height is not None:  # layouts size themselves by aspect
            w, h = figure.get_size_inches()
            figure.set_size_inches(options.width or w, options.height or h)
        canvas = FigureCanvasAgg(figure)  # HoloViews leaves the base canvas, which has no renderer
        bottom = 0.0
        if caption:
            size = 0.75 * (options.fontsize or 10.0)
            words = _wrapped(figure, canvas, _text(caption, "mathtext"), size)
            text = figure.text(0.01, 0.01, words, fontsize=size, va="bottom", ha="left")
            text.set_in_layout(False)
            extent = text.get_window_extent(canvas.get_renderer())  # wrapped to the width
            bottom = min(
                0.5, (extent.height + 0.15 * figure.dpi) / (figure.get_size_inches()[1] * figure.dpi)
            )
        with warnings.catch_warnings():
            warnings.simplefilter(
                "ignore"
            )  # colour bars: "not compatible with tight_layout"; then as laid out
            figure.tight_layout(rect=(0, bottom, 1, 1))
        # the record also in the file's metadata, as plain Unicode text (the caption's mathtext is drawn
        # glyph by glyph)
        metadata = {"Description": _text(caption, "unicode")} if caption else {}
        out = {}
        for fmt in formats:
            buf = io.BytesIO()
            with matplotlib.rc_context({"svg.fonttype": "none"}):  # SVG text stays text: searchable, editable
                figure.savefig(buf, format=fmt, dpi=options.dpi, metadata=metadata)
            out[fmt] = buf.getvalue()
        return out
    finally:
        plt.close(figure)


def _html_bytes(fig, title: str, options: ExportOptions, caption: Caption) -> bytes:
    hv = holoviews()
    load_backend("bokeh")
    opts: dict[str, Any] = {}
    if options.width is not None or options.height is not None:
        opts |= {"responsive": False, "width": int(CSS_DPI * (options.width or 7.0)),
                 "height": int(CSS_DPI * (options.height or 4.0))}  # fmt: skip
    if options.fontsize is not None:
        opts["fontsize"] = {k: f"{v:.3g}pt" for k, v in options.fonts().items()}
    if opts:
        fig = fig.opts(backend="bokeh", **opts)
    from bokeh.document import Document
    from bokeh.embed import file_html
    from bokeh.layouts import column
    from bokeh.models import Div

    # Bokeh alone, in a new document: Panel's ``save`` (behind ``hv.save``) would draw into a served
    # document and rewrite the stylesheet links it shares with it to CDN addresses. The renderer keeps
    # the document given only in "server" mode; otherwise it takes ``curdoc()``, which in a server's
    # thread can be the document of a session that has just closed (and been destroyed).
    plot = hv.renderer("bokeh").instance(mode="server").get_plot(fig, doc=Document())
    root = plot.state
    if caption:
        words = caption("html") if callable(caption) else html.escape(caption)
        root = column(root, Div(text=f"<p style='font-size: 9pt'>{words}</p>"))
    page = file_html(root, _inline_resources(), title=title)
    if caption:  # the record as plain text too: Bokeh stores the caption's HTML escaped in its JSON
        meta = f'<meta name="description" content="{html.escape(_text(caption, "unicode"))}">'
        page = page.replace('<meta charset="utf-8">', f'<meta charset="utf-8">\n    {meta}', 1)
    return page.encode()


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


def save_figure(
    fig: hv.core.Dimensioned,
    path: str | Path,
    *,
    options: ExportOptions | None = None,
    caption: Caption = None,
) -> Path:
    """Write ``fig`` to ``path``; the suffix (``.png``, ``.svg`` or ``.html``) sets the format."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in FIGURE_FORMATS:
        raise ValueError(f"the file name must end in one of {FIGURE_FORMATS}, got {path.name!r}")
    data = figure_bytes(fig, fmt, title=path.stem, options=options, caption=caption)  # type: ignore[arg-type]
    path.write_bytes(data)
    return path


def save_figures(
    fig: hv.core.Dimensioned,
    paths: list[Path],
    *,
    options: ExportOptions | None = None,
    caption: Caption = None,
) -> list[Path]:
    """Write ``fig`` to each of ``paths`` (one format per suffix), drawn once for PNG and SVG."""
    paths = [Path(p) for p in paths]
    formats = tuple(p.suffix.lstrip(".").lower() for p in paths)
    for p, fmt in zip(paths, formats, strict=True):
        if fmt not in FIGURE_FORMATS:
            raise ValueError(f"the file name must end in one of {FIGURE_FORMATS}, got {p.name!r}")
    data = render_figure(fig, formats, title=paths[0].stem if paths else "", options=options, caption=caption)
    for p, fmt in zip(paths, formats, strict=True):
        p.write_bytes(data[fmt])
    return paths


def csv_text(columns: Mapping[str, Any], header: str = "") -> str:
    """CSV text of equal-length ``columns`` (name -> values), column names first; floats with 10 digits.

    ``header`` (e.g. :func:`fretwear.figures.record.csv_header`: ``#`` comment
    lines) comes before the column names.
    """
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
    buf.write(header)
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(names)
    for row in zip(*values, strict=True):
        writer.writerow([fmt(v) for v in row])
    return buf.getvalue()


def save_csv(columns: Mapping[str, Any], path: str | Path, header: str = "") -> Path:
    """Write ``columns`` (see :func:`csv_text`) to ``path``, after ``header``."""
    path = Path(path)
    path.write_text(csv_text(columns, header))
    return path
