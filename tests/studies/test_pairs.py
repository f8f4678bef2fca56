"""Studies over models with contact pairs: the cylinder-on-flat benchmark, the paper's one-pair interface and
interface model files, through the spec, the per-point compute, the Zarr store, the Dask run and the CLI.

The benchmark is coarse (6 pairs, gross slip by a loading arm, ``Nh = 3``) and the grid small (2 x 2
points), so that the whole file takes seconds. Every stored number is checked against direct calls of the
front functions (:func:`fretwear.solve_periodic`, :func:`fretwear.wear_history`) on the model reduced at the
study's ``f_max`` (:func:`fretwear.reduce`), to 1e-12.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest
from scipy.interpolate import CubicHermiteSpline

import fretwear as fw
from fretwear import cli
from fretwear.cli.shared import EXIT_OK, EXIT_USAGE
from fretwear.studies import compute
from fretwear.studies import spec as study_spec
from fretwear.studies.layout import layout
from fretwear.studies.summary import wear_depth_summary, wear_life_summary

xr = pytest.importorskip("xarray")
pytest.importorskip("distributed")

#: the coarse benchmark in gross slip (the dashboard's, with 6 pairs)
BENCHMARK = {"contact_nodes": 6, "window": 3.0, "arm_stiffness": 2e10, "drive_displacement": 2e-5}
SPEC = """
[study]
title = "coarse cylinder on flat"
quantities = ["frf", "wear", "wear_life"]

[model]
name = "cylinder_on_flat"
contact_nodes = 6
window = 3.0
arm_stiffness = 2e10
drive_displacement = 2e-5

[parameters]
frequency = [40.0, 50.0]
mu = [0.5, 0.6]
kw = 1e-14
cycles = 3e4
harmonics = 3

