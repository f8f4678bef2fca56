"""The Accuracy vs cost scene: error against wall time over a ladder of settings, and what to apply."""

from __future__ import annotations

import html
from collections.abc import Callable
from typing import Any

import numpy as np
import param

import fretwear
from fretwear import figures
from fretwear.figures.record import caption
from fretwear.hbm.harmonics import default_samples
from fretwear.studies.accuracy import QUANTITIES, CostStudy, Rung

from ..glossary import term
from ..state import LADDERS, METHODS, Settings, Task, Tasks
from .base import Scene, Selection, ok_value

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
        return ok_value(self.results.get("cost"))

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

    def _measured(self) -> str:
        """What the figure measures and marks, for its caption and CSV: the error, the target, the ladder
        and the current settings the ring marks."""
        s = self.settings
        return (f"error on {QUANTITY_LABELS[self.quantity]}, target {self.target:g}, ladder {self.ladder}; "
                f"ring: the current settings, Nh = {s.harmonics}, {s.label()}")  # fmt: skip

    def caption(self) -> Callable[[str], str]:
        record, measured = self.record(), self._measured()
        return lambda markup: (f"{caption(record, markup=markup)}; "
                               f"{html.escape(measured) if markup == 'html' else measured}")  # fmt: skip

    def csv_header(self) -> str:
        lines = super().csv_header().splitlines(keepends=True)  # the version stays last
        return "".join([*lines[:-1], f"# {self._measured()}\n", lines[-1]])

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
