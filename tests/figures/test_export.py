"""Tests of fretwear.figures.export: figure builders, file formats and the paper's figure set."""

import csv
import io
import xml.etree.ElementTree as ET

import numpy as np
import pytest

from fretwear import figures


def test_csv_text_round_trips():
    text = figures.csv_text({"f_hz": np.array([0.5, 1.0]), "ok": np.array([True, False]), "tag": ["a", "b"]})
    rows = list(csv.reader(io.StringIO(text)))
    assert rows == [["f_hz", "ok", "tag"], ["0.5", "True", "a"], ["1", "False", "b"]]
    with pytest.raises(ValueError, match="equal lengths"):
        figures.csv_text({"a": [1, 2], "b": [1]})


def test_figures_render_to_every_format(tmp_path):
    figures.load_backend("matplotlib")
    figures.load_backend("bokeh")
    x = np.linspace(0.3, 1.3, 11)
    line = figures.line_figure(
        {"a": (x, x**2), "b": (x, x)},
        xlabel="f (Hz)",
        ylabel="y (m)",
        logy=True,
        dashed=["b"],
        vline=0.7,
        point=(0.7, 0.49),
        title="line",
    )
    image = figures.map_figure(
        x,
        np.arange(5.0),
        np.outer(np.arange(5), x),
        xlabel="f",
        ylabel="log N",
        zlabel="w",
        levels=(1.0,),
        curves={"edge": (x, x)},
        hline=2.0,
        point=(1, 1),
    )
    signals = figures.signals_figure(
        x, {"s": np.sin(x)}, spans=[(0.4, 0.6)], hlines=(0.5, -0.5), xlabel="t", ylabel="F"
    )
    for fig in (line, image, signals):
        assert figures.figure_bytes(fig, "png")[:8] == b"\x89PNG\r\n\x1a\n"
    assert ET.fromstring(figures.figure_bytes(image, "svg")).tag.endswith("svg")
    html = figures.save_figure(line, tmp_path / "line.html").read_text()
    assert "<script src=" not in html and "<title>line</title>" in html
    with pytest.raises(ValueError, match="must end in one of"):
        figures.save_figure(line, tmp_path / "line.jpg")


def test_paper_figures_write_the_tables(tmp_path):
    logs = []
    files = figures.paper_figures(
        tmp_path, harmonics=3, frequencies=4, cycle_points=4, cycles=1e4, formats=("csv",), log=logs.append
    )
    assert [f.name for f in files] == [f"fig{n:02d}.csv" for n in range(5, 15)]
    text = (tmp_path / "fig07.csv").read_text()
    header = [line for line in text.splitlines() if line.startswith("#")]  # the parameter record
    assert header[0].startswith("# model: paper 2-DOF") and "F_ex = 6, 10 and 14 N" in header[0]
    assert "# k_w = 1e-11 1/N" in header and "# Nh = 3" in header and header[-1].startswith("# fretwear ")
    rows = list(csv.DictReader(line for line in text.splitlines() if not line.startswith("#")))
    assert {r["fex"] for r in rows} == {"6", "10", "14"} and len(rows) == 3 * 4 * 4
    assert max(float(r["w_over_u0"]) for r in rows) > 0.5
    with open(tmp_path / "fig11.csv") as fh:
        methods = {r["method"] for r in csv.DictReader(line for line in fh if not line.startswith("#"))}
    assert {"stepping", "polynomial"} <= methods
    assert any("wrote fig14" in line for line in logs)
    with pytest.raises(ValueError, match="formats must be among"):
        figures.paper_figures(tmp_path, formats=("gif",))


def test_captions_break_at_their_separators_within_the_figure_width():
    import matplotlib

    matplotlib.use("Agg")
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    from fretwear.figures.layout import wrap_text

    text = figures.caption(
        {"fex": 10.0, "mu": 1.0, "normal_load": 10.0, "kw": 1e-11, "harmonics": 7, "method": "exact"},
        markup="mathtext",
    )
    for inches in (4.0, 7.0):
        fig = Figure(figsize=(inches, 3.0), dpi=100)
        canvas = FigureCanvasAgg(fig)
        lines = wrap_text(fig, text, 7.5, 0.98 * inches * 100).split("\n")
        assert " ".join(lines) == text and len(lines) == (2 if inches == 4.0 else 1)  # nothing lost
        assert all(line.endswith((",", ";")) for line in lines[:-1])  # broken after a separator only
        widths = [
            fig.text(0, 0, line, fontsize=7.5).get_window_extent(canvas.get_renderer()).width
            for line in lines
        ]
        assert max(widths) <= 0.98 * inches * 100
