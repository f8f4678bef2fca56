"""Export of figures (PNG, SVG, standalone HTML) and tables (CSV), with their parameter record.

:class:`ExportOptions` sets the size, resolution and font size of a figure;
a caption (:func:`~fretwear.figures.caption`) goes under the figure and a
comment block (:func:`~fretwear.figures.csv_header`) above a table.
"""

from __future__ import annotations

import csv
import html
import io
import math
import threading
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

from .layout import lay_out
from .plots import holoviews, load_backend
from .record import version

#: a figure's caption: its text, or ``markup -> text`` (``"mathtext"`` for Matplotlib, ``"html"``)
Caption = str | Callable[[str], str] | None

if TYPE_CHECKING:
    import holoviews as hv

__all__ = [
    "EXPORT_FORMATS",
    "SIZES",
    "ExportOptions",
    "figure_title",
    "matplotlib_figure",
    "figure_bytes",
    "render_figure",
    "save_figure",
    "save_figures",
    "csv_text",
    "save_csv",
]

#: formats of :func:`figure_bytes` and of the dashboard's downloads
EXPORT_FORMATS = ("png", "svg", "pdf", "html")
FigureFormat = Literal["png", "svg", "pdf", "html"]
#: named sizes: width and height (in) and font size of the axis labels (pt); one journal column, a page
#: (the dashboard's default size) and a slide
SIZES: dict[str, tuple[float, float, float]] = {
    "column": (3.5, 2.5, 7.0),
    "page": (7.0, 4.0, 10.0),
    "slide": (10.0, 6.0, 14.0),
}
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
        Resolution of PNG files (dots per inch), in [50, 600]; SVG, PDF and HTML
        are vector or screen formats and ignore it (HTML is sized at 96 px per inch).
    fontsize : float
        Font size of the axis labels (pt), in [4, 40]; titles are 1.2 times,
        ticks and legends 0.9 times as large; ``None`` keeps the defaults.
    size : str, optional
        A name of :data:`SIZES` (``"column"``, ``"page"``, ``"slide"``): its
        width, height and font size, for those not given.
    """

    width: float | None = None
    height: float | None = None
    dpi: int = 150
    fontsize: float | None = None
    size: str | None = None

    #: valid ranges: name -> (low, high, unit)
    RANGES = {"width": (2.0, 30.0, "in"), "height": (2.0, 30.0, "in"), "dpi": (50, 600, ""),
              "fontsize": (4.0, 40.0, "pt")}  # fmt: skip

    def __post_init__(self) -> None:
        if self.size is not None:
            if self.size not in SIZES:
                raise ValueError(f"size must be one of {', '.join(SIZES)}, got {self.size!r}")
            for name, value in zip(("width", "height", "fontsize"), SIZES[self.size], strict=True):
                if getattr(self, name) is None:
                    object.__setattr__(self, name, value)  # frozen: filled in once, here
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
    """Render ``fig`` as PNG, SVG or PDF (Matplotlib backend) or standalone HTML (Bokeh, inline resources).

    ``options`` sets the size, the resolution and the font size; ``caption``
    (the parameter record: its text, or a function of the markup, see
    :func:`~fretwear.figures.caption`) is written under the figure. The
    Matplotlib formats are laid out by :func:`~fretwear.figures.lay_out`
    and carry the figure's own title (else ``title``), ``fretwear <version>``
    as their creator and the record as their description in their metadata.
    The HTML page, titled ``title``, embeds BokehJS and the data: it opens offline. Load the backend
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
    """``fig`` in each of ``formats`` (see :func:`figure_bytes`), drawn once for PNG, SVG and PDF together."""
    bad = sorted(set(formats) - set(EXPORT_FORMATS))
    if bad:
        raise ValueError(f"fmt must be one of {EXPORT_FORMATS}, got {bad[0]!r}")
    options = options or ExportOptions()
    out = {}
    raster = tuple(f for f in formats if f in ("png", "svg", "pdf"))
    with _RENDERING:  # the renderers keep process-wide state: renders from a server's threads take turns
        if raster:
            out |= _matplotlib_bytes(fig, raster, options, caption, title)
        if "html" in formats:
            out["html"] = _html_bytes(fig, title, options, caption)
    return out


def _text(caption: Caption, markup: str) -> str:
    return caption(markup) if callable(caption) else (caption or "")


