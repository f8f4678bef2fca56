"""The exact sliding distance per cycle over the load ratio, tabulated once per structure and frequency.

For one friction contact, Coulomb's law is positively homogeneous: the periodic
response to the forcing ``F_ex f(t)`` with slip force ``g = mu F_N`` is ``F_ex``
times the response to the unit forcing ``f(t)`` with slip force
``rho = mu F_N / F_ex``. The distance slid per period is therefore
``s = F_ex s_hat(rho)``, with ``s_hat`` (m per N of forcing) a function of the
structure, the frequency and ``rho`` only. With ``F_N = k_n (u0 - w)``,
Archard's law ``dw/dN = K_w F_N s`` becomes (eq. 30c-d)

    dN = -d rho / (K_w k_n F_ex rho s_hat(rho)),

a one-dimensional quadrature for any ``F_ex``, ``mu``, ``K_w``, ``u0`` and
``k_n``. :func:`sliding_table` samples ``s_hat`` by shooting on the exact
event-driven dynamics (:func:`fretwear.time.shooting`), adaptively in ``rho``
until piecewise-linear interpolation is accurate to ``tol``, and keeps the
table in a process-wide cache, extended when a lower ``rho`` is asked for.
The table also holds the response amplitudes per unit forcing, so that the
records of a wear history are exact as well.
"""

from __future__ import annotations

import threading
from dataclasses import dataclass, field

import numpy as np

from ..hbm.problem import Problem
from ..model import Model
from ..time import shooting

__all__ = ["SlidingTable", "sliding_table", "cached_solves", "unit_forcing"]

#: relative gap below the stick threshold where the table starts
_STICK_MARGIN = 1e-9


def unit_forcing(model: Model) -> float:
    """The forcing amplitude ``F_ex`` (N) of a one-contact model: the largest harmonic force amplitude."""
    return float(np.max(np.hypot(model.force_cos, model.force_sin)))


@dataclass
class SlidingTable:
    """``s_hat(rho)`` and the response per unit forcing at one frequency.

    Attributes
    ----------
    omega : float
        Excitation frequency (rad/s).
    rho_stick : float
        Exact stick threshold (N/N): the contact sticks for ``rho >= rho_stick``.
    rho : ndarray, shape (K,)
        Load ratios ``mu F_N / F_ex`` of the samples, ascending, below ``rho_stick``.
    s_hat : ndarray, shape (K,)
        Distance slid per period per unit forcing (m/N).
    amplitude, half_peak_to_peak : ndarray, shape (K, n)
        First-harmonic amplitude and half peak-to-peak of every DOF per unit forcing (m/N).
    relative_half_peak_to_peak : ndarray, shape (K, n_contacts)
        Half peak-to-peak relative displacement per unit forcing (m/N).
    stuck : dict of ndarray
        The same response quantities of the stuck structure (any ``rho >= rho_stick``).
    solves : int
        Shooting solves spent.
    failures : list of float
        Load ratios where shooting did not converge (left out of the table).
    verified : set
        Intervals of the table whose midpoint passed the interpolation check.
    """

    omega: float
    rho_stick: float
    rho: np.ndarray
    s_hat: np.ndarray
    amplitude: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    stuck: dict
    solves: int = 0
    failures: list[float] = field(default_factory=list)
    verified: set = field(default_factory=set, repr=False)
    _cumulative: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

    def interpolate(self, rho) -> dict[str, np.ndarray]:
        """Every tabulated quantity at ``rho``, linearly interpolated (stuck values from ``rho_stick`` on)."""
        rho = np.atleast_1d(np.asarray(rho, dtype=float))
        r = np.append(self.rho, self.rho_stick)
        out = {"s_hat": np.interp(rho, r, np.append(self.s_hat, 0.0), right=0.0)}
        for name in ("amplitude", "half_peak_to_peak", "relative_half_peak_to_peak"):
            v = np.vstack([getattr(self, name), self.stuck[name][None]])
            out[name] = np.stack([np.interp(rho, r, col, right=col[-1]) for col in v.T], axis=-1)
        return out

    def cycles(self, rho_from: float, rho) -> np.ndarray:
        """``integral_rho^rho_from dr / (r s_hat(r))`` (1/m), exact for piecewise-linear ``s_hat``.

        Multiply by ``1 / (K_w k_n F_ex)`` for the number of cycles from ``rho_from`` down to ``rho``.
        ``inf`` where the integral diverges (a start at or above the stick threshold).
        """
        return self._primitive(rho) - self._primitive(rho_from)

    def _primitive(self, x) -> np.ndarray:
        """``integral_x^r_ref dr / (r s_hat(r))`` with ``r_ref`` the last sample (vectorised)."""
        x = np.atleast_1d(np.asarray(x, dtype=float))
        r = np.append(self.rho, self.rho_stick)
        s = np.append(self.s_hat, 0.0)
        if len(self._cumulative) != len(r):  # from each sample up to the last one (the table grew)
            piece = _piece_integral(r[:-2], r[1:-1], s[:-2], s[1:-1])
            self._cumulative = np.concatenate([np.cumsum(piece[::-1])[::-1], [0.0, np.nan]])
        k = np.clip(np.searchsorted(r, x, side="right") - 1, 0, len(r) - 2)
        sx = np.interp(x, r, s, right=0.0)
        below = self._cumulative[k + 1] + _piece_integral(x, r[k + 1], sx, s[k + 1])  # x in the piece below
        above = -_piece_integral(r[k], x, s[k], sx)  # x in the last piece, above r_ref
        out = np.where(k < len(r) - 2, below, above)
        return np.where(x >= self.rho_stick, -np.inf, out)

