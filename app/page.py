"""The Panel page of one session: sidebar controls, one tab per scene, progress, figures and exports.

Every figure is a ``hv.DynamicMap`` that redraws when its scene publishes
(``Scene.version``); the wear map's tap stream selects the point the other
figures show, and the cycle scene's player moves an instant through the
period (``CycleScene.frame``). Each control is a label with its symbol and
a glossary note, a slider that acts on release, and a text box for the exact
value (what is typed is kept and, when it is not a valid value, reported
with the valid range). Only the visible tab is built: the others are built
when first shown.

The view lives in the page's address (``?fex=14&mu=0.8&...&scene=wearmap``,
keyed like the CLI options), can be copied as a link, and saved to and
loaded from a settings file that ``fretwear COMMAND --settings FILE`` reads too.
"""

from __future__ import annotations

import io
import logging
import math
import threading
import zipfile
from collections.abc import Callable
from functools import partial
from typing import Any
from urllib.parse import urlencode

import holoviews as hv
import numpy as np
import panel as pn
import param

from fretwear import figures
from fretwear.figures.record import parse_settings, settings_json

from .animation import Player, browser_frames
from .glossary import glossary_markdown, help_mark, term
from .live import (
    SIDEBAR_WIDTH,
    STALE_CSS,
    PageScript,
    View,
    control_row,
    figure_grid,
    live_pane,
    message_list,
    run_status,
)
from .scenes import ANIMATION_FRAMES, QUANTITY_LABELS, TARGETS, AccuracyScene, CycleScene, Scene
from .session import Session
from .state import CUSTOM, LADDERS, METHODS, NUMBERS, PRESETS, number_text, parse_number

__all__ = ["apply_tab_address", "build_page", "bundle", "document_dispatch", "ExportSettings", "NumberInput"]

log = logging.getLogger(__name__)

#: the page's own CSS (the template's, outside the components): a title that wraps on a narrow window,
#: larger text in presentation mode
PAGE_CSS = """
@media (max-width: 1100px) { #header .title { font-size: 1.05rem; white-space: normal; } }
body.presentation { font-size: 125%; }
"""
#: presentation mode on the page's side: full screen (where the browser allows it), sidebar folded
PRESENTATION_JS = """
const on = cb_obj.active;
document.body.classList.toggle("presentation", on);
const side = document.getElementById("sidebar");
if (side) side.classList.toggle("show", !on);
try {
  if (on && !document.fullscreenElement) document.documentElement.requestFullscreen().catch(() => {});
  if (!on && document.fullscreenElement) document.exitFullscreen().catch(() => {});
} catch (e) {}
"""
#: the formats of each figure in the zip of every export
BUNDLE_FORMATS = ("png", "svg", "pdf")

TITLE = "fretwear: vibration and fretting wear of a friction contact"
INTRO = f"""A 2-DOF structure with a friction contact between its masses (Salles et al., section 2.1),
solved by harmonic balance with the {term("DLFT")} method; the contact wears by Archard's law on a slow
time scale, which relaxes its normal load. SI units, frequencies in Hz. Hover a ? mark or a dotted term
for its meaning; all terms are in the *Glossary* tab."""
#: copies the page's address (which holds the view) to the clipboard, or selects it for Ctrl+C
COPY_JS = """
const url = window.location.href;
const done = (text) => { button.label = text; setTimeout(() => { button.label = "Copy link"; }, 2500); };
if (navigator.clipboard && window.isSecureContext) {
  navigator.clipboard.writeText(url).then(
    () => done("Copied"), () => done("Copy failed: use the address bar"));
} else {
  const area = document.createElement("textarea");
  area.value = url;
  document.body.appendChild(area);
  area.select();
  done(document.execCommand("copy") ? "Copied" : "Copy failed: use the address bar");
  area.remove();
}
"""


