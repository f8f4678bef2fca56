"""Polynomial slow-time DLFT (paper eq. 25-29), with a slow-time basis built for wear curves.

The whole wear history at one frequency comes from the periodic DLFT response
at the Gauss-Legendre nodes of a slow interval and polynomials of the slow
variable between them. Three bases (``basis=``):

* ``"saturating"`` (default, one friction contact): the slow variable is the
  wear itself, through ``z = -ln(1 - w / u0)``, and ``w = u0 (1 - exp(-z))``
  stays in ``[0, u0)`` by construction. Archard's law reads ``dz/dN = K_w k_n s``
  (``s`` the distance slid per cycle): ``z`` is linear in ``N`` when ``s`` does not
  depend on the load (exact at degree 1), and again above the point of maximal
  slope, where the contact is nearly unloaded and ``s`` levels off. In
  maintenance-engineering terms ``w / u0`` is a life distribution with
  cumulative hazard ``z`` and hazard rate ``K_w k_n s`` (a Weibull law has
  ``z = (N / N_c)^k``). The slow interval ``0 <= z <= z_end`` is mapped onto a
  life fraction ``v`` in [0, 1] (below); at the ``2 m + 2`` Gauss nodes of
  ``v`` the wear is known, the DLFT equations (eq. 29) are solved there
  exactly, and ``dN/dv = (dz/dv) / (K_w k_n s)`` is projected on the Legendre
  polynomials of degree ``< m`` (Galerkin), so that the cycle count ``N(v)`` is a
  polynomial of degree ``m`` with ``N(0) = 0``. Where that projection is not
  positive, ``log dN/dv`` is projected instead. In ``z`` the slow-time system
  is explicit: no Newton iteration in slow time. Between the samples the
  harmonics are linear in the load fraction ``exp(-z)``, in which the DLFT
  response is piecewise linear.
* ``"legendre"`` and ``"monomial"``: the paper's method. ``w`` and the harmonics
  ``x`` are polynomials of degree ``m`` in ``N`` over ``[0, cycles]`` (Legendre
  polynomials, or the paper's powers of ``N / cycles``, eq. 25-27); the DLFT
  residual (eq. 29) and Archard's law ``dw/dN = K_w F_N(w) s`` are projected on
  them with a Gauss-Legendre rule of ``2 m + 2`` nodes (Galerkin), and the
  whole system is solved by Newton's method with its exact Jacobian.

Why the wear variable: with a load-dependent ``s``, Archard's law in ``N`` is
unstable while the wear accelerates (``d(dz/dN)/dz = K_w k_n ds/dz > 0``): a
perturbation of ``z`` grows like ``s(z) / s(0)`` along the history, which is
70 for the paper's 10 N case at 0.6 Hz with ``Nh = 7`` and 10^4 near the stick
limit. A projection in ``N`` spreads its residual over the whole history and
this growth amplifies it: the Galerkin system may have no solution near the
physical one, and its Newton iteration (on a residual that is only piecewise
smooth: the DLFT march changes stick/slip pattern hundreds of times along the
history at ``Nh = 21``) stalls. In ``z`` nothing feeds back.

The map ``v(z)``: the life fraction that Archard's law gives with a *profile*
of the sliding distance, ``log s`` interpolated in ``z`` by a monotone cubic
through periodic solutions sampled along the wear (``N_p(z) / N_p(z_end)``).
With a good profile ``dN/dv`` is nearly constant and the polynomial fits it at
any degree. The first samples are the Gauss nodes of the map of the ramp
``s(0) + z ds/dz(0)`` held between ``s(0)`` and ``s(z_end)`` (the exact tangent
at the start and the exact end value); then every piece of the profile whose
cycles differ, with the cubic and with ``log s`` linear, by more than
:data:`REFINE_TOLERANCE` of them is halved, for at most ``MAX_ROUNDS``
rounds; the Galerkin nodes in the profile's map then test it, and nodes that
contradict it (fit and profile more than :data:`REFINE_TOLERANCE` apart) refine
it in turn, for at most :data:`GALERKIN_PASSES` passes. A profile still coarse
after that is flagged. Refinement is what a single map cannot do: at a finite
``Nh`` the sliding distance has kinks and jumps where the stick/slip pattern
changes, and near the stick limit it grows 770-fold along the history (8-fold
within the first 2 % of ``z``, where 70 % of the life is spent: 10 N, 0.55 Hz,
``Nh = 3``); the Gauss nodes of one map missed such histories by up to 29 % at
degree 4.
Solves along the wear are warm-started and cheap (tens of microseconds at
``Nh = 3``): 35-90 samples cost less than the records.

The slow interval ends at the wear ``FIT_FRACTION u0`` (or at the horizon, if
that comes first); beyond, the contact is nearly unloaded, ``s`` no longer
changes (by < 1 % on the paper cases) and Archard's law is integrated in closed
form from the end state (``z`` linear in ``N``) up to ``stop_fraction u0``.
"""

from __future__ import annotations

import time
from functools import lru_cache
from typing import Literal

import numpy as np
from numba import njit

from ..hbm import dlft
from ..hbm.kernels import LOAD, NEWTON, newton_kernel, walk_kernel
from ..hbm.newton import keep_full_step
from ..hbm.periodic import solve_problem
from ..hbm.problem import Problem
from ..model import Model
from .dynamics import observables
from .result import Recorder, WearHistory, check_wear_inputs, two_scale_warning

__all__ = ["wear_polynomial", "BASES", "FIT_FRACTION", "MISFIT_LIMIT"]

#: ``Nh`` of :func:`wear_polynomial` by default: the paper's (section 2.1.2)
DEFAULT_HARMONICS = 3

#: slow-time bases of :func:`wear_polynomial`, the default first
BASES = ("saturating", "legendre", "monomial")

#: the saturating basis covers the wear up to this fraction of ``u0``; Archard's law in closed form beyond
FIT_FRACTION = 0.95

#: the saturating basis samples the sliding distance until each piece's cycles are this certain (relative)
REFINE_TOLERANCE = 0.005

#: refinement rounds of the saturating basis over one slow interval, at most
MAX_ROUNDS = 12

#: Galerkin passes of the saturating basis, at most: the nodes of a pass that contradict the profile refine it
GALERKIN_PASSES = 3

#: a fit whose cycles to reach its own wear miss its own Archard law by more than this is flagged
MISFIT_LIMIT = 0.02

_W_MAX = 1.0 - 1e-12  # w / u0 stays below 1: the load relaxes to zero only asymptotically


