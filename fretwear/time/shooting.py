"""Periodic solutions by shooting on the exact event-driven integrator.

:func:`shooting` solves ``y(T; y0) = y0`` by Newton's method with the exact
monodromy matrix of :mod:`fretwear.time.integrator` (compiled: every Newton
iteration and period march runs in :mod:`fretwear.time.kernels`);
:func:`steady_state` marches periods until the transient has died out;
:func:`shooting_sweep` follows a frequency grid, each solve seeded by its
predecessor. The result, :class:`ShootingSolution`, has the attributes of
:class:`fretwear.response.PeriodicResponse`.

Cold start (no guess): Newton from the linear steady state with every loaded
contact rigid (exact when it keeps the contacts inside their friction cones),
then, if that fails, from the state reached by marching periods from there
(the transient decays towards a stable orbit), with longer marches between
restarts. A solve that does not converge is reported (``converged=False``,
``message``), never raised.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property

import numpy as np
from scipy import linalg

from ..model import STICK, Model
from . import kernels
from .integrator import (
    ContactEvent,
    Engine,
    Trajectory,
    check_state,
    engine,
    engine_loads,
    model_arrays,
    trajectory,
)

__all__ = ["ShootingSolution", "shooting", "periodic_state", "steady_state", "shooting_sweep"]

_MARCHES = (20, 100, 400)  # periods marched before the second, third and fourth Newton starts
_MAX_PHASES = 1_000_000  # per period: more is a degenerate cascade


@dataclass(frozen=True, eq=False)
class ShootingSolution:
    """Periodic response found by :func:`shooting` (or :func:`steady_state`).

    Signals are sampled over one period on the uniform grid ``t_k = k T / N``
    (computed on first access, from the exact solution).

    Attributes
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s); ``period = 2 pi / omega`` (s).
    y0 : ndarray, shape (2 n,)
        Periodic state ``(u, v)`` at ``t = 0`` (also :attr:`unknowns`).
    converged : bool
    iterations : int
        Newton iterations (:func:`shooting`, summed over its starts) or
        periods marched (:func:`steady_state`).
    residual : float
        Periodicity residual ``|y(T) - y(0)| / |y(0)|`` with velocities scaled
        by ``1 / omega`` (dimension of a displacement).
    message : str
        Reason of a failure, empty on success.
    monodromy : ndarray, shape (2 n, 2 n)
        ``dy(T)/dy(0)``, exact, including the saltation matrices of the events.
    floquet_multipliers : ndarray, shape (2 n,)
        Eigenvalues of ``monodromy``, by decreasing modulus. A contact that
        sticks during the period annihilates perturbations of its relative
        velocity (multiplier 0).
    neutral_multipliers : int
        How many of the multipliers are the neutral ``1`` of a stuck offset:
        each contact stuck during the whole period can stick at any offset (the
        periodic orbits then form a family), which leaves its relative
        displacement unchanged over a period.
    wear, normal_loads, slip_forces : ndarray, shape (n_friction,)
        Wear depth (m), normal load (N) and slip force ``mu F_N`` (N) per contact.
    samples : int
        Number ``N`` of uniform samples of the period in the time histories.
    first_harmonic : ndarray, shape (n, 2)
        Exact first Fourier coefficients ``(a1, b1)`` of each DOF (m),
        ``u ~ a1 cos(omega t) + b1 sin(omega t)``.
    half_peak_to_peak : ndarray, shape (n,)
        ``(max u - min u) / 2`` of each DOF over the period (m), exact extrema.
    relative_half_peak_to_peak : ndarray, shape (n_friction,)
        Same for the relative displacement of each friction contact (m).
    sliding_distance, friction_energy : ndarray, shape (n_friction,)
        Per period, exact (m, J).
    input_work, viscous_dissipation : float
        Per period (J); ``input_work = viscous_dissipation + friction_energy.sum()``
        on a periodic orbit.
    events : tuple of ContactEvent
        Contact state changes over one period.
    trajectory : Trajectory or None
        The exact motion over one period from ``y0`` (dense output:
        ``trajectory.evaluate(times)``); None when even that failed.
    """

    model: Model
    omega: float
    y0: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str
    monodromy: np.ndarray
    floquet_multipliers: np.ndarray
    neutral_multipliers: int
    wear: np.ndarray
    normal_loads: np.ndarray
    slip_forces: np.ndarray
    samples: int
    first_harmonic: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    sliding_distance: np.ndarray
    friction_energy: np.ndarray
    input_work: float
    viscous_dissipation: float
    events: tuple[ContactEvent, ...]
    trajectory: Trajectory | None = field(repr=False)

    @property
    def period(self) -> float:
        """Excitation period ``2 pi / omega`` (s)."""
        return 2 * np.pi / self.omega

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    @property
    def path(self) -> str:
        """How the solution was found: ``"shooting"``."""
        return "shooting"

    @property
    def unknowns(self) -> np.ndarray:
        """The shooting unknowns, the state ``y0`` at ``t = 0``: the guess of a neighbouring solve."""
        return self.y0

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude ``sqrt(a1^2 + b1^2)`` of each DOF (m), shape (n,)."""
        return np.hypot(self.first_harmonic[:, 0], self.first_harmonic[:, 1])

    @property
    def relative_amplitude(self) -> np.ndarray:
        """First-harmonic amplitude of the relative displacement of each contact (m), shape (n_friction,)."""
        rel = self.model.relative_map(self.model.friction) @ self.first_harmonic
        return np.hypot(rel[:, 0], rel[:, 1])

    @property
    def stable(self) -> bool:
        """True when every multiplier but the neutral ones lies strictly inside the unit circle."""
        mult = self.floquet_multipliers
        rest = np.delete(mult, np.argsort(np.abs(mult - 1))[: self.neutral_multipliers])
        return bool(np.abs(rest).max(initial=0.0) < 1.0)

    # -- time histories (computed on first access) ---------------------------------
    @cached_property
    def _histories(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        times = np.arange(self.samples) * (self.period / self.samples)
        nf, n = len(self.model.friction), self.model.n_dofs
        if self.trajectory is None:
            nan = np.full((2 * n, self.samples), np.nan)
            codes = np.full((nf, self.samples), STICK, np.int8)
            return times, nan, np.full((nf, self.samples), np.nan), codes
        states, forces, codes = self.trajectory.evaluate(times)
        return times, states, forces, codes

    @property
    def time(self) -> np.ndarray:
        """Sample times ``k T / N`` (s), shape (N,)."""
        return self._histories[0]

    @property
    def displacement(self) -> np.ndarray:
        """DOF displacements (m), shape (n, N)."""
        return self._histories[1][: self.model.n_dofs]

    @property
    def velocity(self) -> np.ndarray:
        """DOF velocities (m/s), shape (n, N)."""
        return self._histories[1][self.model.n_dofs :]

    @property
    def relative_displacement(self) -> np.ndarray:
        """``u_r = B u`` of every contact (m), shape (n_friction, N)."""
        return self.model.relative_map(self.model.friction) @ self.displacement

    @property
    def contact_force(self) -> np.ndarray:
        """Friction force of every contact (N), shape (n_friction, N)."""
        return self._histories[2]

    @property
    def state(self) -> np.ndarray:
        """:data:`~fretwear.model.STICK`, ``SLIP`` or ``OPEN`` of every contact, shape (n_friction, N)."""
        return self._histories[3]


# ---------------------------------------------------------------------------
# the solver
# ---------------------------------------------------------------------------
def _stuck_state(eng: Engine, g: np.ndarray) -> np.ndarray:
    """State at ``t = 0`` of the linear steady state with every loaded contact rigid (``B u = 0``)."""
    model, n, w = eng.model, eng.n, eng.omega
    Bs = eng.B[g > 0]
    N = linalg.null_space(Bs) if len(Bs) else np.eye(n)
    if N.shape[1] == 0:
        return np.zeros(2 * n)
    Z = N.T @ (model.K - w**2 * model.M + 1j * w * model.C) @ N
    try:
        U = N @ linalg.solve(Z, N.T @ (model.force_cos - 1j * model.force_sin))
    except linalg.LinAlgError:  # resonance of the stuck structure without damping
        U = N @ linalg.lstsq(Z, N.T @ (model.force_cos - 1j * model.force_sin))[0]
    u_static = N @ linalg.lstsq(N.T @ model.K @ N, N.T @ model.force_static)[0]
    return np.concatenate([u_static + U.real, (1j * w * U).real])


def _scaled_norm(eng: Engine, y: np.ndarray) -> float:
    return float(np.hypot(np.linalg.norm(y[: eng.n]), np.linalg.norm(y[eng.n :]) / eng.omega))


def _newton(eng: Engine, g: np.ndarray, y: np.ndarray, tol: float, max_iter: int):
    """Compiled Newton from ``y``: ``(status, y, converged, iterations, residual)``."""
    while True:
        status, need, y1, converged, iterations, residual, _ = kernels.newton(
            *model_arrays(eng), *eng.arrays(), g, y, tol, max_iter, _MAX_PHASES
        )
        if status != kernels.NEED_PATTERN:
            return status, y1, converged, iterations, residual
        eng.require(int(need))


def _settle(eng: Engine, g: np.ndarray, y: np.ndarray, periods: int, tol: float):
    """Compiled march of up to ``periods`` periods: ``(status, y, marched, change)``."""
    while True:
        status, need, y1, marched, change = kernels.settle(
            *model_arrays(eng), *eng.arrays(), g, y, periods, tol, _MAX_PHASES
        )
        if status != kernels.NEED_PATTERN:
            return status, y1, marched, change
        eng.require(int(need))


_STATUS = {
    kernels.DEGENERATE: "a cascade of contact events at one instant could not be resolved",
    kernels.NONFINITE: "the motion became unbounded (non-finite state)",
}


def _solve(eng: Engine, g: np.ndarray, guess, tol: float, max_iter: int, transient_periods: int):
    """Newton from the guess, the rigid linear state, marched states: ``(y, ok, its, res, msg)``."""
    tried: list[str] = []
    iterations, best = 0, None

    def attempt(name: str, y: np.ndarray):
        nonlocal iterations, best
        status, y1, converged, its, residual = _newton(eng, g, y, tol, max_iter)
        iterations += its
        if status == kernels.OK and converged:
            return y1, residual
        if status == kernels.OK and (best is None or residual < best[1]):
            best = (y1, residual)
        why = _STATUS[status] if status != kernels.OK else f"residual {residual:.2e}"
        tried.append(f"from {name}: {why}")
        return None

    found = None if guess is None else attempt("the guess", guess)
    y = guess
    if found is None:
        y = _stuck_state(eng, g)
        found = attempt("the rigid linear state", y)
    marched = 0
    for periods in _MARCHES:
        if found is not None or periods > transient_periods:
            break
        status, y, _, _ = _settle(eng, g, y, periods - marched, 0.0)
        marched = periods
        if status != kernels.OK:
            tried.append(f"marching: {_STATUS[status]}")
            break
        found = attempt(f"{periods} periods marched", y)
    if found is not None:
        return found[0], True, iterations, found[1], ""
    y, residual = best if best is not None else (y, np.inf)
    message = f"Newton on the period map did not reach the tolerance {tol:.1e} ({'; '.join(tried)})"
    return y, False, iterations, residual, message


def _solution(eng: Engine, g: np.ndarray, loads: np.ndarray, wear, y0: np.ndarray, converged: bool,
              iterations: int, residual: float, message: str, samples: int) -> ShootingSolution:  # fmt: skip
    model, n, nf, T = eng.model, eng.n, eng.nf, eng.period
    wear = np.zeros(nf) if wear is None else np.asarray(wear, dtype=float)
    try:
        traj = trajectory(eng, g, y0, 0.0, T, None, jacobian=True)
    except RuntimeError as exc:
        nan = np.full(n, np.nan)
        return ShootingSolution(
            model=model, omega=eng.omega, y0=y0, converged=False, iterations=iterations, residual=np.inf,
            message=f"{message}; the orbit could not be evaluated: {exc}".lstrip("; "),
            monodromy=np.full((2 * n, 2 * n), np.nan), floquet_multipliers=np.full(2 * n, np.nan + 0j),
            neutral_multipliers=0, wear=wear, normal_loads=loads, slip_forces=g,
            samples=samples, first_harmonic=np.full((n, 2), np.nan), half_peak_to_peak=nan,
            relative_half_peak_to_peak=np.full(nf, np.nan), sliding_distance=np.full(nf, np.nan),
            friction_energy=np.full(nf, np.nan), input_work=np.nan, viscous_dissipation=np.nan, events=(),
            trajectory=None,
        )  # fmt: skip
    rec = traj._record
    rows = np.vstack([np.eye(n), eng.B])
    hi, lo = kernels.extrema(
        rec.arrays[1], rec.arrays[5], rec.t, rec.length, rec.pattern, rec.X, len(rec.t), rows
    )
    hpp = (hi - lo) / 2
    residual = _scaled_norm(eng, traj.y - y0) / max(_scaled_norm(eng, y0), 1e-300)
    mult = np.linalg.eigvals(traj.jacobian)
    coef = 2 / T * traj.fourier
    always_stuck = np.all(traj.segment_state == STICK, axis=0) & (g > 0)
    return ShootingSolution(
        model=model,
        omega=eng.omega,
        y0=y0,
        converged=converged,
        iterations=iterations,
        residual=residual,
        message=message,
        monodromy=traj.jacobian,
        floquet_multipliers=mult[np.argsort(-np.abs(mult), kind="stable")],
        neutral_multipliers=int(always_stuck.sum()),
        wear=wear,
        normal_loads=loads,
        slip_forces=g,
        samples=samples,
        first_harmonic=np.column_stack([coef.real, -coef.imag]),
        half_peak_to_peak=hpp[:n],
        relative_half_peak_to_peak=hpp[n:],
        sliding_distance=traj.sliding_distance,
        friction_energy=traj.friction_energy,
        input_work=traj.input_work,
        viscous_dissipation=traj.viscous_dissipation,
        events=traj.events,
        trajectory=traj,
    )


def _check_samples(samples: int) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 4:
        raise ValueError(f"samples must be an integer >= 4, got {samples!r}")
    return int(samples)


def _check_options(tol: float, max_iter: int) -> None:
    if not (isinstance(tol, (int, float, np.floating)) and 0 < tol < 1):
        raise ValueError(f"tol (relative periodicity residual) must be in (0, 1), got {tol!r}")
    if isinstance(max_iter, bool) or not isinstance(max_iter, (int, np.integer)) or max_iter < 0:
        raise ValueError(f"max_iter must be an integer >= 0, got {max_iter!r}")


def shooting(
    model: Model,
    omega: float,
    y_guess=None,
    *,
    wear=None,
    tol: float = 1e-12,
    max_iter: int = 30,
    samples: int = 512,
    transient_periods: int = 400,
) -> ShootingSolution:
    """Periodic response by shooting: Newton on ``y0 - P(y0) = 0``, ``P`` the period map.

    The Jacobian is the exact monodromy matrix (step propagators and event
    saltation matrices). Newton steps are least-squares steps (the Jacobian
    is singular on orbits stuck during the whole period, whose stuck offset is
    arbitrary) with backtracking on the periodicity residual.

    Parameters
    ----------
    model : Model
        Structure with friction contacts only; ``M`` positive definite.
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y_guess : array_like, shape (2 n,), optional
        Guess of the state at ``t = 0`` (e.g. the :attr:`~ShootingSolution.unknowns`
        of a neighbouring solution). Without one, or if Newton fails from it,
        the cold start of the module docstring follows.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    tol : float
        Target periodicity residual (see :attr:`ShootingSolution.residual`), in (0, 1).
    max_iter : int
        Largest number of Newton iterations per start.
    samples : int
        Number ``N`` of uniform samples of the period in the time histories.
    transient_periods : int
        Largest number of periods marched before a restart (marches of 20,
        100 and 400 periods, up to this number; 0: no marching).

    Returns
    -------
    ShootingSolution
        ``iterations`` counts the Newton iterations of every start; a solve
        that fails has ``converged=False`` and says why in ``message``.
    """
    eng, g, loads = engine_loads(model, omega, wear)
    samples = _check_samples(samples)
    _check_options(tol, max_iter)
    guess = None if y_guess is None else check_state(eng, y_guess, "y_guess")
    y, converged, iterations, residual, message = _solve(eng, g, guess, tol, max_iter, transient_periods)
    return _solution(eng, g, loads, wear, y, converged, iterations, residual, message, samples)


def periodic_state(
    model: Model, omega: float, y_guess, *, wear=None, tol: float = 1e-12, max_iter: int = 30
) -> tuple[np.ndarray, bool]:
    """State at ``t = 0`` of the periodic orbit reached by Newton from ``y_guess``.

    The Newton iterations of :func:`shooting` from one start, without its
    post-processing (extrema, Floquet multipliers): a cheap projection of a
    nearby state onto the periodic orbit, e.g. to follow an orbit that drifts
    with wear.

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
    _check_options(tol, max_iter)
    y = check_state(eng, y_guess, "y_guess")
    status, y1, converged, _, _ = _newton(eng, g, y, tol, max_iter)
    return (y1, converged) if status == kernels.OK else (y, False)


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
        Number of uniform samples of the period in the time histories.

    Returns
    -------
    ShootingSolution
        With ``iterations`` the number of periods marched.
    """
    eng, g, loads = engine_loads(model, omega, wear)
    samples = _check_samples(samples)
    y = _stuck_state(eng, g) if y_guess is None else check_state(eng, y_guess, "y_guess").copy()
    status, y, marched, change = _settle(eng, g, y, int(max_periods), float(tol))
    converged = status == kernels.OK and change <= tol
    if status != kernels.OK:
        message = _STATUS[status]
    elif not converged:
        message = f"the change over one period is {change:.2e} > tol = {tol:.1e} after {marched} periods"
    else:
        message = ""
    return _solution(eng, g, loads, wear, y, converged, marched, change, message, samples)


def shooting_sweep(model: Model, omegas, **options) -> list[ShootingSolution]:
    """Exact periodic responses by :func:`shooting` at ``omegas`` (rad/s), each seeded by its predecessor.

    A solve that fails is kept in the list (``converged=False``, with its
    ``message``); the next one then starts cold.
    """
    out, guess = [], None
    for w in np.asarray(omegas, dtype=float):
        sol = shooting(model, w, guess, **options)
        out.append(sol)
        guess = sol.unknowns if sol.converged else None
    return out
