"""Compiled loops of the periodic solver: Newton's method and the piecewise-linear walk.

The algorithms are those documented in :mod:`fretwear.hbm.periodic` (:func:`~fretwear.hbm.periodic.newton`,
:func:`~fretwear.hbm.periodic.load_homotopy`, :func:`~fretwear.hbm.periodic.newton_homotopy`);
compiling the loops removes the Python overhead per iteration, which dominates
at the sizes of harmonic balance (a residual evaluation costs a few microseconds).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .dense import FASTMATH, lu_factor, lu_solve
from .dlft import boundary_distance, evaluate, jacobian_from_blocks

__all__ = ["newton_kernel", "walk_kernel"]

LOAD, NEWTON = 0, 1  # walk modes: load factor, global Newton homotopy
SINGULAR = 4  # code of newton_kernel: a singular Jacobian


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _residual(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, R, A, J, lam, X, state):
    # a run-time True: a literal would compile another version of evaluate
    evaluate(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, np.bool_(True), R, A, lam, X, state)
    jacobian_from_blocks(Z, eps, A, J)
    return np.abs(R).max()


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def newton_kernel(x0, Z, F, eps, kinds, limits, Phi, Psi, half_wave, target, max_iter):
    """Non-monotone Newton with a damped fallback from the best iterate.

    Returns ``(x, converged, iterations, max|R|, code)`` with ``code`` 0 on
    success, 1 non-finite step, 2 line search failed, 3 iteration budget, and
    ``(x0, False, 0, inf, SINGULAR)`` for a singular Jacobian.
    """
    n = x0.shape[0]
    nc = kinds.shape[0]
    Ns, H = Phi.shape
    R, Rt = np.empty(n), np.empty(n)
    A = np.empty((nc, H, H))
    J, Jt = np.empty((n, n)), np.empty((n, n))
    lam, X = np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    piv = np.empty(n, dtype=np.int64)
    x = x0.copy()
    r = _residual(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, R, A, J, lam, X, state)
    best_r, best_x = r, x.copy()
    it = 0
    damped = False
    while it < max_iter:
        if r <= target:
            return x, True, it, r, 0
        if lu_factor(J, piv) == 0:  # J is computed again before it is used again
            return x0.copy(), False, 0, np.inf, SINGULAR
        dx = -R
        lu_solve(J, piv, dx)
        if not np.all(np.isfinite(dx)):
            if damped:
                return x, False, it, r, 1
            damped = True
            x = best_x.copy()
            r = _residual(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, R, A, J, lam, X, state)
            continue
        it += 1
        if not damped:
            xt = x + dx
            rt = _residual(xt, Z, F, eps, kinds, limits, Phi, Psi, half_wave, Rt, A, Jt, lam, X, state)
            if np.isfinite(rt) and rt < 1e3 * best_r and it < max_iter // 2:
                x, r = xt, rt
                R[:] = Rt
                J[:, :] = Jt
                if r < best_r:
                    best_r, best_x = r, x.copy()
                continue
            damped = True
            x = best_x.copy()
            r = _residual(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, R, A, J, lam, X, state)
            continue
        step = 1.0
        accepted = False
        xt = x
        rt = r
        for _ in range(30):
            xt = x + step * dx
            rt = _residual(xt, Z, F, eps, kinds, limits, Phi, Psi, half_wave, Rt, A, Jt, lam, X, state)
            if rt < (1 - 1e-4 * step) * r:
                accepted = True
                break
            step *= 0.5
        if not accepted:
            return x, False, it, r, 2
        x, r = xt, rt
        R[:] = Rt
        J[:, :] = Jt
    if r <= target:
        return x, True, it, r, 0
    return x, False, it, r, 3


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _tangent(J, dR, row, orientation, aug, piv):
    """Unit tangent of ``[J dR]`` oriented as ``orientation`` (sign of ``det [J dR; t]``), and that sign.

    ``sign(det [J dR; t]) = sign(det [J dR; row])`` for ``t`` solving
    ``[J dR; row] t = e_n+1``, so one factorisation gives both; sign 0: singular.
    """
    n = J.shape[0]
    aug[:n, :n] = J
    aug[:n, n] = dR
    aug[n, :] = row
    t = np.zeros(n + 1)
    t[n] = 1.0
    sign = lu_factor(aug, piv)
    if sign == 0:
        return t, 0
    lu_solve(aug, piv, t)
    t /= np.sqrt(np.sum(t * t))
    if orientation != 0 and sign != orientation:
        t = -t
        sign = orientation
    return t, sign


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def walk_kernel(x0, p0, p_end, mode, Z, F, r0, eps, kinds, limits, Phi, Psi, half_wave, max_pieces,
                rec_x, rec_p, rec_s):  # fmt: skip
    """Follow the piecewise-linear solution curve from ``(x0, p0)`` to ``p = p_end``.

    ``mode`` LOAD: the forces are ``p F`` (``F`` at unit load); NEWTON: the
    residual is ``R(x) - (1 - p) r0`` at the forces ``F``. Returns
    ``(x, p, pieces, arrived, recorded)``; see :func:`fretwear.hbm.periodic.walk`.

    When ``rec_x`` has rows, the start of every piece is recorded: unknowns
    ``rec_x``, parameter ``rec_p`` and the distance slid per period by the first
    contact ``rec_s`` (m), which are linear in ``p`` within a piece; the end
    point is recorded last. ``recorded`` counts the rows filled.
    """
    n = x0.shape[0]
    nc = kinds.shape[0]
    Ns, H = Phi.shape
    R = np.empty(n)
    A = np.empty((nc, H, H))
    J = np.empty((n, n))
    lam, X = np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    E = np.empty(n)
    for c in range(nc):
        E[c * H : (c + 1) * H] = eps[c]
    x = x0.copy()
    p = p0
    row = np.zeros(n + 1)
    row[n] = 1.0
    orientation = 0.0
    dR = np.empty(n)
    n_rec = rec_x.shape[0]
    k = 0
    aug, piv = np.empty((n + 1, n + 1)), np.empty(n + 1, dtype=np.int64)
    blocks, no_blocks = np.bool_(True), np.bool_(False)  # not literals: one version of evaluate
    for piece in range(1, max_pieces + 1):
        Fp = p * F if mode == LOAD else F
        evaluate(x, Z, Fp, eps, kinds, limits, Phi, Psi, half_wave, blocks, R, A, lam, X, state)
        if k < n_rec - 1:
            rec_x[k] = x
            rec_p[k] = p
            rec_s[k] = _slid(X[0], half_wave)
            k += 1
        jacobian_from_blocks(Z, eps, A, J)
        if mode == LOAD:
            for c in range(nc):
                AF = A[c] @ F[c * H : (c + 1) * H]
                for j in range(H):
                    dR[c * H + j] = -(F[c * H + j] - AF[j])
        else:
            dR[:] = r0
        t, orientation = _tangent(J, dR, row, orientation, aug, piv)
        if orientation == 0:  # singular: the walk ends where it started
            return x0.copy(), p0, 0, False, 0
        tx = t[:n]
        reach = (p_end - p) / t[n] if t[n] > 0 else np.inf
        lu = Fp - Z @ x + E * x
        dlu = -(Z @ tx) + E * tx
        if mode == LOAD:
            dlu += t[n] * F
        tau = boundary_distance(lu, dlu, eps, kinds, limits, Phi, half_wave, min(reach, 1e300))
        if reach <= tau:
            x = x + reach * tx
            if n_rec > 0:
                Fe = p_end * F if mode == LOAD else F
                evaluate(x, Z, Fe, eps, kinds, limits, Phi, Psi, half_wave, no_blocks, R, A, lam, X, state)
                rec_x[k] = x
                rec_p[k] = p_end
                rec_s[k] = _slid(X[0], half_wave)
                k += 1
            return x, p_end, piece, True, k
        big = max(np.abs(x).max(), abs(p))
        step = tau * (1 + 1e-9) + 1e-13 * (big + 1e-300)
        x = x + step * tx
        p = p + step * t[n]
        row = t
    return x, p, max_pieces, False, k


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _slid(X, half_wave):
    """Distance slid per period from the slip variable of the march (m)."""
    n = X.shape[0]
    total = 0.0
    for s in range(n):
        prev = X[s - 1] if s > 0 else (-X[n - 1] if half_wave else X[n - 1])
        total += abs(X[s] - prev)
    return 2.0 * total if half_wave else total
