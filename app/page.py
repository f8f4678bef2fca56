"""The Panel page of one session: sidebar controls, one tab per scene, progress and figures.

Every figure is a ``hv.DynamicMap`` that redraws when its scene publishes
(``Scene.version``); the wear map's tap stream selects the point the other
figures show. Sliders act on release (``value_throttled``) and have a number
box for precise values; logarithmic quantities (``k_w``, the horizon, the
tolerance) have a slider over the exponent and a text box for the value.
"""

from __future__ import annotations

import io
import math
from collections.abc import Callable
from functools import partial
from typing import Any

import holoviews as hv
import numpy as np
import panel as pn
import param

from fretwear import figures

from .scenes import QUANTITY_LABELS, TARGETS, AccuracyScene, Scene, sidebar_equivalent
from .session import Session
from .state import CUSTOM, LADDERS, METHODS, PRESETS

__all__ = ["build_page", "document_dispatch"]

TITLE = "fretwear: vibration and fretting wear of a friction contact"
INTRO = """A 2-DOF structure with a friction contact between its masses (Salles et al., section 2.1),
solved by harmonic balance with the DLFT method; the contact wears by Archard's law on a slow time
scale, which relaxes its normal load. Values in SI units, frequencies in Hz."""


def document_dispatch(doc) -> Callable[[Callable[[], None]], None]:
    """``dispatch`` of a :class:`Session` served in Bokeh document ``doc``: run callbacks on its loop."""
    from panel.io.state import set_curdoc

    def run(callback: Callable[[], None]) -> None:
        with set_curdoc(doc):
            callback()

    def dispatch(callback: Callable[[], None]) -> None:
        if doc is None or doc.session_context is None:
            callback()
            return
        try:
            doc.add_next_tick_callback(partial(run, callback))
        except Exception:  # noqa: BLE001 - the session was closed: nothing to update
            pass

    return dispatch


def _link(widget, obj: param.Parameterized, name: str, event: str = "value_throttled") -> None:
    """Two-way link of ``widget`` (its ``event``: on release for sliders) and ``obj.name``."""
    widget.param.watch(lambda e: setattr(obj, name, e.new), event)
    obj.param.watch(lambda e: setattr(widget, "value", e.new), name)


class LogInput(pn.Column):
    """A slider over ``log10(value)`` and a text box for the value, linked to a number parameter."""

    def __init__(self, obj: param.Parameterized, name: str, label: str, start: float, end: float) -> None:
        value = getattr(obj, name)
        self._slider = pn.widgets.FloatSlider(
            label=label,
            start=start,
            end=end,
            step=0.1,
            value=float(np.clip(math.log10(value), start, end)),
            format="0.0",
            sizing_mode="stretch_width",
        )
        self._text = pn.widgets.TextInput(value=f"{value:.3g}", sizing_mode="stretch_width")
        super().__init__(self._slider, self._text, sizing_mode="stretch_width", margin=0)
        self._slider.param.watch(lambda e: setattr(obj, name, float(f"{10**e.new:.3g}")), "value_throttled")

        def typed(e):
            if e.new == f"{getattr(obj, name):.3g}":  # the value shown, not an edit
                return
            try:
                number = float(e.new)
            except ValueError:
                number = math.nan
            setattr(obj, name, number)

        self._text.param.watch(typed, "value")

        def pull(e):
            if isinstance(e.new, (int, float)) and math.isfinite(e.new) and e.new > 0:
                self._slider.value = float(np.clip(math.log10(e.new), start, end))
                self._text.value = f"{e.new:.3g}"

        obj.param.watch(pull, name)


