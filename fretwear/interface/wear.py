"""Nodal Archard wear of an interface with pressure redistribution (paper eq. 14-15, 24).

At every pair ``i`` the worn depth grows by Archard's law per cycle,

    dw_i / dN = K_w int_period p_i |ds_i|        (eq. 15, "K_w p_i s_i"),

with ``p_i = lambda_N,i / A_i`` the pressure of the pair and ``ds_i`` its slip
increments (``K_w`` in 1/Pa, ``w`` in m). The worn depth opens the pair's gap
(eq. 17b), so at every slow-time step the periodic solve redistributes the
normal pressure through the elastic bodies: pairs that wear unload, their
neighbours take the load, and the pressure integral stays equal to the
normal load.

Slow time is integrated by an adaptive Bogacki-Shampine 3(2) Runge-Kutta
method in the cycle count ``N``, with warm-started periodic solves (each stage
starts from the previous solution). The step is controlled on the worn depth,
against scales of the contact and never of the horizon, so that a longer
horizon only adds steps at the end (a saturated scar stays as it is):

* the wear scale ``S = max_i lambda_N,i / Z_NN,ii`` (m), the depth that
  unloads the most loaded pair with its neighbours held (``lambda_N,i`` its
  cycle-averaged normal force, ``Z_NN,ii`` its static normal stiffness; about
  the saturated scar depth of the benchmark in partial slip; ``u0`` for the
  paper's 2-DOF model as a one-pair interface), taken at the initial state
  and kept (a scale that followed the worn state would shrink with the
  remaining load and force steps of constant length in ``N`` on an
  exponential approach): no step wears any pair by more than
  ``max_increment * S``;
* the local error on ``w`` stays below ``atol + rtol max|w|``, ``atol = 0.1 rtol S``
  by default;
* the first step wears ``max_increment * S`` at most.

The history stops at ``cycles`` or, with ``converge``, when the profile has
stopped changing: the largest wear rate times the cycles elapsed is below
``converge`` times the largest depth (partial slip: the slip annulus unloads
and wear dies out).

Pairs that stick all period keep their reference slip variable; after each
accepted step every pair's reference is moved to its slip variable at the
start of the period, so that a pair that stops slipping sticks where it is.
"""

from __future__ import annotations

import numpy as np

from ..slow_time import integrate
from .history import InterfaceWearHistory
from .periodic import InterfaceProblem, InterfaceSolution, solve_interface
from .polynomial import DEFAULT_DEGREE, wear_polynomial_interface

__all__ = ["wear_interface", "wear_scale", "sweep_interface", "frf", "METHODS", "MAX_INCREMENT"]

#: slow-time methods of :func:`wear_interface`, the default first
METHODS = ("stepping", "polynomial")

#: default largest wear increment of any pair per step, as a fraction of the wear scale (``wear_scale()``)
MAX_INCREMENT = 0.1

#: failed periodic solves in a row (the step quartered each time) before a history gives up
MAX_RETRIES = 8


def _rate(problem: InterfaceProblem, w: np.ndarray, guess, kw: float, tol: float):
    sol = solve_interface(problem.with_wear(np.maximum(w, 0.0)), guess, tol)
    return kw * sol.pressure_slip, sol


def wear_scale(sol: InterfaceSolution) -> float:
    """Wear scale ``S = max_i lambda_N,i / Z_NN,ii`` of a periodic solution (m).

    ``lambda_N,i`` is the cycle-averaged normal force of pair ``i`` (N) and
    ``Z_NN,ii`` the static stiffness of its normal contact coordinate (N/m, the
    mean-harmonic diagonal of eq. 12's ``Z``): the depth of wear that would
    unload the pair with its neighbours held. 0 when no pair carries load.
    """
    problem = sol.problem
    d = problem.per_pair  # the normal coordinate is a pair's last (2-D friction: after two tangents)
    q = d * problem.n_pairs  # the mean's block of Z by harmonic: the dense Z is not formed
    stiffness = np.abs(np.diag(problem._blocks[0, :q, :q]))[d - 1 :: d]
    return float(np.max(sol.normal_force.mean(axis=1) / stiffness))


