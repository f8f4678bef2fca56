"""Periodic solutions by shooting on the exact event-driven integrator.

:func:`shooting` solves ``y(T; y0) = y0`` by Newton's method with the exact
monodromy matrix of :mod:`fretwear.time.integrator`; :func:`steady_state`
marches periods until the transient has died out; :func:`shooting_sweep`
follows a frequency grid, each solve seeded by its predecessor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import linalg
from scipy.optimize import brentq

from ..model import Model
from .integrator import TIME_TOL, ContactEvent, Engine, Trajectory, check_state, engine

__all__ = ["ShootingSolution", "shooting", "periodic_state", "steady_state", "shooting_sweep"]


@dataclass(frozen=True, eq=False)
class ShootingSolution:
    """Periodic response found by :func:`shooting` (or :func:`steady_state`).

    Signals are sampled over one period on the uniform grid ``t_k = k T / N``.

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s); ``period = 2 pi / omega`` (s).
    y0 : ndarray, shape (2 n,)
        Periodic state ``(u, v)`` at ``t = 0``.
    converged : bool
    iterations : int
        Newton iterations (:func:`shooting`) or periods marched (:func:`steady_state`).
    residual : float
        Periodicity residual ``|y(T) - y(0)| / |y(0)|`` with velocities scaled
        by ``1 / omega`` (dimension of a displacement).
    monodromy : ndarray, shape (2 n, 2 n)
        ``dy(T)/dy(0)``, exact, including the saltation matrices of the events.
    floquet_multipliers : ndarray, shape (2 n,)
        Eigenvalues of ``monodromy``, by decreasing modulus. A contact that
        sticks during the period annihilates perturbations of its relative
        velocity (multiplier 0); on an orbit stuck during the whole period the
        stuck relative displacement is a neutral direction (multiplier 1, the
        periodic orbits then form a family).
    wear, normal_loads, slip_forces : ndarray, shape (n_friction,)
        Wear depth (m), normal load (N) and slip force ``mu F_N`` (N) per contact.
    time : ndarray, shape (N,)
        Sample times (s).
    displacement, velocity : ndarray, shape (n, N)
        DOF displacements (m) and velocities (m/s).
    relative_displacement : ndarray, shape (n_friction, N)
        ``u_r = B u`` of every friction contact (m).
    contact_force : ndarray, shape (n_friction, N)
        Friction forces (N).
    state : ndarray of int8, shape (n_friction, N)
        :data:`STICK`, :data:`SLIP` or :data:`OPEN`.
    first_harmonic : ndarray, shape (n, 2)
        Exact first Fourier coefficients ``(a1, b1)`` of each DOF (m),
        ``u ~ a1 cos(omega t) + b1 sin(omega t)``, from a phase-wise
        Gauss-Legendre quadrature of the exact solution (no FFT aliasing).
    half_peak_to_peak : ndarray, shape (n,)
        ``(max u - min u) / 2`` of each DOF (m), with exact extrema: sampled
        extrema refined by locating the zero of the velocity (brentq).
    relative_half_peak_to_peak : ndarray, shape (n_friction,)
        Same for the relative displacement of each friction contact (m).
    sliding_distance, friction_energy : ndarray, shape (n_friction,)
        Per period, exact (m, J).
    input_work, viscous_dissipation : float
        Per period (J); ``input_work = viscous_dissipation + friction_energy.sum()``
        on a periodic orbit.
    events : tuple of ContactEvent
        Contact state changes over one period.
    """

    omega: float
    y0: np.ndarray
    converged: bool
    iterations: int
    residual: float
    monodromy: np.ndarray
    floquet_multipliers: np.ndarray
    wear: np.ndarray
    normal_loads: np.ndarray
    slip_forces: np.ndarray
    time: np.ndarray
    displacement: np.ndarray
    velocity: np.ndarray
    relative_displacement: np.ndarray
    contact_force: np.ndarray
    state: np.ndarray
    first_harmonic: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    sliding_distance: np.ndarray
    friction_energy: np.ndarray
    input_work: float
    viscous_dissipation: float
    events: tuple[ContactEvent, ...]

    @property
    def period(self) -> float:
        """Excitation period ``2 pi / omega`` (s)."""
        return 2 * np.pi / self.omega

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude ``sqrt(a1^2 + b1^2)`` of each DOF (m), shape (n,)."""
        return np.hypot(self.first_harmonic[:, 0], self.first_harmonic[:, 1])

    @property
    def stable(self) -> bool:
        """True when every Floquet multiplier lies strictly inside the unit circle.

        Orbits stuck during the whole period are neutrally stable (multiplier 1).
        """
        return bool(np.abs(self.floquet_multipliers).max() < 1.0)


