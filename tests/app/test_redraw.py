"""How the page redraws its figures (issue 26): the plots are updated in place, at one pass of Bokeh over
the page's models per redraw, and a run's page updates reach the loop in batches.

The page is built in a Bokeh document without a server (as ``panel serve`` builds it, less the socket);
its session runs inline on small grids. The oracle of the drawn data is the published result itself: the
wear map's ``w / u0`` and the history's curve as :mod:`fretwear.figures` samples it.
"""

from __future__ import annotations

import logging
import sys
import threading
import time
import weakref
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest
from bokeh.document import Document
from bokeh.document.models import DocumentModelManager
from bokeh.models import GlyphRenderer
from panel.io.state import set_curdoc

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the dashboard package lives at the repository root, beside fretwear
    sys.path.insert(0, str(ROOT))

import app.session as session_module  # noqa: E402
from app.backend import Backend, ResultCache  # noqa: E402
from app.page import build_page, document_dispatch  # noqa: E402
from app.session import Runner, Session  # noqa: E402
from app.state import EXACT, Controls, Task  # noqa: E402
from fretwear import figures  # noqa: E402

SMALL = {"n_frequencies": 9, "n_cycles": 12, "harmonics": 3, "fmin": 0.4, "fmax": 1.2}


def change(session: Session, doc: Document, **values) -> None:
    with set_curdoc(doc):
        session.controls.param.update(**values)


@pytest.fixture
def page(monkeypatch):
    """A wear-map page in a Bokeh document, and the model-graph passes Bokeh makes (``passes[0]``)."""
    figures.load_backend("bokeh")
    session = Session(controls=Controls(**SMALL), backend=Backend(workers=2, chunks=3), cache=ResultCache(),
                      start=False)  # fmt: skip
    session.scene = "wearmap"
    session.start()
    doc = Document()
    with set_curdoc(doc):
        build_page(session).server_doc(doc)
    change(session, doc, kw=1.5e-11)  # the first change restyles a text pane, once (a pass of its own)
    passes = [0]
    recompute = DocumentModelManager.recompute

    def counted(self):
        passes[0] += 1
        recompute(self)

    monkeypatch.setattr(DocumentModelManager, "recompute", counted)
    return session, doc, passes


def plots(doc: Document) -> dict[str, object]:
    """The page's Bokeh plots by the start of their title."""
    out = {}
    for model in doc.models:
        if type(model).__name__ == "figure":
            for start in ("Wear map (", "Wear history at", "Pseudo-FRF"):
                if model.title.text.startswith(start):
                    out[start] = model
    return out


def glyphs(plot) -> list[GlyphRenderer]:
    return [r for r in plot.renderers if isinstance(r, GlyphRenderer)]


def glyph(plot, kind: str) -> GlyphRenderer:
    return next(r for r in glyphs(plot) if type(r.glyph).__name__ == kind)


def line(plot, label: str) -> GlyphRenderer:
    """The line of ``plot`` whose legend entry is ``label``."""
    items = [item for legend in plot.legend for item in legend.items]
    return next(item.renderers[0] for item in items if getattr(item.label, "value", item.label) == label)


def test_a_k_w_change_updates_the_plots_in_place_with_the_computed_data(page):
    """The figures' Bokeh models stay (the browser redraws them, it does not make new ones); their data is
    the published map and history."""
    session, doc, passes = page
    before = plots(doc)
    sources = {name: [r.data_source for r in glyphs(plot)] for name, plot in before.items()}
    image = glyph(before["Wear map ("], "Image").data_source
    versions = []
    session.current.param.watch(lambda e: versions.append(e.new), "version")
    passes[0] = 0
    change(session, doc, kw=2.5e-11)
    after = plots(doc)
    assert {n: id(p) for n, p in after.items()} == {n: id(p) for n, p in before.items()}
    assert {n: [r.data_source for r in glyphs(p)] for n, p in after.items()} == sources
    assert "wear coefficient 2.5e-11" in after["Wear map ("].title.text
    scene = session.current
    wm = scene.results["wear_map"]
    # the image is w / u0 over (frequency, N > 0), rows along N: the map as computed
    np.testing.assert_array_equal(image.data["image"][0], wm.wear_fraction[:, 1:, 0].T)
    row = int(np.argmin(np.abs(wm.frequency - session.frequency)))
    assert wm.histories[row].kw == 2.5e-11
    x, y = figures.wear_curve(wm.histories[row], scene.settings.dense_cycles)
    drawn = line(after["Wear history at"], "wear history").data_source.data
    np.testing.assert_allclose(drawn["x"], np.where(x > 0, x, np.nan), rtol=1e-12)  # N = 0 off the log axis
    np.testing.assert_allclose(drawn["y"], y, rtol=1e-12)
    exact = line(after["Wear history at"], EXACT).data_source.data
    reference = figures.wear_curve(scene.results[EXACT], scene.settings.dense_cycles)
    np.testing.assert_allclose(exact["y"], reference[1], rtol=1e-12)
    # one pass of Bokeh over the page's models per redraw of the three figures (it was one per figure)
    assert len(versions) == 1 and passes[0] == 1


