"""Figures and tables of the studies, and their export (PNG, SVG, standalone HTML, CSV).

The figure builders turn library results into HoloViews overlays with the
same look on the Bokeh backend (the dashboard, standalone HTML) and on the
Matplotlib backend (PNG and SVG, rendered without a browser). Options are set
for every backend loaded when a figure is built: call :func:`load_backend`
first for each backend the figure will be rendered with.

:func:`paper_figures` computes and writes the paper's figure set (Fig. 5-14 of
Salles et al. for the 2-DOF example) headlessly.

HoloViews, Bokeh and Matplotlib are imported inside the functions only:
``import fretwear`` does not need them.
"""

from __future__ import annotations

import csv
import io
import warnings
from collections.abc import Callable, Mapping, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

if TYPE_CHECKING:
    import holoviews as hv

__all__ = [
    "FIGURE_FORMATS",
    "load_backend",
    "figure_bytes",
    "save_figure",
    "csv_text",
    "save_csv",
    "line_figure",
    "map_figure",
    "signals_figure",
    "wear_curve",
    "paper_figures",
]

#: formats of :func:`figure_bytes`
FIGURE_FORMATS = ("png", "svg", "html")
FigureFormat = Literal["png", "svg", "html"]
XY = tuple[Any, Any]

_MPL_SIZE = {"fig_inches": (7.0, 4.0), "aspect": "auto"}


def _hv():
    import holoviews as hv

    return hv


def load_backend(name: Literal["bokeh", "matplotlib"]) -> None:
    """Load the HoloViews plotting backend ``name`` and keep the current backend.

    Loading a backend makes it the current one; this restores the previous one
    when another backend was already loaded (e.g. Bokeh in the dashboard).
    """
    hv = _hv()
    loaded = hv.Store.loaded_backends()
    if name in loaded:
        return
    current = hv.Store.current_backend if loaded else None
    if name == "matplotlib":
        import matplotlib

        if matplotlib.get_backend().lower() != "agg":
            matplotlib.use("Agg")
    hv.renderer(name)
    if current is not None:
        hv.Store.set_current_backend(current)


def _ensure_backend() -> None:
    if not _hv().Store.loaded_backends():
        load_backend("matplotlib")


def _opts(obj, common: dict | None = None, bokeh: dict | None = None, mpl: dict | None = None):
    """Apply ``common`` and the backend-specific options for every loaded backend."""
    hv = _hv()
    for backend, extra in (("bokeh", bokeh), ("matplotlib", mpl)):
        if backend in hv.Store.loaded_backends():
            obj = obj.opts(**(common or {}), **(extra or {}), backend=backend)
    return obj


def _positive(y) -> np.ndarray:
    """``y`` with non-positive values masked (NaN) for a logarithmic axis."""
    y = np.asarray(y, dtype=float)
    return np.where(y > 0, y, np.nan)


def _marker_line(hv, x: float | None, vertical: bool = True):
    line = (hv.VLine if vertical else hv.HLine)(np.nan if x is None else float(x))
    return _opts(
        line,
        {"color": "black", "alpha": 0.6},
        {"line_dash": "dotted", "line_width": 1.5},
        {"linestyle": ":", "linewidth": 1.5},
    )


def _overlay_options(overlay, title: str, xlabel: str, ylabel: str, logx: bool, logy: bool, legend: bool):
    return _opts(
        overlay,
        {
            "title": title,
            "xlabel": xlabel,
            "ylabel": ylabel,
            "logx": logx,
            "logy": logy,
            "show_legend": legend,
        },
        {"legend_position": "top_right", "responsive": True, "height": 340, "toolbar": "right"},
        {"legend_position": "right", **_MPL_SIZE},
    )


