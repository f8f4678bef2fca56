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
import param
import pytest

ROOT = Path(__file__).resolve().parents[2]
if str(ROOT) not in sys.path:  # the dashboard package lives at the repository root, beside fretwear
    sys.path.insert(0, str(ROOT))

import fretwear  # noqa: E402
from app.backend import Backend, Failure, ResultCache  # noqa: E402
from app.scenes import TARGETS, sidebar_equivalent  # noqa: E402
from app.session import Session  # noqa: E402
from app.state import CUSTOM, LADDERS, PRESETS, Controls  # noqa: E402
from fretwear.hbm.harmonics import default_samples  # noqa: E402
from fretwear.studies import CostStudy, Rung  # noqa: E402

SOLVERS = ("linear_frf", "sweep", "regime_map", "wear_map", "wear_history", "solve_periodic", "cost_ladder")
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


#: (control, invalid value, the message): every numeric control, below, above and outside its range
INVALID = [
    ("fex", -3.0, "F_ex must be a number > 0 and <= 1000 N, got -3.0"),
    ("fex", 2e3, "F_ex must be a number > 0 and <= 1000 N, got 2000.0"),
    ("fex", None, "F_ex must be a number > 0 and <= 1000 N, got None"),  # an emptied box
    ("mu", 0.0, "mu must be a number > 0 and <= 10, got 0.0"),
    ("normal_load", math.inf, "F_N must be a number > 0 and <= 10000 N, got inf"),
    ("kw", 0.0, "k_w must be a number > 0 and <= 0.0001 1/Pa, got 0.0"),
    ("kw", -1e-11, "k_w must be a number > 0 and <= 0.0001 1/Pa, got -1e-11"),
    ("kw", math.nan, "k_w must be a number > 0 and <= 0.0001 1/Pa, got nan"),
    ("horizon", 0.0, "cycle horizon must be a whole number >= 10 and <= 1e+09 cycles, got 0.0"),
    ("horizon", -5e4, "cycle horizon must be a whole number >= 10 and <= 1e+09 cycles, got -50000.0"),
    ("horizon", 1e10, "cycle horizon must be a whole number >= 10 and <= 1e+09 cycles, got 10000000000.0"),
    ("harmonics", 0, "Nh must be a whole number >= 1 and <= 64, got 0"),
    ("harmonics", 65, "Nh must be a whole number >= 1 and <= 64, got 65"),
    ("harmonics", 2.5, "Nh must be a whole number >= 1 and <= 64, got 2.5"),
    ("degree", -1, "polynomial degree must be a whole number >= 0 and <= 12, got -1"),
    ("degree", 13, "polynomial degree must be a whole number >= 0 and <= 12, got 13"),
    ("fmin", 0.0, "f min must be a number > 0 and <= 20 Hz, got 0.0"),
    ("fmax", 25.0, "f max must be a number > 0 and <= 20 Hz, got 25.0"),
    ("fmin", 1.5, "f min must be below f max, got 1.5 >= 1.2 Hz"),
    ("fmax", 0.4, "f min must be below f max, got 0.4 >= 0.4 Hz"),
    ("tol", 0.0, "tolerance must be a number > 0 and <= 0.5 u0, got 0.0"),
    ("tol", 0.7, "tolerance must be a number > 0 and <= 0.5 u0, got 0.7"),
    ("n_frequencies", 2, "frequencies must be a whole number >= 3 and <= 401, got 2"),
    ("n_cycles", 1000, "cycle points must be a whole number >= 4 and <= 400, got 1000"),
]


@pytest.mark.parametrize("name,value,message", INVALID, ids=[f"{n}={v}" for n, v, _ in INVALID])
def test_invalid_input_names_the_parameter_and_its_range(name, value, message):
    backend = Backend(workers=1, chunks=1)
    session = Session(controls=small_controls(**{name: value}), backend=backend, cache=ResultCache())
    assert session.error == "Invalid input: " + message and backend.calls == {}
    for scene in ("wearmap", "accuracy"):
        session.scene = scene
        assert session.error == "Invalid input: " + message and backend.calls == {}


