"""Every exported figure laid out without overlaps at the three export sizes (issue 26).

Each figure kind the CLI, the paper's set and the dashboard export (maps with a
colour bar and legend, curves with a wide legend on log axes, the hysteresis
loop, signals with shading, the model sketch, the paper's multi-panel grids, the
accuracy scene's labelled Pareto plot, the study's histogram, the interface's
state map) is drawn on small data through the export path
(:func:`fretwear.figures.matplotlib_figure`) at each of
:data:`fretwear.figures.SIZES`, and :func:`fretwear.figures.layout_faults`
measures it with Matplotlib's extents.
"""

import re
import xml.etree.ElementTree as ET

import matplotlib.pyplot as plt
import numpy as np
import pytest

from fretwear import figures, paper_model
from fretwear.figures.paper import _layout
from fretwear.figures.record import MODEL, caption

STAMP = {"fex": 10.0, "mu": 1.0, "fn": 10.0, "kw": 1e-11, "harmonics": 21, "method": "exact", "cycles": 1e5}
#: the paper set's longest model line (its lines measured piece by piece once ran past the edge)
THREE = f"{MODEL}, F_ex = 6, 10 and 14 N"
F = np.linspace(0.3, 1.3, 9)
N = np.r_[0.0, np.geomspace(10, 1e5, 7)]


def _wear(f=F, n=N):
    return np.clip(np.outer(f, np.log10(np.maximum(n, 1.0))) / 5, 0.0, 1.2)


def _frf_curves(levels=(6, 10, 14)):
    curves = {f"{a:g} N": (F, 1e-3 / (1 + (F - 0.7) ** 2 * a)) for a in levels}
    curves |= {f"stuck ({a:g} N)": (F, 1e-4 / (0.01 + (F - 1.0) ** 2)) for a in (levels[0], levels[-1])}
    curves |= {f"open ({a:g} N)": (F, 1e-4 / (0.01 + (F - 0.5) ** 2)) for a in (levels[0], levels[-1])}
    return curves


def _pareto(hv):
    """The accuracy scene's Pareto plot: points on log axes with a label each, two almost on one spot."""
    xd = hv.Dimension("x", label="wall time (s)", range=(1e-3, 10))
    yd = hv.Dimension("y", label="relative error: w(N) at the horizon", range=(1e-6, 1))
    times, errors = np.array([0.002, 0.0022, 0.01, 0.5, 2.0]), np.array([1e-2, 1.1e-2, 1e-3, 1e-4, 1e-5])
    points = figures.styled(hv.Points((times, errors), [xd, yd], label="rungs"), {}, {}, {"s": 40})
    labels = figures.styled(
        hv.Labels((times, errors, [f" stepping, Nh = {i} " for i in range(5)]), [xd, yd], "text"),
        {"show_legend": False}, {}, {"size": 7, "horizontalalignment": "left", "verticalalignment": "center"},
    )  # fmt: skip
    front = hv.Curve((times, errors), xd, yd, label="Pareto front")
    overlay = hv.Overlay([points, front, labels, figures.marker_line(hv, 1e-2, vertical=False)])
    overlay = figures.overlay_options(overlay, "w(N) at the horizon vs wall time at 0.7 Hz (target 0.01)",
                                      xd.label, yd.label, True, True, True)  # fmt: skip
    return figures.styled(overlay, mpl={"fig_inches": (9.0, 5.0)})


def _exported(options: figures.ExportOptions) -> dict:
    """One figure of each kind exported, on small data, laid out for ``options``."""
    hv = figures.holoviews()
    figures.load_backend("matplotlib")
    w = _wear()
    out = {
        "wear map (fretwear map, Wear map scene)": figures.wear_map_figure(
            F, N, w, title="Wear map (exact load path, wear coefficient 1e-11 1/N)", point=(0.7, 1e3),
            reference=0.9 * w,
        ),
        "regime map": figures.map_figure(
            F, np.linspace(0, 3, 6), np.outer(np.linspace(0, 1, 6), np.ones(len(F))),
            xlabel="frequency f (Hz)", ylabel="r = Fₑₓ / (μ Fₙ)", zlabel="slip fraction of the period",
            clim=(0, 1), levels=(0.5,), cmap="magma", curves={"stick boundary": (F, 1 + F)}, hline=1.0,
            title="Stick/slip regimes (current r = 1)",
        ),
        "loop": figures.line_figure(
            {"hysteresis loop": (x := np.linspace(-1e-4, 1e-4, 30), 10 * np.tanh(3e4 * x)),
             "exact": (x, 9 * np.tanh(3e4 * x))},
            xlabel="x₁ − x₂ (m)", ylabel="friction force (N)", padding=0.08, dashed=("exact",),
            title="Hysteresis loop: dissipated energy 1.234e-05 J per cycle (exact 1.235e-05)",
        ),
        "FRF (fig05, log y, wide legend)": figures.line_figure(
            _frf_curves(), xlabel="frequency f (Hz)", ylabel="x₁ amplitude (m)", logy=True, vline=0.7,
            point=(0.7, 1e-3), dashed=["stuck (6 N)", "open (6 N)"], title="Fig. 5: FRF of mass 1",
        ),
        "signals": figures.signals_figure(
            t := np.linspace(0, 1, 30), {"x₁": np.sin(6 * t), "x₂": np.cos(6 * t)}, spans=[(0.2, 0.4)],
            hlines=(0.5, -0.5), xlabel="time t (s)", ylabel="displacement (m)", title="Displacements",
        ),
        "model sketch": figures.model_sketch(
            paper_model(fex=10.0), displacement=(1e-4, -5e-5), scale=figures.sketch_scale(np.array([1e-4])),
            state=1, wear=1e-6, title="The model at t = 0.25 T",
        ),
        "fig07 (three maps)": _layout(
            [figures.wear_map_figure(F, N, w, title=f"Fig. 7{c}: Fₑₓ = {fx} N") for c, fx in
             zip("abc", (6, 10, 14), strict=True)], 3, options,
        ),
        "fig09 (three panels, one legend)": _layout(
            [figures.line_figure(_frf_curves(), xlabel="frequency f (Hz)", ylabel="x₁ amplitude (m)",
                                 logy=True, title=f"Fig. 9{c}: Fₑₓ = {fx} N")
             for c, fx in zip("abc", (6, 10, 14), strict=True)], 1, options,
        ),
        "Pareto (accuracy scene)": _pareto(hv),
        "histogram (study scene)": figures.overlay_options(
            hv.Overlay([hv.Histogram((np.geomspace(1e3, 1e6, 9), np.arange(8.0)),
                                     kdims=[hv.Dimension("x", label="cycles to w = 0.5 u0")],
                                     vdims=[hv.Dimension("y", label="samples")]),
                        figures.marker_line(hv, 1e4)]),
            "Study: wear life, median 1e4, 5 % 2e3, 95 % 5e5", "cycles to w = 0.5 u0", "samples", True,
            False, False, (0.05, 0.0),
        ),
        "stick/slip map (interface scene)": figures.overlay_options(
            hv.Overlay([figures.styled(
                hv.QuadMesh((np.linspace(0, 360, 6), np.linspace(0, 1, 4), np.arange(24.0).reshape(4, 6) % 3),
                            [hv.Dimension("phase", label="phase of the cycle (°)"),
                             hv.Dimension("x", label="x (mm)")], [hv.Dimension("state")]),
                {"cmap": ["#4c72b0", "#dd8452", "#dddddd"], "clim": (-0.5, 2.5), "colorbar": True})]),
            "Interface: stick (0) / slip (1) / open (2) at N = 1e+06", "phase of the cycle (°)", "x (mm)",
            False, False, False,
        ),
    }  # fmt: skip
    return out


