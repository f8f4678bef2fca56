"""The dashboard's live panes: a figure redrawn as a ``hv.DynamicMap``, a list of messages, a run's status."""

from __future__ import annotations

import weakref
from collections.abc import Callable
from typing import Any

import holoviews as hv
import panel as pn
import param
from panel.custom import JSComponent

from fretwear import figures

from .state import number_text, type_text

__all__ = [
    "View",
    "PageScript",
    "live_pane",
    "figure_grid",
    "control_row",
    "message_list",
    "run_status",
    "typed_box",
    "STALE_CSS",
]

#: width (px) a figure asks for beside another: below twice this the figures stack in one column
FIGURE_BASIS = 450
#: the narrowest a figure gets (px): a phone's width less the page's margins
MIN_WIDTH = 300
#: a text box whose value the figures do not show (not a number, or out of range): outlined red
STALE_CSS = ":host(.stale) input { border: 2px solid #d62728; background: #fff4f4; }"
#: height (px) reserved for the progress line
STATUS_HEIGHT = 30
#: a window narrower than this (px) folds the sidebar, which is SIDEBAR_WIDTH px wide
NARROW, SIDEBAR_WIDTH = 1000, 380
#: a figure narrower than this (px) gets its legend and colour bar below its axes, not beside them
NARROW_FIGURE = 600
#: the main area's margins and the gaps around the figures (px)
PAGE_MARGINS = 60
#: the element types that draw a colour bar
COLORBARS = ("Image", "QuadMesh", "HeatMap", "Raster")
#: height (px) of a live figure (as the figures module draws it), and what a narrow one adds for its
#: legend and colour bar below the axes
FIGURE_HEIGHT, BELOW_HEIGHT = 340, 170
#: size of the text labels drawn in a narrow figure (the model sketch's values)
NARROW_TEXT = "7pt"
#: presentation mode: font scale and height (px) of the live figures (a projector seen from the back)
PRESENTATION_FONTSCALE, PRESENTATION_HEIGHT = 1.6, 480


class View(param.Parameterized):
    """How one page shows its figures; one per page (:meth:`current`), shared by every tab."""

    presentation = param.Boolean(False, doc="Larger fonts and figures, for a projector")
    width = param.Integer(0, bounds=(0, None), doc="Width of the browser's window (px); 0 before it is known")
    narrow = param.Boolean(False, doc="Figures narrower than NARROW_FIGURE px: legends below them")

    _pages: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()

    @classmethod
    def current(cls) -> View:
        """The view of the page being built (``pn.state.curdoc``), or a fresh one outside a server."""
        doc = pn.state.curdoc
        if doc is None:
            return cls()
        return cls._pages.setdefault(doc, cls())

    @param.depends("width", watch=True, on_init=True)
    def _narrow(self) -> None:
        main = self.width - (SIDEBAR_WIDTH if self.width >= NARROW else 0) - PAGE_MARGINS
        columns = 2 if main >= 2 * FIGURE_BASIS else 1  # as the figure grid wraps
        self.narrow = 0 < self.width and main / columns < NARROW_FIGURE

    def styled(self, figure: Any, presentation: bool, narrow: bool) -> Any:
        """``figure`` (a Bokeh overlay or element) with the view's sizes: larger in presentation mode, its
        legend below on a narrow window (beside, it would leave the curves a few pixels)."""
        options = {}
        if presentation:
            options |= {"fontscale": PRESENTATION_FONTSCALE, "height": PRESENTATION_HEIGHT}
        if narrow and isinstance(figure, hv.Overlay):
            options |= {"legend_position": "bottom", "legend_cols": 1}
            if figure.opts.get("plot", backend="bokeh").kwargs.get("show_legend", True):
                # the legend and colour bar below take their room from the height, not from the axes
                options["height"] = (PRESENTATION_HEIGHT if presentation else FIGURE_HEIGHT) + BELOW_HEIGHT
        if not options or not isinstance(figure, (hv.Overlay, hv.Element)):
            return figure
        figure = figure.opts(backend="bokeh", **options)
        if narrow:  # colour bars below too, and smaller text on a drawing (the model sketch's values)
            figure = figure.opts(
                *(getattr(hv.opts, kind)(colorbar_position="bottom", backend="bokeh") for kind in COLORBARS),
                hv.opts.Labels(text_font_size=NARROW_TEXT, backend="bokeh"),
            )
        return figure


