"""Contact states at an event of the event-driven march: the Coulomb law at acceleration level.

**Contact states at an event** (:func:`select`). The contacts at zero
relative velocity (stuck ones, the one whose velocity vanished, others within
round-off of zero) get their forces from the Coulomb law at acceleration
level: ``min 1/2 l^T W l - b^T l`` over ``|l_j| <= g_j``, ``W = B_Z M^-1 B_Z^T``
(the Delassus matrix), ``b = B_Z M^-1 r``: a unique solution (``W`` positive
definite). A contact strictly inside its cone sticks; one at its limit whose
relative acceleration points along its force beyond round-off slips that way.
A contact at its limit with zero relative acceleration (critical: stick
exactly at the limit, grazing) is decided at higher order: it slips if its
force guard is the one that triggered the event (a stick that must end at
once); otherwise it slips when the first derivative of its stuck force
(orders 1 to 3, on the pattern where every critical contact sticks) that is
not zero within round-off points out of the cone, and it sticks when it points
inwards or every derivative vanishes (a force held at the limit). A stuck
force that starts beyond the limit within that rule's tolerance (``5e-10``
of ``g_j``) is measured from where it starts (the guard is offset).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .codes import NEED_PATTERN, OK
from .dense import back_substitute, matmul_into, matvec_into
from .series import EPS_GUARD, dot

__all__ = ["select", "find_slot", "augmented", "delassus", "delassus_workspace", "project"]

_BAND = 1e-12  # a force this close to its limit counts as at the limit
_STICK_TOL = 5e-10  # critical contact: relative acceleration below this (force units, of g_j)
_RATE_TOL = 1e-11  # derivatives of a critical stuck force below this (of its scale) vanish


@njit(cache=True, nogil=True)
def _box_qp(W, b, g, L):
    """``min 1/2 x^T W x - b^T x`` subject to ``|x| <= g`` (``W = L L^T`` positive definite)."""
    z = b.shape[0]
    if z == 1:
        return np.array([min(max(b[0] / W[0, 0], -g[0]), g[0])])
    x = _chol_solve(L, b)
    for i in range(z):
        x[i] = min(max(x[i], -g[i]), g[i])
    gmax = g.max()
    for _ in range(10_000):  # projected Gauss-Seidel: converges for positive definite W
        change = 0.0
        for i in range(z):
            s = b[i]
            for k in range(z):
                s -= W[i, k] * x[k]
            xi = min(max(x[i] + s / W[i, i], -g[i]), g[i])
            change = max(change, abs(xi - x[i]))
            x[i] = xi
        if change <= 1e-15 * gmax:
            break
    # polish: exact solve on the identified active set, kept when consistent
    bound = np.abs(x) >= g * (1 - 1e-9)
    xp = np.zeros(z)
    nfree = 0
    for i in range(z):
        if bound[i]:
            xp[i] = g[i] if x[i] > 0 else -g[i]
        else:
            nfree += 1
    if nfree:
        idx = np.flatnonzero(~bound)
        Wf = np.empty((nfree, nfree))
        rhs = np.empty(nfree)
        for p in range(nfree):
            rhs[p] = b[idx[p]]
            for k in range(z):
                if bound[k]:
                    rhs[p] -= W[idx[p], k] * xp[k]
            for q in range(nfree):
                Wf[p, q] = W[idx[p], idx[q]]
        sol = _chol_solve(_cholesky(Wf), rhs)
        for p in range(nfree):
            xp[idx[p]] = sol[p]
    a = np.empty(z)
    matvec_into(W, xp, a)
    bscale = np.abs(b).max()
    for i in range(z):
        if bound[i]:
            if np.sign(xp[i]) * (b[i] - a[i]) < -1e-12 * bscale:
                return x
        elif abs(xp[i]) > g[i]:
            return x
    return xp


@njit(cache=True, nogil=True, inline="always")
def find_slot(masks, count, mask):
    for k in range(count):
        if masks[k] == mask:
            return k
    return -1


@njit(cache=True, nogil=True, inline="always")
def augmented(y, t, g, dirs, omega, nf, X):
    """Augmented state ``(u, v, lambda, 1, cos, sin)``.

    A rigid model's ``y = (u, v)``: the forces ``g d`` (zero for stuck and
    open contacts); a Jenkins model's ``y = (u, v, lambda)`` holds them.
    """
    ny = y.shape[0]
    n2 = X.shape[0] - nf - 3
    X[:ny] = y
    if ny == n2:
        for j in range(nf):
            X[n2 + j] = g[j] * dirs[j]
    X[n2 + nf] = 1.0
    X[n2 + nf + 1] = math.cos(omega * t)
    X[n2 + nf + 2] = math.sin(omega * t)


@njit(cache=True, nogil=True)
def _cholesky(W):
    """Lower Cholesky factor of the small positive definite ``W``."""
    z = W.shape[0]
    L = np.zeros((z, z))
    for i in range(z):
        for k in range(i + 1):
            s = W[i, k]
            for m in range(k):
                s -= L[i, m] * L[k, m]
            L[i, k] = math.sqrt(max(s, 1e-300)) if i == k else s / L[k, k]
    return L


@njit(cache=True, nogil=True)
def _chol_solve(L, b):
    """``W^-1 b`` from the Cholesky factor ``L`` of ``W``."""
    x = b.copy()
    _chol_solve_in_place(L, x)
    return x


@njit(cache=True, nogil=True)
def _chol_solve_in_place(L, x):
    """``x <- W^-1 x`` from the Cholesky factor ``L`` of ``W``."""
    for i in range(L.shape[0]):  # L y = x
        for m in range(i):
            x[i] -= L[i, m] * x[m]
        x[i] /= L[i, i]
    back_substitute(L.T, x)  # L^T x = y


@njit(cache=True, nogil=True)
def delassus_workspace(n, nf):
    """Room for :func:`delassus` with ``n`` DOFs and ``nf`` contacts: ``(mask held, idx, B_Z, M^-1 B_Z^T, W,
    L)`` at their largest, the mask -1 (none held yet)."""
    held, idx = np.full(1, -1, dtype=np.int64), np.empty(nf, dtype=np.int64)
    return held, idx, np.empty((nf, n)), np.empty((n, nf)), np.empty((nf, nf)), np.empty((nf, nf))


@njit(cache=True, nogil=True)
def delassus(Minv, B, mask, ws):
    """The contacts of ``mask`` (indices), ``B_Z``, ``M^-1 B_Z^T``, ``W = B_Z M^-1 B_Z^T`` and its Cholesky
    factor, as views of the workspace ``ws`` (:func:`delassus_workspace`).

    They depend on the set alone: computed only when ``mask`` is not the one
    ``ws`` holds (an event after an event of the same contacts allocates nothing).
    """
    held, idx, BZ, MiBt, W, L = ws
    nf, n = B.shape
    z = 0
    for j in range(nf):
        if mask >> j & 1:
            idx[z] = j
            z += 1
    if held[0] != mask:
        for p in range(z):
            BZ[p] = B[idx[p]]
        matmul_into(Minv, BZ[:z].T, MiBt[:, :z])
        matmul_into(BZ[:z], MiBt[:, :z], W[:z, :z])
        L[:z, :z] = _cholesky(W[:z, :z])
        held[0] = mask
    return idx[:z], BZ[:z], MiBt[:, :z], W[:z, :z], L[:z, :z]


@njit(cache=True, nogil=True)
def project(MiBt, BZ, L, V):
    """``V <- V - M^-1 B_Z^T W^-1 B_Z V`` column by column (M-orthogonal projection onto ``B_Z V = 0``)."""
    n, cols = V.shape
    z = BZ.shape[0]
    w = np.empty(z)
    for col in range(cols):
        for p in range(z):
            s = 0.0
            for m in range(n):
                s += BZ[p, m] * V[m, col]
            w[p] = s
        _chol_solve_in_place(L, w)
        for i in range(n):
            s = 0.0
            for p in range(z):
                s += MiBt[i, p] * w[p]
            V[i, col] -= s


@njit(cache=True, nogil=True)
def select(t, y, Z, forced, g, dirs, model, omega, patterns, ws):
    """Contact states at ``(t, y)`` for the contacts ``Z`` (bit mask) at zero relative velocity.

    See the module docstring for the rule. ``forced``: contacts whose force
    guard triggered the event; ``model``, ``patterns``: packed as
    :mod:`fretwear.time.codes` says; ``ws``: the workspace of :func:`delassus`.
    ``y``'s velocities are projected in place so that the contacts of ``Z``
    have exactly zero relative velocity (an M-orthogonal round-off correction).

    Returns ``(status, stuck mask, directions, need)``.
    """
    Minv, B, C, Kmat, F, _ = model
    masks, Ah, force_rows, _, _, _, count = patterns
    n, nf = Minv.shape[0], B.shape[0]
    out = dirs.copy()
    if Z == 0:
        return OK, 0, out, 0
    idx, BZ, MiBt, W, L = delassus(Minv, B, Z, ws)
    z = idx.size
    project(MiBt, BZ, L, y[n:].reshape((n, 1)))
    co, si = math.cos(omega * t), math.sin(omega * t)
    r = np.empty(n)
    for i in range(n):
        s = F[i, 0] + F[i, 1] * co + F[i, 2] * si
        for m in range(n):
            s -= C[i, m] * y[n + m] + Kmat[i, m] * y[m]
        for j in range(nf):
            if not (Z >> j & 1):
                s -= B[j, i] * g[j] * dirs[j]
        r[i] = s
    b = np.empty(z)
    gz = np.empty(z)
    for p in range(z):
        s = 0.0
        for i in range(n):
            s += MiBt[i, p] * r[i]
        b[p] = s
        gz[p] = g[idx[p]]
    lam = _box_qp(W, b, gz, L)
    rscale = np.abs(r).sum()
    stuck = 0
    critical = 0
    for p in range(z):
        j = idx[p]
        acc = b[p]
        for q in range(z):
            acc -= W[p, q] * lam[q]
        sgn = 1 if lam[p] > 0 else -1
        if abs(lam[p]) < g[j] * (1 - _BAND):
            stuck |= 1 << j
            out[j] = 0
        elif sgn * acc / W[p, p] > _STICK_TOL * g[j] + EPS_GUARD * rscale:
            out[j] = sgn
        elif forced >> j & 1:
            out[j] = sgn
        else:
            critical |= 1 << j
            out[j] = sgn
    if critical:
        trial = stuck | critical
        k = find_slot(masks, count, trial)
        if k < 0:
            return NEED_PATTERN, 0, out, trial
        D = Ah.shape[1]
        X = np.empty(D)
        tmp = out.copy()
        for j in range(nf):
            if trial >> j & 1:
                tmp[j] = 0
        augmented(y, t, g, tmp, omega, nf, X)
        c = np.empty((4, D))
        c[0] = X
        for q in range(1, 4):
            matvec_into(Ah[k], c[q - 1], c[q])
            c[q] /= q
        for p in range(z):
            j = idx[p]
            if not (critical >> j & 1):
                continue
            row = force_rows[k, j]
            scale = g[j] + dot(row, X, 0, D)[1]
            decided = False
            for q in range(1, 4):
                rate = dot(row, c[q], 0, D)[0]
                if abs(rate) > _RATE_TOL * scale:
                    decided = True
                    if out[j] * rate <= 0:  # inwards: stick
                        stuck |= 1 << j
                        out[j] = 0
                    break
            if not decided:  # held at the limit
                stuck |= 1 << j
                out[j] = 0
    return OK, stuck, out, 0
