"""What every slow-time method shares: Archard's law, its inputs, its result type.

Wear changes the dynamics only through the normal loads
``F_N,j(w_j) = k_n,j (u0_j - w_j)`` clipped at zero (eq. 30d). Archard's law
(eq. 15, 30c) over one period of the steady response gives the slow-time
equation, with ``N`` the number of physical vibration cycles,

    dw_j / dN = K_w F_N,j(w) s_j(w),

where ``s_j`` is the distance slid by contact ``j`` per period (m) in the
periodic response at wear ``w``. ``K_w`` is Archard's coefficient in m per
(N m slid), i.e. 1/N.

**Normalised slow time.** For a contact whose sliding distance per cycle does
not depend on the load, ``w / u0 = 1 - exp(-K_w k_n s N)``; ``K_w k_n N`` (m^-1 per
metre slid) is therefore the natural slow time, and the histories expose
``w / u0`` against ``K_w k_n N`` (:attr:`WearHistory.normalised_time`).
Results depend on ``K_w`` and ``N`` only through ``K_w N``.

**Scale separation.** The methods assume that wear barely changes over one
cycle. A warning is raised when the wear per cycle at the start exceeds
``TWO_SCALE_LIMIT * u0`` (the paper's ``K_w = 1e-6`` wears the contact through in
less than a cycle; ``K_w = 1e-11`` is a realistic default).

Here: :class:`WearHistory` (the result of every method), its labels
(:func:`describe`), the :class:`Recorder` that builds it, the cycle grids, the
input checks (:func:`check_wear_inputs`) and the two-scale check.
"""

from __future__ import annotations

import bisect
import warnings
from dataclasses import dataclass, field, replace

import numpy as np

from ..model import Model

__all__ = [
    "WearHistory",
    "Recorder",
    "check_wear_inputs",
    "clip_wear",
    "two_scale_warning",
    "cycle_grid",
    "snapshot_cycles",
    "describe",
    "TWO_SCALE_LIMIT",
]

#: wear per cycle, as a fraction of u0, above which the two-scale assumption is flagged
TWO_SCALE_LIMIT = 1e-2


