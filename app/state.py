"""Controls, the settings they define, and the computations (tasks) the scenes ask for.

:class:`Controls` holds what the sidebar edits, in the units shown (N, Hz,
cycles, 1/N). Values are stored as typed and checked by
:meth:`Controls.problems`, so that an invalid entry is reported, never raised.
:meth:`Controls.settings` freezes valid controls into a hashable
:class:`Settings` with the grids derived from them.

A :class:`Task` is one cached computation, keyed by the call it makes
(:func:`call_key`: the function and its arguments). Each call takes exactly
what its result depends on, so that a change invalidates only the results that
depend on it (``k_w`` is not an argument of the FRF without wear, ``Nh`` not
one of the linear FRFs, ``F_ex`` not one of the regime map over ``r``).
:meth:`Tasks.call` makes a task of any call (the Interface and Study tabs use
it too); the other :class:`Tasks` methods build the scenes' tasks for a settings.
"""

from __future__ import annotations

import inspect
import logging
import math
from collections.abc import Callable
from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import Any

import numpy as np
import param

import fretwear
from fretwear.parameters import CONTROLS, Parameter
from fretwear.studies.maps import LazyHistories

from .backend import Backend, Cancelled, Failure, Grid, ModelSpec, ResultCache

__all__ = [
    "METHODS",
    "PRESETS",
    "Preset",
    "CUSTOM",
    "DEFAULT_PRESET",
    "CONTROL_KEYS",
    "NUMBERS",
    "LADDERS",
    "number_text",
    "parse_number",
    "shown",
    "Controls",
    "Settings",
    "Task",
    "Tasks",
    "Job",
    "WearAfter",
    "ResultOf",
    "call_key",
    "file_stamp",
    "CONVERGENCE_HARMONICS",
]

log = logging.getLogger(__name__)

#: slow-time methods (:func:`fretwear.wear.wear_history`); ``exact`` follows the exact load path
METHODS = tuple(fretwear.METHODS)
#: periodic dynamics of the exact and stepping methods (the library's, without ``auto``)
DYNAMICS = ("shooting", "dlft")
#: harmonic counts of the convergence study (paper Fig. 10)
CONVERGENCE_HARMONICS = (1, 3, 7, 15, 21)
#: result name and legend label of the exact wear reference (exact method on the exact dynamics)
EXACT = "exact dynamics (reference)"
#: result names of the exact wear map and of the exact periodic orbit after wear
EXACT_MAP, EXACT_POINT = "exact wear map", "exact periodic response"
#: the reference's options: the exact method on the event-driven dynamics
_EXACT_OPTIONS = (("dynamics", "shooting"),)
#: load ratios r = F_ex / (mu F_N) of the regime map
RATIOS = (0.08, 2.0, 25)
#: ladders of the accuracy scene: keyword arguments of :func:`fretwear.cost_ladder`; ``quick``
#: keeps the sidebar's defaults (Nh = 7, tolerance 1e-2, degree 4) and computes in well under a second
#: without the wear rungs, ``full`` is the library's ladder (Nh up to 64)
LADDERS: dict[str, dict[str, Any]] = {
    "quick": {
        "harmonics": (1, 3, 5, 7, 11, 15, 21, 31, 41),
        "sample_factors": (8, 16),
        "tolerances": (1e-1, 1e-2),
        "degrees": (2, 4),
        "wear_harmonics": (3, 7),
    },
    "full": {},
}


@dataclass(frozen=True)
class Step:
    """One step of a preset's guided tour: ``text`` says what to change and what to look at; ``change``
    (a settings record: control keys, ``scene``, ``f``, ``N``) is what **Do it** applies."""

    text: str
    change: dict[str, Any] = field(default_factory=dict)


@dataclass(frozen=True)
class Preset:
    """Settings that show one lesson: control values, the scene to open, the point and what to look at.

    Attributes
    ----------
    controls : dict
        Control values (:class:`Controls` names); the others keep their defaults.
    scene : str
        Key of the scene the preset opens.
    frequency, cycles : float
        Selected point (Hz, cycles).
    lesson : str
        One sentence on what to look at: the tour's first step.
    steps : tuple of Step
        The tour's next steps (lesson mode): what to change, what to look at.
    """

    controls: dict[str, Any]
    scene: str
    frequency: float
    cycles: float
    lesson: str
    steps: tuple[Step, ...] = ()

    def tour(self) -> tuple[Step, ...]:
        """Every step of the guided tour, the lesson first."""
        return (Step(self.lesson), *self.steps)


