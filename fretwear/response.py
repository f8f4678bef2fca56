"""What every periodic solution exposes, whichever solver found it.

Harmonic balance (:class:`fretwear.hbm.PeriodicSolution`) and shooting on the
exact integrator (:class:`fretwear.time.ShootingSolution`) return objects with
the attributes of :class:`PeriodicResponse`, so that no caller branches on the
solver. Signals are sampled over one period on the uniform grid ``t_k = k T / N``.
"""

from __future__ import annotations

from typing import Protocol, runtime_checkable

import numpy as np

from .model import Model

__all__ = ["PeriodicResponse", "RESPONSE_ATTRIBUTES"]


@runtime_checkable
class PeriodicResponse(Protocol):
    """A periodic response at one excitation frequency, and how it was found.

    Attributes
    ----------
    model : Model
    omega, frequency : float
        Excitation frequency (rad/s, Hz).
    converged : bool
    iterations : int
    residual : float
        Final residual of the solver (DLFT: ``max |R|`` relative to the largest
        force; shooting: periodicity ``|y(T) - y(0)|``, relative).
    message : str
        Reason of a failure, empty on success.
    path : str
        How it was found (``"dlft"``, ``"linear-stuck"``, ``"shooting"``, ...).
    unknowns : ndarray
        The solver's own unknowns, reusable as the ``guess`` of a neighbouring solve.
    floquet_multipliers : ndarray or None
        Eigenvalues of the monodromy matrix where the solver knows them (shooting).
    wear, normal_loads : ndarray, shape (n_friction,)
        Wear depth (m) and normal load (N) of each friction contact.
    time : ndarray, shape (N,)
        Sample times (s).
    displacement : ndarray, shape (n, N)
        DOF displacements (m).
    relative_displacement, contact_force, state : ndarray, shape (n_contacts, N)
        Relative displacement ``B u`` (m), contact force (N) and state code
        (:data:`~fretwear.model.STICK`, ``SLIP``, ``OPEN``) of each contact.
    amplitude, half_peak_to_peak : ndarray, shape (n,)
        First-harmonic amplitude and half peak-to-peak displacement of each DOF (m).
    relative_amplitude, relative_half_peak_to_peak : ndarray, shape (n_contacts,)
        The same for each contact's relative displacement (m).
    sliding_distance, friction_energy : ndarray, shape (n_friction,)
        Distance slid (m) and energy dissipated (J) per period by each friction contact.
    input_work, viscous_dissipation : float
        Work of the external force and viscous dissipation per period (J).
    """

    model: Model
    omega: float
    converged: bool
    iterations: int
    residual: float

    @property
    def frequency(self) -> float: ...
    @property
    def message(self) -> str: ...
    @property
    def path(self) -> str: ...
    @property
    def unknowns(self) -> np.ndarray: ...
    @property
    def floquet_multipliers(self) -> np.ndarray | None: ...
    @property
    def wear(self) -> np.ndarray: ...
    @property
    def normal_loads(self) -> np.ndarray: ...
    @property
    def time(self) -> np.ndarray: ...
    @property
    def displacement(self) -> np.ndarray: ...
    @property
    def relative_displacement(self) -> np.ndarray: ...
    @property
    def contact_force(self) -> np.ndarray: ...
    @property
    def state(self) -> np.ndarray: ...
    @property
    def amplitude(self) -> np.ndarray: ...
    @property
    def half_peak_to_peak(self) -> np.ndarray: ...
    @property
    def relative_amplitude(self) -> np.ndarray: ...
    @property
    def relative_half_peak_to_peak(self) -> np.ndarray: ...
    @property
    def sliding_distance(self) -> np.ndarray: ...
    @property
    def friction_energy(self) -> np.ndarray: ...
    @property
    def input_work(self) -> float: ...
    @property
    def viscous_dissipation(self) -> float: ...


#: the attribute names of the protocol (the tests check every solver's result against them)
RESPONSE_ATTRIBUTES: tuple[str, ...] = tuple(
    name for name in dir(PeriodicResponse) if not name.startswith("_")
) + tuple(PeriodicResponse.__annotations__)
