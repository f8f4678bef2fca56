"""Polynomials of one step of the event-driven march, and the certified location of a guard's first crossing.

The motion within a stick pattern is propagated by the Taylor series of
:mod:`fretwear.time.patterns` (step ``h_S``, ``K = TAYLOR_ORDER`` terms, tail
below round-off). On a step the augmented state is the polynomial
``X(sigma) = sum_k c_k sigma^k``, ``sigma = s / h_S``, ``c_k = (A_S h_S)^k X / k!``,
and every guard function ``p(sigma) = sum_k a_k sigma^k`` is a polynomial of
known coefficients:

* a stuck contact ``j``: ``g_j - lambda_j`` and ``g_j + lambda_j`` (its
  stuck force within the slip limit ``g_j = mu_j F_N,j``);
* a slipping contact: ``d_j du_r,j/dt`` (its relative velocity keeps the
  slip direction ``d_j``).

The same for Jenkins contacts, whose stuck force is the state entry ``lambda_j``.

**Event location** (:func:`first_crossing`). An event is the first time a
guard falls below ``-eps`` (``eps = 1e-13`` of the guard's round-off scale),
located at the zero of the guard at the start of that descent. The search is
certified: from the left end ``lo`` of the part not yet cleared,
``p(lo + delta) >= p + p' delta + (p''/2 - M3 w/6) delta^2`` on ``[0, w]``,
``M3 = sum_k k (k-1) (k-2) |a_k|`` a bound of the third derivative over the
step, so the interval up to the first crossing of ``-eps`` by that quadratic
is cleared; a crossing is bracketed once ``p < -eps`` at the end of an
interval where ``p'`` is certified negative (exactly one crossing), and
refined by safeguarded Newton to round-off (``~1e-16`` of a step). No
excursion deeper than ``eps`` is missed, however short; shallower ones
(tangencies within round-off) are by rule not events.
"""

from __future__ import annotations

import math

from numba import njit

from .patterns import TAYLOR_ORDER

__all__ = [
    "K",
    "EPS_GUARD",
    "taylor_series",
    "state_at",
    "row_series",
    "dot",
    "poly",
    "poly2",
    "first_crossing",
]

K = TAYLOR_ORDER
EPS_GUARD = 1e-13  # event threshold of a guard, relative to its round-off scale


@njit(cache=True, nogil=True)
def taylor_series(Ah, X, c, n):
    """``c[k] = (A h)^k X / k!`` for ``k = 0..K``, using the structure of ``A`` (:mod:`.patterns`).

    ``u' = v``; only the velocity rows are full; the forces ``lambda`` depend
    on ``v`` only (zero rows but for stuck Jenkins contacts); ``1`` is
    constant; ``(cos, sin)`` rotate.
    """
    D = X.shape[0]
    i_one = D - 3
    c[0, :] = X
    for k in range(1, K + 1):
        inv = 1.0 / k
        for i in range(n):
            c[k, i] = Ah[i, n + i] * c[k - 1, n + i] * inv
        hi = D if k == 1 else i_one  # beyond the first term the constant 1 contributes nothing
        for i in range(n, 2 * n):
            s = 0.0
            for m in range(hi):
                s += Ah[i, m] * c[k - 1, m]
            if k > 1:
                for m in range(i_one + 1, D):
                    s += Ah[i, m] * c[k - 1, m]
            c[k, i] = s * inv
        for i in range(2 * n, i_one):
            s = 0.0
            for m in range(n, 2 * n):
                s += Ah[i, m] * c[k - 1, m]
            c[k, i] = s * inv
        c[k, i_one] = 0.0
        c[k, i_one + 1] = Ah[i_one + 1, i_one + 2] * c[k - 1, i_one + 2] * inv
        c[k, i_one + 2] = Ah[i_one + 2, i_one + 1] * c[k - 1, i_one + 1] * inv


@njit(cache=True, nogil=True, inline="always")
def state_at(c, sigma, out):
    """``X(sigma) = sum_k c[k] sigma^k`` (Horner)."""
    out[:] = c[K]
    for k in range(K - 1, -1, -1):
        for i in range(out.shape[0]):
            out[i] = out[i] * sigma + c[k, i]


@njit(cache=True, nogil=True, inline="always")
def row_series(row, c, lo, hi, scale, a):
    """``a[k] = scale * row[lo:hi] . c[k, lo:hi]``."""
    for k in range(K + 1):
        s = 0.0
        for m in range(lo, hi):
            s += row[m - lo] * c[k, m]
        a[k] = scale * s


@njit(cache=True, nogil=True, inline="always")
def dot(a, b, lo, hi):
    """``a[: hi - lo] . b[lo:hi]`` and ``|a| . |b|`` (value and round-off scale)."""
    s = 0.0
    m = 0.0
    for i in range(lo, hi):
        t = a[i - lo] * b[i]
        s += t
        m += abs(t)
    return s, m


