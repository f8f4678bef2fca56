"""One Newton's method and one piecewise-linear walk for every contact law (compiled).

The periodic DLFT equations of every structure read ``R(x) = Z x + Lambda(x) -
F = 0`` (eq. 12): ``x`` the harmonics of the contact coordinates, ``Lambda`` the
contact forces of a contact law marched over the samples of a period, with
the exact Jacobian ``J = Z + blockdiag(A) (E - Z)``
(:func:`fretwear.hbm.dlft.jacobian_from_blocks`). The residual is piecewise
linear, which both solvers here use:

* :func:`newton`: non-monotone Newton. Once the stick/slip/separation pattern
  is right a full step lands on the solution; on the way, full steps may raise
  the residual while the pattern settles (a monotone line search stalls at the
  kinks), so full steps are taken while the residual stays within a factor
  1000 of the best one seen, for half the budget; then a backtracking line
  search restarts from the best iterate;
* :func:`walk`: the solution curve of ``R(x; F0 + p F1) - (1 - p) r0 = 0`` in
  ``(x, p)`` is a polygon, followed piece by piece along the null vector of
  ``[dR/dx, dR/dp]`` to the next change of state (found exactly by the law) and
  just past it. ``F0 = 0, F1 = F, r0 = 0``: the load continuation;
  ``F0 = F, F1 = 0, r0 = R(x0)``: the global Newton homotopy; ``F0`` static,
  ``F1`` the excitation: the continuation in the excitation amplitude.

**The law** is handed as a tuple built by :func:`dlft_law` (1-D friction,
unilateral and Jenkins contacts, ``fretwear.hbm.dlft``; a Jenkins contact
is an alternating frequency-time law whose rows of ``J`` are ``Z + k_t A``,
:func:`fretwear.hbm.dlft.jacobian_of_kinds`) or :func:`coupled_law` (coupled
normal/tangential node pairs, ``fretwear.hbm.coupled``) or :func:`cone_law` (the
same pairs with 2-D friction, ``fretwear.hbm.cone``), whose integer code
chooses the law's functions inside the kernels. The 2-D law is smooth, not
linear, between changes of state: its walk is a predictor along tangents (its
pieces also bounded by the turn of the slip directions) whose end point the
caller polishes by Newton's method. It is told from the others by its type
(``xref`` of shape (nc, 2)) when a kernel is compiled, so that the kernels of
the other laws do not compile it. The other option, Numba
first-class functions (``types.FunctionType`` arguments), was measured: the
kernel itself loads from the on-disk cache, but every compiled caller that
passes it a law function (the sweep, the polynomial method's node solve)
cannot be cached ("uses dynamic globals") and would compile again in every
new process; with a code, every kernel caches and the law's functions are
inlined.

Each law keeps its linear algebra: the 1-D law's systems have tens of
unknowns, solved by the LU loops of :mod:`fretwear.hbm.dense`, which report a
singular matrix (code ``SINGULAR``; a singular walk ends where it started);
the coupled law's systems have hundreds, most of them in pairs stuck all
period whose block of ``J`` is ``diag(eps)``: those are eliminated first and
the rest solved by LAPACK, which raises on a singular matrix (the caller
reports it). With ``Z`` by harmonic blocks (the pair laws at scale) the
fixed and open coordinates are eliminated exactly and the mixed ones solved
by GMRES (:mod:`fretwear.hbm.krylov`), an inexact Newton step whose forcing
term (:func:`forcing`) keeps the convergence quadratic; convergence is
always judged on the true residual, so an inexact step can slow Newton down
but never make it report a wrong solution.
"""

from __future__ import annotations

import numpy as np
from numba import njit
from numba.extending import overload

from . import cone, coupled, dlft
from .dense import FASTMATH, lu_factor, lu_solve
from .krylov import COUNTERS, KRYLOV_MIN, cached_step, empty_cache

__all__ = [
    "DLFT", "COUPLED", "CONE", "CONVERGED", "NON_FINITE", "LINE_SEARCH", "BUDGET", "SINGULAR", "dlft_law",
    "coupled_law", "cone_law", "block_matvec", "evaluate_blocks", "newton", "walk", "tangent", "step_past",
    "keep_full_step", "forcing", "ETA_MAX", "FORCING_FLOOR",
]  # fmt: skip