@dataclass
class WearHistory:
    """Evolution of wear and response over the slow time ``N`` (cycles) at one frequency.

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    method : str
        The method that ran: ``"exact"``, ``"stepping"``, ``"polynomial"`` or ``"time"``.
    cycles : ndarray, shape (K,)
        Cycle counts ``N`` of the records.
    wear, normal_load, rate, sliding_distance : ndarray, shape (K, n_friction)
        Wear depth (m), normal load (N), wear rate ``dw/dN`` (m/cycle) and
        distance slid per cycle (m) of each friction contact.
    amplitude, half_peak_to_peak : ndarray, shape (K, n)
        First-harmonic amplitude and half peak-to-peak displacement of every DOF (m).
    relative_half_peak_to_peak : ndarray, shape (K, n_contacts)
        Half peak-to-peak relative displacement of every contact (m).
    u0, kn : ndarray, shape (n_friction,)
        Initial interference (m) and normal stiffness (N/m) of each friction contact.
    kw : float
        Archard coefficient (1/N).
    dynamics : str
        The periodic dynamics the slow time ran on: ``"shooting"`` (the exact
        event-driven dynamics), ``"dlft"`` (harmonic balance, truncated at
        ``harmonics``) or ``"time"`` (direct time integration, no periodic solve).
    harmonics : int or None
        ``Nh`` of the DLFT dynamics (``None`` on the exact dynamics).
    converged : bool
        False when a periodic solve failed and the curve stops early.
    status : str
        Why the history ends: ``"horizon"``, ``"worn"`` (every contact at
        ``stop_fraction u0``), ``"stuck"`` (full stick: no wear), or a failure.
    solves : int
        Periodic solves performed.
    wall_time : float
        Seconds spent.
    warnings : list of str
    """

    omega: float
    method: str
    cycles: np.ndarray
    wear: np.ndarray
    normal_load: np.ndarray
    rate: np.ndarray
    sliding_distance: np.ndarray
    amplitude: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    u0: np.ndarray
    kn: np.ndarray
    kw: float
    dynamics: str = "dlft"
    harmonics: int | None = None
    converged: bool = True
    status: str = "horizon"
    solves: int = 0
    wall_time: float = 0.0
    warnings: list[str] = field(default_factory=list)
    info: dict = field(default_factory=dict)

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    def to_xarray(self):
        """The history along ``cycles`` as an ``xarray.Dataset``, with units and long names.

        ``w`` (m), ``wear_fraction``, ``normal_load``, ``rate``, ``sliding_distance`` per
        ``friction_contact``; ``amplitude`` per ``dof``; what ran and how it ended in the
        attributes. ``hist.to_xarray().w.plot()`` draws ``w(N)``.
        """
        from .._xarray import wear_history_dataset

        return wear_history_dataset(self)

    def _repr_html_(self) -> str:
        from .._html import summary_html

        return summary_html(self)

    @property
    def label(self) -> str:
        """What ran, slow-time scheme and dynamics apart (:func:`describe`)."""
        return describe(self.method, self.dynamics, self.harmonics)

    @property
    def wear_fraction(self) -> np.ndarray:
        """``w / u0`` per friction contact, shape (K, n_friction)."""
        with np.errstate(invalid="ignore", divide="ignore"):
            return np.where(self.u0 > 0, self.wear / self.u0, 0.0)

    @property
    def normalised_time(self) -> np.ndarray:
        """Slow time ``K_w k_n N`` per friction contact (1/m), shape (K, n_friction)."""
        return self.kw * np.outer(self.cycles, self.kn)

    def at(self, cycles) -> dict[str, np.ndarray]:
        """Records interpolated at cycle counts ``cycles`` (held constant past the end).

        Wear uses cubic Hermite interpolation with the recorded rates (it is
        monotone and smooth); other fields are interpolated linearly.
        """
        cycles = np.clip(np.asarray(cycles, dtype=float), self.cycles[0], self.cycles[-1])
        out = {"cycles": cycles, "wear": _hermite(self.cycles, self.wear, self.rate, cycles)}
        for name in ("normal_load", "rate", "sliding_distance", "amplitude", "half_peak_to_peak",
                     "relative_half_peak_to_peak"):  # fmt: skip
            values = getattr(self, name)
            out[name] = np.stack([np.interp(cycles, self.cycles, v) for v in values.T], axis=-1)
        return out

    def rescaled(self, kw: float, horizon: float | None = None) -> WearHistory:
        """This history under the Archard coefficient ``kw`` (1/N), by Archard's law alone.

        ``dw/dN = K_w F_N(w) s(w)`` makes the wear states and responses functions of ``K_w N``: the
        records' cycle counts scale by ``self.kw / kw``, their rates by ``kw / self.kw``. Exact (to
        round-off) for a history that reached its end state before its horizon (status ``"worn"``) on a
        method whose records are placed in wear, not in cycles (the exact load path), as long as the
        scaled end stays within the horizon; a history that sticks only changes its ``kw``.
        ``ValueError`` for any other status (its horizon cut it, at a slow time ``K_w N`` that another
        ``kw`` moves), and when the scaled end passes ``horizon`` (cycles; the run at ``kw`` to that
        horizon would stop earlier).
        """
        if not (np.isfinite(kw) and kw > 0):
            raise ValueError(f"kw must be > 0 1/N, got {kw!r}")
        end = self.cycles[-1] * (self.kw / kw)
        if horizon is not None and self.status == "worn" and end > horizon * (1 - 1e-9):
            raise ValueError(f"under kw = {kw!r} 1/N this history ends at N = {end:.6g}, beyond the horizon "
                             f"{horizon!r}: run it again")  # fmt: skip
        if self.status == "stuck":
            return replace(self, kw=kw, warnings=list(self.warnings), info=dict(self.info))
        if self.status != "worn":
            raise ValueError(f"only a history that ended worn or stuck rescales in kw; this one ended "
                             f"{self.status!r}")  # fmt: skip
        rate = self.rate * (kw / self.kw)
        notes = [w for w in self.warnings if not w.startswith(_TWO_SCALE)]
        notes += two_scale_warning(rate[:1], self.u0)
        return replace(self, cycles=self.cycles * (self.kw / kw), rate=rate, kw=kw, warnings=notes,
                       info=dict(self.info))  # fmt: skip

    def error_against(
        self, reference: WearHistory, fractions: tuple[float, ...] = (0.5, 0.9), contact: int = 0
    ) -> dict[str, float]:
        """This history's error against ``reference`` (the exact one), for contact ``contact``.

        Returns
        -------
        dict of float
            ``"wear"``: the largest ``|w - w_ref| / u0`` over the reference's
            records (this history held past its end); ``"cycles_to_<f>"`` for each
            fraction ``f``: ``N_f / N_f,ref - 1`` (negative: this history
            reaches ``f u0`` early; nan where either does not reach it).
        """
        if self.u0[contact] != reference.u0[contact]:
            raise ValueError("reference must be a history of the same contact (u0 differs)")
        w = self.at(reference.cycles)["wear"][:, contact]
        out = {"wear": float(np.max(np.abs(w - reference.wear[:, contact])) / self.u0[contact])}
        for f in fractions:
            out[f"cycles_to_{f:g}"] = self.cycles_to(f, contact) / reference.cycles_to(f, contact) - 1.0
        return out

    def error_note(
        self, reference: WearHistory, fractions: tuple[float, ...] = (0.5, 0.9), label: str | None = None
    ) -> str | None:
        """This history's error against the exact ``reference``, in one sentence (None if either failed),
        naming it by ``label`` (default :attr:`label`)."""
        if not (self.converged and reference.converged):
            return None
        e = self.error_against(reference, fractions)
        parts = []
        for f in fractions:
            c = e[f"cycles_to_{f:g}"]
            if np.isfinite(c):
                parts.append(f"cycles to {f:.0%} of u₀ are {abs(c):.2%} {'early' if c < 0 else 'late'}")
        parts.append(f"w(N) is off by up to {e['wear']:.2%} of u₀")
        name = label or self.label
        return f"{name} at {self.frequency:.4g} Hz against the exact answer: {', '.join(parts)}."

    def cycles_to(self, fraction: float, contact: int = 0) -> float:
        """Cycles at which contact ``contact`` reaches ``fraction * u0`` (nan if it does not).

        Inverts the cubic Hermite interpolant of :meth:`at` by bisection on the record interval that
        crosses ``fraction``, in scalar arithmetic (a map's band error asks this of every history).
        """
        w = self.wear[:, contact] / self.u0[contact]
        k = np.searchsorted(w, fraction)
        if k == 0:
            return 0.0 if w[0] >= fraction else np.nan
        if k >= len(w):
            return np.nan
        x = self.cycles.tolist()
        y, dy, u0 = self.wear[:, contact].tolist(), self.rate[:, contact].tolist(), float(self.u0[contact])
        lo, hi = x[k - 1], x[k]
        for _ in range(60):
            mid = 0.5 * (lo + hi)
            j = min(max(bisect.bisect_right(x, mid) - 1, 0), len(x) - 2)  # the interval _hermite takes
            h = x[j + 1] - x[j]
            t = min(max((mid - x[j]) / (h if h > 0 else 1.0), 0.0), 1.0)
            t2, t3 = t * t, t**3
            h00, h10, h01, h11 = 2 * t3 - 3 * t2 + 1, t3 - 2 * t2 + t, -2 * t3 + 3 * t2, t3 - t2
            wm = h00 * y[j] + h10 * h * dy[j] + h01 * y[j + 1] + h11 * h * dy[j + 1]
            lo, hi = (mid, hi) if wm / u0 < fraction else (lo, mid)
        return 0.5 * (lo + hi)


