"""Summaries of a study's result: the wear life over the random samples, the deepest wear of an interface,
the magnification of a mistuned bladed disk against the mistuning level."""

from __future__ import annotations

import numpy as np

from .compute import HORIZON, OK, STUCK

__all__ = ["magnification_summary", "wear_depth_summary", "wear_life_summary"]


def wear_life_summary(ds, fraction: float = 0.5, *, depth: float | None = None) -> dict[str, float]:
    """Median and 5 / 95 % quantiles of the cycles to ``fraction * u0`` over the samples of a study
    (for a model with contact pairs: to the worn ``depth``, m, at the deepest pair).

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
    level, value = ("depth", depth) if "depth" in ds.coords else ("fraction", fraction)
    levels = ds[level].values
    close = (
        np.isclose(levels, value, atol=0.0 if level == "depth" else 1e-8) if value is not None else [False]
    )
    if not np.any(close):  # a depth (m) is tiny: relative closeness only
        raise ValueError(f"{level} must be one of the study's {level}s {levels.tolist()}, got {value!r}")
    life = ds["cycles_to"].sel({level: levels[close][0]})
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


def wear_depth_summary(ds) -> dict[str, float]:
    """The deepest wear at the horizon over the points of a study of a model with contact pairs.

    Per point, the largest worn depth over the pairs at the last cycle count
    (the horizon); then its smallest, median and largest value over the points
    that did not fail (status ``ok``, ``stuck`` or ``horizon``), and where the deepest of all is.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with the ``wear`` quantity over a model with contact pairs (variable ``wear_depth``).

    Returns
    -------
    dict
        ``min``, ``median``, ``max`` (m), ``position`` (m, the pair of the deepest wear along the
        interface), ``point`` (the point's coordinates, by dimension), counts ``n`` and ``left_out``.
    """
    if "wear_depth" not in ds:
        raise ValueError("the study has no per-pair wear (variable wear_depth): a 'wear' study of a model "
                         "with contact pairs")  # fmt: skip
    last = ds["wear_depth"].isel(cycles=-1)
    usable = np.isin(np.asarray(ds["status"].values), (OK, STUCK, HORIZON))  # stuck: no wear, depth 0
    deepest = last.max("pair").values
    n = int(usable.sum())
    out: dict[str, float] = {"n": n, "left_out": int((~usable).sum())}
    if n == 0:
        return out | {"min": np.nan, "median": np.nan, "max": np.nan, "position": np.nan, "point": {}}
    values = deepest[usable]
    where = np.unravel_index(int(np.argmax(np.where(usable, deepest, -np.inf))), deepest.shape)
    point = dict(zip(ds["status"].dims, where, strict=True))
    pair = int(last.isel(point).argmax("pair"))
    coords = {d: ds[d].values[i].item() for d, i in point.items() if d in ds.coords}
    return out | {
        "min": float(values.min()),
        "median": float(np.median(values)),
        "max": float(values.max()),
        "position": float(ds["position"].values[pair]),
        "point": coords,
    }


def magnification_summary(ds) -> dict:
    """The magnification curve of a mistuning study: per level, the mean, 95th percentile and largest
    amplitude magnification factor over its draws, against Whitehead's bound.

    Only points with status ``ok`` count (the others are NaN in ``factors`` and left out); the
    percentile is NumPy's default (linear), as ``benchmarks/bench_mistuning.py`` prints it.

    Parameters
    ----------
    ds : xarray.Dataset
        A study with the quantity ``magnification`` (``xarray.open_zarr(RESULT)``, or
        :func:`fretwear.studies.store.open_study`).

    Returns
    -------
    dict
        ``levels`` (n_levels,), ``mean``, ``p95``, ``max`` (-, per level; NaN for a level without a
        computed draw), ``n`` (computed draws per level), ``factors`` (n_levels, samples: every draw's
        factor, NaN where not computed), ``above`` (draws above the bound, per level), ``whitehead``
        (``(1 + sqrt(N)) / 2``), ``tuned_amplitude`` (m), ``tuned_frequency`` (Hz), ``band`` (Hz).
    """
    if "magnification" not in ds:
        raise ValueError("the study has no 'magnification' quantity (no variable magnification)")
    factors = np.asarray(ds["magnification"].transpose("level", "sample").values, dtype=float)
    ok = np.asarray(ds["status"].transpose("level", "sample").values) == OK
    factors = np.where(ok, factors, np.nan)
    n = ok.sum(axis=1)
    stats = {"mean": [], "p95": [], "max": []}
    for row, count in zip(factors, n, strict=True):
        f = row[np.isfinite(row)] if count else np.full(1, np.nan)
        stats["mean"].append(f.mean())
        stats["p95"].append(np.percentile(f, 95))
        stats["max"].append(f.max())
    bound = float(ds.attrs["whitehead"])
    return {
        "levels": np.asarray(ds["level"].values, dtype=float),
        **{k: np.array(v) for k, v in stats.items()},
        "n": n,
        "factors": factors,
        "above": (np.nan_to_num(factors) > bound).sum(axis=1),
        "whitehead": bound,
        "tuned_amplitude": float(ds.attrs["tuned_amplitude"]),
        "tuned_frequency": float(ds.attrs["tuned_frequency"]),
        "band": tuple(float(f) for f in ds.attrs["band_hz"]),
    }