def document_dispatch(doc) -> Callable[[Callable[[], None]], None]:
    """``dispatch`` of a :class:`Session` served in Bokeh document ``doc``: run callbacks on its loop.

    Callbacks that arrive before the page has loaded in the browser (a run
    started with the session) wait for it (``pn.state.onload``): an update made
    while the page is being sent could be lost, leaving the figures on the
    results they were first drawn with.
    """
    from panel.io.state import set_curdoc

    served = doc is not None and doc.session_context is not None
    lock = threading.Lock()
    waiting: list[Callable[[], None]] | None = [] if served else None

    def run(callback: Callable[[], None]) -> None:
        with set_curdoc(doc):
            callback()

    def loaded() -> None:
        nonlocal waiting
        with lock:
            queued, waiting = waiting or [], None
        for callback in queued:
            run(callback)

    if served:
        pn.state.onload(loaded)

    def dispatch(callback: Callable[[], None]) -> None:
        if not served or doc.session_context is None:
            callback()
            return
        with lock:
            if waiting is not None:
                waiting.append(callback)
                return
        try:
            doc.add_next_tick_callback(partial(run, callback))
        except Exception:  # noqa: BLE001 - the session was closed: nothing to update
            pass

    return dispatch


def _label(html: str, glossary: str | None, margin=(6, 10, 0, 10)) -> pn.pane.HTML:
    """A control's label: its name with symbols, and the glossary note of ``glossary``."""
    return pn.pane.HTML(f"{html}{'' if glossary is None else help_mark(glossary)}", margin=margin)


class NumberInput(pn.Column):
    """Label, slider (on release) and text box of one number of ``obj`` (a control or the selection).

    ``typer(name, text)`` takes the box's text (``Controls.type_text``); the
    box shows the value with 12 significant digits at most, or what was typed
    while it is not a number. With ``log``, the slider runs over ``log10``. A
    value that is not a number, or not ``valid``, is *stale*: the figures keep
    the last valid one, so the slider stays there and the box is outlined red.
    """

    def __init__(
        self,
        obj: param.Parameterized,
        name: str,
        label: str,
        glossary: str | None,
        start: float,
        end: float,
        step: float,
        typer: Callable[[str, str], None],
        typed: Callable[[], dict[str, str]],
        *,
        integer: bool = False,
        log: bool = False,
        slider: bool = True,
        placeholder: str | None = None,
        valid: Callable[[Any], bool] = lambda _value: True,
    ) -> None:
        self._obj, self._name, self._log, self._typed, self._valid = obj, name, log, typed, valid
        self._start, self._end = start, end
        value = getattr(obj, name)
        self._integer = integer and not log
        kind = pn.widgets.IntSlider if self._integer else pn.widgets.FloatSlider
        position = self._position(value)
        self._slider = kind(
            start=start,
            end=end,
            step=step,
            value=start if position is None else position,
            show_value=False,
            sizing_mode="stretch_width",
            margin=(4, 10),
            visible=slider,
        )
        self._box = pn.widgets.TextInput(
            value=number_text(value), width=110 if slider else None, margin=(0, 10, 4, 0),
            sizing_mode=None if slider else "stretch_width", placeholder=placeholder or name,
            stylesheets=[STALE_CSS],
        )  # fmt: skip
        super().__init__(
            _label(label, glossary),
            pn.Row(self._slider, self._box, sizing_mode="stretch_width", margin=0),
            sizing_mode="stretch_width",
            margin=0,
        )

        def released(event):
            value = float(f"{10**event.new:.3g}") if log else event.new
            setattr(obj, name, value if not integer else int(value))

        self._slider.param.watch(released, "value_throttled")
        self._box.param.watch(lambda e: typer(name, e.new), "value")
        obj.param.watch(self._pull, name)
        if hasattr(obj, "typed"):
            obj.param.watch(self._pull, "typed")

    def _position(self, value: Any) -> float | None:
        """Slider position of ``value`` (``None`` when it has none)."""
        if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
            return None
        if self._log:
            if value <= 0:
                return None
            value = math.log10(value)
        value = float(np.clip(value, self._start, self._end))
        return round(value) if self._integer else value

    def _pull(self, *_events) -> None:
        value = getattr(self._obj, self._name)
        typed = self._name in self._typed()
        if not typed:
            self._box.value = number_text(value)
        stale = typed or not self._valid(value)
        self._box.css_classes = ["stale"] if stale else []
        position = self._position(value)
        if position is not None and not stale:
            self._slider.value = position