#: law codes: the 1-D friction/unilateral law, the coupled normal/tangential pair law, its 2-D friction form
DLFT, COUPLED, CONE = 0, 1, 2
#: codes of :func:`newton`: converged, non-finite step, line search failed, budget, singular Jacobian
CONVERGED, NON_FINITE, LINE_SEARCH, BUDGET, SINGULAR = 0, 1, 2, 3, 4
#: the inexact (GMRES) steps' forcing term (:func:`forcing`): at most ``ETA_MAX`` of the residual, at least
#: ``FORCING_FLOOR`` of the target
ETA_MAX, FORCING_FLOOR = 1e-4, 0.1


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def dlft_law(kinds, limits, Phi, Psi, half_wave):
    """The law of :func:`fretwear.hbm.dlft.evaluate`: contact ``kinds``, ``limits`` (N or m), the iDFT
    ``Phi`` (Ns, H) and DFT ``Psi`` (H, Ns) matrices, ``half_wave`` march."""
    none = np.empty(0)
    return (np.int64(DLFT), kinds, limits, half_wave, none, none, none, Phi, Psi)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def coupled_law(gap, mu, xref, Phi, Psi):
    """The law of :func:`fretwear.hbm.coupled.evaluate`: per pair ``gap`` plus wear (m), friction
    coefficient ``mu`` and reference slip variable ``xref`` (m); ``Phi``, ``Psi`` as in :func:`dlft_law`."""
    none = np.empty(0)
    return (np.int64(COUPLED), np.empty(0, dtype=np.int64), none, False, gap, mu, xref, Phi, Psi)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def cone_law(gap, mu, xref, Phi, Psi):
    """The law of :func:`fretwear.hbm.cone.evaluate` (2-D friction): as :func:`coupled_law` with ``xref``
    (nc, 2) the two tangential reference slip variables of each pair (m)."""
    none = np.empty(0)
    return (np.int64(CONE), np.empty(0, dtype=np.int64), none, False, gap, mu, xref, Phi, Psi)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _buffers(law):
    """Work arrays of the law's march: Jacobian blocks ``A`` (nb, m, m), then per block and sample the
    (tangential) force, the normal force (coupled law), the slip variable and the state."""
    code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
    Ns, H = Phi.shape
    nb, m = (kinds.shape[0], H) if code == DLFT else (gap.shape[0], (3 if code == CONE else 2) * H)
    nt = 2 * nb if code == CONE else nb  # rows of tangential fields: two per pair with 2-D friction
    return (
        np.empty((nb, m, m)),
        np.empty((nt, Ns)),
        np.empty((0, Ns) if code == DLFT else (nb, Ns)),
        np.empty((nt, Ns)),
        np.empty((nb, Ns), dtype=np.int8),
    )


def _is_cone(law) -> bool:
    """Whether a law tuple's Numba type is :func:`cone_law`'s (its ``xref`` (nc, 2)): chosen when the
    kernel is compiled, so that the 2-D law is compiled only into the kernels that take it."""
    return law.types[6].ndim == 2


def _law_evaluate(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state):
    """Compiled only (:func:`_evaluate`)."""


@overload(_law_evaluate, jit_options={"fastmath": FASTMATH})
def _law_evaluate_typed(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state):
    if _is_cone(law):

        def cone_impl(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state):
            code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
            cone.evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, want_blocks, R, A, lam, lamN, X, state)

        return cone_impl

    def impl(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state):
        code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
        if code == DLFT:
            dlft.evaluate(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, want_blocks, R, A, lam, X, state)
        else:
            coupled.evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, want_blocks, R, A, lam, lamN, X, state)

    return impl


def _law_boundary(law, lu, dlu, eps, tau_max):
    """Compiled only (:func:`_boundary`)."""


