"""The DLFT response over frequency: sweeps and the branch through folds.

* :func:`sweep`: the response at given frequencies, each solve warm-started
  from its neighbours (secant predictor, Newton, then the global Newton
  homotopy of ``fretwear.hbm.periodic``, then a cold solve), with the
  condensation of every frequency computed at once;
* :func:`continuation`: the whole branch over a frequency band, folds
  included, by pseudo-arc-length continuation in frequency
  (:func:`fretwear.hbm.arclength.track`) on the DLFT residual.

The cold start of a single-frequency solve (exact load continuation) lives
in ``fretwear.hbm.periodic``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..model import Model
from . import compiled_sweep, dlft
from .arclength import Evaluate, track
from .condensation import Condensed, condense
from .periodic import Problem, newton_homotopy, solve_problem
from .solution import PeriodicSolution
from .strategy import NewtonResult

__all__ = ["Sweep", "sweep", "check_omegas", "Branch", "continuation"]

# -- frequency ------------------------------------------------------------------


def _x_scale(problem: Problem) -> float:
    """Typical relative displacement (m): slip force over the fundamental condensed stiffness."""
    H = problem.basis.size
    z1 = np.abs(np.diag(problem.Z)).reshape(problem.n_active, H)[:, problem.basis.orders == 1].max()
    f = max(np.abs(problem.limits[problem.kinds == dlft.FRICTION]).max(initial=0), np.abs(problem.F).max())
    return max(f / max(z1, 1e-300), 1e-300)


#: the keywords of a sweep or a continuation that go to every :class:`Problem`
SETTINGS = ("samples", "wear", "half_wave")


def _settings(harmonics: int, settings: dict) -> dict:
    """``harmonics`` and ``settings`` as the keywords of :class:`Problem`; other keywords raise ValueError."""
    unknown = sorted(set(settings) - set(SETTINGS))
    if unknown:
        raise ValueError(f"{unknown[0]!r} is not an option of a sweep or a continuation: besides its own "
                         f"(eps, tol, ...) it takes {', '.join(SETTINGS)}")  # fmt: skip
    return dict(harmonics=harmonics, **settings)


def _frequency_evaluate(model: Model, settings: dict, eps) -> Evaluate:
    """Residual, Jacobian and ``dR/d omega``.

    ``R = Z x - F + Psi lambda(Phi (F + (E - Z) x))`` with ``E = diag(eps)``, so
    ``dR/d omega = (I - A) (dZ x - dF) + A dE x``; the default penalty follows
    the condensed stiffness and moves with omega, a user penalty does not.
    """

    def evaluate(x, omega):
        p = Problem(model, omega, eps=eps, derivative=True, **settings)
        R, J, A, *_ = p.evaluate(x)
        A[p.kinds == dlft.JENKINS] = 0.0  # a Jenkins force depends on x alone, not on Z(omega) or F
        nc, H = p.n_active, p.basis.size
        v = (p.dZ @ x - p.force_scale * p.dF0).reshape(nc, H)
        dR = v - np.einsum("cij,cj->ci", A, v - p.deps[:, None] * x.reshape(nc, H))
        return R, J, dR.reshape(-1)

    return evaluate


@dataclass
class Sweep:
    """Responses at a sequence of frequencies (see :func:`sweep`)."""

    solutions: list[PeriodicSolution]

    @property
    def omega(self) -> np.ndarray:
        return np.array([s.omega for s in self.solutions])

    @property
    def converged(self) -> np.ndarray:
        return np.array([s.converged for s in self.solutions])

    def to_xarray(self):
        """The responses along ``frequency`` (Hz) as an ``xarray.Dataset``, with units and long names.

        ``amplitude`` per ``dof``, ``converged``, ``residual``; per contact the relative
        amplitudes, sliding distances and energies (per ``pair`` for contact pairs).
        ``Sweep(fretwear.shooting_sweep(...)).to_xarray()`` converts a shooting sweep.
        """
        from .._xarray import sweep_dataset

        return sweep_dataset(self.solutions)


def check_omegas(omegas) -> np.ndarray:
    """``omegas`` as a new 1-D float array, checked: non-empty, finite, > 0 (rad/s)."""
    omegas = np.array(omegas, dtype=float)  # a copy: contiguous and writable, as the compiled sweep takes it
    if omegas.ndim != 1 or omegas.size == 0 or np.any(~np.isfinite(omegas)) or np.any(omegas <= 0):
        raise ValueError(
            f"omegas must be a non-empty 1-D array of finite frequencies > 0 rad/s, got {omegas}"
        )
    return omegas


def sweep(
    model: Model,
    omegas,
    harmonics: int = 7,
    *,
    eps=None,
    tol: float = 1e-10,
    max_iter: int = 50,
    compiled: bool = True,
    **settings,
) -> Sweep:
    """Periodic responses at the frequencies ``omegas`` (rad/s), in the given order.

    Each point starts from a secant prediction through its two predecessors:
    Newton first, then the exact Newton homotopy from the prediction, then a
    cold solve by load continuation (see ``fretwear.hbm.periodic.solve_problem()``).
    A point that still fails is reported (``converged=False``) and the sweep
    goes on from the last good point. Points whose stuck solution is exact take
    no nonlinear solve.

    The whole sweep (condensation at every frequency, predictions, Newton,
    homotopies) runs in one compiled call (``fretwear.hbm.compiled_sweep``);
    with ``compiled=False`` each point goes through ``solve_problem()`` in
    Python instead: the reference the compiled sweep is checked and timed
    against, with the same answers (to round-off), several times slower.
    ``settings``: ``samples``, ``wear``, ``half_wave`` as :func:`fretwear.solve_periodic`.
    """
    omegas = check_omegas(omegas)
    settings = _settings(harmonics, settings)
    if compiled and all(c.kt is None for c in model.friction):  # Jenkins contacts: solved in x, below
        out = compiled_sweep.solve(model, omegas, settings, eps, tol, max_iter)
        return Sweep(
            [s if isinstance(s, PeriodicSolution) else solve_problem(s, None, tol, max_iter) for s in out]
        )
    out = []
    previous: list[tuple[float, np.ndarray]] = []  # converged points (one active set: wear is fixed)
    first = Problem(model, omegas[0], eps=eps, **settings)
    stiffness = first.n_active and first.form == "stiffness"  # the receptance form condenses per point
    batch = condense(model, first.B, omegas, first.basis) if stiffness else None
    for i, omega in enumerate(omegas):
        cond = Condensed(batch.Z[i], batch.F[i]) if batch is not None else None
        problem = Problem(model, omega, eps=eps, condensed=cond, **settings)
        guess = None
        if len(previous) >= 2:  # secant predictor
            (w0, x0), (w1, x1) = previous[-2:]
            guess = x1 + (omega - w1) / (w1 - w0) * (x1 - x0)
        elif previous:
            guess = previous[-1][1]
        sol = solve_problem(problem, guess, tol, max_iter)
        out.append(sol)
        if sol.converged and problem.n_active:
            previous.append((omega, sol.unknowns))
    return Sweep(out)


@dataclass
class Branch:
    """Solutions along a frequency branch, in arc-length order (see :func:`continuation`)."""

    solutions: list[PeriodicSolution]
    converged: bool
    message: str

    @property
    def omega(self) -> np.ndarray:
        return np.array([s.omega for s in self.solutions])

    @property
    def folds(self) -> np.ndarray:
        """Indices where the frequency turns back (limit points lie between i and i+1)."""
        d = np.sign(np.diff(self.omega))
        return np.flatnonzero(d[1:] * d[:-1] < 0) + 1


def continuation(
    model: Model,
    omega_start: float,
    omega_end: float,
    harmonics: int = 7,
    *,
    eps=None,
    tol: float = 1e-10,
    h_max: float = 0.02,
    max_steps: int = 5000,
    **settings,
) -> Branch:
    """Follow the response branch from ``omega_start`` to ``omega_end`` (rad/s) through folds.

    Pseudo-arc-length continuation in frequency; every accepted point is
    returned, each the same solution :func:`solve_periodic` would give there
    (same penalty), and ``Branch.folds`` locates the turning points.
    ``settings``: ``samples``, ``wear``, ``half_wave`` as :func:`fretwear.solve_periodic`.
    """
    settings = _settings(harmonics, settings)
    first = Problem(model, omega_start, eps=eps, **settings)
    sol0 = solve_problem(first, None, tol, 50)
    if not sol0.converged or first.n_active == 0:
        return Branch([sol0], sol0.converged, sol0.message or "no active contact: linear response")
    evaluate = _frequency_evaluate(model, settings, eps)

    def solve_at(x, omega):
        if omega <= 0:
            return None
        res = newton_homotopy(Problem(model, omega, eps=eps, **settings), x, tol)
        return res.x if res.converged else None

    lo, hi = sorted((omega_start, omega_end))
    tr = track(
        evaluate, sol0.unknowns, omega_start, omega_end, x_scale=_x_scale(first),
        tol=tol * first.residual_scale(), h_max=h_max, max_steps=max_steps, record=True,
        stop_outside=(lo * (1 - 1e-9), hi * (1 + 1e-9)), solve_at=solve_at,
    )  # fmt: skip
    sols = [sol0]
    for x, omega in tr.points:
        p = Problem(model, omega, eps=eps, **settings)
        R = p.evaluate(x, jacobian=False)[0]
        res = NewtonResult(x, True, 0, float(np.abs(R).max() / p.residual_scale()))
        sols.append(PeriodicSolution.build(p, x, res, "dlft-continuation"))
    return Branch(sols, tr.converged, tr.message)
