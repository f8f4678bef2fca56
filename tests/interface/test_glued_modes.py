"""Eq. 11's Schur complement by the glued structure's modes (proportional damping) against a dense solve.

With ``C = alpha K + beta M`` the condensation applies ``D_ss^-1`` through one Cholesky factorization
and the modes of ``(K_ss, M_ss)`` for every harmonic and frequency (``"modal"``); otherwise it factors
``D_ss`` (``"lu"``). Both are checked against ``D_qq - D_qs D_ss^-1 D_sq`` by ``numpy.linalg.solve``
(an independent dense solve) on a Craig-Bampton cylinder (every mode has mass; the pad held by the
contact alone, so ``Z_0`` is singular but finite) and a coarse 3-D sphere (mass on the holder alone:
two modes), for ``k = 0`` and ``k >= 1``, with and without the binormals kept.
"""

from dataclasses import replace

import numpy as np
import pytest

from fretwear.hbm.harmonics import HarmonicBasis
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import holder_frequency, sphere_dynamic_model
from fretwear.model import craig_bampton


def dense_schur(cond: ContactCondensation, omega: float, k: int, keep: int) -> tuple[np.ndarray, np.ndarray]:
    """``Z_k`` and ``F_k`` of eq. 11 at ``omega`` (rad/s) by a dense solve of ``D_ss``."""
    w = k * omega
    D = cond.K - w**2 * cond.M + 1j * w * cond.C
    f = cond.force_static if k == 0 else cond.force_harmonic * (k == 1)
    X = np.linalg.solve(D[keep:, keep:], np.column_stack([D[keep:, :keep], f[keep:]]))
    Z = D[:keep, :keep] - D[:keep, keep:] @ X[:, :keep]
    return 0.5 * (Z + Z.T), f[:keep] - D[:keep, keep:] @ X[:, keep]


def assert_close(a: np.ndarray, b: np.ndarray, rtol: float = 1e-10) -> None:
    assert np.abs(a - b).max() <= rtol * np.abs(b).max()


@pytest.fixture(scope="module")
def cylinder(small_cylinder):
    return craig_bampton(small_cylinder, 1.0e5)


@pytest.fixture(scope="module")
def sphere():
    return sphere_dynamic_model(divisions=4, size=4.0)


def test_modal_schur_is_the_dense_one_on_a_craig_bampton_cylinder(cylinder):
    cond = ContactCondensation(cylinder)
    alpha, beta = cond.proportional
    assert alpha == pytest.approx(2 * 0.01 / (2 * np.pi * 2000.0), rel=1e-10)  # C = beta K of fe.py
    assert abs(beta) * np.abs(cond.M).max() <= 1e-12 * alpha * np.abs(cond.K).max()
    assert cond._modal(cond.n_q).mu.size > 10  # every Craig-Bampton mode has mass
    for k in (0, 1, 3):
        Z, F, path = cond.schur(2 * np.pi * 3e3, k)
        assert path == "modal"
        Zd, Fd = dense_schur(cond, 2 * np.pi * 3e3, k, cond.n_q)
        assert_close(Z, Zd)
        assert_close(F, Fd) if k <= 1 else np.testing.assert_array_equal(F, 0.0)
    # k = 0: the pad hangs on the contact alone, Z_0 singular (sliding it costs no force) but finite
    Z0 = cond.schur(0.0, 0)[0]
    assert np.abs(Z0 @ np.tile([1.0, 0.0], cond.n_pairs)).max() <= 1e-9 * np.abs(Z0).max()


@pytest.mark.parametrize("binormal", [False, True])
def test_modal_schur_is_the_dense_one_on_the_sphere(sphere, binormal):
    cond = ContactCondensation(sphere)
    keep = cond.n_q + int(cond.has_binormal.sum()) * binormal
    assert cond._modal(keep).mu.size == 2  # the holder's mass on pad_x, pad_z
    omega = 2 * np.pi * 0.9 * holder_frequency()
    for k in (0, 1, 2, 5):
        Z, F, path = cond.schur(omega, k, keep)
        assert path == "modal"
        Zd, Fd = dense_schur(cond, omega, k, keep)
        assert_close(Z, Zd)
        assert_close(F, Fd) if k <= 1 else np.testing.assert_array_equal(F, 0.0)
        rhs = np.random.default_rng(k).standard_normal(cond.K.shape[0] - keep)
        D = cond.K - (k * omega) ** 2 * cond.M + 1j * k * omega * cond.C
        assert_close(cond.glued_solve(omega, k, rhs, keep), np.linalg.solve(D[keep:, keep:], rhs))


def test_non_proportional_damping_takes_the_lu_path(cylinder):
    n = cylinder.n_dofs
    extra = np.zeros((n, n))
    extra[n - 1, n - 1] = 10 * np.abs(cylinder.C).max() + 1.0  # a dashpot on one coordinate only
    cond = ContactCondensation(replace(cylinder, C=cylinder.C + extra))
    assert cond.proportional is None
    omega = 2 * np.pi * 3e3
    for k in (0, 1, 2):
        Z, F, path = cond.schur(omega, k)
        assert path == "lu"
        Zd, Fd = dense_schur(cond, omega, k, cond.n_q)
        assert_close(Z, Zd)
        assert_close(F, Fd) if k <= 1 else np.testing.assert_array_equal(F, 0.0)


@pytest.mark.parametrize("binormal", [False, True])
def test_modal_harmonic_blocks_are_the_lu_ones(sphere, cylinder, binormal):
    # the blocks by harmonic in the solver's layout, binormals reordered and a dummy one on the symmetry plane
    omega = 2 * np.pi * 0.3 * holder_frequency()
    basis = HarmonicBasis(3, 16, False)
    for model in (sphere, cylinder) if not binormal else (sphere,):
        fast, ref = ContactCondensation(model), ContactCondensation(model, modal=False)
        assert binormal is False or not fast.has_binormal.all()  # pairs on the symmetry plane
        Zb, F = fast.harmonic_blocks(omega, basis, binormal)
        Zr, Fr = ref.harmonic_blocks(omega, basis, binormal)
        assert ref.schur(omega, 1)[2] == "lu" and fast.schur(omega, 1)[2] == "modal"
        assert_close(Zb, Zr)
        assert_close(F, Fr)
        x = np.random.default_rng(0).standard_normal((F.size // basis.size, 2 * 3 + 1))
        assert_close(fast.recover(omega, 3, x), ref.recover(omega, 3, x))
