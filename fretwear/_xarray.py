"""Results as :class:`xarray.Dataset`: the ``to_xarray()`` of every result type, in one place.

The datasets follow the conventions of the study store (:mod:`fretwear.studies.store`):
named dimensions (``frequency`` in Hz, ``cycles``, ``dof`` named ``x1, x2, ...``,
``contact`` and ``friction_contact`` named ``xr`` or ``xr1, xr2, ...`` friction
first, ``pair`` with its ``position``), ``attrs["units"]`` and ``attrs["long_name"]``
on every variable and coordinate, state codes as CF flags (``flag_values``,
``flag_meanings``), the version and the producer in the dataset's attributes
(``fretwear_version``, ``created_by``), and a scalar attribute's unit in
``NAME_units``. Wear depth is ``w`` (m) in every result, so that
``hist.to_xarray().w.plot()`` draws ``w(N)``.

Every dataset round-trips through ``to_zarr`` / ``xarray.open_zarr`` (Zarr v2
or v3: labels are variable-length strings) and netCDF (``None`` is left out of
the attributes).
xarray is imported by these functions only: the library imports without it.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from ._version import __version__
from .model.structure import OPEN, SLIP, STICK
from .studies.compute import reported_dofs
from .studies.spec import PARAMETERS
from .studies.store import _LONG_NAMES, _UNITS, CYCLES_ATTRS, POSITION_ATTRS

__all__ = [
    "VARIABLES",
    "contact_names",
    "cost_dataset",
    "interface_history_dataset",
    "interface_solution_dataset",
    "periodic_dataset",
    "sweep_dataset",
    "wear_history_dataset",
    "wear_map_dataset",
]


def _store(name: str) -> tuple[str, str]:
    """The study store's unit and long name of variable ``name`` (its "(no wear)" left out: a result
    may carry wear)."""
    return _UNITS[name], _LONG_NAMES[name].replace(" (no wear)", "")


#: unit and long name of every variable a result's dataset may hold (the store's where it has the name)
VARIABLES: dict[str, tuple[str, str]] = {
    "w": ("m", "wear depth w"),
    "wear_fraction": _store("wear_fraction"),
    "amplitude": ("m", "first-harmonic amplitude of each DOF"),
    "half_peak_to_peak": ("m", "half peak-to-peak displacement of each DOF"),
    "relative_amplitude": ("m", "first-harmonic amplitude of each contact's relative displacement"),
    "relative_half_peak_to_peak": ("m", "half peak-to-peak relative displacement of each contact"),
    "sliding_distance": _store("sliding_distance"),
    "friction_energy": _store("friction_energy"),
    "slip_distance": _store("slip_distance"),
    "mean_pressure": _store("mean_pressure"),
    "normal_load": ("N", "normal load F_N = k_n (u0 - w) of each friction contact"),
    "rate": ("m/cycle", "wear rate dw/dN of each friction contact"),
    "normalised_time": ("1/m", "normalised slow time K_w k_n N"),
    "u0": ("m", "initial interference u0 of each friction contact"),
    "kn": ("N/m", "normal stiffness k_n of each friction contact"),
    "displacement": ("m", "displacement of each DOF over one period"),
    "relative_displacement": ("m", "relative displacement u_r = B u of each contact over one period"),
    "contact_force": ("N", "contact force of each contact over one period"),
    "input_work": ("J", "work of the external force per period"),
    "viscous_dissipation": ("J", "energy dissipated by viscous damping per period"),
    "converged": ("-", "the solve converged"),
    "residual": ("-", "final relative residual of the solver"),
    "iterations": ("-", "solver iterations"),
    "pressure": ("Pa", "contact pressure of each pair, mean over the cycle"),
    "tangential_force": ("N", "tangential contact force lambda_T of each pair over one period"),
    "normal_force": ("N", "normal contact force lambda_N of each pair over one period"),
    "slip_variable": ("m", "slip variable X_T of each pair over one period (DLFT, eq. 18-19)"),
    "contact_work": ("J", "work of the contact forces per period, from the harmonics"),
    "peak_pressure": ("Pa", "largest contact pressure of each pair over the cycle"),
    "slip": ("m", "distance slid per cycle by each pair"),
    "stick_fraction": ("-", "fraction of the cycle each pair sticks"),
    "wear_rate": ("m/cycle", "wear rate dw/dN of each pair"),
    "normal_force_sum": ("N", "sum of the normal forces, mean over the cycle"),
    "worn_area": ("m^2", "worn area sum_i w_i A_i (per m of thickness in 2-D)"),
    "area": ("m^2", "tributary area of each pair (m per unit thickness in 2-D)"),
    "wall_time": ("s", "wall time of the rung (median of repeats)"),
    "error": ("-", "relative error against the reference"),
    "reference_value": ("m", "the reference's value of the quantity"),
    "reference": ("-", "the rung is the reference's own method (its error is round-off)"),
}
#: state codes of a contact or pair, as CF flags
STATE_FLAGS = {"flag_values": [STICK, SLIP, OPEN], "flag_meanings": "stick slip open"}
#: unit of each scalar attribute that has one (written as ``NAME_units``)
ATTRIBUTE_UNITS = {"omega": "rad/s", "frequency": "Hz", "kw": "1/N", "wall_time": "s"}


def _frequency_attrs() -> dict[str, str]:
    p = PARAMETERS["frequency"]
    return {"units": p.unit, "long_name": p.long_name}


def dof_names(n: int) -> list[str]:
    """Names of the DOFs of a model with 1-D contacts, as the store's: ``x1, x2, ...``."""
    return [f"x{i + 1}" for i in range(n)]


