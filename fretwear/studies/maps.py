"""Wear maps: wear ``W(f, N)`` over frequency x cycle count (paper Fig. 7, 13-14).

:func:`wear_map` runs :func:`fretwear.wear.wear_history` at every frequency of a
grid (in a thread pool: the compiled kernels release the GIL) and samples each
history on a cycle grid, with the relative displacement (Fig. 13-14) and the
response amplitude, from which :meth:`WearMap.pseudo_frf` gives the pseudo-FRFs
at chosen cycle counts (Fig. 8-9).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass

import numpy as np

from ..model import Model
from ..wear import (
    METHODS,
    WearHistory,
    check_wear_inputs,
    describe,
    resolve_dynamics,
    resolve_method,
    wear_history,
)
from ..wear.exact import exact_wear_map

__all__ = ["WearMap", "wear_map", "map_of_histories", "LazyHistories"]


class LazyHistories(Sequence):
    """Per-frequency wear histories, each computed on first access.

    A map on the exact dynamics does not need them (``exact_wear_map()``);
    a scene that shows the history at one frequency builds that one only.
    ``+`` joins two sequences (chunks of a map).
    """

    def __init__(self, frequencies, build: Callable[[float], WearHistory]):
        self._items = [(float(f), build) for f in np.atleast_1d(frequencies)]
        self._done: dict[int, WearHistory] = {}

    def __len__(self) -> int:
        return len(self._items)

    def __getitem__(self, i):
        if isinstance(i, slice):
            return [self[k] for k in range(*i.indices(len(self)))]
        i = range(len(self))[i]
        if i not in self._done:
            f, build = self._items[i]
            self._done[i] = build(f)
        return self._done[i]

    def built(self) -> list[WearHistory]:
        """The histories computed so far (none is computed here)."""
        return [self._done[k] for k in sorted(self._done)]

    def through(self, get: Callable[[float, Callable[[float], WearHistory]], WearHistory]) -> LazyHistories:
        """The same histories, each built by ``get(f, build)`` on its first access: e.g. a result cache
        that returns a history already computed for frequency ``f`` (Hz) or calls ``build(f)``."""
        joined = LazyHistories([], lambda f: None)
        joined._items = [(f, lambda f_, b=b: get(f_, b)) for f, b in self._items]
        joined._done = dict(self._done)
        return joined

    def __add__(self, other: Sequence[WearHistory]) -> LazyHistories:
        joined = LazyHistories([], lambda f: None)
        mine = [
            (f, lambda _f, h=self._done[k]: h) if k in self._done else (f, b)
            for k, (f, b) in enumerate(self._items)
        ]
        theirs = (
            other._items
            if isinstance(other, LazyHistories)
            else [(h.omega / (2 * np.pi), lambda _f, h=h: h) for h in other]
        )
        joined._items = mine + [(f, b) for f, b in theirs]
        return joined


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
    histories : sequence of WearHistory
        The per-frequency results (status, solves, warnings); a ``LazyHistories``
        for maps on the exact dynamics.
    label : str
        What ran, slow-time scheme and dynamics apart (:func:`fretwear.wear.describe`).
    """

    frequency: np.ndarray
    cycles: np.ndarray
    wear: np.ndarray
    amplitude: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    u0: np.ndarray
    histories: Sequence[WearHistory]
    label: str = ""

    @property
    def wear_fraction(self) -> np.ndarray:
        """``w / u0``, shape (nf, nN, n_friction)."""
        return self.wear / self.u0

    @property
    def converged(self) -> np.ndarray:
        """Per frequency: the history ran without a failed periodic solve."""
        if isinstance(self.histories, LazyHistories):  # a map on sliding tables: a failure raises
            return np.ones(len(self.histories), dtype=bool)
        return np.array([h.converged for h in self.histories])

    def to_xarray(self):
        """The map over ``frequency`` x ``cycles`` as an ``xarray.Dataset``, with units and long names.

        ``w`` and ``wear_fraction`` per ``friction_contact``, ``amplitude`` per ``dof``,
        ``converged`` per frequency.
        """
        from .._xarray import wear_map_dataset

        return wear_map_dataset(self)

    def _repr_html_(self) -> str:
        from .._html import summary_html

        return summary_html(self)

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

    def error_note(self, exact: WearMap, fraction: float = 0.5) -> str | None:
        """How far this map's cycles to ``fraction u0`` are from those of the ``exact`` map, in one
        sentence (None when neither reaches it anywhere)."""
        ours = np.array([h.cycles_to(fraction) if h.converged else np.nan for h in self.histories])
        ref = np.array([h.cycles_to(fraction) for h in exact.histories])
        err = ours / ref - 1
        both = np.isfinite(err)
        if not both.any():
            return None
        k = int(np.nanargmax(np.abs(err)))
        worst = f"{abs(err[k]):.1%} {'early' if err[k] < 0 else 'late'} at {self.frequency[k]:.4g} Hz"
        return (
            f"{self.label} over the band: cycles to {fraction:.0%} of u₀ up to {worst} against the exact "
            f"answer (median |error| {np.nanmedian(np.abs(err)):.1%} over the {int(both.sum())} frequencies "
            f"where both reach it; the exact answer reaches it at {int(np.isfinite(ref).sum())} of "
            f"{len(ref)})."
        )

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

    Each frequency runs :func:`~fretwear.wear_history` to ``max(cycles)`` (or until the
    contacts are worn to 0.99 u0; past that the last state is held) and is
    sampled at ``cycles``. Frequencies that stick fully are not stepped.
    ``options`` go to :func:`~fretwear.wear_history`. The exact method on the exact
    dynamics (``dynamics="shooting"``) samples the map directly from the
    sliding tables (``exact_wear_map()``: exact at every
    cycle count, no history needed) and computes a frequency's history only
    when it is asked for (``LazyHistories``).
    """
    frequencies = np.asarray(frequencies, dtype=float)
    cycles = np.asarray(cycles, dtype=float)
    if frequencies.ndim != 1 or frequencies.size == 0 or np.any(~(frequencies > 0)):
        raise ValueError("frequencies must be a non-empty 1-D array of values > 0 Hz")
    if cycles.ndim != 1 or cycles.size == 0 or np.any(~(cycles >= 0)) or np.any(np.diff(cycles) <= 0):
        raise ValueError("cycles must be a non-empty increasing 1-D array of values >= 0")
    check_wear_inputs(model, kw, float(cycles.max()), options.get("degree"))

    horizon = float(cycles.max())

    def one(f):
        return wear_history(model, 2 * np.pi * f, method, kw=kw, cycles=horizon, **options)

    u0 = np.array([c.u0 for c in model.friction])
    name = resolve_method(model, method, options.get("fixed_step"))
    dynamics = None
    if "dynamics" in METHODS[name].options:
        dynamics = resolve_dynamics(model, options.get("dynamics", "auto"), options.get("harmonics"),
                                    options.get("samples"))  # fmt: skip
    if name == "exact" and dynamics == "shooting" and kw > 0:  # read straight off the sliding tables
        extra = sorted(k for k, v in options.items() if k not in METHODS[name].options and v is not None)
        if extra and method != "auto":
            raise ValueError(f"method {name!r} takes no option {', '.join(map(repr, extra))}")
        arrays = exact_wear_map(model, 2 * np.pi * frequencies, cycles, kw=kw, workers=workers)
        arrays.pop("stuck")
        return WearMap(frequencies, cycles, **arrays, u0=u0, histories=LazyHistories(frequencies, one),
                       label=describe("exact", "shooting"))  # fmt: skip
    if workers > 1 and len(frequencies) > 1:
        with ThreadPoolExecutor(max_workers=workers) as pool:
            histories = list(pool.map(one, frequencies))
    else:
        histories = [one(f) for f in frequencies]
    return map_of_histories(model, frequencies, cycles, histories)


def map_of_histories(model: Model, frequencies, cycles, histories: Sequence[WearHistory]) -> WearMap:
    """The wear map of one history per frequency (Hz), each sampled at the cycle counts ``cycles`` (held
    past its end): what :func:`wear_map` returns once its histories are computed."""
    samples = [h.at(cycles) for h in histories]
    return WearMap(
        frequency=np.asarray(frequencies, dtype=float),
        cycles=np.asarray(cycles, dtype=float),
        wear=np.stack([s["wear"] for s in samples]),
        amplitude=np.stack([s["amplitude"] for s in samples]),
        half_peak_to_peak=np.stack([s["half_peak_to_peak"] for s in samples]),
        relative_half_peak_to_peak=np.stack([s["relative_half_peak_to_peak"] for s in samples]),
        u0=np.array([c.u0 for c in model.friction]),
        histories=list(histories),
        label=histories[0].label,
    )