class BandInput(pn.Column):
    """The frequency band: a range slider and two text boxes that keep what was typed.

    Each box sets its own control (``Controls.type_text``), and an inverted
    band is reported by :meth:`Controls.problems`; the slider keeps the last
    valid band.
    """

    def __init__(self, controls) -> None:
        low, high = NUMBERS["fmin"], NUMBERS["fmax"]
        start, end, step = low.slider
        self._slider = pn.widgets.RangeSlider(
            start=start, end=max(end, high.slider[1]), step=step, value=(controls.fmin, controls.fmax),
            show_value=False, sizing_mode="stretch_width", margin=(4, 10),
        )  # fmt: skip
        self._low, self._high = (
            pn.widgets.TextInput(
                value=number_text(getattr(controls, n)), width=110, margin=(0, 10, 4, 0), placeholder=n
            )  # fmt: skip
            for n in ("fmin", "fmax")
        )
        super().__init__(
            _label(f"Frequency band {low.html} to {high.html} ({low.unit})", None),
            pn.Row(self._slider, sizing_mode="stretch_width", margin=0),
            pn.Row(
                pn.pane.HTML("from", margin=(8, 4, 0, 10)),
                self._low,
                pn.pane.HTML("to", margin=(8, 4, 0, 0)),
                self._high,
                margin=0,
            ),  # fmt: skip
            sizing_mode="stretch_width",
            margin=0,
        )
        self._slider.param.watch(
            lambda e: controls.param.update(fmin=float(f"{e.new[0]:.6g}"), fmax=float(f"{e.new[1]:.6g}")),
            "value_throttled",
        )
        self._low.param.watch(lambda e: controls.type_text("fmin", e.new), "value")
        self._high.param.watch(lambda e: controls.type_text("fmax", e.new), "value")

        def pull(*_events):
            low, high = controls.fmin, controls.fmax
            for box, name, value in ((self._low, "fmin", low), (self._high, "fmax", high)):
                if name not in controls.typed:
                    box.value = number_text(value)
            if all(isinstance(v, (int, float)) and math.isfinite(v) for v in (low, high)) and low < high:
                self._slider.param.update(
                    start=min(self._slider.start, low), end=max(self._slider.end, high), value=(low, high)
                )

        controls.param.watch(pull, ["fmin", "fmax", "typed"])


def _lazy_card(title: str, build: Callable[[], list], collapsed: bool = True) -> pn.Card:
    """A card whose content ``build()`` is made when it is first expanded (a lighter first page)."""
    card = pn.Card(title=title, collapsed=collapsed, sizing_mode="stretch_width")

    def fill(*_events):
        if not card.collapsed and not card.objects:
            card.objects = build()

    card.param.watch(fill, "collapsed")
    fill()
    return card


class ExportSettings(param.Parameterized):
    """Size, resolution and font size of the exported figures, as typed (checked by :meth:`options`)."""

    width = param.Parameter("7", doc="Width (in)")
    height = param.Parameter("4", doc="Height (in)")
    dpi = param.Parameter("150", doc="Resolution of PNG files (dots per inch)")
    fontsize = param.Parameter("10", doc="Font size of the axis labels (pt)")

    def options(self, fmt: str = "png") -> figures.ExportOptions:
        """The :class:`~fretwear.figures.ExportOptions` typed for format ``fmt`` (``ValueError`` naming the
        bad one); the resolution applies to PNG only, and is neither read nor checked for the others."""
        values = {}
        for name in ("width", "height", "dpi", "fontsize"):
            if name == "dpi" and fmt != "png":
                continue
            text = str(getattr(self, name))
            number = parse_number(text)
            if number is None:
                low, high, unit = figures.ExportOptions.RANGES[name]
                unit = f" {unit}" if unit else ""
                raise ValueError(f"{name} must be a number in [{low:g}, {high:g}]{unit}, got {text!r}")
            values[name] = int(number) if name == "dpi" and float(number).is_integer() else number
        return figures.ExportOptions(**values)


class SafeDownload(pn.widgets.FileDownload):
    """A download whose file is made on click by ``make()``; a failure goes to ``failed(message)``,
    never to the server log as a traceback, and nothing downloads."""

    def __init__(self, make: Callable[[], bytes], failed: Callable[[str], None], **params: Any) -> None:
        self._make, self._failed = make, failed
        super().__init__(**params)

    @param.depends("_clicks", watch=True)
    def _transfer(self):
        try:
            data = self._make()
        except Exception as exc:  # noqa: BLE001 - every export failure reaches the page as a message
            log.warning("export failed: %s", exc, exc_info=not isinstance(exc, ValueError))
            self._failed(f"{self.filename}: {' '.join(str(exc).split())}")
            return
        self._failed("")
        self._sync_data(io.BytesIO(data))


