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

import math
import threading
from dataclasses import dataclass, field

import numpy as np
from numba import njit

from ..hbm.problem import Problem
from ..model import Model
from ..time import shooting

__all__ = ["SlidingTable", "sliding_table", "cached_solves", "unit_forcing"]

#: relative gap below the stick threshold where the table starts
_STICK_MARGIN = 1e-9
#: a first table reaches this factor below the load ratio asked for (F_ex up to this factor larger)
_REACH = 4.0


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
    checked : tuple of float
        A range of ``rho`` known to be covered by verified intervals.
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
    checked: tuple[float, float] = (np.inf, -np.inf)
    _r: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)
    _s: np.ndarray = field(default_factory=lambda: np.zeros(0), repr=False)

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
        r, s = self._knots()
        rho = np.atleast_1d(np.asarray(rho, dtype=float))
        return _integrals(r, s, float(rho_from), rho.ravel()).reshape(rho.shape)

    def load_ratio(self, rho_from: float, integral, rho_floor: float) -> np.ndarray:
        """The load ratio reached from ``rho_from`` when :meth:`cycles` equals ``integral`` (1/m).

        The inverse of :meth:`cycles` (Newton on the closed form, to round-off),
        held at ``rho_floor`` once the wear reaches it; ``integral`` ascending,
        ``>= 0``. With ``integral = K_w k_n F_ex N`` it gives ``rho(N)``, hence
        ``w(N) = u0 - rho F_ex / (mu k_n)``.
        """
        r, s = self._knots()
        x = np.asarray(integral, dtype=float)
        if x.ndim != 1 or np.any(np.diff(x) < 0) or (x.size and x[0] < 0):
            raise ValueError("integral must be an ascending 1-D array of values >= 0")
        if not (r[0] <= rho_floor <= rho_from):
            raise ValueError(f"rho_floor must lie in [{r[0]:.6g}, {rho_from:.6g}], got {rho_floor!r}")
        return _invert(r, s, float(rho_from), x, float(rho_floor))

    def _knots(self) -> tuple[np.ndarray, np.ndarray]:
        """Samples of ``s_hat`` with the stick threshold (where ``s_hat = 0``) appended."""
        if len(self._r) != len(self.rho) + 1:  # the table grew
            self._r, self._s = np.append(self.rho, self.rho_stick), np.append(self.s_hat, 0.0)
        return self._r, self._s


@njit(cache=True, nogil=True)
def _segment(x1: float, x2: float, s1: float, s2: float) -> float:
    """``integral_x1^x2 dr / (r s(r))`` for ``s`` linear with ``s(x1) = s1``, ``s(x2) = s2``.

    With ``s = a + b r``: ``ln(x2 s1 / (x1 s2)) / a`` and ``x2 s1 - x1 s2 =
    a (x2 - x1)``, so the integral is ``log1p(a u) / a`` with ``u = (x2 - x1) /
    (x1 s2)``: no case split and no cancellation, also for ``a -> 0`` (``s``
    proportional to ``r``) and ``b = 0``.
    """
    if x2 <= x1:
        return 0.0
    if s1 <= 0.0 or s2 <= 0.0:
        return math.inf
    a = (x2 * s1 - x1 * s2) / (x2 - x1)
    u = (x2 - x1) / (x1 * s2)
    z = a * u
    return u if abs(z) < 1e-300 else u * math.log1p(z) / z


@njit(cache=True, nogil=True)
def _line(r: np.ndarray, s: np.ndarray, j: int, x: float) -> float:
    """``s`` at ``x`` on piece ``j`` of the table (linear between ``r[j]`` and ``r[j + 1]``)."""
    return s[j] + (s[j + 1] - s[j]) * (x - r[j]) / (r[j + 1] - r[j])


@njit(cache=True, nogil=True)
def _piece_of(r: np.ndarray, x: float) -> int:
    """Index ``j`` of the piece ``r[j] <= x < r[j + 1]`` (clamped to the table's pieces)."""
    j = np.searchsorted(r, x, side="right") - 1
    return min(max(j, 0), len(r) - 2)


