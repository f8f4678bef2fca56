"""Tests of the dashboard's state classes, without a server (app.state, app.session, app.scenes).

Sessions run inline (no executor) on small grids with a fresh result cache and
a counting backend (``Backend.calls``), so each test sees exactly which library
functions a change calls again. Export callbacks are checked by their output:
PNG magic bytes, SVG and CSV parsed, HTML self-contained.
"""

import csv
import io
import math
import sys
import threading
import xml.etree.ElementTree as ET
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:  # the dashboard package lives at the repository root, beside fretwear
    sys.path.insert(0, str(ROOT))

from app.backend import Backend, Failure, ResultCache  # noqa: E402
from app.session import Session  # noqa: E402
from app.state import CUSTOM, PRESETS, Controls  # noqa: E402
from fretwear import continuation, studies  # noqa: E402

SOLVERS = ("linear_frf", "sweep", "regime_map", "wear_map", "wear_history", "solve_periodic")
SMALL = {"n_frequencies": 9, "n_cycles": 12, "harmonics": 3, "fmin": 0.4, "fmax": 1.2}


def small_controls(**changes) -> Controls:
    return Controls(**{**SMALL, **changes})


def new_session(backend=None, cache=None, **changes) -> Session:
    backend = backend or Backend(workers=2, chunks=3)
    return Session(
        controls=small_controls(**changes), backend=backend, cache=ResultCache() if cache is None else cache
    )


def calls(session: Session) -> dict[str, int]:
    return {name: session.backend.calls[name] for name in SOLVERS if session.backend.calls[name]}


def is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


@pytest.fixture
def session() -> Session:
    return new_session()


def test_only_the_visible_scene_computes(session):
    assert session.scene == "regimes"
    assert calls(session) == {"linear_frf": 2, "sweep": 1, "regime_map": 3}
    scene = session.current
    assert scene.version == 2 and not session.busy and session.error == ""  # FRFs first, then the map
    assert set(scene.results) == {"linear_stuck", "linear_open", "frf", "regime"}
    reg = scene.results["regime"]
    assert reg["slip_fraction"].shape == (25, 9) and reg["stick_limit"].shape == (9,)
    assert scene.results["frf"]["amplitude"].shape == (33, 2)


def test_parameter_changes_invalidate_only_dependent_results(session):
    c = session.controls
    before = calls(session)
    c.param.update(kw=3e-11, method="polynomial", horizon=2e4, degree=5, tol=1e-3)  # wear parameters
    assert calls(session) == before
    c.harmonics = 5  # FRF and regime map, not the linear FRFs
    assert calls(session) == {"linear_frf": 2, "sweep": 2, "regime_map": 6}
    c.fex = 7.0  # linear and nonlinear FRFs; the regime map is over r = F_ex / (mu F_N)
    assert calls(session) == {"linear_frf": 4, "sweep": 3, "regime_map": 6}
    c.mu = 0.8  # not the linear FRFs
    assert calls(session) == {"linear_frf": 4, "sweep": 4, "regime_map": 9}
    c.param.update(fex=10.0, mu=1.0, harmonics=3)  # back to the first settings: all cached
    assert calls(session) == {"linear_frf": 4, "sweep": 4, "regime_map": 9}
    assert session.current.results["frf"]["f_hz"][0] == pytest.approx(0.4)


