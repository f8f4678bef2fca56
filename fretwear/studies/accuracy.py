"""What accuracy costs: a ladder of discretisations against a converged reference.

:func:`cost_ladder` runs, for one case (model, frequency, optional wear horizon),
a ladder of settings — harmonic count ``Nh``, samples per period, slow-time
tolerance, polynomial degree, and the methods (DLFT, shooting, exact load path,
stepping, polynomial, time integration) — measures the wall time of each rung and its
error against a reference, on the quantities users look at: the first-harmonic
amplitude of ``x1``, the half peak-to-peak relative displacement, the sliding
distance per cycle and, with a wear horizon, ``w(N)``. :meth:`CostStudy.recommend`
returns the cheapest rung that reaches a target error and is not the reference's
own method (shooting: its error is round-off); :meth:`CostStudy.summary` says so
in a sentence, and when only the reference meets the target. Wear rungs are named
by slow-time scheme and dynamics: ``exact-dlft`` (the exact slow time on DLFT
dynamics), ``stepping`` (on DLFT), ``stepping-shooting``, ``polynomial``, ``time``.

References: the exact periodic solution by shooting on the event-driven time
integrator (periodicity residual 1e-12) for the periodic quantities, and for
``w(N)`` the exact method on the exact dynamics (Archard's law integrated on the
sliding table of shooting solutions, ``fretwear.wear.sliding``) where it
applies, else slow-time stepping with shooting dynamics at a tight tolerance
(1e-5 of ``u0``); both are named in :attr:`CostStudy.reference`. The references
are not rungs: a rung is timed (median of repeats) and measured against them,
shooting included.
"""

from __future__ import annotations

import time
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import partial

import numpy as np

from ..hbm.harmonics import default_samples
from ..hbm.periodic import solve_periodic
from ..model import Model
from ..time.shooting import shooting
from ..wear import exact_path_applies, wear_history

__all__ = ["Rung", "CostStudy", "cost_ladder", "QUANTITIES"]

#: error measures, in the order of the columns of a study
QUANTITIES = ("x1_h1", "xr_half_p2p", "sliding_distance", "wear")


@dataclass
class Rung:
    """One discretisation: its settings, wall time (s) and relative errors per quantity.

    ``reference``: the rung is the reference's own method (exact shooting), timed as users would run
    it; its error is round-off, so it is never the recommendation (:meth:`CostStudy.recommend`).
    """

    method: str
    settings: dict
    wall_time: float
    errors: dict[str, float]
    converged: bool = True
    reference: bool = False

    @property
    def label(self) -> str:
        return self.method + " " + " ".join(f"{k}={v:g}" for k, v in self.settings.items())

    def error(self, quantity: str | None = None) -> float:
        """Error on ``quantity``, or the largest error over the measured quantities."""
        if quantity is not None:
            return self.errors.get(quantity, np.nan)
        values = [v for v in self.errors.values() if np.isfinite(v)]
        return max(values) if values else np.nan


