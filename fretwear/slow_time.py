"""Adaptive integration of Archard's law over the slow time, written once for every structure.

Wear follows ``dw/dN = g(w)`` over the cycle count ``N`` (paper eq. 24 in the
limit of small steps), where each evaluation of the rate ``g`` is a periodic
solve of the structure at wear ``w``: the 2-DOF model's contacts
(``fretwear.wear.stepping``) and an interface's pairs
(``fretwear.interface.wear``) hand :func:`integrate` their own rate and
keep their own records; the step control lives here.

Bogacki-Shampine 3(2) with first-same-as-last: three new rate evaluations a
step, the third at the accepted state. The step is bounded by scales of the
contact, never by the horizon, so that a longer horizon only adds steps at the
end (a saturated scar stays as it is):

* no step wears any component by more than ``max_increment * scale`` (checked
  before the step on the rate, and on the step's own increment, which catches a
  rate that rises within the step);
* the local error estimate stays below ``atol + rtol max|w|`` componentwise.

A failed periodic solve shrinks the step and retries, up to ``max_retries``
times in a row: a count, not a step size, so that no horizon-relative floor
exists. ``fixed_step`` replaces the pair by the paper's explicit per-period
rule (``fixed_step = 1`` is eq. 24 exactly).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

__all__ = ["Rate", "integrate"]

#: ``rate(w, c, h) -> (dw/dN, payload)`` at the wear ``w`` of stage ``c`` (fraction of the step ``h``:
#: 0.5, 0.75, 1); ``dw/dN`` is ``None`` when the periodic solve fails, ``payload`` then says why
Rate = Callable[[np.ndarray, float, float], tuple[np.ndarray | None, Any]]


def integrate(
    rate: Rate,
    w: np.ndarray,
    k1: np.ndarray,
    cycles: float,
    accept: Callable[[float, np.ndarray, np.ndarray, Any], str | None],
    *,
    scale: np.ndarray | float,
    atol: np.ndarray | float,
    rtol: float = 0.0,
    max_increment: float = 0.1,
    project: Callable[[np.ndarray], np.ndarray] = lambda w: w,
    first_step: float | None = None,
    fixed_step: float | None = None,
    max_steps: int = 100_000,
    max_retries: int = 20,
    shrink: float = 0.5,
) -> tuple[str, bool]:
    """Integrate ``dw/dN = rate(w)`` from ``N = 0`` (wear ``w``, rate ``k1``) to ``cycles``.

    Parameters
    ----------
    rate : Rate
        The rate at a wear state (a periodic solve), see :data:`Rate`.
    w, k1 : ndarray
        Initial wear (m) and its rate (m/cycle), one entry per contact or pair.
    cycles : float
        Horizon (cycles), > 0.
    accept : callable
        ``accept(N, w, dw/dN, payload)`` after each accepted step (records it);
        a returned string ends the integration with that status (e.g. worn).
    scale : ndarray or float
        Wear scale of each component (m): ``u0`` of a contact, the depth that
        unloads an interface's pairs.
    atol, rtol : ndarray or float, float
        Local error tolerance ``atol + rtol max|w|`` (m).
    max_increment : float
        Largest wear per step, as a fraction of ``scale``.
    project : callable
        Maps a trial wear state into the admissible set (e.g. ``0 <= w < u0``).
    first_step : float, optional
        First step (cycles); default the horizon (bounded by the increment).
    fixed_step : float, optional
        The explicit per-period rule with this step (cycles) instead of the pair.
    max_steps, max_retries : int
        Accepted steps at most; failed solves in a row at most.
    shrink : float
        Step factor after a failed solve.

    Returns
    -------
    (str, bool)
        Why it ended (``"horizon"``, the status ``accept`` returned, or the
        failure) and whether it ended without failure.
    """
    N, failures = 0.0, 0
    h = float(fixed_step or first_step or cycles)
    for _ in range(max_steps):
        if N >= cycles * (1 - 1e-12):
            return "horizon", True
        if not fixed_step:  # the increment bound, whatever the horizon
            fastest = float(np.max(np.abs(k1) / scale))
            if fastest > 0:
                h = min(h, max_increment / fastest)
        h = min(h, cycles - N)
        if fixed_step:
            w_new = project(w + h * k1)
            k_new, payload = rate(w_new, 1.0, h)
            if k_new is None:
                return f"periodic solve failed at N = {N + h:g}: {payload}", False
        else:
            k2, payload = rate(project(w + 0.5 * h * k1), 0.5, h)
            k3 = k_new = None
            if k2 is not None:
                k3, payload = rate(project(w + 0.75 * h * k2), 0.75, h)
            if k3 is not None:
                w_new = project(w + h * (2 * k1 + 3 * k2 + 4 * k3) / 9)
                increment = float(np.max(np.abs(w_new - w) / scale))
                if increment > max_increment:  # the rate rose within the step: shorter, before solving
                    h *= max(0.2, 0.9 * max_increment / increment)
                    continue
                k_new, payload = rate(w_new, 1.0, h)
            if k_new is None:
                failures += 1
                if failures > max_retries:
                    return f"periodic solve failed near N = {N:.6g}: {payload}", False
                h *= shrink
                continue
            failures = 0
            err = h * np.abs(-5 * k1 / 72 + k2 / 12 + k3 / 9 - k_new / 8)
            ratio = float(np.max(err / (atol + rtol * np.max(np.abs(w_new)))))
            h_next = h * min(5.0, max(0.2, 0.9 * ratio ** (-1 / 3) if ratio > 0 else 5.0))
            if ratio > 1:
                h = h_next
                continue
        N, w, k1 = N + h, w_new, k_new
        status = accept(N, w, k1, payload)
        if status:
            return status, True
        if not fixed_step:
            h = h_next
    return f"step budget of {max_steps} exhausted at N = {N:.6g}", False