def _sidebar(session: Session) -> list:
    c = session.controls
    preset = pn.widgets.Select(options=[CUSTOM, *PRESETS], value=c.preset, sizing_mode="stretch_width",
                               margin=(0, 10))  # fmt: skip
    lesson = pn.pane.Markdown("", sizing_mode="stretch_width", margin=(0, 10))
    # lesson mode: the preset's guided tour, one step at a time (buttons: keyboard-operable)
    back, do, forward = (
        pn.widgets.Button(name=name, button_type="primary", button_style="outline", width=width,
                          description=description)
        for name, width, description in (("◀ Back", 80, "The tour's previous step"),
                                         ("Do it", 80, "Apply this step's change"),
                                         ("Next ▶", 80, "The tour's next step"))
    )  # fmt: skip
    steps = pn.Row(back, do, forward, margin=(0, 5))

    def chosen(event):
        if event.new != c.preset:
            session.apply_preset(event.new)

    def show_preset(*_events):
        preset.value = c.preset

    def show_step(*_events):
        tour = session.tour()
        steps.visible = len(tour) > 1
        if not tour:
            lesson.object = ""
            return
        step = tour[session.step]
        where = f"Step {session.step + 1} of {len(tour)}" if len(tour) > 1 else "What to look at"
        lesson.object = f"*{where}* ({session.lesson}): {step.text}"
        back.disabled, forward.disabled = session.step == 0, session.step == len(tour) - 1
        do.disabled = not step.change

    preset.param.watch(chosen, "value")
    c.param.watch(show_preset, "preset")
    session.param.watch(show_step, ["lesson", "step"])
    back.on_click(lambda _event: session.move(-1))
    forward.on_click(lambda _event: session.move(1))
    do.on_click(lambda _event: session.do_step())  # every step's change is valid (tests/app/test_state.py)
    show_step()

    def number(name):
        """The control ``name`` as the parameter table declares it: label, glossary note and slider."""
        p = NUMBERS[name]
        label = p.html + (", slider over log<sub>10</sub>" if p.log else "")
        return NumberInput(c, name, label, p.glossary, *p.slider, c.type_text, lambda: c.typed,
                           integer=p.integer, log=p.log, valid=p.valid)  # fmt: skip

    def selected(name, label, glossary):
        return NumberInput(session, name, label, glossary, 0, 1, 1, session.type_text,
                           lambda: session.typed, slider=False)  # fmt: skip

    method = pn.widgets.RadioButtonGroup(
        options=list(METHODS), value=c.method, color="primary", variant="outline",
        sizing_mode="stretch_width", margin=(4, 10),
    )  # fmt: skip
    method.param.watch(lambda e: setattr(c, "method", e.new), "value")
    c.param.watch(lambda e: setattr(method, "value", e.new), "method")
    dynamics = pn.widgets.RadioButtonGroup(
        options={"exact (shooting)": "shooting", "DLFT (Nₕ)": "dlft"}, value=c.dynamics, color="primary",
        variant="outline", sizing_mode="stretch_width", margin=(4, 10),
    )  # fmt: skip
    dynamics.param.watch(lambda e: setattr(c, "dynamics", e.new), "value")
    c.param.watch(lambda e: setattr(dynamics, "value", e.new), "dynamics")
    advanced = _lazy_card(
        "More settings",
        lambda: [number(name) for name in ("normal_load", "tol", "n_frequencies", "n_cycles")],
    )
    return [
        _label("<b>Preset</b>: one lesson each, a guided tour", None),
        preset,
        lesson,
        steps,
        number("fex"),
        number("mu"),
        number("kw"),
        number("horizon"),
        BandInput(c),
        number("harmonics"),
        _label("Slow-time method", "method"),
        method,
        _label("Dynamics of the exact and stepping methods", "dynamics"),
        dynamics,
        number("degree"),
        advanced,
        _label("<b>Selected point</b> (click the wear map)", None, margin=(12, 10, 0, 10)),
        pn.Row(selected("frequency", "f (Hz)", None), selected("cycles", "N (cycles)", "N"), margin=0),
        _share_card(session),
    ]


def _share_card(session: Session) -> pn.Card:
    """Copy link, save and load the settings (built when first expanded)."""
    return _lazy_card("Link and settings", partial(_share_widgets, session))