class BandInput(pn.Column):
    """The frequency band: a range slider and two number boxes that keep what was typed.

    Panel's ``EditableRangeSlider`` replaces a typed lower bound above the
    upper one by the upper one (and the reverse): the message would then name
    values the user did not type. Here each box sets its own control, and an
    inverted band is reported by :meth:`Controls.problems`.
    """

    def __init__(self, controls: param.Parameterized, start: float, end: float) -> None:
        self._slider = pn.widgets.RangeSlider(
            label="Frequency band (Hz)",
            start=start,
            end=end,
            step=0.01,
            value=(controls.fmin, controls.fmax),
            sizing_mode="stretch_width",
        )
        self._low, self._high = (
            pn.widgets.FloatInput(label=label, value=value, step=0.01, sizing_mode="stretch_width")
            for label, value in (("f min (Hz)", controls.fmin), ("f max (Hz)", controls.fmax))
        )
        super().__init__(
            self._slider,
            pn.Row(self._low, self._high, sizing_mode="stretch_width"),
            sizing_mode="stretch_width",
            margin=0,
        )
        self._slider.param.watch(
            lambda e: controls.param.update(fmin=e.new[0], fmax=e.new[1]), "value_throttled"
        )
        self._low.param.watch(lambda e: setattr(controls, "fmin", e.new), "value")
        self._high.param.watch(lambda e: setattr(controls, "fmax", e.new), "value")

        def pull(*_events):
            low, high = controls.fmin, controls.fmax
            self._low.value, self._high.value = low, high
            # an invalid band stays in the boxes, with its message; the slider keeps the last valid one
            if all(isinstance(v, (int, float)) and math.isfinite(v) for v in (low, high)) and low < high:
                self._slider.param.update(
                    start=min(self._slider.start, low), end=max(self._slider.end, high), value=(low, high)
                )

        controls.param.watch(pull, ["fmin", "fmax"])


def _sidebar(session: Session) -> list:
    c = session.controls
    preset = pn.widgets.Select(label="Preset", options=[CUSTOM, *PRESETS], value=c.preset)
    preset.param.watch(lambda e: c.apply_preset(e.new), "value")
    c.param.watch(lambda e: setattr(preset, "value", e.new), "preset")

    def slider(kind, name, label, start, end, step=None):
        w = kind(
            label=label,
            start=start,
            end=end,
            value=getattr(c, name),
            sizing_mode="stretch_width",
            **({} if step is None else {"step": step}),
        )
        _link(w, c, name)
        return w

    fex = slider(pn.widgets.EditableFloatSlider, "fex", "F_ex: excitation on mass 1 (N)", 0.5, 30, 0.1)
    mu = slider(pn.widgets.EditableFloatSlider, "mu", "mu: friction coefficient", 0.05, 2, 0.01)
    harmonics = slider(pn.widgets.EditableIntSlider, "harmonics", "Nh: harmonics", 1, 41)
    degree = slider(pn.widgets.EditableIntSlider, "degree", "Degree of the polynomial method", 0, 12)
    band = BandInput(c, 0.05, 3.0)
    method = pn.widgets.RadioButtonGroup(
        label="Slow-time method", options=list(METHODS), value=c.method, color="primary", variant="outline"
    )
    _link(method, c, "method", event="value")
    normal = slider(pn.widgets.EditableFloatSlider, "normal_load", "F_N: initial normal load (N)", 1, 50, 0.5)
    n_f = slider(pn.widgets.EditableIntSlider, "n_frequencies", "Frequencies of the maps", 5, 201)
    n_n = slider(pn.widgets.EditableIntSlider, "n_cycles", "Cycle counts of the wear map", 10, 200)
    advanced = pn.Card(
        normal,
        LogInput(c, "tol", "log10 tolerance (fraction of u0)", -4, -1),
        n_f,
        n_n,
        title="More settings",
        collapsed=True,
        sizing_mode="stretch_width",
    )
    f_sel = pn.widgets.FloatInput(
        label="f (Hz)", value=session.frequency, step=0.01, sizing_mode="stretch_width"
    )
    n_sel = pn.widgets.FloatInput(
        label="N (cycles)", value=session.cycles, step=1000, sizing_mode="stretch_width"
    )
    _link(f_sel, session, "frequency", event="value")
    _link(n_sel, session, "cycles", event="value")
    return [
        preset,
        fex,
        mu,
        LogInput(c, "kw", "log10 k_w: Archard coefficient (1/Pa)", -14, -6),
        LogInput(c, "horizon", "log10 cycle horizon", 2, 8),
        band,
        harmonics,
        pn.pane.Markdown("Slow-time method", margin=(0, 10)),
        method,
        degree,
        advanced,
        pn.pane.Markdown("**Selected point** (click the wear map)", margin=(10, 10, 0, 10)),
        pn.Row(f_sel, n_sel),
    ]


