"""One front function per job for every model: the solver is chosen by the model's contact kind.

A :class:`~fretwear.model.Model` holds 1-D contacts (``friction``, ``normal``:
kind ``"contacts"``) or contact node pairs (``pairs``: kind ``"pairs"``). The
table ``SOLVERS`` names, per kind and job, the function that does the
job; the front functions look it up and call it with the same arguments:

============== ======================================= =================================================
job            ``"contacts"`` (1-D friction, normal)   ``"pairs"`` (coupled normal/tangential, eq. 17-23)
============== ======================================= =================================================
solve_periodic :func:`fretwear.hbm.solve_periodic`     :func:`fretwear.interface.jobs.solve_periodic`
sweep          :func:`fretwear.hbm.sweep`              :func:`fretwear.interface.jobs.sweep`
wear_history   :func:`fretwear.wear.wear_history`      ``fretwear.interface.jobs.wear_history()``
static_contact (none)                                  :func:`~fretwear.static_contact`
continuation   :func:`fretwear.hbm.continuation`       (none)
linear_frf     :func:`fretwear.hbm.linear_frf`         (none)
shooting       :func:`fretwear.time.shooting`          (none)
shooting_sweep :func:`fretwear.time.shooting_sweep`    (none)
============== ======================================= =================================================

A job that does not apply to the model's kind raises ``ValueError`` (e.g. the
exact event-driven shooting of a model with pairs) rather than solving the
structure without its contacts.

The arguments are the same for both kinds: frequency ``omega`` in rad/s (an
array ``omegas`` for a sweep), ``harmonics``, and keywords. The results
differ in type (:class:`~fretwear.hbm.PeriodicSolution` or
:class:`~fretwear.interface.InterfaceSolution`; :class:`~fretwear.wear.WearHistory`
or :class:`~fretwear.interface.InterfaceWearHistory`) and share the attributes
read first: ``omega``, ``frequency`` (Hz), ``dof_harmonics`` (n, 2 Nh + 1) and
``amplitude`` (n,) of every DOF, ``converged``, ``residual``, ``iterations``,
``message``, ``path``, ``unknowns`` of a solution; ``omega``, ``frequency``,
``cycles``, ``wear`` (records, contacts or pairs), ``converged``, ``status``,
``solves``, ``method`` of a history. A sweep is a :class:`~fretwear.hbm.Sweep`
of either solution type.

The solvers are imported on first use: the interface stack loads only for a
model with pairs.
"""

from __future__ import annotations

from collections.abc import Callable
from importlib import import_module
from typing import Any

import numpy as np

from .model import Model

__all__ = [
    "SOLVERS",
    "contact_kind",
    "solve_periodic",
    "sweep",
    "wear_history",
    "static_contact",
    "continuation",
    "linear_frf",
    "shooting",
    "shooting_sweep",
]

#: per contact kind, the function of each job as ``"module:function"`` (None: the job does not apply)
SOLVERS: dict[str, dict[str, str | None]] = {
    "contacts": {
        "solve_periodic": "fretwear.hbm.periodic:solve_periodic",
        "sweep": "fretwear.hbm.continuation:sweep",
        "wear_history": "fretwear.wear.history:wear_history",
        "static_contact": None,
        "continuation": "fretwear.hbm.continuation:continuation",
        "linear_frf": "fretwear.hbm.linear:linear_frf",
        "shooting": "fretwear.time.shooting:shooting",
        "shooting_sweep": "fretwear.time.shooting:shooting_sweep",
    },
    "pairs": {
        "solve_periodic": "fretwear.interface.jobs:solve_periodic",
        "sweep": "fretwear.interface.jobs:sweep",
        "wear_history": "fretwear.interface.jobs:wear_history",
        "static_contact": "fretwear.interface.jobs:static_contact",
        "continuation": None,
        "linear_frf": None,
        "shooting": None,
        "shooting_sweep": None,
    },
}


def contact_kind(model: Model) -> str:
    """``"pairs"`` for a model with contact pairs, else ``"contacts"`` (1-D friction and normal contacts)."""
    if not isinstance(model, Model):
        raise ValueError(f"model must be a fretwear Model, got {type(model).__name__}")
    return "contacts" if model.pairs is None else "pairs"


def _solver(job: str, model: Model) -> Callable[..., Any]:
    kind = contact_kind(model)
    target = SOLVERS[kind][job]
    if target is None:
        applies = [k for k, jobs in SOLVERS.items() if jobs[job] is not None]
        raise ValueError(f"{job} applies to models with {' or '.join(applies)}; this model has {kind}")
    module, name = target.split(":")
    return getattr(import_module(module), name)


