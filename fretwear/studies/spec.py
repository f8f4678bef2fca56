"""Study specifications: the TOML file that ``fretwear study`` runs, parsed and checked.

A spec names the model, the parameters (fixed values, grid axes, random draws)
and the quantities to compute. Every error is a :class:`SpecError`, one line
that starts with the key at fault (``parameters.mu: ...``).

Format
------
::

    [study]
    title = "Probabilistic wear life at 0.7 Hz"    # optional
    quantities = ["wear_life"]                      # any of "frf", "wear_life", "wear" ("magnification":
                                                    # the bladed disk's, section "Mistuning" below)
    seed = 2024                                     # integer >= 0; required with random parameters
    samples = 1000                                  # number of random draws; required with them
    points_per_task = 25                            # optional: points computed by one task

    [model]
    name = "paper"                                  # the paper's 2-DOF example (section 2.1), or
    # file = "my_structure.toml"                    # a model file (relative to the spec), or
    # name = "cylinder_on_flat"                     # a model with contact pairs, its builder's
    # contact_nodes = 16                            # parameters in the same table

    [parameters]                                    # each value: fixed, grid or random
    frequency = 0.7                                                 # Hz, fixed
    mu = { distribution = "uniform", low = 0.4, high = 1.0 }        # random
    fex = { distribution = "normal", mean = 10.0, std = 1.0 }       # random, N
    kw = [1e-11, 2e-11]                                             # grid: the listed values
    # frequency = { start = 0.3, stop = 1.3, num = 41 }             # grid: linspace (scale = "log")
    cycles = 1e7                                                    # wear horizon (cycles)

    [wear]
    fractions = [0.1, 0.5, 0.9]                     # "wear_life": cycles to w = fraction * u0
    # depths = [1e-6, 5e-6]                         # contact pairs: cycles to a worn depth (m)
    ncycles = 60                                    # "wear": log-spaced cycle counts from 1 to the horizon

Parameters (:data:`PARAMETERS`): ``frequency`` (Hz), ``fex`` (N, paper model),
``force_scale`` (-, model files: scales every external force), ``mu`` (-),
``normal_load`` (N) or ``u0`` (m), ``kn`` (N/m), ``kw`` (1/N), ``cycles``
(horizon), ``harmonics`` (``Nh`` of the DLFT dynamics: of the ``frf``
quantity, default 21; for the wear quantities, giving it asks for the DLFT
dynamics), ``method`` (``"auto"`` or a key of :data:`fretwear.METHODS`),
``dynamics`` (``"auto"``, ``"shooting"``, ``"dlft"``) and ``tol`` (slow-time
tolerance of the methods that take one). ``method`` and ``dynamics`` mean
what they mean to :func:`fretwear.wear_history` and ``fretwear wear``: with
neither given, the exact method on the exact event-driven dynamics wherever
they apply (:func:`fretwear.wear.resolve_dynamics`). Distributions:
``uniform`` (``low``, ``high``), ``loguniform`` (``low``, ``high``), ``normal``
(``mean``, ``std``) and ``lognormal`` (``median``, ``sigma`` of the logarithm).

Quantities: ``frf`` (periodic response per point: first-harmonic amplitudes,
relative amplitude, sliding distance and friction energy per period),
``wear_life`` (cycles to the wear fractions of ``u0``) and ``wear`` (``w / u0``
and amplitudes on the cycle grid; with a frequency axis, a wear map).

Models with contact pairs (:data:`MODELS`: ``name = "cylinder_on_flat"`` with
the parameters of :class:`fretwear.interface.fe.CylinderOnFlat`, ``name =
"paper_interface"`` with ``fex``, ``mu``, ``normal_load``, ``kn``, or ``file =``
an interface model file, ``fretwear.interface.modelfile``) take the
parameters :data:`PAIR_PARAMETERS`: ``frequency`` (Hz, fixed or a grid),
``force_scale`` (every external force, the static load too), ``mu`` (every
pair), ``kw`` (1/Pa, required with ``wear``), ``cycles``, ``harmonics``
(default 7), ``method`` (``"auto"`` is ``"stepping"``, or ``"polynomial"``)
and ``tol`` (the stepping's ``rtol``). Their quantities are ``frf``, ``wear``
(profiles on the cycle grid) and ``wear_life``: with no ``u0``, the cycles to
the worn depths ``[wear] depths`` (m) at the deepest pair. The model is reduced once
(Craig-Bampton, :func:`fretwear.reduce`) at ``f_max`` = the highest frequency
times the highest ``Nh`` (:attr:`StudySpec.reduce_hz`); each point then calls
:func:`fretwear.solve_periodic` or :func:`fretwear.wear_history` on that
reduced model.

Random draws: parameter ``k`` (in the order of :data:`PARAMETERS`, or of
:data:`PAIR_PARAMETERS` for a model with contact pairs) uses the
stream ``numpy.random.default_rng([seed, k])``, so sample ``i`` is the same
whatever the number of samples (``--samples`` only adds or removes draws at the end).

Mistuning
---------
``name = "bladed_disk"`` is the linear lumped disk (:func:`fretwear.bladed_disk` without contacts), its
parameters in ``[model]``: ``sectors``, ``engine_order``, ``damping_ratio``, ``fex`` (N) and the
sector's masses ``m0, mb1, mb2`` (kg) and springs ``kG, k0, kb1, kb2`` (N/m). Its one quantity is
``magnification`` (:data:`DISK_QUANTITIES`, of no other model), the Monte Carlo of
:func:`fretwear.disk.magnification` over mistuning patterns::

    [study]
    quantities = ["magnification"]
    seed = 2007                                     # required: the patterns' seed
    samples = 100                                   # required: patterns per level

    [model]
    name = "bladed_disk"
    sectors = 24
    engine_order = 3

    [parameters]                                    # :data:`DISK_PARAMETERS`, both required
    level = [0.0, 0.005, 0.01, 0.02, 0.05]          # a grid (list, or start/stop/num), or one value
    band = [165.0, 200.0]                           # Hz: the peaks are searched in [f_low, f_high]

The points are ``(level, sample)`` (:attr:`StudySpec.dims`). The pattern of point ``(level, i)`` is row
``i`` of ``draw_mistuning(sectors, level, samples, seed)`` (:func:`fretwear.disk.draw_mistuning`): the
same normal draws scaled by each level (common random numbers: the curve against the level is smooth),
the patterns of ``fretwear disk mistuning --level L --samples S --seed SEED``, whatever the split into
tasks. Row ``i`` does not depend on ``samples`` unless some ``delta <= -1`` was redrawn (at a level of
0.1, a value 10 standard deviations off: never in practice; at 0.5 about 2 % of the values).
"""

