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
"""

from __future__ import annotations

import logging
import math
import threading
from collections.abc import Callable
from concurrent.futures import Executor, Future
from functools import partial
from typing import Any

import numpy as np
import param

from .backend import Backend, Cancelled, ResultCache, shared_backend, shared_cache
from .scenes import SCENES, Scene, Selection
from .state import Controls, Job, Settings, Task, Tasks

__all__ = ["Session"]

log = logging.getLogger(__name__)

#: before a task at least this heavy (see ``Task.weight``), the results computed so far are shown
PARTIAL_WEIGHT = 3.0


class Session(param.Parameterized):
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
    """

    scene = param.Selector(default=SCENES[0].key, objects=[s.key for s in SCENES], doc="Visible scene")
    frequency = param.Number(0.7, allow_None=True, doc="Selected frequency (Hz)")
    cycles = param.Number(1e4, allow_None=True, doc="Selected cycle count N")
    busy = param.Boolean(False, doc="A run is computing results for the visible scene")
    progress = param.Integer(0, bounds=(0, 100), doc="Progress of the run (%)")
    status = param.String("", doc="What the run is computing")
    error = param.String("", doc="Invalid input, shown instead of computing")

    def __init__(
        self,
        controls: Controls | None = None,
        backend: Backend | None = None,
        cache: ResultCache | None = None,
        executor: Executor | None = None,
        dispatch: Callable[[Callable[[], None]], None] | None = None,
        **params: Any,
    ) -> None:
        super().__init__(**params)
        self.controls = controls or Controls()
        self.backend = backend if backend is not None else shared_backend()
        self.cache = cache if cache is not None else shared_cache()
        self.executor = executor
        self.dispatch = dispatch or (lambda callback: callback())
        tasks = Tasks(self.backend, self.cache)
        self.scenes: dict[str, Scene] = {cls.key: cls(tasks) for cls in SCENES}
        self._generation = 0
        self._lock = threading.Lock()
        self._shown: dict[str, tuple] = {}
        self._future: Future | None = None
        self._reported: tuple[int, int, str] = (0, -1, "")
        self.controls.param.watch(self.refresh, [p for p in self.controls.param if p != "name"])
        self.param.watch(self.refresh, ["scene", "frequency", "cycles"])
        for scene in self.scenes.values():
            if scene.inputs:
                scene.param.watch(self.refresh, list(scene.inputs))
        self.refresh()

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
        self.param.update(frequency=s.snap(f_hz), cycles=float(f"{n:.3g}"))

    def apply(self, changes: dict[str, Any]) -> None:
        """Set the sidebar controls ``changes`` (name -> value) in one update: one request."""
        self.controls.param.update(**changes)

    def _selection_problems(self) -> list[str]:
        out = []
        f, n = self.frequency, self.cycles
        if not (isinstance(f, (int, float)) and math.isfinite(f) and 0 < f <= 20):
            out.append(f"selected frequency must be a number > 0 and <= 20 Hz, got {f!r}")
        if not (isinstance(n, (int, float)) and math.isfinite(n) and 0 <= n <= 1e12):
            out.append(f"selected N must be a number >= 0 and <= 1e12 cycles, got {n!r}")
        return out

    # -- requests ---------------------------------------------------------------------------
    def refresh(self, *_events: Any) -> None:
        """Show the visible scene for the current controls: from the cache, or start a run."""
        problems = self.controls.problems() + self._selection_problems()
        with self._lock:
            self._generation += 1
            generation = self._generation
        if problems:
            self.param.update(error="Invalid input: " + "; ".join(problems), busy=False, status="")
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
        if all(t.key in self.cache for t in tasks):
            self._publish(generation, scene, {t.name: self.cache.get(t.key) for t in tasks}, s, sel, shown)
            return
        self.param.update(busy=True, progress=0, status=f"Computing {tasks[0].label}")
        run = partial(self._run, generation, scene, tasks, s, sel, shown)
        if self.executor is None:
            run()
        else:
            self._future = self.executor.submit(run)

    def close(self) -> None:
        """Stop the pending run (the browser session ended)."""
        with self._lock:
            self._generation += 1

    def wait(self, timeout: float | None = None) -> None:
        """Wait for the last run started (tests, warm-up)."""
        if self._future is not None:
            self._future.result(timeout)

    def _stale(self, generation: int) -> bool:
        return generation != self._generation

    def _run(
        self, generation: int, scene: Scene, tasks: list[Task], s: Settings, sel: Selection, shown: tuple
    ) -> None:
        job = Job(cancelled=partial(self._stale, generation))
        total, done, fresh = sum(t.weight for t in tasks), 0.0, False
        try:
            for task in tasks:
                if job.cancelled():
                    return
                if fresh and task.weight >= PARTIAL_WEIGHT and task.key not in self.cache:
                    # a long task follows: show what is new now, the older results meanwhile
                    self.dispatch(
                        partial(
                            self._publish, generation, scene, {**scene.results, **job.results}, s, sel, None
                        )
                    )
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
        self.dispatch(partial(self._publish, generation, scene, job.results, s, sel, shown))

    def _report(self, generation: int, start: float, weight: float, label: str, fraction: float) -> None:
        percent = int(100 * min(start + weight * fraction, 1.0))
        if (generation, percent, label) == self._reported:
            return
        self._reported = (generation, percent, label)

        def update():
            if not self._stale(generation):
                self.param.update(progress=percent, status=f"Computing {label}")

        self.dispatch(update)

    def _fail(self, generation: int, message: str) -> None:
        if not self._stale(generation):
            self.param.update(error=message, busy=False, status="")

    def _publish(
        self, generation: int, scene: Scene, results: dict, s: Settings, sel: Selection, shown: tuple
    ) -> None:
        if self._stale(generation):
            return
        scene.publish(results, s, sel)
        if shown is not None:  # the final results of the request (``None``: partial ones)
            self._shown[scene.key] = shown
            self.param.update(busy=False, progress=100, status="")
