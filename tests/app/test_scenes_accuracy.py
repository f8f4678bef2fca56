"""Tests of the accuracy scene (app.scenes.accuracy): the cost ladder, its recommendation, the Pareto
figure and table, and the button that applies a rung to the sidebar; without a server."""

import threading
from concurrent.futures import ThreadPoolExecutor

import numpy as np
import param
import pytest
from test_state import calls, new_session, rows_of

from app.backend import Backend
from app.scenes import QUANTITY_LABELS, TARGETS, sidebar_equivalent
from app.state import LADDERS
from fretwear.hbm.harmonics import default_samples
from fretwear.studies import CostStudy, Rung


def dlft(nh: int, seconds: float, error: float, samples: int | None = None) -> Rung:
    errors = dict.fromkeys(("x1_h1", "xr_half_p2p", "sliding_distance"), error)
    return Rung("dlft", {"Nh": nh, "N": samples or default_samples(nh)}, seconds, errors)


#: a ladder with known times and errors: the cheapest rung within 1e-2 has non-default samples
PERIODIC = [
    Rung("shooting", {}, 0.02, dict.fromkeys(("x1_h1", "xr_half_p2p", "sliding_distance"), 0.0), True, True),
    dlft(3, 0.001, 0.3),
    dlft(7, 0.002, 0.05),
    dlft(21, 0.010, 0.004),
    dlft(41, 0.100, 0.002),
    dlft(21, 0.005, 0.004, samples=128),
]
WEAR = [
    Rung("exact-dlft", {"Nh": 3}, 0.003, {"wear": 0.02}),
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
    assert scene.quantity == "worst" and scene.target == 5e-2  # a DLFT rung meets 5 %: Apply has a use
    scene.target = 1e-2
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
    assert "**Apply** sets Nh = 7." in scene.advice()
    scene.target = 1e-3
    assert scene.recommended() is None and scene.applicable() is None  # the reference is no recommendation
    assert "Only the reference reaches 0.001 on worst of all: the exact dynamics" in scene.advice()
    scene.quantity = "wear"
    assert scene.recommended() is None and "tick *wear rungs*" in scene.advice()
    assert scene.version == version + 3 and len(seen) == 1
    overlay = scene.figure("pareto")
    assert [len(layer) for layer in overlay][:4] == [0, 0, 0, 0]  # nothing measures w(N) yet
    assert all(np.isnan(layer.dimension_values("x")).all() for layer in list(overlay)[4:6])  # markers only
    assert list(overlay)[0].kdims[1].label == "relative error: w(N) (largest error over N, / u0)"


def test_pareto_figure_and_csv_show_every_rung(ladder_session):
    session, _ = ladder_session
    scene = session.current
    scene.param.update(quantity="x1_h1", target=5e-2)
    points, front, left, right, current, pick, target = scene.figure("pareto")
    assert len(points) == len(PERIODIC) and len(left) + len(right) == len(PERIODIC)
    texts = [" shooting (reference) ", " Nh=3 ", " Nh=7 ", " Nh=21 ", " Nh=21 N=128 "]
    assert list(left.dimension_values("text")) == texts
    assert list(right.dimension_values("text")) == [" Nh=41 "]  # the slowest, labelled on its left
    assert max(points.dimension_values("x")) * 2 == pytest.approx(points.kdims[0].range[1])  # no empty decade
    assert points.dimension_values("y")[0] == pytest.approx(2e-4)  # zero error: a decade under the rest
    assert list(current.dimension_values("rung")) == ["dlft Nh=3 N=64"]
    assert list(pick.dimension_values("rung")) == ["dlft Nh=7 N=128"]
    assert list(front.dimension_values("x")) == [0.001, 0.002, 0.005, 0.02]  # Pareto front, by time
    assert target.data == 5e-2
    rows = rows_of(scene.export_csv("ladder"))
    assert [r["settings"] for r in rows] == labels(PERIODIC)
    by_name = {r["settings"]: r for r in rows}
    assert (
        by_name["dlft Nh=7 N=128"]["recommended"] == "True" and by_name["dlft Nh=3 N=64"]["current"] == "True"
    )
    assert by_name["shooting"]["sidebar"].startswith("it is the reference, the exact dynamics")
    assert (
        float(by_name["dlft Nh=41 N=1024"]["err_x1_h1"]) == 0.002 and by_name["shooting"]["err_wear"] == "nan"
    )
    assert rows[0]["quantity"] == "x1_h1" and float(rows[0]["target"]) == 0.05
    reference = rows_of(scene.export_csv("reference"))
    assert reference[0]["description"] == "fake reference" and float(reference[1]["value"]) == 1e-3
    # the caption says what is measured and what the ring marks (it lacked the quantity, target and Nh)
    text = scene.caption()("unicode")
    label = scene.settings.label()
    assert f"error on {QUANTITY_LABELS['x1_h1']}, target 0.05, ladder " in text
    assert f"ring: the current settings, Nh = 3, {label}" in text
    assert f"# error on {QUANTITY_LABELS['x1_h1']}, target 0.05" in scene.export_csv("ladder")


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
    assert "**Apply** sets method = stepping, dynamics = dlft, Nh = 7, tolerance = 0.01." in scene.advice()
    scene.target = 1e-3  # stepping on the exact dynamics is the cheapest, and the sidebar sets it
    assert scene.recommended().method == "stepping-shooting" and scene.applicable() is scene.recommended()
    session.apply(sidebar_equivalent(scene.applicable())[0])
    assert (c.method, c.dynamics, c.tol) == ("stepping", "shooting", 0.01) and len(seen) == 2
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
    assert (
        best.error("x1_h1") <= 0.1
        and not best.reference
        and all(
            r.wall_time >= best.wall_time for r in study.rungs if r.error("x1_h1") <= 0.1 and not r.reference
        )
    )
    session.controls.param.update(kw=1e-11, horizon=1e3)
    scene.wear = True  # the wear rungs, on a short horizon
    methods = {r.method for r in scene.study().rungs}
    assert {"exact-dlft", "stepping", "stepping-shooting", "polynomial", "time"} <= methods
    assert scene.study().reference["wear"] in scene.advice()  # the reference is named
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
    assert apply.label == "Apply" and not apply.disabled  # the advice says what it sets
    assert "**Apply** sets Nh = 7." in scene.advice()
    apply.clicks += 1
    assert session.controls.harmonics == 7 and len(seen) == 1
    target.value = 1e-3
    with param.edit_constant(target):
        target.value_throttled = 1e-3
    assert apply.disabled  # only the reference reaches 1e-3
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
    assert [len(layer) for layer in scene.figure("pareto")][:4] == [0, 0, 0, 0]
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
    session.controls.param.update(harmonics=3, dynamics="dlft")  # the exact slow time on DLFT, Nh = 3: a rung
    assert scene.notes == [] and labels([r for r in scene.study().rungs if scene.is_current(r)]) == [
        "dlft Nh=3 N=64",
        "exact-dlft Nh=3",
    ]
