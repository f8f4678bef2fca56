"""Direct time integration of an interface: the check of the harmonic balance and of the slow-time methods.

The reduced, contact-condensed equations of motion
(:class:`~fretwear.interface.reduction.ContactCondensation`, coordinates ``z =
(q, s)``, ``q = (u_T, u_N)`` per pair),

    M z'' + C z' + K z + E lambda = f_s + f_c cos(omega t) + f_s' sin(omega t),

are integrated by the **implicit (backward) Euler method** on ``(z, z')``:
first order, unconditionally stable and L-stable, so that the stiff
constraint modes of the contact nodes are damped at once instead of ringing
(the trapezoidal rule keeps them at amplitude factor -1). At every step the
contact forces ``lambda`` of all pairs solve, with the structure's step
compliance ``W = (M / h^2 + C / h + K)^-1`` restricted to ``q`` (the pairs
are coupled through the elastic bodies), the **same contact law as the
DLFT march** (eq. 17-23) without its penalty, i.e. its rigid limit:

* unilateral normal contact: ``u_N <= g_i`` (gap plus wear), ``lambda_N >= 0``,
  ``(g_i - u_N) lambda_N = 0``;
* Coulomb friction on the step's increment: stick ``u_T = X_i`` (the slip
  variable of the previous step) with ``|lambda_T| <= mu lambda_N``, or slip
  ``lambda_T = mu lambda_N sign(u_T - X_i)``; an open pair has ``lambda = 0``.

The pairs' states (open, stick, slip +-) are found by an active-set iteration
started from the previous step's states: solve the linear system of the
current states, switch every pair whose conditions fail (after a quarter of
the iteration budget only the most violated pair, which breaks cycles of
simultaneous switches), repeat; the law is
piecewise linear, so the iteration ends on the exact step solution once the
states are right (usually at once). A step whose states keep cycling is
reported (``converged=False`` and the step).

Wear (optional): after every step each slipping pair's depth grows by Archard's
law, ``dw_i = K_w (lambda_N,i / A_i) |Delta u_T,i|`` (eq. 15), and opens its gap
for the next step: no slow-time approximation at all.

**2-D friction** (3-D pairs, the law of ``fretwear.hbm.cone``, slip
variables (nc, 2)): the unknowns of a step are the contact forces on ``q``
and on the binormals ``(u_T1, u_T2, u_N)`` of each pair (a pair without a
binormal, on a symmetry plane, has none), the law its rigid limit: unilateral
contact, and stick ``u_T = X`` with ``|lambda_T| <= mu lambda_N`` or slip with
``lambda_T = mu lambda_N (u_T - X) / |u_T - X|`` (the friction along the
step's slip increment, the DLFT's rule). Not piecewise linear: the step is
solved by a semi-smooth Newton method on the Alart-Curnier equations
``lambda_N = max(0, lambda_N + rho (u_N - g))``, ``lambda_T = P(lambda_T + rho
(u_T - X))`` (``P`` the projection on the disk of radius ``mu lambda_N``,
``rho`` per pair the inverse of the step compliance's normal diagonal), with a
backtracking line search, to ``1e-12`` of the load (:func:`integrate_cone_kernel`).

The step loop is compiled (:func:`integrate_kernel`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numba import njit

from .contact import OPEN, SLIP, STICK
from .periodic import InterfaceSolution
from .reduction import ContactCondensation

__all__ = [
    "integrate_kernel", "integrate_cone_kernel", "InterfaceTransient", "integrate_interface", "initial_state",
]  # fmt: skip

_SLIP_NEG = 3  # internal state: slip with u_T decreasing (SLIP is the increasing direction)


@njit(cache=True, nogil=True)
def _step_contact(r, W, gap, mu, X, state, tol_f, tol_u, max_iter, lam, A, b):
    """Contact forces of one step: ``q = r - W lambda`` with every pair's law (active set); True if found."""
    nc = gap.shape[0]
    n = 2 * nc
    for it in range(max_iter):
        A[:, :] = 0.0
        for i in range(nc):
            t, m = 2 * i, 2 * i + 1
            s = state[i]
            if s == OPEN:
                A[t, t] = 1.0
                A[m, m] = 1.0
                b[t] = 0.0
                b[m] = 0.0
                continue
            for j in range(n):  # normal row: u_N = g
                A[m, j] = W[m, j]
            b[m] = r[m] - gap[i]
            if s == STICK:
                for j in range(n):
                    A[t, j] = W[t, j]
                b[t] = r[t] - X[i]
            else:
                sg = 1.0 if s == SLIP else -1.0
                A[t, t] = 1.0
                A[t, m] = -sg * mu[i]
                b[t] = 0.0
        lam[:] = np.linalg.solve(A, b)
        q = r - W @ lam
        worst, which, to = 0.0, -1, STICK  # the most violated condition, in units of its tolerance
        for i in range(nc):
            t, m = 2 * i, 2 * i + 1
            s = state[i]
            if s == OPEN:  # closes, sliding the way it moves (an open pair's slip variable follows it)
                v, du = (q[m] - gap[i]) / tol_u, q[t] - X[i]
                new = STICK if abs(du) <= tol_u else (SLIP if du > 0 else _SLIP_NEG)
            elif lam[m] < -tol_f:
                v, new = -lam[m] / tol_f, OPEN
            elif s == STICK:
                v = (abs(lam[t]) - mu[i] * lam[m]) / tol_f
                new = SLIP if lam[t] > 0 else _SLIP_NEG
            else:
                v, new = -(1.0 if s == SLIP else -1.0) * (q[t] - X[i]) / tol_u, STICK
            if v > 1.0:
                if it < max_iter // 4:  # switch every violated pair at once
                    state[i] = new
                    worst = v
                elif v > worst:  # then one pair at a time: no cycling between simultaneous switches
                    worst, which, to = v, i, new
        if which >= 0:
            state[which] = to
        changed = worst > 1.0
        if not changed:
            return True
    return False