def _metadata(fmt: str, title: str, caption: str) -> dict[str, str]:
    """The file's metadata in ``fmt``'s own keys: the title, fretwear as creator, the record (caption)."""
    creator = f"fretwear {version()}"
    keys = {"png": ("Title", "Software", "Description"), "svg": ("Title", "Creator", "Description"),
            "pdf": ("Title", "Creator", "Subject")}[fmt]  # fmt: skip
    values = dict(zip(keys, (title, creator, caption), strict=True))
    return {k: v for k, v in values.items() if v}


def figure_title(figure) -> str:
    """The titles of ``figure``'s axes (a Matplotlib figure), on one line, joined by ``"; "``."""
    titles = (" ".join(ax.get_title().split()) for ax in figure.axes)
    return "; ".join(dict.fromkeys(t for t in titles if t))


def matplotlib_figure(
    fig: hv.core.Dimensioned, options: ExportOptions | None = None, caption: Caption = None
):
    """``fig`` drawn by Matplotlib and laid out for a file (:func:`~fretwear.figures.lay_out`).

    The figure is ``options``' size (or its own) with ``caption`` under it, on
    an Agg canvas; the caller closes it (``matplotlib.pyplot.close``). Load the
    Matplotlib backend (:func:`load_backend`) before building ``fig``.
    """
    options = options or ExportOptions()
    hv = holoviews()
    load_backend("matplotlib")
    opts: dict[str, Any] = {}
    if options.width is not None or options.height is not None:
        opts["fig_inches"] = (options.width or 7.0, options.height or 4.0)
    if options.fontsize is not None:
        opts["fontsize"] = options.fonts()
    if opts:
        fig = fig.opts(backend="matplotlib", **opts)
    from matplotlib.backends.backend_agg import FigureCanvasAgg

    figure = hv.renderer("matplotlib").get_plot(fig).state
    if options.width is not None or options.height is not None:  # layouts size themselves by aspect
        w, h = figure.get_size_inches()
        figure.set_size_inches(options.width or w, options.height or h)
    FigureCanvasAgg(figure)  # HoloViews leaves the base canvas, which has no renderer
    size = 0.75 * (options.fontsize or 10.0)
    lay_out(figure, _text(caption, "mathtext"), size, options.fontsize)
    return figure


def _matplotlib_bytes(
    fig, formats: tuple[str, ...], options: ExportOptions, caption: Caption, title: str | None
) -> dict:
    import matplotlib
    import matplotlib.pyplot as plt

    figure = matplotlib_figure(fig, options, caption)
    try:
        # the record also in the file's metadata, as plain Unicode text (the caption's mathtext is drawn
        # glyph by glyph)
        name = figure_title(figure) or title or "fretwear figure"
        out = {}
        for fmt in formats:
            buf = io.BytesIO()
            with matplotlib.rc_context({"svg.fonttype": "none"}):  # SVG text stays text: searchable, editable
                figure.savefig(
                    buf, format=fmt, dpi=options.dpi, metadata=_metadata(fmt, name, _text(caption, "unicode"))
                )
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
    """Write ``fig`` to ``path``; the suffix (``.png``, ``.svg``, ``.pdf`` or ``.html``) sets the format."""
    path = Path(path)
    fmt = path.suffix.lstrip(".").lower()
    if fmt not in EXPORT_FORMATS:
        raise ValueError(f"the file name must end in one of {EXPORT_FORMATS}, got {path.name!r}")
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
    """Write ``fig`` to each of ``paths`` (one format per suffix), drawn once for PNG, SVG and PDF."""
    paths = [Path(p) for p in paths]
    formats = tuple(p.suffix.lstrip(".").lower() for p in paths)
    for p, fmt in zip(paths, formats, strict=True):
        if fmt not in EXPORT_FORMATS:
            raise ValueError(f"the file name must end in one of {EXPORT_FORMATS}, got {p.name!r}")
    data = render_figure(fig, formats, title=paths[0].stem if paths else "", options=options, caption=caption)
    for p, fmt in zip(paths, formats, strict=True):
        p.write_bytes(data[fmt])
    return paths


def csv_text(columns: Mapping[str, Any], header: str = "") -> str:
    """CSV text of equal-length ``columns`` (name -> values), column names first; floats with 10 digits.

    ``header`` (e.g. :func:`~fretwear.figures.csv_header`: ``#`` comment
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