def solve_periodic(model: Model, omega: float, harmonics: int = 7, **options) -> Any:
    """Periodic response of ``model`` at ``omega`` by harmonic balance with DLFT contact forces.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s), > 0.
    harmonics : int
        Highest harmonic ``Nh >= 1``.
    **options
        samples : int
            Time samples per period ``N >= 2 Nh + 1`` (default: next power of 2 >= 16 Nh).
        wear : array_like
            Worn depth of each friction contact, or of each pair (m), >= 0.
        eps : float or array_like
            DLFT penalty (N/m): one for all, or one per active contact (per
            contact coordinate for pairs). Default: 10 times the largest
            diagonal entry of the condensed dynamic stiffness (section 1.4).
            It changes the convergence, and at finite ``Nh`` the answer only
            within the truncation error.
        half_wave : bool
            Force or forbid the half-wave (odd harmonics) reduction (never for pairs:
            the static normal load breaks the symmetry).
        guess : ndarray
            Starting unknowns (harmonics of the active contact coordinates),
            e.g. ``solution.unknowns`` of a neighbour.
        tol : float
            Relative residual tolerance (default 1e-10).
        max_iter : int
            Newton iterations per solve (default 50).
        factor : float
            Pairs only: the reduction's mode count criterion
            (``fretwear.interface.jobs.condense()``, default 2).

    Returns
    -------
    PeriodicSolution or InterfaceSolution
        With ``converged``, ``residual``, ``iterations``, ``message`` and
        ``path`` (the strategy of ``fretwear.hbm.strategy``).
    """
    return _solver("solve_periodic", model)(model, omega, harmonics, **options)


def sweep(model: Model, omegas: np.ndarray, harmonics: int = 7, **options) -> Any:
    """Periodic responses of ``model`` at the frequencies ``omegas`` (rad/s), in order, warm-started.

    ``options`` as :func:`solve_periodic` (no ``guess``). Returns a
    :class:`~fretwear.hbm.Sweep` (``solutions``, ``omega``, ``converged``).
    """
    return _solver("sweep", model)(model, omegas, harmonics, **options)


def wear_history(model: Model, omega: float, method: str = "auto", *, kw: float = 1e-11, cycles: float = 1e5,
                 **options) -> Any:  # fmt: skip
    """Wear history of ``model`` at ``omega`` (rad/s) on the slow time, to ``cycles``.

    Parameters
    ----------
    model, omega
        As :func:`solve_periodic`.
    method : str
        Slow-time method; ``"auto"`` picks one. 1-D contacts:
        :data:`fretwear.wear.METHODS`; pairs: ``"stepping"`` or ``"polynomial"``.
    kw : float
        Archard coefficient: 1/N for a friction contact (wear per N of normal
        load and m slid), 1/Pa for a pair (per Pa of pressure).
    cycles : float
        Horizon (cycles), > 0.
    **options
        The method's options (:func:`fretwear.wear.wear_history`,
        ``fretwear.interface.jobs.wear_history()``).

    Returns
    -------
    WearHistory or InterfaceWearHistory
        Per friction contact, or the nodal wear profile of the interface.
    """
    return _solver("wear_history", model)(model, omega, method, kw=kw, cycles=cycles, **options)


def static_contact(model: Model, tangential_scale: float = 0.0, **options) -> Any:
    """Quasi-static contact state of a model with contact pairs under its static load.

    ``tangential_scale`` times the ``cos`` load pattern is then applied
    statically (-). Options as :func:`~fretwear.static_contact`.
    """
    return _solver("static_contact", model)(model, tangential_scale, **options)


def _front(job: str) -> Callable[..., Any]:
    """The front function of a job that one contact kind has: its solver's arguments, checked kind."""
    module, name = next(t for t in (jobs[job] for jobs in SOLVERS.values()) if t is not None).split(":")

    def front(model: Model, *args, **options) -> Any:
        return _solver(job, model)(model, *args, **options)

    front.__name__ = front.__qualname__ = job
    front.__doc__ = f"""``{job}`` of any model: :func:`{module.rsplit(".", 1)[0]}.{name}` for a model of
    the kind that has it (``SOLVERS``); same arguments and result. Other kinds raise ``ValueError``."""
    return front


continuation = _front("continuation")
linear_frf = _front("linear_frf")
shooting = _front("shooting")
shooting_sweep = _front("shooting_sweep")