class PageScript(JSComponent):
    """The page's own code in the browser: reports the window's width to ``width`` (on load, and once a
    resize settles), folds the sidebar on a window narrower than ``NARROW`` px (its toggle button
    unfolds it; a window made wide again unfolds it), and makes the tab headers keyboard tabs:
    ``role="tab"`` in a ``role="tablist"``, ``aria-selected``, focusable, Enter or Space opens one, the
    arrow keys, Home and End move between them, and the focus is outlined."""

    width = param.Integer(0)
    _esm = f"""
    const OUTLINE = "3px solid #f0a202";
    // the shadow roots that hold tab headers, found once by a walk of the whole page (a walk is costly)
    let roots = [];
    function walk(root, out) {{
      if (root.querySelector(".bk-tab")) out.push(root);
      for (const el of root.querySelectorAll("*")) if (el.shadowRoot) walk(el.shadowRoot, out);
      return out;
    }}
    function tabs() {{
      let found = roots.flatMap(root => Array.from(root.querySelectorAll(".bk-tab")));
      if (!found.length) {{
        roots = walk(document, []);
        found = roots.flatMap(root => Array.from(root.querySelectorAll(".bk-tab")));
      }}
      return found;
    }}
    // Bokeh draws the tab headers again when the active tab changes: the focus follows the keyboard
    let refocus = 0;
    function label() {{
      for (const tab of tabs()) {{
        const list = tab.parentElement;
        const all = Array.from(list.querySelectorAll(":scope > .bk-tab"));
        list.setAttribute("role", "tablist");
        tab.setAttribute("role", "tab");
        const active = tab.classList.contains("bk-active");
        tab.setAttribute("aria-selected", active ? "true" : "false");
        tab.tabIndex = active ? 0 : -1;
        if (active && Date.now() - refocus < 5000 && tab.getRootNode().activeElement !== tab) tab.focus();
        if (tab.dataset.keys) continue;
        tab.dataset.keys = "1";
        tab.addEventListener("focus", () => {{ tab.style.outline = OUTLINE; }});
        tab.addEventListener("blur", () => {{ tab.style.outline = ""; }});
        tab.addEventListener("keydown", (event) => {{
          const i = all.indexOf(tab), last = all.length - 1;
          const to = {{ArrowRight: i + 1, ArrowDown: i + 1, ArrowLeft: i - 1, ArrowUp: i - 1, Home: 0,
                      End: last}}[event.key];
          if (event.key === "Enter" || event.key === " ") {{
            tab.click();
          }} else if (to !== undefined) {{
            const next = all[(to + all.length) % all.length];
            next.click();
            next.focus();
          }} else {{
            return;
          }}
          event.preventDefault();
          refocus = Date.now();
          for (const ms of [50, 250, 600, 1200, 2500, 4000]) setTimeout(label, ms);
        }});
      }}
    }}
    function fold(folded) {{
      const side = document.getElementById("sidebar");
      const button = document.getElementById("sidebar-toggle");
      if (side) side.classList.toggle("show", !folded);
      if (button) button.setAttribute("aria-expanded", folded ? "false" : "true");
    }}
    export function render({{ model }}) {{
      model.width = window.innerWidth;
      if (window.innerWidth < {NARROW}) fold(true);
      let timer = null, narrow = window.innerWidth < {NARROW};
      window.addEventListener("resize", () => {{
        clearTimeout(timer);
        timer = setTimeout(() => {{
          model.width = window.innerWidth;
          // the sidebar folds when the window becomes narrow, and unfolds when it becomes wide again
          if ((window.innerWidth < {NARROW}) !== narrow) {{ narrow = !narrow; fold(narrow); }}
        }}, 300);
      }});
      // the tabs appear as the page renders: label them then, and again after a click may have drawn them
      // anew (no timer polls the page: a walk of every shadow root costs the browser)
      for (const ms of [300, 1000, 2500, 6000]) setTimeout(label, ms);
      document.addEventListener("click", () => setTimeout(label, 50), true);
      return document.createElement("span");
    }}
    """