def line_figure(
    curves: Mapping[str, XY],
    *,
    xlabel: str,
    ylabel: str,
    title: str = "",
    logx: bool = False,
    logy: bool = False,
    dashed: Sequence[str] = (),
    vline: float | None = None,
    point: tuple[float, float] | None = None,
) -> hv.Overlay:
    """Curves ``label -> (x, y)`` on common axes, one legend entry each.

    The layers are the curves in the order given, then a vertical marker line
    at ``vline`` and a marker ``point`` when these are given (``nan`` hides
    them): figures built with the same arguments have the same structure, as
    a ``DynamicMap`` needs. Non-positive values are hidden on a logarithmic axis.
    """
    hv = _hv()
    _ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    layers = []
    for label, (x, y) in curves.items():
        x = _positive(x) if logx else np.asarray(x, dtype=float)
        y = _positive(y) if logy else np.asarray(y, dtype=float)
        curve = hv.Curve((x, y), xd, yd, label=label)
        dash = label in dashed
        curve = _opts(
            curve,
            {"framewise": True},
            {"line_width": 2, "line_dash": "dashed" if dash else "solid", "tools": ["hover"]},
            {"linewidth": 1.5, "linestyle": "--" if dash else "-"},
        )
        layers.append(curve)
    if vline is not None:
        layers.append(_marker_line(hv, vline))
    if point is not None:
        pts = hv.Points([point], [xd, yd], label="selected")
        layers.append(
            _opts(
                pts, {"color": "red"}, {"size": 10, "marker": "x", "line_width": 3}, {"s": 80, "marker": "X"}
            )
        )
    return _overlay_options(hv.Overlay(layers), title, xlabel, ylabel, logx, logy, len(curves) > 1)


def map_figure(
    x,
    y,
    z,
    *,
    xlabel: str,
    ylabel: str,
    zlabel: str,
    title: str = "",
    levels: Sequence[float] = (),
    clim: tuple[float, float] | None = None,
    cmap: str = "viridis",
    curves: Mapping[str, XY] | None = None,
    hline: float | None = None,
    point: tuple[float, float] | None = None,
) -> hv.Overlay:
    """Image of ``z`` (shape ``(len(y), len(x))``) over uniform grids ``x`` and ``y``.

    With contour lines at ``levels``, curves ``label -> (x, y)`` drawn on top
    (e.g. a boundary), a horizontal marker at ``hline`` and a marker ``point``.
    """
    hv = _hv()
    _ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    zd = hv.Dimension("z", label=zlabel)
    x, y, z = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    image = hv.Image((x, y, z), [xd, yd], [zd], rtol=1e-6)
    image = _opts(
        image,
        {"cmap": cmap, "colorbar": True, "clim": clim or (np.nan, np.nan), "framewise": True},
        {"tools": ["hover"]},
        {"aspect": "auto"},
    )
    layers = [image]
    if levels:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            contours = hv.operation.contours(image, levels=list(levels), overlaid=False)
        layers.append(
            _opts(
                contours,
                {"color": "white", "show_legend": False},
                {"line_width": 1.5, "tools": []},
                {"linewidth": 1.2},
            )
        )
    for label, (cx, cy) in (curves or {}).items():
        curve = hv.Curve((np.asarray(cx, dtype=float), np.asarray(cy, dtype=float)), xd, yd, label=label)
        layers.append(_opts(curve, {"color": "red"}, {"line_width": 2.5}, {"linewidth": 2}))
    if hline is not None:
        layers.append(
            _opts(
                hv.HLine(float(hline)),
                {"color": "white"},
                {"line_dash": "dashed", "line_width": 2},
                {"linestyle": "--", "linewidth": 1.5},
            )
        )
    if point is not None:
        pts = hv.Points([point], [xd, yd], label="selected")
        layers.append(
            _opts(
                pts, {"color": "red"}, {"size": 14, "marker": "x", "line_width": 3}, {"s": 100, "marker": "X"}
            )
        )
    overlay = hv.Overlay(layers)
    return _overlay_options(overlay, title, xlabel, ylabel, False, False, bool(curves))


