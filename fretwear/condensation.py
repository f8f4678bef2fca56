"""Exact condensation of the linear structure on the contact coordinates (eq. 11).

Per harmonic order ``k`` the linear part is the complex dynamic stiffness
``D_k = K - (k omega)^2 M + i k omega C``. With ``B`` the map to relative
contact coordinates, the contact receptance is ``G_k = B D_k^{-1} B^T`` and
the reduced equations of motion read ``Z_k U_r,k + Lambda_k = F_r,k`` with

    Z_k = G_k^{-1},   F_r,k = Z_k B D_k^{-1} F_k,

exact for any number of DOFs (the paper's eq. 11). Real coefficients
``(a, b)`` of ``a cos + b sin`` relate to the complex amplitude ``a - i b``,
so a complex block ``Z = X + iY`` acts on ``(a, b)`` as ``[[X, Y], [-Y, X]]``.

All reduced arrays use the *contact-major* layout: entry ``c * H + j`` is slot
``j`` of the :class:`~fretwear.harmonics.HarmonicBasis` for contact ``c``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .harmonics import HarmonicBasis
from .model import Model

__all__ = ["Condensed", "condense", "dynamic_stiffness", "forcing", "recover"]


def dynamic_stiffness(model: Model, omega: float, orders: np.ndarray) -> np.ndarray:
    """Complex dynamic stiffness ``D_k`` for each harmonic order, shape (len(orders), n, n)."""
    w = np.asarray(orders, dtype=float)[:, None, None] * omega
    return model.K - w**2 * model.M + 1j * w * model.C


def _d_dynamic_stiffness(model: Model, omega: float, orders: np.ndarray) -> np.ndarray:
    """Derivative ``dD_k / d omega``, shape (len(orders), n, n)."""
    k = np.asarray(orders, dtype=float)[:, None, None]
    return -2 * k**2 * omega * model.M + 1j * k * model.C


def forcing(model: Model, orders: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Complex force amplitude per harmonic order, shape (len(orders), n) (N)."""
    F = np.zeros((len(orders), model.n_dofs), dtype=complex)
    F[np.asarray(orders) == 0] = model.force_static
    F[np.asarray(orders) == 1] = model.force_cos - 1j * model.force_sin
    return scale * F


def _solve(D: np.ndarray, rhs: np.ndarray, omega: float) -> np.ndarray:
    try:
        return np.linalg.solve(D, rhs)
    except np.linalg.LinAlgError:
        raise ValueError(
            f"the dynamic stiffness K - (k omega)^2 M + i k omega C is singular at omega = {omega:g} rad/s "
            "for some harmonic k (an undamped resonance, or a rigid-body mode when k = 0); "
            "add damping, anchor the structure or change the frequency"
        ) from None


def _real_blocks(Z: np.ndarray, basis: HarmonicBasis) -> np.ndarray:
    """Assemble complex per-order blocks (n_orders, nc, nc) into the real contact-major matrix."""
    nc, H = Z.shape[1], basis.size
    orders = _distinct_orders(basis)
    slot_order = np.searchsorted(orders, basis.orders)  # which complex block each slot uses
    X, Y = Z.real[slot_order], Z.imag[slot_order]  # (H, nc, nc)
    same = basis.orders[:, None] == basis.orders[None, :]
    sin_r, sin_c = basis.is_sine[:, None], basis.is_sine[None, :]
    # block (r, c) per slot pair: X on the diagonal slots, +Y (cos row, sin col), -Y (sin row, cos col)
    coef_x = same & (sin_r == sin_c)
    coef_y = same & ~sin_r & sin_c
    coef_my = same & sin_r & ~sin_c
    idx = np.arange(H)
    blocks = (
        coef_x[:, :, None, None] * X[idx][:, None]
        + coef_y[:, :, None, None] * Y[idx][:, None]
        - coef_my[:, :, None, None] * Y[idx][:, None]
    )  # (H_row, H_col, nc, nc), block uses the row slot's order (equal to the column's where non-zero)
    return np.ascontiguousarray(blocks.transpose(2, 0, 3, 1).reshape(nc * H, nc * H))


