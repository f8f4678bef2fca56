"""The Methods scene: the slow-time methods, the harmonic convergence and the polynomial bases compared."""

from __future__ import annotations

from typing import Any

import numpy as np

from fretwear import figures
from fretwear.wear.polynomial import BASES

from ..glossary import term
from ..state import CONVERGENCE_HARMONICS, EXACT, METHODS, Settings, Task
from .base import CYCLES, EMPTY, WEAR, Scene, Selection, error_note, history_notes, ok_value


class MethodsScene(Scene):
    key = "methods"
    title = "Methods"
    figure_names = ("methods", "harmonics", "bases")
    dataset_names = figure_names  # one data set per figure
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
        return history_notes([h for name in METHODS if (h := ok_value(self.results.get(name))) is not None])

    def _findings(self) -> list[str]:
        exact, s = ok_value(self.results.get(EXACT)), self.settings
        errors = [error_note(ok_value(self.results.get(m)), exact) for m in METHODS]
        for b in BASES:
            label = f"{_basis_name(b)} ({s.label('polynomial')})"
            errors.append(error_note(ok_value(self.results.get(_basis_name(b))), exact, label))
        return [e for e in errors if e]

    def _curves(self, names) -> dict[str, tuple]:
        out = {}
        for name in names:
            h = ok_value(self.results.get(name))
            out[name] = EMPTY if h is None else figures.wear_curve(h, self.settings.dense_cycles)
        return out

    def _wear_figure(self, names, title: str, **options):
        """w / u0 over N (log) of the histories ``names``, the exact reference dashed when among them."""
        dashed = (EXACT,) if EXACT in names else ()
        return figures.line_figure(self._curves(names), xlabel=CYCLES, ylabel=WEAR, logx=True, padding=0.05,
                                   dashed=dashed, title=title, **options)  # fmt: skip

    def _figure_methods(self):
        return self._wear_figure(
            (*METHODS, EXACT),
            f"Slow-time methods at {self.selection.frequency:.4g} Hz",
            legend_labels={m: self.settings.label(m) for m in METHODS},
        )

    def _figure_harmonics(self):
        names = [f"Nh = {nh}" for nh in CONVERGENCE_HARMONICS]
        return self._wear_figure(
            names,
            f"Harmonic convergence (exact slow time on DLFT) at {self.selection.frequency:.4g} Hz",
            legend_labels={n: n.replace("Nh", "Nₕ") for n in names},
        )

    def _figure_bases(self):
        where = f"degree {self.settings.degree}, at {self.selection.frequency:.4g} Hz"
        return self._wear_figure(
            (*(_basis_name(b) for b in BASES), EXACT), f"Polynomial method by basis, {where}"
        )

    def _long(self, names, column: str) -> dict[str, np.ndarray]:
        rows = [(n, h) for n in names if (h := ok_value(self.results.get(n))) is not None]
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
