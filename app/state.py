"""Controls, the settings they define, and the computations (tasks) the scenes ask for.

:class:`Controls` holds what the sidebar edits, in the units shown (N, Hz,
cycles, 1/Pa). Values are stored as typed and checked by
:meth:`Controls.problems`, so that an invalid entry is reported, never raised.
:meth:`Controls.settings` freezes valid controls into a hashable
:class:`Settings` with the grids derived from them.

A :class:`Task` is one cached computation: its ``key`` lists exactly the
parameters it depends on, so that a change invalidates only the results that
depend on it (``k_w`` is not in the key of the FRF without wear, ``Nh`` not in
the key of the linear FRFs). :class:`Tasks` builds them for a settings.
"""

from __future__ import annotations

import logging
import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import param

import fretwear
from fretwear.studies.maps import LazyHistories

from .backend import Backend, Cancelled, Failure, ModelSpec, Progress, ResultCache

__all__ = [
    "METHODS",
    "PRESETS",
    "LADDERS",
    "Controls",
    "Settings",
    "Task",
    "Tasks",
    "Job",
    "CONVERGENCE_HARMONICS",
]

log = logging.getLogger(__name__)

#: slow-time methods (:func:`fretwear.wear.wear_history`); ``exact`` follows the exact load path
METHODS = tuple(fretwear.METHODS)
#: harmonic counts of the convergence study (paper Fig. 10)
CONVERGENCE_HARMONICS = (1, 3, 7, 15, 21)
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

_PAPER = {"mu": 1.0, "normal_load": 10.0, "kw": 1e-11, "horizon": 1e5, "fmin": 0.3, "fmax": 1.3}
#: presets: the paper's three excitation levels (section 2.1) and teaching cases
PRESETS: dict[str, dict[str, Any]] = {
    "Paper: F_ex = 6 N": {**_PAPER, "fex": 6.0},
    "Paper: F_ex = 10 N": {**_PAPER, "fex": 10.0},
    "Paper: F_ex = 14 N": {**_PAPER, "fex": 14.0},
    "All stick (r = 0.2, 0.3-0.8 Hz)": {**_PAPER, "fex": 2.0, "fmax": 0.8},
    "Stick-slip (r = 0.6)": {**_PAPER, "fex": 6.0},
    "Gross slip (r = 2.5)": {**_PAPER, "fex": 25.0},
    "Wear-through (k_w = 1e-10)": {**_PAPER, "fex": 10.0, "kw": 1e-10, "horizon": 1e4},
}
CUSTOM = "custom"
DEFAULT_PRESET = "Paper: F_ex = 10 N"

#: (name, low, high, integer, unit) of every control: the valid ranges shown to the user
_RANGES = {
    "fex": ("F_ex", 0.0, 1e3, False, "N"),
    "mu": ("mu", 0.0, 10.0, False, ""),
    "normal_load": ("F_N", 0.0, 1e4, False, "N"),
    "kw": ("k_w", 0.0, 1e-4, False, "1/Pa"),
    "harmonics": ("Nh", 1, 64, True, ""),
    "degree": ("polynomial degree", 0, 12, True, ""),
    "fmin": ("f min", 0.0, 20.0, False, "Hz"),
    "fmax": ("f max", 0.0, 20.0, False, "Hz"),
    "horizon": ("cycle horizon", 10, 1e9, True, "cycles"),
    "tol": ("tolerance", 0.0, 0.5, False, "u0"),
    "n_frequencies": ("frequencies", 3, 401, True, ""),
    "n_cycles": ("cycle points", 4, 400, True, ""),
}