def _draw(
    scene: Scene, name: str, version: int, x: float | None = None, y: float | None = None
) -> hv.Overlay:
    """Figure ``name`` of ``scene``; ``x``, ``y`` (the wear map's tap stream) act through the session."""
    return scene.figure(name)


def _figure_pane(scene: Scene, name: str, session: Session) -> pn.pane.HoloViews:
    streams = [hv.streams.Params(scene, ["version"])]
    if (scene.key, name) == ("wearmap", "wear_map"):
        # a stream of the DynamicMap itself: a Tap with ``source=`` does not link to a plot of overlays
        tap = hv.streams.Tap(x=None, y=None)
        tap.add_subscriber(lambda x, y: session.select(x, y))
        streams.append(tap)
    dmap = hv.DynamicMap(partial(_draw, scene, name), streams=streams)
    return pn.pane.HoloViews(dmap, backend="bokeh", sizing_mode="stretch_width", linked_axes=False)


def _download(scene: Scene, what: pn.widgets.Select, fmt: str) -> io.BytesIO:
    """File of the selected figure or dataset; a note in the file when it cannot be made."""
    try:
        if fmt == "csv":
            return io.BytesIO(scene.export_csv(what.value).encode())
        return io.BytesIO(scene.export_figure(what.value, fmt))
    except ValueError as exc:
        return io.BytesIO(f"not available: {exc}\n".encode())


def _export_card(scene: Scene) -> pn.Card:
    figure = pn.widgets.Select(label="Figure", options=list(scene.figure_names), width=220)
    dataset = pn.widgets.Select(label="Dataset", options=list(scene.dataset_names), width=220)
    buttons: list[tuple[pn.widgets.FileDownload, pn.widgets.Select, str]] = []
    for select, fmt in [(figure, f) for f in figures.FIGURE_FORMATS] + [(dataset, "csv")]:
        button = pn.widgets.FileDownload(
            label=fmt.upper(),
            callback=partial(_download, scene, select, fmt),
            filename=scene.filename(select.value, fmt),
            color="primary",
            variant="outline",
            width=80,
            align="end",
        )
        buttons.append((button, select, fmt))

    def rename(*_events):
        for button, select, fmt in buttons:
            button.filename = scene.filename(select.value, fmt)

    figure.param.watch(rename, "value")
    dataset.param.watch(rename, "value")
    by_format = {fmt: b for b, _, fmt in buttons}
    return pn.Card(
        pn.Row(figure, *(by_format[f] for f in figures.FIGURE_FORMATS)),
        pn.Row(dataset, by_format["csv"]),
        title="Export (PNG and SVG via Matplotlib, standalone HTML, CSV)",
        collapsed=False,
        sizing_mode="stretch_width",
    )


