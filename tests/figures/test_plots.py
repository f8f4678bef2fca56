"""Tests of fretwear.figures.plots: which backends' options a figure gets."""

import threading

import numpy as np
import pytest

from fretwear import figures


def _options(fig, backend: str) -> dict:
    return figures.holoviews().Store.lookup_options(backend, fig, "plot").kwargs


def _figure():
    x = np.linspace(0.3, 1.3, 5)
    return figures.line_figure({"a": (x, x), "b": (x, 2 * x)}, xlabel="f (Hz)", ylabel="y (m)", title="t")


def test_styling_for_sets_the_options_of_the_backends_named_only():
    figures.load_backend("matplotlib")
    figures.load_backend("bokeh")
    both = _figure()
    assert _options(both, "bokeh")["responsive"] is True
    assert _options(both, "matplotlib")["fig_inches"] == (7, 4)
    with figures.styling_for("bokeh"):
        bokeh = _figure()
        seen = {}
        other = threading.Thread(target=lambda: seen.update(fig=_figure()))  # another thread: every backend
        other.start()
        other.join()
    assert _options(bokeh, "bokeh")["responsive"] is True
    assert _options(bokeh, "matplotlib").get("fig_inches") != (7, 4)
    assert _options(seen["fig"], "matplotlib")["fig_inches"] == (7, 4)
    assert _options(_figure(), "matplotlib")["fig_inches"] == (7, 4)  # the context is over
    with pytest.raises(ValueError, match="backends must be 'bokeh' or 'matplotlib', got \\['plotly'\\]"):
        with figures.styling_for("plotly"):
            pass
