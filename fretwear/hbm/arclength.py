"""Pseudo-arc-length path following for ``R(x, p) = 0``.

A generic tool of the solver layer: :func:`track` follows the solution curve
from a known solution to a target parameter value, in scaled variables, so
that it passes steep parts and folds alike and never loops forever.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

__all__ = ["TrackResult", "track", "tangent"]

Evaluate = Callable[[np.ndarray, float], tuple[np.ndarray, np.ndarray, np.ndarray]]


@dataclass
class TrackResult:
    """Outcome of :func:`track`."""

    x: np.ndarray
    p: float
    converged: bool
    steps: int
    iterations: int
    message: str = ""
    points: list[tuple[np.ndarray, float]] = field(default_factory=list)


def tangent(J: np.ndarray, dR: np.ndarray, row: np.ndarray, orientation: float) -> tuple[np.ndarray, float]:
    """Unit null vector ``t`` of ``[J dR]`` and the orientation ``sign det [J dR; t]``.

    With ``orientation = 0`` the sign is chosen so that ``row . t > 0`` and
    returned; otherwise ``t`` is oriented to keep the given sign, which is the
    invariant of a regular solution curve across the kinks of a
    piecewise-linear map (a dot product with the previous tangent is not).
    """
    n = J.shape[0]
    aug = np.empty((n + 1, n + 1))
    aug[:n, :n], aug[:n, n], aug[n] = J, dR, row
    rhs = np.zeros(n + 1)
    rhs[n] = 1.0
    t = np.linalg.solve(aug, rhs)
    t /= np.linalg.norm(t)
    aug[n] = t
    sign = np.linalg.slogdet(aug)[0]
    if orientation and sign != orientation:
        t, sign = -t, orientation
    return t, sign


def track(
    evaluate: Evaluate,
    x0: np.ndarray,
    p0: float,
    p_end: float,
    *,
    x_scale: float,
    tol: float,
    h0: float = 0.05,
    h_min: float = 1e-7,
    h_max: float = 0.5,
    max_steps: int = 2000,
    max_corrector: int = 10,
    record: bool = False,
    stop_outside: tuple[float, float] | None = None,
    solve_at: Callable[[np.ndarray, float], np.ndarray | None] | None = None,
) -> TrackResult:
    """Follow ``R(x, p) = 0`` from a solution ``(x0, p0)`` until ``p = p_end``.

    Pseudo-arc-length continuation in the scaled variables
    ``(x / x_scale, (p - p0) / |p_end - p0|)``: Euler predictor along the
    tangent, Newton corrector on the hyperplane normal to it, step size
    adapted to the corrector's iteration count and halved on failure. When
    the predictor would pass ``p_end``, the last step lands on it exactly.

    Parameters
    ----------
    evaluate : callable
        ``evaluate(x, p) -> (R, J, dR/dp)``.
    x0, p0 : ndarray, float
        A solution of ``R(x0, p0) = 0``.
    p_end : float
        Target parameter value.
    x_scale : float
        Typical size of ``x`` (its units).
    tol : float
        Convergence threshold on ``max |R|`` (units of R).
    h0, h_min, h_max : float
        Initial, smallest and largest scaled step.
    max_steps : int
        Step budget (accepted and rejected), so that it never loops forever.
    record : bool
        Keep every accepted point in ``points``.
    stop_outside : (float, float), optional
        Stop successfully once ``p`` leaves this interval (for a branch that
        turns back out of the band instead of reaching ``p_end``).
    solve_at : callable, optional
        ``solve_at(x, p) -> x*`` solves ``R(x*, p) = 0`` at fixed ``p`` from ``x``
        (or returns None); tried when the corrector fails, e.g. when Newton
        cycles between the pieces of a piecewise-linear residual.
    """
    p_scale = abs(p_end - p0)
    if p_scale == 0:
        return TrackResult(x0, p0, True, 0, 0)
    scales = np.append(np.full(x0.shape, x_scale), p_scale)
    z = np.append(x0, p0) / scales
    R, J, dR = evaluate(x0, p0)
    t, orientation = tangent(J * x_scale, dR * p_scale, np.sign(p_end - p0) * np.eye(z.size)[-1], 0.0)
    e_p = np.zeros(z.size)
    e_p[-1] = 1.0
    target = p_end / p_scale
    iterations, points = 0, []

    def correct(zp, cons):
        """Newton on R = 0 and cons . (z - zp) = 0; returns (z, R, J, dR, iterations) or None."""
        nonlocal iterations
        zc = zp.copy()
        for k in range(max_corrector):
            y = zc * scales
            try:
                R, J, dR = evaluate(y[:-1], y[-1])
            except ValueError:  # left the domain of the parameter (e.g. omega <= 0)
                return None
            iterations += 1
            if not np.all(np.isfinite(R)):
                return None
            if np.abs(R).max() <= tol:
                return zc, J, dR, k
            aug = np.empty((z.size, z.size))
            aug[:-1, :-1], aug[:-1, -1], aug[-1] = J * x_scale, dR * p_scale, cons
            try:
                zc = zc - np.linalg.solve(aug, np.append(R, cons @ (zc - zp)))
            except np.linalg.LinAlgError:
                return None
        if solve_at is None:
            return None
        y = zp * scales
        xs = solve_at(y[:-1], y[-1])
        if xs is None:
            return None
        R, J, dR = evaluate(xs, y[-1])
        return np.append(xs, y[-1]) / scales, J, dR, max_corrector

    def land(zp, steps):
        """The result at ``p_end`` corrected from ``zp`` (on the target) after ``steps`` steps, or None."""
        got = correct(zp, e_p)
        if got is None:
            return None
        y = got[0] * scales
        if record:
            points.append((y[:-1].copy(), p_end))
        return TrackResult(y[:-1], p_end, True, steps, iterations, "", points)

    h = h0
    for step in range(max_steps):
        ahead = (target - z[-1]) / t[-1] if t[-1] != 0 else np.inf
        if 0 < ahead <= h:  # the predictor reaches the target: land on it
            zp = z + ahead * t
            zp[-1] = target
            landed = land(zp, step + 1)
            if landed is not None:
                return landed
            h = 0.5 * ahead
        else:
            got = correct(z + h * t, t)
            if got is not None and (got[0][-1] - target) * (z[-1] - target) < 0:
                # the corrector crossed the target: land between the two points
                zc = got[0]
                zl = z + (target - z[-1]) / (zc[-1] - z[-1]) * (zc - z)
                landed = land(zl, step + 1)
                if landed is not None:
                    return landed
                got = None
            if got is not None:
                zc, J, dR, its = got
                t, orientation = tangent(J * x_scale, dR * p_scale, t, orientation)
                z = zc
                y = z * scales
                if record:
                    points.append((y[:-1].copy(), float(y[-1])))
                if stop_outside is not None and not stop_outside[0] <= y[-1] <= stop_outside[1]:
                    return TrackResult(y[:-1], y[-1], True, step + 1, iterations, "left the band", points)
                h = min(h_max, h * (1.5 if its <= 2 else 0.7 if its >= 5 else 1.0))
                continue
            h *= 0.5
        if h < h_min:
            y = z * scales
            return TrackResult(y[:-1], y[-1], False, step + 1, iterations, "step size underflow", points)
    y = z * scales
    return TrackResult(
        y[:-1], y[-1], False, max_steps, iterations, f"no arrival in {max_steps} steps", points
    )