@njit(cache=True, nogil=True)
def integrate_kernel(z, v, X, state, wear, M, C, Kinv, fs, fc, fsin, omega, t0, h, steps, gap0, mu,
                     area, kw, tol_f, tol_u, every, rec_t, rec_q, rec_lam, rec_state, rec_wear,
                     energy):  # fmt: skip
    """Backward Euler steps with the pairs' contact law (see the module docstring).

    Parameters
    ----------
    z, v : (n,) coordinates (m) and velocities (m/s), updated in place.
    X : (nc,) slip variables (m), updated. state : (nc,) int8 pair states, updated.
    wear : (nc,) worn depths (m), updated (``kw > 0``).
    M, C : (n, n) mass and damping. Kinv : (n, n) inverse of ``M / h^2 + C / h + K``.
    fs, fc, fsin : (n,) static, cosine and sine load patterns (N). omega : rad/s. t0, h : start, step (s).
    steps : int. gap0, mu, area : (nc,) initial gaps (m), friction coefficients, areas.
    kw : Archard coefficient (1/Pa), 0 for none. tol_f, tol_u : force (N) and displacement (m) tolerances.
    every : record every ``every`` steps into ``rec_*`` (time, q, lambda, state, wear).
    energy : (nc,) friction work of each pair (J), accumulated.

    Returns the index of the first step whose contact problem failed, or -1.
    """
    nc = gap0.shape[0]
    nq = 2 * nc
    W = np.ascontiguousarray(Kinv[:nq, :nq])
    G = np.ascontiguousarray(Kinv[:, :nq])
    lam, A, b = np.empty(nq), np.empty((nq, nq)), np.empty(nq)
    gap = gap0 + wear
    rec = 0
    for k in range(steps):
        t1 = t0 + (k + 1) * h
        zfree = _free_step(M, C, Kinv, fs, fc, fsin, omega, t1, h, z, v)
        r = zfree[:nq]
        st = state.copy()
        ok = _step_contact(r, W, gap, mu, X, st, tol_f, tol_u, 200, lam, A, b)
        if not ok:
            return k
        state[:] = st
        z1 = zfree - G @ lam
        for i in range(nc):
            du = z1[2 * i] - X[i]
            if state[i] == SLIP or state[i] == _SLIP_NEG:
                energy[i] += lam[2 * i] * du
                if kw > 0.0:
                    wear[i] += kw * lam[2 * i + 1] / area[i] * abs(du)
                    gap[i] = gap0[i] + wear[i]
            X[i] = z1[2 * i]
        v[:] = (z1 - z) / h
        z[:] = z1
        if (k + 1) % every == 0 and rec < rec_t.shape[0]:
            rec_t[rec] = t1
            rec_q[rec] = z1[:nq]
            rec_lam[rec] = lam
            for i in range(nc):
                rec_state[rec, i] = SLIP if state[i] == _SLIP_NEG else state[i]
            rec_wear[rec] = wear
            rec += 1
    return -1


