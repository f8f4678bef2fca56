"""The periodic response at a wear state, as the slow-time methods call it: exact (shooting) or DLFT.

Wear changes the dynamics only through the normal loads ``F_N,j(w_j)``
(eq. 30d): :class:`Dynamics` solves the periodic response at each wear state
the slow-time scheme asks for, warm-started from the previous one;
:func:`resolve_dynamics` chooses the dynamics, :func:`observables` recovers the
response quantities a history records from DLFT contact forces.
"""

from __future__ import annotations

from dataclasses import replace
from functools import partial

import numpy as np

from ..disk.cyclic import Sector, is_tuned_disk
from ..hbm import strategy
from ..hbm.condensation import recover
from ..hbm.harmonics import amplitude, extrema, full_synthesis
from ..hbm.periodic import Problem, follow_normal_load, solve_problem, steps
from ..hbm.solution import PeriodicSolution
from ..model import Model
from ..time.patterns import unsupported
from ..time.shooting import shooting

__all__ = ["Dynamics", "DYNAMICS", "DEFAULT_HARMONICS", "resolve_dynamics", "observables"]

#: the periodic dynamics a slow-time method can run on (``dynamics=``)
DYNAMICS = ("auto", "shooting", "dlft")
#: ``Nh`` of the DLFT dynamics when ``dynamics="dlft"`` is asked for without ``harmonics``
DEFAULT_HARMONICS = 21


def resolve_dynamics(model: Model, dynamics: str = "auto", harmonics: int | None = None,
                     samples: int | None = None) -> str:  # fmt: skip
    """The dynamics that ``dynamics`` names for ``model``: ``"shooting"`` or ``"dlft"``.

    ``"auto"`` is the exact event-driven dynamics (``"shooting"``) wherever they
    apply (friction contacts only, ``M`` positive definite, independent
    contacts), unless harmonic-balance settings (``harmonics``, ``samples``) are
    given: asking for ``Nh`` asks for the DLFT approximation. ``"shooting"``
    on a model it does not apply to, or with those settings, is a ``ValueError``.
    """
    if dynamics not in DYNAMICS:
        raise ValueError(f"dynamics must be one of {', '.join(map(repr, DYNAMICS))}, got {dynamics!r}")
    dlft_settings = harmonics is not None or samples is not None
    if dynamics == "auto":
        return "dlft" if dlft_settings or unsupported(model) else "shooting"
    if dynamics == "shooting":
        if reason := unsupported(model):
            raise ValueError(
                f"dynamics='shooting' does not apply to this model: the time integrator {reason}"
            )
        if dlft_settings:
            raise ValueError("harmonics and samples are settings of the DLFT dynamics: "
                             "dynamics='shooting' (exact, event-driven) takes neither")  # fmt: skip
    return dynamics


class Dynamics:
    """Periodic response at a wear state, warm-started from the previous call (DLFT or shooting).

    A tuned shrouded bladed disk on the DLFT dynamics is solved on one sector
    (``fretwear.disk.cyclic``): its contacts wear alike, and the sector solve
    is the full disk's to round-off, 14-94 times faster.
    """

    def __init__(self, model, omega, harmonics, samples, kw, dynamics):
        self.model, self.omega, self.kw = model, omega, kw
        self.kind = resolve_dynamics(model, dynamics, harmonics, samples)
        self.harmonics = (harmonics or DEFAULT_HARMONICS) if self.kind == "dlft" else None
        self.solves = 0
        self.guess = None
        self.sector = None
        if self.kind == "dlft" and is_tuned_disk(model):
            self.sector = Sector.of(model, self.harmonics, samples)
        elif self.kind == "dlft":
            self.problem = Problem(model, omega, self.harmonics, samples)

    def _solve(self, problem: Problem) -> PeriodicSolution:
        """Warm start from the last solution: the solve strategy with a short Newton and, for one
        contact, the exact normal-load walk from the last wear state as its homotopy."""
        last = getattr(self, "last", None)
        if self.guess is None or last is None or self.guess.shape != (problem.size,):
            return solve_problem(problem)
        how = replace(steps(problem), guess_steps=8)
        if problem.n_active == 1 and last.n_active == 1:  # the walk starts on the last solution, exact
            walk = partial(follow_normal_load, last, self.guess, problem)
            how = replace(how, homotopy=lambda _x, tol: walk(tol), homotopy_path="dlft-load-walk")
        res, path = strategy.solve(how, self.guess, 1e-10, 50)  # no linear check: the last state slipped
        return PeriodicSolution.build(problem, res.x, res, path)

    def __call__(self, wear: np.ndarray, keep: bool = True):
        """Return ``(rate dw/dN, sliding distance, solution)`` or ``None`` if the solve fails."""
        self.solves += 1
        loads = self.model.normal_loads(wear)
        if self.sector is not None:  # every contact worn alike (wear[0]: they differ by round-off)
            sol = self.sector.solve(self.omega, self.harmonics, self.guess, wear=float(wear[0]))
        elif self.kind == "dlft":
            problem = self.problem.with_wear(wear)
            sol = self._solve(problem)
            self.last = problem if keep and sol.converged else getattr(self, "last", None)
        else:
            sol = shooting(self.model, self.omega, self.guess, wear=wear)
        if not sol.converged:
            return None
        if keep:
            self.guess = sol.unknowns
        slid = np.asarray(sol.sliding_distance)
        return self.kw * loads * slid, slid, sol


def observables(problem: Problem, lam: np.ndarray):
    """Amplitude and half peak-to-peak of every DOF (m), and relative half peak-to-peak (m), of the
    responses with contact-force harmonics ``lam`` (K, nc H) in ``problem``'s basis.

    The DOF harmonics are affine in ``lam`` (eq. 10-11), so one linear map
    recovers all ``K`` responses at once; the extrema are exact (refined from
    4 samples per shortest period).
    """
    model, b = problem.model, problem.basis
    nh = b.harmonics
    # the responses to no contact force and to each unit one, in one batched recovery
    E = np.concatenate([np.zeros((1, problem.size)), np.eye(problem.size)])
    E = E.reshape(-1, problem.n_active, b.size)
    R = recover(model, problem.B, np.full(len(E), float(problem.omega)), nh, b.to_full(E))
    base, unit = R[0], R[1:] - R[0]
    U = base[None] + np.einsum("kj,jnm->knm", lam, unit)  # (K, n, 2 Nh + 1)
    K, n = U.shape[:2]
    rel = np.einsum("cn,knm->kcm", model.relative_map(), U)
    rows = np.concatenate([U.reshape(-1, U.shape[-1]), rel.reshape(-1, U.shape[-1])])
    noise = 1e-12 * np.abs(U).max(initial=0.0)  # relative motions are differences of DOF motions: round-off
    hi, lo = extrema(rows, rows @ full_synthesis(nh, 8 * nh + 8).T, noise)
    half = (hi - lo) / 2
    return amplitude(U), half[: K * n].reshape(K, n), half[K * n :].reshape(K, -1)
