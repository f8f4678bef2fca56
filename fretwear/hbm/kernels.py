"""Compiled loops of the periodic solver of the 1-D DLFT law: Newton's method and the piecewise-linear walk.

The algorithms are those documented in ``fretwear.hbm.periodic`` (:func:`~fretwear.hbm.periodic.newton`,
:func:`~fretwear.hbm.periodic.load_homotopy`, :func:`~fretwear.hbm.periodic.newton_homotopy`),
written once for every contact law in ``fretwear.hbm.newton``; these are
its calls with the law of ``fretwear.hbm.dlft``. Compiling the loops
removes the Python overhead per iteration, which dominates at the sizes of
harmonic balance (a residual evaluation costs a few microseconds).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .dense import FASTMATH
from .newton import SINGULAR, dlft_law, newton, walk

__all__ = ["newton_kernel", "walk_kernel", "LOAD", "NEWTON", "SINGULAR"]

LOAD, NEWTON = 0, 1  # walk modes: load factor, global Newton homotopy


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def newton_kernel(x0, Z, F, eps, kinds, limits, Phi, Psi, half_wave, target, max_iter):
    """Non-monotone Newton with a damped fallback from the best iterate (:func:`fretwear.hbm.newton.newton`).

    Returns ``(x, converged, iterations, max|R|, code)`` with ``code`` 0 on
    success, 1 non-finite step, 2 line search failed, 3 iteration budget, and
    ``(x0, False, 0, inf, SINGULAR)`` for a singular Jacobian.
    """
    return newton(dlft_law(kinds, limits, Phi, Psi, half_wave), x0, Z, F, eps, target, max_iter)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def walk_kernel(x0, p0, p_end, mode, Z, F, r0, eps, kinds, limits, Phi, Psi, half_wave, max_pieces,
                rec_x, rec_p, rec_s):  # fmt: skip
    """Follow the piecewise-linear solution curve from ``(x0, p0)`` to ``p = p_end``.

    ``mode`` LOAD: the forces are ``p F`` (``F`` at unit load); NEWTON: the
    residual is ``R(x) - (1 - p) r0`` at the forces ``F``. Returns
    ``(x, p, pieces, arrived, recorded)``; see :func:`fretwear.hbm.newton.walk`
    (``rec_s``: the distance slid per period by the first contact, m).
    """
    zero, Fc = np.zeros(x0.shape[0]), F.copy()  # copies: one array type in both modes
    F0, F1, offset = (zero, Fc, zero) if mode == LOAD else (Fc, zero, r0.copy())
    law = dlft_law(kinds, limits, Phi, Psi, half_wave)
    return walk(law, x0, p0, p_end, Z, F0, F1, offset, eps, max_pieces, rec_x, rec_p, rec_s)