def test_invalid_input_gives_a_message_and_no_computation(session):
    before = calls(session)
    session.controls.fmin = 1.5
    assert session.error == "Invalid input: f min must be below f max, got 1.5 >= 1.2 Hz"
    session.controls.fmin = 0.4
    assert session.error == ""
    session.controls.param.update(kw=0.0, harmonics=70)  # both reported
    assert "k_w must be a number > 0" in session.error and "Nh must be a whole number" in session.error
    session.controls.param.update(kw=1e-11, harmonics=3)
    session.frequency = -1.0
    assert session.error == "Invalid input: selected frequency must be a number > 0 and <= 20 Hz, got -1.0"
    session.frequency = 0.7
    session.cycles = None
    assert session.error == "Invalid input: selected N must be a number >= 0 and <= 1e12 cycles, got None"
    session.cycles = 1e4
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
        return fretwear.wear_history(model, omega, method, **options)

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
        return fretwear.sweep(model, omegas, harmonics, **kw)

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


def type_into(box, value) -> None:
    """What typing ``value`` and Enter in a number box does in the browser."""
    with param.edit_constant(box):
        box.param.update(value=value, value_throttled=value)


def test_values_typed_into_the_page_are_checked_and_shown(session):
    import panel as pn

    from app.page import BandInput, LogInput, build_page

    page = build_page(session)
    side, main = page.sidebar[0], page.main[0]
    error = next(a for a in main.select(pn.pane.Alert) if a.alert_type == "danger")
    sliders = {w.label: w for w in side.select(pn.widgets.base.CompositeWidget) if hasattr(w, "_value_edit")}
    logs = {w._slider.label.split(":")[0]: w for w in side if isinstance(w, LogInput)}
    band = next(w for w in side if isinstance(w, BandInput))
    f_box = next(w for w in side.select(pn.widgets.FloatInput) if w.label == "f (Hz)")
    before = calls(session)

    def shows(message: str) -> bool:
        return error.visible and error.object == "Invalid input: " + message == session.error

    type_into(sliders["F_ex: excitation on mass 1 (N)"]._value_edit, -3.0)
    assert shows("F_ex must be a number > 0 and <= 1000 N, got -3.0")
    type_into(sliders["F_ex: excitation on mass 1 (N)"]._value_edit, 10.0)
    assert not error.visible
    type_into(sliders["Nh: harmonics"]._value_edit, 65)
    assert shows("Nh must be a whole number >= 1 and <= 64, got 65")
    type_into(sliders["Nh: harmonics"]._value_edit, 3)
    for text, message in [
        ("0", "k_w must be a number > 0 and <= 0.0001 1/Pa, got 0.0"),
        ("-1e-11", "k_w must be a number > 0 and <= 0.0001 1/Pa, got -1e-11"),
        ("1e-11 1/Pa", "k_w must be a number > 0 and <= 0.0001 1/Pa, got nan"),
    ]:
        logs["log10 k_w"]._text.value = text
        assert shows(message), session.error
    logs["log10 k_w"]._text.value = "1e-11"
    logs["log10 cycle horizon"]._text.value = "0"
    assert shows("cycle horizon must be a whole number >= 10 and <= 1e+09 cycles, got 0.0")
    logs["log10 cycle horizon"]._text.value = "1e5"
    band._low.value = 2.0  # above f max: kept as typed, and named in the message
    assert shows("f min must be below f max, got 2 >= 1.2 Hz") and band._low.value == 2.0
    assert band._slider.value == (0.4, 1.2)  # the slider keeps the last valid band
    assert calls(session) == before  # no invalid value reached the library
    band._high.value = 2.5
    assert session.error == "" and band._slider.value == (2.0, 2.5)
    band._low.value, band._high.value = 0.4, 1.2
    f_box.value = None
    assert shows("selected frequency must be a number > 0 and <= 20 Hz, got None")
    f_box.value = 0.7
    assert not error.visible


# -- the accuracy scene -------------------------------------------------------------------------------


def dlft(nh: int, seconds: float, error: float, samples: int | None = None) -> Rung:
    errors = dict.fromkeys(("x1_h1", "xr_half_p2p", "sliding_distance"), error)
    return Rung("dlft", {"Nh": nh, "N": samples or default_samples(nh)}, seconds, errors)