def test_a_band_change_keeps_the_plots_and_moves_their_axes(page):
    """The band's change draws the new band on the same plots: the layout is not rebuilt."""
    session, doc, passes = page
    before = plots(doc)
    ranges = {n: (p.x_range, p.y_range) for n, p in before.items()}
    versions = []
    session.current.param.watch(lambda e: versions.append(e.new), "version")
    passes[0] = 0
    change(session, doc, fmin=0.5)
    after = plots(doc)
    assert {n: id(p) for n, p in after.items()} == {n: id(p) for n, p in before.items()}
    assert {n: (p.x_range, p.y_range) for n, p in after.items()} == ranges
    wm = session.current.results["wear_map"]
    assert wm.frequency[0] == pytest.approx(0.5)
    half = (wm.frequency[1] - wm.frequency[0]) / 2  # an image's cells are centred on the grid
    x_range = after["Wear map ("].x_range
    assert (x_range.start, x_range.end) == pytest.approx((0.5 - half, 1.2 + half))
    np.testing.assert_array_equal(glyph(after["Wear map ("], "Image").data_source.data["image"][0],
                                  wm.wear_fraction[:, 1:, 0].T)  # fmt: skip
    # inline, the results so far are published before the exact map, then all: two redraws, a pass each
    assert len(versions) == 2 and passes[0] == 2


def test_a_burst_of_page_updates_runs_in_one_tick_held_in_order():
    """Each update of a run (progress, results) was a callback of its own, and each change it made a
    message to the browser; those that wait for the loop together now run in one, the document held."""
    doc, context, ticks, seen = Document(), object(), [], []

    class Context:  # what document_dispatch reads of a served document
        pass

    context = Context()
    doc._session_context = weakref.ref(context)
    doc.add_next_tick_callback = ticks.append  # the loop, run by hand
    dispatch = document_dispatch(doc)  # no page to wait for outside a server: loaded at once

    def update(name: str) -> None:
        seen.append((name, doc.callbacks.hold_value))
        if name == "fails":
            raise RuntimeError("a bug in one update")

    threads = [threading.Thread(target=dispatch, args=(lambda n=n: update(n),)) for n in ("a", "b")]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    dispatch(lambda: update("fails"))
    dispatch(lambda: update("c"))
    assert len(ticks) == 1 and seen == []
    ticks.pop()()
    assert sorted(seen[:2]) == [("a", "combine"), ("b", "combine")]
    assert seen[2:] == [("fails", "combine"), ("c", "combine")]  # a failure does not lose the others
    assert doc.callbacks.hold_value is None
    dispatch(lambda: update("d"))  # after the batch ran: a new tick
    assert len(ticks) == 1
    ticks.pop()()
    assert seen[-1] == ("d", "combine")


def test_a_failed_page_update_is_logged(caplog):
    class Context:
        pass

    doc, context, ticks = Document(), Context(), []
    doc._session_context = weakref.ref(context)
    doc.add_next_tick_callback = ticks.append
    dispatch = document_dispatch(doc)
    dispatch(lambda: 1 / 0)
    with caplog.at_level(logging.ERROR, logger="app.page"):
        ticks.pop()()
    assert "page update failed" in caplog.text and "ZeroDivisionError" in caplog.text


def task(name: str, weight: float, run) -> Task:
    return Task(name, (name,), run, name, weight)


def published(long_task, dispatch=None, shown=None) -> list[tuple[list[str], bool]]:
    """What a run of a light task then the ``long_task`` publishes, in order: (names, final); ``shown`` is
    set when the results so far are published."""
    out: list[tuple[list[str], bool]] = []

    def publish(results, final):
        out.append((sorted(results), final))
        if shown is not None and not final:
            shown.set()

    with ThreadPoolExecutor(1) as pool:
        runner = Runner(ResultCache(), pool, dispatch)
        runner.run(runner.new_request(), [task("light", 1.0, lambda _job: 1), long_task], publish)
        runner.wait(10)
    return out


def test_the_results_so_far_show_only_when_the_long_task_lasts(monkeypatch):
    """Before a long task the results computed so far were always published: when the task ended at
    once, the page drew every figure twice for nothing."""
    monkeypatch.setattr(session_module, "PARTIAL_DELAY", 0.1)
    shown = threading.Event()

    def slow(_job):  # lasts until the results so far are shown (or fails the test after 10 s)
        assert shown.wait(10)
        return 2

    start = time.perf_counter()
    assert published(task("long", 5.0, slow), shown=shown) == [(["light"], False), (["light", "long"], True)]
    assert time.perf_counter() - start >= 0.1
    quick = published(task("long", 5.0, lambda _job: 2))
    time.sleep(0.3)  # the delay passed: nothing published late
    assert quick == [(["light", "long"], True)]


def test_results_so_far_that_reach_the_page_after_the_task_ended_are_not_shown(monkeypatch):
    """The results so far of a task that has ended by the time the loop shows them are older than the final
    ones dispatched after them: skipped (the final ones follow)."""
    monkeypatch.setattr(session_module, "PARTIAL_DELAY", 0.05)
    queued = []

    def long(_job):
        time.sleep(0.4)  # the delayed publish is queued meanwhile
        return 2

    out = published(task("long", 5.0, long), queued.append)
    assert out == []  # the loop has not run the callbacks yet: the delayed publish is among them
    assert any(getattr(callback, "func", None) is session_module._while for callback in queued)
    for callback in queued:
        callback()
    assert out == [(["light", "long"], True)]