[wear]
ncycles = 5
depths = [1e-6, 1e-5]
"""


@pytest.fixture(scope="module")
def block(spec_path):
    """The spec and its 4 points computed in one block (the Dask task, called directly)."""
    spec = study_spec.read_spec(spec_path)
    mu, f = np.meshgrid(spec.grid["mu"], spec.grid["frequency"], indexing="ij")
    return spec, compute.compute_block(compute.Work.of(spec), {"mu": mu.ravel(), "frequency": f.ravel()})


def _reference(spec, mu: float, frequency: float):
    """The direct calls at one point: the periodic solve and the wear history of the reduced benchmark."""
    model = fw.reduce(fw.cylinder_on_flat(**BENCHMARK), spec.reduce_hz)
    model = replace(model, pairs=replace(model.pairs, mu=mu))
    omega = 2 * np.pi * frequency
    sol = fw.solve_periodic(model, omega, 3)
    h = fw.wear_history(model, omega, "stepping", kw=1e-14, cycles=3e4, harmonics=3)
    return model, sol, h


def test_the_spec_builds_the_benchmark_and_its_one_reduction(spec_path):
    spec = study_spec.read_spec(spec_path)
    assert spec.pairs and spec.model_kind == "cylinder_on_flat" and spec.model.n_pairs == 6
    assert spec.model_parameters == {**BENCHMARK, "contact_nodes": 6}
    assert spec.reduce_hz == 50.0 * 3  # the highest frequency times Nh
    assert spec.fixed == {"kw": 1e-14, "cycles": 3e4, "harmonics": 3, "method": "auto"}
    assert spec.parameters["kw"].unit == "1/Pa" and spec.parameters["mu"].table == "interface_mu"
    # the builder's parameters are in the study's key: another mesh is another study
    text = SPEC.replace("contact_nodes = 6", "contact_nodes = 5")
    (spec_path.parent / "five.toml").write_text(text)
    assert study_spec.read_spec(spec_path.parent / "five.toml").key() != spec.key()


def test_each_point_is_the_front_functions_on_the_reduced_model(block):
    spec, res = block
    assert res["status"].tolist() == [compute.HORIZON] * 4, res["messages"]  # 10 um is not reached
    grid = spec.cycle_grid()
    for i, (mu, f) in enumerate([(m, f) for m in spec.grid["mu"] for f in spec.grid["frequency"]]):
        model, sol, h = _reference(spec, mu, f)
        dofs = [model.reduction.full.dof("pad_x"), model.reduction.full.dof("pad_y")]
        np.testing.assert_allclose(res["amplitude"][i], sol.amplitude[dofs], rtol=1e-12)
        np.testing.assert_allclose(res["slip_distance"][i], sol.slip_distance, rtol=1e-12, atol=1e-20)
        np.testing.assert_allclose(res["mean_pressure"][i], sol.mean_pressure, rtol=1e-12)
        np.testing.assert_allclose(res["friction_energy"][i], sol.friction_energy, rtol=1e-12)
        assert h.converged and h.cycles[-1] == grid[-1]
        # at the horizon: the history's last record itself; between records: its cubic Hermite interpolant
        np.testing.assert_allclose(res["wear_depth"][i, -1], h.wear[-1], rtol=1e-12, atol=1e-22)
        spline = CubicHermiteSpline(h.cycles, h.wear, h.wear_rate, axis=0)
        np.testing.assert_allclose(res["wear_depth"][i], spline(grid), rtol=1e-12, atol=1e-22)
        np.testing.assert_allclose(res["wear_pressure"][i, -1], h.pressure[-1], rtol=1e-12)
        np.testing.assert_allclose(res["wear_amplitude"][i, -1], h.solutions[-1].amplitude[dofs], rtol=1e-12)
        # the life to a depth: the first pair to reach it (1 um within the horizon, 10 um beyond it)
        first = np.nanmin([h.cycles_to_depth(1e-6, k) for k in range(6)])
        np.testing.assert_allclose(res["cycles_to"][i, 0], first, rtol=1e-12)
        assert 0 < first < 3e4 and np.isnan(res["cycles_to"][i, 1]) and h.wear[-1].max() < 1e-5
    # gross slip: the pairs that carry load slip, wear, and the interface dissipates
    assert np.all(res["friction_energy"] > 0) and np.all(res["wear_depth"][:, -1].max(axis=1) > 0)
    # Archard: wear grows with N at every pair
    assert np.all(np.diff(res["wear_depth"], axis=1) >= 0)


def test_the_cli_runs_the_study_into_a_store_of_the_same_numbers(spec_path, block, tmp_path, capsys):
    spec, res = block
    out = tmp_path / "pairs.zarr"
    assert cli.main(["study", str(spec_path), "--out", str(out), "--workers", "1", "--quiet"]) == EXIT_OK
    err = capsys.readouterr().err
    ds = xr.open_zarr(out).load()
    assert ds.amplitude.dims == ("mu", "frequency", "dof") and ds.dof.values.tolist() == ["pad_x", "pad_y"]
    assert ds.wear_depth.dims == ("mu", "frequency", "cycles", "pair") and ds.wear_depth.attrs["units"] == "m"
    assert ds.cycles_to.dims == ("mu", "frequency", "depth") and ds.depth.values.tolist() == [1e-6, 1e-5]
    np.testing.assert_array_equal(ds.position, spec.model.pairs.position)
    assert ds.attrs["reduce_hz"] == 150.0 and ds.attrs["wear_method"] == "stepping"
    assert ds.mu.attrs["units"] == "-" and "every pair" in ds.mu.attrs["long_name"]
    for name in ("amplitude", "slip_distance", "mean_pressure", "friction_energy", "wear_depth",
                 "wear_pressure", "wear_amplitude", "cycles_to"):  # fmt: skip
        np.testing.assert_array_equal(ds[name].values.reshape(res[name].shape), res[name])
    s = wear_depth_summary(ds)
    deepest = res["wear_depth"][:, -1].max(axis=1)
    assert s["n"] == 4 and s["max"] == deepest.max() and s["min"] == deepest.min()
    assert f"deepest wear at N = 30000: {s['max']:.4g} m" in err


def test_the_papers_interface_by_name_and_as_a_model_file_are_the_same_study(tmp_path):
    """``name = "paper_interface"`` and the same model written as an interface model file (Matrix Market
    matrices, pairs in .npz) give the same numbers: the front functions on the same reduced model."""
    from fretwear.interface import write_interface_model

    write_interface_model(fw.paper_interface(fex=6.0), tmp_path / "one_pair.toml")
    body = "\n[parameters]\nfrequency = [0.5, 0.7]\nforce_scale = 0.8\nharmonics = 5\n"
    results = {}
    for kind, model in (("name", '[model]\nname = "paper_interface"\nfex = 6.0\n'),
                        ("file", '[model]\nfile = "one_pair.toml"\n')):  # fmt: skip
        (tmp_path / f"{kind}.toml").write_text('[study]\nquantities = ["frf"]\n' + model + body)
        spec = study_spec.read_spec(tmp_path / f"{kind}.toml")
        assert spec.pairs and spec.reduce_hz == 0.7 * 5
        results[kind] = compute.compute_block(compute.Work.of(spec), {"frequency": spec.grid["frequency"]})
        assert results[kind]["status"].tolist() == [compute.OK] * 2
    np.testing.assert_array_equal(results["name"]["amplitude"], results["file"]["amplitude"])
    model = fw.reduce(fw.paper_interface(fex=6.0).scaled(0.8), 0.7 * 5)
    for i, f in enumerate([0.5, 0.7]):
        sol = fw.solve_periodic(model, 2 * np.pi * f, 5)
        np.testing.assert_allclose(results["name"]["amplitude"][i], sol.amplitude, rtol=1e-12)
        np.testing.assert_allclose(results["name"]["slip_distance"][i], sol.slip_distance, rtol=1e-12)


_PAIRS = '[model]\nname = "cylinder_on_flat"\ncontact_nodes = 4\n'
_WEAR = "[parameters]\nfrequency = 50.0\ncycles = 1e4\nkw = 1e-14\n"
BAD = [
    ('[study]\nquantities = ["frf"]\n[model]\nname = "cylinder"\n[parameters]\nfrequency = 50.0\n',
     "model.name", "'paper', 'cylinder_on_flat', 'paper_interface'"),
    ('[study]\nquantities = ["frf"]\n[model]\nname = "cylinder_on_flat"\ncontact_nodes = 2\n'
     "[parameters]\nfrequency = 50.0\n", "model.contact_nodes", "an integer in [3, 128]"),
    ('[study]\nquantities = ["frf"]\n[model]\nname = "cylinder_on_flat"\nnodes = 4\n'
     "[parameters]\nfrequency = 50.0\n", "model.nodes", "contact_nodes"),
    ('[study]\nquantities = ["frf"]\n[model]\nname = "cylinder_on_flat"\nradius = -1.0\n'
     "[parameters]\nfrequency = 50.0\n", "model.radius", "radius must be"),
    ('[study]\nquantities = ["frf"]\n' + _PAIRS + "[parameters]\nfrequency = 50.0\nfex = 5.0\n",
     "parameters.fex", "frequency, force_scale, mu, kw, cycles, harmonics, method, tol"),
    ('[study]\nquantities = ["wear_life"]\n' + _PAIRS + _WEAR, "wear.depths", "worn depths (m)"),
    ('[study]\nquantities = ["wear_life"]\n' + _PAIRS + _WEAR + "[wear]\nfractions = [0.5]\n"
     "depths = [1e-6]\n", "wear.fractions", "depths (m)"),
    ('[study]\nquantities = ["wear_life"]\n' + _PAIRS + _WEAR + "[wear]\ndepths = [1e-6, -1e-6]\n",
     "wear.depths", "distinct depths > 0 (m)"),
    ('[study]\nquantities = ["wear_life"]\n[parameters]\nfrequency = 0.7\ncycles = 1e4\n'
     "[wear]\ndepths = [1e-6]\n", "wear.depths", "fractions of u0"),
    ('[study]\nquantities = ["wear"]\n' + _PAIRS + "[parameters]\nfrequency = 50.0\ncycles = 1e4\n",
     "parameters.kw", "1/Pa"),
    ('[study]\nquantities = ["wear"]\n' + _PAIRS + _WEAR + 'method = "exact"\n',
     "parameters.method", "'auto', 'stepping', 'polynomial'"),
    ('[study]\nquantities = ["frf"]\nseed = 1\nsamples = 2\n' + _PAIRS +
     '[parameters]\nfrequency = { distribution = "uniform", low = 40.0, high = 50.0 }\n',
     "parameters.frequency", "reduced once"),
    ('[study]\nquantities = ["wear"]\n' + _PAIRS + _WEAR + 'method = "polynomial"\ntol = 1e-2\n',
     "parameters.tol", "'stepping'"),
    ('[study]\nquantities = ["frf"]\n' + _PAIRS + "[parameters]\nfrequency = 50.0\nmu = 11.0\n",
     "parameters.mu", "a number >= 0 and <= 10"),
]  # fmt: skip


@pytest.mark.parametrize(("text", "key", "valid"), BAD, ids=[k for _, k, _ in BAD])
def test_bad_entries_name_the_key_and_the_valid_values(tmp_path, capsys, text, key, valid):
    path = tmp_path / "bad.toml"
    path.write_text(text)
    with pytest.raises(ValueError, match=f"^{key}: ") as err:
        study_spec.read_spec(path)
    assert valid in str(err.value), err.value
    out = tmp_path / "never.zarr"
    assert cli.main(["study", str(path), "--out", str(out)]) == EXIT_USAGE
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith(f"fretwear study: error: {key}: ") and not out.exists()


def test_random_draws_of_a_pair_model_and_an_invalid_draw_is_a_status(tmp_path):
    """``mu`` drawn at random (seeded per parameter as for 1-D contacts); a negative draw is an invalid
    point (NaN, status ``invalid``, a message naming mu), the others the front function's numbers."""
    path = tmp_path / "random.toml"
    path.write_text(
        '[study]\nquantities = ["frf"]\nseed = 3\nsamples = 8\n[model]\nname = "paper_interface"\n'
        '[parameters]\nfrequency = 0.7\nmu = { distribution = "normal", mean = 0.3, std = 0.4 }\n'
        "harmonics = 5\n"
    )
    spec = study_spec.read_spec(path)
    mu = spec.draws()["mu"]
    np.testing.assert_array_equal(
        mu, np.random.default_rng([3, list(spec.parameters).index("mu")]).normal(0.3, 0.4, 8)
    )
    res = compute.compute_block(compute.Work.of(spec), {"mu": mu})
    bad = mu < 0
    assert bad.any() and (~bad).sum() >= 3
    assert np.all(res["status"][bad] == compute.INVALID) and np.isnan(res["amplitude"][bad]).all()
    assert all("mu" in m for i, m in res["messages"]) and {i for i, _ in res["messages"]} == set(
        np.flatnonzero(bad)
    )
    reduced = fw.reduce(fw.paper_interface(), spec.reduce_hz)
    for i in np.flatnonzero(~bad):
        sol = fw.solve_periodic(replace(reduced, pairs=replace(reduced.pairs, mu=mu[i])), 2 * np.pi * 0.7, 5)
        np.testing.assert_allclose(res["amplitude"][i], sol.amplitude, rtol=1e-12)
        assert res["status"][i] == compute.OK