def live_pane(draw: Callable[..., Any], streams: list) -> pn.pane.HoloViews:
    """A Bokeh pane of ``hv.DynamicMap(draw, streams=streams)``, sized by the page's :class:`View`.

    ``draw`` builds its figure with the Bokeh options only (``figures.styling_for``):
    the server also loads Matplotlib for the exports, whose options would double
    the cost of every redraw. An export builds its figure again, for its backend.
    """
    view = View.current()

    def bokeh_only(**values: Any) -> Any:
        with figures.styling_for("bokeh"):
            return view.styled(draw(**values), view.presentation, view.narrow)

    pane = pn.pane.HoloViews(
        hv.DynamicMap(bokeh_only, streams=streams),
        backend="bokeh",
        sizing_mode="stretch_width",
        linked_axes=False,
        min_width=MIN_WIDTH,
        styles={"flex": f"1 1 {FIGURE_BASIS}px"},
    )

    def resized(*_events: Any) -> None:
        # a new plot, not an update: Bokeh places colour bars and sizes a plot when it makes it
        pane.object = hv.DynamicMap(bokeh_only, streams=streams)

    view.param.watch(resized, ["presentation", "narrow"])
    return pane


def figure_grid(panes: list) -> pn.FlexBox:
    """Figures side by side while each gets ``FIGURE_BASIS`` px, in one column on a narrower window."""
    return pn.FlexBox(*panes, flex_wrap="wrap", sizing_mode="stretch_width")


def control_row(*widgets: Any) -> pn.FlexBox:
    """Controls in a row that wraps on a narrow window rather than clipping its last ones."""
    return pn.FlexBox(*widgets, flex_wrap="wrap", align_items="flex-end", sizing_mode="stretch_width")


def typed_box(obj: param.Parameterized, name: str, label: str, width: int = 120) -> pn.widgets.TextInput:
    """A text box for number ``name`` of ``obj`` (a tab with a ``typed`` parameter), both ways: what is
    typed goes through :func:`app.state.type_text` (a text that is not a number is kept, outlined red,
    and named by the tab's message with the valid range), and the box follows the value (e.g. the
    defaults of a newly chosen model)."""
    box = pn.widgets.TextInput(
        name=label,
        value=number_text(getattr(obj, name)),
        width=width,
        placeholder=name,
        stylesheets=[STALE_CSS],
    )
    box.param.watch(lambda event: type_text(obj, name, event.new), "value")

    def pull(*_events: Any) -> None:
        typed = name in obj.typed
        if not typed:
            box.value = number_text(getattr(obj, name))
        box.css_classes = ["stale"] if typed else []

    obj.param.watch(pull, [name, "typed"])
    return box


def message_list(obj: param.Parameterized, name: str, alert_type: str = "warning") -> pn.pane.Alert:
    """An alert listing the messages of ``obj.<name>`` (a list of texts), one bullet each, hidden while
    there are none; it follows the list."""
    alert = pn.pane.Alert("", alert_type=alert_type, visible=False, sizing_mode="stretch_width")

    def show(*_events: Any) -> None:
        messages = getattr(obj, name)
        alert.object = "\n".join(f"- {m}" for m in messages)
        alert.visible = bool(messages)

    obj.param.watch(show, name)
    show()
    return alert


def run_status(runner: param.Parameterized) -> pn.Column:
    """The error, notice (when ``runner`` has one), progress bar and progress line of a
    :class:`~app.session.Runner`, following it."""
    # the line keeps its place when idle: nothing below it moves when a computation starts
    bar = pn.indicators.Progress(value=0, max=100, sizing_mode="stretch_width", bar_color="info")
    text = pn.pane.Markdown("", margin=(0, 10))
    alerts = {"error": "danger", **({"notice": "info"} if "notice" in runner.param else {})}
    panes = {
        n: pn.pane.Alert("", alert_type=a, visible=False, sizing_mode="stretch_width")
        for n, a in alerts.items()
    }

    def update(*_events: Any) -> None:
        bar.styles = {"visibility": "visible" if runner.busy else "hidden"}
        bar.value = runner.progress
        text.object = f"{runner.status} ({runner.progress} %)" if runner.busy else ""
        for name, pane in panes.items():
            pane.object, pane.visible = getattr(runner, name), bool(getattr(runner, name))

    runner.param.watch(update, ["busy", "progress", "status", *alerts])
    update()
    return pn.Column(
        *panes.values(),
        pn.Row(bar, text, height=STATUS_HEIGHT, sizing_mode="stretch_width"),
        sizing_mode="stretch_width",
    )
