"""The linear dynamics of one stick pattern, and the pattern table of a model at one frequency.

Between two contact events the motion of a :class:`~fretwear.model.Model` with
Coulomb contacts (paper eq. 5, 30) is linear: the contacts of the *stick
pattern* ``S`` keep ``B_S v = 0``, every other contact ``j`` carries a constant
force ``lambda_j = g_j d_j`` (``g_j = mu_j F_N,j``, ``d_j`` the slip direction,
``g_j = 0`` for an open contact). In the augmented state

    X = (u, v, lambda, 1, cos omega t, sin omega t),   size D = 2 n + n_f + 3,

(``lambda`` holds the forces of the contacts that are not stuck, zero for the
stuck ones) the motion is the autonomous linear system ``X' = A_S X`` with

    u' = v,   v' = P_S M^-1 r(X),   r = f(t) - C v - K u - B^T lambda,
    (cos, sin)' = omega (-sin, cos),   lambda' = 0,

``P_S = I - M^-1 B_S^T W_S^-1 B_S`` the M-orthogonal projector onto
``B_S v' = 0`` and ``W_S = B_S M^-1 B_S^T`` the Delassus matrix of the stuck
contacts, whose forces are ``lambda_S = W_S^-1 B_S M^-1 r(X)`` (the rows
:attr:`Pattern.force`). The same coordinates serve every pattern, so that a
change of pattern changes no coordinate.

Each pattern is propagated by its Taylor series over steps of length
``h_S``: ``X(t + s) = sum_k (A_S h_S)^k / k! X(t) (s / h_S)^k`` with
``K = TAYLOR_ORDER`` terms, ``h_S`` chosen so that the rest of the series is
below ``1e-20 |X|`` (a bound in a balanced norm, checked here). On a step
every guard function (a stuck force minus or plus its slip limit, the
relative velocity of a slipping contact) is then a polynomial of known
coefficients: :mod:`fretwear.time.kernels` locates its first root with
certified bounds. The series is exact for any ``A_S``: singular (rigid-body
motion, a free mass slipping), defective or resonant (undamped, ``omega`` an
eigenfrequency) patterns need no special case.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import njit
from scipy import linalg

from ..model import Model

__all__ = ["TAYLOR_ORDER", "Engine", "Structure", "structure"]

#: terms of the Taylor series of a step (polynomial degree)
TAYLOR_ORDER = 30
_REMAINDER = 1e-20  # bound on the truncated tail of a step, relative to |X| in the balanced norm
_STEP_RADIUS = 3.0  # first trial of h_S: growth rate times h_S
_MIN_STEPS = 4  # at least this many steps per excitation period


class Structure:
    """What the stick patterns of one model share at every frequency.

    Checks the model (friction contacts only, ``M`` positive definite,
    independent contacts) and caches, per stuck set, ``A_S`` without its
    ``omega`` entries and the force rows.
    """

    def __init__(self, model: Model) -> None:
        if model.normal:
            raise ValueError(
                "the time integrator supports friction contacts only: unilateral normal contacts "
                f"(model.normal, {len(model.normal)} given) are not implemented"
            )
        M = model.M
        if np.linalg.eigvalsh(M).min() <= 1e-12 * np.abs(M).max():
            raise ValueError(
                "the time integrator requires a positive definite mass matrix M: "
                "massless DOFs (singular M) are not supported; condense them out first"
            )
        self.model = model
        self.n, self.nf = model.n_dofs, len(model.friction)
        self.dim = 2 * self.n + self.nf + 3
        self.B = model.relative_map(model.friction)
        if self.nf and np.linalg.matrix_rank(self.B) < self.nf:
            raise ValueError(
                "friction contacts must be linearly independent (relative map B of full row rank): "
                "redundant contacts make the stuck forces indeterminate"
            )
        Minv = linalg.inv(M)
        self.Minv = (Minv + Minv.T) / 2
        self.C, self.K = model.C, model.K
        self.forces = np.column_stack([model.force_static, model.force_cos, model.force_sin])
        self._matrices: dict[int, tuple[np.ndarray, np.ndarray]] = {}

    def seen(self) -> list[int]:
        """Stuck sets built so far (at any frequency), and every stuck set when there are at most 8."""
        masks = set(self._matrices)
        if self.nf <= 3:
            masks.update(range(1 << self.nf))
        return sorted(masks)

    def matrices(self, mask: int) -> tuple[np.ndarray, np.ndarray]:
        """``A_S`` without its ``omega`` entries and the force rows ``X -> lambda`` of stuck set ``mask``."""
        found = self._matrices.get(mask)
        if found is not None:
            return found
        n, nf, D = self.n, self.nf, self.dim
        stuck = [j for j in range(nf) if mask >> j & 1]
        i_lam, i_one = 2 * n, 2 * n + nf
        R = np.zeros((n, D))  # X -> r = f - C v - K u - B^T lambda
        R[:, :n], R[:, n : 2 * n], R[:, i_lam:i_one] = -self.K, -self.C, -self.B.T
        R[:, i_one : i_one + 3] = self.forces
        rows = np.zeros((nf, D))
        rows[:, i_lam:i_one] = np.eye(nf)
        acc = self.Minv @ R
        if stuck:
            BS = self.B[stuck]
            MiBt = self.Minv @ BS.T
            W = BS @ MiBt
            L = linalg.solve(W, BS @ acc, assume_a="pos")  # lambda_S = W^-1 B_S M^-1 r
            rows[stuck] = L
            acc = acc - MiBt @ L
        A = np.zeros((D, D))
        A[:n, n : 2 * n] = np.eye(n)
        A[n : 2 * n] = acc
        self._matrices[mask] = A, rows
        return A, rows


@lru_cache(maxsize=64)
def structure(model: Model) -> Structure:
    """The (cached) :class:`Structure` of ``model``."""
    return Structure(model)


class Engine:
    """Pattern table of one model at one excitation frequency.

    The patterns are built on demand (:meth:`require`) and packed into arrays
    for the compiled kernels; a pattern's slot never changes, so that step
    records keep their meaning when the table grows.

    Parameters
    ----------
    model : Model
        Friction contacts only, ``M`` positive definite, contacts linearly independent.
    omega : float
        Excitation frequency (rad/s), > 0.
    """

    def __init__(self, model: Model, omega: float) -> None:
        st = structure(model)
        self.structure, self.model = st, model
        self.omega, self.period = float(omega), 2 * np.pi / omega
        self.n, self.nf, self.dim = st.n, st.nf, st.dim
        self.B, self.Minv, self.C, self.K, self.forces = st.B, st.Minv, st.C, st.K, st.forces
        n, D, K = self.n, self.dim, TAYLOR_ORDER
        self.count = 0
        self._slots: dict[int, int] = {}
        seen = st.seen()
        cap = max(2, len(seen) + 1)
        self.masks = np.full(cap, -1, dtype=np.int64)
        self.Ah = np.zeros((cap, D, D))  # A_S h_S
        self.force_rows = np.zeros((cap, self.nf, D))  # X -> friction force of every contact
        self.phi = np.zeros((cap, 2 * n, 2 * n))  # exp(A_yy h_S): state transition of a full step
        self.phi_series = np.zeros((cap, K + 1, 2 * n, 2 * n))  # (A_yy h_S)^k / k!
        self.step = np.zeros(cap)  # h_S (s)
        self.require(0)  # every contact slipping (or open)
        for mask in seen:  # the patterns this model needed at other frequencies
            self.require(mask)

    # -- the table -----------------------------------------------------------
    def slot(self, mask: int) -> int:
        """Slot of the pattern whose stuck contacts are the bits of ``mask``; -1 if not built."""
        return self._slots.get(mask, -1)

    def require(self, mask: int) -> int:
        """Build the pattern of stuck set ``mask`` (bit ``j``: contact ``j`` stuck) if needed; its slot."""
        found = self.slot(mask)
        if found >= 0:
            return found
        if self.count == len(self.masks):
            self._grow()
        A0, rows = self.structure.matrices(mask)
        k = self.count
        self.step[k] = _prepare(A0, self.omega, self.period, 2 * self.n, self.Ah[k], self.phi_series[k],
                                self.phi[k])  # fmt: skip
        self.force_rows[k] = rows
        self.masks[k] = mask
        self._slots[mask] = k
        self.count += 1
        return k

    def arrays(self) -> tuple:
        """The table as the kernels take it: ``(masks, Ah, force_rows, phi, phi_series, step, count)``."""
        return self.masks, self.Ah, self.force_rows, self.phi, self.phi_series, self.step, self.count

    def _grow(self) -> None:
        cap = 2 * len(self.masks)

        def bigger(a, fill=0):
            out = np.full((cap, *a.shape[1:]), fill, dtype=a.dtype)
            out[: len(a)] = a
            return out

        self.masks = bigger(self.masks, -1)
        self.Ah, self.force_rows = bigger(self.Ah), bigger(self.force_rows)
        self.phi, self.phi_series, self.step = bigger(self.phi), bigger(self.phi_series), bigger(self.step)


# ---------------------------------------------------------------------------
# step data of one pattern at one frequency
# ---------------------------------------------------------------------------
@njit(cache=True, nogil=True)
def _balance(A):
    """Diagonally balanced copy of ``A`` (rows and columns of equal off-diagonal 1-norms; zero ones kept)."""
    D = A.shape[0]
    Ab = A.copy()
    for _ in range(30):
        done = True
        for i in range(D):
            r = 0.0
            c = 0.0
            for j in range(D):
                if j != i:
                    r += abs(Ab[i, j])
                    c += abs(Ab[j, i])
            if r == 0.0 or c == 0.0:
                continue
            f = math.sqrt(c / r)
            if abs(f - 1.0) > 0.05:
                done = False
                for j in range(D):
                    Ab[i, j] *= f
                    Ab[j, i] /= f
        if done:
            break
    return Ab


@njit(cache=True, nogil=True)
def _inf_norm(A):
    best = 0.0
    for i in range(A.shape[0]):
        best = max(best, np.abs(A[i]).sum())
    return best


@njit(cache=True, nogil=True)
def _prepare(A0, omega, period, n2, Ah, series, phi):
    """Step ``h_S`` of ``A_S`` (``A0`` plus the rotation ``omega``); fills ``A h``, the series, ``phi``.

    With ``|.|`` the infinity norm after diagonal balancing, the tail of
    ``sum_k (A h)^k / k!`` beyond ``K`` is at most
    ``|A^(K+1)| h^(K+1) / (K+1)! exp(|A| h)``; ``h`` is the longest step
    ``<= T / 4`` and ``<= 3 / |A^(K+1)|^(1 / (K+1))`` with a tail below ``1e-20``.
    """
    K = TAYLOR_ORDER
    D = A0.shape[0]
    A = A0.copy()
    A[D - 2, D - 1] = -omega
    A[D - 1, D - 2] = omega
    Ab = _balance(A)
    norm = _inf_norm(Ab)
    power = np.eye(D)  # Ab^(K+1) by repeated squaring
    base = Ab.copy()
    e = K + 1
    while e:
        if e & 1:
            power = power @ base
        base = base @ base
        e >>= 1
    top = _inf_norm(power)
    root = top ** (1.0 / (K + 1)) if top > 0 else 0.0
    rate = max(root, omega)
    h = min(period / _MIN_STEPS, _STEP_RADIUS / rate)
    if root > 0:
        while (K + 1) * math.log(root * h) - math.lgamma(K + 2) + norm * h > math.log(_REMAINDER):
            h /= 1.25
    Ah[:, :] = A * h
    term = np.eye(n2)
    yy = np.ascontiguousarray(Ah[:n2, :n2])
    phi[:, :] = 0.0
    for k in range(K + 1):
        series[k] = term
        phi += term
        term = term @ yy / (k + 1)
    return h
