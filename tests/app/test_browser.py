"""Browser tests of the dashboard: ``panel serve app/app.py`` driven through Debian's chromium.

Run them alone with ``python -m pytest -m browser``; they need Playwright
(``pip install playwright``, no browser download) and ``/usr/bin/chromium``.
The server runs on 127.0.0.1 on a free port, warmed up by ``--setup
app/warmup.py``. Every test checks that the page made no request outside the
server, that no request failed and that no traceback reached the page; the
server log is checked for tracebacks at the end.

The figures are Bokeh canvases: the tests read the plots' titles and axes
from BokehJS (``Bokeh.index``) to know what is drawn and where to click.
"""

import csv
import io
import os
import socket
import subprocess
import sys
import time
import urllib.request
from pathlib import Path

import pytest

pytestmark = pytest.mark.browser

ROOT = Path(__file__).resolve().parents[2]
CHROMIUM = "/usr/bin/chromium"
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
TIMEOUT = 60_000  # ms
#: server-log tracebacks that are not the app's: Tornado writing to a websocket the browser just closed
BENIGN = ("WebSocketClosedError", "StreamClosedError")

#: the Bokeh plots on the page: title, page position of the canvas, and a data -> page coordinate map
PLOTS_JS = """
([prefix, x, y]) => {
  const out = [];
  const seen = new Set();
  function walk(v) {
    if (!v || seen.has(v)) return;
    seen.add(v);
    if (v.model && v.model.title && typeof v.model.title.text === "string" && v.frame) {
      const r = v.canvas_view.el.getBoundingClientRect();
      const item = {title: v.model.title.text, visible: r.width > 0};
      if (prefix !== null && v.model.title.text.startsWith(prefix)) {
        item.point = [r.left + v.frame.x_scale.compute(x), r.top + v.frame.y_scale.compute(y)];
      }
      out.push(item);
    }
    if (typeof v.children === "function") for (const c of v.children()) walk(c);
  }
  if (window.Bokeh) for (const v of Object.values(Bokeh.index)) walk(v);
  return out;
}
"""


def free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def start_server(log_path: Path) -> tuple[subprocess.Popen, str]:
    """``panel serve app/app.py`` on 127.0.0.1 and a free port, warmed up, logging to ``log_path``.

    Returns the server process and the app's address once it answers.
    """
    if not Path(CHROMIUM).exists():
        pytest.skip(f"browser test: {CHROMIUM} is missing (apt-get install chromium)")
    port = free_port()
    env = {
        **os.environ,
        "PYTHONPATH": os.pathsep.join(filter(None, [str(ROOT), os.environ.get("PYTHONPATH")])),
    }
    command = [
        sys.executable,
        "-m",
        "panel",
        "serve",
        "app/app.py",
        "--address",
        "127.0.0.1",
        "--port",
        str(port),
        "--allow-websocket-origin",
        f"127.0.0.1:{port}",
        "--setup",
        "app/warmup.py",
    ]
    with open(log_path, "w") as log:
        proc = subprocess.Popen(command, cwd=ROOT, env=env, stdout=log, stderr=subprocess.STDOUT)
    url = f"http://127.0.0.1:{port}/app"
    deadline = time.monotonic() + 900  # a fresh install compiles every kernel before the server starts
    while True:
        try:
            with urllib.request.urlopen(url, timeout=5) as response:
                if response.status == 200:
                    return proc, url
        except OSError:
            if proc.poll() is not None or time.monotonic() > deadline:
                proc.kill()
                pytest.fail(f"the server did not start:\n{log_path.read_text()}")
            time.sleep(0.5)


def stop_server(proc: subprocess.Popen, log_path: Path) -> None:
    """Stop the server and check that its log has no traceback (other than ``BENIGN`` ones)."""
    proc.terminate()
    try:
        proc.wait(15)
    except subprocess.TimeoutExpired:
        proc.kill()
    unexpected = [t for t in log_path.read_text().split("Traceback")[1:] if not any(b in t for b in BENIGN)]
    assert unexpected == [], "Traceback".join(["", *unexpected])


