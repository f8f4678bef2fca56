"""Warm-up of a dashboard server: compiled kernels, plotting code and the default scenes' results.

``warm()`` compiles (or loads from Numba's on-disk cache) every kernel the
scenes use, by tiny runs of each solver and slow-time method, builds the
sliding tables of the default exact wear map (:func:`warm_tables`: the exact
method on the event-driven dynamics, whatever the sidebar's method), then
computes the results of the default settings' first scenes into the
process-wide cache and draws their figures once, so that the first page is
served from the cache and no later scene waits for a compilation or a table.
Two ways to run it:

* ``panel serve app/app.py --setup app/warmup.py``: before the server accepts
  connections (it blocks the start-up for a few seconds);
* ``panel serve app/app.py --warm``: Panel executes ``app.py`` at start-up,
  which starts :func:`warm_in_background`; without ``--warm`` that happens when
  the first session opens.
"""

from __future__ import annotations

import logging
import os
import sys
import threading
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))
# One OpenBLAS thread per process (unless set): the sessions share the server's cores, and OpenBLAS threads
# waiting for a busy core made the Interface tab's dense solves 3-25x slower under load (measured; on an
# idle machine one thread was as fast). SciPy's BLAS reads this when it loads, at the first computation.
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

__all__ = ["compile_kernels", "warm", "warm_in_background", "warm_later", "warm_scenes", "warm_tables"]

#: scenes of the defaults computed after the first page's, in the background, this many seconds later
LATER, LATER_DELAY = ("accuracy",), 20.0

log = logging.getLogger(__name__)
_started = threading.Lock()
_thread: list[threading.Thread] = []


def compile_kernels() -> float:
    """Run every solver and slow-time method once on a tiny case (compiling its kernels); seconds spent.

    From Numba's cache this takes about a second. With an empty cache (a fresh
    install) the kernels of every scene, the Interface tab's included, first
    compile in two processes at once (:func:`fretwear.compile.warm_in_processes`):
    two to three minutes on two cores, once.
    """
    import numpy as np

    import fretwear as fw
    from fretwear.compile import warm_in_processes

    start = time.perf_counter()
    warm_in_processes()
    model, omega = fw.paper_model(fex=10), 2 * np.pi * 0.7
    fw.sweep(model, omega * np.array([0.95, 1.0]), 3)
    fw.shooting(model, omega)
    fw.shooting_sweep(model, omega * np.array([0.95, 1.0]))
    for name in fw.METHODS:
        fw.wear_history(model, omega, name, kw=1e-11, cycles=20.0)
    for name in ("exact", "stepping"):
        fw.wear_history(model, omega, name, kw=1e-11, cycles=20.0, dynamics="shooting")
    return time.perf_counter() - start


def warm_tables() -> float:
    """Build the sliding tables of the default exact wear map (the dashboard's settings); seconds spent.

    The exact method on the event-driven dynamics over the default band, at the
    default ``F_N``, ``mu``, ``F_ex``: one table per frequency of the map, kept
    in memory (and on disk, :func:`fretwear.wear.sliding.cache_dir`), so that
    the first exact wear map, and every later one at other ``F_ex``, ``mu``,
    ``k_w`` or ``u0`` in their range, solves nothing.
    """
    import fretwear as fw
    from app.backend import Backend
    from app.state import Controls

    start = time.perf_counter()
    s = Controls().settings()
    model = Backend().model(s.model)
    fw.wear_map(model, s.frequencies, s.cycles, method="exact", dynamics="shooting", kw=s.kw)
    return time.perf_counter() - start


def warm(scenes: tuple[str, ...] = ("regimes", "wearmap"), draw: bool = True, exports: bool = False) -> float:
    """Compute the default ``scenes`` into the shared cache; seconds spent.

    With ``draw``, draw their figures once too (imports the plotting code); with
    ``exports``, also load Matplotlib for the PNG and SVG exports (before the
    server starts only: loading a backend switches HoloViews' current one for
    a moment).
    """
    from fretwear import figures

    start = time.perf_counter()
    compile_kernels()
    warm_tables()
    warm_scenes(scenes, draw)
    if exports:
        figures.load_backend("matplotlib")
    return time.perf_counter() - start


def warm_scenes(scenes: tuple[str, ...], draw: bool = True) -> float:
    """Compute the default ``scenes`` into the shared cache (kernels compiled); seconds spent."""
    from app.session import Session
    from fretwear import figures

    start = time.perf_counter()
    session = Session()
    for key in scenes:
        session.scene = key
        if draw:
            figures.load_backend("bokeh")
            for name in session.current.figure_names:
                session.current.figure(name)
    return time.perf_counter() - start


def warm_later(scenes: tuple[str, ...] = LATER, delay: float = LATER_DELAY) -> threading.Thread:
    """Compute the default ``scenes`` in a daemon thread, ``delay`` seconds from now (after the first
    pages, which it would slow down): the *Accuracy vs cost* ladder of the defaults, a few seconds,
    then comes from the cache when first opened."""

    def run():
        try:
            log.info("fretwear: %s warmed in %.1f s", ", ".join(scenes), warm_scenes(scenes, draw=False))
        except Exception:  # noqa: BLE001 - a failed warm-up only costs time later
            log.exception("fretwear warm-up of %s failed", scenes)

    thread = threading.Timer(delay, run)
    thread.name, thread.daemon = "fretwear-warm-later", True
    thread.start()
    return thread


def warm_in_background() -> threading.Thread:
    """Start :func:`warm` in a daemon thread, once per process; the thread."""
    with _started:
        if not _thread:

            def run():
                try:
                    log.info("fretwear warm-up done in %.1f s", warm())
                except Exception:  # noqa: BLE001 - a failed warm-up only costs time later
                    log.exception("fretwear warm-up failed")
                    return
                warm_later().join()

            _thread.append(threading.Thread(target=run, name="fretwear-warm-up", daemon=True))
            _thread[0].start()
        return _thread[0]


if __name__ in ("__main__", "panel_setup_module"):
    print(f"fretwear: warmed up in {warm(exports=True):.1f} s", flush=True)
    warm_later()  # while the server starts and serves the first pages
