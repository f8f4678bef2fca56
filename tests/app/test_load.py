"""The dashboard under load: eight browser sessions moving sliders at once against one server.

One ``panel serve`` process on 127.0.0.1 (a free port) and one headless
chromium with eight browser contexts, i.e. eight independent Bokeh sessions.
Each session drags the ``F_ex`` slider, and the ``mu`` slider one move in
three, with the mouse (a random walk of its own: different values in each
session) and waits for its figures to redraw, for ``FRETWEAR_LOAD_SECONDS``
seconds: by default 60 s when this test runs alone (``-m load``) and 15 s in a
larger run, which keeps it under two minutes with the server's start-up.
``FRETWEAR_LOAD_SESSIONS`` changes the number of sessions (default 8).
Checked:

* no cross-talk: after each move the plot titles of a session show its own
  ``F_ex`` and ``r = F_ex / (mu F_N)``, and before each move its number boxes
  still show the values it set last;
* correct results: the nonlinear FRF a session displays (read from BokehJS)
  equals a direct library call for that session's parameters, for its
  first, a middle and its last move;
* no crash: every move redraws within ``REDRAW_TIMEOUT``; no traceback, error
  message or uncaught error in any page; no traceback in the server log;
* bounded memory: see :data:`RSS_GROWTH_MB`.

``python -m pytest -m load -s`` prints the numbers: moves, redraw latency
(release of the mouse to both titles redrawn) and the server's memory.
"""

import asyncio
import os
import statistics
import threading
import time
from pathlib import Path

import numpy as np
import pytest
from test_browser import CHROMIUM, CHROMIUM_ARGS, start_server, stop_server

from fretwear import paper_model
from fretwear.hbm.continuation import sweep

pytestmark = [pytest.mark.browser, pytest.mark.load]

SESSIONS = int(os.environ.get("FRETWEAR_LOAD_SESSIONS", "8"))
#: the sidebar's defaults the sessions keep: F_N (N) and Nh
NORMAL_LOAD, HARMONICS = 10.0, 7
#: seconds a redraw may take under load
REDRAW_TIMEOUT = 60.0
#: bound on the growth of the server's resident memory (``VmHWM`` - ``VmRSS`` after the warm-up, MB).
#: Measured on a 2-core machine: 342 MB after the warm-up, + 53 MB for eight open sessions (Bokeh
#: documents, Panel and HoloViews objects: 6-7 MB each), then a plateau at + 85 MB from about 90 s on in
#: a 240 s run (278 moves, as many parameter sets: the result cache holds its 48 results per kind, a
#: few MB here, and least recently used results go). 150 MB leaves room for other allocators and
#: fails on a leak of about 1 MB per move in a 60 s run.
RSS_GROWTH_MB = 150.0

#: the titles of the plots of a page: cheap (no layout), to poll in eight pages at once
TITLES_JS = """
() => {
  const out = [], stack = Object.values(Bokeh.index), seen = new Set();
  while (stack.length) {
    const v = stack.pop();
    if (!v || seen.has(v)) continue;
    seen.add(v);
    if (v.model && v.model.title && typeof v.model.title.text === "string") out.push(v.model.title.text);
    if (typeof v.children === "function") for (const c of v.children()) stack.push(c);
  }
  return out;
}
"""
#: whether the plot titles include all of the given ones
SHOWS_JS = f"(expected) => {{ const t = ({TITLES_JS})(); return expected.every(e => t.includes(e)); }}"
#: the data of the curve labelled ``label`` in the plot whose title starts with ``prefix``
CURVE_JS = """
([prefix, label]) => {
  const stack = Object.values(Bokeh.index), seen = new Set();
  while (stack.length) {
    const v = stack.pop();
    if (!v || seen.has(v)) continue;
    seen.add(v);
    const m = v.model;
    if (m && m.title && typeof m.title.text === "string" && m.title.text.startsWith(prefix)) {
      for (const legend of [...(m.center ?? []), ...(m.right ?? [])]) {  // legends beside the axes too
        for (const item of legend.items ?? []) {
          if ((item.label?.value ?? item.label) === label) {
            const d = item.renderers[0].data_source.data;
            return {title: m.title.text, x: Array.from(d.x), y: Array.from(d.y)};
          }
        }
      }
    }
    if (typeof v.children === "function") for (const c of v.children()) stack.push(c);
  }
  return null;
}
"""


