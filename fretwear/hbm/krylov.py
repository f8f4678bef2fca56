"""The Newton step of the pair laws by GMRES on the mixed coordinates: no dense factorisation (compiled).

:func:`fretwear.hbm.structured.structured_step` eliminates the fixed and open
contact coordinates exactly and factors the dense mixed system

    K dx_M = [(I - A)_MP S_PM + (A E)_MM] dx_M = b_M

of ``nM H`` unknowns (the slip annulus' coordinates, ``H = 2 Nh + 1``): at
523 pairs of the sphere (2 838 unknowns) half of each step. Here the same
system is solved by right-preconditioned restarted GMRES, matrix-free:

* ``K v``: ``S_PM v`` harmonic by harmonic from the complex Schur complement
  by harmonic (``S`` couples no two harmonics: ``(Nh + 1) nP nM`` products),
  then per pair ``u - A_i (u - E v)`` on its ``d H`` unknowns (the law is local);
* the preconditioner ``P``: ``K`` with every law block ``A_i`` replaced by its
  harmonic-diagonal, complex-linear part, the same for all harmonics when
  the law's tangent is constant in time (``A = Psi G Phi``: the period's mean of
  ``G``). ``P`` couples no two harmonics either: ``Nh + 1`` dense complex
  systems of ``nM`` unknowns, inverted once a step (``(Nh + 1) nM^3`` against
  ``(nM H)^3 / 3`` for ``K``'s LU: ~40 times less at ``Nh = 5``). It is exact
  for a pair in one state all period; the pairs that change state within the
  period (the stick/slip boundary) are left to GMRES.

The step is an inexact Newton direction: GMRES stops at a residual ``atol``
(N, 2-norm of the mixed rows, which is the whole step's linear residual: the
other rows are solved exactly) that the caller sets (the forcing term of
:func:`fretwear.hbm.newton.newton`). If GMRES has not reached it after
:data:`MAX_ITERATIONS` products, or the preconditioner is singular, the step
falls back to the exact one (the dense LU of ``K``), and the counters say so.
Below ``krylov_min`` mixed unknowns the exact step is taken at once: the LU is
then cheaper than building the preconditioner.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .structured import (
    MIXED,
    back_substitute,
    classify,
    mixed_matrix,
    mixed_rhs,
    partition,
    reduce_rhs,
    schur,
)

__all__ = [
    "KRYLOV_MIN", "MAX_ITERATIONS", "RESTART", "STEPS", "ITERATIONS", "FALLBACKS", "EXACT", "REUSED",
    "COUNTERS", "harmonic_part", "preconditioner", "mixed_matvec", "gmres", "empty_cache", "cached_step",
    "krylov_step",
]  # fmt: skip

#: default size of the mixed system (``nM H`` unknowns) from which the step is taken by GMRES: below it the
#: LU costs about as much (``benchmarks/bench_interface_scale.py``: whole solves equal within 10 % at 450 on
#: the cylinder, GMRES 1.9 times faster at 1 540 on the sphere) and the exact step is the reference
KRYLOV_MIN = 1500
#: products ``K v`` at most per step before the fallback to the exact step
MAX_ITERATIONS = 200
#: Krylov basis size before a restart
RESTART = 60
#: entries of the counters ``stats`` (int64 array of ``COUNTERS``): GMRES steps taken, their products ``K v``,
#: steps that fell back to the exact solve after GMRES stalled (or a singular preconditioner), exact steps by
#: choice (small systems), steps that reused the last one's Schur complement (the same kinds)
STEPS, ITERATIONS, FALLBACKS, EXACT, REUSED = 0, 1, 2, 3, 4
COUNTERS = 5


@njit(cache=True, nogil=True)
def harmonic_part(A, i, a, b, k, H):
    """The complex-linear part of the ``(k, k)`` block of ``A[i]`` from coordinate ``b`` to ``a`` (-): ``A``'s
    real 2 x 2 block ``[[p, q], [r, t]]`` on (cosine, sine) read as ``(p + t) / 2 + i (r - q) / 2`` (the
    real form of a complex factor is ``[[Re, -Im], [Im, Re]]``); real at ``k = 0``."""
    if k == 0:
        return complex(A[i, a * H, b * H], 0.0)
    rc, rs, cc, cs = a * H + 2 * k - 1, a * H + 2 * k, b * H + 2 * k - 1, b * H + 2 * k
    return complex(0.5 * (A[i, rc, cc] + A[i, rs, cs]), 0.5 * (A[i, rs, cc] - A[i, rc, cs]))


@njit(cache=True, nogil=True)
def preconditioner(Sc, A, eps, kind, Mi, posM, posP):
    """The inverses (Nh + 1, nM, nM) (m/N) of the harmonic-diagonal mixed systems (module text)."""
    K, nM = Sc.shape[0], Sc.shape[2]
    H = 2 * K - 1
    d = A.shape[1] // H
    Pinv = np.empty((K, nM, nM), dtype=np.complex128)
    for k in range(K):
        P = np.empty((nM, nM), dtype=np.complex128)
        for mc in range(nM):
            c = Mi[mc]
            i, a = c // d, c % d
            P[mc] = Sc[k, posP[c]]
            for b in range(d):
                e = d * i + b
                z = harmonic_part(A, i, a, b, k, H)
                if z != 0:
                    P[mc] -= z * Sc[k, posP[e]]
                    if kind[e] == MIXED:
                        P[mc, posM[e]] += z * eps[e]
        Pinv[k] = np.linalg.inv(P)
    return Pinv


@njit(cache=True, nogil=True)
def _to_harmonics(v, n, H):
    """Slots ``v`` (n H,) of ``n`` coordinates as complex amplitudes (Nh + 1, n)."""
    K = (H + 1) // 2
    out = np.empty((K, n), dtype=np.complex128)
    for m in range(n):
        out[0, m] = v[m * H]
        for k in range(1, K):
            out[k, m] = complex(v[m * H + 2 * k - 1], v[m * H + 2 * k])
    return out


@njit(cache=True, nogil=True)
def _from_harmonics(z, H):
    """Complex amplitudes (Nh + 1, n) as slots (n H,) (the inverse of :func:`_to_harmonics`)."""
    K, n = z.shape
    v = np.empty(n * H)
    for m in range(n):
        v[m * H] = z[0, m].real
        for k in range(1, K):
            v[m * H + 2 * k - 1], v[m * H + 2 * k] = z[k, m].real, z[k, m].imag
    return v


@njit(cache=True, nogil=True)
def _precondition(Pinv, v):
    """``P^-1 v`` harmonic by harmonic (m)."""
    K, nM = Pinv.shape[0], Pinv.shape[1]
    z = _to_harmonics(v, nM, 2 * K - 1)
    for k in range(K):
        z[k] = Pinv[k] @ z[k]
    return _from_harmonics(z, 2 * K - 1)


@njit(cache=True, nogil=True)
def mixed_matvec(Sc, A, eps, kind, Mi, posM, posP, v):
    """``K v`` (nM H,) (N) for ``v`` (nM H,) (m) on the mixed coordinates, never forming ``K`` (module)."""
    K, nP, nM = Sc.shape
    H = 2 * K - 1
    d = A.shape[1] // H
    z = _to_harmonics(v, nM, H)
    u = np.empty((K, nP), dtype=np.complex128)
    for k in range(K):
        u[k] = Sc[k] @ z[k]
    us = _from_harmonics(u, H)  # S_PM v in slots, (nP H,)
    y = np.empty(nM * H)
    U, D = np.empty(d * H), np.empty(d * H)
    mc = 0
    while mc < nM:
        i = Mi[mc] // d
        for b in range(d):
            e = d * i + b
            for r in range(H):
                U[b * H + r] = us[posP[e] * H + r]
                D[b * H + r] = U[b * H + r] - (eps[e] * v[posM[e] * H + r] if kind[e] == MIXED else 0.0)
        AD = A[i] @ D
        while mc < nM and Mi[mc] // d == i:
            a = Mi[mc] % d
            for r in range(H):
                y[mc * H + r] = U[a * H + r] - AD[a * H + r]
            mc += 1
    return y


@njit(cache=True, nogil=True)
def gmres(Sc, A, eps, kind, Mi, posM, posP, Pinv, b, atol, max_iter, restart):
    """Right-preconditioned restarted GMRES on ``K x = b`` from ``x = 0``.

    Returns ``(x, products, |b - K x|)`` (2-norm, N, recomputed from ``x``); stops when that is at most
    ``atol`` or after ``max_iter`` products ``K v``. Modified Gram-Schmidt applied twice (a Krylov basis
    orthogonal to rounding), Givens rotations.
    """
    n = b.shape[0]
    x = np.zeros(n)
    r = b.copy()
    beta = np.sqrt(np.sum(r * r))
    m = min(restart, n)
    V = np.empty((m + 1, n))
    Hs = np.zeros((m + 1, m))
    cs, sn, gv = np.empty(m), np.empty(m), np.empty(m + 1)
    products = 0
    while beta > atol and products < max_iter:
        V[0] = r / beta
        gv[:] = 0.0
        gv[0] = beta
        j_end = 0
        for j in range(m):
            w = mixed_matvec(Sc, A, eps, kind, Mi, posM, posP, _precondition(Pinv, V[j]))
            products += 1
            for _sweep in range(2):
                for i in range(j + 1):
                    h = np.dot(w, V[i])
                    Hs[i, j] += h
                    w -= h * V[i]
            Hs[j + 1, j] = np.sqrt(np.sum(w * w))
            for i in range(j):  # the previous rotations on the new column
                t = cs[i] * Hs[i, j] + sn[i] * Hs[i + 1, j]
                Hs[i + 1, j] = -sn[i] * Hs[i, j] + cs[i] * Hs[i + 1, j]
                Hs[i, j] = t
            den = np.hypot(Hs[j, j], Hs[j + 1, j])
            if den == 0.0:  # an exact zero column: K P^-1 singular on the basis
                break
            cs[j], sn[j] = Hs[j, j] / den, Hs[j + 1, j] / den
            hj1 = Hs[j + 1, j]
            Hs[j, j], Hs[j + 1, j] = den, 0.0
            gv[j + 1] = -sn[j] * gv[j]
            gv[j] = cs[j] * gv[j]
            j_end = j + 1
            if abs(gv[j + 1]) <= atol or products >= max_iter or hj1 == 0.0:
                break
            V[j + 1] = w / hj1
        if j_end == 0:
            break
        y = np.empty(j_end)  # back substitution on the rotated Hessenberg matrix
        for i in range(j_end - 1, -1, -1):
            y[i] = (gv[i] - np.dot(Hs[i, i + 1 : j_end], y[i + 1 :])) / Hs[i, i]
        x += _precondition(Pinv, V[:j_end].T @ y)
        r = b - mixed_matvec(Sc, A, eps, kind, Mi, posM, posP, x)
        beta = np.sqrt(np.sum(r * r))
        Hs[:, :] = 0.0
    return x, products, beta


@njit(cache=True, nogil=True)
def empty_cache():
    """The cache of :func:`cached_step` before the first step: no kinds, so the first step fills it."""
    e, c3 = np.empty(0, dtype=np.int64), np.empty((0, 0, 0), dtype=np.complex128)
    return (e, e, e, e, e, e, e), c3, c3, c3


@njit(cache=True, nogil=True)
def cached_step(Zb, A, R, eps, dx, atol, krylov_min, stats, cache):
    """:func:`krylov_step` that keeps the elimination's part that depends on ``Z`` and the kinds alone
    (:func:`fretwear.hbm.structured.schur`: ``Z_OO^-1``, the Schur complement) for the next step: a Newton
    step whose coordinates keep their kinds (fixed, open, mixed) costs products, no factorisation, of
    ``Z``'s blocks. ``cache``: :func:`empty_cache`'s or the last step's, with the same ``Zb``. Returns
    ``(linear residual, cache)``."""
    H = 2 * Zb.shape[0] - 1
    d = A.shape[1] // H
    kind = classify(A, d)
    part, Zinv, G, Sc = cache
    if part[0].shape[0] == kind.shape[0] and np.all(part[0] == kind):
        stats[REUSED] += 1
    else:
        part = partition(kind, d)
        Zinv, G, Sc = schur(Zb, part)
    kind, Fi, Oi, Mi, Pi, posM, posP = part
    g, w = reduce_rhs(Zb, part, Zinv, R, eps, dx)
    nM = Mi.shape[0]
    res = 0.0
    if nM > 0:
        rhs = mixed_rhs(A, R, eps, dx, kind, Mi, posP, g)
        dxM = np.empty(0)
        ok = False
        if nM * H >= krylov_min and atol > 0:
            stats[STEPS] += 1
            Pinv = np.empty((0, 0, 0), dtype=np.complex128)
            try:
                Pinv = preconditioner(Sc, A, eps, kind, Mi, posM, posP)
            except Exception:  # noqa: BLE001 - a singular preconditioner: the exact step
                pass
            if Pinv.shape[0] > 0:
                dxM, products, res = gmres(Sc, A, eps, kind, Mi, posM, posP, Pinv, rhs, atol, MAX_ITERATIONS,
                                           RESTART)  # fmt: skip
                stats[ITERATIONS] += products
                ok = res <= atol and np.all(np.isfinite(dxM))
            if not ok:
                stats[FALLBACKS] += 1
        else:
            stats[EXACT] += 1
        if not ok:
            dxM = np.linalg.solve(mixed_matrix(Sc, A, eps, kind, Mi, posM, posP), rhs)
            res = 0.0
        for mc in range(nM):
            dx[Mi[mc] * H : (Mi[mc] + 1) * H] = dxM[mc * H : (mc + 1) * H]
    back_substitute(dx, Oi, Mi, G, w)
    return res, (part, Zinv, G, Sc)


@njit(cache=True, nogil=True)
def krylov_step(Zb, A, R, eps, dx, atol, krylov_min, stats):
    """The Newton step ``J dx = -R`` of a pair law with GMRES on the mixed coordinates (module text).

    Parameters
    ----------
    Zb, A, R, eps, dx
        As :func:`fretwear.hbm.structured.structured_step`'s (``dx`` out, m).
    atol : float
        The step's largest linear residual ``|J dx + R|`` (N, 2-norm); the exact step at 0.
    krylov_min : int
        Mixed unknowns ``nM H`` from which GMRES is used; below, the exact step.
    stats : (COUNTERS,) int64, accumulated: GMRES steps, their products, fallbacks to the exact step, exact
        steps by choice, reused eliminations (:data:`STEPS` ...).

    Returns the linear residual reached (N, 2-norm of the mixed rows; 0 for an exact step).
    """
    return cached_step(Zb, A, R, eps, dx, atol, krylov_min, stats, empty_cache())[0]
