"""Layout of an exported Matplotlib figure, and the check that nothing in it overlaps.

HoloViews draws a figure for a screen: its colour bars are axes placed by hand
beside the map (outside any layout engine), its legends hang past the right of
the axes, its titles are as long as they come. :func:`lay_out` hands such a
figure to Matplotlib's constrained layout: colour bars attached to their axes
(``fig.colorbar(..., ax=...)``), legends beside or below the axes as part of
them, titles wrapped to the width of their column, tick labels thinned where
they would touch, labels in the axes kept apart, and the caption under it all
(the layout's ``rect`` stops above it).

:func:`layout_faults` lists what still overlaps or is cut by the figure's edge,
from Matplotlib's own extents (``get_window_extent``); the tests run it on every
exported figure at the three :data:`fretwear.figures.export.SIZES`.
"""

from __future__ import annotations

import re
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    from matplotlib.axes import Axes
    from matplotlib.backend_bases import RendererBase
    from matplotlib.figure import Figure
    from matplotlib.text import Text
    from matplotlib.transforms import Bbox

__all__ = ["lay_out", "layout_faults", "set_fonts", "wrap_text"]

#: smallest font the layout shrinks labels in the axes to (pt)
MIN_LABEL_SIZE = 5.0
#: room between the caption and what is above it, and around the figure (in)
CAPTION_GAP, PAD = 0.08, 0.04


#: widths (px) of the pieces :func:`wrap_text` measured, by piece, size, dpi and fonts
_WIDTHS: dict[tuple, float] = {}


def wrap_text(figure: Figure, text: str, size: float, room: float, split: str = r"(?<=[,;]) ") -> str:
    """``text`` in lines at most ``room`` pixels wide at font ``size`` (pt), broken after ``split``.

    Each piece is measured once: Matplotlib's own wrapping measures every
    growing line, each a new mathtext parse (about 1.4 s per exported figure).
    A piece wider than ``room`` stays whole on its own line.
    """
    import matplotlib

    renderer = figure.canvas.get_renderer()
    probe = figure.text(0, 0, "", fontsize=size)
    fonts = (size, figure.dpi, *(str(matplotlib.rcParams[k]) for k in ("font.family", "mathtext.fontset")))

    def width(piece: str) -> float:
        key = (piece, *fonts)
        if key not in _WIDTHS:  # the same captions come again and again (a figure set, the dashboard)
            probe.set_text(piece)
            _WIDTHS[key] = probe.get_window_extent(renderer).width
        return _WIDTHS[key]

    space = width("a a") - width("aa")
    lines: list[list[str]] = [[]]
    used = 0.0
    for piece in re.split(split, text):
        w = width(piece)
        if lines[-1] and used + space + w > room:
            lines.append([])
            used = 0.0
        used += (space if lines[-1] else 0.0) + w
        lines[-1].append(piece)
    probe.remove()
    return "\n".join(" ".join(line) for line in lines)


def _panels(figure: Figure) -> list[Axes]:
    """The axes of the figure's grid (not its colour bars)."""
    return [ax for ax in figure.axes if ax.get_subplotspec() is not None and ax.get_visible()]


def _redraw_colorbar(figure: Figure, bars: list, parents: list[Axes]) -> None:
    """``bars`` (colour bars of one mappable's scale) replaced by one ``fig.colorbar(..., ax=parents)``,
    part of the layout, with the first one's label, ticks, tick format and font sizes."""
    first = bars[0]
    label = first.ax.yaxis.label
    text, size = label.get_text(), label.get_fontsize()
    ticks = first.ax.yaxis.get_ticklabels()
    tick_size = ticks[0].get_fontsize() if ticks else None
    locator, formatter, extend, mappable = first.locator, first.formatter, first.extend, first.mappable
    for bar in bars:
        bar.remove()
    new = figure.colorbar(
        mappable, ax=parents if len(parents) > 1 else parents[0], extend=extend, pad=0.02,
        fraction=0.06 / len(parents), aspect=25,
    )  # fmt: skip
    new.locator, new.formatter = locator, formatter
    new.set_label(text, fontsize=size)
    if tick_size:
        new.ax.tick_params(labelsize=tick_size)