from __future__ import annotations

import hashlib
import json
import math
import tomllib
from collections.abc import Mapping
from dataclasses import dataclass, field, fields
from pathlib import Path
from typing import Any

import numpy as np

from .._version import __version__
from ..model import paper_model, read_model
from ..parameters import describe
from ..wear import DYNAMICS, METHODS

__all__ = [
    "DISK_PARAMETERS",
    "DISK_QUANTITIES",
    "FRF_HARMONICS",
    "MODELS",
    "PAIR_PARAMETERS",
    "PAIR_QUANTITIES",
    "PARAMETERS",
    "QUANTITIES",
    "Distribution",
    "Parameter",
    "SpecError",
    "StudySpec",
    "parse_spec",
    "read_spec",
]


class SpecError(ValueError):
    """Invalid study specification; the message starts with the key at fault."""

    def __init__(self, key: str, message: str):
        super().__init__(f"{key}: {message}")
        self.key = key


@dataclass(frozen=True)
class Parameter:
    """A study parameter: its entry ``table`` of :data:`fretwear.parameters.PARAMETERS` (unit, type, valid
    range, default, description), or its ``choices``; and whether it may be drawn at random."""

    name: str
    table: str = ""  # its entry in fretwear.parameters.PARAMETERS
    choices: tuple[str, ...] = ()
    random: bool = True
    note: str = ""  # what the spec adds to the table's description
    fixed_why: str = ""  # why it cannot be random, when that is not its type

    @property
    def kind(self) -> type:
        """``str`` for a choice, else ``int`` or ``float`` as the table says."""
        return str if not self.table else int if describe(self.table).integer else float

    @property
    def unit(self) -> str:
        """The table's unit (``"-"`` for a pure number, ``""`` for a choice)."""
        return describe(self.table).unit or "-" if self.table else ""

    @property
    def long_name(self) -> str:
        """The table's description (and the spec's note)."""
        return " ".join(filter(None, (describe(self.table).doc if self.table else "", self.note)))

    def check(self, key: str, value: Any) -> Any:
        """``value`` converted to the parameter's type, or :class:`SpecError` naming ``key``."""
        if self.kind is str:
            if not isinstance(value, str) or value not in self.choices:
                raise SpecError(key, f"must be one of {', '.join(map(repr, self.choices))}, got {value!r}")
            return value
        bounds = describe(self.table)
        if self.kind is int and (isinstance(value, bool) or not isinstance(value, int)):
            raise SpecError(key, f"must be {bounds.range_text()}, got {value!r}")
        if not bounds.valid(value):
            raise SpecError(key, f"must be {bounds.range_text()}, got {value!r}")
        return self.kind(value)


#: every parameter a spec may set, in the order of the random streams and of the grid axes' defaults
PARAMETERS: Mapping[str, Parameter] = {
    p.name: p
    for p in (
        Parameter("frequency", "f"),
        Parameter("fex", "fex", note="(paper model)"),
        Parameter("force_scale", "force_scale"),
        Parameter("mu", "mu"),
        Parameter("normal_load", "fn"),
        Parameter("u0", "u0"),
        Parameter("kn", "kn"),
        Parameter("kw", "kw"),
        Parameter("cycles", "cycles"),
        Parameter("harmonics", "harmonics", random=False),
        Parameter("method", choices=("auto", *METHODS), random=False, note="slow-time method"),
        Parameter(
            "dynamics",
            choices=DYNAMICS,
            random=False,
            note="periodic dynamics of the exact and stepping methods",
        ),  # fmt: skip
        Parameter("tol", "tol", random=False),
    )
}

#: the quantities a study computes, and the parameters each one uses
QUANTITIES: Mapping[str, tuple[str, ...]] = {
    "frf": ("frequency", "fex", "force_scale", "mu", "normal_load", "u0", "kn", "harmonics"),
    "wear_life": tuple(PARAMETERS),
    "wear": tuple(PARAMETERS),
}