@pytest.fixture(scope="module")
def exported() -> dict:
    """The figures, built once: every size is landscape, so the paper's grids are one row for each."""
    assert all(w >= h for w, h, _ in figures.SIZES.values())
    return _exported(figures.ExportOptions(size="page"))


@pytest.mark.parametrize("size", list(figures.SIZES))
def test_no_text_overlaps_in_any_exported_figure(size, exported):
    """Defects (issue 26): the wear map's colour bar over the map and the caption, the regime map's
    legend over its colour bar, the loop's title cut and x ticks overlapping, the Pareto title cut and
    labels stacked, the sketch's labels overlapping, fig07/fig09's caption over the x tick labels, fig09's
    y tick labels cut, the colour bar of fig12-14 over the map and the caption cut on the right."""
    options = figures.ExportOptions(size=size)
    faults = {}
    for name, fig in exported.items():
        figure = figures.matplotlib_figure(fig, options, lambda markup: caption(STAMP, THREE, markup))
        try:
            assert tuple(figure.get_size_inches()) == figures.SIZES[size][:2]
            found = figures.layout_faults(figure)
            if found:
                faults[name] = found[:4]
        finally:
            plt.close(figure)
    assert not faults, faults


def test_layout_faults_finds_overlaps_and_cut_text():
    """The check itself: text over text, text over another axes, text past the edge."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    fig = Figure(figsize=(4, 3), layout="constrained")
    FigureCanvasAgg(fig)
    left, right = fig.subplots(1, 2)
    left.set_title("a title")
    assert figures.layout_faults(fig) == []
    left.text(0.5, 0.5, "one")
    left.text(0.5, 0.5, "two")
    fig.text(0.9, 0.5, "a text past the right edge")
    left.set_xlabel("a label as wide as both axes together, over the right one too")
    faults = "\n".join(figures.layout_faults(fig))
    assert re.search(r"label 'one' overlaps .*label 'two'", faults)
    assert "is cut by the figure's edge" in faults
    assert "overlaps the plotting area of axes 1" in faults


def test_size_presets_fill_in_what_is_not_given():
    assert figures.ExportOptions(size="column") == figures.ExportOptions(
        width=3.5, height=2.5, fontsize=7.0, size="column"
    )
    page = figures.ExportOptions(size="page", width=8.0)
    assert (page.width, page.height, page.fontsize, page.dpi) == (8.0, 4.0, 10.0, 150)
    with pytest.raises(ValueError, match="size must be one of column, page, slide, got 'poster'"):
        figures.ExportOptions(size="poster")


def test_svg_and_pdf_carry_the_figure_title_and_fretwear_as_creator():
    """Defect (issue 26): the SVG's dc:title was "Matplotlib v3.x"."""
    figures.load_backend("matplotlib")
    fig = figures.line_figure({"a": (F, F)}, xlabel="f (Hz)", ylabel="y (m)", title="Wear map (exact)")
    files = figures.render_figure(
        fig, ("svg", "pdf"), options=figures.ExportOptions(size="column"),
        caption=lambda markup: caption(STAMP, markup=markup),
    )  # fmt: skip
    dc = "{http://purl.org/dc/elements/1.1/}"
    root = ET.fromstring(files["svg"])
    work = root.find(".//{*}Work")
    assert work.find(f"{dc}title").text == "Wear map (exact)"
    assert work.find(f"{dc}creator//{dc}title").text == f"fretwear {figures.record.version()}"
    assert "Fₑₓ = 10 N" in work.find(f"{dc}description").text
    pdf = files["pdf"].decode("latin-1")
    assert "/Title (Wear map \\(exact\\))" in pdf and f"/Creator (fretwear {figures.record.version()})" in pdf
    assert "Matplotlib v" not in "".join(root.itertext())