@njit(cache=True, nogil=True)
def _free_step(M, C, Kinv, fs, fc, fsin, omega, t1, h, z, v):
    """Coordinates at ``t1 = t + h`` of the backward-Euler step from ``(z, v)`` without contact forces (m)."""
    f = fs + np.cos(omega * t1) * fc + np.sin(omega * t1) * fsin
    return Kinv @ (f + (M @ z) / h**2 + (M @ v) / h + (C @ z) / h)


@njit(cache=True, nogil=True)
def _cone_residual(lam, r, W, cols, gap, mu, X, rho, G, D, want):
    """Alart-Curnier residual ``G`` of the step's contact forces ``lam``; with ``want``, ``D = dG / dlam``.

    ``cols`` (nc, 3): per pair the index in ``lam`` of ``(T1, T2, N)`` (-1: no binormal).
    Returns ``max |G|`` (N).
    """
    nc = gap.shape[0]
    n = lam.shape[0]
    u = r - W @ lam
    if want:
        D[:, :] = 0.0
        for a in range(n):
            D[a, a] = 1.0
    worst = 0.0
    for i in range(nc):
        t1, t2, m = cols[i, 0], cols[i, 1], cols[i, 2]
        pN = lam[m] + rho[i] * (u[m] - gap[i])
        closed = pN > 0.0
        G[m] = lam[m] - (pN if closed else 0.0)
        if want and closed:  # dG_N = dlam_N - (dlam_N - rho W_N dlam)
            for b in range(n):
                D[m, b] += rho[i] * W[m, b]
            D[m, m] -= 1.0
        L = mu[i] * pN if closed else 0.0
        p1 = lam[t1] + rho[i] * (u[t1] - X[i, 0])
        p2 = lam[t2] + rho[i] * (u[t2] - X[i, 1]) if t2 >= 0 else 0.0
        norm = np.hypot(p1, p2)
        if norm <= L:  # stick: P(p) = p
            s, e1, e2, k = 1.0, 0.0, 0.0, 1.0
        else:  # slip: P(p) = L p / |p|
            e1, e2 = (p1 / norm, p2 / norm) if norm > 0.0 else (0.0, 0.0)
            k = L / norm if norm > 0.0 else 0.0
            s = 0.0
        G[t1] = lam[t1] - (p1 if s == 1.0 else L * e1)
        if t2 >= 0:
            G[t2] = lam[t2] - (p2 if s == 1.0 else L * e2)
        if want:
            # dP = M dp + e dL, M = I (stick) or k (I - e e^T); dp = dlam_T - rho W_T dlam
            m11, m12, m22 = (
                (1.0, 0.0, 1.0) if s == 1.0 else (k * (1 - e1 * e1), -k * e1 * e2, k * (1 - e2 * e2))
            )
            rows = (t1, t2)
            for a in range(2):
                ra = rows[a]
                if ra < 0:
                    continue
                ma = (m11, m12) if a == 0 else (m12, m22)
                ea = e1 if a == 0 else e2
                for c in range(2):
                    rc = rows[c]
                    if rc < 0:
                        continue
                    D[ra, rc] -= ma[c]
                    for b in range(n):
                        D[ra, b] += ma[c] * rho[i] * W[rc, b]
                if closed and s == 0.0:  # dL = mu (dlam_N - rho W_N dlam)
                    D[ra, m] -= ea * mu[i]
                    for b in range(n):
                        D[ra, b] += ea * mu[i] * rho[i] * W[m, b]
        for c in (t1, t2, m):
            if c >= 0:
                worst = max(worst, abs(G[c]))
    return worst


