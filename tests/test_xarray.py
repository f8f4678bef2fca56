"""Results as xarray (``to_xarray``) and their Jupyter summaries (``_repr_html_``), on small cases.

Every result type round-trips through ``to_zarr`` / ``xarray.open_zarr`` (and netCDF) unchanged
(values, dimensions, coordinates, attributes); every variable and coordinate of
a measured quantity has a unit and a long name; the values are the result's own.
"""

import warnings

import numpy as np
import pytest

import fretwear as fw
from fretwear.hbm import Sweep
from fretwear.studies.accuracy import QUANTITIES, CostStudy, Rung

xr = pytest.importorskip("xarray")

OMEGA = 2 * np.pi * 0.7


@pytest.fixture(scope="module")
def model():
    return fw.paper_model()


@pytest.fixture(scope="module")
def results(model):
    """One result of every type (a few solves each)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", RuntimeWarning)
        return {
            "dlft": fw.solve_periodic(model, OMEGA, 3),
            "shooting": fw.shooting(model, OMEGA, samples=64),
            "sweep": fw.sweep(model, 2 * np.pi * np.array([0.6, 0.7, 0.8]), 3),
            "shooting_sweep": Sweep(fw.shooting_sweep(model, 2 * np.pi * np.array([0.6, 0.7]), samples=32)),
            "interface_solution": fw.solve_periodic(fw.paper_interface(), OMEGA, 3),
            "interface_sweep": fw.sweep(fw.paper_interface(), 2 * np.pi * np.array([0.6, 0.7]), 3),
            "history": fw.wear_history(model, OMEGA, "stepping", harmonics=3, kw=1e-11, cycles=1e4),
            "map": fw.wear_map(model, [0.6, 0.7], [0.0, 1e3, 1e4], method="stepping", harmonics=3, workers=1),
            "interface": fw.wear_history(
                fw.paper_interface(), OMEGA, "stepping", harmonics=3, kw=1e-11, cycles=1e4
            ),  # fmt: skip
            "ladder": CostStudy(
                0.7,
                [
                    Rung("shooting", {}, 0.01, {"x1_h1": 1e-15}, reference=True),
                    Rung("dlft", {"Nh": 3, "N": 64}, 1e-3, {"x1_h1": 2e-3, "xr_half_p2p": 0.1}),
                    Rung("polynomial", {"Nh": 3, "degree": 4}, 0.05, {"wear": 0.02}, converged=False),
                ],
                {"periodic": "shooting, tol 1e-12"},
                {"x1_h1": 1.5e-3},
            ),  # fmt: skip
            "cost_ladder": fw.cost_ladder(model, 0.7, harmonics=(1, 3), sample_factors=(4,)),
        }


KINDS = (
    "dlft",
    "shooting",
    "sweep",
    "shooting_sweep",
    "interface_solution",
    "interface_sweep",
    "history",
    "map",
    "interface",
    "ladder",
    "cost_ladder",
)


@pytest.mark.filterwarnings("error")  # e.g. Zarr's warning for a data type without a stable v3 encoding
@pytest.mark.parametrize("kind", KINDS)
def test_every_result_round_trips_through_zarr(results, kind, tmp_path):
    ds = results[kind].to_xarray()
    ds.to_zarr(tmp_path / "r.zarr", consolidated=False)
    back = xr.open_zarr(tmp_path / "r.zarr", consolidated=False).load()
    xr.testing.assert_identical(back, ds)  # values, dims, coords, attrs (of the dataset and every variable)
    # and with the study store's format (Zarr v2, consolidated)
    ds.to_zarr(tmp_path / "r2.zarr", zarr_format=2, consolidated=True)
    xr.testing.assert_identical(xr.open_zarr(tmp_path / "r2.zarr").load(), ds)
    # and netCDF (no booleans or None in attributes)
    ds.to_netcdf(tmp_path / "r.nc")
    with xr.open_dataset(tmp_path / "r.nc") as back:
        xr.testing.assert_identical(back.load(), ds)


@pytest.mark.parametrize("kind", KINDS)
def test_every_quantity_has_a_unit_and_a_long_name(results, kind):
    ds = results[kind].to_xarray()
    assert ds.attrs["fretwear_version"] == fw.__version__ and ds.attrs["created_by"].startswith("fretwear ")
    for name, var in ds.variables.items():
        assert var.attrs.get("long_name"), f"{kind}: {name} has no long name"
        if var.dtype.kind == "f":  # a measured quantity (labels and flags have no unit)
            assert var.attrs.get("units"), f"{kind}: {name} has no unit"


def test_a_periodic_solution_keeps_its_values_and_names(results, model):
    for kind in ("dlft", "shooting"):
        sol = results[kind]
        ds = sol.to_xarray()
        assert list(ds.dof.values) == ["x1", "x2"] and list(ds.friction_contact.values) == ["xr"]
        assert ds.displacement.dims == ("dof", "time") and ds.time.attrs["units"] == "s"
        np.testing.assert_array_equal(ds.displacement.values, sol.displacement)
        np.testing.assert_array_equal(ds.amplitude.sel(dof="x1").values, sol.amplitude[0])
        assert float(ds.frequency) == pytest.approx(0.7) and ds.frequency.attrs["units"] == "Hz"
        assert ds.state.attrs["flag_meanings"] == "stick slip open"
        assert ds.attrs["converged"] is True and ds.attrs["residual"] == sol.residual
    assert results["dlft"].to_xarray().attrs["harmonics"] == 3
    shooting = results["shooting"].to_xarray()
    assert shooting.attrs["method"] == "shooting" and "harmonics" not in shooting.attrs  # None: left out


def test_an_interface_solution_keeps_its_signals_per_pair(results):
    sol = results["interface_solution"]
    ds = sol.to_xarray()
    assert ds.normal_force.dims == ("pair", "time") and ds.state.dims == ("pair", "time")
    np.testing.assert_array_equal(ds.normal_force.values, sol.normal_force)
    np.testing.assert_array_equal(ds.tangential_force.values, sol.tangential_force)
    np.testing.assert_array_equal(ds.slip_distance.values, sol.slip_distance)
    np.testing.assert_array_equal(ds.position.values, sol.position)
    assert list(ds.dof.values) == ["x1", "x2", "y"]  # the reported DOFs, as the interface sweep's
    np.testing.assert_array_equal(ds.amplitude.values, sol.amplitude)
    # the pressure is the normal force over the tributary area, sampled on one period
    np.testing.assert_allclose(ds.pressure * ds.area, ds.normal_force, rtol=1e-12)
    assert ds.time.size == sol.normal_force.shape[1] and float(ds.time[-1]) < 1 / 0.7
    assert float(ds.frequency) == pytest.approx(0.7) and ds.state.attrs["flag_meanings"] == "stick slip open"
    assert ds.attrs["method"] == "dlft, Nh = 3" and ds.attrs["converged"] is True
    assert float(ds.friction_energy) == sol.friction_energy and ds.friction_energy.attrs["units"] == "J"


def test_an_interface_solution_with_the_cone_has_two_tangent_directions(results, tmp_path):
    """With the Coulomb cone the tangential signals are (pair, time, direction): a solution stand-in with
    the cone's shapes (the 1-D solution's signals along t1, zero along t2)."""
    from types import SimpleNamespace

    from fretwear._xarray import interface_solution_dataset

    sol = results["interface_solution"]
    fields = {name: getattr(sol, name) for name in (
        "model", "frequency", "omega", "position", "area", "normal_force", "pressure", "state",
        "mean_pressure", "slip_distance", "state_fraction", "amplitude", "friction_energy", "contact_work",
        "path", "harmonics", "converged", "iterations", "residual", "message")}  # fmt: skip
    lam = np.stack([sol.tangential_force, np.zeros_like(sol.tangential_force)], axis=-1)
    slip = np.stack([sol.slip_variable, np.zeros_like(sol.slip_variable)], axis=-1)
    problem = SimpleNamespace(cone=True)
    cone = SimpleNamespace(**fields, tangential_force=lam, slip_variable=slip, problem=problem)
    ds = interface_solution_dataset(cone)
    assert ds.tangential_force.dims == ("pair", "time", "direction")
    assert list(ds.direction.values) == ["t1", "t2"]
    np.testing.assert_array_equal(ds.slip_variable.sel(direction="t1").values, sol.slip_variable)
    assert ds.normal_force.dims == ("pair", "time") and ds.attrs["cone"] is True
    ds.to_zarr(tmp_path / "cone.zarr", consolidated=False)
    xr.testing.assert_identical(xr.open_zarr(tmp_path / "cone.zarr", consolidated=False).load(), ds)


def test_a_sweep_is_an_frf_along_frequency(results):
    for kind in ("sweep", "shooting_sweep"):
        sweep = results[kind]
        ds = sweep.to_xarray()
        np.testing.assert_allclose(ds.frequency.values, sweep.omega / (2 * np.pi))
        assert ds.amplitude.dims == ("frequency", "dof")
        np.testing.assert_array_equal(ds.amplitude.values, [s.amplitude for s in sweep.solutions])
        np.testing.assert_array_equal(ds.converged.values, sweep.converged)
    pairs = results["interface_sweep"]
    ds = pairs.to_xarray()
    assert list(ds.dof.values) == ["x1", "x2", "y"] and ds.slip_distance.dims == ("frequency", "pair")
    np.testing.assert_array_equal(ds.amplitude.values, [s.amplitude for s in pairs.solutions])
    np.testing.assert_array_equal(ds.friction_energy.values, [s.friction_energy for s in pairs.solutions])


def test_a_wear_history_plots_w_against_cycles(results):
    import matplotlib

    matplotlib.use("Agg")
    h = results["history"]
    ds = h.to_xarray()
    assert ds.w.dims == ("cycles", "friction_contact") and ds.w.attrs["units"] == "m"
    np.testing.assert_array_equal(ds.w.values, h.wear)
    np.testing.assert_array_equal(ds.cycles.values, h.cycles)
    np.testing.assert_allclose(ds.wear_fraction.values, h.wear / h.u0)
    assert ds.cycles.attrs == {"units": "cycles", "long_name": "vibration cycles N"}  # the store's
    assert ds.attrs["label"] == h.label and ds.attrs["kw"] == 1e-11 and ds.attrs["kw_units"] == "1/N"
    lines = ds.w.plot()  # one contact: a line w(N), labelled with the long names and units
    assert len(lines) == 1 and np.array_equal(lines[0].get_ydata(), h.wear[:, 0])
    assert "[cycles]" in lines[0].axes.get_xlabel() and "[m]" in lines[0].axes.get_ylabel()


def test_a_wear_map_and_an_interface_history_keep_their_grids(results):
    m = results["map"]
    ds = m.to_xarray()
    assert ds.w.dims == ("frequency", "cycles", "friction_contact")
    np.testing.assert_array_equal(ds.w.values, m.wear)
    np.testing.assert_array_equal(ds.frequency.values, m.frequency)
    h = results["interface"]
    ds = h.to_xarray()
    assert ds.w.dims == ("cycles", "pair") and ds.state.dims == ("cycles", "pair", "phase")
    np.testing.assert_array_equal(ds.w.values, h.wear)
    np.testing.assert_array_equal(ds.position.values, h.position)
    np.testing.assert_allclose(ds.worn_area.values, h.worn_area)
    assert ds.attrs["kw_units"] == "1/Pa" and ds.position.attrs["units"] == "m"


def test_a_cost_ladder_is_a_table_of_rungs_and_quantities(results):
    study = results["ladder"]
    ds = study.to_xarray()
    assert list(ds.quantity.values) == list(QUANTITIES)
    assert ds.error.sel(rung=1, quantity="xr_half_p2p") == 0.1
    assert np.isnan(ds.error.sel(rung=0, quantity="wear"))  # not measured: NaN, not 0
    assert ds.Nh.values[1] == 3 and np.isnan(ds.Nh.values[0]) and ds.degree.values[2] == 4
    assert list(ds.converged.values) == [True, True, False]
    assert list(ds.reference.values) == [True, False, False]
    assert ds.attrs["reference_periodic"] == "shooting, tol 1e-12"


@pytest.mark.parametrize("kind", ("dlft", "shooting", "history", "map", "interface"))
def test_the_html_summary_shows_the_key_fields(results, kind):
    r = results[kind]
    html = r._repr_html_()
    assert html.startswith("<table>") and f"<b>{type(r).__name__}</b>" in html
    assert "<th" in html and "converged" in html and "0.7 Hz" in html
    if kind in ("dlft", "shooting"):
        assert f"{r.residual:.2e}" in html
        assert ("Nh = 3" if kind == "dlft" else "shooting") in html
    if kind in ("history", "interface"):
        assert r.status in html and "cycles" in html
    if kind == "history":
        assert r.label in html and r.dynamics in html


def test_the_html_summary_shows_the_measured_error_and_escapes_text(results):
    h = results["history"]
    h2 = type(h)(**{**h.__dict__, "info": {"misfit": 0.0123}, "status": "failed: <x> & y"})
    html = h2._repr_html_()
    assert "misfit 0.0123" in html and "failed: &lt;x&gt; &amp; y" in html


def test_the_library_imports_without_xarray():
    """xarray is imported by ``to_xarray`` only: without xarray, fretwear imports and builds models."""
    import subprocess
    import sys

    code = "import sys; sys.modules['xarray'] = None; import fretwear; fretwear.paper_model(); print('ok')"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, stdin=subprocess.PIPE)
    assert run.returncode == 0 and run.stdout.strip() == "ok", run.stderr[-2000:]
