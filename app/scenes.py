"""The scenes: what each computes (:meth:`Scene.needs`), draws, explains and exports.

A scene draws only what its session published into it (:meth:`Scene.publish`):
results, the settings and the selected point they belong to. Its figures keep
the same layers whatever the state (empty data while nothing is computed), as
the dashboard's ``DynamicMap`` objects require. Figures come from the builders
of :mod:`fretwear.figures`, which also renders them to PNG, SVG and HTML with
their parameter record (:meth:`Scene.record`).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, ClassVar

import numpy as np
import param

import fretwear
from fretwear import figures
from fretwear.figures.record import caption, csv_header
from fretwear.figures.sketch import STATE_NAMES, model_sketch, sketch_scale
from fretwear.hbm.harmonics import default_samples
from fretwear.studies.accuracy import QUANTITIES, CostStudy, Rung
from fretwear.wear.polynomial import BASES

from .backend import Failure
from .glossary import term
from .state import (
    CONVERGENCE_HARMONICS,
    EXACT,
    EXACT_MAP,
    EXACT_POINT,
    LADDERS,
    METHODS,
    Controls,
    Settings,
    Task,
    Tasks,
)

if TYPE_CHECKING:
    import holoviews as hv

__all__ = ["Selection", "Scene", "SCENES", "sidebar_equivalent", "ANIMATION_FRAMES"]

HZ = "frequency f (Hz)"
X1 = "x₁ amplitude, first harmonic (m)"
WEAR = "w / u₀"
CYCLES = "cycles N"
EMPTY = (np.zeros(0), np.zeros(0))
#: frames of the animation of one period (the cycle scene)
ANIMATION_FRAMES = 32


@dataclass(frozen=True)
class Selection:
    """The point picked on the wear map: frequency (Hz) and cycle count."""

    frequency: float
    cycles: float


def _ok(value: Any) -> Any:
    """``value``, or ``None`` for a missing or failed result."""
    return None if value is None or isinstance(value, Failure) else value


def _failure_note(name: str, value: Any) -> list[str]:
    return [f"{name}: {value}"] if isinstance(value, Failure) else []


def _history_notes(histories: list, limit: int = 4) -> list[str]:
    """Notes on wear histories: where each stopped early or warned, and where one overshoots ``u0``.

    Each note names its frequency; past ``limit`` notes the rest are counted.
    """
    notes = [
        f"{h.frequency:.4g} Hz ({h.label}): stopped early, {h.status}" for h in histories if not h.converged
    ]
    notes += [f"{h.frequency:.4g} Hz ({h.label}): {w}" for h in histories for w in h.warnings]
    worst = max(histories, key=lambda h: np.nanmax(h.wear_fraction), default=None)
    if worst is not None and np.nanmax(worst.wear_fraction) > 1:
        k = int(np.nanargmax(worst.wear_fraction[:, 0]))
        notes.insert(
            0,
            f"w / u₀ reaches {worst.wear_fraction[k, 0]:.3g} > 1 at {worst.frequency:.4g} Hz, "
            f"N = {worst.cycles[k]:.3g} ({worst.label}): past u₀ the contact is unloaded and stops "
            "wearing, so the excess is the method's error (the colour scale extends to show it)",
        )
    if len(notes) > limit:
        notes = [*notes[:limit], f"and {len(notes) - limit} more notes (the CSV export has every history)"]
    return notes


def _error_note(h, reference, label: str | None = None) -> str | None:
    """How far the approximation ``h`` (named ``label``, default its own) is from the exact ``reference``
    (None for the exact answer itself, or while either computes)."""
    if h is None or reference is None or h.label == "exact":
        return None
    return h.error_note(reference, label=label)


def _relative(value: float, reference: float) -> str:
    """``value`` against ``reference`` as a signed percentage (in words when the reference is 0)."""
    if reference == 0:
        return "0 (exact 0)" if value == 0 else f"{value:.3g} (exact 0)"
    return f"{value / reference - 1:+.1%}"


def _exact_map(scene: Scene, wm) -> Any:
    """The published exact wear map when it has the grids of ``wm`` (None while it computes, or failed)."""
    exact = _ok(scene.results.get(EXACT_MAP))
    if exact is None or wm is None or exact.wear.shape != wm.wear.shape:
        return None
    return exact if np.allclose(exact.frequency, wm.frequency, rtol=1e-9) else None


def _band_error(wm, exact) -> str | None:
    """How far the cycles to 0.5 u0 of map ``wm`` are from the exact map's, over the band."""
    if wm is None or exact is None or wm.label == "exact":
        return None
    note = wm.error_note(exact)
    return None if note is None else f"{note} Exact contours dashed."


class Scene(param.Parameterized):
    """One tab of the dashboard. Subclasses set the class attributes and the ``_figure_*`` methods."""

    key: ClassVar[str]
    title: ClassVar[str]
    explanation: ClassVar[str]
    figure_names: ClassVar[tuple[str, ...]]
    dataset_names: ClassVar[tuple[str, ...]]
    uses_selection: ClassVar[bool] = False
    #: whether the scene's results depend on wear (its record has k_w, the method and its options)
    wears: ClassVar[bool] = True
    #: parameters of the scene that change what it computes (the session refreshes when they change)
    inputs: ClassVar[tuple[str, ...]] = ()

    version = param.Integer(0, doc="Incremented at each publish: the figures redraw")
    notes = param.List([], doc="Messages about the published results (failures, warnings)")
    findings = param.List([], doc="What the published results show (e.g. an error against the exact answer)")

    def __init__(self, tasks: Tasks, **params: Any) -> None:
        super().__init__(**params)
        self.tasks = tasks
        self.results: dict[str, Any] = {}
        self.settings: Settings = Controls().settings()
        self.selection = Selection(0.7, 1e4)

    # -- what to compute ----------------------------------------------------------------
    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        """The tasks whose results this scene draws, for settings ``s`` and selection ``sel``."""
        raise NotImplementedError

    def publish(self, results: dict[str, Any], s: Settings, sel: Selection) -> None:
        """Show ``results`` computed for ``s`` and ``sel``: the figures redraw."""
        self.results, self.settings, self.selection = results, s, sel
        self.redraw()

    def redraw(self) -> None:
        """Redraw the published results (after a change of how they are shown)."""
        self.notes = [
            n for name, value in self.results.items() for n in _failure_note(name, value)
        ] + self._notes()
        self.findings = self._findings()
        self.version += 1

    def _notes(self) -> list[str]:
        return []

    def _findings(self) -> list[str]:
        return []

    # -- what to show ---------------------------------------------------------------------
    def figure(self, name: str, live: bool = False) -> hv.Overlay:
        """Figure ``name`` of the published results, as a HoloViews overlay.

        ``live``: as the page shows it (with what only the page has, e.g. the
        animation's cursor); exports draw the figure without it.
        """
        if name not in self.figure_names:
            raise ValueError(f"scene {self.key!r} has no figure {name!r}; it has {self.figure_names}")
        return getattr(self, f"_figure_{name}")(**({"live": True} if live and self.live else {}))

    #: whether the page's figures have more than the exported ones (``_figure_*`` take ``live``)
    live: ClassVar[bool] = False

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        """Tables (column name -> values) of the published results, by name."""
        return {}

    def record(self) -> dict[str, Any]:
        """The parameter record of the published results (settings record keys, see
        :mod:`fretwear.figures.record`): what every export of this scene is stamped with."""
        out = self.settings.record(wear=self.wears)
        if self.uses_selection:
            out["f"] = self.selection.frequency
            if self.wears:
                out["N"] = self.selection.cycles
        return out

    # -- export ---------------------------------------------------------------------------
    def filename(self, name: str, fmt: str) -> str:
        """Download file name of figure or dataset ``name``."""
        return f"fretwear_{self.key}_{name}.{fmt}"

    def export_figure(self, name: str, fmt: str, options: figures.ExportOptions | None = None) -> bytes:
        """Figure ``name`` as ``png``, ``svg`` or standalone ``html`` bytes, with its parameter record
        as a caption; ``options``: size, resolution, font size."""
        if fmt not in figures.FIGURE_FORMATS:
            raise ValueError(f"fmt must be one of {figures.FIGURE_FORMATS}, got {fmt!r}")
        if not self.results:
            raise ValueError(f"nothing to export yet: the {self.title} scene has not been computed")
        figures.load_backend("bokeh" if fmt == "html" else "matplotlib")
        record = self.record()
        return figures.figure_bytes(
            self.figure(name),
            fmt,
            title=f"fretwear: {self.title}, {name}",
            options=options,
            caption=lambda markup: caption(record, markup=markup),
        )

    def export_csv(self, name: str) -> str:
        """Dataset ``name`` as CSV text, after its parameter record (``#`` lines)."""
        tables = self.datasets()
        if name not in tables:
            raise ValueError(f"no dataset {name!r} in scene {self.key!r} (yet); available: {sorted(tables)}")
        return figures.csv_text(tables[name], csv_header(self.record()))