def _real_vector(v: np.ndarray, basis: HarmonicBasis) -> np.ndarray:
    """Complex per-order vectors (n_orders, nc) -> real contact-major vector (nc * H)."""
    orders = _distinct_orders(basis)
    slot = v[np.searchsorted(orders, basis.orders)]  # (H, nc)
    real = np.where(basis.is_sine[:, None], -slot.imag, slot.real)
    return np.ascontiguousarray(real.T.reshape(-1))


def _distinct_orders(basis: HarmonicBasis) -> np.ndarray:
    return np.unique(basis.orders)


@dataclass(frozen=True)
class Condensed:
    """Reduced dynamic stiffness and force on the contact coordinates at one frequency.

    Attributes
    ----------
    Z : ndarray, shape (nc H, nc H)
        Real reduced dynamic stiffness ``Z_r`` (N/m), contact-major.
    F : ndarray, shape (nc H,)
        Reduced external force ``F_r`` (N) for unit force scale.
    dZ, dF : ndarray or None
        Derivatives with respect to ``omega`` (per rad/s), when requested.
    """

    Z: np.ndarray
    F: np.ndarray
    dZ: np.ndarray | None = None
    dF: np.ndarray | None = None


def condense(
    model: Model, B: np.ndarray, omega: float, basis: HarmonicBasis, derivative: bool = False
) -> Condensed:
    """Condense ``model`` on the relative coordinates ``B u`` at ``omega`` (rad/s), eq. 11.

    Parameters
    ----------
    model : Model
    B : ndarray, shape (nc, n)
        Map from DOFs to the active contact coordinates.
    omega : float
        Excitation frequency (rad/s).
    basis : HarmonicBasis
    derivative : bool
        Also return ``dZ/d omega`` and ``dF/d omega`` (for continuation).
    """
    orders = _distinct_orders(basis)
    D = dynamic_stiffness(model, omega, orders)
    F = forcing(model, orders)
    rhs = np.concatenate([np.broadcast_to(B.T, D.shape[:1] + B.T.shape), F[:, :, None]], axis=2)
    sol = _solve(D, rhs.astype(complex), omega)  # D^{-1} [B^T, F]
    nc = B.shape[0]
    G = B @ sol[:, :, :nc]  # receptance (n_orders, nc, nc)
    u_lin = (B @ sol[:, :, nc:])[..., 0]  # linear open relative displacement (n_orders, nc)
    Z = np.linalg.inv(G)
    Fr = np.einsum("kij,kj->ki", Z, u_lin)
    if not derivative:
        return Condensed(_real_blocks(Z, basis), _real_vector(Fr, basis))
    dD = _d_dynamic_stiffness(model, omega, orders)
    dsol = -np.linalg.solve(D, dD @ sol)  # d(D^{-1} [B^T, F]) / d omega
    dG = B @ dsol[:, :, :nc]
    du_lin = (B @ dsol[:, :, nc:])[..., 0]
    dZ = -Z @ dG @ Z
    dFr = np.einsum("kij,kj->ki", dZ, u_lin) + np.einsum("kij,kj->ki", Z, du_lin)
    return Condensed(
        _real_blocks(Z, basis), _real_vector(Fr, basis), _real_blocks(dZ, basis), _real_vector(dFr, basis)
    )


def recover(
    model: Model, B: np.ndarray, omega: float, harmonics: int, contact_force: np.ndarray, scale: float = 1.0
) -> np.ndarray:
    """Full harmonics of every DOF from the contact-force harmonics.

    ``U_k = D_k^{-1} (F_k - B^T Lambda_k)`` for ``k = 0..Nh``.

    Parameters
    ----------
    contact_force : ndarray, shape (nc, 2 Nh + 1)
        Full coefficients of the active contact forces (N).

    Returns
    -------
    ndarray, shape (n, 2 Nh + 1)
        Full coefficients of the DOF displacements (m).
    """
    orders = np.arange(harmonics + 1)
    D = dynamic_stiffness(model, omega, orders)
    lam = np.concatenate([contact_force[:, :1], contact_force[:, 1::2] - 1j * contact_force[:, 2::2]], axis=1)
    rhs = forcing(model, orders, scale) - (B.T @ lam).T  # (n_orders, n)
    U = _solve(D, rhs[:, :, None], omega)[..., 0]  # (n_orders, n)
    out = np.empty((model.n_dofs, 2 * harmonics + 1))
    out[:, 0] = U[0].real
    out[:, 1::2] = U[1:].real.T
    out[:, 2::2] = -U[1:].imag.T
    return out
