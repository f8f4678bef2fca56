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
``k_n``. :func:`sliding_tables` samples ``s_hat`` by shooting on the exact
event-driven dynamics (:func:`fretwear.time.shooting`), adaptively in ``rho``
until a monotone cubic in ``q = s_hat / (rho_stick - rho)^2`` (smooth up to
the stick threshold, where ``s_hat`` vanishes quadratically) is accurate to
``tol``, and keeps the table in a process-wide cache (and on disk), extended
when a lower ``rho`` is asked for. Every refinement pass of every frequency is
one compiled call (the kernels release the GIL: a thread per chunk of
frequencies). A last knot at ``rho = 0``, the frictionless response, carries
the quadrature to the gross-slip limit, where ``rho`` decays exponentially in
``N`` and the wear tends to ``u0``. The table also holds the response
amplitudes per unit forcing and the periodic states of its samples (the
guesses of later solves at nearby load ratios).
"""

from __future__ import annotations

import hashlib
import logging
import math
import os
import pickle
import tempfile
import threading
import zipfile
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from functools import partial
from pathlib import Path

import numpy as np
from numba import njit

from .._version import __version__
from ..hbm.problem import Problem
from ..model import Model
from ..time.patterns import Table
from ..time.shooting import _orbits

__all__ = ["SlidingTable", "sliding_table", "sliding_tables", "cached_solves", "cache_dir", "unit_forcing"]

log = logging.getLogger(__name__)

#: the last sample sits this far below the stick threshold (relative): closer, s_hat ~ 1e-8 loses digits
_TOP = 1e-4
#: relative error of the cubic in ``q`` (or share of the cycles) each interval meets: 1e-2 let an extended
#: table put the cycles to 0.5 u0 2.5e-3 off direct time integration; 3e-3 keeps them within 2e-4
#: (+35 % solves for a map from scratch)
TOL = 3e-3
#: samples of a first table, evenly spaced in log(rho / (rho_stick - rho))
_FIRST = 8
#: a first table reaches this factor below the load ratio asked for (F_ex up to this factor larger)
_REACH = 4.0
#: a table's solve keeps the period of Newton's last evaluation (no period marched to record the orbit)
#: when Newton's last step is at most ``_REUSE d^1.5`` of the state, ``d = 1 - rho / rho_stick``: a relative
#: state error e moves s_hat by up to ~ e / d^1.5 (grazing slip near the threshold; measured on the paper
#: model at 0.5, 0.7 and 1.1 Hz, within a factor 2), hence by up to TOL / 30 here
_REUSE = TOL / 30
#: the response quantities of a table besides s_hat (per unit forcing)
_RESPONSE = ("amplitude", "half_peak_to_peak", "relative_half_peak_to_peak")


def unit_forcing(model: Model) -> float:
    """The forcing amplitude ``F_ex`` (N) of a one-contact model: the largest harmonic force amplitude."""
    return float(np.max(np.hypot(model.force_cos, model.force_sin)))


@dataclass
class SlidingTable:
    """``s_hat(rho)`` and the response per unit forcing at one frequency.

    Near the stick threshold the stick force grazes the slip limit at a
    quadratic maximum: the slip phase lasts ``~ sqrt(rho_stick - rho)`` and
    slides ``~ (rho_stick - rho)^2``. The table therefore interpolates
    ``q = s_hat / (rho_stick - rho)^2``, smooth and positive up to the
    threshold, by a monotone cubic (PCHIP) through the samples, a last knot
    at ``rho_stick`` (the end slope extrapolated over the last ``1e-4`` of
    ``rho_stick``) and, with :attr:`free`, a first knot at ``rho = 0``.

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
    free : dict or None
        ``s_hat`` and the response quantities of the frictionless structure
        (``rho = 0``, gross slip), the table's first knot; None: the table
        starts at its first sample.
    orbit : ndarray, shape (K, 2 n), or None
        Periodic state ``(u, v)`` at ``t = 0`` of each sample (per unit forcing).
    events : ndarray of int, shape (K,), or None
        Contact events per period of each sample's orbit. Where two neighbours
        differ, a stick phase appears or vanishes between them: ``s_hat`` has a
        kink there, and the interpolants take the straight line between them
        (:func:`pchip`'s ``breaks``).
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
    free: dict | None = None
    orbit: np.ndarray | None = field(default=None, repr=False)
    events: np.ndarray | None = field(default=None, repr=False)
    solves: int = 0
    failures: list[float] = field(default_factory=list)
    verified: set = field(default_factory=set, repr=False)
    checked: tuple[float, float] = (np.inf, -np.inf)
    _built: tuple = field(default=(), repr=False)

    def interpolate(self, rho) -> dict[str, np.ndarray]:
        """Every tabulated quantity at ``rho`` (stuck values from ``rho_stick`` on).

        ``s_hat`` from the cubic in ``q``; the response amplitudes by a monotone
        cubic through the samples and the stuck response at ``rho_stick``.
        """
        rho = np.atleast_1d(np.asarray(rho, dtype=float))
        x, c, response = self._interpolants()
        d = np.clip(self.rho_stick - rho, 0.0, None)
        inside = np.clip(rho, x[0], x[-1])
        out = {"s_hat": d**2 * _q_at(x, c, inside)}
        for name, fn in response.items():
            out[name] = fn(np.clip(rho, x[0], x[-1]))
        return out

    def q(self, rho) -> np.ndarray:
        """The interpolated ``q = s_hat / (rho_stick - rho)^2`` at ``rho`` (m/N), inside the table."""
        x, c, _ = self._interpolants()
        return _q_at(x, c, np.atleast_1d(np.asarray(rho, dtype=float)))

    def cycles(self, rho_from: float, rho) -> np.ndarray:
        """``integral_rho^rho_from dr / (r s_hat(r))`` (1/m) on the table's interpolant.

        Each piece is integrated in ``t = 1 / (rho_stick - r)``, where the
        integrand ``1 / (r q(r))`` is smooth and bounded, by 12-point
        Gauss-Legendre on geometric sub-intervals (1e-11 of scipy's adaptive
        quadrature in the tests). Multiply by
        ``1 / (K_w k_n F_ex)`` for the number of cycles from ``rho_from`` down to
        ``rho``. ``inf`` where the integral diverges (a start at or above the
        stick threshold).
        """
        x, c, _ = self._interpolants()
        rho = np.atleast_1d(np.asarray(rho, dtype=float))
        return _integrals(x, c, float(rho_from), rho.ravel(), _GAUSS_T, _GAUSS_W).reshape(rho.shape)

    def load_ratio(self, rho_from: float, integral, rho_floor: float) -> np.ndarray:
        """The load ratio reached from ``rho_from`` when :meth:`cycles` equals ``integral`` (1/m).

        The inverse of :meth:`cycles` (Newton on the piece integrals, to
        round-off), held at ``rho_floor`` once the wear reaches it; ``integral``
        ascending, ``>= 0``. With ``integral = K_w k_n F_ex N`` it gives
        ``rho(N)``, hence ``w(N) = u0 - rho F_ex / (mu k_n)``.
        """
        x, c, _ = self._interpolants()
        v = np.asarray(integral, dtype=float)
        if v.ndim != 1 or np.any(np.diff(v) < 0) or (v.size and v[0] < 0):
            raise ValueError("integral must be an ascending 1-D array of values >= 0")
        if not (x[0] <= rho_floor <= rho_from):
            raise ValueError(f"rho_floor must lie in [{x[0]:.6g}, {rho_from:.6g}], got {rho_floor!r}")
        return _invert(x, c, float(rho_from), v, float(rho_floor), _GAUSS_T, _GAUSS_W)

    def _interpolants(self) -> tuple[np.ndarray, np.ndarray, dict]:
        """Knots (0 with :attr:`free`, the samples, ``rho_stick``), the ``q`` cubic, the response cubics."""
        knots = len(self.rho) + 1 + (self.free is not None)
        if not self._built or len(self._built[0]) != knots:  # the table grew
            rho, s_hat = self.rho, self.s_hat
            rows = {name: getattr(self, name) for name in _RESPONSE}
            if self.free is not None:
                rho, s_hat = np.append(0.0, rho), np.append(self.free["s_hat"], s_hat)
                rows = {name: np.vstack([self.free[name][None], y]) for name, y in rows.items()}
            breaks = kinks(self.events, len(rho))
            x, c = q_cubic(rho, s_hat, self.rho_stick, breaks)
            breaks = np.append(breaks, False)  # the last piece, up to rho_stick
            response = {
                name: partial(_evaluate, x, pchip(x, np.vstack([y, self.stuck[name][None]]), breaks))
                for name, y in rows.items()
            }
            self._built = (x, c, response)
        return self._built


def pchip(x: np.ndarray, y: np.ndarray, breaks: np.ndarray | None = None) -> np.ndarray:
    """Coefficients of the monotone piecewise-cubic Hermite interpolant (Fritsch-Carlson) of ``y(x)``.

    ``x`` (K,) ascending, ``y`` (K, ...); returns ``c`` (4, K - 1, ...): on
    ``[x[j], x[j + 1]]`` the cubic is ``((c[0, j] h + c[1, j]) h + c[2, j]) h + c[3, j]``,
    ``h = r - x[j]``. Slopes: the weighted harmonic mean of the neighbouring
    secants inside (zero where they change sign, so that no extremum is made),
    a shape-preserving three-point formula at the ends. ``breaks`` (K - 1,)
    bool marks the intervals that hold a kink of ``y`` (a change of the
    orbit's events): such a piece is the straight line, and the smooth runs on
    either side are interpolated on their own (their end slopes one-sided), so
    that the kink does not bend the pieces next to it.
    """
    y = np.asarray(y, dtype=float)
    columns = np.ascontiguousarray(y.reshape(len(y), -1))
    brk = np.zeros(len(x) - 1, dtype=np.bool_) if breaks is None else np.asarray(breaks, dtype=np.bool_)
    c = _pchip(np.ascontiguousarray(x, dtype=float), columns, np.ascontiguousarray(brk))
    return c.reshape((4, len(y) - 1, *y.shape[1:]))


@njit(cache=True, nogil=True)
def _pchip(x: np.ndarray, y: np.ndarray, breaks: np.ndarray) -> np.ndarray:
    """:func:`pchip` of each column of ``y`` (K, m): compiled, as the tables are refined in threads."""
    K, m = y.shape
    c = np.empty((4, K - 1, m))
    d = np.empty(K)
    left, right = np.empty(K - 1), np.empty(K - 1)  # each piece's end slopes
    for col in range(m):
        for j in range(K - 1):
            c[3, j, col] = (y[j + 1, col] - y[j, col]) / (x[j + 1] - x[j])  # the secants, for now
        j = 0
        while j < K - 1:
            if breaks[j]:
                left[j] = right[j] = c[3, j, col]
                j += 1
                continue
            e = j  # the smooth run of knots j..e
            while e < K - 1 and not breaks[e]:
                e += 1
            if e - j == 1:
                d[j] = d[e] = c[3, j, col]
            else:
                for i in range(j + 1, e):
                    h0, h1, m0, m1 = x[i] - x[i - 1], x[i + 1] - x[i], c[3, i - 1, col], c[3, i, col]
                    if m0 * m1 <= 0.0:  # a sign change or a flat secant: no extremum made
                        d[i] = 0.0
                    else:
                        w1, w2 = 2 * h1 + h0, h1 + 2 * h0
                        d[i] = (w1 + w2) / (w1 / m0 + w2 / m1)
                d[j] = _end_slope(x[j + 1] - x[j], x[j + 2] - x[j + 1], c[3, j, col], c[3, j + 1, col])
                d[e] = _end_slope(x[e] - x[e - 1], x[e - 1] - x[e - 2], c[3, e - 1, col], c[3, e - 2, col])
            for i in range(j, e):
                left[i], right[i] = d[i], d[i + 1]
            j = e
        for j in range(K - 1):
            h, secant = x[j + 1] - x[j], c[3, j, col]
            c[0, j, col] = (left[j] + right[j] - 2 * secant) / h**2
            c[1, j, col] = (3 * secant - 2 * left[j] - right[j]) / h
            c[2, j, col] = left[j]
            c[3, j, col] = y[j, col]
    return c


@njit(cache=True, nogil=True)
def _end_slope(h0: float, h1: float, m0: float, m1: float) -> float:
    """Three-point slope at an end of a monotone cubic, kept to the end secant's sign and to 3x it."""
    d = ((2 * h0 + h1) * m0 - h0 * m1) / (h0 + h1)
    if np.sign(d) != np.sign(m0):
        return 0.0
    if np.sign(m0) != np.sign(m1) and abs(d) > 3 * abs(m0):
        return 3 * m0
    return d


def _evaluate(x: np.ndarray, c: np.ndarray, r) -> np.ndarray:
    """The cubic pieces ``(x, c)`` of :func:`pchip` at ``r`` in ``[x[0], x[-1]]``, shape (len(r), ...)."""
    r = np.atleast_1d(np.asarray(r, dtype=float))
    j = np.clip(np.searchsorted(x, r, side="right") - 1, 0, len(x) - 2)
    h = (r - x[j]).reshape((-1,) + (1,) * (c.ndim - 2))
    return ((c[0, j] * h + c[1, j]) * h + c[2, j]) * h + c[3, j]


def kinks(events: np.ndarray | None, knots: int) -> np.ndarray:
    """Which of the ``knots - 1`` intervals lie between samples whose orbits have different events per
    period (bool): the last ``len(events)`` knots are the samples (None: unknown, no kink)."""
    flags = np.zeros(max(knots - 1, 0), dtype=np.bool_)
    if events is not None and len(events) > 1:
        flags[len(flags) - len(events) + 1 :] = np.diff(events) != 0
    return flags


def q_cubic(
    rho: np.ndarray, s_hat: np.ndarray, rho_stick: float, breaks: np.ndarray | None = None
) -> tuple[np.ndarray, np.ndarray]:
    """Knots and PCHIP coefficients of ``q = s_hat / (rho_stick - rho)^2``, with a knot at ``rho_stick``.

    Returns ``x`` (K + 1,) and ``c`` (4, K): on ``[x[j], x[j + 1]]``,
    ``q = ((c[0, j] h + c[1, j]) h + c[2, j]) h + c[3, j]`` with ``h = r - x[j]``.
    ``q(rho_stick)`` continues the cubic's end slope (at least 2 samples).
    ``breaks`` (K - 1,): the kinks between samples (:func:`pchip`).
    """
    q = s_hat / (rho_stick - rho) ** 2
    breaks = np.zeros(max(len(rho) - 1, 0), dtype=np.bool_) if breaks is None else breaks
    if len(rho) == 1:
        q_end = q[0]
    else:
        last = pchip(rho, q, breaks)[:, -1]  # the last piece: its slope at rho[-1]
        h = rho[-1] - rho[-2]
        q_end = q[-1] + (3 * last[0] * h**2 + 2 * last[1] * h + last[2]) * (rho_stick - rho[-1])
    x = np.append(rho, rho_stick)
    c = pchip(x, np.append(q, max(q_end, 0.5 * q[-1])), np.append(breaks, False))  # q > 0 below rho_stick
    return x, np.ascontiguousarray(c)


#: Gauss-Legendre rule of the pieces of the Archard quadrature
_GAUSS_T, _GAUSS_W = np.polynomial.legendre.leggauss(12)


@njit(cache=True, nogil=True)
def _piece_of(x: np.ndarray, v: float) -> int:
    """Index ``j`` of the piece ``x[j] <= v < x[j + 1]`` (clamped to the table's pieces)."""
    j = np.searchsorted(x, v, side="right") - 1
    return min(max(j, 0), len(x) - 2)


@njit(cache=True, nogil=True)
def _q(x: np.ndarray, c: np.ndarray, j: int, v: float) -> float:
    """``q`` at ``v`` on piece ``j``."""
    h = v - x[j]
    return ((c[0, j] * h + c[1, j]) * h + c[2, j]) * h + c[3, j]


@njit(cache=True, nogil=True)
def _q_at(x: np.ndarray, c: np.ndarray, vs: np.ndarray) -> np.ndarray:
    out = np.empty(len(vs))
    for i in range(len(vs)):
        out[i] = _q(x, c, _piece_of(x, vs[i]), vs[i])
    return out


@njit(cache=True, nogil=True)
def _s(x: np.ndarray, c: np.ndarray, j: int, v: float) -> float:
    """``s_hat = (rho_stick - v)^2 q`` at ``v`` on piece ``j``."""
    return (x[-1] - v) ** 2 * _q(x, c, j, v)


@njit(cache=True, nogil=True)
def _piece(x: np.ndarray, c: np.ndarray, j: int, a: float, b: float, gt: np.ndarray, gw: np.ndarray) -> float:
    """``integral_a^b dr / (r s_hat(r))`` on piece ``j``, ``0 <= a <= b < rho_stick = x[-1]``.

    With ``t = 1 / (rho_stick - r)``, ``dr / (rho_stick - r)^2 = dt`` and the
    integral is ``integral dt / (r q(r))``: smooth and bounded up to the
    threshold. Gauss-Legendre on sub-intervals of ``t`` in geometric
    progression, at most a factor 2 in ``t`` and in ``r`` each (the ends of a
    piece near the threshold or near ``rho = 0`` vary on their own scale).
    The piece from the knot ``rho = 0`` is :func:`_tail_piece`.
    """
    if b <= a:
        return 0.0
    if x[j] == 0.0:
        return _tail_piece(x, c, a, b, gt, gw)
    top = x[-1]
    ta, tb = 1.0 / (top - a), 1.0 / (top - b)
    n = int(math.ceil(math.log2(tb / ta) + math.log2(b / a))) + 1
    grow = (tb / ta) ** (1.0 / n)
    total, lo = 0.0, ta
    for i in range(n):
        hi = tb if i == n - 1 else lo * grow
        half, mid = 0.5 * (hi - lo), 0.5 * (hi + lo)
        part = 0.0
        for k in range(len(gt)):
            r = top - 1.0 / (mid + half * gt[k])
            part += gw[k] / (r * _q(x, c, j, r))
        total += half * part
        lo = hi
    return total


@njit(cache=True, nogil=True)
def _tail_piece(x: np.ndarray, c: np.ndarray, a: float, b: float, gt: np.ndarray, gw: np.ndarray) -> float:
    """``integral_a^b dr / (r s_hat(r))`` on the first piece, from the knot ``rho = 0`` (inf for ``a = 0``).

    Gross slip: ``s_hat`` tends to the frictionless ``s_0`` and the integral
    diverges as ``log(b / a) / s_0``, in closed form; the rest,
    ``(s_0 - s_hat) / (r s_hat s_0)``, is smooth on ``[0, b]`` (``b`` at most a
    quarter of ``rho_stick``): one Gauss-Legendre rule.
    """
    if a <= 0.0:
        return math.inf
    s0 = _s(x, c, 0, 0.0)
    half, mid = 0.5 * (b - a), 0.5 * (b + a)
    part = 0.0
    for k in range(len(gt)):
        r = mid + half * gt[k]
        s = _s(x, c, 0, r)
        part += gw[k] * (s0 - s) / (r * s * s0)
    return (math.log(b) - math.log(a)) / s0 + half * part


@njit(cache=True, nogil=True)
def _tail_invert(x: np.ndarray, c: np.ndarray, upper: float, rest: float, lower: float, gt, gw) -> float:
    """``v`` in ``[lower, upper]`` with ``integral_v^upper dr / (r s_hat(r)) = rest`` on the first piece.

    Newton's method in ``log v``, where the integral is nearly linear (slope
    ``-1 / s_hat``), kept inside its bracket by bisection; ``lower`` past it
    (with ``lower = 0``: worn through to round-off, ``v`` below 5e-324).
    """
    la, lb = math.log(max(lower, 5e-324)), math.log(upper)
    if _tail_piece(x, c, math.exp(la), upper, gt, gw) <= rest:  # below the floor, or below round-off
        return lower
    L = lb - rest * _s(x, c, 0, 0.0)  # Newton's first step, with s_hat at its gross-slip value
    for _ in range(100):
        if not (la < L < lb):
            L = 0.5 * (la + lb)
        v = math.exp(L)
        g = _tail_piece(x, c, v, upper, gt, gw) - rest  # falls as L grows
        if g > 0.0:
            la = L
        else:
            lb = L
        step = g * _s(x, c, 0, v)
        L += step
        if abs(step) <= 1e-15 * max(1.0, abs(L)) or lb - la <= 1e-15 * max(1.0, abs(lb)):
            break
    return max(math.exp(L), lower)


@njit(cache=True, nogil=True)
def _integrals(x, c, top: float, xs: np.ndarray, gt: np.ndarray, gw: np.ndarray) -> np.ndarray:
    """``integral_v^top dr / (r s_hat(r))`` for each ``v`` in ``xs`` (negative for ``v > top``)."""
    out = np.empty(len(xs))
    for i in range(len(xs)):
        lo, hi, sign = xs[i], top, 1.0
        if lo > hi:
            lo, hi, sign = hi, lo, -1.0
        if hi >= x[-1]:  # at or above the stick threshold: nothing slides, the integral diverges
            out[i] = sign * math.inf
            continue
        j, total, v = _piece_of(x, lo), 0.0, lo
        while v < hi:
            end = min(x[j + 1], hi)
            total += _piece(x, c, j, v, end, gt, gw)
            v, j = end, j + 1
        out[i] = sign * total
    return out


@njit(cache=True, nogil=True)
def _invert(x, c, top: float, targets: np.ndarray, floor: float, gt, gw) -> np.ndarray:
    """``v`` with ``integral_v^top dr / (r s_hat(r)) = target`` for ascending ``targets`` (``floor`` past it).

    The pieces are walked down from ``top`` once for all targets; inside a piece
    the integral is solved by Newton's method (``d/dv = -1 / (v s_hat(v))``)
    kept inside its bracket by bisection.
    """
    out = np.full(len(targets), floor)
    if top >= x[-1]:  # stuck: no wear
        out[:] = top
        return out
    rc = x[-1]
    j = _piece_of(x, top)
    upper, done = top, 0.0  # the walk has integrated from upper to top
    for i in range(len(targets)):
        want = targets[i]
        while True:
            lower = max(x[j], floor)
            piece = _piece(x, c, j, lower, upper, gt, gw)
            if done + piece >= want:
                break
            if lower <= floor:  # worn to the floor before this target: it and the rest stay there
                return out
            done, upper, j = done + piece, lower, j - 1
        rest = want - done  # solve integral_v^upper = rest on [lower, upper]
        if x[j] == 0.0:  # the gross-slip tail: rho decays exponentially in N
            out[i] = _tail_invert(x, c, upper, rest, lower, gt, gw)
            continue
        a, b = lower, upper
        v = upper - rest * upper * (rc - upper) ** 2 * _q(x, c, j, upper)  # Newton's first step
        for _ in range(100):
            if not (a < v < b):
                v = 0.5 * (a + b)
            g = _piece(x, c, j, v, upper, gt, gw) - rest  # falls as v grows
            if g > 0.0:
                a = v
            else:
                b = v
            step = g * v * (rc - v) ** 2 * _q(x, c, j, v)  # g / (-dg/dv)
            v_new = v + step
            if abs(step) <= 1e-15 * v or b - a <= 1e-15 * b:
                v = v_new if a <= v_new <= b else v
                break
            v = v_new
        out[i] = v
    return out


# -- the table and its cache ------------------------------------------------------------------------
_cache: dict[tuple, SlidingTable] = {}
_lock = threading.Lock()  # guards the two dicts; each table is built under its own lock
_locks: dict[tuple, threading.Lock] = {}


def cached_solves(model: Model, omega: float) -> int:
    """Shooting solves already in the cached table of ``model`` at ``omega`` (0 without one).

    A table on disk counts (it is loaded): a history built on it spent no solve.
    """
    key = _key(model, omega)
    with _lock:
        lock = _locks.setdefault(key, threading.Lock())
    with lock:
        table = _lookup(key)
    return 0 if table is None else table.solves


# -- on disk: the tables outlive the process -----------------------------------------------------
#: version of the file layout below (a new layout ignores the old files)
_FORMAT = 3
_ARRAYS = ("rho", "s_hat", *_RESPONSE, "orbit", "events")


def cache_dir() -> Path | None:
    """Directory of the tables on disk, or None when disabled.

    ``FRETWEAR_CACHE_DIR`` if set (an empty value disables the disk cache),
    else ``$XDG_CACHE_HOME/fretwear`` or ``~/.cache/fretwear``; a subdirectory
    per fretwear version and file layout. Delete it to forget every table.
    """
    root = os.environ.get("FRETWEAR_CACHE_DIR")
    if root is None:
        root = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.expanduser("~/.cache"), "fretwear")
    elif not root:
        return None
    return Path(root) / f"sliding-v{_FORMAT}-{__version__}"


