"""The front functions' interface side: a :class:`~fretwear.model.Model` with contact pairs in, a result out.

``fretwear.solve_periodic``, ``fretwear.sweep``, ``fretwear.wear_history`` and
``fretwear.static_contact`` send a model with ``pairs`` here
(:data:`fretwear.front.SOLVERS`). Each function takes the arguments of the
front (frequency ``omega`` in rad/s, ``harmonics``, ``wear``, ``eps``, ``tol``,
...), reduces the model unless it is reduced already (:func:`condense`), and
calls the interface solvers: :func:`~fretwear.interface.periodic.solve_interface`,
:func:`~fretwear.interface.wear.sweep_interface`,
:func:`~fretwear.interface.wear.wear_interface`,
:func:`~fretwear.interface.static.solve_static`.

**Reduction.** A model that is not reduced yet is reduced by Craig-Bampton
with every fixed-interface mode up to ``factor`` times the highest frequency
the harmonic balance sees (``harmonics`` times the highest excitation
frequency; :func:`~fretwear.model.craig_bampton`). The reduction
is done on every call: to solve one model many times, reduce it once
(``fretwear.reduce(model, f_max)``) and pass the reduced model, which is used
as it is.
"""

from __future__ import annotations

import inspect

import numpy as np

from ..hbm.continuation import Sweep, check_omegas
from ..model import Model, craig_bampton
from .history import InterfaceWearHistory
from .periodic import InterfaceProblem, InterfaceSolution, solve_interface
from .reduction import ContactCondensation
from .static import StaticResult, solve_static
from .wear import sweep_interface, wear_interface

__all__ = ["condense", "solve_periodic", "sweep", "wear_history", "static_contact"]


def condense(model: Model, f_max: float, factor: float = 2.0) -> ContactCondensation:
    """The condensation of ``model`` on its contact coordinates, reduced first unless it is reduced.

    Parameters
    ----------
    model : Model
        A model with contact pairs.
    f_max : float
        Highest frequency the harmonic balance sees (Hz), >= 0.
    factor : float
        Mode count criterion of the reduction (fixed-interface modes up to ``factor * f_max``).
    """
    if not isinstance(model, Model) or model.pairs is None:
        raise ValueError(f"model must be a Model with contact pairs, got {model!r:.80}")
    return ContactCondensation(model if model.reduction is not None else craig_bampton(model, f_max, factor))


def _problem(
    cond: ContactCondensation, omega: float, harmonics: int, samples=None, wear=None, eps=None, half_wave=None
) -> InterfaceProblem:
    """The problem at ``omega`` with the settings of :func:`fretwear.solve_periodic` (``wear`` per pair)."""
    if half_wave:
        raise ValueError(
            "half_wave must be None or False for a model with contact pairs (the static normal load breaks "
            f"the half-wave symmetry), got {half_wave!r}"
        )
    if eps is not None and np.ndim(eps) == 0:
        eps = np.full(2 * cond.n_pairs, float(eps))  # one penalty for every contact coordinate
    return InterfaceProblem(cond, omega, harmonics=harmonics, samples=samples, wear=wear, eps=eps)


def _check_omega(omega: float) -> float:
    if isinstance(omega, bool) or not isinstance(omega, (int, float, np.integer, np.floating)):
        raise ValueError(f"omega must be a frequency > 0 rad/s, got {omega!r}")
    if not (np.isfinite(omega) and omega > 0):
        raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {omega!r}")
    return float(omega)


def solve_periodic(
    model: Model,
    omega: float,
    harmonics: int = 7,
    *,
    guess: np.ndarray | None = None,
    tol: float = 1e-10,
    max_iter: int = 50,
    factor: float = 2.0,
    **settings,
) -> InterfaceSolution:
    """Periodic response of a model with contact pairs at ``omega`` (rad/s): :func:`solve_interface`.

    Parameters as :func:`fretwear.solve_periodic`; ``settings`` are ``samples``,
    ``wear`` (per pair, m), ``eps`` (one penalty for every contact coordinate
    or one per coordinate, 2 nc, N/m) and ``half_wave`` (None or False);
    ``factor`` is the reduction's mode count criterion (module docstring).
    """
    omega = _check_omega(omega)
    cond = condense(model, harmonics * omega / (2 * np.pi), factor)
    return solve_interface(_problem(cond, omega, harmonics, **settings), guess, tol, max_iter)


