"""Parameter studies on Dask: spec checks, draws, blocks, local and distributed runs, a killed worker, resume.

The clusters listen on 127.0.0.1 only. The study of the runs is small (24 points of the
wear-life example's kind, a K_w grid x 12 draws) and checked against direct library calls
and Archard's scaling: the cycles to a wear fraction are proportional to 1 / K_w.
"""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pytest

import fretwear as fw
from fretwear import cli
from fretwear.cli.shared import EXIT_INTERRUPTED, EXIT_NOT_CONVERGED, EXIT_USAGE
from fretwear.figures import wear_life_figure
from fretwear.studies import compute, store
from fretwear.studies import run as study_run
from fretwear.studies import spec as study_spec
from fretwear.studies.layout import layout
from fretwear.studies.summary import wear_life_summary

xr = pytest.importorskip("xarray")
zarr = pytest.importorskip("zarr")
distributed = pytest.importorskip("distributed")

DATA = Path(fw.__file__).parent / "data"
STUDY_COMMAND = [sys.executable, "-m", "fretwear", "study"]

SPEC = """
[study]
title = "test study"
quantities = ["wear_life"]
seed = 17
samples = 12

[parameters]
frequency = 0.7
mu = { distribution = "normal", mean = 0.5, std = 0.3 }
fex = { distribution = "normal", mean = 10.0, std = 1.0 }
kw = [1e-11, 2e-11]
cycles = 1e7
harmonics = 9
"""


def _data(ds):
    """The results of a study, without the compute times."""
    return ds.drop_vars("task_seconds").load()


@pytest.fixture(scope="module")
def local_run(spec_path, tmp_path_factory):
    """The study on a local cluster of two worker processes: (exit status, Dataset)."""
    out = tmp_path_factory.mktemp("local") / "result.zarr"
    status = cli.main(["study", str(spec_path), "--out", str(out), "--workers", "2", "--quiet"])
    return status, xr.open_zarr(out)


# -- the spec ---------------------------------------------------------------------------

BAD = [
    ("[parameters]\nfrequency = 0.7\n", "study.quantities"),
    ('[study]\nquantities = ["life"]\n[parameters]\nfrequency = 0.7\n', "study.quantities"),
    ('[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nmuu = 1\n', "parameters.muu"),
    ('[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nmu = -0.1\n', "parameters.mu"),
    ('[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nmu = [0.5, -1]\n', "parameters.mu[1]"),
    (
        '[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nharmonics = 2.5\n',
        "parameters.harmonics",
    ),
    (
        '[study]\nquantities = ["frf"]\n[parameters]\nfrequency = { start = 1, stop = 0.5, num = 3 }\n',
        "parameters.frequency.stop",
    ),
    (
        '[study]\nquantities = ["frf"]\nseed = 1\nsamples = 3\n[parameters]\nfrequency = 0.7\n'
        'mu = { distribution = "beta", a = 1 }\n',
        "parameters.mu.distribution",
    ),
    (
        '[study]\nquantities = ["frf"]\nseed = 1\nsamples = 3\n[parameters]\nfrequency = 0.7\n'
        'mu = { distribution = "uniform", low = 1.0, high = 0.4 }\n',
        "parameters.mu.high",
    ),
    (
        '[study]\nquantities = ["frf"]\nsamples = 3\n[parameters]\nfrequency = 0.7\n'
        'mu = { distribution = "uniform", low = 0.4, high = 1.0 }\n',
        "study.seed",
    ),
    (
        '[study]\nquantities = ["frf"]\nseed = 1\nsamples = 3\n[parameters]\nfrequency = 0.7\n'
        'harmonics = { distribution = "uniform", low = 1, high = 9 }\n',
        "parameters.harmonics",
    ),
    ('[study]\nquantities = ["frf"]\n[parameters]\nmu = 0.5\n', "parameters.frequency"),
    ('[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nkw = 1e-11\n', "parameters.kw"),
    (
        '[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\nnormal_load = 10\nu0 = 1e-6\n',
        "parameters.u0",
    ),
    ('[study]\nquantities = ["wear_life"]\n[parameters]\nfrequency = 0.7\n', "parameters.cycles"),
    (
        '[study]\nquantities = ["wear_life"]\n[parameters]\nfrequency = 0.7\ncycles = 1e5\nmethod = "exact"\n'
        "tol = 1e-3\n",
        "parameters.tol",
    ),
    (
        '[study]\nquantities = ["wear_life"]\n[parameters]\nfrequency = 0.7\ncycles = 1e5\n[wear]\n'
        "fractions = [0.5, 1.5]\n",
        "wear.fractions",
    ),
    (
        '[study]\nquantities = ["frf"]\n[model]\nname = "interface_benchmark"\n'
        "[parameters]\nfrequency = 0.7\n",
        "model.name",
    ),
    (
        '[study]\nquantities = ["frf"]\n[model]\nfile = "missing.toml"\n[parameters]\nfrequency = 0.7\n',
        "model.file",
    ),
    (
        '[study]\nquantities = ["frf"]\n[model]\nfile = "paper.toml"\n[parameters]\n'
        "frequency = 0.7\nfex = 5\n",
        "parameters.fex",
    ),
    ('[study\nquantities = ["frf"]\n', "SPEC"),
]


