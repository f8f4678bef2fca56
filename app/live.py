"""The dashboard's live plots: a figure builder redrawn as a ``hv.DynamicMap`` with Bokeh."""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import holoviews as hv
import panel as pn

from fretwear import figures


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
