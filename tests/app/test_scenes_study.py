"""The Study scene: a study written by ``fretwear study`` browsed without recomputing anything.

Two tiny studies are run once for the module through the library's own study
runner (an in-process Dask client): a grid (mu x frequency, with the FRF
metrics, the wear life and w(N)) and random samples of mu and F_ex whose
normal draws of mu go negative for some samples (invalid points: NaN with a
status). The scene must show exactly the stored numbers, mark every point
without a value, and never call a solver.
"""

import os
from importlib import import_module

import numpy as np
import pytest
import xarray as xr
from test_browser import STUDY_SPEC

from app.backend import Backend, ResultCache
from app.scenes.study import StudyScene
from app.state import Tasks, call_key
from fretwear import figures
from fretwear.studies.compute import STATUS
from fretwear.studies.run import run_study
from fretwear.studies.spec import read_spec
from fretwear.studies.store import open_study
from fretwear.studies.summary import wear_life_summary

GRID = """
[study]
title = "grid"
quantities = ["frf", "wear_life", "wear"]
[model]
name = "paper"
[parameters]
frequency = [0.5, 0.7, 0.9]
mu = [0.5, 1.0]
kw = 1e-11
cycles = 1e6
harmonics = 5
[wear]
ncycles = 12
"""
#: a study of the paper's 2-DOF model as a one-pair interface (a model with contact pairs)
PAIRS = """
[study]
title = "pairs"
quantities = ["frf"]
[model]
name = "paper_interface"
[parameters]
frequency = [0.5, 0.7, 0.9]
mu = [0.5, 1.0]
harmonics = 5
"""
#: the wear life of the one-pair interface over random friction coefficients, to worn depths (m)
PAIRS_LIFE = """
[study]
title = "pairs life"
quantities = ["wear_life"]
seed = 4
samples = 6
[model]
name = "paper_interface"
[parameters]
frequency = 0.7
mu = { distribution = "uniform", low = 0.6, high = 1.0 }
kw = 1e-11
cycles = 2e4
harmonics = 5
[wear]
depths = [1e-7, 3e-7]
"""
#: a mistuning study of a 6-sector disk (linear: the amplitude magnification of seeded patterns)
MISTUNING = """
[study]
title = "mistuning"
quantities = ["magnification"]
seed = 3
samples = 8
[model]
name = "bladed_disk"
sectors = 6
engine_order = 1
[parameters]
level = [0.0, 0.03]
band = [165.0, 200.0]
"""
#: the browser tests' study (16 draws; the normal mu goes negative for some), under its own title
RANDOM = STUDY_SPEC.replace('title = "browser study"', 'title = "random"')


@pytest.fixture(scope="module")
def stores(tmp_path_factory):
    from distributed import Client

    root = tmp_path_factory.mktemp("studies")
    out = {}
    with Client(
        processes=False, n_workers=1, threads_per_worker=1, dashboard_address="127.0.0.1:0"
    ) as client:
        for name, text in (("grid", GRID), ("random", RANDOM), ("pairs", PAIRS), ("pairs_life", PAIRS_LIFE),
                           ("mistuning", MISTUNING)):  # fmt: skip
            spec_path = root / f"{name}.toml"
            spec_path.write_text(text)
            out[name] = root / f"{name}.zarr"
            run_study(read_spec(spec_path), out[name], client=client, progress=False)
    return out


@pytest.fixture
def no_solver(monkeypatch):
    """Every solver entry point raises: a scene that recomputes anything fails the test."""

    def refuse(*_args, **_kwargs):
        raise AssertionError("a solver was called")

    entries = [("fretwear.hbm.periodic", "solve_periodic"), ("fretwear.hbm.continuation", "sweep"),
               ("fretwear.wear.history", "wear_history"), ("fretwear.studies.run", "compute_block"),
               ("fretwear.studies.compute", "sweep"), ("fretwear.studies.compute", "wear_history"),
               ("fretwear.studies.compute", "solve_periodic"),
               ("fretwear.studies.run", "run_study")]  # fmt: skip
    for module, name in entries:
        module = import_module(module)  # the module, not a function of the package named like it
        assert hasattr(module, name), f"{module.__name__}.{name}"
        monkeypatch.setattr(module, name, refuse)


def curve_data(overlay, label):
    """``(x, y)`` of the layer of ``overlay`` labelled ``label``."""
    layer = next(e for e in overlay if e.label == label)
    return layer.dimension_values(0), layer.dimension_values(1)