def _attach_colorbars(figure: Figure) -> None:
    """Colour bars placed by hand (``fig.add_axes``) drawn again with ``fig.colorbar(..., ax=parent)``."""
    for cax in list(figure.axes):
        bar = getattr(cax, "_colorbar", None)
        parent = getattr(bar, "mappable", None) and bar.mappable.axes
        if bar is not None and parent is not None and not hasattr(cax, "_colorbar_info"):
            _redraw_colorbar(figure, [bar], [parent])


def _share_decorations(figure: Figure) -> None:
    """An axis label repeated on the panels of a grid kept on one of them (y along a row: the leftmost;
    x along a column: the bottom one; along the other direction: the middle one), and the colour bars
    of a row of panels with the same label, range and map drawn once, beside the row."""
    panels = _panels(figure)
    if len(panels) < 2:
        return
    spec = {ax: ax.get_subplotspec() for ax in panels}
    # (axis, the grid lines along which the label repeats, which panel keeps it)
    rules = (
        ("y", "rowspan", lambda axes: min(axes, key=lambda a: spec[a].colspan.start)),
        ("x", "colspan", lambda axes: max(axes, key=lambda a: spec[a].rowspan.stop)),
        ("x", "rowspan", lambda axes: sorted(axes, key=lambda a: spec[a].colspan.start)[len(axes) // 2]),
        ("y", "colspan", lambda axes: sorted(axes, key=lambda a: spec[a].rowspan.start)[len(axes) // 2]),
    )
    for letter, line, keeper in rules:
        groups: dict[tuple, list] = {}
        for ax in panels:
            groups.setdefault(
                (getattr(spec[ax], line).start, getattr(ax, f"get_{letter}label")()), []
            ).append(ax)
        for (_, label), axes in groups.items():
            if label and len(axes) > 1:
                keep = keeper(axes)
                for ax in axes:
                    if ax is not keep:
                        getattr(ax, f"set_{letter}label")("")
    rows: dict[tuple, list] = {}
    for cax in figure.axes:
        bar = getattr(cax, "_colorbar", None)
        if bar is None or bar.mappable.axes not in spec:
            continue
        key = (spec[bar.mappable.axes].rowspan.start, cax.get_ylabel(), tuple(bar.mappable.get_clim()),
               bar.mappable.get_cmap().name)  # fmt: skip
        rows.setdefault(key, []).append(bar)
    for bars in rows.values():
        if len(bars) > 1:
            _redraw_colorbar(figure, bars, [bar.mappable.axes for bar in bars])


def _fit_texts(figure: Figure, renderer: RendererBase) -> bool:
    """Titles and x labels wrapped to the width of their axes, y labels to its height (the layout
    leaves them out of the axes' extent along the axes); whether any changed."""
    changed = False
    for ax in _panels(figure):
        area = ax.get_window_extent(renderer)
        for text, room in (
            (ax.title, area.width),
            (ax.xaxis.label, area.width),
            (ax.yaxis.label, area.height),
        ):
            whole = getattr(text, "_fretwear_whole", None) or " ".join(text.get_text().split())
            text._fretwear_whole = whole
            if not whole:
                continue
            probe = text.get_text()
            text.set_text(whole)
            wide = text.get_window_extent(renderer)
            along = wide.height if text is ax.yaxis.label else wide.width
            new = whole
            if along > room:
                new = wrap_text(
                    figure, whole, text.get_fontsize(), max(room, 1.0), split=r"(?<=[,:;]) | (?=\()| "
                )
            text.set_text(new)
            changed |= new != probe
    return changed


def _clear_titles(figure: Figure, renderer: RendererBase) -> bool:
    """Titles raised above the tick labels they touch (a tall top label of a log axis); whether any
    moved."""
    changed = False
    for ax in _panels(figure):
        title = ax.title
        if not title.get_text():
            continue
        box = title.get_window_extent(renderer)
        ticks = [t.get_window_extent(renderer) for t in _drawn_ticks(ax.yaxis)]
        rise = max((t.y1 - box.y0 + 2 for t in ticks if _touch(t, box)), default=0.0)
        if rise > 0:
            pad = getattr(title, "_fretwear_pad", 6.0) + rise * 72 / figure.dpi
            title._fretwear_pad = pad
            ax._set_title_offset_trans(pad)
            changed = True
    return changed


def set_fonts(figure: Figure, size: float) -> None:
    """Font sizes of ``figure``'s texts from that of the axis labels, ``size`` (pt): titles 1.2 times,
    tick labels and legends 0.9 times (as :meth:`fretwear.figures.ExportOptions.fonts`), labels in the
    axes (e.g. the sketch's values) scaled from Matplotlib's 10 pt to ``size``."""
    for ax in figure.axes:
        for text in ax.texts:
            text.set_fontsize(text.get_fontsize() * size / 10.0)
        for title in (ax.title, ax._left_title, ax._right_title):
            title.set_fontsize(1.2 * size)
        for axis in (ax.xaxis, ax.yaxis):
            axis.label.set_fontsize(size)
            axis.offsetText.set_fontsize(0.9 * size)
        ax.tick_params(which="both", labelsize=0.9 * size)
        legend = ax.get_legend()
        if legend is not None:
            for text in legend.get_texts():
                text.set_fontsize(0.9 * size)
            legend.get_title().set_fontsize(0.9 * size)


def _outside(box: Bbox, area: Bbox) -> bool:
    return box.x0 >= area.x1 - 1 or box.x1 <= area.x0 + 1 or box.y0 >= area.y1 - 1 or box.y1 <= area.y0 + 1


def _place_legends(figure: Figure, renderer: RendererBase) -> list:
    """Legends that hang outside their axes put beside them, as part of the axes for the layout; the
    same legend on several axes once. Those too wide for the side (every column of the grid narrows by
    their width) and those of a map with a colour bar become figure legends, returned for the footer."""
    barred = {bar.mappable.axes for ax in figure.axes if (bar := getattr(ax, "_colorbar", None)) is not None}
    cols = max((ax.get_subplotspec().get_gridspec().ncols for ax in _panels(figure)), default=1)
    taken: dict[tuple[str, ...], tuple] = {}
    for ax in _panels(figure):
        old = ax.get_legend()
        if old is None or not old.get_visible():
            continue
        if not _outside(old.get_window_extent(renderer), ax.get_window_extent(renderer)):
            continue  # a legend inside its axes (HoloViews' "inner" positions) stays
        labels = tuple(t.get_text() for t in old.get_texts())
        size = old.get_texts()[0].get_fontsize() if labels else None
        where = taken.setdefault(labels, (list(old.legend_handles), size, []))
        where[2].append(ax)
        old.remove()
    footer = []
    for labels, (handles, size, owners) in taken.items():
        ax = min(owners, key=lambda a: (a.get_subplotspec().rowspan.start, -a.get_subplotspec().colspan.stop))
        common = {"fontsize": size, "borderaxespad": 0.0, "frameon": False}
        legend = ax.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0), **common)
        if ax not in barred and cols * legend.get_window_extent(renderer).width <= 0.3 * figure.bbox.width:
            continue
        legend.remove()
        for ncols in range(len(labels), 0, -1):  # as few rows as fit the width
            legend = figure.legend(handles, labels, loc="lower center", ncols=ncols, **common)
            if ncols == 1 or legend.get_window_extent(renderer).width <= 0.95 * figure.bbox.width:
                break
            legend.remove()
        legend.set_in_layout(False)
        footer.append(legend)
    return footer


def _drawn_ticks(axis) -> list[Text]:
    return [
        label
        for tick in axis._update_ticks()
        for label in (tick.label1, tick.label2)
        if label.get_visible() and label.get_text()
    ]


def _touch(a: Bbox, b: Bbox, gap: float = 0.0) -> bool:
    return min(a.x1, b.x1) - max(a.x0, b.x0) > -gap and min(a.y1, b.y1) - max(a.y0, b.y0) > -gap


def _thin_ticks(figure: Figure, renderer: RendererBase) -> bool:
    """Fewer ticks on an axis whose tick labels touch; whether any changed."""
    from matplotlib.ticker import LogLocator, MaxNLocator, NullFormatter

    changed = False
    for ax in figure.axes:
        for axis in (ax.xaxis, ax.yaxis):
            if not axis.get_visible():
                continue
            labels = _drawn_ticks(axis)
            boxes = sorted((t.get_window_extent(renderer) for t in labels), key=lambda b: (b.x0, b.y0))
            if not any(_touch(a, b, 2.0) for i, a in enumerate(boxes) for b in boxes[i + 1 :]):
                continue
            changed = True
            if len(labels) <= 2:  # as few as can be: smaller labels
                axis.set_tick_params(which="both", labelsize=0.9 * labels[0].get_fontsize())
            elif not isinstance(axis.get_minor_formatter(), NullFormatter) and any(
                t.get_text() for t in (tick.label1 for tick in axis.get_minor_ticks())
            ):
                axis.set_minor_formatter(NullFormatter())  # the labels between decades go first
            elif axis.get_scale() == "log":
                axis.set_major_locator(LogLocator(numticks=max(2, len(labels) // 2 + 1)))
            else:
                axis.set_major_locator(MaxNLocator(nbins=max(1, len(labels) // 2), steps=[1, 2, 2.5, 5, 10]))
        # the first x and y tick labels meet at the corner (a tall label of a log axis): the x ones lower
        xs = [t.get_window_extent(renderer) for t in _drawn_ticks(ax.xaxis)] if ax.xaxis.get_visible() else []
        ys = [t.get_window_extent(renderer) for t in _drawn_ticks(ax.yaxis)] if ax.yaxis.get_visible() else []
        drop = max((min(x.y1, y.y1) - max(x.y0, y.y0) for x in xs for y in ys if _touch(x, y)), default=0.0)
        if drop > 0:
            pad = ax.xaxis.get_major_ticks()[0].get_pad() + drop * 72 / figure.dpi + 1
            ax.xaxis.set_tick_params(which="both", pad=pad)
            changed = True
    return changed


def _move_apart(figure: Figure, texts: list[Text], area: Bbox, renderer: RendererBase) -> None:
    """Each of ``texts``, bottom to top, moved into ``area`` and up past those below it that it touches."""
    from matplotlib.transforms import offset_copy

    placed: list[Bbox] = []
    scale = 72 / figure.dpi
    for t in texts:
        if not hasattr(t, "_fretwear_base"):
            t._fretwear_base = t.get_transform()
        t.set_transform(t._fretwear_base)
    for t in sorted(texts, key=lambda t: t.get_window_extent(renderer).y0):
        box = t.get_window_extent(renderer)
        dx = max(0.0, area.x0 - box.x0) - max(0.0, box.x1 - area.x1)
        dy = max(0.0, area.y0 - box.y0) - max(0.0, box.y1 - area.y1)
        for other in sorted(placed, key=lambda b: b.y0):
            moved = box.translated(dx, dy)
            if _touch(moved, other):
                dy += other.y1 - moved.y0 + 1
        t.set_transform(offset_copy(t._fretwear_base, figure, x=dx * scale, y=dy * scale, units="points"))
        placed.append(t.get_window_extent(renderer))


def _separate_labels(figure: Figure, renderer: RendererBase) -> bool:
    """Labels drawn in an axes (``hv.Labels``) moved apart and into the axes where they touch or leave
    it, and made smaller (to ``MIN_LABEL_SIZE``) while that is not enough; whether any changed."""
    changed = False
    for ax in figure.axes:
        texts = [t for t in ax.texts if t.get_visible() and t.get_text().strip()]
        area = ax.get_window_extent(renderer)

        def faults(texts: list[Text] = texts, area: Bbox = area) -> bool:
            boxes = [t.get_window_extent(renderer) for t in texts]
            crossed = any(_touch(a, b) for i, a in enumerate(boxes) for b in boxes[i + 1 :])
            return crossed or any(not _inside(b, area) for b in boxes)

        if not texts or not faults():
            continue
        changed = True
        while True:  # moved apart; then, while they still touch, smaller and moved again
            _move_apart(figure, texts, area, renderer)
            if not faults() or min(t.get_fontsize() for t in texts) <= MIN_LABEL_SIZE:
                break
            for t in texts:
                t.set_fontsize(max(MIN_LABEL_SIZE, 0.9 * t.get_fontsize()))
    return changed


def _inside(box: Bbox, area: Bbox, tol: float = 0.5) -> bool:
    return (
        box.x0 >= area.x0 - tol
        and box.x1 <= area.x1 + tol
        and box.y0 >= area.y0 - tol
        and box.y1 <= area.y1 + tol
    )


def lay_out(
    figure: Figure, caption: str = "", caption_size: float = 7.5, fontsize: float | None = None
) -> None:
    """Lay out ``figure`` (drawn by HoloViews, on an Agg canvas) for a file, ``caption`` under it.

    Matplotlib's constrained layout places the axes, their colour bars,
    legends and labels; the caption (``caption_size`` pt, wrapped to the
    figure's width) sits under the layout's ``rect``. Tick labels that would
    touch are thinned and labels in the axes shrunk (to ``MIN_LABEL_SIZE``)
    and moved apart, each followed by a new layout.
    """
    from matplotlib.layout_engine import ConstrainedLayoutEngine

    renderer = figure.canvas.get_renderer()
    if fontsize is not None:
        set_fonts(figure, fontsize)
    engine = ConstrainedLayoutEngine(h_pad=PAD, w_pad=PAD)
    figure.set_layout_engine(engine)  # first: colour bars made then are the layout's (not gridspec cells)
    _attach_colorbars(figure)
    for ax in _panels(figure):
        ax.set_in_layout(True)  # HoloViews positions them by hand, which takes them out of a layout
        grid = ax.get_subplotspec().get_gridspec()
        if getattr(grid, "figure", None) is None:  # HoloViews' layouts make their grid without the figure
            grid.figure = figure
        grid.wspace = grid.hspace = None  # HoloViews' spacing (a fraction of the axes), the layout's instead
    # the footer, under the layout's rect: the caption, and above it the legends too wide for a side
    bottom = 0.0  # its height (in)
    if caption:
        room = figure.bbox.width - 2 * PAD * figure.dpi
        text = figure.text(PAD / figure.get_figwidth(), PAD / figure.get_figheight(), "",
                           fontsize=caption_size, va="bottom", ha="left")  # fmt: skip
        text.set_in_layout(False)
        for narrower in (1.0, 0.97, 0.94, 0.9):  # the pieces measured apart can add up narrower than joined
            text.set_text(wrap_text(figure, caption, caption_size, narrower * room))
            if text.get_window_extent(renderer).width <= room:
                break
        bottom = text.get_window_extent(renderer).height / figure.dpi + PAD + CAPTION_GAP
    _share_decorations(figure)
    for legend in _place_legends(figure, renderer):
        legend.set_bbox_to_anchor(
            (0.5, max(bottom, PAD) / figure.get_figheight()), transform=figure.transFigure
        )
        bottom = max(bottom, PAD) + legend.get_window_extent(renderer).height / figure.dpi + CAPTION_GAP
    bottom = min(0.6, bottom / figure.get_figheight())
    engine.set(rect=(0.0, bottom, 1.0, 1.0 - bottom))
    for _ in range(8):
        engine.execute(figure)
        changed = _fit_texts(figure, renderer) | _thin_ticks(figure, renderer)
        changed |= _separate_labels(figure, renderer) | _clear_titles(figure, renderer)
        if not changed:
            break
    # laid out: later draws (each file format, the check) keep these positions
    figure.set_layout_engine("none")


def _text_boxes(figure: Figure, renderer: RendererBase):
    """(name, owner axes or None, box, in the axes) of every text drawn, and (name, axes, box) of the
    plotting area of each axes."""
    texts, areas = [], []
    for i, ax in enumerate(figure.axes):
        if not ax.get_visible():
            continue
        name = f"axes {i}" + (" (colour bar)" if hasattr(ax, "_colorbar") else "")
        areas.append((name, ax, ax.get_window_extent(renderer)))
        own = [(f"{name} title", t) for t in (ax.title, ax._left_title, ax._right_title)]
        for letter, axis in (("x", ax.xaxis), ("y", ax.yaxis)):
            if axis.get_visible():
                own += [(f"{name} {letter} label", axis.label), (f"{name} {letter} offset", axis.offsetText)]
                own += [(f"{name} {letter} tick {t.get_text()!r}", t) for t in _drawn_ticks(axis)]
        texts += [(n, ax, t.get_window_extent(renderer), False) for n, t in own
                  if t.get_visible() and t.get_text().strip()]  # fmt: skip
        texts += [(f"{name} label {t.get_text()!r}", ax, t.get_window_extent(renderer), True)
                  for t in ax.texts if t.get_visible() and t.get_text().strip()]  # fmt: skip
        legend = ax.get_legend()
        if legend is not None and legend.get_visible():
            texts.append((f"{name} legend", ax, legend.get_window_extent(renderer), None))
    texts += [(f"figure text {t.get_text()[:30]!r}", None, t.get_window_extent(renderer), False)
              for t in figure.texts if t.get_visible() and t.get_text().strip()]  # fmt: skip
    texts += [("figure legend", None, leg.get_window_extent(renderer), False) for leg in figure.legends]
    return texts, areas


def layout_faults(figure: Figure, tol: float = 0.5) -> list[str]:
    """What overlaps in ``figure`` as drawn, one line each (none: the layout is clean).

    Text boxes (titles, axis and tick labels, colour bar labels, legends,
    labels in the axes, the caption) must lie inside the figure and not overlap
    one another by more than ``tol`` pixels; those outside the axes (titles,
    axis and tick labels, the caption) must not overlap the plotting area of any
    axes; labels in an axes stay inside it; a legend may lie in its own axes
    only. Extents are Matplotlib's own (``get_window_extent``) after a draw.
    """
    figure.draw_without_rendering()
    renderer = figure.canvas.get_renderer()
    texts, areas = _text_boxes(figure, renderer)
    edge = figure.bbox
    out = []
    for name, _, box, _ in texts:
        if not _inside(box, edge, tol):
            out.append(f"{name} is cut by the figure's edge")
    for i, (name, _, box, _) in enumerate(texts):
        for other, _, obox, _ in texts[i + 1 :]:
            if (
                min(box.x1, obox.x1) - max(box.x0, obox.x0) > tol
                and min(box.y1, obox.y1) - max(box.y0, obox.y0) > tol
            ):
                out.append(f"{name} overlaps {other}")
    for name, owner, box, inner in texts:
        for area_name, ax, area in areas:
            if inner is True and ax is owner:
                if not _inside(box, area, tol):
                    out.append(f"{name} leaves its axes")
            elif (inner is False or ax is not owner) and _touch(box, area, -tol):
                out.append(f"{name} overlaps the plotting area of {area_name}")
    return out