@njit(cache=True, nogil=True)
def _step_cone(r, W, cols, gap, mu, X, rho, tol_f, max_iter, lam):
    """Contact forces of one step with 2-D friction (semi-smooth Newton, module text); True if found."""
    n = lam.shape[0]
    G, Gt, D = np.empty(n), np.empty(n), np.empty((n, n))
    g = _cone_residual(lam, r, W, cols, gap, mu, X, rho, G, D, True)
    for _ in range(max_iter):
        if g <= tol_f:
            return True
        d = np.linalg.solve(D, -G)
        step = 1.0
        for _ in range(40):
            trial = lam + step * d
            gt = _cone_residual(trial, r, W, cols, gap, mu, X, rho, Gt, D, False)
            if gt < (1.0 - 1e-4 * step) * g or gt <= tol_f:
                break
            step *= 0.5
        lam[:] = trial
        g = _cone_residual(lam, r, W, cols, gap, mu, X, rho, G, D, True)
    return g <= tol_f


@njit(cache=True, nogil=True)
def integrate_cone_kernel(z, v, X, state, wear, M, C, Kinv, fs, fc, fsin, omega, t0, h, steps, gap0, mu,
                          area, cols, kw, tol_f, every, rec_t, rec_q, rec_lam, rec_state, rec_wear,
                          energy):  # fmt: skip
    """:func:`integrate_kernel` with 2-D friction (module text): ``X`` (nc, 2), ``cols`` (nc, 3) the columns
    of ``z`` of each pair's ``(u_T1, u_T2, u_N)`` (-1: no binormal), all among its first ``nk``; records of
    ``q`` and ``lambda`` on those ``nk`` coordinates. Returns the first failed step, or -1."""
    nc = gap0.shape[0]
    nk = rec_q.shape[1]
    W = np.ascontiguousarray(Kinv[:nk, :nk])
    G = np.ascontiguousarray(Kinv[:, :nk])
    rho = np.empty(nc)
    for i in range(nc):
        rho[i] = 1.0 / W[cols[i, 2], cols[i, 2]]
    lam = np.zeros(nk)
    gap = gap0 + wear
    rec = 0
    for k in range(steps):
        t1 = t0 + (k + 1) * h
        zfree = _free_step(M, C, Kinv, fs, fc, fsin, omega, t1, h, z, v)
        if not _step_cone(zfree[:nk], W, cols, gap, mu, X, rho, tol_f, 100, lam):
            return k
        z1 = zfree - G @ lam
        for i in range(nc):
            a, b, m = cols[i, 0], cols[i, 1], cols[i, 2]
            d1, d2 = z1[a] - X[i, 0], (z1[b] - X[i, 1]) if b >= 0 else 0.0
            lT1, lT2 = lam[a], lam[b] if b >= 0 else 0.0
            if lam[m] <= 0.0:
                state[i] = OPEN
            elif np.hypot(lT1, lT2) < mu[i] * lam[m] * (1.0 - 1e-9):
                state[i] = STICK
            else:
                state[i] = SLIP
                energy[i] += lT1 * d1 + lT2 * d2
                if kw > 0.0:
                    wear[i] += kw * lam[m] / area[i] * np.hypot(d1, d2)
                    gap[i] = gap0[i] + wear[i]
            X[i, 0] = z1[a]
            X[i, 1] = z1[b] if b >= 0 else 0.0
        v[:] = (z1 - z) / h
        z[:] = z1
        if (k + 1) % every == 0 and rec < rec_t.shape[0]:
            rec_t[rec] = t1
            rec_q[rec] = z1[:nk]
            rec_lam[rec] = lam
            rec_state[rec] = state
            rec_wear[rec] = wear
            rec += 1
    return -1


