"""Summaries of a study's result: the wear life over the random samples."""

from __future__ import annotations

import numpy as np

from .compute import HORIZON, OK, STUCK

__all__ = ["wear_life_summary"]


def wear_life_summary(ds, fraction: float = 0.5) -> dict[str, float]:
    """Median and 5 / 95 % quantiles of the cycles to ``fraction * u0`` over the samples of a study.

    Points that stick count as an infinite life, points whose wear stays below
    ``fraction * u0`` at the horizon as a life beyond the horizon (``inf`` in
    the ranking too); failed or not computed points are left out. Quantiles are
    empirical (``inverted_cdf``): a quantile that falls among the infinite lives is ``inf``.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with the ``wear_life`` quantity (``xarray.open_zarr(RESULT)``), whose only
        point dimension is ``sample`` (select grid points first).

    Returns
    -------
    dict
        ``median``, ``q05``, ``q95`` (cycles), and counts ``n`` (points used), ``stuck``,
        ``beyond_horizon``, ``left_out``.
    """
    if "cycles_to" not in ds:
        raise ValueError("the study has no 'wear_life' quantity (no variable cycles_to)")
    fractions = ds["fraction"].values
    if not np.any(np.isclose(fractions, fraction)):
        raise ValueError(
            f"fraction must be one of the study's fractions {fractions.tolist()}, got {fraction!r}"
        )
    life = ds["cycles_to"].sel(fraction=fractions[np.isclose(fractions, fraction)][0])
    if set(life.dims) - {"sample"}:
        raise ValueError(f"select one point of the grid axes {sorted(set(life.dims) - {'sample'})} first")
    values = np.asarray(life.values, dtype=float).ravel()
    status = np.asarray(ds["status"].values).ravel()
    usable = np.isin(status, (OK, STUCK, HORIZON))
    ranked = np.where(np.isnan(values), np.inf, values)[usable]
    q = np.quantile(ranked, [0.5, 0.05, 0.95], method="inverted_cdf") if ranked.size else np.full(3, np.nan)
    return {
        "median": float(q[0]),
        "q05": float(q[1]),
        "q95": float(q[2]),
        "n": int(usable.sum()),
        "stuck": int((status == STUCK).sum()),
        "beyond_horizon": int((usable & (status != STUCK) & np.isnan(values)).sum()),
        "left_out": int((~usable).sum()),
    }
