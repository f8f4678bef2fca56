"""The Bladed disk scene: the shrouded disk of :func:`fretwear.bladed_disk`, its friction and its wear.

The 24-sector lumped disk (Laxalde et al.) with a Jenkins shroud contact
between neighbouring blade tips, under a travelling wave of engine order EO.
One run is five tasks of the session's machinery (:class:`~app.session.Runner`,
:class:`~app.state.Tasks`), each keyed by the backend call it caches: the model
(:meth:`~app.backend.Backend.disk_model`), the blade-tip FRF before wear
(:meth:`~app.backend.Backend.disk_frf`), the wear of every shroud contact at the
chosen frequency (:meth:`~app.backend.Backend.disk_history`), and the FRF and
the response at that frequency after wear. A tuned disk is solved on one
sector (cyclic symmetry, ``fretwear.disk.cyclic``); a mistuned one (level >
0, a seeded pattern) as a whole. The figures: the disk seen from the front
(blades displaced by the response at the chosen phase, magnified; tips
coloured by worn depth), the ZZENF diagram (frequency against nodal diameter,
the excitation marked), the largest blade-tip amplitude before and after wear,
and the worn depth of every contact at several N. Harmonic balance with DLFT
(Jenkins contacts) is an approximation: its truncation error at the chosen Nh
is what ``benchmarks/bench_disk_exact.py`` measures against the exact dynamics.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import partial
from typing import Any

import numpy as np
import panel as pn
import param

from fretwear import figures
from fretwear.figures.plots import ensure_backend, holoviews, overlay_options, styled
from fretwear.figures.record import version
from fretwear.model import DiskSector

from ..backend import DiskSpec, Failure, Grid
from ..live import control_row, figure_grid, live_pane, message_list, run_status, typed_box
from ..session import Runner
from ..state import ResultOf, Task, Tasks, WearAfter, whole
from .base import Addressed, Exports, OwnSettings

__all__ = ["DiskScene", "DiskSettings", "disk_tab", "PROFILES"]

#: records of the wear history drawn as profiles over the blades (first, last, evenly between)
PROFILES = 4
#: the tab's sliders: parameter, label, (low, high, step)
SLIDERS = (
    ("engine_order", "EO", (0, 12, 1)),
    ("fex", "F_ex (N)", (0.5, 10.0, 0.1)),
    ("mu", "mu", (0.05, 1.0, 0.01)),
    ("level", "mistuning level", (0.0, 0.1, 0.0025)),
)
#: displacement magnification of the drawing, as a fraction of the blade length per largest amplitude
DRAWN_SWING = 0.25


@dataclass(frozen=True)
class DiskSettings:
    """What one run of the Bladed disk scene computes (SI units, frequencies in Hz)."""

    engine_order: int = 3
    fex: float = 2.0
    mu: float = 0.3
    level: float = 0.0
    seed: int = 0
    frequency: float = 205.0
    harmonics: int = 5
    kw: float = 1e-8
    cycles: float = 1e6
    fmin: float = 190.0
    fmax: float = 215.0
    n_frequencies: int = 26
    sectors: int = 24

    def problems(self) -> list[str]:
        """Invalid values, one line each naming the setting and its valid range."""
        out = []
        bounds = (("fex", 0.0, 1e3, "N"), ("mu", 0.0, 10.0, ""), ("kw", 0.0, 1e-4, "1/N"),
                  ("cycles", 0.0, 1e12, "cycles"), ("frequency", 0.0, 1e5, "Hz"))  # fmt: skip
        for name, low, high, unit in bounds:
            v = getattr(self, name)
            if not (isinstance(v, (int, float)) and np.isfinite(v) and low < v <= high):
                out.append(
                    f"{name} must be a number > {low:g} and <= {high:g} {unit}".rstrip() + f", got {v!r}"
                )
        if not (isinstance(self.level, (int, float)) and 0 <= self.level <= 0.5):
            out.append(
                f"level must be a number in [0, 0.5] (the blades' standard deviation), got {self.level!r}"
            )
        if not whole(self.engine_order, 0, self.sectors // 2):
            out.append(
                f"engine_order must be an integer in [0, {self.sectors // 2}], got {self.engine_order!r}"
            )
        if not whole(self.harmonics, 1, 15):
            out.append(f"harmonics must be an integer in [1, 15], got {self.harmonics!r}")
        if not whole(self.seed, 0, 2**32 - 1):
            out.append(f"seed must be an integer in [0, 2^32), got {self.seed!r}")
        return out

    def spec(self) -> DiskSpec:
        """The model of the settings, as the backend builds it (its cache key)."""
        return DiskSpec(self.sectors, self.engine_order, self.fex, self.mu, self.level, self.seed)

    def tasks(self, tasks: Tasks) -> list[Task]:
        """The run's tasks: the model, the FRF before wear, the wear history, the FRF and the response at
        the chosen frequency after wear."""
        b = tasks.backend
        model = tasks.call("disk_model", "the bladed disk", 0.1, b.disk_model, self.spec())
        disk = ResultOf.of(model)
        grid = Grid(self.fmin, self.fmax, self.n_frequencies)
        before = tasks.call(
            "frf_before", "the FRF before wear", 1.0, b.disk_frf, disk, grid, self.harmonics, None
        )
        history = tasks.call("disk_history", f"the wear history to N = {self.cycles:g}", 1.5, b.disk_history,
                             disk, self.frequency, self.harmonics, self.kw, self.cycles)  # fmt: skip
        worn = WearAfter.of(history, self.cycles)
        after = tasks.call(
            "frf_after", "the FRF after wear", 1.0, b.disk_frf, disk, grid, self.harmonics, worn
        )
        point = tasks.call("point_after", "the response after wear", 0.1, b.disk_frf, disk,
                           Grid(self.frequency, self.frequency, 1), self.harmonics, worn)  # fmt: skip
        return [model, before, history, after, point]


class DiskScene(Addressed, OwnSettings, Exports, Runner):
    """The Bladed disk tab's state: its settings, the run in progress and the published results.

    ``options``: ``tasks``, ``executor``, ``dispatch`` of :class:`~app.scenes.base.OwnSettings`, and
    values of the parameters.
    """

    key = "disk"
    title = "Bladed disk"
    address_params = ("engine_order", "fex", "mu", "kw", "level", "seed", "frequency", "cycles")
    figure_names = ("disk", "zzenf", "frf", "wear")
    dataset_names = ("frf", "wear")

    engine_order = param.Integer(3, bounds=(0, 12), doc="Engine order EO of the travelling-wave excitation")
    fex = param.Number(2.0, doc="Force on every blade tip (N)")
    mu = param.Number(0.3, doc="Friction coefficient of the shroud contacts")
    kw = param.Number(1e-8, doc="Archard coefficient (1/N)")
    level = param.Number(0.0, doc="Mistuning level: standard deviation of the blade stiffnesses (0: tuned)")
    seed = param.Integer(0, doc="Seed of the mistuning pattern")
    frequency = param.Number(205.0, doc="Frequency of the wear history (Hz)")
    cycles = param.Number(1e6, doc="Wear horizon (cycles)")
    phase = param.Number(0.0, bounds=(0.0, 360.0), doc="Phase of the cycle drawn (degrees)")
    typed = param.Dict({}, doc="Texts typed into the boxes that are not numbers, by setting")
    notes = param.List([])
    version = param.Integer(0)

    def __init__(self, **options: Any) -> None:
        super().__init__(**options)
        self.param.watch(
            self.refresh, ["engine_order", "fex", "mu", "kw", "level", "seed", "frequency", "cycles", "typed"]
        )

    def settings(self) -> DiskSettings:
        """The settings of the controls."""
        return DiskSettings(
            engine_order=int(self.engine_order), fex=float(self.fex), mu=float(self.mu),
            level=float(self.level), seed=int(self.seed), frequency=float(self.frequency), kw=float(self.kw),
            cycles=float(self.cycles),
        )  # fmt: skip

    def _publish_results(self, results: dict[str, Any], final: bool) -> None:
        if not final:
            return
        failed = next((r for r in results.values() if isinstance(r, Failure)), None)
        if failed is not None:
            self.error = f"The bladed disk run failed: {failed.reason}"
            return
        model, before, h, after, point = (results[k] for k in ("disk_model", "frf_before", "disk_history",
                                                                "frf_after", "point_after"))  # fmt: skip
        self.results = {
            "info": dict(model.info),
            "u0": model.friction[0].u0,
            "f_hz": before["f_hz"],
            "before": before["tips"],
            "after": after["tips"],
            "frf_ok": before["converged"] & after["converged"],
            "solved_on": before["solved_on"],
            "cycles": h.cycles,
            "wear": h.wear,
            "converged": h.converged,
            "status": h.status,
            "label": h.label,
            "tip_harmonics": point["tip_harmonics"][0],
        }
        notes = [f"{h.label} (harmonic balance, an approximation); the FRFs are solved on "
                 f"{before['solved_on']}."]  # fmt: skip
        if not h.converged:
            notes.append(f"The wear history stopped early ({h.status}).")
        if not self.results["frf_ok"].all():
            bad = self.results["f_hz"][~self.results["frf_ok"]]
            notes.append(f"FRF points that did not converge: {', '.join(f'{f:.4g}' for f in bad)} Hz")
        self.notes = notes
        self.version += 1

    # -- figures -----------------------------------------------------------------------------
    def _figure_disk(self):
        hv = holoviews()
        ensure_backend()
        r = self.results
        n = int(r["info"]["sectors"]) if r else 24
        angle = 2 * np.pi * np.arange(n) / n
        root, tip = 1.0, 1.8
        if r:
            coeffs = r["tip_harmonics"]  # (N, 2 Nh + 1)
            nh = (coeffs.shape[1] - 1) // 2
            t = np.deg2rad(self.phase) * np.arange(1, nh + 1)
            u = coeffs[:, 0] + coeffs[:, 1::2] @ np.cos(t) + coeffs[:, 2::2] @ np.sin(t)
            scale = DRAWN_SWING * (tip - root) / max(np.abs(coeffs).max(), 1e-300)
            worn = r["wear"][-1] / r["u0"]
        else:
            u, scale, worn = np.zeros(n), 0.0, np.zeros(n)
        # a blade's tip moves tangentially by its displacement, magnified
        tx = tip * np.cos(angle) - scale * u * np.sin(angle)
        ty = tip * np.sin(angle) + scale * u * np.cos(angle)
        blades = hv.Segments((root * np.cos(angle), root * np.sin(angle), tx, ty), ["x0", "y0", "x1", "y1"])
        shroud = hv.Segments((tx, ty, np.roll(tx, -1), np.roll(ty, -1)), ["x0", "y0", "x1", "y1"])
        ring = hv.Ellipse(0, 0, 2 * root)
        w_dim = hv.Dimension("w", label="worn depth w / u₀ of contact i to i + 1")
        tips = hv.Points({"x": tx, "y": ty, "w": worn, "blade": np.arange(n)}, ["x", "y"], [w_dim, "blade"])
        common = {"color": hv.dim("w"), "cmap": "viridis", "clim": (0.0, 1.0), "colorbar": True}
        tips = styled(tips, common, {"size": 9, "tools": ["hover"]}, {"s": 40})
        title = short = "Bladed disk"
        if r:
            title = f"Bladed disk: tips coloured by worn depth w/u₀ at N = {r['cycles'][-1]:.3g}"
            short = f"Bladed disk: tip wear w/u₀ at N = {r['cycles'][-1]:.3g}"
        layers = hv.Overlay([ring, blades, shroud, tips])
        overlay = overlay_options(layers, title, "x", "y", False, False, False, padding=0.05)
        # a square drawing leaves the title the drawing's width: a shorter one in the static export
        return styled(overlay, {"data_aspect": 1.0, "xaxis": None, "yaxis": None}, {}, {"title": short})

    def _figure_zzenf(self):
        s = self.settings()
        zz = DiskSector(s.sectors).zzenf()
        nd = np.arange(len(zz))
        curves = {f"family {j + 1}": (nd, zz[:, j]) for j in range(3)}
        eo = s.engine_order % s.sectors
        eo = min(eo, s.sectors - eo)
        return figures.line_figure(
            curves,
            xlabel="nodal diameter",
            ylabel="natural frequency (Hz)",
            logy=True,
            vline=eo,
            point=(eo, s.frequency),
            title="Bladed disk: ZZENF diagram (no contacts), EO and f marked",
        )

    def _figure_frf(self):
        r, empty = self.results, (np.zeros(0), np.zeros(0))
        curves = {
            "before wear": (r["f_hz"], r["before"].max(axis=1)) if r else empty,
            "after wear": (r["f_hz"], r["after"].max(axis=1)) if r else empty,
        }
        return figures.line_figure(
            curves,
            xlabel="frequency f (Hz)",
            ylabel="largest blade-tip amplitude, 1st harmonic (m)",
            logy=True,
            vline=self.frequency,
            title="Bladed disk: largest blade-tip amplitude before/after wear",
        )

    def records(self) -> np.ndarray:
        """Indices of the history records drawn: first, last, evenly between."""
        n = len(self.results.get("cycles", ()))
        return (
            np.unique(np.round(np.linspace(0, n - 1, min(PROFILES, n))).astype(int))
            if n
            else np.zeros(0, int)
        )

    def _figure_wear(self):
        r = self.results
        records = self.records()
        curves, labels = {}, {}
        for k in range(PROFILES):
            if k < len(records):
                i = records[k]
                curves[f"record {k + 1}"] = (np.arange(r["wear"].shape[1]), r["wear"][i] / r["u0"])
                labels[f"record {k + 1}"] = f"N = {r['cycles'][i]:.3g}"
            else:
                curves[f"record {k + 1}"] = (np.zeros(0), np.zeros(0))
        return figures.line_figure(
            curves,
            xlabel="shroud contact (blade i to i + 1)",
            ylabel="worn depth w / u0",
            legend_labels=labels,
            title="Bladed disk: worn depth of every contact at several N",
        )

    # -- exports -----------------------------------------------------------------------------
    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        """``frf``: every blade tip before and after wear; ``wear``: a row per record, a column per pair."""
        r = self.results
        if not r:
            return {}
        frf = {"f_hz": r["f_hz"], "converged": r["frf_ok"]}
        for i in range(r["before"].shape[1]):
            frf[f"tip{i}_before_m"] = r["before"][:, i]
            frf[f"tip{i}_after_m"] = r["after"][:, i]
        wear = {"cycles": r["cycles"], **{f"w{i}_m": r["wear"][:, i] for i in range(r["wear"].shape[1])}}
        return {"frf": frf, "wear": wear}

    def csv_header(self) -> str:
        """``#`` lines of a CSV export: the model, the settings and the version."""
        s = self.settings()
        tuned = "tuned" if s.level == 0 else f"mistuned (level {s.level:g}, seed {s.seed})"
        lines = [
            f"bladed disk: {s.sectors} sectors, shroud of Jenkins contacts, {tuned}, EO {s.engine_order}",
            f"F_ex = {s.fex:g} N, mu = {s.mu:g}, f = {s.frequency:g} Hz, Nh = {s.harmonics} (DLFT, an "
            f"approximation), K_w = {s.kw:g} 1/N, N = {s.cycles:g} cycles",
            f"fretwear {version()}",
        ]
        return "".join(f"# {line}\n" for line in lines)