_PAPER = {"fex": 10.0, "mu": 1.0, "normal_load": 10.0, "kw": 1e-11, "horizon": 1e5, "fmin": 0.3, "fmax": 1.3}
#: presets: the paper's three excitation levels (section 2.1) and teaching cases, one lesson each
PRESETS: dict[str, Preset] = {
    "Paper, Fₑₓ = 10 N: regimes": Preset(
        _PAPER,
        "regimes",
        0.7,
        1e4,
        "Without wear the response of mass 1 follows the stuck curve away from 1 Hz and leaves it where "
        "the dashed line r = 1 enters the region where the contact slips.",
        (
            Step(
                "Raise Fₑₓ to 14 N: the dashed line r = Fₑₓ / (μ Fₙ) rises to 1.4 and the nonlinear FRF "
                "leaves the stuck curve over a wider band.",
                {"fex": 14.0},
            ),
            Step(
                "Raise Nₕ to 21: the corners of the FRF where stick gives way to slip sharpen; elsewhere "
                "the curve hardly moves (the harmonic balance has converged there).",
                {"harmonics": 21},
            ),
            Step(
                "Open the wear map: the contact wears only where it slips, the band the regime map showed.",
                {"scene": "wearmap"},
            ),
        ),  # fmt: skip
    ),
    "Paper, Fₑₓ = 6 N: wear opens the contact": Preset(
        {**_PAPER, "fex": 6.0},
        "evolution",
        0.95,
        1e4,
        "Only where the contact slips, between 0.85 and 1.1 Hz, does it wear: there the response falls "
        "from the stuck curve onto the open one as the cycles go by.",
        (
            Step(
                "Open the wear map: the worn band is the slipping band; outside it the depth stays zero.",
                {"scene": "wearmap"},
            ),
            Step(
                "Raise Fₑₓ to 10 N: the contact slips over a wider band, so a wider band wears.",
                {"fex": 10.0},
            ),
        ),  # fmt: skip
    ),
    "Paper, Fₑₓ = 14 N: the worn band": Preset(
        {**_PAPER, "fex": 14.0, "kw": 2e-12, "horizon": 5e5},
        "wearmap",
        0.6,
        5e4,
        "Wear starts near 0.5 Hz, where the contact slips most, and the worn band spreads to higher "
        "frequencies as the normal load relaxes.",
        (
            Step(
                "Select 0.9 Hz: its wear history starts later than at 0.6 Hz and rises once the band "
                "reaches it (the wear rate can rise before it falls).",
                {"f": 0.9},
            ),
            Step(
                "Switch the slow-time method to polynomial: the map becomes the paper's approximation; the "
                "dashed red contours stay the exact answer and the notes give the method's error.",
                {"method": "polynomial"},
            ),
        ),  # fmt: skip
    ),
    "Resonance moves down (Fₑₓ = 10 N, 1e6 cycles)": Preset(
        {**_PAPER, "kw": 1e-12, "horizon": 1e6},
        "evolution",
        0.7,
        1e5,
        "As the contact wears, the resonance moves from the stuck one near 1 Hz to the free one at 0.5 Hz.",
        (
            Step(
                "Open the wear map: the worn band follows the resonance down in frequency.",
                {"scene": "wearmap"},
            ),
            Step("Lower the cycle horizon to 1e5: the resonance has not moved far yet.", {"cycles": 1e5}),
        ),  # fmt: skip
    ),
    "All stick (r = 0.2)": Preset(
        {**_PAPER, "fex": 2.0, "fmax": 0.8},
        "regimes",
        0.6,
        1e4,
        "Below the red stick boundary the contact never slips: the nonlinear FRF lies on the stuck linear "
        "FRF and nothing wears.",
        (
            Step(
                "Raise Fₑₓ to 8 N: the dashed line r = 0.8 crosses the red boundary near the stuck "
                "resonance, and there the nonlinear FRF leaves the stuck curve.",
                {"fex": 8.0},
            ),
            Step(
                "Raise μ to 3: the friction limit triples, r falls to 0.27 and the contact sticks again.",
                {"mu": 3.0},
            ),
        ),  # fmt: skip
    ),
    "Stick-slip inside one cycle (r = 0.8)": Preset(
        {**_PAPER, "fex": 8.0},
        "cycle",
        0.75,
        0.0,
        "Press play: the interface turns red while the masses slide at the friction limit and green "
        "while they move together; the flat parts of the loop are the slips.",
        (
            Step(
                "Raise Fₑₓ to 25 N: the contact slips almost all the period and the loop becomes nearly a "
                "rectangle between ±μ Fₙ.",
                {"fex": 25.0},
            ),
            Step(
                "Lower Fₑₓ to 2 N: the contact sticks all the period; the loop closes to a line, no energy "
                "is dissipated by friction.",
                {"fex": 2.0},
            ),
        ),  # fmt: skip
    ),
    "Gross slip (r = 2.5)": Preset(
        {**_PAPER, "fex": 25.0},
        "cycle",
        0.8,
        0.0,
        "The contact slips almost all the period: the friction force sits at ±μ F_N and the loop is "
        "nearly a rectangle.",
        (
            Step(
                "Lower μ to 0.5: the friction limit halves, and so does the loop's height (±5 N).",
                {"mu": 0.5},
            ),
            Step(
                "Open the regime map: r = 5 lies far above the red stick boundary at every frequency.",
                {"scene": "regimes"},
            ),
        ),  # fmt: skip
    ),
    "Worn through (Fₑₓ = 12 N)": Preset(
        {**_PAPER, "fex": 12.0},
        "cycle",
        0.7,
        1e5,
        "Worn to 0.99 u0, the contact has lost 99 % of its normal load: the friction limit and the loop "
        "shrink a hundredfold and the masses slide past each other.",
        (
            Step(
                "Select N = 0: the fresh contact, at its full normal load: the loop is a hundred times "
                "taller.",
                {"N": 0.0},
            ),
            Step(
                "Open the wear map: at 0.7 Hz the depth reaches u₀ within the horizon.", {"scene": "wearmap"}
            ),
        ),  # fmt: skip
    ),
}
CUSTOM = "custom"
DEFAULT_PRESET = "Paper, Fₑₓ = 10 N: regimes"