@dataclass
class CostStudy:
    """Rungs of a cost ladder and the reference they were measured against."""

    frequency: float
    rungs: list[Rung]
    reference: dict[str, str]
    reference_values: dict[str, float] = field(default_factory=dict)

    def required(self, quantity: str | None = None) -> tuple[str, ...]:
        """What a rung must measure to answer for ``quantity``; for all (``None``): ``w(N)`` when the
        study has wear rungs (the answer users come for), else every periodic quantity."""
        if quantity is not None:
            return (quantity,)
        if any(np.isfinite(r.errors.get("wear", np.nan)) for r in self.rungs):
            return ("wear",)
        return tuple(q for q in QUANTITIES if q != "wear")

    def within(self, target: float, quantity: str | None = None) -> list[Rung]:
        """Converged rungs whose error on :meth:`required` quantities is at most ``target``."""
        if not target > 0:
            raise ValueError(f"target must be > 0 (a relative error), got {target!r}")
        need = self.required(quantity)
        return [r for r in self.rungs if r.converged and all(r.errors.get(q, np.inf) <= target for q in need)]

    def recommend(self, target: float, quantity: str | None = None) -> Rung | None:
        """Cheapest rung within ``target`` that is not the reference (None: only the reference meets it,
        or nothing does; :meth:`summary` says which)."""
        ok = [r for r in self.within(target, quantity) if not r.reference]
        return min(ok, key=lambda r: r.wall_time) if ok else None

    def summary(self, target: float, quantity: str | None = None) -> str:
        """The recommendation in one sentence, with what the exact answer costs."""
        best = self.recommend(target, quantity)
        kind = "wear" if "wear" in self.required(quantity) else "periodic"
        exact = f"the exact answer: {self.reference.get(kind, 'the reference')}"
        if best is None:
            return f"no approximation meets {target:g}: only the reference does ({exact})"
        return f"cheapest rung within {target:g}: {best.label} ({best.wall_time * 1e3:.1f} ms); {exact}"

    def to_xarray(self):
        """The rungs as an ``xarray.Dataset``, with units and long names.

        ``wall_time``, ``converged`` and ``error`` per ``quantity`` along ``rung``, the
        settings (``Nh``, ``N``, ``tol``, ``degree``; NaN where a rung has none) as coordinates.
        """
        from .._xarray import cost_dataset

        return cost_dataset(self)

    def pareto(self, quantity: str | None = None) -> list[Rung]:
        """Rungs not beaten by a faster and more accurate one, by increasing wall time."""
        front, best = [], np.inf
        for r in sorted(self.rungs, key=lambda r: r.wall_time):
            e = r.error(quantity)
            if r.converged and e < best:
                front.append(r)
                best = e
        return front


def _timed(fn, budget: float = 0.2, repeats: int = 5):
    """Median wall time (s) of up to ``repeats`` runs of ``fn`` within about ``budget`` s, and its result."""
    times = []
    while True:
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
        if len(times) >= repeats or sum(times) + times[-1] > budget:
            return float(np.median(times)), out


def _rel(value: float, ref: float) -> float:
    return abs(value / ref - 1) if ref != 0 else abs(value)


