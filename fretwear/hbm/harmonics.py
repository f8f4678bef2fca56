"""Truncated Fourier series on one period: the multi-harmonic basis (eq. 9-10).

A periodic signal is ``u(t) = a_0 + sum_{k=1}^{Nh} a_k cos(k omega t) + b_k sin(k omega t)``.
Its *full* coefficient vector is ``[a_0, a_1, b_1, ..., a_Nh, b_Nh]`` (eq. 10),
of length ``2 Nh + 1``.

For half-wave symmetric problems (``u(t + T/2) = -u(t)``) only odd harmonics
are non-zero; the *reduced* basis then keeps odd orders only and the time
grid covers half a period. :class:`HarmonicBasis` holds the slots of the basis
in use and the matrices that map between coefficients and time samples
(the iDFT/DFT of the alternating frequency-time scheme).
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np

__all__ = ["HarmonicBasis", "default_samples", "full_synthesis", "amplitude", "extrema"]


def default_samples(harmonics: int) -> int:
    """Default samples per period: the next power of two ``>= 16 Nh`` (at least 16).

    Friction forces are non-smooth in time; about 16 samples per period of the
    highest harmonic resolve the stick/slip transitions well enough for the
    truncation error of the harmonic balance to dominate.
    """
    _check_sizes(harmonics, 2 * harmonics + 1)
    return max(16, 1 << int(np.ceil(np.log2(16 * harmonics))))


def _check_sizes(harmonics: int, samples: int) -> None:
    if not isinstance(harmonics, (int, np.integer)) or harmonics < 1:
        raise ValueError(f"harmonics (Nh) must be an integer >= 1, got {harmonics!r}")
    if not isinstance(samples, (int, np.integer)) or samples < 2 * harmonics + 1:
        raise ValueError(
            f"samples (N) must be an integer >= 2*Nh+1 = {2 * harmonics + 1} (no aliasing), got {samples!r}"
        )


@dataclass(frozen=True)
class HarmonicBasis:
    """Slots of a (possibly half-wave reduced) harmonic basis and its time grid.

    Parameters
    ----------
    harmonics : int
        Highest harmonic order ``Nh >= 1``.
    samples : int
        Time samples per *full* period ``N >= 2 Nh + 1``. Half-wave bases use
        the first ``N / 2`` of them and need ``N`` even.
    half_wave : bool
        Keep odd harmonics only and march over half a period.
    """

    harmonics: int
    samples: int
    half_wave: bool = False

    def __post_init__(self) -> None:
        _check_sizes(self.harmonics, self.samples)
        if self.half_wave and self.samples % 2:
            raise ValueError(f"samples (N) must be even for a half-wave basis, got {self.samples}")

    # -- slots ------------------------------------------------------------
    @cached_property
    def orders(self) -> np.ndarray:
        """Harmonic order of each slot, shape (H,)."""
        ks = np.arange(1, self.harmonics + 1, 2 if self.half_wave else 1)
        body = np.repeat(ks, 2)
        return body if self.half_wave else np.concatenate([[0], body])

    @cached_property
    def is_sine(self) -> np.ndarray:
        """True for the ``sin`` slots, shape (H,)."""
        flags = np.tile([False, True], len(self.orders) // 2)
        return flags if self.half_wave else np.concatenate([[False], flags])

    @property
    def size(self) -> int:
        """Number of slots ``H`` (``2 Nh + 1`` for the full basis)."""
        return len(self.orders)

    @cached_property
    def full_index(self) -> np.ndarray:
        """Position of each slot in the full coefficient vector of eq. 10, shape (H,)."""
        return np.where(self.orders == 0, 0, 2 * self.orders - 1 + self.is_sine)

    # -- time grid --------------------------------------------------------
    @property
    def marched_samples(self) -> int:
        """Samples marched in time: ``N`` (full) or ``N / 2`` (half-wave)."""
        return self.samples // 2 if self.half_wave else self.samples

    @cached_property
    def phases(self) -> np.ndarray:
        """Phases ``omega t_n = 2 pi n / N`` of the marched samples (rad)."""
        return 2 * np.pi * np.arange(self.marched_samples) / self.samples

    @property
    def synthesis(self) -> np.ndarray:
        """iDFT matrix, shape (N_marched, H): samples = synthesis @ coefficients (read-only, shared)."""
        return _dft_pair(self.harmonics, self.samples, self.half_wave)[0]

    @property
    def analysis(self) -> np.ndarray:
        """DFT matrix, shape (H, N_marched): coefficients = analysis @ samples (read-only, shared).

        Exact inverse of :attr:`synthesis` on the basis (``analysis @ synthesis = I``),
        the discrete Galerkin projection of the AFT scheme.
        """
        return _dft_pair(self.harmonics, self.samples, self.half_wave)[1]

    def to_full(self, coeffs: np.ndarray) -> np.ndarray:
        """Scatter reduced coefficients (..., H) into the full layout (..., 2 Nh + 1)."""
        out = np.zeros(coeffs.shape[:-1] + (2 * self.harmonics + 1,), dtype=coeffs.dtype)
        out[..., self.full_index] = coeffs
        return out

    def from_full(self, coeffs: np.ndarray) -> np.ndarray:
        """Gather the slots of this basis from full coefficients (..., 2 Nh + 1)."""
        return coeffs[..., self.full_index]


@lru_cache(maxsize=64)
def _dft_pair(harmonics: int, samples: int, half_wave: bool) -> tuple[np.ndarray, np.ndarray]:
    """Synthesis and analysis matrices of a basis, computed once per size."""
    basis = HarmonicBasis(harmonics, samples, half_wave)
    arg = np.outer(basis.phases, basis.orders)
    phi = np.ascontiguousarray(np.where(basis.is_sine, np.sin(arg), np.cos(arg)))
    n = basis.marched_samples
    weight = np.where(basis.orders == 0, 1.0 / n, 2.0 / n)
    psi = np.ascontiguousarray(weight[:, None] * phi.T)
    phi.setflags(write=False)
    psi.setflags(write=False)
    return phi, psi


def full_synthesis(harmonics: int, samples: int) -> np.ndarray:
    """iDFT matrix (N, 2 Nh + 1) of the full basis on a full period of ``samples`` points."""
    return HarmonicBasis(harmonics, samples).synthesis


def amplitude(coeffs: np.ndarray, order: int = 1) -> np.ndarray:
    """Amplitude ``sqrt(a_k^2 + b_k^2)`` of harmonic ``order`` from full coefficients (..., 2 Nh + 1)."""
    return np.hypot(coeffs[..., 2 * order - 1], coeffs[..., 2 * order])


def extrema(coeffs: np.ndarray, samples: np.ndarray, atol: float = 0.0) -> tuple[np.ndarray, np.ndarray]:
    """Exact maximum and minimum over the period of each truncated Fourier series.

    Starts from the extreme samples of ``samples`` (the series on a uniform
    grid) and refines the phase by Newton's method on the derivative, so that
    peak-to-peak values do not depend on the grid.

    Parameters
    ----------
    coeffs : ndarray, shape (m, 2 Nh + 1)
        Full coefficients of ``m`` signals.
    samples : ndarray, shape (m, N)
        The same signals on ``N`` uniform samples of the period.
    atol : float
        Signals whose harmonics sum to at most ``atol`` in magnitude keep their
        sampled extremes (refining them would change them by less than
        ``atol``): round-off, such as the relative motion of a stuck contact,
        where Newton's method only chases noise.

    Returns
    -------
    (ndarray, ndarray)
        Maxima and minima, shape (m,).
    """
    m, N = samples.shape
    hi, lo = samples.max(axis=1), samples.min(axis=1)
    rows = np.flatnonzero(np.sum(np.abs(coeffs[:, 1:]), axis=1) > atol)
    if rows.size == 0:
        return hi, lo
    coeffs, samples = coeffs[rows], samples[rows]
    k = np.arange(1, (coeffs.shape[1] - 1) // 2 + 1)
    c2 = np.concatenate([coeffs, coeffs])  # maxima then minima, refined together
    a, b = c2[:, 1::2], c2[:, 2::2]
    # f = a0 + Re sum_k q_k e^{i k theta} with q_k = a_k - i b_k: f' and f'' are row products with the
    # powers of e^{i theta}, built by products (one complex exponential per row, not one per harmonic)
    q = a - 1j * b
    q1, q2 = 1j * k * q, -(k**2) * q
    idx = np.concatenate([np.argmax(samples, axis=1), np.argmin(samples, axis=1)])
    theta = 2 * np.pi * idx / N
    for _ in range(8):
        powers = np.cumprod(np.repeat(np.exp(1j * theta)[:, None], len(k), axis=1), axis=1)
        d1 = np.einsum("ij,ij->i", q1, powers).real
        d2 = np.einsum("ij,ij->i", q2, powers).real
        with np.errstate(divide="ignore", invalid="ignore"):
            step = np.clip(np.where(d2 != 0, d1 / d2, 0.0), -np.pi / N, np.pi / N)  # stay within the cell
        theta = theta - step
        if np.all(np.abs(step) <= 1e-7):  # quadratic convergence: the next step would be < 1e-13
            break
    kt = np.outer(theta, k)
    value = c2[:, 0] + np.sum(a * np.cos(kt) + b * np.sin(kt), axis=1)
    n = len(rows)
    hi[rows], lo[rows] = np.maximum(value[:n], hi[rows]), np.minimum(value[n:], lo[rows])
    return hi, lo