def test_grid_slices_show_the_stored_values_without_a_solver(stores, no_solver):
    figures.load_backend("bokeh")
    ds = xr.open_zarr(stores["grid"])
    scene = StudyScene(stores["grid"])
    assert scene.error == "" and scene.grid_dims == ("mu", "frequency")
    assert set(scene.figure_names) == {"slice", "history", "wear_map"}
    assert scene.axis == "frequency" and scene.quantity == "cycles_to" and scene.fraction == 0.5
    for i_mu in range(2):
        scene.select("mu", i_mu)
        x, y = curve_data(scene.figure("slice"), "cycles_to")
        np.testing.assert_array_equal(x, ds.frequency.values)
        np.testing.assert_array_equal(y, ds.cycles_to.isel(mu=i_mu).sel(fraction=0.5).values)
    # the amplitudes, one curve per DOF, along mu at the third frequency
    scene.param.update(quantity="amplitude", axis="mu")
    scene.select("frequency", 2)
    fig = scene.figure("slice")
    for j, dof in enumerate(ds.dof.values):
        x, y = curve_data(fig, f"amplitude {dof}")
        np.testing.assert_array_equal(x, ds.mu.values)
        np.testing.assert_array_equal(y, ds.amplitude.isel(frequency=2, dof=j).values)
    # w(N) at (mu, f) and its marks at the cycles to 10/50/90 %, as stored
    scene.select("mu", 0)
    n, w = curve_data(scene.figure("history"), "w(N)")
    np.testing.assert_array_equal(w, ds.wear_fraction.isel(mu=0, frequency=2).values)
    np.testing.assert_array_equal(n, ds.cycles.values)
    table = scene.datasets()["history"]
    np.testing.assert_array_equal(table["wear_fraction"], w)
    image = scene.figure("wear_map").get(0)
    stored = ds.wear_fraction.isel(mu=0).transpose("cycles", "frequency").values
    np.testing.assert_array_equal(image.dimension_values(2, flat=False), stored)


def test_a_study_of_a_model_with_contact_pairs_shows_its_per_pair_values(stores, no_solver):
    figures.load_backend("bokeh")
    ds = xr.open_zarr(stores["pairs"])
    scene = StudyScene(stores["pairs"])
    assert scene.error == "" and scene.grid_dims == ("mu", "frequency")
    assert {"amplitude", "slip_distance", "mean_pressure", "friction_energy"} <= set(
        scene.param.quantity.objects
    )
    scene.param.update(quantity="slip_distance", axis="frequency")
    scene.select("mu", 1)
    x, y = curve_data(scene.figure("slice"), "slip_distance pair1")
    np.testing.assert_array_equal(x, ds.frequency.values)
    np.testing.assert_array_equal(y, ds.slip_distance.isel(mu=1, pair=0).values)
    assert y[0] == 0 and np.all(y[1:] > 0)  # the paper's 10 N case: stuck at 0.5 Hz, slipping from 0.7 Hz
    table = scene.datasets()["slice"]
    np.testing.assert_array_equal(table["slip_distance pair1"], y)


def test_the_life_of_a_pair_study_is_to_worn_depths(stores, no_solver):
    figures.load_backend("bokeh")
    ds = xr.open_zarr(stores["pairs_life"])
    scene = StudyScene(stores["pairs_life"])
    assert scene.error == "" and scene.level == "depth" and scene.param.fraction.objects == [1e-7, 3e-7]
    assert "histogram" in scene.figure_names
    scene.fraction = 1e-7
    life, summary = scene._life()
    np.testing.assert_array_equal(life, ds.cycles_to.sel(depth=1e-7).values)
    assert summary == wear_life_summary(ds, depth=1e-7) and np.isfinite(life).all()
    hist = scene.figure("histogram")
    assert hist.get(0).kdims[0].label == "cycles to a worn depth of 1e-07 m"


def test_random_samples_histogram_quantiles_and_invalid_draws(stores, no_solver):
    figures.load_backend("bokeh")
    ds = open_study(stores["random"])
    status = np.array([STATUS[s] for s in ds.status.values])
    assert (ds.mu.values < 0).any() and (status == "invalid").sum() == (ds.mu.values < 0).sum()
    scene = StudyScene(stores["random"])
    assert scene.dims == ("sample",) and set(scene.figure_names) == {"histogram", "scatter"}
    # the histogram counts every finite life once; its marks are the summary's quantiles
    hist = scene.figure("histogram").get(0)
    life = ds.cycles_to.sel(fraction=0.5).values
    assert hist.dimension_values(1).sum() == np.isfinite(life).sum()
    summary = wear_life_summary(ds, 0.5)
    lines = [e.data for e in scene.figure("histogram") if type(e).__name__ == "VLine"]
    marks = [summary[k] for k in ("median", "q05", "q95")]
    np.testing.assert_allclose(lines, np.where(np.isfinite(marks), marks, np.nan))  # inf: no line
    assert f"median {summary['median']:.4g}" in scene.figure("histogram").opts.get().kwargs["title"]
    # invalid draws: red crosses at their drawn mu, counted in the notes, NaN with their status in the CSV
    scene.input = "mu"
    x_failed, _y = curve_data(scene.figure("scatter"), "failed (no value)")
    np.testing.assert_array_equal(np.sort(x_failed), np.sort(ds.mu.values[status == "invalid"]))
    x_ok, y_ok = curve_data(scene.figure("scatter"), "cycles_to")
    assert len(x_ok) == np.isfinite(life).sum()
    n_bad = int((status == "invalid").sum())
    assert any(f"{n_bad} invalid" in note for note in scene.notes), scene.notes
    rows = scene.export_csv("samples").splitlines()
    assert rows[0].startswith("# study: random")
    assert "# quantity: cycles_to = cycles to w = 0.5 u₀ (cycles)" in rows  # which fraction the life is to
    body = [r.split(",") for r in rows if not r.startswith("#")]
    header, body = body[0], body[1:]
    assert len(body) == ds.sizes["sample"]
    for row, s in zip(body, status, strict=True):
        assert row[header.index("status")] == s
        if s == "invalid":
            assert row[header.index("cycles_to")] == "nan"