def _file(key: tuple) -> Path | None:
    folder = cache_dir()
    return (
        None
        if folder is None
        else folder / (hashlib.sha256(pickle.dumps(key, protocol=4)).hexdigest()[:32] + ".npz")
    )


def _lookup(key: tuple) -> SlidingTable | None:
    """The table of ``key`` from memory, else from disk (then kept in memory); None without one."""
    table = _cache.get(key)
    if table is None and (table := _load(key)) is not None:
        _cache[key] = table
    return table


def _load(key: tuple) -> SlidingTable | None:
    """The table saved for ``key``; None when there is none or it cannot be read (it is then rebuilt)."""
    path = _file(key)
    if path is None or not path.exists():
        return None
    try:
        with np.load(path, allow_pickle=False) as data:
            if float(data["omega"]) != key[-1]:
                return None
            stuck = {name: data[f"stuck_{name}"] for name in _RESPONSE}
            free = None
            if "free_s_hat" in data:
                free = {name: data[f"free_{name}"] for name in ("s_hat", *_RESPONSE)}
            return SlidingTable(
                float(data["omega"]), float(data["rho_stick"]), *(data[name] for name in _ARRAYS[:-2]), stuck,
                free=free, orbit=data["orbit"], events=data["events"], solves=int(data["solves"]),
                failures=data["failures"].tolist(),
                verified={tuple(pair) for pair in data["verified"].tolist()}, checked=tuple(data["checked"]),
            )  # fmt: skip
    except (OSError, ValueError, KeyError, TypeError, EOFError, zipfile.BadZipFile):
        log.warning("sliding table %s is unreadable: rebuilt", path)
        return None