def wear_interface(
    problem: InterfaceProblem,
    kw: float,
    cycles: float,
    rtol: float = 1e-2,
    atol: float | None = None,
    converge: float | None = None,
    first_step: float | None = None,
    max_steps: int = 400,
    tol: float = 1e-10,
    method: str = "stepping",
    degree: int | None = None,
    max_increment: float = MAX_INCREMENT,
) -> InterfaceWearHistory:
    """Wear history of the interface ``problem`` from its current wear state to ``cycles``.

    ``method="stepping"`` (default) integrates slow time step by step (module
    docstring); ``method="polynomial"`` solves the whole period at once with the
    worn depths as polynomials of degree ``degree`` in ``N``
    (:func:`~fretwear.interface.wear_polynomial_interface`; ``rtol``,
    ``atol``, ``converge``, ``first_step`` and ``max_steps`` do not apply).

    Parameters
    ----------
    problem : InterfaceProblem
        The interface at its frequency (its ``wear`` is the initial profile).
    kw : float
        Archard coefficient ``K_w`` (1/Pa), > 0.
    cycles : float
        Cycle count to reach, > 0.
    rtol, atol : float
        Step control: local error on ``w`` below ``atol + rtol max|w|`` (m);
        default ``atol = 0.1 rtol S`` with ``S`` the wear scale of the initial
        state (``wear_scale()``).
    converge : float, optional
        Stop early once ``max(dw/dN) N < converge max(w)`` (a converged profile).
    first_step : float, optional
        First step (cycles); default: the step that wears ``max_increment S``
        (or ``cycles``, if shorter).
    max_steps : int
        Accepted steps at most.
    tol : float
        Relative residual tolerance of the periodic solves.
    method : {"stepping", "polynomial"}
        Slow-time method.
    degree : int, optional
        Polynomial degree of the polynomial method (default
        ``DEFAULT_DEGREE``).
    max_increment : float
        Largest depth any pair may wear in one step, as a fraction of the
        wear scale ``S`` of the initial state (-), in (0, 1].
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {', '.join(map(repr, METHODS))}, got {method!r}")
    if method == "polynomial":
        return wear_polynomial_interface(
            problem, kw, cycles, degree=DEFAULT_DEGREE if degree is None else degree, solve_tol=tol
        )
    if degree is not None:
        raise ValueError("degree applies to method='polynomial' only")
    if not (np.isfinite(kw) and kw > 0):
        raise ValueError(f"kw must be a finite Archard coefficient > 0 1/Pa, got {kw!r}")
    if not (np.isfinite(cycles) and cycles > 0):
        raise ValueError(f"cycles must be finite and > 0, got {cycles!r}")
    if not (0 < rtol < 1):
        raise ValueError(f"rtol must be in (0, 1), got {rtol!r}")
    if not (0 < max_increment <= 1):
        raise ValueError(f"max_increment must be in (0, 1], got {max_increment!r}")
    if first_step is not None and not (np.isfinite(first_step) and first_step > 0):
        raise ValueError(f"first_step must be a finite number of cycles > 0, got {first_step!r}")
    contact = problem.condensation.model.pairs
    hist = InterfaceWearHistory(
        position=contact.position, area=contact.area, kw=float(kw), omega=problem.omega
    )
    w = problem.wear.copy()
    k1, sol = _rate(problem, w, None, kw, tol)
    hist.solves += 1
    if not sol.converged:
        hist.record(0.0, w, sol)
        hist.converged, hist.message = False, f"periodic solve failed at N = 0: {sol.message}"
        return hist.finish()
    hist.record(0.0, w, sol)
    scale = wear_scale(sol)
    if atol is None:
        atol = 0.1 * rtol * max(scale, 1e-300)
    # the unknowns along the slow time: each stage starts from the secant prediction of the last step
    state = {"x": sol.unknowns, "dx_dN": np.zeros_like(sol.unknowns), "problem": problem}

    def rate(w_trial: np.ndarray, c: float, h: float):
        k, s = _rate(state["problem"], w_trial, state["x"] + c * h * state["dx_dN"], kw, tol)
        hist.solves += 1
        return (k, s) if s.converged else (None, s.message)

    def accept(N: float, w_new: np.ndarray, k: np.ndarray, s) -> str | None:
        h = N - (hist.cycles[-1] if hist.cycles else 0.0)
        state["dx_dN"], state["x"] = (s.unknowns - state["x"]) / h, s.unknowns
        state["problem"] = state["problem"].with_wear(state["problem"].wear, xref=s.slip_variable[:, 0])
        hist.record(N, w_new, s)
        if converge is not None and np.abs(k).max() * N < converge * np.abs(w_new).max():
            return f"profile converged at N = {N:.6g}"
        return None

    status, ok = integrate(rate, w, k1, cycles, accept, scale=scale, atol=atol, rtol=rtol,
                           max_increment=max_increment, project=lambda w_trial: np.maximum(w_trial, 0.0),
                           first_step=first_step, max_steps=max_steps, max_retries=MAX_RETRIES,
                           shrink=0.25)  # fmt: skip
    hist.converged = ok
    if status != "horizon":
        hist.message = status
    return hist.finish()


def sweep_interface(problems, tol: float = 1e-10, max_iter: int = 50) -> list[InterfaceSolution]:
    """Periodic responses of the interface problems ``problems`` (e.g. over frequency), in the given order.

    Each solve starts from the previous converged solution (a warm start); a
    failed point is reported (``converged=False``) and the next starts cold.

    Parameters
    ----------
    problems : iterable of InterfaceProblem
    tol : float
        Relative residual tolerance.
    max_iter : int
        Newton iterations per solve.
    """
    out, guess = [], None
    for prob in problems:
        sol = solve_interface(prob, guess, tol, max_iter)
        out.append(sol)
        guess = sol.unknowns if sol.converged else None
    return out


def frf(
    make_problem,
    freqs_hz: np.ndarray,
    dof: int | str,
    wear: np.ndarray | None = None,
    tol: float = 1e-10,
) -> tuple[np.ndarray, np.ndarray]:
    """First-harmonic amplitude of one DOF over frequency at a fixed wear profile (pseudo-FRF).

    Parameters
    ----------
    make_problem : callable
        ``make_problem(omega) -> InterfaceProblem`` (rad/s).
    freqs_hz : ndarray
        Frequencies (Hz), swept in the given order with warm starts (:func:`sweep_interface`).
    dof : int or str
        DOF of the full model (index or name).
    wear : ndarray, optional
        Worn depth per pair (m).

    Returns
    -------
    (ndarray, ndarray)
        Amplitude ``sqrt(a1^2 + b1^2)`` (m) and a converged flag per frequency.
    """
    problems = (make_problem(2 * np.pi * f) for f in freqs_hz)
    if wear is not None:
        problems = (prob.with_wear(wear) for prob in problems)
    sols = sweep_interface(problems, tol)
    amp = np.empty(len(sols))
    for j, sol in enumerate(sols):
        p = sol.problem
        d = p.condensation.full.dof(dof)
        h = p.condensation.full_harmonics(p.omega, p.harmonics, sol.contact_harmonics, [d])[0]
        amp[j] = np.hypot(h[1], h[2])
    return amp, np.array([s.converged for s in sols], dtype=bool)
