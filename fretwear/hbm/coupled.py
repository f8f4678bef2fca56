"""Coupled normal/tangential DLFT law of a contact node pair, residual and exact Jacobian (eq. 17-23).

Unknowns are the harmonics of the contact coordinates ``q = (u_T, u_N)`` of
every pair (contact-major: entry ``c H + j`` is slot ``j`` of coordinate ``c``,
with ``c = 2 i`` the tangential and ``c = 2 i + 1`` the normal coordinate of
pair ``i``). The augmented Lagrangian of eq. 18,

    lambda_u = F - Z q + eps q,

is taken to time by the iDFT. For pair ``i`` at sample ``n`` (compressive
normal force positive, gap ``g_i = g0_i + w_i``, initial gap plus wear):

* normal prediction (eq. 19) ``lambda_N = lambda_u,N - eps_N g_i``; if it is
  not compressive the pair separates (eq. 21): ``lambda_N = lambda_T = 0`` and
  the slip variable follows the pair, ``X_T = lambda_u,T / eps_T``;
* otherwise the friction limit is ``L_n = mu lambda_N`` (varying in time with
  the normal force), stick is predicted, ``lambda_T = lambda_u,T - eps_T
  X_T^{n-1}`` (eq. 22), and if ``|lambda_T| >= L_n`` the pair slips: ``lambda_T =
  L_n sign`` and ``X_T`` moves (eq. 23).

The residual is eq. 12, ``R = Z q + Lambda - F`` (``= eps (q - X~)``).

**Periodicity.** Each sample maps the slip variable by a clamp, ``X_n =
clip(X_{n-1}, lo_n, hi_n)`` with ``lo, hi = (lambda_u,T -+ L_n) / eps_T``
(``lo = hi`` for an open sample), and a composition of clamps is either a
constant or a clamp. The period map is composed in one pass: a constant is
the unique periodic slip variable (some sample slips or opens); a clamp
``[A, B]`` means the pair can stick all period at any ``X`` in ``[A, B]`` and the
pair keeps its reference ``X_ref`` (the slip variable reached when the normal
load was applied, or at the previous slow-time step), clipped into ``[A,
B]``: a pair that never slips stays where it stuck. A second pass then
marches from the periodic start.

**Jacobian.** The law is piecewise linear in ``lambda_u``: a stick sample
``n`` whose slip variable was set at sample ``m`` (the last slip, separation or
clip) has ``lambda_T^n = lambda_u,T^n - lambda_u,T^m + s_m mu lambda_N^m``; a
slip sample has ``lambda_T^n = s_n mu lambda_N^n``; a closed sample has
``lambda_N^n = lambda_u,N^n - eps_N g``. Its exact derivative gives ``J = Z +
A (E - Z)`` with ``A`` block-diagonal, one ``2H x 2H`` block ``Psi (d lambda / d
lambda_u) Phi`` per pair (assembled by :func:`fretwear.hbm.dlft.jacobian_from_blocks`,
shared with the 1-D law). The periodic solvers of both laws are
``fretwear.hbm.newton``.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..model.structure import OPEN, SLIP, STICK

__all__ = ["STICK", "SLIP", "OPEN", "march_pair", "evaluate", "slip_work", "boundary_distance"]

# how the tangential force of a sample depends on lambda_u (see _march_pair)
_OPEN_ROW, _SLIP_ROW, _STICK_FROM, _STICK_REF = 0, 1, 2, 3


@njit(cache=True, nogil=True)
def _period_map(uT, uN, gap, mu, epsT, epsN):
    """The period map of the slip variable composed over the samples (see the module's text).

    Returns ``(const, value, source, sign, A, B, srcA, srcB)``: a constant map
    (``const``) with its ``value`` set at sample ``source`` by a slip of
    ``sign`` (0 for an opening); else a clamp to ``[A, B]`` whose bounds are set
    at samples ``srcA``, ``srcB``.
    """
    const = False
    cval, csrc, csgn = 0.0, -1, 0.0
    A, B = -np.inf, np.inf
    srcA, srcB = -1, -1
    for s in range(uT.shape[0]):
        pN = uN[s] - epsN * gap
        L = mu * pN if pN > 0.0 else 0.0
        lo = (uT[s] - L) / epsT
        hi = (uT[s] + L) / epsT
        if const:
            if cval < lo:
                cval, csrc, csgn = lo, s, 1.0
            elif cval > hi:
                cval, csrc, csgn = hi, s, -1.0
        elif B < lo:
            const = True
            cval, csrc, csgn = lo, s, 1.0
        elif A > hi:
            const = True
            cval, csrc, csgn = hi, s, -1.0
        else:
            if lo > A:
                A, srcA = lo, s
            if hi < B:
                B, srcB = hi, s
    return const, cval, csrc, csgn, A, B, srcA, srcB


@njit(cache=True, nogil=True)
def march_pair(uT, uN, gap, mu, epsT, epsN, xref, lamT, lamN, X, state, kind, src, sgn):
    """Periodic DLFT march of one pair over the samples of a period.

    Parameters
    ----------
    uT, uN : (Ns,) augmented Lagrangian ``lambda_u`` in time (N).
    gap : float, gap plus wear (m). mu : float. epsT, epsN : penalties (N/m).
    xref : float, reference slip variable of a pair that sticks all period (m).
    lamT, lamN, X : (Ns,) out: contact forces (N) and slip variable (m).
    state : (Ns,) int8 out: STICK, SLIP, OPEN.
    kind, src, sgn : (Ns,) out: derivative encoding (row kind, source sample, sign).
    """
    n = uT.shape[0]
    const, cval, csrc, csgn, A, B, srcA, srcB = _period_map(uT, uN, gap, mu, epsT, epsN)
    if const:
        x, cur, cur_sgn = cval, csrc, csgn
    elif xref < A:
        x, cur, cur_sgn = A, srcA, 1.0
    elif xref > B:
        x, cur, cur_sgn = B, srcB, -1.0
    else:
        x, cur, cur_sgn = xref, -1, 0.0
    for s in range(n):
        pN = uN[s] - epsN * gap
        if pN <= 0.0:
            lamN[s] = 0.0
            lamT[s] = 0.0
            x = uT[s] / epsT
            state[s] = OPEN
            kind[s] = _OPEN_ROW
            cur, cur_sgn = s, 0.0
        else:
            L = mu * pN
            lamN[s] = pN
            pred = uT[s] - epsT * x
            if abs(pred) < L:
                lamT[s] = pred
                state[s] = STICK
                if cur >= 0:
                    kind[s] = _STICK_FROM
                    src[s] = cur
                    sgn[s] = cur_sgn
                else:
                    kind[s] = _STICK_REF
            else:
                sg = 1.0 if pred > 0 else -1.0
                lamT[s] = sg * L
                x = (uT[s] - lamT[s]) / epsT
                state[s] = SLIP
                kind[s] = _SLIP_ROW
                sgn[s] = sg
                cur, cur_sgn = s, sg
        X[s] = x


@njit(cache=True, nogil=True)
def _block(Phi, Psi, mu, state, kind, src, sgn, GT, GN, GNN, Ai):
    """Ai (2H, 2H) = Psi (d lambda / d lambda_u) Phi for one pair, from the march's encoding."""
    Ns, H = Phi.shape
    GT[:, :] = 0.0
    GN[:, :] = 0.0
    GNN[:, :] = 0.0
    for s in range(Ns):
        k = kind[s]
        if k == _STICK_FROM:
            m = src[s]
            for j in range(H):
                p = Psi[j, s]
                GT[j, s] += p
                GT[j, m] -= p
                if state[m] != OPEN:
                    GN[j, m] += sgn[s] * mu * p
        elif k == _STICK_REF:
            for j in range(H):
                GT[j, s] += Psi[j, s]
        elif k == _SLIP_ROW:
            for j in range(H):
                GN[j, s] += sgn[s] * mu * Psi[j, s]
        if state[s] != OPEN:
            for j in range(H):
                GNN[j, s] += Psi[j, s]
    Ai[:, :] = 0.0
    Ai[:H, :H] = GT @ Phi
    Ai[:H, H:] = GN @ Phi
    Ai[H:, H:] = GNN @ Phi


@njit(cache=True, nogil=True)
def evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, want_blocks, R, A, lamT, lamN, X, state):
    """DLFT residual of eq. 12 for every pair and, optionally, the Jacobian blocks.

    Parameters
    ----------
    x : (2 nc H,) harmonics of the contact coordinates (m), contact-major.
    Z, F : reduced dynamic stiffness (2 nc H, 2 nc H) (N/m) and force (2 nc H,) (N).
    eps : (2 nc,) penalty per coordinate (N/m). gap : (nc,) gap plus wear (m).
    mu : (nc,) friction coefficients. xref : (nc,) reference slip variables (m).
    Phi, Psi : iDFT (Ns, H) and DFT (H, Ns) matrices.
    want_blocks : bool, fill ``A`` (nc, 2H, 2H).
    R : (2 nc H,) residual out (N). lamT, lamN, X : (nc, Ns) out. state : (nc, Ns) int8 out.
    """
    nc = gap.shape[0]
    Ns, H = Phi.shape
    lu = F - Z @ x
    kind = np.empty(Ns, dtype=np.int64)
    src = np.zeros(Ns, dtype=np.int64)
    sgn = np.zeros(Ns)
    GT, GN, GNN = np.empty((H, Ns)), np.empty((H, Ns)), np.empty((H, Ns))
    for i in range(nc):
        t0, n0 = 2 * i * H, (2 * i + 1) * H
        for j in range(H):
            lu[t0 + j] += eps[2 * i] * x[t0 + j]
            lu[n0 + j] += eps[2 * i + 1] * x[n0 + j]
        uT = Phi @ lu[t0 : t0 + H]
        uN = Phi @ lu[n0 : n0 + H]
        march_pair(
            uT, uN, gap[i], mu[i], eps[2 * i], eps[2 * i + 1], xref[i], lamT[i], lamN[i], X[i], state[i],
            kind, src, sgn,
        )  # fmt: skip
        LT = Psi @ lamT[i]
        LN = Psi @ lamN[i]
        for j in range(H):
            R[t0 + j] = LT[j] - F[t0 + j]
            R[n0 + j] = LN[j] - F[n0 + j]
        if want_blocks:
            _block(Phi, Psi, mu[i], state[i], kind, src, sgn, GT, GN, GNN, A[i])
    R += Z @ x


