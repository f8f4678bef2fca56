"""Figures of a study's result (``fretwear study``): the histogram of the wear life."""

from __future__ import annotations

import numpy as np

from ..studies.summary import wear_life_summary

__all__ = ["wear_life_figure"]


def wear_life_figure(ds, fraction: float = 0.5, bins: int = 40):
    """Histogram of the cycles to ``fraction * u0`` with its median and 5 / 95 % quantiles.

    Parameters
    ----------
    ds : xarray.Dataset
        As for ``wear_life_summary()``.
    fraction : float
        Wear fraction of ``u0`` (one of the study's ``fraction`` coordinates).
    bins : int
        Log-spaced bins over the finite lives.

    Returns
    -------
    matplotlib.figure.Figure
    """
    from matplotlib.figure import Figure  # plotting only here: the numerical core does not import it
    from matplotlib.ticker import NullFormatter

    summary = wear_life_summary(ds, fraction)
    life = ds["cycles_to"].sel(fraction=fraction, method="nearest").values.ravel()
    finite = life[np.isfinite(life)]
    fig = Figure(figsize=(7, 4.2), layout="constrained")
    ax = fig.add_subplot()
    if finite.size:
        edges = np.geomspace(finite.min(), finite.max() * 1.0001, bins + 1) if finite.min() > 0 else bins
        ax.hist(finite, bins=edges, color="#4c72b0", alpha=0.8, label=f"{finite.size} samples")
        ax.set_xscale("log")
        ax.xaxis.set_minor_formatter(NullFormatter())
    styles = {"median": ("k", "-"), "q05": ("#c44e52", "--"), "q95": ("#c44e52", "--")}
    labels = {"median": "median", "q05": "5 %", "q95": "95 %"}
    for key, (color, style) in styles.items():
        value = summary[key]
        if np.isfinite(value):
            ax.axvline(value, color=color, linestyle=style, label=f"{labels[key]}: {value:.4g} cycles")
        else:
            ax.plot([], [], " ", label=f"{labels[key]}: no wear-through ({value})")
    notes = []
    if summary["stuck"]:
        notes.append(f"{summary['stuck']} stuck (no wear)")
    if summary["beyond_horizon"]:
        notes.append(f"{summary['beyond_horizon']} beyond the horizon")
    if summary["left_out"]:
        notes.append(f"{summary['left_out']} failed or not computed")
    if notes:
        ax.plot([], [], " ", label=", ".join(notes))
    ax.set_xlabel(f"cycles to w = {fraction:g} u0")
    ax.set_ylabel("samples")
    ax.set_title(str(ds.attrs.get("title", "wear life")))
    ax.legend(loc="best", fontsize="small")
    return fig
