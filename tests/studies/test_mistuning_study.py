"""The bladed disk's mistuning Monte Carlo as a study: the stored points against the library's
:func:`fretwear.disk.magnification` of the same patterns, the spec's checks, the task split and the
number of workers, the summary (the curve against the level) and the example spec.

The runs use in-process Dask clusters (threads, no worker processes to start) on a 6-sector disk
with 3 levels x 5 draws: a few seconds in all.
"""

from __future__ import annotations

import contextlib
import io
from pathlib import Path

import numpy as np
import pytest

import fretwear as fw
from fretwear import cli
from fretwear.cli.shared import EXIT_OK
from fretwear.disk import draw_mistuning, magnification
from fretwear.studies import compute
from fretwear.studies import run as study_run
from fretwear.studies import spec as study_spec
from fretwear.studies.layout import layout
from fretwear.studies.summary import magnification_summary

xr = pytest.importorskip("xarray")
distributed = pytest.importorskip("distributed")

DATA = Path(fw.__file__).parent / "data"
SECTORS, ENGINE_ORDER, SEED, SAMPLES, BAND = 6, 1, 11, 5, (165.0, 200.0)
LEVELS = (0.0, 0.02, 0.1)
SPEC = f"""
[study]
title = "small mistuning study"
quantities = ["magnification"]
seed = {SEED}
samples = {SAMPLES}

[model]
name = "bladed_disk"
sectors = {SECTORS}
engine_order = {ENGINE_ORDER}

[parameters]
level = {list(LEVELS)}
band = {list(BAND)}
"""


def _local(workers: int):
    """An in-process cluster of ``workers`` single-threaded workers: (client, cluster)."""
    cluster = distributed.LocalCluster(n_workers=workers, threads_per_worker=1, processes=False,
                                       dashboard_address=None)  # fmt: skip
    return distributed.Client(cluster, set_as_default=False), cluster


@pytest.fixture(scope="module")
def runs(spec_path, tmp_path_factory):
    """The study by ``fretwear study`` on one worker in one task (its printed lines), and on two
    workers in tasks of two points (a level's draws split between tasks): (one, two, printed)."""
    one, two = (tmp_path_factory.mktemp(n) / "result.zarr" for n in ("one", "two"))
    err = io.StringIO()
    with pytest.MonkeyPatch.context() as mp, contextlib.redirect_stderr(err):
        mp.setattr(study_run, "_start_client", lambda scheduler, workers: _local(workers))  # in-process
        status = cli.main(["study", str(spec_path), "--out", str(one), "--workers", "1",
                           "--points-per-task", str(len(LEVELS) * SAMPLES), "--quiet"])  # fmt: skip
    printed = err.getvalue().splitlines()
    assert status == EXIT_OK, printed
    spec = study_spec.read_spec(spec_path, points_per_task=2)
    client, cluster = _local(2)
    try:
        res = study_run.run_study(spec, two, client=client, progress=False)
    finally:
        client.close()
        cluster.close()
    assert res.complete and res.n_tasks == len(LEVELS) * 3 and res.workers == 2
    return xr.open_zarr(one).load(), xr.open_zarr(two).load(), printed


def _library(level: float, samples: int = SAMPLES):
    return magnification(draw_mistuning(SECTORS, level, samples, seed=SEED), BAND, sectors=SECTORS,
                         engine_order=ENGINE_ORDER)  # fmt: skip


def test_stored_points_equal_the_librarys_magnification_of_the_same_patterns(runs):
    ds = runs[1]
    assert ds["magnification"].dims == ("level", "sample")
    assert ds["delta"].dims == ("level", "sample", "blade")
    assert np.all(ds["status"].values == compute.OK)
    for level in LEVELS:
        lib, point = _library(level), ds.sel(level=level)
        np.testing.assert_allclose(point["magnification"].values, lib.factor, rtol=1e-12, atol=0)
        np.testing.assert_allclose(point["peak_frequency"].values, lib.frequency, rtol=1e-12, atol=0)
        np.testing.assert_array_equal(point["peak_blade"].values, lib.blade)
        np.testing.assert_array_equal(point["delta"].values, draw_mistuning(SECTORS, level, SAMPLES, SEED))
    np.testing.assert_allclose(ds.sel(level=0.0)["magnification"].values, 1.0, rtol=1e-12)  # tuned: 1
    assert ds.attrs["tuned_amplitude"] == pytest.approx(lib.tuned, rel=1e-12)
    assert ds.attrs["tuned_frequency"] == pytest.approx(lib.tuned_frequency, rel=1e-12)
    assert ds.attrs["whitehead"] == (1 + np.sqrt(SECTORS)) / 2 and ds.attrs["band_hz"] == list(BAND)
    assert ds.attrs["engine_order"] == ENGINE_ORDER and ds.attrs["sectors"] == SECTORS


def test_a_two_worker_run_in_small_tasks_equals_a_one_worker_run_in_one_task(runs):
    one, two, _ = runs
    for name in ("magnification", "peak_frequency", "peak_blade", "delta", "status"):
        np.testing.assert_array_equal(one[name].values, two[name].values, err_msg=name)
    assert one["task_seconds"].size == 1 and two["task_seconds"].size == len(LEVELS) * 3


