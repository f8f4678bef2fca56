"""The linear dynamics of one stick pattern, and the pattern table of a model at one frequency.

Between two contact events the motion of a :class:`~fretwear.model.Model` with
Coulomb contacts (paper eq. 5, 30) is linear: the contacts of the *stick
pattern* ``S`` keep ``B_S v = 0``, every other contact ``j`` carries a constant
force ``lambda_j = g_j d_j`` (``g_j = mu_j F_N,j``, ``d_j`` the slip direction,
``g_j = 0`` for an open contact). In the augmented state

    X = (u, v, lambda, 1, cos omega t, sin omega t),   size D = 2 n + n_f + 3,

(``lambda`` holds the forces of the contacts that are not stuck, zero for the
stuck ones; Jenkins contacts below) the motion is the autonomous linear system ``X' = A_S X`` with

    u' = v,   v' = P_S M^-1 r(X),   r = f(t) - C v - K u - B^T lambda,
    (cos, sin)' = omega (-sin, cos),   lambda' = 0,

``P_S = I - M^-1 B_S^T W_S^-1 B_S`` the M-orthogonal projector onto
``B_S v' = 0`` and ``W_S = B_S M^-1 B_S^T`` the Delassus matrix of the stuck
contacts, whose forces are ``lambda_S = W_S^-1 B_S M^-1 r(X)`` (the rows
:attr:`Pattern.force`). The same coordinates serve every pattern, so that a
change of pattern changes no coordinate.

**Jenkins contacts** (``FrictionContact(..., kt=...)``: a spring ``k_t`` in
series with the Coulomb slider, force ``lambda_j = k_t (u_r,j - s_j)``,
``|lambda_j| <= g_j``). Their force is a state: ``lambda`` holds every
contact's force, and the state of the march is ``y = (u, v, lambda)``
(``2 n + n_f``, the first entries of ``X``). A stuck Jenkins contact is no
constraint: ``lambda_j' = k_t,j (B v)_j`` (no Delassus matrix, no rank
condition); a slipping one keeps ``lambda_j = g_j d_j`` (``lambda_j' = 0``).
Its force row is ``e_lambda_j``, so the guards are the same polynomials: the
stuck force reaching ``+-g_j``, the relative velocity of a slipping contact
changing sign. A model's friction contacts are all rigid or all Jenkins.

Each pattern is propagated by its Taylor series over steps of length
``h_S``: ``X(t + s) = sum_k (A_S h_S)^k / k! X(t) (s / h_S)^k`` with
``K = TAYLOR_ORDER`` terms, ``h_S`` chosen so that the rest of the series is
below ``1e-20 |X|`` (a bound in a balanced norm, checked here). On a step
every guard function (a stuck force minus or plus its slip limit, the
relative velocity of a slipping contact) is then a polynomial of known
coefficients: :mod:`fretwear.time.series` locates its first root with
certified bounds. The series is exact for any ``A_S``: singular (rigid-body
motion, a free mass slipping), defective or resonant (undamped, ``omega`` an
eigenfrequency) patterns need no special case.
"""

from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from numba import njit

from ..model import Model
from .dense import matmul_into

__all__ = ["TAYLOR_ORDER", "Engine", "Structure", "Table", "structure", "unsupported"]

#: terms of the Taylor series of a step (polynomial degree)
TAYLOR_ORDER = 30
_REMAINDER = 1e-20  # bound on the truncated tail of a step, relative to |X| in the balanced norm
_STEP_RADIUS = 3.0  # first trial of h_S: growth rate times h_S
_MIN_STEPS = 4  # at least this many steps per excitation period


def _null_space(A: np.ndarray) -> np.ndarray:
    """Orthonormal basis (columns) of the null space of ``A``, by SVD (rank tolerance as scipy's)."""
    _, s, vh = np.linalg.svd(A)
    rank = int(np.sum(s > np.finfo(float).eps * max(A.shape) * s.max())) if s.size else 0
    return vh[rank:].T