@overload(_law_boundary, jit_options={"fastmath": FASTMATH})
def _law_boundary_typed(law, lu, dlu, eps, tau_max):
    if _is_cone(law):

        def cone_impl(law, lu, dlu, eps, tau_max):
            code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
            return cone.boundary_distance(lu, dlu, eps, gap, mu, xref, Phi, tau_max)

        return cone_impl

    def impl(law, lu, dlu, eps, tau_max):
        code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
        if code == DLFT:
            return dlft.boundary_distance(lu, dlu, eps, kinds, limits, Phi, half_wave, tau_max)
        return coupled.boundary_distance(lu, dlu, eps, gap, mu, xref, Phi, tau_max)

    return impl


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _evaluate(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state):
    """The law's residual (eq. 12) into ``R`` and, with ``want_blocks``, its blocks into ``A``."""
    _law_evaluate(law, x, Z, F, eps, want_blocks, R, A, lam, lamN, X, state)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _boundary(law, lu, dlu, eps, tau_max):
    """Largest step along ``lambda_u + tau d lambda_u`` (``tau <= tau_max``) that keeps every state."""
    return _law_boundary(law, lu, dlu, eps, tau_max)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def block_matvec(Zb, x):
    """``Z x`` from ``Z``'s harmonic blocks ``Zb`` (Nh + 1, 2 q, 2 q) (the layout of
    :func:`fretwear.hbm.structured.harmonic_blocks`) for ``x`` (q H,) contact-major: ``(Nh + 1) 4 q^2``
    products against ``(q H)^2`` for the dense ``Z``."""
    K = Zb.shape[0]
    H = 2 * K - 1
    q = Zb.shape[1] // 2
    y = np.zeros(q * H)
    xk = np.zeros(2 * q)  # the mean's block is on its first q coordinates: the sine half stays 0
    for c in range(q):
        xk[c] = x[c * H]
    yk = Zb[0] @ xk
    for c in range(q):
        y[c * H] = yk[c]
    for k in range(1, K):
        for c in range(q):
            xk[c] = x[c * H + 2 * k - 1]
            xk[q + c] = x[c * H + 2 * k]
        yk = Zb[k] @ xk
        for c in range(q):
            y[c * H + 2 * k - 1] = yk[c]
            y[c * H + 2 * k] = yk[q + c]
    return y


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def evaluate_blocks(law, x, Zb, F, eps, want_blocks, R, A, lam, lamN, X, state):
    """:func:`_evaluate` of a pair law (coupled or 2-D friction), ``Z`` given by harmonic blocks ``Zb``.

    ``Z x`` is taken block by block (:func:`block_matvec`), then every pair is
    the law's own evaluation on its ``d H`` unknowns alone, with ``F - Z x`` as its force and a zero
    ``Z``: ``R = Z x + Lambda(x) - F`` is the same (eq. 12), and the law is local per pair.
    """
    code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
    nc = gap.shape[0]
    m = x.shape[0] // nc
    d = eps.shape[0] // nc
    t = lam.shape[0] // nc  # rows of tangential fields a pair
    f = F - block_matvec(Zb, x)
    Z0 = np.zeros((m, m))
    for i in range(nc):
        r = slice(i * m, (i + 1) * m)
        sub = (code, kinds, limits, half_wave, gap[i : i + 1], mu[i : i + 1], xref[i : i + 1], Phi, Psi)
        rt = slice(i * t, (i + 1) * t)
        _law_evaluate(sub, x[r], Z0, f[r], eps[i * d : (i + 1) * d], want_blocks, R[r], A[i : i + 1], lam[rt],
                      lamN[i : i + 1], X[rt], state[i : i + 1])  # fmt: skip


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _residual(law, x, Z, F, eps, R, J, buffers, blocks=None):
    """Residual ``R`` and Jacobian ``J`` at ``x`` (with ``Z``'s harmonic ``blocks``: from them, no ``J``);
    returns ``max |R|`` (N)."""
    A, lam, lamN, X, state = buffers
    if blocks is not None:
        evaluate_blocks(law, x, blocks, F, eps, np.bool_(True), R, A, lam, lamN, X, state)
        return np.abs(R).max()
    _evaluate(law, x, Z, F, eps, np.bool_(True), R, A, lam, lamN, X, state)  # not a literal: one version
    if J.shape[0] > 0:  # else the structured step works from the blocks A alone
        dlft.jacobian_of_kinds(Z, eps, A, law[1], J)
    return np.abs(R).max()


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _eliminated_solve(J, R, A, eps):
    """Solve ``J dx = -R``, eliminating the blocks that are the identity first (LAPACK; raises if singular).

    A block closed and stuck all period at its reference slip variable has
    ``A_i = I``, so its rows of ``J`` are ``diag(eps)``: its step is ``-R / eps``
    and only the other blocks enter the dense solve (in partial slip the whole
    stick zone drops out).
    """
    nb, m = A.shape[0], A.shape[1]
    n = J.shape[0]
    H = n // eps.shape[0]
    fixed = np.zeros(nb, dtype=np.bool_)
    n_free = 0
    for i in range(nb):
        dev = 0.0
        for a in range(m):
            for b in range(m):
                dev = max(dev, abs(A[i, a, b] - (1.0 if a == b else 0.0)))
        fixed[i] = dev < 1e-12
        if not fixed[i]:
            n_free += m
    if n_free == n:
        return np.linalg.solve(J, -R)
    dx = np.zeros(n)
    free = np.empty(n_free, dtype=np.int64)
    k = 0
    for i in range(nb):
        for a in range(m):
            r = i * m + a
            if fixed[i]:
                dx[r] = -R[r] / eps[r // H]
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


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _direction(code, J, R, A, eps, piv, dx, blocks, atol, krylov_min, stats, cache):
    """The Newton step ``dx = -J^-1 R`` by the law's linear algebra (module text) and the step cache;
    False if ``J`` is singular (the LU loops; ``J`` is overwritten by its factors). With ``Z``'s harmonic
    ``blocks`` (pair laws), the step of :func:`fretwear.hbm.krylov.cached_step` (no ``J``): the open and
    fixed coordinates eliminated exactly (reusing the last step's factors while the kinds are the same),
    the mixed ones by GMRES to the linear residual ``atol`` (N) from ``krylov_min`` mixed unknowns, else
    exactly."""
    if blocks is not None:
        cache = cached_step(blocks, A, R, eps, dx, atol, krylov_min, stats, cache)[1]
        return True, cache
    if code != DLFT:
        dx[:] = _eliminated_solve(J, R, A, eps)
        return True, cache
    if lu_factor(J, piv) == 0:
        return False, cache
    dx[:] = -R
    lu_solve(J, piv, dx)
    return True, cache


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def forcing(r, r0, target):
    """The linear residual (N) to which an inexact Newton step from residual ``r`` solves (``r0`` the
    solve's first residual, ``target`` its tolerance, both N): ``eta r`` with ``eta = min(ETA_MAX, r / r0)``,
    which makes Newton's convergence quadratic near the solution (``r_next ~ r^2 / r0``), but no tighter
    than ``FORCING_FLOOR`` times ``target``: a step on the solution's stick/slip pattern, where the
    residual is linear, then lands within the tolerance (the linear residual is a 2-norm, at least the
    largest entry that the tolerance judges)."""
    return max(FORCING_FLOOR * target, min(ETA_MAX, r / max(r0, 1e-300)) * r)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def keep_full_step(r, best, it, max_iter):
    """Whether full Newton step ``it`` (counted from 1) to residual ``r`` is kept, ``best`` the least seen.

    The non-monotone rule of :func:`newton` (and of the Galerkin Newton of
    ``fretwear.wear.polynomial``): within a factor 1000 of the best
    residual, for the first half of the budget ``max_iter``.
    """
    return np.isfinite(r) and r < 1e3 * best and it < max_iter // 2


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def newton(law, x0, Z, F, eps, target, max_iter, blocks=None, krylov_min=KRYLOV_MIN, stats=None):
    """Non-monotone Newton's method from ``x0`` with a damped fallback from the best iterate (module text).

    Parameters
    ----------
    law : tuple of :func:`dlft_law` or :func:`coupled_law`.
    x0 : (n,) start (m). Z, F : dynamic stiffness (n, n) (N/m) and force (n,) (N).
    eps : penalty per coordinate (N/m). target : float, converged when ``max |R| <= target`` (N).
    max_iter : int, Newton steps at most.
    blocks : (Nh + 1, 2 q, 2 q) ``Z`` by harmonic (``fretwear.hbm.structured.harmonic_blocks()``), pair
        laws only: the residuals by ``evaluate_blocks()`` and the steps by
        :func:`~fretwear.hbm.krylov.krylov_step`, no dense ``Z`` or ``J`` (``Z`` may then be empty).
    krylov_min : int, with ``blocks``: the mixed unknowns from which the steps are inexact, by GMRES to the
        forcing term :func:`forcing`; below, exact (:func:`~fretwear.hbm.structured.structured_step`'s).
    stats : (5,) int64, optional, with ``blocks``: counters accumulated by
        :func:`~fretwear.hbm.krylov.cached_step` (GMRES steps, products, fallbacks, exact steps, reused
        eliminations).

    Returns ``(x, converged, iterations, max|R|, code)``, ``code`` one of
    ``CONVERGED``, ``NON_FINITE``, ``LINE_SEARCH``, ``BUDGET``, and ``(x0,
    False, 0, inf, SINGULAR)`` for a singular Jacobian.
    """
    code = law[0]
    n = x0.shape[0]
    counters = np.zeros(COUNTERS, dtype=np.int64) if stats is None else stats
    cache = empty_cache()
    buffers = _buffers(law)
    A = buffers[0]
    R, Rt, dx = np.empty(n), np.empty(n), np.empty(n)
    nJ = n if blocks is None else 0
    J, Jt = np.empty((nJ, nJ)), np.empty((nJ, nJ))
    piv = np.empty(n, dtype=np.int64)
    x = x0.copy()
    r = _residual(law, x, Z, F, eps, R, J, buffers, blocks)
    best_r, best_x = r, x.copy()
    r0 = r
    it = 0
    damped = False
    while it < max_iter:
        if r <= target:
            return x, True, it, r, CONVERGED
        atol = forcing(r, r0, target)
        # J is computed again before it is used again
        ok, cache = _direction(code, J, R, A, eps, piv, dx, blocks, atol, krylov_min, counters, cache)
        if not ok:
            return x0.copy(), False, 0, np.inf, SINGULAR
        if not np.all(np.isfinite(dx)):
            if damped:
                return x, False, it, r, NON_FINITE
            damped = True
            x = best_x.copy()
            r = _residual(law, x, Z, F, eps, R, J, buffers, blocks)
            continue
        it += 1
        if not damped:
            xt = x + dx
            rt = _residual(law, xt, Z, F, eps, Rt, Jt, buffers, blocks)
            if keep_full_step(rt, best_r, it, max_iter):
                x, r = xt, rt
                R[:] = Rt
                J[:, :] = Jt
                if r < best_r:
                    best_r, best_x = r, x.copy()
                continue
            damped = True
            x = best_x.copy()
            r = _residual(law, x, Z, F, eps, R, J, buffers, blocks)
            continue
        step = 1.0
        accepted = False
        xt = x
        rt = r
        for _ in range(30):
            xt = x + step * dx
            rt = _residual(law, xt, Z, F, eps, Rt, Jt, buffers, blocks)
            if rt < (1 - 1e-4 * step) * r:
                accepted = True
                break
            step *= 0.5
        if not accepted:
            return x, False, it, r, LINE_SEARCH
        x, r = xt, rt
        R[:] = Rt
        J[:, :] = Jt
    if r <= target:
        return x, True, it, r, CONVERGED
    return x, False, it, r, BUDGET


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def tangent(aug, piv, t, orientation):
    """Unit tangent ``t`` of ``[J dR]`` from ``aug = [J dR; row]`` (factorised in place), oriented.

    ``sign(det [J dR; t]) = sign(det [J dR; row])`` for ``t`` solving
    ``[J dR; row] t = e_n+1``, so one LU factorisation gives both; ``t`` is
    flipped to keep ``orientation`` (0: the first piece, any). Returns the
    sign kept, 0 for a singular ``aug``.
    """
    m = aug.shape[0]
    sign = lu_factor(aug, piv)
    if sign == 0:
        return 0
    for i in range(m):
        t[i] = 0.0
    t[m - 1] = 1.0
    lu_solve(aug, piv, t)
    norm = 0.0
    for i in range(m):
        norm += t[i] * t[i]
    flip = -1.0 if orientation != 0 and sign != orientation else 1.0
    scale = flip / np.sqrt(norm)
    for i in range(m):
        t[i] *= scale
    return orientation if flip < 0 else sign


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _tangent_lapack(aug, orientation):
    """:func:`tangent` by LAPACK for the large systems of the coupled law (raises if singular)."""
    m = aug.shape[0]
    rhs = np.zeros(m)
    rhs[m - 1] = 1.0
    t = np.linalg.solve(aug, rhs)
    t /= np.sqrt(np.sum(t * t))
    aug[m - 1, :] = t
    sign = int(np.linalg.slogdet(aug)[0])
    if orientation != 0 and sign != orientation:
        t = -t
        sign = orientation
    return t, sign


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def step_past(tau, big, stalled):
    """The step that goes just past a state change at distance ``tau``, and the new count of stalls.

    ``big``: the size of the point (``max |x|, |p|``), which sets the nudge
    past the change. A vertex where several samples change state at once can
    send a walk back and forth between their pieces without progress: each
    stalled piece (``tau`` below the nudge) steps ten times further past.
    """
    nudge = 1e-13 * (big + 1e-300)
    stalled = stalled + 1 if tau < nudge else 0
    return tau * (1 + 1e-9) + nudge * 10.0 ** min(stalled, 8), stalled


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _slid(X, half_wave):
    """Distance slid per period from the slip variable of the march (m)."""
    n = X.shape[0]
    total = 0.0
    for s in range(n):
        prev = X[s - 1] if s > 0 else (-X[n - 1] if half_wave else X[n - 1])
        total += abs(X[s] - prev)
    return 2.0 * total if half_wave else total


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def walk(law, x0, p0, p_end, Z, F0, F1, r0, eps, max_pieces, rec_x, rec_p, rec_s):
    """Follow the piecewise-linear solution curve of ``R(x; F0 + p F1) - (1 - p) r0 = 0`` to ``p_end``.

    Parameters
    ----------
    law : tuple of :func:`dlft_law` or :func:`coupled_law`.
    x0, p0 : (n,) start on the curve (m) and its parameter. p_end : float, where to stop.
    Z : (n, n) dynamic stiffness (N/m). F0, F1 : (n,) forces (N): ``F0 + p F1`` at ``p``.
    r0 : (n,) residual offset (N) of the Newton homotopy (zeros otherwise).
    eps : penalty per coordinate (N/m). max_pieces : int, pieces at most.
    rec_x, rec_p, rec_s : (k, n), (k,), (k,) out, or with no rows: the start of every
        piece (unknowns, parameter and the distance slid per period by the first
        block's slip variable, m), which are linear in ``p`` within a piece; the
        end point last.

    Returns ``(x, p, pieces, arrived, recorded)``; the tangent keeps the sign of
    ``det [J dR/dp; t]``, the invariant of a regular curve across the kinks (a
    dot product with the previous tangent is not). A singular augmented matrix
    ends the walk where it started (no piece).
    """
    code, kinds, limits, half_wave, gap, mu, xref, Phi, Psi = law
    n = x0.shape[0]
    A, lam, lamN, X, state = _buffers(law)
    nb, m = A.shape[0], A.shape[1]
    R, J, dR = np.empty(n), np.empty((n, n)), np.empty(n)
    H = n // eps.shape[0]
    E = np.empty(n)
    for k in range(n):
        E[k] = eps[k // H]
    x = x0.copy()
    p = p0
    row = np.zeros(n + 1)
    row[n] = 1.0
    orientation = 0
    n_rec = rec_x.shape[0]
    k = 0
    aug, piv, t = np.empty((n + 1, n + 1)), np.empty(n + 1, dtype=np.int64), np.empty(n + 1)
    blocks, no_blocks = np.bool_(True), np.bool_(False)  # not literals: one version of evaluate
    stalled = 0
    for piece in range(1, max_pieces + 1):
        Fp = F0 + p * F1
        _evaluate(law, x, Z, Fp, eps, blocks, R, A, lam, lamN, X, state)
        if k < n_rec - 1:
            rec_x[k] = x
            rec_p[k] = p
            rec_s[k] = _slid(X[0], half_wave)
            k += 1
        dlft.jacobian_of_kinds(Z, eps, A, kinds, J)
        for c in range(nb):  # dR/dp = -(I - A) F1 + r0, block by block; a Jenkins force ignores F
            jenkins = c < kinds.shape[0] and kinds[c] == dlft.JENKINS
            AF = A[c] @ F1[c * m : (c + 1) * m]
            for j in range(m):
                dR[c * m + j] = -(F1[c * m + j] - (0.0 if jenkins else AF[j])) + r0[c * m + j]
        aug[:n, :n] = J
        aug[:n, n] = dR
        aug[n, :] = row
        if code != DLFT:
            t, orientation = _tangent_lapack(aug, orientation)
        else:
            orientation = tangent(aug, piv, t, orientation)
        if orientation == 0:  # singular: the walk ends where it started
            return x0.copy(), p0, 0, False, 0
        tx = t[:n]
        reach = (p_end - p) / t[n] if t[n] > 0 else np.inf
        lu = Fp - Z @ x + E * x
        dlu = -(Z @ tx) + E * tx + t[n] * F1
        dlft.jenkins_lagrangian(x, eps, kinds, H, lu)  # a Jenkins contact marches k_t x
        dlft.jenkins_lagrangian(tx, eps, kinds, H, dlu)
        tau = _boundary(law, lu, dlu, eps, min(reach, 1e300))
        if reach <= tau:
            x = x + reach * tx
            if n_rec > 0:
                _evaluate(law, x, Z, F0 + p_end * F1, eps, no_blocks, R, A, lam, lamN, X, state)
                rec_x[k] = x
                rec_p[k] = p_end
                rec_s[k] = _slid(X[0], half_wave)
                k += 1
            return x, p_end, piece, True, k
        step, stalled = step_past(tau, max(np.abs(x).max(), abs(p)), stalled)
        x = x + step * tx
        p = p + step * t[n]
        row[:] = t
    return x, p, max_pieces, False, k