#: values of the parameters a spec leaves out (the paper model's are those of section 2.1); ``harmonics``
#: has none: the wear quantities then run on the exact dynamics, the ``frf`` on :data:`FRF_HARMONICS`
DEFAULTS: Mapping[str, Any] = {"kw": describe("kw").default, "method": "auto", "dynamics": "auto"}
#: ``Nh`` of the ``frf`` quantity when the spec gives no ``harmonics`` (the table's for a study)
FRF_HARMONICS = describe("harmonics").default_for("study")
PAPER_DEFAULTS: Mapping[str, float] = {
    name: describe(PARAMETERS[name].table).default for name in ("fex", "mu", "normal_load", "kn")
}

#: slow-time methods of a model with contact pairs (``fretwear.interface.jobs.wear_history()``)
PAIR_METHODS = ("auto", "stepping", "polynomial")
#: the parameters of a study over a model with contact pairs (module docstring): the interface rows of
#: the table where the unit differs (``kw`` in 1/Pa, ``mu`` may be 0, ``tol`` is the stepping's ``rtol``)
PAIR_PARAMETERS: Mapping[str, Parameter] = {
    p.name: p
    for p in (
        Parameter(
            "frequency",
            "f",
            random=False,
            fixed_why="a model with contact pairs is reduced once at the highest frequency: "
            "give a value or a grid",
        ),
        Parameter("force_scale", "force_scale", note="(every external force, the static load too)"),
        Parameter("mu", "interface_mu", note="(every pair)"),
        Parameter("kw", "interface_kw"),
        Parameter("cycles", "cycles"),
        Parameter("harmonics", "harmonics", random=False),
        Parameter("method", choices=PAIR_METHODS, random=False, note="slow-time method"),
        Parameter("tol", "rtol", random=False),
    )
}
#: the quantities of a study over a model with contact pairs, and the parameters each one uses
PAIR_QUANTITIES: Mapping[str, tuple[str, ...]] = {
    "frf": ("frequency", "force_scale", "mu", "harmonics"),
    "wear_life": tuple(PAIR_PARAMETERS),
    "wear": tuple(PAIR_PARAMETERS),
}
#: ``Nh`` of a model with contact pairs when the spec gives none (the front functions' default)
PAIR_HARMONICS = describe("harmonics").default
#: the ``CylinderOnFlat`` fields checked against a row of the table (the others by the builder itself)
_CYLINDER_ROWS = {"contact_nodes": "contact_nodes", "q_ratio": "q_ratio", "window": "window",
                  "normal_load": "line_load", "mu": "interface_mu", "drive_displacement": "drive",
                  "arm_stiffness": "arm_stiffness"}  # fmt: skip
#: the named models of ``[model] name``: the keys of the ``[model]`` table each takes, by its table row
#: (None: checked by the builder), with ``paper`` the 1-D model and the others models with contact pairs
MODELS: Mapping[str, Mapping[str, str | None]] = {
    "paper": {},
    "cylinder_on_flat": {},  # CylinderOnFlat's fields, by _model_keys (scikit-fem loads on first use)
    "paper_interface": {"fex": "fex", "mu": "mu", "normal_load": "fn", "kn": "kn"},
    # the linear disk: its contacts are not in a mistuning study (fretwear.disk.magnification)
    "bladed_disk": {"sectors": "sectors", "engine_order": "engine_order", "damping_ratio": None, "fex": "fex",
                    **dict.fromkeys(("m0", "mb1", "mb2", "kG", "k0", "kb1", "kb2"))},
}  # fmt: skip
#: the parameters of the bladed disk's mistuning study: ``level`` a grid (module docstring); ``band``
#: the pair ``[f_low, f_high]`` (Hz), each end in the range of the table's ``fmin`` and ``fmax``
DISK_PARAMETERS: Mapping[str, Parameter] = {
    "level": Parameter("level", "level", random=False, fixed_why="its draws are the study's: give a grid"),
    "band": Parameter("band", "fmin", random=False, note="(the band [f_low, f_high] of the peaks)"),
}
#: the quantities of the bladed disk (and of no other model), and the parameters each one uses
DISK_QUANTITIES: Mapping[str, tuple[str, ...]] = {"magnification": ("level", "band")}

_DISTRIBUTIONS = {
    "uniform": ("low", "high"),
    "loguniform": ("low", "high"),
    "normal": ("mean", "std"),
    "lognormal": ("median", "sigma"),
}


@dataclass(frozen=True)
class Distribution:
    """A random parameter: ``kind`` (a key of ``_DISTRIBUTIONS``) and its two arguments."""

    kind: str
    a: float
    b: float

    def draw(self, n: int, rng: np.random.Generator) -> np.ndarray:
        """``n`` draws from ``rng`` (in order: the first ``m`` do not depend on ``n``)."""
        if self.kind == "uniform":
            return rng.uniform(self.a, self.b, n)
        if self.kind == "loguniform":
            return np.exp(rng.uniform(np.log(self.a), np.log(self.b), n))
        if self.kind == "normal":
            return rng.normal(self.a, self.b, n)
        return self.a * np.exp(rng.normal(0.0, self.b, n))

    def describe(self) -> dict[str, Any]:
        names = _DISTRIBUTIONS[self.kind]
        return {"distribution": self.kind, names[0]: self.a, names[1]: self.b}


