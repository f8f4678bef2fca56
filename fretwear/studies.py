"""Studies built on the slow-time wear solvers: the paper's figures as data.

* :func:`wear_history` runs one method at one frequency (the single entry
  point used by the CLI and the app);
* :func:`wear_map`: wear ``W(f, N)`` over a frequency grid and a cycle grid
  (paper Fig. 7), with the relative displacement (Fig. 13-14) and the
  response amplitude, from which :meth:`WearMap.pseudo_frf` gives the pseudo-
  FRFs at chosen cycle counts (Fig. 8-9);
* :func:`harmonic_convergence`: ``w(N)`` for several harmonic counts (Fig. 10);
* :func:`compare_methods`: stepping, polynomial and time integration at one
  frequency (Fig. 11-12).

Frequencies are independent and are spread over a thread pool; the
compiled DLFT kernels release the GIL.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from typing import Literal

import numpy as np

from .model import Model
from .wear import (
    WearHistory,
    check_wear_inputs,
    exact_path_applies,
    wear_exact,
    wear_polynomial,
    wear_stepping,
)

__all__ = [
    "WearMap",
    "wear_history",
    "wear_map",
    "harmonic_convergence",
    "compare_methods",
    "stick_limit",
    "regime_map",
    "shooting_sweep",
]

Method = Literal["auto", "exact", "stepping", "polynomial", "time"]


def wear_history(
    model: Model,
    omega: float,
    method: Method = "auto",
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int = 21,
    samples: int | None = None,
    tol: float = 1e-3,
    degree: int = 4,
    basis: str = "legendre",
    dynamics: str = "dlft",
    fixed_step: float | None = None,
) -> WearHistory:
    """Wear evolution at ``omega`` (rad/s) by ``method`` (see :mod:`fretwear.wear`).

    ``"exact"`` integrates along the exact load path (one friction contact);
    ``"auto"`` picks it when it applies and DLFT dynamics are asked for, else
    stepping. ``tol`` is the local error tolerance on ``w / u0`` of stepping and
    of the cycle jumps of time integration; ``degree`` and ``basis`` set the
    polynomial method; ``dynamics`` the periodic solver of stepping.
    """
    if method == "auto":
        method = (
            "exact" if exact_path_applies(model) and dynamics == "dlft" and not fixed_step else "stepping"
        )
    if method == "exact":
        return wear_exact(model, omega, kw=kw, cycles=cycles, harmonics=harmonics, samples=samples)
    if method == "stepping":
        return wear_stepping(model, omega, kw=kw, cycles=cycles, harmonics=harmonics, samples=samples,
                             tol=tol, dynamics=dynamics, fixed_step=fixed_step)  # fmt: skip
    if method == "polynomial":
        return wear_polynomial(model, omega, kw=kw, cycles=cycles, harmonics=harmonics, samples=samples,
                               degree=degree, basis=basis)  # fmt: skip
    if method == "time":
        from .wear_time import integrate_wear

        return integrate_wear(model, omega, cycles, kw=kw, tol=tol)
    raise ValueError(f"method must be 'auto', 'exact', 'stepping', 'polynomial' or 'time', got {method!r}")


@dataclass
class WearMap:
    """Wear and response over frequency x cycle count (paper Fig. 7, 13-14).

    Attributes
    ----------
    frequency : ndarray, shape (nf,)
        Frequencies (Hz).
    cycles : ndarray, shape (nN,)
        Cycle counts.
    wear : ndarray, shape (nf, nN, n_friction)
        Wear depth (m).
    amplitude, half_peak_to_peak : ndarray, shape (nf, nN, n)
        First-harmonic amplitude and half peak-to-peak of every DOF (m).
    relative_half_peak_to_peak : ndarray, shape (nf, nN, n_contacts)
        Half peak-to-peak relative displacement of each contact (m).
    histories : list of WearHistory
        The per-frequency results (status, solves, warnings).
    """

    frequency: np.ndarray
    cycles: np.ndarray
    wear: np.ndarray
    amplitude: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    u0: np.ndarray
    histories: list[WearHistory]

    @property
    def wear_fraction(self) -> np.ndarray:
        """``w / u0``, shape (nf, nN, n_friction)."""
        return self.wear / self.u0

    @property
    def converged(self) -> np.ndarray:
        """Per frequency: the history ran without a failed periodic solve."""
        return np.array([h.converged for h in self.histories])

    def pseudo_frf(self, cycles) -> np.ndarray:
        """First-harmonic amplitudes at cycle counts ``cycles``, shape (len(cycles), nf, n) (Fig. 8-9).

        Linear interpolation in ``N`` between the map's cycle counts (held past the ends).
        """
        c = np.clip(np.atleast_1d(np.asarray(cycles, dtype=float)), self.cycles[0], self.cycles[-1])
        k = np.clip(np.searchsorted(self.cycles, c, side="right") - 1, 0, len(self.cycles) - 2)
        if len(self.cycles) == 1:
            return np.repeat(self.amplitude[None, :, 0], len(c), axis=0)
        t = ((c - self.cycles[k]) / (self.cycles[k + 1] - self.cycles[k]))[:, None, None]
        a = np.moveaxis(self.amplitude, 1, 0)  # (nN, nf, n)
        return (1 - t) * a[k] + t * a[k + 1]

    def long_table(self) -> dict[str, np.ndarray]:
        """Columns of the long-format table (one row per frequency and cycle count)."""
        nf, nN = len(self.frequency), len(self.cycles)
        cols = {"f_hz": np.repeat(self.frequency, nN), "cycles": np.tile(self.cycles, nf)}
        for j in range(self.wear.shape[2]):
            suffix = "" if self.wear.shape[2] == 1 else str(j + 1)
            cols[f"w{suffix}"] = self.wear[:, :, j].ravel()
            cols[f"w{suffix}_over_u0"] = self.wear_fraction[:, :, j].ravel()
        for i in range(self.amplitude.shape[2]):
            cols[f"x{i + 1}_h1"] = self.amplitude[:, :, i].ravel()
            cols[f"x{i + 1}_half_p2p"] = self.half_peak_to_peak[:, :, i].ravel()
        for j in range(self.relative_half_peak_to_peak.shape[2]):
            suffix = "" if self.relative_half_peak_to_peak.shape[2] == 1 else str(j + 1)
            cols[f"xr{suffix}_half_p2p"] = self.relative_half_peak_to_peak[:, :, j].ravel()
        return cols


def wear_map(
    model: Model,
    frequencies,
    cycles,
    *,
    method: Method = "auto",
    kw: float = 1e-11,
    harmonics: int = 21,
    workers: int = 2,
    **options,
) -> WearMap:
    """Wear map over ``frequencies`` (Hz) and the cycle grid ``cycles`` (paper Fig. 7).

    Each frequency runs :func:`wear_history` to ``max(cycles)`` (or until the
    contacts are worn to 0.99 u0; past that the last state is held) and is
    sampled at ``cycles``. Frequencies that stick fully are not stepped.
    ``options`` go to :func:`wear_history`.
    """
    frequencies = np.asarray(frequencies, dtype=float)
    cycles = np.asarray(cycles, dtype=float)
    if frequencies.ndim != 1 or frequencies.size == 0 or np.any(~(frequencies > 0)):
        raise ValueError("frequencies must be a non-empty 1-D array of values > 0 Hz")
    if cycles.ndim != 1 or cycles.size == 0 or np.any(~(cycles >= 0)) or np.any(np.diff(cycles) <= 0):
        raise ValueError("cycles must be a non-empty increasing 1-D array of values >= 0")
    check_wear_inputs(model, kw, float(cycles.max()), options.get("degree"))

    def one(f):
        return wear_history(model, 2 * np.pi * f, method, kw=kw, cycles=float(cycles.max()),
                            harmonics=harmonics, **options)  # fmt: skip

    if workers > 1 and len(frequencies) > 1:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            histories = list(pool.map(one, frequencies))
    else:
        histories = [one(f) for f in frequencies]
    samples = [h.at(cycles) for h in histories]
    return WearMap(
        frequency=frequencies,
        cycles=cycles,
        wear=np.stack([s["wear"] for s in samples]),
        amplitude=np.stack([s["amplitude"] for s in samples]),
        half_peak_to_peak=np.stack([s["half_peak_to_peak"] for s in samples]),
        relative_half_peak_to_peak=np.stack([s["relative_half_peak_to_peak"] for s in samples]),
        u0=np.array([c.u0 for c in model.friction]),
        histories=histories,
    )


def harmonic_convergence(
    model: Model, frequency: float, harmonics=(1, 3, 7, 15, 21), **options
) -> dict[int, WearHistory]:
    """``w(N)`` at ``frequency`` (Hz) for several harmonic counts (paper Fig. 10), by stepping."""
    return {int(nh): wear_history(model, 2 * np.pi * frequency, "stepping", harmonics=int(nh), **options)
            for nh in harmonics}  # fmt: skip


def compare_methods(
    model: Model, frequency: float, methods=("stepping", "polynomial", "time"), **options
) -> dict[str, WearHistory]:
    """The same wear evolution at ``frequency`` (Hz) by several methods (paper Fig. 11-12).

    ``options`` are passed to every method (see :func:`wear_history`); give
    ``harmonics`` per method with a dict, e.g. ``harmonics={"polynomial": 3}``.
    """
    out = {}
    for method in methods:
        opts = {
            k: (v.get(method, v.get("default")) if isinstance(v, dict) else v) for k, v in options.items()
        }
        opts = {k: v for k, v in opts.items() if v is not None}
        out[method] = wear_history(model, 2 * np.pi * frequency, method, **opts)
    return out


def shooting_sweep(model: Model, omegas, **options) -> list:
    """Exact periodic responses by shooting at ``omegas`` (rad/s), each seeded by its predecessor.

    ``options`` go to :func:`fretwear.time_integration.shooting`.
    """
    from .time_integration import shooting

    out, guess = [], None
    for w in np.asarray(omegas, dtype=float):
        sol = shooting(model, w, guess, **options)
        out.append(sol)
        guess = sol.y0 if sol.converged else None
    return out


def stick_limit(model: Model, frequencies, harmonics: int = 1) -> np.ndarray:
    """Largest load ratio ``r = F_ex / (mu F_N)`` (relative to the model's forcing) that keeps full stick.

    Exact: the linear stuck solution at load factor ``s`` needs the stick force
    ``s * Lambda_stuck``; it stays in the friction cone while ``s <= 1 / stick_ratio``.
    Returns, per frequency (Hz), the load factor at the stick boundary (``inf`` for no
    active friction contact).
    """
    from .periodic import Problem

    out = []
    for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
        p = Problem(model, 2 * np.pi * f, harmonics)
        out.append(np.inf if p.n_active == 0 else 1.0 / p.stick_ratio())
    return np.array(out)


def regime_map(model: Model, frequencies, load_factors, harmonics: int = 7) -> dict[str, np.ndarray]:
    """Stick/slip regime over frequency (Hz) x load factor (forcing scaled by ``load_factors``).

    By homogeneity of the friction law, scaling the forcing by ``s`` is scaling
    ``r = F_ex / (mu F_N)`` by ``s``. Returns the fraction of the period spent
    slipping (first friction contact), the sliding distance per period, the
    first-harmonic amplitude of DOF 1 and the exact stick boundary per frequency.
    """
    from .continuation import sweep

    frequencies = np.asarray(frequencies, dtype=float)
    load_factors = np.asarray(load_factors, dtype=float)
    slip = np.zeros((len(load_factors), len(frequencies)))
    slid = np.zeros_like(slip)
    amp = np.zeros_like(slip)
    for i, s in enumerate(load_factors):
        sw = sweep(model.scaled(s), 2 * np.pi * frequencies, harmonics)
        for j, sol in enumerate(sw.solutions):
            slip[i, j] = np.mean(sol.state[0] == 1) if model.friction else 0.0
            slid[i, j] = sol.sliding_distance[0] if model.friction else 0.0
            amp[i, j] = sol.amplitude[0]
    return {"slip_fraction": slip, "sliding_distance": slid, "amplitude": amp,
            "stick_limit": stick_limit(model, frequencies)}  # fmt: skip