def test_a_pattern_depends_on_its_index_not_on_the_number_of_draws(spec_path):
    """Point (level, i) of a study of 8 draws is point (level, i) of one of 5 (rows of draw_mistuning)."""
    more = study_spec.read_spec(spec_path, samples=8)
    rows = np.array([4, 0, 2])
    got = compute.compute_block(compute.Work.of(more), {"level": np.full(3, 0.02), "sample": rows})
    lib = _library(0.02)
    np.testing.assert_array_equal(got["delta"], draw_mistuning(SECTORS, 0.02, SAMPLES, SEED)[rows])
    np.testing.assert_allclose(got["magnification"], lib.factor[rows], rtol=1e-12, atol=0)


def test_the_summary_is_the_curve_of_the_library_and_the_command_prints_it(runs):
    one, _, printed = runs
    s = magnification_summary(one)
    np.testing.assert_array_equal(s["levels"], LEVELS)
    for j, level in enumerate(LEVELS):
        f = _library(level).factor
        np.testing.assert_allclose([s["mean"][j], s["p95"][j], s["max"][j]],
                                   [f.mean(), np.percentile(f, 95), f.max()], rtol=1e-12)  # fmt: skip
        np.testing.assert_allclose(s["factors"][j], f, rtol=1e-12)
    assert s["whitehead"] == pytest.approx(1.7247448714) and s["band"] == BAND
    assert list(s["n"]) == [SAMPLES] * 3 and list(s["above"]) == [0, 0, 0]
    rows = [r[2:] for r in map(str.split, printed) if len(r) == 8 and r[2][0].isdigit()]  # the curve
    np.testing.assert_allclose([float(r[0]) for r in rows], 100 * np.array(LEVELS), err_msg=str(printed))
    np.testing.assert_allclose([[float(x) for x in r[1:4]] for r in rows],
                               np.column_stack([s["mean"], s["p95"], s["max"]]), atol=5e-4)  # fmt: skip
    assert [int(r[4]) for r in rows] == [SAMPLES] * 3 and [int(r[5]) for r in rows] == [0, 0, 0]
    assert any("Whitehead's bound 1.725" in line for line in printed)
    # a point not computed (status 0) is left out of its level, NaN among the factors
    partial = one.copy(deep=True)
    partial["status"][1, 0] = compute.NOT_COMPUTED
    p = magnification_summary(partial)
    f = _library(0.02).factor[1:]
    assert p["n"][1] == SAMPLES - 1 and np.isnan(p["factors"][1, 0])
    assert p["mean"][1] == pytest.approx(f.mean(), rel=1e-12) and p["max"][1] == pytest.approx(f.max())


BAD = [
    ("level = [0.0, -0.01]\nband = [165.0, 200.0]", None, "parameters.level[1]"),
    ("level = -0.01\nband = [165.0, 200.0]", None, "parameters.level"),
    ('level = { distribution = "uniform", low = 0, high = 0.1 }\nband = [165.0, 200.0]', None,
     "parameters.level"),
    ("level = [0.01]\nband = [200.0, 165.0]", None, "parameters.band"),
    ("level = [0.01]\nband = [165.0]", None, "parameters.band"),
    ("level = [0.01]\nband = [-1.0, 200.0]", None, "parameters.band[0]"),
    ("level = [0.01]", None, "parameters.band"),
    ("band = [165.0, 200.0]", None, "parameters.level"),
    ("level = [0.01]\nband = [165.0, 200.0]\nfrequency = 190.0", None, "parameters.frequency"),
    ("level = [0.01]\nband = [165.0, 200.0]", ("frf", "bladed_disk"), "study.quantities"),
    ("frequency = 0.7", ("magnification", "paper"), "study.quantities"),
    ("frequency = 0.7", ("magnification", "paper_interface"), "study.quantities"),
    ("level = [0.01]\nband = [165.0, 200.0]", ("mu = 0.3", "bladed_disk"), "model.mu"),
    ("level = [0.01]\nband = [165.0, 200.0]", ("sectors = 2", "bladed_disk"), "model.sectors"),
    ("level = [0.01]\nband = [165.0, 200.0]", ("no seed", "bladed_disk"), "study.seed"),
]  # fmt: skip


@pytest.mark.parametrize(
    ("parameters", "change", "key"), BAD, ids=[f"{i}-{k}" for i, (*_, k) in enumerate(BAD)]
)
def test_bad_entries_are_one_line_errors_naming_the_key(refused, parameters, change, key):
    quantity, model, extra, seed = "magnification", "bladed_disk", "", "seed = 1\n"
    if change is not None:
        what, model = change
        if what in ("frf", "magnification"):
            quantity = what
        elif what == "no seed":
            seed = ""
        else:
            extra = what + "\n"
    text = (f'[study]\nquantities = ["{quantity}"]\n{seed}samples = 3\n[model]\nname = "{model}"\n{extra}'
            f"[parameters]\n{parameters}\n")  # fmt: skip
    if model != "bladed_disk":
        text = text.replace("seed = 1\nsamples = 3\n", "")
    line = refused(text, key)
    if quantity == "magnification" and model != "bladed_disk":
        assert "'bladed_disk' only" in line


def test_the_example_spec_is_the_benchmarks_curve():
    spec = study_spec.read_spec(DATA / "mistuning.toml")
    assert spec.quantities == ("magnification",) and spec.dims == ("level", "sample")
    assert spec.shape == (11, 100) and spec.fixed["band"] == [165.0, 200.0] and spec.seed == 2007
    assert spec.grid["level"][0] == 0 and spec.grid["level"][-1] == 0.1
    assert spec.model.info["sectors"] == 24 and spec.model.info["engine_order"] == 3
    assert not spec.model.contacts
    lay = layout(spec)
    assert lay.chunks[0] == 1 and 32 <= lay.n_tasks <= 64  # a task's draws share their level
