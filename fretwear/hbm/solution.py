"""The periodic solution and the quantities derived from it per period.

Time histories are sampled on the DLFT grid of one full period
(``t_n = n T / N``); for a half-wave solve the second half follows from
``u(t + T/2) = -u(t)``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property

import numpy as np

from ..model import Model
from . import dlft
from .condensation import recover
from .harmonics import amplitude, extrema, full_synthesis
from .problem import Problem
from .strategy import NewtonResult

__all__ = ["PeriodicSolution"]


@dataclass(eq=False)
class PeriodicSolution:
    """Periodic response at one frequency and its status.

    Attributes
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s).
    harmonics, samples : int
        ``Nh`` and the samples per period ``N`` of the DLFT grid.
    half_wave : bool
        Whether the odd-harmonics, half-period reduction was used.
    path : str
        ``"linear-open"``, ``"linear-stuck"`` (exact, no nonlinear solve),
        ``"dlft"`` or ``"dlft-homotopy"``.
    converged : bool
    iterations : int
        Newton iterations (summed over a homotopy).
    residual : float
        Final ``max |R|`` relative to the largest external or friction force.
    message : str
        Reason of a failure, empty on success.
    wear, normal_loads : ndarray, shape (n_friction,)
        Wear depth (m) and normal load (N) of each friction contact.
    unknowns : ndarray
        Solver unknowns (harmonics of the active contact coordinates), reusable
        as the ``guess`` of a neighbouring solve.
    problem : Problem
        The solved problem (condensation, basis, penalties).

    The time histories and harmonics (``dof_harmonics``, ``displacement``,
    ``contact_force``, ``state``, ``slip``, ...) are computed on first access.
    """

    model: Model
    omega: float
    harmonics: int
    samples: int
    half_wave: bool
    path: str
    converged: bool
    iterations: int
    residual: float
    message: str
    wear: np.ndarray
    normal_loads: np.ndarray
    unknowns: np.ndarray
    problem: Problem = field(repr=False, compare=False)
    _fields = None  # not a field: the batch provider of ``build``, if any

    @classmethod
    def build(
        cls,
        problem: Problem,
        x: np.ndarray | None,
        res: NewtonResult,
        path: str,
        fields: Callable[[], tuple[tuple, np.ndarray]] | None = None,
    ) -> PeriodicSolution:
        """The solution of ``problem`` at unknowns ``x``; time histories are computed on first access.

        ``fields``: a function that returns the march (contact force, slip
        variable, state over the full period and the force harmonics) and the
        DOF harmonics, when a sweep computes them for all its frequencies at
        once (on the first request of any of them).
        """
        basis = problem.basis
        sol = cls(
            model=problem.model,
            omega=problem.omega,
            harmonics=basis.harmonics,
            samples=basis.samples,
            half_wave=basis.half_wave,
            path=path,
            converged=res.converged,
            iterations=res.iterations,
            residual=res.residual,
            message=res.message,
            wear=problem.wear,
            normal_loads=problem.normal_loads,
            unknowns=np.zeros(0) if x is None else x,
            problem=problem,
        )
        sol._fields = fields
        return sol

    @cached_property
    def _march(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """Contact force, slip variable, state over the full period, and the force harmonics."""
        if self._fields is not None:
            return self._fields()[0]
        problem, basis = self.problem, self.problem.basis
        n_all, N = len(self.model.contacts), self.samples
        force = np.zeros((n_all, N))
        slip = np.zeros((n_all, N))
        state = np.full((n_all, N), dlft.OPEN, dtype=np.int8)
        lam_h = np.zeros((problem.n_active, 2 * self.harmonics + 1))
        if problem.n_active:
            _, _, _, lam, X, st = problem.evaluate(self.unknowns, jacobian=False)
            lam_h = basis.to_full(lam @ basis.analysis.T)
            if basis.half_wave:
                lam, X, st = np.hstack([lam, -lam]), np.hstack([X, -X]), np.hstack([st, st])
            force[problem.active_index], slip[problem.active_index], state[problem.active_index] = lam, X, st
        return force, slip, state, lam_h

    @cached_property
    def dof_harmonics(self) -> np.ndarray:
        """Coefficients ``[a0, a1, b1, ...]`` of every DOF (m), shape (n, 2 Nh + 1), eq. 10."""
        if self._fields is not None:
            return self._fields()[1]
        p = self.problem
        return recover(self.model, p.B, self.omega, self.harmonics, self._march[3], p.force_scale)

    @cached_property
    def time(self) -> np.ndarray:
        """Sample times over one period (s), shape (N,)."""
        return np.arange(self.samples) * (2 * np.pi / self.omega / self.samples)

    @cached_property
    def displacement(self) -> np.ndarray:
        """DOF displacements on the grid (m), shape (n, N)."""
        return self.dof_harmonics @ full_synthesis(self.harmonics, self.samples).T

    @cached_property
    def _relative_map(self) -> np.ndarray:
        return self.model.relative_map()

    @cached_property
    def relative_displacement(self) -> np.ndarray:
        """``u_r = B u`` of every contact of the model, friction first (m), shape (n_contacts, N)."""
        return self._relative_map @ self.displacement

    @property
    def contact_force(self) -> np.ndarray:
        """Contact force ``lambda`` from the DLFT march (N), shape (n_contacts, N); zero when open."""
        return self._march[0]

    @property
    def state(self) -> np.ndarray:
        """Sample states, int8 (n_contacts, N): 0 stick (or closed), 1 slip, 2 open/separated."""
        return self._march[2]

    @cached_property
    def slip(self) -> np.ndarray:
        """Slip variable ``X`` of the march (m), shape (n_contacts, N): it moves only while slipping.

        For a contact left out of the solve (open), the relative displacement.
        """
        slip = self._march[1].copy()
        mu = np.array([c.mu for c in self.model.friction])
        inactive = np.flatnonzero(mu * self.normal_loads == 0)  # left out of the solve: open
        if inactive.size:
            slip[inactive] = self.relative_displacement[inactive]
        return slip

    @property
    def floquet_multipliers(self) -> None:
        """Not known to harmonic balance (``None``); shooting gives them (:func:`fretwear.shooting`)."""
        return None

    # -- amplitudes -----------------------------------------------------------
    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude of every DOF (m), shape (n,)."""
        return amplitude(self.dof_harmonics)

    @cached_property
    def half_peak_to_peak(self) -> np.ndarray:
        """Half peak-to-peak displacement of every DOF (m), shape (n): exact extrema of the series."""
        hi, lo = extrema(self.dof_harmonics, self.displacement)
        return (hi - lo) / 2

    @property
    def relative_harmonics(self) -> np.ndarray:
        """Coefficients of every contact's relative displacement (m), shape (n_contacts, 2 Nh + 1)."""
        return self._relative_map @ self.dof_harmonics

    @property
    def relative_amplitude(self) -> np.ndarray:
        """First-harmonic amplitude of every contact's relative displacement (m)."""
        return amplitude(self.relative_harmonics)

    @cached_property
    def relative_half_peak_to_peak(self) -> np.ndarray:
        """Half peak-to-peak relative displacement of every contact (m): exact extrema of the series."""
        noise = 1e-12 * np.abs(self.dof_harmonics).max(initial=0.0)  # a difference of DOF motions: round-off
        hi, lo = extrema(self.relative_harmonics, self.relative_displacement, noise)
        return (hi - lo) / 2

    # -- per-period quantities ------------------------------------------------
    @property
    def sliding_distance(self) -> np.ndarray:
        """Distance slid per period by each friction contact (m): total variation of ``X``.

        ``X`` moves only in slip, so sticking samples contribute nothing; this is
        the ``integral |du_r/dt| dt`` of Archard's law (eq. 15, 30c) on the grid.
        """
        nf = len(self.model.friction)
        return np.abs(np.diff(self.slip[:nf], axis=1, append=self.slip[:nf, :1])).sum(axis=1)

    @property
    def friction_energy(self) -> np.ndarray:
        """Energy dissipated by each friction contact per period (J): ``sum lambda dX``."""
        nf = len(self.model.friction)
        dX = np.diff(self.slip[:nf], axis=1, prepend=self.slip[:nf, -1:])
        return np.sum(self.contact_force[:nf] * dX, axis=1)

    @property
    def _velocity(self) -> np.ndarray:
        k = np.arange(1, self.harmonics + 1)
        a, b = self.dof_harmonics[:, 1::2], self.dof_harmonics[:, 2::2]
        dU = np.zeros_like(self.dof_harmonics)
        dU[:, 1::2], dU[:, 2::2] = k * self.omega * b, -k * self.omega * a
        return dU @ full_synthesis(self.harmonics, self.samples).T

    def _period_integral(self, signal: np.ndarray) -> float:
        return float(np.sum(signal) * (2 * np.pi / self.omega) / self.samples)

    @property
    def input_work(self) -> float:
        """Work of the external force over one period (J)."""
        m = self.model
        phase = self.omega * self.time
        F = (
            m.force_static[:, None]
            + np.outer(m.force_cos, np.cos(phase))
            + np.outer(m.force_sin, np.sin(phase))
        )
        return self._period_integral(np.sum(F * self._velocity, axis=0))

    @property
    def viscous_dissipation(self) -> float:
        """Energy dissipated by viscous damping over one period (J)."""
        v = self._velocity
        return self._period_integral(np.einsum("it,ij,jt->t", v, self.model.C, v))

    @property
    def contact_work(self) -> float:
        """Work of the contact forces on the relative motion over one period (J).

        ``integral lambda . du_r/dt dt`` on the DLFT grid; it closes the energy
        balance ``input_work = viscous_dissipation + contact_work`` exactly at
        convergence, and tends to ``friction_energy`` as ``Nh`` grows.
        """
        v_rel = self._relative_map @ self._velocity
        return self._period_integral(np.sum(self.contact_force * v_rel, axis=0))

    def to_xarray(self):
        """The solution as an ``xarray.Dataset``, with units and long names.

        Signals over one period on ``time`` (s): ``displacement`` per ``dof``,
        ``relative_displacement``, ``contact_force`` and ``state`` per ``contact``;
        amplitudes per DOF and contact; ``w``, ``normal_load``, ``sliding_distance``
        and ``friction_energy`` per ``friction_contact``; the solve's status in the attributes.
        """
        from .._xarray import periodic_dataset

        return periodic_dataset(self)

    def _repr_html_(self) -> str:
        from .._html import summary_html

        return summary_html(self)

    @property
    def slipping(self) -> np.ndarray:
        """True for each friction contact that slips somewhere in the period."""
        nf = len(self.model.friction)
        return np.any(self.state[:nf] == dlft.SLIP, axis=1)