def initial_state(solution: InterfaceSolution) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Coordinates ``z`` (m), velocities (m/s), slip variables (m; (nc, 2) with the 2-D friction law) and pair
    states at ``t = 0`` of a periodic harmonic-balance solution, in the condensation's coordinates."""
    prob = solution.problem
    cond = prob.condensation
    nh, w = prob.harmonics, prob.omega
    coords = cond.recover(w, nh, solution.condensation_harmonics)  # reduced coordinates' harmonics
    zh = np.linalg.solve(cond.T, coords)
    k = np.arange(1, nh + 1)
    z = zh[:, 0] + zh[:, 1::2].sum(axis=1)
    v = (zh[:, 2::2] * (k * w)).sum(axis=1)
    state = np.where(solution.state[:, 0] == OPEN, OPEN, STICK).astype(np.int8)
    if prob.cone:  # slip variables (nc, 2): the tangent's and the binormal's relative displacements
        cols = cond.cone_coordinates()
        X = np.column_stack([z[cols[:, 0]], np.where(cols[:, 1] >= 0, z[cols[:, 1]], 0.0)])
        return z, v, X, state
    return z, v, z[: 2 * cond.n_pairs : 2].copy(), state


@dataclass(eq=False)
class InterfaceTransient:
    """Time history of an interface, sampled every ``every`` steps.

    Attributes
    ----------
    time : ndarray (m,)
        Times (s).
    contact : ndarray (m, 2 nc)
        Contact coordinates ``(u_T, u_N)`` per pair (m); with 2-D friction (m, 2 nc + nb), the
        binormals after them (the condensation's order, :meth:`ContactCondensation.cone_coordinates`).
    forces : ndarray (m, 2 nc)
        Contact forces ``(lambda_T, lambda_N)`` per pair (N); with 2-D friction as ``contact``.
    state : ndarray (m, nc)
        STICK, SLIP or OPEN per pair.
    wear : ndarray (m, nc)
        Worn depths (m).
    energy_per_period : ndarray (periods, nc)
        Friction work of each pair in each period (J).
    z, v : ndarray (n,)
        Final coordinates and velocities (continue with :func:`integrate_interface`).
    slip_variable : ndarray (nc,) or (nc, 2)
        Final slip variables (m).
    converged : bool
        Every step's contact problem was solved.
    message : str
        Where it failed, if it did.
    """

    time: np.ndarray
    contact: np.ndarray
    forces: np.ndarray
    state: np.ndarray
    wear: np.ndarray
    energy_per_period: np.ndarray
    z: np.ndarray
    v: np.ndarray
    slip_variable: np.ndarray
    pair_state: np.ndarray
    converged: bool
    message: str


