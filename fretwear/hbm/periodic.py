"""Periodic response at one frequency: harmonic balance with DLFT contact forces.

:func:`solve_periodic` is the single-frequency solver (paper sections 1.3-1.5).
It computes only the effects present:

1. contacts with zero normal load are open and left out of the nonlinear system;
2. with no active contact left, the linear open solution is exact (path ``"linear-open"``);
3. with friction contacts only, the exact linear *stuck* solution is returned when
   it keeps every contact strictly inside its friction cone over the whole
   period (path ``"linear-stuck"``), with no nonlinear solve;
4. otherwise Newton's method with backtracking line search on the DLFT residual,
   from a guess or from the stuck solution (path ``"dlft"``); if that fails, a
   continuation in the load factor from the largest load that still sticks
   (path ``"dlft-homotopy"``), which is reliable at any harmonic count.

The problem itself (condensation, DFT matrices, penalties, residual) is
:class:`fretwear.hbm.problem.Problem`; :func:`walk` follows its exact
piecewise-linear solution curves (load continuation, Newton homotopy, the
normal-load walk of wear). ``solve_problem()`` runs this logic in Python
around the compiled loops of ``fretwear.hbm.kernels``; :func:`solve_periodic`
runs it in one compiled call (``fretwear.hbm.compiled_sweep``, the sweep's
kernel at one frequency), with the same answers.
"""

from __future__ import annotations

from functools import partial

import numpy as np

from ..model import Model
from . import compiled_sweep, dlft, receptance, strategy
from .kernels import LOAD, NEWTON, newton_kernel, walk_kernel
from .problem import Problem
from .solution import PeriodicSolution
from .strategy import NewtonResult, newton_message

__all__ = [
    "Problem",
    "NewtonResult",
    "solve_periodic",
    "solve_problem",
    "steps",
    "newton",
    "load_homotopy",
    "newton_homotopy",
    "follow_normal_load",
    "walk",
    "polish",
    "LOAD",
    "NEWTON",
]


def _norm(v: np.ndarray) -> float:
    return float(np.abs(v).max(initial=0.0))


def newton(problem: Problem, x0: np.ndarray, tol: float = 1e-10, max_iter: int = 50) -> NewtonResult:
    """Newton's method on the DLFT residual, non-monotone, with a damped fallback.

    Converged when ``max |R| <= tol * scale`` with ``scale`` the largest
    external or friction force (N). The residual is piecewise linear: once the
    stick/slip pattern is right, a full Newton step lands on the solution. On
    the way, full steps must be allowed to raise the residual while the pattern
    settles (a monotone line search stalls at the kinks), so full steps are
    taken while the residual stays within a factor 1000 of the best one seen,
    for half the budget; then a backtracking line search restarts from the best
    iterate. The loop is compiled (:func:`fretwear.hbm.kernels.newton_kernel`).
    """
    scale = problem.residual_scale()
    b = problem.basis
    x, ok, it, r, code = newton_kernel(
        np.array(x0, dtype=float), problem.Z, problem.F, problem.eps, problem.kinds, problem.limits,
        b.synthesis, b.analysis, b.half_wave, tol * scale, max_iter,
    )  # fmt: skip
    return NewtonResult(x, bool(ok), int(it), float(r / scale), newton_message(code, max_iter))


def polish(problem: Problem, x: np.ndarray) -> np.ndarray:
    """One full Newton step from ``x``, kept if it does not raise the residual.

    A walk ends on the last piece of its path, exact up to the round-off
    gathered over the pieces; on a piecewise-linear residual one full step
    from there lands on the solution of that piece to machine precision.
    """
    R, J, *_ = problem.evaluate(x)
    try:
        xt = x - np.linalg.solve(J, R)
    except np.linalg.LinAlgError:
        return x
    Rt = problem.evaluate(xt, jacobian=False)[0]
    return xt if np.abs(Rt).max() <= np.abs(R).max() else x


