"""Dynamic Lagrangian Frequency-Time (DLFT) contact law: residual and Jacobian (eq. 17-23).

Unknowns are the harmonics ``x`` of the relative contact displacements. The
augmented Lagrangian of eq. 18 is

    lambda_u = F_r - Z_r x + eps x              (frequency domain),

taken to time by the iDFT. A prediction/correction march over the period
enforces the contact laws sample by sample:

* friction (eq. 19, 22, 23): predict stick, ``lambda = lambda_u - eps X_{n-1}``;
  if ``|lambda| >= mu F_N`` correct to slip, ``lambda = mu F_N sign``, and move
  the slip variable ``X_n = (lambda_u - lambda) / eps``;
* unilateral contact (eq. 21): compressive prediction ``lambda_u - eps g > 0``
  keeps contact (``X = g``), otherwise separation (``lambda = 0``).

The DFT brings ``lambda`` back and the residual is eq. 12,
``R = Z_r x + Lambda - F_r`` (equal to ``eps (x - X~)``).

Periodicity of the friction march: when the span of ``lambda_u`` over the period
exceeds ``2 mu F_N`` the sample of largest ``|lambda_u|`` is necessarily in slip,
which fixes the state there exactly; the march starts from it and one pass
gives the periodic solution. Otherwise the contact sticks all period and the
slip variable is undetermined (the singular Jacobian of full stick). The stick
force is then *centred*: zero mean when that stays in the cone (the symmetric
solution when the forcing has no mean), else mid-range; the derivative of this
choice keeps the Jacobian regular.

The residual is piecewise linear in ``x`` (stick: ``lambda_n = lambda_u,n -
lambda_u,m + lambda_m`` with ``m`` the last slip sample; slip: constant), and
the Jacobian below is its exact derivative on each piece.

**Jenkins contacts** (kind ``JENKINS``: a tangential stiffness ``k_t`` in series
with Coulomb friction) are an alternating frequency-time law, not a DLFT one:
the force follows from the relative displacement itself by the return map

    f_{j+1} = clip(f_j + k_t (x_{j+1} - x_j), -mu F_N, +mu F_N),

which is the friction march above with ``lambda_u = k_t x`` and ``eps = k_t``
(the slip variable ``X`` is then the slider's position ``s``, ``f = k_t (x -
s)``), so the same march, periodic start and derivative rows serve both. The
contact's penalty slot holds ``k_t``. Its residual is still eq. 12, ``R = Z_r x
+ Lambda(x) - F_r``, but ``d lambda_u / d x = k_t I`` instead of ``E - Z_r``:
the Jacobian rows are ``Z_r + k_t A_c`` (:func:`jacobian_of_kinds`), with
``A_c = Psi (d lambda / d lambda_u) Phi``: in stick ``d f_n / d x = k_t (e_n -
e_m)`` back to the last slip sample ``m`` (the start of the stick interval),
in slip zero. Full stick: the slider is undetermined by a periodic march; the
stick force is centred as above, ``f = k_t (x - mean(x))`` (zero mean force,
the symmetric solution under a forcing without mean), or mid-range when that
leaves the cone.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from ..model.structure import OPEN, SLIP, STICK
from .dense import FASTMATH

__all__ = [
    "FRICTION", "UNILATERAL", "STICK", "SLIP", "OPEN", "evaluate", "jacobian_from_blocks", "augmented_march",
    "sampled_march", "augmented_residual", "assemble_augmented", "sampled_residual", "augmented_jacobian",
    "augmented_boundary", "block_sums", "state_code", "forced_march", "JENKINS", "jacobian_of_kinds",
    "jenkins_lagrangian",
]  # fmt: skip

FRICTION, UNILATERAL, JENKINS = 0, 1, 2  # contact kinds: rigid friction, unilateral, Jenkins (AFT)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _march_friction(u, limit, eps, half_wave, lam, X, state, dep, sgn):
    """Friction march on one contact. Fills lam, X, state; dep/sgn encode d lam / d u.

    Row ``s`` of ``d lam / d u`` is ``e_s - sgn[s] e_dep[s]`` for a stick sample with a
    preceding slip sample; ``dep[s] = -1`` marks a slip/open row (zero). Full stick
    rows: ``-2`` is ``e_s - mean``, ``-5`` is ``e_s - (e_hi + e_lo) / 2``, ``-3`` is ``e_s``.
    """
    n = u.shape[0]
    if limit <= 0.0:
        for s in range(n):
            lam[s] = 0.0
            X[s] = u[s] / eps
            state[s] = OPEN
            dep[s] = -1
        return
    hi_i, lo_i, big_i = 0, 0, 0
    for s in range(n):
        if u[s] > u[hi_i]:
            hi_i = s
        if u[s] < u[lo_i]:
            lo_i = s
        if abs(u[s]) > abs(u[big_i]):
            big_i = s
    # full stick: the slip variable is undetermined; centre the stick force in the cone
    code = 0
    if half_wave:
        if abs(u[big_i]) <= limit:
            code, centre = -3, 0.0  # antiperiodic: symmetric about zero
    else:
        mean = 0.0
        for s in range(n):
            mean += u[s]
        mean /= n
        if max(u[hi_i] - mean, mean - u[lo_i]) <= limit:
            code, centre = -2, mean  # zero mean stick force
        elif u[hi_i] - u[lo_i] <= 2.0 * limit:
            code, centre = -5, 0.5 * (u[hi_i] + u[lo_i])  # mid-range
    if code != 0:
        for s in range(n):
            X[s] = centre / eps
            lam[s] = u[s] - centre
            state[s] = STICK
            dep[s] = code
        return
    # start at the sample of largest |lambda_u|: necessarily slipping
    s0 = big_i
    sign0 = 1.0 if u[s0] > 0 else -1.0
    lam[s0] = sign0 * limit
    X[s0] = (u[s0] - lam[s0]) / eps
    state[s0] = SLIP
    dep[s0] = -1
    y_prev = u[s0] - lam[s0]  # eps times the slip variable, in the marched (virtual) frame
    last = s0
    last_sign = 1.0
    for v in range(1, n):
        s = s0 + v
        p = 1.0
        if s >= n:
            s -= n
            if half_wave:
                p = -1.0
        uv = p * u[s]
        pred = uv - y_prev  # eps X carried, not X: no division on the march's chain of samples
        if abs(pred) < limit:
            lam_v = pred
            state[s] = STICK
            dep[s] = last
            sgn[s] = p * last_sign
        else:
            lam_v = limit if pred > 0 else -limit
            y_prev = uv - lam_v
            state[s] = SLIP
            dep[s] = -1
            last = s
            last_sign = p
        lam[s] = p * lam_v
        X[s] = p * (y_prev / eps)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _march_unilateral(u, gap, eps, lam, X, state, dep):
    n = u.shape[0]
    for s in range(n):
        pred = u[s] - eps * gap
        if pred > 0.0:
            lam[s] = pred
            X[s] = gap
            state[s] = STICK
            dep[s] = -4  # row e_s
        else:
            lam[s] = 0.0
            X[s] = u[s] / eps
            state[s] = OPEN
            dep[s] = -1


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _block(Phi, Psi, dep, sgn, hi_i, lo_i, A):
    """A = Psi @ (d lam / d u) @ Phi for one contact, exploiting the sparse rows."""
    H = Phi.shape[1]
    n = Phi.shape[0]
    A[:, :] = 0.0
    n_self = 0
    for s in range(n):
        if dep[s] != -1:
            n_self += 1
    # diagonal part: sum over rows with an e_s term of Psi[:, s] Phi[s, :]
    if 2 * n_self <= n:
        for s in range(n):
            if dep[s] != -1:
                for i in range(H):
                    ps = Psi[i, s]
                    for j in range(H):
                        A[i, j] += ps * Phi[s, j]
    else:  # identity minus the complement (Psi @ Phi = I)
        for i in range(H):
            A[i, i] = 1.0
        for s in range(n):
            if dep[s] == -1:
                for i in range(H):
                    ps = Psi[i, s]
                    for j in range(H):
                        A[i, j] -= ps * Phi[s, j]
    # coupling to the last slip sample, accumulated over each stick run
    g = np.zeros(H)
    cur = -1
    for s in range(n + 1):
        d = dep[s] if s < n else -1
        if d != cur and cur >= 0:
            for i in range(H):
                for j in range(H):
                    A[i, j] -= g[i] * Phi[cur, j]
            g[:] = 0.0
        if d >= 0:
            for i in range(H):
                g[i] += sgn[s] * Psi[i, s]
        cur = d
    if n > 0 and (dep[0] == -2 or dep[0] == -5):  # centred full stick
        for j in range(H):
            if dep[0] == -2:  # e_s - mean: (sum_s Psi[:, s]) (mean_s Phi[s, :])
                w = 0.0
                for s in range(n):
                    w += Phi[s, j]
                w /= n
            else:  # e_s - (e_hi + e_lo) / 2
                w = 0.5 * (Phi[hi_i, j] + Phi[lo_i, j])
            for i in range(H):
                tot = 0.0
                for s in range(n):
                    tot += Psi[i, s]
                A[i, j] -= tot * w


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def evaluate(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, want_blocks, R, A, lam, X, state):
    """DLFT residual of eq. 12 and the per-contact derivative blocks.

    Parameters
    ----------
    x : (nc H,) harmonics of relative displacements (m), contact-major.
    Z, F : reduced dynamic stiffness (nc H, nc H) (N/m) and force (nc H,) (N).
    eps : (nc,) penalty coefficients (N/m); ``k_t`` for a Jenkins contact.
    kinds : (nc,) FRICTION, UNILATERAL or JENKINS. limits : (nc,) ``mu F_N`` (N) or gap (m).
    Phi, Psi : iDFT (Ns, H) and DFT (H, Ns) matrices.
    half_wave : bool, antiperiodic march over half a period.
    want_blocks : bool, fill ``A`` (nc, H, H) with ``Psi dlam/dlambda_u Phi``.
    R : (nc H,) residual out (N). lam, X : (nc, Ns) contact force (N) and slip
    variable (m) out. state : (nc, Ns) STICK/SLIP/OPEN out.
    """
    nc = kinds.shape[0]
    Ns, H = Phi.shape
    lu = F - Z @ x
    dep = np.empty(Ns, dtype=np.int64)
    sgn = np.ones(Ns)
    jenkins_lagrangian(x, eps, kinds, H, lu)
    for c in range(nc):
        lo_c = c * H
        if kinds[c] != JENKINS:
            for j in range(H):
                lu[lo_c + j] += eps[c] * x[lo_c + j]
        u = Phi @ lu[lo_c : lo_c + H]
        if kinds[c] != UNILATERAL:  # a Jenkins contact marches k_t x with eps = k_t (module text)
            _march_friction(u, limits[c], eps[c], half_wave, lam[c], X[c], state[c], dep, sgn)
        else:
            _march_unilateral(u, limits[c], eps[c], lam[c], X[c], state[c], dep)
        Lc = Psi @ lam[c]
        for j in range(H):
            R[lo_c + j] = Lc[j] - F[lo_c + j]
        if want_blocks:
            hi_i, lo_i = np.argmax(u), np.argmin(u)
            _block(Phi, Psi, dep, sgn, hi_i, lo_i, A[c])
    R += Z @ x


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def jacobian_from_blocks(Z, eps, A, J):
    """J = Z + blockdiag(A_c) (diag(eps) - Z): exact derivative of the residual of any DLFT law (N/m).

    ``A`` (nb, m, m): one block per contact (``m = H``, this module's law) or per
    pair of coordinates (``m = 2 H``, ``fretwear.hbm.coupled``); ``eps`` one
    penalty per coordinate, each over ``H = n / len(eps)`` consecutive unknowns.
    """
    nb, m = A.shape[0], A.shape[1]
    n = Z.shape[0]
    H = n // eps.shape[0]
    for c in range(nb):
        r0 = c * m
        AZ = A[c] @ np.ascontiguousarray(Z[r0 : r0 + m, :])
        for i in range(m):
            for j in range(n):
                J[r0 + i, j] = Z[r0 + i, j] - AZ[i, j]
            for j in range(m):
                J[r0 + i, r0 + j] += eps[(r0 + j) // H] * A[c, i, j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def jacobian_of_kinds(Z, eps, A, kinds, J):
    """:func:`jacobian_from_blocks` with Jenkins contacts: their rows are ``Z + k_t A_c`` (N/m).

    ``d lambda_u / d x`` is ``E - Z`` for a DLFT contact and ``k_t I`` for a
    Jenkins contact (module text); ``kinds`` (nc,) the contact kinds of
    :func:`evaluate`, or empty for every block a DLFT one (the coupled law).
    """
    nb, m = A.shape[0], A.shape[1]
    n = Z.shape[0]
    H = n // eps.shape[0]
    for c in range(nb):
        r0 = c * m
        if c < kinds.shape[0] and kinds[c] == JENKINS:
            for i in range(m):
                for j in range(n):
                    J[r0 + i, j] = Z[r0 + i, j]
        else:
            AZ = A[c] @ np.ascontiguousarray(Z[r0 : r0 + m, :])
            for i in range(m):
                for j in range(n):
                    J[r0 + i, j] = Z[r0 + i, j] - AZ[i, j]
        for i in range(m):
            for j in range(m):
                J[r0 + i, r0 + j] += eps[(r0 + j) // H] * A[c, i, j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def jenkins_lagrangian(x, eps, kinds, H, lu):
    """Set the march input of every Jenkins contact, ``lu_c = k_t x_c`` (N), leaving the others.

    ``x`` (nc H,) unknowns or a direction (m); ``eps`` holds ``k_t`` in a
    Jenkins contact's slot. A DLFT contact's ``lu_c`` is its augmented
    Lagrangian ``F_r - Z_r x + eps x`` (eq. 18), computed by the caller.
    """
    for c in range(kinds.shape[0]):
        if kinds[c] == JENKINS:
            for j in range(c * H, (c + 1) * H):
                lu[j] = eps[c] * x[j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _synthesise(v, PhiT, U):
    """Samples ``U[c] = Phi v_c`` of every contact from the transposed iDFT ``PhiT`` (H, Ns)."""
    H, Ns = PhiT.shape
    for c in range(U.shape[0]):
        u = U[c]
        u[:] = 0.0
        for j in range(H):
            vj = v[c * H + j]
            for s in range(Ns):
                u[s] += vj * PhiT[j, s]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def augmented_march(v, eps, kinds, limits, PhiT, half_wave, lam, X, state, dep, sgn, hilo, U):
    """The march of :func:`evaluate` from the augmented Lagrangian harmonics ``v`` (N) directly.

    ``v = F_r + (E - Z_r) x`` with ``E = diag(eps)`` (eq. 18); ``PhiT`` is the
    transposed iDFT (H, Ns). Fills ``lam``, ``X``, ``state`` (nc, Ns) as
    :func:`evaluate` does, ``U`` (nc, Ns) with the samples of ``lambda_u``, and
    for :func:`augmented_jacobian` the march's dependency rows ``dep`` (int64)
    and signs ``sgn`` (nc, Ns) and the samples of largest and smallest
    ``lambda_u``, ``hilo`` (nc, 2) int64.
    """
    _synthesise(v, PhiT, U)
    sampled_march(eps, kinds, limits, half_wave, lam, X, state, dep, sgn, hilo, U)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def sampled_march(eps, kinds, limits, half_wave, lam, X, state, dep, sgn, hilo, U):
    """:func:`augmented_march` from the samples ``U`` (nc, Ns) of ``lambda_u`` at hand (no synthesis).

    A walk along ``v + t dv`` updates them as ``U + t dU``, ``dU`` the samples of ``dv``.
    """
    nc, Ns = U.shape
    for c in range(nc):
        u = U[c]
        hi_i, lo_i = 0, 0
        for s in range(Ns):
            if u[s] > u[hi_i]:
                hi_i = s
            if u[s] < u[lo_i]:
                lo_i = s
        hilo[c, 0], hilo[c, 1] = hi_i, lo_i
        if kinds[c] != UNILATERAL:
            _march_friction(u, limits[c], eps[c], half_wave, lam[c], X[c], state[c], dep[c], sgn[c])
        else:
            _march_unilateral(u, limits[c], eps[c], lam[c], X[c], state[c], dep[c])


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def augmented_residual(
    v, M, F, eps, kinds, limits, PhiT, PsiT, half_wave, R, lam, X, state, dep, sgn, hilo, U
):
    """DLFT residual of eq. 12 in the augmented variables ``v = F_r + (E - Z_r) x`` (eq. 18).

    With ``W = E - Z_r`` invertible, ``x = W^-1 (v - F_r)`` and the residual
    reads ``R = M (v - F_r) - F_r + Psi lambda(Phi v)`` with ``M = Z_r W^-1``:
    the march takes ``v`` directly (:func:`augmented_march`), and the Jacobian
    ``M + blockdiag(A_c)`` needs no product with ``Z_r`` (:func:`augmented_jacobian`).
    Newton's method and the piecewise-linear walks are invariant under this
    affine change of unknowns: they visit the same solutions as in ``x``.

    Parameters
    ----------
    v : (nc H,) augmented Lagrangian harmonics (N), contact-major.
    M : (nc H, nc H) ``Z_r (E - Z_r)^-1`` (-). F : (nc H,) reduced force (N).
    eps, kinds, limits, half_wave : as in :func:`evaluate`.
    PhiT, PsiT : the transposed iDFT (H, Ns) and DFT (Ns, H) matrices.
    R : (nc H,) residual out (N); the other arrays as in :func:`augmented_march`.

    Returns ``max |R|`` (N), ``inf`` if not finite.
    """
    _synthesise(v, PhiT, U)
    return sampled_residual(v, M, F, eps, kinds, limits, PsiT, half_wave, R, lam, X, state, dep, sgn, hilo, U)


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def sampled_residual(v, M, F, eps, kinds, limits, PsiT, half_wave, R, lam, X, state, dep, sgn, hilo, U):
    """:func:`augmented_residual` with ``U`` holding the samples of ``v`` already (:func:`sampled_march`)."""
    n = v.shape[0]
    sampled_march(eps, kinds, limits, half_wave, lam, X, state, dep, sgn, hilo, U)
    assemble_augmented(v, M, F, lam, PsiT, R)
    r = 0.0
    for i in range(n):
        if not abs(R[i]) < np.inf:
            return np.inf
        r = max(r, abs(R[i]))
    return r


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def assemble_augmented(v, M, F, lam, PsiT, R):
    """``R = M (v - F) - F + Psi lam`` (N): the augmented residual from the march's forces ``lam``."""
    nc = lam.shape[0]
    Ns, H = PsiT.shape
    n = v.shape[0]
    for i in range(n):
        acc = -F[i]
        for j in range(n):
            acc += M[i, j] * (v[j] - F[j])
        R[i] = acc
    for c in range(nc):
        Rc = R[c * H : (c + 1) * H]
        for s in range(Ns):
            ls = lam[c, s]
            for j in range(H):
                Rc[j] += ls * PsiT[s, j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def block_sums(Phi, Psi, stride):
    """Prefix sums ``P[m] = sum_{s < m stride} Psi[:, s] Phi[s, :]`` and ``Q[s] = sum_{s' < s} Psi[:, s']``.

    With them a derivative block costs O(H^2) per run of samples instead of
    per sample (:func:`augmented_jacobian`); a ``stride`` above 1 keeps every
    ``stride``-th sum only (less memory, up to ``stride - 1`` terms per run end).
    """
    Ns, H = Phi.shape
    P = np.zeros(((Ns + stride - 1) // stride + 1, H, H))
    Q = np.zeros((Ns + 1, H))
    acc = np.zeros((H, H))
    for s in range(Ns):
        for i in range(H):
            Q[s + 1, i] = Q[s, i] + Psi[i, s]
            ps = Psi[i, s]
            for j in range(H):
                acc[i, j] += ps * Phi[s, j]
        if (s + 1) % stride == 0 or s == Ns - 1:
            m = (s + stride) // stride
            for i in range(H):
                for j in range(H):
                    P[m, i, j] = acc[i, j]
    return P, Q


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _add_range(P, stride, Phi, Psi, a, b, A):
    """``A += sum_{a <= s < b} Psi[:, s] Phi[s, :]`` from the strided prefix sums of :func:`block_sums`."""
    H = Phi.shape[1]
    ma, mb = a // stride, b // stride
    for i in range(H):
        for j in range(H):
            A[i, j] += P[mb, i, j] - P[ma, i, j]
    for s in range(mb * stride, b):
        for i in range(H):
            ps = Psi[i, s]
            for j in range(H):
                A[i, j] += ps * Phi[s, j]
    for s in range(ma * stride, a):
        for i in range(H):
            ps = Psi[i, s]
            for j in range(H):
                A[i, j] -= ps * Phi[s, j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def augmented_jacobian(M, dep, sgn, hilo, Phi, Psi, P, Q, stride, A, J):
    """Exact Jacobian ``dR/dv = M + blockdiag(A_c)`` of :func:`augmented_residual` at its last march.

    ``A_c = Psi (d lambda / d lambda_u) Phi`` from the rows of the march
    (``dep``, ``sgn``, see :func:`evaluate`), one run of samples at a time with
    the prefix sums ``P, Q`` of :func:`block_sums` (every ``stride``-th). ``A`` (H, H) is a work
    array; ``J`` (nc H, nc H) is filled.
    """
    nc, Ns = dep.shape
    H = Phi.shape[1]
    for i in range(M.shape[0]):
        for j in range(M.shape[1]):
            J[i, j] = M[i, j]
    w = np.empty(H)
    for c in range(nc):
        d_c, sg_c = dep[c], sgn[c]
        A[:, :] = 0.0
        s = np.int64(0)  # not a literal 0: that would compile _add_range twice
        while s < Ns:  # rows with an e_s term (stick, closed, full stick), by runs
            if d_c[s] == -1:
                s += 1
                continue
            a = s
            while s < Ns and d_c[s] != -1:
                s += 1
            _add_range(P, stride, Phi, Psi, a, s, A)
        s = 0
        while s < Ns:  # coupling of each stick run to its last slip sample
            d = d_c[s]
            if d < 0:
                s += 1
                continue
            a, sg = s, sg_c[s]
            while s < Ns and d_c[s] == d and sg_c[s] == sg:
                s += 1
            for i in range(H):
                w[i] = sg * (Q[s, i] - Q[a, i])
            for i in range(H):
                for j in range(H):
                    A[i, j] -= w[i] * Phi[d, j]
        d0 = d_c[0]
        if d0 == -2 or d0 == -5:  # centred full stick: rows e_s - (the centre's row)
            for j in range(H):
                if d0 == -2:  # the mean
                    w[j] = 0.0
                    for s in range(Ns):
                        w[j] += Phi[s, j]
                    w[j] /= Ns
                else:  # mid-range
                    w[j] = 0.5 * (Phi[hilo[c, 0], j] + Phi[hilo[c, 1], j])
            for i in range(H):
                for j in range(H):
                    A[i, j] -= Q[Ns, i] * w[j]
        r0 = c * H
        for i in range(H):
            for j in range(H):
                J[r0 + i, r0 + j] += A[i, j]


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def augmented_boundary(U, dv, eps, kinds, limits, PhiT, half_wave, tau_max, dU, synthesise):
    """:func:`boundary_distance` from the samples ``U`` (nc, Ns) of ``lambda_u`` and a direction ``dv``.

    With ``synthesise``, ``dU`` (nc, Ns) is filled with the samples of the
    direction; without, it holds them already (several boundaries along one line).
    """
    if synthesise:
        _synthesise(dv, PhiT, dU)
    tau = tau_max
    for c in range(kinds.shape[0]):
        tau = _contact_boundary(kinds[c], U[c], dU[c], limits[c], eps[c], half_wave, tau)
    return tau


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _contact_boundary(kind, u, du, limit, eps, half_wave, tau):
    """First pattern change of one contact along ``u + t du`` before ``tau`` (its samples ``u``, ``du``)."""
    if kind != UNILATERAL:  # friction, or Jenkins with u = k_t x
        return _friction_boundary(u, du, limit, eps, half_wave, tau)
    for s in range(u.shape[0]):
        tau = _crossing(u[s] - eps * limit, du[s], 0.0, tau)
    return tau


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def state_code(kind, lam, state, code):
    """Signed state of every sample of one contact (int8): friction ``0`` stick, ``+-1`` slip in the
    direction of the force; unilateral ``1`` closed, ``0`` open. The pattern :func:`forced_march` imposes."""
    for s in range(lam.shape[0]):
        if kind != UNILATERAL:
            code[s] = 0 if state[s] != SLIP else (1 if lam[s] > 0 else -1)
        else:
            code[s] = 1 if state[s] == STICK else 0


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def forced_march(u, code, kind, limit, eps, half_wave, lam, dep, sgn):
    """The contact force of a prescribed pattern ``code`` (:func:`state_code`), affine in ``u``.

    Friction: a slip sample carries ``code * limit``; a stick sample ``s``
    follows its last slip sample ``m`` (backwards, across the antiperiodic
    wrap for half waves): ``lambda_s = u_s - sgn (u_m - lambda_m)``, the
    march's own formula, so that ``dep``/``sgn`` give the same derivative
    blocks. Unilateral: closed ``u - eps g``, open zero. Returns False if a
    friction pattern has no slip sample (full stick is not prescribed).
    """
    n = u.shape[0]
    if kind == UNILATERAL:
        for s in range(n):
            if code[s]:
                lam[s], dep[s] = u[s] - eps * limit, -4
            else:
                lam[s], dep[s] = 0.0, -1
        return True
    last = -1
    for s in range(n - 1, -1, -1):
        if code[s]:
            last = s
            break
    if last < 0:
        return False
    last_sign = -1.0 if half_wave else 1.0  # the last slip sample seen from sample 0, across the wrap
    for s in range(n):
        if code[s]:
            lam[s] = code[s] * limit
            dep[s] = -1
            last, last_sign = s, 1.0
        else:
            dep[s], sgn[s] = last, last_sign
            lam[s] = u[s] - last_sign * (u[last] - code[last] * limit)
    return True


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _crossing(pred, dpred, level, tau):
    """Smallest tau' in [0, tau) with pred + tau' dpred = level, else tau.

    The division, the costly part of a boundary search, is taken only where
    the crossing can come before ``tau`` (a test by products with a margin,
    so that the answer is that of the division alone).
    """
    gap = level - pred
    if dpred == 0.0 or (gap != 0.0 and (gap < 0.0) == (dpred > 0.0)):
        return tau  # parallel to the level, or moving away from it
    if abs(gap) > 1.000001 * tau * abs(dpred):
        return tau
    t = gap / dpred
    if 0.0 <= t < tau:
        return t
    return tau


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def _friction_boundary(u, du, limit, eps, half_wave, tau):
    """Distance along ``u + tau du`` to the first change of a friction stick/slip pattern."""
    n = u.shape[0]
    if limit <= 0.0:
        return tau
    big_i, hi_i, lo_i = 0, 0, 0
    mean, dmean = 0.0, 0.0
    for s in range(n):
        if abs(u[s]) > abs(u[big_i]):
            big_i = s
        if u[s] > u[hi_i]:
            hi_i = s
        if u[s] < u[lo_i]:
            lo_i = s
        mean += u[s]
        dmean += du[s]
    mean /= n
    dmean /= n
    full_stick = abs(u[big_i]) <= limit if half_wave else max(u[hi_i] - mean, mean - u[lo_i]) <= limit
    if full_stick:  # first sample to reach the cone edge
        c, dc = (0.0, 0.0) if half_wave else (mean, dmean)
        for s in range(n):
            tau = _crossing(u[s] - c, du[s] - dc, limit, tau)
            tau = _crossing(u[s] - c, du[s] - dc, -limit, tau)
        return tau
    s0 = big_i
    sign0 = 1.0 if u[s0] > 0 else -1.0
    y_prev, dy_prev = u[s0] - sign0 * limit, du[s0]  # eps times the slip variable, as in the march
    for v in range(1, n + 1):  # one full turn, back to s0 to check its own prediction
        s = s0 + v
        p = 1.0
        while s >= n:
            s -= n
            if half_wave:
                p = -p
        uv, duv = p * u[s], p * du[s]
        pred = uv - y_prev
        dpred = duv - dy_prev
        if abs(pred) < limit:  # stick: leaves the cone at +-limit
            tau = _crossing(pred, dpred, limit, tau)
            tau = _crossing(pred, dpred, -limit, tau)
        else:  # slip with sign sg: returns inside the cone at sg * limit
            sg = 1.0 if pred > 0 else -1.0
            if sg * dpred < 0.0:
                tau = _crossing(pred, dpred, sg * limit, tau)
            y_prev, dy_prev = uv - sg * limit, duv
    return tau


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def boundary_distance(lu, dlu, eps, kinds, limits, Phi, half_wave, tau_max):
    """Largest step ``tau <= tau_max`` along ``lambda_u + tau d lambda_u`` keeping every sample's state.

    The DLFT residual is linear on each such piece, so a path that is straight
    in the unknowns is exact up to the returned distance.

    Parameters
    ----------
    lu, dlu : (nc H,) augmented Lagrangian harmonics and their direction (N).
    eps, kinds, limits, Phi, half_wave : as in :func:`evaluate`.
    tau_max : float, upper bound on the returned step.
    """
    nc = kinds.shape[0]
    H = Phi.shape[1]
    tau = tau_max
    for c in range(nc):
        u = Phi @ lu[c * H : (c + 1) * H]
        du = Phi @ dlu[c * H : (c + 1) * H]
        tau = _contact_boundary(kinds[c], u, du, limits[c], eps[c], half_wave, tau)
    return tau


@njit(cache=True, nogil=True, fastmath=FASTMATH)
def friction_sensitivity(u, limit, eps, half_wave, lam, X, state, dlam_dL, ds_du):
    """Friction march with the derivatives the slow-time (wear) equations need.

    Fills ``lam``, ``X``, ``state`` as :func:`evaluate` does for one friction
    contact, ``dlam_dL`` (d lambda_n / d(mu F_N)) and ``ds_du`` (derivative of the
    distance slid per period with respect to each sample of ``lambda_u``), and
    returns ``(s, ds/d(mu F_N))`` with ``s`` the distance slid per full period (m).
    """
    n = u.shape[0]
    dep = np.empty(n, dtype=np.int64)
    sgn = np.ones(n)
    _march_friction(u, limit, eps, half_wave, lam, X, state, dep, sgn)
    # dX_s/du = coef_s * e_{src_s} and dX_s/dL = dXdL_s (full stick: X is constant, s = 0)
    src = np.empty(n, dtype=np.int64)
    coef = np.zeros(n)
    dXdL = np.zeros(n)
    for s in range(n):
        d = dep[s]
        if limit <= 0.0 or state[s] == SLIP:
            src[s], coef[s] = s, 1.0 / eps
            dXdL[s] = 0.0 if limit <= 0.0 else -np.sign(lam[s]) / eps
            dlam_dL[s] = 0.0 if limit <= 0.0 else np.sign(lam[s])
        elif d >= 0:
            src[s], coef[s] = d, sgn[s] / eps
            dXdL[s] = -sgn[s] * np.sign(lam[d]) / eps
            dlam_dL[s] = sgn[s] * np.sign(lam[d])
        else:  # full stick: X does not depend on the limit
            src[s], coef[s] = -1, 0.0
            dXdL[s] = 0.0
            dlam_dL[s] = 0.0
    ds_du[:] = 0.0
    total, dtotal = 0.0, 0.0
    wrap = -1.0 if half_wave else 1.0
    for s in range(n):
        p = s - 1 if s > 0 else n - 1
        w = wrap if s == 0 else 1.0
        diff = X[s] - w * X[p]
        if diff == 0.0:
            continue
        sg = 1.0 if diff > 0 else -1.0
        total += abs(diff)
        dtotal += sg * (dXdL[s] - w * dXdL[p])
        if src[s] >= 0:
            ds_du[src[s]] += sg * coef[s]
        if src[p] >= 0:
            ds_du[src[p]] -= sg * w * coef[p]
    if half_wave:
        total *= 2.0
        dtotal *= 2.0
        for s in range(n):
            ds_du[s] *= 2.0
    return total, dtotal