class Controls(param.Parameterized):
    """What the sidebar edits, kept as entered (an emptied box gives ``None``); see :meth:`problems`."""

    preset = param.Selector(default=DEFAULT_PRESET, objects=[CUSTOM, *PRESETS], doc="Preset")
    fex = param.Number(
        10.0, allow_None=True, softbounds=(0.5, 30.0), doc="Excitation amplitude F_ex on mass 1 (N)"
    )
    mu = param.Number(1.0, allow_None=True, softbounds=(0.05, 2.0), doc="Friction coefficient mu (-)")
    normal_load = param.Number(
        10.0, allow_None=True, softbounds=(1.0, 50.0), doc="Initial normal load F_N (N)"
    )
    kw = param.Number(1e-11, allow_None=True, doc="Archard wear coefficient k_w (1/Pa)")
    harmonics = param.Number(7, allow_None=True, softbounds=(1, 41), doc="Harmonics Nh")
    degree = param.Number(4, allow_None=True, softbounds=(0, 12), doc="Degree of the polynomial method")
    fmin = param.Number(0.3, allow_None=True, softbounds=(0.05, 3.0), doc="Lowest frequency (Hz)")
    fmax = param.Number(1.3, allow_None=True, softbounds=(0.05, 3.0), doc="Highest frequency (Hz)")
    horizon = param.Number(1e5, allow_None=True, doc="Cycle horizon of the wear studies")
    method = param.Selector(default="exact", objects=list(METHODS), doc="Slow-time method")
    tol = param.Number(
        1e-2, allow_None=True, doc="Tolerance of stepping and time integration (fraction of u0)"
    )
    n_frequencies = param.Number(41, allow_None=True, softbounds=(5, 201), doc="Frequencies of the maps")
    n_cycles = param.Number(60, allow_None=True, softbounds=(10, 200), doc="Cycle counts of the wear map")

    _physical = ("fex", "mu", "normal_load", "kw", "fmin", "fmax", "horizon")

    def __init__(self, **params: Any) -> None:
        preset = params.get("preset", DEFAULT_PRESET)
        if preset != CUSTOM and preset in PRESETS:
            params = {**PRESETS[preset], **params}
        super().__init__(**params)
        self._applying = False
        self._edited()
        self.param.watch(self._edited, list(self._physical))

    def apply_preset(self, name: str) -> None:
        """Set the controls of preset ``name`` in one update."""
        if name == CUSTOM:
            self.preset = CUSTOM
            return
        self._applying = True
        try:
            self.param.update(preset=name, **PRESETS[name])
        finally:
            self._applying = False

    def _edited(self, *_events) -> None:
        if not self._applying and self.preset != CUSTOM:
            values = PRESETS[self.preset]
            if any(getattr(self, k) != v for k, v in values.items()):
                self.preset = CUSTOM

    def problems(self) -> list[str]:
        """One message per invalid control (empty when every value is valid)."""
        out = []
        for name, (label, low, high, integer, unit) in _RANGES.items():
            value = getattr(self, name)
            unit = f" {unit}" if unit else ""
            kind = "a whole number" if integer else "a number"
            ok = isinstance(value, (int, float)) and math.isfinite(value)
            ok = ok and (value >= low if integer else value > low) and value <= high
            ok = ok and (not integer or float(value).is_integer())
            if not ok:
                op = ">=" if integer else ">"
                out.append(f"{label} must be {kind} {op} {low:g} and <= {high:g}{unit}, got {value!r}")
        if not out and self.fmin >= self.fmax:
            out.append(f"f min must be below f max, got {self.fmin:g} >= {self.fmax:g} Hz")
        return out

    def settings(self) -> Settings:
        """The valid controls as :class:`Settings` (``ValueError`` listing the problems otherwise)."""
        problems = self.problems()
        if problems:
            raise ValueError("; ".join(problems))
        return Settings(
            model=ModelSpec(float(self.fex), float(self.mu), float(self.normal_load)),
            kw=float(self.kw),
            harmonics=int(self.harmonics),
            degree=int(self.degree),
            fmin=float(self.fmin),
            fmax=float(self.fmax),
            horizon=float(int(self.horizon)),
            method=self.method,
            tol=float(self.tol),
            n_frequencies=int(self.n_frequencies),
            n_cycles=int(self.n_cycles),
        )


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
    tol: float
    n_frequencies: int
    n_cycles: int

    @property
    def frequencies(self) -> np.ndarray:
        """Frequency grid of the maps (Hz)."""
        return np.linspace(self.fmin, self.fmax, self.n_frequencies)

    @property
    def frf_frequencies(self) -> np.ndarray:
        """Frequency grid of the nonlinear FRF (Hz), four times finer than the maps'."""
        return np.linspace(self.fmin, self.fmax, 4 * (self.n_frequencies - 1) + 1)

    @property
    def linear_frequencies(self) -> np.ndarray:
        """Frequency grid of the linear FRFs (Hz)."""
        return np.linspace(self.fmin, self.fmax, 1001)

    @property
    def cycles(self) -> np.ndarray:
        """Cycle grid of the wear map: 0, then log-spaced from ``1e-4`` horizon to the horizon."""
        return fretwear.wear.cycle_grid(self.horizon, self.n_cycles)

    @property
    def ratios(self) -> np.ndarray:
        """Load ratios ``r = F_ex / (mu F_N)`` of the regime map."""
        return np.linspace(*RATIOS[:2], RATIOS[2])

    @property
    def dense_cycles(self) -> np.ndarray:
        """Cycle counts at which wear histories are drawn: 0, then log-spaced up to the horizon."""
        return fretwear.wear.cycle_grid(self.horizon)

    @property
    def snapshots(self) -> np.ndarray:
        """Cycle counts of the pseudo-FRFs of the FRF-evolution scene."""
        return fretwear.wear.snapshot_cycles(self.horizon)

    def options(self, method: str | None = None, harmonics: int | None = None) -> dict[str, Any]:
        """Options of ``method`` (default the selected one): only those it takes (``fretwear.METHODS``)."""
        nh = self.harmonics if harmonics is None else harmonics
        settings = {"harmonics": nh, "tol": self.tol, "degree": self.degree}
        return fretwear.wear.method_options(method or self.method, settings)

    def snap(self, f_hz: float) -> float:
        """The frequency of the map grid nearest to ``f_hz``."""
        grid = self.frequencies
        return float(grid[np.argmin(np.abs(grid - f_hz))])