def test_wear_results_are_shared_by_scenes_and_sessions(session):
    session.scene = "wearmap"
    assert calls(session) == {"linear_frf": 2, "sweep": 1, "regime_map": 3, "wear_map": 3}
    wm = session.current.results["wear_map"]
    assert wm.wear.shape == (9, 12, 1) and wm.cycles[0] == 0 and wm.cycles[-1] == 1e5
    session.scene = "evolution"  # the same wear map, the cached linear FRFs
    session.scene = "cycle"  # the selected frequency (0.7 Hz) is on the grid: its history comes with the map
    assert calls(session) == {
        "linear_frf": 2,
        "sweep": 1,
        "regime_map": 3,
        "wear_map": 3,
        "solve_periodic": 1,
    }
    sol = session.current.results["point"]
    assert sol.converged and sol.wear[0] > 0
    other = Session(controls=small_controls(), backend=session.backend, cache=session.cache)
    for key in ("wearmap", "evolution", "cycle", "regimes"):
        other.scene = key
    assert calls(other) == calls(session)  # a second session computes nothing
    session.controls.param.update(tol=1e-3, degree=6)  # options the exact load path does not use
    assert calls(session)["wear_map"] == 3
    session.controls.kw = 2e-11
    session.scene = "regimes"
    assert calls(session)["sweep"] == 1  # k_w does not touch the FRF without wear
    session.scene = "wearmap"
    assert calls(session)["wear_map"] == 6
    session.controls.method = "stepping"
    assert calls(session)["wear_map"] == 9
    session.controls.degree = 4  # not a stepping option
    assert calls(session)["wear_map"] == 9


def test_selection_snaps_to_the_map_and_redraws_without_solving(session):
    session.scene = "wearmap"
    before, version = calls(session), session.current.version
    session.select(1.02, 3.0)
    assert session.frequency == pytest.approx(1.0) and session.cycles == pytest.approx(1e3)
    assert calls(session) == before and session.current.version == version + 1
    assert "1 Hz" in session.current.figure("history").opts.get().kwargs["title"]
    session.select(0.5, 9.0)  # beyond the horizon: held at the horizon
    assert session.cycles == pytest.approx(1e5)
    table = session.current.datasets()["pseudo_frf"]
    assert np.all(table["selected_cycles"] == 1e5)


def test_invalid_input_gives_a_message_and_no_computation(session):
    before = calls(session)
    session.controls.fmin = 1.5
    assert "f min must be below f max" in session.error
    session.controls.fmin = 0.4
    assert session.error == ""
    session.controls.kw = math.nan
    assert "k_w must be a number > 0" in session.error
    session.controls.kw = 1e-11
    session.controls.harmonics = 2.5
    assert "Nh must be a whole number" in session.error
    session.controls.harmonics = 3
    session.controls.fex = None  # an emptied number box
    assert "F_ex must be a number" in session.error
    session.controls.fex = 10.0
    session.frequency = -1.0
    assert "selected frequency" in session.error
    session.frequency = 0.7
    assert session.error == "" and calls(session) == before


def test_presets_set_the_controls_at_once(session):
    c = session.controls
    c.apply_preset("Paper: F_ex = 14 N")
    assert c.preset == "Paper: F_ex = 14 N" and c.fex == 14.0
    assert calls(session)["sweep"] == 2  # one request for the whole preset
    c.fex = 13.0
    assert c.preset == CUSTOM
    for name, values in PRESETS.items():
        c.apply_preset(name)
        assert all(getattr(c, k) == v for k, v in values.items())
        assert c.problems() == []


def test_a_failing_method_is_a_message_not_a_traceback():
    def wear_history(model, omega, method, **options):
        if method == "time":
            raise RuntimeError("time integration is not available")
        return studies.wear_history(model, omega, method, **options)

    session = new_session(Backend(wear_history=wear_history))
    session.scene = "methods"
    scene = session.current
    assert isinstance(scene.results["time"], Failure)
    assert any("time integration is not available" in n for n in scene.notes)
    assert scene.results["stepping"].wear_fraction[-1, 0] > 0
    assert set(scene.datasets()["methods"]["method"]) == {"exact", "stepping", "polynomial"}
    scene.figure("methods")


def test_a_newer_request_supersedes_a_stale_run():
    started, release = threading.Event(), threading.Event()

    def sweep(model, omegas, harmonics, **kw):
        if model.force_cos[0] == 7.0:  # the request that will be stale
            started.set()
            release.wait(10)
        return continuation.sweep(model, omegas, harmonics, **kw)

    session = new_session(Backend(sweep=sweep))
    scene = session.current
    versions = []
    scene.param.watch(lambda e: versions.append(scene.settings.model.fex), "version")
    with ThreadPoolExecutor(2) as pool:
        session.executor = pool
        session.controls.fex = 7.0
        assert started.wait(10) and session.busy
        session.controls.fex = 8.0
        session.wait(10)
        assert scene.settings.model.fex == 8.0 and not session.busy
        release.set()
    assert versions == [8.0]  # the stale run never published
    frf_key = scene.tasks.frf(session.controls.settings()).key
    assert frf_key[1].fex == 8.0 and scene.results["frf"] is session.cache.get(frf_key)