def walk(problem: Problem, x, p, p_end, mode, F, r0, max_pieces, record: int = 0):
    """Follow a piecewise-linear solution curve of the DLFT equations (compiled walk).

    Each step goes along the null vector of ``[dR/dx, dR/dp]`` to the next
    state change, computed exactly by :func:`fretwear.hbm.dlft.boundary_distance`,
    and just past it. The tangent keeps the sign of ``det [J dR/dp; t]``, the
    invariant of a regular curve across the kinks (a dot product with the
    previous tangent is not); a singular augmented matrix ends the walk where
    it started (no piece). Returns ``(x, p, pieces, arrived)``, and with
    ``record > 0`` also the path's breakpoints ``(x_k, p_k, slid_k)`` (at most ``record``).
    """
    b = problem.basis
    x = np.array(x, dtype=float)
    rec = np.empty((record, x.size)), np.empty(record), np.empty(record)
    x, p, pieces, arrived, k = walk_kernel(
        x, float(p), float(p_end), mode, problem.Z, F, r0, problem.eps, problem.kinds, problem.limits,
        b.synthesis, b.analysis, b.half_wave, max_pieces, *rec,
    )  # fmt: skip
    out = (x, p, int(pieces), bool(arrived))
    return out + ((rec[0][:k], rec[1][:k], rec[2][:k]) if record else ())


def load_homotopy(
    problem: Problem, tol: float = 1e-10, max_iter: int = 50, max_pieces: int = 100_000
) -> NewtonResult:
    """Solve ``problem`` by exact piecewise-linear continuation in the load factor.

    With the forces scaled by ``s``, the DLFT residual ``R(x, s)`` is piecewise
    linear in ``(x, s)`` jointly (linear while no sample changes state), so its
    solution curve is a polygon, followed piece by piece by :func:`walk`: no
    Newton iteration can fail on the way, and the cost is one linear solve per
    piece crossed.

    For friction-only problems the curve starts at the largest load factor for
    which the stuck solution is exact; otherwise at zero load.
    """
    full = problem.force_scale
    if np.all(problem.kinds == dlft.FRICTION):
        s = full * min(1.0, 1.0 / problem.stick_ratio())
        x = problem.at_load(s).stuck_solution()
    else:
        s = 0.0
        start = newton(problem.at_load(s), problem.stuck_guess(), tol, max_iter)
        if not start.converged:
            return NewtonResult(start.x, False, start.iterations, start.residual, "no solution at zero load")
        x = start.x
    x, s, pieces, _ = walk(problem, x, s, full, LOAD, problem.F0, np.zeros(0), max_pieces)
    final = newton(problem, polish(problem, x), tol, max_iter)
    final.iterations += pieces + 1
    if not final.converged:
        final.message = (
            f"load continuation ended at load factor {s / full:.6g} after {pieces} pieces; " + final.message
        )
    return final


def follow_normal_load(problem: Problem, x: np.ndarray, target: Problem, tol: float = 1e-10) -> NewtonResult:
    """Solve ``target`` from a solution ``x`` of ``problem`` that differs only by the normal load.

    With one friction contact and no unilateral contact, the DLFT equations are
    positively homogeneous in the forces and the friction limit: the response
    at limit ``L2`` equals ``L2 / L1`` times the response at limit ``L1`` under the
    forces scaled by ``L1 / L2``. The exact load walk from force scale 1 to
    ``L1 / L2`` therefore follows the physical path between the two normal loads
    (as wear relaxes the load) crossing only the stick/slip changes on the way.
    """
    if not (problem.n_active == target.n_active == 1 and problem.kinds[0] != dlft.UNILATERAL
            and problem.basis == target.basis):  # fmt: skip
        raise ValueError("follow_normal_load needs one active friction or Jenkins contact and the same basis")
    ratio = target.limits[0] / problem.limits[0]
    x_end, s, pieces, arrived = walk(problem, x, 1.0, 1.0 / ratio, LOAD, problem.F0 * problem.force_scale,
                                      np.zeros(0), 100_000)  # fmt: skip
    res = newton(target, ratio * x_end, tol, 20)
    res.iterations += pieces
    if not res.converged:
        res.message = f"normal-load walk ended at load ratio {s:.6g} ({pieces} pieces); " + res.message
    return res


