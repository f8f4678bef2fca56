"""Polynomial slow-time method for an interface (paper eq. 25-29): one nonlinear solve over the wear period.

The worn depth of every pair is a polynomial of degree ``m`` in the cycle
count over ``[0, cycles]``, in the Legendre basis of ``tau = 2 N / cycles - 1``
(the basis the 2-DOF slow-time work found best for several contacts,
``fretwear.wear.polynomial``):

    w_i(N) = sum_r a_ri P_r(tau)                                    (eq. 25)

Archard's law ``dw_i/dN = K_w int p_i ds_i`` (eq. 15) is projected on the first
``m`` Legendre polynomials with the Gauss-Legendre rule of ``2 m + 2`` nodes
``tau_k`` (Galerkin), and ``w_i(0)`` is the initial depth: ``(m + 1) nc``
equations for the ``(m + 1) nc`` coefficients, solved together by Newton's
method over the whole period.

The harmonics of the contact coordinates (eq. 26-29) are eliminated: at each
node the periodic DLFT equations (eq. 12) are solved exactly for the node's
worn depths (warm-started from the previous iterate at that node), so the
Archard rates at the nodes are functions of the wear coefficients alone. The
Jacobian of a node's rates with respect to its depths is the total derivative
along the solution: ``dx/dg = -J^-1 dR/dg`` on the node's stick/slip pattern
(exact, the residual being piecewise linear), then central differences of the
pairs' ``int p ds`` along ``(dx/dg_j, e_j)`` (compiled: :func:`rate_sensitivity`).
The harmonics' slow-time polynomials (degree ``m``) are the Gauss-weighted
least-squares fit of the node solutions; they warm-start the solves at the
records.

Pairs that stick all period keep a reference slip variable (see
``fretwear.interface.contact``): the nodes are solved in increasing ``N``,
each with the reference of the previous node's solution at the start of its
period, as the slow-time stepping of ``fretwear.interface.wear`` does.

Convergence is judged on the Galerkin residual relative to the largest wear
over the period at the first node's rates; failure is reported in
``converged``, ``message`` and ``info["residual"]``, never hidden. The fit is
checked against its own Archard law at the records: ``info["wear_defect"]`` is
the largest difference between the polynomial wear and the trapezoidal
integral of the recorded rates, relative to the largest wear.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from .contact import evaluate, jacobian, slip_work
from .history import InterfaceWearHistory
from .periodic import InterfaceProblem, solve_interface

__all__ = ["rate_sensitivity", "wear_polynomial_interface", "DEFAULT_DEGREE"]

#: default polynomial degree in slow time
DEFAULT_DEGREE = 6
# ``evaluate``'s Jacobian flag as a NumPy scalar: a Python literal would make Numba compile one more
# specialisation of it per literal value
_NO_JACOBIAN = np.bool_(False)


@njit(cache=True, nogil=True)
def rate_sensitivity(x, Z, F, eps, gap, mu, xref, Phi, Psi, area, A, h, ps, dps):
    """Archard integrand ``int p ds`` per pair (Pa m) and its total derivative in the gaps.

    Parameters
    ----------
    x : (2 nc H,) converged harmonics of the contact coordinates (m).
    Z, F, eps, gap, mu, xref, Phi, Psi : as :func:`~fretwear.interface.contact.evaluate`.
    area : (nc,) tributary areas. A : (nc, 2H, 2H) Jacobian blocks at ``x``.
    h : float, gap increment of the central differences (m).
    ps : (nc,) out. dps : (nc, nc) out, ``d ps_i / d g_j`` (Pa).
    """
    n = x.shape[0]
    nc = gap.shape[0]
    Ns, H = Phi.shape
    J = np.empty((n, n))
    jacobian(Z, eps, A, J)
    rhs = np.zeros((n, nc))
    for j in range(nc):  # -dR/dg_j: the gap shifts lambda_u,N by -eps_N g at every sample
        for a in range(2 * H):
            rhs[2 * j * H + a, j] = eps[2 * j + 1] * A[j, a, H]
    dx = np.linalg.solve(J, rhs)
    R = np.empty(n)
    Ab = np.empty((nc, 2 * H, 2 * H))
    lamT, lamN, X = np.empty((nc, Ns)), np.empty((nc, Ns)), np.empty((nc, Ns))
    state = np.empty((nc, Ns), dtype=np.int8)
    evaluate(x, Z, F, eps, gap, mu, xref, Phi, Psi, _NO_JACOBIAN, R, Ab, lamT, lamN, X, state)
    ps[:] = slip_work(X, lamN, state)[1] / area
    g = gap.copy()
    for j in range(nc):
        g[j] = gap[j] + h
        evaluate(
            x + h * dx[:, j], Z, F, eps, g, mu, xref, Phi, Psi, _NO_JACOBIAN, R, Ab, lamT, lamN, X, state
        )
        up = slip_work(X, lamN, state)[1]
        g[j] = gap[j] - h
        evaluate(
            x - h * dx[:, j], Z, F, eps, g, mu, xref, Phi, Psi, _NO_JACOBIAN, R, Ab, lamT, lamN, X, state
        )
        down = slip_work(X, lamN, state)[1]
        g[j] = gap[j]
        dps[:, j] = (up - down) / (2 * h * area)


def _legendre(degree: int, tau: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Legendre polynomials ``P_0..P_m`` and their ``d/dtau`` at ``tau``, shape (len(tau), m + 1)."""
    leg = np.polynomial.legendre
    V = leg.legvander(tau, degree)
    D = V[:, :-1] @ leg.legder(np.eye(degree + 1))
    return V, D


