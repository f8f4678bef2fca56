"""Dashboard timings as a user sees them: first page, and F_ex slider release to redrawn FRF.

Runs ``panel serve app/app.py --setup app/warmup.py`` (warmed up: Numba kernels
loaded, the default scenes in the cache) on a free port of 127.0.0.1 and drives
it with Debian's chromium through Playwright (``pip install playwright``; no
browser download):

* first page: a new browser context (empty browser cache) opens the app; the
  time from the request to the first plot drawn (the FRF of the Regimes scene),
  and to both plots of the scene;
* F_ex slider: the slider's handle is dragged and released (a new value each
  time: a new FRF is computed); the time from the release to the redrawn FRF
  (its title shows the new value);
* changes on the wear map: a new k_w typed in its box, a new Nh (on the DLFT
  dynamics, where the map depends on it), another slow-time method clicked, a
  new lower end of the band typed; the time from Enter (or the click) to the
  map drawn for it (its title shows the new value, its axis the new band);
* Study tab (the server opens a study, ``--args --study``: the shipped example
  ``fretwear/data/wear_life.toml`` at 200 samples, run first, or ``--study PATH``):
  the time from the tab's click to its histogram drawn, in new pages (nothing is
  recomputed: the study is read once per server);
* Interface tab: the time from the tab's click to the FRF before/after wear
  drawn, in the first page (a run: reduction, wear history, FRFs of the
  16-pair benchmark at Nh = 5) and in later pages (from the server's cache);
* Accuracy tab: the time from the tab's click to the Pareto plot drawn (its
  default ladder computed by the warm-up in the background);
* animation of one period (Inside one cycle, Play): the frames the browser shows
  per second, counted over 3 s as changes of the cursor line (target >= 20).

Each figure is printed next to its target with the ratio (median / target),
with the machine's load average: on a loaded machine every figure grows.

    python benchmarks/bench_app.py            # 5 first pages, 10 slider moves
    python benchmarks/bench_app.py --quick    # 3 and 5
    python benchmarks/bench_app.py --quick --screenshots assets   # and a screenshot of every scene

With ``--screenshots DIR``, every scene and tab is also opened from its address
(the settings of its screenshot in :data:`SCREENSHOTS`, then a click on its tab
for the Interface and Study tabs) and saved as
``DIR/scene_KEY.png`` once computed: the README's screenshots.
"""

from __future__ import annotations

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
from app.scenes import QUANTITY_LABELS, AccuracyScene  # noqa: E402
from app.serve import TEXT_JS  # noqa: E402
from app.serve import serve as serve_app  # noqa: E402

CHROMIUM = "/usr/bin/chromium"
ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking", "--no-first-run"]
#: targets (s)
FIRST_PAGE, SLIDER = 3.0, 0.3
#: Study tab drawn (a stored study: "instantly"), Interface tab computed (first run) and from the cache
STUDY_TAB, INTERFACE_RUN, INTERFACE_CACHED = 1.0, 20.0, 1.0
#: a change of k_w, Nh, method or band on the wear map, warm (issue 26)
WEAR_MAP_CHANGE = 0.5
#: calls ``visit(view)`` on every plot on screen until it returns a value (a replaced plot's model stays
#: in the document for a while: only the views on screen say what the page shows)
ON_SCREEN_JS = """
(visit) => {
  const stack = window.Bokeh ? Object.values(Bokeh.index) : [], seen = new Set();
  while (stack.length) {
    const v = stack.pop();
    if (!v || seen.has(v)) continue;
    seen.add(v);
    if (v.model && v.model.title && typeof v.model.title.text === "string" && v.frame
        && v.canvas_view.el.getBoundingClientRect().width > 0) {
      const found = visit(v);
      if (found !== undefined) return found;
    }
    if (typeof v.children === "function") for (const c of v.children()) stack.push(c);
  }
}
"""
#: the lower end of the wear map's frequency axis
MAP_START_JS = f"""
() => ({ON_SCREEN_JS})(v => v.model.title.text.startsWith("Wear map (") ? v.model.x_range.start : undefined)
"""
#: the Accuracy tab's first opening (its default ladder computed by the warm-up, after the first page's)
ACCURACY_TAB = 3.0
#: frames per second of the animation of one period (a lower bound)
ANIMATION_FPS = 20.0
#: counts, over ``ms`` milliseconds of the browser's frames, the changes of the animation's cursor line
#: on screen
FPS_JS = """
async (ms) => {
  const line = () => (ON_SCREEN)(v => {  // the cursor of the force plot (the player writes only those)
    for (const r of [...(v.model.center ?? []), ...(v.model.renderers ?? [])])
      if (r.name === "fw-anim-cursor-force") return r.location;
  });
  let changes = 0, last = line();
  const start = performance.now();
  while (performance.now() - start < ms) {
    await new Promise(resolve => requestAnimationFrame(resolve));
    const now = line();
    if (now !== last && !(Number.isNaN(now) && Number.isNaN(last))) changes += 1;  // NaN: no frame yet
    last = now;
  }
  return changes * 1000 / (performance.now() - start);
}
""".replace("ON_SCREEN", ON_SCREEN_JS)
#: the title of the Accuracy tab's plot at the default quantity
PARETO = f"{QUANTITY_LABELS[AccuracyScene.param.quantity.default]} vs wall time"
#: scene -> (address query, tab clicked after loading or None, a plot title the computed scene shows)
#: of the README's screenshots
SCREENSHOTS = {
    "regimes": ("", None, "Stick/slip regimes"),
    "wearmap": ("scene=wearmap&f=0.6&N=3000", None, "Wear history at 0.6 Hz"),
    "evolution": ("scene=evolution&fex=6&f=0.95", None, "Pseudo-FRFs of mass 1"),
    "cycle": ("scene=cycle&fex=8&f=0.75&N=0", None, "Hysteresis loop"),
    "methods": ("scene=methods", None, "Slow-time methods"),
    "accuracy": ("scene=accuracy", None, "vs wall time"),
    "interface": ("", "Interface", "Interface: FRF of pad_x"),
    "study": ("", "Study", "Study: wear life"),
}
#: the visible plot titles of a page, from BokehJS
TITLES_JS = f"""
() => {{ const out = []; ({ON_SCREEN_JS})(v => {{ out.push(v.model.title.text); }}); return out; }}
"""