def signals_figure(
    t,
    signals: Mapping[str, Any],
    *,
    spans: Sequence[tuple[float, float]] = (),
    hlines: Sequence[float] = (),
    xlabel: str,
    ylabel: str,
    title: str = "",
) -> hv.Overlay:
    """Signals over one period with shaded intervals ``spans`` (e.g. where the contact slips).

    The shading comes first, then one curve per signal, then dotted horizontal
    lines at ``hlines`` (e.g. the slip limits ``+-mu F_N``).
    """
    hv = _hv()
    _ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    shade = hv.VSpans(list(spans) or [(np.nan, np.nan)], [xd, yd])
    layers = [
        _opts(
            shade,
            {"alpha": 0.25},
            {"color": "orange", "line_alpha": 0},
            {"facecolor": "orange", "linewidth": 0},
        )
    ]
    t = np.asarray(t, dtype=float)
    for label, y in signals.items():
        curve = hv.Curve((t, np.asarray(y, dtype=float)), xd, yd, label=label)
        layers.append(
            _opts(curve, {"framewise": True}, {"line_width": 2, "tools": ["hover"]}, {"linewidth": 1.5})
        )
    layers += [_marker_line(hv, h, vertical=False) for h in hlines]
    return _overlay_options(hv.Overlay(layers), title, xlabel, ylabel, False, False, len(signals) > 1)


def wear_curve(history, cycles) -> tuple[np.ndarray, np.ndarray]:
    """``(N, w / u0)`` of the first contact of a :class:`~fretwear.wear.WearHistory` at ``cycles``.

    Uses the history's own interpolation (:meth:`~fretwear.wear.WearHistory.at`),
    which holds the last state past the last record (worn through, or stuck); a
    history that stopped on a failure is drawn up to its last record only.
    """
    cycles = np.asarray(cycles, dtype=float)
    if not history.converged:
        cycles = cycles[cycles <= history.cycles[-1]]
    return cycles, history.at(cycles)["wear"][:, 0] / history.u0[0]


# -- export ------------------------------------------------------------------------


def figure_bytes(fig: hv.core.Dimensioned, fmt: FigureFormat, *, title: str = "fretwear figure") -> bytes:
    """Render ``fig`` as PNG or SVG (Matplotlib backend) or standalone HTML (Bokeh, inline resources).

    The HTML page, titled ``title``, embeds BokehJS and the data: it opens
    offline. Load the backend (:func:`load_backend`) before building ``fig``
    so that its options apply.
    """
    hv = _hv()
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


