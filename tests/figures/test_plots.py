"""Tests of fretwear.figures.plots: which backends' options a figure gets, what its legends name."""

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


@pytest.mark.parametrize("backend", ["bokeh", "matplotlib"])
def test_every_line_of_a_map_has_a_legend_entry_on_a_grey_background(backend):
    """Defect: the wear map's white (method) and red dashed (exact) contours and the regime map's marker
    line had no legend entry, while the text referred to them."""
    for name in ("matplotlib", "bokeh"):
        figures.load_backend(name)
    hv = figures.holoviews()
    f, cycles = np.linspace(0.3, 1.3, 11), np.r_[0, np.logspace(1, 5, 12)]
    z = np.clip(np.outer(f, np.log10(cycles + 1)) / 6, 0, 1)
    wear = figures.wear_map_figure(f, cycles, z, reference=1.1 * z, label="w/u0 (stepping)")
    regimes = figures.map_figure(f, np.linspace(0, 2, 5), np.random.default_rng(0).random((5, 11)),
                                 xlabel="f", ylabel="r", zlabel="slip", levels=(0.5,), hline=1.0,
                                 curves={"stick boundary": (f, f)})  # fmt: skip
    expected = [["w/u0 (stepping)", "exact (same levels)"], ["slip = 0.5", "stick boundary", "r = 1"]]
    for fig, names in zip((wear, regimes), expected, strict=True):
        plot = hv.renderer(backend).get_plot(fig).state
        if backend == "bokeh":
            legend = next(x for x in plot.right + plot.center if getattr(x, "items", None))
            labels = [item.label.value for item in legend.items]
            assert legend.background_fill_color == figures.plots.LEGEND_GREY
        else:
            legend = plot.axes[0].get_legend()
            labels = [t.get_text() for t in legend.get_texts()]
            assert legend.get_frame().get_facecolor()[:3] == pytest.approx((176 / 255,) * 3)
        assert labels == names
    # without a reference, the empty layer has no entry
    alone = hv.renderer(backend).get_plot(figures.wear_map_figure(f, cycles, z)).state
    if backend == "bokeh":
        items = [i for x in alone.right + alone.center for i in getattr(x, "items", [])]
        assert [i.label.value for i in items] == ["w / u₀ = 0.1, 0.5, 0.9"]


def test_the_wear_maps_hover_shows_n_not_only_its_logarithm():
    """Defect: hover on the wear map showed log10 N, the axis's coordinate, instead of N."""
    for name in ("matplotlib", "bokeh"):
        figures.load_backend(name)
    hv = figures.holoviews()
    f, cycles = np.linspace(0.3, 1.3, 5), np.r_[0, np.logspace(1, 5, 7)]
    image = figures.wear_map_figure(f, cycles, np.zeros((5, 8))).get(0)
    n = image.dimension_values("hover0", flat=False)
    np.testing.assert_allclose(n[:, 0], cycles[1:], rtol=1e-12)  # a row per cycle count, N itself
    plot = hv.renderer("bokeh").get_plot(figures.wear_map_figure(f, cycles, np.zeros((5, 8)))).state
    assert ("N (cycles)", "@{hover0}") in next(t for t in plot.tools if hasattr(t, "tooltips")).tooltips


def test_log_axes_label_one_two_and_five_times_each_decade():
    """Defect: a log axis over data within one decade (lives of 2000-5000 cycles) had no label there."""
    for name in ("matplotlib", "bokeh"):
        figures.load_backend(name)
    hv = figures.holoviews()
    x = np.linspace(2000, 4500, 20)
    fig = figures.line_figure({"a": (x, x), "b": (x, 2 * x)}, xlabel="N", ylabel="y", logx=True)
    plot = hv.renderer("bokeh").get_plot(fig).state
    assert list(plot.xaxis[0].ticker.mantissas) == [1, 2, 5]
    assert type(plot.yaxis[0].ticker).__name__ != "LogTicker"  # a linear axis keeps its own


@pytest.mark.parametrize("backend", ["bokeh", "matplotlib"])
def test_the_slip_shading_has_a_legend_entry(backend):
    """Defect: the text referred to the slip shading of the signals, which had no legend entry."""
    for name in ("matplotlib", "bokeh"):
        figures.load_backend(name)
    hv = figures.holoviews()
    t = np.linspace(0, 1, 50)
    fig = figures.signals_figure(t, {"x1": np.sin(2 * np.pi * t)}, spans=[(0.1, 0.3)], xlabel="t", ylabel="x")
    plot = hv.renderer(backend).get_plot(fig).state
    if backend == "bokeh":
        labels = [i.label.value for x in plot.right + plot.center for i in getattr(x, "items", [])]
    else:
        labels = [t.get_text() for t in plot.axes[0].get_legend().get_texts()]
    assert labels == ["x1", "contact slips (shaded)"]
