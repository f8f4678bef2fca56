"""One front function for wear on the slow time scale, and the registry of its methods.

:func:`~fretwear.wear.wear_history` runs one slow-time method at one frequency and returns a
:class:`~fretwear.wear.result.WearHistory`. Each method lives in a module of its
own and is registered in :data:`METHODS` with the options it takes, so that the
command line, the dashboard and the figures ask the registry instead of
keeping their own lists:

========== ============================================== =====================================
method     module                                         options
========== ============================================== =====================================
exact      ``fretwear.wear.exact`` (load path)         dynamics, harmonics, samples
stepping   ``fretwear.wear.stepping`` (eq. 24, RK23)   harmonics, samples, tol, dynamics,
                                                          fixed_step
polynomial ``fretwear.wear.polynomial`` (eq. 25-29)    harmonics, samples, degree, basis
time       ``fretwear.wear.time_integration``          tol
========== ============================================== =====================================

Adding a method: one module with a function ``solve(model, omega, *, kw,
cycles, **options) -> WearHistory``, and one :class:`Method` entry below.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

from ..model import Model
from ..time.patterns import unsupported
from .dynamics import resolve_dynamics
from .exact import exact_path_applies, wear_exact
from .polynomial import wear_polynomial
from .result import WearHistory
from .stepping import wear_stepping
from .time_integration import integrate_wear

__all__ = ["Method", "METHODS", "wear_history", "resolve_method", "method_options", "exact_answer_applies"]


@dataclass(frozen=True)
class Method:
    """A slow-time method: its front function and the options it takes.

    Attributes
    ----------
    name : str
        Registry key (``method=`` of :func:`~fretwear.wear.wear_history`).
    solve : callable
        ``solve(model, omega, *, kw, cycles, **options) -> WearHistory``.
    options : tuple of str
        Keyword options it takes besides ``kw`` and ``cycles``.
    title : str
        One line for menus and legends.
    applies : callable
        ``applies(model) -> bool``: whether the method can run on ``model``.
    """

    name: str
    solve: Callable[..., WearHistory]
    options: tuple[str, ...]
    title: str
    applies: Callable[[Model], bool] = lambda _model: True


METHODS: Mapping[str, Method] = {
    m.name: m
    for m in (
        Method(
            "exact", wear_exact, ("harmonics", "samples", "dynamics"), "exact load path", exact_path_applies
        ),
        Method(
            "stepping",
            wear_stepping,
            ("harmonics", "samples", "tol", "dynamics", "fixed_step"),
            "slow-time stepping",
        ),  # fmt: skip
        Method("polynomial", wear_polynomial, ("harmonics", "samples", "degree", "basis"), "polynomial"),
        Method("time", integrate_wear, ("tol",), "time integration"),
    )
}


def resolve_method(model: Model, method: str = "auto", fixed_step=None) -> str:
    """The method that ``method`` names for ``model``: ``"auto"`` is ``"exact"`` where it applies.

    ``"auto"`` falls back to ``"stepping"`` for several contacts or unilateral
    contacts, and for a fixed step (an option only stepping takes). The
    dynamics the method runs on are resolved apart
    (:func:`~fretwear.wear.resolve_dynamics`): with no options, the exact
    ones wherever they apply.
    """
    if method == "auto":
        return "exact" if METHODS["exact"].applies(model) and not fixed_step else "stepping"
    if method not in METHODS:
        raise ValueError(f"method must be 'auto' or one of {', '.join(map(repr, METHODS))}, got {method!r}")
    return method


def exact_answer_applies(model: Model) -> bool:
    """Whether the exact answer exists for ``model``: the exact method on the exact dynamics."""
    return METHODS["exact"].applies(model) and resolve_dynamics(model) == "shooting"


def method_options(method: str, settings: Mapping[str, Any]) -> dict[str, Any]:
    """The entries of ``settings`` that ``method`` takes (``None`` values left out)."""
    taken = METHODS[method].options
    return {k: v for k, v in settings.items() if k in taken and v is not None}


def wear_history(
    model: Model, omega: float, method: str = "auto", *, kw: float = 1e-11, cycles: float = 1e5, **options
) -> WearHistory:
    """Wear evolution ``w(N)`` at ``omega`` (rad/s) by one slow-time method.

    Parameters
    ----------
    model : Model
        Structure with at least one friction contact with ``u0 > 0``.
    omega : float
        Excitation frequency (rad/s), > 0.
    method : {"auto", "exact", "stepping", "polynomial", "time"}
        See the module docstring; ``"auto"`` is :func:`resolve_method`.
        With no options, ``"auto"`` runs the exact method on the exact
        event-driven dynamics wherever they apply: the reference.
    kw : float
        Archard coefficient ``K_w`` (1/N: m of wear per N of load and m slid), >= 0.
    cycles : float
        Horizon (cycles), > 0.
    **options
        The method's options (:data:`METHODS`): ``harmonics`` (``Nh``), ``samples``
        (per period), ``tol`` (local error on ``w / u0``, or of the cycle jumps),
        ``dynamics`` (``"auto"``, ``"shooting"`` or ``"dlft"``: see
        :func:`~fretwear.wear.resolve_dynamics`), ``fixed_step`` (cycles),
        ``degree`` and ``basis`` (polynomial). An option the method does not
        take raises ``ValueError``, except with ``"auto"``, which uses those of
        the method it picks.

    Returns
    -------
    WearHistory
        Its ``method`` and ``dynamics`` are those that ran, ``label`` says both.
    """
    name = resolve_method(model, method, options.get("fixed_step"))
    entry = METHODS[name]
    if method == "auto":  # "pick for me": the options of the other methods are not errors
        options = {k: v for k, v in options.items() if k in entry.options}
    extra = sorted(k for k, v in options.items() if k not in entry.options and v is not None)
    if extra:
        raise ValueError(
            f"method {name!r} takes no option {', '.join(map(repr, extra))} "
            f"(it takes {', '.join(entry.options)})"
        )
    options = {k: v for k, v in options.items() if v is not None}
    hist = entry.solve(model, omega, kw=kw, cycles=cycles, **options)
    reason = unsupported(model) if options.get("dynamics", "auto") == "auto" else None
    if reason and hist.dynamics == "dlft":
        hist.warnings.append(f"{hist.label}, an approximation: the exact dynamics do not apply "
                             f"(the time integrator {reason})")  # fmt: skip
    return hist