def _share_widgets(session: Session) -> list:
    copy = pn.widgets.Button(label="Copy link", color="primary", variant="outline",
                             description="Copy the page's address: it reproduces this view")  # fmt: skip
    copy.js_on_click(args={"button": copy}, code=COPY_JS)
    message = pn.pane.Alert("", alert_type="danger", visible=False, sizing_mode="stretch_width")

    def failed(text: str) -> None:
        message.object, message.visible = text, bool(text)

    save = SafeDownload(
        lambda: settings_json(session.record()).encode(),
        failed,
        filename="fretwear_settings.json",
        label="Save settings",
        color="primary",
        variant="outline",
    )
    load = pn.widgets.FileInput(accept=".json", multiple=False, sizing_mode="stretch_width")

    def loaded(event):
        if not event.new:
            return
        name = load.filename or "settings"
        try:
            text = event.new.decode("utf-8", errors="replace")
            record = parse_settings(text, f"settings file {name!r}", ranges=True)
        except ValueError as exc:
            failed(str(exc))
            return
        problems = session.apply_record(record, source=f"settings file {name!r}")
        failed("; ".join(problems))

    load.param.watch(loaded, "value")
    return [
        pn.Row(copy, save, margin=0),
        _label("Load settings (a file saved here; the CLI reads it with --settings FILE)", None),
        load,
        message,
    ]


def _draw(scene: Scene, name: str, version: int, **_streams: Any) -> hv.Overlay:
    """Figure ``name`` of ``scene``; other stream values (the tap, the frame) act through the scene."""
    return scene.figure(name, live=True)


def _figure_pane(scene: Scene, name: str, session: Session) -> pn.pane.HoloViews:
    streams: list = [hv.streams.Params(scene, ["version"])]
    if (scene.key, name) == ("wearmap", "wear_map"):
        # a stream of the DynamicMap itself: a Tap with ``source=`` does not link to a plot of overlays
        tap = hv.streams.Tap(x=None, y=None)
        tap.add_subscriber(lambda x, y: session.select(x, y))
        streams.append(tap)
    if isinstance(scene, CycleScene):
        streams = [hv.streams.Params(scene, ["version", "frame"])]  # the animation redraws them
    return live_pane(partial(_draw, scene, name), streams)


def _export_card(
    scene: Scene, settings: ExportSettings, view: Callable[[], dict[str, Any]] | None = None
) -> pn.Card:
    """Downloads of the scene's figures and datasets, with the export options (built when expanded)."""
    return _lazy_card(
        "Export: figures as PNG, SVG, PDF (Matplotlib) or HTML, data as CSV, each with its parameters",
        partial(_export_widgets, scene, settings, view),
    )


def bundle(
    scene: Any, options: Callable[[str], figures.ExportOptions], view: Callable[[], dict] | None = None
) -> bytes:
    """Every figure (PNG, SVG, PDF) and data set (CSV) of ``scene`` in one zip, with the settings file of
    the page's ``view()`` (``settings.json``, which ``fretwear COMMAND --settings`` and the sidebar read)
    or, for a tab with settings of its own, its parameters (``parameters.txt``); what could not be
    exported yet (not computed) is listed in ``missing.txt``. ``options(fmt)``: the export options of
    each format.
    ``ValueError`` when nothing could be exported."""
    buffer, missing, done = io.BytesIO(), [], 0
    with zipfile.ZipFile(buffer, "w", zipfile.ZIP_DEFLATED) as archive:
        items = [(n, f) for n in scene.figure_names for f in BUNDLE_FORMATS]
        items += [(n, "csv") for n in scene.dataset_names]
        for name, fmt in items:
            try:
                data = (
                    scene.export_csv(name).encode()
                    if fmt == "csv"
                    else scene.export_figure(name, fmt, options(fmt))
                )
            except ValueError as exc:  # not computed yet, or nothing to draw: listed, not fatal
                missing.append(f"{scene.filename(name, fmt)}: {' '.join(str(exc).split())}")
                continue
            archive.writestr(scene.filename(name, fmt), data)
            done += 1
        if not done:
            raise ValueError(f"nothing to export yet: {missing[0] if missing else 'no figure or data set'}")
        if view is not None:
            archive.writestr("settings.json", settings_json(view()))
        else:
            archive.writestr("parameters.txt", scene.csv_header())
        if missing:
            archive.writestr("missing.txt", "\n".join(missing) + "\n")
    return buffer.getvalue()