#: the sidebar's numbers, by control: valid range, default, label and slider from the one parameter table
NUMBERS = CONTROLS
#: key of each control in a settings record (URL query, settings file): the table's name, as the CLI options
CONTROL_KEYS = {
    **{name: p.name for name, p in NUMBERS.items()},
    "method": "method",
    "dynamics": "dynamics",
}


def number_text(value: Any) -> str:
    """``value`` as a number box shows it: 12 significant digits at most (no float noise), ``""`` for none."""
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return ""
    return f"{value:.12g}" if math.isfinite(value) else str(value)


def shown(value: Any) -> str:
    """``value`` as a message names it: a number as its box shows it, anything else as its repr."""
    return number_text(value) or repr(value)


def parse_number(text: str) -> float | None:
    """The number typed as ``text`` (``None`` when it is not one), rounded to 12 significant digits."""
    try:
        value = float(text.strip().replace("\u2212", "-"))
    except ValueError:
        return None
    return float(f"{value:.12g}") if math.isfinite(value) else value


def whole(value: Any, low: int, high: int) -> bool:
    """Whether ``value`` is a whole number (not a bool, not a text) in ``[low, high]``."""
    if isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
        return False
    return float(value).is_integer() and low <= value <= high


def type_text(owner: param.Parameterized, name: str, text: str) -> None:
    """Set number ``name`` of ``owner`` from the text of its box; text that is no number (or not a whole
    number, for an integer parameter) stays in ``owner.typed`` (for the message naming it) until a
    number replaces it."""
    value = parse_number(text)
    if value is not None and isinstance(owner.param[name], param.Integer):  # 2.5 harmonics: typed, named
        value = int(value) if float(value).is_integer() else None
    typed = {k: v for k, v in owner.typed.items() if k != name}
    if value is None:
        owner.typed = {**typed, name: text}
    else:
        owner.param.update(typed=typed, **{name: value})