#: a ladder with known times and errors: the cheapest rung within 1e-2 has non-default samples
PERIODIC = [
    Rung("shooting", {}, 0.02, dict.fromkeys(("x1_h1", "xr_half_p2p", "sliding_distance"), 0.0)),
    dlft(3, 0.001, 0.3),
    dlft(7, 0.002, 0.05),
    dlft(21, 0.010, 0.004),
    dlft(41, 0.100, 0.002),
    dlft(21, 0.005, 0.004, samples=128),
]
WEAR = [
    Rung("exact", {"Nh": 3}, 0.003, {"wear": 0.02}),
    Rung("stepping", {"Nh": 7, "tol": 0.01}, 0.010, {"wear": 0.01}),
    Rung("stepping-shooting", {"tol": 0.01}, 0.200, {"wear": 1e-4}),
    Rung("polynomial", {"Nh": 3, "degree": 4}, 0.300, {"wear": 0.05}),
    Rung("time", {"tol": 0.01}, 0.400, {"wear": 5e-4}),
]


def fake_ladder(seen: list):
    """A ``cost_ladder`` returning the rungs above (the wear rungs with ``kw``), recording its calls."""

    def cost_ladder(model, frequency, *, kw=None, cycles=None, progress, **ladder):
        seen.append({"fex": model.force_cos[0], "f": frequency, "kw": kw, "cycles": cycles, **ladder})
        for step in range(1, 5):
            progress(step / 4)
        rungs = PERIODIC + (WEAR if kw is not None else [])
        return CostStudy(frequency, rungs, {"periodic": "fake reference"}, {"x1_h1": 1e-3})

    return cost_ladder


@pytest.fixture
def ladder_session():
    seen: list = []
    session = new_session(Backend(cost_ladder=fake_ladder(seen)))
    session.scene = "accuracy"
    return session, seen


def labels(rungs) -> list[str]:
    return [r.label.strip() for r in rungs]


def test_accuracy_scene_recommends_the_cheapest_rung_within_the_target(ladder_session):
    session, seen = ladder_session
    scene = session.current
    assert len(seen) == 1 and seen[0]["kw"] is None and seen[0]["harmonics"] == LADDERS["quick"]["harmonics"]
    assert seen[0]["f"] == 0.7 and not session.busy and session.error == ""
    assert scene.quantity == "worst" and scene.target == 1e-2
    assert TARGETS[:4] == (1e-1, 5e-2, 2e-2, 1e-2) and TARGETS[-1] == 1e-6 and len(TARGETS) == 16
    assert labels([r for r in scene.study().rungs if scene.is_current(r)]) == ["dlft Nh=3 N=64"]  # Nh = 3
    assert scene.recommended().label == "dlft Nh=21 N=128"  # the cheapest within 1e-2: no sidebar control
    assert scene.applicable().label == "dlft Nh=21 N=512"  # the cheapest the sidebar can set
    advice = scene.advice()
    assert "no sidebar equivalent: N = 128 samples per period has no sidebar control" in advice
    assert "**Apply** sets Nh = 21" in advice
    version = scene.version
    scene.target = 5e-2  # the target and the quantity redraw, never recompute
    assert scene.recommended().label == "dlft Nh=7 N=128" and scene.applicable() is scene.recommended()
    assert scene.advice().endswith("**Apply** sets Nh = 7.")
    scene.target = 1e-3
    assert scene.recommended().label == "shooting " and scene.applicable() is None
    assert "shooting is the reference solver" in scene.advice()
    assert "No setting the sidebar can reproduce reaches 0.001" in scene.advice()
    scene.quantity = "wear"
    assert scene.recommended() is None and "tick *wear rungs*" in scene.advice()
    assert scene.version == version + 3 and len(seen) == 1
    overlay = scene.figure("pareto")
    assert [len(layer) for layer in overlay][:5] == [0, 0, 0, 0, 0]  # nothing measures w(N) yet
    assert list(overlay)[0].kdims[1].label == "relative error: w(N) (largest error over N, / u0)"


