"""Compiled event-driven integration of the piecewise-linear Coulomb dynamics, and shooting on it.

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

**Monodromy**. The state-transition matrix of ``y = (u, v)`` is the product of
the step propagators ``exp(A_yy s)`` and, at each event, of the saltation
matrix ``I + (f+ - f-) grad(h)^T / (dh/dt)`` of the triggering guard ``h``; a
contact that becomes stuck, or is stuck at the start, annihilates the
perturbations of its relative velocity (M-orthogonal projection, the
first-order effect of the short slip such a perturbation causes).

Status codes of the kernels: :data:`OK`, :data:`NEED_PATTERN` (the caller
builds the pattern ``need`` and calls again), :data:`NEED_SPACE` (record
buffers full), :data:`DEGENERATE` (more than ``_MAX_NULL`` consecutive events
at one instant, or ``max_phases`` phases), :data:`NONFINITE`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .patterns import TAYLOR_ORDER, matmul_into

__all__ = [
    "OK",
    "NEED_PATTERN",
    "NEED_SPACE",
    "DEGENERATE",
    "NONFINITE",
    "first_crossing",
    "march",
    "newton",
    "settle",
    "dense",
    "quadrature",
    "extrema",
    "orbit",
    "solve",
]

OK, NEED_PATTERN, NEED_SPACE, DEGENERATE, NONFINITE = 0, 1, 2, 3, 4
STICK_EVENT, SLIP_EVENT, REVERSAL_EVENT = 0, 1, 2
STICK_CODE, SLIP_CODE, OPEN_CODE = 0, 1, 2  # fretwear.model.STICK, SLIP, OPEN

_K = TAYLOR_ORDER
_EPS_GUARD = 1e-13  # event threshold of a guard, relative to its round-off scale
_NEAR = 1e-12  # a slipping contact this close to zero relative velocity joins an event
_BAND = 1e-12  # a force this close to its limit counts as at the limit
_STICK_TOL = 5e-10  # critical contact: relative acceleration below this (force units, of g_j)
_RATE_TOL = 1e-11  # derivatives of a critical stuck force below this (of its scale) vanish
_MAX_NULL = 40  # consecutive events at one instant before giving up
_STALL = 6  # Newton gives up when its residual has not halved over this many iterations
_STEP_TOL = 1e-7  # a Newton step below this (relative) ends the iterations (residual ~ step^2)
_GL_X, _GL_W = np.polynomial.legendre.leggauss(12)
# Flags and masks passed from one kernel to another as NumPy scalars: a Python literal (``True``, ``0``)
# would make Numba compile one more specialisation of the callee per literal value (seconds each).
_TRUE, _FALSE, _NONE = np.bool_(True), np.bool_(False), np.int64(0)


# ---------------------------------------------------------------------------
# polynomials of one step
# ---------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def _series(Ah, X, c, n):
    """``c[k] = (A h)^k X / k!`` for ``k = 0..K``, using the structure of ``A`` (:mod:`.patterns`).

    ``u' = v``; only the velocity rows are full; ``lambda`` and ``1`` are
    constant; ``(cos, sin)`` rotate.
    """
    D = X.shape[0]
    i_one = D - 3
    c[0, :] = X
    for k in range(1, _K + 1):
        inv = 1.0 / k
        for i in range(n):
            c[k, i] = Ah[i, n + i] * c[k - 1, n + i] * inv
        hi = D if k == 1 else 2 * n
        for i in range(n, 2 * n):
            s = 0.0
            for m in range(hi):
                s += Ah[i, m] * c[k - 1, m]
            if k > 1:
                for m in range(i_one + 1, D):
                    s += Ah[i, m] * c[k - 1, m]
            c[k, i] = s * inv
        for i in range(2 * n, i_one + 1):
            c[k, i] = 0.0
        c[k, i_one + 1] = Ah[i_one + 1, i_one + 2] * c[k - 1, i_one + 2] * inv
        c[k, i_one + 2] = Ah[i_one + 2, i_one + 1] * c[k - 1, i_one + 1] * inv


@njit(cache=True, nogil=True)
def _state_at(c, sigma, out):
    """``X(sigma) = sum_k c[k] sigma^k`` (Horner)."""
    out[:] = c[_K]
    for k in range(_K - 1, -1, -1):
        for i in range(out.shape[0]):
            out[i] = out[i] * sigma + c[k, i]


@njit(cache=True, nogil=True)
def _row_series(row, c, lo, hi, scale, a):
    """``a[k] = scale * row[lo:hi] . c[k, lo:hi]``."""
    for k in range(_K + 1):
        s = 0.0
        for m in range(lo, hi):
            s += row[m - lo] * c[k, m]
        a[k] = scale * s


@njit(cache=True, nogil=True)
def _dot(a, b, lo, hi):
    """``a[: hi - lo] . b[lo:hi]`` and ``|a| . |b|`` (value and round-off scale)."""
    s = 0.0
    m = 0.0
    for i in range(lo, hi):
        t = a[i - lo] * b[i]
        s += t
        m += abs(t)
    return s, m


@njit(cache=True, nogil=True)
def _poly(a, x):
    """Value and derivative of ``sum_k a[k] x^k``."""
    p = a[_K]
    d = 0.0
    for k in range(_K - 1, -1, -1):
        d = d * x + p
        p = p * x + a[k]
    return p, d


@njit(cache=True, nogil=True)
def _refine(a, shift, lo, hi):
    """Root of the decreasing ``p + shift`` on ``[lo, hi]`` (``> 0`` at ``lo``, ``< 0`` at ``hi``)."""
    x = lo
    for _ in range(100):
        p, d = _poly(a, x)
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


@njit(cache=True, nogil=True)
def _poly2(a, x):
    """Value, first and second derivative of ``sum_k a[k] x^k``."""
    p = a[_K]
    d = 0.0
    dd = 0.0
    for k in range(_K - 1, -1, -1):
        dd = dd * x + d
        d = d * x + p
        p = p * x + a[k]
    return p, d, 2.0 * dd


@njit(cache=True, nogil=True)
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
        for k in range(1, _K + 1):
            x *= smax
            tail += abs(a[k]) * x
        if a[0] - tail > -eps:
            return -1.0
    m3 = 0.0
    x = 1.0
    for k in range(3, _K + 1):
        m3 += k * (k - 1) * (k - 2) * abs(a[k]) * x
        x *= smax
    lo = start
    for _ in range(100_000):
        rem = smax - lo
        if rem <= 0:
            return -1.0
        p0, d1, d2 = _poly2(a, lo)
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
            pb = _poly(a, b)[0]
            if pb + eps < 0:
                if p0 > 0:
                    return _refine(a, 0.0, lo, b)
                return _refine(a, eps, lo, b)
        if w <= 1e-16 * smax:  # no progress
            if _poly(a, b)[0] + eps < 0:
                return lo
            w = width  # a tangency within round-off: not an event
        lo += w
    return lo


# ---------------------------------------------------------------------------
# contact states at an event
# ---------------------------------------------------------------------------
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
    a = b - W @ xp
    bscale = np.abs(b).max()
    for i in range(z):
        if bound[i]:
            if np.sign(xp[i]) * a[i] < -1e-12 * bscale:
                return x
        elif abs(xp[i]) > g[i]:
            return x
    return xp


@njit(cache=True, nogil=True)
def _find(masks, count, mask):
    for k in range(count):
        if masks[k] == mask:
            return k
    return -1


@njit(cache=True, nogil=True)
def _augmented(y, t, g, dirs, omega, nf, X):
    """Augmented state ``(u, v, lambda, 1, cos, sin)`` (zero force for stuck and open contacts)."""
    n2 = y.shape[0]
    X[:n2] = y
    for j in range(nf):
        X[n2 + j] = g[j] * dirs[j]
    X[n2 + nf] = 1.0
    X[n2 + nf + 1] = math.cos(omega * t)
    X[n2 + nf + 2] = math.sin(omega * t)


@njit(cache=True, nogil=True)
def _bits(mask, nf):
    """Indices of the set bits of ``mask`` below ``nf``."""
    count = 0
    for j in range(nf):
        if mask >> j & 1:
            count += 1
    idx = np.empty(count, dtype=np.int64)
    count = 0
    for j in range(nf):
        if mask >> j & 1:
            idx[count] = j
            count += 1
    return idx


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
    z = L.shape[0]
    x = b.copy()
    for i in range(z):
        for m in range(i):
            x[i] -= L[i, m] * x[m]
        x[i] /= L[i, i]
    for i in range(z - 1, -1, -1):
        for m in range(i + 1, z):
            x[i] -= L[m, i] * x[m]
        x[i] /= L[i, i]
    return x


@njit(cache=True, nogil=True)
def _delassus(Minv, B, idx):
    """``B_Z``, ``M^-1 B_Z^T`` and the Cholesky factor of ``W = B_Z M^-1 B_Z^T``."""
    n, z = Minv.shape[0], idx.shape[0]
    BZ = np.empty((z, n))
    for p in range(z):
        BZ[p] = B[idx[p]]
    MiBt = np.zeros((n, z))
    for i in range(n):
        for p in range(z):
            s = 0.0
            for m in range(n):
                s += Minv[i, m] * BZ[p, m]
            MiBt[i, p] = s
    W = np.zeros((z, z))
    for p in range(z):
        for q in range(z):
            s = 0.0
            for m in range(n):
                s += BZ[p, m] * MiBt[m, q]
            W[p, q] = s
    return BZ, MiBt, W, _cholesky(W)


@njit(cache=True, nogil=True)
def _project(MiBt, BZ, L, V):
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
        x = _chol_solve(L, w)
        for i in range(n):
            s = 0.0
            for p in range(z):
                s += MiBt[i, p] * x[p]
            V[i, col] -= s


@njit(cache=True, nogil=True)
def select(t, y, Z, forced, g, dirs, Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, count):
    """Contact states at ``(t, y)`` for the contacts ``Z`` (bit mask) at zero relative velocity.

    See the module docstring for the rule. ``forced``: contacts whose force
    guard triggered the event. ``y``'s velocities are projected in place so
    that the contacts of ``Z`` have exactly zero relative velocity (an
    M-orthogonal round-off correction).

    Returns ``(status, stuck mask, directions, need)``.
    """
    n, nf = Minv.shape[0], B.shape[0]
    out = dirs.copy()
    idx = _bits(Z, nf)
    z = idx.size
    if z == 0:
        return OK, 0, out, 0
    BZ, MiBt, W, L = _delassus(Minv, B, idx)
    _project(MiBt, BZ, L, y[n:].reshape((n, 1)))
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
        elif sgn * acc / W[p, p] > _STICK_TOL * g[j] + _EPS_GUARD * rscale:
            out[j] = sgn
        elif forced >> j & 1:
            out[j] = sgn
        else:
            critical |= 1 << j
            out[j] = sgn
    if critical:
        trial = stuck | critical
        k = _find(masks, count, trial)
        if k < 0:
            return NEED_PATTERN, 0, out, trial
        D = Ah.shape[1]
        X = np.empty(D)
        tmp = out.copy()
        for j in range(nf):
            if trial >> j & 1:
                tmp[j] = 0
        _augmented(y, t, g, tmp, omega, nf, X)
        c = np.empty((4, D))
        c[0] = X
        for q in range(1, 4):
            c[q] = Ah[k] @ c[q - 1] / q
        for p in range(z):
            j = idx[p]
            if not (critical >> j & 1):
                continue
            row = force_rows[k, j]
            scale = g[j] + _dot(row, X, 0, D)[1]
            decided = False
            for q in range(1, 4):
                rate = _dot(row, c[q], 0, D)[0]
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


# ---------------------------------------------------------------------------
# the march
# ---------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def _phi_at(series, sigma, out):
    """``exp(A_yy h sigma) = sum_k series[k] sigma^k``."""
    out[:, :] = series[_K]
    for k in range(_K - 1, -1, -1):
        out *= sigma
        out += series[k]


@njit(cache=True, nogil=True)
def march(
    Minv, B, C, Kmat, F, omega,
    masks, Ah, force_rows, phi, phi_series, step, count,
    g, y0, t0, t1, jacobian, record, max_phases,
    st_t, st_len, st_pat, st_phase, st_X, ph_t, ph_state, ph_dir, ev_t, ev_c, ev_kind, ev_dir,
):  # fmt: skip
    """Integrate from ``(t0, y0)`` to ``t1``.

    Returns ``(status, need, y, J, sliding, n_steps, n_phases, n_events)``:
    the state at ``t1``, ``dy(t1)/dy(t0)`` (identity unless ``jacobian``) and
    the distance slid by each contact (m). With ``record``, the steps
    (start time, length, pattern slot, phase, start state), phases (start,
    state codes, directions) and events (time, contact, kind, direction) are
    written to the buffers; :data:`NEED_SPACE` when they are full.
    """
    n, nf = Minv.shape[0], B.shape[0]
    n2 = 2 * n
    D = n2 + nf + 3
    y = y0.copy()
    J = np.eye(n2)
    sliding = np.zeros(nf)
    n_steps = n_phases = n_events = 0
    t = t0
    # initial states: contacts at zero relative velocity are decided by the Coulomb law
    vscale = 0.0
    for i in range(n):
        vscale = max(vscale, 2 * abs(y[n + i]))
    dirs = np.zeros(nf, dtype=np.int64)
    Z = _NONE
    for j in range(nf):
        if g[j] <= 0:
            continue
        vr = _dot(B[j], y, n, 2 * n)[0]
        if abs(vr) <= 1e-13 * vscale:
            Z |= 1 << j
        else:
            dirs[j] = 1 if vr > 0 else -1
    status, S, dirs, need = select(
        t, y, Z, _NONE, g, dirs, Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, count
    )
    if status != OK:
        return status, need, y, J, sliding, 0, 0, 0
    if jacobian and S:
        BZ, MiBt, _, L = _delassus(Minv, B, _bits(S, nf))
        _project(MiBt, BZ, L, J[n:, :])
    X = np.empty(D)
    Xn = np.empty(D)
    c = np.empty((_K + 1, D))
    a = np.empty(_K + 1)
    Phi = np.empty((n2, n2))
    Jt = np.empty((n2, n2))
    ur0 = np.zeros(nf)
    off_up = np.zeros(nf)
    off_lo = np.zeros(nf)
    null_events = 0
    new_phase = True
    phase_start = t
    while True:
        k = _find(masks, count, S)
        if k < 0:
            return NEED_PATTERN, S, y, J, sliding, n_steps, n_phases, n_events
        h = step[k]
        _augmented(y, t, g, dirs, omega, nf, X)
        for j in range(nf):
            if S >> j & 1:
                X[n2 + j] = 0.0
        # guard offsets: a stuck force that starts beyond its limit (within the rule's tolerance)
        for j in range(nf):
            off_up[j] = off_lo[j] = 0.0
            if S >> j & 1:
                lam = _dot(force_rows[k, j], X, 0, D)[0]
                off_up[j] = max(0.0, lam - g[j])
                off_lo[j] = max(0.0, -lam - g[j])
        if new_phase:
            if record:
                if n_phases >= ph_t.shape[0]:
                    return NEED_SPACE, 0, y, J, sliding, n_steps, n_phases, n_events
                ph_t[n_phases] = t
                for j in range(nf):
                    ph_dir[n_phases, j] = dirs[j]
                    code = SLIP_CODE if g[j] > 0 else OPEN_CODE
                    ph_state[n_phases, j] = STICK_CODE if S >> j & 1 else code
            n_phases += 1
            if n_phases > max_phases:
                return DEGENERATE, 0, y, J, sliding, n_steps, n_phases, n_events
            phase_start = t
            for j in range(nf):
                ur0[j] = _dot(B[j], y, 0, n)[0]
        who = -1
        kind = -1  # 0 force up, 1 force down, 2 velocity
        while True:
            remaining = t1 - t
            smax = min(1.0, remaining / h)
            if smax <= 0.0:
                break
            _series(Ah[k], X, c, n)
            best = smax
            who = -1
            for j in range(nf):
                if g[j] <= 0:
                    continue
                if S >> j & 1:
                    row = force_rows[k, j]
                    eps = _EPS_GUARD * (g[j] + _dot(row, X, 0, D)[1])
                    for side in range(2):
                        sgn = -1.0 if side == 0 else 1.0
                        _row_series(row, c, 0, D, sgn, a)
                        a[0] += g[j] + (off_up[j] if side == 0 else off_lo[j])
                        s = first_crossing(a, eps, 0.0, best)
                        if s >= 0 and (s < best or who < 0):
                            best, who, kind = s, j, side
                else:
                    _row_series(B[j], c, n, n2, float(dirs[j]), a)
                    scale = 0.0
                    for i in range(n):
                        scale += abs(B[j, i]) * (abs(X[n + i]) + omega * abs(X[i]))
                    s = first_crossing(a, _EPS_GUARD * scale, 0.0, best)
                    if s >= 0 and (s < best or who < 0):
                        best, who, kind = s, j, 2
            if record:
                if n_steps >= st_t.shape[0]:
                    return NEED_SPACE, 0, y, J, sliding, n_steps, n_phases, n_events
                st_t[n_steps] = t
                st_len[n_steps] = best * h
                st_pat[n_steps] = k
                st_phase[n_steps] = n_phases - 1
                st_X[n_steps] = X
            n_steps += 1
            _state_at(c, best, Xn)
            if jacobian:
                if best == 1.0:
                    matmul_into(phi[k], J, Jt)
                else:
                    _phi_at(phi_series[k], best, Phi)
                    matmul_into(Phi, J, Jt)
                J, Jt = Jt, J
            X[:] = Xn
            if who < 0 and best == smax and smax < 1.0:
                t = t1
            else:
                t = t + best * h
            if who >= 0 or t >= t1:
                break
        y[:] = X[:n2]
        for i in range(n2):
            if not math.isfinite(y[i]):
                return NONFINITE, 0, y, J, sliding, n_steps, n_phases, n_events
        for j in range(nf):
            if g[j] > 0 and not (S >> j & 1):
                sliding[j] += max(dirs[j] * (_dot(B[j], y, 0, n)[0] - ur0[j]), 0.0)
        if who < 0:
            return OK, 0, y, J, sliding, n_steps, n_phases, n_events
        # the event: contacts at zero relative velocity, and the triggering guard
        Zm = S
        forced = 0
        if kind == 2:
            Zm |= 1 << who
        else:
            forced = 1 << who
        for j in range(nf):
            if g[j] > 0 and not (Zm >> j & 1):
                vr = _dot(B[j], y, n, n2)[0]
                vs = 0.0
                for i in range(n):
                    vs += abs(B[j, i]) * (abs(y[n + i]) + omega * abs(y[i]))
                if abs(vr) <= _NEAR * vs:
                    Zm |= 1 << j
        status, S_new, d_new, need = select(
            t, y, Zm, forced, g, dirs, Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, count
        )
        if status != OK:
            return status, need, y, J, sliding, n_steps, n_phases, n_events
        k_new = _find(masks, count, S_new)
        if k_new < 0:
            return NEED_PATTERN, S_new, y, J, sliding, n_steps, n_phases, n_events
        changed = S_new != S
        for j in range(nf):
            if d_new[j] != dirs[j]:
                changed = True
        if jacobian and changed:
            # saltation of the triggering guard
            grad = np.zeros(n2)
            if kind == 2:
                for i in range(n):
                    grad[n + i] = dirs[who] * B[who, i]
            else:
                sgn = -1.0 if kind == 0 else 1.0
                for i in range(n2):
                    grad[i] = sgn * force_rows[k, who, i]
            f_minus = (Ah[k] @ X)[:n2] / h
            Xp = np.empty(D)
            _augmented(y, t, g, d_new, omega, nf, Xp)
            for j in range(nf):
                if S_new >> j & 1:
                    Xp[n2 + j] = 0.0
            f_plus = (Ah[k_new] @ Xp)[:n2] / step[k_new]
            hdot = grad @ f_minus
            jump = f_plus - f_minus
            if abs(hdot) > 1e-14 * np.abs(grad).sum() * np.abs(f_minus).sum() and np.abs(jump).max() > 0:
                for col in range(n2):  # J += (jump / hdot) (grad^T J)
                    gj = 0.0
                    for r in range(n2):
                        gj += grad[r] * J[r, col]
                    gj /= hdot
                    for r in range(n2):
                        J[r, col] += jump[r] * gj
            if S_new & ~S:
                BZ, MiBt, _, L = _delassus(Minv, B, _bits(S_new, nf))
                _project(MiBt, BZ, L, J[n:, :])
        if changed and record:
            for j in range(nf):
                was, now = S >> j & 1, S_new >> j & 1
                kd = -1
                if was and not now:
                    kd = SLIP_EVENT
                elif now and not was:
                    kd = STICK_EVENT
                elif not now and d_new[j] != dirs[j] and g[j] > 0:
                    kd = REVERSAL_EVENT
                if kd >= 0:
                    if n_events >= ev_t.shape[0]:
                        return NEED_SPACE, 0, y, J, sliding, n_steps, n_phases, n_events
                    ev_t[n_events] = t
                    ev_c[n_events] = j
                    ev_kind[n_events] = kd
                    ev_dir[n_events] = d_new[j]
                    n_events += 1
        elif changed:
            n_events += 1
        if t - phase_start <= 1e-13 * h or not changed:
            null_events += 1
            if null_events > _MAX_NULL:
                return DEGENERATE, 0, y, J, sliding, n_steps, n_phases, n_events
        else:
            null_events = 0
        new_phase = changed
        if not changed:  # same states: the phase goes on (guards measured from here)
            for j in range(nf):
                if g[j] > 0 and not (S >> j & 1):
                    sliding[j] -= max(dirs[j] * (_dot(B[j], y, 0, n)[0] - ur0[j]), 0.0)
        S, dirs = S_new, d_new


# ---------------------------------------------------------------------------
# periodic orbits
# ---------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def _scaled_norm(y, n, omega):
    s = 0.0
    for i in range(n):
        s += y[i] * y[i] + (y[n + i] / omega) ** 2
    return math.sqrt(s)


@njit(cache=True, nogil=True)
def _period(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count, g, y,
            jacobian, max_phases):  # fmt: skip
    e = np.zeros(0)
    ei = np.zeros(0, dtype=np.int64)
    e2 = np.zeros((0, 0))
    e8 = np.zeros((0, 0), dtype=np.int8)
    return march(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count,
                 g, y, 0.0, 2 * math.pi / omega, jacobian, _FALSE, max_phases,
                 e, e, ei, ei, e2, e, e8, e8, e, ei, ei, ei)  # fmt: skip


@njit(cache=True, nogil=True)
def _newton_step(A, b):
    """``A^-1 b`` by LU with partial pivoting; the least-squares minimum-norm solution when ``A`` is singular.

    ``A = J - I`` is singular on orbits stuck during the whole period (the
    stuck offset is neutral): the minimum-norm step leaves it unchanged.
    """
    m = A.shape[0]
    LU = A.copy()
    x = b.copy()
    scale = np.abs(A).max()
    for col in range(m):
        piv = col
        for r in range(col + 1, m):
            if abs(LU[r, col]) > abs(LU[piv, col]):
                piv = r
        if not abs(LU[piv, col]) > 1e-10 * scale:
            return np.linalg.lstsq(A, b)[0]
        if piv != col:
            for q in range(m):
                LU[col, q], LU[piv, q] = LU[piv, q], LU[col, q]
            x[col], x[piv] = x[piv], x[col]
        for r in range(col + 1, m):
            f = LU[r, col] / LU[col, col]
            for q in range(col, m):
                LU[r, q] -= f * LU[col, q]
            x[r] -= f * x[col]
    for r in range(m - 1, -1, -1):
        for q in range(r + 1, m):
            x[r] -= LU[r, q] * x[q]
        x[r] /= LU[r, r]
    return x


@njit(cache=True, nogil=True)
def newton(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count,
           g, y_guess, tol, max_iter, max_phases, verify):  # fmt: skip
    """Newton on ``P(y) - y = 0``, ``P`` the period map, with the exact monodromy.

    Least-squares steps (the Jacobian is singular on orbits with a contact
    stuck during the whole period) and backtracking on the periodicity
    residual ``|P(y) - y|`` (velocities scaled by ``1 / omega``). Stops early
    when the residual has not halved over ``_STALL`` iterations. Without
    ``verify``, a Newton step below ``_STEP_TOL`` of ``|y|`` is taken and
    returned as converged without evaluating the period map there (its
    residual is then of the order of the step squared): the caller verifies it.

    Returns ``(status, need, y, converged, verified, iterations, residual, J)``
    with the residual (relative to ``|y|``) and the monodromy ``J`` at the last
    evaluated state.
    """
    n = Minv.shape[0]
    n2 = 2 * n
    y = y_guess.copy()
    I = np.eye(n2)
    status, need, y1, J, _, _, _, _ = _period(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi,
                                              phi_series, step, count, g, y, _TRUE, max_phases)  # fmt: skip
    if status != OK:
        return status, need, y, False, False, 0, math.inf, J
    res = _scaled_norm(y1 - y, n, omega)
    history = np.empty(max_iter + 1)
    for it in range(max_iter + 1):
        size = max(_scaled_norm(y, n, omega), 1e-300)
        history[it] = res / size
        if res <= tol * size:
            return OK, 0, y, True, True, it, res / size, J
        if it == max_iter or (it >= _STALL and history[it] > 0.5 * history[it - _STALL]):
            return OK, 0, y, False, False, it, res / size, J
        dy = _newton_step(J - I, y - y1)
        if not verify and _scaled_norm(dy, n, omega) <= _STEP_TOL * size:
            return OK, 0, y + dy, True, False, it + 1, res / size, J
        alpha = 1.0
        while True:
            trial = y + alpha * dy
            status, need, t1, tJ, _, _, _, _ = _period(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows,
                                                       phi, phi_series, step, count, g, trial, _TRUE,
                                                       max_phases)  # fmt: skip
            if status == NEED_PATTERN:
                return status, need, y, False, False, it, res / size, J
            tres = _scaled_norm(t1 - trial, n, omega) if status == OK else math.inf
            if tres < res or alpha < 1e-4:
                break
            alpha *= 0.5
        if status != OK:
            return status, need, y, False, False, it, res / size, J
        y, y1, J, res = trial, t1, tJ, tres
    return OK, 0, y, False, False, max_iter, math.inf, J


@njit(cache=True, nogil=True)
def settle(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count,
           g, y0, periods, tol, max_phases):  # fmt: skip
    """March up to ``periods`` periods from ``y0``; stop once the change over one period is below ``tol``.

    Returns ``(status, need, y, marched, change)``, ``change`` relative (velocities scaled by ``1 / omega``).
    """
    n = Minv.shape[0]
    y = y0.copy()
    change = math.inf
    for p in range(periods):
        status, need, y1, _, _, _, _, _ = _period(
            Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count, g, y, _FALSE,
            max_phases,
        )  # fmt: skip
        if status != OK:
            return status, need, y, p, change
        change = _scaled_norm(y1 - y, n, omega) / max(_scaled_norm(y1, n, omega), 1e-300)
        y = y1
        if change <= tol:
            return OK, 0, y, p + 1, change
    return OK, 0, y, periods, change


# ---------------------------------------------------------------------------
# dense output and integrals of a recorded march
# ---------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def dense(Ah, force_rows, step, st_t, st_len, st_pat, st_phase, st_X, ph_state, n_steps, times):
    """States, friction forces and state codes at sorted ``times`` inside the recorded steps."""
    D = st_X.shape[1]
    nf = force_rows.shape[1]
    n2 = D - nf - 3
    n = n2 // 2
    m = times.shape[0]
    states = np.zeros((n2, m))
    forces = np.zeros((nf, m))
    codes = np.zeros((nf, m), dtype=np.int8)
    c = np.empty((_K + 1, D))
    X = np.empty(D)
    i = 0
    for s in range(n_steps):
        end = st_t[s] + st_len[s]
        last = s == n_steps - 1
        if i < m and (times[i] <= end or last):
            k = st_pat[s]
            _series(Ah[k], st_X[s], c, n)
            while i < m and (times[i] <= end or last):
                sigma = (times[i] - st_t[s]) / step[k]
                _state_at(c, max(sigma, 0.0), X)
                states[:, i] = X[:n2]
                for j in range(nf):
                    forces[j, i] = _dot(force_rows[k, j], X, 0, D)[0]
                    codes[j, i] = ph_state[st_phase[s], j]
                i += 1
    return states, forces, codes


@njit(cache=True, nogil=True)
def quadrature(Ah, step, st_t, st_len, st_pat, st_X, n_steps, n, F, C, omega):
    """Input work, viscous dissipation (J) and ``integral u exp(-i omega t) dt`` (m s) over the steps.

    12-point Gauss-Legendre per step: the integrands are products of step
    polynomials whose degree-``k`` coefficients fall as ``(2 rho h)^k / k!``
    (``rho h <= 3``); the rule's error on ``sigma^24`` is ``6e-15`` of it, on a
    coefficient below ``1e-5``: round-off.
    """
    D = st_X.shape[1]
    nf = D - 2 * n - 3
    i1 = 2 * n + nf
    c = np.empty((_K + 1, D))
    X = np.empty(D)
    work = visc = 0.0
    fre = np.zeros(n)
    fim = np.zeros(n)
    for s in range(n_steps):
        L = st_len[s]
        if L <= 0:
            continue
        k = st_pat[s]
        _series(Ah[k], st_X[s], c, n)
        for q in range(_GL_X.shape[0]):
            tau = 0.5 * L * (1 + _GL_X[q])
            w = 0.5 * L * _GL_W[q]
            _state_at(c, tau / step[k], X)
            co, si = X[i1 + 1], X[i1 + 2]
            for i in range(n):
                f = F[i, 0] + F[i, 1] * co + F[i, 2] * si
                work += w * f * X[n + i]
                cv = 0.0
                for m in range(n):
                    cv += C[i, m] * X[n + m]
                visc += w * X[n + i] * cv
                fre[i] += w * X[i] * co
                fim[i] -= w * X[i] * si
    return work, visc, fre, fim


@njit(cache=True, nogil=True)
def extrema(Ah, step, st_t, st_len, st_pat, st_X, n_steps, rows):
    """Exact maximum and minimum over the recorded steps of ``rows @ u`` (one row per channel).

    The candidates are the ends of the steps and the zeros of the channel's
    velocity inside them where it changes sign, located alternately as the
    first crossings (:func:`first_crossing`, certified) of ``+V`` and ``-V``
    from the previous zero; the channel's polynomial is evaluated there.
    """
    D = st_X.shape[1]
    nch, n = rows.shape
    c = np.empty((_K + 1, D))
    a = np.empty(_K + 1)
    v = np.zeros(_K + 1)
    w = np.zeros(_K + 1)
    hi_out = np.full(nch, -math.inf)
    lo_out = np.full(nch, math.inf)
    for s in range(n_steps):
        k = st_pat[s]
        smax = st_len[s] / step[k]
        _series(Ah[k], st_X[s], c, n)
        for ch in range(nch):
            _row_series(rows[ch], c, 0, n, 1.0, a)
            for x in (0.0, smax):
                p = _poly(a, x)[0]
                hi_out[ch] = max(hi_out[ch], p)
                lo_out[ch] = min(lo_out[ch], p)
            if smax <= 0:
                continue
            scale = 0.0
            for q in range(_K):
                v[q] = (q + 1) * a[q + 1]
                w[q] = -v[q]
                scale += abs(v[q])
            eps = _EPS_GUARD * scale
            rising = v[0] > 0 or (v[0] == 0 and v[1] >= 0)  # next: a maximum
            pos = 0.0
            for _ in range(4 * _K):
                root = first_crossing(v if rising else w, eps, pos, smax)
                if root < 0:
                    break
                p = _poly(a, root)[0]
                if rising:
                    hi_out[ch] = max(hi_out[ch], p)
                else:
                    lo_out[ch] = min(lo_out[ch], p)
                pos, rising = root, not rising
    return hi_out, lo_out


@njit(cache=True, nogil=True)
def orbit(Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count,
          g, y0, t0, t1, jacobian, max_phases, rows,
          st_t, st_len, st_pat, st_phase, st_X, ph_t, ph_state, ph_dir, ev_t, ev_c, ev_kind,
          ev_dir):  # fmt: skip
    """Recorded :func:`march`, its integrals and the extrema of ``rows @ u``, in one call.

    Returns ``(status, need, y, J, sliding, n_steps, n_phases, n_events, work, viscous, fourier_re,
    fourier_im, maxima, minima)``.
    """
    n = Minv.shape[0]
    status, need, y, J, sliding, ns, nph, nev = march(
        Minv, B, C, Kmat, F, omega, masks, Ah, force_rows, phi, phi_series, step, count, g, y0, t0, t1,
        jacobian, _TRUE, max_phases, st_t, st_len, st_pat, st_phase, st_X, ph_t, ph_state, ph_dir, ev_t, ev_c,
        ev_kind, ev_dir,
    )  # fmt: skip
    work = visc = 0.0
    fre = np.zeros(n)
    fim = np.zeros(n)
    hi = np.full(rows.shape[0], np.nan)
    lo = np.full(rows.shape[0], np.nan)
    if status == OK:
        work, visc, fre, fim = quadrature(Ah, step, st_t, st_len, st_pat, st_X, ns, n, F, C, omega)
        if rows.shape[0]:
            hi, lo = extrema(Ah, step, st_t, st_len, st_pat, st_X, ns, rows)
    return status, need, y, J, sliding, ns, nph, nev, work, visc, fre, fim, hi, lo


# attempts of a periodic solve (kinds; a march start is MARCH_START + its index in ``marches``)
GUESS_START, EXTRAPOLATED_START, NEIGHBOUR_START, RIGID_START, MARCH_START = 0, 1, 2, 3, 4
NOT_CONVERGED = -1  # attempt code of a Newton that ended without reaching the tolerance


@njit(cache=True, nogil=True)
def solve(Minv, B, C, Kmat, F, omegas, masks, Ah, force_rows, phi, phi_series, step, count, at, path,
          g, guesses, n_guesses, rigid, rigid_ok, chain, tol, max_iter, marches, max_phases, rows, start,
          y0_out, y1_out, conv_out, iters_out, att_kind, att_code, att_res, n_att,
          J_out, slid_out, work_out, visc_out, fre_out, fim_out, hi_out, lo_out, neutral_out,
          st_off, ph_off, ev_off, st_t, st_len, st_pat, st_phase, st_X, ph_t, ph_state, ph_dir,
          ev_t, ev_c, ev_kind, ev_dir):  # fmt: skip
    """Periodic orbits of the problems ``start, start + 1, ...`` by shooting, with their recorded period.

    Problem ``i`` is frequency ``at[i]`` of the table (``omegas``, ``Ah``, ...)
    with slip forces ``g[i]``: one call solves a frequency sweep (``at = 0, 1,
    ...``), the load ratios of one frequency, or any mix. ``path[i]`` is the
    parameter along which a sweep extrapolates (the frequency, the slip force).
    In a sweep (``chain``) or without guesses, the rigid
    state ``rigid[i]`` is taken at once when ``rigid_ok[i]`` (a stuck orbit,
    without offset; the recorded period verifies it). Otherwise Newton
    (:func:`newton`, without verification) starts from each of the
    ``n_guesses[i]`` rows of ``guesses[i]``; with ``chain``, then from the
    linear extrapolation of the two previous orbits (when both converged
    with the same, non-zero number of events) and from the previous orbit;
    then from ``rigid[i]`` and from the states reached by marching
    ``marches[j]`` periods (cumulative) from it. The first converged start
    wins; its period is recorded (steps, phases, events at the offsets
    ``st_off[i]``, ``ph_off[i]``, ``ev_off[i]``, which this sets for ``i + 1``)
    with :func:`orbit`, and a final Newton step that leaves a residual above
    ``tol`` is iterated further with verification. ``neutral_out[i]`` counts
    the contacts stuck during the whole period (neutral stuck offsets).

    Returns ``(status, need, i)``: :data:`OK` when every frequency is done,
    else :data:`NEED_PATTERN` (build pattern ``need``) or :data:`NEED_SPACE`
    (grow the record buffers) at problem ``i``, to be called again from ``i``.
    """
    n = Minv.shape[0]
    for i in range(start, at.shape[0]):
        w = at[i]
        om, g_i = omegas[w], g[i]
        T = 2 * math.pi / om
        Ah_i, phi_i, series_i, step_i = Ah[w], phi[w], phi_series[w], step[w]
        iters = 0
        na = 0
        found = False
        y = rigid[i].copy()
        best_res = math.inf
        best_y = rigid[i].copy()
        n_starts = n_guesses[i] + 3 + marches.shape[0]
        marched = 0
        ys = rigid[i].copy()
        # a stuck orbit: the rigid state (without offset) when its forces stay within the limits
        found = rigid_ok[i] and (chain or n_guesses[i] == 0)
        for a in range(n_starts):
            if found:
                break
            if a < n_guesses[i]:
                kind, y = GUESS_START, guesses[i, a].copy()
            elif a == n_guesses[i]:
                if not (chain and i > 1 and conv_out[i - 1] and conv_out[i - 2]):
                    continue
                events = ev_off[i] - ev_off[i - 1]
                if events == 0 or events != ev_off[i - 1] - ev_off[i - 2] or path[i - 1] == path[i - 2]:
                    continue
                slope = (path[i] - path[i - 1]) / (path[i - 1] - path[i - 2])
                kind, y = EXTRAPOLATED_START, y0_out[i - 1] + slope * (y0_out[i - 1] - y0_out[i - 2])
            elif a == n_guesses[i] + 1:
                if not (chain and i > 0 and conv_out[i - 1]):
                    continue
                kind, y = NEIGHBOUR_START, y0_out[i - 1].copy()
            elif a == n_guesses[i] + 2:
                kind, y = RIGID_START, rigid[i].copy()
            else:
                j = a - n_guesses[i] - 3
                status, need, ys, _, _ = settle(
                    Minv, B, C, Kmat, F, om, masks, Ah_i, force_rows, phi_i, series_i, step_i, count, g_i, ys,
                    marches[j] - marched, 0.0, max_phases,
                )  # fmt: skip
                if status == NEED_PATTERN:
                    return status, need, i
                marched = marches[j]
                if status != OK:
                    att_kind[i, na], att_code[i, na], att_res[i, na] = MARCH_START + j, status, math.inf
                    na += 1
                    break
                kind, y = MARCH_START + j, ys.copy()
            status, need, y1, ok, _, its, res, _ = newton(
                Minv, B, C, Kmat, F, om, masks, Ah_i, force_rows, phi_i, series_i, step_i, count, g_i, y, tol,
                max_iter, max_phases, _FALSE,
            )  # fmt: skip
            if status == NEED_PATTERN:
                return status, need, i
            iters += its
            att_kind[i, na], att_res[i, na] = kind, res
            att_code[i, na] = OK if status == OK and ok else (NOT_CONVERGED if status == OK else status)
            na += 1
            if status == OK and ok:
                found, y = True, y1
                break
            if status == OK and res < best_res:
                best_res, best_y = res, y1.copy()
        if not found:
            y = best_y
        n_att[i] = na
        # the recorded period
        for attempt in range(2):
            s0, p0, e0 = st_off[i], ph_off[i], ev_off[i]
            status, need, y1, J, slid, ns, nph, nev, work, visc, fre, fim, hi, lo = orbit(
                Minv, B, C, Kmat, F, om, masks, Ah_i, force_rows, phi_i, series_i, step_i, count, g_i, y, 0.0,
                T, _TRUE, max_phases, rows, st_t[s0:], st_len[s0:], st_pat[s0:], st_phase[s0:], st_X[s0:],
                ph_t[p0:], ph_state[p0:], ph_dir[p0:], ev_t[e0:], ev_c[e0:], ev_kind[e0:], ev_dir[e0:],
            )  # fmt: skip
            if status == NEED_PATTERN or status == NEED_SPACE:
                return status, need, i
            if status != OK:
                found = False
                ns = nph = nev = 0
                break
            res = _scaled_norm(y1 - y, n, om) / max(_scaled_norm(y, n, om), 1e-300)
            if not found or res <= tol or attempt == 1:
                found = found and res <= tol
                break
            status, need, y2, ok, _, its, _, _ = newton(
                Minv, B, C, Kmat, F, om, masks, Ah_i, force_rows, phi_i, series_i, step_i, count, g_i, y, tol,
                max_iter, max_phases, _TRUE,
            )  # fmt: skip
            if status == NEED_PATTERN:
                return status, need, i
            iters += its
            if not (status == OK and ok):
                att_code[i, na - 1], att_res[i, na - 1] = NOT_CONVERGED, res
                found = False
                break
            y = y2
        st_off[i + 1], ph_off[i + 1], ev_off[i + 1] = st_off[i] + ns, ph_off[i] + nph, ev_off[i] + nev
        y0_out[i] = y
        conv_out[i] = found
        iters_out[i] = iters
        neutral_out[i] = 0
        if ns:
            for j in range(B.shape[0]):  # contacts stuck during the whole period: neutral offsets
                stuck = g_i[j] > 0
                for p in range(ph_off[i], ph_off[i + 1]):
                    stuck = stuck and ph_state[p, j] == STICK_CODE
                neutral_out[i] += stuck
            y1_out[i], J_out[i], slid_out[i] = y1, J, slid
            work_out[i], visc_out[i], fre_out[i], fim_out[i], hi_out[i], lo_out[i] = (
                work,
                visc,
                fre,
                fim,
                hi,
                lo,
            )
        else:
            y1_out[i] = np.nan
            J_out[i] = np.nan
            slid_out[i] = np.nan
            work_out[i] = visc_out[i] = np.nan
            fre_out[i] = fim_out[i] = hi_out[i] = lo_out[i] = np.nan
    return OK, 0, at.shape[0]