def wear_polynomial(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = DEFAULT_HARMONICS,
    samples: int | None = None,
    degree: int = 4,
    basis: Literal["saturating", "legendre", "monomial"] | None = None,
    tol: float = 1e-10,
    max_iter: int = 40,
    outputs: int = 101,
    stop_fraction: float = 0.99,
) -> WearHistory:
    """Wear evolution at one frequency by the polynomial slow-time DLFT (eq. 25-29).

    The default basis is ``"saturating"``, for one friction contact: the slow
    variable is the wear variable ``z = -ln(1 - w/u0)`` (see the module
    docstring). ``"legendre"`` and ``"monomial"`` are the paper's polynomials in
    the cycle count ``N`` (any number of friction contacts).

    Saturating: the history ends at ``stop_fraction u0`` (status ``"worn"``) or
    at the horizon (``"horizon"``); records are ``outputs`` cycle counts evenly
    spread over the polynomial's interval, then ``outputs // 4 + 1`` over the
    closed-form tail. Legendre and monomial: the interval is ``[0, cycles]``;
    Newton's method solves the Galerkin system from a start that integrates
    Archard's law on a coarse grid of wear levels, and a failure is reported in
    ``converged``, ``status`` and ``info["residual"]``.

    The fit is checked against its own Archard law: ``info["misfit"]`` is the
    largest relative difference, over the records beyond 10 % of ``u0``, between
    the fit's cycles and the cycles Archard's law takes to reach the fit's wear
    with the fit's own sliding distances: for the saturating basis, the larger of
    that difference at the nodes without truncation (the interpolant of
    ``dN/dv`` through every node) and between the fit and its profile
    (``info["change"]``); along the records' response for the others. ``info["wear_defect"]`` is the
    largest difference in wear (fraction of ``u0``). Above ``MISFIT_LIMIT``
    a warning names the frequency (Hz) and the misfit. The recorded ``rate`` is
    the fit's ``dw/dN``, limited so that :meth:`WearHistory.at` is monotone
    between monotone records and stays in ``[0, u0)``.

    Compiled: the periodic solves at the nodes (Newton, then the global Newton
    homotopy), the Galerkin assembly and its Jacobian, the sliding distances.

    Parameters
    ----------
    model : Model
        Structure whose contacts are all loaded friction contacts.
    omega : float
        Excitation frequency (rad/s).
    kw : float
        Archard coefficient (1/N), >= 0.
    cycles : float
        Horizon (cycles), > 0.
    harmonics, samples : int
        Harmonic balance settings (``Nh``, samples per period); the paper uses ``Nh = 3``.
    degree : int
        Polynomial degree ``m`` in [1, 12] (the paper uses 4); ``2 m + 2`` nodes.
    basis : {"saturating", "legendre", "monomial"}, optional
        Slow-time basis (see the module docstring); default ``"saturating"`` for one
        friction contact, ``"legendre"`` for several.
    tol : float
        Newton tolerance on the Galerkin residual (legendre, monomial), in (0, 1).
    max_iter : int
        Newton iterations (legendre, monomial).
    outputs : int
        Records over the polynomial's interval, >= 2.
    stop_fraction : float
        The history ends when the wear reaches ``stop_fraction u0``, in (0, 1).

    Returns
    -------
    WearHistory
        ``info``: ``basis``, ``degree``, ``nodes``, ``misfit``, ``wear_defect``,
        ``poor_fit``; saturating: ``end`` (cycles at the end of the polynomial),
        ``log_density``, ``sliding_ratio`` (``s`` at the end over ``s`` at the
        start), ``rounds`` (of refinement), ``settled`` (False: a piece of the
        profile was still coarse after ``MAX_ROUNDS`` rounds; the fit is then
        flagged), ``change``; legendre, monomial: ``iterations``, ``residual``.
    """
    check_wear_inputs(model, kw, cycles, degree)
    if degree < 1:
        raise ValueError(f"degree must be >= 1 for the polynomial method (w(0) = 0 takes one), got {degree}")
    if basis is None:
        basis = "saturating" if len(model.friction) == 1 else "legendre"
    if basis not in BASES:
        raise ValueError(f"basis must be one of {', '.join(map(repr, BASES))}, got {basis!r}")
    if basis == "saturating" and len(model.friction) != 1:
        raise ValueError(
            f"basis 'saturating' needs exactly one friction contact (its wear is the slow variable), the "
            f"model has {len(model.friction)}: use basis 'legendre' or 'monomial'"
        )
    if not 0 < stop_fraction < 1:
        raise ValueError(f"stop_fraction must be in (0, 1), got {stop_fraction!r}")
    if not (isinstance(outputs, (int, np.integer)) and outputs >= 2):
        raise ValueError(f"outputs must be an integer >= 2, got {outputs!r}")
    if not 0 < tol < 1:
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    start = time.perf_counter()
    problem = Problem(model, omega, harmonics, samples)
    sol0 = solve_problem(problem)
    if not sol0.converged:
        raise RuntimeError(f"the periodic solve of the unworn structure failed: {sol0.message}")
    u0 = np.array([c.u0 for c in model.friction])
    slid0 = sol0.sliding_distance
    rate0 = kw * model.normal_loads() * slid0
    info = {"basis": basis, "degree": degree, "nodes": 2 * degree + 2}
    if not np.any(rate0 > 0):
        rec = Recorder()
        for N in (0.0, float(cycles)):
            rec.add(N, np.zeros_like(u0), rate0, slid0, sol0, model)
        return rec.history(omega, "polynomial", model, kw, status="stuck", solves=1, info=info,
                           dynamics="dlft", harmonics=harmonics,
                           wall_time=time.perf_counter() - start)  # fmt: skip
    if problem.n_active != len(model.friction) or np.any(problem.kinds != dlft.FRICTION):
        raise ValueError("wear_polynomial needs every contact to be a loaded friction contact")
    notes = two_scale_warning(rate0, u0)
    slow = _Slow(problem, kw, degree, basis)
    if basis == "saturating":
        hist = slow.saturating(sol0.unknowns, float(cycles), outputs, stop_fraction)
    else:
        hist = slow.galerkin(sol0.unknowns, float(cycles), outputs, stop_fraction, tol, max_iter)
    hist.omega, hist.solves, hist.warnings = omega, slow.solves + 1, notes
    hist.info.update(info)
    if hist.info["poor_fit"]:
        remedy = "raise the degree"
        if basis == "saturating":
            remedy = "use the exact method" if not hist.info["settled"] else remedy
        hist.warnings.append(
            f"polynomial fit ({basis} basis, degree {degree}) at {hist.frequency:.4g} Hz misses its own "
            f"Archard law: the cycles to reach its wear differ by {hist.info['misfit']:.1%} "
            f"(its wear by {hist.info['wear_defect']:.1%} of u0); {remedy}"
        )
    hist.wall_time = time.perf_counter() - start
    return hist


