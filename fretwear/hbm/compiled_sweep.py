"""The compiled frequency sweep: every frequency of a sweep in one compiled call.

:func:`sweep_kernel` solves the DLFT equations (eq. 12, 17-23) at each
frequency in turn with the logic of ``fretwear.hbm.periodic.solve_problem()``
(the exact stuck solution when it holds; Newton from a prediction, then the
global Newton homotopy; a cold start by the exact load continuation), with no
Python between frequencies. Two things make it fast:

* the unknowns are the augmented Lagrangian harmonics ``v = F_r + (E - Z_r) x``
  (eq. 18; :func:`fretwear.hbm.dlft.augmented_residual`): the march takes
  ``v`` directly and the Jacobian ``M + blockdiag(A_c)``, ``M = Z_r (E - Z_r)^-1``,
  needs no matrix product. Newton's method and the piecewise-linear walks
  are invariant under this affine change of unknowns: they visit the same
  solutions as in ``x``;
* the prediction. Besides the secant through the last two solutions, the
  stick/slip runs of those solutions are extrapolated to the new frequency
  (:func:`_predict_pattern`) and the DLFT equations solved with that pattern
  prescribed, an affine problem (:func:`_pattern_start`). When the runs move
  smoothly, this lands within a few samples of the solution's pattern,
  where Newton takes one or two steps; the walk, whose pieces are the samples
  that change state on the way, starts from the better of the two. Where slip
  sets in (the last point stuck) the exact load path from the stuck solution
  (:func:`fretwear.hbm.periodic.load_homotopy`) crosses only the samples that
  start to slip, and the next secant does not go through the stuck point.

Every solve ends with at least one full Newton step (``min_steps`` of
:func:`_newton`): on the piece where a walk arrives that step is exact, so
that the answer does not depend on the path taken to it (to round-off).
"""

from __future__ import annotations

from functools import cached_property, partial

import numpy as np
from numba import njit, typeof

from ..model import Model
from . import dlft
from .condensation import Condensed, condense_sweep, recover
from .dense import FASTMATH, lu_factor, lu_solve
from .dlft import (
    FRICTION,
    assemble_augmented,
    augmented_boundary,
    augmented_jacobian,
    augmented_march,
    augmented_residual,
    block_sums,
    forced_march,
    sampled_residual,
    state_code,
)
from .newton import step_past, tangent
from .problem import EPS_FACTOR, Problem
from .solution import PeriodicSolution
from .strategy import NewtonResult, newton_message

__all__ = ["solve", "sweep_kernel", "compile_callees"]