@pytest.mark.parametrize(("text", "key"), BAD, ids=[k for _, k in BAD])
def test_bad_specs_are_one_line_errors_naming_the_key(tmp_path, refused, text, key):
    (tmp_path / "paper.toml").write_text((DATA / "paper_2dof.toml").read_text())
    line = refused(text, key)
    if key == "model.name":  # the named models, those with contact pairs too (tests/studies/test_pairs.py)
        assert "'paper', 'cylinder_on_flat', 'paper_interface'" in line


def test_bad_options_are_one_line_errors(spec_path, tmp_path, capsys):
    frf = tmp_path / "frf.toml"
    frf.write_text('[study]\nquantities = ["frf"]\n[parameters]\nfrequency = 0.7\n')
    for args, key in (
        ([str(frf), "--samples", "5"], "--samples"),
        ([str(spec_path), "--samples", "0"], "--samples"),
        ([str(frf), "--figure", "x.png"], "--figure"),
    ):
        assert cli.main(["study", *args, "--out", str(tmp_path / "x.zarr")]) == EXIT_USAGE
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and key in err[0], err


def test_draws_are_seeded_and_do_not_depend_on_the_sample_count(spec_path):
    a = study_spec.read_spec(spec_path).draws()
    b = study_spec.read_spec(spec_path, samples=40).draws()
    assert set(a) == {"mu", "fex"} and len(b["mu"]) == 40
    for name in a:
        np.testing.assert_array_equal(a[name], b[name][:12])
    assert not np.array_equal(a["mu"], a["fex"] - 9.5)  # independent streams, not one shifted
    example = study_spec.read_spec(DATA / "wear_life.toml")
    draws = example.draws()
    assert (
        example.samples == 1000 and example.fixed["frequency"] == 0.7 and example.quantities == ("wear_life",)
    )
    assert 0.4 <= draws["mu"].min() and draws["mu"].max() <= 1.0
    assert abs(draws["fex"].mean() - 10.0) < 4 / np.sqrt(1000) and abs(draws["fex"].std() - 1.0) < 0.1


def test_blocks_cover_every_point_once_and_fill_the_frequency_axis_first(tmp_path):
    path = tmp_path / "grid.toml"
    path.write_text(
        '[study]\nquantities = ["frf"]\npoints_per_task = 10\n[parameters]\n'
        "frequency = { start = 0.3, stop = 1.3, num = 7 }\nmu = [0.2, 0.5, 1.0]\n"
        "fex = [5.0, 10.0]\n"
    )
    spec = study_spec.read_spec(path)
    assert spec.dims == ("mu", "fex", "frequency")
    lay = layout(spec)
    assert lay.chunks == (1, 1, 7)
    seen = np.zeros(spec.shape, dtype=int)
    for task in range(lay.n_tasks):
        seen[lay.block(task)] += 1
    assert np.all(seen == 1)


