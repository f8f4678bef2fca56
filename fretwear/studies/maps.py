"""Wear maps: wear ``W(f, N)`` over frequency x cycle count (paper Fig. 7, 13-14).

:func:`wear_map` runs :func:`fretwear.wear.wear_history` at every frequency of a
grid (in a thread pool: the compiled kernels release the GIL) and samples each
history on a cycle grid, with the relative displacement (Fig. 13-14) and the
response amplitude, from which :meth:`WearMap.pseudo_frf` gives the pseudo-FRFs
at chosen cycle counts (Fig. 8-9).
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from ..model import Model
from ..wear import WearHistory, check_wear_inputs, wear_history

__all__ = ["WearMap", "wear_map"]


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
    method: str = "auto",
    kw: float = 1e-11,
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
        return wear_history(model, 2 * np.pi * f, method, kw=kw, cycles=float(cycles.max()), **options)

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
