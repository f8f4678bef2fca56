"""Condensation of a reduced model on its contact coordinates (eq. 11)."""

import numpy as np
import pytest

from fretwear.hbm.harmonics import HarmonicBasis
from fretwear.interface.reduction import ContactCondensation
from fretwear.model import craig_bampton


@pytest.fixture(scope="module")
def model(small_cylinder):
    return small_cylinder


def test_condensation_on_contact_coordinates(model):
    r = craig_bampton(model, 1.0e5)
    cond = ContactCondensation(r)
    nc = model.n_pairs
    # k >= 1: the Schur complement is the inverse of the contact receptance B D^-1 B^T
    B = r.pairs.relative_map(r.n_dofs).toarray()
    w = 2 * np.pi * 3e3
    for k in (1, 3):
        D = r.K - (k * w) ** 2 * r.M + 1j * k * w * r.C
        Z, F, _ = cond.schur(w, k)
        G = B @ np.linalg.solve(D, B.T)
        assert np.abs(Z @ G - np.eye(2 * nc)).max() < 1e-8
        # the reduced force is the force that holds every pair glued (the excitation is at k = 1)
        u_open = B @ np.linalg.solve(D, r.force_cos if k == 1 else 0 * r.force_cos)
        assert np.allclose(F, Z @ u_open, rtol=1e-8, atol=1e-8 * r.force_cos.max())
    # k = 0: the pad hangs on the contact only, so sliding or lifting it rigidly costs no force
    Z0, Fs, Fc = cond.static
    slide = np.tile([1.0, 0.0], nc)
    lift = np.tile([0.0, -1.0], nc)
    for mode in (slide, lift):
        assert np.abs(Z0 @ mode).max() <= 1e-9 * np.abs(Z0).max()
    # with every pair glued, the pairs carry the whole normal and tangential loads
    P, Q = model.info["normal_load"], model.info["tangential_load"]
    assert Fs[1::2].sum() == pytest.approx(P, rel=1e-10) and abs(Fs[0::2].sum()) < 1e-8 * P
    assert Fc[0::2].sum() == pytest.approx(Q, rel=1e-10)


def test_recover_satisfies_the_equations_off_the_contact(model):
    r = craig_bampton(model, 1.0e5)
    cond = ContactCondensation(r)
    nh, w = 2, 2 * np.pi * 2e3
    rng = np.random.default_rng(1)
    q = 1e-7 * rng.standard_normal((2 * model.n_pairs, 2 * nh + 1))
    coords = cond.recover(w, nh, q)
    B = r.pairs.relative_map(r.n_dofs).toarray()
    assert np.allclose(B @ coords, q, atol=1e-15)
    # the contact forces lambda = F_k - Z_k q close the equations on every coordinate
    basis = HarmonicBasis(nh, 16)
    Z, F = cond.harmonic(w, basis)
    lam = (F - Z @ q.reshape(-1)).reshape(q.shape)  # contact-major = coordinate-major here
    for k in range(nh + 1):
        D = r.K - (k * w) ** 2 * r.M + 1j * k * w * r.C
        u = coords[:, 0] if k == 0 else coords[:, 2 * k - 1] - 1j * coords[:, 2 * k]
        lk = lam[:, 0] if k == 0 else lam[:, 2 * k - 1] - 1j * lam[:, 2 * k]
        f = r.force_static if k == 0 else (r.force_cos if k == 1 else 0 * r.force_cos)
        res = D @ u + B.T @ lk - f
        assert np.abs(res).max() <= 1e-8 * (np.abs(D @ u).max() + np.abs(f).max())