def _hermite(x: np.ndarray, y: np.ndarray, dy: np.ndarray, xi: np.ndarray) -> np.ndarray:
    """Cubic Hermite interpolation of columns ``y`` (K, m) with slopes ``dy`` at ``xi``."""
    if len(x) == 1:
        return np.repeat(y[:1], len(xi), axis=0)
    k = np.clip(np.searchsorted(x, xi, side="right") - 1, 0, len(x) - 2)
    h = (x[k + 1] - x[k])[:, None]
    t = ((xi - x[k])[:, None] / np.where(h > 0, h, 1.0)).clip(0, 1)
    h00, h10, h01, h11 = 2 * t**3 - 3 * t**2 + 1, t**3 - 2 * t**2 + t, -2 * t**3 + 3 * t**2, t**3 - t**2
    return h00 * y[k] + h10 * h * dy[k] + h01 * y[k + 1] + h11 * h * dy[k + 1]


def cycle_grid(horizon: float, points: int = 201, decades: float = 4.0) -> np.ndarray:
    """Cycle counts of wear maps and curves: 0, then ``points - 1`` log-spaced over ``decades`` (N)."""
    return np.concatenate([[0.0], np.geomspace(horizon * 10.0**-decades, horizon, points - 1)])


def snapshot_cycles(horizon: float) -> np.ndarray:
    """Cycle counts of the pseudo-FRFs (paper Fig. 8-9): 0 and 1e-3, 1e-2, 1e-1, 1 times ``horizon``."""
    return np.concatenate([[0.0], horizon * np.array([1e-3, 1e-2, 1e-1, 1.0])])