def test_frf_block_matches_a_sweep_and_a_model_file_matches_the_paper_model(tmp_path):
    (tmp_path / "paper.toml").write_text((DATA / "paper_2dof.toml").read_text())
    path = tmp_path / "frf.toml"
    path.write_text(
        '[study]\nquantities = ["frf"]\n[model]\nfile = "paper.toml"\n[parameters]\n'
        "frequency = { start = 0.3, stop = 1.3, num = 9 }\nforce_scale = 0.6\nharmonics = 5\n"
    )
    spec = study_spec.read_spec(path)
    freqs = spec.grid["frequency"]
    res = compute.compute_block(compute.Work.of(spec), {"frequency": freqs})
    ref = fw.sweep(fw.paper_model(fex=6.0), 2 * np.pi * freqs, 5).solutions
    assert np.all(res["status"] == compute.OK)
    np.testing.assert_allclose(res["amplitude"], [s.amplitude for s in ref], rtol=1e-8)
    np.testing.assert_allclose(
        res["sliding_distance"], [s.sliding_distance for s in ref], rtol=1e-8, atol=1e-14
    )


def test_wear_block_matches_a_wear_map_and_flags_stuck_and_horizon_points(tmp_path):
    path = tmp_path / "wear.toml"
    path.write_text(
        '[study]\nquantities = ["wear", "wear_life"]\n[parameters]\nfrequency = [0.3, 0.7]\n'
        "cycles = 2e3\nharmonics = 5\n[wear]\nncycles = 7\nfractions = [0.1, 0.9]\n"
    )
    spec = study_spec.read_spec(path)
    res = compute.compute_block(compute.Work.of(spec), {"frequency": spec.grid["frequency"]})
    wm = fw.wear_map(fw.paper_model(), [0.3, 0.7], spec.cycle_grid(), kw=1e-11, harmonics=5)
    np.testing.assert_allclose(res["wear_fraction"], wm.wear_fraction[:, :, 0], rtol=1e-12, atol=1e-15)
    np.testing.assert_allclose(res["wear_amplitude"], wm.amplitude, rtol=1e-12)
    # 0.3 Hz sticks: infinite life; at 0.7 Hz 10 % of u0 wears off within 2000 cycles, 90 % does not
    assert res["status"].tolist() == [compute.STUCK, compute.HORIZON]
    assert np.isinf(res["cycles_to"][0]).all()
    assert 0 < res["cycles_to"][1, 0] < 2e3 and np.isnan(res["cycles_to"][1, 1])


# -- runs ---------------------------------------------------------------------------


def test_local_cluster_matches_direct_calls_and_archard_scaling(local_run, spec_path):
    status, ds = local_run
    spec = study_spec.read_spec(spec_path)
    assert ds.cycles_to.dims == ("sample", "kw", "fraction")
    assert ds.cycles_to.attrs["units"] == "cycles" and ds.mu.attrs["distribution"] == "normal"
    assert ds.attrs["fretwear_version"] == fw.__version__ and ds.attrs["spec"] == SPEC
    assert ds.attrs["study_key"] == spec.key()
    assert np.all(np.isfinite(ds.task_seconds))
    draws = spec.draws()
    np.testing.assert_array_equal(ds.mu, draws["mu"])
    codes = ds.status.values
    invalid = draws["mu"] < 0  # drawn out of range: NaN with its status, the study goes on
    assert invalid.any() and (~invalid).sum() >= 8
    assert np.all(codes[invalid] == compute.INVALID) and np.isnan(ds.cycles_to.values[invalid]).all()
    assert status == EXIT_NOT_CONVERGED
    life = ds.cycles_to.values
    for i in np.flatnonzero(~invalid)[:4]:
        model = fw.paper_model(fex=draws["fex"][i], mu=draws["mu"][i])
        h = fw.wear_history(model, 2 * np.pi * 0.7, "exact", kw=1e-11, cycles=1e7, harmonics=9)
        np.testing.assert_allclose(life[i, 0], [h.cycles_to(f) for f in (0.1, 0.5, 0.9)], rtol=1e-12)
    ok = codes[:, 0] == compute.OK
    assert ok.sum() >= 6
    # Archard: cycles to a wear fraction scale as 1 / K_w (exact load path: no slow-time error)
    np.testing.assert_allclose(life[ok, 1], life[ok, 0] / 2, rtol=1e-9)
    assert np.all(np.diff(life[ok], axis=-1) > 0)  # more wear takes more cycles
    stuck = codes == compute.STUCK
    assert np.all(np.isinf(life[stuck]))


