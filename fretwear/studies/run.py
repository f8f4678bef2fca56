"""Running a study on Dask: a local cluster or a scheduler, retries and resubmissions, Ctrl-C, progress.

The client writes each block into the store as soon as it comes back, then marks it done
(``task_seconds``): a rerun computes only the blocks not marked.
"""

from __future__ import annotations

import logging
import math
import os
import signal
import sys
import threading
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from .compute import FAILED, STATUS, Work, compute_block, prepared
from .layout import block_params, layout
from .spec import SpecError, StudySpec
from .store import open_store

__all__ = ["Progress", "StudyRun", "run_study"]


@dataclass
class StudyRun:
    """What a run did.

    Attributes
    ----------
    path : Path
        The Zarr store.
    n_points, n_tasks : int
        Points and tasks of the study.
    computed : list of int
        Tasks computed by this run.
    resumed : int
        Tasks found done in the store.
    failed_tasks : dict of int -> str
        Tasks that failed at the Dask level (left to a rerun).
    workers : int
        Worker threads of the cluster.
    wall_time : float
        Seconds from the first task submitted to the last block written.
    compute_seconds : float
        Compute time of the tasks of this run, summed.
    cpu_seconds : float
        CPU time of the tasks of this run, summed (below ``compute_seconds`` on a busy machine).
    startup_seconds : float
        Time the workers took to import fretwear, before the clock of ``wall_time`` starts.
    status_counts : dict of str -> int
        Points per status over the whole store.
    messages : list of str
        The first failures of points (point, reason).
    """

    path: Path
    n_points: int
    n_tasks: int
    computed: list[int] = field(default_factory=list)
    resumed: int = 0
    failed_tasks: dict[int, str] = field(default_factory=dict)
    workers: int = 0
    wall_time: float = 0.0
    compute_seconds: float = 0.0
    cpu_seconds: float = 0.0
    startup_seconds: float = 0.0
    status_counts: dict[str, int] = field(default_factory=dict)
    messages: list[str] = field(default_factory=list)

    @property
    def overhead_per_task(self) -> float:
        """Worker time not spent computing, per task (s): ``(workers * wall - compute) / tasks``."""
        return (self.workers * self.wall_time - self.compute_seconds) / max(1, len(self.computed))

    @property
    def overhead_fraction(self) -> float:
        """``1 - compute / (workers * wall)``: the share of the workers' time lost to overhead and idling."""
        busy = self.workers * self.wall_time
        return 1.0 - self.compute_seconds / busy if busy > 0 else 0.0

    @property
    def complete(self) -> bool:
        return not self.failed_tasks and self.status_counts.get("not_computed", 0) == 0

    @property
    def failed_points(self) -> int:
        return sum(self.status_counts.get(STATUS[c], 0) for c in FAILED)


class Progress:
    """A progress bar on a terminal (``\\r`` updates), or a line per tenth on a file."""

    def __init__(self, total_points: int, tasks: int, stream=None, enabled: bool = True):
        self.stream = stream if stream is not None else sys.stderr
        self.total, self.tasks, self.enabled = total_points, tasks, enabled and tasks > 0
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()
        self.start = time.perf_counter()
        self.points = self.done = self.failed = self.tenth = 0

    def update(self, points: int, failed: int) -> None:
        self.done += 1
        self.points += points
        self.failed += failed
        if not self.enabled:
            return
        frac = self.done / self.tasks
        elapsed = time.perf_counter() - self.start
        eta = elapsed * (1 - frac) / frac if frac > 0 else math.nan
        bar = "#" * int(30 * frac)
        line = (
            f"[{bar:<30}] {self.done}/{self.tasks} tasks, {self.points}/{self.total} points, "
            f"{self.failed} failed, {elapsed:.1f} s, eta {eta:.0f} s"
        )
        if self.tty:
            self.stream.write("\r" + line + ("\n" if self.done == self.tasks else ""))
        elif int(10 * frac) > self.tenth or self.done == self.tasks:
            self.tenth = int(10 * frac)
            self.stream.write(line + "\n")
        self.stream.flush()


@contextmanager
def _ctrl_c() -> Iterator[threading.Event]:
    """An event that Ctrl-C (SIGINT, main thread only) sets; the study stops where it checks it.

    The handler only sets the event, so that no interrupt can land inside the
    scheduler client's code (which may swallow it) or in the middle of a block's write.
    """
    pressed = threading.Event()
    if threading.current_thread() is not threading.main_thread():
        yield pressed
        return
    previous = signal.signal(signal.SIGINT, lambda signum, frame: pressed.set())
    try:
        yield pressed
    finally:
        signal.signal(signal.SIGINT, previous)


def _ready() -> int:
    """Nothing: run on every worker, it makes the worker import this module (and fretwear)."""
    return os.getpid()


def _start_client(scheduler: str | None, workers: int | None):
    """A Dask client: on ``scheduler``, or on a new local cluster of ``workers`` single-threaded processes."""
    from distributed import Client, LocalCluster

    if scheduler is not None:
        try:
            return Client(scheduler, timeout="20s", set_as_default=False), None
        except OSError as exc:
            raise SpecError("--scheduler", f"cannot reach a Dask scheduler at {scheduler!r}: {exc}") from None
    n = workers or len(os.sched_getaffinity(0))
    # Ctrl-C reaches the workers too: they start with SIGINT ignored, and the client closes them
    main = threading.current_thread() is threading.main_thread()
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN) if main else None
    try:
        cluster = LocalCluster(
            n_workers=n,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address="127.0.0.1:0",  # the scheduler's HTTP server: local, a free port
            silence_logs=logging.ERROR,
        )
    finally:
        if main:
            signal.signal(signal.SIGINT, previous)
    return Client(cluster, set_as_default=False), cluster