def _number(p: Parameter) -> param.Number:
    """The control of parameter ``p``: its default, its slider's range as soft bounds and its doc (unit)."""
    unit = f" ({p.unit})" if p.unit else ""
    doc = f"{p.doc[0].upper()}{p.doc[1:]}{unit}"
    return param.Number(p.default, allow_None=True, softbounds=p.soft_bounds, doc=doc)


class Controls(param.Parameterized):
    """What the sidebar edits, in the units shown; see :meth:`problems`.

    Its numbers (:data:`NUMBERS`) are made from the parameter table
    (:data:`fretwear.parameters.CONTROLS`): default, slider range as soft bounds,
    and the valid range :meth:`problems` checks.

    Number boxes set a value with :meth:`type_text`: a text that is not a
    number is kept in :attr:`typed` and reported as typed, and nothing is
    computed until it is corrected.
    """

    preset = param.Selector(default=DEFAULT_PRESET, objects=[CUSTOM, *PRESETS], doc="Preset")
    method = param.Selector(default="exact", objects=list(METHODS), doc="Slow-time method")
    dynamics = param.Selector(
        default="shooting",
        objects=list(DYNAMICS),
        doc="Periodic dynamics of the exact and stepping methods: the exact event-driven dynamics "
        "(shooting) or harmonic balance (DLFT, truncated at Nh: an approximation)",
    )
    typed = param.Dict({}, doc="Texts typed into number boxes that are not numbers, by control")

    _physical = ("fex", "mu", "normal_load", "kw", "fmin", "fmax", "horizon")

    def __init__(self, **params: Any) -> None:
        preset = params.get("preset", DEFAULT_PRESET)
        if preset != CUSTOM and preset in PRESETS:
            params = {**PRESETS[preset].controls, **params}
        super().__init__(**params)
        self._applying = False
        self._edited()
        self.param.watch(self._edited, list(self._physical))

    def apply_preset(self, name: str) -> None:
        """Set the controls of preset ``name`` in one update (the others to their defaults)."""
        if name == CUSTOM:
            self.preset = CUSTOM
            return
        defaults = {k: self.param[k].default for k in CONTROL_KEYS}
        self._applying = True
        try:
            self.param.update(preset=name, typed={}, **{**defaults, **PRESETS[name].controls})
        finally:
            self._applying = False

    def recognise_preset(self) -> None:
        """Name the preset whose settings the controls hold, the others at their defaults (a preset's
        link or settings file opens with its lesson, not as "custom")."""
        if self.typed:
            return
        defaults = {k: self.param[k].default for k in CONTROL_KEYS}
        for name, preset in PRESETS.items():
            if all(getattr(self, k) == v for k, v in {**defaults, **preset.controls}.items()):
                self.preset = name
                return

    def _edited(self, *_events) -> None:
        if not self._applying and self.preset != CUSTOM:
            values = PRESETS[self.preset].controls
            if any(getattr(self, k) != v for k, v in values.items()):
                self.preset = CUSTOM

    def type_text(self, name: str, text: str) -> None:
        """Set control ``name`` from the text of its number box (kept in :attr:`typed` if not a number)."""
        type_text(self, name, text)

    def problems(self) -> list[str]:
        """One message per invalid control (empty when every value is valid)."""
        out = []
        for name, p in NUMBERS.items():
            value = getattr(self, name)
            valid = f"{p.label} must be {p.range_text(whole=True)}"
            if name in self.typed:
                text = self.typed[name]
                out.append(f"{valid}, got {text!r}" if text.strip() else f"{valid}; the box is empty")
            elif not p.valid(value):
                out.append(f"{valid}, got {shown(value)}")
        if not out and self.fmin >= self.fmax:
            out.append(f"f min must be below f max, got {self.fmin:g} >= {self.fmax:g} Hz")
        return out

    def settings(self) -> Settings:
        """The valid controls as :class:`Settings` (``ValueError`` listing the problems otherwise)."""
        problems = self.problems()
        if problems:
            raise ValueError("; ".join(problems))
        # each number as its table entry types it; the model's three make the model's key
        values = {name: (int if p.integer else float)(getattr(self, name)) for name, p in NUMBERS.items()}
        model = ModelSpec(*(values.pop(name) for name in ("fex", "mu", "normal_load")))
        return Settings(model=model, method=self.method, dynamics=self.dynamics, **values)

    def record(self) -> dict[str, Any]:
        """The controls as a settings record (``fretwear.figures.record`` keys), as they stand."""
        out = {}
        for name, key in CONTROL_KEYS.items():
            value = getattr(self, name)
            if isinstance(value, float) and value.is_integer() and name in NUMBERS and NUMBERS[name].integer:
                value = int(value)
            out[key] = value
        return out


