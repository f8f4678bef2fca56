"""What every scene shares: the base :class:`Scene`, the selected point, and the notes on results.

A scene draws only what its session published into it (:meth:`Scene.publish`):
results, the settings and the selected point they belong to. Its figures keep
the same layers whatever the state (empty data while nothing is computed), as
the dashboard's ``DynamicMap`` objects require. Figures come from the builders
of :mod:`fretwear.figures`, which also renders them to PNG, SVG and HTML with
their parameter record (:meth:`Scene.record`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable
from concurrent.futures import Executor
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import param

from fretwear import figures
from fretwear.figures.record import caption, csv_header
from fretwear.studies.maps import LazyHistories

from ..backend import Failure, shared_backend, shared_cache
from ..state import EXACT_MAP, Controls, Settings, Task, Tasks, number_text, parse_number, type_text

if TYPE_CHECKING:
    import holoviews as hv

HZ = "frequency f (Hz)"
X1 = "x₁ amplitude, first harmonic (m)"
WEAR = "w / u₀"
CYCLES = "cycles N"
EMPTY = (np.zeros(0), np.zeros(0))


@dataclass(frozen=True)
class Selection:
    """The point picked on the wear map: frequency (Hz) and cycle count."""

    frequency: float
    cycles: float


def ok_value(value: Any) -> Any:
    """``value``, or ``None`` for a missing or failed result."""
    return None if value is None or isinstance(value, Failure) else value


def _failure_note(name: str, value: Any) -> list[str]:
    return [f"{name}: {value}"] if isinstance(value, Failure) else []


def history_notes(histories: list, limit: int = 4) -> list[str]:
    """Notes on wear histories: where each stopped early or warned, and where one overshoots ``u0``.

    Each note names its frequency; past ``limit`` notes the rest are counted. Of the lazy histories of a
    map on sliding tables (whose failures raise: the map has none to report), only those already
    computed: computing the others for their notes cost a second at every change of ``k_w``.
    """
    if isinstance(histories, LazyHistories):
        histories = histories.built()
    notes = [
        f"{h.frequency:.4g} Hz ({h.label}): stopped early, {h.status}" for h in histories if not h.converged
    ]
    notes += [f"{h.frequency:.4g} Hz ({h.label}): {w}" for h in histories for w in h.warnings]
    worst = max(histories, key=lambda h: np.nanmax(h.wear_fraction), default=None)
    if worst is not None and np.nanmax(worst.wear_fraction) > 1:
        k = int(np.nanargmax(worst.wear_fraction[:, 0]))
        notes.insert(
            0,
            f"w / u₀ reaches {worst.wear_fraction[k, 0]:.3g} > 1 at {worst.frequency:.4g} Hz, "
            f"N = {worst.cycles[k]:.3g} ({worst.label}): past u₀ the contact is unloaded and stops "
            "wearing, so the excess is the method's error (the colour scale extends to show it)",
        )
    if len(notes) > limit:
        notes = [*notes[:limit], f"and {len(notes) - limit} more notes (the CSV export has every history)"]
    return notes


def error_note(h, reference, label: str | None = None) -> str | None:
    """How far the approximation ``h`` (named ``label``, default its own) is from the exact ``reference``
    (None for the exact answer itself, or while either computes)."""
    if h is None or reference is None or h.label == "exact":
        return None
    return h.error_note(reference, label=label)


def exact_map(scene: Scene, wm) -> Any:
    """The published exact wear map when it has the grids of ``wm`` (None while it computes, or failed)."""
    exact = ok_value(scene.results.get(EXACT_MAP))
    if exact is None or wm is None or exact.wear.shape != wm.wear.shape:
        return None
    return exact if np.allclose(exact.frequency, wm.frequency, rtol=1e-9) else None


class Exports:
    """Figures and downloads of a tab: what every tab (the session's scenes, Interface, Study) shares.

    A tab sets ``key``, ``title``, ``figure_names`` and ``results``, and has ``_figure_NAME`` methods,
    ``datasets()`` and ``csv_header()`` (the ``#`` lines of its exports).
    """

    key: ClassVar[str]
    title: ClassVar[str]
    #: whether the page's figures have more than the exported ones (``_figure_*`` take ``live``)
    live: ClassVar[bool] = False

    def figure(self, name: str, live: bool = False) -> hv.Overlay:
        """Figure ``name`` of the published results, as a HoloViews overlay.

        ``live``: as the page shows it (with what only the page has, e.g. the
        animation's cursor); exports draw the figure without it.
        """
        if name not in self.figure_names:
            raise ValueError(f"scene {self.key!r} has no figure {name!r}; it has {self.figure_names}")
        return getattr(self, f"_figure_{name}")(**({"live": True} if live and self.live else {}))

    def _check_export(self, name: str) -> None:
        """``ValueError`` while figure ``name`` has nothing to export."""
        if not self.results:
            raise ValueError(f"nothing to export yet: the {self.title} scene has not been computed")

    def caption(self) -> str | Callable[[bool], str]:
        """Caption of an exported figure: the ``#`` lines of ``csv_header()`` in one line."""
        return " ".join(self.csv_header().replace("# ", "").splitlines())

    def filename(self, name: str, fmt: str) -> str:
        """Download file name of figure or dataset ``name``."""
        return f"fretwear_{self.key}_{name}.{fmt}"

    def export_figure(self, name: str, fmt: str, options: figures.ExportOptions | None = None) -> bytes:
        """Figure ``name`` as ``png``, ``svg`` or standalone ``html`` bytes, captioned with its
        parameters; ``options``: size, resolution, font size."""
        if fmt not in figures.EXPORT_FORMATS:
            raise ValueError(f"fmt must be one of {figures.EXPORT_FORMATS}, got {fmt!r}")
        self._check_export(name)
        figures.load_backend("bokeh" if fmt == "html" else "matplotlib")
        return figures.figure_bytes(
            self.figure(name),
            fmt,
            title=f"fretwear: {self.title}, {name}",
            options=options,
            caption=self.caption(),
        )

    def export_csv(self, name: str) -> str:
        """Dataset ``name`` as CSV text, after its parameters (``#`` lines)."""
        tables = self.datasets()
        if name not in tables:
            raise ValueError(f"no dataset {name!r} in scene {self.key!r} (yet); available: {sorted(tables)}")
        return figures.csv_text(tables[name], self.csv_header())


class Addressed:
    """A tab whose view lives in the page's address under keys of its own, ``KEY.NAME`` (``KEY`` the tab's
    ``key``): ``?tab=interface&interface.model=...&interface.frequency=0.7``.

    A tab lists its ``address_params`` (parameters of its own: numbers, integers, selectors, and a
    ``point`` dict of indices written ``dim:index,...``); :meth:`address` writes those that differ
    from their defaults, :meth:`apply_address` reads them back and returns the problems met (a number
    that is not one is kept in ``typed`` when the tab has it, as if typed in its box).
    """

    key: ClassVar[str]
    address_params: ClassVar[tuple[str, ...]] = ()

    def address(self) -> dict[str, str]:
        """The tab's view: its parameters that differ from their defaults, keyed ``KEY.NAME``."""
        out = {}
        for name in self.address_params:
            value = getattr(self, name)
            if name == "point":
                text = ",".join(f"{d}:{i}" for d, i in value.items() if i)
            else:
                text = "" if value == self.param[name].default else number_text(value) or str(value)
            if text:
                out[f"{self.key}.{name}"] = text
        return out

    def apply_address(self, values: dict[str, str]) -> list[str]:
        """Apply ``KEY.NAME -> text`` pairs of the address; the problems met, one line each."""
        problems = []
        order = {f"{self.key}.{n}": i for i, n in enumerate(self.address_params)}  # a model before its values
        for key, text in sorted(values.items(), key=lambda item: order.get(item[0], -1)):
            name = key.removeprefix(f"{self.key}.")
            if name not in self.address_params or not key.startswith(f"{self.key}."):
                known = ", ".join(f"{self.key}.{n}" for n in self.address_params)
                problems.append(f"address: unknown setting {key!r} of the {self.title} tab (known: {known})")
            elif name == "point":
                problems += self._apply_point(text)
            elif isinstance(self.param[name], param.Selector):
                objects = self.param[name].objects
                match = [o for o in objects if str(o) == text or number_text(o) == text]
                if match:
                    setattr(self, name, match[0])
                else:
                    shown = ", ".join(str(o) for o in objects)
                    problems.append(f"address: {key} must be one of {shown}, got {text!r}")
            elif "typed" in self.param:
                type_text(self, name, text)
            else:
                value = parse_number(text)
                if value is None:
                    problems.append(f"address: {key} must be a number, got {text!r}")
                else:
                    setattr(self, name, value)
        return problems

    def _apply_point(self, text: str) -> list[str]:
        problems = []
        for item in filter(None, text.split(",")):
            dim, _, index = item.partition(":")
            try:
                self.select(dim, int(index))
            except ValueError as exc:
                problems.append(f"address: {self.key}.point: {' '.join(str(exc).split())}")
        return problems


class OwnSettings:
    """A tab with settings of its own (Interface, Bladed disk), on the session's machinery
    (:class:`~app.session.Runner`): nothing computes until :meth:`activate`; then :meth:`refresh` shows
    the results of ``settings()`` from the cache or runs its ``tasks()``, after naming its ``problems()``.
    The tab provides ``settings()``, ``_publish_results`` and a ``typed`` parameter (texts of its boxes
    that are not numbers, by setting: :func:`app.state.type_text`), and refreshes when it changes.

    Parameters
    ----------
    tasks : Tasks, optional
        Builds the task and holds the result cache (default: the server's shared cache).
    executor : Executor, optional
        Where runs go; ``None`` computes in the calling thread (tests).
    dispatch : callable, optional
        ``dispatch(callback)`` runs ``callback`` where the page may be updated.
    """

    active = False

    def __init__(
        self,
        tasks: Tasks | None = None,
        executor: Executor | None = None,
        dispatch: Callable[[Callable[[], None]], None] | None = None,
        **params: Any,
    ) -> None:
        self.tasks = tasks or Tasks(shared_backend(), shared_cache())
        super().__init__(self.tasks.cache, executor, dispatch, **params)
        self.results: dict[str, Any] = {}

    def activate(self) -> None:
        """The tab is shown: compute (only visible plots compute)."""
        if not self.active:
            self.active = True
            self.refresh()

    def refresh(self, *_events: Any) -> None:
        """Show the results of the current settings: from the cache, or start a run."""
        if not self.active:
            return
        generation = self.new_request()
        # a text that is not a number stands in for its setting: problems() names it with its range
        s = dataclasses.replace(self.settings(), **self.typed)
        problems = s.problems()
        if problems:
            self.invalid(problems)
            return
        self.run(generation, s.tasks(self.tasks), self._publish_results)


class Scene(Exports, param.Parameterized):
    """One tab of the dashboard. Subclasses set the class attributes and the ``_figure_*`` methods."""

    explanation: ClassVar[str]
    figure_names: ClassVar[tuple[str, ...]]
    dataset_names: ClassVar[tuple[str, ...]]
    uses_selection: ClassVar[bool] = False
    #: whether the scene's results depend on wear (its record has k_w, the method and its options)
    wears: ClassVar[bool] = True
    #: parameters of the scene that change what it computes (the session refreshes when they change)
    inputs: ClassVar[tuple[str, ...]] = ()

    version = param.Integer(0, doc="Incremented at each publish: the figures redraw")
    notes = param.List([], doc="Messages about the published results (failures, warnings)")
    findings = param.List([], doc="What the published results show (e.g. an error against the exact answer)")

    def __init__(self, tasks: Tasks, **params: Any) -> None:
        super().__init__(**params)
        self.tasks = tasks
        self.results: dict[str, Any] = {}
        self.settings: Settings = Controls().settings()
        self.selection = Selection(0.7, 1e4)

    # -- what to compute ----------------------------------------------------------------
    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        """The tasks whose results this scene draws, for settings ``s`` and selection ``sel``."""
        raise NotImplementedError

    def publish(self, results: dict[str, Any], s: Settings, sel: Selection) -> None:
        """Show ``results`` computed for ``s`` and ``sel``: the figures redraw."""
        self.results, self.settings, self.selection = results, s, sel
        self.redraw()

    def redraw(self) -> None:
        """Redraw the published results (after a change of how they are shown)."""
        self.notes = [
            n for name, value in self.results.items() for n in _failure_note(name, value)
        ] + self._notes()
        self.findings = self._findings()
        self.version += 1

    def _notes(self) -> list[str]:
        return []

    def _findings(self) -> list[str]:
        return []

    # -- what to show ---------------------------------------------------------------------
    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        """Tables (column name -> values) of the published results, by name."""
        return {}

    def record(self) -> dict[str, Any]:
        """The parameter record of the published results (settings record keys, see
        ``fretwear.figures.record``): what every export of this scene is stamped with."""
        out = self.settings.record(wear=self.wears)
        if self.uses_selection:
            out["f"] = self.selection.frequency
            if self.wears:
                out["N"] = self.selection.cycles
        return out

    # -- export ---------------------------------------------------------------------------
    def csv_header(self) -> str:
        """``#`` lines of a CSV export: the parameter record."""
        return csv_header(self.record())

    def caption(self) -> Callable[[bool], str]:
        """Caption of an exported figure: the parameter record (``markup``: with HTML tags)."""
        record = self.record()
        return lambda markup: caption(record, markup=markup)


def linear_curves(scene: Scene) -> dict[str, tuple]:
    out = {}
    for state in ("stuck", "open"):
        lin = ok_value(scene.results.get(f"linear_{state}"))
        out[f"{state} (linear)"] = EMPTY if lin is None else (lin["f_hz"], np.abs(lin["amplitude"][:, 0]))
    return out


def linear_table(scene: Scene) -> dict[str, dict[str, np.ndarray]]:
    stuck, free = (ok_value(scene.results.get(f"linear_{s}")) for s in ("stuck", "open"))
    if stuck is None or free is None or len(stuck["f_hz"]) != len(free["f_hz"]):
        return {}
    table = {"f_hz": stuck["f_hz"]}
    for label, lin in (("stuck", stuck), ("open", free)):
        u = lin["amplitude"]
        table |= {f"x{i + 1}_{label}": np.abs(u[:, i]) for i in range(u.shape[1])}
    return {"linear_frf": table}


def no_wear(scene: Scene) -> tuple:
    """``(f, x1)`` of the nonlinear FRF without wear (HBM + DLFT sweep), whatever the slow-time method."""
    frf = ok_value(scene.results.get("frf"))
    return EMPTY if frf is None else (frf["f_hz"], frf["amplitude"][:, 0])
