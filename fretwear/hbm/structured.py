"""The Newton step of the coupled DLFT law from its structure: no dense Jacobian (compiled).

The Jacobian of the coupled law is ``J = Z + blockdiag(A_i) (E - Z)``
(``fretwear.hbm.coupled``), of size ``n = 2 nc H`` (``nc`` pairs, ``H = 2 Nh
+ 1`` harmonic slots). Forming it costs ``2 H n^2`` and factoring it ``n^3 /
3``: at 128 pairs and ``Nh = 7`` (n = 3 840) about 1.3 s a step. The same
holds for the 2-D friction law (``fretwear.hbm.cone``) with three
coordinates a pair, ``n = 3 nc H``: below, "pair" has ``d`` = 2 or 3
coordinates and ``q = d nc``. Two structures make the step cheap:

* ``Z`` (the condensed dynamic stiffness, eq. 11) couples no two harmonics:
  per harmonic ``k`` it is one real block on the ``2 nc`` contact coordinates
  (``k = 0``) or ``4 nc`` coordinates (cosine and sine slots, ``k >= 1``),
  :func:`harmonic_blocks`;
* the law is local: ``A_i`` couples only the ``2 H`` unknowns of pair ``i``.
  Per contact coordinate ``c`` its rows ``A_c`` (``H x 2 H``) are, in the
  solve, of three kinds:

  - *fixed*: ``A_c`` is the identity on ``c`` (a closed normal coordinate, a
    tangential one stuck all period): ``J_c = E_c``, so ``dx_c = -R_c / eps_c``;
  - *free*: ``A_c = 0`` (a pair open all period): ``J_c = Z_c``;
  - *mixed*: any other (slip, or contact part of the period), and the other
    coordinate of a mixed one's pair.

With ``dx_F`` known, the free rows ``Z_OO dx_O + Z_OM dx_M = -R_O - Z_OF dx_F``
give ``dx_O`` harmonic by harmonic, and the mixed rows become the Schur
complement on the mixed coordinates alone,

    [(I - A)_MP S_PM + (A E)_MM] dx_M = -R_M - (I - A)_MP g_P - (A E)_MF dx_F,

with ``S = Z_PM - Z_PO Z_OO^-1 Z_OM`` and ``g_P = Z_PF dx_F + Z_PO Z_OO^-1
(-R_O - Z_OF dx_F)`` per harmonic (``P`` the coordinates of the pairs with a
mixed coordinate). Only this system, of ``H`` times the number of mixed
coordinates (the slip annulus' tangential coordinates in partial slip), is
dense. The step is the dense one's to rounding: the elimination is exact.
:func:`structured_step` factors it (:func:`mixed_matrix`); ``fretwear.hbm.krylov``
solves it by GMRES without forming it. The elimination is in two parts:
:func:`schur` (``Z_OO^-1`` and ``S`` by harmonic) depends on ``Z`` and the
kinds alone, so a Newton step that keeps the kinds reuses the last one's;
:func:`reduce_rhs` (``g``, ``w``) is a few products per step.
Per harmonic ``k >= 1`` the free and pair rows are eliminated in complex
arithmetic (``Z_k``'s real block ``[[X, Y], [-Y, X]]`` is ``X - i Y`` on the
amplitude ``a_k + i b_k``): a complex LU of the open coordinates costs half the
real one of twice their size.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = [
    "FIXED", "FREE", "MIXED", "harmonic_blocks", "dense_from_blocks", "classify", "partition", "schur",
    "reduce_rhs", "eliminate", "mixed_rhs", "mixed_matrix", "back_substitute", "structured_step",
]  # fmt: skip

#: kinds of a contact coordinate's rows of ``J`` (module text)
FIXED, FREE, MIXED = 0, 1, 2

#: an entry of ``A`` this close to 0 or 1 is exact (``A = Psi G Phi`` rounds at ~1e-15)
_EXACT = 1e-12


def harmonic_blocks(Z: np.ndarray, coordinates: int, H: int) -> np.ndarray:
    """Per harmonic ``k`` the real block ``Z^k`` of ``Z`` (contact-major layout), shape (Nh + 1, 2 q, 2 q).

    Parameters
    ----------
    Z : (q H, q H) real dynamic stiffness (N/m), entry ``c H + j`` slot ``j`` of coordinate ``c``
        (slot 0 the mean, ``2 k - 1`` and ``2 k`` the cosine and sine of harmonic ``k``).
    coordinates : ``q``, the number of contact coordinates. H : slots per coordinate, ``2 Nh + 1``.

    Returns
    -------
    Zb : ``Zb[0, :q, :q]`` the mean's block; ``Zb[k]`` for ``k >= 1`` on the coordinates' cosine
        slots then their sine slots. ``Z`` has no entry between two harmonics (eq. 11 holds
        harmonic by harmonic), so ``Zb`` holds all of it.
    """
    q = coordinates
    if Z.shape != (q * H, q * H) or H % 2 != 1:
        raise ValueError(f"Z must be ({q * H}, {q * H}) with H = 2 Nh + 1 odd, got {Z.shape} and H = {H}")
    Nh = (H - 1) // 2
    Zb = np.zeros((Nh + 1, 2 * q, 2 * q))
    c = np.arange(q) * H
    Zb[0, :q, :q] = Z[np.ix_(c, c)]
    for k in range(1, Nh + 1):
        idx = np.concatenate([c + 2 * k - 1, c + 2 * k])
        Zb[k] = Z[np.ix_(idx, idx)]
    return Zb


def dense_from_blocks(Zb: np.ndarray) -> np.ndarray:
    """The dense ``Z`` (q H, q H) (N/m) from its harmonic blocks: the inverse of :func:`harmonic_blocks`.

    Parameters
    ----------
    Zb : (Nh + 1, 2 q, 2 q) blocks in :func:`harmonic_blocks`' layout (``Zb[0, q:, :]`` and
        ``Zb[0, :, q:]`` unused).

    Returns
    -------
    Z : (q H, q H), ``H = 2 Nh + 1``, contact-major (entry ``c H + j`` slot ``j`` of coordinate ``c``);
        zero between two harmonics (eq. 11).
    """
    if Zb.ndim != 3 or Zb.shape[1] != Zb.shape[2] or Zb.shape[1] % 2:
        raise ValueError(f"Zb must be (Nh + 1, 2 q, 2 q), got shape {Zb.shape}")
    Nh, q = Zb.shape[0] - 1, Zb.shape[1] // 2
    H = 2 * Nh + 1
    Z = np.zeros((q, H, q, H))
    Z[:, 0, :, 0] = Zb[0, :q, :q]
    for k in range(1, Nh + 1):  # Nh + 1 block copies, not a hot path
        for a, sa in ((0, 2 * k - 1), (1, 2 * k)):
            for b, sb in ((0, 2 * k - 1), (1, 2 * k)):
                Z[:, sa, :, sb] = Zb[k, a * q : (a + 1) * q, b * q : (b + 1) * q]
    return Z.reshape(q * H, q * H)


@njit(cache=True, nogil=True)
def classify(A, per_pair=2):
    """Kind (FIXED, FREE, MIXED) of every contact coordinate's rows of ``J`` from the blocks ``A``
    (``per_pair`` coordinates a pair: 2 for the coupled law, 3 for the 2-D friction law)."""
    nc, m = A.shape[0], A.shape[1]
    H = m // per_pair
    kind = np.empty(per_pair * nc, dtype=np.int64)
    for i in range(nc):
        mixed = False
        for a in range(per_pair):
            dev_id, dev_zero = 0.0, 0.0
            for r in range(a * H, (a + 1) * H):
                for s in range(m):
                    v = A[i, r, s]
                    dev_id = max(dev_id, abs(v - (1.0 if r == s else 0.0)))
                    dev_zero = max(dev_zero, abs(v))
            c = per_pair * i + a
            kind[c] = FIXED if dev_id < _EXACT else (FREE if dev_zero < _EXACT else MIXED)
            mixed = mixed or kind[c] == MIXED
        if mixed:  # a mixed row reads the whole pair
            for a in range(per_pair):
                if kind[per_pair * i + a] == FREE:
                    kind[per_pair * i + a] = MIXED
    return kind


@njit(cache=True, nogil=True)
def _cgather(Zbk, q, rows, cols, k):
    """``Z_k[rows, cols]`` as a complex matrix (coordinates ``rows``, ``cols``): ``X - i Y`` from the block
    ``[[X, Y], [-Y, X]]`` of harmonic ``k >= 1`` (it maps ``a + i b`` to ``(X - i Y)(a + i b)``), ``X`` at
    ``k = 0``. Half the real form's size: a quarter of its LU's work less the complex arithmetic's."""
    out = np.empty((rows.shape[0], cols.shape[0]), dtype=np.complex128)
    for a in range(rows.shape[0]):
        for b in range(cols.shape[0]):
            im = 0.0 if k == 0 else -Zbk[rows[a], q + cols[b]]
            out[a, b] = complex(Zbk[rows[a], cols[b]], im)
    return out