def load_seconds(request: pytest.FixtureRequest) -> float:
    """Duration of the run: ``FRETWEAR_LOAD_SECONDS``, else 60 s alone and 15 s in a larger run."""
    if os.environ.get("FRETWEAR_LOAD_SECONDS"):
        return float(os.environ["FRETWEAR_LOAD_SECONDS"])
    return 60.0 if len(request.session.items) == 1 else 15.0


def memory_mb(pid: int, field: str = "VmRSS") -> float:
    """``field`` of ``/proc/<pid>/status`` in MB (``VmRSS``: resident now, ``VmHWM``: its peak)."""
    for line in Path(f"/proc/{pid}/status").read_text().splitlines():
        if line.startswith(field + ":"):
            return int(line.split()[1]) / 1024
    raise KeyError(field)


class Sampler(threading.Thread):
    """Samples the server's ``VmRSS`` every ``period`` seconds until ``done`` is set."""

    def __init__(self, pid: int, period: float = 0.5) -> None:
        super().__init__(daemon=True)
        self.pid, self.period, self.samples = pid, period, []
        self.done = threading.Event()

    def run(self) -> None:
        while not self.done.wait(self.period):
            self.samples.append(memory_mb(self.pid))


def titles_for(fex: float, mu: float) -> list[str]:
    """The plot titles of the Regimes scene for ``F_ex`` and ``mu`` (see ``app.scenes.RegimesScene``)."""
    r = fex / (mu * NORMAL_LOAD)
    return [f"FRF of mass 1, Fₑₓ = {fex:g} N", f"Stick/slip regimes (current r = {r:.3g})"]


class Driver:
    """One browser session: drags its sliders in a random walk of its own and checks each redraw."""

    def __init__(self, index: int, page) -> None:
        self.index, self.page = index, page
        self.rng = np.random.default_rng(index)
        self.direction = [1 if index % 2 else -1, 1 if index % 4 < 2 else -1]  # of F_ex and mu
        self.values = (10.0, 1.0)
        self.moves: list[tuple[int, tuple[float, float]]] = []
        self.latencies: list[float] = []
        self.snapshots: list[dict] = []
        self.errors: list[str] = []
        page.on("pageerror", lambda e: self.errors.append(f"uncaught error: {e}"))

    async def read(self) -> tuple[float, float]:
        """``F_ex`` and ``mu`` in the number boxes: exact (set by the server), after a server round trip."""
        boxes = await self.page.locator("input").evaluate_all("els => els.slice(0, 2).map(e => e.value)")
        return float(boxes[0]), float(boxes[1])

    async def handles(self) -> tuple[float, float]:
        """``F_ex`` and ``mu`` on the sliders' handles: at once on release, to two decimals."""
        text = await self.page.locator(".noUi-handle").evaluate_all(
            "els => els.slice(0, 2).map(e => e.getAttribute('aria-valuetext'))"
        )
        return float(text[0]), float(text[1])

    async def move(self) -> None:
        """Drag ``F_ex`` (``mu`` one move in three), wait for both figures and check what they show."""
        from playwright.async_api import TimeoutError as PlaywrightTimeout

        assert await self.read() == self.values, f"session {self.index}: its sliders moved: {self.moves}"
        which = 1 if len(self.moves) % 3 == 2 else 0
        low, high = ((3.0, 25.0), (0.2, 1.8))[which]
        if not low < self.values[which] < high:  # the walk stays where the contact sticks and slips
            self.direction[which] = 1 if self.values[which] <= low else -1
        box = await self.page.locator(".noUi-handle").nth(which).bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        await self.page.mouse.move(x, y)
        await self.page.mouse.down()
        await self.page.mouse.move(x + self.direction[which] * int(self.rng.integers(6, 30)), y, steps=4)
        start = time.monotonic()
        await self.page.mouse.up()
        handles = await self.handles()
        self.moves.append((which, handles))
        try:  # the server's exact values reach the boxes, then the figures drawn for them
            while not np.allclose(values := await self.read(), handles, atol=0.006):
                assert time.monotonic() < start + REDRAW_TIMEOUT, f"the server did not get {handles}"
                await asyncio.sleep(0.1)
            await self.page.wait_for_function(
                SHOWS_JS, arg=titles_for(*values), polling=100, timeout=REDRAW_TIMEOUT * 1e3
            )
        except (AssertionError, PlaywrightTimeout) as exc:
            titles = await self.page.evaluate(TITLES_JS)
            pytest.fail(f"session {self.index}: {exc}; titles {titles}; moves {self.moves}")
        self.latencies.append(time.monotonic() - start)
        self.values = values
        curve = await self.page.evaluate(CURVE_JS, ["FRF of mass 1", "nonlinear, no wear"])
        assert curve["title"] == titles_for(*values)[0]
        self.snapshots.append({"fex": values[0], "mu": values[1], "f": curve["x"], "x1": curve["y"]})

    async def run(self, until: float) -> None:
        """Move until the time ``until`` (``time.monotonic``), and at least twice (on a loaded machine a
        move can take longer than the whole run)."""
        while time.monotonic() < until or len(self.latencies) < 2:
            await self.move()

    async def check_clean(self) -> None:
        """No traceback, internal error or invalid-input message on the page, no uncaught error."""
        for text in ("Traceback", "Internal error", "Invalid input"):
            assert await self.page.get_by_text(text).count() == 0, f"session {self.index}: {text}"
        assert self.errors == []


