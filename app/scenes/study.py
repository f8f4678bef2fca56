"""The Study scene: browse a parameter study written by ``fretwear study`` (nothing is recomputed).

``panel serve app/app.py --args --study RESULT.zarr`` opens the store once
per server process while it is unchanged (:meth:`~app.backend.Backend.study`,
a task in the server's shared cache) and every session slices it: over grid axes, a quantity along one
axis with the others fixed (sliders); over random samples, the histogram of
the cycles to a fraction of ``u0`` with its median and 5 / 95 % quantiles
and the scatter of a quantity against each input; with the ``wear``
quantity, ``w(N)`` at the selected point and the wear map over frequency.
Points that failed (NaN with a status) are drawn as markers of their own and
listed in the notes, never dropped. A bad path or a store that is not a study
is one message in the page.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import partial
from pathlib import Path
from typing import Any

import numpy as np
import panel as pn
import param

from fretwear import figures
from fretwear.figures.plots import ensure_backend, holoviews, marker_line, overlay_options, styled
from fretwear.studies.compute import STATUS
from fretwear.studies.summary import magnification_summary, wear_life_summary

from ..backend import Failure, shared_backend, shared_cache
from ..live import control_row, figure_grid, live_pane, message_list
from ..session import Runner
from ..state import Tasks, file_stamp
from .base import Addressed, Exports

__all__ = ["StudyScene", "study_tab", "QUANTITIES"]

#: the per-point quantities a study may hold: variable -> (label, unit, logarithmic axis)
QUANTITIES = {
    "cycles_to": ("cycles to w = fraction × u₀", "cycles", True),
    "amplitude": ("first-harmonic amplitude, no wear", "m", True),
    "relative_amplitude": ("relative displacement amplitude, no wear", "m", True),
    "sliding_distance": ("distance slid per period, no wear", "m", False),
    "friction_energy": ("friction energy per period, no wear", "J", False),
    "slip_distance": ("distance slid per period by each pair, no wear", "m", False),  # contact pairs
    "mean_pressure": ("pressure of each pair, mean over the period, no wear", "Pa", False),
    "magnification": ("amplitude magnification factor (mistuned over tuned peak)", "-", False),  # bladed disk
    "peak_frequency": ("frequency of the largest blade-tip amplitude", "Hz", False),
}
#: statuses drawn as markers of their own (their value is NaN or inf)
FAILED = tuple(s for s in STATUS if s in ("not_computed", "not_converged", "invalid", "error"))
HOW_TO = """**No study is open.** Run a study (see the user guide's page
`docs/user_guide/studies.md`), e.g.

    fretwear study fretwear/data/wear_life.toml --out wear_life.zarr --samples 200

