"""Linear frequency responses with every contact stuck or every contact open.

These bound the nonlinear response (paper Fig. 8-9): with all friction
contacts stuck the structure is linear with rigid links, with all contacts
open it is the free structure. Unilateral contacts count as closed (rigid) in
the stuck state and as absent in the open state.
"""

from __future__ import annotations

from typing import Literal

import numpy as np

from ..model import Model
from .condensation import dynamic_stiffness, forcing

__all__ = ["linear_frf"]


def linear_frf(model: Model, omegas, state: Literal["stuck", "open"] = "stuck") -> np.ndarray:
    """Complex first-harmonic amplitudes of every DOF at each frequency.

    ``u(t) = Re(U exp(i omega t))`` with ``U`` solving the linear equations of
    motion for the excitation ``force_cos - i force_sin``; in the ``"stuck"``
    state, each contact is a rigid constraint ``u_r = 0`` (Lagrange multipliers).

    Parameters
    ----------
    model : Model
    omegas : array_like
        Frequencies (rad/s), > 0.
    state : {"stuck", "open"}

    Returns
    -------
    ndarray of complex, shape (len(omegas), n)
        Amplitudes (m).
    """
    omegas = np.atleast_1d(np.asarray(omegas, dtype=float))
    if np.any(~np.isfinite(omegas)) or np.any(omegas <= 0):
        raise ValueError("omegas must be finite frequencies > 0 rad/s")
    if state not in ("stuck", "open"):
        raise ValueError(f"state must be 'stuck' or 'open', got {state!r}")
    n = model.n_dofs
    D = np.stack([dynamic_stiffness(model, w, [1])[0] for w in omegas])
    F = np.broadcast_to(forcing(model, [1])[0], (len(omegas), n))
    if state == "open" or not model.contacts:
        return np.linalg.solve(D, F[..., None])[..., 0]
    B = model.relative_map()
    m = B.shape[0]
    K = np.zeros((len(omegas), n + m, n + m), dtype=complex)
    K[:, :n, :n], K[:, :n, n:], K[:, n:, :n] = D, B.T, B
    rhs = np.concatenate([F, np.zeros((len(omegas), m))], axis=1)
    return np.linalg.solve(K, rhs[..., None])[:, :n, 0]