def _accuracy_controls(scene: AccuracyScene, session: Session) -> pn.Column:
    """The accuracy scene's own controls, its recommendation and the button that applies it."""
    quantity = pn.widgets.Select(
        label="Error on", options={v: k for k, v in QUANTITY_LABELS.items()}, value=scene.quantity, width=250
    )
    _link(quantity, scene, "quantity", event="value")
    target = pn.widgets.DiscreteSlider(
        label="Target error", options={f"{t:g}": t for t in TARGETS}, value=scene.target, width=300
    )
    _link(target, scene, "target")
    ladder = pn.widgets.RadioButtonGroup(
        label="Ladder", options=list(LADDERS), value=scene.ladder, variant="outline", align="end"
    )
    _link(ladder, scene, "ladder", event="value")
    wear = pn.widgets.Checkbox(label="wear rungs: w(N) (several seconds)", value=scene.wear, align="end")
    _link(wear, scene, "wear", event="value")
    advice = pn.pane.Markdown("", sizing_mode="stretch_width")
    apply = pn.widgets.Button(label="Apply", color="primary", disabled=True, min_width=120, align="center")

    def show(*_events):
        advice.object = scene.advice()
        rung = scene.applicable()
        apply.disabled = rung is None
        apply.label = "Apply" if rung is None else f"Apply: {sidebar_equivalent(rung)[1]}"

    def click(_event):
        rung = scene.applicable()
        if rung is not None:
            session.apply(sidebar_equivalent(rung)[0])

    scene.param.watch(show, "version")
    apply.on_click(click)
    show()
    return pn.Column(
        pn.Row(quantity, target, pn.pane.Markdown("Ladder", align="end"), ladder, wear),
        pn.Row(advice, apply, sizing_mode="stretch_width"),
        sizing_mode="stretch_width",
    )


def _scene_tab(scene: Scene, session: Session) -> pn.Column:
    panes = [_figure_pane(scene, name, session) for name in scene.figure_names]
    grid = pn.GridBox(*panes, ncols=min(2, len(panes)), sizing_mode="stretch_width")
    notes = pn.pane.Alert("", alert_type="warning", visible=False, sizing_mode="stretch_width")

    def show_notes(*_events):
        notes.object = "\n".join(f"- {n}" for n in scene.notes)
        notes.visible = bool(scene.notes)

    scene.param.watch(show_notes, "notes")
    show_notes()
    explanation = pn.pane.Markdown(scene.explanation.strip(), sizing_mode="stretch_width")
    controls = [_accuracy_controls(scene, session)] if isinstance(scene, AccuracyScene) else []
    return pn.Column(
        explanation,
        *controls,
        grid,
        notes,
        _export_card(scene),
        name=scene.title,
        sizing_mode="stretch_width",
    )


def _status(session: Session) -> pn.Column:
    bar = pn.indicators.Progress(
        value=0, max=100, sizing_mode="stretch_width", visible=False, bar_color="info"
    )
    text = pn.pane.Markdown("", margin=(0, 10))
    error = pn.pane.Alert("", alert_type="danger", visible=False, sizing_mode="stretch_width")

    def update(*_events: Any) -> None:
        bar.visible = session.busy
        bar.value = session.progress
        text.object = f"{session.status} ({session.progress} %)" if session.busy else ""
        error.object, error.visible = session.error, bool(session.error)

    session.param.watch(update, ["busy", "progress", "status", "error"])
    update()
    return pn.Column(error, pn.Row(bar, text, sizing_mode="stretch_width"), sizing_mode="stretch_width")


def build_page(session: Session) -> pn.template.BootstrapTemplate:
    """The page of ``session``: sidebar, status line and one tab per scene."""
    figures.load_backend("bokeh")
    keys = list(session.scenes)
    tabs = pn.Tabs(
        *(_scene_tab(session.scenes[k], session) for k in keys),
        dynamic=True,
        active=keys.index(session.scene),
        sizing_mode="stretch_width",
    )
    tabs.param.watch(lambda e: setattr(session, "scene", keys[e.new]), "active")
    return pn.template.BootstrapTemplate(
        title=TITLE,
        # one root per area: every root costs Bokeh a pass over all the document's models
        sidebar=[pn.Column(pn.pane.Markdown(INTRO), *_sidebar(session), sizing_mode="stretch_width")],
        main=[pn.Column(_status(session), tabs, sizing_mode="stretch_width")],
        sidebar_width=360,
    )