def _piece_integral(r1, r2, s1, s2) -> np.ndarray:
    """``integral_r1^r2 dr / (r s(r))`` with ``s`` linear from ``s1`` to ``s2`` (closed form)."""
    r1, r2, s1, s2 = (np.asarray(v, dtype=float) for v in (r1, r2, s1, s2))
    b = (s2 - s1) / np.where(r2 > r1, r2 - r1, 1.0)
    a = s1 - b * r1  # s(r) = a + b r
    with np.errstate(divide="ignore", invalid="ignore"):
        general = (np.log(r2 / r1) - np.log(s2 / s1)) / a  # d/dr [ln(r / (a + b r)) / a] = 1 / (r (a + b r))
        flat = np.log(r2 / r1) / s1  # a = s (b = 0)
        proportional = (1.0 / r1 - 1.0 / r2) / b  # a = 0: s = b r
        out = np.where(np.abs(a) > 1e-9 * np.abs(s1 + s2), general, np.where(b == 0, flat, proportional))
    out = np.where((s1 <= 0) | (s2 <= 0), np.inf, out)
    return np.where(r2 > r1, out, 0.0)


# -- the table and its cache ------------------------------------------------------------------------
_cache: dict[tuple, SlidingTable] = {}
_lock = threading.Lock()


def cached_solves(model: Model, omega: float) -> int:
    """Shooting solves already in the cached table of ``model`` at ``omega`` (0 without one)."""
    table = _cache.get(_key(model, omega))
    return 0 if table is None else table.solves


def _key(model: Model, omega: float) -> tuple:
    """What ``s_hat`` depends on: the structure, the forcing's shape, the contact's DOFs, the frequency."""
    f = unit_forcing(model)
    c = model.friction[0]
    return (
        model.M.tobytes(), model.K.tobytes(), model.C.tobytes(),
        (model.force_cos / f).round(12).tobytes(), (model.force_sin / f).round(12).tobytes(),
        c.dof, c.other, float(omega),
    )  # fmt: skip


def _response(sol) -> tuple:
    return (
        float(sol.sliding_distance[0]),
        np.asarray(sol.amplitude, dtype=float),
        np.asarray(sol.half_peak_to_peak, dtype=float),
        np.asarray(sol.relative_half_peak_to_peak, dtype=float),
    )


class _Sampler:
    """Shooting on the unit-forcing structure with slip force ``rho`` (wear sets the slip force)."""

    def __init__(self, model: Model, omega: float, rho_max: float):
        f = unit_forcing(model)
        self.model = model.scaled(1.0 / f).with_friction(mu=1.0, kn=1.0, u0=rho_max)
        self.omega, self.rho_max = omega, rho_max
        self.solves = 0
        self.guesses: dict[float, np.ndarray] = {}

    def __call__(self, rho: float):
        """``(s_hat, amplitude, half p2p, relative half p2p)`` at ``rho``, or ``None`` when shooting fails."""
        near = min(self.guesses, key=lambda r: abs(r - rho), default=None)
        guess = None if near is None else self.guesses[near]
        sol = self._shoot(rho, guess)
        if (sol is None or not sol.converged) and guess is not None:
            sol = self._shoot(rho, None)
        if sol is None or not sol.converged:
            return None
        self.guesses[rho] = np.asarray(sol.unknowns)
        return _response(sol)

    def _shoot(self, rho: float, guess):
        try:
            return shooting(self.model, self.omega, guess, wear=np.array([self.rho_max - rho]))
        except (RuntimeError, ValueError):  # a failed solve: this sample is left out (table.failures)
            return None
        finally:
            self.solves += 1


def _stick_threshold(model: Model, omega: float) -> float:
    """Exact ``rho`` at and above which the structure sticks: the stuck force amplitude per unit forcing."""
    problem = Problem(model, omega, 1)  # the stuck response to a harmonic forcing is one harmonic, exactly
    if problem.n_active == 0:
        return 0.0
    return problem.stick_ratio() * float(model.slip_forces()[0]) / unit_forcing(model)


def _complete(table: SlidingTable, lo: float, hi: float) -> bool:
    """True when the table reaches ``lo`` and every interval meeting ``[lo, hi]`` passed its check."""
    r = table.rho
    if not len(r) or r[0] > lo:
        return False
    pairs = [(a, b) for a, b in zip(r[:-1], r[1:], strict=True) if a < hi and b > lo and b > a * (1 + 1e-9)]
    return all(p in table.verified for p in pairs)


