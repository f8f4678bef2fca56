"""The Interface scene: wear of a contact interface with many node pairs (:mod:`fretwear.interface`).

Models: the cylinder-on-flat fretting benchmark in partial slip (force
control, ``Q0 / (mu P) = 0.5``) or in gross slip (displacement control), the
3-D sphere on a flat (:func:`fretwear.interface.sphere.sphere_dynamic_model`,
2-D friction on a coarse half mesh of 29 pairs: partial slip at ``Q* / (mu P)
= 0.6``, or gross slip driven through a loading arm), the
paper's 2-DOF example as a one-pair interface (its single node drawn as a
short segment in the profiles), or a
model file given to the server (``panel serve app/app.py --args
--interface-model FILE.toml``). One run is four tasks of the session's
machinery (:class:`~app.session.Runner`, :class:`~app.state.Tasks`), each
keyed by the backend call it caches: the model reduced once
(:meth:`~app.backend.Backend.interface_model`, :func:`fretwear.reduce`), the
nodal wear history (:meth:`~app.backend.Backend.interface_history`,
:func:`fretwear.wear_history`) and the FRF of the chosen DOF before and after
wear (:meth:`~app.backend.Backend.interface_frf`, :func:`fretwear.sweep`, the
worn profile of the history at the horizon). The figures show
``w(x)`` and ``p(x)`` at several ``N`` (with the Hertz pressure for the
benchmark), the stick/slip state over ``(x, phase of the cycle)`` at the last
record, the FRFs, and the fretting loop (tangential force against the driven
DOF's displacement over one period, at the first and last records). For the
sphere, the profiles are drawn against the distance ``r`` from the centre and
the 3-D patch is shown from above at the last record
(:func:`fretwear.figures.patch.patch_figure`): mean pressure, peak shear
traction, where the pairs stick, slip or open over the cycle, worn depth.
Nothing computes until the tab is first shown; results are kept in the
server's shared cache.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import panel as pn
import param

from fretwear import figures
from fretwear.figures.patch import patch_figure
from fretwear.figures.plots import ensure_backend, holoviews, overlay_options, styled
from fretwear.figures.record import version
from fretwear.model import OPEN, SLIP, STICK

from ..backend import Failure, Grid, InterfaceModel
from ..live import control_row, figure_grid, live_pane, message_list, run_status, typed_box
from ..session import Runner
from ..state import ResultOf, Task, Tasks, WearAfter, file_stamp, whole
from .base import Addressed, Exports, OwnSettings

__all__ = ["InterfaceScene", "InterfaceSettings", "interface_tab", "MODELS", "PAPER", "RTOL"]

PARTIAL, GROSS, FILE = "benchmark, partial slip", "benchmark, gross slip", "model file"
PAPER = "paper's 2-DOF (one pair)"
SPHERE_PARTIAL, SPHERE_GROSS = "sphere (3-D), partial slip", "sphere (3-D), gross slip"
#: settings each model choice starts from (the benchmark at 50 Hz; the paper's case at 0.7 Hz; the sphere
#: at 150 Hz, 1/20 of its holder's mode: quasi-static, Nh = 3 for a first run in seconds, its gross slip to
#: 1e4 cycles, a scar about Hertz's approach a^2 / R deep)
DEFAULTS = {
    GROSS: {"frequency": 50.0, "kw": 1e-14, "cycles": 3e4, "harmonics": 5},
    PARTIAL: {"frequency": 50.0, "kw": 1e-14, "cycles": 3e4, "harmonics": 5},
    SPHERE_PARTIAL: {"frequency": 150.0, "kw": 1e-14, "cycles": 1e5, "harmonics": 3},
    SPHERE_GROSS: {"frequency": 150.0, "kw": 1e-14, "cycles": 1e4, "harmonics": 3},
    PAPER: {"frequency": 0.7, "kw": 1e-11, "cycles": 2e4, "harmonics": 5},
}
#: benchmark settings of each model choice (``fretwear.interface.cylinder_on_flat`` parameters)
MODELS = {
    PARTIAL: {"q_ratio": 0.5},
    GROSS: {"window": 3.0, "arm_stiffness": 2e10, "drive_displacement": 2e-5},
}
#: the sphere's coarse half mesh (``sphere_dynamic_model`` parameters): 29 pairs, a first run in seconds
SPHERE_MESH = {"divisions": 4, "size": 4.0}
#: sphere settings of each model choice: Q* = 0.6 mu P; or the holder driven through an arm, k_a delta0 =
#: 300 N = 5 mu P
SPHERES = {
    SPHERE_PARTIAL: {**SPHERE_MESH, "q_ratio": 0.6},
    SPHERE_GROSS: {**SPHERE_MESH, "arm_stiffness": 2e7, "drive_displacement": 1.5e-5},
}
#: the 3-D patch figures (the sphere's only)
PATCH_FIGURES = ("patch_pressure", "patch_shear", "patch_state", "patch_wear")
#: the patch's stick/slip/open map (:func:`fretwear.interface.history.cycle_state`): code -> (name, colour),
#: the colours of the stick/slip map over the cycle
PATCH_STATES = {
    0: ("sticks (never slips)", "#4c72b0"),
    1: ("slips", "#dd8452"),
    2: ("open all cycle", "#dddddd"),
}
#: records of the history drawn as profiles (the first, the last, and log-spaced ones between)
PROFILES = 4
#: slow-time step tolerance of the wear history (``rtol`` of :func:`fretwear.wear_history`)
RTOL = 3e-2
#: the contact states of the stick/slip map, by their codes there
STATE_NAMES = {0: "stick", 1: "slip", 2: "open"}


@dataclass(frozen=True)
class InterfaceSettings:
    """What one run of the Interface scene computes (SI units, frequencies in Hz)."""

    model: str = GROSS
    path: str | None = None
    contact_nodes: int = 16
    frequency: float = 50.0
    harmonics: int = 5
    kw: float = 1e-14
    cycles: float = 3e4
    dof: str = "pad_x"
    fmin: float = 20.0
    fmax: float = 200.0
    n_frequencies: int = 10
    #: modification time of the model file (s): a changed file is another run (its cache key)
    stamp: float | None = None

    def problems(self) -> list[str]:
        """Invalid values, one line each naming the setting and its valid range."""
        out = []
        checks = (
            ("frequency", 0.0, 1e5, "Hz"),
            ("kw", 0.0, 1e-6, "1/Pa"),
            ("cycles", 0.0, 1e9, "cycles"),
            ("fmin", 0.0, 1e5, "Hz"),
            ("fmax", 0.0, 1e5, "Hz"),
        )
        for name, low, high, unit in checks:
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and low < v <= high):
                out.append(f"{name} must be a number > {low:g} and <= {high:g} {unit}, got {v!r}")
                if name == "frequency":
                    break  # the FRF band follows the frequency: one message
        if not out and self.fmin >= self.fmax:
            out.append(f"fmin must be below fmax, got {self.fmin:g} >= {self.fmax:g} Hz")
        if not whole(self.harmonics, 1, 15):
            out.append(f"harmonics must be an integer in [1, 15], got {self.harmonics!r}")
        if not 3 <= self.n_frequencies <= 50:
            out.append(f"n_frequencies must be an integer in [3, 50], got {self.n_frequencies!r}")
        if self.model == FILE and not self.path:
            out.append(
                "model file: none was given (panel serve app/app.py --args --interface-model FILE.toml)"
            )
        return out

    def model_spec(self) -> InterfaceModel:
        """The model of the settings, as the backend builds it (its cache key)."""
        if self.model == FILE:
            return InterfaceModel("file", path=self.path, stamp=self.stamp)
        if self.model == PAPER:
            return InterfaceModel("paper_interface")
        if self.model in SPHERES:
            return InterfaceModel("sphere_dynamic_model", tuple(SPHERES[self.model].items()))
        return InterfaceModel(
            "cylinder_on_flat", (("contact_nodes", self.contact_nodes), *MODELS[self.model].items())
        )

    @property
    def f_max(self) -> float:
        """Highest frequency the harmonic balance sees (Hz), ``Nh`` times the highest excitation
        frequency: the reduction keeps the modes up to twice it (:func:`fretwear.reduce`)."""
        return self.harmonics * max(self.frequency, self.fmax)

    def tasks(self, tasks: Tasks) -> list[Task]:
        """The run's tasks: the reduced model, the wear history, the FRFs before and after wear."""
        b = tasks.backend
        model = tasks.call("interface_model", "the reduced model (Craig-Bampton)", 1.0, b.interface_model,
                           self.model_spec(), self.f_max)  # fmt: skip
        reduced = ResultOf.of(model)
        history = tasks.call("interface_history", f"the wear history to N = {self.cycles:g}", 2.5,
                             b.interface_history, reduced, self.frequency, self.harmonics, self.kw,
                             self.cycles, RTOL)  # fmt: skip
        grid = Grid(self.fmin, self.fmax, self.n_frequencies)
        frfs = [
            tasks.call(
                f"frf_{when}",
                f"the FRF {when} wear",
                1.0,
                b.interface_frf,
                reduced,
                grid,
                self.harmonics,
                self.dof,
                wear,
            )  # fmt: skip
            for when, wear in (("before", None), ("after", WearAfter.of(history, self.cycles)))
        ]
        return [model, history, *frfs]