def _linear_curves(scene: Scene) -> dict[str, tuple]:
    out = {}
    for state in ("stuck", "open"):
        lin = _ok(scene.results.get(f"linear_{state}"))
        out[f"{state} (linear)"] = EMPTY if lin is None else (lin["f_hz"], np.abs(lin["amplitude"][:, 0]))
    return out


def _linear_table(scene: Scene) -> dict[str, dict[str, np.ndarray]]:
    stuck, free = (_ok(scene.results.get(f"linear_{s}")) for s in ("stuck", "open"))
    if stuck is None or free is None or len(stuck["f_hz"]) != len(free["f_hz"]):
        return {}
    table = {"f_hz": stuck["f_hz"]}
    for label, lin in (("stuck", stuck), ("open", free)):
        u = lin["amplitude"]
        table |= {f"x{i + 1}_{label}": np.abs(u[:, i]) for i in range(u.shape[1])}
    return {"linear_frf": table}


def _no_wear(scene: Scene) -> tuple:
    """``(f, x1)`` of the nonlinear FRF without wear (HBM + DLFT sweep), whatever the slow-time method."""
    frf = _ok(scene.results.get("frf"))
    return EMPTY if frf is None else (frf["f_hz"], frf["amplitude"][:, 0])


class RegimesScene(Scene):
    key = "regimes"
    title = "Regimes"
    figure_names = ("frf", "regime_map")
    dataset_names = ("nonlinear_frf", "linear_frf", "regime_map", "stick_boundary")
    wears = False
    explanation = f"""
**What you see.** Left: the response of mass 1 with the contact stuck and with it open (linear,
dashed), and the nonlinear response without wear ({term("DLFT", "HBM + DLFT")}). Right: the fraction
of the period the contact slips, over frequency and the load ratio
{term("r", "r = F<sub>ex</sub> / (μ F<sub>N</sub>)")};
the red line is the exact stick boundary (below it the contact never slips, so it never wears), the
white line separates mostly stuck from mostly slipping periods, the dashed line is the current r.

**Try.** Move {term("F_ex")}: the dashed line moves and the nonlinear FRF leaves the stuck curve where
the line crosses the stick boundary. Raise {term("Nh")} to sharpen the stick-slip transitions."""

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        t = self.tasks
        return [t.linear(s, "stuck"), t.linear(s, "open"), t.frf(s), t.regime(s)]

    def _notes(self) -> list[str]:
        frf = _ok(self.results.get("frf"))
        if frf is not None and not frf["converged"].all():
            bad = int((~frf["converged"]).sum())
            return [f"{bad} of {len(frf['converged'])} FRF points did not converge (shown as computed)"]
        return []

    def _figure_frf(self):
        curves = _linear_curves(self)
        curves["nonlinear, no wear"] = _no_wear(self)
        return figures.line_figure(
            curves,
            xlabel=HZ,
            ylabel=X1,
            logy=True,
            dashed=list(curves)[:2],
            title=f"FRF of mass 1, Fₑₓ = {self.settings.model.fex:g} N",
        )

    def _figure_regime_map(self):
        s = self.settings
        reg = _ok(self.results.get("regime"))
        f, ratios = (s.frequencies, s.ratios) if reg is None else (reg["f_hz"], reg["ratios"])
        z = np.zeros((len(ratios), len(f))) if reg is None else reg["slip_fraction"]
        boundary = (
            EMPTY
            if reg is None
            else (f, np.where(reg["stick_limit"] <= ratios[-1], reg["stick_limit"], np.nan))
        )
        return figures.map_figure(
            f,
            ratios,
            z,
            xlabel=HZ,
            ylabel="r = Fₑₓ / (μ Fₙ)",
            zlabel="slip fraction of the period",
            clim=(0, 1),
            levels=(0.5,),
            cmap="magma",
            curves={"stick boundary": boundary},
            hline=s.model.r,
            title=f"Stick/slip regimes (current r = {s.model.r:.3g})",
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        out = _linear_table(self)
        frf = _ok(self.results.get("frf"))
        if frf is not None:
            table = {"f_hz": frf["f_hz"]}
            for i in range(frf["amplitude"].shape[1]):
                table[f"x{i + 1}_h1"] = frf["amplitude"][:, i]
            table |= {
                "xr_h1": frf["relative_amplitude"][:, 0],
                "sliding_distance": frf["sliding_distance"][:, 0],
                "friction_energy": frf["friction_energy"][:, 0],
                "converged": frf["converged"],
            }
            out["nonlinear_frf"] = table
        reg = _ok(self.results.get("regime"))
        if reg is not None:
            f, r = np.meshgrid(reg["f_hz"], reg["ratios"])
            out["regime_map"] = {
                "f_hz": f.ravel(),
                "r": r.ravel(),
                "slip_fraction": reg["slip_fraction"].ravel(),
                "sliding_distance": reg["sliding_distance"].ravel(),
                "x1_h1": reg["amplitude"].ravel(),
            }
            out["stick_boundary"] = {"f_hz": reg["f_hz"], "r_stick": reg["stick_limit"]}
        return out


class WearMapScene(Scene):
    key = "wearmap"
    title = "Wear map"
    figure_names = ("wear_map", "history", "pseudo_frf")
    dataset_names = ("wear_map", "history", "pseudo_frf")
    uses_selection = True
    explanation = f"""
**What you see.** The {term("wear map")}: the worn depth w / {term("u0")} over frequency and the number
of cycles {term("N")} (log scale), by the selected {term("method", "slow-time method")} (exact: no
slow-time error), with contours at 10, 50 and 90 %. Hover for values. **Click a point**: beside and
below, the wear history w(N) at that frequency, with the exact answer dashed (Archard's law on the
exact event-driven dynamics: no harmonic truncation) and the selected method's error against it in the
findings below, and the {term("pseudo-FRF")} of mass 1 at that cycle count, next to the response without wear.

**Try.** Click inside the worn band, then near its edges: wear starts where the contact slips and
spreads as the normal load relaxes. Raise {term("k_w")} to wear faster (only N k<sub>w</sub> matters).
Change {term("Nh")} and watch the finding below: what more harmonics buy, and what they cost."""

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        near = float(s.frequencies[np.argmin(np.abs(s.frequencies - sel.frequency))])  # a row of the map
        t = self.tasks
        return [t.frf(s), t.wear_map(s), t.exact_history(s, near), t.exact_wear_map(s)]

    def _map(self):
        return _ok(self.results.get("wear_map"))

    def _index(self) -> int:
        wm = self._map()
        grid = self.settings.frequencies if wm is None else wm.frequency
        return int(np.argmin(np.abs(grid - self.selection.frequency)))

    def _notes(self) -> list[str]:
        wm = self._map()
        return [] if wm is None else _history_notes(wm.histories)

    def _findings(self) -> list[str]:
        error = _error_note(self._history(), self._exact())
        wm = self._map()
        exact = _exact_map(self, wm)
        if not (self._band[0] is wm and self._band[1] is exact):  # needs every history: once per map
            self._band = (wm, exact, _band_error(wm, exact))
        return [text for text in (error, self._band[2]) if text]

    _band: tuple = (None, None, None)

    def _exact(self):
        """The exact wear history at the selected row of the map (None while it computes, or failed)."""
        h, wm = _ok(self.results.get(EXACT)), self._map()
        if h is None or wm is None or not np.isclose(h.frequency, wm.frequency[self._index()], rtol=1e-9):
            return None
        return h

    def _figure_wear_map(self):
        s, wm, sel = self.settings, self._map(), self.selection
        f, cycles = (s.frequencies, s.cycles) if wm is None else (wm.frequency, wm.cycles)
        z = np.zeros((len(f), len(cycles))) if wm is None else wm.wear_fraction[:, :, 0]
        exact = _exact_map(self, wm)
        reference = None if exact is None else exact.wear_fraction[:, :, 0]
        title = f"Wear map ({s.label()}, wear coefficient {s.kw:.3g} 1/N)"
        return figures.wear_map_figure(
            f, cycles, z, title=title, point=(sel.frequency, sel.cycles), reference=reference
        )

    def _history(self):
        wm = self._map()
        return None if wm is None else wm.histories[self._index()]

    def _figure_history(self):
        h, sel, exact = self._history(), self.selection, self._exact()
        curve, point = EMPTY, (np.nan, np.nan)
        if h is not None:
            curve = figures.wear_curve(h, self.settings.dense_cycles)
            point = (sel.cycles, float(h.at([sel.cycles])["wear"][0, 0] / h.u0[0]))
        reference = EMPTY if exact is None else figures.wear_curve(exact, self.settings.dense_cycles)
        f = np.nan if h is None else h.frequency
        title = f"Wear history at {f:.4g} Hz"
        if h is not None and not np.isclose(f, sel.frequency, rtol=1e-9):
            title += f" (the map's frequency nearest to f = {sel.frequency:.4g} Hz)"
        return figures.line_figure(
            {"wear history": curve, EXACT: reference},
            xlabel=CYCLES,
            ylabel=WEAR,
            logx=True,
            dashed=(EXACT,),
            point=point,
            padding=0.05,
            title=title,
        )

    def _pseudo(self) -> np.ndarray | None:
        wm = self._map()
        return None if wm is None else wm.pseudo_frf([self.selection.cycles])[0, :, 0]

    def _figure_pseudo_frf(self):
        wm, sel, p = self._map(), self.selection, self._pseudo()
        curves = {"no wear": _no_wear(self), "selected N": EMPTY if p is None else (wm.frequency, p)}
        return figures.line_figure(
            curves,
            xlabel=HZ,
            ylabel=X1,
            logy=True,
            vline=sel.frequency,
            title=f"Pseudo-FRF of mass 1 at N = {sel.cycles:.3g}",
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        wm, h, p = self._map(), self._history(), self._pseudo()
        if wm is None:
            return {}
        table = wm.long_table()
        exact = _exact_map(self, wm)
        if exact is not None:  # same grids, same row order
            table["w_exact_over_u0"] = exact.long_table()["w_over_u0"]
        out = {
            "wear_map": table,
            "history": {
                "cycles": h.cycles,
                "w": h.wear[:, 0],
                "w_over_u0": h.wear_fraction[:, 0],
                "normal_load": h.normal_load[:, 0],
                "rate": h.rate[:, 0],
                "x1_h1": h.amplitude[:, 0],
                "xr_half_p2p": h.relative_half_peak_to_peak[:, 0],
                "w_exact_over_u0": (
                    np.full(len(h.cycles), np.nan)
                    if (exact := self._exact()) is None
                    else exact.at(h.cycles)["wear"][:, 0] / exact.u0[0]
                ),
            },
            "pseudo_frf": {
                "f_hz": wm.frequency,
                "x1_h1_selected": p,
                "selected_cycles": np.full(len(wm.frequency), self.selection.cycles),
            },
        }
        return out


class EvolutionScene(Scene):
    key = "evolution"
    title = "FRF evolution"
    figure_names = ("evolution",)
    dataset_names = ("pseudo_frfs", "linear_frf")
    explanation = f"""
**What you see.** {term("pseudo-FRF", "Pseudo-FRFs")} of mass 1 (the response after {term("N")} cycles
of wear at each frequency) without wear and at four cycle counts up to the horizon, over the linear
FRFs with the contact stuck and open (paper Fig. 8-9). As the contact wears, the normal load relaxes
and the response moves from the stuck resonance (1 Hz) towards the free one (0.5 Hz). Dashed, in the
same colours: the exact answer (Archard's law on the event-driven dynamics, no harmonic truncation);
the findings below say how far the selected method is from it.

**Try.** The paper presets at 6, 10 and 14 N; the wear map of the same settings is shared with the
*Wear map* scene, so switching between them costs nothing. Lower {term("Nh")} and watch the solid
curves leave the dashed ones."""

    #: keys of the snapshot curves (their legend shows the cycle counts)
    _keys = ("no wear", "snapshot 1", "snapshot 2", "snapshot 3", "snapshot 4")
    #: colours of the snapshot curves, shared by their exact counterparts
    _colors = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd")

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        t = self.tasks
        return [t.linear(s, "stuck"), t.linear(s, "open"), t.frf(s), t.wear_map(s), t.exact_wear_map(s)]

    def _snapshots(self) -> np.ndarray:
        """Cycle counts of the worn curves (the first snapshot, ``N = 0``, is drawn from the FRF)."""
        return self.settings.snapshots[1:]

    def _pseudo(self, exact: bool = False):
        """``x1`` (m) of the selected method's map (or the exact one) at the snapshots, shape (4, nf)."""
        wm = _ok(self.results.get("wear_map"))
        if exact:
            wm = _exact_map(self, wm)
        return None if wm is None else wm.pseudo_frf(self._snapshots())[:, :, 0]

    def _notes(self) -> list[str]:
        wm = _ok(self.results.get("wear_map"))
        return [] if wm is None else _history_notes(wm.histories)

    def _findings(self) -> list[str]:
        p, ref = self._pseudo(), self._pseudo(exact=True)
        if p is None or ref is None:
            return []
        err = np.abs(p / ref - 1)
        if not np.isfinite(err).any():
            return []
        i, k = np.unravel_index(int(np.nanargmax(err)), err.shape)
        wm, s = _ok(self.results.get("wear_map")), self.settings
        if wm.label == "exact":  # the exact answer is its own reference
            return []
        f = wm.frequency
        worst = f"{err[i, k]:.1%} off" if err[i, k] < 1 else f"{p[i, k] / ref[i, k]:.3g} times"
        share = np.mean(err[np.isfinite(err)] > 0.1)
        return [
            f"{s.label()}: pseudo-FRFs of mass 1 up to {worst} the exact answer "
            f"(at N = {self._snapshots()[i]:.3g}, {f[k]:.4g} Hz); more than 10 % off at {share:.0%} of the "
            "frequencies and cycle counts shown."
        ]

    def _figure_evolution(self):
        curves = _linear_curves(self)
        wm, p, ref = _ok(self.results.get("wear_map")), self._pseudo(), self._pseudo(exact=True)
        curves["no wear"] = _no_wear(self)
        colors = {"stuck (linear)": "#555555", "open (linear)": "#aaaaaa", "no wear": self._colors[0]}
        for i, key in enumerate(self._keys[1:]):
            curves[key] = EMPTY if p is None else (wm.frequency, p[i])
            colors[key] = colors[f"{key} exact"] = self._colors[i + 1]
        for i, key in enumerate(self._keys[1:]):
            curves[f"{key} exact"] = EMPTY if ref is None else (wm.frequency, ref[i])
        shown = {"no wear": "N = 0 (no wear)"} | {
            key: f"N = {n:.3g}" for key, n in zip(self._keys[1:], self._snapshots(), strict=True)
        }
        shown |= {
            f"{key} exact": f"N = {n:.3g}, exact"
            for key, n in zip(self._keys[1:], self._snapshots(), strict=True)
        }
        return figures.line_figure(
            curves,
            xlabel=HZ,
            ylabel=X1,
            logy=True,
            dashed=[*list(curves)[:2], *(f"{key} exact" for key in self._keys[1:])],
            legend_labels=shown,
            colors=colors,
            title=f"Pseudo-FRFs of mass 1, horizon {self.settings.horizon:.3g} cycles (exact dashed)",
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        out = _linear_table(self)
        wm, p, ref = _ok(self.results.get("wear_map")), self._pseudo(), self._pseudo(exact=True)
        if p is not None:
            out["pseudo_frfs"] = {"f_hz": wm.frequency} | {
                f"x1_h1_N{n:.6g}": p[i] for i, n in enumerate(self._snapshots())
            }
            if ref is not None:
                snaps = self._snapshots()
                out["pseudo_frfs"] |= {f"x1_h1_N{n:.6g}_exact": ref[i] for i, n in enumerate(snaps)}
        return out


class CycleScene(Scene):
    key = "cycle"
    title = "Inside one cycle"
    figure_names = ("model", "displacements", "force", "loop")
    dataset_names = ("cycle",)
    uses_selection = True
    explanation = f"""
**What you see.** The model (paper Fig. 4) with its current values and one period of its steady
response at the selected frequency after {term("N")} cycles of wear: the masses move (displacements
magnified), the interface is green while the contact sticks and red while it slips
({term("stick-slip", "stick / slip")}), the worn depth w is drawn on mass 1 to scale of {term("u0")}.
Below: the displacements, the friction force and its limits ±{term("mu")} {term("F_N")}(w), with the
slipping intervals shaded, and the hysteresis loop (friction force against relative displacement),
whose area is the energy dissipated per cycle. Dashed: the exact orbit (event-driven dynamics, worn as
the exact wear history says at N); the findings below compare the two. **Play** runs the period; the
black lines and the dot follow it on the plots.

**Try.** Pick a point on the wear map, or type f and N in the sidebar: with wear the limits shrink,
the contact slips longer and the loop flattens."""

    frame = param.Integer(0, bounds=(0, ANIMATION_FRAMES - 1), doc="Frame of the animation of one period")
    live = True

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        t, f, n = self.tasks, sel.frequency, sel.cycles
        history, exact = (t.history(s, f), t.exact_history(s, f)) if n > 0 else (None, None)
        return [
            *([history, exact] if n > 0 else []),
            t.point(s, f, n, history),
            t.exact_point(s, f, n, exact),
        ]

    def _exact(self):
        return _ok(self.results.get(EXACT_POINT))

    def _findings(self) -> list[str]:
        sol, ref = self._point(), self._exact()
        if sol is None or ref is None or not (sol.converged and ref.converged):
            return []
        s, u0 = self.settings, sol.model.friction[0].u0
        parts = [
            f"x₁ amplitude {sol.amplitude[0] / ref.amplitude[0] - 1:+.1%}",
            f"dissipated energy {_relative(sol.friction_energy[0], ref.friction_energy[0])}",
            f"slipping {100 * np.mean(sol.state[0] == 1):.0f} % of the period (exact "
            f"{100 * np.mean(ref.state[0] == 1):.0f} %)",
        ]
        if self.selection.cycles > 0:
            parts.insert(0, f"worn depth w / u₀ {sol.wear[0] / u0:.3f} (exact {ref.wear[0] / u0:.3f})")
        if s.label() == "exact":  # the orbit shown is the exact one
            return []
        return [f"{s.label()} against the exact orbit at {self._title()}: {', '.join(parts)}."]

    def _point(self):
        return _ok(self.results.get("point"))

    def _notes(self) -> list[str]:
        sol = self._point()
        if sol is None:
            return []
        notes = []
        if not sol.converged:
            notes.append(f"the periodic solve did not converge: {sol.message}")
        h = _ok(self.results.get("history"))
        return notes + ([] if h is None else _history_notes([h]))

    def summary(self) -> str:
        """What the published solution shows, in one line (empty while there is none)."""
        sol = self._point()
        if sol is None:
            return ""
        return (
            f"w = {sol.wear[0]:.4g} m (w / u₀ = {sol.wear[0] / sol.model.friction[0].u0:.3f}), "
            f"F_N = {sol.normal_loads[0]:.4g} N, "
            f"slipping {100 * np.mean(sol.state[0] == 1):.0f} % of the period, "
            f"dissipated energy {sol.friction_energy[0]:.4g} J per cycle"
        )

    def sample(self, frame: int | None = None) -> int | None:
        """Index of the time sample shown at animation ``frame`` (default the current one)."""
        sol = self._point()
        if sol is None:
            return None
        frame = self.frame if frame is None else frame
        return int(round(frame * sol.samples / ANIMATION_FRAMES)) % sol.samples

    def phase(self, frame: int | None = None) -> float:
        """``t / T`` shown at animation ``frame`` (NaN while there is no solution)."""
        k = self.sample(frame)
        sol = self._point()
        return np.nan if k is None else float(sol.time[k] * sol.omega / (2 * np.pi))

    def _spans(self, sol) -> list[tuple[float, float]]:
        """Intervals of t / T where the contact slips."""
        slip = np.concatenate([[False], sol.state[0] == 1, [False]]).astype(int)
        edges = np.flatnonzero(np.diff(slip))
        n = sol.samples
        return [(a / n, b / n) for a, b in zip(edges[::2], edges[1::2], strict=True)]

    def _title(self) -> str:
        sel = self.selection
        return f"f = {sel.frequency:.4g} Hz, N = {sel.cycles:.3g}"

    def _figure_model(self, live: bool = False):
        sol, k = self._point(), self.sample()
        if sol is None:
            s = self.settings.model
            model = fretwear.paper_model(fex=s.fex, mu=s.mu, normal_load=s.normal_load, kn=s.kn)
            return model_sketch(model, title=f"The model (at rest), {self._title()}")
        state = int(sol.state[0, k])
        scale = sketch_scale(sol.displacement)
        return model_sketch(
            sol.model,
            displacement=tuple(sol.displacement[:, k]),
            scale=scale,
            state=state,
            wear=float(sol.wear[0]),
            normal_load=float(sol.normal_loads[0]),
            title=f"t / T = {self.phase():.2f}: {STATE_NAMES[state]} (displacements × {scale:.2g})",
        )

    def _cursor(self, name: str, live: bool) -> list:
        """The animation's current instant on the page's figure ``name`` (none in exports): a vertical
        line at ``t / T`` on the signals, a dot on the hysteresis loop."""
        if not live:
            return []
        hv = figures.holoviews()
        t, k, sol = self.phase(), self.sample(), self._point()
        if name == "loop":
            xy = (
                (np.nan, np.nan)
                if sol is None
                else (sol.relative_displacement[0][k], sol.contact_force[0][k])
            )
            return [figures.styled(hv.Points([xy], ["x", "y"]), {"color": "black"}, {"size": 12}, {"s": 60})]
        return [figures.styled(hv.VLine(t), {"color": "black"}, {"line_width": 2}, {"linewidth": 1.5})]

    def _figure_displacements(self, live: bool = False):
        sol = self._point()
        names = ("x₁", "x₂", "x₁ − x₂")
        cursor = self._cursor("displacements", live)
        if sol is None:
            return figures.signals_figure(
                [], {n: [] for n in names}, xlabel="t / T", ylabel="displacement (m)", title=self._title(),
                extra=cursor,
            )  # fmt: skip
        t = sol.time * sol.omega / (2 * np.pi)
        signals = dict(zip(names, (*sol.displacement, sol.relative_displacement[0]), strict=True))
        signals[f"{names[2]}, exact"] = self._exact_signal(lambda ref: ref.relative_displacement[0])
        return figures.signals_figure(
            t,
            signals,
            spans=self._spans(sol),
            xlabel="t / T",
            ylabel="displacement (m)",
            title=f"Displacements, {self._title()}",
            extra=cursor,
            dashed=(f"{names[2]}, exact",),
        )

    def _exact_signal(self, values: Callable) -> tuple:
        """``(t / T, values(exact orbit))``, empty while the exact orbit computes (or failed)."""
        ref = self._exact()
        return EMPTY if ref is None else (ref.time * ref.omega / (2 * np.pi), values(ref))

    def _figure_force(self, live: bool = False):
        sol = self._point()
        t, force, limit = [], [], np.nan
        spans = []
        if sol is not None:
            t = sol.time * sol.omega / (2 * np.pi)
            force, limit, spans = (
                sol.contact_force[0],
                sol.model.slip_forces(sol.wear)[0],
                self._spans(sol),
            )
        return figures.signals_figure(
            t,
            {"friction force": force, EXACT: self._exact_signal(lambda ref: ref.contact_force[0])},
            dashed=(EXACT,),
            spans=spans,
            hlines=(limit, -limit),
            xlabel="t / T",
            ylabel="friction force (N)",
            title=f"Friction force and ±μ Fₙ, {self._title()}",
            extra=self._cursor("force", live),
        )

    def _figure_loop(self, live: bool = False):
        curves, energy = {}, {}
        for name, sol in (("hysteresis loop", self._point()), (EXACT, self._exact())):
            curves[name], energy[name] = EMPTY, np.nan
            if sol is not None:
                close = np.r_[np.arange(sol.samples), 0]
                curves[name] = (sol.relative_displacement[0][close], sol.contact_force[0][close])
                energy[name] = sol.friction_energy[0]
        return figures.line_figure(
            curves,
            xlabel="x₁ − x₂ (m)",
            ylabel="friction force (N)",
            padding=0.08,
            dashed=(EXACT,),
            title=f"Hysteresis loop: dissipated energy {energy['hysteresis loop']:.4g} J per cycle "
            f"(exact {energy[EXACT]:.4g})",
            extra=self._cursor("loop", live),
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        sol = self._point()
        if sol is None:
            return {}
        return {
            "cycle": {
                "t": sol.time,
                "t_over_T": sol.time * sol.omega / (2 * np.pi),
                "x1": sol.displacement[0],
                "x2": sol.displacement[1],
                "xr": sol.relative_displacement[0],
                "friction_force": sol.contact_force[0],
                "state": np.array(["stick", "slip", "open"])[sol.state[0]],
            }
        }


class MethodsScene(Scene):
    key = "methods"
    title = "Methods"
    figure_names = ("methods", "harmonics", "bases")
    dataset_names = ("methods", "harmonics", "bases")
    uses_selection = True
    explanation = f"""
**What you see.** Left: the wear history at the selected frequency by the four
{term("method", "slow-time methods")}: the exact load path (Archard's law integrated along the exact
piecewise-linear path of the periodic response as the load relaxes: no slow-time error), stepping
(HBM + {term("DLFT")}, adaptive steps in N), the paper's polynomial method (one nonlinear solve for
the whole evolution) and direct time integration with cycle jumps (paper Fig. 11), with the reference
dashed: the exact method on the exact (event-driven) dynamics, no harmonic truncation; the findings
below say how far each method is from it. Right: the exact
load path with 1, 3, 7, 15 and 21 harmonics, so that only the harmonic truncation differs (paper
Fig. 10). Below: the polynomial method at the selected degree in its three slow-time bases, the
paper's monomials and Legendre polynomials and the saturating basis (in z = -ln(1 - w/u₀), so that w
stays below u₀; the cycle count a polynomial of the life fraction, the sliding distance sampled along
the wear until resolved), against the same exact reference.

**Try.** The paper's case: F<sub>ex</sub> = 10 N, f = 0.7 Hz, {term("Nh")} = 3, degree 4. Raise the
degree when the polynomial curve misses the plateau; loosen the {term("tolerance")} to see stepping
drift."""

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        t, f = self.tasks, sel.frequency
        methods = [t.history(s, f, m, name=m) for m in METHODS] + [t.exact_history(s, f)]
        convergence = [t.history(s, f, "exact", nh, name=f"Nh = {nh}") for nh in CONVERGENCE_HARMONICS]
        bases = [t.history(s, f, "polynomial", name=_basis_name(b), basis=b) for b in BASES]
        return sorted(methods + convergence + bases, key=lambda task: task.weight)

    def record(self) -> dict[str, Any]:
        """The record of the comparison: every method runs, so the method is not one of the settings."""
        return {k: v for k, v in super().record().items() if k not in ("method",)}

    def _notes(self) -> list[str]:
        return _history_notes([h for name in METHODS if (h := _ok(self.results.get(name))) is not None])

    def _findings(self) -> list[str]:
        exact, s = _ok(self.results.get(EXACT)), self.settings
        errors = [_error_note(_ok(self.results.get(m)), exact) for m in METHODS]
        for b in BASES:
            label = f"{_basis_name(b)} ({s.label('polynomial')})"
            errors.append(_error_note(_ok(self.results.get(_basis_name(b))), exact, label))
        return [e for e in errors if e]

    def _curves(self, names) -> dict[str, tuple]:
        out = {}
        for name in names:
            h = _ok(self.results.get(name))
            out[name] = EMPTY if h is None else figures.wear_curve(h, self.settings.dense_cycles)
        return out

    def _figure_methods(self):
        sel = self.selection
        return figures.line_figure(
            self._curves((*METHODS, EXACT)),
            xlabel=CYCLES,
            ylabel=WEAR,
            logx=True,
            dashed=(EXACT,),
            padding=0.05,
            legend_labels={m: self.settings.label(m) for m in METHODS},
            title=f"Slow-time methods at {sel.frequency:.4g} Hz",
        )

    def _figure_harmonics(self):
        names = [f"Nh = {nh}" for nh in CONVERGENCE_HARMONICS]
        return figures.line_figure(
            self._curves(names),
            xlabel=CYCLES,
            ylabel=WEAR,
            logx=True,
            padding=0.05,
            legend_labels={n: n.replace("Nh", "Nₕ") for n in names},
            title=f"Harmonic convergence (exact slow time on DLFT) at {self.selection.frequency:.4g} Hz",
        )

    def _figure_bases(self):
        names = [_basis_name(b) for b in BASES]
        where = f"degree {self.settings.degree}, at {self.selection.frequency:.4g} Hz"
        return figures.line_figure(
            self._curves((*names, EXACT)),
            xlabel=CYCLES,
            ylabel=WEAR,
            logx=True,
            dashed=(EXACT,),
            padding=0.05,
            title=f"Polynomial method by basis, {where}",
        )

    def _long(self, names, column: str) -> dict[str, np.ndarray]:
        rows = [(n, h) for n in names if (h := _ok(self.results.get(n))) is not None]
        if not rows:
            return {}
        return {
            column: np.concatenate([np.full(len(h.cycles), n) for n, h in rows]),
            "cycles": np.concatenate([h.cycles for _, h in rows]),
            "w": np.concatenate([h.wear[:, 0] for _, h in rows]),
            "w_over_u0": np.concatenate([h.wear_fraction[:, 0] for _, h in rows]),
        }

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        tables = {
            "methods": self._long((*METHODS, EXACT), "method"),
            "harmonics": self._long([f"Nh = {nh}" for nh in CONVERGENCE_HARMONICS], "harmonics"),
            "bases": self._long([*(_basis_name(b) for b in BASES), EXACT], "basis"),
        }
        return {k: v for k, v in tables.items() if v}


def _basis_name(basis: str) -> str:
    """Result name and legend label of the polynomial method in ``basis``."""
    return f"polynomial, {basis} basis"


#: error measure of the accuracy scene that takes, for each rung, the largest error it measures
WORST = "worst"
#: error measures of the accuracy scene and how they are named
QUANTITY_LABELS = {
    WORST: "worst of all",
    "x1_h1": "x1 amplitude (first harmonic)",
    "xr_half_p2p": "x1 - x2, half peak-to-peak",
    "sliding_distance": "sliding distance per cycle",
    "wear": "w(N) (largest error over N, / u0)",
}
#: target errors of the accuracy scene, 1-2-5 per decade from 1e-1 down to 1e-6
TARGETS = (*(float(f"{m}e-{e}") for e in range(2, 7) for m in (10, 5, 2)), 1e-6)
#: colour of each kind of rung
FAMILY_COLORS = {
    "shooting": "black",
    "dlft": "#1f77b4",
    "dlft, samples": "#17becf",
    "exact": "#2ca02c",
    "stepping": "#ff7f0e",
    "stepping-shooting": "#d62728",
    "polynomial": "#9467bd",
    "time": "#8c564b",
}


def _family(rung: Rung) -> str:
    """Kind of ``rung`` (its colour): its method, DLFT with other than the default samples apart."""
    if rung.method == "dlft" and rung.settings["N"] != default_samples(rung.settings["Nh"]):
        return "dlft, samples"
    return rung.method


def sidebar_equivalent(rung: Rung) -> tuple[dict[str, Any] | None, str]:
    """The sidebar settings that reproduce ``rung``: ``(changes, description)``.

    ``changes`` maps control names (:class:`~app.state.Controls`) to values, or
    is ``None`` when no sidebar setting reproduces the rung; the description
    says then why.
    """
    p = rung.settings
    if rung.method == "dlft":
        nh, n = p["Nh"], p["N"]
        if n != default_samples(nh):
            return None, (
                f"N = {n} samples per period has no sidebar control (the app takes the default "
                f"{default_samples(nh)} at Nh = {nh})"
            )
        return {"harmonics": nh}, f"Nh = {nh}"
    scheme, _, dynamics = rung.method.partition("-")  # wear rungs: exact-dlft, stepping-shooting, ...
    if rung.reference:
        return None, "it is the reference, the exact dynamics (dynamics = exact in the sidebar)"
    names = {"Nh": ("harmonics", "Nh"), "tol": ("tol", "tolerance"), "degree": ("degree", "degree")}
    if scheme not in METHODS or set(p) - set(names):
        return None, f"the sidebar has no setting for {_name(rung)}"
    if "dynamics" in fretwear.METHODS[scheme].options:
        dynamics = dynamics or "dlft"
    changes = {"method": scheme} | ({"dynamics": dynamics} if dynamics else {})
    changes |= {names[k][0]: v for k, v in p.items()}
    words = [f"method = {scheme}", *([f"dynamics = {dynamics}"] if dynamics else [])]
    return changes, ", ".join([*words, *(f"{names[k][1]} = {v:g}" for k, v in p.items())])


def _name(rung: Rung) -> str:
    """``rung.label`` without the trailing space of a rung without settings (the reference)."""
    return rung.label.strip()


def _short(rung: Rung) -> str:
    """Text label of ``rung`` on the figure (DLFT rungs: ``N`` only when it is not the default)."""
    if rung.method == "shooting":
        return "shooting (reference)"
    p = dict(rung.settings)
    if rung.method == "dlft" and p["N"] == default_samples(p["Nh"]):
        del p["N"]
    text = " ".join(f"{k}={v:g}" for k, v in p.items())
    return text if rung.method == "dlft" else f"{rung.method} {text}"


class AccuracyScene(Scene):
    key = "accuracy"
    title = "Accuracy vs cost"
    figure_names = ("pareto",)
    dataset_names = ("ladder", "reference")
    inputs = ("ladder", "wear")
    explanation = f"""
**What you see.** Each point is one discretisation (a *rung*) at the selected frequency f: its wall
time on this server against its relative error on the chosen quantity, measured against a converged
reference (named under the recommendation: shooting on the exact event-driven time integration for the
periodic quantities, the library's most accurate slow-time solution for w(N)). {term("DLFT")} rungs
vary {term("Nh")} (and the samples per period N), the wear rungs the {term("method", "slow-time method")},
N<sub>h</sub>, {term("tolerance")} and degree; *worst of all* takes each rung's largest error over what it
measures. The dashed line is the Pareto front, the red ring marks the sidebar's current settings, the
star the cheapest rung within the target error. **Apply** sets the sidebar to the cheapest rung within
the target that the sidebar can reproduce: the shooting reference, stepping with shooting dynamics and
DLFT with other than the default samples have no sidebar setting.

**Try.** Move the target: the star moves along the front. Tick *wear rungs* (the slow-time methods
with {term("k_w")} and the horizon of the sidebar: several seconds) and choose w(N). Wall times are
single runs on a server that works for every session: compare them within one ladder."""

    quantity = param.Selector(default=WORST, objects=list(QUANTITY_LABELS), doc="Error measure")
    target = param.Selector(
        default=5e-2,
        objects=list(TARGETS),
        doc="Target relative error (5 %: a DLFT rung meets it at the paper point, only the reference 1 %)",
    )
    ladder = param.Selector(default="quick", objects=list(LADDERS), doc="Ladder of settings")
    wear = param.Boolean(False, doc="Include the wear rungs (w(N); k_w and the horizon of the sidebar)")

    def __init__(self, tasks: Tasks, **params: Any) -> None:
        super().__init__(tasks, **params)
        self.param.watch(lambda *_events: self.redraw(), ["quantity", "target"])

    def needs(self, s: Settings, sel: Selection) -> list[Task]:
        return [self.tasks.cost(s, sel.frequency, self.ladder, self.wear)]

    def study(self) -> CostStudy | None:
        """The published cost ladder (``None`` while there is none)."""
        return _ok(self.results.get("cost"))

    def _measure(self) -> str | None:
        return None if self.quantity == WORST else self.quantity

    def error(self, rung: Rung) -> float:
        """Error of ``rung`` on the selected quantity (NaN when the rung does not measure it)."""
        return rung.error(self._measure())

    def is_current(self, rung: Rung) -> bool:
        """Whether the sidebar's settings are those of ``rung``."""
        changes, _ = sidebar_equivalent(rung)
        return changes is not None and all(getattr(self.settings, k) == v for k, v in changes.items())

    def recommended(self) -> Rung | None:
        """The cheapest converged rung within the target error on the selected quantity."""
        study = self.study()
        return None if study is None else study.recommend(self.target, self._measure())

    def applicable(self) -> Rung | None:
        """The cheapest converged rung within the target that the sidebar can reproduce."""
        study = self.study()
        ok = [
            r
            for r in (study.rungs if study else [])
            if r.converged and self.error(r) <= self.target and sidebar_equivalent(r)[0] is not None
        ]
        return min(ok, key=lambda r: r.wall_time) if ok else None

    def advice(self) -> str:
        """What the scene recommends for the target, in Markdown (empty while nothing is computed)."""
        study = self.study()
        if study is None:
            return ""
        reference = "; ".join(f"{k}: {v}" for k, v in sorted(study.reference.items()))
        return f"{self._advice(study)}\n\n*Reference* ({reference})."

    def _advice(self, study: CostStudy) -> str:
        name, target = QUANTITY_LABELS[self.quantity], self.target
        measured = [r for r in study.rungs if np.isfinite(self.error(r))]
        if not measured:
            if self.wear:  # the ladder shown is the one without them
                return f"No rung measures {name} yet: the wear rungs are being computed."
            return f"No rung measures {name}: tick *wear rungs* to compute `w(N)`."
        best, settable = self.recommended(), self.applicable()
        if best is None and any(r.reference and self.error(r) <= target for r in measured):
            return (
                f"Only the reference reaches {target:g} on {name}: the exact dynamics "
                "(*dynamics = exact* in the sidebar, the default)."
            )
        if best is None:
            top = min(measured, key=self.error)
            return (
                f"No rung reaches {target:g} on {name}; the most accurate is `{_name(top)}` "
                f"(error {self.error(top):.2g})."
            )
        text = (
            f"**Cheapest within {target:g}** on {name}: `{_name(best)}` "
            f"({_seconds(best.wall_time)}, error {self.error(best):.2g})."
        )
        changes, why = sidebar_equivalent(best)
        if changes is not None:
            return f"{text} **Apply** sets {why}."
        text += f" It has no sidebar equivalent: {why}."
        if settable is None:
            return f"{text} No setting the sidebar can reproduce reaches {target:g}."
        return (
            f"{text} The cheapest the sidebar can reproduce: `{_name(settable)}` "
            f"({_seconds(settable.wall_time)}, error {self.error(settable):.2g}); **Apply** sets "
            f"{sidebar_equivalent(settable)[1]}."
        )

    def export_figure(self, name: str, fmt: str, options: figures.ExportOptions | None = None) -> bytes:
        """Figure ``name`` as ``png``, ``svg`` or ``html`` bytes; ``ValueError`` when no rung is drawn."""
        study = self.study()
        if study is None or not any(np.isfinite(self.error(r)) for r in study.rungs):
            raise ValueError(f"no rung measures {QUANTITY_LABELS[self.quantity]} (yet)")
        return super().export_figure(name, fmt, options)

    def record(self) -> dict[str, Any]:
        """The ladder's record: the model and frequency, and ``k_w`` and the horizon with the wear rungs
        (the ladder does not depend on the sidebar's Nh, method or tolerances)."""
        s = self.settings
        out = {"fex": s.model.fex, "mu": s.model.mu, "fn": s.model.normal_load, "f": self.selection.frequency}
        return out | ({"kw": s.kw, "cycles": s.horizon} if self.wear else {})

    def _notes(self) -> list[str]:
        study = self.study()
        if study is None:
            return []
        notes = [f"{_name(r)} did not converge (left out)" for r in study.rungs if not r.converged]
        measured = [r for r in study.rungs if np.isfinite(self.error(r))]
        if measured and not any(self.is_current(r) for r in measured):
            s = self.settings
            notes.append(
                f"the current settings (Nh = {s.harmonics}, method {s.method}) are not among the rungs "
                f"that measure {QUANTITY_LABELS[self.quantity]}"
            )
        return notes

    def _figure_pareto(self):
        hv = figures.holoviews()
        study, name = self.study(), QUANTITY_LABELS[self.quantity]
        rungs = [r for r in (study.rungs if study else []) if np.isfinite(self.error(r))]
        errors = np.array([self.error(r) for r in rungs])
        times = np.array([r.wall_time for r in rungs])
        # errors of zero (the reference; rungs exact to round-off) are drawn at the bottom of the axis
        floor = min([*errors[errors > 0], self.target]) / 10
        # ranges with room for the text labels beside the points, valid without points too: labels go
        # right of the points, and left of those in the last half decade
        xlim = (times.min() / 2, times.max() * 2) if len(rungs) else (1e-4, 1.0)
        right_edge = times.max() / 10**0.5 if len(rungs) else np.inf
        ylim = (floor / 2, max([*errors, self.target]) * 3)
        xd = hv.Dimension("x", label="wall time (s)", range=xlim)
        yd = hv.Dimension("y", label=f"relative error: {name}", range=ylim)
        vdims = ["rung", "family", "error", "converged"]

        def points(items: list[Rung], label: str, style: dict, bokeh: dict, mpl: dict, marker: bool = False):
            table = {
                "x": np.array([r.wall_time for r in items], dtype=float),
                "y": np.array([max(self.error(r), floor) for r in items], dtype=float),
                "rung": [_name(r) for r in items],
                "family": [_family(r) for r in items],
                "error": np.array([self.error(r) for r in items], dtype=float),
                "converged": [str(r.converged) for r in items],
            }
            if marker and not items:  # a marker with no point: one hidden row, so that its legend has a glyph
                table = {k: np.array([np.nan]) if k in ("x", "y", "error") else [""] for k in table}
            layer = hv.Points(table, [xd, yd], vdims, label=label)
            return figures.styled(layer, {"framewise": True, **style}, {"tools": ["hover"], **bokeh}, mpl)

        front = [r for r in (study.pareto(self._measure()) if study else []) if r in rungs]
        curve = hv.Curve(
            ([r.wall_time for r in front], [max(self.error(r), floor) for r in front]),
            xd,
            yd,
            label="Pareto front",
        )

        def labels(items: list[Rung], align: str):
            text = hv.Labels(
                (
                    [r.wall_time for r in items],
                    [max(self.error(r), floor) for r in items],
                    [f" {_short(r)} " for r in items],
                ),
                [xd, yd],
                "text",
            )
            return figures.styled(
                text,
                {"show_legend": False},
                {
                    "text_font_size": "8pt",
                    "text_align": align,
                    "text_baseline": "middle",
                    "text_color": "#333",
                },
                {"size": 7, "horizontalalignment": align, "verticalalignment": "center", "color": "#333"},
            )

        best = self.recommended()
        layers = [
            points(
                rungs,
                "rungs",
                {"color": hv.dim("family").categorize(FAMILY_COLORS, default="gray")},
                {"size": 9, "line_color": "white"},
                {"s": 40},
            ),
            figures.styled(curve, {"color": "gray"}, {"line_dash": "dashed"}, {"linestyle": "--"}),
            labels([r for r in rungs if r.wall_time <= right_edge], "left"),
            labels([r for r in rungs if r.wall_time > right_edge], "right"),
            points(
                [r for r in rungs if self.is_current(r)],
                "current settings",
                {},
                {"size": 20, "fill_alpha": 0, "line_color": "red", "line_width": 2.5},
                {"s": 250, "facecolors": "none", "edgecolors": "red", "linewidth": 2},
                marker=True,
            ),
            points(
                [best] if best in rungs else [],
                "recommended",
                {},
                {"size": 22, "marker": "star", "fill_color": "gold", "line_color": "black"},
                {"s": 300, "marker": "*", "color": "gold", "edgecolors": "black"},
                marker=True,
            ),
            figures.marker_line(hv, self.target, vertical=False),
        ]
        f = self.selection.frequency if study is None else study.frequency
        title = f"{name} vs wall time at {f:.4g} Hz (target {self.target:g})"
        overlay = figures.overlay_options(hv.Overlay(layers), title, xd.label, yd.label, True, True, True)
        return figures.styled(overlay, mpl={"fig_inches": (9.0, 5.0)})

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        study = self.study()
        if study is None:
            return {}
        front, best = set(map(id, study.pareto(self._measure()))), self.recommended()
        rungs = study.rungs
        table = {
            "method": np.array([r.method for r in rungs]),
            "settings": np.array([_name(r) for r in rungs]),
            "wall_time_s": np.array([r.wall_time for r in rungs]),
            **{f"err_{q}": np.array([r.errors.get(q, np.nan) for r in rungs]) for q in QUANTITIES},
            "converged": np.array([r.converged for r in rungs]),
            "pareto": np.array([id(r) in front for r in rungs]),
            "recommended": np.array([r is best for r in rungs]),
            "current": np.array([self.is_current(r) for r in rungs]),
            "sidebar": np.array([sidebar_equivalent(r)[1] for r in rungs]),
            "quantity": np.full(len(rungs), self.quantity),
            "target": np.full(len(rungs), self.target),
        }
        names = sorted(study.reference)
        reference = {
            "item": np.array([*names, *study.reference_values]),
            "description": np.array([study.reference[n] for n in names] + [""] * len(study.reference_values)),
            "value": np.array([np.nan] * len(names) + list(study.reference_values.values()), dtype=float),
            "frequency_hz": np.full(len(names) + len(study.reference_values), study.frequency),
        }
        return {"ladder": table, "reference": reference}


def _seconds(t: float) -> str:
    return f"{t * 1e3:.3g} ms" if t < 1 else f"{t:.3g} s"


#: the scenes in tab order
SCENES: tuple[type[Scene], ...] = (
    RegimesScene,
    WearMapScene,
    EvolutionScene,
    CycleScene,
    MethodsScene,
    AccuracyScene,
)