@dataclass(frozen=True)
class StudySpec:
    """A checked study specification.

    Attributes
    ----------
    title : str
    quantities : tuple of str
        Keys of :data:`QUANTITIES`.
    model_kind : str
        ``"file"``, or the name of :data:`MODELS` (``"paper"``, ``"cylinder_on_flat"``, ...).
    model : Model
        The base model (the paper model with its defaults, the model file's, or the named builder's).
    model_parameters : dict
        The builder's parameters given in ``[model]`` (named models with contact pairs).
    fixed : dict
        Fixed parameters (with the defaults filled in).
    grid : dict of ndarray
        Grid axes, in spec order with ``frequency`` last.
    random : dict of Distribution
        Random parameters, in the order of :data:`PARAMETERS`.
    samples, seed : int
        Number of draws and seed (0 and ``None`` without random parameters).
    fractions : tuple of float
        Wear fractions of ``u0`` (``wear_life``; 1-D contacts).
    depths : tuple of float
        Worn depths (m) of ``wear_life`` for a model with contact pairs.
    ncycles : int
        Cycle counts of the wear grid (``wear``).
    points_per_task : int or None
        Points per task, when the spec sets it.
    text : str
        The spec file as written.
    model_file : str or None
        The model file's path, as given in the spec.
    """

    title: str
    quantities: tuple[str, ...]
    model_kind: str
    model: Any
    fixed: dict[str, Any]
    grid: dict[str, np.ndarray]
    random: dict[str, Distribution]
    samples: int = 0
    seed: int | None = None
    fractions: tuple[float, ...] = (0.1, 0.5, 0.9)
    depths: tuple[float, ...] = ()
    ncycles: int = 60
    points_per_task: int | None = None
    text: str = ""
    model_file: str | None = None
    model_text: str = field(default="", repr=False)
    model_parameters: dict[str, Any] = field(default_factory=dict)

    @property
    def pairs(self) -> bool:
        """Whether the model has contact pairs (the parameters :data:`PAIR_PARAMETERS`)."""
        return self.model.pairs is not None

    @property
    def mistuning(self) -> bool:
        """Whether this is the bladed disk's mistuning study (the quantity ``magnification``)."""
        return "magnification" in self.quantities

    @property
    def parameters(self) -> Mapping[str, Parameter]:
        """The parameters this spec's model takes: :data:`PAIR_PARAMETERS`, :data:`DISK_PARAMETERS` or
        :data:`PARAMETERS`."""
        return PAIR_PARAMETERS if self.pairs else DISK_PARAMETERS if self.mistuning else PARAMETERS

    @property
    def reduce_hz(self) -> float | None:
        """``f_max`` (Hz) of the one reduction of a model with contact pairs: the highest frequency times
        the highest ``Nh`` (None for a model with 1-D contacts)."""
        if not self.pairs:
            return None
        top = {
            k: np.max(self.grid[k]) if k in self.grid else self.fixed[k] for k in ("frequency", "harmonics")
        }
        return float(top["frequency"] * top["harmonics"])

    @property
    def dims(self) -> tuple[str, ...]:
        """Dimensions of the points: ``sample`` (with random parameters), then the grid axes; for the
        mistuning study ``("level", "sample")`` (a task's patterns share their level and its tuned peak)."""
        if self.mistuning:
            return ("level", "sample")
        return (("sample",) if self.random else ()) + tuple(self.grid)

    @property
    def shape(self) -> tuple[int, ...]:
        if self.mistuning:
            return (len(self.grid["level"]), self.samples)
        return ((self.samples,) if self.random else ()) + tuple(len(v) for v in self.grid.values())

    @property
    def n_points(self) -> int:
        return int(np.prod(self.shape, dtype=np.int64))

    @property
    def wear(self) -> bool:
        """Whether a wear quantity is asked for."""
        return any(q in self.quantities for q in ("wear_life", "wear"))

    def draws(self) -> dict[str, np.ndarray]:
        """The random parameters' values, shape (samples,) each (see the module docstring)."""
        keys = list(self.parameters)
        return {
            name: dist.draw(self.samples, np.random.default_rng([self.seed, keys.index(name)]))
            for name, dist in self.random.items()
        }

    def cycle_grid(self) -> np.ndarray:
        """Cycle counts of the ``wear`` quantity: ``ncycles`` log-spaced from 1 to the horizon."""
        return np.geomspace(1.0, self.fixed["cycles"], self.ncycles)

    def resolved(self) -> dict[str, Any]:
        """Everything that defines the results, as plain JSON data (the store's key is its hash)."""
        return {
            "title": self.title,
            "quantities": list(self.quantities),
            "model": {
                "kind": self.model_kind,
                "file": self.model_file,
                "file_sha256": _sha(self.model_text),
                "parameters": self.model_parameters,
            },
            "fixed": self.fixed,
            "grid": {k: v.tolist() for k, v in self.grid.items()},
            "random": {k: v.describe() for k, v in self.random.items()},
            "samples": self.samples,
            "seed": self.seed,
            "fractions": list(self.fractions),
            "depths": list(self.depths),
            "ncycles": self.ncycles,
            "points_per_task": self.points_per_task,
            "fretwear_version": __version__,
        }

    def key(self) -> str:
        """Hash of :meth:`resolved`: two runs with the same key compute the same numbers."""
        return _sha(json.dumps(self.resolved(), sort_keys=True))