def _export_widgets(scene: Scene, settings: ExportSettings, view: Callable[[], dict] | None) -> list:
    figure = pn.widgets.Select(label="Figure", options=list(scene.figure_names), width=200)
    dataset = pn.widgets.Select(label="Dataset", options=list(scene.dataset_names), width=200)
    message = pn.pane.Alert("", alert_type="danger", visible=False, sizing_mode="stretch_width")

    def failed(text: str) -> None:
        message.object = f"Export failed: {text}" if text else ""
        message.visible = bool(text)

    def make(select: pn.widgets.Select, fmt: str) -> bytes:
        if fmt == "csv":
            return scene.export_csv(select.value).encode()
        return scene.export_figure(select.value, fmt, settings.options(fmt))

    buttons = {}
    for select, fmt in [(figure, f) for f in figures.EXPORT_FORMATS] + [(dataset, "csv")]:
        buttons[fmt] = SafeDownload(
            partial(make, select, fmt),
            failed,
            label=fmt.upper(),
            filename=scene.filename(select.value, fmt),
            color="primary",
            variant="outline",
            width=70,
            align="end",
        )

    def rename(*_events):
        for fmt, button in buttons.items():
            button.filename = scene.filename((dataset if fmt == "csv" else figure).value, fmt)

    everything = SafeDownload(
        lambda: bundle(scene, settings.options, view),
        failed,
        label="Download all (zip)",
        filename=f"fretwear_{scene.key}.zip",
        color="primary",
        width=170,
        align="end",
    )
    figure.param.watch(rename, "value")
    dataset.param.watch(rename, "value")
    boxes = []
    for name, label in (("width", "width (in)"), ("height", "height (in)"), ("dpi", "dpi (PNG)"),
                        ("fontsize", "font size (pt)")):  # fmt: skip
        box = pn.widgets.TextInput(
            label=label, value=str(getattr(settings, name)), width=95, placeholder=name
        )
        box.param.watch(lambda e, n=name: setattr(settings, n, e.new), "value")
        settings.param.watch(lambda e, b=box: setattr(b, "value", str(e.new)), name)
        boxes.append(box)
    return [
        control_row(figure, *(buttons[f] for f in figures.EXPORT_FORMATS), *boxes),
        control_row(dataset, buttons["csv"], everything),
        message,
    ]


def _accuracy_controls(scene: AccuracyScene, session: Session) -> pn.Column:
    """The accuracy scene's own controls, its recommendation and the button that applies it."""
    quantity = pn.widgets.Select(
        label="Error on", options={v: k for k, v in QUANTITY_LABELS.items()}, value=scene.quantity, width=250
    )
    quantity.param.watch(lambda e: setattr(scene, "quantity", e.new), "value")
    scene.param.watch(lambda e: setattr(quantity, "value", e.new), "quantity")
    target = pn.widgets.DiscreteSlider(
        label="Target error", options={f"{t:g}": t for t in TARGETS}, value=scene.target, width=300
    )
    target.param.watch(lambda e: setattr(scene, "target", e.new), "value_throttled")
    scene.param.watch(lambda e: setattr(target, "value", e.new), "target")
    ladder = pn.widgets.RadioButtonGroup(
        options=list(LADDERS), value=scene.ladder, variant="outline", align="end"
    )
    ladder.param.watch(lambda e: setattr(scene, "ladder", e.new), "value")
    scene.param.watch(lambda e: setattr(ladder, "value", e.new), "ladder")
    wear = pn.widgets.Checkbox(label="wear rungs: w(N) (several seconds)", value=scene.wear, align="end")
    wear.param.watch(lambda e: setattr(scene, "wear", e.new), "value")
    scene.param.watch(lambda e: setattr(wear, "value", e.new), "wear")
    advice = pn.pane.Markdown("", sizing_mode="stretch_width")
    apply = pn.widgets.Button(label="Apply", color="primary", disabled=True, width=100, align="center")

    def show(*_events):
        advice.object = scene.advice()
        apply.disabled = scene.applicable() is None

    def click(_event):
        from .scenes import sidebar_equivalent

        rung = scene.applicable()
        if rung is not None:
            session.apply(sidebar_equivalent(rung)[0])

    scene.param.watch(show, "version")
    apply.on_click(click)
    show()
    return pn.Column(
        # wraps on a narrow window rather than running off the card
        pn.FlexBox(
            quantity,
            target,
            pn.pane.Markdown("Ladder", align="end"),
            ladder,
            wear,
            flex_wrap="wrap",
            align_items="flex-end",
            sizing_mode="stretch_width",
        ),
        pn.Row(apply, advice, sizing_mode="stretch_width"),
        sizing_mode="stretch_width",
    )