def unsupported(model: Model, *, jenkins: bool = False) -> str | None:
    """Why the event-driven integrator cannot run ``model`` (``None`` when it can).

    It needs friction contacts only, a positive definite ``M`` and, for rigid
    contacts, linearly independent contacts; the exact dynamics
    (:func:`fretwear.shooting`) apply exactly where it runs. Jenkins contacts
    (``kt`` given) are taken when ``jenkins`` (the integrator and shooting);
    without it (the default, the exact wear dynamics) they are a reason.
    """
    if model.pairs is not None:
        return (
            "supports 1-D friction contacts only: contact node pairs (model.pairs, "
            f"{model.n_pairs} given) have the coupled normal/tangential law; use fretwear.solve_periodic"
        )
    if model.normal:
        return (
            "supports friction contacts only: unilateral normal contacts "
            f"(model.normal, {len(model.normal)} given) are not implemented"
        )
    M = model.M
    if np.linalg.eigvalsh(M).min() <= 1e-12 * np.abs(M).max():
        return (
            "requires a positive definite mass matrix M: "
            "massless DOFs (singular M) are not supported; condense them out first "
            "(a Jenkins element is a FrictionContact with kt)"
        )
    n_jenkins = sum(c.kt is not None for c in model.friction)
    if n_jenkins and not jenkins:
        return (
            f"takes Jenkins contacts (kt given: {n_jenkins} of the friction contacts) in fretwear.shooting "
            "and fretwear.time.integrate only: the exact wear dynamics are for rigid contacts"
        )
    if n_jenkins and n_jenkins < len(model.friction):
        return (
            f"requires the friction contacts to be all rigid or all Jenkins (kt given), got {n_jenkins} "
            f"Jenkins of {len(model.friction)}: mixed models are not implemented"
        )
    if (
        model.friction
        and not n_jenkins
        and np.linalg.matrix_rank(model.relative_map(model.friction)) < len(model.friction)
    ):
        return (
            "requires linearly independent friction contacts (relative map B of full row rank): "
            "redundant contacts make the stuck forces indeterminate"
        )
    return None


class Structure:
    """What the stick patterns of one model share at every frequency.

    Checks the model (friction contacts only, ``M`` positive definite,
    independent rigid contacts) and caches, per stuck set, ``A_S`` without its
    ``omega`` entries and the force rows. ``kt``: the tangential stiffnesses
    (N/m) of a Jenkins model, empty for rigid contacts; ``ny``: the size of the
    state ``y``, ``2 n`` (rigid) or ``2 n + n_f`` (Jenkins: ``(u, v, lambda)``).
    """

    def __init__(self, model: Model) -> None:
        reason = unsupported(model, jenkins=True)
        if reason:
            raise ValueError(f"the time integrator {reason}")
        self.model = model
        self.n, self.nf = model.n_dofs, len(model.friction)
        self.dim = 2 * self.n + self.nf + 3
        jenkins = any(c.kt is not None for c in model.friction)
        self.kt = np.array([c.kt for c in model.friction], dtype=float) if jenkins else np.zeros(0)
        self.ny = 2 * self.n + len(self.kt)
        self.B = model.relative_map(model.friction)
        Minv = np.linalg.inv(model.M)
        self.Minv = (Minv + Minv.T) / 2
        self.C, self.K = model.C, model.K
        self.forces = np.column_stack([model.force_static, model.force_cos, model.force_sin])
        self.extrema_rows = np.vstack([np.eye(self.n), self.B])  # u -> (u, B u): the channels of extrema
        self._matrices: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._rigid: dict[int, tuple] = {}

    def rigid_basis(self, active: int) -> tuple:
        """The structure with the contacts of bit mask ``active`` rigid (``B_a u = 0``), reduced.

        Returns ``(N, K_r, M_r, C_r, f_r, u_static)``: an orthonormal basis
        ``N`` of ``B_a u = 0``, the reduced matrices ``N^T (K, M, C) N``, the
        reduced complex load ``N^T (F_c - i F_s)`` and the static solution (m).
        """
        found = self._rigid.get(active)
        if found is None:
            model = self.model
            Ba = self.B[[j for j in range(self.nf) if active >> j & 1]]
            N = _null_space(Ba) if len(Ba) else np.eye(self.n)
            Kr, Mr, Cr = (N.T @ a @ N for a in (model.K, model.M, model.C))
            u_static = (
                N @ np.linalg.lstsq(Kr, N.T @ model.force_static)[0] if N.shape[1] else np.zeros(self.n)
            )
            found = self._rigid[active] = (
                N,
                Kr,
                Mr,
                Cr,
                N.T @ (model.force_cos - 1j * model.force_sin),
                u_static,
            )
        return found

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
        if stuck and len(self.kt):  # Jenkins: the stuck forces follow the springs, lambda' = k_t B v
            A_lam = np.zeros((nf, D))
            A_lam[stuck, n : 2 * n] = self.kt[stuck, None] * self.B[stuck]
        elif stuck:
            BS = self.B[stuck]
            MiBt = self.Minv @ BS.T
            W = BS @ MiBt
            L = np.linalg.solve(W, BS @ acc)  # lambda_S = W^-1 B_S M^-1 r
            rows[stuck] = L
            acc = acc - MiBt @ L
        A = np.zeros((D, D))
        A[:n, n : 2 * n] = np.eye(n)
        A[n : 2 * n] = acc
        if stuck and len(self.kt):
            A[i_lam:i_one] = A_lam
        self._matrices[mask] = A, rows
        return A, rows


