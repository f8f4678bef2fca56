"""The Inside one cycle scene: one period of the response after wear, animated, against the exact orbit."""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
import param

import fretwear
from fretwear import figures
from fretwear.figures.sketch import (
    LAYERS,
    STATE_COLORS,
    STATE_NAMES,
    model_sketch,
    sketch_layers,
    sketch_scale,
)

from ..animation import named
from ..glossary import term
from ..state import EXACT, EXACT_POINT, Settings, Task
from .base import EMPTY, Scene, Selection, history_notes, ok_value

#: frames of the animation of one period (the cycle scene): the browser plays them at 32 per second at
#: its default speed (a period in 4 s)
ANIMATION_FRAMES = 128


def _relative(value: float, reference: float) -> str:
    """``value`` against ``reference`` as a signed percentage (in words when the reference is 0)."""
    if reference == 0:
        return "0 (exact 0)" if value == 0 else f"{value:.3g} (exact 0)"
    return f"{value / reference - 1:+.1%}"


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
        return ok_value(self.results.get(EXACT_POINT))

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
        return ok_value(self.results.get("point"))

    def _notes(self) -> list[str]:
        sol = self._point()
        if sol is None:
            return []
        notes = []
        if not sol.converged:
            notes.append(f"the periodic solve did not converge: {sol.message}")
        h = ok_value(self.results.get("history"))
        return notes + ([] if h is None else history_notes([h]))

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
        sketch = model_sketch(sol.model, title=self._sketch_title(k), **self._instant(sol, k))
        if not live:
            return sketch
        # the browser animates these layers and the title (app.animation.Player), found by name
        color = {"interface": {"glyph": "sketch-color"}}
        layers = [
            named(layer, source=f"sketch-{name}", **color.get(name, {}))
            for layer, name in zip(sketch, LAYERS, strict=True)
        ]
        return named(sketch.clone(layers), title="sketch-title")

    def _sketch_title(self, k: int) -> str:
        sol = self._point()
        state = int(sol.state[0, k])
        scale = sketch_scale(sol.displacement)
        phase = sol.time[k] * sol.omega / (2 * np.pi)
        return f"t / T = {phase:.2f}: {STATE_NAMES[state]} (displacements × {scale:.2g})"

    @staticmethod
    def _instant(sol, k: int) -> dict:
        """The arguments of :func:`model_sketch` at time sample ``k`` of ``sol``."""
        return {
            "displacement": tuple(sol.displacement[:, k]),
            "scale": sketch_scale(sol.displacement),
            "state": int(sol.state[0, k]),
            "wear": float(sol.wear[0]),
            "normal_load": float(sol.normal_loads[0]),
        }

    def animation(self) -> dict | None:
        """Every frame of one period for the browser's player (None while there is no solution): ``t``
        (t / T), the loop's dot ``loop_x``, ``loop_y``, the sketch's ``title``, the interface's
        ``color`` and ``layers`` (:func:`sketch_layers` of each frame), one entry per frame."""
        sol = self._point()
        if sol is None:
            return None
        samples = [self.sample(frame) for frame in range(ANIMATION_FRAMES)]
        return {
            "t": [float(sol.time[k] * sol.omega / (2 * np.pi)) for k in samples],
            "loop_x": [float(sol.relative_displacement[0][k]) for k in samples],
            "loop_y": [float(sol.contact_force[0][k]) for k in samples],
            "title": [self._sketch_title(k) for k in samples],
            "color": [STATE_COLORS[int(sol.state[0, k])] for k in samples],
            "layers": [sketch_layers(sol.model, **self._instant(sol, k)) for k in samples],
        }

    def _cursor(self, name: str, live: bool) -> list:
        """The animation's current instant on the page's figure ``name`` (none in exports): a vertical
        line at ``t / T`` on the signals, a dot on the hysteresis loop (named for the browser's player)."""
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
            dot = figures.styled(hv.Points([xy], ["x", "y"]), {"color": "black"}, {"size": 12}, {"s": 60})
            return [named(dot, source="cursor-loop")]
        line = figures.styled(hv.VLine(t), {"color": "black"}, {"line_width": 2}, {"linewidth": 1.5})
        return [named(line, glyph=f"cursor-{name}")]

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
            # short: the title fits the plot's width at every layout (the energy is the loop's area)
            title=f"Hysteresis loop: {energy['hysteresis loop']:.4g} J/cycle (exact {energy[EXACT]:.4g})",
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