def test_wear_life_summary_and_figure(local_run):
    _, ds = local_run
    one = ds.sel(kw=1e-11)
    summary = wear_life_summary(one, 0.5)
    life = one.cycles_to.sel(fraction=0.5).values
    usable = np.isin(one.status.values, (compute.OK, compute.STUCK, compute.HORIZON))
    ranked = np.where(np.isnan(life), np.inf, life)[usable]
    assert summary["n"] == usable.sum() and summary["left_out"] == (~usable).sum()
    for key, q in (("median", 0.5), ("q05", 0.05), ("q95", 0.95)):  # empirical quantile: a sample value
        assert summary[key] in ranked
        assert np.mean(ranked <= summary[key]) >= q and np.mean(ranked < summary[key]) < q
    fig = wear_life_figure(one, 0.5)
    ax = fig.axes[0]
    assert ax.get_xscale() == "log" and len(ax.patches) > 0
    assert {line.get_xdata()[0] for line in ax.lines if len(line.get_xdata())} == {
        summary["median"],
        summary["q05"],
        summary["q95"],
    }
    with pytest.raises(ValueError, match="kw"):
        wear_life_summary(ds, 0.5)


def test_the_numerical_core_imports_no_plotting_or_cluster_library():
    code = (
        "import sys, fretwear.studies.run, fretwear.studies.store, fretwear.studies.compute; "
        "print(sorted(m for m in ('matplotlib', 'dask', 'distributed', 'xarray') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


def _dask(*args: str) -> subprocess.Popen:
    return subprocess.Popen(
        [sys.executable, "-m", "dask", *args, "--no-dashboard"], stderr=subprocess.DEVNULL
    )


@pytest.fixture(scope="module")
def scheduler(tmp_path_factory):
    """A ``dask scheduler`` and two ``dask worker`` processes (with nannies) on 127.0.0.1: a client to it."""
    file = tmp_path_factory.mktemp("dask") / "scheduler.json"
    procs = [_dask("scheduler", "--host", "127.0.0.1", "--port", "0", "--scheduler-file", str(file))]
    try:
        deadline = time.monotonic() + 60
        while not file.exists():
            assert time.monotonic() < deadline and procs[0].poll() is None, "the scheduler did not start"
            time.sleep(0.05)
        for _ in range(2):
            procs.append(
                _dask("worker", "--scheduler-file", str(file), "--nthreads", "1", "--host", "127.0.0.1")
            )
        # not the default client: one left set as default (dask's scheduler config) outlives this module
        with distributed.Client(scheduler_file=str(file), timeout="30s", set_as_default=False) as client:
            client.wait_for_workers(2, timeout=60)
            yield client
            client.shutdown()  # the scheduler and the workers' nannies exit
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=20)
            except subprocess.TimeoutExpired:
                p.kill()
                p.wait()


def _done(out) -> np.ndarray:
    """Which tasks of the store at ``out`` are written."""
    try:
        return np.isfinite(zarr.open_group(out, mode="r")["task_seconds"][:])
    except Exception:  # noqa: BLE001 - not created yet
        return np.zeros(0, dtype=bool)


def _wait_for_tasks(running, out, count, timeout=60.0) -> np.ndarray:
    deadline = time.monotonic() + timeout
    while (done := _done(out)).sum() < count:
        assert running(), "the study ended before it was disturbed"
        assert time.monotonic() < deadline, "no task finished in time"
        time.sleep(0.01)
    return done