class _Nodes:
    """Periodic solves at the Gauss nodes for given wear coefficients, with their rate sensitivities."""

    def __init__(self, problem: InterfaceProblem, kw: float, N: np.ndarray, tol: float, h: float):
        self.problem, self.kw, self.N, self.tol, self.h = problem, kw, N, tol, h
        self.x = [None] * len(N)
        self.solves = 0

    def __call__(self, w: np.ndarray):
        """Rates (K, nc) (m/cycle), their derivatives (K, nc, nc) in the depths, the solutions; None if a
        solve fails (with the failed solution)."""
        p = self.problem
        b = p.basis
        area = p.condensation.model.pairs.area
        K, nc = w.shape
        rate, drate, sols = np.empty((K, nc)), np.empty((K, nc, nc)), []
        xref = p.xref
        for k in range(K):
            prob = p.with_wear(np.maximum(w[k], 0.0), xref=xref)
            sol = solve_interface(
                prob, self.x[k] if self.x[k] is not None else (sols[-1].unknowns if sols else None), self.tol
            )
            self.solves += 1
            if not sol.converged:
                return None, None, sol
            self.x[k] = sol.unknowns
            A = prob.evaluate(sol.unknowns, jacobian=True)[1]
            ps, dps = np.empty(nc), np.empty((nc, nc))
            rate_sensitivity(sol.unknowns, prob.Z, prob.F, prob.eps, prob.gap, prob.mu, prob.xref,
                             b.synthesis, b.analysis, area, A, self.h, ps, dps)  # fmt: skip
            rate[k] = self.kw * ps
            drate[k] = self.kw * dps * (w[k] > 0)[None, :]  # the gap is max(w, 0)
            sols.append(sol)
            xref = sol.slip_variable[:, 0]
        return rate, drate, sols


