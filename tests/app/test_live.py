"""Tests of app.live without a browser: how the page's view sizes a figure."""

import numpy as np

from app.live import BELOW_HEIGHT, FIGURE_HEIGHT, NARROW_TEXT, PRESENTATION_FONTSCALE, View
from fretwear import figures
from fretwear.figures.sketch import model_sketch
from fretwear.model import paper_model


def bokeh_options(fig) -> dict:
    return figures.holoviews().Store.lookup_options("bokeh", fig, "plot").kwargs


def test_narrow_figures_put_legends_below_and_grow_only_when_they_have_one():
    figures.load_backend("bokeh")
    hv = figures.holoviews()
    x = np.linspace(0.3, 1.3, 5)
    curves = figures.line_figure({"a": (x, x), "b": (x, 2 * x)}, xlabel="f (Hz)", ylabel="x (m)")
    view = View(width=390)
    assert view.narrow and not View(width=1920).narrow and not View().narrow  # 0: not known yet
    styled = view.styled(curves, False, True)
    assert bokeh_options(styled)["legend_position"] == "bottom"
    assert bokeh_options(styled)["height"] == FIGURE_HEIGHT + BELOW_HEIGHT
    # the model sketch has no legend: its height stays, its values are drawn smaller
    sketch = view.styled(model_sketch(paper_model()), False, True)
    assert bokeh_options(sketch)["height"] == FIGURE_HEIGHT
    labels = next(layer for layer in sketch if isinstance(layer, hv.Labels))
    style = figures.holoviews().Store.lookup_options("bokeh", labels, "style").kwargs
    assert style["text_font_size"] == NARROW_TEXT
    # presentation mode: larger fonts; a wide window leaves the figure as drawn
    assert bokeh_options(view.styled(curves, True, False))["fontscale"] == PRESENTATION_FONTSCALE
    assert view.styled(curves, False, False) is curves
