"""The periodic-solve strategy, written once for every contact law and handed its steps.

A periodic solve on a DLFT residual (1-D friction and unilateral contacts,
``fretwear.hbm.periodic``; coupled contact pairs,
``fretwear.interface.periodic``) goes the same way whatever the law:

1. from a ``guess`` (a neighbour's solution): Newton's method, a short budget
   (:data:`GUESS_STEPS`); if it fails, the global Newton homotopy from Newton's
   best iterate, which crosses few pieces from a near point;
2. else, or if those fail: Newton from the law's own start (the stuck
   solution, the quasi-static state), :data:`START_STEPS` iterations;
3. then the exact load walk from a state known to be exact, which cannot fail
   on the way.

:func:`solve` runs these steps; each law hands its own (:class:`Steps`). The
compiled sweep (``fretwear.hbm.compiled_sweep``) runs the same strategy
inside one compiled call.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from .newton import BUDGET, LINE_SEARCH, NON_FINITE, SINGULAR

__all__ = ["NewtonResult", "Steps", "solve", "newton_message", "GUESS_STEPS", "START_STEPS"]

#: Newton iterations from a guess before the Newton homotopy takes over
GUESS_STEPS = 12

#: Newton iterations from the law's start before the load walk takes over
START_STEPS = 16


@dataclass
class NewtonResult:
    """Outcome of a solve on a DLFT residual: unknowns, status, iterations (or pieces), relative residual."""

    x: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str = ""


def newton_message(code: int, max_iter: int) -> str:
    """The message of a compiled Newton loop's return ``code`` (``fretwear.hbm.newton``)."""
    return {
        NON_FINITE: "non-finite Newton step",
        LINE_SEARCH: "line search failed",
        BUDGET: f"no convergence in {max_iter} iterations",
        SINGULAR: "singular Jacobian",
    }.get(code, "")


@dataclass(frozen=True)
class Steps:
    """The steps of one problem that :func:`solve` calls.

    Attributes
    ----------
    size : int
        Number of unknowns.
    newton : callable
        ``newton(x0, tol, max_iter) -> NewtonResult``.
    homotopy : callable
        ``homotopy(x0, tol) -> NewtonResult``: the global Newton homotopy from ``x0``.
    start : callable
        ``start() -> x``: the law's starting point (exact at some load).
    load_walk : callable
        ``load_walk(tol, max_iter) -> NewtonResult``: the exact walk in the load.
    guess_steps, start_steps : int
        Newton iterations at most from the guess and from the start (and at
        most ``max_iter``). Short budgets suit a law whose walk is cheap per
        piece; a law with costly pieces lets Newton run longer.
    homotopy_path : str
        The path of a solution the homotopy found (another homotopy than
        Newton's names itself, e.g. the normal-load walk of a wear history).
    """

    size: int
    newton: Callable[[np.ndarray, float, int], NewtonResult]
    homotopy: Callable[[np.ndarray, float], NewtonResult]
    start: Callable[[], np.ndarray]
    load_walk: Callable[[float, int], NewtonResult]
    guess_steps: int = GUESS_STEPS
    start_steps: int = START_STEPS
    homotopy_path: str = "dlft-newton-homotopy"


def solve(steps: Steps, guess: np.ndarray | None, tol: float, max_iter: int) -> tuple[NewtonResult, str]:
    """Solve by the strategy of the module docstring; returns the result and its path.

    The path is ``"dlft"`` (Newton), ``steps.homotopy_path`` (the homotopy from
    the guess) or ``"dlft-homotopy"`` (the load walk). ``iterations`` counts every
    Newton iteration and walk piece spent.
    """
    spent = 0
    if guess is not None:
        guess = np.asarray(guess, dtype=float)
        if guess.shape != (steps.size,):
            raise ValueError(f"guess must have shape ({steps.size},), got {guess.shape}")
        res = steps.newton(guess, tol, min(max_iter, steps.guess_steps))
        if res.converged:
            return res, "dlft"
        spent = res.iterations
        res = steps.homotopy(res.x, tol)  # from Newton's best iterate
        res.iterations += spent
        if res.converged:
            return res, steps.homotopy_path
        spent = res.iterations
    res, path = steps.newton(steps.start(), tol, min(max_iter, steps.start_steps)), "dlft"
    if not res.converged:
        res, path = steps.load_walk(tol, max_iter), "dlft-homotopy"
    res.iterations += spent
    return res, path