class InterfaceScene(Addressed, OwnSettings, Exports, Runner):
    """The Interface tab's state: its settings, the run in progress and the published results.

    Its run is the tasks of :meth:`InterfaceSettings.tasks` on the session's machinery
    (:class:`~app.session.Runner`, :class:`~app.state.Tasks`), each keyed by the backend call it caches.

    Parameters
    ----------
    path : str or Path, optional
        An interface model file (``--interface-model``): offered as the third model.
    **options
        ``tasks``, ``executor``, ``dispatch`` of :class:`~app.scenes.base.OwnSettings`, and values of the
        parameters.
    """

    key = "interface"
    title = "Interface"
    address_params = ("model", "contact_nodes", "frequency", "harmonics", "kw", "cycles")
    figure_names = ("wear_profile", "pressure_profile", "stick_slip", "frf", "loop", *PATCH_FIGURES)
    dataset_names = ("profiles", "frf", "loop", "patch")

    model = param.Selector(
        default=GROSS, objects=[GROSS, PARTIAL, SPHERE_PARTIAL, SPHERE_GROSS, PAPER], doc="Model"
    )
    contact_nodes = param.Selector(default=16, objects=[16, 32], doc="Benchmark pairs across the contact")
    frequency = param.Number(50.0, doc="Excitation frequency (Hz)")
    harmonics = param.Integer(5, doc="Harmonics Nh")
    kw = param.Number(1e-14, doc="Archard coefficient (1/Pa)")
    cycles = param.Number(3e4, doc="Wear horizon (cycles)")
    typed = param.Dict({}, doc="Texts typed into the boxes that are not numbers, by setting")
    notes = param.List([])
    version = param.Integer(0)

    def __init__(self, path: str | Path | None = None, **options: Any) -> None:
        super().__init__(**options)
        self.path = None if path is None else str(path)
        if self.path is not None:
            self.param.model.objects = [*self.param.model.objects, FILE]
        self.param.watch(self._defaults, ["model"])  # first: the run below sees the model's settings
        self.param.watch(
            self.refresh, ["model", "contact_nodes", "frequency", "harmonics", "kw", "cycles", "typed"]
        )

    def _defaults(self, event: param.parameterized.Event) -> None:
        """A new model starts from its own frequency, wear coefficient and horizon (a file keeps them)."""
        if event.new in DEFAULTS and DEFAULTS.get(event.old) != DEFAULTS[event.new]:
            self.param.update(typed={}, **DEFAULTS[event.new])

    def settings(self) -> InterfaceSettings:
        """The settings of the controls (a model file's DOF is its first named one, or DOF 0)."""
        return InterfaceSettings(
            model=self.model,
            path=self.path,
            contact_nodes=int(self.contact_nodes),
            frequency=float(self.frequency),
            harmonics=int(self.harmonics),
            kw=float(self.kw),
            cycles=float(self.cycles),
            fmin=0.4 * float(self.frequency),
            fmax=4.0 * float(self.frequency),
            stamp=file_stamp(self.path) if self.model == FILE else None,
        )

    def _publish_results(self, results: dict[str, Any], final: bool) -> None:
        if not final:
            return
        failed = next((r for r in results.values() if isinstance(r, Failure)), None)
        if failed is not None:  # a bad model file, a solver that failed: one line in the page
            self.error = f"The interface run failed: {failed.reason}"
            return
        model, h, before, after = (results[k] for k in ("interface_model", "interface_history", "frf_before",
                                                         "frf_after"))  # fmt: skip
        info = dict(model.info)
        self.results = results = {
            "position": h.position,
            "cycles": h.cycles,
            "wear": h.wear,
            "pressure": h.pressure,
            "state": h.state,
            "stick_fraction": h.stick_fraction,
            "converged": h.converged,
            "message": h.message,
            "solves": h.solves,
            "normal_force_sum": h.normal_force_sum,
            "shear": h.shear,
            "peak_pressure": h.peak_pressure,
            "info": info,
            # the sphere's: the pairs' (x, y) (a half model, y >= 0), its radii (m)
            "points": info.get("pair_points"),
            **self._radii(info),
            # the fretting loops (delta, Q) of the first and last records, on the FRF's DOF
            "loops": [h.loop(before["dof"], k) for k in (0, -1)],
            "dof": before["dof"],
            "dof_name": before["dof_name"],
            "frf_hz": before["f_hz"],
            "frf_before": before["amplitude"],
            "frf_after": after["amplitude"],
            "frf_ok": before["converged"] & after["converged"],
        }
        notes = []
        if not results["converged"]:
            notes.append(f"The wear history stopped early: {results['message']}")
        if not results["frf_ok"].all():
            bad = results["frf_hz"][~results["frf_ok"]]
            notes.append(
                "FRF points that did not converge (shown as computed): "
                f"{', '.join(f'{f:.4g}' for f in bad)} Hz"
            )
        self.notes = notes
        self.version += 1

    @staticmethod
    def _radii(info: dict) -> dict[str, float]:
        """The sphere's Hertz radius ``a`` and Mindlin's stick radius ``c`` (0 in gross slip), or none."""
        if "pair_points" not in info:
            return {}
        from fretwear.interface.sphere import mindlin_stick_radius

        a = info["hertz_radius"]
        q = 1.0 if "drive_displacement" in info else info["q_ratio"]  # driven by the arm: gross slip
        return {"hertz_radius": a, "stick_radius": mindlin_stick_radius(a, q)}

    @property
    def sphere(self) -> bool:
        """Whether the published results are of a 3-D patch (the sphere's pairs have points)."""
        return self.results.get("points") is not None

    def _check_export(self, name: str) -> None:
        super()._check_export(name)
        if name in PATCH_FIGURES and not self.sphere:
            raise ValueError(f"{name} is the 3-D patch of the sphere: choose a sphere model to draw it")

    # -- figures -----------------------------------------------------------------------------
    def abscissa(self) -> tuple[np.ndarray, np.ndarray, str]:
        """The profiles' abscissa (mm), the order of the pairs along it and its label: ``x``, or for the
        sphere the distance ``r`` from the centre (pairs sorted by ``r``)."""
        r = self.results
        if not r:
            return np.zeros(0), np.zeros(0, dtype=int), "x (mm)"
        if self.sphere:
            radius = np.hypot(*r["points"].T) * 1e3
            order = np.argsort(radius, kind="stable")
            return radius[order], order, "distance r from the centre (mm)"
        return r["position"] * 1e3, np.arange(len(r["position"])), "x (mm)"

    def records(self) -> np.ndarray:
        """Indices of the history records drawn as profiles: first, last, log-spaced between."""
        n = len(self.results.get("cycles", ()))
        if n == 0:
            return np.zeros(0, dtype=int)
        return np.unique(np.round(np.linspace(0, n - 1, min(PROFILES, n))).astype(int))

    def _profiles(self, name: str) -> dict[str, tuple]:
        """Profiles of ``name`` keyed ``record 1..PROFILES`` (a DynamicMap keeps its layers' labels)."""
        r, empty = self.results, (np.zeros(0), np.zeros(0))
        records = self.records()
        x, order, _ = self.abscissa()
        single = len(x) == 1  # one pair (the paper's model): its value drawn over +-0.5 mm
        return {
            f"record {k + 1}": (
                (x + [-0.5, 0.5], np.repeat(r[name][records[k]], 2))
                if single
                else (x, r[name][records[k]][order])
            )
            if k < len(records)
            else empty
            for k in range(PROFILES)
        }

    def _legend(self) -> dict[str, str]:
        """Legend text of the profiles: their cycle counts."""
        cycles = self.results.get("cycles", ())
        return {f"record {k + 1}": f"N = {cycles[i]:.3g}" for k, i in enumerate(self.records())}

    def _figure_wear_profile(self):
        curves = {k: (x, y * 1e6) for k, (x, y) in self._profiles("wear").items()}
        return figures.line_figure(
            curves,
            xlabel=self.abscissa()[2],
            ylabel="worn depth w (µm)",
            legend_labels=self._legend(),
            title=f"Interface: wear profile w({'r' if self.sphere else 'x'}) at several N",
        )

    def hertz(self) -> tuple[np.ndarray, np.ndarray]:
        """Hertz pressure ``p0 sqrt(1 - (x/a)^2)`` of the benchmark at N = 0 (x in mm, Pa), or empty; for
        the sphere over ``0 <= r <= a`` (``a`` its contact radius)."""
        info = self.results.get("info", {})
        a = info.get("hertz_half_width", info.get("hertz_radius"))  # the cylinder's, the sphere's
        if a is None:
            return np.zeros(0), np.zeros(0)
        p0 = info["hertz_peak_pressure"]
        x = np.linspace(0.0 if self.sphere else -a, a, 201)  # the sphere's profiles are over r >= 0
        return x * 1e3, p0 * np.sqrt(np.clip(1 - (x / a) ** 2, 0, None))

    def _figure_pressure_profile(self):
        curves = self._profiles("pressure")
        curves["Hertz (N = 0)"] = self.hertz()
        curves = {k: (x, y / 1e6) for k, (x, y) in curves.items()}
        return figures.line_figure(
            curves,
            xlabel=self.abscissa()[2],
            ylabel="pressure p, cycle mean (MPa)",
            dashed=["Hertz (N = 0)"],
            legend_labels=self._legend(),
            title=f"Interface: pressure p({'r' if self.sphere else 'x'}) at several N",
        )

    def _figure_stick_slip(self):
        hv = holoviews()
        ensure_backend()
        r = self.results
        ylabel = "x (mm)"
        if r:
            x, order, ylabel = self.abscissa()
            state = np.asarray(r["state"][-1], dtype=float)[order]
            if self.sphere:  # the pairs in the order of r, which repeats: one row each
                x, ylabel = np.arange(len(x), dtype=float), "pairs, in the order of r from the centre"
            phase = np.arange(state.shape[1]) / state.shape[1] * 360.0
            title = f"Interface: stick / slip / open at N = {r['cycles'][-1]:.3g}"
        else:
            state, x, phase, title = (
                np.zeros((2, 2)),
                np.arange(2.0),
                np.arange(2.0),
                "Interface: stick/slip map",
            )
        codes = np.select([state == STICK, state == SLIP, state == OPEN], [0.0, 1.0, 2.0], np.nan)
        mesh = hv.QuadMesh(
            (phase, x, codes),
            [hv.Dimension("phase", label="phase of the cycle (°)"), hv.Dimension("x", label=ylabel)],
            [hv.Dimension("state")],
        )
        mesh = styled(
            mesh,
            {
                "cmap": ["#4c72b0", "#dd8452", "#dddddd"],
                "clim": (-0.5, 2.5),
                "colorbar": True,
                "framewise": True,
            },
            # three states, three colours: the colour bar names them at their colours' middles
            {"tools": ["hover"], "color_levels": 3, "cticks": list(STATE_NAMES),
             "colorbar_opts": {"major_label_overrides": STATE_NAMES}},
            {"color_levels": 3, "cbar_ticks": list(STATE_NAMES.items())},
        )  # fmt: skip
        return overlay_options(
            hv.Overlay([mesh]), title, "phase of the cycle (°)", ylabel, False, False, False
        )

    def _figure_frf(self):
        r = self.results
        empty = (np.zeros(0), np.zeros(0))
        curves = {
            "before wear": (r["frf_hz"], r["frf_before"]) if r else empty,
            "after wear": (r["frf_hz"], r["frf_after"]) if r else empty,
        }
        name = r.get("dof_name", "") if r else ""
        return figures.line_figure(
            curves,
            xlabel="frequency f (Hz)",
            ylabel=f"{name} amplitude, 1st harmonic (m)",
            logy=True,
            vline=self.frequency,
            title=f"Interface: FRF of {name} before/after wear",
        )

    def _figure_loop(self):
        r = self.results
        empty = (np.zeros(0), np.zeros(0))
        names = ("first record", "last record")
        curves = {k: ((d * 1e6, q) if r else empty) for k, (d, q) in zip(names, r.get("loops", [empty] * 2),
                                                                           strict=True)}  # fmt: skip
        labels = {k: f"N = {r['cycles'][i]:.3g}" for k, i in zip(names, (0, -1), strict=True)} if r else {}
        # the cylinder is 2-D: its forces are per unit length of contact
        unit = "N/m" if "hertz_half_width" in r.get("info", {}) else "N"
        name = r.get("dof_name", "") if r else ""
        return figures.line_figure(
            curves,
            xlabel=f"{name} displacement δ (µm)",
            ylabel=f"tangential force Q, whole contact ({unit})",
            legend_labels=labels,
            padding=0.06,
            title=f"Interface: fretting loop Q(δ) of {name}",
        )

    @staticmethod
    def _cycle_state(state: np.ndarray) -> np.ndarray:
        from fretwear.interface.history import cycle_state  # the interface stack loads with a run

        return cycle_state(state)

    def _patch(self, values: np.ndarray | None, zlabel: str, what: str, states: dict | None = None):
        """The 3-D patch seen from above with one value per pair (empty for a model that is not the
        sphere), Hertz's and Mindlin's circles."""
        r = self.results
        if self.sphere and values is not None:
            points, n = r["points"] * 1e3, r["cycles"][-1]
            title = f"Interface: 3-D patch, {what} at N = {n:.3g}"
            circles = {
                "Hertz radius a": r["hertz_radius"] * 1e3,
                "Mindlin stick radius c": r["stick_radius"] * 1e3,
            }
        else:
            points, values = np.array([[0.0, 0.0], [0.1, 0.0], [0.0, 0.1], [0.1, 0.1]]), np.full(4, np.nan)
            title = f"Interface: 3-D patch, {what} (sphere only)"
            circles = {"Hertz radius a": np.nan, "Mindlin stick radius c": np.nan}
        return patch_figure(points, values, zlabel=zlabel, title=title, circles=circles, states=states)

    def _figure_patch_pressure(self):
        r = self.results
        return self._patch(r["pressure"][-1] / 1e6 if r else None, "pressure p, cycle mean (MPa)", "pressure")

    def _figure_patch_shear(self):
        r = self.results
        return self._patch(r["shear"][-1] / 1e6 if r else None, "shear traction |q|, cycle peak (MPa)",
                           "shear")  # fmt: skip

    def _figure_patch_state(self):
        r = self.results
        codes = self._cycle_state(r["state"][-1]) if r else None
        return self._patch(codes, "over the cycle", "stick / slip / open", PATCH_STATES)

    def _figure_patch_wear(self):
        r = self.results
        return self._patch(r["wear"][-1] * 1e6 if r else None, "worn depth w (µm)", "worn depth")

    # -- exports -----------------------------------------------------------------------------
    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        """``profiles``: one row per (record, pair), the CLI's columns; ``frf``: before/after wear."""
        r = self.results
        if not r:
            return {}
        m, nc = r["wear"].shape
        profiles = {
            "cycles": np.repeat(r["cycles"], nc),
            "x": np.tile(r["position"], m),
            "w": r["wear"].ravel(),
            "pressure": r["pressure"].ravel(),
            "state_fraction_stick": r["stick_fraction"].ravel(),
        }
        frf = {
            "f_hz": r["frf_hz"],
            "before": r["frf_before"],
            "after": r["frf_after"],
            "converged": r["frf_ok"],
        }
        (d0, q0), (d1, q1) = r["loops"]
        loop = {
            "sample": np.arange(len(d0)),
            "delta_first": d0,
            "q_first": q0,
            "delta_last": d1,
            "q_last": q1,
        }
        out = {"profiles": profiles, "frf": frf, "loop": loop}
        if self.sphere:  # the 3-D patch at the last record (half model, y >= 0)
            out["patch"] = {
                "x": r["points"][:, 0],
                "y": r["points"][:, 1],
                "w": r["wear"][-1],
                "pressure": r["pressure"][-1],
                "shear_peak": r["shear"][-1],
                "state": self._cycle_state(r["state"][-1]),
            }
        return out

    def csv_header(self) -> str:
        """``#`` lines of a CSV export: the model, the settings and the version."""
        s = self.settings()
        model = s.model if s.model != FILE else f"model file {Path(s.path).name}"
        lines = [
            f"interface model: {model}",
            f"f = {s.frequency:g} Hz, Nh = {s.harmonics}, K_w = {s.kw:g} 1/Pa, N = {s.cycles:g} cycles",
            f"fretwear {version()}",
        ]
        return "".join(f"# {line}\n" for line in lines)


