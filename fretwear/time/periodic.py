"""Periodic orbits of the event-driven dynamics by shooting: Newton on the period map, marching, sweeps."""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .codes import FALSE, NEED_PATTERN, NEED_SPACE, OK, STICK_CODE, TRUE
from .dense import back_substitute
from .integrals import integrals, orbit
from .marching import march

__all__ = [
    "newton",
    "settle",
    "solve",
    "scaled_norm",
    "GUESS_START",
    "EXTRAPOLATED_START",
    "NEIGHBOUR_START",
    "RIGID_START",
    "MARCH_START",
    "NOT_CONVERGED",
]

# attempts of a periodic solve (kinds; a march start is MARCH_START + its index in ``marches``)
GUESS_START, EXTRAPOLATED_START, NEIGHBOUR_START, RIGID_START, MARCH_START = 0, 1, 2, 3, 4
NOT_CONVERGED = -1  # attempt code of a Newton that ended without reaching the tolerance
_STALL = 6  # Newton gives up when its residual has not halved over this many iterations
_STEP_TOL = 1e-7  # a Newton step below this (relative) ends the iterations (residual ~ step^2)


@njit(cache=True, nogil=True, inline="always")
def scaled_norm(y, n, omega, kt):
    """``|y|`` with the velocities ``y[n:2 n]`` scaled by ``1 / omega`` and Jenkins forces ``y[2 n:]`` by
    ``1 / kt`` (m)."""
    s = 0.0
    for i in range(n):
        s += y[i] * y[i] + (y[n + i] / omega) ** 2
    for j in range(y.shape[0] - 2 * n):
        s += (y[2 * n + j] / kt[j]) ** 2
    return math.sqrt(s)


@njit(cache=True, nogil=True)
def no_records():
    """Empty record buffers: a march into them records nothing (:mod:`.codes`)."""
    e = np.zeros(0)
    ei = np.zeros(0, dtype=np.int64)
    e8 = np.zeros((0, 0), dtype=np.int8)
    return (e, e, ei, ei, np.zeros((0, 0))), (e, e8, e8), (e, ei, ei, ei)


@njit(cache=True, nogil=True)
def _period(model, omega, patterns, g, y, jacobian, max_phases, records):
    """One period of :func:`.march` from ``(0, y)``, recorded unless ``records`` is empty."""
    record = records[0][0].shape[0] > 0
    return march(
        model, omega, patterns, g, y, 0.0, 2 * math.pi / omega, jacobian, record, max_phases, records
    )


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
    back_substitute(LU, x)
    return x


@njit(cache=True, nogil=True)
def newton(model, omega, patterns, g, y_guess, tol, max_iter, max_phases, accept, records):
    """Newton on ``P(y) - y = 0``, ``P`` the period map, with the exact monodromy.

    Least-squares steps (the Jacobian is singular on orbits with a contact
    stuck during the whole period) and backtracking on the periodicity
    residual ``|P(y) - y|`` (velocities scaled by ``1 / omega``). Stops early
    when the residual has not halved over ``_STALL`` iterations. A Newton
    step below ``accept`` of ``|y|`` (0: none) is taken and returned as
    converged without evaluating the period map there (its residual is then
    of the order of the step squared): the caller verifies it, or keeps the
    period last evaluated, that step away from the orbit.

    Every period marched is recorded into ``records`` unless they are empty
    (:func:`no_records`); :data:`NEED_SPACE` when they are full.

    Returns ``(status, need, y, converged, verified, iterations, residual, J,
    last)`` with the residual (relative to ``|y|``) and the monodromy ``J`` at
    the last evaluated state, ``last = (y0, y1, sliding, n_steps, n_phases,
    n_events)`` its period (the one left in ``records``).
    """
    n, kt = model[0].shape[0], model[5]
    y = y_guess.copy()
    I = np.eye(y.shape[0])
    status, need, y1, J, sliding, ns, nph, nev = _period(
        model, omega, patterns, g, y, TRUE, max_phases, records
    )
    last = (y, y1, sliding, ns, nph, nev)
    if status != OK:
        return status, need, y, False, False, 0, math.inf, J, last
    res = scaled_norm(y1 - y, n, omega, kt)
    history = np.empty(max_iter + 1)
    for it in range(max_iter + 1):
        size = max(scaled_norm(y, n, omega, kt), 1e-300)
        history[it] = res / size
        if res <= tol * size:
            return OK, 0, y, True, True, it, res / size, J, last
        if it == max_iter or (it >= _STALL and history[it] > 0.5 * history[it - _STALL]):
            return OK, 0, y, False, False, it, res / size, J, last
        dy = _newton_step(J - I, y - y1)
        if scaled_norm(dy, n, omega, kt) <= accept * size:
            return OK, 0, y + dy, True, False, it + 1, res / size, J, last
        alpha = 1.0
        while True:
            trial = y + alpha * dy
            status, need, t1, tJ, sliding, ns, nph, nev = _period(
                model, omega, patterns, g, trial, TRUE, max_phases, records
            )
            last = (trial, t1, sliding, ns, nph, nev)
            if status == NEED_PATTERN or status == NEED_SPACE:
                return status, need, y, False, False, it, res / size, J, last
            tres = scaled_norm(t1 - trial, n, omega, kt) if status == OK else math.inf
            if tres < res or alpha < 1e-4:
                break
            alpha *= 0.5
        if status != OK:
            return status, need, y, False, False, it, res / size, J, last
        y, y1, J, res = trial, t1, tJ, tres
    return OK, 0, y, False, False, max_iter, math.inf, J, last