def _cycle_controls(scene: CycleScene) -> pn.Row:
    """Play/pause of the animation of one period, its speed, the instant shown, and the summary of the
    solution.

    The browser plays the frames (:class:`app.animation.Player`): the server sends
    them once per solution and draws only the instant where the animation pauses
    or the slider stops.
    """
    play = pn.widgets.Toggle(label="Play", value=False, width=90, align="end", color="primary")
    speed = pn.widgets.FloatSlider(
        label="seconds per period", start=1.0, end=30.0, step=0.5, value=4.0, width=180, align="end"
    )
    instant = pn.widgets.IntSlider(
        label="instant of the period (frame)", start=0, end=ANIMATION_FRAMES - 1, value=scene.frame, width=260
    )
    player = Player(period=speed.value, frame=scene.frame)
    instant.param.watch(lambda e: setattr(scene, "frame", e.new), "value_throttled")
    scene.param.watch(lambda e: setattr(instant, "value", e.new), "frame")
    scene.param.watch(lambda e: setattr(player, "frame", e.new), "frame")
    player.param.watch(lambda e: setattr(scene, "frame", e.new % ANIMATION_FRAMES), "frame")
    speed.param.watch(lambda e: setattr(player, "period", e.new), "value")

    def toggled(event) -> None:
        play.label = "Pause" if event.new else "Play"
        player.playing = event.new

    play.param.watch(toggled, "value")
    summary = pn.pane.Markdown("", sizing_mode="stretch_width")

    def show(*_events):
        summary.object = scene.summary()
        player.data = browser_frames(scene.animation())

    scene.param.watch(show, "version")
    show()
    return control_row(play, speed, instant, player, summary)


def _scene_tab(scene: Scene, session: Session, export: ExportSettings) -> list:
    panes = [_figure_pane(scene, name, session) for name in scene.figure_names]
    grid = figure_grid(panes)
    notes, findings = message_list(scene, "notes"), message_list(scene, "findings", "info")
    explanation = pn.pane.Markdown(scene.explanation.strip(), sizing_mode="stretch_width")
    controls = []
    if isinstance(scene, AccuracyScene):
        controls = [_accuracy_controls(scene, session)]
    elif isinstance(scene, CycleScene):
        controls = [_cycle_controls(scene)]
    return [explanation, *controls, grid, notes, findings, _export_card(scene, export, session.record)]


def _address(session: Session, location, tabs: pn.Tabs, extra: tuple) -> None:
    """Keep the page's address query equal to the view: ``Session.query`` on the session's scenes, the
    tab's own (``tab=KEY&KEY.NAME=...``, :class:`~app.scenes.base.Addressed`) on a tab of its own."""
    if location is None:
        return
    first = len(session.scenes)

    def write(*_events):
        index = tabs.active - first
        if 0 <= index < len(extra):
            scene = extra[index][2]
            search = "?" + urlencode({"tab": scene.key, **scene.address()})
        else:
            search = "?" + session.query()
        if location.search != search:
            location.search = search

    watched = [(session, ["scene", "frequency", "cycles"]), (session.controls, list(session.controls.param))]
    watched.append((session.scenes["accuracy"], ["quantity", "target", "ladder", "wear"]))
    watched += [(scene, list(scene.address_params)) for _title, _build, scene in extra]
    for obj, names in watched:
        obj.param.watch(write, [n for n in names if n not in ("name", "typed", "preset")])
    tabs.param.watch(write, "active")