@lru_cache(maxsize=64)
def structure(model: Model) -> Structure:
    """The (cached) :class:`Structure` of ``model``."""
    return Structure(model)


class Table:
    """Stick-pattern propagators of one model at one or several excitation frequencies.

    The patterns are built on demand (:meth:`require`, for every frequency at
    once) and packed into arrays for the compiled kernels; a pattern's slot
    never changes, so that step records keep their meaning when the table grows.

    Parameters
    ----------
    model : Model
        Friction contacts only (all rigid or all Jenkins), ``M`` positive definite, rigid
        contacts linearly independent.
    omegas : array_like, shape (W,)
        Excitation frequencies (rad/s), > 0.
    """

    def __init__(self, model: Model, omegas) -> None:
        st = structure(model)
        self.structure, self.model = st, model
        self.omegas = np.array(omegas, dtype=float).reshape(-1)
        self.periods = 2 * np.pi / self.omegas
        self.n, self.nf, self.dim, self.ny, self.kt = st.n, st.nf, st.dim, st.ny, st.kt
        self.B, self.Minv, self.C, self.K, self.forces = st.B, st.Minv, st.C, st.K, st.forces
        #: ``(M^-1, B, C, K, forces, kt)`` as the kernels take them (:mod:`fretwear.time.codes`)
        self.model_arrays = (st.Minv, st.B, st.C, st.K, st.forces, st.kt)
        self.extrema_rows = st.extrema_rows
        self.count = 0
        #: the linear stuck responses per set of loaded contacts (filled by the shooting solver)
        self.rigid: dict[int, tuple] = {}
        self._slots: dict[int, int] = {}
        masks = [0] + [m for m in st.seen() if m]  # every contact slipping, then those seen before
        self._allocate(max(2, len(masks)))
        self._add(masks)

    def slot(self, mask: int) -> int:
        """Slot of the pattern whose stuck contacts are the bits of ``mask``; -1 if not built."""
        return self._slots.get(mask, -1)

    def require(self, mask: int) -> int:
        """Build the pattern of stuck set ``mask`` (bit ``j``: contact ``j`` stuck) if needed; its slot."""
        if mask not in self._slots:
            self._add([mask])
        return self._slots[mask]

    def table(self, i: int) -> tuple:
        """Frequency ``i`` as the kernels take it: ``(masks, Ah, force_rows, phi, series, step, count)``."""
        return (self.masks, self.Ah[i], self.force_rows, self.phi[i], self.phi_series[i], self.step[i],
                self.count)  # fmt: skip

    def stacked(self) -> tuple:
        """Every frequency: :meth:`table` with a frequency axis first on ``Ah``, ``phi``, series, ``step``."""
        return self.masks, self.Ah, self.force_rows, self.phi, self.phi_series, self.step, self.count

    def _allocate(self, cap: int) -> None:
        W, ny, D, K = len(self.omegas), self.ny, self.dim, TAYLOR_ORDER
        old = self.__dict__.get("masks")
        arrays = {
            "masks": np.full(cap, -1, dtype=np.int64),
            "Ah": np.zeros((W, cap, D, D)),  # A_S h_S
            "force_rows": np.zeros((cap, self.nf, D)),  # X -> friction force of every contact
            "phi": np.zeros((W, cap, ny, ny)),  # exp(A_yy h_S): state transition of a full step
            "phi_series": np.zeros((W, cap, K + 1, ny, ny)),  # (A_yy h_S)^k / k!
            "step": np.zeros((W, cap)),  # h_S (s)
        }
        for name, a in arrays.items():
            if old is not None:
                prev = getattr(self, name)
                if name in ("masks", "force_rows"):
                    a[: self.count] = prev[: self.count]
                else:
                    a[:, : self.count] = prev[:, : self.count]
            setattr(self, name, a)

    def _add(self, masks: list[int]) -> None:
        if self.count + len(masks) > len(self.masks):
            self._allocate(max(2 * len(self.masks), self.count + len(masks)))
        k0 = self.count
        A0 = np.empty((len(masks), self.dim, self.dim))
        for p, mask in enumerate(masks):
            A0[p], self.force_rows[k0 + p] = self.structure.matrices(mask)
            self.masks[k0 + p] = mask
            self._slots[mask] = k0 + p
        _prepare_all(A0, self.omegas, self.ny, k0, self.Ah, self.phi_series, self.phi, self.step)
        self.count += len(masks)