def _sha(text: str) -> str:
    return hashlib.sha256(text.encode()).hexdigest()


def read_spec(path: str | Path, samples: int | None = None, points_per_task: int | None = None) -> StudySpec:
    """Read and check the study spec at ``path`` (see the module docstring).

    ``samples`` and ``points_per_task`` override the spec's values (``--samples``,
    ``--points-per-task``). Raises :class:`SpecError`.
    """
    path = Path(path)
    try:
        text = path.read_text(encoding="utf-8")
    except OSError as exc:
        raise SpecError("SPEC", f"cannot read {str(path)!r}: {exc.strerror or exc}") from None
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise SpecError("SPEC", f"{str(path)!r} is not valid TOML: {exc}") from None
    return parse_spec(data, text=text, base=path.parent, samples=samples, points_per_task=points_per_task)


def _table(data: Mapping[str, Any], key: str, allowed: tuple[str, ...]) -> dict[str, Any]:
    table = data.get(key, {})
    if not isinstance(table, dict):
        raise SpecError(key, f"must be a table ([{key}]), got {table!r}")
    for name in table:
        if name not in allowed:
            raise SpecError(f"{key}.{name}", f"unknown key (valid: {', '.join(allowed)})")
    return table


def _integer(key: str, value: Any, table: str) -> int:
    """``value``, an integer in the range of :data:`fretwear.parameters.PARAMETERS` ``[table]``."""
    bounds = describe(table)
    if isinstance(value, bool) or not isinstance(value, int) or not bounds.valid(value):
        raise SpecError(key, f"must be {bounds.range_text()}, got {value!r}")
    return value


def parse_spec(
    data: Mapping[str, Any],
    *,
    text: str = "",
    base: str | Path = ".",
    samples: int | None = None,
    points_per_task: int | None = None,
) -> StudySpec:
    """Check parsed TOML ``data`` and build the :class:`StudySpec` (see :func:`read_spec`)."""
    for name in data:
        if name not in ("study", "model", "parameters", "wear"):
            raise SpecError(name, "unknown table (valid: study, model, parameters, wear)")
    study = _table(data, "study", ("title", "quantities", "seed", "samples", "points_per_task"))
    model_kind, model, model_file, model_text, model_params = _model(_model_table(data), Path(base))
    pairs, disk = model.pairs is not None, model_kind == "bladed_disk"
    table, uses = (
        (PAIR_PARAMETERS, PAIR_QUANTITIES) if pairs else
        (DISK_PARAMETERS, DISK_QUANTITIES) if disk else (PARAMETERS, QUANTITIES)
    )  # fmt: skip
    quantities = study.get("quantities")
    if quantities is None:
        raise SpecError("study.quantities", f"required: a list of {', '.join(map(repr, uses))}")
    if isinstance(quantities, str):
        quantities = [quantities]
    if not disk and isinstance(quantities, list) and any(q in DISK_QUANTITIES for q in quantities):
        raise SpecError("study.quantities", "'magnification' is a quantity of the model 'bladed_disk' only "
                        f"([model] name = 'bladed_disk'), not of the model {model_kind!r}")  # fmt: skip
    if not isinstance(quantities, list) or not quantities or any(q not in uses for q in quantities):
        raise SpecError(
            "study.quantities",
            f"must be a non-empty list of {', '.join(map(repr, uses))}, got {study['quantities']!r}",
        )
    quantities = tuple(dict.fromkeys(quantities))
    title = study.get("title", "parameter study")
    if not isinstance(title, str):
        raise SpecError("study.title", f"must be a string, got {title!r}")
    ppt = study.get("points_per_task")
    ppt = _integer("study.points_per_task", ppt, "points_per_task") if ppt is not None else None
    if points_per_task is not None:
        ppt = _integer("--points-per-task", points_per_task, "points_per_task")

    raw = data.get("parameters", {})
    for name in raw if pairs and isinstance(raw, dict) else ():
        if name in PARAMETERS and name not in table:
            raise SpecError(
                f"parameters.{name}",
                f"not a parameter of a model with contact pairs (valid: {', '.join(table)})",
            )
    params = _table(data, "parameters", tuple(table))
    if disk:
        return _disk_spec(data, study, params, samples, title=title, quantities=quantities, model=model,
                          points_per_task=ppt, text=text, model_parameters=model_params)  # fmt: skip
    used = set().union(*(uses[q] for q in quantities))
    fixed: dict[str, Any] = {}
    grid: dict[str, np.ndarray] = {}
    random: dict[str, Distribution] = {}
    for name, value in params.items():
        key = f"parameters.{name}"
        if name not in used:
            raise SpecError(key, f"not used by the quantities {', '.join(quantities)}")
        if model_kind == "paper" and name == "force_scale":
            raise SpecError(key, "only for a model file; the paper model's excitation is fex (N)")
        if model_kind == "file" and name == "fex":
            raise SpecError(key, "only for the paper model; scale a model file's forces with force_scale")
        kind, parsed = _value(key, table[name], value)
        {"fixed": fixed, "grid": grid, "random": random}[kind][name] = parsed
    if "normal_load" in params and "u0" in params:
        raise SpecError("parameters.u0", "give normal_load (N) or u0 (m), not both")
    if "frequency" not in params:
        raise SpecError("parameters.frequency", "required: the excitation frequency (Hz), > 0")
    if "frequency" in grid:  # frequency last: an FRF is computed along it with warm starts
        grid["frequency"] = grid.pop("frequency")
    if pairs:
        _pair_checks(quantities, params, fixed, grid)
        for name, value in (("method", "auto"), ("harmonics", PAIR_HARMONICS)):
            if name in used and name not in params:
                fixed[name] = value
    else:
        _wear_checks(quantities, params, fixed, grid)
    for name, value in DEFAULTS.items() if not pairs else ():
        if name in used and name not in params and not (name == "dynamics" and not _stepping(fixed, grid)):
            fixed[name] = value
    if model_kind == "paper":
        for name, value in PAPER_DEFAULTS.items():
            if name not in params and not (name == "normal_load" and "u0" in params):
                fixed[name] = value

    wear = _table(data, "wear", ("fractions", "depths", "ncycles"))
    if wear and not any(q in quantities for q in ("wear_life", "wear")):
        raise SpecError("wear", "the [wear] table needs the quantity 'wear_life' or 'wear'")
    depths = _depths(wear, pairs, "wear_life" in quantities)
    if pairs and "fractions" in wear:
        raise SpecError("wear.fractions", "a model with contact pairs has no u0: give depths (m), > 0")
    fractions = wear.get("fractions", [0.1, 0.5, 0.9])
    if (
        not isinstance(fractions, list)
        or not fractions
        or any(isinstance(f, bool) or not isinstance(f, (int, float)) or not 0 < f < 1 for f in fractions)
        or len(set(fractions)) != len(fractions)
    ):
        raise SpecError(
            "wear.fractions", f"must be a non-empty list of distinct numbers in (0, 1), got {fractions!r}"
        )
    ncycles = _integer("wear.ncycles", wear.get("ncycles", 60), "ncycles")

    n_samples, seed = 0, None
    if random:
        seed = study.get("seed")
        if seed is None:
            raise SpecError("study.seed", "required with random parameters: an integer >= 0")
        seed = _integer("study.seed", seed, "seed")
        n_samples = study.get("samples") if samples is None else samples
        if n_samples is None:
            raise SpecError("study.samples", "required with random parameters: an integer >= 1")
        n_samples = _integer("--samples" if samples is not None else "study.samples", n_samples, "draws")
    else:
        for name in ("seed", "samples"):
            if name in study:
                raise SpecError(f"study.{name}", "no parameter is random (give one a distribution)")
        if samples is not None:
            raise SpecError("--samples", "the spec has no random parameter")
    points = max(n_samples, 1) * math.prod(len(v) for v in grid.values())
    _integer("study points (grid x samples)", points, "points")
    return StudySpec(
        title=title,
        quantities=quantities,
        model_kind=model_kind,
        model=model,
        fixed=fixed,
        grid=grid,
        random=random,
        samples=n_samples,
        seed=seed,
        fractions=tuple(float(f) for f in fractions),
        depths=depths,
        ncycles=ncycles,
        points_per_task=ppt,
        text=text,
        model_file=model_file,
        model_text=model_text,
        model_parameters=model_params,
    )


