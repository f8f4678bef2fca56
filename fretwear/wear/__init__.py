"""Fretting wear on the slow time scale (paper sections 1.3, 1.6; eq. 15, 24-30).

:func:`~fretwear.wear.wear_history` is the front function; :data:`METHODS` the registry of the
slow-time methods, one module each (``fretwear.wear.exact``,
``fretwear.wear.stepping``, ``fretwear.wear.polynomial``,
``fretwear.wear.time_integration``); ``fretwear.wear.result`` holds
Archard's law, the input checks and the result type :class:`WearHistory`;
``fretwear.wear.dynamics`` the periodic response at a wear state.
"""

from .dynamics import DYNAMICS, resolve_dynamics
from .exact import exact_path_applies, wear_exact
from .history import METHODS, Method, exact_answer_applies, method_options, resolve_method, wear_history
from .polynomial import wear_polynomial
from .result import TWO_SCALE_LIMIT, WearHistory, check_wear_inputs, cycle_grid, describe, snapshot_cycles
from .stepping import wear_stepping
from .time_integration import integrate_wear

__all__ = [
    "DYNAMICS",
    "METHODS",
    "Method",
    "TWO_SCALE_LIMIT",
    "WearHistory",
    "check_wear_inputs",
    "cycle_grid",
    "exact_answer_applies",
    "describe",
    "snapshot_cycles",
    "exact_path_applies",
    "integrate_wear",
    "method_options",
    "resolve_dynamics",
    "resolve_method",
    "wear_exact",
    "wear_history",
    "wear_polynomial",
    "wear_stepping",
]