def interface_tab(scene: InterfaceScene, export_card: Callable[[Any], Any]) -> list:
    """The Interface tab: its controls, progress, figures, notes and exports; starts the first run."""
    hv = holoviews()
    model = pn.widgets.RadioButtonGroup(
        options=list(scene.param.model.objects), value=scene.model, variant="outline", color="primary"
    )
    model.link(scene, value="model")
    nodes = pn.widgets.Select(
        label="pairs (benchmark)", options=[16, 32], value=scene.contact_nodes, width=130
    )
    nodes.link(scene, value="contact_nodes")
    # the sphere's 3-D patch: its own row of figures, shown with a sphere model only; its pairs are its mesh's
    patch = figure_grid([])
    boxes = [
        typed_box(scene, name, label)
        for name, label in (
            ("frequency", "f (Hz)"),
            ("harmonics", "Nh"),
            ("kw", "K_w (1/Pa)"),
            ("cycles", "N (cycles)"),
        )
    ]
    status, notes = run_status(scene), message_list(scene, "notes")

    def pane(name: str) -> Any:
        return live_pane(
            partial(lambda n, **_k: scene.figure(n), name), [hv.streams.Params(scene, ["version"])]
        )

    panes = [pane(name) for name in scene.figure_names if name not in PATCH_FIGURES]

    def follow(*_events: Any) -> None:
        sphere = scene.model in SPHERES
        # the patch's figures are drawn only while a sphere is shown (four plots fewer to build and send)
        if sphere and not patch.objects:
            patch.objects = [pane(name) for name in PATCH_FIGURES]
        elif not sphere:
            patch.objects = []
        patch.visible = nodes.disabled = sphere

    scene.param.watch(follow, ["model"])
    follow()
    explanation = pn.pane.Markdown(
        "A contact interface of many node pairs, each with Coulomb friction, unilateral contact and "
        "Archard wear: the worn depth opens the local gap and the pressure redistributes. **Partial slip** "
        "wears only the slip annulus around the stick zone; **gross slip** widens the scar and lowers the "
        "peak pressure. Left: the wear and pressure profiles at several N (dashed: Hertz at N = 0); right: "
        "which pairs stick, slip or open over one cycle, and the FRF before and after wear; then the "
        "fretting loop, tangential force against displacement over one period. The **sphere** (3-D, 29 "
        "pairs of a coarse half mesh, 2-D friction) adds its contact patch seen from above at the last "
        "record: pressure, shear, stick/slip map and worn depth, with Hertz's contact radius a and Mindlin's "
        "stick radius c; its scar is an annulus in partial slip, a disk in gross slip.",
        sizing_mode="stretch_width",
    )
    scene.activate()
    return [
        explanation,
        control_row(model, nodes, *boxes),
        status,
        figure_grid(panes),
        patch,
        notes,
        export_card(scene),
    ]