class Engine(Table):
    """The :class:`Table` of one model at one excitation frequency ``omega`` (rad/s)."""

    def __init__(self, model: Model, omega: float) -> None:
        super().__init__(model, [omega])
        self.omega, self.period = float(self.omegas[0]), float(self.periods[0])

    def arrays(self) -> tuple:
        """The table as the kernels take it: ``(masks, Ah, force_rows, phi, phi_series, step, count)``."""
        return self.table(0)


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
def _prepare(A0, omega, period, ny, Ah, series, phi):
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
    work = np.empty((D, D))
    e = K + 1
    while e:
        if e & 1:
            matmul_into(power, base, work)
            power, work = work, power
        matmul_into(base, base, work)
        base, work = work, base
        e >>= 1
    top = _inf_norm(power)
    root = top ** (1.0 / (K + 1)) if top > 0 else 0.0
    rate = max(root, omega)
    h = min(period / _MIN_STEPS, _STEP_RADIUS / rate)
    if root > 0:
        while (K + 1) * math.log(root * h) - math.lgamma(K + 2) + norm * h > math.log(_REMAINDER):
            h /= 1.25
    for i in range(D):
        for j in range(D):
            Ah[i, j] = A[i, j] * h
    phi[:, :] = 0.0
    series[0] = 0.0
    for i in range(ny):
        series[0, i, i] = 1.0
        phi[i, i] = 1.0
    for k in range(1, K + 1):  # (A_yy h)^k / k!
        for i in range(ny):
            for j in range(ny):
                t = 0.0
                for q in range(ny):
                    t += series[k - 1, i, q] * Ah[q, j]
                series[k, i, j] = t / k
                phi[i, j] += series[k, i, j]
    return h


@njit(cache=True, nogil=True)
def _prepare_all(A0, omegas, ny, k0, Ah, series, phi, step):
    """:func:`_prepare` of the patterns ``A0`` (slots ``k0, k0 + 1, ...``) at every frequency."""
    for w in range(omegas.shape[0]):
        period = 2 * math.pi / omegas[w]
        for p in range(A0.shape[0]):
            k = k0 + p
            step[w, k] = _prepare(A0[p], omegas[w], period, ny, Ah[w, k], series[w, k], phi[w, k])