def test_the_wear_life_summary_of_a_pair_study_is_over_depths():
    """The quantiles of the cycles to a worn depth (m) over the samples, as for the fractions of u0."""
    life = np.array([[1e3, np.nan], [2e3, 5e4], [np.inf, np.inf], [4e3, np.nan]])
    ds = xr.Dataset(
        {"cycles_to": (("sample", "depth"), life),
         "status": ("sample", [compute.HORIZON, compute.OK, compute.STUCK, compute.ERROR])},
        coords={"sample": np.arange(4), "depth": [1e-6, 5e-6]},
    )  # fmt: skip
    s = wear_life_summary(ds, depth=5e-6)
    assert (s["n"], s["stuck"], s["beyond_horizon"], s["left_out"]) == (3, 1, 1, 1)
    assert s["median"] == np.inf and s["q05"] == 5e4  # ranked: 5e4, inf (stuck), inf (beyond the horizon)
    assert wear_life_summary(ds, depth=1e-6)["median"] == 2e3
    with pytest.raises(
        ValueError, match=r"depth must be one of the study's depths \[1e-06, 5e-06\], got None"
    ):
        wear_life_summary(ds)


def test_a_pair_that_sticks_has_an_infinite_life(tmp_path):
    """The paper's one-pair interface sticks at 0.3 Hz (no wear: life inf, status stuck) and wears at
    0.7 Hz (the front function's history: its pair reaches 0.1 u0 = 1e-7 m within 2e4 cycles)."""
    path = tmp_path / "life.toml"
    path.write_text(
        '[study]\nquantities = ["wear_life"]\n[model]\nname = "paper_interface"\n[parameters]\n'
        "frequency = [0.3, 0.7]\nkw = 1e-11\ncycles = 2e4\nharmonics = 5\n[wear]\ndepths = [1e-7, 2e-6]\n"
    )
    spec = study_spec.read_spec(path)
    assert layout(spec).n_tasks == 2  # the wear life alone is costed too: a task a point (MIN_TASKS)
    res = compute.compute_block(compute.Work.of(spec), {"frequency": spec.grid["frequency"]})
    assert res["status"].tolist() == [compute.STUCK, compute.HORIZON]  # 2e-6 m > u0 = 1e-6 m: never
    assert np.isinf(res["cycles_to"][0]).all() and np.isnan(res["cycles_to"][1, 1])
    model = fw.reduce(fw.paper_interface(), spec.reduce_hz)
    h = fw.wear_history(model, 2 * np.pi * 0.7, "stepping", kw=1e-11, cycles=2e4, harmonics=5)
    np.testing.assert_allclose(res["cycles_to"][1, 0], h.cycles_to_depth(1e-7, 0), rtol=1e-12)
    assert 0 < res["cycles_to"][1, 0] < 2e4