def wear_polynomial_interface(
    problem: InterfaceProblem,
    kw: float,
    cycles: float,
    degree: int = DEFAULT_DEGREE,
    outputs: int = 21,
    tol: float = 1e-8,
    max_iter: int = 30,
    solve_tol: float = 1e-10,
):
    """Wear history of an interface by the polynomial slow-time method (see the module docstring).

    Parameters
    ----------
    problem : InterfaceProblem
        The interface at its frequency (its ``wear`` is the initial profile, m).
    kw : float
        Archard coefficient ``K_w`` (1/Pa), > 0.
    cycles : float
        Wear period ``[0, cycles]`` covered by the polynomials, > 0.
    degree : int
        Polynomial degree ``m`` in [1, 12]; ``2 m + 2`` Gauss nodes.
    outputs : int
        Records evenly spread over ``[0, cycles]`` (>= 2), each an exact periodic
        solve at the polynomial's wear, warm-started by the harmonics' polynomials.
    tol : float
        Newton tolerance on the Galerkin residual, relative to the largest depth, in (0, 1).
    max_iter : int
        Newton iterations.
    solve_tol : float
        Relative residual tolerance of the periodic solves.

    Returns
    -------
    InterfaceWearHistory
        ``method = "polynomial"``; ``info``: ``degree``, ``nodes``, ``iterations``,
        ``residual`` (Galerkin, relative), ``wear_defect``, ``coefficients``
        (wear, (m + 1, nc), m) and ``harmonic_coefficients`` ((m + 1, 2 nc H), m).
    """
    if not (np.isfinite(kw) and kw > 0):
        raise ValueError(f"kw must be a finite Archard coefficient > 0 1/Pa, got {kw!r}")
    if not (np.isfinite(cycles) and cycles > 0):
        raise ValueError(f"cycles must be finite and > 0, got {cycles!r}")
    if not (isinstance(degree, (int, np.integer)) and 1 <= degree <= 12):
        raise ValueError(f"degree must be an integer in [1, 12], got {degree!r}")
    if not (isinstance(outputs, (int, np.integer)) and outputs >= 2):
        raise ValueError(f"outputs must be an integer >= 2, got {outputs!r}")
    if not 0 < tol < 1:
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    contact = problem.condensation.model.pairs
    nc, m = contact.count, degree
    hist = InterfaceWearHistory(
        position=contact.position, area=contact.area, kw=float(kw), omega=problem.omega, method="polynomial"
    )
    tau, wq = np.polynomial.legendre.leggauss(2 * m + 2)
    V, D = _legendre(m, tau)
    V0 = _legendre(m, np.array([-1.0]))[0][0]
    N_nodes = (tau + 1) * cycles / 2
    w0 = problem.wear.copy()
    scale_x = max(float(np.abs(problem.start()).max()), 1e-300)
    nodes = _Nodes(problem, kw, N_nodes, solve_tol, 1e-7 * scale_x)
    first = solve_interface(problem, None, solve_tol)
    hist.solves += 1
    if not first.converged:
        hist.record(0.0, w0, first)
        hist.converged, hist.message = False, f"periodic solve failed at N = 0: {first.message}"
        return hist.finish()
    # start: Heun's method along the nodes, in substeps that raise the largest depth by at most 25 %
    r0 = kw * first.pressure_slip
    w_scale = max(float(r0.max()) * cycles, 1e-300)
    w_nodes = np.empty((len(tau), nc))
    w, N, r, guess = w0, 0.0, r0, first.unknowns
    for k, Nk in enumerate(N_nodes):
        while N < Nk:
            grow = 0.25 * float(np.abs(w).max()) / max(float(r.max()), 1e-300)
            dN = Nk - N if (N == 0.0 or not 0 < grow < Nk - N) else grow
            s = solve_interface(problem.with_wear(np.maximum(w + dN * r, 0.0)), guess, solve_tol)
            corr = w + 0.5 * dN * (r + kw * s.pressure_slip)
            s = solve_interface(problem.with_wear(np.maximum(corr, 0.0)), s.unknowns, solve_tol)
            hist.solves += 2
            if not s.converged:
                hist.record(0.0, w0, first)
                hist.converged, hist.message = (
                    False,
                    f"periodic solve failed at N = {N + dN:.6g}: {s.message}",
                )
                return hist.finish()
            w, N, r, guess = corr, N + dN if N + dN < Nk else Nk, kw * s.pressure_slip, s.unknowns
        w_nodes[k] = w
        nodes.x[k] = guess
    sw = np.sqrt(wq)[:, None]
    rows = np.vstack([V * sw, 10 * V0[None]])
    a = np.linalg.lstsq(rows, np.vstack([w_nodes * sw, 10 * w0[None]]), rcond=None)[0]

    def galerkin(a):
        rate, drate, sols = nodes(V @ a)
        if rate is None:
            return None, None, sols
        G = np.vstack([V0 @ a - w0, (V[:, :m] * wq[:, None]).T @ (D @ a - 0.5 * cycles * rate)]) / w_scale
        J = np.zeros((m + 1, nc, m + 1, nc))
        J[0] = np.einsum("r,ij->irj", V0, np.eye(nc))
        J[1:] = np.einsum("k,kq,kr,ij->qirj", wq, V[:, :m], D, np.eye(nc))
        J[1:] -= 0.5 * cycles * np.einsum("k,kq,kr,kij->qirj", wq, V[:, :m], V, drate)
        return G.ravel(), J.reshape((m + 1) * nc, (m + 1) * nc) / w_scale, sols

    G, J, sols = galerkin(a)
    it, res, ok, message = 0, np.inf, False, ""
    while G is not None:
        res = float(np.abs(G).max())
        if res <= tol:
            ok = True
            break
        if it >= max_iter:
            message = f"Newton did not converge in {max_iter} iterations (Galerkin residual {res:.2e})"
            break
        it += 1
        try:
            d = np.linalg.solve(J, -G).reshape(a.shape)
        except np.linalg.LinAlgError:
            message = f"singular Galerkin Jacobian (Galerkin residual {res:.2e})"
            break
        step = 1.0
        while step > 1e-4:
            Gt, Jt, st = galerkin(a + step * d)
            if Gt is not None and np.abs(Gt).max() < (1 - 1e-4 * step) * res:
                break
            step *= 0.5
        else:
            message = f"line search failed (Galerkin residual {res:.2e})"
            break
        a, G, J, sols = a + step * d, Gt, Jt, st
    if G is None:
        message = f"periodic solve failed at a Gauss node: {sols.message}"
    hist.solves += nodes.solves
    X = np.array(nodes.x if all(x is not None for x in nodes.x) else [first.unknowns] * len(tau))
    Cx = np.linalg.lstsq(V * sw, X * sw, rcond=None)[0]  # harmonics' polynomials (eq. 26-27)
    # records: exact periodic solves at the polynomial's wear
    N = np.linspace(0.0, cycles, outputs)
    Vr = _legendre(m, 2 * N / cycles - 1)[0]
    W = Vr @ a
    xref = problem.xref
    for k, Nk in enumerate(N):
        wk = np.maximum(W[k], 0.0)
        sol = solve_interface(problem.with_wear(wk, xref=xref), Vr[k] @ Cx, solve_tol)
        hist.solves += 1
        if not sol.converged:
            ok, message = False, f"periodic solve failed at the record N = {Nk:.6g}: {sol.message}"
            break
        hist.record(Nk, wk, sol)
        xref = sol.slip_variable[:, 0]
    hist.finish()
    if len(hist.cycles) == outputs:
        integral = np.concatenate(
            [w0[None], w0 + np.cumsum(0.5 * np.diff(N)[:, None] * (hist.wear_rate[1:] + hist.wear_rate[:-1]),
                                      axis=0)]
        )  # fmt: skip
        defect = float(np.abs(integral - hist.wear).max() / max(np.abs(hist.wear).max(), 1e-300))
    else:
        defect = np.inf
    hist.converged, hist.message = ok, message
    hist.info = {"degree": m, "nodes": len(tau), "iterations": it, "residual": res, "wear_defect": defect,
                 "coefficients": a, "harmonic_coefficients": Cx}  # fmt: skip
    return hist