async def run_sessions(url: str, seconds: float) -> tuple[list[Driver], float]:
    """Open the sessions, drive them for ``seconds``; the drivers and the time to load every page."""
    from playwright.async_api import async_playwright

    async with async_playwright() as p:
        browser = await p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        pages = []
        for _ in range(SESSIONS):
            context = await browser.new_context(viewport={"width": 1280, "height": 900})
            pages.append(await context.new_page())
        start = time.monotonic()
        await asyncio.gather(*(page.goto(url, timeout=REDRAW_TIMEOUT * 1e3) for page in pages))
        await asyncio.gather(
            *(
                page.wait_for_function(SHOWS_JS, arg=titles_for(10.0, 1.0), polling=100, timeout=120_000)
                for page in pages
            )
        )
        loaded = time.monotonic() - start
        drivers = [Driver(i, page) for i, page in enumerate(pages)]
        until = time.monotonic() + seconds
        await asyncio.gather(*(d.run(until) for d in drivers))
        for d in drivers:
            await d.check_clean()
        await browser.close()
    return drivers, loaded


def library_frf(fex: float, mu: float, f_hz: list[float]) -> np.ndarray:
    """First-harmonic amplitude of x1 over ``f_hz`` by the library, for the sidebar's other defaults."""
    model = paper_model(fex=fex, mu=mu, normal_load=NORMAL_LOAD)
    solutions = sweep(model, 2 * np.pi * np.asarray(f_hz), HARMONICS).solutions
    return np.array([s.amplitude[0] for s in solutions])


def test_eight_sessions_moving_sliders(request, tmp_path):
    seconds = load_seconds(request)
    log_path = tmp_path / "panel.log"
    proc, url = start_server(log_path)
    baseline = memory_mb(proc.pid)
    sampler = Sampler(proc.pid)
    sampler.start()
    try:
        drivers, loaded = asyncio.run(run_sessions(url, seconds))
        peak = memory_mb(proc.pid, "VmHWM")
    finally:
        sampler.done.set()
        sampler.join()
        stop_server(proc, log_path)  # and no traceback in its log
    moves = [len(d.latencies) for d in drivers]
    latency = sorted(t for d in drivers for t in d.latencies)
    rss = sampler.samples
    print(
        f"\n{SESSIONS} sessions, {seconds:g} s: pages loaded in {loaded:.1f} s; {sum(moves)} moves "
        f"({min(moves)}-{max(moves)} per session, "
        f"{len({(s['fex'], s['mu']) for d in drivers for s in d.snapshots})} parameter sets); "
        f"redraw latency median {statistics.median(latency):.2f} s, "
        f"p95 {latency[int(0.95 * (len(latency) - 1))]:.2f} s, max {latency[-1]:.2f} s\n"
        f"server RSS: {baseline:.0f} MB warmed up, {rss[len(rss) // 2]:.0f} MB half-way, "
        f"{rss[-1]:.0f} MB at the end, peak {peak:.0f} MB"
    )
    assert min(moves) >= 2  # every session was served
    assert peak - baseline < RSS_GROWTH_MB
    for d in drivers:
        for i in sorted({0, len(d.snapshots) // 2, len(d.snapshots) - 1}):  # first, middle and last move
            snap = d.snapshots[i]
            np.testing.assert_allclose(
                snap["x1"],
                library_frf(snap["fex"], snap["mu"], snap["f"]),
                rtol=1e-9,
                err_msg=f"session {d.index}, F_ex = {snap['fex']}, mu = {snap['mu']}",
            )
