"""Figure builders: library results as HoloViews overlays, for the dashboard and the exports.

The builders give the same look on the Bokeh backend (the dashboard,
standalone HTML) and on the Matplotlib backend (PNG and SVG, rendered without a
browser). Options are set for every backend loaded when a figure is built:
call :func:`load_backend` first for each backend the figure will be rendered with.
A figure only drawn on one backend (the dashboard's live plots) is built inside
:func:`styling_for`: HoloViews options cost about 10 ms per element and backend.
HoloViews, Bokeh and Matplotlib are imported inside the functions only.
"""

from __future__ import annotations

import warnings
from collections.abc import Iterator, Mapping, Sequence
from contextlib import contextmanager
from contextvars import ContextVar
from typing import TYPE_CHECKING, Any, Literal

import numpy as np

if TYPE_CHECKING:
    import holoviews as hv

__all__ = [
    "holoviews",
    "load_backend",
    "ensure_backend",
    "styling_for",
    "styled",
    "positive",
    "marker_line",
    "overlay_options",
    "line_figure",
    "map_figure",
    "wear_map_figure",
    "signals_figure",
    "wear_curve",
]

XY = tuple[Any, Any]

_MPL_SIZE = {"fig_inches": (7.0, 4.0), "aspect": "auto"}
#: legend background of maps (white contour lines must show on it)
LEGEND_GREY = "#b0b0b0"

#: the backends whose options :func:`styled` sets (``None``: every loaded backend); per thread and task
_STYLED_FOR: ContextVar[tuple[str, ...] | None] = ContextVar("fretwear_styled_for", default=None)


def holoviews():
    """The ``holoviews`` module, imported on first use."""
    import holoviews as hv

    return hv


def load_backend(name: Literal["bokeh", "matplotlib"]) -> None:
    """Load the HoloViews plotting backend ``name`` and keep the current backend.

    Loading a backend makes it the current one; this restores the previous one
    when another backend was already loaded (e.g. Bokeh in the dashboard).
    """
    hv = holoviews()
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


def ensure_backend() -> None:
    """Load the Matplotlib backend when no HoloViews backend is loaded yet."""
    if not holoviews().Store.loaded_backends():
        load_backend("matplotlib")


@contextmanager
def styling_for(*backends: Literal["bokeh", "matplotlib"]) -> Iterator[None]:
    """Figures built in this context get the options of ``backends`` only (of those loaded).

    For figures drawn on one backend only, e.g. the dashboard's live plots with
    ``styling_for("bokeh")`` while Matplotlib is loaded for its exports. The
    setting holds in the current thread (or task) only.
    """
    unknown = sorted(set(backends) - {"bokeh", "matplotlib"})
    if unknown:
        raise ValueError(f"backends must be 'bokeh' or 'matplotlib', got {unknown}")
    token = _STYLED_FOR.set(tuple(backends))
    try:
        yield
    finally:
        _STYLED_FOR.reset(token)


def styled(obj, common: dict | None = None, bokeh: dict | None = None, mpl: dict | None = None):
    """Apply ``common`` and the backend-specific options for every loaded backend (of
    :func:`styling_for`'s backends, inside it)."""
    hv = holoviews()
    only = _STYLED_FOR.get()
    for backend, extra in (("bokeh", bokeh), ("matplotlib", mpl)):
        if backend in hv.Store.loaded_backends() and (only is None or backend in only):
            obj = obj.opts(**(common or {}), **(extra or {}), backend=backend)
    return obj


def positive(y) -> np.ndarray:
    """``y`` with non-positive values masked (NaN) for a logarithmic axis."""
    y = np.asarray(y, dtype=float)
    return np.where(y > 0, y, np.nan)


def marker_line(hv, x: float | None, vertical: bool = True):
    """A dotted black line at ``x``: vertical, or horizontal if not ``vertical``; none if ``x`` is None.

    ``hv`` is the HoloViews module (imported by the caller, so that this module loads without it).
    """
    line = (hv.VLine if vertical else hv.HLine)(np.nan if x is None else float(x))
    return styled(
        line,
        {"color": "black", "alpha": 0.6},
        {"line_dash": "dotted", "line_width": 1.5},
        {"linestyle": ":", "linewidth": 1.5},
    )