# -- compiled kernels ---------------------------------------------------------------------------------
# Counts and flags passed to the solver's kernels as NumPy scalars: a Python literal (``12``, ``True``)
# would make Numba compile one more specialisation of the callee per literal value (seconds each).
_NEWTON_ITER, _POLISH_ITER, _MAX_PIECES = np.int64(12), np.int64(20), np.int64(5000)
_WALK_MODE, _LOAD_MODE = np.int64(NEWTON), np.int64(LOAD)
_JACOBIAN, _NO_JACOBIAN = np.bool_(True), np.bool_(False)


@njit(cache=True, nogil=True)
def _node_solve(x0, L0, Z, F, eps, kinds, limits, Phi, Psi, half_wave, target):
    """Periodic DLFT solution at friction limits ``limits`` from the solution ``x0`` at limits ``L0``.

    Newton first; then the exact path from ``x0`` (the DLFT equations are
    positively homogeneous in the unknowns, forces and limits together, so
    ``x0 p0`` solves them at the limits ``limits`` under the forces ``p0 F``,
    ``p0 = limits / L0``: the load walk from ``p0`` to 1 crosses exactly the
    stick/slip changes between the two states); then the global Newton
    homotopy from Newton's iterate; each with a polish.
    """
    x, ok, it, r, code = newton_kernel(
        x0.copy(), Z, F, eps, kinds, limits, Phi, Psi, half_wave, target, _NEWTON_ITER
    )
    if ok:
        return x, True
    n, nc = x0.shape[0], kinds.shape[0]
    Ns, H = Phi.shape
    none = np.empty((0, n))
    p0 = limits[0] / L0[0]
    same = 0.0 < p0 <= 1.0
    for c in range(nc):
        same = same and abs(limits[c] / L0[c] - p0) <= 1e-12 * p0
    if same:
        xw, p, pieces, arrived, k = walk_kernel(x0 * p0, p0, 1.0, _LOAD_MODE, Z, F, np.zeros(n), eps, kinds,
                                                limits, Phi, Psi, half_wave, _MAX_PIECES, none, np.empty(0),
                                                np.empty(0))  # fmt: skip
        if arrived:
            xp, ok, it, r, code = newton_kernel(xw, Z, F, eps, kinds, limits, Phi, Psi, half_wave, target,
                                                _POLISH_ITER)  # fmt: skip
            if ok:
                return xp, True
    R = np.empty(n)
    A = np.empty((nc, H, H))
    lam, X = np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    dlft.evaluate(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, _NO_JACOBIAN, R, A, lam, X, state)
    x, p, pieces, arrived, k = walk_kernel(x, 0.0, 1.0, _WALK_MODE, Z, F, R, eps, kinds, limits, Phi, Psi,
                                           half_wave, _MAX_PIECES, none, np.empty(0),
                                           np.empty(0))  # fmt: skip
    x, ok, it, r, code = newton_kernel(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, target, _POLISH_ITER)
    return x, ok


@njit(cache=True, nogil=True)
def _slid(x, Z, F, eps, limits, Phi, half_wave, s, dsdL):
    """Distance slid per period by each contact (m) at unknowns ``x``, and its partial derivative in ``L``."""
    Ns, H = Phi.shape
    lam, X, dlam, dsu = np.empty(Ns), np.empty(Ns), np.empty(Ns), np.empty(Ns)
    st = np.empty(Ns, dtype=np.int8)
    lu = F - Z @ x
    for c in range(limits.shape[0]):
        u = Phi @ (lu[c * H : (c + 1) * H] + eps[c] * x[c * H : (c + 1) * H])
        s[c], dsdL[c] = dlft.friction_sensitivity(u, limits[c], eps[c], half_wave, lam, X, st, dlam, dsu)


@njit(cache=True, nogil=True)
def _chain(limits, x0, L0, Z, F, eps, kinds, Phi, Psi, half_wave, target, X, S):
    """Periodic solutions at the friction limits ``limits[k]`` (K, nc), the first from the solution ``x0``
    at limits ``L0``, each next from the one before (:func:`_node_solve`).

    Fills ``X`` (K, n) and the sliding distances ``S`` (K, nc); returns the
    number of solves before the first that fails (K: none).
    """
    nc = limits.shape[1]
    dsdL = np.empty(nc)
    x, L = x0, L0
    for k in range(limits.shape[0]):
        x, ok = _node_solve(x, L, Z, F, eps, kinds, limits[k], Phi, Psi, half_wave, target)
        if not ok:
            return k
        X[k], L = x, limits[k]
        _slid(x, Z, F, eps, limits[k], Phi, half_wave, S[k], dsdL)
    return limits.shape[0]


@njit(cache=True, nogil=True)
def _slope(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave):
    """Total derivative ``ds/dL`` (nc,) of the sliding distance of each contact along the solution.

    ``dx/dL = -J^-1 dR/dL`` (exact on the current stick/slip pattern); contact ``c``'s own limit only.
    """
    n, nc = x.shape[0], kinds.shape[0]
    Ns, H = Phi.shape
    R, J = np.empty(n), np.empty((n, n))
    A = np.empty((nc, H, H))
    lam, X = np.empty((nc, Ns)), np.empty((nc, Ns))
    st = np.empty((nc, Ns), dtype=np.int8)
    dlft.evaluate(x, Z, F, eps, kinds, limits, Phi, Psi, half_wave, _JACOBIAN, R, A, lam, X, st)
    dlft.jacobian_from_blocks(Z, eps, A, J)
    lam_c, X_c, dlam, dsu = np.empty(Ns), np.empty(Ns), np.empty(Ns), np.empty(Ns)
    st_c = np.empty(Ns, dtype=np.int8)
    lu = F - Z @ x
    out = np.empty(nc)
    for c in range(nc):
        lo = c * H
        u = Phi @ (lu[lo : lo + H] + eps[c] * x[lo : lo + H])
        s, own = dlft.friction_sensitivity(u, limits[c], eps[c], half_wave, lam_c, X_c, st_c, dlam, dsu)
        dRdL = np.zeros(n)
        dRdL[lo : lo + H] = Psi @ dlam
        v = Phi.T @ dsu
        g = -(v @ np.ascontiguousarray(Z[lo : lo + H, :]))
        g[lo : lo + H] += eps[c] * v
        out[c] = own + g @ (-np.linalg.solve(J, dRdL))
    return out