def contact_names(n: int) -> list[str]:
    """Names of ``n`` contacts, friction first: ``xr`` for one, else ``xr1, xr2, ...`` (the columns of
    the CLI's tables)."""
    return ["xr"] if n == 1 else [f"xr{j + 1}" for j in range(n)]


def _var(name: str, dims: tuple[str, ...], values: Any, **attrs: Any) -> tuple:
    units, long_name = VARIABLES[name]
    return dims, np.asarray(values), {"units": units, "long_name": long_name, **attrs}


def _scalar(value: Any) -> Any:
    """A value for the attributes of a dataset (Zarr and netCDF): numpy scalars as Python's, ``None`` left
    out (returned as ``None``), anything but a number, a bool or a text as its text."""
    if value is None:
        return None
    if isinstance(value, (bool, int, float, str, np.bool_, np.integer, np.floating)):
        return value.item() if isinstance(value, np.generic) else value
    return str(value)


def _solve_status(sol: Any) -> dict[str, Any]:
    """The attributes every periodic solution carries: its path, frequency and how its solve ended."""
    return {"path": sol.path, "omega": sol.omega, "converged": sol.converged, "iterations": sol.iterations,
            "residual": sol.residual, "message": sol.message}  # fmt: skip


def _attrs(obj: Any, title: str, **values: Any) -> dict[str, Any]:
    """The dataset's attributes: the store's (title, version, producer), ``values`` (with their units,
    ``None`` left out) and the scalar entries of ``obj.info`` as ``info_KEY``."""
    out: dict[str, Any] = {
        "title": title,
        "fretwear_version": __version__,
        "created_by": f"fretwear {type(obj).__name__}.to_xarray",
    }
    for key, value in values.items():
        value = _scalar(value)
        if value is not None:
            out[key] = value
            if key in ATTRIBUTE_UNITS:
                out[f"{key}_units"] = ATTRIBUTE_UNITS[key]
    for key, value in (getattr(obj, "info", None) or {}).items():
        if np.ndim(value) == 0 and _scalar(value) is not None:
            out[f"info_{key}"] = _scalar(value)
    return out


def _dataset(data_vars: Mapping, coords: Mapping, attrs: Mapping):
    import xarray as xr

    # labels as variable-length strings: Zarr v3 has no stable fixed-width string type
    coords = {k: (v[0], _text(v[1]), *v[2:]) for k, v in coords.items()}
    return xr.Dataset(dict(data_vars), coords=coords, attrs=dict(attrs))