for _name, _p in NUMBERS.items():
    Controls.param.add_parameter(_name, _number(_p))


@dataclass(frozen=True)
class Settings:
    """Valid controls, hashable, with the grids they define (frequencies in Hz)."""

    model: ModelSpec
    kw: float
    harmonics: int
    degree: int
    fmin: float
    fmax: float
    horizon: float
    method: str
    dynamics: str
    tol: float
    n_frequencies: int
    n_cycles: int

    @property
    def frequency_grid(self) -> Grid:
        """Frequency grid of the maps (Hz)."""
        return Grid(self.fmin, self.fmax, self.n_frequencies)

    @property
    def frequencies(self) -> np.ndarray:
        """The values of :attr:`frequency_grid` (Hz)."""
        return self.frequency_grid.values

    @property
    def frf_grid(self) -> Grid:
        """Frequency grid of the nonlinear FRF (Hz), four times finer than the maps'."""
        return Grid(self.fmin, self.fmax, 4 * (self.n_frequencies - 1) + 1)

    @property
    def linear_grid(self) -> Grid:
        """Frequency grid of the linear FRFs (Hz)."""
        return Grid(self.fmin, self.fmax, 1001)

    @property
    def cycles(self) -> np.ndarray:
        """Cycle grid of the wear map: 0, then log-spaced from ``1e-4`` horizon to the horizon."""
        return fretwear.wear.cycle_grid(self.horizon, self.n_cycles)

    @property
    def ratio_grid(self) -> Grid:
        """Load ratios ``r = F_ex / (mu F_N)`` of the regime map."""
        return Grid(*RATIOS)

    @property
    def ratios(self) -> np.ndarray:
        """The values of :attr:`ratio_grid`."""
        return self.ratio_grid.values

    @property
    def dense_cycles(self) -> np.ndarray:
        """Cycle counts at which wear histories are drawn: 0, then log-spaced up to the horizon."""
        return fretwear.wear.cycle_grid(self.horizon)

    @property
    def snapshots(self) -> np.ndarray:
        """Cycle counts of the pseudo-FRFs of the FRF-evolution scene."""
        return fretwear.wear.snapshot_cycles(self.horizon)

    def options(self, method: str | None = None, harmonics: int | None = None) -> dict[str, Any]:
        """Options of ``method`` (default the selected one): only those it takes (``fretwear.METHODS``).

        The exact and stepping methods run on the selected dynamics, with ``Nh`` on DLFT only; an
        explicit ``harmonics`` asks for DLFT at that ``Nh`` (the convergence study)."""
        method = method or self.method
        dynamics = self.dynamics if harmonics is None else "dlft"
        nh = self.harmonics if harmonics is None else harmonics
        if "dynamics" not in fretwear.METHODS[method].options:
            dynamics = None
        settings = {"harmonics": None if dynamics == "shooting" else nh, "tol": self.tol,
                    "degree": self.degree, "dynamics": dynamics}  # fmt: skip
        return fretwear.wear.method_options(method, settings)

    def label(self, method: str | None = None, harmonics: int | None = None) -> str:
        """What ``method`` (default the selected one) computes with these settings, scheme and dynamics
        apart (:func:`fretwear.wear.describe`): ``"exact"`` only for the exact answer."""
        method = method or self.method
        options = self.options(method, harmonics)
        dynamics = options.get("dynamics", "time" if method == "time" else "dlft")
        text = fretwear.wear.describe(method, dynamics, options.get("harmonics"))
        return text + (f", degree {self.degree}" if method == "polynomial" else "")

    def snap(self, f_hz: float) -> float:
        """The frequency of the map grid nearest to ``f_hz``."""
        grid = self.frequencies
        return float(grid[np.argmin(np.abs(grid - f_hz))])

    def record(self, wear: bool = True) -> dict[str, Any]:
        """Settings record of a figure or table drawn for these settings (its parameter record).

        With ``wear``, the slow-time method and only the options it takes
        (tolerance, degree), ``k_w`` and the horizon; without, the harmonics only.
        """
        out: dict[str, Any] = {
            "fex": self.model.fex,
            "mu": self.model.mu,
            "fn": self.model.normal_load,
            "harmonics": self.harmonics,
        }
        if wear:
            options = self.options()
            out |= {"kw": self.kw, "cycles": self.horizon, "method": self.method}
            out |= {k: options[k] for k in ("dynamics", "tol", "degree") if k in options}
        return out


