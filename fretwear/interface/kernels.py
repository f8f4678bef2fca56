"""Compiled Newton loop on the coupled interface DLFT residual (:mod:`fretwear.interface.contact`).

The residual is piecewise linear: once the stick/slip/separation pattern of
every sample is right, a full Newton step lands on the solution. On the way,
full steps may raise the residual while the pattern settles, so full steps
are taken while the residual stays within a factor 1000 of the best one seen,
for half the budget; then a backtracking line search restarts from the best
iterate (the same strategy as the single-contact solver of :mod:`fretwear.hbm`).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .contact import boundary_distance, evaluate, jacobian

__all__ = ["newton_kernel", "load_walk_kernel"]

# ``evaluate``'s Jacobian flag as a NumPy scalar: a Python literal would make Numba compile one more
# specialisation of it per literal value
_JACOBIAN = np.bool_(True)


@njit(cache=True, nogil=True)
def _residual(x, Z, F, eps, gap, mu, xref, Phi, Psi, R, A, J, lamT, lamN, X, state):
    evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, _JACOBIAN, R, A, lamT, lamN, X, state)
    jacobian(Z, eps, A, J)
    return np.abs(R).max()


@njit(cache=True, nogil=True)
def _newton_step(J, R, A, eps):
    """Solve ``J dx = -R``, eliminating the pairs whose block is the identity first.

    A pair closed and stuck all period at its reference slip variable has
    ``A_i = I``, so its rows of ``J`` are ``diag(eps)``: its step is ``-R / eps``
    and only the other pairs enter the dense solve (in partial slip the whole
    stick zone drops out).
    """
    nc, H2 = A.shape[0], A.shape[1]
    H = H2 // 2
    n = J.shape[0]
    fixed = np.zeros(nc, dtype=np.bool_)
    n_free = 0
    for i in range(nc):
        dev = 0.0
        for a in range(H2):
            for b in range(H2):
                dev = max(dev, abs(A[i, a, b] - (1.0 if a == b else 0.0)))
        fixed[i] = dev < 1e-12
        if not fixed[i]:
            n_free += H2
    if n_free == n:
        return np.linalg.solve(J, -R)
    dx = np.zeros(n)
    free = np.empty(n_free, dtype=np.int64)
    k = 0
    for i in range(nc):
        for a in range(H2):
            r = i * H2 + a
            if fixed[i]:
                dx[r] = -R[r] / (eps[2 * i] if a < H else eps[2 * i + 1])
            else:
                free[k] = r
                k += 1
    if n_free == 0:
        return dx
    rhs = -R - J @ dx
    Jr = np.empty((n_free, n_free))
    br = np.empty(n_free)
    for a in range(n_free):
        br[a] = rhs[free[a]]
        for b in range(n_free):
            Jr[a, b] = J[free[a], free[b]]
    sol = np.linalg.solve(Jr, br)
    for a in range(n_free):
        dx[free[a]] = sol[a]
    return dx


@njit(cache=True, nogil=True)
def newton_kernel(x0, Z, F, eps, gap, mu, xref, Phi, Psi, target, max_iter):
    """Newton's method from ``x0``: returns ``(x, converged, iterations, max|R|, code)``.

    ``code``: 0 converged, 1 non-finite step, 2 line search failed, 3 iteration budget.
    """
    n = x0.shape[0]
    nc = gap.shape[0]
    Ns, H = Phi.shape
    R, Rt = np.empty(n), np.empty(n)
    A = np.empty((nc, 2 * H, 2 * H))
    J, Jt = np.empty((n, n)), np.empty((n, n))
    lamT, lamN, X = np.empty((nc, Ns)), np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    x = x0.copy()
    r = _residual(x, Z, F, eps, gap, mu, xref, Phi, Psi, R, A, J, lamT, lamN, X, state)
    best_r, best_x = r, x.copy()
    it = 0
    damped = False
    while it < max_iter:
        if r <= target:
            return x, True, it, r, 0
        dx = _newton_step(J, R, A, eps)  # a singular J raises: the caller reports it
        if not np.all(np.isfinite(dx)):
            if damped:
                return x, False, it, r, 1
            damped = True
            x = best_x.copy()
            r = _residual(x, Z, F, eps, gap, mu, xref, Phi, Psi, R, A, J, lamT, lamN, X, state)
            continue
        it += 1
        if not damped:
            xt = x + dx
            rt = _residual(xt, Z, F, eps, gap, mu, xref, Phi, Psi, Rt, A, Jt, lamT, lamN, X, state)
            if np.isfinite(rt) and rt < 1e3 * best_r and it < max_iter // 2:
                x, r = xt, rt
                R[:] = Rt
                J[:, :] = Jt
                if r < best_r:
                    best_r, best_x = r, x.copy()
                continue
            damped = True
            x = best_x.copy()
            r = _residual(x, Z, F, eps, gap, mu, xref, Phi, Psi, R, A, J, lamT, lamN, X, state)
            continue
        step = 1.0
        accepted = False
        xt = x
        rt = r
        for _ in range(30):
            xt = x + step * dx
            rt = _residual(xt, Z, F, eps, gap, mu, xref, Phi, Psi, Rt, A, Jt, lamT, lamN, X, state)
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


@njit(cache=True, nogil=True)
def _tangent(J, dR, row, orientation):
    n = J.shape[0]
    aug = np.empty((n + 1, n + 1))
    aug[:n, :n] = J
    aug[:n, n] = dR
    aug[n, :] = row
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    t = np.linalg.solve(aug, rhs)
    t /= np.sqrt(np.sum(t * t))
    aug[n, :] = t
    sign = np.linalg.slogdet(aug)[0]
    if orientation != 0.0 and sign != orientation:
        t = -t
        sign = orientation
    return t, sign


@njit(cache=True, nogil=True)
def load_walk_kernel(x0, p0, Z, F_static, F_exc, eps, gap, mu, xref, Phi, Psi, max_pieces):
    """Follow the piecewise-linear solution curve in the excitation scale ``p`` from ``(x0, p0)`` to 1.

    The forces are ``F_static + p F_exc``; the residual is piecewise linear in
    ``(x, p)`` jointly, so its solution curve is a polygon: each piece goes
    along the null vector of ``[dR/dx, dR/dp]`` to the next state change
    (:func:`~fretwear.interface.contact.boundary_distance`) and just past it.
    The tangent keeps the sign of ``det [J dR/dp; t]``. Returns ``(x, p, pieces, arrived)``.
    """
    n = x0.shape[0]
    nc = gap.shape[0]
    Ns, H = Phi.shape
    R = np.empty(n)
    A = np.empty((nc, 2 * H, 2 * H))
    J = np.empty((n, n))
    lamT, lamN, X = np.empty((nc, Ns)), np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    E = np.empty(n)
    for c in range(2 * nc):
        E[c * H : (c + 1) * H] = eps[c]
    x = x0.copy()
    p = p0
    row = np.zeros(n + 1)
    row[n] = 1.0
    orientation = 0.0
    dR = np.empty(n)
    stalled = 0
    for piece in range(1, max_pieces + 1):
        Fp = F_static + p * F_exc
        evaluate(x, Z, Fp, eps, gap, mu, xref, Phi, Psi, _JACOBIAN, R, A, lamT, lamN, X, state)
        jacobian(Z, eps, A, J)
        for i in range(nc):
            r0 = 2 * i * H
            AF = A[i] @ F_exc[r0 : r0 + 2 * H]
            for j in range(2 * H):
                dR[r0 + j] = -(F_exc[r0 + j] - AF[j])
        t, orientation = _tangent(J, dR, row, orientation)
        tx = t[:n]
        reach = (1.0 - p) / t[n] if t[n] > 0 else np.inf
        lu = Fp - Z @ x + E * x
        dlu = -(Z @ tx) + E * tx + t[n] * F_exc
        tau = boundary_distance(lu, dlu, eps, gap, mu, xref, Phi, min(reach, 1e300))
        if reach <= tau:
            return x + reach * tx, 1.0, piece, True
        big = max(np.abs(x).max(), abs(p))
        nudge = 1e-13 * (big + 1e-300)
        # a vertex where several samples change state at once can send the walk back and forth between
        # their pieces without progress: each stalled piece steps ten times further past its boundary
        stalled = stalled + 1 if tau < nudge else 0
        step = tau * (1 + 1e-9) + nudge * 10.0 ** min(stalled, 8)
        x = x + step * tx
        p = p + step * t[n]
        row = t
    return x, p, max_pieces, False