@njit(cache=True, nogil=True)
def _galerkin(Cx, a, H, V, D, wq, V0, kw, kn, mu, u0, Z, F, eps, kinds, Phi, Psi, half_wave, scale, want):
    """Galerkin residual of the paper's polynomial DLFT and its exact Jacobian (with ``want``).

    Unknowns: harmonics ``Cx`` (m+1, nx) and wear ``a`` (m+1, nc) in the slow-time
    basis ``V`` (values at the K nodes, ``D`` = d/dtau), ``N = (tau + 1) H / 2``, wear
    unknown ``y = w / u0``. Rows: the DLFT residual (eq. 29) projected on the
    basis (per unit of ``scale``); per contact ``y(0) = 0``, then Archard's law
    ``dy/dtau = (H / 2) K_w k_n (1 - y) s`` projected on the first ``m`` functions.
    """
    K, nq = V.shape
    m = nq - 1
    nx, nc = Cx.shape[1], a.shape[1]
    Ns, Hs = Phi.shape
    nX = nq * nx
    n = nX + nq * nc
    G = np.zeros(n)
    J = np.zeros((n, n))
    R, Jk = np.empty(nx), np.empty((nx, nx))
    A = np.empty((nc, Hs, Hs))
    lam, Xs = np.empty((nc, Ns)), np.empty((nc, Ns))
    st = np.empty((nc, Ns), dtype=np.int8)
    lam_c, X_c, dlam, dsu = np.empty(Ns), np.empty(Ns), np.empty(Ns), np.empty(Ns)
    st_c = np.empty(Ns, dtype=np.int8)
    L, dL, s, dsL = np.empty(nc), np.empty(nc), np.empty(nc), np.empty(nc)
    dRdL, g = np.zeros((nx, nc)), np.zeros((nc, nx))
    y = V @ a
    dy = D @ a
    for k in range(K):
        x = V[k] @ Cx
        for j in range(nc):
            yc = min(max(y[k, j], 0.0), _W_MAX)
            L[j] = mu[j] * kn[j] * u0[j] * (1.0 - yc)
            dL[j] = -mu[j] * kn[j] * u0[j] if 0.0 < y[k, j] < _W_MAX else 0.0
        dlft.evaluate(x, Z, F, eps, kinds, L, Phi, Psi, half_wave, want, R, A, lam, Xs, st)
        lu = F - Z @ x
        for c in range(nc):
            lo = c * Hs
            u = Phi @ (lu[lo : lo + Hs] + eps[c] * x[lo : lo + Hs])
            s[c], dsL[c] = dlft.friction_sensitivity(u, L[c], eps[c], half_wave, lam_c, X_c, st_c, dlam, dsu)
            if want:
                dRdL[lo : lo + Hs, c] = Psi @ dlam
                v = Phi.T @ dsu
                g[c] = -(v @ np.ascontiguousarray(Z[lo : lo + Hs, :]))
                g[c, lo : lo + Hs] += eps[c] * v
        wk = wq[k]
        for q in range(nq):
            for i in range(nx):
                G[q * nx + i] += wk * V[k, q] * R[i] / scale
        for j in range(nc):
            c = kw * kn[j]
            fac = 1.0 - min(max(y[k, j], 0.0), _W_MAX)
            dfac = -1.0 if 0.0 < y[k, j] < _W_MAX else 0.0
            rate = c * fac * s[j]
            E = dy[k, j] - 0.5 * H * rate
            for q in range(m):
                G[nX + nc + q * nc + j] += wk * V[k, q] * E
            if not want:
                continue
            drate = c * (fac * dsL[j] * dL[j] + dfac * s[j])  # d rate / d y_j at fixed x
            for q in range(m):
                row = nX + nc + q * nc + j
                t = wk * V[k, q]
                for r in range(nq):
                    cu = -t * 0.5 * H * c * fac * V[k, r]
                    for i in range(nx):
                        J[row, r * nx + i] += cu * g[j, i]
                    J[row, nX + r * nc + j] += t * (D[k, r] - 0.5 * H * drate * V[k, r])
        if not want:
            continue
        dlft.jacobian_from_blocks(Z, eps, A, Jk)
        for q in range(nq):
            for r in range(nq):
                f = wk * V[k, q] * V[k, r] / scale
                for i in range(nx):
                    for i2 in range(nx):
                        J[q * nx + i, r * nx + i2] += f * Jk[i, i2]
                    for l in range(nc):
                        J[q * nx + i, nX + r * nc + l] += f * dRdL[i, l] * dL[l]
    for j in range(nc):
        for r in range(nq):
            G[nX + j] += V0[r] * a[r, j]
            J[nX + j, nX + r * nc + j] = V0[r]
    return G, J


@njit(cache=True, nogil=True)
def _sliding(X, limits, Z, F, eps, Phi, half_wave):
    """Sliding distances (K, nc) of the responses ``X`` (K, n) at friction limits ``limits`` (K, nc)."""
    K, nc = limits.shape
    out, dsdL = np.empty((K, nc)), np.empty(nc)
    for k in range(K):
        _slid(X[k], Z, F, eps, limits[k], Phi, half_wave, out[k], dsdL)
    return out


# -- the slow-time systems ----------------------------------------------------------------------------