def _model_table(data: Mapping[str, Any]) -> dict[str, Any]:
    """The ``[model]`` table, its keys checked against those of its named model (:data:`MODELS`)."""
    table = data.get("model", {})
    if not isinstance(table, dict):
        raise SpecError("model", f"must be a table ([model]), got {table!r}")
    name = table.get("name", "paper")
    if "file" in table and "name" not in table:
        return _table(data, "model", ("file",))
    if not isinstance(name, str) or name not in MODELS:
        raise SpecError("model.name", f"must be one of {', '.join(map(repr, MODELS))} (or use file = "
                        f"'model.toml'), got {name!r}")  # fmt: skip
    return _table(data, "model", ("name", "file", *_model_keys(name)))


def _model_keys(name: str) -> Mapping[str, str | None]:
    """The parameters of the named model ``name`` and their table rows (:data:`MODELS`)."""
    if name == "cylinder_on_flat":
        from ..interface.fe import CylinderOnFlat  # the mesher loads scikit-fem: only for this model

        return {f.name: _CYLINDER_ROWS.get(f.name) for f in fields(CylinderOnFlat)}
    return MODELS[name]


def _model(table: Mapping[str, Any], base: Path):
    """``(kind, model, file, file text, builder parameters)`` of the ``[model]`` table."""
    if "name" in table and "file" in table:
        raise SpecError("model.file", "give name or file, not both")
    if "file" in table:
        file = table["file"]
        if not isinstance(file, str) or not file:
            raise SpecError("model.file", f"must be the path of a model file, got {file!r}")
        path = Path(file) if Path(file).is_absolute() else base / file
        try:
            text = path.read_text(encoding="utf-8")
            return "file", _read_model_file(path, text), file, text, {}
        except OSError as exc:
            raise SpecError("model.file", f"cannot read {str(path)!r}: {exc.strerror or exc}") from None
        except ValueError as exc:
            raise SpecError("model.file", " ".join(str(exc).split())) from None
    name = table.get("name", "paper")
    if name == "paper":
        return "paper", paper_model(), None, "", {}
    keys = _model_keys(name)
    params = {}
    for key, value in table.items():
        if key == "name":
            continue
        row = keys[key]
        if row is not None:
            params[key] = _integer(f"model.{key}", value, row) if describe(row).integer else _number(
                f"model.{key}", value, row)  # fmt: skip
        elif isinstance(value, bool) or not isinstance(value, (int, float)):
            raise SpecError(f"model.{key}", f"must be a number, got {value!r}")
        else:
            params[key] = float(value)
    try:
        if name == "cylinder_on_flat":
            from ..interface.fe import cylinder_on_flat

            model = cylinder_on_flat(**params)
        elif name == "bladed_disk":
            from ..model import bladed_disk

            model = bladed_disk(contacts="none", **params)
        else:
            from ..interface.paper import paper_interface

            model = paper_interface(**params)
    except ValueError as exc:  # the builder's own checks name the parameter first
        first = str(exc).split()[0]
        raise SpecError(f"model.{first}" if first in keys else "model", " ".join(str(exc).split())) from None
    return name, model, None, "", params