def overlay_options(
    overlay,
    title: str,
    xlabel: str,
    ylabel: str,
    logx: bool,
    logy: bool,
    legend: bool,
    padding: float | tuple[float, float] = 0.0,
):
    """Title, axis labels and scales of ``overlay``, its legend beside the axes; ``padding``: room
    around the data (fraction of its range; or ``(x, y)``) so that no curve runs along the frame."""
    return styled(
        overlay,
        {
            "title": title,
            "xlabel": xlabel,
            "ylabel": ylabel,
            "logx": logx,
            "logy": logy,
            "show_legend": legend,
            "padding": padding,
        },
        # legends beside the axes, never over the curves
        {"legend_position": "right", "responsive": True, "height": 340, "toolbar": "right",
         **_log_ticks(logx, logy)},
        {"legend_position": "right", **_MPL_SIZE},
    )  # fmt: skip


def _log_ticks(logx: bool, logy: bool) -> dict:
    """Bokeh tickers that label 1, 2 and 5 times each power of ten on log axes: data within one decade
    (a life of 2000 to 5000 cycles) gets labels where it lies, not only at the decades around it."""
    if not (logx or logy) or "bokeh" not in holoviews().Store.loaded_backends():
        return {}
    from bokeh.models import LogTicker

    return {f"{axis}ticks": LogTicker(mantissas=[1, 2, 5]) for axis, log in (("x", logx), ("y", logy)) if log}


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
    padding: float = 0.0,
    legend_labels: Mapping[str, str] | None = None,
    extra: Sequence = (),
    colors: Mapping[str, str] | None = None,
    ylim: tuple[float, float] | None = None,
) -> hv.Overlay:
    """Curves ``label -> (x, y)`` on common axes, one legend entry each.

    The layers are the curves in the order given, then a vertical marker line
    at ``vline`` and a marker ``point`` when these are given (``nan`` hides
    them): figures built with the same arguments have the same structure, as
    a ``DynamicMap`` needs. Non-positive values are hidden on a logarithmic axis.
    ``padding`` leaves room around the data (e.g. a loop whose sides would sit
    on the frame). ``legend_labels`` shows other text for some labels: the
    labels stay the keys of the layers, which a ``DynamicMap`` keeps from frame
    to frame. ``extra`` layers (e.g. a cursor) come last. A curve label may not
    be an axis label: HoloViews would read it as that axis's values.
    ``colors``: label -> colour for some curves (e.g. a dashed reference in the
    colour of the curve it belongs to); the others take the default cycle.
    ``ylim``: the y range (default: all the data), e.g. the curves of interest when a reference peaks
    far above them.
    """
    hv = holoviews()
    ensure_backend()
    clash = sorted(set(curves) & {xlabel, ylabel})
    if clash:
        raise ValueError(f"curve labels must differ from the axis labels, got {clash}")
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    layers = []
    for label, (x, y) in curves.items():
        x = positive(x) if logx else np.asarray(x, dtype=float)
        y = positive(y) if logy else np.asarray(y, dtype=float)
        curve = hv.Curve((x, y), xd, yd, label=label)
        dash = label in dashed
        curve = styled(
            curve,
            {"framewise": True} | ({"color": colors[label]} if colors and label in colors else {}),
            {"line_width": 2, "line_dash": "dashed" if dash else "solid", "tools": ["hover"]},
            {"linewidth": 1.5, "linestyle": "--" if dash else "-"},
        )
        layers.append(curve)
    if vline is not None:
        layers.append(marker_line(hv, vline))
    if point is not None:
        pts = hv.Points([point], [xd, yd], label="selected")
        layers.append(
            styled(
                pts, {"color": "red"}, {"size": 10, "marker": "x", "line_width": 3}, {"s": 80, "marker": "X"}
            )
        )
    layers += list(extra)
    overlay = overlay_options(hv.Overlay(layers), title, xlabel, ylabel, logx, logy, len(curves) > 1, padding)
    if ylim is not None:
        overlay = styled(overlay, {"ylim": tuple(float(v) for v in ylim)})
    return styled(overlay, {"legend_labels": dict(legend_labels)}) if legend_labels else overlay


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
    reference: np.ndarray | None = None,
    level_label: str | None = None,
    reference_label: str = "reference",
    hline_label: str | None = None,
    hover: Mapping[str, np.ndarray] | None = None,
) -> hv.Overlay:
    """Image of ``z`` (shape ``(len(y), len(x))``) over uniform grids ``x`` and ``y``.

    With contour lines at ``levels`` (solid white; those of ``reference``, an
    array like ``z``, dashed red, e.g. an exact answer under an approximate
    one: the layer is there, empty, without it), curves ``label -> (x, y)``
    drawn on top (e.g. a boundary), a horizontal marker at ``hline`` and a
    marker ``point``. Every line has a legend entry: ``level_label`` (default
    the levels), ``reference_label``, ``hline_label`` (default "y = hline");
    the legend's background is grey, for the white lines to show. ``hover``:
    more values shown on hover, ``label -> array like z`` (e.g. N where the
    axis shows log10 N).
    """
    hv = holoviews()
    ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    zd = hv.Dimension("z", label=zlabel)
    x, y, z = np.asarray(x, dtype=float), np.asarray(y, dtype=float), np.asarray(z, dtype=float)
    extra = {
        label: np.broadcast_to(np.asarray(v, dtype=float), z.shape) for label, v in (hover or {}).items()
    }
    vdims = [zd, *(hv.Dimension(f"hover{i}", label=label) for i, label in enumerate(extra))]
    image = hv.Image((x, y, z, *extra.values()), [xd, yd], vdims, rtol=1e-6)
    image = styled(
        image,
        {"cmap": cmap, "colorbar": True, "clim": clim or (np.nan, np.nan), "framewise": True},
        {"tools": ["hover"]},
        {"aspect": "auto"},
    )
    layers = [image]
    if levels:

        def contours(z: np.ndarray | None) -> hv.Contours:
            if z is None:
                return hv.Contours([], [xd, yd], vdims=[zd])
            with warnings.catch_warnings():  # a level outside the data's range is no error here
                warnings.simplefilter("ignore")
                return hv.operation.contours(
                    hv.Image((x, y, np.asarray(z, dtype=float)), [xd, yd], [zd], rtol=1e-6),
                    levels=list(levels),
                    overlaid=False,
                )

        solid = ({"color": "white"}, {"line_width": 1.5, "tools": []}, {"linewidth": 1.2})
        dashed = (
            {"color": "red"},
            {"line_width": 2, "line_dash": "dashed", "tools": []},
            {"linewidth": 1.5, "linestyle": "--"},
        )
        if level_label is None:
            level_label = f"{zlabel} = {', '.join(f'{v:g}' for v in levels)}"
        for data, label, (common, bokeh, mpl) in (
            (z, level_label, solid),
            (reference, reference_label, dashed),
        ):
            if data is not None or reference is None:  # the empty layer keeps no legend entry
                layers.append(
                    styled(contours(data).relabel(label if data is not None else ""), common, bokeh, mpl)
                )
            else:
                layers.append(styled(contours(data), common, bokeh, mpl))
    for label, (cx, cy) in (curves or {}).items():
        curve = hv.Curve((np.asarray(cx, dtype=float), np.asarray(cy, dtype=float)), xd, yd, label=label)
        layers.append(styled(curve, {"color": "red"}, {"line_width": 2.5}, {"linewidth": 2}))
    if hline is not None:  # a curve across the map, not an annotation: it takes a legend entry
        label = hline_label or f"{ylabel} = {hline:.3g}"
        layers.append(
            styled(
                hv.Curve(([float(x.min()), float(x.max())], [float(hline)] * 2), xd, yd, label=label),
                {"color": "white"},
                {"line_dash": "dashed", "line_width": 2},
                {"linestyle": "--", "linewidth": 1.5},
            )
        )
    if point is not None:
        pts = hv.Points([point], [xd, yd], label="selected")
        layers.append(
            styled(
                pts, {"color": "red"}, {"size": 14, "marker": "x", "line_width": 3}, {"s": 100, "marker": "X"}
            )
        )
    overlay = overlay_options(hv.Overlay(layers), title, xlabel, ylabel, False, False, True)
    # a grey legend background: the white lines' entries would not show on white
    return styled(overlay, None, {"legend_opts": {"background_fill_color": LEGEND_GREY}},
                  {"legend_opts": {"facecolor": LEGEND_GREY}})  # fmt: skip