def _stuck_state(eng: Engine, g: np.ndarray) -> np.ndarray:
    """State at ``t = 0`` of the linear steady state with every loaded contact rigid (``B u = 0``)."""
    model, n, w = eng.model, eng.n, eng.omega
    Bs = eng.B[g > 0]
    N = linalg.null_space(Bs) if len(Bs) else np.eye(n)
    Z = N.T @ (model.K - w**2 * model.M + 1j * w * model.C) @ N
    U = N @ linalg.solve(Z, N.T @ (model.force_cos - 1j * model.force_sin))
    u_static = N @ linalg.lstsq(N.T @ model.K @ N, N.T @ model.force_static)[0]
    return np.concatenate([u_static + U.real, (1j * w * U).real])


def _scaled_norm(eng: Engine, y: np.ndarray) -> float:
    return float(np.hypot(np.linalg.norm(y[: eng.n]), np.linalg.norm(y[eng.n :]) / eng.omega))


def _refine_extrema(traj: Trajectory, c: np.ndarray, times: np.ndarray, values: np.ndarray, period: float):
    """Exact maximum and minimum over one period of ``c . u(t)`` (rate ``c . v(t)``)."""
    n = len(c)
    N = len(times)

    def value(t):
        return float(c @ traj.evaluate([t])[0][:n, 0])

    def rate(t):
        return float(c @ traj.evaluate([t])[0][n:, 0])

    result = []
    for sign in (1.0, -1.0):
        vals = sign * values
        best = vals.max()
        span = max(vals.max() - vals.min(), 1e-300)
        local = (vals >= np.roll(vals, 1)) & (vals >= np.roll(vals, -1)) & (vals >= best - 1e-2 * span)
        for k in np.flatnonzero(local):
            tk = times[k]
            rk = sign * rate(tk)
            if rk == 0.0:
                continue
            a, b = (tk, tk + period / N) if rk > 0 else (tk - period / N, tk)
            if a < 0:
                a, b = a + period, b + period
            b = min(b, period)
            ra, rb = sign * rate(a), sign * rate(b)
            if ra > 0 > rb:
                best = max(best, sign * value(brentq(rate, a, b, xtol=TIME_TOL * period)))
        result.append(sign * best)
    return result[0], result[1]