@pytest.fixture(scope="module")
def server(tmp_path_factory):
    log_path = tmp_path_factory.mktemp("server") / "panel.log"
    proc, url = start_server(log_path)
    yield url
    stop_server(proc, log_path)


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        chromium = p.chromium.launch(executable_path=CHROMIUM, headless=True, args=CHROMIUM_ARGS)
        yield chromium
        chromium.close()


class Page:
    """A page of the dashboard that records its requests."""

    def __init__(self, browser, url: str) -> None:
        self.url, self.requests, self.failed = url, [], []
        self.context = browser.new_context(viewport={"width": 1500, "height": 1200}, accept_downloads=True)
        self.page = self.context.new_page()
        self.page.set_default_timeout(TIMEOUT)
        self.page.on("request", lambda r: self.requests.append(r.url))
        self.page.on("requestfailed", lambda r: self.failed.append(f"{r.url}: {r.failure}"))
        start = time.perf_counter()
        self.page.goto(url)
        self.wait_title("FRF of mass 1, F_ex = 10 N")
        self.load_time = time.perf_counter() - start

    def plots(self, prefix: str | None = None, x: float = 0.0, y: float = 0.0) -> list[dict]:
        return self.page.evaluate(PLOTS_JS, [prefix, x, y])

    def titles(self) -> list[str]:
        return [p["title"] for p in self.plots() if p["visible"]]

    def wait_title(self, text: str, absent: bool = False) -> float:
        """Wait until a visible plot title contains ``text`` (or none does); seconds waited."""
        start = time.perf_counter()
        self.page.wait_for_function(
            f"""() => {{ const t = ({PLOTS_JS})([null, 0, 0]).filter(p => p.visible).map(p => p.title);
                        return {"!" if absent else ""}t.some(s => s.includes({text!r})); }}""",
            timeout=TIMEOUT,
        )
        return time.perf_counter() - start

    def input_with(self, value: str):
        """The text box showing ``value``."""
        inputs = self.page.locator("input[type=text]")
        index = inputs.evaluate_all(f"els => els.findIndex(e => e.value === {value!r})")
        assert index >= 0, f"no text box shows {value!r}"
        return inputs.nth(index)

    def tab(self, name: str) -> None:
        self.page.locator(".bk-tab", has_text=name).click()

    def check_clean(self) -> None:
        local = ("http://127.0.0.1", "ws://127.0.0.1", "blob:http://127.0.0.1", "data:")
        assert [u for u in self.requests if not u.startswith(local)] == []
        assert self.failed == []
        assert "Traceback" not in self.page.content()


@pytest.fixture
def page(browser, server):
    p = Page(browser, server)
    yield p
    p.check_clean()
    p.context.close()


def test_load_and_slider_redraws_the_plot(page):
    print(f"\nfirst page (to the first plot): {page.load_time:.2f} s")
    assert any(t.startswith("Stick/slip regimes") for t in page.titles())
    handle = page.page.locator(".noUi-handle").first  # the F_ex slider
    box = handle.bounding_box()
    page.page.mouse.move(box["x"] + box["width"] / 2, box["y"] + box["height"] / 2)
    page.page.mouse.down()
    page.page.mouse.move(box["x"] + box["width"] / 2 + 40, box["y"] + box["height"] / 2, steps=5)
    page.page.mouse.up()
    redraw = page.wait_title("FRF of mass 1, F_ex = 10 N", absent=True)
    print(f"slider release to redrawn FRF: {redraw:.2f} s")
    title = next(t for t in page.titles() if t.startswith("FRF of mass 1"))
    assert float(title.split("=")[1].split()[0]) > 10


def test_clicking_the_wear_map_changes_the_cross_sections(page):
    page.tab("Wear map")
    start = time.perf_counter()
    page.wait_title("Wear history at 0.7 Hz")
    print(f"\nwear map scene (warm cache): {time.perf_counter() - start:.2f} s")
    target = next(p for p in page.plots("Wear map", 1.0, 4.5) if p["visible"] and "point" in p)
    page.page.mouse.click(*target["point"])
    page.wait_title("Wear history at 1 Hz")
    page.wait_title("Pseudo-FRF of mass 1 at N = 3.16e+04")


