"""Studies built on the periodic solvers and the slow-time methods: the paper's figures as data.

* ``fretwear.studies.maps``: wear maps ``W(f, N)`` and pseudo-FRFs (Fig. 7-9, 12-14);
* ``fretwear.studies.convergence``: harmonics (Fig. 10) and methods (Fig. 11);
* ``fretwear.studies.regimes``: stick/slip regimes over frequency x ``r`` and the exact stick limit;
* ``fretwear.studies.accuracy``: what accuracy costs: error against wall time over a ladder of settings.
"""

from .accuracy import CostStudy, Rung, cost_ladder
from .convergence import compare_methods, harmonic_convergence
from .maps import WearMap, wear_map
from .regimes import regime_map, stick_limit

__all__ = [
    "CostStudy",
    "Rung",
    "WearMap",
    "compare_methods",
    "cost_ladder",
    "harmonic_convergence",
    "regime_map",
    "stick_limit",
    "wear_map",
]