class Job:
    """What a task sees while it runs: the earlier results of its run, progress and cancellation.

    ``progress(fraction)`` reports the task's progress; ``progress(fraction, stage)`` also says what it
    computes now (the progress line shows the stage instead of the task's label).
    """

    def __init__(self, cancelled: Callable[[], bool] = lambda: False) -> None:
        self.results: dict[str, Any] = {}
        self.cancelled = cancelled
        self.progress: Callable[..., None] = lambda _fraction, _stage=None: None


@dataclass(frozen=True)
class Task:
    """One cached computation.

    Attributes
    ----------
    name : str
        Name of the result in the scene.
    key : tuple
        Cache key: the computation and every parameter it depends on (:func:`call_key`).
    run : callable
        ``run(job) -> result``; a library error gives a :class:`Failure`.
    label : str
        What the progress line says while it runs.
    weight : float
        Relative cost, for the progress bar.
    """

    name: str
    key: tuple
    run: Callable[[Job], Any]
    label: str
    weight: float = 1.0


def call_key(function: Callable, *args: Any, **kwargs: Any) -> tuple:
    """The cache key of ``function(*args, **kwargs)``: the function's name, then its arguments.

    The arguments must be hashable (grids as :class:`~app.backend.Grid`, options as pairs): an array
    raises ``TypeError`` here rather than in the cache.
    """
    key = (function.__name__, *args, *sorted(kwargs.items()))
    hash(key)
    return key


def _guard(compute: Callable[[], Any]) -> Any:
    """``compute()``, with any library error turned into a :class:`Failure`."""
    try:
        return compute()
    except Cancelled:
        raise
    except Exception as exc:  # noqa: BLE001 - shown to the user as a message, logged with its traceback
        log.warning("computation failed", exc_info=True)
        return Failure(f"{type(exc).__name__}: {exc}", " ".join(str(exc).split()))


def file_stamp(path: str | Path) -> float:
    """Modification time of the file or folder ``path`` (s; -1 when missing): in the key of a call that
    reads it, so that a changed file is another call."""
    path = Path(path)
    return path.stat().st_mtime if path.exists() else -1.0


def _digits(value: float) -> float:
    """``value`` to 12 significant digits: a typed 0.7 Hz and the grid's 0.7000000000000001 share a key."""
    return float(f"{value:.12g}")


@dataclass(frozen=True)
class WearAfter:
    """An argument of a task: the worn depths after ``cycles`` by the wear history of an earlier task
    of the same run, resolved when the task runs (its key holds the history's key and ``cycles``)."""

    history: tuple
    cycles: float
    name: str = field(compare=False)
    label: str = field(compare=False)

    @classmethod
    def of(cls, history: Task | None, cycles: float) -> WearAfter | None:
        """The wear after ``cycles`` by task ``history`` (``None`` without one: the unworn contact)."""
        return None if history is None else cls(history.key, float(cycles), history.name, history.label)

    def resolve(self, job: Job) -> np.ndarray | Failure:
        """The worn depths (m) from the history's result in ``job`` (a :class:`Failure` if it failed):
        per contact, or per pair for the nodal history of an interface (its profile at ``cycles``,
        linear between records and held past the last)."""
        h = job.results[self.name]
        if isinstance(h, Failure):
            return Failure(f"no {self.label}: {h}", h.reason)
        if not hasattr(h, "at"):  # an interface's history: the profile of its records
            return np.array([np.interp(self.cycles, h.cycles, w) for w in h.wear.T])
        return h.at([self.cycles])["wear"][0]


