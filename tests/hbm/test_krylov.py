"""The GMRES step of the pair laws (``fretwear.hbm.krylov``) against the dense Jacobian's exact solve."""

import numpy as np
import pytest

from fretwear.hbm.dlft import jacobian_from_blocks
from fretwear.hbm.harmonics import HarmonicBasis
from fretwear.hbm.krylov import (
    COUNTERS,
    EXACT,
    FALLBACKS,
    ITERATIONS,
    MAX_ITERATIONS,
    REUSED,
    STEPS,
    cached_step,
    empty_cache,
    krylov_step,
)
from fretwear.hbm.structured import FIXED, FREE, MIXED, classify, dense_from_blocks, structured_step

NH = 3


def _case(d: int, nc: int, seed: int):
    """A random well-posed step: ``Z`` by harmonic blocks (a mass-spring-damper chain's dynamic stiffness on
    ``q = d nc`` coordinates, plus a random symmetric coupling), and per pair law blocks ``A = Psi G(t) Phi``
    of a state that is fixed (``G = I``), free (``G = 0``) or changes within the period (per sample ``I``, a
    random rank-deficient projection, or 0): every kind of coordinate is present."""
    rng = np.random.default_rng(seed)
    basis = HarmonicBasis(NH, 32)
    H, Phi, Psi = basis.size, basis.synthesis, basis.analysis
    q = d * nc
    K = np.diag(np.full(q, 2.0)) - np.diag(np.ones(q - 1), 1) - np.diag(np.ones(q - 1), -1)
    B = rng.standard_normal((q, q))
    K = 1e6 * (K + 0.05 * (B + B.T) / np.sqrt(q) + 0.5 * np.eye(q))
    M, C = np.eye(q), 1e-3 * K
    Zb = np.zeros((NH + 1, 2 * q, 2 * q))
    Zb[0, :q, :q] = K
    for k in range(1, NH + 1):
        X, Y = K - (3e2 * k) ** 2 * M, 3e2 * k * C
        Zb[k] = np.block([[X, Y], [-Y, X]])
    A = np.zeros((nc, d * H, d * H))
    kinds = rng.permutation(np.arange(nc) % 3)  # 0 fixed, 1 free, 2 changes state: a third of each
    for i in range(nc):
        if kinds[i] == 0:
            A[i] = np.eye(d * H)
        elif kinds[i] == 2:
            G = np.zeros((Phi.shape[0], d, d))
            for s in range(Phi.shape[0]):
                state = rng.integers(3)
                if state == 0:
                    G[s] = np.eye(d)
                elif state == 1:  # slip: a projection that keeps the normal coordinate (the last)
                    t = rng.standard_normal(d - 1)
                    P = np.eye(d)
                    P[: d - 1, : d - 1] -= np.outer(t, t) / (t @ t)
                    P[: d - 1, d - 1] = 0.3 * rng.standard_normal(d - 1)
                    G[s] = P
            for a in range(d):
                for b in range(d):
                    A[i, a * H : (a + 1) * H, b * H : (b + 1) * H] = Psi @ (G[:, a, b, None] * Phi)
    eps = 10 * np.abs(np.diag(K))
    R = 1e-3 * rng.standard_normal(q * H)
    return Zb, A, R, eps


def _dense_step(Zb, A, R, eps):
    Z = dense_from_blocks(Zb)
    J = np.empty_like(Z)
    jacobian_from_blocks(Z, eps, A, J)
    return np.linalg.solve(J, -R), J


@pytest.mark.parametrize("d", [2, 3])  # the coupled law, the 2-D (cone) law
def test_krylov_step_is_the_dense_step(d):
    """With fixed, free and mixed coordinates, the exact structured step is LAPACK's dense solve to
    rounding, and the GMRES step solves to the linear residual asked (checked on the dense ``J``) and, asked
    1e-12 of the residual, equals the dense step to 1e-8 of its size."""
    Zb, A, R, eps = _case(d, 24, seed=d)
    assert set(classify(A, d).tolist()) == {FIXED, FREE, MIXED}
    ref, J = _dense_step(Zb, A, R, eps)
    dx = np.empty_like(R)
    structured_step(Zb, A, R, eps, dx)
    assert np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()
    r = np.linalg.norm(R)
    for rel in (1e-4, 1e-12):
        stats = np.zeros(COUNTERS, dtype=np.int64)
        res = krylov_step(Zb, A, R, eps, dx, rel * r, 0, stats)
        assert stats[STEPS] == 1 and stats[FALLBACKS] == 0 and 0 < stats[ITERATIONS] < MAX_ITERATIONS
        assert res <= rel * r
        assert np.linalg.norm(J @ dx + R) <= 1.01 * rel * r + 1e-12 * r  # the whole step's residual
    assert np.abs(dx - ref).max() <= 1e-8 * np.abs(ref).max()


def test_small_systems_and_a_stalled_gmres_take_the_exact_step():
    """Below ``krylov_min`` mixed unknowns, and when GMRES cannot reach its tolerance (here one below
    rounding) within its products, the step is the exact one and the counters say which."""
    Zb, A, R, eps = _case(3, 18, seed=7)
    ref, _ = _dense_step(Zb, A, R, eps)
    dx = np.empty_like(R)
    stats = np.zeros(COUNTERS, dtype=np.int64)
    assert krylov_step(Zb, A, R, eps, dx, 1e-6, 10**9, stats) == 0.0
    assert stats.tolist() == [0, 0, 0, 1, 0] and np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()
    stats[:] = 0
    assert krylov_step(Zb, A, R, eps, dx, 1e-300, 0, stats) == 0.0
    assert stats[STEPS] == 1 and stats[FALLBACKS] == 1 and stats[ITERATIONS] == MAX_ITERATIONS
    assert stats[EXACT] == 0 and np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()


def test_a_step_with_the_same_kinds_reuses_the_elimination():
    """Two steps with the same law blocks and another residual: the second reuses the first's ``Z_OO^-1`` and
    Schur complement, and is still the dense step of its residual; new kinds rebuild them."""
    Zb, A, R, eps = _case(2, 30, seed=11)
    stats = np.zeros(COUNTERS, dtype=np.int64)
    dx = np.empty_like(R)
    cache = cached_step(Zb, A, R, eps, dx, 0.0, 0, stats, empty_cache())[1]
    R2 = np.random.default_rng(1).standard_normal(R.size) * np.abs(R).max()
    cache = cached_step(Zb, A, R2, eps, dx, 0.0, 0, stats, cache)[1]
    assert stats[REUSED] == 1 and stats[EXACT] == 2
    ref, _ = _dense_step(Zb, A, R2, eps)
    assert np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()
    A2, i = A.copy(), np.flatnonzero(classify(A, 2)[::2] == FREE)[0]  # a free pair closes: new kinds
    A2[i] = np.eye(A.shape[1])
    cached_step(Zb, A2, R2, eps, dx, 0.0, 0, stats, cache)
    assert stats[REUSED] == 1
    ref, _ = _dense_step(Zb, A2, R2, eps)
    assert np.abs(dx - ref).max() <= 1e-10 * np.abs(ref).max()
