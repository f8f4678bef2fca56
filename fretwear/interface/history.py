"""The record of a nodal wear history of an interface: profiles of wear, pressure and slip over ``N``.

Shared by the slow-time methods of ``fretwear.interface.wear`` (stepping)
and ``fretwear.interface.polynomial``.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy.interpolate import CubicHermiteSpline
from scipy.optimize import brentq

from ..hbm.harmonics import full_synthesis
from .contact import SLIP, STICK
from .periodic import InterfaceSolution

__all__ = ["InterfaceWearHistory", "cycle_state", "fretting_loop", "shear_traction"]


def cycle_state(state: np.ndarray) -> np.ndarray:
    """What each pair does over the cycle, from its states at the samples (nc, N): one code per pair.

    1 where the pair slips at some sample, else 0 where it is in contact at some sample (it sticks, never
    slips: Mindlin's stick zone), else 2 (open the whole cycle: outside the contact).
    """
    state = np.asarray(state)
    return np.where((state == SLIP).any(axis=1), 1, np.where((state == STICK).any(axis=1), 0, 2))


def shear_traction(sol: InterfaceSolution) -> np.ndarray:
    """Shear traction magnitude ``|lambda_T| / A`` per pair and sample (Pa), shape (nc, N).

    ``|lambda_T|`` is the norm of the two tangential components with the 2-D friction law (the cone), the
    absolute value of the one component otherwise.
    """
    lam = sol.tangential_force
    magnitude = np.hypot(lam[..., 0], lam[..., 1]) if lam.ndim == 3 else np.abs(lam)
    return magnitude / sol.area[:, None]


def fretting_loop(sol: InterfaceSolution, dof: int | str) -> tuple[np.ndarray, np.ndarray]:
    """The fretting loop of a periodic solution: displacement of ``dof`` and tangential force over one period.

    Parameters
    ----------
    sol : InterfaceSolution
    dof : int or str
        The DOF of the full model whose displacement is the loop's abscissa (index or name), e.g. the
        holder's ``pad_x``.

    Returns
    -------
    (ndarray, ndarray)
        ``delta(t_n)`` (m) and ``Q(t_n) = s sum_i lambda_T,i(t_n)`` (N, the first tangent's component,
        ``x`` for the benchmarks) at the DLFT samples ``t_n = n T / N``, with ``s`` the model's
        ``symmetry_factor`` (2 for the sphere's half model, 1 without one): the whole contact's force.
        ``oint Q d(delta)`` is the energy the contact takes from the holder per period (J, or J/m in 2-D).
    """
    model = sol.model
    lam = sol.tangential_force
    tangent = lam[..., 0] if lam.ndim == 3 else lam
    force = model.info.get("symmetry_factor", 1.0) * tangent.sum(axis=0)
    harmonics = sol.dof_harmonics[model.dof(dof)]
    return full_synthesis(sol.harmonics, tangent.shape[1]) @ harmonics, force


@dataclass(eq=False)
class InterfaceWearHistory:
    """Wear profile history of an interface.

    Attributes
    ----------
    position : ndarray, shape (nc,)
        Coordinate of each pair along the interface (m).
    area : ndarray, shape (nc,)
        Tributary area of each pair (m, per unit thickness in 2-D).
    cycles : ndarray, shape (m,)
        Cycle counts ``N`` of the records (starting at 0).
    wear : ndarray, shape (m, nc)
        Worn depth ``w(x, N)`` (m).
    pressure : ndarray, shape (m, nc)
        Pressure averaged over the cycle, ``p(x, N)`` (Pa).
    peak_pressure : ndarray, shape (m, nc)
        Largest pressure over the cycle (Pa).
    shear : ndarray, shape (m, nc)
        Largest shear traction magnitude over the cycle, ``max_t |lambda_T| / A`` (Pa;
        :func:`shear_traction`).
    slip : ndarray, shape (m, nc)
        Distance slid per cycle ``s(x, N)`` (m).
    stick_fraction : ndarray, shape (m, nc)
        Fraction of the cycle each pair sticks.
    wear_rate : ndarray, shape (m, nc)
        ``dw / dN = K_w int p ds`` (m per cycle).
    state : ndarray, shape (m, nc, N_samples)
        Stick/slip/open state over ``(x, phase of the cycle)`` at each record.
    normal_force_sum : ndarray, shape (m,)
        Cycle-averaged sum of the normal forces, the pressure integral (N).
    kw : float
        Archard coefficient (1/Pa).
    omega : float
        Excitation frequency (rad/s).
    converged : bool
        Every periodic solve converged and the history reached its end.
    message : str
        Why the history stopped early, if it did.
    solves : int
        Periodic solves performed.
    solutions : list of InterfaceSolution
        The periodic solution at each record.
    method : str
        ``"stepping"`` or ``"polynomial"``.
    info : dict
        Method-specific diagnostics (polynomial: see
        :func:`~fretwear.interface.wear_polynomial_interface`).
    """

    position: np.ndarray
    area: np.ndarray
    kw: float
    omega: float
    cycles: list = field(default_factory=list)
    wear: list = field(default_factory=list)
    pressure: list = field(default_factory=list)
    peak_pressure: list = field(default_factory=list)
    shear: list = field(default_factory=list)
    slip: list = field(default_factory=list)
    stick_fraction: list = field(default_factory=list)
    wear_rate: list = field(default_factory=list)
    state: list = field(default_factory=list)
    normal_force_sum: list = field(default_factory=list)
    solutions: list = field(default_factory=list)
    converged: bool = True
    message: str = ""
    solves: int = 0
    method: str = "stepping"
    info: dict = field(default_factory=dict)

    def record(self, N: float, w: np.ndarray, sol: InterfaceSolution) -> None:
        self.cycles.append(float(N))
        self.wear.append(w.copy())
        self.pressure.append(sol.mean_pressure)
        self.peak_pressure.append(sol.pressure.max(axis=1))
        self.shear.append(shear_traction(sol).max(axis=1))
        self.slip.append(sol.slip_distance)
        self.stick_fraction.append(sol.state_fraction(STICK))
        self.wear_rate.append(self.kw * sol.pressure_slip)
        self.state.append(sol.state.copy())
        self.normal_force_sum.append(float(sol.normal_force.mean(axis=1).sum()))
        self.solutions.append(sol)

    def finish(self) -> InterfaceWearHistory:
        for name in ("cycles", "normal_force_sum", "wear", "pressure", "peak_pressure", "shear", "slip",
                     "stick_fraction", "wear_rate", "state"):  # fmt: skip
            setattr(self, name, np.array(getattr(self, name)))
        return self

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    def to_xarray(self):
        """The history along ``cycles`` and ``pair`` (with ``position``) as an ``xarray.Dataset``."""
        from .._xarray import interface_history_dataset

        return interface_history_dataset(self)

    def _repr_html_(self) -> str:
        from .._html import summary_html

        return summary_html(self)

    @property
    def status(self) -> str:
        """Why the history ends: ``"horizon"``, or the :attr:`message` (an early stop or a failure)."""
        return self.message or "horizon"

    def cycles_to_depth(self, depth: float, pair: int = 0) -> float:
        """Cycles at which pair ``pair`` reaches the worn depth ``depth`` (m); nan if it does not.

        Inverts the cubic Hermite interpolant of the records (depths and their
        rates, as :meth:`fretwear.wear.WearHistory.cycles_to`), monotone as Archard's law.
        """
        w, rate = self.wear[:, pair], self.wear_rate[:, pair]
        k = int(np.searchsorted(w, depth))
        if k == 0:
            return 0.0 if len(w) and w[0] >= depth else np.nan
        if k >= len(w):
            return np.nan
        spline = CubicHermiteSpline(self.cycles[k - 1 : k + 1], w[k - 1 : k + 1], rate[k - 1 : k + 1])
        return float(brentq(lambda n: spline(n) - depth, self.cycles[k - 1], self.cycles[k]))

    def loop(self, dof: int | str, record: int = -1) -> tuple[np.ndarray, np.ndarray]:
        """The fretting loop ``(delta, Q)`` of record ``record`` over one period (:func:`fretting_loop`)."""
        return fretting_loop(self.solutions[record], dof)

    @property
    def worn_area(self) -> np.ndarray:
        """Worn area per unit length ``sum_i w_i A_i`` at each record (m^2 per m of thickness in 2-D)."""
        return self.wear @ self.area

    @property
    def worn_area_rate(self) -> np.ndarray:
        """Archard's worn area per cycle ``K_w sum_i (int p ds)_i A_i`` at each record."""
        return self.wear_rate @ self.area

    @property
    def contact_width(self) -> np.ndarray:
        """Extent of the pairs that carry load at some time of the cycle, at each record (m)."""
        loaded = self.peak_pressure > 0
        x = self.position
        return np.array([x[row].max() - x[row].min() if row.any() else 0.0 for row in loaded])