def _disk_spec(data, study, params, samples, **spec) -> StudySpec:
    """The bladed disk's mistuning study (module docstring): ``level``, ``band``, ``seed`` and ``samples``
    checked; ``spec`` the :class:`StudySpec` fields read already."""
    if "wear" in data:
        raise SpecError("wear", "the bladed disk's study has no wear (its quantity is 'magnification')")
    for name, what in (("level", "the mistuning levels, a grid of standard deviations in [0, 0.5]"),
                       ("band", "[f_low, f_high] (Hz), the band of the peaks")):  # fmt: skip
        if name not in params:
            raise SpecError(f"parameters.{name}", f"required: {what}")
    kind, level = _value("parameters.level", DISK_PARAMETERS["level"], params["level"])
    band = params["band"]
    if (
        not isinstance(band, list)
        or len(band) != 2
        or any(isinstance(f, bool) or not isinstance(f, (int, float)) for f in band)
    ):
        raise SpecError("parameters.band", f"must be [f_low, f_high], two frequencies (Hz), got {band!r}")
    band = [_number("parameters.band[0]", band[0], "fmin"), _number("parameters.band[1]", band[1], "fmax")]
    if not band[0] < band[1]:
        raise SpecError("parameters.band", f"must be [f_low, f_high] with f_low < f_high (Hz), got {band!r}")
    values = {}
    for name, row, why in (("seed", "seed", "the patterns' seed"), ("samples", "draws", "draws per level")):
        value = study.get(name) if name == "seed" or samples is None else samples
        if value is None:
            raise SpecError(f"study.{name}", f"required for the quantity 'magnification': {why}")
        values[name] = _integer(f"study.{name}" if name == "seed" or samples is None else "--samples",
                                value, row)  # fmt: skip
    grid = {"level": level if kind == "grid" else np.array([level])}
    _integer("study points (grid x samples)", len(grid["level"]) * values["samples"], "points")
    return StudySpec(model_kind="bladed_disk", fixed={"band": band}, grid=grid, random={}, **values, **spec)


def _read_model_file(path: Path, text: str):
    """The model of a model file: an interface model file (``[matrices]`` and ``[contact]``:
    :func:`fretwear.interface.read_interface_model`) or a 1-D model file (:func:`fretwear.read_model`)."""
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError:
        data = {}  # read_model says what is wrong with it
    if "contact" in data or "matrices" in data:
        from ..interface.modelfile import read_interface_model

        return read_interface_model(path)
    return read_model(path)


def _depths(wear: Mapping[str, Any], pairs: bool, life: bool) -> tuple[float, ...]:
    """The worn depths (m) of ``wear_life`` for a model with contact pairs: ``[wear] depths``."""
    if not pairs:
        if "depths" in wear:
            raise SpecError("wear.depths", "only for a model with contact pairs; give fractions of u0")
        return ()
    depths = wear.get("depths")
    if depths is None:
        if life:
            raise SpecError("wear.depths", "required for 'wear_life' of a model with contact pairs: the worn "
                            "depths (m) to reach, e.g. [1e-6, 5e-6]")  # fmt: skip
        return ()
    if (
        not isinstance(depths, list)
        or not depths
        or any(isinstance(d, bool) or not isinstance(d, (int, float)) or not 0 < d < math.inf for d in depths)
        or len(set(depths)) != len(depths)
    ):
        raise SpecError("wear.depths", f"must be a non-empty list of distinct depths > 0 (m), got {depths!r}")
    return tuple(float(d) for d in depths)


def _number(key: str, value: Any, table: str) -> float:
    """``value``, a number in the range of :data:`fretwear.parameters.PARAMETERS` ``[table]``."""
    bounds = describe(table)
    if not bounds.valid(value):
        raise SpecError(key, f"must be {bounds.range_text()}, got {value!r}")
    return float(value)