#: outcome of one frequency (column ``PATH`` of ``status``); ``FALLBACK``: left to the caller
FALLBACK, STUCK, DLFT, NEWTON_HOMOTOPY, LOAD_HOMOTOPY = -1, 1, 2, 3, 4
#: columns of ``status``: path, converged, iterations, message code, last Newton budget, pieces
PATH, CONVERGED, ITERATIONS, CODE, BUDGET, PIECES = 0, 1, 2, 3, 4, 5
#: message codes: 1 non-finite Newton step, 2 line search failed, 3 iteration budget, and
SINGULAR, ZERO_LOAD = 4, 5
#: walk modes: load factor, global Newton homotopy
LOAD, NEWTON = 0, 1
#: the stages of a frequency in :func:`sweep_kernel`
GUESS, HOMOTOPY, COLD, ZERO_LOAD_START, LOAD_CONTINUATION, DONE = 0, 1, 2, 3, 4, 5
#: Newton steps from a prediction before the walk takes over; pieces of that walk; most state changes
#: crossed by one Newton step (:func:`_newton`)
GUESS_STEPS, HOMOTOPY_PIECES, KINKS = 40, 500, 8
STALL_STEPS = 16
#: block sums (:func:`fretwear.hbm.dlft.block_sums`) up to this many numbers (32 MB), then every 2nd, 4th...
BLOCK_SUMS_SIZE = 4_000_000


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _newton(v0, M, F, eps, law, target, max_iter, min_steps, stall, r_start, cur, trial, work):
    """Newton's method: the full step if it lowers the residual, else cut at its ``K``-th change of pattern.

    Newton's own full step is tried first and kept whenever it lowers the
    residual (exact once the stick/slip pattern is right). Otherwise: the
    residual is piecewise linear; along the Newton direction ``d`` it is
    exactly ``(1 - tau) R`` up to the first sample that changes state, and a
    step cut there (``K = 1``) is the global Newton homotopy restarted at each
    piece (:func:`_walk`), sure to lower the residual. Past a few such changes
    the prediction still holds roughly, so a step crosses up to ``K`` of them
    (found along the line in ``O(samples)`` each, with no factorisation; the
    samples of the cut step are those of ``v`` plus ``tau`` times those of
    ``d``, no synthesis), and is kept when the residual falls by half the
    predicted amount: ``K`` then
    doubles (up to ``KINKS``), else halves (each change located once per
    direction, kept for the shorter steps). A full step (``tau = 1``) with no
    change of pattern is Newton's own. At least ``min_steps`` steps: from the
    end of a walk, exact up to round-off, one full step lands on the solution
    of its piece. ``stall`` (0: never): give up when that many steps have not
    halved the residual (the caller's walk is then cheaper). ``r_start``: the
    residual at ``v0`` when ``cur`` already holds its march, else negative.
    ``cur``, ``trial``: march buffers ``(R, lam, X, state, dep, sgn, hilo,
    U)``; ``work``: ``(J, A, aug, dU, piv, dv, Ut, t, dR)``.

    Returns ``(v, converged, iterations, max|R|, code, buffers)``: code 0, 1
    non-finite step, 3 no convergence in ``max_iter`` steps, ``SINGULAR``;
    ``buffers`` (``cur`` or ``trial``) hold the march and residual at ``v``.
    """
    kinds, limits, Phi, Psi, half_wave, PhiT, PsiT, P, Q, stride = law
    J, A, aug, dU, piv, dv, Ut, t, dR = work
    n, (nc, Ns) = v0.shape[0], Ut.shape
    no = np.bool_(False)
    v = v0.copy()
    r = r_start
    if r < 0:
        r = augmented_residual(v, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, *cur)
    K = KINKS
    taus = np.empty(KINKS)
    it = 0
    r_mark, it_mark = r, 0  # the last iterate that halved the residual
    while it < max_iter:
        if r <= target and it >= min_steps:
            return v, True, it, r, 0, cur
        if r <= 0.5 * r_mark:
            r_mark, it_mark = r, it
        elif stall and it - it_mark >= stall:
            return v, False, it, r, 3, cur
        R, lam, X, state, dep, sgn, hilo, U = cur
        augmented_jacobian(M, dep, sgn, hilo, Phi, Psi, P, Q, stride, A, J)
        if lu_factor(J, piv) == 0:
            return v, False, it, r, SINGULAR, cur
        finite = True
        for i in range(n):
            dv[i] = -R[i]
        lu_solve(J, piv, dv)
        for i in range(n):
            finite = finite and abs(dv[i]) < np.inf
        if not finite:
            return v, False, it, r, 1, cur
        it += 1
        vt = v + dv  # Newton's own full step first: exact once the pattern is right
        rt = augmented_residual(vt, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, *trial)
        if rt < r or r <= target:
            v, r = vt, rt
            cur, trial = trial, cur
            continue
        synthesise = np.bool_(True)
        for c in range(nc):
            for s in range(Ns):
                Ut[c, s] = U[c, s]
        known, line_end = 0, no  # state changes located along the line (at taus), whether tau = 1 follows
        while True:
            while known < K and not line_end:  # the next state change, from Ut = samples at the last
                tau = taus[known - 1] if known else 0.0
                to_change = augmented_boundary(
                    Ut, dv, eps, kinds, limits, PhiT, half_wave, 1.0 - tau, dU, synthesise
                )
                synthesise = no
                if tau + to_change >= 1.0:
                    line_end = np.bool_(True)
                    break
                step = to_change * (1 + 1e-9) + 1e-13
                taus[known] = tau + step
                for c in range(nc):
                    for s in range(Ns):
                        Ut[c, s] += step * dU[c, s]
                known += 1
            kinks = min(K, known)
            tau = 1.0 if kinks == known and line_end else taus[kinks - 1]
            vt = v + tau * dv
            Uc, Ut_ = cur[7], trial[7]  # the samples of vt from those of v and dv (dU)
            for c in range(nc):
                for s in range(Ns):
                    Ut_[c, s] = Uc[c, s] + tau * dU[c, s]
            rt = sampled_residual(vt, M, F, eps, kinds, limits, PsiT, half_wave, *trial)
            if rt <= r * (1.0 - 0.5 * tau) or K == 1 or r <= target:
                v, r = vt, rt
                cur, trial = trial, cur
                if kinks >= K:
                    K = min(2 * K, KINKS)
                break
            K = max(1, K // 2)
    if r <= target:
        return v, True, it, r, 0, cur
    return v, False, it, r, 3, cur


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _walk(v0, p0, p_end, mode, M, F, r0, eps, law, max_pieces, cur, work):
    """The walk of :func:`fretwear.hbm.kernels.walk_kernel` in the augmented variables, no records.

    Returns ``(v, p, pieces, arrived)``. In ``v`` the march does not depend on
    the parameter: LOAD moves the residual by ``dR/dp = -(M + I) F``, NEWTON
    by ``r0``. The tangent keeps the sign of ``det [J dR/dp; t]``, which is the
    sign of the factorised ``det [J dR/dp; previous t]``. A singular augmented
    matrix ends the walk where it started, as in ``walk_kernel``.
    """
    kinds, limits, Phi, Psi, half_wave, PhiT, PsiT, P, Q, stride = law
    J, A, aug, dU, piv, dv, Ut, t, dR = work
    R, lam, X, state, dep, sgn, hilo, U = cur
    n = v0.shape[0]
    for i in range(n):
        if mode == LOAD:
            acc = F[i]
            for j in range(n):
                acc += M[i, j] * F[j]
            dR[i] = -acc
        else:
            dR[i] = r0[i]
    v = v0.copy()
    p = p0
    row = np.zeros(n + 1)
    row[n] = 1.0
    orientation, stalled = 0, 0
    yes = np.bool_(True)
    for piece in range(1, max_pieces + 1):
        augmented_march(v, eps, kinds, limits, PhiT, half_wave, lam, X, state, dep, sgn, hilo, U)
        augmented_jacobian(M, dep, sgn, hilo, Phi, Psi, P, Q, stride, A, J)
        for i in range(n):
            for j in range(n):
                aug[i, j] = J[i, j]
            aug[i, n] = dR[i]
        for j in range(n + 1):
            aug[n, j] = row[j]
        orientation = tangent(aug, piv, t, orientation)
        if orientation == 0:
            return v0.copy(), p0, 0, False
        for i in range(n):
            dv[i] = t[i]
        reach = (p_end - p) / t[n] if t[n] > 0 else np.inf
        tau = augmented_boundary(U, dv, eps, kinds, limits, PhiT, half_wave, min(reach, 1e300), dU, yes)
        if reach <= tau:
            for i in range(n):
                v[i] += reach * dv[i]
            return v, p_end, piece, True
        big = abs(p)
        for i in range(n):
            big = max(big, abs(v[i]))
        step, stalled = step_past(tau, big, stalled)
        for i in range(n):
            v[i] += step * dv[i]
        p += step * t[n]
        for i in range(n + 1):
            row[i] = t[i]
    return v, p, max_pieces, False


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _boundaries(code, half_wave, pos, frm, to):
    """Run boundaries of a state code over the full period: ``pos[k]`` starts a run of ``to[k]`` after
    one of ``frm[k]``; a half-wave code continues antiperiodically. Returns their number."""
    Ns = code.shape[0]
    N = 2 * Ns if half_wave else Ns
    L = 0
    for k in range(N):
        c = code[k] if k < Ns else -code[k - Ns]
        kp = k - 1 if k > 0 else N - 1
        cp = code[kp] if kp < Ns else -code[kp - Ns]
        if c != cp:
            pos[L], frm[L], to[L] = k, cp, c
            L += 1
    return L


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _predict_pattern(c0, c1, a, half_wave, out):
    """Extrapolate the stick/slip runs of one contact to the next frequency: the secant of the runs.

    ``c0``, ``c1``: state codes (:func:`fretwear.hbm.dlft.state_code`) of the
    last two solutions, ``a`` the ratio of the frequency steps. Each run
    boundary of ``c1`` is matched with one of ``c0`` (same cyclic order and
    kind, least total displacement) and moved on by ``a`` times its
    displacement. False when the runs do not match or moved boundaries would
    cross.
    """
    Ns = c1.shape[0]
    N = 2 * Ns if half_wave else Ns
    pos0, frm0, to0 = np.empty(N, np.int64), np.empty(N, np.int64), np.empty(N, np.int64)
    pos1, frm1, to1 = np.empty(N, np.int64), np.empty(N, np.int64), np.empty(N, np.int64)
    L = _boundaries(c1, half_wave, pos1, frm1, to1)
    if _boundaries(c0, half_wave, pos0, frm0, to0) != L:
        return False
    if L == 0:
        for s in range(Ns):
            out[s] = c1[s]
        return True
    best, best_d = -1, N * N
    for sh in range(L):
        d = 0
        for k in range(L):
            j = (k + sh) % L
            if frm0[j] != frm1[k] or to0[j] != to1[k]:
                d = -1
                break
            dd = (pos1[k] - pos0[j]) % N
            d += min(dd, N - dd)
        if 0 <= d < best_d:
            best, best_d = sh, d
    if best < 0:
        return False
    q = np.empty(L, np.int64)
    for k in range(L):
        dd = (pos1[k] - pos0[(k + best) % L]) % N
        if dd > N // 2:
            dd -= N
        q[k] = (pos1[k] + int(np.floor(a * dd + 0.5))) % N
    total = 0
    for k in range(L):  # the moved boundaries keep their cyclic order (a circle has L >= 2)
        gap = (q[(k + 1) % L] - q[k]) % N
        if gap == 0:
            return False
        total += gap
    if total != N:
        return False
    for k in range(L):
        for j in range((q[(k + 1) % L] - q[k]) % N):
            s = (q[k] + j) % N
            if s < Ns:
                out[s] = to1[k]
    return True


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _pattern_start(v, M, F, eps, law, code, at_v, cur, work, vp):
    """Solve the DLFT equations with the pattern ``code`` (nc, Ns) prescribed, from ``v``, into ``vp``.

    With the pattern fixed the residual is affine in ``v``
    (:func:`fretwear.hbm.dlft.forced_march`), so one Newton step solves it.
    ``at_v``: march buffers holding the (free) march at ``v``, whose samples
    are reused; ``cur``: buffers for the forced march. False if the pattern
    cannot be prescribed.
    """
    kinds, limits, Phi, Psi, half_wave, PhiT, PsiT, P, Q, stride = law
    J, A, aug, dU, piv, dv, Ut, t, dR = work
    R, lam, dep, sgn = cur[0], cur[1], cur[4], cur[5]
    hilo, U = at_v[6], at_v[7]  # the samples of v and their extremes
    nc = kinds.shape[0]
    n = v.shape[0]
    for c in range(nc):
        if not forced_march(U[c], code[c], kinds[c], limits[c], eps[c], half_wave, lam[c], dep[c], sgn[c]):
            return False
    assemble_augmented(v, M, F, lam, PsiT, R)
    augmented_jacobian(M, dep, sgn, hilo, Phi, Psi, P, Q, stride, A, J)
    if lu_factor(J, piv) == 0:
        return False
    for i in range(n):
        dv[i] = -R[i]
    lu_solve(J, piv, dv)
    finite = True
    for i in range(n):
        vp[i] = v[i] + dv[i]
        finite = finite and abs(vp[i]) < np.inf
    return finite


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _stuck(Z, F, scale, kinds, limits, H, half_wave, x):
    """The stuck start of :class:`~fretwear.hbm.problem.Problem` at load ``scale``, in ``x``.

    Friction only: the centred stuck solution (zero harmonics but the means,
    which solve the mean equations); otherwise every unilateral contact closed at its gap.
    """
    nc = kinds.shape[0]
    for i in range(x.shape[0]):
        x[i] = 0.0
    if half_wave:
        return
    friction_only = True
    for c in range(nc):
        if kinds[c] != FRICTION:
            friction_only = False
            x[c * H] = limits[c]
    if friction_only:
        Zm = np.empty((nc, nc))
        b = np.empty(nc)
        piv = np.empty(nc, dtype=np.int64)
        for a in range(nc):
            b[a] = scale * F[a * H]
            for c in range(nc):
                Zm[a, c] = Z[a * H, c * H]
        if lu_factor(Zm, piv) == 0:
            for i in range(x.shape[0]):
                x[i] = np.nan
            return
        lu_solve(Zm, piv, b)
        for a in range(nc):
            x[a * H] = b[a]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _to_v(x, Z, F, scale, eps, H, v):
    """Augmented variables ``v = scale F + (E - Z) x`` (N) of the unknowns ``x`` (m)."""
    n = x.shape[0]
    for i in range(n):
        acc = scale * F[i] + eps[i // H] * x[i]
        for j in range(n):
            acc -= Z[i, j] * x[j]
        v[i] = acc


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _penalty_map(Z, eps, H, Winv, M):
    """``W^-1`` and ``M = Z W^-1 = E W^-1 - I`` for ``W = E - Z``; False if ``W`` is nearly singular.

    ``Z`` of a linear structure couples the slots of one harmonic only (across
    contacts): ``W`` is then inverted harmonic by harmonic (blocks of ``nc`` or
    ``2 nc``), else as a whole. The test for a nearly singular ``W`` is the
    same either way (the pivots of its LU factors).
    """
    n = Z.shape[0]
    first = H % 2  # 1: slot 0 is the mean, then (cos, sin) pairs; 0: pairs only (half-wave basis)
    blocks = True
    for i in range(n):
        gi = (i % H + first) // 2
        for j in range(n):
            if Z[i, j] != 0.0 and (j % H + first) // 2 != gi:
                blocks = False
    lo, hi = np.inf, 0.0
    if blocks:
        nc = n // H
        for i in range(n):
            for j in range(n):
                Winv[i, j] = 0.0
        for g in range((H + first) // 2):
            s0 = 2 * g - first if g else 0
            size = 1 if first and g == 0 else 2
            idx = np.empty(nc * size, dtype=np.int64)
            for c in range(nc):
                for k in range(size):
                    idx[c * size + k] = c * H + s0 + k
            b_lo, b_hi = _invert_block(Z, eps, H, idx, Winv)
            lo, hi = min(lo, b_lo), max(hi, b_hi)
    else:
        lo, hi = _invert_block(Z, eps, H, np.arange(n), Winv)
    if not lo > 1e-12 * hi:  # also a zero pivot (lo = -1)
        return False
    for i in range(n):
        for j in range(n):
            M[i, j] = eps[i // H] * Winv[i, j]
        M[i, i] -= 1.0
    return True


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _invert_block(Z, eps, H, idx, Winv):
    """``Winv[idx, idx] = W^-1`` of the rows and columns ``idx`` of ``W = E - Z``.

    Returns the smallest and largest magnitude of the LU pivots, ``(-1, 0)``
    for a zero pivot.
    """
    m = idx.shape[0]
    W, piv, col = np.empty((m, m)), np.empty(m, dtype=np.int64), np.empty(m)
    for a in range(m):
        for b in range(m):
            W[a, b] = -Z[idx[a], idx[b]]
        W[a, a] += eps[idx[a] // H]
    if lu_factor(W, piv) == 0:
        return -1.0, 0.0
    lo, hi = np.inf, 0.0
    for k in range(m):
        lo, hi = min(lo, abs(W[k, k])), max(hi, abs(W[k, k]))
    for b in range(m):
        for a in range(m):
            col[a] = 0.0
        col[b] = 1.0
        lu_solve(W, piv, col)
        for a in range(m):
            Winv[idx[a], idx[b]] = col[a]
    return lo, hi


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _march_buffers(n, nc, Ns):
    """Work arrays of one DLFT march: unknowns, then forces and states per contact and sample."""
    return (
        np.empty(n),
        np.empty((nc, Ns)),
        np.empty((nc, Ns)),
        np.empty((nc, Ns), dtype=np.int8),
        np.empty((nc, Ns), dtype=np.int64),
        np.ones((nc, Ns)),
        np.zeros((nc, 2), dtype=np.int64),
        np.empty((nc, Ns)),
    )


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def sweep_kernel(
    omegas,
    Zs,
    Fs,
    eps_user,
    eps_factor,
    kinds,
    limits,
    Phi,
    Psi,
    half_wave,
    tol,
    max_iter,
    x_start,
    x_out,
    R_out,
    lam_out,
    X_out,
    state_out,
    eps_out,
    status,
    reals,
):
    """Solve the DLFT equations at every frequency of ``omegas``, in order (see the module's text).

    Per frequency: the exact stuck solution when it holds (friction only);
    else, from the better of the secant prediction and the pattern prediction,
    ``GUESS_STEPS`` full Newton steps, then the global Newton homotopy from
    the best iterate and a polish; else the cold start of
    ``solve_problem()`` (Newton from the stuck
    start, then the exact load continuation and a polish).

    Parameters
    ----------
    omegas : (nw,) frequencies (rad/s). Zs, Fs : (nw, n, n), (nw, n) condensed stiffness (N/m) and force (N).
    eps_user : (nc,) penalties (N/m), or empty: ``eps_factor`` times the largest
        diagonal entry of ``Z`` per contact, as :class:`~fretwear.hbm.problem.Problem` chooses.
    kinds, limits, Phi, Psi, half_wave : as in :func:`fretwear.hbm.dlft.evaluate`.
    tol, max_iter : relative residual tolerance and Newton budget.
    x_start : (n,) unknowns to start the first frequency from (m), or empty for a cold start.
    x_out, R_out : (nw, n) out: unknowns (m) and residual (N). lam_out, X_out,
        state_out : (nw, nc, Ns) out: the march at the solution. eps_out : (nw, nc) out: penalties.
    status : (nw, 6) int64 out: ``PATH``, ``CONVERGED``, ``ITERATIONS``,
        ``CODE`` (0, or the failure), ``BUDGET`` (the last Newton budget),
        ``PIECES``. ``PATH`` is ``FALLBACK`` when ``E - Z`` is nearly singular:
        the caller solves that frequency.
    reals : (nw, 2) out: residual relative to the force scale; load factor reached by a load continuation.
    """
    nw, n = Fs.shape
    nc = kinds.shape[0]
    Ns, H = Phi.shape
    friction_only = True
    for c in range(nc):
        if kinds[c] != FRICTION:
            friction_only = False
    f0, f1 = (0, 1) if half_wave else (1, 2)  # slots of the fundamental
    stride = 1
    while ((Ns + stride - 1) // stride + 1) * H * H > BLOCK_SUMS_SIZE:
        stride *= 2
    P, Q = block_sums(Phi, Psi, stride)
    PhiT, PsiT = np.ascontiguousarray(Phi.T), np.ascontiguousarray(Psi.T)
    law = (kinds, limits, Phi, Psi, half_wave, PhiT, PsiT, P, Q, stride)
    cur, trial = _march_buffers(n, nc, Ns), _march_buffers(n, nc, Ns)
    work = (
        np.empty((n, n)),
        np.empty((H, H)),
        np.empty((n + 1, n + 1)),
        np.empty((nc, Ns)),
        np.empty(n + 1, dtype=np.int64),
        np.empty(n),
        np.empty((nc, Ns)),
        np.empty(n + 1),
        np.empty(n),
    )
    Winv, M = np.empty((n, n)), np.empty((n, n))
    x, v, vp, vn, r0, zero = np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.empty(n), np.zeros(n)
    w_prev, x_prev = np.zeros(2), np.zeros((2, n))  # zeros: a lone predecessor is read with a = 0
    codes, code = np.empty((2, nc, Ns), dtype=np.int8), np.empty((nc, Ns), dtype=np.int8)
    after_stuck = before_stuck = False  # the last (the one before) converged point is exactly stuck
    n_prev, n_codes = 0, 0  # converged points behind, and how many of them have their pattern in codes
    from_start = x_start.shape[0] > 0  # the prediction is x_start until a point converges
    if from_start:
        n_prev, w_prev[1] = 1, omegas[0]
        for k in range(n):
            x_prev[1, k] = x_start[k]
    # arguments of the inner calls as run-time values: constants would compile one specialisation each
    guess_steps, homotopy_pieces, load_pieces = (
        np.int64(GUESS_STEPS),
        np.int64(HOMOTOPY_PIECES),
        np.int64(100_000),
    )
    polish_iter, zero_steps, one_step, stall_steps = (
        np.int64(20),
        np.int64(0),
        np.int64(1),
        np.int64(STALL_STEPS),
    )
    newton_mode, load_mode = np.int64(NEWTON), np.int64(LOAD)
    for i in range(nw):
        Z, F, eps = Zs[i], Fs[i], eps_out[i]
        for c in range(nc):
            if eps_user.shape[0]:
                eps[c] = eps_user[c]
            else:
                jmax = c * H
                for j in range(c * H, (c + 1) * H):
                    if abs(Z[j, j]) > abs(Z[jmax, jmax]):
                        jmax = j
                eps[c] = eps_factor * abs(Z[jmax, jmax])
        scale0 = 0.0  # the residual scale of Problem.residual_scale, at full and at zero load
        for c in range(nc):
            if kinds[c] == FRICTION:
                scale0 = max(scale0, abs(limits[c]))
        scale = scale0
        for k in range(n):
            scale = max(scale, abs(F[k]))
        scale = scale if scale > 0 else 1.0
        scale0 = scale0 if scale0 > 0 else 1.0
        target = tol * scale
        st = status[i]
        for k in range(6):
            st[k] = 0
        reals[i, 0], reals[i, 1] = 0.0, 1.0
        ratio = 0.0
        if friction_only:
            for c in range(nc):
                ratio = max(ratio, np.sqrt(F[c * H + f0] ** 2 + F[c * H + f1] ** 2) / limits[c])
            if ratio < 1.0:
                _stuck(Z, F, 1.0, kinds, limits, H, half_wave, x)
                st[PATH], st[CONVERGED] = STUCK, 1
        if st[PATH] == 0 and not _penalty_map(Z, eps, H, Winv, M):
            st[PATH] = FALLBACK
            continue
        stage, carry, last = (GUESS if n_prev else COLD) if st[PATH] == 0 else DONE, 0, cur
        if stage == GUESS and after_stuck:  # slip sets in: the exact load path from the stuck solution
            stage = LOAD_CONTINUATION
        while stage != DONE:  # the stages of solve_problem; each: a start, a walk or not, then Newton
            walk_mode, p0, max_pieces, Fn, target_n = -1, 0.0, homotopy_pieces, F, target
            budget, min_steps, stall = max_iter, one_step, zero_steps
            r_start, first, second = -1.0, cur, trial  # the residual at the start, if known (in first)
            if stage == GUESS:  # from the better of the secant and the pattern predictions
                a = 0.0  # the secant, but not through a stuck solution: slip has just set in
                if n_prev == 2 and not before_stuck:
                    a = (omegas[i] - w_prev[1]) / (w_prev[1] - w_prev[0])
                for k in range(n):
                    x[k] = x_prev[1, k] + a * (x_prev[1, k] - x_prev[0, k])
                _to_v(x, Z, F, 1.0, eps, H, v)
                for c in range(nc):  # extrapolated runs, else the last pattern
                    if n_codes < 2 or not _predict_pattern(codes[0, c], codes[1, c], a, half_wave, code[c]):
                        for s_ in range(Ns):
                            code[c, s_] = codes[1, c, s_]
                rv = augmented_residual(v, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, *trial)
                r_start, first, second = rv, trial, cur  # Newton from the better start, its march in first
                if n_codes and _pattern_start(v, M, F, eps, law, code, trial, cur, work, vp):
                    rp = augmented_residual(vp, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, *cur)
                    if rp < rv:
                        r_start, first, second = rp, cur, trial
                        for k in range(n):
                            v[k] = vp[k]
                        if rp <= target:  # the pattern's solve was the full Newton step on the final piece
                            min_steps = zero_steps
                budget, stall = guess_steps, stall_steps
            elif stage == HOMOTOPY:  # the global Newton homotopy from the best iterate, then a polish
                augmented_residual(vn, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, r0, *cur[1:])
                for k in range(n):
                    v[k] = vn[k]
                walk_mode, budget = newton_mode, polish_iter
            elif stage == COLD:  # Newton from the stuck start
                _stuck(Z, F, 1.0, kinds, limits, H, half_wave, x)
                _to_v(x, Z, F, 1.0, eps, H, v)
                budget, min_steps = min(max_iter, 16), zero_steps
            elif stage == ZERO_LOAD_START:  # no friction-only problem: the solution at zero load first
                _stuck(Z, F, 0.0, kinds, limits, H, half_wave, x)
                _to_v(x, Z, F, 0.0, eps, H, v)
                Fn, target_n, min_steps = zero, tol * scale0, zero_steps
            else:  # LOAD_CONTINUATION: the exact load continuation, then a polish
                if friction_only:  # from the largest load that sticks
                    p0 = min(1.0, 1.0 / ratio)
                    _stuck(Z, F, p0, kinds, limits, H, half_wave, x)
                    _to_v(x, Z, F, p0, eps, H, v)
                else:  # from the solution at zero load
                    for k in range(n):
                        v[k] = vn[k]
                walk_mode, max_pieces = load_mode, load_pieces
            pieces, p = 0, 1.0
            if walk_mode >= 0:
                v_walk, p, pieces, arrived = _walk(
                    v, p0, 1.0, walk_mode, M, F, r0, eps, law, max_pieces, cur, work
                )
                for k in range(n):
                    v[k] = v_walk[k]
            vn, ok, it, r, flag, last = _newton(
                v, M, Fn, eps, law, target_n, budget, min_steps, stall, r_start, first, second, work
            )
            st[PIECES] = pieces
            if stage == GUESS:
                st[PATH], st[ITERATIONS], carry = DLFT, it, it
                stage = DONE if ok else HOMOTOPY
            elif stage == HOMOTOPY:
                carry += pieces + it
                st[PATH], st[ITERATIONS] = NEWTON_HOMOTOPY, carry
                stage = DONE if ok else COLD
            elif stage == COLD:
                st[PATH], st[ITERATIONS] = DLFT, it + carry
                stage = DONE if ok else (LOAD_CONTINUATION if friction_only else ZERO_LOAD_START)
            elif stage == ZERO_LOAD_START:
                st[PATH], st[ITERATIONS] = LOAD_HOMOTOPY, it + carry
                stage = LOAD_CONTINUATION if ok else DONE
                if not ok:
                    flag = ZERO_LOAD
                    r *= scale / scale0  # reported relative to the zero-load scale
            else:
                st[PATH], st[ITERATIONS] = LOAD_HOMOTOPY, it + pieces + carry
                reals[i, 1] = p
                stage = DONE
            st[CONVERGED], st[CODE], st[BUDGET] = ok, flag, budget
            reals[i, 0] = r / scale
            for k in range(n):
                v[k] = vn[k]
        if st[PATH] == STUCK:  # the march and the residual R = Z x - F + Psi lam, as the Problem has them
            _to_v(x, Z, F, 1.0, eps, H, v)
            R, lam, X, state, dep, sgn, hilo, U = cur
            augmented_march(
                v, eps, kinds, limits, PhiT, half_wave, lam_out[i], X_out[i], state_out[i], dep, sgn, hilo, U
            )
            for k in range(n):
                acc = -F[k]
                for j in range(n):
                    acc += Z[k, j] * x[j]
                c, slot = k // H, k % H
                for s_ in range(Ns):
                    acc += Psi[slot, s_] * lam_out[i, c, s_]
                R_out[i, k] = acc
        else:  # x = W^-1 (v - F); the march and R = M (v - F) - F + Psi lam (= Z x - F ...): the last step's
            R, lam, X, state = last[0], last[1], last[2], last[3]
            for k in range(n):
                acc = 0.0
                for j in range(n):
                    acc += Winv[k, j] * (v[j] - F[j])
                x[k] = acc
                R_out[i, k] = R[k]
            for c in range(nc):
                for s_ in range(Ns):
                    lam_out[i, c, s_], X_out[i, c, s_], state_out[i, c, s_] = (
                        lam[c, s_],
                        X[c, s_],
                        state[c, s_],
                    )
        for k in range(n):
            x_out[i, k] = x[k]
        if st[CONVERGED]:
            if from_start:
                n_prev, from_start = 0, False
            if n_prev:
                w_prev[0] = w_prev[1]
                for k in range(n):
                    x_prev[0, k] = x_prev[1, k]
                for c in range(nc):
                    for s_ in range(Ns):
                        codes[0, c, s_] = codes[1, c, s_]
            w_prev[1] = omegas[i]
            for k in range(n):
                x_prev[1, k] = x[k]
            for c in range(nc):
                state_code(kinds[c], lam_out[i, c], state_out[i, c], codes[1, c])
            n_prev, n_codes = min(n_prev + 1, 2), min(n_codes + 1, 2)
            before_stuck, after_stuck = after_stuck, st[PATH] == STUCK


def _callee_arguments() -> list[tuple]:
    """The callees of :func:`sweep_kernel`, slowest to compile first, with arguments of its types."""
    n, nc, Ns, H = 2, 1, 4, 2
    vec, mat, ivec = np.zeros(n), np.zeros((n, n)), np.zeros(n, np.int64)
    samples, codes, indices = np.zeros((nc, Ns)), np.zeros((nc, Ns), np.int8), np.zeros((nc, Ns), np.int64)
    Phi, Psi = np.zeros((Ns, H)), np.zeros((H, Ns))
    Phi.flags.writeable = Psi.flags.writeable = False  # a HarmonicBasis hands out read-only matrices
    kinds = np.zeros(nc, np.int64)
    P, Q = np.zeros((2, H, H)), np.zeros((Ns + 1, H))
    law = (kinds, np.zeros(nc), Phi, Psi, True, Psi.copy(), Phi.copy(), P, Q, 1)
    cur = (vec, samples, samples, codes, indices, samples, np.zeros((nc, 2), np.int64), samples)
    work = (mat, mat, mat, samples, ivec, vec, samples, vec, vec)
    return [
        (_pattern_start, (vec, mat, vec, vec, law, codes, cur, cur, work, vec)),
        (_newton, (vec, mat, vec, vec, law, 0.0, 1, 1, 1, 0.0, cur, cur, work)),
        (_walk, (vec, 0.0, 1.0, 1, mat, vec, vec, vec, law, 1, cur, work)),
        (_predict_pattern, (codes[0], codes[0], 0.0, True, codes[0])),
        (_penalty_map, (mat, vec, 1, mat, mat)),
        (_march_buffers, (1, 1, 1)),
        (_stuck, (mat, vec, 0.0, kinds, vec, 1, True, vec)),
        (_to_v, (vec, mat, vec, 0.0, vec, 1, vec)),
    ]


def compile_callees(share: int, shares: int) -> None:
    """Compile and cache the callees of :func:`sweep_kernel` from the ``share``-th, every ``shares``-th.

    Nothing runs: each is compiled for the argument types the sweep passes.
    On a cold start two processes compile their shares at once, and
    :func:`sweep_kernel` then loads its callees from the cache
    (:func:`fretwear.compile.compile_ahead`).
    """
    for kernel, arguments in _callee_arguments()[share::shares]:
        kernel.compile(tuple(typeof(a) for a in arguments))


_PATHS = {
    STUCK: "linear-stuck",
    DLFT: "dlft",
    NEWTON_HOMOTOPY: "dlft-newton-homotopy",
    LOAD_HOMOTOPY: "dlft-homotopy",
}


def _message(code: int, budget: int, pieces: int, load: float) -> str:
    """The failure message of ``fretwear.hbm.periodic.solve_problem()`` from a ``status`` row."""
    if code == ZERO_LOAD:
        return "no solution at zero load"
    return f"load continuation ended at load factor {load:.6g} after {pieces} pieces; " + newton_message(
        code, budget
    )


def solve(
    model: Model, omegas: np.ndarray, settings: dict, eps, tol: float, max_iter: int, guess=None
) -> list[PeriodicSolution | Problem]:
    """The periodic solutions at ``omegas`` (rad/s, validated) by :func:`sweep_kernel`.

    ``settings``: ``harmonics``, ``samples``, ``wear``, ``half_wave`` of
    :class:`~fretwear.hbm.problem.Problem`; ``guess``: unknowns to start the
    first frequency from. Where ``E - Z`` is nearly singular the entry is the
    prepared :class:`Problem` instead, for the caller to solve in ``x``; so is
    every entry for a model with Jenkins contacts, whose force is a function of
    ``x``, not of the augmented unknowns ``v`` of :func:`sweep_kernel` (in ``v``
    their Jacobian would couple every contact through ``(E - Z)^-1``).
    """
    batch: list[Condensed] = []

    def condensation(B: np.ndarray, basis) -> Condensed:  # every frequency at once
        batch.append(condense_sweep(model, B, omegas, basis))
        return Condensed(batch[0].Z[0], batch[0].F[0])

    first = Problem(model, omegas[0], eps=eps, condensed=condensation, **settings)  # one active set for all
    if first.n_active == 0:  # the linear open response, exact
        return [
            PeriodicSolution.build(p, None, NewtonResult(np.zeros(0), True, 0, 0.0), "linear-open")
            for p in (Problem(model, w, eps=eps, **settings) for w in omegas)
        ]
    x_start = np.empty(0)
    if guess is not None:
        x_start = np.array(guess, dtype=float)  # a copy: contiguous and writable, one compiled version
        if x_start.shape != (first.size,):
            raise ValueError(f"guess must have shape ({first.size},), got {x_start.shape}")
    if np.any(first.kinds == dlft.JENKINS):  # left to the caller: module text of fretwear.hbm.dlft
        return [
            Problem(model, w, eps=eps, condensed=Condensed(Zi, Fi), **settings)
            for w, Zi, Fi in zip(omegas.tolist(), batch[0].Z, batch[0].F, strict=True)
        ]
    b, (Zs, Fs) = first.basis, (batch[0].Z, batch[0].F)
    nw, n, nc, Ns = len(omegas), first.size, first.n_active, b.marched_samples
    x, R = np.empty((nw, n)), np.empty((nw, n))
    lam, X, state = np.empty((nw, nc, Ns)), np.empty((nw, nc, Ns)), np.empty((nw, nc, Ns), dtype=np.int8)
    eps_all, status, reals = np.empty((nw, nc)), np.empty((nw, 6), dtype=np.int64), np.empty((nw, 2))
    sweep_kernel(
        omegas,
        Zs,
        Fs,
        np.empty(0) if eps is None else first.eps,
        EPS_FACTOR,
        first.kinds,
        first.limits,
        b.synthesis,
        b.analysis,
        b.half_wave,
        float(tol),
        int(max_iter),
        x_start,
        x,
        R,
        lam,
        X,
        state,
        eps_all,
        status,
        reals,
    )
    batch = _Fields(model, first, omegas, lam, X, state, status[:, PATH] == FALLBACK)
    out: list[PeriodicSolution | Problem] = []
    for i, (omega, st, (res, load), Zi, Fi, xi, Ri, li, Xi, si, ei) in enumerate(zip(
        omegas.tolist(), status.tolist(), reals.tolist(), Zs, Fs, x, R, lam, X, state, eps_all, strict=True,
    )):  # fmt: skip
        path, ok, its, code, budget, pieces = st
        if path == FALLBACK:
            out.append(Problem(model, omega, eps=eps, condensed=Condensed(Zi, Fi), **settings))
            continue
        problem = first.at_frequency(omega, Zi, Fi, ei, (xi, Ri, li, Xi, si))
        message = "" if ok else _message(code, budget, pieces, load)
        result = NewtonResult(xi, ok == 1, its, res, message)
        out.append(PeriodicSolution.build(problem, xi, result, _PATHS[path], partial(batch.of, i)))
    return out


class _Fields:
    """Per frequency, the full-period march of every contact and the DOF harmonics, all at once.

    What :class:`PeriodicSolution` would compute point by point (the march and
    ``dof_harmonics``, eq. 10-11), batched over the frequencies of a sweep, on
    the first request of any of them; rows of ``fallback`` frequencies are
    left to their own solve.
    """

    def __init__(self, model: Model, first: Problem, omegas, lam, X, state, fallback) -> None:
        self.args = (model, first, omegas, lam, X, state, fallback)

    @cached_property
    def arrays(self) -> tuple[list[tuple], np.ndarray]:
        return _fields(*self.args)

    def of(self, i: int) -> tuple[tuple, np.ndarray]:
        """The march and the DOF harmonics (m) at frequency ``i``."""
        marches, dofs = self.arrays
        return marches[i], dofs[i]


def _fields(model: Model, first: Problem, omegas, lam, X, state, fallback):
    """The arrays of :class:`_Fields`: a list of marches, the DOF harmonics (nw, n, 2 Nh + 1)."""
    b = first.basis
    lam, X, state = lam.copy(), X.copy(), state.copy()
    lam[fallback], X[fallback], state[fallback] = 0.0, 0.0, dlft.STICK  # no garbage into the recovery
    lam_h = b.to_full(lam @ b.analysis.T)  # (nw, nc, 2 Nh + 1)
    if b.half_wave:
        lam, X, state = (
            np.concatenate([lam, -lam], -1),
            np.concatenate([X, -X], -1),
            np.concatenate([state, state], -1),
        )
    nw, n_all = len(omegas), len(model.contacts)
    force, slip = np.zeros((nw, n_all, b.samples)), np.zeros((nw, n_all, b.samples))
    states = np.full((nw, n_all, b.samples), dlft.OPEN, dtype=np.int8)
    force[:, first.active_index], slip[:, first.active_index], states[:, first.active_index] = lam, X, state
    dofs = recover(model, first.B, omegas, b.harmonics, lam_h, first.force_scale)
    return list(zip(force, slip, states, lam_h, strict=True)), dofs