def cost_ladder(
    model: Model,
    frequency: float,
    *,
    harmonics=(1, 3, 5, 7, 11, 15, 21, 31, 41, 64),
    sample_factors=(4, 8, 16, 32),
    kw: float | None = None,
    cycles: float | None = None,
    tolerances=(1e-1, 1e-2, 1e-3),
    degrees=(2, 4, 6, 8),
    wear_harmonics=(3, 7, 21),
    include_time_integration: bool = True,
    progress: Callable[[float], None] | None = None,
) -> CostStudy:
    """Error against wall time for a ladder of discretisations at ``frequency`` (Hz).

    Parameters
    ----------
    model : Model
        Friction contacts only, positive definite mass (the shooting reference).
    frequency : float
        Excitation frequency (Hz), > 0.
    harmonics : sequence of int
        ``Nh`` of the DLFT rungs (default samples per period).
    sample_factors : sequence of int
        Samples per period as multiples of ``Nh`` at ``Nh = 21`` (power of two above).
    kw, cycles : float, optional
        Archard coefficient (1/N) and horizon (cycles): adds the wear rungs
        (the exact load path at ``wear_harmonics`` when it applies, stepping
        with DLFT dynamics at ``wear_harmonics`` x ``tolerances``, stepping
        with shooting dynamics, the polynomial method at ``degrees``, time
        integration at ``tolerances``), judged on ``w(N)``.
    tolerances, degrees, wear_harmonics : sequence
        Slow-time tolerances (fraction of ``u0``), polynomial degrees and
        ``Nh`` of the wear rungs.
    include_time_integration : bool
        Include the time-integration wear rungs.
    progress : callable, optional
        ``progress(fraction)`` after the reference and after each rung, outside
        the timed calls, with the fraction of the computations done (0 to 1);
        an exception it raises stops the ladder and propagates (a caller's
        cancellation).

    Returns
    -------
    CostStudy
        The rungs: shooting, DLFT, then the wear rungs in the order above.
    """
    if not np.isfinite(frequency) or frequency <= 0:
        raise ValueError(f"frequency must be > 0 Hz, got {frequency!r}")
    if (kw is None) != (cycles is None):
        raise ValueError("kw and cycles go together: give both for the wear rungs, or neither")
    omega = 2 * np.pi * frequency
    wear_runs = []
    if kw is not None:
        if exact_path_applies(model):
            wear_runs += [("exact-dlft", {"Nh": nh}, dict(harmonics=nh)) for nh in wear_harmonics]
        wear_runs += [("stepping", {"Nh": nh, "tol": tol}, dict(harmonics=nh, tol=tol))
                      for nh in wear_harmonics for tol in tolerances]  # fmt: skip
        wear_runs += [
            ("stepping-shooting", {"tol": tol}, dict(dynamics="shooting", tol=tol)) for tol in tolerances
        ]
        wear_runs += [("polynomial", {"Nh": 3, "degree": d}, dict(harmonics=3, degree=d)) for d in degrees]
        if include_time_integration:
            wear_runs += [("time", {"tol": tol}, dict(tol=tol)) for tol in tolerances]
    total = 2 + len(harmonics) + len(sample_factors) + (1 + len(wear_runs) if kw is not None else 0)
    done = [0]

    def advance() -> None:
        done[0] += 1
        if progress is not None:
            progress(done[0] / total)

    solve_periodic(model, omega, 3)  # compile and warm the kernels before timing
    t_ref, ref = _timed(lambda: shooting(model, omega, tol=1e-12), repeats=1)
    if not ref.converged:
        raise RuntimeError(f"the shooting reference did not converge at {frequency:g} Hz")
    B = model.relative_map()
    ref_values = {
        "x1_h1": float(ref.amplitude[0]),
        "xr_half_p2p": float(ref.relative_half_peak_to_peak[0]) if len(B) else np.nan,
        "sliding_distance": float(ref.sliding_distance[0]) if model.friction else np.nan,
    }
    reference = {"periodic": f"shooting, tol 1e-12 (residual {ref.residual:.1e}, {t_ref * 1e3:.0f} ms)"}
    rungs = []
    advance()

    def periodic_errors(sol) -> dict[str, float]:
        rel_p2p = sol.relative_half_peak_to_peak[0] if len(B) else np.nan
        slid = sol.sliding_distance[0] if model.friction else np.nan
        return {
            "x1_h1": _rel(sol.amplitude[0], ref_values["x1_h1"]),
            "xr_half_p2p": _rel(rel_p2p, ref_values["xr_half_p2p"]),
            "sliding_distance": _rel(slid, ref_values["sliding_distance"]) if ref_values["sliding_distance"]
            else float(abs(slid)),
        }  # fmt: skip

    t, sol = _timed(lambda: shooting(model, omega))
    rungs.append(Rung("shooting", {}, t, periodic_errors(sol), sol.converged, reference=True))
    advance()
    for nh in harmonics:
        t, sol = _timed(lambda nh=nh: solve_periodic(model, omega, int(nh)))
        rungs.append(Rung("dlft", {"Nh": int(nh), "N": default_samples(int(nh))}, t, periodic_errors(sol),
                          sol.converged))  # fmt: skip
        advance()
    for factor in sample_factors:
        n = max(43, 1 << int(np.ceil(np.log2(factor * 21))))
        t, sol = _timed(lambda n=n: solve_periodic(model, omega, 21, samples=n))
        rungs.append(Rung("dlft", {"Nh": 21, "N": n}, t, periodic_errors(sol), sol.converged))
        advance()
    if kw is not None:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)
            if exact_path_applies(model):
                name, opts = "exact method on the exact dynamics (sliding table)", {"dynamics": "shooting"}
                t_w, exact = _timed(lambda: wear_history(model, omega, "exact", kw=kw, cycles=cycles,
                                                         **opts), repeats=1)  # fmt: skip
            else:
                name = "stepping with shooting dynamics, tol 1e-5"
                opts = {"dynamics": "shooting", "tol": 1e-5}
                t_w, exact = _timed(lambda: wear_history(model, omega, "stepping", kw=kw, cycles=cycles,
                                                         **opts), repeats=1)  # fmt: skip
            reference["wear"] = f"{name} ({t_w:.2f} s)"
            advance()

            def werr(h) -> float:
                return h.error_against(exact, fractions=())["wear"]

            for label, settings, opts in wear_runs:
                method = label.split("-")[0]  # exact-dlft, stepping-shooting: the scheme, then the dynamics
                run = partial(wear_history, model, omega, method, kw=kw, cycles=cycles, **opts)
                t, h = _timed(run, repeats=3)
                rungs.append(Rung(label, settings, t, {"wear": werr(h)}, h.converged))
                advance()
    return CostStudy(frequency, rungs, reference, ref_values)