def wear_map_figure(
    frequency,
    cycles,
    wear_fraction,
    *,
    title: str = "",
    point: tuple[float, float] | None = None,
    reference=None,
    label: str | None = None,
    reference_label: str = "exact (same levels)",
) -> hv.Overlay:
    """Wear map ``w / u0`` over frequency (Hz) x log10 cycles (paper Fig. 7, 12), contours at 0.1/0.5/0.9.

    ``reference``: another map on the same grids (e.g. the exact one) whose contours are drawn dashed.
    ``label``, ``reference_label``: the legend entries of the two sets of contours.

    The colour scale runs from 0 to 1, or to the largest value when a method
    overshoots ``u0`` (never clipped: values above 1 stay visible).
    ``cycles`` starts at 0 (left out: the log axis starts at the next count);
    ``wear_fraction`` has shape ``(len(frequency), len(cycles))``; ``point`` is
    ``(f, N)`` in Hz and cycles.
    """
    logn = np.log10(np.asarray(cycles, dtype=float)[1:])
    z = np.asarray(wear_fraction, dtype=float)[:, 1:].T
    top = float(np.nanmax(z)) if np.isfinite(z).any() else 1.0
    return map_figure(
        frequency, logn, z,
        xlabel="frequency f (Hz)", ylabel="log₁₀ N (cycles)", zlabel="w / u₀",
        clim=(0, max(1.0, top)), levels=(0.1, 0.5, 0.9), title=title,
        point=None if point is None else (point[0], np.log10(point[1])),
        reference=None if reference is None else np.asarray(reference, dtype=float)[:, 1:].T,
        level_label=label, reference_label=reference_label,
        hover={"N (cycles)": np.broadcast_to(10.0 ** logn[:, None], z.shape)},  # the axis shows log10 N
    )  # fmt: skip