@njit(cache=True, nogil=True)
def slip_work(X, lamN, state):
    """Per pair: distance slid per period ``s`` (m) and ``sum_n lambda_N^n |X^n - X^(n-1)|`` (N m).

    Only slip increments count (a separated pair's slip variable follows it
    without friction). The second sum over the pair's area is the Archard
    integrand ``int p ds`` per cycle of eq. 15 (Pa m).
    """
    nc, Ns = X.shape
    s = np.zeros(nc)
    w = np.zeros(nc)
    for i in range(nc):
        for n in range(Ns):
            if state[i, n] == SLIP:
                d = abs(X[i, n] - X[i, n - 1 if n > 0 else Ns - 1])
                s[i] += d
                w[i] += lamN[i, n] * d
    return s, w


@njit(cache=True, nogil=True)
def _cross(v, dv, level, tau):
    """Smallest t in [0, tau) with v + t dv = level (else tau)."""
    if dv != 0.0:
        t = (level - v) / dv
        if 0.0 <= t < tau:
            return t
    return tau


@njit(cache=True, nogil=True)
def _pair_boundary(uT, duT, uN, duN, gap, mu, epsT, epsN, xref, tau):
    """Distance along ``lambda_u + t d lambda_u`` to the first change of the pair's sample states."""
    n = uT.shape[0]
    const, cval, csrc, csgn, A, B, srcA, srcB = _period_map(uT, uN, gap, mu, epsT, epsN)
    for s in range(n):  # separations and contacts
        tau = _cross(uN[s] - epsN * gap, duN[s], 0.0, tau)
    if not const:
        if xref < A:
            const, csrc, csgn = True, srcA, 1.0
        elif xref > B:
            const, csrc, csgn = True, srcB, -1.0
    if not const:  # sticks all period at X = xref: leaves the cone somewhere
        for s in range(n):
            pN = uN[s] - epsN * gap
            pred, dpred = uT[s] - epsT * xref, duT[s]
            tau = _cross(pred - mu * pN, dpred - mu * duN[s], 0.0, tau)
            tau = _cross(pred + mu * pN, dpred + mu * duN[s], 0.0, tau)
        return tau
    # march one full turn from the sample that sets the slip variable, with first-order sensitivities
    s0 = csrc
    pN0 = uN[s0] - epsN * gap
    if pN0 > 0.0:
        x = (uT[s0] - csgn * mu * pN0) / epsT
        dx = (duT[s0] - csgn * mu * duN[s0]) / epsT
    else:
        x, dx = uT[s0] / epsT, duT[s0] / epsT
    for v in range(1, n + 1):
        s = (s0 + v) % n
        pN, dpN = uN[s] - epsN * gap, duN[s]
        if pN <= 0.0:
            x, dx = uT[s] / epsT, duT[s] / epsT
            continue
        L, dL = mu * pN, mu * dpN
        pred, dpred = uT[s] - epsT * x, duT[s] - epsT * dx
        if abs(pred) < L:
            tau = _cross(pred - L, dpred - dL, 0.0, tau)
            tau = _cross(pred + L, dpred + dL, 0.0, tau)
        else:
            sg = 1.0 if pred > 0 else -1.0
            if sg * dpred - dL < 0.0:  # moving back into the cone
                tau = _cross(sg * pred - L, sg * dpred - dL, 0.0, tau)
            x = (uT[s] - sg * L) / epsT
            dx = (duT[s] - sg * dL) / epsT
    return tau


@njit(cache=True, nogil=True)
def boundary_distance(lu, dlu, eps, gap, mu, xref, Phi, tau_max):
    """Largest step ``t <= tau_max`` along ``lambda_u + t d lambda_u`` that keeps every sample's state.

    The residual is linear on each such piece, so a straight path in the
    unknowns is exact up to the returned distance.
    """
    nc = gap.shape[0]
    H = Phi.shape[1]
    tau = tau_max
    for i in range(nc):
        t0, n0 = 2 * i * H, (2 * i + 1) * H
        tau = _pair_boundary(
            Phi @ lu[t0 : t0 + H], Phi @ dlu[t0 : t0 + H], Phi @ lu[n0 : n0 + H], Phi @ dlu[n0 : n0 + H],
            gap[i], mu[i], eps[2 * i], eps[2 * i + 1], xref[i], tau,
        )  # fmt: skip
    return tau