@njit(cache=True, nogil=True, inline="always")
def poly(a, x):
    """Value and derivative of ``sum_k a[k] x^k``."""
    p = a[K]
    d = 0.0
    for k in range(K - 1, -1, -1):
        d = d * x + p
        p = p * x + a[k]
    return p, d


@njit(cache=True, nogil=True)
def _refine(a, shift, lo, hi):
    """Root of the decreasing ``p + shift`` on ``[lo, hi]`` (``> 0`` at ``lo``, ``< 0`` at ``hi``)."""
    x = lo
    for _ in range(100):
        p, d = poly(a, x)
        p += shift
        if p > 0:
            lo = x
        elif p < 0:
            hi = x
        else:
            return x
        xn = x - p / d if d < 0 else 0.5 * (lo + hi)
        if not lo <= xn <= hi:
            xn = 0.5 * (lo + hi)
        if abs(xn - x) <= 2e-16 * max(abs(x), 1e-300) or hi - lo <= 2e-16 * max(hi, 1e-300):
            return xn
        x = xn
    return x


@njit(cache=True, nogil=True, inline="always")
def poly2(a, x):
    """Value, first and second derivative of ``sum_k a[k] x^k``."""
    p = a[K]
    d = 0.0
    dd = 0.0
    for k in range(K - 1, -1, -1):
        dd = dd * x + d
        d = d * x + p
        p = p * x + a[k]
    return p, d, 2.0 * dd


@njit(cache=True, nogil=True, inline="always")
def _quadratic_reach(q0, d1, c):
    """First positive root of ``q0 + d1 x + c x^2`` (``q0 >= 0``), ``inf`` if none."""
    if c == 0.0:
        return -q0 / d1 if d1 < 0 else math.inf
    disc = d1 * d1 - 4 * c * q0
    if disc < 0:
        return math.inf
    sq = math.sqrt(disc)
    qq = -0.5 * (d1 + (sq if d1 >= 0 else -sq))  # the roots are qq / c and q0 / qq, without cancellation
    root = math.inf
    if qq != 0:
        r = qq / c
        if 0 <= r < root:
            root = r
        r = q0 / qq
        if 0 <= r < root:
            root = r
    return root


@njit(cache=True, nogil=True)
def first_crossing(a, eps, start, smax):
    """First ``sigma`` in ``[start, smax]`` where ``p(sigma) = sum_k a[k] sigma^k`` falls below ``-eps``.

    Certified advance from the left: at ``lo``, for ``delta`` in ``[0, w]``,
    ``p(lo + delta) >= p + p' delta + (p'' / 2 - M3 w / 6) delta^2`` with
    ``M3`` a bound of the third derivative on ``[0, smax]``; up to the first
    crossing of ``-eps`` by that quadratic there is no crossing. A crossing is
    bracketed when ``p`` is below ``-eps`` at the end of an interval on which
    the derivative is certified negative (a unique crossing) and refined by
    safeguarded Newton. Returns the zero of ``p`` at the start of that descent
    (of ``p + eps`` when ``p`` was already within ``(-eps, 0]`` there), or
    ``-1`` when ``p >= -eps`` on the whole interval. A tangency within
    round-off of ``-eps`` (no progress at ``1e-16`` of the step) is not an event.
    """
    if start == 0.0:
        tail = 0.0
        x = 1.0
        for k in range(1, K + 1):
            x *= smax
            tail += abs(a[k]) * x
        if a[0] - tail > -eps:
            return -1.0
    m3 = 0.0
    x = 1.0
    for k in range(3, K + 1):
        m3 += k * (k - 1) * (k - 2) * abs(a[k]) * x
        x *= smax
    lo = start
    for _ in range(100_000):
        rem = smax - lo
        if rem <= 0:
            return -1.0
        p0, d1, d2 = poly2(a, lo)
        q0 = p0 + eps
        if q0 < 0:
            return lo
        w = min(rem, _quadratic_reach(q0, d1, 0.5 * d2 - m3 * rem / 6))
        if w >= rem:
            return -1.0
        for _ in range(8):  # longer intervals while the bound still certifies them
            wt = min(2 * w, rem)
            if wt <= w or _quadratic_reach(q0, d1, 0.5 * d2 - m3 * wt / 6) < wt:
                break
            w = wt
        b = min(smax, lo + max(4 * w, 1e-15 * smax))  # a bracket just ahead?
        width = b - lo
        if d1 + abs(d2) * width + 0.5 * m3 * width * width < 0:
            pb = poly(a, b)[0]
            if pb + eps < 0:
                if p0 > 0:
                    return _refine(a, 0.0, lo, b)
                return _refine(a, eps, lo, b)
        if w <= 1e-16 * smax:  # no progress
            if poly(a, b)[0] + eps < 0:
                return lo
            w = width  # a tangency within round-off: not an event
        lo += w
    return lo