def shows(prefixes: list[str]) -> str:
    """JS predicate: every prefix starts a visible plot title."""
    every = f"{prefixes!r}.every(p => t.some(s => s.startsWith(p)))"
    return f"() => {{ const t = ({TITLES_JS})(); return {every}; }}"


def serve(log: Path, app_args: tuple[str, ...] = ()) -> tuple[subprocess.Popen, str]:
    try:
        return serve_app(log, app_args, timeout=300)
    except RuntimeError as exc:
        sys.exit(str(exc))


def first_pages(browser, url: str, repeats: int) -> tuple[list[float], list[float]]:
    """Seconds to the first plot and to the whole first scene, for ``repeats`` new browser contexts."""
    first, whole = [], []
    for _ in range(repeats):
        context = browser.new_context(viewport={"width": 1500, "height": 1200})
        page = context.new_page()
        start = time.perf_counter()
        page.goto(url, wait_until="commit")
        page.wait_for_function(shows(["FRF of mass 1"]), polling=20, timeout=120_000)
        first.append(time.perf_counter() - start)
        page.wait_for_function(shows(["FRF of mass 1", "Stick/slip regimes"]), polling=20, timeout=120_000)
        whole.append(time.perf_counter() - start)
        context.close()
    return first, whole


def slider_moves(browser, url: str, moves: int) -> list[float]:
    """Seconds from releasing the F_ex slider to the FRF drawn for its new value, ``moves`` times."""
    context = browser.new_context(viewport={"width": 1500, "height": 1200})
    page = context.new_page()
    page.goto(url)
    page.wait_for_function(shows(["FRF of mass 1", "Stick/slip regimes"]), timeout=120_000)
    handle = page.locator(".noUi-handle").first  # the F_ex slider
    seconds = []
    for k in range(moves):
        title = next(t for t in page.evaluate(TITLES_JS) if t.startswith("FRF of mass 1"))
        box = handle.bounding_box()
        x, y = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2
        page.mouse.move(x, y)
        page.mouse.down()
        page.mouse.move(x + (7 if k % 2 == 0 else -4), y, steps=3)  # a new value at every move
        start = time.perf_counter()
        page.mouse.up()
        page.wait_for_function(
            f"() => {{ const t = ({TITLES_JS})().filter(s => s.startsWith('FRF of mass 1'));"
            f" return t.length && t[0] !== {title!r}; }}",
            polling=10,
            timeout=120_000,
        )
        seconds.append(time.perf_counter() - start)
        page.wait_for_function("() => !document.body.innerText.includes('Computing')", timeout=120_000)
    context.close()
    return seconds