def signals_figure(
    t,
    signals: Mapping[str, Any],
    *,
    spans: Sequence[tuple[float, float]] = (),
    hlines: Sequence[float] = (),
    xlabel: str,
    ylabel: str,
    title: str = "",
    extra: Sequence = (),
    dashed: Sequence[str] = (),
    span_label: str = "contact slips (shaded)",
) -> hv.Overlay:
    """Signals over one period with shaded intervals ``spans`` (e.g. where the contact slips), named
    ``span_label`` in the legend.

    A signal is its values at ``t``, or a pair ``(t, values)`` on its own
    instants (e.g. an exact reference); those named in ``dashed`` are drawn dashed.
    The shading comes first, then one curve per signal, then dotted horizontal
    lines at ``hlines`` (e.g. the slip limits ``+-mu F_N``), then the ``extra``
    layers (e.g. a cursor). The vertical axis leaves 6 % of room above and below,
    so that a signal at its limit does not run along the frame.
    """
    hv = holoviews()
    ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    shade = hv.VSpans(list(spans) or [(np.nan, np.nan)], [xd, yd])
    layers = [
        styled(
            shade,
            {"alpha": 0.25},
            {"color": "orange", "line_alpha": 0},
            {"facecolor": "orange", "linewidth": 0},
        )
    ]
    t = np.asarray(t, dtype=float)
    for label, y in signals.items():
        ty, y = (np.asarray(y[0], dtype=float), y[1]) if isinstance(y, tuple) else (t, y)
        curve = hv.Curve((ty, np.asarray(y, dtype=float)), xd, yd, label=label)
        dash = label in dashed
        layers.append(
            styled(
                curve,
                {"framewise": True},
                {"line_width": 2, "line_dash": "dashed" if dash else "solid", "tools": ["hover"]},
                {"linewidth": 1.5, "linestyle": "--" if dash else "-"},
            )
        )
    # the shading's legend entry: a thick line of its colour (a span has no legend handle in Matplotlib)
    proxy = hv.Curve(([np.nan, np.nan], [np.nan, np.nan]), xd, yd, label=span_label)
    layers.append(styled(proxy, {"color": "orange", "alpha": 0.35}, {"line_width": 10}, {"linewidth": 8}))
    layers += [marker_line(hv, h, vertical=False) for h in hlines]
    layers += list(extra)
    return overlay_options(hv.Overlay(layers), title, xlabel, ylabel, False, False, True, (0.0, 0.06))


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
