"""The Wear map scene: w / u0 over frequency and cycles, the history and pseudo-FRF at the selected point."""

from __future__ import annotations

import numpy as np

from fretwear import figures

from ..glossary import term
from ..state import EXACT, Settings, Task
from .base import (
    CYCLES,
    EMPTY,
    HZ,
    WEAR,
    X1,
    Scene,
    Selection,
    error_note,
    exact_map,
    history_notes,
    no_wear,
    ok_value,
)


def _band_error(wm, exact) -> str | None:
    """How far the cycles to 0.5 u0 of map ``wm`` are from the exact map's, over the band."""
    if wm is None or exact is None or wm.label == "exact":
        return None
    note = wm.error_note(exact)
    return None if note is None else f"{note} Exact contours dashed."


class WearMapScene(Scene):
    key = "wearmap"
    title = "Wear map"
    figure_names = ("wear_map", "history", "pseudo_frf")
    dataset_names = figure_names  # one data set per figure
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
        return ok_value(self.results.get("wear_map"))

    def _index(self) -> int:
        wm = self._map()
        grid = self.settings.frequencies if wm is None else wm.frequency
        return int(np.argmin(np.abs(grid - self.selection.frequency)))

    def _notes(self) -> list[str]:
        wm = self._map()
        return [] if wm is None else history_notes(wm.histories)

    def _findings(self) -> list[str]:
        error = error_note(self._history(), self._exact())
        wm = self._map()
        exact = exact_map(self, wm)
        if not (self._band[0] is wm and self._band[1] is exact):  # needs every history: once per map
            self._band = (wm, exact, _band_error(wm, exact))
        return [text for text in (error, self._band[2]) if text]

    _band: tuple = (None, None, None)

    def _exact(self):
        """The exact wear history at the selected row of the map (None while it computes, or failed)."""
        h, wm = ok_value(self.results.get(EXACT)), self._map()
        if h is None or wm is None or not np.isclose(h.frequency, wm.frequency[self._index()], rtol=1e-9):
            return None
        return h

    def _figure_wear_map(self):
        s, wm, sel = self.settings, self._map(), self.selection
        f, cycles = (s.frequencies, s.cycles) if wm is None else (wm.frequency, wm.cycles)
        z = np.zeros((len(f), len(cycles))) if wm is None else wm.wear_fraction[:, :, 0]
        exact = exact_map(self, wm)
        reference = None if exact is None else exact.wear_fraction[:, :, 0]
        title = f"Wear map ({s.label()}, wear coefficient {s.kw:.3g} 1/N)"
        return figures.wear_map_figure(
            f, cycles, z, title=title, point=(sel.frequency, sel.cycles), reference=reference,
            label=f"w/u₀ = 0.1, 0.5, 0.9 ({s.label()})",
        )  # fmt: skip

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
        curves = {"no wear": no_wear(self), "selected N": EMPTY if p is None else (wm.frequency, p)}
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
        exact = exact_map(self, wm)
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