def apply_tab_address(args: dict[str, list[bytes]], scenes: list) -> tuple[dict, str | None, list[str]]:
    """Split the page's address (``pn.state.session_args``): the session's keys, returned, and a tab of
    its own (``tab=KEY``) with its ``KEY.NAME`` keys, applied to that tab's scene (of ``scenes``).

    Returns the session's part, the key of the tab to open (None: a scene of the session) and the
    problems met with the tab's part.
    """
    text = {k: (v[-1].decode() if isinstance(v[-1], bytes) else v[-1]) for k, v in args.items()}
    rest = {k: v for k, v in args.items() if k != "tab" and "." not in k}
    tab, problems = text.get("tab"), []
    by_key = {scene.key: scene for scene in scenes}
    if tab is not None and tab not in by_key:
        problems.append(f"address: tab must be one of {', '.join(by_key)}, got {tab!r}")
        tab = None
    own = {k: v for k, v in text.items() if "." in k}
    if tab is not None:
        problems += by_key[tab].apply_address({k: v for k, v in own.items() if k.startswith(f"{tab}.")})
    problems += [f"address: {k} belongs to another tab than {tab!r}" for k in own if not tab or
                 not k.startswith(f"{tab}.")]  # fmt: skip
    return rest, tab, problems


def build_page(
    session: Session, location=None, extra: tuple = (), tab: str | None = None
) -> pn.template.BootstrapTemplate:
    """The page of ``session``: sidebar, status line and one tab per scene and the glossary.

    ``location`` (``pn.state.location`` when served) receives the view as the
    address's query. ``extra``: tabs of their own state, placed before the glossary, as
    ``(title, build, scene)`` triples; ``build(export_card)`` makes the tab's content when first shown
    (``export_card(scene)``: the export card of an object with the scenes' export methods), ``scene``
    keeps its view in the address (:class:`~app.scenes.base.Addressed`). ``tab``: the key of the
    scene of an extra tab to open first (None: the session's scene).
    """
    figures.load_backend("bokeh")
    # canvas, not WebGL (HoloViews' default): the figures hold hundreds of points, and each WebGL figure
    # costs a context to make and, on a machine without a GPU, 60-150 ms to draw: the animation drew
    # 3 frames/s with it, the tabs opened slower
    hv.renderer("bokeh").webgl = False
    keys = list(session.scenes)
    export = ExportSettings()
    glossary = pn.pane.Markdown(glossary_markdown(), sizing_mode="stretch_width", name="Glossary")
    opened = next((len(keys) + i for i, e in enumerate(extra) if e[2].key == tab), keys.index(session.scene))
    tabs = pn.Tabs(
        *(pn.Column(name=session.scenes[k].title, sizing_mode="stretch_width") for k in keys),
        *(pn.Column(name=title, sizing_mode="stretch_width") for title, _build, _scene in extra),
        glossary,
        dynamic=True,
        active=opened,
        sizing_mode="stretch_width",
    )

    def fill(index: int) -> None:
        """Build the tab ``index`` when first shown."""
        if index < len(keys) and not tabs[index].objects:
            tabs[index].objects = _scene_tab(session.scenes[keys[index]], session, export)
        elif len(keys) <= index < len(keys) + len(extra) and not tabs[index].objects:
            tabs[index].objects = extra[index - len(keys)][1](partial(_export_card, settings=export))

    def shown(event):
        fill(event.new)
        if event.new < len(keys):
            session.scene = keys[event.new]

    def follow(event):
        index = keys.index(event.new)
        fill(index)
        tabs.active = index

    fill(tabs.active)
    tabs.param.watch(shown, "active")
    session.param.watch(follow, "scene")
    _address(session, location, tabs, extra)
    view = View.current()
    script = PageScript(width=view.width, height=0, width_policy="fixed", margin=0)
    script.link(view, width="width")
    template = pn.template.BootstrapTemplate(
        title=TITLE,
        # one root per area: every root costs Bokeh a pass over all the document's models
        sidebar=[pn.Column(pn.pane.Markdown(INTRO), *_sidebar(session), sizing_mode="stretch_width")],
        main=[pn.Column(run_status(session), tabs, sizing_mode="stretch_width")],
        header=[_presentation_toggle(view), script],
        sidebar_width=SIDEBAR_WIDTH,
        raw_css=[PAGE_CSS],
    )
    return template


def _presentation_toggle(view: View) -> pn.widgets.Toggle:
    """The header's presentation switch: larger figures and fonts, full screen, the sidebar folded."""
    toggle = pn.widgets.Toggle(name="Presentation", value=view.presentation, button_type="light", width=130)
    toggle.link(view, value="presentation")
    toggle.jscallback(value=PRESENTATION_JS)
    return toggle
