"""Dense output, integrals and extrema of a recorded march (:func:`orbit`: the march and all three)."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .codes import OK, TRUE
from .marching import march
from .series import EPS_GUARD, K, dot, first_crossing, poly, row_series, state_at, taylor_series

__all__ = ["dense", "quadrature", "extrema", "integrals", "orbit"]

_GL_X, _GL_W = np.polynomial.legendre.leggauss(12)


@njit(cache=True, nogil=True)
def dense(patterns, steps, ph_state, n_steps, times):
    """States, friction forces and state codes at sorted ``times`` inside the recorded ``steps``.

    ``patterns``, ``steps``: as :mod:`.codes` packs them; ``ph_state``: the state codes of the
    recorded phases.
    """
    _, Ah, force_rows, _, _, step, _ = patterns
    st_t, st_len, st_pat, st_phase, st_X = steps
    D = st_X.shape[1]
    nf = force_rows.shape[1]
    n2 = D - nf - 3
    n = n2 // 2
    m = times.shape[0]
    states = np.zeros((n2, m))
    forces = np.zeros((nf, m))
    codes = np.zeros((nf, m), dtype=np.int8)
    c = np.empty((K + 1, D))
    X = np.empty(D)
    i = 0
    for s in range(n_steps):
        end = st_t[s] + st_len[s]
        last = s == n_steps - 1
        if i < m and (times[i] <= end or last):
            k = st_pat[s]
            taylor_series(Ah[k], st_X[s], c, n)
            while i < m and (times[i] <= end or last):
                sigma = (times[i] - st_t[s]) / step[k]
                state_at(c, max(sigma, 0.0), X)
                states[:, i] = X[:n2]
                for j in range(nf):
                    forces[j, i] = dot(force_rows[k, j], X, 0, D)[0]
                    codes[j, i] = ph_state[st_phase[s], j]
                i += 1
    return states, forces, codes


@njit(cache=True, nogil=True)
def quadrature(model, omega, patterns, steps, n_steps):
    """Input work, viscous dissipation (J) and ``integral u exp(-i omega t) dt`` (m s) over the ``steps``.

    12-point Gauss-Legendre per step: the integrands are products of step
    polynomials whose degree-``k`` coefficients fall as ``(2 rho h)^k / k!``
    (``rho h <= 3``); the rule's error on ``sigma^24`` is ``6e-15`` of it, on a
    coefficient below ``1e-5``: round-off.
    """
    Minv, _, C, _, F, _ = model
    _, Ah, _, _, _, step, _ = patterns
    _, st_len, st_pat, _, st_X = steps
    n = Minv.shape[0]
    D = st_X.shape[1]
    nf = D - 2 * n - 3
    i1 = 2 * n + nf
    c = np.empty((K + 1, D))
    X = np.empty(D)
    work = visc = 0.0
    fre = np.zeros(n)
    fim = np.zeros(n)
    for s in range(n_steps):
        L = st_len[s]
        if L <= 0:
            continue
        k = st_pat[s]
        taylor_series(Ah[k], st_X[s], c, n)
        for q in range(_GL_X.shape[0]):
            tau = 0.5 * L * (1 + _GL_X[q])
            w = 0.5 * L * _GL_W[q]
            state_at(c, tau / step[k], X)
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
def extrema(patterns, steps, n_steps, rows):
    """Exact maximum and minimum over the recorded steps of ``rows @ u`` (one row per channel).

    The candidates are the ends of the steps and the zeros of the channel's
    velocity inside them where it changes sign, located alternately as the
    first crossings (:func:`first_crossing`, certified) of ``+V`` and ``-V``
    from the previous zero; the channel's polynomial is evaluated there.
    """
    _, Ah, _, _, _, step, _ = patterns
    _, st_len, st_pat, _, st_X = steps
    D = st_X.shape[1]
    nch, n = rows.shape
    c = np.empty((K + 1, D))
    a = np.empty(K + 1)
    v = np.zeros(K + 1)
    w = np.zeros(K + 1)
    hi_out = np.full(nch, -math.inf)
    lo_out = np.full(nch, math.inf)
    for s in range(n_steps):
        k = st_pat[s]
        smax = st_len[s] / step[k]
        taylor_series(Ah[k], st_X[s], c, n)
        for ch in range(nch):
            row_series(rows[ch], c, 0, n, 1.0, a)
            for x in (0.0, smax):
                p = poly(a, x)[0]
                hi_out[ch] = max(hi_out[ch], p)
                lo_out[ch] = min(lo_out[ch], p)
            if smax <= 0:
                continue
            scale = 0.0
            for q in range(K):
                v[q] = (q + 1) * a[q + 1]
                w[q] = -v[q]
                scale += abs(v[q])
            eps = EPS_GUARD * scale
            rising = v[0] > 0 or (v[0] == 0 and v[1] >= 0)  # next: a maximum
            pos = 0.0
            for _ in range(4 * K):
                root = first_crossing(v if rising else w, eps, pos, smax)
                if root < 0:
                    break
                p = poly(a, root)[0]
                if rising:
                    hi_out[ch] = max(hi_out[ch], p)
                else:
                    lo_out[ch] = min(lo_out[ch], p)
                pos, rising = root, not rising
    return hi_out, lo_out


@njit(cache=True, nogil=True)
def orbit(model, omega, patterns, g, y0, t0, t1, jacobian, max_phases, rows, records):
    """Recorded :func:`~fretwear.time.marching.march`, its integrals and the extrema of ``rows @ u``.

    Returns ``(status, need, y, J, sliding, n_steps, n_phases, n_events, work, viscous, fourier_re,
    fourier_im, maxima, minima)``.
    """
    status, need, y, J, sliding, ns, nph, nev = march(
        model, omega, patterns, g, y0, t0, t1, jacobian, TRUE, max_phases, records
    )
    if status == OK:
        work, visc, fre, fim, hi, lo = integrals(model, omega, patterns, records[0], ns, rows)
    else:
        n = model[0].shape[0]
        work, visc, fre, fim = 0.0, 0.0, np.zeros(n), np.zeros(n)
        hi, lo = np.full(rows.shape[0], np.nan), np.full(rows.shape[0], np.nan)
    return status, need, y, J, sliding, ns, nph, nev, work, visc, fre, fim, hi, lo


@njit(cache=True, nogil=True)
def integrals(model, omega, patterns, steps, n_steps, rows):
    """:func:`quadrature` and :func:`extrema` of the recorded ``steps``: ``(work, viscous, fourier_re,
    fourier_im, maxima, minima)`` (NaN extrema without ``rows``)."""
    work, visc, fre, fim = quadrature(model, omega, patterns, steps, n_steps)
    hi = np.full(rows.shape[0], np.nan)
    lo = np.full(rows.shape[0], np.nan)
    if rows.shape[0]:
        hi, lo = extrema(patterns, steps, n_steps, rows)
    return work, visc, fre, fim, hi, lo