def _layout(panels: list, cols: int):
    """Panels in a grid of ``cols`` columns, sized for Matplotlib."""
    hv = _hv()
    rows = -(-len(panels) // cols)
    layout = hv.Layout(panels).cols(cols)
    return _opts(
        layout,
        mpl={"fig_inches": (5.5 * cols, 3.8 * rows), "sublabel_format": "", "vspace": 0.6, "hspace": 0.5},
    )


def _wear_map_table(maps: Mapping[float, Any]) -> dict[str, np.ndarray]:
    """Long tables of several wear maps, with a ``fex`` column."""
    tables = []
    for fex, wm in maps.items():
        t = wm.long_table()
        tables.append({"fex": np.full(len(t["f_hz"]), fex), **t})
    return {k: np.concatenate([t[k] for t in tables]) for k in tables[0]}


def _history_table(histories: Mapping[str, Any], key: str) -> dict[str, np.ndarray]:
    rows = [(name, h) for name, h in histories.items() if h is not None]
    return {
        key: np.concatenate([np.full(len(h.cycles), name) for name, h in rows]),
        "cycles": np.concatenate([h.cycles for _, h in rows]),
        "w": np.concatenate([h.wear[:, 0] for _, h in rows]),
        "w_over_u0": np.concatenate([h.wear_fraction[:, 0] for _, h in rows]),
    }


def paper_figures(
    out: str | Path,
    *,
    harmonics: int = 21,
    kw: float = 1e-11,
    cycles: float = 1e5,
    frequencies: int = 41,
    cycle_points: int = 60,
    fmin: float = 0.3,
    fmax: float = 1.3,
    f_study: float = 0.7,
    method: str = "auto",
    tol: float = 1e-3,
    degree: int = 4,
    polynomial_harmonics: int = 3,
    formats: Sequence[str] = ("png", "svg", "csv"),
    workers: int = 2,
    log: Callable[[str], None] | None = None,
) -> list[Path]:
    """Compute the paper's figures 5-14 for the 2-DOF example and write them to ``out``.

    Each figure ``figNN`` is written in every format of ``formats`` (``png``,
    ``svg``, ``html``, and ``csv`` for its data). Excitation levels 6, 10 and
    14 N, ``mu = 1``, ``F_N = 10`` N (section 2.1):

    * fig05, fig06: nonlinear FRFs of mass 1 and of the relative displacement,
      with the linear stuck and open FRFs;
    * fig07: wear ``w / u0`` over frequency x cycles by ``method`` (a, b, c: 6,
      10, 14 N);
    * fig08: pseudo-FRFs of mass 1 at 6 N: open, stuck, initial and worn;
    * fig09: pseudo-FRFs at five cycle counts (a, b, c: 6, 10, 14 N);
    * fig10: ``w(N)`` at ``f_study`` Hz and 10 N for 1, 3, 7, 15 and 21 harmonics;
    * fig11: stepping, polynomial (``polynomial_harmonics``, ``degree``) and
      time integration at ``f_study`` Hz and 10 N, with the exact load path
      for reference (a method that fails is left out and reported through
      ``log``);
    * fig12: the wear map by the polynomial method at 10 N;
    * fig13, fig14: half peak-to-peak relative displacement over frequency x
      cycles at 10 N, by ``method`` and by the polynomial method.

    Parameters
    ----------
    out : str or Path
        Output directory (created if missing).
    harmonics : int
        Harmonics of the FRFs, of the wear maps and of stepping.
    kw : float
        Archard coefficient (1/Pa).
    cycles : float
        Cycle horizon of the wear studies.
    frequencies, cycle_points : int
        Sizes of the frequency grid (``fmin``-``fmax`` Hz) and of the
        logarithmic cycle grid of the maps.
    method : str
        Slow-time method of the wear maps (see :func:`fretwear.studies.wear_history`;
        ``"auto"``: the exact load path for this model).
    tol : float
        Tolerance of stepping and of the time integration (fraction of ``u0``).
    formats : sequence of str
        Any of ``png``, ``svg``, ``html``, ``csv``.
    workers : int
        Threads of the wear maps.
    log : callable, optional
        Receives one line per figure written and per problem met.

    Returns
    -------
    list of Path
        The files written.
    """
    from .continuation import sweep
    from .linear import linear_frf
    from .model import paper_model
    from .studies import harmonic_convergence, wear_history, wear_map

    bad = sorted(set(formats) - {*FIGURE_FORMATS, "csv"})
    if bad:
        raise ValueError(f"formats must be among {(*FIGURE_FORMATS, 'csv')}, got {bad}")
    if not 0 < fmin < fmax or not 0 < f_study:
        raise ValueError(f"need 0 < fmin < fmax and f_study > 0 (Hz), got {fmin}, {fmax}, {f_study}")
    if int(frequencies) < 2 or int(cycle_points) < 3:
        raise ValueError("frequencies must be >= 2 and cycle_points >= 3")
    say = log or (lambda _msg: None)
    for fmt in formats:
        if fmt in FIGURE_FORMATS:
            load_backend("matplotlib" if fmt != "html" else "bokeh")
    out = Path(out)
    out.mkdir(parents=True, exist_ok=True)
    written: list[Path] = []

    def write(name: str, fig, table: Mapping[str, Any]) -> None:
        for fmt in formats:
            path = out / f"{name}.{fmt}"
            if fmt == "csv":
                save_csv(table, path)
            else:
                save_figure(fig, path)
            written.append(path)
        say(f"wrote {name} ({', '.join(formats)})")

    levels = (6.0, 10.0, 14.0)
    f_fine = np.linspace(fmin, fmax, 8 * (int(frequencies) - 1) + 1)
    f_map = np.linspace(fmin, fmax, int(frequencies))
    n_grid = np.concatenate([[0.0], np.geomspace(cycles * 1e-4, cycles, int(cycle_points) - 1)])
    logn = np.log10(n_grid[1:])
    snapshots = np.concatenate([[0.0], cycles * np.array([1e-3, 1e-2, 1e-1, 1.0])])
    models = {fex: paper_model(fex=fex) for fex in levels}
    m10 = models[10.0]
    lin = {
        fex: {s: linear_frf(m, 2 * np.pi * f_fine, s) for s in ("stuck", "open")} for fex, m in models.items()
    }
    x1 = {fex: {s: np.abs(u[:, 0]) for s, u in lu.items()} for fex, lu in lin.items()}

    # Fig. 5-6: nonlinear FRFs
    sweeps = {fex: sweep(m, 2 * np.pi * f_fine, harmonics) for fex, m in models.items()}
    amp = {fex: np.array([s.amplitude[0] for s in sw.solutions]) for fex, sw in sweeps.items()}
    rel = {
        fex: np.array([s.relative_half_peak_to_peak[0] for s in sw.solutions]) for fex, sw in sweeps.items()
    }
    curves = {f"{fex:g} N": (f_fine, a) for fex, a in amp.items()}
    curves |= {f"stuck ({fex:g} N)": (f_fine, x1[fex]["stuck"]) for fex in (levels[0], levels[-1])}
    curves |= {f"open ({fex:g} N)": (f_fine, x1[fex]["open"]) for fex in (levels[0], levels[-1])}
    dashed = [k for k in curves if k.startswith(("stuck", "open"))]
    table = {"f_hz": f_fine, **{f"x1_h1_{fex:g}N": a for fex, a in amp.items()}}
    write(
        "fig05",
        line_figure(
            curves,
            xlabel="frequency (Hz)",
            ylabel="x1 amplitude (m)",
            logy=True,
            dashed=dashed,
            title="Fig. 5: FRF of mass 1",
        ),
        table,
    )
    curves = {f"{fex:g} N": (f_fine, r) for fex, r in rel.items()}
    curves |= {
        f"open ({fex:g} N)": (f_fine, np.abs(lin[fex]["open"] @ m10.relative_map()[0]))
        for fex in (levels[0], levels[-1])
    }
    table = {"f_hz": f_fine, **{f"xr_half_p2p_{fex:g}N": r for fex, r in rel.items()}}
    write(
        "fig06",
        line_figure(
            curves,
            xlabel="frequency (Hz)",
            ylabel="x1 - x2, half peak-to-peak (m)",
            logy=True,
            dashed=[k for k in curves if k.startswith("open")],
            title="Fig. 6: FRF of the relative displacement",
        ),
        table,
    )

    # Fig. 7, 9, 13: wear maps by ``method``
    opts = {"kw": kw, "harmonics": harmonics, "tol": tol, "workers": workers}
    maps = {fex: wear_map(m, f_map, n_grid, method=method, **opts) for fex, m in models.items()}
    say(f"computed the wear maps ({method})")
    panels = [
        map_figure(
            f_map,
            logn,
            wm.wear_fraction[:, 1:, 0].T,
            xlabel="frequency (Hz)",
            ylabel="log10 cycles",
            zlabel="w / u0",
            clim=(0, 1),
            levels=(0.1, 0.5, 0.9),
            title=f"Fig. 7{'abc'[i]}: F_ex = {fex:g} N",
        )
        for i, (fex, wm) in enumerate(maps.items())
    ]
    write("fig07", _layout(panels, 3), _wear_map_table(maps))
    # Fig. 8: four cases at 6 N
    wm6 = maps[6.0]
    late = snapshots[-2]
    pseudo = wm6.pseudo_frf([0.0, late])[:, :, 0]
    curves = {
        "open": (f_fine, x1[6.0]["open"]),
        "stuck": (f_fine, x1[6.0]["stuck"]),
        "NL, N = 0": (f_map, pseudo[0]),
        f"NL, N = {late:.3g}": (f_map, pseudo[1]),
    }
    table = {"f_hz": f_map, "x1_h1_N0": pseudo[0], f"x1_h1_N{late:.6g}": pseudo[1]}
    write(
        "fig08",
        line_figure(
            curves,
            xlabel="frequency (Hz)",
            ylabel="x1 amplitude (m)",
            logy=True,
            dashed=["open", "stuck"],
            title="Fig. 8: pseudo-FRFs of mass 1, 6 N",
        ),
        table,
    )
    # Fig. 9: pseudo-FRFs at several cycle counts
    panels, table = [], {"f_hz": f_map}
    for i, (fex, wm) in enumerate(maps.items()):
        pseudo = wm.pseudo_frf(snapshots)[:, :, 0]
        curves = {"open": (f_fine, x1[fex]["open"]), "stuck": (f_fine, x1[fex]["stuck"])}
        curves |= {f"N = {n:.3g}": (f_map, p) for n, p in zip(snapshots, pseudo, strict=True)}
        table |= {f"x1_h1_{fex:g}N_N{n:.6g}": p for n, p in zip(snapshots, pseudo, strict=True)}
        panels.append(
            line_figure(
                curves,
                xlabel="frequency (Hz)",
                ylabel="x1 amplitude (m)",
                logy=True,
                dashed=["open", "stuck"],
                title=f"Fig. 9{'abc'[i]}: F_ex = {fex:g} N",
            )
        )
    write("fig09", _layout(panels, 1), table)

    # Fig. 10: harmonic convergence at f_study, 10 N
    hc = harmonic_convergence(m10, f_study, kw=kw, cycles=cycles, tol=tol)
    dense = np.concatenate([[0.0], np.geomspace(cycles * 1e-4, cycles, 200)])
    curves = {f"Nh = {nh}": wear_curve(h, dense) for nh, h in hc.items()}
    write(
        "fig10",
        line_figure(
            curves,
            xlabel="cycles",
            ylabel="w / u0",
            logx=True,
            title=f"Fig. 10: harmonics, {f_study:g} Hz, 10 N",
        ),
        _history_table({f"{nh}": h for nh, h in hc.items()}, "harmonics"),
    )

    # Fig. 11: three methods at f_study, 10 N
    methods: dict[str, Any] = {}
    settings = {
        "exact": {"harmonics": harmonics},
        "stepping": {"harmonics": harmonics, "tol": tol},
        "polynomial": {"harmonics": polynomial_harmonics, "degree": degree},
        "time": {"tol": tol},
    }
    for method, extra in settings.items():
        try:
            methods[method] = wear_history(m10, 2 * np.pi * f_study, method, kw=kw, cycles=cycles, **extra)
        except Exception as exc:  # noqa: BLE001 - a failing method is reported and left out
            methods[method] = None
            say(f"fig11: method {method!r} failed: {exc}")
    curves = {m: wear_curve(h, dense) for m, h in methods.items() if h is not None}
    write(
        "fig11",
        line_figure(
            curves,
            xlabel="cycles",
            ylabel="w / u0",
            logx=True,
            title=f"Fig. 11: three methods, {f_study:g} Hz, 10 N",
        ),
        _history_table(methods, "method"),
    )

    # Fig. 12, 14: polynomial wear map at 10 N; Fig. 13: stepping relative displacement
    poly = wear_map(
        m10,
        f_map,
        n_grid,
        method="polynomial",
        kw=kw,
        harmonics=polynomial_harmonics,
        degree=degree,
        workers=workers,
    )
    say("computed the polynomial wear map")
    write(
        "fig12",
        map_figure(
            f_map,
            logn,
            poly.wear_fraction[:, 1:, 0].T,
            xlabel="frequency (Hz)",
            ylabel="log10 cycles",
            zlabel="w / u0",
            clim=(0, 1),
            levels=(0.1, 0.5, 0.9),
            title="Fig. 12: polynomial method, 10 N",
        ),
        poly.long_table(),
    )
    for name, wm, label in (("fig13", maps[10.0], method), ("fig14", poly, "polynomial")):
        z = np.log10(_positive(wm.relative_half_peak_to_peak[:, 1:, 0].T))
        top = np.nanmax(z)
        write(
            name,
            map_figure(
                f_map,
                logn,
                z,
                xlabel="frequency (Hz)",
                ylabel="log10 cycles",
                zlabel="log10 |x1 - x2| (m)",
                clim=(top - 4, top),
                cmap="magma",
                title=f"Fig. {name[-2:]}: relative displacement, {label}, 10 N",
            ),
            wm.long_table(),
        )
    return written