def newton_homotopy(
    problem: Problem, x0: np.ndarray, tol: float = 1e-10, max_pieces: int = 500
) -> NewtonResult:
    """Solve ``problem`` from a nearby point ``x0`` by the global Newton homotopy.

    ``R(x) = (1 - sigma) R(x0)`` is piecewise linear in ``(x, sigma)``; its curve
    from ``(x0, 0)`` to ``sigma = 1`` is followed exactly by :func:`walk`. From
    the solution at a neighbouring frequency this crosses few pieces, and it
    does not fail where Newton's method jumps between stick/slip patterns.
    """
    r0 = problem.evaluate(x0, jacobian=False)[0]
    x, sigma, pieces, _ = walk(problem, x0, 0.0, 1.0, NEWTON, problem.F, r0, max_pieces)
    final = newton(problem, polish(problem, x), tol, 20)
    final.iterations += pieces + 1
    if not final.converged:
        final.message = f"Newton homotopy ended at sigma {sigma:.6g} after {pieces} pieces; " + final.message
    return final


def solve_periodic(
    model: Model,
    omega: float,
    harmonics: int = 7,
    *,
    samples: int | None = None,
    wear=None,
    eps=None,
    half_wave: bool | None = None,
    guess: np.ndarray | None = None,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> PeriodicSolution:
    """Periodic response of a model with 1-D contacts at ``omega`` by HBM + DLFT.

    Parameters and result as :func:`fretwear.solve_periodic`, which calls this
    function for such a model. The solve is the logic of ``solve_problem()``,
    compiled: a one-frequency ``fretwear.hbm.compiled_sweep.solve()``.
    """
    settings = dict(harmonics=harmonics, samples=samples, wear=wear, half_wave=half_wave)
    if any(c.kt is not None for c in model.friction):  # solved in x: module text of fretwear.hbm.dlft
        return solve_problem(Problem(model, omega, eps=eps, **settings), guess, tol, max_iter)
    (out,) = compiled_sweep.solve(model, np.array([omega], dtype=float), settings, eps, tol, max_iter, guess)
    return out if isinstance(out, PeriodicSolution) else solve_problem(out, guess, tol, max_iter)


def steps(problem: Problem) -> strategy.Steps:
    """The steps of :func:`fretwear.hbm.strategy.solve` on ``problem``: Newton, the Newton homotopy, the
    stuck solution (friction only) or the stuck guess as the start, the exact load continuation."""
    if problem.form == "receptance":
        return receptance.steps(problem)
    friction_only = bool(np.all(problem.kinds == dlft.FRICTION))
    start = problem.stuck_solution if friction_only else problem.stuck_guess
    return strategy.Steps(problem.size, partial(newton, problem), partial(newton_homotopy, problem), start,
                          partial(load_homotopy, problem))  # fmt: skip


def solve_problem(
    problem: Problem, guess: np.ndarray | None = None, tol: float = 1e-10, max_iter: int = 50
) -> PeriodicSolution:
    """Solve a prepared :class:`Problem`, computing only the effects present.

    Linear paths first (no active contact; exact stuck solution); then the
    strategy of ``fretwear.hbm.strategy`` with this law's :func:`steps`:
    Newton and the Newton homotopy from the ``guess``, Newton from the stuck
    solution, the exact load continuation.
    """
    if problem.n_active == 0:
        return PeriodicSolution.build(problem, None, NewtonResult(np.zeros(0), True, 0, 0.0), "linear-open")
    if np.all(problem.kinds == dlft.FRICTION) and problem.stick_ratio() < 1.0:
        x = problem.stuck_solution()
        return PeriodicSolution.build(problem, x, NewtonResult(x, True, 0, 0.0), "linear-stuck")
    res, path = strategy.solve(steps(problem), guess, tol, max_iter)
    return PeriodicSolution.build(problem, res.x, res, path)