def _solution(
    eng: Engine, g: np.ndarray, wear, y0: np.ndarray, converged: bool, iterations: int, samples: int
) -> ShootingSolution:
    model, n, T = eng.model, eng.n, eng.period
    times = np.arange(samples) * (T / samples)
    traj = eng.run(y0, 0.0, T, g, sample_times=times, jacobian=True, quadrature=True)
    residual = _scaled_norm(eng, traj.y - y0) / max(_scaled_norm(eng, y0), 1e-300)
    u, v = traj.states[:n], traj.states[n:]
    rel = eng.B @ u
    hpp = np.zeros(n)
    for i in range(n):
        hi, lo = _refine_extrema(traj, np.eye(n)[i], times, u[i], T)
        hpp[i] = (hi - lo) / 2
    rhpp = np.zeros(eng.nf)
    for j in range(eng.nf):
        hi, lo = _refine_extrema(traj, eng.B[j], times, rel[j], T)
        rhpp[j] = (hi - lo) / 2
    mult = linalg.eigvals(traj.jacobian)
    coef = 2 / T * traj.fourier
    wear = np.zeros(eng.nf) if wear is None else np.asarray(wear, dtype=float)
    return ShootingSolution(
        omega=eng.omega,
        y0=y0,
        converged=converged,
        iterations=iterations,
        residual=residual,
        monodromy=traj.jacobian,
        floquet_multipliers=mult[np.argsort(-np.abs(mult), kind="stable")],
        wear=wear,
        normal_loads=model.normal_loads(wear),
        slip_forces=g,
        time=times,
        displacement=u,
        velocity=v,
        relative_displacement=rel,
        contact_force=traj.contact_force,
        state=traj.contact_state,
        first_harmonic=np.column_stack([coef.real, -coef.imag]),
        half_peak_to_peak=hpp,
        relative_half_peak_to_peak=rhpp,
        sliding_distance=traj.sliding_distance,
        friction_energy=traj.friction_energy,
        input_work=traj.input_work,
        viscous_dissipation=traj.viscous_dissipation,
        events=traj.events,
    )


def _check_samples(samples: int) -> int:
    if not isinstance(samples, (int, np.integer)) or samples < 4:
        raise ValueError(f"samples must be an integer >= 4, got {samples!r}")
    return int(samples)


def _newton(eng: Engine, g: np.ndarray, y: np.ndarray, tol: float, max_iter: int):
    """Newton iterations on ``P(y) - y = 0``: ``(y, converged, iterations)``."""
    T, identity = eng.period, np.eye(2 * eng.n)
    run = eng.run(y, 0.0, T, g, jacobian=True)
    res = _scaled_norm(eng, run.y - y)
    for iteration in range(max_iter + 1):
        if res <= tol * max(_scaled_norm(eng, y), 1e-300):
            return y, True, iteration
        if iteration == max_iter:
            break
        step = linalg.lstsq(run.jacobian - identity, y - run.y)[0]
        alpha = 1.0
        while True:  # backtracking on the periodicity residual
            trial = y + alpha * step
            trial_run = eng.run(trial, 0.0, T, g, jacobian=True)
            trial_res = _scaled_norm(eng, trial_run.y - trial)
            if trial_res < res or alpha < 1e-4:
                break
            alpha /= 2
        y, run, res = trial, trial_run, trial_res
    return y, False, max_iter


def shooting(
    model: Model,
    omega: float,
    y_guess=None,
    *,
    wear=None,
    tol: float = 1e-12,
    max_iter: int = 50,
    samples: int = 512,
    transient_periods: int = 200,
) -> ShootingSolution:
    """Periodic response by shooting: Newton on ``y0 - P(y0) = 0``, ``P`` the period map.

    The Jacobian is the exact monodromy matrix (phase transition matrices and
    event saltation matrices). Newton steps are least-squares steps (the
    Jacobian is singular on orbits stuck during the whole period, whose stuck
    offset is arbitrary) with backtracking on the periodicity residual.

    Parameters
    ----------
    model : Model
        Structure with friction contacts only; ``M`` positive definite.
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y_guess : array_like, shape (2 n,), optional
        Guess of the state at ``t = 0``. By default Newton starts from the
        linear steady state with every loaded contact rigid (exact when it
        keeps the contacts inside their friction cones); if that fails, it
        restarts after marching ``transient_periods`` periods from there.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    tol : float
        Target periodicity residual (see :attr:`ShootingSolution.residual`).
    max_iter : int
        Largest number of Newton iterations (per start).
    samples : int
        Number ``N`` of uniform samples of the period in the result.
    transient_periods : int
        Periods marched before the second start, without a guess.

    Returns
    -------
    ShootingSolution
        ``iterations`` counts the Newton iterations of every start.
    """
    eng, g = engine(model, omega, wear)
    samples = _check_samples(samples)
    if y_guess is not None:
        y, converged, iterations = _newton(eng, g, check_state(eng, y_guess, "y_guess"), tol, max_iter)
        return _solution(eng, g, wear, y, converged, iterations, samples)
    y_stuck = _stuck_state(eng, g)
    y, converged, iterations = _newton(eng, g, y_stuck, tol, max_iter)
    if not converged and transient_periods > 0:
        y = y_stuck
        for _ in range(transient_periods):
            y = eng.run(y, 0.0, eng.period, g).y
        y, converged, more = _newton(eng, g, y, tol, max_iter)
        iterations += more
    return _solution(eng, g, wear, y, converged, iterations, samples)