def run_study(
    spec: StudySpec,
    out: str | Path,
    *,
    client=None,
    scheduler: str | None = None,
    workers: int | None = None,
    retries: int = 2,
    overwrite: bool = False,
    progress: bool = True,
    log: Callable[[str], None] | None = None,
) -> StudyRun:
    """Run the study ``spec`` into the Zarr store ``out`` (created, or resumed when it holds the same study).

    Parameters
    ----------
    spec : StudySpec
        The study (:func:`fretwear.studies.spec.read_spec`).
    out : path
        Zarr store (a folder).
    client : distributed.Client, optional
        Use this client; else one on ``scheduler``, else a new local cluster of ``workers`` processes
        (default: one per core), closed at the end.
    retries : int
        Reruns of a task that raises, and resubmissions of a task the cluster loses (a worker that
        dies has its tasks rerun by the scheduler anyway, up to Dask's ``allowed-failures``).
    overwrite : bool
        Replace a store that holds another study.
    progress : bool
        Progress bar on stderr.
    log : callable, optional
        Receives the lines to print (the failures of points).

    Raises
    ------
    SpecError
        ``out`` holds another study, or is not a study store.
    KeyboardInterrupt
        Interrupted: the blocks written so far stay in the store; rerun to resume.
    """
    out = Path(out)
    connected = None
    if client is None and scheduler is not None:  # an unreachable scheduler must not leave a new store
        client, _ = connected = _start_client(scheduler, None)
    try:
        group, _ = open_store(spec, out, overwrite)
        lay = layout(spec)
        seconds_done = np.asarray(group["task_seconds"][:])
        pending = [t for t in range(lay.n_tasks) if np.isnan(seconds_done[t])]
        result = StudyRun(out, spec.n_points, lay.n_tasks, resumed=lay.n_tasks - len(pending))
        if pending:
            _compute(spec, lay, group, pending, result, client, scheduler, workers, retries, progress, log)
    finally:
        if connected is not None:
            connected[0].close()
    status = np.asarray(group["status"][:]).ravel()
    counts = np.bincount(status.astype(np.int64), minlength=len(STATUS))
    result.status_counts = {STATUS[c]: int(counts[c]) for c in range(len(STATUS)) if counts[c]}
    return result


def _compute(spec, lay, group, pending, result, client, scheduler, workers, retries, progress, log) -> None:
    from distributed import as_completed

    own = client is None
    cluster = None
    if own:
        client, cluster = _start_client(scheduler, workers)
    futures = {}
    try:
        ready = time.perf_counter()
        client.run(_ready)  # the workers import this module (and fretwear) before the clock starts
        result.startup_seconds = time.perf_counter() - ready
        result.workers = sum(w["nthreads"] for w in client.scheduler_info()["workers"].values())
        work = prepared(Work.of(spec))  # a model with contact pairs is reduced here, once
        if work.pairs:  # its reduction holds the full model (MBs): sent to each worker once, not per task
            work = client.scatter(work, broadcast=True, hash=False)
        draws = spec.draws()
        bar = Progress(spec.n_points, len(pending), enabled=progress)
        start = time.perf_counter()
        blocks = {}
        lost = dict.fromkeys(pending, 0)  # resubmissions of each task after a failure outside it
        for task in pending:
            params, slices, shape = block_params(spec, lay, draws, task)
            future = client.submit(compute_block, work, params, pure=False, retries=retries)
            futures[future] = task
            blocks[task] = (slices, shape, params)
        queue = as_completed(list(futures), loop=client.loop)
        with _ctrl_c() as pressed:
            for future in queue:
                if pressed.is_set():  # Ctrl-C: the blocks written so far are whole and marked done
                    raise KeyboardInterrupt
                task = futures.pop(future)
                slices, shape, params = blocks[task]
                if future.status != "finished":
                    # compute_block records every failure of a point, so an error here is the cluster's
                    # (a worker killed while it held the task more often than Dask allows, a lost
                    # connection): resubmit the task rather than leave a hole in the study.
                    reason = repr(future.exception()) if future.status == "error" else future.status
                    if lost[task] < retries:
                        lost[task] += 1
                        if log is not None:
                            log(f"task {task} lost ({reason}): resubmitted")
                        again = client.submit(compute_block, work, params, pure=False, retries=retries)
                        futures[again] = task
                        queue.add(again)
                        continue
                    result.failed_tasks[task] = reason
                    blocks.pop(task)
                    bar.update(0, int(np.prod(shape)))
                    continue
                blocks.pop(task)
                res = future.result()
                future.release()
                for name, values in res.items():  # Ctrl-C waits: a block is written whole, then marked done
                    if name in ("seconds", "cpu_seconds", "messages"):
                        continue
                    group[name][slices] = values.reshape(shape + values.shape[1:])
                group["task_seconds"][task : task + 1] = [res["seconds"]]
                result.computed.append(task)
                result.compute_seconds += res["seconds"]
                result.cpu_seconds += res["cpu_seconds"]
                failed = int(np.isin(res["status"], FAILED).sum())
                for i, message in res["messages"]:
                    if len(result.messages) < 20:
                        point = np.unravel_index(i, shape)
                        where = ", ".join(
                            f"{d}={s.start + int(j)}"
                            for d, s, j in zip(spec.dims, slices, point, strict=True)
                        )
                        result.messages.append(f"point ({where}): {message}")
                        if log is not None:
                            log(result.messages[-1])
                bar.update(int(np.prod(shape)), failed)
            if pressed.is_set():
                raise KeyboardInterrupt
        result.wall_time = time.perf_counter() - start
    finally:
        if futures:
            client.cancel(list(futures))
        if own:
            client.close()
            if cluster is not None:
                cluster.close()
