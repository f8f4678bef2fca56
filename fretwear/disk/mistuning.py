"""Linear forced response of mistuned bladed disks: modal superposition and amplitude magnification.

A mistuned disk (:func:`fretwear.bladed_disk` with ``mistuning``) loses the
cyclic symmetry: under an engine-order excitation the blades no longer respond
alike, and the largest blade amplitude exceeds the tuned one. The
*amplitude magnification factor* of a mistuning pattern is

    A = max over blades and frequencies of |x_tip,i(omega)|  /  max over frequencies of |x_tip(omega)| tuned,

both maxima over the same frequency band (the tuned disk's peak is its own
resonance in that band). Whitehead (1966, 1998) bounds it by
``(1 + sqrt(N)) / 2`` for ``N`` blades when each blade has one mode in the band
(a family of blade-dominated modes, weakly coupled through the disk).

The response is the modal sum ``x(omega) = sum_r phi_r phi_r^T F / (omega_r^2
- omega^2 + 2 i zeta_r omega_r omega)`` over the mass-normalised modes of the
undamped structure, exact for modal damping (``Phi^T C Phi`` diagonal, as the
bladed disk's). Peaks are found on a grid about every natural frequency in
the band (a few samples per half-power width), then refined by a bounded
scalar search on the best candidates: the figure does not depend on a
frequency grid.
"""

from __future__ import annotations

from dataclasses import dataclass, fields

import numpy as np
import scipy.linalg as sl
from scipy.optimize import minimize_scalar

from ..model import Model, bladed_disk
from ..model.disk import DiskSector

__all__ = ["ModalBasis", "modes", "modal_basis", "peak", "Magnification", "magnification", "draw_mistuning"]

#: grid about each natural frequency: half-width in damping bandwidths ``zeta omega_r``, samples
PEAK_HALF_WIDTH, PEAK_SAMPLES = 6.0, 49
#: candidates (DOF, grid peak) refined by the bounded search
REFINED = 3


@dataclass(frozen=True)
class ModalBasis:
    """Mass-normalised modes of a model with modal damping, and its harmonic forcing in modal coordinates.

    Attributes
    ----------
    omega : ndarray, shape (m,)
        Natural frequencies (rad/s), ascending.
    zeta : ndarray, shape (m,)
        Modal damping ratios (-).
    shapes : ndarray, shape (k, m)
        Mode shapes at the observed DOFs (mass-normalised, m/sqrt(kg)).
    force : ndarray of complex, shape (m,)
        Modal force ``Phi^T (f_cos - i f_sin)`` (N/sqrt(kg)).
    """

    omega: np.ndarray
    zeta: np.ndarray
    shapes: np.ndarray
    force: np.ndarray

    def response(self, omegas: np.ndarray) -> np.ndarray:
        """Complex amplitudes ``U`` at the observed DOFs (m), ``u = Re(U e^{i omega t})``, (omegas, k)."""
        w = np.asarray(omegas, dtype=float)[:, None]
        q = self.force / (self.omega**2 - w**2 + 2j * self.zeta * self.omega * w)
        return q @ self.shapes.T

    def amplitude(self, omega: float, dof: int) -> float:
        """``|U|`` of observed DOF ``dof`` at ``omega`` (m)."""
        return float(abs(self.response(np.array([omega]))[0, dof]))