def sweep(
    model: Model, omegas, harmonics: int = 7, *, tol: float = 1e-10, max_iter: int = 50, factor: float = 2.0,
    **settings,
) -> Sweep:  # fmt: skip
    """Periodic responses of a model with contact pairs at ``omegas`` (rad/s), warm-started in order.

    Parameters as :func:`solve_periodic` (no ``guess``); the points are
    :func:`sweep_interface`'s.
    """
    omegas = check_omegas(omegas)
    cond = condense(model, harmonics * omegas.max() / (2 * np.pi), factor)
    problems = (_problem(cond, w, harmonics, **settings) for w in omegas)  # one at a time: Z is large
    return Sweep(sweep_interface(problems, tol, max_iter))


#: options of :func:`~fretwear.wear_history` passed on to :func:`wear_interface`
_WEAR_OPTIONS = tuple(
    p for p in inspect.signature(wear_interface).parameters if p not in ("problem", "kw", "cycles", "method")
)


def wear_history(
    model: Model,
    omega: float,
    method: str = "auto",
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 7,
    samples: int | None = None,
    wear=None,
    factor: float = 2.0,
    **options,
) -> InterfaceWearHistory:
    """Nodal wear history of a model with contact pairs at ``omega`` (rad/s): :func:`wear_interface`.

    Parameters
    ----------
    model : Model
        A model with contact pairs.
    omega : float
        Excitation frequency (rad/s), > 0.
    method : {"auto", "stepping", "polynomial"}
        Slow-time method; ``"auto"`` is ``"stepping"``.
    kw : float
        Archard coefficient ``K_w`` (1/Pa), > 0.
    cycles : float
        Horizon (cycles), > 0.
    harmonics, samples : int
        ``Nh`` and samples per period of the periodic solves.
    wear : ndarray, shape (nc,), optional
        Initial worn depth per pair (m).
    factor : float
        Mode count criterion of the reduction (module docstring).
    **options
        Options of :func:`wear_interface` (``rtol``, ``atol``, ``converge``,
        ``first_step``, ``max_steps``, ``tol``, ``degree``, ``max_increment``).

    Returns
    -------
    InterfaceWearHistory
        Wear, pressure and slip profiles over ``N`` (``wear`` shape (records, nc)).
    """
    unknown = sorted(set(options) - set(_WEAR_OPTIONS))
    if unknown:
        raise ValueError(
            f"{unknown[0]!r} is not an option of wear_history for a model with contact pairs; "
            f"valid options are {', '.join(_WEAR_OPTIONS)}"
        )
    if method not in ("auto", "stepping", "polynomial"):
        raise ValueError(
            f"method must be 'auto', 'stepping' or 'polynomial' for contact pairs, got {method!r}"
        )
    omega = _check_omega(omega)
    cond = condense(model, harmonics * omega / (2 * np.pi), factor)
    problem = _problem(cond, omega, harmonics, samples, wear)
    return wear_interface(problem, kw, cycles, method="stepping" if method == "auto" else method, **options)


def static_contact(
    model: Model,
    tangential_scale: float = 0.0,
    *,
    wear=None,
    normal_steps: int = 4,
    tangential_steps: int = 8,
    tol: float = 1e-10,
) -> StaticResult:
    """Quasi-static contact state of a model with contact pairs: :func:`solve_static`.

    The static load in ``normal_steps`` increments, then ``tangential_scale``
    times the ``cos`` load pattern applied statically (-); ``wear`` is the worn
    depth per pair (m). The model is reduced with no mode (statics) unless it
    is reduced already.
    """
    cond = condense(model, 0.0)
    return solve_static(cond, tangential_scale, normal_steps, tangential_steps, wear=wear, tol=tol)