def map_changes(browser, url: str, moves: int) -> dict[str, list[float]]:
    """Seconds from a change on the wear-map scene to the map drawn for it, per kind of change.

    ``moves`` new values of k_w, then of Nh on the DLFT dynamics (on the exact
    dynamics the map does not depend on Nh) and of the band's lower end; each
    other slow-time method once (its first map at these settings).
    """
    context = browser.new_context(viewport={"width": 1500, "height": 1200})
    page = context.new_page()
    page.goto(url + "?scene=wearmap")
    idle = f"() => !({TEXT_JS})().includes('Computing')"

    def timed(act, drawn) -> float:
        page.wait_for_function(idle, polling=200, timeout=300_000)
        start = time.perf_counter()
        act()
        page.wait_for_function(drawn, polling=10, timeout=300_000)
        return time.perf_counter() - start

    def typed(name: str, text: str):
        box = page.locator(f"input[placeholder='{name}']").first
        box.fill(text)
        return lambda: box.press("Enter")

    def click(label: str):
        return lambda: page.get_by_role("button", name=label, exact=True).first.click()

    page.wait_for_function(shows(["Wear map (", "Wear history at"]), timeout=300_000)
    out: dict[str, list[float]] = {"k_w": [], "Nh": [], "method": [], "band": []}
    for k in range(moves):
        kw = f"{1.1 + 0.1 * k:.2g}e-11"
        drawn = shows([f"Wear map (exact, wear coefficient {float(kw):.3g}"])
        out["k_w"].append(timed(typed("kw", kw), drawn))
    timed(click("DLFT (Nₕ)"), shows(["Wear map (exact slow time on DLFT, Nh = 7"]))
    for nh in (9, 5, 11, 3, 13)[:moves]:
        drawn = shows([f"Wear map (exact slow time on DLFT, Nh = {nh},"])
        out["Nh"].append(timed(typed("harmonics", str(nh)), drawn))
    timed(typed("harmonics", "7"), shows(["Wear map (exact slow time on DLFT, Nh = 7,"]))
    timed(click("exact (shooting)"), shows(["Wear map (exact, "]))
    others = (("polynomial", "Wear map (polynomial on DLFT"), ("stepping", "Wear map (stepping on the exact"))
    for method, title in others:
        out["method"].append(timed(click(method), shows([title])))
    timed(click("exact"), shows(["Wear map (exact, "]))
    for k in range(moves):
        fmin = 0.31 + 0.02 * k
        # the map's axis starts half a cell (< 0.02 Hz) below the band's new lower end
        drawn = f"() => {{ const x = ({MAP_START_JS})(); return x > {fmin - 0.02} && x < {fmin}; }}"
        out["band"].append(timed(typed("fmin", f"{fmin:g}"), drawn))
    context.close()
    return out


def make_study(folder: Path) -> Path:
    """The shipped wear-life example at 200 samples, run in this process (a few seconds to a minute)."""
    from distributed import Client

    from fretwear.studies.run import run_study
    from fretwear.studies.spec import read_spec

    out = folder / "wear_life.zarr"
    spec = read_spec(ROOT / "fretwear" / "data" / "wear_life.toml", samples=200)
    with Client(
        processes=False, n_workers=1, threads_per_worker=1, dashboard_address="127.0.0.1:0"
    ) as client:
        run_study(spec, out, client=client, progress=False)
    return out


def tab_times(browser, url: str, tab: str, title: str, repeats: int) -> list[float]:
    """Seconds from a click on ``tab`` to a plot titled ``title...`` drawn, in ``repeats`` new pages."""
    seconds = []
    for _ in range(repeats):
        context = browser.new_context(viewport={"width": 1500, "height": 1200})
        page = context.new_page()
        page.goto(url)
        page.wait_for_function(shows(["FRF of mass 1"]), timeout=120_000)
        start = time.perf_counter()
        page.locator(".bk-tab", has_text=tab).click()
        page.wait_for_function(shows([title]), polling=20, timeout=300_000)
        seconds.append(time.perf_counter() - start)
        context.close()
    return seconds


def animation_fps(browser, url: str, repeats: int) -> list[float]:
    """Frames per second of the cycle scene's animation (3 s of play each), in ``repeats`` new pages."""
    query, _, title = SCREENSHOTS["cycle"]
    rates = []
    for _ in range(repeats):
        context = browser.new_context(viewport={"width": 1500, "height": 1200})
        page = context.new_page()
        page.goto(f"{url}?{query}")
        page.wait_for_function(shows([title]), timeout=120_000)
        page.get_by_role("button", name="Play", exact=True).click()
        # counted once it plays: its frames come a moment after the press (then the browser plays them)
        moved = (f"() => {{ const t = ({TITLES_JS})(); return t.some(s => s.startsWith('t / T =')) "
                 "&& !t.some(s => s.startsWith('t / T = 0.00')); }")  # fmt: skip
        page.wait_for_function(moved, timeout=60_000, polling=50)
        rates.append(page.evaluate(FPS_JS, 3000))
        context.close()
    return rates