def _eigen(M: np.ndarray, K: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Natural frequencies (rad/s) and mass-normalised mode shapes of ``(M, K)``."""
    w2, phi = sl.eigh(K, M)
    if w2[0] <= 0:
        raise ValueError(f"the stiffness must be positive definite, lowest eigenvalue {w2[0]:.3g}")
    return np.sqrt(w2), phi


def modes(M: np.ndarray, K: np.ndarray, force: np.ndarray, zeta, dofs) -> ModalBasis:
    """The modes of ``(M, K)`` with damping ratios ``zeta`` (one, or one per mode), observed at ``dofs``.

    ``force``: the complex harmonic force ``f_cos - i f_sin`` (N).
    """
    omega, phi = _eigen(M, K)
    zeta = np.broadcast_to(np.asarray(zeta, dtype=float), omega.shape)
    return ModalBasis(omega, zeta, phi[np.asarray(dofs, dtype=int)], phi.T @ force)


def modal_basis(model: Model, dofs) -> ModalBasis:
    """The modes of a linear ``model`` observed at ``dofs``; its damping must be modal.

    Raises ``ValueError`` for a model with contacts, or when an off-diagonal
    modal damping term ``Phi^T C Phi`` exceeds ``1e-8`` of the diagonal (the
    modal sum would not be the response).
    """
    if model.contacts or model.pairs is not None:
        raise ValueError("modal_basis needs a linear model (no contacts): its modes are those of M and K")
    M, K, C = (
        a.toarray() if hasattr(a, "toarray") else np.asarray(a, float) for a in (model.M, model.K, model.C)
    )
    omega, phi = _eigen(M, K)
    c = phi.T @ C @ phi
    diag = np.diag(c).copy()
    off = np.abs(c - np.diag(diag)).max()
    if off > 1e-8 * max(np.abs(diag).max(), 1e-300):
        raise ValueError(f"damping is not modal: off-diagonal term {off:.3g} against {diag.max():.3g}")
    force = phi.T @ (model.force_cos - 1j * model.force_sin)
    return ModalBasis(omega, diag / (2 * omega), phi[np.asarray(dofs, dtype=int)], force)


def peak(basis: ModalBasis, band: tuple[float, float]) -> tuple[float, float, int]:
    """Largest amplitude over the observed DOFs and the band ``(f_low, f_high)`` (Hz).

    Returns ``(amplitude (m), frequency (Hz), observed DOF index)``. The
    maximum is searched about each natural frequency in the band (and at its
    ends), then refined by a bounded scalar search.
    """
    lo, hi = 2 * np.pi * band[0], 2 * np.pi * band[1]
    inside = (basis.omega >= lo) & (basis.omega <= hi)
    offsets = np.linspace(-PEAK_HALF_WIDTH, PEAK_HALF_WIDTH, PEAK_SAMPLES)
    grid = (basis.omega[inside, None] * (1 + basis.zeta[inside, None] * offsets)).ravel()
    grid = np.unique(np.clip(np.concatenate([grid, [lo, hi]]), lo, hi))
    amp = np.abs(basis.response(grid))  # (grid, dofs)
    best = (0.0, lo, 0)
    for flat in np.argsort(amp, axis=None)[::-1][:REFINED]:
        i, dof = np.unravel_index(flat, amp.shape)
        a, b = grid[max(i - 1, 0)], grid[min(i + 1, grid.size - 1)]
        res = minimize_scalar(lambda w, d=dof: -basis.amplitude(w, d), bounds=(a, b), method="bounded",
                              options={"xatol": 1e-10 * b})  # fmt: skip
        w, value = (res.x, -res.fun) if -res.fun >= amp[i, dof] else (grid[i], amp[i, dof])
        if value > best[0]:
            best = (float(value), float(w), int(dof))
    return best[0], best[1] / (2 * np.pi), best[2]


def draw_mistuning(sectors: int, level: float, draws: int, seed: int = 0) -> np.ndarray:
    """``draws`` mistuning patterns ``delta_i`` of standard deviation ``level`` (-), shape (draws, sectors).

    Normal deviations, redrawn (per value) until ``delta_i > -1`` (a blade
    stiffness stays positive); seeded: the same ``seed`` gives the same patterns.
    """
    if not (np.isfinite(level) and 0 <= level <= 0.5):
        raise ValueError(f"level must be a standard deviation in [0, 0.5], got {level!r}")
    if isinstance(draws, bool) or not isinstance(draws, (int, np.integer)) or draws < 1:
        raise ValueError(f"draws must be an integer >= 1, got {draws!r}")
    rng = np.random.default_rng(seed)
    delta = level * rng.standard_normal((draws, sectors))
    while np.any(bad := delta <= -1):
        delta[bad] = level * rng.standard_normal(int(bad.sum()))
    return delta


@dataclass(frozen=True)
class Magnification:
    """Amplitude magnification factors of mistuning patterns (module docstring).

    Attributes
    ----------
    factor : ndarray, shape (draws,)
        Largest blade-tip amplitude over the tuned peak (-), per pattern.
    frequency : ndarray, shape (draws,)
        Where the largest amplitude is (Hz).
    blade : ndarray of int, shape (draws,)
        Which blade has it.
    tuned : float
        The tuned disk's peak tip amplitude in the band (m).
    tuned_frequency : float
        Where it is (Hz).
    band : (float, float)
        The frequency band (Hz).
    blades : int
        Number of blades ``N``.
    """

    factor: np.ndarray
    frequency: np.ndarray
    blade: np.ndarray
    tuned: float
    tuned_frequency: float
    band: tuple[float, float]

    @property
    def whitehead(self) -> float:
        """Whitehead's bound ``(1 + sqrt(N)) / 2`` for the disk's ``N`` blades."""
        return (1 + np.sqrt(self.blades)) / 2

    blades: int = 0


def magnification(patterns, band: tuple[float, float], **disk) -> Magnification:
    """Amplitude magnification of each mistuning pattern of the bladed disk over ``band`` (Hz).

    Parameters
    ----------
    patterns : array_like, shape (draws, sectors)
        ``delta_i`` per pattern (e.g. :func:`draw_mistuning`).
    band : (float, float)
        Frequency band (Hz), ``0 < f_low < f_high``.
    **disk
        Parameters of :func:`fretwear.bladed_disk` (``sectors``, ``engine_order``,
        ``damping_ratio``, ...), the same for the tuned and every mistuned disk.
    """
    patterns = np.atleast_2d(np.asarray(patterns, dtype=float))
    if not (len(band) == 2 and 0 < band[0] < band[1] and np.isfinite(band[1])):
        raise ValueError(f"band must be (f_low, f_high) with 0 < f_low < f_high (Hz), got {band!r}")
    tuned_model = bladed_disk(**{"contacts": "none", **disk})  # linear mistuning: the disk alone
    info = tuned_model.info
    sector = DiskSector(**{f.name: info[f.name] for f in fields(DiskSector)})
    if patterns.shape[1] != sector.sectors:
        raise ValueError(
            f"patterns must have {sector.sectors} columns (one per sector), got {patterns.shape[1]}"
        )
    tips = 3 * np.arange(sector.sectors) + 2
    force, zeta = tuned_model.force_cos - 1j * tuned_model.force_sin, info["damping_ratio"]
    tuned, tuned_f, _ = peak(modal_basis(tuned_model, tips), band)
    if not np.all(np.isfinite(patterns)) or np.any(patterns <= -1):
        raise ValueError(
            "patterns must hold finite deviations delta_i > -1 (a blade stiffness stays positive)"
        )
    out = np.array([peak(modes(*sector.assemble(delta), force, zeta, tips), band) for delta in patterns])
    return Magnification(out[:, 0] / tuned, out[:, 1], out[:, 2].astype(int), tuned, tuned_f, tuple(band),
                         sector.sectors)  # fmt: skip