def test_distributed_scheduler_gives_the_same_result(scheduler, spec_path, local_run, tmp_path, capsys):
    out = tmp_path / "dist.zarr"
    status = cli.main(
        ["study", str(spec_path), "--out", str(out), "--scheduler", scheduler.scheduler.address]
    )
    err = capsys.readouterr().err
    assert status == EXIT_NOT_CONVERGED, err  # the drawn negative mu
    invalid = int((local_run[1].status == compute.INVALID).sum())
    assert "on 2 workers" in err and f"invalid {invalid}" in err and "[####" in err  # progress bar
    xr.testing.assert_identical(_data(xr.open_zarr(out)), _data(local_run[1]))


def test_a_killed_worker_is_replaced_and_the_result_is_identical(scheduler, spec_path, local_run, tmp_path):
    out = tmp_path / "killed.zarr"
    pids = sorted(scheduler.run(os.getpid).values())
    args = [str(spec_path), "--out", str(out), "--scheduler", scheduler.scheduler.address, "--quiet"]
    statuses = []
    # enough tasks to be disturbed mid-run however fast the machine; the first 12 draws are the reference's
    more = ["--points-per-task", "1", "--samples", "150"]
    thread = threading.Thread(target=lambda: statuses.append(cli.main(["study", *args, *more])))
    thread.start()
    done = _wait_for_tasks(thread.is_alive, out, 1)
    os.kill(pids[0], signal.SIGKILL)
    thread.join(timeout=300)
    assert done.sum() < len(done), "the study ended before the worker was killed"
    assert statuses == [EXIT_NOT_CONVERGED]
    scheduler.wait_for_workers(2, timeout=60)
    now = set(scheduler.run(os.getpid).values())
    assert pids[0] not in now and len(now) == 2  # the nanny started a new worker process
    result, reference = _data(xr.open_zarr(out)).isel(sample=slice(12)), _data(local_run[1])
    for name in ("cycles_to", "status", "mu", "fex"):
        xr.testing.assert_identical(result[name], reference[name])


def test_a_task_the_cluster_loses_is_resubmitted(spec_path, local_run, tmp_path, monkeypatch):
    # A block whose every Dask retry fails outside the numerics (as a task does when the workers
    # holding it die more often than Dask allows) is submitted again, not left as a hole.
    compute_block, attempts = study_run.compute_block, tmp_path / "attempts"
    attempts.mkdir()

    def flaky(work, params):  # Dask pickles the task function: count the attempts in files
        tally = attempts / f"{float(params['mu'][0])!r}-{float(params['kw'][0])!r}"
        with tally.open("a") as f:
            f.write(".")
        if len(tally.read_text()) <= 3:  # the first run and Dask's two retries
            raise OSError("connection to the worker lost")
        return compute_block(work, params)

    monkeypatch.setattr(study_run, "compute_block", flaky)  # the task run_study submits
    spec = study_spec.read_spec(spec_path)
    local = dict(processes=False, n_workers=1, threads_per_worker=1, dashboard_address="127.0.0.1:0")
    with distributed.Client(**local) as client:
        lines = []
        run = study_run.run_study(
            spec, tmp_path / "lost.zarr", client=client, progress=False, log=lines.append
        )
    assert run.complete and not run.failed_tasks
    assert sum("resubmitted" in line for line in lines) == run.n_tasks
    xr.testing.assert_identical(_data(xr.open_zarr(tmp_path / "lost.zarr")), _data(local_run[1]))