def integrate_interface(
    condensation: ContactCondensation,
    omega: float,
    z0: np.ndarray,
    v0: np.ndarray,
    slip0: np.ndarray,
    state0: np.ndarray,
    periods: int,
    steps_per_period: int = 512,
    wear0: np.ndarray | None = None,
    kw: float = 0.0,
    samples_per_period: int | None = None,
) -> InterfaceTransient:
    """Integrate the interface over ``periods`` excitation periods from ``t = 0`` (see the module docstring).

    Parameters
    ----------
    condensation : ContactCondensation
    omega : float
        Excitation frequency (rad/s), > 0.
    z0, v0 : ndarray (n,)
        Initial coordinates (m) and velocities (m/s) in the condensation's coordinates
        (e.g. ``initial_state()``).
    slip0 : ndarray (nc,) or (nc, 2)
        Initial slip variables (m); (nc, 2): the 2-D friction law (3-D pairs, module text).
        state0 : ndarray (nc,) initial pair states (a guess).
    periods : int
        Periods to integrate, >= 1.
    steps_per_period : int
        Time steps per period, >= 8.
    wear0 : ndarray (nc,), optional
        Initial worn depths (m).
    kw : float
        Archard coefficient (1/Pa), >= 0 (0: no wear).
    samples_per_period : int, optional
        Records per period (must divide ``steps_per_period``; default ``steps_per_period``).
    """
    if not (np.isfinite(omega) and omega > 0):
        raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {omega!r}")
    if not (isinstance(periods, (int, np.integer)) and periods >= 1):
        raise ValueError(f"periods must be an integer >= 1, got {periods!r}")
    if not (isinstance(steps_per_period, (int, np.integer)) and steps_per_period >= 8):
        raise ValueError(f"steps_per_period must be an integer >= 8, got {steps_per_period!r}")
    if not (np.isfinite(kw) and kw >= 0):
        raise ValueError(f"kw must be a finite Archard coefficient >= 0 1/Pa, got {kw!r}")
    samples = steps_per_period if samples_per_period is None else int(samples_per_period)
    if samples < 1 or steps_per_period % samples:
        raise ValueError(
            f"samples_per_period must divide steps_per_period = {steps_per_period}, got {samples}"
        )
    c = condensation
    contact = c.model.pairs
    nc = contact.count
    h = 2 * np.pi / omega / steps_per_period
    Kinv = np.linalg.inv(c.M / h**2 + c.C / h + c.K)
    fs = c.force_static
    fc, fsin = c.force_harmonic.real.copy(), -c.force_harmonic.imag
    z, v = np.array(z0, dtype=float), np.array(v0, dtype=float)
    X, state = np.array(slip0, dtype=float), np.array(state0, dtype=np.int8)
    wear = np.zeros(nc) if wear0 is None else np.array(wear0, dtype=float)
    scale_f = max(float(np.abs(fs).max()), float(np.abs(fc).max()), float(np.abs(fsin).max()), 1e-300)
    scale_u = max(float(np.abs(z[: 2 * nc]).max()), 1e-300)
    cone = X.ndim == 2
    if X.shape != ((nc, 2) if cone else (nc,)):
        raise ValueError(f"slip0 must be ({nc},) or ({nc}, 2) slip variables (m), got shape {X.shape}")
    if cone and contact.dim != 3:
        raise ValueError(
            f"slip0 of shape ({nc}, 2) (2-D friction) needs 3-D contact pairs, got dim = {contact.dim}"
        )
    nk = c.n_q + int(c.has_binormal.sum()) if cone else 2 * nc
    every = steps_per_period // samples
    m = periods * samples
    rec_t, rec_q, rec_lam = np.empty(m), np.empty((m, nk)), np.empty((m, nk))
    rec_state, rec_wear = np.empty((m, nc), dtype=np.int8), np.empty((m, nc))
    energy = np.zeros((periods, nc))
    failed, message = -1, ""
    for p in range(periods):  # one compiled call per period: the friction work per period
        e = np.zeros(nc)
        sl = slice(p * samples, (p + 1) * samples)
        if cone:
            failed = integrate_cone_kernel(
                z, v, X, state, wear, c.M, c.C, Kinv, fs, fc, fsin, omega, p * 2 * np.pi / omega, h,
                steps_per_period, contact.gap, contact.mu, contact.area, c.cone_coordinates(), kw,
                1e-12 * scale_f, every, rec_t[sl], rec_q[sl], rec_lam[sl], rec_state[sl], rec_wear[sl], e,
            )  # fmt: skip
        else:
            failed = integrate_kernel(
                z, v, X, state, wear, c.M, c.C, Kinv, fs, fc, fsin, omega, p * 2 * np.pi / omega, h,
                steps_per_period, contact.gap, contact.mu, contact.area, kw, 1e-12 * scale_f, 1e-12 * scale_u,
                every, rec_t[sl], rec_q[sl], rec_lam[sl], rec_state[sl], rec_wear[sl], e,
            )  # fmt: skip
        energy[p] = e
        if failed >= 0:
            message = f"contact states kept cycling at step {failed} of period {p}"
            m = p * samples
            break
    return InterfaceTransient(
        time=rec_t[:m], contact=rec_q[:m], forces=rec_lam[:m], state=rec_state[:m], wear=rec_wear[:m],
        energy_per_period=energy[: (m // samples)], z=z, v=v, slip_variable=X, pair_state=state,
        converged=failed < 0, message=message,
    )  # fmt: skip