def test_progress_is_determinate():
    session = new_session(Backend(workers=1, chunks=4))
    seen = []
    session.param.watch(lambda e: seen.append(e.new), "progress")
    session.scene = "wearmap"
    assert seen == sorted(seen) and seen[-1] == 100
    assert len([p for p in seen if 0 < p < 100]) >= 3


def test_result_cache_is_bounded_and_computes_once():
    cache = ResultCache(max_entries=2, per_kind={"history": 3})
    for k in "abc":
        cache.put(("map", k), k.upper())
    for k in "abcd":
        cache.put(("history", k), k)
    assert ("map", "a") not in cache and cache.get(("map", "c")) == "C" and len(cache) == 2 + 3
    assert ("history", "a") not in cache and ("history", "b") in cache
    count, gate = [], threading.Event()

    def slow():
        count.append(1)
        gate.wait(5)
        return 42

    with ThreadPoolExecutor(3) as pool:
        futures = [pool.submit(cache.get_or_compute, "x", slow) for _ in range(3)]
        gate.set()
        assert [f.result() for f in futures] == [42, 42, 42]
    assert count == [1]


@pytest.fixture(scope="module")
def computed() -> Session:
    """A session that has visited every scene."""
    s = new_session()
    for key in s.scenes:
        s.scene = key
    return s


def test_every_scene_draws_and_tabulates(computed):
    for scene in computed.scenes.values():
        assert scene.notes == [] or all(isinstance(n, str) for n in scene.notes)
        for name in scene.figure_names:
            assert len(scene.figure(name)) >= 1
        tables = scene.datasets()
        assert set(tables) == set(scene.dataset_names), scene.key
        for name in scene.dataset_names:
            rows = list(csv.reader(io.StringIO(scene.export_csv(name))))
            assert len(rows) > 2 and all(len(r) == len(rows[0]) for r in rows)
            assert sum(is_number(v) for v in rows[1]) >= 2
    header = next(csv.reader(io.StringIO(computed.scenes["wearmap"].export_csv("wear_map"))))
    assert header[:4] == ["f_hz", "cycles", "w", "w_over_u0"]


def test_figure_exports_are_valid_files(computed):
    for scene in computed.scenes.values():
        name = scene.figure_names[0]
        png = scene.export_figure(name, "png")
        assert png[:8] == b"\x89PNG\r\n\x1a\n" and len(png) > 5000
        root = ET.fromstring(scene.export_figure(name, "svg"))
        assert root.tag.endswith("svg")
    html = computed.scenes["wearmap"].export_figure("wear_map", "html").decode()
    assert html.lstrip().lower().startswith("<!doctype html>")
    assert "<script src=" not in html and "Bokeh" in html and "Wear map" in html
    with pytest.raises(ValueError, match="fmt must be one of"):
        computed.current.export_figure("frf", "jpg")


def test_page_widgets_drive_the_session():
    import param

    from app.page import LogInput, build_page

    session = new_session()
    page = build_page(session)
    assert len(page.main) == 1
    log_kw = next(w for w in page.sidebar[0] if isinstance(w, LogInput) and "k_w" in w._slider.label)
    log_kw._text.value = "abc"
    assert "k_w must be a number" in session.error
    log_kw._text.value = "2e-11"
    assert session.controls.kw == 2e-11 and session.error == ""
    with param.edit_constant(log_kw._slider):
        log_kw._slider.value_throttled = -10.0
    assert session.controls.kw == pytest.approx(1e-10)
    assert log_kw._text.value == "1e-10"