def _text(values: Any) -> Any:
    array = np.asarray(values)
    return array.astype(object) if array.dtype.kind == "U" else values


def _contact_coords(n_contacts: int, n_friction: int, n_shown: int | None = None) -> dict[str, tuple]:
    """``contact`` (the first ``n_shown`` of the ``n_contacts``) and ``friction_contact`` coordinates."""
    names = contact_names(n_contacts)
    return {
        "contact": ("contact", names[: n_contacts if n_shown is None else n_shown], {"long_name": "contact"}),
        "friction_contact": ("friction_contact", names[:n_friction], {"long_name": "friction contact"}),
    }


def _dof_coords(model: Any) -> tuple[dict[str, tuple], np.ndarray]:
    """The ``dof`` coordinate and the DOF indices it names: every DOF of a model with 1-D contacts, the
    reported DOFs of a model with pairs (the store's :func:`~fretwear.studies.compute.reported_dofs`)."""
    if model.pairs is None and model.reduction is None:
        names, index = dof_names(model.n_dofs), np.arange(model.n_dofs)
    else:
        dofs = reported_dofs(model)
        names, index = list(dofs), np.array(list(dofs.values()), dtype=int)
    return {"dof": ("dof", names, {"long_name": "degree of freedom"})}, index


# ---------------------------------------------------------------------------------------------------
# periodic solutions and sweeps
# ---------------------------------------------------------------------------------------------------
def _method(sol: Any) -> str:
    """What found a periodic solution: ``"shooting"`` (the exact dynamics) or ``"dlft, Nh = 7"``."""
    return "shooting" if sol.path == "shooting" else f"{sol.path}, Nh = {sol.harmonics}"


def periodic_dataset(sol: Any):
    """The dataset of a periodic solution of a model with 1-D contacts (DLFT or shooting).

    Dimensions ``time`` (the ``N`` samples of one period, s), ``dof``,
    ``contact`` (shooting: the friction contacts) and ``friction_contact``;
    the scalar coordinate ``frequency`` (Hz). Time signals: ``displacement``,
    ``relative_displacement``, ``contact_force``, ``state`` (flags); per DOF
    or contact: ``amplitude``, ``half_peak_to_peak``, ``relative_amplitude``,
    ``relative_half_peak_to_peak``; per friction contact: ``w``,
    ``normal_load``, ``sliding_distance``, ``friction_energy``; per period:
    ``input_work``, ``viscous_dissipation``. Attributes: the solve's status.
    """
    model = sol.model
    rel = np.asarray(sol.relative_displacement)
    nf = len(model.friction)
    coords = {
        "time": ("time", sol.time, {"units": "s", "long_name": "time over one period t_k = k T / N"}),
        "frequency": ((), sol.frequency, _frequency_attrs()),
        "dof": ("dof", dof_names(model.n_dofs), {"long_name": "degree of freedom"}),
        **_contact_coords(len(model.contacts), nf, rel.shape[0]),
    }
    data = {
        "displacement": _var("displacement", ("dof", "time"), sol.displacement),
        "relative_displacement": _var("relative_displacement", ("contact", "time"), rel),
        "contact_force": _var("contact_force", ("contact", "time"), sol.contact_force),
        "state": (
            ("contact", "time"),
            np.asarray(sol.state, dtype=np.int8),
            {"long_name": "state of each contact over one period", **STATE_FLAGS},
        ),
        "amplitude": _var("amplitude", ("dof",), sol.amplitude),
        "half_peak_to_peak": _var("half_peak_to_peak", ("dof",), sol.half_peak_to_peak),
        "relative_amplitude": _var("relative_amplitude", ("contact",), sol.relative_amplitude),
        "relative_half_peak_to_peak": _var(
            "relative_half_peak_to_peak", ("contact",), sol.relative_half_peak_to_peak
        ),
        "w": _var("w", ("friction_contact",), sol.wear),
        "normal_load": _var("normal_load", ("friction_contact",), sol.normal_loads),
        "sliding_distance": _var("sliding_distance", ("friction_contact",), sol.sliding_distance),
        "friction_energy": _var("friction_energy", ("friction_contact",), sol.friction_energy),
        "input_work": _var("input_work", (), sol.input_work),
        "viscous_dissipation": _var("viscous_dissipation", (), sol.viscous_dissipation),
    }
    attrs = _attrs(
        sol,
        f"periodic solution at {sol.frequency:.6g} Hz ({_method(sol)})",
        method=_method(sol),
        **_solve_status(sol),
        harmonics=getattr(sol, "harmonics", None),
        samples=sol.samples,
    )
    return _dataset(data, coords, attrs)


