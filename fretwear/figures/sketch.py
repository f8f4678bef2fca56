"""The paper's 2-DOF model drawn as a sketch (paper Fig. 4), with its values and its state at one instant.

Mass 1 (bottom, on rollers) is tied to the left wall by ``k1`` and ``c1`` and
driven by ``F_ex cos(omega t)``; mass 2 (top) is tied to the right wall by
``k2`` and ``c2`` and pressed on mass 1 by the normal spring ``kn``, whose
compression ``u0 - w`` gives the normal load ``F_N = kn (u0 - w)``; the friction
interface between the masses is coloured by its state (stick, slip, open) and
the worn depth ``w`` is drawn as a band of mass 1's face, to scale of ``u0``.

The masses are drawn displaced by ``scale`` times their displacements (the
amplitudes are micrometres to millimetres: :func:`sketch_scale` makes the
largest one a fixed length). Every figure has the same layers, whatever the
values, so that a ``DynamicMap`` can redraw it frame by frame.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..model import OPEN, SLIP, STICK, Model
from .plots import ensure_backend, holoviews, styled

if TYPE_CHECKING:
    import holoviews as hv

__all__ = ["LAYERS", "model_sketch", "sketch_layers", "sketch_scale", "STATE_COLORS", "STATE_NAMES"]

#: colour and name of the friction interface in each state
STATE_COLORS = {STICK: "#2ca02c", SLIP: "#d62728", OPEN: "#7f7f7f"}
STATE_NAMES = {STICK: "stick", SLIP: "slip", OPEN: "open"}
#: drawing units: walls at 0 and 10, mass 1 (x0, x1, y0, y1) centred at 5, mass 2 on it
_M1 = (3.0, 7.0, 0.45, 1.45)
_M2 = (3.8, 6.2, 1.45, 2.35)
_WALLS = (0.0, 10.0)
_TOP = 3.55
#: largest drawn excursion of a mass, and drawn depth of a contact worn through (drawing units)
_EXCURSION, _WORN = 0.9, 0.3


def sketch_scale(displacement: np.ndarray) -> float:
    """Drawing units per metre that make the largest excursion of ``displacement`` (m) a fixed length."""
    peak = float(np.max(np.abs(displacement))) if np.size(displacement) else 0.0
    return _EXCURSION / peak if peak > 0 else 0.0


def _zigzag(x0: float, x1: float, y: float, turns: int = 6, height: float = 0.14) -> tuple:
    """A horizontal spring from ``x0`` to ``x1`` at height ``y`` (straight ends, zigzag middle)."""
    ends = 0.12 * (x1 - x0)
    xs = np.linspace(x0 + ends, x1 - ends, 2 * turns + 1)
    ys = y + height * np.r_[0, np.tile([1, -1], turns)[: 2 * turns - 1], 0]
    return np.r_[x0, xs, x1], np.r_[y, ys, y]


def _dashpot(x0: float, x1: float, y: float, h: float = 0.12) -> list[tuple]:
    """A damper from ``x0`` to ``x1`` at height ``y``: rod, cylinder (open to the right) and piston."""
    mid = 0.5 * (x0 + x1)
    cyl0, cyl1 = mid - 0.35, mid + 0.25
    return [
        ([x0, cyl0], [y, y]),
        ([cyl1, cyl0, cyl0, cyl1], [y + h, y + h, y - h, y - h]),
        ([mid, mid], [y - 0.8 * h, y + 0.8 * h]),
        ([mid, x1], [y, y]),
    ]


#: the layers of a sketch, bottom to top, with the kind of element each is drawn as
LAYERS = {
    "walls": "rectangles", "springs": "path", "dampers": "path", "rollers": "points",
    "masses": "rectangles", "worn": "rectangles", "interface": "segments", "arrow": "segments",
    "head": "polygons", "labels": "labels",
}  # fmt: skip


def sketch_layers(
    model: Model,
    *,
    displacement: tuple[float, float] = (0.0, 0.0),
    scale: float = 0.0,
    state: int | None = None,
    wear: float = 0.0,
    normal_load: float | None = None,
) -> dict[str, list]:
    """The geometry of :func:`model_sketch` (drawing units), layer by layer (:data:`LAYERS`).

    Each layer is a list: of ``(x0, y0, x1, y1)`` for rectangles and segments,
    of ``(xs, ys)`` arrays for paths, of ``(x, y)`` for points, of
    ``{"x": xs, "y": ys}`` for polygons and of ``(x, y, text)`` for labels.
    Plain numbers, so that a page can animate the drawing frame by frame
    without drawing it anew. Parameters as :func:`model_sketch`.
    """
    if model.n_dofs != 2 or len(model.friction) != 1:
        raise ValueError(
            f"model_sketch draws the paper's 2-DOF model (2 DOFs, 1 friction contact), got "
            f"{model.n_dofs} DOFs and {len(model.friction)} friction contacts"
        )
    contact = model.friction[0]
    fn = contact.normal_load(wear) if normal_load is None else float(normal_load)
    fraction = float(np.clip(wear / contact.u0, 0.0, 1.0)) if contact.u0 > 0 else 0.0
    dx1, dx2 = (scale * float(d) for d in displacement)
    depth = _WORN * fraction
    m1 = (_M1[0] + dx1, _M1[1] + dx1, _M1[2], _M1[3])
    m2 = (_M2[0] + dx2, _M2[1] + dx2, _M2[2], _M2[3])
    k, c, m = np.diag(model.K), np.diag(model.C), np.diag(model.M)
    left, right = _WALLS
    x0, x1 = max(m1[0], m2[0]), min(m1[1], m2[1])  # the contact: where the masses overlap
    springs = [_zigzag(left, m1[0], 1.15), _zigzag(m2[1], right, 2.1)]
    # the normal spring, from the fixed plate to a roller on mass 2: its length follows the wear
    xn = 0.5 * (m2[0] + m2[1])
    ys = np.linspace(m2[3] + 0.15, _TOP - 0.1, 11)
    normal = (xn + 0.14 * np.r_[0, np.tile([1, -1], 5)[:9], 0], ys)
    springs.append((np.r_[xn, normal[0], xn], np.r_[m2[3], normal[1], _TOP]))
    tip = m1[0] + 1.6
    label = "" if state is None else f": {STATE_NAMES.get(state, '')}"
    mid1, mid2 = 0.5 * (m1[0] + m1[1]), 0.5 * (m2[0] + m2[1])
    return {
        "walls": [
            (left - 0.3, 0.0, left, _TOP),
            (right, 0.0, right + 0.3, _TOP),
            (3.5, _TOP, 6.5, _TOP + 0.25),
            (left - 0.3, -0.25, right + 0.3, 0.0),
        ],
        "springs": springs,
        "dampers": _dashpot(left, m1[0], 0.7) + _dashpot(m2[1], right, 1.7),
        "rollers": [(m1[0] + 0.6, 0.22), (m1[1] - 0.6, 0.22)],
        "masses": [(m1[0], m1[2], m1[1], m1[3]), (m2[0], m2[2], m2[1], m2[3])],
        "worn": [(x0, m1[3] - depth, x1, m1[3])],  # the depth worn away from mass 1, to scale
        "interface": [(x0, m1[3], x1, m1[3])],
        "arrow": [(m1[0] + 0.3, 0.7, m1[0] + 1.35, 0.7)],
        "head": [{"x": [tip, tip - 0.25, tip - 0.25], "y": [0.7, 0.8, 0.6]}],
        "labels": [
            (mid1 + 0.9, 1.15, f"m₁ = {m[0]:.3g} kg"),
            (mid1 + 1.0, 0.7, f"Fₑₓ = {model.force_cos[0]:.3g} N"),
            (mid2, 1.9, f"m₂ = {m[1]:.3g} kg"),
            (0.5 * (left + m1[0]), 1.5, f"k₁ = {k[0]:.3g} N/m"),
            (0.5 * (left + m1[0]), 0.35, f"c₁ = {c[0]:.2g} N s/m"),
            (0.5 * (m2[1] + right), 2.45, f"k₂ = {k[1]:.3g} N/m"),
            # right of mass 1's farthest excursion (its right side reaches 7.9 at the largest drawn excursion)
            (0.5 * (_M2[1] + right) + 0.85, 1.38, f"c₂ = {c[1]:.2g} N s/m"),
            (xn + 2.2, 3.25, f"kₙ = {contact.kn:.3g} N/m"),
            (xn + 2.2, 2.9, f"Fₙ = kₙ(u₀ − w) = {fn:.3g} N"),
            # left of mass 2 at its farthest (3.8 - 0.9), three short lines: legible in one journal column
            (1.6, 2.95, f"μ = {contact.mu:.3g}{label}"),
            (1.6, 2.6, f"w = {100 * fraction:.0f} % of u₀"),
            (1.6, 2.25, f"u₀ = {contact.u0:.2g} m"),
        ],
    }


def model_sketch(
    model: Model,
    *,
    displacement: tuple[float, float] = (0.0, 0.0),
    scale: float = 0.0,
    state: int | None = None,
    wear: float = 0.0,
    normal_load: float | None = None,
    title: str = "",
) -> hv.Overlay:
    """Sketch of the paper's 2-DOF ``model`` (:func:`fretwear.paper_model`) at one instant.

    Parameters
    ----------
    model : Model
        Two DOFs, diagonal mass, stiffness and damping, one friction contact between them.
    displacement : (float, float)
        ``x1``, ``x2`` at the instant drawn (m), drawn times ``scale``.
    scale : float
        Drawing units per metre (:func:`sketch_scale`); 0 draws the rest position.
    state : int, optional
        State of the friction contact (``STICK``, ``SLIP``, ``OPEN``); ``None``: not known.
    wear : float
        Worn depth ``w`` (m), drawn to scale of ``u0``.
    normal_load : float, optional
        Normal load at this wear (N); default ``F_N(w)`` of the contact.
    title : str
        Figure title.

    The overlay's elements are the :data:`LAYERS` of :func:`sketch_layers`, in that order.
    """
    geometry = sketch_layers(
        model, displacement=displacement, scale=scale, state=state, wear=wear, normal_load=normal_load
    )
    hv = holoviews()
    ensure_backend()
    texts = geometry["labels"]
    element = {
        "rectangles": hv.Rectangles,
        "segments": hv.Segments,
        "points": hv.Points,
        "polygons": hv.Polygons,
        "path": lambda paths: hv.Path([np.column_stack(p) for p in paths]),
        "labels": lambda _: hv.Labels(
            {"x": [t[0] for t in texts], "y": [t[1] for t in texts], "text": [t[2] for t in texts]},
            ["x", "y"],
            "text",
        ),
    }
    drawn = {name: element[kind](geometry[name]) for name, kind in LAYERS.items()}

    def fill(element, face: str, edge: str, width: float = 1.0):
        return styled(
            element,
            {},
            {"fill_color": face, "line_color": edge, "line_width": width},
            {"facecolor": face, "edgecolor": edge, "linewidth": width},
        )

    def line(element, color: str, width: float, mpl_width: float):
        return styled(element, {"color": color}, {"line_width": width}, {"linewidth": mpl_width})

    layers = [
        fill(drawn["walls"], "#d9d9d9", "#999999"),
        line(drawn["springs"], "#444444", 2, 1.5),
        line(drawn["dampers"], "#444444", 2, 1.5),
        styled(drawn["rollers"], {"color": "#999999"}, {"size": 9}, {"s": 40}),
        fill(drawn["masses"], "#c6dbef", "#08519c", 2.0),
        fill(drawn["worn"], "#fdae6b", "#e6550d"),
        styled(
            drawn["interface"],
            {"color": STATE_COLORS.get(state, "black")},
            {"line_width": 6},
            {"linewidth": 4},
        ),  # fmt: skip
        line(drawn["arrow"], "#08519c", 3, 2),
        fill(drawn["head"], "#08519c", "#08519c"),
        styled(
            drawn["labels"],
            {},
            {"text_font_size": "9pt", "text_color": "#222222"},
            {"size": 8, "color": "#222222"},
        ),
    ]
    return styled(
        hv.Overlay(layers),
        {
            "title": title,
            "xlim": (-0.5, 10.5),
            "ylim": (-0.4, 4.0),
            "xaxis": None,
            "yaxis": None,
            "show_legend": False,
        },  # fmt: skip
        {"responsive": True, "height": 340, "toolbar": None, "show_grid": False},
        {"fig_inches": (7.0, 3.5), "aspect": "auto"},
    )