def _save(key: tuple, table: SlidingTable) -> None:
    """Write ``table`` for ``key`` (atomically: a reader sees the old file or the new one); a cache
    directory that cannot be written only costs the next process the build."""
    path = _file(key)
    if path is None:
        return
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        with tempfile.NamedTemporaryFile(dir=path.parent, suffix=".npz", delete=False) as tmp:
            np.savez(
                tmp, omega=table.omega, rho_stick=table.rho_stick, solves=table.solves,
                failures=np.array(table.failures, dtype=float), checked=np.array(table.checked, dtype=float),
                verified=np.array(sorted(table.verified), dtype=float).reshape(-1, 2),
                **{name: getattr(table, name) for name in _ARRAYS[:-1]}, events=_events(table),
                **{f"stuck_{name}": table.stuck[name] for name in _RESPONSE},
                **{f"free_{name}": value for name, value in (table.free or {}).items()},
            )  # fmt: skip
        os.replace(tmp.name, path)
    except OSError:
        log.warning("sliding table not saved to %s", path, exc_info=True)


def _events(table: SlidingTable) -> np.ndarray:
    """The table's events per sample; -1 (unknown: no kink) for a table made without them."""
    return np.full(len(table.rho), -1, dtype=np.int64) if table.events is None else table.events


def _key(model: Model, omega: float) -> tuple:
    """What ``s_hat`` depends on: the structure, the forcing's shape, the contact's DOFs, the frequency.

    The frequency to 12 significant digits: the same frequency of two grids
    (``np.linspace(0.3, 1.3, 101)`` and ``np.linspace(0.3, 1.2, 91)`` differ in
    the last bits at 37 of their 91 common points) shares its table, built at
    the rounded frequency (a relative shift below 5e-13, against the tables'
    tolerance ``TOL``).
    """
    f = unit_forcing(model)
    c = model.friction[0]
    return (
        model.M.tobytes(), model.K.tobytes(), model.C.tobytes(),
        (model.force_cos / f).round(12).tobytes(), (model.force_sin / f).round(12).tobytes(),
        c.dof, c.other, float(f"{float(omega):.11e}"),
    )  # fmt: skip