@dataclass(frozen=True)
class ResultOf:
    """An argument of a task: the result of an earlier task of the same run (e.g. a reduced model that
    later calls take), resolved when the task runs; its key is that task's key."""

    key: tuple
    name: str = field(compare=False)
    label: str = field(compare=False)

    @classmethod
    def of(cls, task: Task) -> ResultOf:
        """The result of ``task``."""
        return cls(task.key, task.name, task.label)

    def resolve(self, job: Job) -> Any:
        """The earlier task's result in ``job`` (a :class:`Failure` naming it if it failed)."""
        value = job.results[self.name]
        return Failure(f"no {self.label}: {value}", value.reason) if isinstance(value, Failure) else value


class Tasks:
    """Builds the tasks of the scenes, each keyed by the call it caches (:func:`call_key`)."""

    def __init__(self, backend: Backend, cache: ResultCache) -> None:
        self.backend, self.cache = backend, cache

    def call(
        self, name: str, label: str, weight: float, function: Callable, *args: Any, **kwargs: Any
    ) -> Task:
        """The task ``name`` that computes ``function(*args, **kwargs)``, keyed by that call.

        ``function`` (a :class:`~app.backend.Backend` method, or a pipeline of library calls) gets the
        run's ``progress`` and ``cancelled`` when it takes them; a :class:`WearAfter` or :class:`ResultOf`
        argument is resolved from the run's earlier results; a library error gives a :class:`Failure`.
        """
        hooks = [h for h in ("progress", "cancelled") if h in inspect.signature(function).parameters]

        def run(job: Job) -> Any:
            values = [a.resolve(job) if isinstance(a, (WearAfter, ResultOf)) else a for a in args]
            failed = next((v for v in values if isinstance(v, Failure)), None)
            if failed is not None:
                return failed
            return _guard(lambda: function(*values, **kwargs, **{h: getattr(job, h) for h in hooks}))

        return Task(name, call_key(function, *args, **kwargs), run, label, weight)

    def linear(self, s: Settings, state: str) -> Task:
        """Linear FRF with the contact stuck or open: depends on ``F_ex`` and the band only."""
        b = self.backend
        return self.call(f"linear_{state}", f"linear FRF ({state})", 0.1, b.linear, s.model.linear_part(),
                         s.linear_grid, state)  # fmt: skip

    def frf(self, s: Settings) -> Task:
        """Nonlinear FRF without wear: not ``k_w``, the method or the horizon."""
        return self.call("frf", "nonlinear FRF", 1.0, self.backend.frf, s.model, s.frf_grid, s.harmonics)

    def regime(self, s: Settings) -> Task:
        """Regime map over frequency x ``r``: not ``F_ex`` (the map is over ``r``), ``k_w`` or the method."""
        b = self.backend
        return self.call("regime", "regime map", 3.0, b.regime, s.model.unit_forcing(), s.frequency_grid,
                         s.ratio_grid, s.harmonics)  # fmt: skip

    def _map(self, s: Settings, name: str, label: str, weight: float, method: str, options: tuple) -> Task:
        """Wear map by ``method`` with ``options`` over the settings' grids; stores each frequency's
        history in the cache too, under the key of its own task (:meth:`history`). The lazy histories of a
        map on sliding tables go through that key when built: the exact history the scene shows beside
        the map is computed once, by whichever asks first."""
        task = self.call(name, label, weight, self.backend.wear_map, s.model, s.frequency_grid, s.horizon,
                         s.n_cycles, method, s.kw, options)  # fmt: skip

        def run(job: Job):
            result = task.run(job)
            if isinstance(result, Failure):
                return result
            if isinstance(result.histories, LazyHistories):  # built on demand: through the cache, once

                def cached(f: float, build: Callable[[float], Any]) -> Any:
                    key = self._history_key(s, f, method, options)
                    value = self.cache.get_or_compute(key, lambda: build(f))
                    return build(f) if isinstance(value, Failure) else value  # its task failed: raise here

                result.histories = result.histories.through(cached)
            else:
                for f, history in zip(s.frequencies, result.histories, strict=True):
                    self.cache.put(self._history_key(s, f, method, options), history)
            return result

        return replace(task, run=run)

    def _history_key(self, s: Settings, f_hz: float, method: str, options: tuple) -> tuple:
        return call_key(self.backend.history, s.model, _digits(f_hz), method, s.kw, s.horizon, options)

    def wear_map(self, s: Settings) -> Task:
        """Wear map over frequency x cycles by the selected method, with only the options it uses."""
        options = tuple(s.options().items())
        return self._map(s, "wear_map", f"wear map ({s.method})", 10.0, s.method, options)

    def history(
        self,
        s: Settings,
        f_hz: float,
        method: str | None = None,
        harmonics: int | None = None,
        name: str = "history",
        basis: str | None = None,
    ) -> Task:
        """Wear evolution at ``f_hz`` by ``method`` (default the selected one); ``basis``: the polynomial
        method's slow-time basis (default the library's). Its key is that of the wear map's row at
        ``f_hz`` (12 digits)."""
        method = method or s.method
        options = tuple((s.options(method, harmonics) | ({"basis": basis} if basis else {})).items())
        label = f"wear history ({method}{'' if harmonics is None else f', Nh = {harmonics}'}"
        label += f"{'' if basis is None else f', {basis} basis'})"
        weight = 5.0 if method == "time" else 1.0
        return self.call(name, label, weight, self.backend.history, s.model, _digits(f_hz), method, s.kw,
                         s.horizon, options)  # fmt: skip

    def exact_history(self, s: Settings, f_hz: float, name: str = EXACT) -> Task:
        """The reference wear evolution at ``f_hz``: the exact method on the exact (event-driven) dynamics.

        Archard's law integrated on the sliding distance of shooting solutions
        (:func:`fretwear.wear.wear_history` with ``dynamics="shooting"``): no
        harmonic truncation, no slow-time error; what every approximation the
        sidebar selects is measured against.
        """
        return self.call(name, "exact wear (event-driven dynamics)", 2.0, self.backend.history, s.model,
                         _digits(f_hz), "exact", s.kw, s.horizon, _EXACT_OPTIONS)  # fmt: skip

    def exact_wear_map(self, s: Settings) -> Task:
        """The reference wear map: the exact method on the exact dynamics, over the map's grids.

        Built on the sliding tables of ``fretwear.wear.sliding``, cached per
        structure and frequency: a first map costs about 0.1 s per frequency,
        later changes of ``F_ex``, ``mu``, ``k_w`` or ``u0`` milliseconds.
        """
        label = "exact wear map (event-driven dynamics)"
        return self._map(s, EXACT_MAP, label, 5.0, "exact", _EXACT_OPTIONS)

    def exact_point(self, s: Settings, f_hz: float, cycles: float, history: Task | None) -> Task:
        """The exact periodic orbit at ``f_hz`` after ``cycles``, worn as the exact ``history`` says."""
        return self.call(EXACT_POINT, "exact periodic response", 0.3, self.backend.exact_point, s.model,
                         _digits(f_hz), WearAfter.of(history, cycles))  # fmt: skip

    def point(self, s: Settings, f_hz: float, cycles: float, history: Task | None) -> Task:
        """Periodic response at ``f_hz`` after ``cycles`` (the wear of ``history`` there; none at 0): on
        the selected dynamics (the exact orbit when they are the exact ones, else DLFT with ``Nh``)."""
        if s.dynamics == "shooting":
            return replace(self.exact_point(s, f_hz, cycles, history), name="point")
        return self.call("point", "periodic response", 0.3, self.backend.point, s.model, _digits(f_hz),
                         s.harmonics, WearAfter.of(history, cycles))  # fmt: skip

    def cost(self, s: Settings, f_hz: float, ladder: str, wear: bool) -> Task:
        """Cost ladder at ``f_hz`` (:data:`LADDERS`): not ``Nh``, the method or the tolerances.

        With ``wear``, the ladder has the wear rungs too and depends on ``k_w``
        and the horizon; without, it does not.
        """
        kw, cycles = (s.kw, s.horizon) if wear else (None, None)
        label = f"cost ladder ({ladder}{', with wear' if wear else ''})"
        return self.call("cost", label, 10.0 if wear else 1.0, self.backend.cost, s.model, _digits(f_hz),
                         tuple(LADDERS[ladder].items()), kw, cycles)  # fmt: skip