def periodic_state(
    model: Model, omega: float, y_guess, *, wear=None, tol: float = 1e-12, max_iter: int = 50
) -> tuple[np.ndarray, bool]:
    """State at ``t = 0`` of the periodic orbit reached by Newton from ``y_guess``.

    The Newton iterations of :func:`shooting` without its post-processing
    (sampling, extrema, Floquet multipliers): a cheap projection of a nearby
    state onto the periodic orbit, e.g. to follow an orbit that drifts with wear.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y_guess : array_like, shape (2 n,)
        Starting state ``(u, v)`` at ``t = 0`` (m, m/s).
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    tol : float
        Target periodicity residual (see :attr:`ShootingSolution.residual`).
    max_iter : int
        Largest number of Newton iterations.

    Returns
    -------
    y0 : ndarray, shape (2 n,)
        Periodic state (the last iterate when Newton fails).
    converged : bool
    """
    eng, g = engine(model, omega, wear)
    y, converged, _ = _newton(eng, g, check_state(eng, y_guess, "y_guess"), tol, max_iter)
    return y, converged


def steady_state(
    model: Model,
    omega: float,
    y_guess=None,
    *,
    wear=None,
    max_periods: int = 20_000,
    tol: float = 1e-10,
    samples: int = 512,
) -> ShootingSolution:
    """Periodic response by plain time marching, period after period.

    Independent of :func:`shooting` (no Newton, no Jacobian). With light
    damping the transient decays slowly: seed it with a good guess. The
    marching stops when the change over one period falls below ``tol``
    (relative, velocities scaled by ``1 / omega``); the distance to the
    periodic orbit is then about ``tol / (1 - |mu_max|)``, ``mu_max`` the
    largest Floquet multiplier.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y_guess : array_like, shape (2 n,), optional
        Initial state at ``t = 0``; default the linear steady state with
        every loaded contact rigid.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    max_periods : int
        Largest number of periods marched.
    tol : float
        Convergence tolerance on the change over one period.
    samples : int
        Number of uniform samples of the period in the result.

    Returns
    -------
    ShootingSolution
        With ``iterations`` the number of periods marched.
    """
    eng, g = engine(model, omega, wear)
    samples = _check_samples(samples)
    y = _stuck_state(eng, g) if y_guess is None else check_state(eng, y_guess, "y_guess").copy()
    converged, periods = False, 0
    while not converged and periods < max_periods:
        y1 = eng.run(y, 0.0, eng.period, g).y
        converged = _scaled_norm(eng, y1 - y) <= tol * max(_scaled_norm(eng, y1), 1e-300)
        y, periods = y1, periods + 1
    return _solution(eng, g, wear, y, converged, periods, samples)


def shooting_sweep(model: Model, omegas, **options) -> list[ShootingSolution]:
    """Exact periodic responses by :func:`shooting` at ``omegas`` (rad/s), each seeded by its predecessor."""
    out, guess = [], None
    for w in np.asarray(omegas, dtype=float):
        sol = shooting(model, w, guess, **options)
        out.append(sol)
        guess = sol.y0 if sol.converged else None
    return out