def download(page: Page, button: str) -> tuple[str, bytes]:
    with page.page.expect_download() as info:
        page.page.get_by_role("button", name=button, exact=True).click()
    return info.value.suggested_filename, Path(info.value.path()).read_bytes()


def test_downloads(page):
    page.tab("Wear map")
    page.wait_title("Wear history at")
    name, data = download(page, "CSV")
    assert name == "fretwear_wearmap_wear_map.csv"
    lines = data.decode().splitlines()
    assert lines[0].startswith("f_hz,cycles,w,w_over_u0,x1_h1") and len(lines) == 1 + 41 * 60
    assert float(lines[1].split(",")[0]) == pytest.approx(0.3)
    name, data = download(page, "HTML")
    assert name == "fretwear_wearmap_wear_map.html"
    assert data.startswith(b"<!DOCTYPE html>") and b"<script src=" not in data
    page.tab("Methods")  # the page the export leaves behind still loads nothing from outside
    page.wait_title("Slow-time methods at")


def test_invalid_input_shows_a_message(page):
    box = page.input_with("1e-11")  # the k_w value box
    box.fill("abc")
    box.press("Enter")
    page.page.get_by_text("Invalid input").wait_for()
    box.fill("1e-11")
    box.press("Enter")
    page.page.get_by_text("Invalid input").wait_for(state="hidden")


def test_a_wear_map_computes_within_seconds(page):
    page.tab("Wear map")
    page.wait_title("Wear history at")
    box = page.input_with("1e-11")
    box.fill("3e-11")
    box.press("Enter")
    seconds = page.wait_title("k_w = 3e-11")
    print(f"\nnew wear map (k_w changed): {seconds:.2f} s")
    assert seconds < 30


def test_accuracy_scene_recommends_and_applies(page):
    start = time.perf_counter()
    page.tab("Accuracy vs cost")
    page.page.get_by_text("Cheapest within 0.01").wait_for()
    print(f"\naccuracy scene (quick ladder, no wear): {time.perf_counter() - start:.2f} s")
    assert any(t.startswith("worst of all vs wall time at 0.7 Hz") for t in page.titles())
    quantity = page.page.locator("select", has=page.page.locator("option", has_text="worst of all"))
    quantity.select_option(label="x1 amplitude (first harmonic)")
    handle = page.page.locator(".noUi-handle").last  # the target slider: 1e-2 -> 2e-2 -> 5e-2
    handle.focus()
    handle.press("ArrowLeft")
    handle.press("ArrowLeft")
    page.page.get_by_text("Cheapest within 0.05").wait_for()
    apply = page.page.get_by_role("button", name="Apply: Nh = ")
    nh = apply.inner_text().split("=")[1].strip()
    assert nh != "7"
    apply.click()
    boxes = page.page.locator("input[type=text]")
    deadline = time.monotonic() + 30
    while boxes.evaluate_all(f"els => els.findIndex(e => e.value === {nh!r})") < 0:  # the sidebar's Nh box
        assert time.monotonic() < deadline, f"the sidebar does not show Nh = {nh}"
        time.sleep(0.1)
    page.wait_title("x1 amplitude (first harmonic) vs wall time at 0.7 Hz (target 0.05)")
    name, data = download(page, "CSV")
    assert name == "fretwear_accuracy_ladder.csv"
    rows = list(csv.DictReader(io.StringIO(data.decode())))
    current = [r["settings"] for r in rows if r["current"] == "True"]
    assert current and all(s.startswith(f"dlft Nh={nh} ") for s in current)
    assert [r for r in rows if r["recommended"] == "True"][0]["quantity"] == "x1_h1"
    # the wear rungs: opt-in, with a determinate progress
    page.page.locator("input[type=checkbox]").check()  # the only check box: the wear rungs
    seen = set()
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        text = page.page.get_by_text("Computing cost ladder (quick, with wear)").all_inner_texts()
        if text:
            seen.add(int(text[0].rsplit("(", 1)[1].split()[0]))
        elif seen:
            break
        time.sleep(0.1)
    assert len(seen) >= 3, seen
    quantity.select_option(label="w(N) (largest error over N, / u0)")
    page.wait_title("w(N) (largest error over N, / u0) vs wall time")
    page.page.get_by_text("Cheapest within 0.05 on w(N)").wait_for()