@njit(cache=True, nogil=True)
def _integrals(r: np.ndarray, s: np.ndarray, top: float, xs: np.ndarray) -> np.ndarray:
    """``integral_x^top dr / (r s(r))`` for each ``x`` in ``xs`` (negative for ``x > top``)."""
    out = np.empty(len(xs))
    for i in range(len(xs)):
        lo, hi, sign = xs[i], top, 1.0
        if lo > hi:
            lo, hi, sign = hi, lo, -1.0
        if hi >= r[-1]:  # at or above the stick threshold: nothing slides, the integral diverges
            out[i] = sign * math.inf
            continue
        j, total = _piece_of(r, lo), 0.0
        x = lo
        while x < hi:
            end = min(r[j + 1], hi)
            total += _segment(x, end, _line(r, s, j, x), _line(r, s, j, end))
            x, j = end, j + 1
        out[i] = sign * total
    return out


@njit(cache=True, nogil=True)
def _invert(r: np.ndarray, s: np.ndarray, top: float, targets: np.ndarray, floor: float) -> np.ndarray:
    """``x`` with ``integral_x^top dr / (r s(r)) = target`` for ascending ``targets`` (``floor`` past it).

    The pieces are walked down from ``top`` once for all targets; inside a piece
    the closed form is solved by Newton's method (``d/dx = -1 / (x s(x))``) kept
    inside its bracket by bisection.
    """
    out = np.full(len(targets), floor)
    if top >= r[-1]:  # stuck: no wear
        out[:] = top
        return out
    j = _piece_of(r, top)
    upper, s_upper, done = top, _line(r, s, j, top), 0.0  # the walk has integrated from upper to top
    for i in range(len(targets)):
        want = targets[i]
        while True:
            lower = max(r[j], floor)
            s_lower = _line(r, s, j, lower)
            piece = _segment(lower, upper, s_lower, s_upper)
            if done + piece >= want:
                break
            if lower <= floor:  # worn to the floor before this target: it and the rest stay there
                return out
            done, upper, s_upper, j = done + piece, lower, s_lower, j - 1
        rest = want - done  # solve integral_x^upper = rest on [lower, upper]
        a, b = lower, upper
        x = upper - rest * upper * s_upper  # Newton's first step from the upper end
        for _ in range(100):
            if not (a < x < b):
                x = 0.5 * (a + b)
            sx = _line(r, s, j, x)
            g = _segment(x, upper, sx, s_upper) - rest  # falls as x grows
            if g > 0.0:
                a = x
            else:
                b = x
            step = g * x * sx  # g / (-dg/dx)
            x_new = x + step
            if abs(step) <= 1e-15 * x or b - a <= 1e-15 * b:
                x = x_new if a <= x_new <= b else x
                break
            x = x_new
        out[i] = x
    return out


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
    if table.checked[0] <= lo and hi <= table.checked[1]:
        return True
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
            if not len(table.rho):  # a first build also covers F_ex up to _REACH times larger
                lo /= _REACH
            sampler = _Sampler(model, omega, 2.0 * table.rho_stick)
            sampler.solves = table.solves
            _adapt(table, sampler, lo, hi, tol, max_solves)
            if _complete(table, lo, hi):
                table.checked = (min(lo, table.checked[0]), max(hi, table.checked[1]))
        return table


def _stuck_response(model: Model, omega: float, rho_stick: float) -> dict[str, np.ndarray]:
    """Response per unit forcing of the stuck structure (exact, linear)."""
    sampler = _Sampler(model, omega, 2.0 * max(rho_stick, 1.0))
    got = sampler(2.0 * max(rho_stick, 1.0) * 0.75)  # any slip force above the threshold
    if got is None:
        raise RuntimeError("shooting failed on the stuck structure")
    return {"amplitude": got[1], "half_peak_to_peak": got[2], "relative_half_peak_to_peak": got[3]}
