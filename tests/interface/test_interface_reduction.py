"""Craig-Bampton reduction and condensation on the contact coordinates (eq. 11)."""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from fretwear.hbm.harmonics import HarmonicBasis
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.reduction import ContactCondensation, craig_bampton


@pytest.fixture(scope="module")
def model():
    return cylinder_on_flat(contact_nodes=5, growth=1.6, pad_height=0.004, pad_half_width=0.004,
                            flat_half_width=0.006, flat_depth=0.004)  # fmt: skip


def test_guyan_stiffness_is_the_exact_schur_complement(model):
    r = craig_bampton(model, 0.0)
    K = model.K.toarray()
    b, i = r.boundary, r.interior
    S = K[np.ix_(b, b)] - K[np.ix_(b, i)] @ np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    assert r.n_modes == 0
    assert np.abs(r.K - S).max() <= 1e-9 * np.abs(S).max()


def test_mode_count_follows_the_frequency_criterion(model):
    r = craig_bampton(model, 1.5e5, factor=2.0)
    assert r.cutoff == 3e5 and r.n_modes > 0
    assert np.all(r.mode_frequencies <= r.cutoff)
    Kii = model.K[r.interior][:, r.interior]
    Mii = model.M[r.interior][:, r.interior]
    w2 = np.sort(spla.eigsh(Kii.tocsc(), k=r.n_modes + 1, M=Mii.tocsc(), sigma=0, which="LM")[0])
    assert np.allclose(np.sqrt(w2[:-1]) / (2 * np.pi), r.mode_frequencies, rtol=1e-8)
    assert np.sqrt(w2[-1]) / (2 * np.pi) > r.cutoff  # the first mode left out is above the cutoff


def _receptance(model, dofs, f_hz):
    w = 2 * np.pi * f_hz
    D = (model.K - w**2 * model.M + 1j * w * model.C).tocsc()
    rhs = np.zeros((model.n_dofs, len(dofs)), dtype=complex)
    rhs[dofs, np.arange(len(dofs))] = 1.0
    return spla.spsolve(D, rhs)[dofs] if len(dofs) > 1 else spla.spsolve(D, rhs[:, 0])[dofs]


def test_reduced_receptance_converges_with_the_mode_count(model):
    """At a frequency of interest, the error of the reduced receptance falls as the cutoff rises."""
    dofs = np.array([model.names["pad_x"], model.contact.dofs_b[2, 0], model.contact.dofs_a[2, 1]])
    f = 2.0e5  # near the first fixed-interface modes of this small model (226 kHz, ...)
    exact = _receptance(model, dofs, f)
    errors = []
    for f_max in (0.0, f, 4 * f):  # Guyan, then the criterion (modes up to 2 f_max) with f_max = f and 4 f
        r = craig_bampton(model, f_max)
        w = 2 * np.pi * f
        D = r.K - w**2 * r.M + 1j * w * r.C
        j = np.searchsorted(r.boundary, dofs)
        G = np.linalg.inv(D)[np.ix_(j, j)]
        errors.append(np.abs(G - exact).max() / np.abs(exact).max())
    assert errors[1] < errors[0] and errors[2] < errors[1]
    assert errors[0] > 1e-2 and errors[2] < 1e-4


def test_condensation_on_contact_coordinates(model):
    r = craig_bampton(model, 1.0e5)
    cond = ContactCondensation(r)
    nc = model.n_pairs
    # k >= 1: the Schur complement is the inverse of the contact receptance B D^-1 B^T
    B = r.contact.relative_map(r.size).toarray()
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
    B = r.contact.relative_map(r.size).toarray()
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


def test_interior_singular_structure_is_reported():
    from fretwear.interface.structure import ContactPairs, InterfaceModel

    K = np.diag([2.0, 2.0, 3.0, 3.0, 0.0])  # DOF 4 is held by nothing
    pairs = ContactPairs(dofs_a=[[0, 1]], dofs_b=[[2, 3]], normal=[[0.0, 1.0]], area=[1.0], mu=0.5)
    floating = InterfaceModel(M=np.eye(5), K=K, contact=pairs)
    with pytest.raises(ValueError, match="interior stiffness K_ii .* is singular"):
        craig_bampton(floating, 0.0)