@njit(cache=True, nogil=True)
def settle(model, omega, patterns, g, y0, periods, tol, max_phases):
    """March up to ``periods`` periods from ``y0``; stop once the change over one period is below ``tol``.

    Returns ``(status, need, y, marched, change)``, ``change`` relative (velocities scaled by ``1 / omega``).
    """
    n, kt = model[0].shape[0], model[5]
    y = y0.copy()
    change = math.inf
    for p in range(periods):
        status, need, y1, _, _, _, _, _ = _period(
            model, omega, patterns, g, y, FALSE, max_phases, no_records()
        )
        if status != OK:
            return status, need, y, p, change
        change = scaled_norm(y1 - y, n, omega, kt) / max(scaled_norm(y1, n, omega, kt), 1e-300)
        y = y1
        if change <= tol:
            return OK, 0, y, p + 1, change
    return OK, 0, y, periods, change


@njit(cache=True, nogil=True)
def solve(
    model, omegas, patterns, problems, starts, options, rows, start, results, attempts, offsets, records
):
    """Periodic orbits of the problems ``start, start + 1, ...`` by shooting, with their recorded period.

    Packed arguments (``model``, ``patterns`` at every frequency, ``records``:
    :mod:`fretwear.time.codes`):

    * ``problems = (at, path, g, reuse)``: problem ``i`` is frequency ``at[i]``
      of the table (``omegas``, ``patterns``) with slip forces ``g[i]``: one
      call solves a frequency sweep (``at = 0, 1, ...``), the load ratios of one
      frequency, or any mix; ``path[i]`` is the parameter along which a sweep
      extrapolates (the frequency, the slip force); ``reuse[i]``: see below;
    * ``starts = (guesses, n_guesses, rigid, rigid_ok, marches)``: the
      guesses per problem and their number, the rigid states and whether
      each is a stuck orbit, the cumulative numbers of periods to march;
    * ``options = (chain, tol, max_iter, max_phases)``;
    * ``results = (y0, y1, converged, iterations, J, sliding, work, viscous,
      fourier_re, fourier_im, maxima, minima, neutral)``, one row per problem
      (written);
    * ``attempts = (kind, code, residual, count)``: the starts tried per problem (written);
    * ``offsets = (steps, phases, events)``: where the records of each problem start (written).

    At problem ``i``, in a sweep (``chain``) or without guesses, the rigid
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
    ``tol`` is iterated further with verification. Newton records every period
    it marches: when its last step is at most ``reuse[i]`` (relative to the
    state; 0: only a verified state) the period of its last evaluation, that
    close to the orbit, is the recorded one and no further period is marched;
    Newton then also stops at the first step below ``reuse[i]``.
    ``neutral_out[i]`` counts the contacts stuck during the whole period
    (neutral stuck offsets).

    Returns ``(status, need, i)``: :data:`OK` when every problem is done,
    else :data:`NEED_PATTERN` (build pattern ``need``) or :data:`NEED_SPACE`
    (grow the record buffers) at problem ``i``, to be called again from ``i``.
    """
    B, kt = model[1], model[5]
    n = model[0].shape[0]
    masks, Ah, force_rows, phi, phi_series, step, count = patterns
    at, path, g, reuse = problems
    guesses, n_guesses, rigid, rigid_ok, marches = starts
    chain, tol, max_iter, max_phases = options
    (
        y0_out,
        y1_out,
        conv_out,
        iters_out,
        J_out,
        slid_out,
        work_out,
        visc_out,
        fre_out,
        fim_out,
        hi_out,
        lo_out,
        neutral_out,
    ) = results
    att_kind, att_code, att_res, n_att = attempts
    st_off, ph_off, ev_off = offsets
    (st_t, st_len, st_pat, st_phase, st_X), (ph_t, ph_state, ph_dir), (ev_t, ev_c, ev_kind, ev_dir) = records
    for i in range(start, at.shape[0]):
        w = at[i]
        om, g_i = omegas[w], g[i]
        T = 2 * math.pi / om
        patterns_i = (masks, Ah[w], force_rows, phi[w], phi_series[w], step[w], count)
        iters = 0
        na = 0
        found = False
        y = rigid[i].copy()
        best_res = math.inf
        best_y = rigid[i].copy()
        n_starts = n_guesses[i] + 3 + marches.shape[0]
        marched = 0
        ys = rigid[i].copy()
        s0, p0, e0 = st_off[i], ph_off[i], ev_off[i]
        records_i = (
            (st_t[s0:], st_len[s0:], st_pat[s0:], st_phase[s0:], st_X[s0:]),
            (ph_t[p0:], ph_state[p0:], ph_dir[p0:]),
            (ev_t[e0:], ev_c[e0:], ev_kind[e0:], ev_dir[e0:]),
        )
        last = (y, y, np.zeros(B.shape[0]), 0, 0, 0)
        J = np.eye(rigid.shape[1])
        # a stuck orbit: the rigid state (without offset) when its forces stay within the limits
        found = rigid_ok[i] and (chain or n_guesses[i] == 0)
        stuck_found = found
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
                    model, om, patterns_i, g_i, ys, marches[j] - marched, 0.0, max_phases
                )
                if status == NEED_PATTERN:
                    return status, need, i
                marched = marches[j]
                if status != OK:
                    att_kind[i, na], att_code[i, na], att_res[i, na] = MARCH_START + j, status, math.inf
                    na += 1
                    break
                kind, y = MARCH_START + j, ys.copy()
            status, need, y1, ok, _, its, res, J, last = newton(
                model, om, patterns_i, g_i, y, tol, max_iter, max_phases, max(_STEP_TOL, reuse[i]), records_i
            )
            if status == NEED_PATTERN or status == NEED_SPACE:
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
        # the recorded period: Newton's last one, or marched from the orbit's state
        y_last, y1, slid, ns, nph, nev = last
        reused = (
            found
            and not stuck_found
            and scaled_norm(y - y_last, n, om, kt) <= reuse[i] * scaled_norm(y, n, om, kt)
        )
        if reused:
            y = y_last
            work, visc, fre, fim, hi, lo = integrals(model, om, patterns_i, records_i[0], ns, rows)
        for attempt in range(0 if reused else 2):
            status, need, y1, J, slid, ns, nph, nev, work, visc, fre, fim, hi, lo = orbit(
                model, om, patterns_i, g_i, y, 0.0, T, TRUE, max_phases, rows, records_i
            )
            if status == NEED_PATTERN or status == NEED_SPACE:
                return status, need, i
            if status != OK:
                found = False
                ns = nph = nev = 0
                break
            res = scaled_norm(y1 - y, n, om, kt) / max(scaled_norm(y, n, om, kt), 1e-300)
            if not found or res <= tol or attempt == 1:
                found = found and res <= tol
                break
            status, need, y2, ok, _, its, _, _, _ = newton(
                model, om, patterns_i, g_i, y, tol, max_iter, max_phases, 0.0, no_records()
            )
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
