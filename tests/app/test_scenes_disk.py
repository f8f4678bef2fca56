"""The Bladed disk scene: one run of the shrouded disk (6 sectors, Nh = 3), drawn and exported.

The run goes through the scene as the page drives it, in the calling thread:
five tasks keyed by the backend calls they cache. Checked: the numbers are the
library's (the sector sweep for the tuned disk, the full sweep for a mistuned
one, the wear history), a tuned disk wears every contact alike and a mistuned
one does not, bad input is named, nothing computes before the tab is shown.
"""

import numpy as np
import pytest

import fretwear as fw
from app.backend import Backend, ResultCache
from app.scenes.disk import DiskScene, DiskSettings
from app.state import Tasks
from fretwear import figures
from fretwear.disk import draw_mistuning, sweep_sector

SMALL = dict(engine_order=1, frequency=222.0, kw=3e-7, cycles=2e4)


class SmallScene(DiskScene):
    """The scene on a 6-sector disk at Nh = 3 (the tab's 24 sectors at Nh = 5 take seconds)."""

    def settings(self) -> DiskSettings:
        s = super().settings()
        return DiskSettings(**{**s.__dict__, "sectors": 6, "harmonics": 3, "fmin": 210.0, "fmax": 234.0,
                               "n_frequencies": 7})  # fmt: skip


@pytest.fixture(scope="module")
def run():
    figures.load_backend("bokeh")
    scene = SmallScene(tasks=Tasks(Backend(), ResultCache()), **SMALL)
    assert scene.results == {} and scene.version == 0  # nothing computes before the tab is shown
    scene.activate()
    return scene


def test_one_run_of_five_cached_tasks_with_the_librarys_numbers(run):
    scene = run
    assert scene.error == "" and scene.version == 1, scene.error
    tasks = scene.settings().tasks(scene.tasks)
    assert [t.key[0] for t in tasks] == ["disk_model", "disk_frf", "disk_history", "disk_frf", "disk_frf"]
    assert all(t.key in scene.cache for t in tasks)
    r, s = scene.results, scene.settings()
    model = fw.bladed_disk(6, engine_order=1, fex=2.0, mu=0.3)
    omegas = 2 * np.pi * np.linspace(s.fmin, s.fmax, s.n_frequencies)
    ref = sweep_sector(model, omegas, 3)
    assert r["solved_on"] == "one sector"
    assert np.array_equal(r["before"], [x.amplitude[2::3] for x in ref.solutions])
    hist = fw.wear_history(model, 2 * np.pi * 222.0, "stepping", kw=3e-7, cycles=2e4, harmonics=3)
    assert np.array_equal(r["wear"], hist.wear)
    assert np.ptp(r["wear"][-1]) <= 1e-12 * r["wear"][-1].max()  # a tuned disk wears alike
    worn = sweep_sector(model, omegas, 3, wear=hist.at([2e4])["wear"][0][0])
    assert np.array_equal(r["after"], [x.amplitude[2::3] for x in worn.solutions])
    assert "an approximation" in scene.notes[0]


def test_figures_and_exports(run):
    scene = run
    for name in scene.figure_names:
        assert scene.figure(name) is not None
    assert scene.export_figure("disk", "png")[:4] == b"\x89PNG"
    import matplotlib.pyplot as plt

    figures.load_backend("matplotlib")
    for size in figures.SIZES:  # defect: the square drawing's title ran past the figure's right edge
        figure = figures.matplotlib_figure(scene.figure("disk"), figures.ExportOptions(size=size),
                                           lambda _markup: scene.caption())  # fmt: skip
        try:
            assert figures.layout_faults(figure) == [], size
        finally:
            plt.close(figure)
    text = scene.export_csv("wear")
    assert text.startswith("# bladed disk: 6 sectors") and "w5_m" in text


def test_a_mistuned_disk_is_solved_whole_and_wears_unevenly(run):
    scene = run
    scene.level = 0.02
    assert scene.error == "" and scene.results["solved_on"] == "full disk"
    model = fw.bladed_disk(6, engine_order=1, fex=2.0, mistuning=draw_mistuning(6, 0.02, 1, seed=0)[0])
    hist = fw.wear_history(model, 2 * np.pi * 222.0, "stepping", kw=3e-7, cycles=2e4, harmonics=3)
    assert np.array_equal(scene.results["wear"], hist.wear)
    assert np.ptp(hist.wear[-1]) > 0.01 * hist.wear[-1].max()
    scene.level = 0.0


@pytest.mark.parametrize(
    ("change", "message"),
    [(dict(level=0.7), "level must be a number in [0, 0.5]"), (dict(fex=-1.0), "fex must be a number > 0"),
     (dict(engine_order=5), "engine_order must be an integer in [0, 3]")],
)  # fmt: skip
def test_bad_input_is_named(run, change, message):
    scene = run
    scene.param.update(**change)
    assert message in scene.error
    scene.param.update(**{k: SMALL.get(k, DiskScene.param[k].default) for k in change})
    assert scene.error == ""