@njit(cache=True, nogil=True)
def _amplitude(v, start, k):
    """Complex amplitude ``a_k + i b_k`` of harmonic ``k`` of the slots ``v[start : start + H]``."""
    if k == 0:
        return complex(v[start], 0.0)
    return complex(v[start + 2 * k - 1], v[start + 2 * k])


@njit(cache=True, nogil=True)
def partition(kind, d):
    """The index sets of the coordinates' ``kind`` (:func:`classify`, ``d`` coordinates a pair): ``(kind, Fi,
    Oi, Mi, Pi, posM, posP)``, the fixed, open, mixed coordinates and those of the pairs with a mixed
    coordinate (``P``), then each coordinate's index among the mixed ones and among ``P`` (-1 if none)."""
    q = kind.shape[0]
    nF, nO, nM = np.sum(kind == FIXED), np.sum(kind == FREE), np.sum(kind == MIXED)
    Fi, Oi, Mi = np.empty(nF, np.int64), np.empty(nO, np.int64), np.empty(nM, np.int64)
    posM = np.full(q, -1)
    nF, nO, nM = 0, 0, 0
    for c in range(q):
        if kind[c] == FIXED:
            Fi[nF] = c
            nF += 1
        elif kind[c] == FREE:
            Oi[nO] = c
            nO += 1
        else:
            Mi[nM] = c
            posM[c] = nM
            nM += 1
    nP = 0
    posP = np.full(q, -1)
    for c in range(q):
        first = c - c % d
        for b in range(d):
            if kind[first + b] == MIXED:
                posP[c] = nP
                nP += 1
                break
    Pi = np.empty(nP, np.int64)
    for c in range(q):
        if posP[c] >= 0:
            Pi[posP[c]] = c
    return kind, Fi, Oi, Mi, Pi, posM, posP