def screenshots(browser, url: str, folder: Path) -> list[Path]:
    """Each scene of :data:`SCREENSHOTS` opened from its address (and tab), computed, saved as a PNG."""
    folder.mkdir(parents=True, exist_ok=True)
    written = []
    for key, (query, tab, title) in SCREENSHOTS.items():
        context = browser.new_context(viewport={"width": 1500, "height": 1100})
        page = context.new_page()
        page.goto(url + (f"?{query}" if query else ""))
        if tab is not None:
            page.wait_for_function(shows(["FRF of mass 1"]), timeout=120_000)
            page.locator(".bk-tab", has_text=tab).click()
        page.wait_for_function(
            f"() => ({TITLES_JS})().some(s => s.includes({title!r}))", polling=200, timeout=300_000
        )
        page.wait_for_function(f"() => !({TEXT_JS})().includes('Computing')", polling=200, timeout=300_000)
        # the page draws its figures again once it knows the window's width (legends below narrow ones)
        time.sleep(4.0)
        path = folder / f"scene_{key}.png"
        page.screenshot(path=str(path), full_page=True)
        written.append(path)
        context.close()
    return written


def line(name: str, values: list[float], target: float) -> str:
    median = statistics.median(values)
    return (
        f"{name:<42} median {median:6.2f} s  (min {min(values):.2f}, max {max(values):.2f}, "
        f"n = {len(values)})"
        f"  target <= {target:g} s  ratio {median / target:.2f}"
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true", help="3 first pages and 5 slider moves")
    parser.add_argument("--screenshots", type=Path, metavar="DIR", help="save a screenshot of every scene")
    parser.add_argument("--study", type=Path, metavar="PATH", help="the study the Study tab opens")
    args = parser.parse_args()
    if not Path(CHROMIUM).exists():
        sys.exit(f"{CHROMIUM} is missing (apt-get install chromium)")
    from playwright.sync_api import sync_playwright

    pages, moves = (3, 5) if args.quick else (5, 10)
    with tempfile.TemporaryDirectory() as tmp:
        study = args.study or make_study(Path(tmp))
        start = time.perf_counter()
        proc, url = serve(Path(tmp) / "panel.log", ("--study", str(study)))
        warm = time.perf_counter() - start
        try:
            with sync_playwright() as p:
                browser = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=ARGS)
                first, whole = first_pages(browser, url, pages)
                slider = slider_moves(browser, url, moves)
                changes = map_changes(browser, url, moves)
                study_tab = tab_times(browser, url, "Study", "Study: wear life", pages)
                interface = tab_times(browser, url, "Interface", "Interface: FRF of pad_x", pages)
                accuracy = tab_times(browser, url, "Accuracy vs cost", PARETO, pages)
                fps = animation_fps(browser, url, pages)
                shots = screenshots(browser, url, args.screenshots) if args.screenshots else []
                browser.close()
        finally:
            proc.terminate()
            proc.wait(15)
    load = os.getloadavg()
    print(
        f"fretwear dashboard, {os.cpu_count()} CPUs, load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f} "
        f"(1, 5, 15 min); server start with warm-up {warm:.1f} s"
    )
    print(line("first page: first plot drawn", first, FIRST_PAGE))
    print(line("first page: the whole first scene", whole, FIRST_PAGE))
    print(line("F_ex slider release -> redrawn FRF", slider, SLIDER))
    for kind, what in (
        ("k_w", "k_w typed"),
        ("Nh", "Nh typed (DLFT)"),
        ("method", "method clicked"),
        ("band", "band's f_min typed"),
    ):
        print(line(f"wear map: {what} -> redrawn map", changes[kind], WEAR_MAP_CHANGE))
    print(line(f"Study tab -> histogram ({study.name})", study_tab, STUDY_TAB))
    print(line("Interface tab -> FRF, first run", interface[:1], INTERFACE_RUN))
    print(line("Interface tab -> FRF, from the cache", interface[1:], INTERFACE_CACHED))
    print(line("Accuracy tab -> Pareto plot (warmed ladder)", accuracy, ACCURACY_TAB))
    median = statistics.median(fps)
    print(
        f"{'animation of one period (frames/s)':<42} median {median:6.1f}    (min {min(fps):.1f}, "
        f"max {max(fps):.1f}, n = {len(fps)})  target >= {ANIMATION_FPS:g}  "
        f"ratio {median / ANIMATION_FPS:.2f}"
    )
    for path in shots:
        print(f"wrote {path}")


if __name__ == "__main__":
    main()
