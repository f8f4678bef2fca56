"""The FRF evolution scene: pseudo-FRFs of mass 1 at four cycle counts, against the exact answer."""

from __future__ import annotations

import numpy as np

from fretwear import figures

from ..glossary import term
from ..state import Settings, Task
from .base import (
    EMPTY,
    HZ,
    X1,
    Scene,
    Selection,
    exact_map,
    history_notes,
    linear_curves,
    linear_table,
    no_wear,
    ok_value,
)


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
        wm = ok_value(self.results.get("wear_map"))
        if exact:
            wm = exact_map(self, wm)
        return None if wm is None else wm.pseudo_frf(self._snapshots())[:, :, 0]

    def _notes(self) -> list[str]:
        wm = ok_value(self.results.get("wear_map"))
        return [] if wm is None else history_notes(wm.histories)

    def _findings(self) -> list[str]:
        p, ref = self._pseudo(), self._pseudo(exact=True)
        if p is None or ref is None:
            return []
        err = np.abs(p / ref - 1)
        if not np.isfinite(err).any():
            return []
        i, k = np.unravel_index(int(np.nanargmax(err)), err.shape)
        wm, s = ok_value(self.results.get("wear_map")), self.settings
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
        curves = linear_curves(self)
        wm, p, ref = ok_value(self.results.get("wear_map")), self._pseudo(), self._pseudo(exact=True)
        curves["no wear"] = no_wear(self)
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
        # the axis spans the worn responses, not the linear peaks (they squeezed the curves to the bottom)
        worn = [np.asarray(y, dtype=float) for key, (_x, y) in curves.items() if "linear" not in key]
        values = np.concatenate([y[np.isfinite(y) & (y > 0)] for y in worn]) if worn else np.zeros(0)
        ylim = (values.min() / 2, values.max() * 3) if values.size else None
        return figures.line_figure(
            curves,
            xlabel=HZ,
            ylabel=X1,
            logy=True,
            ylim=ylim,
            dashed=[*list(curves)[:2], *(f"{key} exact" for key in self._keys[1:])],
            legend_labels=shown,
            colors=colors,
            title=f"Pseudo-FRFs of mass 1, horizon {self.settings.horizon:.3g} cycles (exact dashed)",
        )

    def datasets(self) -> dict[str, dict[str, np.ndarray]]:
        out = linear_table(self)
        wm, p, ref = ok_value(self.results.get("wear_map")), self._pseudo(), self._pseudo(exact=True)
        if p is not None:
            out["pseudo_frfs"] = {"f_hz": wm.frequency} | {
                f"x1_h1_N{n:.6g}": p[i] for i, n in enumerate(self._snapshots())
            }
            if ref is not None:
                snaps = self._snapshots()
                out["pseudo_frfs"] |= {f"x1_h1_N{n:.6g}_exact": ref[i] for i, n in enumerate(snaps)}
        return out
