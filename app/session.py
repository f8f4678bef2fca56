"""One browser session: the visible scene, the selected point, the runs and their progress.

:meth:`Session.refresh` runs whenever a control, the scene, the selection or
an input of a scene (``Scene.inputs``: the accuracy scene's ladder) changes.
It asks the visible scene for its tasks; when every result is cached the
scene is redrawn at once, otherwise a run computes the missing ones off the
UI thread (``executor``) and publishes them when it ends. Each request has a
generation number: a newer request makes the older run stale, so it stops at
its next task, chunk or rung and never publishes.

Results are published through ``dispatch``, which the page sets to schedule
the update on the session's event loop (Bokeh's ``add_next_tick_callback``);
without one (tests, warm-up) they are published from the running thread.
Before a long task (a wear map, a regime map, time integration), the results
computed so far are shown next to the previous ones.

The running itself (:class:`Runner`: requests, runs, progress, errors) is the
same for every tab: the Interface and Study tabs are runners too, on the
session's :class:`~app.state.Tasks` and cache.
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable, Iterator
from concurrent.futures import Executor, Future
from contextlib import contextmanager
from functools import partial
from typing import Any
from urllib.parse import parse_qsl, urlencode

import numpy as np
import param

from fretwear import compile as kernels
from fretwear.figures.record import SETTINGS_KEYS

from .backend import Backend, Cancelled, ResultCache, shared_backend, shared_cache
from .scenes import SCENES, AccuracyScene, Scene, Selection
from .state import (
    CONTROL_KEYS,
    CUSTOM,
    PRESETS,
    Controls,
    Job,
    Settings,
    Step,
    Task,
    Tasks,
    number_text,
    parse_number,
    shown,
    type_text,
)

__all__ = ["Runner", "Session"]

log = logging.getLogger(__name__)

#: ``publish(results, final)``: shows the results of a request's tasks by name (``final``: all of them)
Publish = Callable[[dict[str, Any], bool], None]
#: before a task at least this heavy (see ``Task.weight``), the results computed so far are shown
PARTIAL_WEIGHT = 3.0
#: set once every kernel group of :mod:`fretwear.compile` is compiled or in Numba's cache
_compiled = threading.Event()


def computing(label: str) -> str:
    """The progress line of a run computing ``label``, saying so while the kernels still compile.

    On a fresh install the first computations wait for Numba to compile the
    kernels (the server's warm-up compiles them all, a few minutes, once).
    """
    if not _compiled.is_set():
        if kernels.pending():
            return f"Computing {label} (compiling numerical kernels, first run only: a few minutes, once)"
        _compiled.set()
    return f"Computing {label}"


class Runner(param.Parameterized):
    """Runs the tasks of a request through the result cache, off the UI thread, and publishes them.

    Every tab computes this way (the session's scenes, the Interface and Study
    tabs): :meth:`new_request` makes the runs started before stale (they stop
    at their next task, chunk or rung and never publish), :meth:`run` publishes
    the tasks' results at once when all are cached and otherwise computes the
    missing ones in ``executor`` (``None``: in the calling thread), with the
    progress in :attr:`progress` and :attr:`status`. A library error is a
    :class:`~app.backend.Failure` result (see :meth:`Tasks.call`); anything else
    is a bug, logged with its traceback and shown in :attr:`error` in one line.

    Parameters
    ----------
    cache : ResultCache
        Where results are kept.
    executor : Executor, optional
        Where runs go; ``None`` computes in the calling thread.
    dispatch : callable, optional
        ``dispatch(callback)`` runs ``callback`` where the page may be
        updated; default: call it at once.
    """

    busy = param.Boolean(False, doc="A run is computing results for the visible scene")
    progress = param.Integer(0, bounds=(0, 100), doc="Progress of the run (%)")
    status = param.String("", doc="What the run is computing")
    error = param.String("", doc="Invalid input, shown instead of computing")

    def __init__(
        self,
        cache: ResultCache,
        executor: Executor | None = None,
        dispatch: Callable[[Callable[[], None]], None] | None = None,
        **params: Any,
    ) -> None:
        super().__init__(**params)
        self.cache, self.executor = cache, executor
        self.dispatch = dispatch or (lambda callback: callback())
        self._generation = 0
        self._lock = threading.Lock()
        self._future: Future | None = None
        self._reported: tuple[int, int, str] = (0, -1, "")

    def new_request(self) -> int:
        """Make the runs started so far stale; the number of the new request."""
        with self._lock:
            self._generation += 1
            return self._generation

    def invalid(self, problems: list[str]) -> None:
        """Show ``problems`` (of the input) instead of computing."""
        self.param.update(error="Invalid input: " + "; ".join(problems), busy=False, status="")

    def run(self, generation: int, tasks: list[Task], publish: Publish) -> None:
        """Publish the results of ``tasks`` (by task name) with ``publish(results, final)`` for request
        ``generation``: at once from the cache, or when a run has computed them.

        Before a long task, the results computed so far are published with ``final`` false.
        """
        self.error = ""
        if all(t.key in self.cache for t in tasks):
            self._publish(generation, publish, {t.name: self.cache.get(t.key) for t in tasks}, True)
            return
        self.param.update(busy=True, progress=0, status=computing(tasks[0].label))
        run = partial(self._run, generation, tasks, publish)
        if self.executor is None:
            run()
        else:
            self._future = self.executor.submit(run)

    def close(self) -> None:
        """Stop the pending run (the browser session ended)."""
        self.new_request()

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the last run started (tests, warm-up)."""
        if self._future is not None:
            self._future.result(timeout)

    def _stale(self, generation: int) -> bool:
        return generation != self._generation

    def _run(self, generation: int, tasks: list[Task], publish: Publish) -> None:
        job = Job(cancelled=partial(self._stale, generation))
        total, done, fresh = sum(t.weight for t in tasks), 0.0, False
        try:
            for task in tasks:
                if job.cancelled():
                    return
                if fresh and task.weight >= PARTIAL_WEIGHT and task.key not in self.cache:
                    # a long task follows: show what is new now, the older results meanwhile
                    self.dispatch(partial(self._publish, generation, publish, dict(job.results), False))
                fresh = fresh or task.key not in self.cache
                job.progress = partial(
                    self._report, generation, done / total, task.weight / total, task.label
                )
                job.progress(0.0)
                job.results[task.name] = self.cache.get_or_compute(task.key, partial(task.run, job))
                done += task.weight
        except Cancelled:
            return
        except Exception as exc:  # noqa: BLE001 - a bug: logged with its traceback, reported in one line
            log.exception("run failed")
            message = f"Internal error ({type(exc).__name__}: {exc}); the server log has the details"
            self.dispatch(partial(self._fail, generation, message))
            return
        self.dispatch(partial(self._publish, generation, publish, job.results, True))

    def _report(
        self,
        generation: int,
        start: float,
        weight: float,
        label: str,
        fraction: float,
        stage: str | None = None,
    ) -> None:
        percent = int(100 * min(start + weight * fraction, 1.0))
        label = stage or label
        if (generation, percent, label) == self._reported:
            return
        self._reported = (generation, percent, label)

        def update():
            if not self._stale(generation):
                self.param.update(progress=percent, status=computing(label))

        self.dispatch(update)

    def _fail(self, generation: int, message: str) -> None:
        if not self._stale(generation):
            self.param.update(error=message, busy=False, status="")

    def _publish(self, generation: int, publish: Publish, results: dict, final: bool) -> None:
        if self._stale(generation):
            return
        publish(results, final)
        if final:
            self.param.update(busy=False, progress=100, status="")


class Session(Runner):
    """State of one dashboard session.

    Parameters
    ----------
    controls : Controls, optional
        The sidebar's values (default: the paper's 10 N case).
    backend : Backend, optional
        Library calls (default: the server's shared backend).
    cache : ResultCache, optional
        Result cache (default: the server's shared cache).
    executor : Executor, optional
        Where runs go; ``None`` computes in the calling thread.
    dispatch : callable, optional
        ``dispatch(callback)`` runs ``callback`` where the page may be
        updated; default: call it at once.
    start : bool
        Show the visible scene at once; ``False`` waits for :meth:`start`
        (e.g. after applying the page's address).
    """

    scene = param.Selector(default=SCENES[0].key, objects=[s.key for s in SCENES], doc="Visible scene")
    frequency = param.Number(0.7, allow_None=True, doc="Selected frequency (Hz)")
    cycles = param.Number(1e4, allow_None=True, doc="Selected cycle count N")
    notice = param.String("", doc="What the dashboard changed by itself (e.g. moved the selected point)")
    typed = param.Dict({}, doc="Texts typed into the selection's boxes that are not numbers")
    lesson = param.String("", doc="The preset whose guided tour is shown (lesson mode); '' for none")
    step = param.Integer(0, bounds=(0, None), doc="The tour's current step")

    def __init__(
        self,
        controls: Controls | None = None,
        backend: Backend | None = None,
        cache: ResultCache | None = None,
        executor: Executor | None = None,
        dispatch: Callable[[Callable[[], None]], None] | None = None,
        start: bool = True,
        **params: Any,
    ) -> None:
        super().__init__(cache if cache is not None else shared_cache(), executor, dispatch, **params)
        self.controls = controls or Controls()
        self.backend = backend if backend is not None else shared_backend()
        self.tasks = Tasks(self.backend, self.cache)
        self.scenes: dict[str, Scene] = {cls.key: cls(self.tasks) for cls in SCENES}
        self._shown: dict[str, tuple] = {}
        self._held, self._pending, self._moving = 0, False, False
        self.controls.param.watch(self.refresh, [p for p in self.controls.param if p != "name"])
        self.controls.param.watch(self._lesson, "preset")
        self._lesson()
        self.param.watch(self.refresh, ["scene", "frequency", "cycles", "typed"])
        for scene in self.scenes.values():
            if scene.inputs:
                scene.param.watch(self.refresh, list(scene.inputs))
        if start:
            self.refresh()
        else:
            self._held = 1

    def start(self, problems: list[str] = ()) -> None:
        """Show the visible scene (a session made with ``start=False``); ``problems``: of the settings
        applied before, shown as a notice."""
        self._held, self._pending = 0, False
        self.refresh()
        if problems:
            self.notice = "Some settings of the address were left out: " + "; ".join(problems)

    @property
    def current(self) -> Scene:
        """The visible scene."""
        return self.scenes[self.scene]

    def select(self, f_hz: float, log10_cycles: float) -> None:
        """Select the wear-map point nearest to (``f_hz``, ``10**log10_cycles``)."""
        if f_hz is None or log10_cycles is None or not np.isfinite([f_hz, log10_cycles]).all():
            return
        try:
            s = self.controls.settings()
        except ValueError:
            return
        grid = s.cycles
        n = float(np.clip(10.0**log10_cycles, grid[1], grid[-1]))
        self.param.update(frequency=s.snap(f_hz), cycles=float(f"{n:.3g}"), typed={})

    def apply(self, changes: dict[str, Any]) -> None:
        """Set the sidebar controls ``changes`` (name -> value) in one update: one request."""
        self.controls.param.update(**changes)

    @contextmanager
    def one_request(self) -> Iterator[None]:
        """Changes made inside make one request, when the block ends (not one per change)."""
        self._held += 1
        try:
            yield
        finally:
            self._held -= 1
        if not self._held and self._pending:
            self._pending = False
            self.refresh()

    def apply_preset(self, name: str) -> None:
        """Preset ``name``: its controls, scene and selected point in one request; its tour starts."""
        if name == CUSTOM:
            self.controls.preset = CUSTOM
            return
        preset = PRESETS[name]
        with self.one_request():
            self.controls.apply_preset(name)
            self.param.update(scene=preset.scene, frequency=preset.frequency, cycles=preset.cycles, typed={},
                              lesson=name, step=0)  # fmt: skip

    # -- lesson mode: a preset's guided tour ----------------------------------------------------
    def _lesson(self, *_events: Any) -> None:
        """A preset chosen or recognised starts its tour; editing the controls ("custom") keeps it."""
        preset = self.controls.preset
        if preset in PRESETS and preset != self.lesson:
            self.param.update(lesson=preset, step=0)

    def tour(self) -> tuple[Step, ...]:
        """The steps of the current lesson's tour (none without a lesson)."""
        return PRESETS[self.lesson].tour() if self.lesson in PRESETS else ()

    def move(self, by: int) -> None:
        """Go ``by`` steps forward (or back) in the tour, within its ends."""
        self.step = int(np.clip(self.step + by, 0, max(len(self.tour()) - 1, 0)))

    def do_step(self) -> list[str]:
        """Apply the current step's change (its controls, scene or point) in one request; the problems."""
        tour = self.tour()
        return self.apply_record(dict(tour[self.step].change), recognise=False) if tour else []

    # -- the view as a settings record (URL query, settings file) -----------------------------
    def record(self) -> dict[str, Any]:
        """The whole view as a settings record: controls, scene, selected point, accuracy settings."""
        acc = self.scenes["accuracy"]
        return {
            **self.controls.record(),
            "f": self.frequency,
            "N": self.cycles,
            "scene": self.scene,
            "quantity": acc.quantity,
            "target": acc.target,
            "ladder": acc.ladder,
            "rungs": acc.wear,
        }

    def query(self) -> str:
        """The view as a URL query (``fex=14&mu=0.8&...&scene=wearmap``): the values that differ from
        the defaults, and always the scene and the selected point."""
        default = Session.defaults()
        items = []
        for key, value in self.record().items():
            if key in ("scene", "f", "N") or value != default.get(key):
                text = str(value).lower() if isinstance(value, bool) else number_text(value) or str(value)
                items.append((key, text))
        return urlencode(items)

    @staticmethod
    def defaults() -> dict[str, Any]:
        """The settings record of a new session."""
        controls = Controls()
        record = {CONTROL_KEYS[name]: getattr(controls, name) for name in CONTROL_KEYS}
        acc = {p: AccuracyScene.param[p].default for p in ("quantity", "target", "ladder", "wear")}
        return record | {"f": Session.param.frequency.default, "N": Session.param.cycles.default,
                         "scene": Session.param.scene.default, "quantity": acc["quantity"],
                         "target": acc["target"], "ladder": acc["ladder"], "rungs": acc["wear"]}  # fmt: skip

    def apply_query(self, query: str | dict[str, list[str]]) -> list[str]:
        """Apply a URL query (text, or parsed: key -> values); the problems met, each in one line.

        Numbers are typed into the controls as into their boxes (an invalid one
        is kept and reported like a typed one); unknown keys and bad names are
        reported and left out.
        """
        pairs = parse_qsl(query) if isinstance(query, str) else [(k, v[-1]) for k, v in query.items()]
        record, problems = {}, []
        for key, text in pairs:
            text = text.decode() if isinstance(text, bytes) else text
            if key not in SETTINGS_KEYS:
                problems.append(f"address: unknown setting {key!r} (known: {', '.join(SETTINGS_KEYS)})")
                continue
            kind = SETTINGS_KEYS[key][0]
            if kind is str:
                record[key] = text
            elif kind is bool:
                record[key] = text.lower() in ("1", "true", "yes", "on")
            else:
                record[key] = text  # typed as into a box: checked with the controls
        return problems + self.apply_record(record, source="address")

    def apply_record(
        self, record: dict[str, Any], source: str = "settings", recognise: bool = True
    ) -> list[str]:
        """Apply a settings record (values or their texts) in one request; the problems met.

        ``recognise``: name the preset the controls then hold (a link, a settings file; not a tour's step,
        which keeps its tour).

        Control values go through the controls' checks (an invalid one is shown
        as typed, with its valid range); the scene, the method and the accuracy
        scene's choices must be among theirs.
        """
        problems = []
        names = {key: name for name, key in CONTROL_KEYS.items()}
        acc = self.scenes["accuracy"]
        with self.one_request():
            for key, value in record.items():
                if key in ("scene", "method", "dynamics", "quantity", "ladder") or key == "target":
                    owner, name = {"scene": (self, "scene"), "method": (self.controls, "method"),
                                   "dynamics": (self.controls, "dynamics"), "quantity": (acc, "quantity"),
                                   "ladder": (acc, "ladder"), "target": (acc, "target")}[key]  # fmt: skip
                    objects = owner.param[name].objects
                    if key == "target":
                        value = parse_number(str(value))
                        match = [t for t in objects if value is not None and math.isclose(t, value)]
                        value = match[0] if match else value
                    if value not in objects:
                        shown = ", ".join(number_text(o) or str(o) for o in objects)
                        problems.append(f"{source}: {key} must be one of {shown}, got {value!r}")
                        continue
                    setattr(owner, name, value)
                elif key == "rungs":
                    acc.wear = bool(value)
                elif key in ("f", "N"):
                    number = value if isinstance(value, (int, float)) else parse_number(str(value))
                    if number is None:
                        problems.append(f"{source}: {key} must be a number, got {value!r}")
                        continue
                    self.type_text("frequency" if key == "f" else "cycles", number_text(number))
                elif key in names:
                    self.controls.type_text(
                        names[key], value if isinstance(value, str) else number_text(value)
                    )
            if recognise:
                self.controls.recognise_preset()
        return problems

    def type_text(self, name: str, text: str) -> None:
        """Set the selected ``frequency`` or ``cycles`` from the text of its box (``Controls.type_text``)."""
        type_text(self, name, text)

    def _selection_problems(self) -> list[str]:
        out = []
        for name, label, unit in (("frequency", "selected f", "Hz"), ("cycles", "selected N", "cycles")):
            if name in self.typed:
                text = self.typed[name]
                out.append(f"{label} must be a number ({unit}), got {text!r}" if text.strip()
                           else f"{label} must be a number ({unit}); the box is empty")  # fmt: skip
        if out:
            return out
        f, n = self.frequency, self.cycles
        band, horizon = self._band(), self._horizon()
        if not (isinstance(f, (int, float)) and math.isfinite(f) and 0 < f <= 20):
            out.append(f"selected f must be a number > 0 and <= 20 Hz, got {shown(f)}")
        elif band is not None and not band[0] <= f <= band[1]:
            out.append(
                f"selected f must be within the frequency band {band[0]:g} to {band[1]:g} Hz, "
                f"got {number_text(f)}"
            )
        top = 1e12 if horizon is None else horizon
        if not (isinstance(n, (int, float)) and math.isfinite(n) and 0 <= n <= top):
            within = "1e12 cycles" if horizon is None else f"the cycle horizon {horizon:g}"
            out.append(f"selected N must be a number >= 0 and <= {within}, got {shown(n)}")
        return out

    def _band(self) -> tuple[float, float] | None:
        """The frequency band of valid controls (``None`` when they are not)."""
        c = self.controls
        if any(k in c.typed for k in ("fmin", "fmax")) or any(p.startswith("f m") for p in c.problems()):
            return None
        return (c.fmin, c.fmax)

    def _horizon(self) -> float | None:
        c = self.controls
        if "horizon" in c.typed or any(p.startswith("cycle horizon") for p in c.problems()):
            return None
        return float(c.horizon)

    def _follow(self, events: tuple) -> bool:
        """Move the selected point into a band or horizon that a control change left it out of.

        Returns whether it moved (the move makes its own request).
        """
        changed = {e.name for e in events if getattr(e, "obj", None) is self.controls}
        if not changed & {"fmin", "fmax", "n_frequencies", "horizon"}:
            return False
        try:
            s = self.controls.settings()
        except ValueError:
            return False
        f, n, moves = self.frequency, self.cycles, []
        if isinstance(f, (int, float)) and math.isfinite(f) and not s.fmin <= f <= s.fmax:
            f = s.snap(f)
            moves.append(f"f from {number_text(self.frequency)} to {number_text(f)} Hz "
                         f"(the band is {s.fmin:g} to {s.fmax:g} Hz)")  # fmt: skip
        if isinstance(n, (int, float)) and math.isfinite(n) and n > s.horizon:
            n = s.horizon
            moves.append(f"N from {number_text(self.cycles)} to the horizon {s.horizon:g}")
        if not moves:
            return False
        self._moving = True
        try:
            self.param.update(
                frequency=f, cycles=n, notice="The selected point moved: " + "; ".join(moves) + "."
            )
        finally:
            self._moving = False
        return True

    # -- requests ---------------------------------------------------------------------------
    def refresh(self, *events: Any) -> None:
        """Show the visible scene for the current controls: from the cache, or start a run."""
        if self._held:
            self._pending = True
            return
        if events and not self._moving:
            self.notice = ""  # a change by the user: what the dashboard moved before is old news
        if self._follow(events):
            return
        problems = self.controls.problems() + self._selection_problems()
        generation = self.new_request()
        if problems:
            self.invalid(problems)
            return
        s, sel, scene = (
            self.controls.settings(),
            Selection(float(self.frequency), float(self.cycles)),
            self.current,
        )
        tasks = scene.needs(s, sel)
        shown = (tuple(t.key for t in tasks), s, sel if scene.uses_selection else None)
        self.error = ""
        if self._shown.get(scene.key) == shown:
            self.param.update(busy=False, status="")
            return
        self.run(generation, tasks, partial(self._show, scene, s, sel, shown))

    def _show(
        self, scene: Scene, s: Settings, sel: Selection, shown: tuple, results: dict, final: bool
    ) -> None:
        """Publish ``results`` into ``scene``: the final ones of the request, or those computed so far
        (shown with the scene's older results)."""
        scene.publish(results if final else {**scene.results, **results}, s, sel)
        if final:
            self._shown[scene.key] = shown