def _adapt(table: SlidingTable, sampler: _Sampler, lo: float, hi: float, tol: float, max_solves: int) -> None:
    """Add samples to ``table`` down to ``lo`` until linear interpolation is within ``tol`` (relative) on
    every interval that meets ``[lo, hi]``."""
    t = table
    rows = zip(t.s_hat, t.amplitude, t.half_peak_to_peak, t.relative_half_peak_to_peak, strict=True)
    points = dict(zip(t.rho.tolist(), rows, strict=True))
    if not len(t.rho):
        starts = np.geomspace(lo, table.rho_stick * (1 - _STICK_MARGIN), 25)
    elif t.rho[0] > lo:
        starts = np.geomspace(lo, t.rho[0], 12)[:-1]
    else:
        starts = []
    for r in starts:
        if (got := sampler(float(r))) is not None:
            points[float(r)] = got
    verified = table.verified
    while sampler.solves < max_solves:
        r = np.array(sorted(points))
        pairs = [(a, b) for a, b in zip(r[:-1], r[1:], strict=True) if a < hi and b > lo]
        todo = [(a, b) for a, b in pairs if (a, b) not in verified and b > a * (1 + 1e-9)]
        if not todo:
            break
        for a, b in todo:
            mid = float(np.sqrt(a * b))
            got = sampler(mid)
            if got is None:
                table.failures.append(mid)
                verified.add((a, b))
                continue
            sa, sb, sm = points[a][0], points[b][0], got[0]
            linear = sa + (sb - sa) * (mid - a) / (b - a)
            points[mid] = got
            if abs(sm - linear) <= tol * max(sm, 1e-3 * max(sa, sb)):
                verified |= {(a, mid), (mid, b)}
            if sampler.solves >= max_solves:
                break
    r = np.array(sorted(points))
    table.rho = r
    table.s_hat = np.array([points[k][0] for k in r])
    table.amplitude = np.array([points[k][1] for k in r])
    table.half_peak_to_peak = np.array([points[k][2] for k in r])
    table.relative_half_peak_to_peak = np.array([points[k][3] for k in r])
    table.solves = sampler.solves


def sliding_table(
    model: Model,
    omega: float,
    rho_min: float,
    rho_max: float | None = None,
    *,
    tol: float = 1e-3,
    max_solves: int = 2000,
) -> SlidingTable:
    """The exact ``s_hat(rho)`` of ``model`` at ``omega`` (rad/s), sampled down to ``rho_min`` (N/N).

    Cached per structure and frequency (whatever the forcing amplitude, ``mu``,
    ``u0``, ``k_n``); a later call with a lower ``rho_min`` extends the table.

    Parameters
    ----------
    model : Model
        One friction contact, no unilateral contact (positive definite mass).
    omega : float
        Excitation frequency (rad/s), > 0.
    rho_min, rho_max : float
        Range of load ratios ``mu F_N / F_ex`` where the table must meet ``tol``,
        ``0 < rho_min``; default ``rho_max``: the stick threshold.
    tol : float
        Relative error of the linear interpolation of ``s_hat`` between samples, checked at
        every interval's geometric midpoint (the relative error of the number of cycles
        it gives is of the same order or smaller).
    max_solves : int
        Budget of shooting solves.
    """
    if len(model.friction) != 1 or model.normal:
        raise ValueError("sliding_table needs exactly one friction contact and no unilateral contact")
    if not (np.isfinite(rho_min) and rho_min > 0):
        raise ValueError(f"rho_min must be a finite load ratio > 0, got {rho_min!r}")
    key = _key(model, omega)
    with _lock:
        table = _cache.get(key)
        if table is None:
            rho_stick = _stick_threshold(model, omega)
            stuck = _stuck_response(model, omega, rho_stick)
            table = SlidingTable(omega, rho_stick, np.zeros(0), np.zeros(0), np.zeros((0, model.n_dofs)),
                                 np.zeros((0, model.n_dofs)), np.zeros((0, len(model.contacts))), stuck,
                                 failures=[])  # fmt: skip
            _cache[key] = table
        lo = min(rho_min, table.rho_stick * (1 - 1e-3))
        hi = table.rho_stick if rho_max is None else min(rho_max, table.rho_stick)
        if table.rho_stick > 0 and lo < hi and not _complete(table, lo, hi):
            sampler = _Sampler(model, omega, 2.0 * table.rho_stick)
            sampler.solves = table.solves
            _adapt(table, sampler, lo, hi, tol, max_solves)
        return table


def _stuck_response(model: Model, omega: float, rho_stick: float) -> dict[str, np.ndarray]:
    """Response per unit forcing of the stuck structure (exact, linear)."""
    sampler = _Sampler(model, omega, 2.0 * max(rho_stick, 1.0))
    got = sampler(2.0 * max(rho_stick, 1.0) * 0.75)  # any slip force above the threshold
    if got is None:
        raise RuntimeError("shooting failed on the stuck structure")
    return {"amplitude": got[1], "half_peak_to_peak": got[2], "relative_half_peak_to_peak": got[3]}
