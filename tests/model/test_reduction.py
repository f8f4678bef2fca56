"""Craig-Bampton reduction of a model with contact pairs: a Model in, a Model out."""

import numpy as np
import pytest
import scipy.sparse.linalg as spla

from fretwear.model import ContactPairs, Model, craig_bampton


@pytest.fixture(scope="module")
def model(small_cylinder):
    return small_cylinder


def test_guyan_stiffness_is_the_exact_schur_complement(model):
    r = craig_bampton(model, 0.0)
    K = model.K.toarray()
    b, i = r.reduction.boundary, r.reduction.interior
    S = K[np.ix_(b, b)] - K[np.ix_(b, i)] @ np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    assert r.reduction.n_modes == 0
    assert np.abs(r.K - S).max() <= 1e-9 * np.abs(S).max()


def test_mode_count_follows_the_frequency_criterion(model):
    r = craig_bampton(model, 1.5e5, factor=2.0)
    assert r.reduction.cutoff == 3e5 and r.reduction.n_modes > 0
    assert np.all(r.reduction.mode_frequencies <= r.reduction.cutoff)
    Kii = model.K[r.reduction.interior][:, r.reduction.interior]
    Mii = model.M[r.reduction.interior][:, r.reduction.interior]
    w2 = np.sort(spla.eigsh(Kii.tocsc(), k=r.reduction.n_modes + 1, M=Mii.tocsc(), sigma=0, which="LM")[0])
    assert np.allclose(np.sqrt(w2[:-1]) / (2 * np.pi), r.reduction.mode_frequencies, rtol=1e-8)
    assert np.sqrt(w2[-1]) / (2 * np.pi) > r.reduction.cutoff  # the first mode left out is above the cutoff


def _receptance(model, dofs, f_hz):
    w = 2 * np.pi * f_hz
    D = (model.K - w**2 * model.M + 1j * w * model.C).tocsc()
    rhs = np.zeros((model.n_dofs, len(dofs)), dtype=complex)
    rhs[dofs, np.arange(len(dofs))] = 1.0
    return spla.spsolve(D, rhs)[dofs] if len(dofs) > 1 else spla.spsolve(D, rhs[:, 0])[dofs]


def test_reduced_receptance_converges_with_the_mode_count(model):
    """At a frequency of interest, the error of the reduced receptance falls as the cutoff rises."""
    dofs = np.array([model.names["pad_x"], model.pairs.dofs_b[2, 0], model.pairs.dofs_a[2, 1]])
    f = 2.0e5  # near the first fixed-interface modes of this small model (226 kHz, ...)
    exact = _receptance(model, dofs, f)
    errors = []
    for f_max in (0.0, f, 4 * f):  # Guyan, then the criterion (modes up to 2 f_max) with f_max = f and 4 f
        r = craig_bampton(model, f_max)
        w = 2 * np.pi * f
        D = r.K - w**2 * r.M + 1j * w * r.C
        j = np.searchsorted(r.reduction.boundary, dofs)
        G = np.linalg.inv(D)[np.ix_(j, j)]
        errors.append(np.abs(G - exact).max() / np.abs(exact).max())
    assert errors[1] < errors[0] and errors[2] < errors[1]
    assert errors[0] > 1e-2 and errors[2] < 1e-4


def test_interior_singular_structure_is_reported():
    K = np.diag([2.0, 2.0, 3.0, 3.0, 0.0])  # DOF 4 is held by nothing
    pairs = ContactPairs(dofs_a=[[0, 1]], dofs_b=[[2, 3]], normal=[[0.0, 1.0]], area=[1.0], mu=0.5)
    floating = Model(M=np.eye(5), C=None, K=K, pairs=pairs)
    with pytest.raises(ValueError, match="interior stiffness K_ii .* is singular"):
        craig_bampton(floating, 0.0)


def test_reduced_model_is_a_model_that_recovers_the_full_one(model):
    """The reduction returns a Model: dense, pairs renumbered, names of boundary DOFs, and the way back."""
    r = craig_bampton(model, 1.0e5)
    assert isinstance(r, Model) and not r.sparse and r.reduction.full is model
    assert r.n_pairs == model.n_pairs and r.info == model.info
    assert model.dof("pad_x") == r.reduction.boundary[r.dof("pad_x")]
    # expanded coordinates keep the boundary DOFs and the contact coordinates of every pair
    rng = np.random.default_rng(0)
    coords = rng.standard_normal(r.n_dofs)
    full = r.reduction.expand(coords)
    assert full[r.reduction.boundary] == pytest.approx(coords[: len(r.reduction.boundary)])
    assert np.allclose(r.pairs.relative_map(r.n_dofs) @ coords, model.pairs.relative_map(model.n_dofs) @ full)
    for d in (int(r.reduction.interior[3]), int(r.reduction.boundary[2])):
        assert r.reduction.coordinate(d) @ coords == pytest.approx(full[d], rel=1e-12)


def test_reduction_needs_contact_pairs():
    with pytest.raises(ValueError, match="model must be a Model with contact pairs"):
        craig_bampton(Model(np.eye(2), None, np.eye(2)), 0.0)