def test_png_export_of_the_slice(stores, no_solver):
    scene = StudyScene(stores["grid"])
    data = scene.export_figure("slice", "png")
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    with pytest.raises(ValueError, match="no figure 'histogram'"):
        scene.export_figure("histogram", "png")


def test_bad_paths_are_one_message_not_a_crash(tmp_path, stores):
    assert StudyScene(tmp_path / "missing.zarr").error.endswith("no such file or folder")
    (tmp_path / "text.zarr").write_text("not a store")
    assert "not a readable Zarr store" in StudyScene(tmp_path / "text.zarr").error
    xr.Dataset({"a": ("x", np.arange(3.0))}).to_zarr(tmp_path / "other.zarr", zarr_format=2)
    scene = StudyScene(tmp_path / "other.zarr")
    assert "not a fretwear study" in scene.error and scene.figure_names == ()
    assert StudyScene().error == "" and StudyScene().ds is None
    scene = StudyScene(stores["grid"])
    with pytest.raises(ValueError, match=r"index of mu must be in \[0, 1\]"):
        scene.select("mu", 2)


def test_the_store_is_read_once_per_cache_while_unchanged(stores):
    """The store is read by a task on the session's machinery: sessions sharing a cache share the
    dataset, keyed by the call (path and modification time); a changed store is read again."""
    reads = []
    tasks = Tasks(Backend(open_study=lambda path: reads.append(path) or open_study(path)), ResultCache())
    first, second = StudyScene(stores["grid"], tasks=tasks), StudyScene(stores["grid"], tasks=tasks)
    assert len(reads) == 1 and second.ds is first.ds and not second.busy
    path = stores["grid"].resolve()
    # the same task path as every tab: a backend call, keyed by that call
    assert tasks.cache.get(call_key(tasks.backend.study, str(path), path.stat().st_mtime)) is first.ds
    assert tasks.backend.calls["open_study"] == 1
    os.utime(path, (path.stat().st_atime, path.stat().st_mtime + 10))
    assert StudyScene(stores["grid"], tasks=tasks).error == "" and len(reads) == 2


def test_the_tab_has_a_slider_per_axis_and_says_how_to_open_a_study(stores, no_solver):
    import panel as pn

    from app.scenes.study import study_tab

    scene = StudyScene(stores["grid"])
    objects = study_tab(scene, lambda _scene: pn.pane.Markdown("exports"))
    sliders = [w for w in objects[1] if isinstance(w, pn.widgets.DiscreteSlider)]
    assert [w.label for w in sliders] == ["mu", "frequency"]
    assert list(sliders[1].options) == ["0.5", "0.7", "0.9"]
    scene.select("mu", 1)
    assert (
        scene.point == {"mu": 1, "frequency": 0}
        and "mu = 1" in scene.figure("slice").opts.get().kwargs["title"]
    )
    empty = study_tab(StudyScene(), lambda _scene: None)
    assert "--study" in empty[0].object and "fretwear study" in empty[0].object
    bad = study_tab(StudyScene(stores["grid"].parent / "missing.zarr"), lambda _scene: None)
    assert bad[0].object.startswith("Cannot open the study: study ") and "no such file" in bad[0].object


def test_a_mistuning_study_shows_the_magnification_of_its_draws(stores, no_solver):
    """Issue 24: the dashboard opens a mistuning study: the histogram at a level counts its draws' factors,
    its lines are their mean, 95th percentile and Whitehead's bound; nothing is recomputed."""
    from fretwear.disk import draw_mistuning, magnification

    scene = StudyScene(stores["mistuning"], tasks=Tasks(Backend(), ResultCache()))
    assert scene.error == "" and "histogram" in scene.figure_names and scene.quantity == "magnification"
    scene.select("level", 1)
    overlay = scene.figure("histogram")
    hist = overlay.Histogram.I
    assert hist.dimension_values(1).sum() == 8
    ref = magnification(draw_mistuning(6, 0.03, 8, seed=3), (165.0, 200.0), sectors=6, engine_order=1)
    lines = [e.data for e in overlay if type(e).__name__ == "VLine"]
    assert lines == pytest.approx([ref.factor.mean(), np.percentile(ref.factor, 95), ref.whitehead])
    assert f"mean {ref.factor.mean():.4g}" in overlay.opts.get().kwargs["title"]