class _Job:
    """A table to extend: its samples, the range ``[lo, hi]`` to meet, its row in the pattern table.

    Every sample's row is in :attr:`points`; the refinement reads sorted
    arrays of them (``rho``, ``s_hat``, ``events``, ``orbits``), into which
    :meth:`merge` inserts the samples added since (once per pass, not per use).
    """

    def __init__(self, table: SlidingTable, lo: float, hi: float, index: int):
        self.table, self.lo, self.hi, self.index = table, lo, hi, index
        orbit = table.orbit  # a table made without orbits gives no guesses (NaN)
        if orbit is None:
            orbit = np.full((len(table.rho), 2 * table.amplitude.shape[1]), np.nan)
        rows = zip(table.s_hat, *(getattr(table, name) for name in _RESPONSE), orbit, _events(table),
                   strict=True)  # fmt: skip
        self.points: dict[float, tuple] = dict(zip(table.rho.tolist(), rows, strict=True))
        self.rho, self.s_hat, self.events, self.orbits = table.rho, table.s_hat, _events(table), orbit
        self._added: list[float] = []
        self.to_u, self.from_u = _spacing(table.rho_stick)

    def add(self, rho: float, row: tuple | None) -> bool:
        """Record a solve at ``rho``: a sample, or a failure (left out); whether it is a sample."""
        if row is None:
            self.table.failures.append(rho)
            return False
        self.points[rho] = row
        self._added.append(rho)
        return True

    def merge(self) -> None:
        """Insert the samples added since the last call into the sorted arrays."""
        if not self._added:
            return
        rows = [self.points[r] for r in self._added]
        rho = np.concatenate([self.rho, self._added])
        order = np.argsort(rho, kind="stable")
        self.rho = rho[order]
        self.s_hat = np.concatenate([self.s_hat, [row[0] for row in rows]])[order]
        self.events = np.concatenate([self.events, [row[5] for row in rows]])[order]
        self.orbits = np.concatenate([self.orbits, [row[4] for row in rows]])[order]
        self._added = []

    def knots(self) -> tuple[np.ndarray, np.ndarray]:
        """The knots of the interpolant and ``s_hat`` there: ``rho = 0`` (with ``free``), the samples."""
        self.merge()
        if self.table.free is None:
            return self.rho, self.s_hat
        return np.append(0.0, self.rho), np.append(self.table.free["s_hat"], self.s_hat)

    def open(self, a: float, b: float) -> bool:
        """Whether the interval ``[a, b]`` between two knots is still to be checked."""
        return (
            ((a < self.hi and b > self.lo) or a == 0.0)
            and (a, b) not in self.table.verified
            and b > max(a * (1 + 1e-9), 1e-9 * self.table.rho_stick)
        )

    def guesses(self, rho: np.ndarray) -> np.ndarray:
        """Newton's starts at ``rho``: the orbits of the (up to) four samples around each, interpolated
        (Lagrange, cubic in ``rho``), shape (len(rho), 2 n); NaN rows without stored orbits."""
        self.merge()
        return _lagrange(self.rho, self.orbits, np.ascontiguousarray(rho, dtype=float))

    def problems(self, rho: np.ndarray) -> list[tuple[int, float, list]]:
        """The solves at load ratios ``rho``: ``(frequency index, rho, [Newton's start])`` each."""
        starts = self.guesses(rho) if len(self.rho) else np.full((len(rho), 1), np.nan)
        usable = np.isfinite(starts).all(axis=1)
        return [
            (self.index, r, [y] if ok else []) for r, y, ok in zip(rho.tolist(), starts, usable, strict=True)
        ]

    def store(self, solves: int) -> None:
        """Write the samples back into the table, ascending in ``rho``."""
        self.merge()
        t = self.table
        rows = [self.points[v] for v in self.rho.tolist()]
        t.rho, t.s_hat, t.events, t.orbit = self.rho, self.s_hat, self.events.astype(np.int64), self.orbits
        for k, name in enumerate(_RESPONSE, start=1):
            setattr(t, name, np.array([row[k] for row in rows]))
        t.solves += solves


