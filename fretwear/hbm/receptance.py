"""Jenkins contacts in the receptance form: ``U_r = s u_lin - G_r Lambda(U_r)``, for dependent contacts.

Condensed on its contact coordinates, a structure reads ``U_r = s u_lin -
G_r Lambda`` (``fretwear.hbm.condensation``, ``s`` the load factor). The
DLFT residual ``Z_r U_r + Lambda - F_r`` needs ``Z_r = G_r^{-1}``, which does
not exist when the contact coordinates are dependent: around a closed ring
(the shroud of a bladed disk) the relative displacements sum to zero, and a
force equal at every contact of the ring moves nothing. A Jenkins contact's
force is a function of its own relative displacement (the return map of
``fretwear.hbm.dlft``), so the residual can stay in the receptance form,

    R(U_r) = k_t (U_r - s u_lin + G_r Lambda(U_r))      (N),

whose Jacobian ``k_t (I + G_r k_t A)`` (``A`` the blocks of the march) is
regular wherever the contact states are: no inverse of ``G_r`` is needed.
The rows are scaled by each contact's ``k_t`` so that the residual is a force,
judged like every other one (:meth:`fretwear.hbm.problem.Problem.evaluate`).

:func:`steps` hands this law to the periodic-solve strategy
(``fretwear.hbm.strategy``): Newton (non-monotone, then backtracking), a
continuation in the homotopy parameter from Newton's best iterate, and the
continuation in the load factor from zero, where every contact sticks.
"""

from __future__ import annotations

from functools import partial
from typing import TYPE_CHECKING

import numpy as np

from . import strategy
from .strategy import NewtonResult

if TYPE_CHECKING:
    from .problem import Problem

__all__ = ["newton", "homotopy", "load_walk", "steps"]

#: smallest load or homotopy step of a continuation before it gives up
MIN_STEP = 1e-6


def _norm(v: np.ndarray) -> float:
    return float(np.abs(v).max(initial=0.0))


def _newton(residual, x0: np.ndarray, atol: float, max_iter: int) -> tuple[np.ndarray, bool, int, float, str]:
    """Newton on ``residual(x, jacobian) -> (R, J)``: full steps while the residual stays within 1e3 of the
    best for half the budget (the pieces settle), then backtracking from the best iterate."""
    x = np.array(x0, dtype=float)
    R, J = residual(x, True)
    best_x, best_r = x, _norm(R)
    for it in range(1, max_iter + 1):
        r = _norm(R)
        if not np.isfinite(r):
            return best_x, False, it, best_r, "non-finite Newton step"
        if r <= atol:
            return x, True, it - 1, r, ""
        try:
            dx = np.linalg.solve(J, -R)
        except np.linalg.LinAlgError:
            return best_x, False, it, best_r, "singular Jacobian"
        free = it <= max_iter // 2
        t = 1.0
        while True:
            xt = x + t * dx
            Rt, _ = residual(xt, False)
            rt = _norm(Rt)
            if rt < (1 - 1e-4 * t) * r or (free and rt <= 1e3 * best_r):
                break
            t *= 0.5
            if t < 1e-10:
                return best_x, False, it, best_r, "line search failed"
        x = xt
        R, J = residual(x, True)
        if _norm(R) < best_r:
            best_x, best_r = x, _norm(R)
    if _norm(R) <= atol:
        return x, True, max_iter, _norm(R), ""
    return best_x, False, max_iter, best_r, f"no convergence in {max_iter} iterations"


def _result(problem: Problem, out) -> NewtonResult:
    x, ok, it, r, msg = out
    return NewtonResult(x, ok, it, r / problem.residual_scale(), msg)


def newton(problem: Problem, x0: np.ndarray, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Newton's method on the receptance residual; converged when ``max |R| <= tol * scale`` (N)."""
    residual = lambda x, jac: problem.evaluate(x, jac)[:2]  # noqa: E731
    return _result(problem, _newton(residual, x0, tol * problem.residual_scale(), max_iter))


def _continue(residual_at, x0: np.ndarray, atol: float, max_iter: int) -> tuple[np.ndarray, bool, int, str]:
    """Follow ``residual_at(p)(x, jacobian) = 0`` from ``p = 0`` (solved by ``x0``) to ``p = 1``.

    Newton at each step from a secant prediction; a step that fails is halved
    (down to :data:`MIN_STEP`), one that converges fast is doubled. Returns the
    unknowns at the last parameter reached, whether it is 1, the Newton
    iterations spent and a message.
    """
    p, dp, x, x_prev, p_prev, spent = 0.0, 0.25, np.array(x0, dtype=float), None, None, 0
    while p < 1.0:
        q = min(1.0, p + dp)
        guess = x if x_prev is None else x + (x - x_prev) * (q - p) / (p - p_prev)
        y, ok, it, _, _ = _newton(residual_at(q), guess, atol, 12)
        spent += it
        if ok:
            x_prev, p_prev, x, p = x, p, y, q
            dp = 2 * dp if it <= 4 else dp
        else:
            dp *= 0.5
            if dp < MIN_STEP or spent > 40 * max_iter:
                return x, False, spent, f"continuation stopped at {p:.6g} (step {dp:.2g})"
    return x, True, spent, ""


def load_walk(problem: Problem, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Continuation in the load factor from zero (every contact stuck, ``x = 0``) to the full load."""
    full = problem.force_scale

    def residual_at(s):
        p = problem.at_load(s * full)
        return lambda x, jac: p.evaluate(x, jac)[:2]

    x, ok, spent, msg = _continue(
        residual_at, np.zeros(problem.size), tol * problem.residual_scale(), max_iter
    )
    r = _norm(problem.evaluate(x, False)[0]) / problem.residual_scale()
    return NewtonResult(x, ok, spent, r, msg)


def homotopy(problem: Problem, x0: np.ndarray, tol: float = 1e-10) -> NewtonResult:
    """The Newton homotopy ``R(x) = (1 - sigma) R(x0)`` from ``x0`` to ``sigma = 1``, followed by steps."""
    r0 = problem.evaluate(x0, False)[0]

    def residual_at(sigma):
        def residual(x, jac):
            R, J = problem.evaluate(x, jac)[:2]
            return R - (1 - sigma) * r0, J

        return residual

    x, ok, spent, msg = _continue(residual_at, x0, tol * problem.residual_scale(), 50)
    r = _norm(problem.evaluate(x, False)[0]) / problem.residual_scale()
    return NewtonResult(x, ok, spent, r, msg)


def steps(problem: Problem) -> strategy.Steps:
    """The steps of :func:`fretwear.hbm.strategy.solve` on a problem in the receptance form."""
    return strategy.Steps(
        problem.size, partial(newton, problem), partial(homotopy, problem), lambda: np.zeros(problem.size),
        partial(load_walk, problem), homotopy_path="receptance-homotopy",
    )  # fmt: skip