def test_pareto_figure_and_csv_show_every_rung(ladder_session):
    session, _ = ladder_session
    scene = session.current
    scene.param.update(quantity="x1_h1", target=5e-2)
    points, front, text, current, pick, target = scene.figure("pareto")
    assert len(points) == len(PERIODIC) and len(text) == len(PERIODIC)
    assert list(text.dimension_values("text")) == [
        " shooting (reference)",
        " Nh=3",
        " Nh=7",
        " Nh=21",
        " Nh=41",
        " Nh=21 N=128",
    ]
    assert points.dimension_values("y")[0] == pytest.approx(2e-4)  # zero error: a decade under the rest
    assert list(current.dimension_values("rung")) == ["dlft Nh=3 N=64"]
    assert list(pick.dimension_values("rung")) == ["dlft Nh=7 N=128"]
    assert list(front.dimension_values("x")) == [0.001, 0.002, 0.005, 0.02]  # Pareto front, by time
    assert target.data == 5e-2
    rows = list(csv.DictReader(io.StringIO(scene.export_csv("ladder"))))
    assert [r["settings"] for r in rows] == labels(PERIODIC)
    by_name = {r["settings"]: r for r in rows}
    assert (
        by_name["dlft Nh=7 N=128"]["recommended"] == "True" and by_name["dlft Nh=3 N=64"]["current"] == "True"
    )
    assert by_name["shooting"]["sidebar"].startswith("shooting is the reference solver")
    assert (
        float(by_name["dlft Nh=41 N=1024"]["err_x1_h1"]) == 0.002 and by_name["shooting"]["err_wear"] == "nan"
    )
    assert rows[0]["quantity"] == "x1_h1" and float(rows[0]["target"]) == 0.05
    reference = list(csv.DictReader(io.StringIO(scene.export_csv("reference"))))
    assert reference[0]["description"] == "fake reference" and float(reference[1]["value"]) == 1e-3


def test_apply_sets_the_sidebar_in_one_click_without_recomputing(ladder_session):
    session, seen = ladder_session
    scene = session.current
    scene.param.update(quantity="x1_h1", target=1e-2)
    rung, version = scene.applicable(), scene.version
    session.apply(sidebar_equivalent(rung)[0])
    assert session.controls.harmonics == 21 and scene.version == version + 1  # one request
    assert scene.is_current(rung) and len(seen) == 1  # the ladder does not depend on Nh
    assert labels([r for r in scene.study().rungs if scene.is_current(r)]) == ["dlft Nh=21 N=512"]
    assert calls(session)["sweep"] == 1  # the other scenes compute only when shown


def test_wear_rungs_are_opt_in_and_depend_on_kw_and_the_horizon(ladder_session):
    session, seen = ladder_session
    scene, c = session.current, session.controls
    c.kw = 3e-11  # no wear rungs: nothing to recompute
    assert len(seen) == 1
    scene.wear = True
    assert len(seen) == 2 and (seen[1]["kw"], seen[1]["cycles"]) == (3e-11, 1e5)
    assert scene.study().rungs[-1].method == "time"
    scene.param.update(quantity="wear", target=1e-2)
    assert scene.recommended().label == "stepping Nh=7 tol=0.01"
    assert scene.advice().endswith("**Apply** sets method = stepping, Nh = 7, tolerance = 0.01.")
    scene.target = 1e-3  # stepping-shooting is cheapest, time integration is what the sidebar can set
    assert scene.recommended().method == "stepping-shooting" and scene.applicable().method == "time"
    session.apply(sidebar_equivalent(scene.applicable())[0])
    assert (c.method, c.tol) == ("time", 0.01) and len(seen) == 2
    c.horizon = 2e4
    assert len(seen) == 3 and seen[2]["cycles"] == 2e4
    scene.ladder = "full"
    assert len(seen) == 4 and "harmonics" not in seen[3]  # the library's ladder
    scene.param.update(ladder="quick", wear=False)
    c.horizon = 1e5
    assert len(seen) == 4  # all cached
    session.frequency = 0.9
    assert len(seen) == 5 and seen[4]["f"] == 0.9


def test_accuracy_progress_is_determinate_and_a_stale_ladder_stops():
    started, release = threading.Event(), threading.Event()
    seen: list = []
    fake = fake_ladder(seen)

    def cost_ladder(model, frequency, **kw):
        if frequency == 0.8:  # the request that will be stale: blocks in its first rung
            started.set()
            release.wait(10)
        return fake(model, frequency, **kw)

    session = new_session(Backend(cost_ladder=cost_ladder))
    progress = []
    session.param.watch(lambda e: progress.append(e.new), "progress")
    session.scene = "accuracy"
    assert progress[-1] == 100 and [p for p in progress if 0 < p < 100] == [25, 50, 75]
    scene = session.current
    with ThreadPoolExecutor(2) as pool:
        session.executor = pool
        session.frequency = 0.8
        assert started.wait(10) and session.busy
        session.frequency = 0.9
        session.wait(10)
        release.set()
    assert scene.study().frequency == 0.9 and not session.busy
    key = scene.tasks.cost(session.controls.settings(), 0.8, "quick", False).key
    assert key not in session.cache  # cancelled at its first progress report: nothing cached


