"""Plotting and export, kept out of the numerical layers.

:mod:`~fretwear.figures.plots` builds HoloViews figures from library results,
:mod:`~fretwear.figures.export` writes them (PNG, SVG, HTML) and tables (CSV),
:mod:`~fretwear.figures.paper` computes and writes the paper's figure set.
"""

from .export import FIGURE_FORMATS, csv_text, figure_bytes, save_csv, save_figure
from .paper import paper_figures
from .plots import (
    holoviews,
    line_figure,
    load_backend,
    map_figure,
    marker_line,
    overlay_options,
    signals_figure,
    styled,
    wear_curve,
    wear_map_figure,
)

__all__ = [
    "FIGURE_FORMATS",
    "csv_text",
    "figure_bytes",
    "holoviews",
    "line_figure",
    "load_backend",
    "map_figure",
    "marker_line",
    "overlay_options",
    "paper_figures",
    "save_csv",
    "save_figure",
    "signals_figure",
    "styled",
    "wear_curve",
    "wear_map_figure",
]