@pytest.mark.slow  # a study process started and interrupted, then resumed: the longest of the file
def test_an_interrupted_study_resumes_with_only_the_missing_blocks(
    scheduler, spec_path, local_run, tmp_path, capsys
):
    out = tmp_path / "resume.zarr"
    # enough tasks to be interrupted mid-run however fast the machine
    args = [str(spec_path), "--out", str(out), "--points-per-task", "1", "--samples", "150", "--quiet"]
    address = ["--scheduler", scheduler.scheduler.address]
    proc = subprocess.Popen([*STUDY_COMMAND, *args, *address], stderr=subprocess.PIPE, text=True)
    _wait_for_tasks(lambda: proc.poll() is None, out, 2)
    proc.send_signal(signal.SIGINT)  # Ctrl-C
    _, err = proc.communicate(timeout=120)
    assert proc.returncode == EXIT_INTERRUPTED, err
    assert "rerun the same command to resume" in err
    seconds = zarr.open_group(out, mode="r")["task_seconds"][:]
    done = np.isfinite(seconds)
    assert 2 <= done.sum() < len(done)
    # one point per task; Ctrl-C waits for the block being written (data and mark) to be whole
    not_computed = np.sum(xr.open_zarr(out).status.values == compute.NOT_COMPUTED)
    assert not_computed == np.sum(~done)
    assert cli.main(["study", *args, *address]) == EXIT_NOT_CONVERGED
    assert f"computed {(~done).sum()} tasks ({done.sum()} already in the store)" in capsys.readouterr().err
    after = zarr.open_group(out, mode="r")["task_seconds"][:]
    # the blocks already written were not recomputed
    np.testing.assert_array_equal(after[done], seconds[done])
    result = _data(xr.open_zarr(out)).isel(sample=slice(12))
    for name in ("cycles_to", "status"):
        xr.testing.assert_identical(result[name], _data(local_run[1])[name])
    assert cli.main(["study", *args]) == EXIT_NOT_CONVERGED  # no cluster needed: nothing left
    assert "nothing to compute" in capsys.readouterr().err


def test_the_shipped_study_computes_the_exact_answer():
    """``wear_life.toml`` with no method options: every point is the exact answer (exact slow time on the
    exact dynamics), as ``fw.wear_history`` gives it with no options, and the draws' cycles to 0.5 u0
    agree with direct time integration with wear within 1e-3."""
    spec = study_spec.read_spec(DATA / "wear_life.toml", samples=3)
    assert spec.fixed["dynamics"] == "auto" and "harmonics" not in spec.fixed
    ds, _ = store.template(spec, layout(spec))
    assert ds.attrs["wear_method"] == "exact"  # the store says what ran
    draws = spec.draws()
    out = compute.compute_block(compute.Work.of(spec), draws)
    assert np.all(out["status"] == compute.OK)
    for i in range(3):
        model = fw.paper_model(fex=draws["fex"][i], mu=draws["mu"][i])
        omega = 2 * np.pi * 0.7
        exact = fw.wear_history(model, omega, kw=1e-11, cycles=1e7)
        assert exact.label == "exact"
        np.testing.assert_allclose(out["cycles_to"][i], [exact.cycles_to(f) for f in (0.1, 0.5, 0.9)],
                                   rtol=1e-12)  # fmt: skip
        ref = fw.wear_history(model, omega, "time", kw=1e-11, cycles=1e7, tol=1e-4)
        assert abs(out["cycles_to"][i, 1] / ref.cycles_to(0.5) - 1) < 1e-3


@pytest.mark.parametrize(
    ("method", "dynamics"), [("exact", "shooting"), ("exact", "dlft"), ("stepping", "auto")]
)
def test_a_study_takes_every_method_and_dynamics_the_cli_takes(method, dynamics):
    text = (f'[study]\nquantities = ["wear_life"]\n[parameters]\nfrequency = 0.7\ncycles = 1e5\n'
            f'method = "{method}"\ndynamics = "{dynamics}"\n')  # fmt: skip
    spec = study_spec.parse_spec(study_spec.tomllib.loads(text), text=text)
    out = compute.compute_block(compute.Work.of(spec), {})
    model = fw.paper_model()
    h = fw.wear_history(model, 2 * np.pi * 0.7, method, kw=1e-11, cycles=1e5, dynamics=dynamics)
    assert out["status"][0] == compute.OK
    np.testing.assert_allclose(out["cycles_to"][0], [h.cycles_to(f) for f in (0.1, 0.5, 0.9)], rtol=1e-9)