then start the dashboard on it: `panel serve app/app.py --args --study wear_life.zarr`."""


def _number(value: Any) -> str:
    return f"{value:.4g}" if isinstance(value, (float, np.floating)) else str(value)


def _points(n: int) -> str:
    return f"{n} point" if n == 1 else f"{n} points"


class StudyScene(Addressed, Exports, Runner):
    """The Study tab's state: the open study, how it is sliced, and what the slice shows.

    The store is read by a task (:meth:`~app.backend.Backend.study`) on the session's machinery
    (:class:`~app.session.Runner`, :class:`~app.state.Tasks`), in the calling thread.

    Parameters
    ----------
    path : str or Path, optional
        The study's Zarr store; ``None``: no study (the tab says how to open one).
    tasks : Tasks, optional
        Builds the task and holds the result cache (default: the server's shared cache).
    """

    key = "study"
    title = "Study"
    address_params = ("quantity", "axis", "fraction", "input", "point")

    axis = param.Selector(default=None, objects=[], doc="Grid axis along which the slice is drawn")
    quantity = param.Selector(default=None, objects=[], doc="Stored quantity shown")
    fraction = param.Selector(default=None, objects=[], doc="Wear fraction of u0 (cycles_to)")
    input = param.Selector(default=None, objects=[], doc="Random input on the scatter's horizontal axis")
    point = param.Dict({}, doc="Index of the selected value on each point dimension")
    error = param.String("", doc="Why no study is shown (bad path, not a study)")
    version = param.Integer(0, doc="Incremented at each change: the figures redraw")
    notes = param.List([], doc="Failed points of the slice, counts")

    def __init__(self, path: str | Path | None = None, tasks: Tasks | None = None, **params: Any) -> None:
        self.tasks = tasks or Tasks(shared_backend(), shared_cache())
        super().__init__(self.tasks.cache, **params)
        self.path, self.ds = path, None
        self.level = "fraction"  # the dimension of the life's levels (_setup)
        if path is not None:
            stamp = file_stamp(path)
            backend = self.tasks.backend
            task = self.tasks.call("study", "the study", 1.0, backend.study, str(Path(path).resolve()), stamp)
            self.run(self.new_request(), [task], self._opened)
        if self.ds is not None:
            self._setup()
        self.param.watch(self._changed, ["axis", "quantity", "fraction", "input", "point"])
        self._changed()

    def _opened(self, results: dict[str, Any], _final: bool) -> None:
        ds = results["study"]
        if isinstance(ds, Failure):
            self.error = ds.reason
        else:
            self.ds = ds

    # -- structure of the study ----------------------------------------------------------
    def _setup(self) -> None:
        ds = self.ds
        self.dims: tuple[str, ...] = tuple(ds["status"].dims)
        self.grid_dims = tuple(d for d in self.dims if d != "sample")
        # a sample is picked for its w(N) and for the slices over grid axes; histogram and scatter show all
        self.slider_dims = tuple(
            d for d in self.dims if d != "sample" or "wear_fraction" in ds or self.grid_dims
        )
        self.inputs = tuple(c for c in ds.coords if c != "sample" and ds[c].dims == ("sample",))
        quantities = [q for q in QUANTITIES if q in ds]
        self.param.axis.objects = list(self.grid_dims)
        self.param.quantity.objects = quantities
        self.param.input.objects = list(self.inputs)
        # the life's levels: fractions of u0, or worn depths (m) for a model with contact pairs
        self.level = "depth" if "depth" in ds.coords else "fraction"
        fractions = [float(f) for f in ds[self.level].values] if self.level in ds.coords else []
        self.param.fraction.objects = fractions
        with param.parameterized.discard_events(self):
            self.axis = "frequency" if "frequency" in self.grid_dims else (self.grid_dims or (None,))[0]
            self.quantity = quantities[0] if quantities else None
            middle = 0.5 if self.level == "fraction" else np.median(fractions) if fractions else None
            self.fraction = min(fractions, key=lambda f: abs(f - middle)) if fractions else None
            self.input = self.inputs[0] if self.inputs else None
            self.point = {d: 0 for d in self.dims}

    @property
    def figure_names(self) -> tuple[str, ...]:
        """The figures this study has data for."""
        if self.ds is None:
            return ()
        names = []
        if self.grid_dims and self.quantity:
            names.append("slice")
        if "sample" in self.dims and ("cycles_to" in self.ds or "magnification" in self.ds):
            names.append("histogram")
        if "sample" in self.dims and self.quantity and self.inputs:
            names.append("scatter")
        if "wear_fraction" in self.ds:
            names.append("history")
            if "frequency" in self.grid_dims and self.ds.sizes["frequency"] > 1:
                names.append("wear_map")
        return tuple(names)

    @property
    def dataset_names(self) -> tuple[str, ...]:
        return tuple(n for n in ("slice", "samples", "history") if n in self.figure_names or (
            n == "samples" and "sample" in self.dims and self.ds is not None))  # fmt: skip

    def values(self, dim: str) -> np.ndarray:
        """The coordinate values of point dimension ``dim`` (sample numbers for ``sample``)."""
        return np.asarray(self.ds[dim].values)

    def select(self, dim: str, index: int) -> None:
        """Select value number ``index`` of point dimension ``dim`` (``ValueError`` out of range)."""
        if dim not in self.dims:
            raise ValueError(f"dim must be one of the study's dimensions {self.dims}, got {dim!r}")
        n = self.ds.sizes[dim]
        if not 0 <= int(index) < n:
            raise ValueError(f"index of {dim} must be in [0, {n - 1}], got {index!r}")
        self.point = {**self.point, dim: int(index)}

    def _at(self, keep: tuple[str, ...]):
        """The study at the selected point, keeping dimensions ``keep`` whole."""
        return self.ds.isel({d: i for d, i in self.point.items() if d not in keep})

    def _component(self, da) -> dict[str, np.ndarray]:
        """The selected quantity's values by component (DOF, contact), after the fraction is chosen."""
        if self.level in da.dims:
            da = da.sel({self.level: self.fraction})
        extra = [d for d in da.dims if d not in self.dims]
        if not extra:
            return {self.quantity: np.asarray(da.values, dtype=float)}
        d = extra[0]
        return {f"{self.quantity} {n}": np.asarray(da.isel({d: i}).values, dtype=float)
                for i, n in enumerate(da[d].values)}  # fmt: skip

    def _where(self, keep: str | None = None) -> str:
        """The selected point in words (the dimension ``keep`` left out)."""
        parts = []
        for d in self.slider_dims:
            if d == keep:
                continue
            value = self.values(d)[self.point[d]]
            unit = self.ds[d].attrs.get("units", "") if d != "sample" else ""
            parts.append(f"{d} = {_number(value)}{' ' + unit if unit and unit != '-' else ''}")
        return ", ".join(parts)

    def _label(self) -> str:
        label, unit, _log = QUANTITIES[self.quantity]
        if self.quantity == "cycles_to":
            label = self._life_label()
        return f"{label} ({unit})"

    def _life_label(self) -> str:
        """The life at the selected level: to a fraction of u0, or to a worn depth (contact pairs)."""
        if self.level == "depth":
            return f"cycles to a worn depth of {self.fraction:g} m"
        return f"cycles to w = {self.fraction:g} u₀"

    def _changed(self, *_events: Any) -> None:
        self.notes = self._notes() if self.ds is not None else []
        self.version += 1

    def _status_names(self, status: np.ndarray) -> np.ndarray:
        return np.array([STATUS[int(s)] for s in np.ravel(status)])

    def _notes(self) -> list[str]:
        keep = ("sample",) if "sample" in self.dims else (self.axis,)
        scope = "over the samples" if "sample" in self.dims else f"along {self.axis}"
        status = self._status_names(self._at(keep)["status"].values)
        counts = {s: int((status == s).sum()) for s in STATUS if (status == s).any()}
        notes = []
        bad = {s: n for s, n in counts.items() if s in FAILED}
        if bad:
            shown = ", ".join(f"{n} {s.replace('_', ' ')}" for s, n in bad.items())
            notes.append(f"Points {scope} without a value: {shown} (drawn as red crosses, NaN in the CSV)")
        if counts.get("stuck"):
            notes.append(f"{_points(counts['stuck'])} {scope} stick: no wear (infinite life, grey markers)")
        if counts.get("horizon"):
            notes.append(f"{_points(counts['horizon'])} {scope} do not reach the fraction within the horizon")
        return notes

    # -- figures ---------------------------------------------------------------------------
    def figure(self, name: str, live: bool = False):
        """Figure ``name`` of the current slice (a HoloViews overlay)."""
        if name not in ("slice", "histogram", "scatter", "history", "wear_map"):
            raise ValueError(f"the study scene has no figure {name!r}; it has {self.figure_names}")
        return getattr(self, f"_figure_{name}")()

    def _marks(self, hv, x, status, y_low, y_high, xd, yd) -> list:
        """Markers of the points without a value: failed (red crosses, below ``y_low``) and stuck (grey
        triangles, above ``y_high``)."""
        failed, stuck = np.isin(status, FAILED), status == "stuck"
        layers = []
        kinds = (
            (failed, "failed (no value)", y_low / 1.2, "red", ("x", "X")),
            (stuck, "stuck (no wear)", y_high * 1.2, "grey", ("triangle", "^")),
        )
        for mask, label, y, color, (bokeh, mpl) in kinds:
            pts = hv.Points((np.asarray(x, dtype=float)[mask], np.full(int(mask.sum()), y)), [xd, yd],
                            label=label)  # fmt: skip
            layers.append(
                styled(
                    pts,
                    {"color": color},
                    {"size": 10, "line_width": 2, "marker": bokeh},
                    {"s": 50, "marker": mpl},
                )
            )
        return layers

    @staticmethod
    def _span(values) -> tuple[float, float]:
        v = np.concatenate([np.ravel(a) for a in values]) if values else np.zeros(0)
        v = v[np.isfinite(v) & (v > 0)]
        return (float(v.min()), float(v.max())) if v.size else (1.0, 1.0)

    def _figure_slice(self):
        hv = holoviews()
        sl = self._at((self.axis,))
        x = np.asarray(sl[self.axis].values, dtype=float)
        curves = {k: (x, v) for k, v in self._component(sl[self.quantity]).items()}
        log = QUANTITIES[self.quantity][2]
        low, high = self._span([v for _x, v in curves.values()])
        xlabel = f"{self.axis} ({self.ds[self.axis].attrs.get('units', '-')})"
        xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=self._label())
        marks = self._marks(hv, x, self._status_names(sl["status"].values), low, high, xd, yd)
        where = self._where(self.axis)
        return figures.line_figure(
            curves,
            xlabel=xlabel,
            ylabel=self._label(),
            logy=log,
            padding=0.05,
            extra=marks,
            title=f"Study: {self._label().split(' (')[0]} along {self.axis}"
            + (f" ({where})" if where else ""),
        )

    def _samples(self):
        return self._at(("sample",))

    def _life(self) -> tuple[np.ndarray, dict[str, float]]:
        sl = self._samples()
        level = {self.level: self.fraction}
        return np.asarray(sl["cycles_to"].sel(level).values, dtype=float), wear_life_summary(sl, **level)

    def _figure_magnification(self):
        """Histogram of the magnification factors of the draws at the selected mistuning level, with their
        mean, 95th percentile and Whitehead's bound (a mistuning study of the bladed disk)."""
        hv = holoviews()
        summary = magnification_summary(self.ds)
        i = self.point.get("level", 0)
        factors = summary["factors"][i]
        finite = factors[np.isfinite(factors)]
        bound = summary["whitehead"]
        top = max(bound, finite.max() if finite.size else 1.0) * 1.02
        counts, edges = np.histogram(finite, bins=np.linspace(min(1.0, finite.min(initial=1.0)), top, 31))
        xlabel = "amplitude magnification factor (-)"
        hist = hv.Histogram((edges, counts), kdims=[hv.Dimension("x", label=xlabel)],
                            vdims=[hv.Dimension("y", label="draws")])  # fmt: skip
        hist = styled(hist, {"alpha": 0.8, "framewise": True}, {"color": "#4c72b0", "tools": ["hover"]},
                      {"facecolor": "#4c72b0"})  # fmt: skip
        lines = [marker_line(hv, v) for v in (summary["mean"][i], summary["p95"][i], bound)]
        mean, p95 = _number(summary["mean"][i]), _number(summary["p95"][i])
        title = (f"Study: magnification at level {summary['levels'][i]:g}, mean {mean}, 95 % {p95}, "
                 f"Whitehead's bound {bound:.3g}")  # fmt: skip
        return overlay_options(hv.Overlay([hist, *lines]), title, xlabel, "draws", False, False, False,
                               (0.05, 0.0))  # fmt: skip

    def _figure_histogram(self):
        hv = holoviews()
        ensure_backend()
        if "magnification" in self.ds:
            return self._figure_magnification()
        life, summary = self._life()
        finite = life[np.isfinite(life) & (life > 0)]
        if finite.size:
            top = finite.max() * 1.0001 if finite.max() > finite.min() else finite.min() * 1.5
            edges = np.geomspace(finite.min(), top, min(40, max(5, finite.size // 5)) + 1)
            counts, edges = np.histogram(finite, bins=edges)
        else:
            counts, edges = np.zeros(1), np.array([1.0, 10.0])
        xlabel = self._life_label()
        hist = hv.Histogram((edges, counts), kdims=[hv.Dimension("x", label=xlabel)],
                            vdims=[hv.Dimension("y", label="samples")])  # fmt: skip
        hist = styled(hist, {"alpha": 0.8, "framewise": True}, {"color": "#4c72b0", "tools": ["hover"]},
                      {"facecolor": "#4c72b0"})  # fmt: skip
        lines = [
            marker_line(hv, summary[k] if np.isfinite(summary[k]) else None) for k in ("median", "q05", "q95")
        ]
        text = ", ".join(f"{lab} {_number(summary[k])}" for k, lab in
                         (("median", "median"), ("q05", "5 %"), ("q95", "95 %")))  # fmt: skip
        where = self._where("sample")
        title = f"Study: wear life, {text}" + (f" ({where})" if where else "")
        return overlay_options(hv.Overlay([hist, *lines]), title, xlabel, "samples", True, False,
                               False, (0.05, 0.0))  # fmt: skip

    def _figure_scatter(self):
        hv = holoviews()
        ensure_backend()
        sl = self._samples()
        x = np.asarray(sl[self.input].values, dtype=float)
        values = self._component(sl[self.quantity])
        log = QUANTITIES[self.quantity][2]
        low, high = self._span(list(values.values()))
        xlabel = f"{self.input} ({self.ds[self.input].attrs.get('units', '-')})"
        xd, yd = hv.Dimension("x", label=xlabel), hv.Dimension("y", label=self._label())
        layers = []
        for label, y in values.items():
            y = np.where(y > 0, y, np.nan) if log else y
            ok = np.isfinite(y)
            pts = hv.Points((x[ok], y[ok]), [xd, yd], label=label)
            layers.append(styled(pts, {"framewise": True}, {"size": 7, "tools": ["hover"]}, {"s": 20}))
        layers += self._marks(hv, x, self._status_names(sl["status"].values), low, high, xd, yd)
        where = self._where("sample")
        title = f"Study: {self._label().split(' (')[0]} against {self.input}" + (
            f" ({where})" if where else ""
        )
        return overlay_options(hv.Overlay(layers), title, xlabel, self._label(), False, log, True,
                                             0.05)  # fmt: skip

    def _history(self) -> tuple[np.ndarray, np.ndarray, dict[float, float]]:
        sl = self._at(())
        n = np.asarray(sl["cycles"].values, dtype=float)
        w = np.asarray(sl["wear_fraction"].values, dtype=float)
        marks = {}
        if "cycles_to" in sl:
            marks = {float(f): float(sl["cycles_to"].sel(fraction=f)) for f in sl["fraction"].values}
        return n, w, marks

    def _figure_history(self):
        hv = holoviews()
        n, w, marks = self._history()
        lines = [marker_line(hv, c if np.isfinite(c) else None) for c in marks.values()]
        status = STATUS[int(self._at(())["status"])]
        title = f"Study: w(N) at {self._where()}" + (
            "" if status == "ok" else f" ({status.replace('_', ' ')})"
        )
        return figures.line_figure({"w(N)": (n, w)}, xlabel="cycles N", ylabel="w / u₀", logx=True,
                                   title=title, extra=lines)  # fmt: skip

    def _figure_wear_map(self):
        sl = self._at(("frequency",))
        f = np.asarray(sl["frequency"].values, dtype=float)
        logn = np.log10(np.asarray(sl["cycles"].values, dtype=float))
        z = np.asarray(sl["wear_fraction"].transpose("cycles", "frequency").values, dtype=float)
        top = float(np.nanmax(z)) if np.isfinite(z).any() else 1.0
        where = self._where("frequency")
        sel = (float(f[self.point["frequency"]]), float("nan"))
        return figures.map_figure(
            f, logn, z, xlabel="frequency f (Hz)", ylabel="log₁₀ N (cycles)", zlabel="w / u₀",
            clim=(0, max(1.0, top)), levels=(0.1, 0.5, 0.9), point=sel,
            title="Study: wear map" + (f" ({where})" if where else ""),
        )  # fmt: skip

    # -- tables and exports ----------------------------------------------------------------
    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        """Tables of the current slice (column -> values), by name; NaN where a point has no value."""
        if self.ds is None:
            return {}
        out = {}
        if "slice" in self.figure_names:
            sl = self._at((self.axis,))
            out["slice"] = {self.axis: sl[self.axis].values, **self._component(sl[self.quantity]),
                            "status": self._status_names(sl["status"].values)}  # fmt: skip
        if "sample" in self.dims:
            sl = self._samples()
            table = {"sample": sl["sample"].values, **{c: sl[c].values for c in self.inputs}}
            for q in QUANTITIES:
                if q in sl and q == self.quantity:
                    table |= self._component(sl[q])
            out["samples"] = table | {"status": self._status_names(sl["status"].values)}
        if "history" in self.figure_names:
            n, w, _marks = self._history()
            out["history"] = {"cycles": n, "wear_fraction": w}
        return out

    def csv_header(self) -> str:
        """``#`` lines of a CSV export: the study, its path, the selected point, the quantity and the
        version."""
        lines = [
            f"study: {self.ds.attrs.get('title', '')}",
            f"store: {Path(self.path).name}",
            f"point: {self._where() or '-'}",
            f"quantity: {self.quantity} = {self._label()}",  # which fraction (or depth) a life is to
            f"fretwear {self.ds.attrs.get('fretwear_version', '?')}",
        ]
        return "".join(f"# {line}\n" for line in lines)

    def _check_export(self, name: str) -> None:
        if name not in self.figure_names:
            raise ValueError(f"the study scene has no figure {name!r}; it has {self.figure_names}")


# -- the tab -------------------------------------------------------------------------------


def _selectors(scene: StudyScene) -> list:
    """A slider per point dimension (its values shown), and the quantity, axis, fraction, input choices."""
    widgets = []
    for d in scene.slider_dims:
        values = scene.values(d)
        options = {f"{_number(v)}": i for i, v in enumerate(values)}
        slider = pn.widgets.DiscreteSlider(label=d, options=options, value=scene.point[d], width=260)
        slider.param.watch(lambda e, d=d: scene.select(d, e.new), "value_throttled")
        widgets.append(slider)
    level = "Worn depth (m)" if scene.level == "depth" else "Fraction of u₀"
    for name, label in (("quantity", "Quantity"), ("axis", "Along"), ("fraction", level),
                        ("input", "Against input")):  # fmt: skip
        objects = scene.param[name].objects
        if len(objects) > 1:
            select = pn.widgets.Select(
                label=label, options=list(objects), value=getattr(scene, name), width=200
            )
            select.param.watch(lambda e, n=name: setattr(scene, n, e.new), "value")
            widgets.append(select)
    return widgets


def study_tab(scene: StudyScene, export_card: Callable[[Any], Any]) -> list:
    """The Study tab: the study's title, its selectors, figures, notes and exports (``export_card``)."""
    if scene.ds is None:
        if scene.error:
            return [pn.pane.Alert(f"Cannot open the study: {scene.error}", alert_type="danger",
                                  sizing_mode="stretch_width"), pn.pane.Markdown(HOW_TO)]  # fmt: skip
        return [pn.pane.Markdown(HOW_TO, sizing_mode="stretch_width")]
    hv = holoviews()
    ds = scene.ds
    status = np.asarray(ds["status"].values).ravel()
    counts = ", ".join(f"{int((status == i).sum())} {s.replace('_', ' ')}" for i, s in enumerate(STATUS)
                       if (status == i).any())  # fmt: skip
    intro = pn.pane.Markdown(
        f"**{ds.attrs.get('title', 'study')}** ({Path(scene.path).name}, fretwear "
        f"{ds.attrs.get('fretwear_version', '?')}): {status.size} points ({counts}); dimensions "
        f"{', '.join(f'{d} ({ds.sizes[d]})' for d in scene.dims)}. "
        "Stored results only: nothing is recomputed.",
        sizing_mode="stretch_width",
    )
    panes = [
        live_pane(partial(lambda n, **_k: scene.figure(n), name), [hv.streams.Params(scene, ["version"])])
        for name in scene.figure_names
    ]
    notes = message_list(scene, "notes")
    return [intro, control_row(*_selectors(scene)), figure_grid(panes), notes, export_card(scene)]
