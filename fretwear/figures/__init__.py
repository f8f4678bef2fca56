"""Plotting and export, kept out of the numerical layers.

``fretwear.figures.plots`` builds HoloViews figures from library results,
``fretwear.figures.sketch`` draws the paper's 2-DOF model,
``fretwear.figures.patch`` draws a 3-D contact patch seen from above,
``fretwear.figures.export`` writes figures (PNG, SVG, PDF, HTML) and tables (CSV),
``fretwear.figures.layout`` lays them out for a file and checks that nothing overlaps,
``fretwear.figures.record`` stamps them with their parameters and reads and
writes the settings files of the dashboard and the CLI,
``fretwear.figures.paper`` computes and writes the paper's figure set,
``fretwear.figures.study`` draws the result of a study (``fretwear study``).
"""

from .export import (
    EXPORT_FORMATS,
    SIZES,
    ExportOptions,
    csv_text,
    figure_bytes,
    figure_title,
    matplotlib_figure,
    render_figure,
    save_csv,
    save_figure,
    save_figures,
)
from .layout import lay_out, layout_faults
from .paper import paper_figures
from .patch import patch_figure, patch_grid
from .plots import (
    holoviews,
    line_figure,
    load_backend,
    map_figure,
    marker_line,
    overlay_options,
    signals_figure,
    styled,
    styling_for,
    wear_curve,
    wear_map_figure,
)
from .record import caption, csv_header, parameter_record, parse_settings, read_settings, settings_json
from .sketch import model_sketch, sketch_scale
from .study import wear_life_figure

__all__ = [
    "EXPORT_FORMATS",
    "SIZES",
    "ExportOptions",
    "figure_title",
    "lay_out",
    "layout_faults",
    "matplotlib_figure",
    "caption",
    "csv_header",
    "csv_text",
    "figure_bytes",
    "model_sketch",
    "parameter_record",
    "parse_settings",
    "read_settings",
    "render_figure",
    "save_figures",
    "settings_json",
    "sketch_scale",
    "holoviews",
    "line_figure",
    "load_backend",
    "styling_for",
    "map_figure",
    "marker_line",
    "overlay_options",
    "paper_figures",
    "patch_figure",
    "patch_grid",
    "save_csv",
    "save_figure",
    "signals_figure",
    "styled",
    "wear_curve",
    "wear_map_figure",
    "wear_life_figure",
]
