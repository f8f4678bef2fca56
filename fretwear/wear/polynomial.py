"""Polynomial slow-time DLFT (paper eq. 25-29).

The Fourier coefficients of the contact unknowns and the wear depth are
polynomials of the slow time ``eta`` (Legendre basis by default, the paper's
monomials on request); a Galerkin projection on Gauss-Legendre nodes of
``eta`` turns the whole wear history at one frequency into one nonlinear
system, solved by Newton's method with exact derivatives of the DLFT march.
"""

from __future__ import annotations

import time
from typing import Literal

import numpy as np

from ..hbm import dlft
from ..hbm.periodic import NewtonResult, Problem, solve_problem
from ..hbm.solution import PeriodicSolution
from ..model import Model
from .common import (
    Dynamics,
    Recorder,
    WearHistory,
    check_wear_inputs,
    clip_wear,
    two_scale_warning,
)

__all__ = ["wear_polynomial"]
from .stepping import wear_stepping


def _basis(kind: str, degree: int, xi: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Values and d/dxi of the slow-time basis at ``xi`` in [-1, 1], shape (len(xi), degree + 1)."""
    if kind == "legendre":
        V = np.polynomial.legendre.legvander(xi, degree)
        D = np.stack([np.polynomial.legendre.legval(xi, np.polynomial.legendre.legder(np.eye(degree + 1)[q]))
                      for q in range(degree + 1)], axis=1)  # fmt: skip
    elif kind == "monomial":  # powers of the normalised slow time eta / N_end = (xi + 1) / 2
        s = (xi + 1) / 2
        q = np.arange(degree + 1)
        V = s[:, None] ** q
        D = np.where(q > 0, 0.5 * q * s[:, None] ** np.maximum(q - 1, 0), 0.0)
    else:
        raise ValueError(f"basis must be 'legendre' or 'monomial', got {kind!r}")
    return V, D


def wear_polynomial(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 3,
    samples: int | None = None,
    degree: int = 4,
    basis: Literal["legendre", "monomial"] = "legendre",
    tol: float = 1e-9,
    max_iter: int = 60,
    outputs: int = 101,
) -> WearHistory:
    """Wear evolution at one frequency by the polynomial slow-time DLFT (eq. 25-29).

    The harmonics ``x`` of the contact coordinates and the wear ``w`` are
    polynomials of degree ``m`` in the slow time ``eta`` in [0, cycles] (eq.
    25-27). Galerkin projection on the polynomial basis, with Gauss-Legendre
    quadrature in ``eta``, of the DLFT equations (eq. 29) and of the Archard law
    ``dw/deta = K_w F_N(w) s``, with ``w(0) = 0``, gives one nonlinear system of
    ``(m + 1) (n_c H + n_f)`` unknowns per frequency (``H = 2 Nh + 1`` slots per
    contact, fewer with half-wave symmetry), solved by Newton's method with the
    exact derivatives of the DLFT march. When Newton fails from the frozen-
    dynamics start, the horizon is grown from a short one.

    The fit is checked afterwards at ``outputs`` points: ``info["wear_defect"]``
    is the largest misfit of the Archard law integrated over the horizon, as a
    fraction of ``u0``, and ``info["poor_fit"]`` flags misfits above 2 % (the
    paper notes that polynomials cannot follow abrupt changes of the wear rate).

    Parameters
    ----------
    degree : int
        Polynomial degree ``m`` in [0, 12] (the paper uses 4).
    basis : {"legendre", "monomial"}
        Legendre polynomials on the slow interval (well conditioned, default) or
        the paper's monomials (in normalised slow time).
    Other parameters as in :func:`wear_stepping`.
    """
    check_wear_inputs(model, kw, cycles, degree)
    start = time.perf_counter()
    dyn = Dynamics(model, omega, harmonics, samples, kw, "dlft")
    first = dyn(np.zeros(len(model.friction)))
    if first is None:
        raise RuntimeError("the periodic solve of the unworn structure failed")
    g0, slid0, sol0 = first
    u0 = np.array([c.u0 for c in model.friction])
    rec = Recorder()
    if not np.any(g0 > 0):
        for N in (0.0, float(cycles)):
            rec.add(N, np.zeros_like(u0), g0, slid0, sol0, model)
        return rec.history(omega, "polynomial", model, kw, status="stuck", solves=1,
                           wall_time=time.perf_counter() - start)  # fmt: skip
    notes = two_scale_warning(g0, u0)
    problem = dyn.problem
    if problem.n_active != len(model.friction) or np.any(problem.kinds != dlft.FRICTION):
        raise ValueError("wear_polynomial needs every contact to be a loaded friction contact")
    system = _PolySystem(problem, kw, degree, basis)
    x0 = sol0.unknowns
    # frozen dynamics start: x constant, w = u0 (1 - exp(-kw kn s0 eta)) projected on the basis
    result, start_kind = None, "frozen dynamics, growing horizon"
    for horizon in _horizons(cycles, g0, u0):
        guess = system.initial(x0, slid0, horizon) if result is None else system.rescale(result, horizon)
        result, ok, its, res = system.solve(guess, horizon, tol, max_iter)
        if not ok:
            break
    if not ok:  # start again from a coarse stepping solution sampled at the quadrature nodes
        coarse = wear_stepping(
            model, omega, kw=kw, cycles=cycles, harmonics=harmonics, samples=samples, tol=1e-2
        )
        result, ok, more, res = system.solve(system.from_history(coarse, cycles), cycles, tol, max_iter)
        its += more
        start_kind = "coarse stepping"
    status = "horizon" if ok else f"Newton did not converge (residual {res:.2e})"
    etas = np.linspace(0.0, cycles, outputs)
    defect = 0.0
    prev_w = None
    for eta in etas:
        x, w = system.evaluate_at(result, eta, cycles)
        p = problem.with_wear(clip_wear(w, u0))
        sol = PeriodicSolution.build(p, x, _newton_stub(p, x), "polynomial")
        slid = sol.sliding_distance
        rate = kw * model.normal_loads(clip_wear(w, u0)) * slid
        rec.add(eta, clip_wear(w, u0), rate, slid, sol, model)
        if prev_w is not None:  # trapezoidal Archard integral between records vs the polynomial's increment
            prev_eta, prev_w_val, prev_rate, acc = prev_w
            acc = acc + 0.5 * (eta - prev_eta) * (rate + prev_rate)
            defect = max(defect, float(np.max(np.abs(acc - w) / u0)))
            prev_w = (eta, w, rate, acc)
        else:
            prev_w = (eta, w, rate, np.zeros_like(w))
    info = {"wear_defect": defect, "poor_fit": defect > 0.02, "iterations": its, "degree": degree,
            "basis": basis, "start": start_kind}  # fmt: skip
    if info["poor_fit"]:
        notes.append(f"polynomial fit is poor: Archard-law misfit {defect:.1%} of u0 (raise the degree)")
    hist = rec.history(omega, "polynomial", model, kw, converged=ok, status=status, solves=its,
                       wall_time=time.perf_counter() - start, warnings=notes, info=info)  # fmt: skip
    if ok and np.all(hist.wear[-1] >= 0.99 * u0):
        hist.status = "worn"
    return hist


def _horizons(cycles: float, g0: np.ndarray, u0: np.ndarray) -> list[float]:
    """Horizons for the continuation in the slow interval: from ~5 % wear up to ``cycles``."""
    short = float(np.min(0.05 * u0[g0 > 0] / g0[g0 > 0]))
    if short >= cycles:
        return [cycles]
    return list(np.geomspace(short, cycles, max(2, int(np.ceil(np.log(cycles / short) / np.log(4))) + 1)))


def _newton_stub(problem: Problem, x: np.ndarray):

    R = problem.evaluate(x, jacobian=False)[0]
    return NewtonResult(x, True, 0, float(np.abs(R).max() / problem.residual_scale()))


class _PolySystem:
    """Galerkin system of the polynomial slow-time DLFT for friction-only problems."""

    def __init__(self, problem: Problem, kw: float, degree: int, basis: str):
        self.p, self.kw, self.m, self.kind = problem, kw, degree, basis
        self.nq = degree + 1
        nodes, weights = np.polynomial.legendre.leggauss(max(2 * degree + 2, 4))
        self.xi, self.wq = nodes, weights
        self.V, self.D = _basis(basis, degree, nodes)  # (K, m+1)
        self.nc, self.H = problem.n_active, problem.basis.size
        self.nx = self.nc * self.H
        self.mu = np.array([c.mu for c in problem.model.friction])
        self.kn = np.array([c.kn for c in problem.model.friction])
        self.u0 = np.array([c.u0 for c in problem.model.friction])
        self.eps_diag = np.repeat(problem.eps, self.H)

    # unknowns: Cx (m+1, nx) then Cw (m+1, nc), flattened
    def split(self, y):
        return y[: self.nq * self.nx].reshape(self.nq, self.nx), y[self.nq * self.nx :].reshape(
            self.nq, self.nc
        )

    def initial(self, x0, s0, horizon):
        eta = (self.xi + 1) / 2 * horizon
        w = self.u0 * (1 - np.exp(-self.kw * self.kn * s0 * eta[:, None]))
        fit = np.linalg.lstsq(self.V, w, rcond=None)[0]
        Cx = np.zeros((self.nq, self.nx))
        Cx[:] = np.linalg.lstsq(self.V, np.tile(x0, (len(eta), 1)), rcond=None)[0]
        return np.concatenate([Cx.ravel(), fit.ravel()])

    def from_history(self, history: WearHistory, horizon: float):
        """Coefficients fitted to a stepping history at the quadrature nodes (x from fresh solves)."""
        eta = (self.xi + 1) / 2 * horizon
        w = history.at(eta)["wear"]
        xs, guess = [], None
        for wk in w:
            sol = solve_problem(self.p.with_wear(clip_wear(wk, self.u0)), guess)
            guess = sol.unknowns
            xs.append(sol.unknowns)
        self._horizon = horizon
        return np.concatenate([np.linalg.lstsq(self.V, np.array(xs), rcond=None)[0].ravel(),
                               np.linalg.lstsq(self.V, w, rcond=None)[0].ravel()])  # fmt: skip

    def evaluate_at(self, y, eta, horizon):
        Cx, Cw = self.split(y)
        V, _ = _basis(self.kind, self.m, np.array([2 * eta / horizon - 1]))
        return V[0] @ Cx, V[0] @ Cw

    def rescale(self, y, horizon_new):
        """Re-fit a solution on a longer horizon: reuse its values at the new nodes (held past its end)."""
        Cx, Cw = self.split(y)
        eta_new = (self.xi + 1) / 2 * horizon_new
        old = self._horizon
        xi_old = np.clip(2 * eta_new / old - 1, -1, 1)
        V_old, _ = _basis(self.kind, self.m, xi_old)
        xs, ws = V_old @ Cx, V_old @ Cw
        beyond = eta_new > old
        ws[beyond] = self.u0 - (self.u0 - ws[beyond]) * np.exp(-(eta_new[beyond, None] - old) * 1e-3 / old)
        ws = np.minimum(ws, self.u0 * 0.999)
        return np.concatenate([np.linalg.lstsq(self.V, xs, rcond=None)[0].ravel(),
                               np.linalg.lstsq(self.V, ws, rcond=None)[0].ravel()])  # fmt: skip

    def residual(self, y, horizon, jacobian=True):
        p, nq, nx, nc, H = self.p, self.nq, self.nx, self.nc, self.H
        Cx, Cw = self.split(y)
        X, W = self.V @ Cx, self.V @ Cw  # values at the quadrature nodes
        dW = self.D @ Cw * (2.0 / horizon)  # d w / d eta
        K = len(self.xi)
        Rx = np.zeros((K, nx))
        Rw = np.zeros((K, nc))
        if jacobian:
            Jxx = np.zeros((K, nx, nx))
            Jxw = np.zeros((K, nx, nc))
            Jwx = np.zeros((K, nc, nx))
            Jww = np.zeros((K, nc, nc))
        phi, psi = p.basis.synthesis, p.basis.analysis
        Ns = phi.shape[0]
        lam, Xs, st = np.empty(Ns), np.empty(Ns), np.empty(Ns, dtype=np.int8)
        dlam, dsu = np.empty(Ns), np.empty(Ns)
        for k in range(K):
            wk = clip_wear(W[k], self.u0)
            fn = np.maximum(self.kn * (self.u0 - W[k]), 0.0)
            q = p.with_wear(wk)
            R, J, *_ = q.evaluate(X[k], jacobian=jacobian)
            Rx[k] = R
            lu = q.F - q.Z @ X[k] + self.eps_diag * X[k]
            for c in range(nc):
                u = phi @ lu[c * H : (c + 1) * H]
                s, ds_dL = dlft.friction_sensitivity(u, q.limits[c], q.eps[c], p.basis.half_wave,
                                                     lam, Xs, st, dlam, dsu)  # fmt: skip
                Rw[k, c] = dW[k, c] - self.kw * fn[c] * s
                if jacobian:
                    dL_dw = -self.mu[c] * self.kn[c] if fn[c] > 0 else 0.0
                    dfn_dw = -self.kn[c] if fn[c] > 0 else 0.0
                    Jxw[k, c * H : (c + 1) * H, c] = (psi @ dlam) * dL_dw
                    # d s / d x = (d lambda_u / d x)^T Phi^T ds/du, lambda_u = F + (E - Z) x
                    ds_dlu = phi.T @ dsu
                    dlu_dx = -q.Z[c * H : (c + 1) * H, :].copy()
                    dlu_dx[:, c * H : (c + 1) * H] += q.eps[c] * np.eye(H)
                    Jwx[k, c] = -self.kw * fn[c] * (ds_dlu @ dlu_dx)
                    Jww[k, c, c] = -self.kw * (dfn_dw * s + fn[c] * ds_dL * dL_dw)
            if jacobian:
                Jxx[k] = J
        wV = self.wq[:, None] * self.V  # (K, m+1) quadrature-weighted test functions
        # dynamics: Galerkin on all m+1 test functions; wear: initial condition + m test functions
        G = np.concatenate([(wV.T @ Rx).ravel(), (self.V0 @ Cw).ravel(),
                            (wV[:, :-1].T @ Rw).ravel()])  # fmt: skip
        if not jacobian:
            return G, None
        n = y.size
        Jac = np.zeros((n, n))
        # rows: dyn (q, i) ; cols: Cx (r, j) -> sum_k wV[k,q] V[k,r] Jxx[k,i,j]
        Jac[: nq * nx, : nq * nx] = np.einsum("kq,kr,kij->qirj", wV, self.V, Jxx).reshape(nq * nx, nq * nx)
        Jac[: nq * nx, nq * nx :] = np.einsum("kq,kr,kij->qirj", wV, self.V, Jxw).reshape(nq * nx, nq * nc)
        r0 = nq * nx
        Jac[r0 : r0 + nc, nq * nx :] = np.kron(self.V0, np.eye(nc))
        r1 = r0 + nc
        Jac[r1:, : nq * nx] = np.einsum("kq,kr,kij->qirj", wV[:, :-1], self.V, Jwx).reshape(
            (nq - 1) * nc, nq * nx
        )
        dWdC = self.D * (2.0 / horizon)
        Jww_full = np.einsum("kq,kr,kij->qirj", wV[:, :-1], self.V, Jww) + np.einsum(
            "kq,kr,ij->qirj", wV[:, :-1], dWdC, np.eye(nc)
        )
        Jac[r1:, nq * nx :] = Jww_full.reshape((nq - 1) * nc, nq * nc)
        return G, Jac

    @property
    def V0(self):
        return _basis(self.kind, self.m, np.array([-1.0]))[0]  # basis at eta = 0, shape (1, m+1)

    def solve(self, y, horizon, tol, max_iter):
        self._horizon = horizon
        scale = max(self.p.residual_scale(), 1e-300)
        wscale = float(np.max(self.u0)) / horizon
        weights = np.concatenate([np.full(self.nq * self.nx, 1 / scale), np.full(self.nc, 1 / self.u0.max()),
                                  np.full((self.nq - 1) * self.nc, 1 / wscale)])  # fmt: skip
        G, Jac = self.residual(y, horizon)
        r = np.abs(G * weights).max()
        its = 0
        for its in range(1, max_iter + 1):
            if r <= tol:
                return y, True, its - 1, r
            try:
                dy = np.linalg.lstsq(Jac * weights[:, None], -G * weights, rcond=None)[0]
            except np.linalg.LinAlgError:
                return y, False, its, r
            step = 1.0
            for _ in range(20):
                yt = y + step * dy
                Gt, Jt = self.residual(yt, horizon)
                rt = np.abs(Gt * weights).max()
                if rt < r or step < 1e-3:
                    break
                step *= 0.5
            y, G, Jac, r = yt, Gt, Jt, rt
        return y, r <= tol, its, r
