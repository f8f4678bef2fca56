"""The compiled event-driven march of the piecewise-linear Coulomb dynamics, with its monodromy.

Steps of the Taylor series of :mod:`fretwear.time.patterns` up to the first
crossing of a guard (:mod:`fretwear.time.series`), contact states at each
event (:mod:`fretwear.time.events`; Jenkins contacts below).

**Jenkins contacts** (the state is ``y = (u, v, lambda)``). At the start a
contact whose force is inside its cone (``|lambda_j| < g_j``) sticks; one at
its limit (its force clipped to ``+-g_j``) slips when its relative velocity
points along its force, or, at rest, its relative acceleration does; it
sticks otherwise. At an event the triggering contact alone changes: a stuck
force reaching ``d g_j`` starts a slip in direction ``d`` (the force set to
``d g_j`` exactly), a slip whose relative velocity vanishes sticks; events of
other contacts at the same instant follow at once as null steps.

**Monodromy**. The state-transition matrix of ``y = (u, v)`` is the product of
the step propagators ``exp(A_yy s)`` and, at each event, of the saltation
matrix ``I + (f+ - f-) grad(h)^T / (dh/dt)`` of the triggering guard ``h``; a
contact that becomes stuck, or is stuck at the start, annihilates the
perturbations of its relative velocity (M-orthogonal projection, the
first-order effect of the short slip such a perturbation causes).

For Jenkins contacts the saltation matrices follow from the same formula in
``y = (u, v, lambda)``. Stick to slip, guard ``h = g_j - d lambda_j``: the
vector fields differ only in ``lambda_j' = k_t (B v)_j`` (before) and ``0``
(after), so ``f+ - f- = -k_t v_r e_j`` and ``grad(h) . f- = -d k_t v_r``: the
saltation is ``I - e_j e_j^T`` (a perturbation of a slipping force is lost).
Slip to stick, guard ``h = d (B v)_j``: ``lambda_j' = k_t (B v)_j`` vanishes
at the event and the force is continuous, so ``f+ = f-``: no saltation. A
contact that slips at the start has its force's perturbation annihilated
likewise.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from .codes import (
    DEGENERATE,
    NEED_PATTERN,
    NEED_SPACE,
    NONE,
    NONFINITE,
    OK,
    OPEN_CODE,
    REVERSAL_EVENT,
    SLIP_CODE,
    SLIP_EVENT,
    STICK_CODE,
    STICK_EVENT,
)
from .dense import matmul_into, matvec_into
from .events import augmented, delassus, delassus_workspace, find_slot, project, select
from .series import EPS_GUARD, K, dot, first_crossing, row_series, state_at, taylor_series

__all__ = ["march", "MAX_NULL"]

MAX_NULL = 40  # consecutive events at one instant before giving up
_NEAR = 1e-12  # a slipping contact this close to zero relative velocity joins an event
_AT_LIMIT = 1e-12  # a Jenkins force this close to its slip force is at the limit at the start
_AT_REST = 1e-13  # a relative velocity this small (of the velocities' scale) is zero at the start


@njit(cache=True, nogil=True, inline="always")
def _phi_at(series, sigma, out):
    """``exp(A_yy h sigma) = sum_k series[k] sigma^k``."""
    out[:, :] = series[K]
    for k in range(K - 1, -1, -1):
        out *= sigma
        out += series[k]


@njit(cache=True, nogil=True)
def _jenkins_start(t, y, g, model, omega):
    """Stuck mask and slip directions of a Jenkins model at ``(t, y)`` (module docstring).

    Clips the forces ``y[2 n:]`` into their cones in place (zero for an open contact).
    """
    Minv, B, C, Kmat, F, _ = model
    n, nf = Minv.shape[0], B.shape[0]
    n2 = 2 * n
    dirs = np.zeros(nf, dtype=np.int64)
    S = NONE
    limit = np.zeros(nf, dtype=np.int64)
    for j in range(nf):
        lam = y[n2 + j]
        if g[j] <= 0:
            y[n2 + j] = 0.0
        elif abs(lam) < g[j] * (1 - _AT_LIMIT):
            S |= 1 << j
        else:
            limit[j] = 1 if lam > 0 else -1
            y[n2 + j] = limit[j] * g[j]
    if not np.any(limit != 0):
        return S, dirs
    vscale = 0.0
    for i in range(n):
        vscale = max(vscale, 2 * abs(y[n + i]))
    co, si = math.cos(omega * t), math.sin(omega * t)
    r = np.empty(n)  # M a = f - C v - K u - B^T lambda
    for i in range(n):
        s = F[i, 0] + F[i, 1] * co + F[i, 2] * si
        for m in range(n):
            s -= C[i, m] * y[n + m] + Kmat[i, m] * y[m]
        for j in range(nf):
            s -= B[j, i] * y[n2 + j]
        r[i] = s
    acc = Minv @ r
    for j in range(nf):
        d = limit[j]
        if d == 0:
            continue
        vr = dot(B[j], y, n, n2)[0]
        if abs(vr) <= _AT_REST * vscale:
            vr = dot(B[j], acc, 0, n)[0]
        if d * vr > 0:
            dirs[j] = d
        else:
            S |= 1 << j
    return S, dirs


@njit(cache=True, nogil=True)
def march(model, omega, patterns, g, y0, t0, t1, jacobian, record, max_phases, records):
    """Integrate from ``(t0, y0)`` to ``t1`` (``model``, ``patterns``, ``records``: :mod:`.codes`).

    Returns ``(status, need, y, J, sliding, n_steps, n_phases, n_events)``:
    the state at ``t1`` (``(u, v)``, or ``(u, v, lambda)`` for Jenkins
    contacts), ``dy(t1)/dy(t0)`` (identity unless ``jacobian``) and
    the distance slid by each contact (m). With ``record``, the steps
    (start time, length, pattern slot, phase, start state), phases (start,
    state codes, directions) and events (time, contact, kind, direction) are
    written to the buffers ``records``; :data:`NEED_SPACE` when they are full.
    """
    Minv, B, _, _, _, kt = model
    masks, Ah, force_rows, phi, phi_series, step, count = patterns
    steps, phases, events = records
    st_t, st_len, st_pat, st_phase, st_X = steps
    ph_t, ph_state, ph_dir = phases
    ev_t, ev_c, ev_kind, ev_dir = events
    n, nf = Minv.shape[0], B.shape[0]
    n2 = 2 * n
    D = n2 + nf + 3
    jen = kt.shape[0] > 0  # Jenkins contacts: y = (u, v, lambda)
    ny = n2 + kt.shape[0]
    y = y0.copy()
    J = np.eye(ny)
    ws = delassus_workspace(n, nf)
    sliding = np.zeros(nf)
    n_steps = n_phases = n_events = 0
    t = t0
    if jen:
        S, dirs = _jenkins_start(t, y, g, model, omega)
        if jacobian:
            for j in range(nf):
                if not (S >> j & 1):
                    J[n2 + j, n2 + j] = 0.0
    else:
        # initial states: contacts at zero relative velocity are decided by the Coulomb law
        vscale = 0.0
        for i in range(n):
            vscale = max(vscale, 2 * abs(y[n + i]))
        dirs = np.zeros(nf, dtype=np.int64)
        Z = NONE
        for j in range(nf):
            if g[j] <= 0:
                continue
            vr = dot(B[j], y, n, 2 * n)[0]
            if abs(vr) <= 1e-13 * vscale:
                Z |= 1 << j
            else:
                dirs[j] = 1 if vr > 0 else -1
        status, S, dirs, need = select(t, y, Z, NONE, g, dirs, model, omega, patterns, ws)
        if status != OK:
            return status, need, y, J, sliding, 0, 0, 0
        if jacobian and S:
            _, BZ, MiBt, _, L = delassus(Minv, B, S, ws)
            project(MiBt, BZ, L, J[n:, :])
    X = np.empty(D)
    Xn = np.empty(D)
    c = np.empty((K + 1, D))
    a = np.empty(K + 1)
    Phi = np.empty((ny, ny))
    Jt = np.empty((ny, ny))
    ur0 = np.zeros(nf)
    grad, f_minus, f_plus, Xp = np.empty(n2), np.empty(n2), np.empty(n2), np.empty(D)  # saltation
    off_up = np.zeros(nf)
    off_lo = np.zeros(nf)
    null_events = 0
    new_phase = True
    phase_start = t
    while True:
        k = find_slot(masks, count, S)
        if k < 0:
            return NEED_PATTERN, S, y, J, sliding, n_steps, n_phases, n_events
        h = step[k]
        augmented(y, t, g, dirs, omega, nf, X)
        for j in range(nf):
            if S >> j & 1 and not jen:
                X[n2 + j] = 0.0
        # guard offsets: a stuck force that starts beyond its limit (within the rule's tolerance)
        for j in range(nf):
            off_up[j] = off_lo[j] = 0.0
            if S >> j & 1:
                lam = dot(force_rows[k, j], X, 0, D)[0]
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
                ur0[j] = dot(B[j], y, 0, n)[0]
        who = -1
        kind = -1  # 0 force up, 1 force down, 2 velocity
        while True:
            remaining = t1 - t
            smax = min(1.0, remaining / h)
            if smax <= 0.0:
                break
            taylor_series(Ah[k], X, c, n)
            best = smax
            who = -1
            for j in range(nf):
                if g[j] <= 0:
                    continue
                if S >> j & 1:
                    row = force_rows[k, j]
                    eps = EPS_GUARD * (g[j] + dot(row, X, 0, D)[1])
                    for side in range(2):
                        sgn = -1.0 if side == 0 else 1.0
                        row_series(row, c, 0, D, sgn, a)
                        a[0] += g[j] + (off_up[j] if side == 0 else off_lo[j])
                        s = first_crossing(a, eps, 0.0, best)
                        if s >= 0 and (s < best or who < 0):
                            best, who, kind = s, j, side
                else:
                    row_series(B[j], c, n, n2, float(dirs[j]), a)
                    scale = 0.0
                    for i in range(n):
                        scale += abs(B[j, i]) * (abs(X[n + i]) + omega * abs(X[i]))
                    s = first_crossing(a, EPS_GUARD * scale, 0.0, best)
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
            state_at(c, best, Xn)
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
        y[:] = X[:ny]
        for i in range(ny):
            if not math.isfinite(y[i]):
                return NONFINITE, 0, y, J, sliding, n_steps, n_phases, n_events
        for j in range(nf):
            if g[j] > 0 and not (S >> j & 1):
                sliding[j] += max(dirs[j] * (dot(B[j], y, 0, n)[0] - ur0[j]), 0.0)
        if who < 0:
            return OK, 0, y, J, sliding, n_steps, n_phases, n_events
        if jen:  # the triggering contact changes alone (module docstring)
            S_new = S
            d_new = dirs.copy()
            if kind == 2:
                S_new |= 1 << who
                d_new[who] = 0
            else:
                S_new &= ~(1 << who)
                d_new[who] = 1 if kind == 0 else -1
                y[n2 + who] = d_new[who] * g[who]
                if jacobian:  # saltation I - e e^T of a force reaching its limit
                    J[n2 + who, :] = 0.0
            changed = True
            if find_slot(masks, count, S_new) < 0:
                return NEED_PATTERN, S_new, y, J, sliding, n_steps, n_phases, n_events
        else:
            # the event: contacts at zero relative velocity, and the triggering guard
            Zm = S
            forced = 0
            if kind == 2:
                Zm |= 1 << who
            else:
                forced = 1 << who
            for j in range(nf):
                if g[j] > 0 and not (Zm >> j & 1):
                    vr = dot(B[j], y, n, n2)[0]
                    vs = 0.0
                    for i in range(n):
                        vs += abs(B[j, i]) * (abs(y[n + i]) + omega * abs(y[i]))
                    if abs(vr) <= _NEAR * vs:
                        Zm |= 1 << j
            status, S_new, d_new, need = select(t, y, Zm, forced, g, dirs, model, omega, patterns, ws)
            if status != OK:
                return status, need, y, J, sliding, n_steps, n_phases, n_events
            k_new = find_slot(masks, count, S_new)
            if k_new < 0:
                return NEED_PATTERN, S_new, y, J, sliding, n_steps, n_phases, n_events
            changed = S_new != S
            for j in range(nf):
                if d_new[j] != dirs[j]:
                    changed = True
            if jacobian and changed:
                # saltation of the triggering guard
                grad[:] = 0.0
                if kind == 2:
                    for i in range(n):
                        grad[n + i] = dirs[who] * B[who, i]
                else:
                    sgn = -1.0 if kind == 0 else 1.0
                    for i in range(n2):
                        grad[i] = sgn * force_rows[k, who, i]
                matvec_into(Ah[k], X, f_minus)
                augmented(y, t, g, d_new, omega, nf, Xp)
                for j in range(nf):
                    if S_new >> j & 1:
                        Xp[n2 + j] = 0.0
                matvec_into(Ah[k_new], Xp, f_plus)
                hdot = jump_max = g_abs = f_abs = 0.0
                for r in range(n2):  # f_minus, f_plus: (A X)[:n2] / h, the vector fields either side
                    f_minus[r] /= h
                    f_plus[r] /= step[k_new]
                    hdot += grad[r] * f_minus[r]
                    g_abs += abs(grad[r])
                    f_abs += abs(f_minus[r])
                    f_plus[r] -= f_minus[r]  # the jump
                    jump_max = max(jump_max, abs(f_plus[r]))
                if abs(hdot) > 1e-14 * g_abs * f_abs and jump_max > 0:
                    for col in range(n2):  # J += (jump / hdot) (grad^T J)
                        gj = 0.0
                        for r in range(n2):
                            gj += grad[r] * J[r, col]
                        gj /= hdot
                        for r in range(n2):
                            J[r, col] += f_plus[r] * gj
                if S_new & ~S:
                    _, BZ, MiBt, _, L = delassus(Minv, B, S_new, ws)
                    project(MiBt, BZ, L, J[n:, :])
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
            if null_events > MAX_NULL:
                return DEGENERATE, 0, y, J, sliding, n_steps, n_phases, n_events
        else:
            null_events = 0
        new_phase = changed
        if not changed:  # same states: the phase goes on (guards measured from here)
            for j in range(nf):
                if g[j] > 0 and not (S >> j & 1):
                    sliding[j] -= max(dirs[j] * (dot(B[j], y, 0, n)[0] - ur0[j]), 0.0)
        S, dirs = S_new, d_new