def sweep_dataset(solutions: Sequence[Any]):
    """The dataset of periodic solutions along ``frequency`` (Hz): an FRF.

    Per frequency: ``converged``, ``residual``, ``iterations`` and the
    ``amplitude`` of each DOF (the reported DOFs of a model with pairs).
    1-D contacts add ``half_peak_to_peak``, ``relative_amplitude``,
    ``relative_half_peak_to_peak``, ``sliding_distance`` and
    ``friction_energy`` per contact; pairs add ``slip_distance`` and
    ``mean_pressure`` per pair and the interface's ``friction_energy``.
    """
    if not len(solutions):
        raise ValueError("solutions must hold at least one periodic solution, got none")
    first = solutions[0]
    frequency = np.array([s.frequency for s in solutions])
    dofs, index = _dof_coords(first.model)
    coords: dict[str, tuple] = {"frequency": ("frequency", frequency, _frequency_attrs()), **dofs}
    f, fd = ("frequency",), ("frequency", "dof")
    data = {
        "converged": _var("converged", f, [s.converged for s in solutions]),
        "residual": _var("residual", f, [s.residual for s in solutions]),
        "iterations": _var("iterations", f, [s.iterations for s in solutions]),
        "amplitude": _var("amplitude", fd, [np.asarray(s.amplitude)[index] for s in solutions]),
    }
    if hasattr(first, "slip_distance"):  # contact pairs
        pairs = first.model.pairs
        coords["pair"] = ("pair", [f"pair{j + 1}" for j in range(len(pairs.position))], {"long_name": "pair"})
        coords["position"] = ("pair", pairs.position, POSITION_ATTRS)
        for name in ("slip_distance", "mean_pressure"):
            data[name] = _var(name, ("frequency", "pair"), [getattr(s, name) for s in solutions])
        energy = [s.friction_energy for s in solutions]
        data["friction_energy"] = _var(
            "friction_energy",
            f,
            energy,
            long_name="energy dissipated per period by friction on the interface (J per m in 2-D)",
        )
    else:
        model = first.model
        n_rel = len(np.asarray(first.relative_amplitude))
        coords.update(_contact_coords(len(model.contacts), len(model.friction), n_rel))
        fc, ff = ("frequency", "contact"), ("frequency", "friction_contact")
        data["half_peak_to_peak"] = _var("half_peak_to_peak", fd, [s.half_peak_to_peak for s in solutions])
        for name in ("relative_amplitude", "relative_half_peak_to_peak"):
            data[name] = _var(name, fc, [getattr(s, name) for s in solutions])
        for name in ("sliding_distance", "friction_energy"):
            data[name] = _var(name, ff, [getattr(s, name) for s in solutions])
    methods = sorted({_method(s) if hasattr(s, "samples") else s.path for s in solutions})
    title = f"periodic responses at {len(solutions)} frequencies"
    attrs = _attrs(solutions, title, method=", ".join(methods))
    attrs["created_by"] = "fretwear Sweep.to_xarray"
    return _dataset(data, coords, attrs)