@njit(cache=True, nogil=True)
def _lagrange(r: np.ndarray, y: np.ndarray, at: np.ndarray) -> np.ndarray:
    """The cubic through the (up to) four samples ``(r, y)`` around each of ``at`` (``r`` ascending)."""
    m = min(4, len(r))
    out = np.zeros((len(at), y.shape[1]))
    for p in range(len(at)):
        first = min(max(np.searchsorted(r, at[p]) - 2, 0), len(r) - m)
        for i in range(first, first + m):
            w = 1.0
            for o in range(first, first + m):
                if o != i:
                    w *= (at[p] - r[o]) / (r[i] - r[o])
            out[p] += w * y[i]
    return out


def _shoot(
    engine: Table, problems: list[tuple[int, float, list]], chain: bool, stick: np.ndarray | None = None
) -> list[tuple | None]:
    """Periodic orbits of ``(frequency index, rho, guesses)`` under unit forcing with slip force ``rho``.

    One compiled call for all (:func:`fretwear.time.shooting._orbits`). With
    ``stick`` (the stick threshold per frequency index), a solve records the
    period of Newton's last evaluation when its last step is below ``_REUSE
    d^1.5``; without, every orbit is verified to the shooting tolerance.
    Returns per problem ``(s_hat, amplitude, half p2p, relative half p2p, y0, events per period)``
    per unit forcing, or None where shooting failed (left out of the table).
    """
    at = np.array([p[0] for p in problems], dtype=np.int64)
    g = np.array([[p[1]] for p in problems])
    reuse = 0.0
    if stick is not None:
        reuse = _REUSE * np.clip(1.0 - g[:, 0] / stick[at], 0.0, 1.0) ** 1.5
    o = _orbits(engine, at, g, [p[2] for p in problems], chain, 1e-10, 30, 400, reuse=reuse)
    amplitude = np.hypot(o["fre"], o["fim"]) * (2.0 / engine.periods[at])[:, None]
    half = (o["hi"] - o["lo"]) / 2
    events = np.diff(o["offsets"][2])  # per period of the recorded orbit
    n = engine.n
    return [
        (float(o["sliding"][k, 0]), amplitude[k], half[k, :n], half[k, n:], o["y0"][k], int(events[k]))
        if o["converged"][k] and np.isfinite(o["sliding"][k, 0])
        else None
        for k in range(len(problems))
    ]


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


