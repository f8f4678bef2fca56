"""fretwear: dynamics of structures with dry-friction contacts that wear.

Harmonic balance with the Dynamic Lagrangian Frequency-Time method (DLFT) for
the periodic response, exact event-driven dynamics (shooting) as the
reference, and Archard wear on a slow time scale, after Salles et al.,
"Dynamic analysis of fretting-wear in friction contact interfaces".

The layers, bottom up: :mod:`fretwear.model` (structures, model files),
:mod:`fretwear.hbm` (harmonic balance + DLFT, sweeps), :mod:`fretwear.time`
(exact integration, shooting), :mod:`fretwear.wear` (slow-time methods),
:mod:`fretwear.studies` (maps, convergence, regimes, accuracy vs cost). Plotting
lives in :mod:`fretwear.figures`, which the numerical layers never import.
"""

from . import _kernel_cache  # noqa: F401 - first, before any kernel: their caches track every kernel source
from ._version import __version__ as __version__
from .hbm import PeriodicSolution, continuation, linear_frf, solve_periodic, sweep
from .model import FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model, read_model
from .studies import compare_methods, cost_ladder, harmonic_convergence, regime_map, wear_map
from .time import ShootingSolution, shooting, shooting_sweep
from .wear import METHODS, WearHistory, wear_history

__all__ = [
    "METHODS",
    "FrictionContact",
    "Model",
    "NormalContact",
    "PeriodicSolution",
    "ShootingSolution",
    "WearHistory",
    "compare_methods",
    "continuation",
    "cost_ladder",
    "harmonic_convergence",
    "jenkins_oscillator",
    "linear_frf",
    "paper_model",
    "read_model",
    "regime_map",
    "shooting",
    "shooting_sweep",
    "solve_periodic",
    "sweep",
    "wear_history",
    "wear_map",
]