def check_wear_inputs(model: Model, kw: float, cycles: float, degree: int | None = None) -> None:
    """Raise ``ValueError`` naming the parameter and its valid range for bad wear inputs."""
    if not np.isfinite(kw) or kw < 0:
        raise ValueError(f"kw (Archard coefficient, 1/N) must be finite and >= 0, got {kw!r}")
    if not np.isfinite(cycles) or cycles <= 0:
        raise ValueError(f"cycles (horizon) must be finite and > 0, got {cycles!r}")
    if not model.friction:
        raise ValueError("the model has no friction contact: nothing can wear")
    for j, c in enumerate(model.friction):
        if c.u0 <= 0:
            raise ValueError(f"friction[{j}].u0 must be > 0 m for a wearing contact, got {c.u0!r}")
        if c.kn <= 0:
            raise ValueError(f"friction[{j}].kn must be > 0 N/m, got {c.kn!r}")
    if degree is not None and not (isinstance(degree, (int, np.integer)) and 1 <= degree <= 12):
        raise ValueError(f"degree must be an integer in [1, 12], got {degree!r}")


def describe(method: str, dynamics: str, harmonics: int | None = None) -> str:
    """A label of what ran, the slow-time scheme and the dynamics apart.

    Only the exact slow time on the exact dynamics is called ``"exact"``; every
    label with a truncation error says so (``"exact slow time on DLFT, Nh = 7"``).
    """
    if method == "time":
        return "time integration (event-driven, cycle jumps)"
    scheme = {"exact": "exact slow time", "stepping": "stepping", "polynomial": "polynomial"}.get(
        method, method
    )
    if dynamics == "shooting":
        return "exact" if method == "exact" else f"{scheme} on the exact dynamics"
    return f"{scheme} on DLFT, Nh = {harmonics}"


def clip_wear(w: np.ndarray, u0: np.ndarray) -> np.ndarray:
    """Wear stays in [0, u0): the normal load relaxes to zero only asymptotically."""
    return np.clip(w, 0.0, u0 * (1 - 1e-12))


class Recorder:
    def __init__(self):
        self.rows = []

    def add(self, N, w, rate, slid, sol, model):
        self.rows.append((N, w.copy(), model.normal_loads(w), rate.copy(), slid.copy(),
                          np.asarray(sol.amplitude), np.asarray(sol.half_peak_to_peak),
                          np.asarray(sol.relative_half_peak_to_peak)))  # fmt: skip

    def history(self, omega, method, model, kw, **status) -> WearHistory:
        cols = list(zip(*self.rows, strict=True))
        u0 = np.array([c.u0 for c in model.friction])
        kn = np.array([c.kn for c in model.friction])
        return WearHistory(omega, method, np.array(cols[0]), *(np.array(c) for c in cols[1:]),
                           u0=u0, kn=kn, kw=kw, **status)  # fmt: skip


#: how the two-scale warning starts (:func:`two_scale_warning`)
_TWO_SCALE = "wear per cycle at the start is"


def two_scale_warning(rate0: np.ndarray, u0: np.ndarray) -> list[str]:
    per_cycle = float(np.max(rate0 / u0))
    if per_cycle > TWO_SCALE_LIMIT:
        msg = (
            f"{_TWO_SCALE} {per_cycle:.3g} u0 > {TWO_SCALE_LIMIT:g} u0: the two-scale "
            "assumption (wear barely changes over a cycle) does not hold; lower kw"
        )
        warnings.warn(msg, RuntimeWarning, stacklevel=3)
        return [msg]
    return []