@njit(cache=True, nogil=True)
def schur(Zb, part):
    """The part of the elimination that depends on ``Z`` and the kinds alone, the same for every Newton step
    that keeps them: per harmonic ``Z_OO^-1`` (Nh + 1, nO, nO), ``G = Z_OO^-1 Z_OM`` (Nh + 1, nO, nM) and
    the Schur complement ``S_PM = Z_PM - Z_PO G`` (Nh + 1, nP, nM) (complex, the amplitude ``a_k + i b_k``;
    real at ``k = 0``), ``part`` of :func:`partition`. Returns ``(Zinv, G, Sc)``."""
    kind, Fi, Oi, Mi, Pi, posM, posP = part
    K = Zb.shape[0]
    q = kind.shape[0]
    nO, nM, nP = Oi.shape[0], Mi.shape[0], Pi.shape[0]
    Zinv = np.zeros((K, nO, nO), dtype=np.complex128)
    G = np.zeros((K, nO, nM), dtype=np.complex128)
    Sc = np.zeros((K, nP, nM), dtype=np.complex128)
    for k in range(K):
        Zk = Zb[k]
        if nO > 0:
            ZOO = _cgather(Zk, q, Oi, Oi, k)
            if k == 0:  # real
                Zinv[0] = np.linalg.inv(np.ascontiguousarray(ZOO.real))
            else:
                Zinv[k] = np.linalg.inv(ZOO)
            G[k] = Zinv[k] @ _cgather(Zk, q, Oi, Mi, k)
        if nP > 0:
            Sc[k] = _cgather(Zk, q, Pi, Mi, k) - _cgather(Zk, q, Pi, Oi, k) @ G[k]
    return Zinv, G, Sc


