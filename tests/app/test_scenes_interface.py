"""The Interface scene: one run of the cylinder-on-flat benchmark (16 pairs, Nh = 5), drawn and exported.

The run goes through the scene as the page drives it (settings, progress by
task, the shared-cache protocol), in the calling thread: four tasks keyed by the
backend calls they cache, which call the front functions (``fretwear.reduce``,
``fretwear.wear_history``, ``fretwear.sweep``). The checks compare
what the figures draw with the library's results and with the invariants of
the benchmark: the pressure integral equals the normal load at every record,
the Hertz reference peaks at the benchmark's ``p0`` over its half-width ``a``,
gross slip widens the worn scar.
"""

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from app.backend import Backend, ResultCache
from app.live import typed_box
from app.scenes.interface import FILE, GROSS, MODELS, PROFILES, RTOL, InterfaceScene
from app.state import Tasks
from fretwear import figures
from fretwear.model import OPEN, SLIP, STICK


def layer(overlay, label):
    return next(e for e in overlay if e.label == label)


@pytest.fixture(scope="module")
def run():
    figures.load_backend("bokeh")
    reports = []
    scene = InterfaceScene(tasks=Tasks(Backend(), ResultCache()))
    scene.param.watch(lambda e: reports.append((scene.progress, scene.status)), "progress")
    assert scene.results == {} and scene.version == 0  # nothing computes before the tab is shown
    scene.activate()
    return scene, reports


def test_nothing_computes_until_shown_then_one_run_with_progress(run):
    scene, reports = run
    assert scene.error == "" and not scene.busy and scene.version == 1
    done = [p for p, _s in reports]
    assert done == sorted(done) and done[-1] == 100 and len(done) >= 3
    assert any("wear history" in s for _p, s in reports) and any("FRF" in s for _p, s in reports)
    assert scene.model == GROSS and scene.results["converged"], scene.results["message"]
    # the run is four tasks of the session's machinery, each cached under the backend call it makes
    tasks = scene.settings().tasks(scene.tasks)
    assert [t.key[0] for t in tasks] == [
        "interface_model",
        "interface_history",
        "interface_frf",
        "interface_frf",
    ]
    assert all(t.key in scene.cache for t in tasks)
    assert scene.tasks.backend.calls == {"cylinder_on_flat": 1, "reduce": 1, "wear_history": 1, "sweep": 2}


def test_the_numbers_are_those_of_the_interface_solvers_the_scene_called_before(run):
    """The same reduction, history and FRFs as the scene's former direct calls of ``fretwear.interface``."""
    from fretwear.interface import (
        ContactCondensation,
        InterfaceProblem,
        cylinder_on_flat,
        frf,
        wear_interface,
    )
    from fretwear.model import craig_bampton

    scene, _ = run
    s, r = scene.settings(), scene.results
    model = cylinder_on_flat(contact_nodes=s.contact_nodes, **MODELS[GROSS])
    cond = ContactCondensation(craig_bampton(model, s.harmonics * max(s.frequency, s.fmax)))

    def make(omega):
        return InterfaceProblem(cond, omega, harmonics=s.harmonics)

    h = wear_interface(make(2 * np.pi * s.frequency), s.kw, s.cycles, rtol=RTOL)
    np.testing.assert_array_equal(r["cycles"], h.cycles)
    np.testing.assert_allclose(r["wear"], h.wear, rtol=1e-12, atol=1e-20)
    np.testing.assert_allclose(r["pressure"], h.pressure, rtol=1e-12)
    freqs = np.linspace(s.fmin, s.fmax, s.n_frequencies)
    np.testing.assert_allclose(r["frf_before"], frf(make, freqs, "pad_x")[0], rtol=1e-12)
    np.testing.assert_allclose(r["frf_after"], frf(make, freqs, "pad_x", wear=h.wear[-1])[0], rtol=1e-12)
    assert r["dof_name"] == "pad_x" and r["dof"] == model.dof("pad_x")


