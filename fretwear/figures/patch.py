"""A 3-D contact patch seen from above: one value per contact pair, mapped over the contact plane.

The pairs of a 3-D interface (the sphere on the flat, :mod:`fretwear.interface.sphere`) sit at points
``(x, y)`` of the contact plane. :func:`patch_figure` draws a value per pair as an image over the
plane, each grid cell taking the value of its nearest pair (the benchmark's pairs lie on a regular grid:
one cell each), with a colour bar that names the value and its unit, and dashed circles at given radii
(e.g. Hertz's contact radius ``a`` and Mindlin's stick radius ``c``), each with a legend entry. Discrete
values (stick, slip, open) get one colour each, a legend entry each and a colour bar naming them. A half
model (symmetry plane ``y = 0``) is mirrored to show the whole patch. The same figure renders on Bokeh
(the dashboard) and Matplotlib (exports), as the builders of :mod:`~fretwear.figures.plots`.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import TYPE_CHECKING

import numpy as np

from .plots import ensure_backend, holoviews, overlay_options, styled

if TYPE_CHECKING:
    import holoviews as hv

__all__ = ["patch_figure", "patch_grid"]


def patch_grid(
    points: np.ndarray, values: np.ndarray, mirror: bool = True
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``values`` at the pairs' ``points`` on a regular grid of the plane: ``(x, y, z)``, ``z`` (ny, nx).

    The grid spacing is the median distance of a pair to its nearest neighbour; each cell takes the
    value of its nearest pair, NaN where no pair lies within 0.75 spacings (outside the patch). With
    ``mirror`` the points are reflected ``y -> -y`` first (a half model's symmetry plane ``y = 0``; the
    pairs on it are not doubled). Coordinates in the unit of ``points``.
    """
    from scipy.spatial import cKDTree

    points = np.asarray(points, dtype=float).reshape(-1, 2)
    values = np.asarray(values, dtype=float).ravel()
    if len(points) != len(values):
        raise ValueError(f"values must have one entry per point ({len(points)}), got {len(values)}")
    if mirror:
        off = points[:, 1] != 0
        points = np.vstack([points, points[off] * [1.0, -1.0]])
        values = np.concatenate([values, values[off]])
    if len(points) < 2:
        raise ValueError(f"a patch needs at least 2 points, got {len(points)}")
    tree = cKDTree(points)
    h = float(np.median(tree.query(points, k=2)[0][:, 1]))
    low, high = points.min(axis=0), points.max(axis=0)
    n = np.round((high - low) / h).astype(int) + 1
    x, y = low[0] + h * np.arange(n[0]), low[1] + h * np.arange(n[1])
    distance, nearest = tree.query(np.stack(np.meshgrid(x, y), axis=-1).reshape(-1, 2))
    z = np.where(distance <= 0.75 * h, values[nearest], np.nan).reshape(len(y), len(x))
    return x, y, z


#: colours of the circles, in order: they show on the colour maps and the states' colours alike
CIRCLE_COLOURS = ("red", "black")


def _circle(hv, radius: float, label: str, colour: str, xd, yd) -> hv.Curve:
    t = np.linspace(0.0, 2 * np.pi, 129)
    curve = hv.Curve((radius * np.cos(t), radius * np.sin(t)), xd, yd, label=label)
    return styled(curve, {"color": colour}, {"line_dash": "dashed", "line_width": 2},
                  {"linestyle": "--", "linewidth": 1.5})  # fmt: skip


def patch_figure(
    points: np.ndarray,
    values: np.ndarray,
    *,
    zlabel: str,
    title: str = "",
    xlabel: str = "x (mm)",
    ylabel: str = "y (mm)",
    mirror: bool = True,
    circles: Mapping[str, float] | None = None,
    states: Mapping[int, tuple[str, str]] | None = None,
    clim: tuple[float, float] | None = None,
    cmap: str = "viridis",
) -> hv.Overlay:
    """The contact patch seen from above: ``values`` (one per pair) over the pairs' ``points`` (nc, 2).

    Parameters
    ----------
    points : ndarray, shape (nc, 2)
        The pairs' ``(x, y)`` in the axes' unit (e.g. mm).
    values : ndarray, shape (nc,)
        One value per pair (NaN: not drawn), in the colour bar's unit; with ``states``, their codes.
    zlabel : str
        The colour bar's title: the value and its unit.
    mirror : bool
        Reflect the points ``y -> -y`` (a half model; :func:`patch_grid`).
    circles : dict, optional
        ``label -> radius`` (axes' unit): dashed circles about the origin (red, then black), one legend
        entry each,
        e.g. ``{"Hertz radius a": 0.19}``. The figure has the same layers whatever the radii (NaN hides
        one), as a ``DynamicMap`` needs.
    states : dict, optional
        ``code -> (name, colour)`` for discrete values (e.g. ``{0: ("stick", "#4c72b0"), ...}``): one
        colour per code, named on the colour bar and in the legend.
    clim : (float, float), optional
        Colour limits (default: the data's).
    cmap : str
        Colour map of continuous values.
    """
    hv = holoviews()
    ensure_backend()
    xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=ylabel)
    zd = hv.Dimension("z", label=zlabel)
    x, y, z = patch_grid(points, values, mirror)
    image = hv.Image((x, y, z), [xd, yd], [zd], rtol=1e-6)
    common = {"colorbar": True, "framewise": True, "clim": clim or (np.nan, np.nan)}
    bokeh = {"tools": ["hover"], "clabel": zlabel}
    mpl = {"aspect": "equal", "clabel": zlabel}
    layers = []
    if states:
        codes = sorted(states)
        colours = [states[c][1] for c in codes]
        common |= {"cmap": colours, "clim": (codes[0] - 0.5, codes[-1] + 0.5), "color_levels": len(codes)}
        names = {c: states[c][0] for c in codes}
        # discrete states, discrete colours: the colour bar names each at its colour's middle
        bokeh |= {"cticks": codes, "colorbar_opts": {"major_label_overrides": names}}
        mpl |= {"cbar_ticks": list(names.items())}
        layers.append(styled(image, common, bokeh, mpl))
        for c in codes:  # a legend entry per state: a square of its colour (an image has none)
            proxy = hv.Points([(np.nan, np.nan)], [xd, yd], label=states[c][0])
            layers.append(styled(proxy, {"color": states[c][1]}, {"size": 12, "marker": "square"},
                                 {"s": 80, "marker": "s"}))  # fmt: skip
    else:
        layers.append(styled(image, common | {"cmap": cmap}, bokeh, mpl))
    for (label, r), colour in zip((circles or {}).items(), CIRCLE_COLOURS * len(circles or ()), strict=False):
        layers.append(_circle(hv, float(r), label, colour, xd, yd))
    overlay = overlay_options(hv.Overlay(layers), title, xlabel, ylabel, False, False, True)
    return overlay  # axes of any aspect: a square one cut the title at a column's width (issue 26)