@njit(cache=True, nogil=True)
def reduce_rhs(Zb, part, Zinv, R, eps, dx):
    """The part of the elimination that depends on the residual: the fixed coordinates' steps ``-R / eps``
    into ``dx`` (m), and per harmonic ``w = Z_OO^-1 (-R_O - Z_OF dx_F)`` (Nh + 1, nO) (m) and ``g_P = Z_PF
    dx_F + Z_PO w`` (nP, H) in slots (N), from ``Z``'s blocks times the fixed steps (one product a
    harmonic, no gather). Returns ``(g, w)``."""
    kind, Fi, Oi, Mi, Pi, posM, posP = part
    K = Zb.shape[0]
    H = 2 * K - 1
    q = kind.shape[0]
    nO, nP = Oi.shape[0], Pi.shape[0]
    for c in range(q):
        for j in range(H):
            dx[c * H + j] = -R[c * H + j] / eps[c] if kind[c] == FIXED else 0.0
    g = np.zeros((nP, H))
    w = np.zeros((K, nO), dtype=np.complex128)
    v = np.zeros(2 * q)
    for k in range(K):
        for c in range(q):  # Z_k dx_F (dx is 0 off the fixed coordinates): the real form on (cos, sin)
            v[c] = dx[c * H] if k == 0 else dx[c * H + 2 * k - 1]
            v[q + c] = 0.0 if k == 0 else dx[c * H + 2 * k]
        y = Zb[k] @ v
        bO = np.empty(nO, dtype=np.complex128)
        for a in range(nO):
            c = Oi[a]
            bO[a] = -_amplitude(R, c * H, k) - complex(y[c], 0.0 if k == 0 else y[q + c])
        w[k] = Zinv[k] @ bO
        if nP > 0:
            gk = _cgather(Zb[k], q, Pi, Oi, k) @ w[k]
            for a in range(nP):
                c = Pi[a]
                gk[a] += complex(y[c], 0.0 if k == 0 else y[q + c])
                _put_amplitude(g[a], 0, k, gk[a])
    return g, w


@njit(cache=True, nogil=True)
def eliminate(Zb, A, R, eps, dx):
    """The exact part of the step (module text): the fixed coordinates' steps into ``dx`` and, harmonic by
    harmonic, the open coordinates eliminated onto the mixed ones (:func:`partition`, :func:`schur`,
    :func:`reduce_rhs`).

    Parameters as :func:`structured_step`'s. Returns ``(kind, Oi, Mi, posM, posP, Sc, g, G, w)``: the
    kinds, the open and mixed coordinates, each coordinate's index among the mixed ones and among ``P``
    (or -1), the Schur complement ``S_PM`` by harmonic ``Sc`` (Nh + 1, nP, nM) complex (N/m), ``g_P``
    (nP, H) in slots (N), and ``Z_OO^-1 Z_OM`` (Nh + 1, nO, nM), ``Z_OO^-1 (-R_O - Z_OF dx_F)`` (Nh + 1,
    nO) for :func:`back_substitute`.
    """
    d = A.shape[1] // (2 * Zb.shape[0] - 1)
    part = partition(classify(A, d), d)
    Zinv, G, Sc = schur(Zb, part)
    g, w = reduce_rhs(Zb, part, Zinv, R, eps, dx)
    kind, Fi, Oi, Mi, Pi, posM, posP = part
    return kind, Oi, Mi, posM, posP, Sc, g, G, w


@njit(cache=True, nogil=True)
def _put_amplitude(v, start, k, z):
    """Write the complex amplitude ``z`` of harmonic ``k`` into the slots ``v[start : start + H]``."""
    if k == 0:
        v[start] = z.real
    else:
        v[start + 2 * k - 1], v[start + 2 * k] = z.real, z.imag


@njit(cache=True, nogil=True)
def mixed_rhs(A, R, eps, dx, kind, Mi, posP, g):
    """The mixed rows' right-hand side ``-R_M - (I - A)_MP g_P - (A E)_MF dx_F`` (nM H,) (N), pair by pair
    (``dx`` holds the fixed coordinates' steps)."""
    nM, H = Mi.shape[0], g.shape[1]
    d = A.shape[1] // H
    rhs = np.zeros(nM * H)
    t = np.zeros(d * H)
    for mc in range(nM):
        c = Mi[mc]
        i, a = c // d, c % d
        if mc == 0 or Mi[mc - 1] // d != i:  # a pair's mixed coordinates are consecutive: t once a pair
            for b in range(d):
                e = d * i + b
                for r in range(H):
                    t[b * H + r] = g[posP[e], r] - (eps[e] * dx[e * H + r] if kind[e] == FIXED else 0.0)
        At = A[i, a * H : (a + 1) * H] @ t
        for r in range(H):
            rhs[mc * H + r] = -R[c * H + r] - g[posP[c], r] + At[r]
    return rhs


