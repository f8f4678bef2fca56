"""fretwear: dynamics of structures with dry-friction contacts that wear.

Harmonic balance with the Dynamic Lagrangian Frequency-Time method (DLFT) for
the periodic response, exact event-driven dynamics (shooting) as the
reference, and Archard wear on a slow time scale, after Salles et al.,
"Dynamic analysis of fretting-wear in friction contact interfaces".

The layers, bottom up: :mod:`fretwear.model` (one :class:`~fretwear.model.Model` type for every
structure, its contacts, Craig-Bampton reduction, model files),
:mod:`fretwear.hbm` (harmonic balance + DLFT, sweeps), :mod:`fretwear.time`
(exact integration, shooting), :mod:`fretwear.wear` (slow-time methods),
:mod:`fretwear.interface` (contact interfaces of many node pairs),
:mod:`fretwear.studies` (maps, convergence, regimes, accuracy vs cost). Plotting
lives in :mod:`fretwear.figures`, which the numerical layers never import.

The front functions :func:`solve_periodic`, :func:`sweep`, :func:`~fretwear.wear_history`
and :func:`static_contact` take any model and pick the solver of its contact
kind (``fretwear.front``).
"""

from . import _kernel_cache  # noqa: F401 - first, before any kernel: their caches track every kernel source
from ._version import __version__ as __version__
from .front import (
    continuation,
    linear_frf,
    shooting,
    shooting_sweep,
    solve_periodic,
    static_contact,
    sweep,
    wear_history,
)
from .hbm import PeriodicSolution
from .model import (
    ContactPairs,
    FrictionContact,
    Model,
    NormalContact,
    bladed_disk,
    jenkins_oscillator,
    paper_model,
    read_model,
)
from .model import craig_bampton as reduce
from .studies import compare_methods, cost_ladder, harmonic_convergence, regime_map, wear_map
from .time import ShootingSolution
from .wear import METHODS, WearHistory

#: builders of interface models, imported on first use (the benchmark's mesher loads scikit-fem)
_LAZY = {"cylinder_on_flat": ".interface.fe", "paper_interface": ".interface.paper"}

__all__ = [
    "METHODS",
    "ContactPairs",
    "FrictionContact",
    "Model",
    "NormalContact",
    "PeriodicSolution",
    "ShootingSolution",
    "WearHistory",
    "bladed_disk",
    "compare_methods",
    "continuation",
    "cost_ladder",
    "cylinder_on_flat",
    "harmonic_convergence",
    "jenkins_oscillator",
    "linear_frf",
    "paper_interface",
    "paper_model",
    "read_model",
    "reduce",
    "regime_map",
    "shooting",
    "shooting_sweep",
    "solve_periodic",
    "static_contact",
    "sweep",
    "wear_history",
    "wear_map",
]


def __getattr__(name: str):
    if name in _LAZY:
        from importlib import import_module

        return getattr(import_module(_LAZY[name], __name__), name)
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
