"""The dashboard's live panes: a figure redrawn as a ``hv.DynamicMap``, a list of messages, a run's status."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import holoviews as hv
import panel as pn
import param

from fretwear import figures

__all__ = ["live_pane", "message_list", "run_status"]


def live_pane(draw: Callable[..., Any], streams: list) -> pn.pane.HoloViews:
    """A Bokeh pane of ``hv.DynamicMap(draw, streams=streams)``, full width.

    ``draw`` builds its figure with the Bokeh options only (``figures.styling_for``):
    the server also loads Matplotlib for the exports, whose options would double
    the cost of every redraw. An export builds its figure again, for its backend.
    """

    def bokeh_only(**values: Any) -> Any:
        with figures.styling_for("bokeh"):
            return draw(**values)

    dmap = hv.DynamicMap(bokeh_only, streams=streams)
    return pn.pane.HoloViews(dmap, backend="bokeh", sizing_mode="stretch_width", linked_axes=False)


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
    bar = pn.indicators.Progress(
        value=0, max=100, sizing_mode="stretch_width", visible=False, bar_color="info"
    )
    text = pn.pane.Markdown("", margin=(0, 10))
    alerts = {"error": "danger", **({"notice": "info"} if "notice" in runner.param else {})}
    panes = {
        n: pn.pane.Alert("", alert_type=a, visible=False, sizing_mode="stretch_width")
        for n, a in alerts.items()
    }

    def update(*_events: Any) -> None:
        bar.visible = runner.busy
        bar.value = runner.progress
        text.object = f"{runner.status} ({runner.progress} %)" if runner.busy else ""
        for name, pane in panes.items():
            pane.object, pane.visible = getattr(runner, name), bool(getattr(runner, name))

    runner.param.watch(update, ["busy", "progress", "status", *alerts])
    update()
    return pn.Column(
        *panes.values(), pn.Row(bar, text, sizing_mode="stretch_width"), sizing_mode="stretch_width"
    )