@njit(cache=True, nogil=True)
def mixed_matrix(Sc, A, eps, kind, Mi, posM, posP):
    """The dense mixed system ``(I - A)_MP S_PM + (A E)_MM`` (nM H, nM H) (N/m), pair by pair from the
    Schur complement by harmonic ``Sc`` (:func:`eliminate`)."""
    K, nM = Sc.shape[0], Sc.shape[2]
    H = 2 * K - 1
    d = A.shape[1] // H
    Kmat = np.zeros((nM * H, nM * H))
    SR = np.zeros((d * H, nM * H))  # a pair's rows of S_PM in slots
    mc = 0
    while mc < nM:
        i = Mi[mc] // d
        SR[:, :] = 0.0
        for b in range(d):
            p = posP[d * i + b]
            for k in range(K):
                for m in range(nM):
                    z = Sc[k, p, m]
                    if k == 0:
                        SR[b * H, m * H] = z.real
                    else:  # the real form of a complex amplitude: [[Re, -Im], [Im, Re]]
                        rc, rs, cc, cs = b * H + 2 * k - 1, b * H + 2 * k, m * H + 2 * k - 1, m * H + 2 * k
                        SR[rc, cc], SR[rc, cs], SR[rs, cc], SR[rs, cs] = z.real, -z.imag, z.imag, z.real
        T = SR - A[i] @ SR
        for b in range(d):
            e = d * i + b
            if kind[e] == MIXED:
                for r in range(d * H):
                    for s in range(H):
                        T[r, posM[e] * H + s] += A[i, r, b * H + s] * eps[e]
        while mc < nM and Mi[mc] // d == i:
            a = Mi[mc] % d
            Kmat[mc * H : (mc + 1) * H] = T[a * H : (a + 1) * H]
            mc += 1
    return Kmat


@njit(cache=True, nogil=True)
def back_substitute(dx, Oi, Mi, G, w):
    """The open coordinates' steps ``dx_O = w - G dx_M`` harmonic by harmonic into ``dx`` (m)."""
    K, nO, nM = G.shape[0], Oi.shape[0], Mi.shape[0]
    H = 2 * K - 1
    for k in range(K):
        dxMk = np.empty(nM, dtype=np.complex128)
        for b in range(nM):
            dxMk[b] = _amplitude(dx, Mi[b] * H, k)
        dO = w[k] - G[k] @ dxMk
        for a in range(nO):
            _put_amplitude(dx, Oi[a] * H, k, dO[a])


@njit(cache=True, nogil=True)
def structured_step(Zb, A, R, eps, dx):
    """The Newton step ``dx = -J^-1 R`` of the coupled law by the elimination of the module text.

    Parameters
    ----------
    Zb : (Nh + 1, 2 q, 2 q) blocks of ``Z`` by harmonic (:func:`harmonic_blocks`) (N/m).
    A : (nc, d H, d H) the law's Jacobian blocks, ``d`` coordinates a pair (2: the coupled law, 3: the 2-D
        friction law of ``fretwear.hbm.cone``), ``q = d nc``. R : (q H,) residual (N).
    eps : (q,) penalty per coordinate (N/m). dx : (q H,) out, the step (m).

    Returns the number of mixed coordinates. A singular ``Z_OO`` or Schur
    complement raises (LAPACK), as the dense solve does.
    """
    H = 2 * Zb.shape[0] - 1
    kind, Oi, Mi, posM, posP, Sc, g, G, w = eliminate(Zb, A, R, eps, dx)
    nM = Mi.shape[0]
    if nM > 0:
        rhs = mixed_rhs(A, R, eps, dx, kind, Mi, posP, g)
        dxM = np.linalg.solve(mixed_matrix(Sc, A, eps, kind, Mi, posM, posP), rhs)
        for mc in range(nM):
            dx[Mi[mc] * H : (Mi[mc] + 1) * H] = dxM[mc * H : (mc + 1) * H]
    back_substitute(dx, Oi, Mi, G, w)
    return nM
