"""The Regimes scene: linear and nonlinear FRFs without wear, and the stick/slip regime map."""

from __future__ import annotations

import numpy as np

from fretwear import figures

from ..glossary import term
from ..state import Settings, Task
from .base import EMPTY, HZ, X1, Scene, Selection, linear_curves, linear_table, no_wear, ok_value


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
        frf = ok_value(self.results.get("frf"))
        if frf is not None and not frf["converged"].all():
            bad = int((~frf["converged"]).sum())
            return [f"{bad} of {len(frf['converged'])} FRF points did not converge (shown as computed)"]
        return []

    def _figure_frf(self):
        curves = linear_curves(self)
        curves["nonlinear, no wear"] = no_wear(self)
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
        reg = ok_value(self.results.get("regime"))
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
            level_label="slip fraction 0.5",
            hline_label=f"current r = {s.model.r:.3g}",
            title=f"Stick/slip regimes (current r = {s.model.r:.3g})",
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        out = linear_table(self)
        frf = ok_value(self.results.get("frf"))
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
        reg = ok_value(self.results.get("regime"))
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