# ---------------------------------------------------------------------------------------------------
# wear
# ---------------------------------------------------------------------------------------------------
def wear_history_dataset(h: Any):
    """The dataset of a :class:`~fretwear.wear.WearHistory` along ``cycles``.

    Per record and friction contact: ``w``, ``wear_fraction``, ``normal_load``,
    ``rate``, ``sliding_distance``, ``normalised_time``; per DOF: ``amplitude``,
    ``half_peak_to_peak``; per contact: ``relative_half_peak_to_peak``; per
    friction contact: ``u0``, ``kn``. Attributes: what ran and how it ended.
    """
    n_dofs, n_rel, nf = h.amplitude.shape[1], h.relative_half_peak_to_peak.shape[1], len(h.u0)
    coords = {
        "cycles": ("cycles", h.cycles, CYCLES_ATTRS),
        "frequency": ((), h.frequency, _frequency_attrs()),
        "dof": ("dof", dof_names(n_dofs), {"long_name": "degree of freedom"}),
        **_contact_coords(n_rel, nf),
    }
    cf, cd, cc = ("cycles", "friction_contact"), ("cycles", "dof"), ("cycles", "contact")
    data = {
        "w": _var("w", cf, h.wear),
        "wear_fraction": _var("wear_fraction", cf, h.wear_fraction),
        "normal_load": _var("normal_load", cf, h.normal_load),
        "rate": _var("rate", cf, h.rate),
        "sliding_distance": _var("sliding_distance", cf, h.sliding_distance),
        "normalised_time": _var("normalised_time", cf, h.normalised_time),
        "amplitude": _var("amplitude", cd, h.amplitude),
        "half_peak_to_peak": _var("half_peak_to_peak", cd, h.half_peak_to_peak),
        "relative_half_peak_to_peak": _var("relative_half_peak_to_peak", cc, h.relative_half_peak_to_peak),
        "u0": _var("u0", ("friction_contact",), h.u0),
        "kn": _var("kn", ("friction_contact",), h.kn),
    }
    attrs = _attrs(
        h,
        f"wear history at {h.frequency:.6g} Hz ({h.label})",
        method=h.method,
        label=h.label,
        dynamics=h.dynamics,
        harmonics=h.harmonics,
        omega=h.omega,
        kw=h.kw,
        converged=h.converged,
        status=h.status,
        solves=h.solves,
        wall_time=h.wall_time,
    )
    attrs["warnings"] = "\n".join(h.warnings)
    return _dataset(data, coords, attrs)


def wear_map_dataset(m: Any):
    """The dataset of a :class:`~fretwear.studies.WearMap` over ``frequency`` x ``cycles``.

    ``w``, ``wear_fraction`` per friction contact; ``amplitude`` and
    ``half_peak_to_peak`` per DOF; ``relative_half_peak_to_peak`` per contact;
    ``converged`` per frequency; ``u0`` per friction contact.
    """
    nf = m.wear.shape[2]
    coords = {
        "frequency": ("frequency", m.frequency, _frequency_attrs()),
        "cycles": ("cycles", m.cycles, CYCLES_ATTRS),
        "dof": ("dof", dof_names(m.amplitude.shape[2]), {"long_name": "degree of freedom"}),
        **_contact_coords(m.relative_half_peak_to_peak.shape[2], nf),
    }
    fcf, fcd = ("frequency", "cycles", "friction_contact"), ("frequency", "cycles", "dof")
    data = {
        "w": _var("w", fcf, m.wear),
        "wear_fraction": _var("wear_fraction", fcf, m.wear_fraction),
        "amplitude": _var("amplitude", fcd, m.amplitude),
        "half_peak_to_peak": _var("half_peak_to_peak", fcd, m.half_peak_to_peak),
        "relative_half_peak_to_peak": _var(
            "relative_half_peak_to_peak", ("frequency", "cycles", "contact"), m.relative_half_peak_to_peak
        ),
        "converged": _var(
            "converged", ("frequency",), m.converged, long_name="the history ran without a failure"
        ),
        "u0": _var("u0", ("friction_contact",), m.u0),
    }
    return _dataset(data, coords, _attrs(m, f"wear map ({m.label})", label=m.label))


