"""Exact dynamics in time: the event-driven integrator and periodic solutions by shooting.

``fretwear.time.integrator`` integrates the equations of motion with
Coulomb contacts, rigid or Jenkins (a tangential stiffness in series),
exactly (piecewise-linear dynamics, events located to round-off);
:mod:`~fretwear.time.shooting` finds periodic orbits on it
(:func:`shooting`), the truth every harmonic-balance answer is measured against.
"""

from .integrator import ContactEvent, Trajectory, integrate, period_map
from .shooting import ShootingSolution, periodic_state, shooting, shooting_sweep, steady_state

__all__ = [
    "ContactEvent",
    "ShootingSolution",
    "Trajectory",
    "integrate",
    "period_map",
    "periodic_state",
    "shooting",
    "shooting_sweep",
    "steady_state",
]