class _Slow:
    """The polynomial slow-time DLFT of one problem: both formulations, their start and their records."""

    def __init__(self, problem: Problem, kw: float, degree: int, basis: str):
        friction = problem.model.friction
        self.p, self.kw, self.m, self.basis = problem, kw, degree, basis
        self.mu = np.array([c.mu for c in friction])
        self.kn = np.array([c.kn for c in friction])
        self.u0 = np.array([c.u0 for c in friction])
        self.L0 = self.mu * self.kn * self.u0  # friction limits of the unworn contacts (N)
        self.nc, self.nx = len(friction), problem.size
        self.scale = problem.residual_scale()
        self.target = 1e-10 * self.scale
        b = problem.basis
        self.dyn = (problem.Z, problem.F, problem.eps, problem.kinds, b.synthesis, b.analysis, b.half_wave)
        self.solves = 0

    def _chain(self, limits: np.ndarray, x0: np.ndarray, L0: np.ndarray):
        """Periodic solutions at friction limits (K, nc) by the kernel :func:`_chain` from the solution
        ``x0`` at limits ``L0``; the library's solver (stuck start, exact load continuation) where the
        kernel fails, the chain going on from there."""
        limits = np.ascontiguousarray(limits)
        K = len(limits)
        X, S = np.empty((K, self.nx)), np.empty((K, self.nc))
        Z, F, eps, kinds, Phi, Psi, half_wave = self.dyn
        self.solves += K
        k, x, L = 0, np.ascontiguousarray(x0), np.ascontiguousarray(L0, dtype=float)
        while k < K:
            try:
                k += _chain(
                    limits[k:], x, L, Z, F, eps, kinds, Phi, Psi, half_wave, self.target, X[k:], S[k:]
                )
            except Exception:  # noqa: BLE001 - numba raises a plain Exception for a singular matrix
                pass
            if k == K:
                break
            sol = solve_problem(self.p.with_wear(self.u0 * np.maximum(1 - limits[k] / self.L0, 0.0)))
            if not sol.converged:
                raise RuntimeError(
                    f"the periodic solve at friction limits {limits[k]} N failed: {sol.message}"
                )
            X[k], S[k] = sol.unknowns, sol.sliding_distance
            k, x, L = k + 1, X[k], limits[k]
        return X, S

    # -- saturating basis: the wear variable as the slow variable ----------------------------------
    def saturating(self, x0: np.ndarray, cycles: float, outputs: int, stop_fraction: float) -> WearHistory:
        """History in the wear variable ``z`` (one contact); see the module docstring."""
        Z, F, eps, kinds, Phi, Psi, half_wave = self.dyn
        c = float(self.kw * self.kn[0])  # dz/dN = c s
        s0 = _sliding(x0[None], self.L0[None], Z, F, eps, Phi, half_wave)[0, 0]
        s1 = -self.L0[0] * _slope(x0, Z, F, eps, kinds, self.L0, Phi, Psi, half_wave)[0]  # ds/dz at z = 0
        z_stop = -np.log1p(-stop_fraction)
        z_end = -np.log1p(-min(FIT_FRACTION, stop_fraction))
        samples = _Samples(x0, s0)
        s_end = self._sample(samples, np.array([z_end]))[0]
        ramp = _Ramp(c, s0, s1, s_end, z_end)
        tau = _quadrature("legendre", self.m)[0]
        self._sample(samples, ramp.z((tau + 1) / 2 * ramp.N_end))  # the nodes in the ramp's map
        fit, rounds = self._fit(samples, z_end)
        if cycles < fit.N_end * (1 - 1e-9):  # the horizon comes first: the slow interval ends there
            z_end = float(fit.z(np.array([cycles]))[0])
            s_end = self._sample(samples, np.array([z_end]))[0]
            fit, more = self._fit(samples, z_end)
            rounds += more
        profile, density = fit.profile, fit.density
        # records on the polynomial's interval
        N = np.linspace(0.0, min(fit.N_end, cycles), outputs)
        vr = density.v(N)
        z = profile.z_at(vr * profile.N_end)
        dz = profile.N_end * c * profile.s(z) / density(vr)  # dz/dN = (dz/dv) / (dN/dv)
        Xr = samples.harmonics(z)
        w = self.u0 * -np.expm1(-z[:, None])
        dw = self.u0 * np.exp(-z[:, None]) * dz[:, None]
        slid = _sliding(Xr, self.L0 * np.exp(-z[:, None]), Z, F, eps, Phi, half_wave)
        # the misfit: against Archard's law at the nodes without truncation (the interpolant, collocation)
        col = _Density(fit.f, fit.wq, np.polynomial.legendre.legvander(fit.tau, len(fit.tau) - 1))
        far = (w[:, 0] > 0.1 * self.u0[0]) & (N > 0)
        misfit = float(np.max(np.abs(np.interp(vr[far], col.grid, col.N) / N[far] - 1), initial=fit.change))
        defect = float(
            np.max(np.abs(-np.expm1(-profile.z_at(col.v(N) * profile.N_end)) - w[:, 0] / self.u0[0]))
        )
        # closed-form tail: z linear in N at the end state's sliding distance
        N_stop = N[-1] + (z_stop - z[-1]) / (c * s_end)
        status = "worn" if N_stop <= cycles else "horizon"
        if N[-1] < min(N_stop, cycles):
            Nt = np.linspace(N[-1], min(N_stop, cycles), outputs // 4 + 2)[1:]
            zt = z[-1] + c * s_end * (Nt - N[-1])
            N, w = np.concatenate([N, Nt]), np.vstack([w, self.u0 * -np.expm1(-zt[:, None])])
            dw = np.vstack([dw, self.u0 * np.exp(-zt[:, None]) * c * s_end])
            slid = np.vstack([slid, np.full((len(Nt), 1), s_end)])
            Xr = np.vstack([Xr, np.repeat(Xr[-1:], len(Nt), axis=0)])
        info = {"misfit": misfit, "wear_defect": defect, "poor_fit": misfit > MISFIT_LIMIT or not fit.settled,
                "settled": fit.settled, "rounds": rounds, "change": fit.change, "end": N[-1],
                "log_density": density.log, "sliding_ratio": float(s_end / s0)}  # fmt: skip
        return self._history(N, w, dw, Xr, slid, status, info)

    def _sample(self, samples: _Samples, z: np.ndarray) -> np.ndarray:
        """Periodic solutions at the wear variables ``z`` (increasing), kept in ``samples``; their sliding
        distances."""
        x0, z0 = samples.start(z[0])
        X, S = self._chain(self.L0 * np.exp(-z[:, None]), x0, self.L0 * np.exp(-z0))
        if np.any(S[:, 0] <= 0):
            raise RuntimeError(f"the contact sticks at wear {self.u0[0] * -np.expm1(-z[S[:, 0] <= 0])} m")
        samples.add(z, X, S)
        return S[:, 0]

    def _fit(self, samples: _Samples, z_end: float) -> tuple[_Fit, int]:
        """The fit on ``0 <= z <= z_end``: the profile of ``s`` refined until every piece is settled (at most
        ``MAX_ROUNDS`` rounds), then the Galerkin projection in its map; again with the nodes among the
        samples while fit and profile disagree (at most :data:`GALERKIN_PASSES` passes). See the module
        docstring.

        Returns the fit and the number of refinement rounds.
        """
        c = float(self.kw * self.kn[0])
        tau, wq, Vq, _, _ = _quadrature("legendre", self.m)
        rounds = 0
        for _ in range(GALERKIN_PASSES):
            profile = samples.profile(c, z_end)
            while (coarse := profile.coarse(REFINE_TOLERANCE)).size and rounds < MAX_ROUNDS:
                rounds += 1
                self._sample(samples, 0.5 * (profile.z[coarse] + profile.z[coarse + 1]))  # halve them
                profile = samples.profile(c, z_end)
            zk = profile.z_at(0.5 * (tau + 1) * profile.N_end)
            f = profile.N_end * profile.s(zk) / self._sample(samples, zk)  # dN/dv at the nodes
            fit = _Fit(profile, _Density(f, wq, Vq[:, : self.m]), f, tau, wq)  # projection on degree m - 1
            fit.settled = not coarse.size
            fit.change = fit.difference(profile, z_end)
            if fit.change <= REFINE_TOLERANCE:  # the nodes confirm the profile
                break
        return fit, rounds

    # -- legendre, monomial: the paper's Galerkin system in N -----------------------------------------
    def galerkin(self, x0, cycles, outputs, stop_fraction, tol, max_iter) -> WearHistory:
        """The paper's coupled Galerkin system in ``N`` over ``[0, cycles]``, by Newton's method."""
        tau, wq, V, D, V0 = _quadrature(self.basis, self.m)
        Cx, a = self._start(x0, cycles, tau, wq, V, V0, stop_fraction)
        Cx, a, ok, its, res = self._newton(Cx, a, cycles, V, D, wq, V0, tol, max_iter)
        N = np.linspace(0.0, cycles, outputs)
        Vr, Dr = _slow_basis(self.basis, self.m, 2 * N / cycles - 1)
        y, dy = Vr @ a, Dr @ a * (2 / cycles)
        w = self.u0 * np.clip(y, 0.0, _W_MAX)
        dw = np.where(y < _W_MAX, self.u0 * dy, 0.0)
        Xr = Vr @ Cx
        Z, F, eps, kinds, Phi, Psi, half_wave = self.dyn
        slid = _sliding(Xr, self.mu * self.kn * (self.u0 - w), Z, F, eps, Phi, half_wave)
        misfit, defect = _misfit(N, w, dw, self.kw * self.kn * (self.u0 - w) * slid, self.u0)
        status = ("worn" if np.all(w[-1] >= stop_fraction * self.u0) else "horizon") if ok else (
            f"Newton did not converge (Galerkin residual {res:.2e})")  # fmt: skip
        info = {"misfit": misfit, "wear_defect": defect, "poor_fit": misfit > MISFIT_LIMIT,
                "iterations": its, "residual": res}  # fmt: skip
        hist = self._history(N, w, dw, Xr, slid, status, info)
        hist.converged = ok
        return hist

    def _start(self, x0, cycles, tau, wq, V, V0, stop_fraction):
        """Archard's law integrated on a coarse grid of wear levels with exact periodic solutions there;
        its ``z(N)`` and harmonics, fitted at the nodes of ``[0, cycles]``."""
        levels = -np.log1p(-stop_fraction) * np.linspace(0.0, 1.0, 9) ** 2  # finer where wear is slowest
        Xg, S = self._chain(self.L0 * np.exp(-levels[:, None]), x0, self.L0)
        rate = np.mean(self.kw * self.kn * S, axis=1)  # dz/dN
        Ng = np.concatenate([[0.0], np.cumsum(np.diff(levels) * 0.5 * (1 / rate[1:] + 1 / rate[:-1]))])
        zk = np.interp((tau + 1) / 2 * cycles, Ng, levels)
        sw = np.sqrt(wq)[:, None]
        rows = np.vstack([V * sw, 10 * V0[None]])
        a = np.linalg.lstsq(rows, np.concatenate([-np.expm1(-zk) * sw[:, 0], [0.0]]), rcond=None)[0]
        X = np.stack([np.interp(zk, levels, col) for col in Xg.T], axis=1)
        Cx = np.linalg.lstsq(V * sw, X * sw, rcond=None)[0]
        return np.ascontiguousarray(Cx), np.ascontiguousarray(np.repeat(a[:, None], self.nc, axis=1))

    def _newton(self, Cx, a, H, V, D, wq, V0, tol, max_iter):
        """Newton's method, non-monotone (full steps while the residual stays within 1e3 of the best) for
        half the budget (:func:`~fretwear.hbm.newton.keep_full_step`), then damped from the best iterate:
        the residual is only piecewise smooth."""
        Z, F, eps, kinds, Phi, Psi, half_wave = self.dyn
        nX = Cx.size

        def evaluate(v):
            return _galerkin(v[:nX].reshape(Cx.shape), v[nX:].reshape(a.shape), H, V, D, wq, V0, self.kw,
                             self.kn, self.mu, self.u0, Z, F, eps, kinds, Phi, Psi, half_wave, self.scale,
                             True)  # fmt: skip

        col = np.concatenate([np.full(nX, max(np.abs(Cx).max(), 1e-300)), np.ones(a.size)])
        v = np.concatenate([Cx.ravel(), a.ravel()])
        G, J = evaluate(v)
        r = float(np.abs(G).max())
        best = (r, v, G, J)
        damped, it = False, 0
        while it < max_iter and r > tol:
            it += 1
            try:
                d = np.linalg.solve(J * col, -G) * col
            except np.linalg.LinAlgError:
                break
            if not damped:
                Gt, Jt = evaluate(v + d)
                rt = float(np.abs(Gt).max())
                if keep_full_step(rt, best[0], it, max_iter):
                    v, G, J, r = v + d, Gt, Jt, rt
                    if r < best[0]:
                        best = (r, v, G, J)
                    continue
                damped = True
                r, v, G, J = best
                continue
            step = 1.0
            while step > 1e-9:
                Gt, Jt = evaluate(v + step * d)
                rt = float(np.abs(Gt).max())
                if rt < (1 - 1e-4 * step) * r:
                    break
                step *= 0.5
            else:
                break
            v, G, J, r = v + step * d, Gt, Jt, rt
            if r < best[0]:
                best = (r, v, G, J)
        r, v = best[0], best[1]
        return v[:nX].reshape(Cx.shape), v[nX:].reshape(a.shape), r <= tol, it, r

    # -- records -----------------------------------------------------------------------------------
    def _history(self, N, w, dw, X, slid, status, info) -> WearHistory:
        rows, index = np.unique(X, axis=0, return_inverse=True)  # the tail repeats the end state
        lam = self.p.F[None, :] - rows @ self.p.Z.T
        amp, hp2p, rel = (o[index.ravel()] for o in observables(self.p, lam))
        return WearHistory(
            0.0, "polynomial", N, w, self.kn * (self.u0 - w), _monotone_slopes(N, w, dw), slid, amp, hp2p,
            rel, u0=self.u0, kn=self.kn, kw=self.kw, dynamics="dlft", harmonics=self.p.harmonics,
            status=status, info=info,
        )  # fmt: skip


class _Ramp:
    """The map's model of the sliding distance: ``s(0) + z ds/dz(0)`` held between ``s(0)`` and ``s(z_end)``.

    ``N(z)`` is the cycle count Archard's law takes with it (closed form) and
    ``z(N)`` its inverse; ``N_end = N(z_end)``.
    """

    def __init__(self, c: float, s0: float, s1: float, s_end: float, z_end: float):
        self.c, self.s0, self.lo, self.hi = c, s0, min(s0, s_end), max(s0, s_end)
        reach = s_end if (s_end - s0) * s1 > 0 else s0  # the value the tangent runs to
        self.s1 = s1 if reach != s0 else 0.0
        self.zc = min((reach - s0) / self.s1, z_end) if self.s1 else 0.0  # end of the ramp
        self.sc = s0 + self.s1 * self.zc
        self.Nc = self._ramp_cycles(self.zc)
        self.N_end = float(self.N(np.array([z_end]))[0])

    def s(self, z):
        return np.clip(self.s0 + self.s1 * z, self.lo, self.hi)

    def _ramp_cycles(self, z):
        if self.s1 == 0.0:
            return z / (self.c * self.s0)
        return np.log1p(self.s1 * z / self.s0) / (self.c * self.s1)

    def N(self, z):
        return np.where(
            z <= self.zc,
            self._ramp_cycles(np.minimum(z, self.zc)),
            self.Nc + (z - self.zc) / (self.c * self.sc),
        )

    def z(self, N):
        if self.s1 == 0.0:
            ramp = N * self.c * self.s0
        else:
            ramp = self.s0 * np.expm1(self.c * self.s1 * np.minimum(N, self.Nc)) / self.s1
        return np.where(N <= self.Nc, ramp, self.zc + (N - self.Nc) * self.c * self.sc)


class _Profile:
    """The sliding distance along the wear variable from its samples: the map of the saturating basis.

    ``log s`` is interpolated in ``z`` by a monotone cubic (PCHIP) through the
    samples; ``N(z)``, the cycles Archard's law takes with it, by the trapezoidal
    rule on 32 steps per piece, ``z_at(N)`` its inverse. A piece is *coarse*
    when the cycles it takes with the cubic and with ``log s`` linear differ by
    more than a fraction ``tol`` of them (and of ``tol / 100`` of the whole):
    the samples have not resolved ``s`` there.
    """

    _STEPS = 32

    def __init__(self, c: float, z: np.ndarray, s: np.ndarray):
        self.c, self.z, self._l = c, z, np.log(s)
        self._h = np.diff(z)
        self._m = _pchip_slopes(self._h, self._l)
        t = np.arange(self._STEPS + 1) / self._STEPS  # both ends of every piece
        grid = z[:-1, None] + self._h[:, None] * t
        cubic = self._cycles(grid, np.exp(-self._hermite(np.arange(len(self._h))[:, None], t)))
        linear = self._cycles(grid, np.exp(-(self._l[:-1, None] + np.diff(self._l)[:, None] * t)))
        self._pieces = cubic[:, -1]
        self._misses = np.abs(cubic[:, -1] - linear[:, -1])
        start = np.concatenate([[0.0], np.cumsum(self._pieces)])
        self.grid = np.append(grid[:, :-1].ravel(), z[-1])
        self.N_grid = np.append((start[:-1, None] + cubic[:, :-1]).ravel(), start[-1])
        self.N_end = float(start[-1])

    def _hermite(self, i, t):
        """``log s`` at the fraction ``t`` of piece ``i`` (cubic Hermite)."""
        rise, h = self._l[i + 1] - self._l[i], self._h[i]
        m0, m1 = h * self._m[i], h * self._m[i + 1]
        return self._l[i] + t * (m0 + t * ((3 * rise - 2 * m0 - m1) + t * (m0 + m1 - 2 * rise)))

    def _cycles(self, grid: np.ndarray, inverse_s: np.ndarray) -> np.ndarray:
        """Cycles from the start of each piece (rows) to each point of ``grid``: the trapezoidal rule."""
        steps = 0.5 * np.diff(grid, axis=1) * (inverse_s[:, 1:] + inverse_s[:, :-1]) / self.c
        return np.concatenate([np.zeros((len(grid), 1)), np.cumsum(steps, axis=1)], axis=1)

    def s(self, z):
        i = np.clip(np.searchsorted(self.z, z, side="right") - 1, 0, len(self._h) - 1)
        return np.exp(self._hermite(i, (z - self.z[i]) / self._h[i]))

    def N(self, z):
        return np.interp(z, self.grid, self.N_grid)

    def z_at(self, N):
        return np.interp(N, self.N_grid, self.grid)

    def coarse(self, tol: float) -> np.ndarray:
        """Indices of the coarse pieces."""
        return np.flatnonzero(self._misses > tol * np.maximum(self._pieces, 0.01 * self.N_end))


def _pchip_slopes(h: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Slopes at the knots of the monotone cubic interpolant of ``y`` (PCHIP: Fritsch-Butland inside, the
    shape-preserving three-point formula at the ends), ``h`` the knot spacings."""
    d = np.diff(y) / h
    if len(h) == 1:
        return np.full(2, d[0])
    m = np.zeros_like(y)
    w1, w2 = 2 * h[1:] + h[:-1], h[1:] + 2 * h[:-1]
    same = d[:-1] * d[1:] > 0
    left, right = np.where(same, d[:-1], 1.0), np.where(same, d[1:], 1.0)
    m[1:-1] = np.where(same, (w1 + w2) / (w1 / left + w2 / right), 0.0)
    for k, (h0, h1, d0, d1) in ((0, (h[0], h[1], d[0], d[1])), (-1, (h[-1], h[-2], d[-1], d[-2]))):
        e = ((2 * h0 + h1) * d0 - h0 * d1) / (h0 + h1)
        if np.sign(e) != np.sign(d0):
            e = 0.0
        elif np.sign(d0) != np.sign(d1) and abs(e) > abs(3 * d0):
            e = 3 * d0
        m[k] = e
    return m


class _Samples:
    """Periodic solutions met along the wear variable ``z``: the profile's knots, the records' harmonics."""

    def __init__(self, x0: np.ndarray, s0: float):
        self.z, self.X, self.s = np.zeros(1), x0[None].copy(), np.array([s0])

    def add(self, z: np.ndarray, X: np.ndarray, S: np.ndarray) -> None:
        z, order = np.unique(np.concatenate([self.z, z]), return_index=True)
        self.z = z
        self.X = np.vstack([self.X, X])[order]
        self.s = np.concatenate([self.s, S[:, 0]])[order]

    def profile(self, c: float, z_end: float) -> _Profile:
        """The profile through the samples up to ``z_end``."""
        keep = self.z <= z_end
        return _Profile(c, self.z[keep], self.s[keep])

    def start(self, z: float) -> tuple[np.ndarray, float]:
        """Start of a chain of solves from ``z`` on: the sample at the largest wear variable up to ``z``, and
        that variable. (Measured: solves chained from there are faster than solves each from its nearest
        sample.)"""
        k = max(np.searchsorted(self.z, z, side="right") - 1, 0)
        return self.X[k], float(self.z[k])

    def harmonics(self, z: np.ndarray) -> np.ndarray:
        """Unknowns at ``z``, linear in the load fraction ``exp(-z)`` between the samples."""
        rho = np.exp(-self.z[::-1])  # increasing
        return np.stack([np.interp(np.exp(-z), rho, col) for col in self.X[::-1].T], axis=1)


class _Fit:
    """The saturating basis's cycle count ``N(v)`` in the map ``v = N_p(z) / N_p(z_end)`` of profile ``p``."""

    def __init__(self, profile: _Profile, density: _Density, f: np.ndarray, tau: np.ndarray, wq: np.ndarray):
        self.profile, self.density, self.f, self.tau, self.wq = profile, density, f, tau, wq
        self.N_end = float(density.N[-1])
        self.change, self.settled = np.inf, False

    def z(self, N):
        return self.profile.z_at(self.density.v(N) * self.profile.N_end)

    def N(self, z):
        return np.interp(self.profile.N(z) / self.profile.N_end, self.density.grid, self.density.N)

    def difference(self, profile: _Profile, z_end: float) -> float:
        """Largest relative difference from the profile's cycles to reach ``z`` in ``[z_lo, z_end]`` (``w``
        from a tenth of its value at ``z_end``)."""
        z = np.linspace(-np.log1p(0.1 * np.expm1(-z_end)), z_end, 64)
        return float(np.max(np.abs(self.N(z) / profile.N(z) - 1)))


class _Density:
    """The time density ``dN/dv`` and its integral ``N(v)``, ``N(0) = 0``, from its values ``f`` at the nodes.

    ``dN/dv`` is the Legendre series in ``2 v - 1`` that projects ``f`` (Gauss
    weights ``wq``) on the columns of ``basis``; if that series is not positive
    on [0, 1] (a density that varies by orders of magnitude, near the stick
    limit), ``exp`` of the projection of ``log f``, positive by construction.
    Either way ``N`` increases with ``v``, so the wear increases with ``N``.
    """

    def __init__(self, f: np.ndarray, wq: np.ndarray, basis: np.ndarray):
        weights = (2 * np.arange(basis.shape[1]) + 1) / 2
        self.grid = np.linspace(0.0, 1.0, 2001)
        self.log = False
        self.coef = weights * (basis.T @ (wq * f))
        d = self(self.grid)
        if np.any(d <= 0):
            self.log = True
            self.coef = weights * (basis.T @ (wq * np.log(f)))
            d = self(self.grid)
        self.N = np.concatenate([[0.0], np.cumsum(0.5 * np.diff(self.grid) * (d[1:] + d[:-1]))])

    def __call__(self, v):
        p = np.polynomial.legendre.legval(2 * np.asarray(v) - 1, self.coef)
        return np.exp(p) if self.log else p

    def v(self, N):
        """``v`` with ``N(v) = N`` (N in [0, N(1)])."""
        return np.interp(np.atleast_1d(N), self.N, self.grid)


def _slow_basis(kind: str, degree: int, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and d/dtau of the slow-time basis at ``tau`` in [-1, 1], shape (len(tau), degree + 1)."""
    q = np.arange(degree + 1)
    if kind == "monomial":  # powers of the normalised slow time eta / N_end = (tau + 1) / 2
        s = (tau + 1) / 2
        V = s[:, None] ** q
        D = np.where(q > 0, 0.5 * q * s[:, None] ** np.maximum(q - 1, 0), 0.0)
    else:
        V = np.polynomial.legendre.legvander(tau, degree)
        D = V[:, :-1] @ np.polynomial.legendre.legder(np.eye(degree + 1))
    return np.ascontiguousarray(V), np.ascontiguousarray(D)


@lru_cache(maxsize=64)
def _quadrature(basis: str, degree: int):
    """Gauss-Legendre nodes and weights (2 m + 2), the slow-time basis and its derivative there, and at 0."""
    tau, wq = np.polynomial.legendre.leggauss(2 * degree + 2)
    V, D = _slow_basis(basis, degree, tau)
    V0 = _slow_basis(basis, degree, np.array([-1.0]))[0][0]
    for arr in (tau, wq, V, D, V0):
        arr.setflags(write=False)
    return tau, wq, V, D, V0


def _misfit(N, w, dw, archard, u0) -> tuple[float, float]:
    """How far a fit is from Archard's law with its own sliding distances.

    Returns the largest relative difference between the cycles Archard's law
    takes to reach the fit's wear, ``integral dw / rate``, and the fit's cycles
    (records beyond 10 % of ``u0``; at most 10, i.e. 1000 %: where the contact
    sticks and the fit still wears, Archard's law never gets there), and the
    largest difference (fraction of ``u0``) between the fit's wear and
    ``integral rate dN``.
    """
    dN = np.diff(N)[:, None]
    zero = np.zeros((1, w.shape[1]))
    w_archard = np.concatenate([zero, np.cumsum(0.5 * dN * (archard[1:] + archard[:-1]), axis=0)])
    defect = float(np.max(np.abs(w_archard - w) / u0))
    idle = np.abs(dw) <= 1e-9 * u0 / N[-1]  # neither the fit nor Archard's law wears: time runs alike
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = np.where(archard > 0, dw / archard, np.where(idle, 1.0, np.inf))
    N_archard = np.concatenate([zero, np.cumsum(0.5 * dN * (ratio[1:] + ratio[:-1]), axis=0)])
    far = (w > 0.1 * u0) & (N[:, None] > 0)
    rel = np.abs(N_archard / np.where(N[:, None] > 0, N[:, None], 1.0) - 1)
    return min(float(np.max(rel[far], initial=0.0)), 10.0), defect


def _monotone_slopes(N, w, dw):
    """Slopes for a monotone cubic Hermite interpolation of ``w(N)`` (Fritsch-Carlson limiter).

    Where the records are monotone the interpolant stays between them, hence in ``[0, u0)``.
    """
    secant = np.diff(w, axis=0) / np.diff(N)[:, None]
    left, right = np.vstack([secant[:1], secant]), np.vstack([secant, secant[-1:]])
    d = np.where((left * right <= 0) | (dw * right < 0), 0.0, dw)
    return np.sign(d) * np.minimum(np.abs(d), 3 * np.minimum(np.abs(left), np.abs(right)))
