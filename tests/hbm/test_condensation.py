"""Exact condensation on the contact coordinates (eq. 11) against a direct solve of all DOFs."""

import numpy as np

from fretwear import FrictionContact, Model
from fretwear.hbm.condensation import condense, recover
from fretwear.hbm.harmonics import HarmonicBasis


def random_model(n=5, seed=0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    K = A @ A.T + n * np.eye(n)
    M = np.diag(rng.uniform(0.5, 2, n))
    M[-1, -1] = 0.0  # a massless DOF
    contacts = (
        FrictionContact.from_normal_load(0, 2, 0.5, 1.0),
        FrictionContact.from_normal_load(4, None, 0.5, 1.0),
    )
    return Model(M=M, C=0.01 * K, K=K, force_cos=rng.normal(size=n), force_sin=rng.normal(size=n),
                 force_static=rng.normal(size=n), friction=contacts)  # fmt: skip


def test_reduced_equations_reproduce_the_full_linear_solve():
    model, omega, nh = random_model(), 1.3, 4
    basis = HarmonicBasis(nh, 64)
    B = model.relative_map()
    cond = condense(model, B, omega, basis, derivative=True)
    lam = np.random.default_rng(1).normal(size=(2, basis.size))  # arbitrary contact-force harmonics
    U = recover(model, B, omega, nh, lam)  # all DOFs from the full equations
    x = np.linalg.solve(cond.Z, cond.F - lam.reshape(-1))  # eq. 11: Z x + Lambda = F
    np.testing.assert_allclose(x.reshape(2, -1), B @ U, rtol=1e-10, atol=1e-12)
    # the full harmonic-balance equations hold for U, term by term (cos and sin of each order)
    k = np.arange(1, nh + 1)
    a, b = U[:, 1::2], U[:, 2::2]
    fa, fb = np.zeros((5, nh)), np.zeros((5, nh))
    fa[:, 0], fb[:, 0] = model.force_cos, model.force_sin
    for j, kk in enumerate(k):
        w = kk * omega
        cos_eq = (model.K - w**2 * model.M) @ a[:, j] + w * model.C @ b[:, j] + B.T @ lam[:, 1 + 2 * j]
        sin_eq = (model.K - w**2 * model.M) @ b[:, j] - w * model.C @ a[:, j] + B.T @ lam[:, 2 + 2 * j]
        np.testing.assert_allclose(cos_eq, fa[:, j], atol=1e-10)
        np.testing.assert_allclose(sin_eq, fb[:, j], atol=1e-10)
    np.testing.assert_allclose(model.K @ U[:, 0] + B.T @ lam[:, 0], model.force_static, atol=1e-10)


def test_frequency_derivatives():
    model, nh, h = random_model(seed=2), 3, 1e-6
    basis = HarmonicBasis(nh, 32)
    B = model.relative_map()
    c = condense(model, B, 0.9, basis, derivative=True)
    up, dn = condense(model, B, 0.9 + h, basis), condense(model, B, 0.9 - h, basis)
    np.testing.assert_allclose(c.dZ, (up.Z - dn.Z) / (2 * h), rtol=1e-5, atol=1e-6 * np.abs(c.dZ).max())
    np.testing.assert_allclose(c.dF, (up.F - dn.F) / (2 * h), rtol=1e-5, atol=1e-6 * np.abs(c.dF).max())


def test_batched_frequencies_equal_single_ones():
    model, basis = random_model(seed=3), HarmonicBasis(5, 64, half_wave=False)
    B = model.relative_map()
    omegas = np.array([0.4, 0.9, 1.7])
    many = condense(model, B, omegas, basis, derivative=True)
    for i, w in enumerate(omegas):
        one = condense(model, B, w, basis, derivative=True)
        for name in ("Z", "F", "dZ", "dF"):
            np.testing.assert_allclose(getattr(many, name)[i], getattr(one, name), rtol=1e-12, atol=1e-14)
