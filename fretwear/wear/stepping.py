"""Slow-time stepping of Archard's law (paper eq. 24 and its adaptive form).

``dw/dN = K_w F_N(w) s(w)`` is integrated over the cycle count ``N`` by an
embedded Runge-Kutta pair (Bogacki-Shampine 3(2)) with a local error estimate
on ``w``, each stage a periodic solve (DLFT or shooting) warm-started from the
previous one; or by the paper's explicit per-period rule with a fixed step
(``fixed_step=1`` is eq. 24 exactly).

The adaptive steps are bounded by the wear scale ``u0`` of each contact, never
by the horizon: no step wears a contact by more than ``max_increment * u0``
(whatever the tolerance), and the local error stays below ``tol * u0``; the
first step is the one that wears ``tol * u0``. A longer horizon therefore only
adds steps at the end.
"""

from __future__ import annotations

import time
from typing import Literal

import numpy as np

from ..model import Model
from ..slow_time import integrate
from .dynamics import Dynamics
from .result import Recorder, WearHistory, check_wear_inputs, clip_wear, two_scale_warning

__all__ = ["wear_stepping", "MAX_INCREMENT"]

#: default largest wear of any contact in one adaptive step, as a fraction of its u0
MAX_INCREMENT = 0.1

#: failed periodic solves in a row (the step halved each time) before a history gives up
MAX_RETRIES = 20


def wear_stepping(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int | None = None,
    samples: int | None = None,
    tol: float = 1e-3,
    fixed_step: float | None = None,
    dynamics: Literal["auto", "dlft", "shooting"] = "auto",
    stop_fraction: float = 0.99,
    max_steps: int = 100_000,
    max_increment: float = MAX_INCREMENT,
) -> WearHistory:
    """Wear evolution at one frequency by stepping on the slow time (eq. 24 and RK23).

    Parameters
    ----------
    model, omega, kw, cycles
        As :func:`fretwear.wear.wear_history` (rad/s, 1/N, cycles).
    harmonics, samples : int, optional
        Harmonic balance settings of the DLFT periodic solves (``Nh`` default 21);
        giving either makes ``dynamics="auto"`` the DLFT dynamics.
    tol : float
        Local error tolerance on ``w`` per step, as a fraction of ``u0``.
    fixed_step : float, optional
        Explicit Euler with this step (cycles) instead of the adaptive pair;
        ``fixed_step=1`` is the paper's per-period update (eq. 24).
    dynamics : {"auto", "dlft", "shooting"}
        Periodic solver: exact shooting on the event-driven dynamics, or HBM + DLFT
        (an approximation); ``"auto"``: :func:`~fretwear.wear.resolve_dynamics`.
    stop_fraction : float
        Stop when every contact reaches ``stop_fraction * u0``.
    max_steps : int
        Step budget.
    max_increment : float
        Largest wear of any contact in one adaptive step, as a fraction of its
        ``u0`` (-), in (0, 1]; ``fixed_step`` is not bounded.
    """
    check_wear_inputs(model, kw, cycles)
    if not 0 < tol < 1:
        raise ValueError(f"tol must be in (0, 1), got {tol!r}")
    if not 0 < max_increment <= 1:
        raise ValueError(f"max_increment must be in (0, 1], got {max_increment!r}")
    if fixed_step is not None and not (np.isfinite(fixed_step) and fixed_step > 0):
        raise ValueError(f"fixed_step must be > 0 cycles, got {fixed_step!r}")
    start = time.perf_counter()
    u0 = np.array([c.u0 for c in model.friction])
    dyn = Dynamics(model, omega, harmonics, samples, kw, dynamics)
    rec = Recorder()
    w = np.zeros(len(model.friction))
    first = dyn(w)
    if first is None:
        raise RuntimeError("the periodic solve of the unworn structure failed")
    g, slid, sol = first
    rec.add(0.0, w, g, slid, sol, model)
    method = "stepping"

    def done(**kw_):
        return rec.history(omega, method, model, kw, dynamics=dyn.kind, harmonics=dyn.harmonics,
                           solves=dyn.solves, wall_time=time.perf_counter() - start, warnings=notes,
                           **kw_)  # fmt: skip

    if not np.any(g > 0):
        notes = []
        rec.add(float(cycles), w, g, slid, sol, model)
        return done(status="stuck")
    notes = two_scale_warning(g, u0)

    def rate(w_trial: np.ndarray, c: float, _h: float):
        # stages are trials (the warm start stays); the step's last state becomes the next guess
        r = dyn(w_trial, keep=c == 1.0)
        return (None, "not converged") if r is None else (r[0], r)

    def accept(N: float, w_new: np.ndarray, _g: np.ndarray, r) -> str | None:
        rec.add(N, w_new, *r, model)
        return "worn" if np.all(w_new >= stop_fraction * u0) else None

    status, ok = integrate(rate, w, g, cycles, accept, scale=u0, atol=tol * u0, max_increment=max_increment,
                           project=lambda w_trial: clip_wear(w_trial, u0),
                           first_step=tol * u0.max() / g.max(), fixed_step=fixed_step, max_steps=max_steps,
                           max_retries=MAX_RETRIES)  # fmt: skip
    return done(converged=ok, status=status)