def _value(key: str, param: Parameter, value: Any) -> tuple[str, Any]:
    """``("fixed" | "grid" | "random", parsed value)`` of one parameter entry."""
    if isinstance(value, list):
        if not value:
            raise SpecError(key, "an empty list: a grid needs at least one value")
        _integer(f"{key} (its length)", len(value), "grid_num")
        values = [param.check(f"{key}[{i}]", v) for i, v in enumerate(value)]
        if len(set(values)) != len(values):
            raise SpecError(key, f"grid values must be distinct, got {value!r}")
        return "grid", np.array(values)
    if not isinstance(value, dict):
        return "fixed", param.check(key, value)
    if "distribution" in value:
        if not param.random:
            raise SpecError(key, f"cannot be random ({param.fixed_why or f'a {param.kind.__name__}'}): "
                            "give a value or a list")  # fmt: skip
        kind = value["distribution"]
        if kind not in _DISTRIBUTIONS:
            raise SpecError(
                f"{key}.distribution", f"must be one of {', '.join(map(repr, _DISTRIBUTIONS))}, got {kind!r}"
            )
        names = _DISTRIBUTIONS[kind]
        for k in value:
            if k not in ("distribution", *names):
                raise SpecError(
                    f"{key}.{k}", f"unknown key of a {kind} distribution (valid: {', '.join(names)})"
                )
        for k in names:
            v = value.get(k)
            if isinstance(v, bool) or not isinstance(v, (int, float)) or not math.isfinite(v):
                raise SpecError(f"{key}.{k}", f"required: a finite number, got {v!r}")
        a, b = float(value[names[0]]), float(value[names[1]])
        if kind in ("uniform", "loguniform"):
            if not a < b:
                raise SpecError(f"{key}.high", f"must be > low = {a:g}, got {b:g}")
            if kind == "loguniform" and a <= 0:
                raise SpecError(f"{key}.low", f"must be > 0 for a loguniform distribution, got {a:g}")
            param.check(f"{key}.low", a)
            param.check(f"{key}.high", b)
        elif b <= 0:
            raise SpecError(f"{key}.{names[1]}", f"must be > 0, got {b:g}")
        elif kind == "lognormal":
            param.check(f"{key}.median", a)
            if a <= 0:
                raise SpecError(f"{key}.median", f"must be > 0, got {a:g}")
        else:
            param.check(f"{key}.mean", a)
        return "random", Distribution(kind, a, b)
    if param.kind is not float:
        raise SpecError(key, f"a grid of {param.name} is a list of values, got {value!r}")
    for k in value:
        if k not in ("start", "stop", "num", "scale"):
            raise SpecError(
                f"{key}.{k}", "unknown key (a grid: start, stop, num, scale; random: distribution)"
            )
    for k in ("start", "stop", "num"):
        if k not in value:
            raise SpecError(f"{key}.{k}", "required for a grid (start, stop, num[, scale])")
    start, stop = param.check(f"{key}.start", value["start"]), param.check(f"{key}.stop", value["stop"])
    num = _integer(f"{key}.num", value["num"], "grid_num")
    scale = value.get("scale", "linear")
    if scale not in ("linear", "log"):
        raise SpecError(f"{key}.scale", f"must be 'linear' or 'log', got {scale!r}")
    if num > 1 and not stop > start:
        raise SpecError(f"{key}.stop", f"must be > start = {start:g}, got {stop:g}")
    if scale == "log":
        if start <= 0:
            raise SpecError(f"{key}.start", f"must be > 0 with scale = 'log', got {start:g}")
        return "grid", np.geomspace(start, stop, num)
    return "grid", np.linspace(start, stop, num)


def _stepping(fixed: Mapping[str, Any], grid: Mapping[str, np.ndarray]) -> bool:
    """Whether some point may run a method that takes ``dynamics`` (exact, stepping, or auto)."""
    methods = grid["method"].tolist() if "method" in grid else [fixed.get("method", "auto")]
    return any(m == "auto" or "dynamics" in METHODS[m].options for m in methods)


def _wear_checks(quantities, params, fixed, grid) -> None:
    """Checks that involve the wear quantities."""
    if not any(q in quantities for q in ("wear_life", "wear")):
        return
    if "cycles" not in params:
        raise SpecError("parameters.cycles", "required for the wear quantities: the horizon (cycles), > 0")
    if "wear" in quantities and "cycles" not in fixed:
        raise SpecError(
            "parameters.cycles",
            "must be one value with the quantity 'wear' (its cycle grid is log-spaced from 1 to the horizon)",
        )
    if "dynamics" in params and not _stepping(fixed, grid):
        raise SpecError(
            "parameters.dynamics", "only the methods 'exact' and 'stepping' (or 'auto') take dynamics"
        )
    if "tol" in params:
        methods = grid["method"].tolist() if "method" in grid else [fixed.get("method", "auto")]
        if not any(m in ("auto", "stepping", "time") for m in methods):
            raise SpecError("parameters.tol", "only the methods 'stepping' and 'time' take a tolerance")


def _pair_checks(quantities, params, fixed, grid) -> None:
    """Checks of a study over a model with contact pairs (its wear quantities)."""
    if not any(q in quantities for q in ("wear_life", "wear")):
        return
    for name, what in (("cycles", "the horizon (cycles), > 0"), ("kw", "the Archard coefficient K_w (1/Pa)")):
        if name not in params:
            raise SpecError(f"parameters.{name}", f"required for the wear quantities: {what}")
    if "wear" in quantities and "cycles" not in fixed:
        raise SpecError(
            "parameters.cycles",
            "must be one value with the quantity 'wear' (its cycle grid is log-spaced from 1 to the horizon)",
        )
    if "tol" in params:
        methods = grid["method"].tolist() if "method" in grid else [fixed.get("method", "auto")]
        if not any(m in ("auto", "stepping") for m in methods):
            raise SpecError("parameters.tol", "only the method 'stepping' (or 'auto') takes a tolerance")
