"""Coupled normal/tangential DLFT law with 2-D friction (circular Coulomb cone), residual and exact Jacobian.

The 3-D counterpart of ``fretwear.hbm.coupled`` (eq. 17-23 with a tangential
plane instead of a line). Unknowns are the harmonics of the contact
coordinates ``q = (u_T1, u_T2, u_N)`` of every pair, contact-major: entry ``c H
+ j`` is slot ``j`` of coordinate ``c``, with ``c = 3 i``, ``3 i + 1`` the two
tangential and ``c = 3 i + 2`` the normal coordinate of pair ``i``. The
augmented Lagrangian ``lambda_u = F - Z q + eps q`` (eq. 18) is taken to time by
the iDFT. For pair ``i`` at sample ``n`` (compressive normal force positive,
gap ``g_i`` = initial gap plus wear):

* normal prediction (eq. 19) ``lambda_N = lambda_u,N - eps_N g_i``; if it is
  not compressive the pair separates (eq. 21): ``lambda_N = 0``, ``lambda_T =
  0`` and the slip variable follows the pair, ``X = E_T^-1 lambda_u,T``;
* otherwise stick is predicted (eq. 22), ``lambda_T = lambda_u,T - E_T
  X^{n-1}`` (2-vectors, ``E_T = diag(eps_T1, eps_T2)``), and if ``|lambda_T| >=
  L_n = mu lambda_N`` the pair slips (eq. 23 in 2-D): ``lambda_T = L_n
  lambda_T / |lambda_T|`` and ``X^n = E_T^-1 (lambda_u,T - lambda_T)``.

In the variable ``y = E_T X`` (N) a sample is the projection of ``y^{n-1}`` on
the disk of centre ``c_n = lambda_u,T^n`` and radius ``L_n`` (radius 0 when open),
``lambda_T^n = c_n - y^n``: the friction force resists the slip increment
``X^n - X^{n-1}``, which it is parallel to. That increment is a backward
difference: on a circle the friction lags the velocity by ``pi / N`` (``N``
samples per period), an ``O(1 / N)`` error against Coulomb's law in continuous
time that the 1-D law only shows at its reversals (``tests/hbm/test_cone.py``:
3.6e-2 on the radius of a sliding circle at ``N = 64``, halving with ``N``).

**Periodic start.** The period map is a composition of projections on disks,
non-expansive. Three cases, in this order:

1. some sample opens: the slip variable is set there, the march starts at the
   last opening and is periodic at once;
2. the disks have a common point: every point of their intersection is a fixed
   point, the pair can stick all period, and it keeps its reference ``X_ref``
   (where it stuck when the normal load was applied) projected on the
   intersection, the nearest admissible point: ``fretwear.hbm.coupled``'s
   clip into ``[A, B]`` is this projection in 1-D. A pair never slips unless it
   must. The projection lies inside (nothing active), on one circle (the
   projection on that disk) or at a corner of two circles;
3. otherwise the fixed point is unique (the pair slips every period) and is
   found by Newton's method on ``P(y) - y = 0`` with the period's 2x2 transfer
   matrix ``T`` (product of the samples' ``dy^n / dy^{n-1}``: ``I`` for a stick,
   ``(L / |p|) (I - u u^T)`` for a slip in direction ``u``, 0 for an opening),
   safeguarded by a plain march (``|P(y) - y|`` never grows under it), to
   round-off. Newton lands in one or two steps once the pattern is right;
   marching alone converges like ``prod L / |p|``, close to 1 for slips that
   barely leave the cone.

**Jacobian.** The law is smooth between changes of state (not piecewise
linear: the projection turns with the slip direction). The sensitivity of
the slip variable ``Y_n = d y^n / d lambda_u`` is marched with it, ``Y_n = T_n
Y_{n-1} + S_n (d c_n, d L_n)``, from the start's: 0 after an opening or for a
pair stuck at its reference; the derivative of the projection for a pair
stuck on a circle or a corner; ``(I - T)^-1`` times the period's sum for a
slipping pair. The ``3H x 3H`` block of each pair is ``Psi (d lambda / d
lambda_u) Phi`` and ``J = Z + blockdiag(A) (E - Z)``
(:func:`fretwear.hbm.dlft.jacobian_from_blocks`), solved by the compiled
solvers of ``fretwear.hbm.newton`` (law code ``CONE``).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..model.structure import OPEN, SLIP, STICK

__all__ = ["STICK", "SLIP", "OPEN", "march_pair", "evaluate", "slip_work", "boundary_distance"]

#: relative tolerance of the tests "inside every disk" (of the scale of the pair's forces)
_FEASIBLE = 1e-12
#: the periodic start is converged when ``|P(y) - y|`` is below this times the pair's force scale
_PERIODIC = 1e-14
#: largest turn of a slip direction along one piece of the walk (rad): the law is smooth, not linear, there
_TURN = 0.05
#: how the start of the march was set: an opening, the reference, the projection on the disks, a slip cycle
_FROM_OPEN, _AT_REF, _PROJECTED, _CYCLE = 0, 1, 2, 3


@njit(cache=True, nogil=True)
def _period(c1, c2, L, y1, y2):
    """March every sample from ``y`` (entering sample 0) of a pair closed all period.

    Returns ``(y1, y2, t11, t12, t21, t22)``: the state after the last sample and
    the period's transfer matrix ``T = dP / dy``.
    """
    t11, t12, t21, t22 = 1.0, 0.0, 0.0, 1.0
    for n in range(c1.shape[0]):
        p1, p2 = c1[n] - y1, c2[n] - y2
        rho = np.hypot(p1, p2)
        if rho >= L[n]:
            u1, u2 = (p1 / rho, p2 / rho) if rho > 0.0 else (0.0, 0.0)
            s = L[n] / rho if rho > 0.0 else 0.0
            y1, y2 = c1[n] - L[n] * u1, c2[n] - L[n] * u2
            # T <- s (I - u u^T) T
            a11, a12, a21, a22 = s * (1 - u1 * u1), -s * u1 * u2, -s * u1 * u2, s * (1 - u2 * u2)
            t11, t12, t21, t22 = (a11 * t11 + a12 * t21, a11 * t12 + a12 * t22,
                                  a21 * t11 + a22 * t21, a21 * t12 + a22 * t22)  # fmt: skip
    return y1, y2, t11, t12, t21, t22


@njit(cache=True, nogil=True)
def _fixed_point(c1, c2, L, y1, y2, scale):
    """The periodic state ``y = P(y)`` of a pair closed all period (case 3 of the module's text).

    Newton's method with the period's transfer matrix, a step kept when it at
    least halves ``|P(y) - y|``; else one plain march (non-expansive).
    """
    e1, e2, t11, t12, t21, t22 = _period(c1, c2, L, y1, y2)
    g = np.hypot(e1 - y1, e2 - y2)
    for _ in range(200):
        if g <= _PERIODIC * scale:
            break
        a, b, c, d = t11 - 1.0, t12, t21, t22 - 1.0
        det = a * d - b * c
        kept = False
        if det != 0.0:
            g1, g2 = e1 - y1, e2 - y2
            z1 = y1 + (-g1 * d + g2 * b) / det
            z2 = y2 + (c * g1 - a * g2) / det
            f1, f2, s11, s12, s21, s22 = _period(c1, c2, L, z1, z2)
            h = np.hypot(f1 - z1, f2 - z2)
            if h <= 0.5 * g:
                y1, y2, e1, e2, g = z1, z2, f1, f2, h
                t11, t12, t21, t22 = s11, s12, s21, s22
                kept = True
        if not kept:
            y1, y2 = e1, e2
            e1, e2, t11, t12, t21, t22 = _period(c1, c2, L, y1, y2)
            g = np.hypot(e1 - y1, e2 - y2)
    return y1, y2


@njit(cache=True, nogil=True)
def _inside_all(c1, c2, L, y1, y2, tol):
    """Whether ``y`` is in every disk, to ``tol`` (N)."""
    for n in range(c1.shape[0]):
        if np.hypot(y1 - c1[n], y2 - c2[n]) > L[n] + tol:
            return False
    return True


@njit(cache=True, nogil=True)
def _some_disjoint(c1, c2, L):
    """Whether two of the disks are disjoint (then the intersection is empty)."""
    n = c1.shape[0]
    for a in range(n):
        for b in range(a + 1, n):
            if np.hypot(c1[a] - c1[b], c2[a] - c2[b]) > L[a] + L[b]:
                return True
    return False


@njit(cache=True, nogil=True)
def _project(c1, c2, L, r1, r2, tol):
    """Projection of ``r`` outside the disks on their intersection (case 2 of the module's text).

    Returns ``(found, y1, y2, a, b)``, ``a`` and ``b`` the active disks (``b = -1``
    for one). A projection on one disk that lies in all is the answer; else it
    is a corner of two circles, one of them a disk ``r`` violates.
    """
    n = c1.shape[0]
    for k in range(n):
        rho = np.hypot(r1 - c1[k], r2 - c2[k])
        if rho > L[k]:
            p1 = c1[k] + L[k] * (r1 - c1[k]) / rho
            p2 = c2[k] + L[k] * (r2 - c2[k]) / rho
            if _inside_all(c1, c2, L, p1, p2, tol):
                return True, p1, p2, k, -1
    best, y1, y2, ka, kb = np.inf, 0.0, 0.0, -1, -1
    for a in range(n):
        if np.hypot(r1 - c1[a], r2 - c2[a]) <= L[a]:
            continue
        for b in range(n):
            d1, d2 = c1[b] - c1[a], c2[b] - c2[a]
            d = np.hypot(d1, d2)
            if b == a or d == 0.0 or d > L[a] + L[b] or d < abs(L[a] - L[b]):
                continue
            along = (L[a] * L[a] - L[b] * L[b] + d * d) / (2.0 * d)
            h = np.sqrt(max(L[a] * L[a] - along * along, 0.0))
            for side in (-1.0, 1.0):
                p1 = c1[a] + (along * d1 - side * h * d2) / d
                p2 = c2[a] + (along * d2 + side * h * d1) / d
                dist = np.hypot(p1 - r1, p2 - r2)
                if dist < best and _inside_all(c1, c2, L, p1, p2, tol):
                    best, y1, y2, ka, kb = dist, p1, p2, a, b
    return ka >= 0, y1, y2, ka, kb


@njit(cache=True, nogil=True)
def _start_sensitivity(y1, y2, r1, r2, c1, c2, L, mu, a, b, D1, D2, DN, Y0):
    """``Y0 = d y / d(inputs)`` (2, m) of the projection ``y`` of the fixed ``r`` on disk ``a`` or the
    corner of circles ``a``, ``b`` (``D1``, ``D2``, ``DN``: the derivatives of c_n, uN_n)."""
    if b < 0:  # y = c + L w, w = (r - c) / |r - c|: dy = (I - (L / rho)(I - w w^T)) dc + w dL
        rho = np.hypot(r1 - c1[a], r2 - c2[a])
        w1, w2 = (r1 - c1[a]) / rho, (r2 - c2[a]) / rho
        s = L[a] / rho
        m11, m12, m22 = 1.0 - s * (1.0 - w1 * w1), s * w1 * w2, 1.0 - s * (1.0 - w2 * w2)
        Y0[0] = m11 * D1[a] + m12 * D2[a] + w1 * mu * DN[a]
        Y0[1] = m12 * D1[a] + m22 * D2[a] + w2 * mu * DN[a]
        return
    # |y - c_k| = L_k for k = a, b: (y - c_k) . (dy - dc_k) = L_k dL_k
    n11, n12, n21, n22 = y1 - c1[a], y2 - c2[a], y1 - c1[b], y2 - c2[b]
    ra = n11 * D1[a] + n12 * D2[a] + L[a] * mu * DN[a]
    rb = n21 * D1[b] + n22 * D2[b] + L[b] * mu * DN[b]
    det = n11 * n22 - n12 * n21
    Y0[0] = (n22 * ra - n12 * rb) / det
    Y0[1] = (-n21 * ra + n11 * rb) / det


@njit(cache=True, nogil=True)
def march_pair(c1, c2, uN, gap, mu, epsT1, epsT2, epsN, xref1, xref2, D1, D2, DN, want,
               lamT1, lamT2, lamN, X1, X2, state, Y):  # fmt: skip
    """Periodic DLFT march of one pair over the samples of a period, with the slip variable's sensitivity.

    Parameters
    ----------
    c1, c2, uN : (Ns,) augmented Lagrangian ``lambda_u`` in time (N): tangential and normal.
    gap : float, gap plus wear (m). mu : float. epsT1, epsT2, epsN : penalties (N/m).
    xref1, xref2 : float, reference slip variable of a pair that can stick all period (m).
    D1, D2, DN : (Ns, m) derivatives of ``c1``, ``c2``, ``uN`` at each sample with respect to
        ``m`` inputs (the harmonics of ``lambda_u``, or one direction).
    want : bool, compute ``Y``.
    lamT1, lamT2, lamN, X1, X2 : (Ns,) out: contact forces (N) and slip variable (m).
    state : (Ns,) int8 out: STICK, SLIP, OPEN.
    Y : (Ns, 2, m) out with ``want``: ``d (E_T X^n) / d(inputs)`` (N).
    """
    n = c1.shape[0]
    m = D1.shape[1]
    L = np.empty(n)
    last_open = -1
    scale = 0.0
    for s in range(n):
        pN = uN[s] - epsN * gap
        L[s] = mu * pN if pN > 0.0 else 0.0
        if pN <= 0.0:
            last_open = s
        scale = max(scale, abs(c1[s]), abs(c2[s]), L[s])
    r1, r2 = epsT1 * xref1, epsT2 * xref2
    Y0 = np.zeros((2, m))
    if last_open >= 0:
        how, s0, y1, y2 = _FROM_OPEN, last_open, 0.0, 0.0
    elif _inside_all(c1, c2, L, r1, r2, 0.0):
        how, s0, y1, y2 = _AT_REF, 0, r1, r2
    else:
        found, a, b = False, -1, -1
        if not _some_disjoint(c1, c2, L):
            found, y1, y2, a, b = _project(c1, c2, L, r1, r2, _FEASIBLE * scale)
        if found:
            how, s0 = _PROJECTED, 0
            if want:
                _start_sensitivity(y1, y2, r1, r2, c1, c2, L, mu, a, b, D1, D2, DN, Y0)
        else:
            how, s0 = _CYCLE, 0
            y1, y2 = _fixed_point(c1, c2, L, r1, r2, scale)
    Q = np.empty((n, 2, 2))  # T_n ... T_0 of a slip cycle, for the periodic correction of Y
    q11, q12, q21, q22 = 1.0, 0.0, 0.0, 1.0
    Yp = Y0
    for v in range(n):
        s = (s0 + v) % n
        t11, t12, t21, t22 = 1.0, 0.0, 0.0, 1.0
        if uN[s] - epsN * gap <= 0.0:
            y1, y2 = c1[s], c2[s]
            lamT1[s], lamT2[s], lamN[s] = 0.0, 0.0, 0.0
            state[s] = OPEN
            t11, t22 = 0.0, 0.0
            if want:
                Y[s, 0] = D1[s]
                Y[s, 1] = D2[s]
        else:
            lamN[s] = uN[s] - epsN * gap
            p1, p2 = c1[s] - y1, c2[s] - y2
            rho = np.hypot(p1, p2)
            if rho < L[s]:
                lamT1[s], lamT2[s] = p1, p2
                state[s] = STICK
                if want:
                    Y[s] = Yp
            else:
                # y = c - L u, u = p / |p|, p = c - y_prev: dy = (I - K) dc - u dL + K dy_prev,
                # K = (L / rho)(I - u u^T) (rho = 0 only at a zero limit: y = c)
                u1, u2 = (p1 / rho, p2 / rho) if rho > 0.0 else (0.0, 0.0)
                k = L[s] / rho if rho > 0.0 else 0.0
                lamT1[s], lamT2[s] = L[s] * u1, L[s] * u2
                y1, y2 = c1[s] - lamT1[s], c2[s] - lamT2[s]
                state[s] = SLIP
                t11, t12, t21, t22 = k * (1 - u1 * u1), -k * u1 * u2, -k * u1 * u2, k * (1 - u2 * u2)
                if want:
                    for j in range(m):
                        d1, d2, dn = D1[s, j], D2[s, j], mu * DN[s, j]
                        e1, e2 = Yp[0, j], Yp[1, j]
                        Y[s, 0, j] = t11 * e1 + t12 * e2 + (1 - t11) * d1 - t12 * d2 - u1 * dn
                        Y[s, 1, j] = t21 * e1 + t22 * e2 - t21 * d1 + (1 - t22) * d2 - u2 * dn
        X1[s], X2[s] = y1 / epsT1, y2 / epsT2
        q11, q12, q21, q22 = (t11 * q11 + t12 * q21, t11 * q12 + t12 * q22,
                              t21 * q11 + t22 * q21, t21 * q12 + t22 * q22)  # fmt: skip
        Q[s, 0, 0], Q[s, 0, 1], Q[s, 1, 0], Q[s, 1, 1] = q11, q12, q21, q22
        if want:
            Yp = Y[s]
    if want and how == _CYCLE:
        # the start y* = P(y*) moves with the inputs: Y* = (I - T)^-1 Y_end(start held), then Y_n += Q_n Y*
        a, b, c, d = 1.0 - q11, -q12, -q21, 1.0 - q22
        det = a * d - b * c
        if det != 0.0:  # a singular I - T: a cycle that only touches the cone; the start is then held
            e = Y[n - 1].copy()
            y01 = (d * e[0] - b * e[1]) / det
            y02 = (-c * e[0] + a * e[1]) / det
            for s in range(n):
                Y[s, 0] += Q[s, 0, 0] * y01 + Q[s, 0, 1] * y02
                Y[s, 1] += Q[s, 1, 0] * y01 + Q[s, 1, 1] * y02


@njit(cache=True, nogil=True)
def _inputs(Phi):
    """``(D1, D2, DN)`` (Ns, 3H): each sample's ``c1``, ``c2``, ``uN`` as rows over a pair's harmonics."""
    Ns, H = Phi.shape
    D1, D2, DN = np.zeros((Ns, 3 * H)), np.zeros((Ns, 3 * H)), np.zeros((Ns, 3 * H))
    D1[:, :H] = Phi
    D2[:, H : 2 * H] = Phi
    DN[:, 2 * H :] = Phi
    return D1, D2, DN


@njit(cache=True, nogil=True)
def _block(Phi, Psi, D1, D2, DN, state, Y, W, Ai):
    """Ai (3H, 3H) = Psi (d lambda / d lambda_u) Phi: ``lambda_T^n = c_n - y^n``, and ``lambda_N^n = uN^n -
    eps_N g`` when closed."""
    Ns, H = Phi.shape
    Ai[:, :] = 0.0
    for r in range(2):
        D = D1 if r == 0 else D2
        for s in range(Ns):
            W[s] = D[s] - Y[s, r]
        Ai[r * H : (r + 1) * H, :] = Psi @ W
    for s in range(Ns):
        if state[s] == OPEN:
            W[s] = 0.0
        else:
            W[s] = DN[s]
    Ai[2 * H :, :] = Psi @ W


@njit(cache=True, nogil=True)
def evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, want_blocks, R, A, lamT, lamN, X, state):
    """DLFT residual of eq. 12 for every pair and, optionally, the Jacobian blocks.

    Parameters
    ----------
    x : (3 nc H,) harmonics of the contact coordinates (m), contact-major.
    Z, F : reduced dynamic stiffness (3 nc H, 3 nc H) (N/m) and force (3 nc H,) (N).
    eps : (3 nc,) penalty per coordinate (N/m). gap : (nc,) gap plus wear (m).
    mu : (nc,) friction coefficients. xref : (nc, 2) reference slip variables ``(X_1, X_2)`` (m).
    Phi, Psi : iDFT (Ns, H) and DFT (H, Ns) matrices.
    want_blocks : bool, fill ``A`` (nc, 3H, 3H).
    R : (3 nc H,) residual out (N). lamT, X : (2 nc, Ns) out, rows ``2 i``, ``2 i + 1`` the two tangential
        components of pair ``i``. lamN : (nc, Ns) out. state : (nc, Ns) int8 out.
    """
    nc = gap.shape[0]
    Ns, H = Phi.shape
    lu = F - Z @ x
    D1, D2, DN = _inputs(Phi)
    Y = np.empty((Ns, 2, 3 * H) if want_blocks else (Ns, 2, 0))
    W = np.empty((Ns, 3 * H))
    for i in range(nc):
        b = 3 * i * H
        for j in range(3 * H):
            lu[b + j] += eps[3 * i + j // H] * x[b + j]
        march_pair(
            Phi @ lu[b : b + H], Phi @ lu[b + H : b + 2 * H], Phi @ lu[b + 2 * H : b + 3 * H], gap[i], mu[i],
            eps[3 * i], eps[3 * i + 1], eps[3 * i + 2], xref[i, 0], xref[i, 1], D1, D2, DN, want_blocks,
            lamT[2 * i], lamT[2 * i + 1], lamN[i], X[2 * i], X[2 * i + 1], state[i], Y,
        )  # fmt: skip
        L1, L2, LN = Psi @ lamT[2 * i], Psi @ lamT[2 * i + 1], Psi @ lamN[i]
        for j in range(H):
            R[b + j] = L1[j] - F[b + j]
            R[b + H + j] = L2[j] - F[b + H + j]
            R[b + 2 * H + j] = LN[j] - F[b + 2 * H + j]
        if want_blocks:
            _block(Phi, Psi, D1, D2, DN, state[i], Y, W, A[i])
    R += Z @ x


@njit(cache=True, nogil=True)
def slip_work(X, lamN, state):
    """Per pair: distance slid per period ``s`` (m) and ``sum_n lambda_N^n |X^n - X^(n-1)|`` (N m).

    ``X`` (2 nc, Ns) as :func:`evaluate` fills it; only slip increments count
    (a separated pair's slip variable follows it without friction). The
    friction work per period is ``mu`` times the second sum: a slip increment is
    parallel to its friction force of magnitude ``mu lambda_N``.
    """
    nc, Ns = lamN.shape
    s = np.zeros(nc)
    w = np.zeros(nc)
    for i in range(nc):
        for n in range(Ns):
            if state[i, n] == SLIP:
                p = n - 1 if n > 0 else Ns - 1
                d = np.hypot(X[2 * i, n] - X[2 * i, p], X[2 * i + 1, n] - X[2 * i + 1, p])
                s[i] += d
                w[i] += lamN[i, n] * d
    return s, w


@njit(cache=True, nogil=True)
def _smallest_root(a, b, c, tau):
    """Smallest root in ``(0, tau)`` of ``a t^2 + b t + c`` (else ``tau``)."""
    if a == 0.0:
        if b != 0.0:
            t = -c / b
            if 0.0 < t < tau:
                return t
        return tau
    disc = b * b - 4.0 * a * c
    if disc < 0.0:
        return tau
    sq = np.sqrt(disc)
    q = -0.5 * (b + (sq if b >= 0 else -sq))
    for t in (q / a, c / q if q != 0.0 else np.inf):
        if 0.0 < t < tau:
            tau = t
    return tau


@njit(cache=True, nogil=True)
def boundary_distance(lu, dlu, eps, gap, mu, xref, Phi, tau_max):
    """A step ``t <= tau_max`` along ``lambda_u + t d lambda_u`` for the walk of ``fretwear.hbm.newton``.

    The law is smooth, not linear, between changes of state: the distance is
    that to the first change of a sample's state along the linearised march
    (a separation, a prediction crossing the cone ``|p| = L``), and at most the
    one that turns a slip direction by ``_TURN`` rad. The walk is then a
    predictor whose end point the caller polishes by Newton's method.
    """
    nc = gap.shape[0]
    Ns, H = Phi.shape
    tau = tau_max
    lamT1, lamT2, lamN = np.empty(Ns), np.empty(Ns), np.empty(Ns)
    X1, X2 = np.empty(Ns), np.empty(Ns)
    state = np.empty(Ns, dtype=np.int8)
    Y = np.empty((Ns, 2, 1))
    for i in range(nc):
        b = 3 * i * H
        c1, c2, uN = Phi @ lu[b : b + H], Phi @ lu[b + H : b + 2 * H], Phi @ lu[b + 2 * H : b + 3 * H]
        D1 = np.ascontiguousarray((Phi @ dlu[b : b + H]).reshape(Ns, 1))
        D2 = np.ascontiguousarray((Phi @ dlu[b + H : b + 2 * H]).reshape(Ns, 1))
        DN = np.ascontiguousarray((Phi @ dlu[b + 2 * H : b + 3 * H]).reshape(Ns, 1))
        e1, e2, eN = eps[3 * i], eps[3 * i + 1], eps[3 * i + 2]
        march_pair(c1, c2, uN, gap[i], mu[i], e1, e2, eN, xref[i, 0], xref[i, 1], D1, D2, DN, True,
                   lamT1, lamT2, lamN, X1, X2, state, Y)  # fmt: skip
        for s in range(Ns):
            pN = uN[s] - eN * gap[i]
            if DN[s, 0] != 0.0:  # separation or contact
                t = -pN / DN[s, 0]
                if 0.0 < t < tau:
                    tau = t
            if pN <= 0.0:
                continue
            prev = s - 1 if s > 0 else Ns - 1
            p1, p2 = c1[s] - e1 * X1[prev], c2[s] - e2 * X2[prev]
            dp1, dp2 = D1[s, 0] - Y[prev, 0, 0], D2[s, 0] - Y[prev, 1, 0]
            L, dL = mu[i] * pN, mu[i] * DN[s, 0]
            tau = _smallest_root(dp1 * dp1 + dp2 * dp2 - dL * dL, 2.0 * (p1 * dp1 + p2 * dp2 - L * dL),
                                 p1 * p1 + p2 * p2 - L * L, tau)  # fmt: skip
            if state[s] == SLIP:
                rho = np.hypot(p1, p2)
                turn = abs(p1 * dp2 - p2 * dp1) / rho  # |d p_perp|
                if turn > 0.0:
                    tau = min(tau, _TURN * rho / turn)
    return tau