def _spacing(rho_stick: float):
    """``rho -> log(rho / (rho_stick - rho))`` and its inverse: geometric at both ends of the table."""
    return (lambda r: np.log(r / (rho_stick - r))), (lambda u: rho_stick / (1.0 + np.exp(-u)))


def _first_samples(engine: Table, jobs: list[_Job], stick: np.ndarray) -> None:
    """The ends (frictionless and stuck responses) and the first samples of new tables.

    The first samples lie evenly in ``log(rho / (rho_stick - rho))`` from
    ``lo / _REACH`` up to ``_TOP`` below the threshold; the k-th samples of all
    frequencies are one sweep, each solve seeded by the orbits of its
    neighbours in frequency.
    """
    ends = [(job.index, 0.0, []) for job in jobs] + [(job.index, 2.0 * max(job.table.rho_stick, 1.0), [])
                                                    for job in jobs]  # fmt: skip
    rows = _shoot(engine, ends, False, stick)
    for job, free, stuck in zip(jobs, rows[: len(jobs)], rows[len(jobs) :], strict=True):
        if stuck is None:
            raise RuntimeError("shooting failed on the stuck structure")
        job.table.stuck = dict(zip(_RESPONSE, stuck[1:4], strict=True))
        if free is not None:  # else the table starts at its first sample (and wear holds below it)
            # the frictionless relative motion is harmonic: it slides 4 times its amplitude per period
            response = dict(zip(_RESPONSE, free[1:4], strict=True))
            job.table.free = {"s_hat": 4.0 * float(free[3][0]), **response}
    grids = [job.from_u(np.linspace(job.to_u(job.lo / _REACH), job.to_u(job.table.rho_stick * (1.0 - _TOP)),
                                    _FIRST)) for job in jobs]  # fmt: skip
    for k in range(_FIRST):
        problems = [(job.index, float(grid[k]), []) for job, grid in zip(jobs, grids, strict=True)]
        for (_, rho, _), job, row in zip(problems, jobs, _shoot(engine, problems, True, stick), strict=True):
            job.add(rho, row)


#: the smallest relative change of the load ratio whose cycles must meet the tolerance (wear to 0.1 u0)
_WINDOW = 1.1


def _small_share(
    x: np.ndarray, c: np.ndarray, a: float, b: float, error: float, tol: float, top: float
) -> bool:
    """True when a relative error ``error`` of ``1 / s_hat`` on ``[a, b]`` moves the cycles of any wear
    over a factor ``_WINDOW`` of the load ratio that contains ``[a, b]`` by at most ``tol`` (relative).

    Near the sudden changes of ``s_hat`` where a stick phase appears or vanishes,
    the cubic meets ``tol`` pointwise only on tiny intervals (tens of solves for
    each); their share of any number of cycles is what matters.
    """
    if a <= 0.0:
        return False
    share = _integrals(x, c, b, np.array([a, b / _WINDOW]), _GAUSS_T, _GAUSS_W)
    after = np.inf
    if a * _WINDOW < top:
        after = _integrals(x, c, a * _WINDOW, np.array([a]), _GAUSS_T, _GAUSS_W)[0]
    return bool(error * share[0] <= tol * min(share[1], after))


