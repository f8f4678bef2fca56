"""Compiled Newton loop and piecewise-linear walk on the interface DLFT law (``fretwear.hbm.coupled``).

Both are written once for every contact law in ``fretwear.hbm.newton``
(non-monotone Newton; the exact piecewise-linear walk); these are their calls
with the coupled normal/tangential law of the interface's node pairs, and the residual of either pair law
(coupled, or the 2-D friction law) from ``Z``'s harmonic blocks (:func:`evaluate_kernel`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..hbm.dense import FASTMATH
from ..hbm.newton import cone_law, coupled_law, evaluate_blocks, newton, walk

__all__ = ["newton_kernel", "walk_kernel", "evaluate_kernel"]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def newton_kernel(x0, Z, F, eps, gap, mu, xref, Phi, Psi, target, max_iter, blocks=None):
    """Newton's method from ``x0``: returns ``(x, converged, iterations, max|R|, code)``.

    ``code``: 0 converged, 1 non-finite step, 2 line search failed, 3 iteration
    budget; a singular Jacobian raises (LAPACK), for the caller to report.
    ``blocks``: ``Z`` by harmonic (``fretwear.hbm.structured.harmonic_blocks()``) for the
    structured steps (no dense Jacobian), else the dense steps.
    """
    return newton(coupled_law(gap, mu, xref, Phi, Psi), x0, Z, F, eps, target, max_iter, blocks)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def walk_kernel(x0, p0, Z, F0, F1, r0, eps, gap, mu, xref, Phi, Psi, max_pieces):
    """Follow the piecewise-linear solution curve of ``R(x; F0 + p F1) = (1 - p) r0`` from ``(x0, p0)`` to 1.

    The load walk has ``F0`` the static load, ``F1`` the excitation and
    ``r0 = 0``; the Newton homotopy has ``F0`` the full load, ``F1 = 0`` and
    ``r0 = R(x0)``. The residual is piecewise linear in ``(x, p)`` jointly, so
    its solution curve is a polygon (:func:`fretwear.hbm.newton.walk`).
    Returns ``(x, p, pieces, arrived)``.
    """
    none = np.empty((0, x0.shape[0]))
    x, p, pieces, arrived, _ = walk(
        coupled_law(gap, mu, xref, Phi, Psi), x0, p0, 1.0, Z, F0, F1, r0, eps, max_pieces,
        none, np.empty(0), np.empty(0),
    )  # fmt: skip
    return x, p, pieces, arrived


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def evaluate_kernel(x, Zb, F, eps, gap, mu, xref, Phi, Psi, want_blocks, R, A, lamT, lamN, X, state):
    """The law's residual (eq. 12) into ``R`` and, with ``want_blocks``, its blocks into ``A``, with ``Z``
    given by its harmonic blocks ``Zb`` (:func:`fretwear.hbm.newton.evaluate_blocks`); the arguments as
    :func:`fretwear.hbm.coupled.evaluate`'s, or :func:`fretwear.hbm.cone.evaluate`'s for ``xref`` (nc, 2)."""
    law = cone_law(gap, mu, xref, Phi, Psi) if xref.ndim == 2 else coupled_law(gap, mu, xref, Phi, Psi)
    evaluate_blocks(law, x, Zb, F, eps, want_blocks, R, A, lamT, lamN, X, state)
