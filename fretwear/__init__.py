"""fretwear: dynamics of structures with dry-friction contacts that wear.

Harmonic balance with the Dynamic Lagrangian Frequency-Time method (DLFT) for
the periodic response, and Archard wear on a slow time scale, after Salles et
al., "Dynamic analysis of fretting-wear in friction contact interfaces".
"""

from .model import FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model
from .periodic import solve_periodic
from .results import PeriodicSolution

__all__ = [
    "FrictionContact",
    "Model",
    "NormalContact",
    "PeriodicSolution",
    "jenkins_oscillator",
    "paper_model",
    "solve_periodic",
]