def _bisected(job: _Job, j: int, a: float, b: float, mid: float, row: tuple | None, x: np.ndarray,
              c: np.ndarray, kinked: np.ndarray, tol: float) -> list[tuple[float, float]]:  # fmt: skip
    """Record the solve at ``mid``, halfway in ``u`` across the kink on piece ``j = [a, b]``; the halves
    left to check.

    The cubics of the smooth runs beside the kink (the pieces ``j - 1`` and
    ``j + 1``, where they are not kinks themselves) continue into ``[a, b]``:
    the truth follows one of them up to the kink and the other after it.

    * A half whose ends have the same events is smooth: it passes when it is
      no wider than its side's piece and that piece's cubic, continued to
      ``mid``, predicts ``q(mid)`` within ``tol`` (a short continuation
      checked at its end); else it is checked at its thirds in the next pass.
    * A half that still holds the kink is the straight line of :func:`pchip`.
      Its error is taken as the larger of ``|q(hi) - q(lo)|`` and the
      distance from the line of either side's cubic over the half; it passes
      when that error, or its share of the cycles (:func:`_small_share`), is
      small enough.
    """
    table = job.table
    if not job.add(mid, row):
        table.verified.add((a, b))  # a failed sample: the kink cannot be refined
        return []
    stick = table.rho_stick
    q = {r: job.points[r][0] / (stick - r) ** 2 for r in (a, mid, b)}
    events = {r: job.points[r][5] for r in (a, mid, b)}
    sides = [p for p in (j - 1, j + 1) if 0 <= p < len(x) - 1 and not (p < len(kinked) and kinked[p])]
    left = []
    for lo, hi, side in ((a, mid, j - 1), (mid, b, j + 1)):
        if events[lo] == events[hi]:
            short = side in sides and hi - lo <= x[side + 1] - x[side]
            if short and abs(q[mid] - _q(x, c, side, mid)) <= tol * q[mid]:
                table.verified.add((lo, hi))
            else:
                left.append((lo, hi))
            continue
        r = np.linspace(lo, hi, 9)
        line = q[lo] + (r - lo) * (q[hi] - q[lo]) / (hi - lo)
        error = abs(q[hi] - q[lo])
        for p in sides:
            error = max(error, max(abs(_q(x, c, p, v) - w) for v, w in zip(r, line, strict=True)))
        error /= min(q[hi], q[lo])
        if error <= tol or _small_share(x, c, lo, hi, error, tol, stick):
            table.verified.add((lo, hi))
        else:
            left.append((lo, hi))
    return left


def _refine(model: Model, jobs: list[_Job], tol: float, max_solves: int) -> None:
    """Sample the tables of ``jobs`` until the cubic in ``q`` predicts the two new samples at the thirds
    of every interval that meets ``[lo, hi]`` within ``tol`` (relative); one compiled call per pass.

    Two checks per interval, not one: a single midpoint can sit where the
    cubic's error changes sign and pass by chance (seen: 2.5 % off between two
    samples whose midpoint agreed to 1e-3). An interval also passes when its
    error changes the cycles over any factor ``_WINDOW`` of the load ratio by
    at most ``tol`` (:func:`_small_share`). The interval from the knot
    ``rho = 0`` to the first sample is checked at its thirds in ``rho``. An
    interval across a kink (its samples' orbits have different events) is
    bisected instead (:func:`_bisected`). Each pass checks only the intervals
    the last one split.
    """
    engine = Table(model, [job.table.omega for job in jobs])
    stick = np.array([job.table.rho_stick for job in jobs])
    spent = dict.fromkeys(range(len(jobs)), 0)
    new = [job for job in jobs if not job.points]
    if new:
        for job in new:
            spent[job.index] += 2 + _FIRST
        _first_samples(engine, new, stick)
    below = []  # an existing table extended below its lowest sample: three samples, from its lowest orbit
    for job in jobs:
        r0 = min(job.points, default=np.inf)
        if job not in new and r0 > job.lo:
            below += job.problems(job.from_u(np.linspace(job.to_u(job.lo), job.to_u(r0), 4))[:-1])
    if below:
        for (i, rho, _), row in zip(below, _shoot(engine, below, False, stick), strict=True):
            spent[i] += 1
            jobs[i].add(rho, row)
    pending = {}
    for job in jobs:
        knots = job.knots()[0].tolist() if len(job.points) >= 2 else []
        pending[job.index] = [(a, b) for a, b in zip(knots[:-1], knots[1:], strict=False) if job.open(a, b)]
    while True:
        problems, checks = [], []
        for job in jobs:
            pairs = pending.pop(job.index, [])
            if not pairs or job.table.solves + spent[job.index] >= max_solves:
                continue
            knots, s_hat = job.knots()
            kinked = kinks(job.events, len(knots))
            x, c = q_cubic(knots, s_hat, job.table.rho_stick, kinked)
            a, b = np.array(pairs).T
            j = np.searchsorted(knots, a)  # the piece of each pair
            at_kink = kinked[j]
            a, b, smooth = a[~at_kink], b[~at_kink], [p for p, k in zip(pairs, at_kink, strict=True) if not k]
            ua, third = job.to_u(np.where(a > 0, a, b)), np.array([1 / 3, 2 / 3])
            inside = job.from_u(ua[:, None] + third * (job.to_u(b) - ua)[:, None])
            thirds = np.where((a > 0)[:, None], inside, b[:, None] * third).reshape(-1, 2)
            across = [(int(i), p) for i, p, k in zip(j, pairs, at_kink, strict=True) if k]
            # a kink is bisected in u (a kink lies between samples, never next to the knot at 0)
            mids = np.array([job.from_u((job.to_u(p[0]) + job.to_u(p[1])) / 2) for _, p in across])
            checks.append((job, smooth, thirds, across, mids, x, c, kinked))
            problems += job.problems(np.concatenate([thirds.ravel(), mids]))
        if not problems:
            break
        rows = iter(_shoot(engine, problems, False, stick))
        for job, smooth, thirds, across, mids, x, c, kinked in checks:
            spent[job.index] += thirds.size + len(mids)
            predicted = _q_at(x, c, thirds.ravel()).reshape(thirds.shape)
            left = []
            for (a, b), between, q_cubic_mids in zip(smooth, thirds.tolist(), predicted, strict=True):
                error, edges = 0.0, [a]  # a failed sample counts as passed: it cannot be refined
                for mid, q_pred in zip(between, q_cubic_mids, strict=True):
                    row = next(rows)
                    if job.add(mid, row):
                        edges.append(mid)
                        q_mid = row[0] / (job.table.rho_stick - mid) ** 2
                        error = max(error, abs(q_mid - q_pred) / q_mid)
                edges.append(b)
                halves = list(zip(edges[:-1], edges[1:], strict=True))
                if error <= tol or _small_share(x, c, a, b, error, tol, job.table.rho_stick):
                    job.table.verified |= set(halves)
                else:
                    left += halves
            for (piece, (a, b)), mid in zip(across, mids.tolist(), strict=True):
                left += _bisected(job, piece, a, b, mid, next(rows), x, c, kinked, tol)
            pending[job.index] = [p for p in left if job.open(*p)]
    for job in jobs:
        job.store(spent[job.index])


