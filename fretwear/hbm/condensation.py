"""Exact condensation of the linear structure on the contact coordinates (eq. 11).

Per harmonic order ``k`` the linear part is the complex dynamic stiffness
``D_k = K - (k omega)^2 M + i k omega C``. With ``B`` the map to relative
contact coordinates, the contact receptance is ``G_k = B D_k^{-1} B^T`` and
the reduced equations of motion read ``Z_k U_r,k + Lambda_k = F_r,k`` with

    Z_k = G_k^{-1},   F_r,k = Z_k B D_k^{-1} F_k,

exact for any number of DOFs (the paper's eq. 11). When the relative
coordinates are dependent (contacts in a closed ring: a shroud around a
bladed disk, where they sum to zero) ``G_k`` is singular and ``Z_k`` does not
exist; :func:`receptance` then keeps the receptance form ``U_r,k = u_lin,k -
G_k Lambda_k`` with ``u_lin,k = B D_k^{-1} F_k`` (``fretwear.hbm.receptance``).
Real coefficients
``(a, b)`` of ``a cos + b sin`` relate to the complex amplitude ``a - i b``,
so a complex block ``Z = X + iY`` acts on ``(a, b)`` as ``[[X, Y], [-Y, X]]``.

All reduced arrays use the *contact-major* layout: entry ``c * H + j`` is slot
``j`` of the :class:`~fretwear.hbm.harmonics.HarmonicBasis` for contact ``c``.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numba import njit

from ..model import Model
from .dense import lu_factor, lu_solve
from .harmonics import HarmonicBasis

__all__ = [
    "Condensed",
    "Receptance",
    "condense",
    "receptance",
    "condense_sweep",
    "condense_loop",
    "dynamic_stiffness",
    "forcing",
    "recover",
]

#: largest number of DOFs condensed by the compiled loop of :func:`condense_sweep` (LAPACK above)
COMPILED_DOFS = 24


def dynamic_stiffness(model: Model, omega, orders: np.ndarray) -> np.ndarray:
    """Complex dynamic stiffness ``D_k`` per harmonic order, shape (..., len(orders), n, n).

    ``omega`` (rad/s) is a scalar, or an array broadcast against the orders.
    """
    w = (np.asarray(orders, dtype=float) * np.asarray(omega, dtype=float))[..., None, None]
    return model.K - w**2 * model.M + 1j * w * model.C


def _d_dynamic_stiffness(model: Model, omega, orders: np.ndarray) -> np.ndarray:
    """Derivative ``dD_k / d omega``, shape (..., len(orders), n, n)."""
    k = np.asarray(orders, dtype=float)
    k, w = (k + 0 * np.asarray(omega))[..., None, None], np.asarray(omega, dtype=float)[..., None, None]
    return -2 * k**2 * w * model.M + 1j * k * model.C


def forcing(model: Model, orders: np.ndarray, scale: float = 1.0) -> np.ndarray:
    """Complex force amplitude per harmonic order, shape (len(orders), n) (N)."""
    F = np.zeros((len(orders), model.n_dofs), dtype=complex)
    F[np.asarray(orders) == 0] = model.force_static
    F[np.asarray(orders) == 1] = model.force_cos - 1j * model.force_sin
    return scale * F


def _solve(D: np.ndarray, rhs: np.ndarray, omega) -> np.ndarray:
    try:
        return np.linalg.solve(D, rhs)
    except np.linalg.LinAlgError:
        where = np.array2string(np.atleast_1d(np.asarray(omega, dtype=float)), precision=6, threshold=4)
        raise ValueError(
            f"the dynamic stiffness K - (k omega)^2 M + i k omega C is singular at omega = {where} rad/s "
            "for some harmonic k (an undamped resonance, or a rigid-body mode when k = 0); "
            "add damping, anchor the structure or change the frequency"
        ) from None


@lru_cache(maxsize=64)
def _slots(basis: HarmonicBasis) -> tuple[np.ndarray, np.ndarray]:
    """Cos and sin slot of each distinct order (sin slot -1 for the mean)."""
    orders = _distinct_orders(basis)
    cos = np.array([np.flatnonzero((basis.orders == k) & ~basis.is_sine)[0] for k in orders])
    sin = np.array(
        [(np.flatnonzero((basis.orders == k) & basis.is_sine).tolist() or [-1])[0] for k in orders]
    )
    cos.setflags(write=False)
    sin.setflags(write=False)
    return cos, sin


def _real_blocks(Z: np.ndarray, basis: HarmonicBasis) -> np.ndarray:
    """Assemble complex per-order blocks (..., n_orders, nc, nc) into real contact-major matrices.

    A block ``X + iY`` acts on ``(a, b)`` as ``[[X, Y], [-Y, X]]``; the mean slot takes ``X``.
    """
    nc, H = Z.shape[-1], basis.size
    cos, sin = _slots(basis)
    out = np.zeros(Z.shape[:-3] + (nc * H, nc * H))
    c = np.arange(nc) * H
    rows = lambda s: c[None, :, None] + s[:, None, None]  # noqa: E731 - (n_orders, nc, 1)
    cols = lambda s: c[None, None, :] + s[:, None, None]  # noqa: E731 - (n_orders, 1, nc)
    X, Y = Z.real, Z.imag
    out[..., rows(cos), cols(cos)] = X
    k = sin >= 0
    out[..., rows(sin[k]), cols(sin[k])] = X[..., k, :, :]
    out[..., rows(cos[k]), cols(sin[k])] = Y[..., k, :, :]
    out[..., rows(sin[k]), cols(cos[k])] = -Y[..., k, :, :]
    return out


def _real_vector(v: np.ndarray, basis: HarmonicBasis) -> np.ndarray:
    """Complex per-order vectors (..., n_orders, nc) -> real contact-major vectors (..., nc * H)."""
    nc, H = v.shape[-1], basis.size
    cos, sin = _slots(basis)
    out = np.zeros(v.shape[:-2] + (nc, H))
    out[..., cos] = np.swapaxes(v.real, -1, -2)
    k = sin >= 0
    out[..., sin[k]] = -np.swapaxes(v.imag[..., k, :], -1, -2)
    return out.reshape(v.shape[:-2] + (nc * H,))


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


def condense(model: Model, B: np.ndarray, omega, basis: HarmonicBasis, derivative: bool = False) -> Condensed:
    """Condense ``model`` on the relative coordinates ``B u`` at ``omega`` (rad/s), eq. 11.

    Parameters
    ----------
    model : Model
    B : ndarray, shape (nc, n)
        Map from DOFs to the active contact coordinates.
    omega : float or ndarray
        Excitation frequency (rad/s); an array condenses every frequency at
        once (arrays of the result then have a leading frequency axis).
    basis : HarmonicBasis
    derivative : bool
        Also return ``dZ/d omega`` and ``dF/d omega`` (for continuation).
    """
    orders = _distinct_orders(basis)
    omega_arr = np.asarray(omega, dtype=float)
    D = dynamic_stiffness(model, omega_arr[..., None], orders)  # (..., n_orders, n, n)
    F = np.broadcast_to(forcing(model, orders), D.shape[:-1])
    rhs = np.concatenate([np.broadcast_to(B.T, D.shape[:-2] + B.T.shape), F[..., None]], axis=-1)
    sol = _solve(D, rhs.astype(complex), omega)  # D^{-1} [B^T, F]
    nc = B.shape[0]
    G = B @ sol[..., :nc]  # receptance (..., n_orders, nc, nc)
    u_lin = (B @ sol[..., nc:])[..., 0]  # linear open relative displacement (..., n_orders, nc)
    Z = np.linalg.inv(G)
    Fr = np.einsum("...ij,...j->...i", Z, u_lin)
    if not derivative:
        return Condensed(_real_blocks(Z, basis), _real_vector(Fr, basis))
    dD = _d_dynamic_stiffness(model, omega_arr[..., None], orders)
    dsol = -np.linalg.solve(D, dD @ sol)  # d(D^{-1} [B^T, F]) / d omega
    dG = B @ dsol[..., :nc]
    du_lin = (B @ dsol[..., nc:])[..., 0]
    dZ = -Z @ dG @ Z
    dFr = np.einsum("...ij,...j->...i", dZ, u_lin) + np.einsum("...ij,...j->...i", Z, du_lin)
    return Condensed(
        _real_blocks(Z, basis), _real_vector(Fr, basis), _real_blocks(dZ, basis), _real_vector(dFr, basis)
    )


@dataclass(frozen=True)
class Receptance:
    """Contact receptance and linear relative displacement at one frequency (the receptance form).

    Attributes
    ----------
    G : ndarray, shape (nc H, nc H)
        Real contact receptance ``G_r`` (m/N), contact-major; may be singular.
    U : ndarray, shape (nc H,)
        Linear relative displacement ``u_lin`` under the external force (m) for unit force scale.
    """

    G: np.ndarray
    U: np.ndarray


def receptance(model: Model, B: np.ndarray, omega: float, basis: HarmonicBasis) -> Receptance:
    """The receptance form of the condensation on ``B u`` at ``omega`` (rad/s): ``G_k`` and ``u_lin,k``.

    Unlike :func:`condense` it never inverts ``G_k``: it serves contacts whose
    relative coordinates are dependent.
    """
    orders = _distinct_orders(basis)
    D = dynamic_stiffness(model, float(omega), orders)  # (n_orders, n, n)
    Bt = np.broadcast_to(B.T, (len(orders),) + B.T.shape)
    rhs = np.concatenate([Bt, forcing(model, orders)[..., None]], axis=-1)
    sol = _solve(D, rhs.astype(complex), omega)
    nc = B.shape[0]
    G = B @ sol[..., :nc]
    u_lin = (B @ sol[..., nc:])[..., 0]
    return Receptance(_real_blocks(G, basis), _real_vector(u_lin, basis))


def recover(
    model: Model, B: np.ndarray, omega, harmonics: int, contact_force: np.ndarray, scale: float = 1.0
) -> np.ndarray:
    """Full harmonics of every DOF from the contact-force harmonics.

    ``U_k = D_k^{-1} (F_k - B^T Lambda_k)`` for ``k = 0..Nh``.

    Parameters
    ----------
    omega : float or ndarray, shape (nw,)
        Excitation frequency (rad/s); an array recovers every frequency at once.
    contact_force : ndarray, shape (nc, 2 Nh + 1), or (nw, nc, 2 Nh + 1) with an array ``omega``
        Full coefficients of the active contact forces (N).

    Returns
    -------
    ndarray, shape (n, 2 Nh + 1), or (nw, n, 2 Nh + 1)
        Full coefficients of the DOF displacements (m).
    """
    orders = np.arange(harmonics + 1)
    omega = np.asarray(omega, dtype=float)
    D = dynamic_stiffness(model, omega[..., None], orders)  # (..., n_orders, n, n)
    cf = contact_force
    lam = np.concatenate([cf[..., :1], cf[..., 1::2] - 1j * cf[..., 2::2]], axis=-1)  # (..., nc, n_orders)
    rhs = forcing(model, orders, scale) - np.swapaxes(B.T @ lam, -1, -2)  # (..., n_orders, n)
    U = _solve(D, rhs[..., None], omega)[..., 0]  # (..., n_orders, n)
    out = np.empty(omega.shape + (model.n_dofs, 2 * harmonics + 1))
    out[..., 0] = U[..., 0, :].real
    out[..., 1::2] = np.swapaxes(U[..., 1:, :].real, -1, -2)
    out[..., 2::2] = -np.swapaxes(U[..., 1:, :].imag, -1, -2)
    return out


@njit(cache=True, nogil=True)
def condense_loop(
    K, M, C, force_static, force_cos, force_sin, B, omegas, orders, cos_slot, sin_slot, H, Z, F
):
    """:func:`condense` at every frequency in one compiled loop, in real arithmetic.

    A complex system ``(X + iY)(y + iz) = c + id`` is solved as the real
    ``[[X, -Y], [Y, X]] [y; z] = [c; d]``. Returns the index of a frequency
    where some ``D_k`` or ``G_k`` is singular, or -1.
    """
    n, nc = K.shape[0], B.shape[0]
    D, piv = np.empty((2 * n, 2 * n)), np.empty(2 * n, dtype=np.int64)
    sol = np.empty((nc + 1, 2 * n))  # D^-1 [B^T, F_k], by columns
    G, gpiv = np.empty((2 * nc, 2 * nc)), np.empty(2 * nc, dtype=np.int64)
    col = np.empty(2 * nc)
    for i in range(omegas.shape[0]):
        Z[i] = 0.0
        F[i] = 0.0
        for o in range(orders.shape[0]):
            k, w = orders[o], orders[o] * omegas[i]
            for r in range(n):
                for c in range(n):
                    re, im = K[r, c] - w * w * M[r, c], w * C[r, c]
                    D[r, c], D[r, n + c], D[n + r, c], D[n + r, n + c] = re, -im, im, re
                for c in range(nc):
                    sol[c, r], sol[c, n + r] = B[c, r], 0.0
                re, im = (
                    (force_static[r], 0.0)
                    if k == 0
                    else ((force_cos[r], -force_sin[r]) if k == 1 else (0.0, 0.0))
                )
                sol[nc, r], sol[nc, n + r] = re, im
            if lu_factor(D, piv) == 0:
                return i
            for c in range(nc + 1):
                lu_solve(D, piv, sol[c])
            for a in range(nc):  # G = B D^-1 B^T, the receptance (complex, as a real block matrix)
                for c in range(nc):
                    re, im = 0.0, 0.0
                    for r in range(n):
                        re += B[a, r] * sol[c, r]
                        im += B[a, r] * sol[c, n + r]
                    G[a, c], G[a, nc + c], G[nc + a, c], G[nc + a, nc + c] = re, -im, im, re
            if lu_factor(G, gpiv) == 0:
                return i
            cs, ss = cos_slot[o], sin_slot[o]
            for c in range(nc + 1):  # Z_k = G^-1 by columns, then F_r = G^-1 (B D^-1 F_k)
                for a in range(nc):
                    if c < nc:
                        col[a], col[nc + a] = (1.0 if a == c else 0.0), 0.0
                    else:
                        col[a], col[nc + a] = 0.0, 0.0
                        for r in range(n):
                            col[a] += B[a, r] * sol[nc, r]
                            col[nc + a] += B[a, r] * sol[nc, n + r]
                lu_solve(G, gpiv, col)
                for a in range(nc):  # X + iY acts on (a, b) as [[X, Y], [-Y, X]]; the mean slot takes X
                    if c == nc:
                        F[i, a * H + cs] = col[a]
                        if ss >= 0:
                            F[i, a * H + ss] = -col[nc + a]
                        continue
                    X, Y = col[a], col[nc + a]
                    Z[i, a * H + cs, c * H + cs] = X
                    if ss >= 0:
                        Z[i, a * H + ss, c * H + ss] = X
                        Z[i, a * H + cs, c * H + ss] = Y
                        Z[i, a * H + ss, c * H + cs] = -Y
    return -1


def condense_sweep(model: Model, B: np.ndarray, omegas: np.ndarray, basis: HarmonicBasis) -> Condensed:
    """:func:`condense` at every frequency of ``omegas`` (rad/s), arrays with a leading frequency axis.

    Models of at most ``COMPILED_DOFS`` DOFs are condensed in one compiled loop
    (no array of per-order matrices); larger ones by :func:`condense`.
    """
    if model.n_dofs > COMPILED_DOFS:
        return condense(model, B, omegas, basis)
    nc, H = B.shape[0], basis.size
    cos, sin = _slots(basis)
    Z, F = np.empty((len(omegas), nc * H, nc * H)), np.empty((len(omegas), nc * H))
    failed = condense_loop(
        model.K, model.M, model.C, model.force_static, model.force_cos, model.force_sin,
        np.ascontiguousarray(B, dtype=float), np.ascontiguousarray(omegas, dtype=float),
        _distinct_orders(basis).astype(float), cos, sin, H, Z, F,
    )  # fmt: skip
    if failed >= 0:
        return condense(model, B, omegas, basis)  # raises with the frequency named, as a single solve would
    return Condensed(Z, F)