def _pair_coords(position: np.ndarray) -> dict[str, tuple]:
    """The ``pair`` coordinate (``pair1, pair2, ...``) and its ``position`` (m)."""
    names = [f"pair{j + 1}" for j in range(len(position))]
    return {
        "pair": ("pair", names, {"long_name": "contact pair"}),
        "position": ("pair", position, POSITION_ATTRS),
    }


def interface_solution_dataset(sol: Any):
    """The dataset of an :class:`~fretwear.interface.InterfaceSolution` (DLFT on the contact pairs).

    Dimensions ``time`` (the ``N`` samples of one period, s), ``pair`` (with
    its ``position``, m), ``dof`` (the model's reported DOFs) and, with the
    Coulomb cone, ``direction`` (the two tangents ``t1``, ``t2``); the scalar
    coordinate ``frequency`` (Hz). Time signals per pair: ``tangential_force``,
    ``normal_force``, ``slip_variable``, ``pressure``, ``state`` (flags); per
    pair: ``mean_pressure``, ``slip_distance``, ``stick_fraction``, ``area``;
    per DOF: ``amplitude``; per period: ``friction_energy`` and
    ``contact_work``. Attributes: the solve's status.
    """
    normal = np.asarray(sol.normal_force)
    samples = normal.shape[1]
    dofs, index = _dof_coords(sol.model)
    period = 1.0 / sol.frequency
    coords = {
        "time": ("time", np.arange(samples) * period / samples,
                 {"units": "s", "long_name": "time over one period t_k = k T / N"}),
        "frequency": ((), sol.frequency, _frequency_attrs()),
        **dofs,
        **_pair_coords(np.asarray(sol.position)),
    }  # fmt: skip
    pt = ("pair", "time")
    tangential = pt
    if sol.problem.cone:  # (nc, N, 2): the two tangents of each pair
        coords["direction"] = ("direction", ["t1", "t2"], {"long_name": "tangent direction"})
        tangential = ("pair", "time", "direction")
    data = {
        "tangential_force": _var("tangential_force", tangential, sol.tangential_force),
        "normal_force": _var("normal_force", pt, normal),
        "slip_variable": _var("slip_variable", tangential, sol.slip_variable),
        "pressure": _var("pressure", pt, sol.pressure,
                         long_name="contact pressure of each pair over one period"),
        "state": (
            pt,
            np.asarray(sol.state, dtype=np.int8),
            {"long_name": "state of each pair over one period", **STATE_FLAGS},
        ),
        "mean_pressure": _var("mean_pressure", ("pair",), sol.mean_pressure),
        "slip_distance": _var("slip_distance", ("pair",), sol.slip_distance),
        "stick_fraction": _var("stick_fraction", ("pair",), sol.state_fraction(STICK),
                               long_name="fraction of the period each pair sticks"),
        "area": _var("area", ("pair",), sol.area),
        "amplitude": _var("amplitude", ("dof",), np.asarray(sol.amplitude)[index]),
        "friction_energy": _var(
            "friction_energy", (), sol.friction_energy,
            long_name="energy dissipated per period by friction on the interface (J per m in 2-D)",
        ),
        "contact_work": _var("contact_work", (), sol.contact_work),
    }  # fmt: skip
    method = f"{sol.path}, Nh = {sol.harmonics}"
    attrs = _attrs(
        sol,
        f"interface periodic solution at {sol.frequency:.6g} Hz ({method})",
        method=method,
        **_solve_status(sol),
        harmonics=sol.harmonics,
        samples=samples,
        cone=bool(sol.problem.cone),
    )
    return _dataset(data, coords, attrs)