def test_accuracy_scene_with_the_library():
    session = new_session()
    session.scene = "accuracy"
    scene = session.current
    study = scene.study()
    quick = LADDERS["quick"]
    assert calls(session)["cost_ladder"] == 1
    assert len(study.rungs) == 1 + len(quick["harmonics"]) + len(quick["sample_factors"])
    assert "shooting" in study.reference["periodic"] and all(r.converged for r in study.rungs)
    errors = {r.settings["Nh"]: r.error("x1_h1") for r in study.rungs if r.method == "dlft"}
    assert errors[41] < errors[7] < errors[1]
    scene.param.update(quantity="x1_h1", target=1e-1)
    best = scene.recommended()
    assert best.error("x1_h1") <= 0.1 and all(
        r.wall_time >= best.wall_time for r in study.rungs if r.error("x1_h1") <= 0.1
    )
    session.controls.param.update(kw=1e-11, horizon=1e3)
    scene.wear = True  # the wear rungs, on a short horizon
    methods = {r.method for r in scene.study().rungs}
    assert {"exact", "stepping", "stepping-shooting", "polynomial", "time"} <= methods
    assert "exact dynamics" in scene.study().reference["wear"]  # the exact method on the sliding table
    scene.quantity = "wear"
    assert len(list(scene.figure("pareto"))[0]) == len([r for r in scene.study().rungs if "wear" in r.errors])


def test_accuracy_controls_on_the_page(ladder_session):
    import panel as pn

    from app.page import build_page

    session, seen = ladder_session
    page = build_page(session)
    main = page.main[0]
    quantity = next(w for w in main.select(pn.widgets.Select) if w.label == "Error on")
    target = next(w for w in main.select(pn.widgets.DiscreteSlider))
    wear = next(w for w in main.select(pn.widgets.Checkbox) if w.label.startswith("wear rungs"))
    apply = next(w for w in main.select(pn.widgets.Button) if w.label.startswith("Apply"))
    scene = session.current
    quantity.value = "x1_h1"
    with param.edit_constant(target):
        target.value_throttled = 5e-2
    assert (scene.quantity, scene.target) == ("x1_h1", 5e-2)
    assert apply.label == "Apply: Nh = 7" and not apply.disabled
    apply.clicks += 1
    assert session.controls.harmonics == 7 and len(seen) == 1
    target.value = 1e-3
    with param.edit_constant(target):
        target.value_throttled = 1e-3
    assert apply.disabled and apply.label == "Apply"  # only the reference reaches 1e-3
    wear.value = True
    assert len(seen) == 2 and seen[1]["kw"] == 1e-11


def test_a_failing_ladder_is_a_message_and_nothing_to_export():
    def cost_ladder(model, frequency, **_kw):
        raise RuntimeError(f"the shooting reference did not converge at {frequency:g} Hz")

    session = new_session(Backend(cost_ladder=cost_ladder))
    session.scene = "accuracy"
    scene = session.current
    assert scene.notes == ["cost: RuntimeError: the shooting reference did not converge at 0.7 Hz"]
    assert scene.study() is None and scene.advice() == "" and scene.applicable() is None
    assert [len(layer) for layer in scene.figure("pareto")][:5] == [0, 0, 0, 0, 0]
    with pytest.raises(ValueError, match="no rung measures worst of all"):
        scene.export_figure("pareto", "png")
    with pytest.raises(ValueError, match="no dataset 'ladder'"):
        scene.export_csv("ladder")


def test_settings_off_the_ladder_are_said(ladder_session):
    session, _ = ladder_session
    scene = session.current
    session.controls.harmonics = 9
    assert scene.notes == [
        "the current settings (Nh = 9, method exact) are not among the rungs that measure worst of all"
    ]
    scene.wear = True
    scene.quantity = "wear"
    session.controls.harmonics = 3  # the exact load path at Nh = 3 is a wear rung
    assert scene.notes == [] and labels([r for r in scene.study().rungs if scene.is_current(r)]) == [
        "dlft Nh=3 N=64",
        "exact Nh=3",
    ]