class Job:
    """What a task sees while it runs: the earlier results of its run, progress and cancellation."""

    def __init__(self, cancelled: Callable[[], bool] = lambda: False) -> None:
        self.results: dict[str, Any] = {}
        self.cancelled = cancelled
        self.progress: Progress = lambda _fraction: None


@dataclass(frozen=True)
class Task:
    """One cached computation.

    Attributes
    ----------
    name : str
        Name of the result in the scene.
    key : tuple
        Cache key: the computation and every parameter it depends on.
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


def _guard(compute: Callable[[], Any]) -> Any:
    """``compute()``, with any library error turned into a :class:`Failure`."""
    try:
        return compute()
    except Cancelled:
        raise
    except Exception as exc:  # noqa: BLE001 - shown to the user as a message, logged with its traceback
        log.warning("computation failed", exc_info=True)
        return Failure(f"{type(exc).__name__}: {exc}")


def _grid(fmin: float, fmax: float, n: int) -> tuple:
    return ("grid", fmin, fmax, n)


def _digits(value: float) -> float:
    """``value`` to 12 significant digits: a typed 0.7 Hz and the grid's 0.7000000000000001 share a key."""
    return float(f"{value:.12g}")


class Tasks:
    """Builds the tasks of the scenes, each with the cache key of what it depends on."""

    def __init__(self, backend: Backend, cache: ResultCache) -> None:
        self.backend, self.cache = backend, cache

    def linear(self, s: Settings, state: str) -> Task:
        """Linear FRF with the contact stuck or open: depends on ``F_ex`` and the band only."""
        f = s.linear_frequencies
        return Task(
            f"linear_{state}",
            ("linear", state, s.model.fex, _grid(s.fmin, s.fmax, len(f))),
            lambda job: _guard(lambda: self.backend.linear(s.model, f, state)),
            f"linear FRF ({state})",
            0.1,
        )

    def frf(self, s: Settings) -> Task:
        """Nonlinear FRF without wear: not ``k_w``, the method or the horizon."""
        f = s.frf_frequencies
        return Task(
            "frf",
            ("frf", s.model, _grid(s.fmin, s.fmax, len(f)), s.harmonics),
            lambda job: _guard(lambda: self.backend.frf(s.model, f, s.harmonics)),
            "nonlinear FRF",
            1.0,
        )

    def regime(self, s: Settings) -> Task:
        """Regime map over frequency x ``r``: not ``F_ex`` (the map is over ``r``), ``k_w`` or the method."""
        spec = s.model.unit_forcing()
        key = ("regime", spec, _grid(s.fmin, s.fmax, s.n_frequencies), RATIOS, s.harmonics)

        def run(job: Job):
            return _guard(
                lambda: self.backend.regime(
                    s.model, s.frequencies, s.ratios, s.harmonics, job.progress, job.cancelled
                )
            )

        return Task("regime", key, run, "regime map", 3.0)

    def wear_map_key(self, s: Settings) -> tuple:
        """Cache key of the wear map: the model, the grids, the method and only the options it uses."""
        grid = _grid(s.fmin, s.fmax, s.n_frequencies)
        return ("wear_map", s.model, grid, s.horizon, s.n_cycles, s.method, s.kw, tuple(s.options().items()))

    def history_key(self, s: Settings, f_hz: float, method: str, harmonics: int | None = None) -> tuple:
        """Cache key of a wear history: the same as the wear map's row at ``f_hz`` (12 digits)."""
        options = tuple(s.options(method, harmonics).items())
        return ("history", s.model, _digits(f_hz), method, s.kw, s.horizon, options)

    def wear_map(self, s: Settings) -> Task:
        """Wear map over frequency x cycles; stores each frequency's history in the cache too."""

        def run(job: Job):
            result = _guard(
                lambda: self.backend.wear_map(
                    s.model, s.frequencies, s.cycles, s.method, s.kw, s.options(), job.progress, job.cancelled
                )
            )
            if not isinstance(result, Failure) and not isinstance(result.histories, LazyHistories):
                for f, history in zip(s.frequencies, result.histories, strict=True):
                    self.cache.put(self.history_key(s, f, s.method), history)
            return result

        return Task("wear_map", self.wear_map_key(s), run, f"wear map ({s.method})", 10.0)

    def history(
        self,
        s: Settings,
        f_hz: float,
        method: str | None = None,
        harmonics: int | None = None,
        name: str = "history",
    ) -> Task:
        """Wear evolution at ``f_hz`` by ``method`` (default the selected one)."""
        method = method or s.method
        options = s.options(method, harmonics)

        def run(job: Job):
            return _guard(lambda: self.backend.history(s.model, f_hz, method, s.kw, s.horizon, options))

        label = f"wear history ({method}{'' if harmonics is None else f', Nh = {harmonics}'})"
        weight = 5.0 if method == "time" else 1.0
        return Task(name, self.history_key(s, f_hz, method, harmonics), run, label, weight)

    def point(self, s: Settings, f_hz: float, cycles: float, history: Task | None) -> Task:
        """Periodic response at ``f_hz`` after ``cycles`` (the wear of ``history`` there; none at 0)."""

        def run(job: Job):
            wear = None
            if history is not None:
                h = job.results[history.name]
                if isinstance(h, Failure):
                    return Failure(f"no wear history: {h}")
                wear = h.at([cycles])["wear"][0]
            return _guard(lambda: self.backend.point(s.model, f_hz, s.harmonics, wear))

        source = None if history is None else history.key
        return Task(
            "point",
            ("point", s.model, _digits(f_hz), s.harmonics, source, float(cycles)),
            run,
            "periodic response",
            0.3,
        )

    def cost(self, s: Settings, f_hz: float, ladder: str, wear: bool) -> Task:
        """Cost ladder at ``f_hz`` (:data:`LADDERS`): not ``Nh``, the method or the tolerances.

        With ``wear``, the ladder has the wear rungs too and depends on ``k_w``
        and the horizon; without, it does not.
        """
        horizon = (s.kw, s.horizon) if wear else None

        def run(job: Job):
            kw, cycles = horizon or (None, None)
            return _guard(
                lambda: self.backend.cost(
                    s.model, f_hz, LADDERS[ladder], kw, cycles, job.progress, job.cancelled
                )
            )

        label = f"cost ladder ({ladder}{', with wear' if wear else ''})"
        key = ("cost", s.model, _digits(f_hz), ladder, horizon)
        return Task("cost", key, run, label, 10.0 if wear else 1.0)