def interface_history_dataset(h: Any):
    """The dataset of an :class:`~fretwear.interface.InterfaceWearHistory` along ``cycles`` and ``pair``.

    Per record and pair: ``w``, ``pressure``, ``peak_pressure``, ``slip``,
    ``stick_fraction``, ``wear_rate``, and ``state`` over the ``phase`` of the
    cycle (flags); per record: ``normal_force_sum``, ``worn_area``; per pair:
    ``area`` and the coordinate ``position`` (m).
    """
    n_pairs = len(h.position)
    state = np.asarray(h.state, dtype=np.int8).reshape(len(h.cycles), n_pairs, -1)
    coords = {
        "cycles": ("cycles", h.cycles, CYCLES_ATTRS),
        "frequency": ((), h.frequency, _frequency_attrs()),
        **_pair_coords(np.asarray(h.position)),
        "phase": (
            "phase",
            np.arange(state.shape[2]) / max(state.shape[2], 1),
            {"units": "-", "long_name": "time over the cycle t / T"},
        ),
    }
    cp = ("cycles", "pair")
    data = {
        name: _var(name, cp, np.reshape(getattr(h, name), (len(h.cycles), n_pairs)))
        for name in ("pressure", "peak_pressure", "slip", "stick_fraction", "wear_rate")
    }
    data["w"] = _var("w", cp, np.reshape(h.wear, (len(h.cycles), n_pairs)), long_name="worn depth w(x, N)")
    data["state"] = (
        ("cycles", "pair", "phase"),
        state,
        {"long_name": "state of each pair over the cycle", **STATE_FLAGS},
    )
    data["normal_force_sum"] = _var("normal_force_sum", ("cycles",), h.normal_force_sum)
    data["worn_area"] = _var("worn_area", ("cycles",), data["w"][1] @ h.area)
    data["area"] = _var("area", ("pair",), h.area)
    title = f"interface wear history at {h.frequency:.6g} Hz ({h.method})"
    attrs = _attrs(
        h,
        title,
        method=h.method,
        omega=h.omega,
        kw=h.kw,
        converged=h.converged,
        status=h.status,
        solves=h.solves,
    )
    attrs["kw_units"] = "1/Pa"
    return _dataset(data, coords, attrs)


# ---------------------------------------------------------------------------------------------------
# accuracy
# ---------------------------------------------------------------------------------------------------
def cost_dataset(study: Any):
    """The dataset of a :class:`~fretwear.studies.CostStudy` along ``rung``.

    Per rung: ``wall_time``, ``converged``, ``reference`` and ``error`` per
    ``quantity``; the coordinates ``label``, ``method`` and one per setting
    (``Nh``, ``N``, ``tol``, ``degree``: NaN where the rung has none); per
    quantity: the ``reference_value``. The references in the attributes.
    """
    from .studies.accuracy import QUANTITIES

    rungs = study.rungs
    keys = sorted({k for r in rungs for k in r.settings})
    coords: dict[str, tuple] = {
        "rung": ("rung", np.arange(len(rungs)), {"long_name": "rung of the ladder"}),
        "quantity": ("quantity", list(QUANTITIES), {"long_name": "measured quantity"}),
        "label": ("rung", [r.label for r in rungs], {"long_name": "method and settings"}),
        "method": ("rung", [r.method for r in rungs], {"long_name": "method"}),
        "frequency": ((), study.frequency, _frequency_attrs()),
    }
    for key in keys:
        attrs = {"units": "-", "long_name": f"setting {key} (NaN: not a setting of the rung)"}
        coords[key] = ("rung", [float(r.settings.get(key, np.nan)) for r in rungs], attrs)
    data = {
        "wall_time": _var("wall_time", ("rung",), [r.wall_time for r in rungs]),
        "converged": _var("converged", ("rung",), [r.converged for r in rungs]),
        "reference": _var("reference", ("rung",), [r.reference for r in rungs]),
        "error": _var(
            "error", ("rung", "quantity"), [[r.errors.get(q, np.nan) for q in QUANTITIES] for r in rungs]
        ),
        "reference_value": _var(
            "reference_value", ("quantity",), [study.reference_values.get(q, np.nan) for q in QUANTITIES]
        ),
    }
    refs = {f"reference_{k}": v for k, v in study.reference.items()}
    attrs = _attrs(study, f"cost ladder at {study.frequency:.6g} Hz", **refs)
    return _dataset(data, coords, attrs)
