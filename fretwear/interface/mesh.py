"""Meshes of the cylinder-on-flat fretting benchmark (plane strain), refined under the contact.

Two bodies of bilinear quadrilaterals (scikit-fem ``MeshQuad``), built on
graded tensor grids:

* the **flat**: the block ``[-W_f, W_f] x [-D_f, 0]``, top surface ``y = 0``;
* the **pad**: the cylinder of radius ``R`` cut to ``|x| <= W_p``, between its
  circular contact face ``y = g(x) = R - sqrt(R^2 - x^2)`` and the flat top
  ``y = H_p`` by which it is held.

In ``x`` both grids share ``n`` equally spaced columns over the contact window
``|x| <= x_w`` (spacing ``h = 2 x_w / (n - 1)``), then spacings that grow by a
constant ratio up to the body edges. In depth (flat) and height (pad) the
spacing is ``h`` down to ``x_w`` and then grows likewise. Pad and flat nodes
of the window columns face each other (same ``x``) and form the node pairs of
the contact, with initial gap ``g(x)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from skfem import MeshQuad

__all__ = ["graded_axis", "CylinderOnFlatMesh", "cylinder_on_flat_mesh"]


def graded_axis(h: float, inner: float, outer: float, growth: float) -> np.ndarray:
    """Points from ``0`` to ``outer``: spacing ``h`` up to ``inner``, then growing by ``growth``.

    The uniform part has ``round(inner / h)`` cells; the graded part starts at
    spacing ``h * growth`` and its last cell is stretched or merged so that the
    axis ends exactly at ``outer``.

    Parameters
    ----------
    h : float
        Spacing near the origin (m), > 0.
    inner : float
        Extent of the uniform part (m), ``0 <= inner <= outer``.
    outer : float
        End of the axis (m), > 0.
    growth : float
        Ratio of consecutive spacings in the graded part, ``>= 1``.
    """
    if not (h > 0 and 0 <= inner <= outer and outer > 0 and growth >= 1):
        raise ValueError(
            f"graded_axis needs h > 0, 0 <= inner <= outer, outer > 0 and growth >= 1; "
            f"got h={h!r}, inner={inner!r}, outer={outer!r}, growth={growth!r}"
        )
    n_uniform = int(round(inner / h))
    pts = list(h * np.arange(n_uniform + 1))
    step = h
    while pts[-1] < outer:
        step *= growth
        pts.append(pts[-1] + step)
    if len(pts) > 2 and (outer - pts[-2]) < 0.5 * (pts[-2] - pts[-3]):
        pts.pop(-2)  # merge a sliver last cell into its neighbour
    pts[-1] = outer
    return np.array(pts)


@dataclass(frozen=True, eq=False)
class CylinderOnFlatMesh:
    """Pad and flat meshes of the benchmark and their contact and boundary nodes.

    Attributes
    ----------
    pad, flat : skfem.MeshQuad
        The two bodies (m).
    pad_contact, flat_contact : ndarray of int, shape (nc,)
        Mesh nodes of the contact pairs, ordered by ``x``.
    pad_top : ndarray of int
        Pad nodes of the held face ``y = H_p``.
    flat_bottom : ndarray of int
        Flat nodes of the clamped face ``y = -D_f``.
    x : ndarray, shape (nc,)
        Abscissa of each pair (m).
    tributary : ndarray, shape (nc,)
        Tributary length of each pair along the flat's surface (m): half the sum
        of its two neighbouring spacings.
    gap : ndarray, shape (nc,)
        Initial gap ``g(x) = R - sqrt(R^2 - x^2)`` between the pad and the flat (m).
    """

    pad: MeshQuad
    flat: MeshQuad
    pad_contact: np.ndarray
    flat_contact: np.ndarray
    pad_top: np.ndarray
    flat_bottom: np.ndarray
    x: np.ndarray
    tributary: np.ndarray
    gap: np.ndarray

    @property
    def n_nodes(self) -> int:
        """Nodes of both bodies."""
        return self.pad.p.shape[1] + self.flat.p.shape[1]


def cylinder_on_flat_mesh(
    radius: float,
    window: float,
    contact_nodes: int,
    pad_half_width: float,
    pad_height: float,
    flat_half_width: float,
    flat_depth: float,
    growth: float = 1.25,
) -> CylinderOnFlatMesh:
    """Graded meshes of a cylindrical pad on a flat block.

    Parameters
    ----------
    radius : float
        Pad radius ``R`` (m), > 0.
    window : float
        Half-width ``x_w`` of the contact window (m), the extent of the node
        pairs; a few per cent wider than the contact, or wider still when wear
        will widen the scar. ``0 < x_w < W_p``.
    contact_nodes : int
        Node pairs across the window, ``>= 3``.
    pad_half_width, pad_height : float
        ``W_p < R`` and ``H_p > x_w`` (m).
    flat_half_width, flat_depth : float
        ``W_f >= W_p`` and ``D_f > x_w`` (m).
    growth : float
        Ratio of consecutive element sizes away from the window, in ``[1, 2]``.
    """
    checks = {
        "radius": radius > 0,
        "contact_nodes": isinstance(contact_nodes, (int, np.integer)) and contact_nodes >= 3,
        "window": 0 < window < pad_half_width,
        "pad_half_width": 0 < pad_half_width < radius,
        "pad_height": pad_height > window,
        "flat_half_width": flat_half_width >= pad_half_width,
        "flat_depth": flat_depth > window,
        "growth": 1 <= growth <= 2,
    }
    ranges = {
        "radius": "> 0 m",
        "contact_nodes": "an integer >= 3",
        "window": "in (0, pad_half_width) m",
        "pad_half_width": "in (0, radius) m",
        "pad_height": "> window m",
        "flat_half_width": ">= pad_half_width m",
        "flat_depth": "> window m",
        "growth": "in [1, 2]",
    }
    values = dict(radius=radius, contact_nodes=contact_nodes, window=window, pad_half_width=pad_half_width,
                  pad_height=pad_height, flat_half_width=flat_half_width, flat_depth=flat_depth,
                  growth=growth)  # fmt: skip
    for name, ok in checks.items():
        if not ok:
            raise ValueError(f"{name} must be {ranges[name]}, got {values[name]!r}")
    h = 2 * window / (contact_nodes - 1)
    x_window = np.linspace(-window, window, contact_nodes)

    def x_axis(half_width: float) -> np.ndarray:
        right = window + graded_axis(h, 0.0, half_width - window, growth)[1:]
        return np.concatenate([-right[::-1], x_window, right])

    depth = graded_axis(h, window, flat_depth, growth)
    height = graded_axis(h, window, pad_height, growth)

    xf = x_axis(flat_half_width)
    flat = MeshQuad.init_tensor(xf, -depth[::-1])
    xp = x_axis(pad_half_width)
    pad = MeshQuad.init_tensor(xp, height)
    # bend the pad's bottom onto the circle, keeping its top flat
    px, s = pad.p
    g = radius - np.sqrt(radius**2 - px**2)
    pad = MeshQuad(np.vstack([px, g * (1 - s / pad_height) + s]), pad.t)

    tol = 1e-9 * h

    def on_window(mesh: MeshQuad, y: float) -> np.ndarray:
        px, py = mesh.p
        idx = np.flatnonzero((np.abs(py - y) < tol) & (np.abs(px) <= window + tol))
        return idx[np.argsort(px[idx])]

    pad_contact = np.flatnonzero((np.abs(pad.p[1] - (radius - np.sqrt(radius**2 - pad.p[0] ** 2))) < tol)
                                 & (np.abs(pad.p[0]) <= window + tol))  # fmt: skip
    pad_contact = pad_contact[np.argsort(pad.p[0, pad_contact])]
    flat_contact = on_window(flat, 0.0)
    if len(pad_contact) != contact_nodes or len(flat_contact) != contact_nodes:
        raise RuntimeError("contact node search failed: the window columns of pad and flat do not match")
    cols = np.searchsorted(xf, x_window)
    tributary = 0.5 * (xf[cols + 1] - xf[cols - 1])
    return CylinderOnFlatMesh(
        pad=pad,
        flat=flat,
        pad_contact=pad_contact,
        flat_contact=flat_contact,
        pad_top=np.flatnonzero(np.abs(pad.p[1] - pad_height) < tol),
        flat_bottom=np.flatnonzero(np.abs(flat.p[1] + flat_depth) < tol),
        x=x_window,
        tributary=tributary,
        gap=radius - np.sqrt(radius**2 - x_window**2),
    )