def _shoot_at(model: Model, table: SlidingTable, rho: np.ndarray) -> tuple[dict[str, np.ndarray], int]:
    """The exact response per unit forcing at load ratios ``rho`` (the table's quantities), by shooting.

    One compiled call, each solve seeded by the orbits of the table's samples
    around it; the stuck response at and above ``rho_stick``. Where shooting
    fails, the table's interpolation stands in. Returns the quantities and
    the number of solves.
    """
    rho = np.asarray(rho, dtype=float)
    out = table.interpolate(rho)
    slipping = np.flatnonzero((rho < table.rho_stick) & (rho > 0))
    if not len(slipping) or table.orbit is None or not table.orbit.size:
        return out, 0
    problems = _Job(table, 0.0, 0.0, 0).problems(rho[slipping])
    unit = model.scaled(1.0 / unit_forcing(model))
    for k, row in zip(slipping, _shoot(Table(unit, [table.omega]), problems, False), strict=True):
        if row is not None:
            for name, value in zip(("s_hat", *_RESPONSE), row[:4], strict=True):
                out[name][k] = value
    return out, len(problems)


def sliding_tables(
    model: Model,
    omegas,
    rho_min: float,
    rho_max: float | None = None,
    *,
    tol: float = TOL,
    max_solves: int = 2000,
    workers: int = 1,
) -> list[SlidingTable]:
    """The exact ``s_hat(rho)`` of ``model`` at each of ``omegas`` (rad/s), sampled down to ``rho_min`` (N/N).

    Cached per structure and frequency (whatever the forcing amplitude, ``mu``,
    ``u0``, ``k_n``); a later call with a lower ``rho_min`` extends the table.
    The missing tables are built together: each refinement pass of a chunk of
    frequencies is one compiled call, the chunks in ``workers`` threads.

    Parameters
    ----------
    model : Model
        One friction contact, no unilateral contact (positive definite mass).
    omegas : array_like, shape (nf,)
        Excitation frequencies (rad/s), > 0.
    rho_min, rho_max : float
        Range of load ratios ``mu F_N / F_ex`` where the tables must meet ``tol``,
        ``0 < rho_min``; default ``rho_max``: the stick threshold. Below its
        lowest sample a table follows its cubic to the frictionless knot at
        ``rho = 0`` (checked at the thirds of that interval too).
    tol : float
        Relative error of the cubic in ``q = s_hat / (rho_stick - rho)^2``, checked
        at the thirds of every interval (in ``log(rho / (rho_stick - rho))``)
        before those samples join the table. The number of cycles it gives is
        more accurate: within 1e-3 of direct time integration with wear at 0.55,
        0.7, 0.9 and 1.1 Hz on the paper model (10 N; tests and benchmark).
    max_solves : int
        Budget of shooting solves per table.
    workers : int
        Threads that build missing tables (>= 1).
    """
    if len(model.friction) != 1 or model.normal:
        raise ValueError("sliding_table needs exactly one friction contact and no unilateral contact")
    if not (np.isfinite(rho_min) and rho_min > 0):
        raise ValueError(f"rho_min must be a finite load ratio > 0, got {rho_min!r}")
    omegas = np.atleast_1d(np.asarray(omegas, dtype=float))
    keys = [_key(model, w) for w in omegas]
    unique = sorted(set(keys))  # locks taken in one global order: no deadlock between callers
    with _lock:
        locks = [_locks.setdefault(key, threading.Lock()) for key in unique]
    for lock in locks:
        lock.acquire()
    try:
        jobs, tables = [], {}
        for key in unique:
            table = _lookup(key)
            if table is None:
                omega = key[-1]
                table = SlidingTable(omega, _stick_threshold(model, omega), np.zeros(0), np.zeros(0),
                                     np.zeros((0, model.n_dofs)), np.zeros((0, model.n_dofs)),
                                     np.zeros((0, len(model.contacts))), {}, failures=[])  # fmt: skip
            tables[key] = table
            lo = min(rho_min, table.rho_stick * (1 - 1e-2))
            hi = table.rho_stick if rho_max is None else min(rho_max, table.rho_stick)
            if table.rho_stick > 0 and lo < hi and not _complete(table, lo, hi):
                jobs.append((key, _Job(table, lo, hi, 0)))
        jobs.sort(key=lambda item: item[0][-1])  # by frequency: the first samples sweep it
        # interleaved: the solves a table needs vary across the band (resonances), a chunk per thread
        # of every k-th frequency balances them (contiguous halves: 3140 against 5338 solves)
        chunks = [c for c in (np.arange(k, len(jobs), workers) for k in range(max(1, workers))) if len(c)]
        work = []
        for chunk in chunks:
            mine = [jobs[i][1] for i in chunk]
            for index, job in enumerate(mine):
                job.index = index
            work.append(mine)
        unit = model.scaled(1.0 / unit_forcing(model))
        if len(work) > 1:
            with ThreadPoolExecutor(max_workers=len(work)) as pool:
                list(pool.map(lambda mine: _refine(unit, mine, tol, max_solves), work))
        elif work:
            _refine(unit, work[0], tol, max_solves)
        for key, job in jobs:
            if _complete(job.table, job.lo, job.hi):
                job.table.checked = (min(job.lo, job.table.checked[0]), max(job.hi, job.table.checked[1]))
            _cache[key] = job.table
            _save(key, job.table)
        for key, table in tables.items():
            _cache.setdefault(key, table)
        return [tables[key] for key in keys]
    finally:
        for lock in locks:
            lock.release()


def sliding_table(
    model: Model,
    omega: float,
    rho_min: float,
    rho_max: float | None = None,
    *,
    tol: float = TOL,
    max_solves: int = 2000,
) -> SlidingTable:
    """The exact ``s_hat(rho)`` of ``model`` at ``omega`` (rad/s): :func:`sliding_tables` at one frequency."""
    return sliding_tables(model, [omega], rho_min, rho_max, tol=tol, max_solves=max_solves)[0]