def disk_tab(scene: DiskScene, export_card: Callable[[Any], Any]) -> list:
    """The Bladed disk tab: its controls, progress, figures, notes and exports; starts the first run."""
    hv = holoviews()
    boxes = []
    # sliders for what a class explores (a run when released), boxes for the rest
    for name, label, (low, high, step) in SLIDERS:
        kind = pn.widgets.IntSlider if name == "engine_order" else pn.widgets.EditableFloatSlider
        slider = kind(name=label, start=low, end=high, step=step, value=getattr(scene, name), width=170)
        slider.param.watch(partial(lambda n, event: setattr(scene, n, event.new), name), "value_throttled")
        boxes.append(slider)
    log_kw = pn.widgets.EditableFloatSlider(name="log10 k_w (1/N)", start=-10.0, end=-5.0, step=0.1,
                                            value=float(np.log10(scene.kw)), width=170)  # fmt: skip
    log_kw.param.watch(lambda event: setattr(scene, "kw", float(10**event.new)), "value_throttled")
    boxes.append(log_kw)
    boxes += [typed_box(scene, name, label) for name, label in (("seed", "seed"), ("frequency", "f (Hz)"),
                                                                ("cycles", "N (cycles)"))]  # fmt: skip
    phase = pn.widgets.Player(name="phase (°)", start=0, end=350, step=10, value=0, interval=60,
                              loop_policy="loop", width=300)  # fmt: skip
    phase.link(scene, value="phase")
    status, notes = run_status(scene), message_list(scene, "notes")
    streams = {"disk": ["version", "phase"], "zzenf": ["version", "engine_order", "frequency"]}
    panes = [
        live_pane(
            partial(lambda n, **_k: scene.figure(n), name),
            [hv.streams.Params(scene, streams.get(name, ["version"]))],
        )  # fmt: skip
        for name in scene.figure_names
    ]
    explanation = pn.pane.Markdown(
        "The lumped 24-sector bladed disk (Laxalde et al.) with a **shroud**: a Jenkins friction contact "
        "between neighbouring blade tips, its normal load relaxing as it wears. A travelling wave of engine "
        "order EO excites every tip. A **tuned** disk is solved on one sector (cyclic symmetry) and wears "
        "every contact alike; a **mistuned** disk (level > 0) localises the response and the wear on a few "
        "blades. Play the phase to see the travelling wave (displacements magnified).",
        sizing_mode="stretch_width",
    )
    scene.activate()
    return [
        explanation,
        control_row(*boxes),
        phase,
        status,
        figure_grid(panes),
        notes,
        export_card(scene),
    ]