def test_a_change_recomputes_only_the_tasks_whose_call_it_changes(run):
    """``K_w`` is an argument of the history (and so of the FRF after wear), not of the reduced model or
    of the FRF before wear: those come from the cache."""
    scene, _ = run
    calls = scene.tasks.backend.calls
    before = dict(calls)
    scene.kw = 2e-14
    assert scene.error == "" and calls["reduce"] == before["reduce"]
    assert calls["wear_history"] == before["wear_history"] + 1 and calls["sweep"] == before["sweep"] + 1
    scene.kw = 1e-14  # back: everything from the cache
    assert dict(calls) == {**before, "wear_history": before["wear_history"] + 1, "sweep": before["sweep"] + 1}


def test_profiles_are_the_histories_and_the_load_is_carried(run):
    scene, _ = run
    r = scene.results
    info = r["info"]
    # the pressure integral of every record is the benchmark's normal load per unit length
    np.testing.assert_allclose(r["normal_force_sum"], info["normal_load"], rtol=1e-6)
    fig = scene.figure("wear_profile")
    records = scene.records()
    assert records[0] == 0 and records[-1] == len(r["cycles"]) - 1 and len(records) == PROFILES
    for k, i in enumerate(records):
        curve = layer(fig, f"record {k + 1}")
        np.testing.assert_array_equal(curve.dimension_values(0), r["position"] * 1e3)
        np.testing.assert_array_equal(curve.dimension_values(1), r["wear"][i] * 1e6)
    assert np.all(r["wear"][0] == 0) and r["wear"][-1].max() > 0
    # gross slip widens the scar: more pairs carry wear at the end than half-way
    worn = (r["wear"] > 1e-3 * r["wear"][-1].max()).sum(axis=1)
    assert worn[-1] >= worn[len(worn) // 2] > 0
    hertz = layer(scene.figure("pressure_profile"), "Hertz (N = 0)")
    x, p = hertz.dimension_values(0), hertz.dimension_values(1)
    assert p.max() == pytest.approx(info["hertz_peak_pressure"] / 1e6, rel=1e-12)
    assert x.max() == pytest.approx(info["hertz_half_width"] * 1e3, rel=1e-12)
    # the first record's pressure is the Hertz one, within the mesh's resolution
    first = layer(scene.figure("pressure_profile"), "record 1").dimension_values(1)
    assert first.max() == pytest.approx(info["hertz_peak_pressure"] / 1e6, rel=0.1)


def test_stick_slip_map_and_frf(run):
    scene, _ = run
    r = scene.results
    mesh = scene.figure("stick_slip").get(0)
    codes = mesh.dimension_values(2, flat=False)
    state = r["state"][-1]
    expected = np.select([state == STICK, state == SLIP, state == OPEN], [0.0, 1.0, 2.0], np.nan)
    np.testing.assert_array_equal(codes, expected)
    assert np.isin(codes[np.isfinite(codes)], (0, 1, 2)).all() and (codes == 1).any()
    frf = scene.figure("frf")
    np.testing.assert_array_equal(layer(frf, "before wear").dimension_values(1), r["frf_before"])
    np.testing.assert_array_equal(layer(frf, "after wear").dimension_values(1), r["frf_after"])
    assert r["frf_ok"].all() and not np.array_equal(r["frf_before"], r["frf_after"])
    rows = scene.export_csv("profiles").splitlines()
    assert rows[0].startswith("# interface model: benchmark, gross slip")
    assert len([x for x in rows if not x.startswith("#")]) == 1 + r["wear"].size
    assert scene.export_figure("stick_slip", "png")[:8] == b"\x89PNG\r\n\x1a\n"
    # three discrete colours named on the colour bar (it was a continuous scale from -0.5 to 2.5)
    hv = figures.holoviews()
    bar = hv.renderer("bokeh").get_plot(scene.figure("stick_slip")).state.right[0]
    assert len(bar.color_mapper.palette) == 3 and list(bar.ticker.ticks) == [0, 1, 2]
    assert bar.major_label_overrides == {0: "stick", 1: "slip", 2: "open"}


def test_bad_input_and_a_bad_model_file_are_messages(run, tmp_path):
    scene, _ = run
    scene.frequency = -1.0
    assert scene.error == "Invalid input: frequency must be a number > 0 and <= 100000 Hz, got -1.0"
    scene.frequency = 50.0
    assert scene.error == "" and scene.version >= 2  # the same settings again: from the cache
    # the boxes: what is typed is named with the valid range (it reverted silently; an empty f put a
    # traceback in the server log), kept and outlined red, and the box follows the scene
    boxes = {name: typed_box(scene, name, name) for name in ("frequency", "harmonics")}
    for name, text, message in (
        ("frequency", "abc", "frequency must be a number > 0 and <= 100000 Hz, got 'abc'"),
        ("frequency", "", "frequency must be a number > 0 and <= 100000 Hz, got ''"),
        ("harmonics", "2.5", "harmonics must be an integer in [1, 15], got '2.5'"),
    ):
        boxes[name].value = text
        assert scene.error == f"Invalid input: {message}" and boxes[name].css_classes == ["stale"]
        assert boxes[name].value == text and scene.frequency == 50.0 and scene.harmonics == 5
        boxes[name].value = {"frequency": "50", "harmonics": "5"}[name]
        assert scene.error == "" and boxes[name].css_classes == []
    scene.frequency = 60.0
    assert boxes["frequency"].value == "60"
    scene.frequency = 50.0
    bad = tmp_path / "bad.toml"
    bad.write_text('title = "x"\n[matrices]\nM = "missing.mtx"\n')
    other = InterfaceScene(bad, tasks=Tasks(Backend(), ResultCache()))
    assert FILE in other.param.model.objects
    other.model = FILE
    other.activate()
    assert other.error.startswith("The interface run failed: ") and "bad.toml" in other.error
    assert other.results == {} and not other.busy
    # the file's failure is kept for these settings; a changed file is another run
    before = other.settings()
    os.utime(bad, (bad.stat().st_atime, bad.stat().st_mtime + 10))
    assert other.settings() != before


def test_the_papers_two_dof_model_is_a_choice_and_wears_like_the_single_contact():
    import fretwear as fw
    from app.scenes.interface import PAPER

    scene = InterfaceScene(tasks=Tasks(Backend(), ResultCache()))
    scene.activate()
    boxes = [typed_box(scene, name, name) for name in ("frequency", "kw", "cycles")]
    scene.model = PAPER  # its own settings: the paper's case at 0.7 Hz
    assert (scene.frequency, scene.kw, scene.cycles) == (0.7, 1e-11, 2e4)
    assert [b.value for b in boxes] == ["0.7", "1e-11", "20000"]  # the boxes follow (they kept 50 Hz)
    r = scene.results
    assert scene.error == "" and r["dof_name"] == "x1" and r["wear"].shape[1] == 1
    # the one pair's wear follows the single-contact exact load path at the same Nh (slow-time error)
    ref = fw.wear_history(fw.paper_model(), 2 * np.pi * 0.7, "exact", harmonics=scene.harmonics, kw=1e-11,
                          cycles=2e4)  # fmt: skip
    inside = ref.at(r["cycles"])["wear"][:, 0] < 0.98 * ref.u0[0]
    assert np.abs(ref.at(r["cycles"])["wear"][inside, 0] - r["wear"][inside, 0]).max() < 0.05 * ref.u0[0]
    # the single pair is drawn as a short segment at its value
    last = layer(scene.figure("wear_profile"), f"record {len(scene.records())}")
    assert len(last) == 2 and np.all(last.dimension_values(1) == r["wear"][-1, 0] * 1e6)
    scene.model = GROSS  # back to the benchmark's settings
    assert (scene.frequency, scene.kw) == (50.0, 1e-14)


WARMED_RUN = """
import gc, json, fretwear.compile as c
from numba.core.dispatcher import Dispatcher
from app.backend import Backend, ResultCache
from app.scenes.interface import InterfaceScene
from app.state import Tasks


def versions():
    return {(d.py_func.__module__, d.py_func.__qualname__, str(s))
            for d in gc.get_objects() if isinstance(d, Dispatcher) for s in d.signatures}


c.warm("interface")
c.warm("cone")
warmed = versions()
scene = InterfaceScene(tasks=Tasks(Backend(), ResultCache()))
scene.activate()
scene.model = "sphere (3-D), partial slip"
assert scene.error == "", scene.error
print(json.dumps(sorted(f"{m}.{q}{s}" for m, q, s in versions() - warmed if m.startswith("fretwear"))))
"""


def test_the_warm_up_loads_every_kernel_version_the_scene_runs():
    """After ``warm("interface")`` and ``warm("cone")`` the scene's runs (the benchmark, the sphere) need no
    other version of any kernel.

    A kernel called with other argument types than the warm-up's (a strided
    column of a history where the warm-up passes a contiguous array) compiled
    a second version, 5 s, in the first run of the tab after a server's
    warm-up. Counted in a new process as the versions each dispatcher holds
    (compiled, or loaded from the Numba cache: the same with an empty cache,
    without compiling every kernel here).
    """
    root = Path(__file__).resolve().parents[2]
    path = os.pathsep.join(filter(None, [str(root), os.environ.get("PYTHONPATH")]))
    env = {**os.environ, "PYTHONPATH": path}
    command = [sys.executable, "-c", WARMED_RUN]
    run = subprocess.run(command, env=env, cwd=root, capture_output=True, text=True)
    assert run.returncode == 0, run.stderr
    assert json.loads(run.stdout.splitlines()[-1]) == []


# -- the sphere: its 3-D patch from above and the fretting loop (issue 25) ----------------------------------


@pytest.fixture(scope="module")
def sphere():
    from app.scenes.interface import SPHERE_PARTIAL

    figures.load_backend("bokeh")
    scene = InterfaceScene(tasks=Tasks(Backend(), ResultCache()))
    scene.activate()
    scene.model = SPHERE_PARTIAL
    assert scene.error == "" and scene.results["converged"], scene.results.get("message")
    return scene


def test_patch_grid_puts_each_pair_in_its_cell_and_mirrors_a_half_model():
    from fretwear.figures.patch import patch_grid

    pts = np.array([[0.0, 0.0], [1.0, 0.0], [0.0, 1.0], [1.0, 1.0], [2.0, 0.0]])
    x, y, z = patch_grid(pts, np.arange(5.0))
    assert list(x) == [0, 1, 2] and list(y) == [-1, 0, 1]
    np.testing.assert_array_equal(z, [[2, 3, np.nan], [0, 1, 4], [2, 3, np.nan]])  # y -> -y, none doubled
    assert np.isnan(patch_grid(pts, np.arange(5.0), mirror=False)[2][1, 2])  # no pair near (2, 1)
    with pytest.raises(ValueError, match="one entry per point"):
        patch_grid(pts, np.arange(4.0))


def test_the_sphere_shows_its_patch_from_above(sphere):
    """Partial slip on the sphere (29 pairs, Nh = 3): pressure, shear, stick/slip/open and worn depth over
    the patch; the stick zone is Mindlin's disk (unworn), the scar an annulus, every traction in the cone."""
    from app.scenes.interface import PATCH_FIGURES, SPHERE_PARTIAL

    r, info = sphere.results, sphere.results["info"]
    assert (sphere.frequency, sphere.harmonics, sphere.cycles) == (150.0, 3, 1e5)
    assert sphere.tasks.backend.calls["sphere_dynamic_model"] == 1 and r["wear"].shape[1] == 29
    np.testing.assert_allclose(r["normal_force_sum"], info["normal_load"] / 2, rtol=1e-6)  # half model
    pts = r["points"] * 1e3
    rad = np.hypot(*r["points"].T)
    hv = figures.holoviews()
    for name, values, unit in (
        ("patch_pressure", r["pressure"][-1] / 1e6, "pressure p, cycle mean (MPa)"),
        ("patch_shear", r["shear"][-1] / 1e6, "shear traction |q|, cycle peak (MPa)"),
        ("patch_wear", r["wear"][-1] * 1e6, "worn depth w (µm)"),
    ):
        fig = sphere.figure(name)
        image = fig.get(0)
        assert image.vdims[0].label == unit and fig.get(0).opts.get("plot").kwargs["colorbar"]
        # each pair's cell holds its value, and its mirror image's too (y -> -y)
        for (x, y), v in zip(pts, values, strict=True):
            assert image[x, y] == pytest.approx(v, rel=1e-12, abs=1e-12)
            assert image[x, -y] == pytest.approx(v, rel=1e-12, abs=1e-12)
        assert [e.label for e in fig][-2:] == ["Hertz radius a", "Mindlin stick radius c"]
        bar = hv.renderer("bokeh").get_plot(fig).state.right[0]
        assert bar.title == unit  # the colour bar names the value and its unit
    # every traction within the Coulomb cone: the peak shear at most mu times the peak pressure
    assert np.all(r["shear"][-1] <= info["mu"] * r["peak_pressure"][-1] * (1 + 1e-9) + 1e-6)
    state = sphere.figure("patch_state")
    codes = np.array([state.get(0)[x, y] for x, y in pts])
    assert set(codes) == {0, 1, 2}  # partial slip: a stick disk, a slip annulus, open outside
    assert [e.label for e in state][1:4] == ["sticks (never slips)", "slips", "open all cycle"]
    bar = hv.renderer("bokeh").get_plot(state).state.right[0]
    assert len(bar.color_mapper.palette) == 3 and list(bar.ticker.ticks) == [0, 1, 2]
    c = r["stick_radius"]
    assert c == pytest.approx(info["hertz_radius"] * 0.4 ** (1 / 3), rel=1e-12)
    assert np.all(rad[codes == 0] < c) and np.all(rad[codes == 1] > c)  # Mindlin's stick disk
    w = r["wear"][-1]
    assert np.all(w[codes == 0] == 0) and np.all(w[codes == 1] > 0)  # the scar: an annulus
    # the profiles are drawn against r, sorted
    x = layer(sphere.figure("wear_profile"), "record 1").dimension_values(0)
    np.testing.assert_allclose(x, np.sort(rad) * 1e3, rtol=1e-12)
    # and the pressure with Hertz's over 0 <= r <= a: the first record's peak is p0
    hertz = layer(sphere.figure("pressure_profile"), "Hertz (N = 0)").dimension_values(0)
    assert hertz.min() == 0 and hertz.max() == pytest.approx(info["hertz_radius"] * 1e3, rel=1e-12)
    first = layer(sphere.figure("pressure_profile"), "record 1").dimension_values(1)
    assert first.max() == pytest.approx(info["hertz_peak_pressure"] / 1e6, rel=0.05)
    # exports: every patch figure, and the patch's table (half model: x, y >= 0)
    for name in PATCH_FIGURES:
        assert sphere.export_figure(name, "png")[:8] == b"\x89PNG\r\n\x1a\n"
    rows = sphere.export_csv("patch").splitlines()
    assert rows[0] == f"# interface model: {SPHERE_PARTIAL}" and rows[3] == "x,y,w,pressure,shear_peak,state"
    assert len(rows) == 4 + 29


def test_the_fretting_loop_encloses_the_energy_the_contact_dissipates(sphere):
    """The loop Q(delta) of the holder: its area is twice the half model's friction energy per cycle (the
    holder's damping takes a few per mille at 1/20 of its mode); Q stays within +-mu P."""
    r = sphere.results
    fig = sphere.figure("loop")
    assert [e.label for e in fig] == ["first record", "last record"]
    history = next(t for t in sphere.settings().tasks(sphere.tasks) if t.key[0] == "interface_history")
    solutions = sphere.cache.get(history.key).solutions
    for k, label in ((0, "first record"), (-1, "last record")):
        curve = layer(fig, label)
        delta, Q = curve.dimension_values(0) * 1e-6, curve.dimension_values(1)
        np.testing.assert_allclose(delta, r["loops"][k][0], rtol=1e-12)
        area = np.sum(0.5 * (Q + np.roll(Q, -1)) * (np.roll(delta, -1) - delta))
        energy = solutions[k].friction_energy
        assert area == pytest.approx(2 * energy, rel=0.03) and area > 0
        assert np.abs(Q).max() < r["info"]["mu"] * r["info"]["normal_load"]  # partial slip
    assert fig.opts.get("plot").kwargs["legend_labels"] == {
        "first record": "N = 0",
        "last record": "N = 1e+05",
    }


def test_gross_slip_on_the_sphere_wears_the_whole_disk(sphere):
    from app.scenes.interface import SPHERE_GROSS, SPHERE_PARTIAL

    sphere.model = SPHERE_GROSS
    try:
        r = sphere.results
        assert sphere.error == "" and r["converged"] and r["stick_radius"] == 0
        rad = np.hypot(*r["points"].T) / r["hertz_radius"]
        codes = np.array([sphere.figure("patch_state").get(0)[x, y] for x, y in r["points"] * 1e3])
        w = r["wear"][-1]
        assert np.all(codes[rad < 1] == 1) and np.all(w[rad < 1] > 0)  # the whole contact slides and wears
        assert rad[np.argmax(w)] == 0  # deepest at the centre
    finally:
        sphere.model = SPHERE_PARTIAL


def test_the_patch_is_the_spheres_only(run):
    scene, _ = run
    with pytest.raises(ValueError, match="3-D patch of the sphere"):
        scene.export_figure("patch_wear", "png")
    title = scene.figure("patch_wear").opts.get("plot").kwargs["title"]
    assert title == "Interface: 3-D patch, worn depth (sphere only)"
    assert "patch" not in scene.datasets() and "loop" in scene.datasets()
    # the cylinder's loop in gross slip: its force plateaus at mu P, per unit length of the 2-D contact
    info, loop = scene.results["info"], scene.figure("loop")
    assert loop.opts.get("plot").kwargs["ylabel"] == "tangential force Q, whole contact (N/m)"
    for label in ("first record", "last record"):
        Q = layer(loop, label).dimension_values(1)
        assert np.abs(Q).max() == pytest.approx(info["mu"] * info["normal_load"], rel=1e-6)


@pytest.mark.parametrize("size", sorted(figures.SIZES))
def test_the_patch_and_loop_exports_have_no_overlaps(sphere, size):
    """Issue 26's standard for the new figures: laid out at each export size, no text over text or axes."""
    import matplotlib.pyplot as plt

    from app.scenes.interface import PATCH_FIGURES

    figures.load_backend("matplotlib")
    faults = {}
    for name in ("loop", *PATCH_FIGURES):
        figure = figures.matplotlib_figure(sphere.figure(name), figures.ExportOptions(size=size),
                                           sphere.caption())  # fmt: skip
        try:
            faults[name] = figures.layout_faults(figure)[:3]
        finally:
            plt.close(figure)
    assert {k: v for k, v in faults.items() if v} == {}


def test_the_patch_figures_are_built_only_while_a_sphere_is_shown(run, sphere):
    """The four plots of the 3-D patch are made (and sent to the browser) only for a sphere model: the
    cylinder's tab draws five figures, not nine."""
    import panel as pn

    from app.scenes.interface import GROSS, PATCH_FIGURES, SPHERE_PARTIAL, interface_tab

    def tab(scene):  # (its figures, the patch's row)
        layout = interface_tab(scene, lambda _scene: pn.Column())
        return layout[3], layout[4]

    grid, row = tab(InterfaceScene(tasks=run[0].tasks))  # its run is in that cache: nothing computes
    assert len(grid.objects) == 5 and row.objects == [] and not row.visible
    shown = InterfaceScene(tasks=sphere.tasks)
    shown.model = SPHERE_PARTIAL
    grid, row = tab(shown)
    assert len(grid.objects) == 5 and len(row.objects) == len(PATCH_FIGURES) and row.visible
    shown.model = GROSS  # the row empties (a run of the 16-pair cylinder)
    assert row.objects == [] and not row.visible
