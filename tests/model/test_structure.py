"""Tests of fretwear.model: validation, the paper's 2-DOF model, contact laws and derived models."""

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp
from hypothesis import given
from hypothesis import strategies as st

import fretwear as fw
from fretwear import ContactPairs, FrictionContact, Model, NormalContact, jenkins_oscillator, paper_model

finite = st.floats(allow_nan=False, allow_infinity=False)


def two_dof(**changes) -> Model:
    """A valid 2-DOF model, with keyword ``changes`` to the constructor arguments."""
    args = dict(
        M=np.eye(2),
        C=0.01 * np.eye(2),
        K=np.array([[2.0, -1.0], [-1.0, 2.0]]),
        force_cos=np.array([1.0, 0.0]),
    )
    args.update(changes)
    return Model(**args)


# -- validation -----------------------------------------------------------------
@pytest.mark.parametrize(
    ("changes", "match"),
    [
        (dict(M=np.ones((2, 3))), r"^M must be a non-empty square matrix"),
        (dict(K=np.ones(2)), r"^K must be a non-empty square matrix"),
        (dict(M=np.zeros((0, 0))), r"^M must be a non-empty square matrix"),
        (dict(K=np.eye(3)), r"^K must have shape \(2, 2\)"),
        (dict(C=np.eye(3)), r"^C must have shape \(2, 2\)"),
        (dict(M=np.diag([1.0, -1.0])), r"^M must be positive semi-definite"),
        (dict(K=np.diag([1.0, -0.5])), r"^K must be positive semi-definite"),
        (dict(K=np.array([[1.0, 2.0], [2.0, 1.0]])), r"^K must be positive semi-definite"),
        (dict(C=np.diag([0.1, -0.1])), r"^C must be positive semi-definite"),
        (dict(K=np.array([[2.0, -1.0], [-0.9, 2.0]])), r"^K must be symmetric"),
        (dict(M=np.array([[1.0, np.nan], [np.nan, 1.0]])), r"^M must contain finite numbers"),
        (dict(C=np.diag([np.inf, 0.0])), r"^C must contain finite numbers"),
        (dict(force_cos=np.ones(3)), r"^force_cos must have shape \(2,\), got \(3,\)"),
        (dict(force_sin=np.ones(1)), r"^force_sin must have shape \(2,\), got \(1,\)"),
        (dict(force_static=np.array([0.0, np.nan])), r"^force_static must contain finite numbers only"),
        (dict(friction=(FrictionContact(2, None, 1.0, 1e7, 1e-6),)), r"^friction\[0\]\.dof must be a DOF"),
        (dict(friction=(FrictionContact(-1, None, 1.0, 1e7, 1e-6),)), r"^friction\[0\]\.dof must be a DOF"),
        (dict(friction=(FrictionContact(0, 1.0, 1.0, 1e7, 1e-6),)), r"^friction\[0\]\.other must be a DOF"),
        (dict(normal=(NormalContact(0, None), NormalContact(0, 5))), r"^normal\[1\]\.other must be a DOF"),
        (
            dict(friction=(FrictionContact(1, 1, 1.0, 1e7, 1e-6),)),
            r"^friction\[0\]: dof and other must differ",
        ),
        (dict(normal=(NormalContact(0, 0),)), r"^normal\[0\]: dof and other must differ"),
    ],
)
def test_model_rejects_invalid_input(changes, match):
    with pytest.raises(ValueError, match=match):
        two_dof(**changes)


@pytest.mark.parametrize(
    ("make", "match"),
    [
        (lambda: FrictionContact(0, None, -0.1, 1e7, 1e-6), r"^mu must be >= 0"),
        (lambda: FrictionContact(0, None, np.nan, 1e7, 1e-6), r"^mu must be a finite number"),
        (lambda: FrictionContact(0, None, 1.0, 0.0, 1e-6), r"^kn must be > 0"),
        (lambda: FrictionContact(0, None, 1.0, -1e7, 1e-6), r"^kn must be > 0"),
        (lambda: FrictionContact(0, None, 1.0, 1e7, -1e-6), r"^u0 must be >= 0"),
        (lambda: FrictionContact.from_normal_load(0, None, 1.0, -10.0), r"^normal_load must be >= 0"),
        (lambda: FrictionContact.from_normal_load(0, None, 1.0, 10.0, kn=0.0), r"^kn must be > 0"),
        (lambda: NormalContact(0, None, np.inf), r"^gap must be a finite number"),
        (lambda: paper_model(fex=np.nan), r"^fex must be a finite number"),
        (lambda: paper_model(damping_ratio=-1e-3), r"^damping_ratio must be >= 0"),
        (lambda: paper_model(mu=-1.0), r"^mu must be >= 0"),
        (lambda: paper_model(normal_load=-1.0), r"^normal_load must be >= 0"),
    ],
)
def test_contacts_reject_invalid_parameters(make, match):
    with pytest.raises(ValueError, match=match):
        make()


def test_model_arrays_are_read_only_copies():
    K = np.array([[2.0, -1.0], [-1.0, 2.0]])
    model = two_dof(K=K)
    K[0, 0] = 100.0
    assert model.K[0, 0] == 2.0
    with pytest.raises(ValueError):
        model.K[0, 0] = 3.0
    with pytest.raises(ValueError):
        model.force_sin[0] = 3.0


def test_model_defaults_and_massless_dofs():
    model = jenkins_oscillator()
    assert model.n_dofs == 2
    np.testing.assert_array_equal(model.force_sin, [0.0, 0.0])
    np.testing.assert_array_equal(model.force_static, [0.0, 0.0])
    assert model.normal == ()
    assert model.M[1, 1] == 0.0  # singular mass matrix is allowed


# -- the 2-DOF model of the paper (section 2.1) ------------------------------------
def test_paper_model_values():
    model = paper_model()
    k1, k2 = np.pi**2, 7 * np.pi**2
    np.testing.assert_array_equal(model.M, np.eye(2))
    np.testing.assert_allclose(model.K, np.diag([k1, k2]), rtol=1e-15)
    np.testing.assert_allclose(
        model.C, np.diag([2 * 0.001 * np.sqrt(k1), 2 * 0.001 * np.sqrt(k2)]), rtol=1e-15
    )
    np.testing.assert_array_equal(model.force_cos, [10.0, 0.0])
    (contact,) = model.friction
    assert (contact.dof, contact.other, contact.mu, contact.kn) == (0, 1, 1.0, 1e7)
    assert contact.u0 == pytest.approx(1e-6, rel=1e-15)  # 1e-3 mm
    assert contact.normal_load() == pytest.approx(10.0, rel=1e-15)
    assert contact.slip_force() == pytest.approx(10.0, rel=1e-15)
    np.testing.assert_allclose(model.normal_loads(), [10.0], rtol=1e-15)


def natural_frequencies(K: np.ndarray, M: np.ndarray) -> np.ndarray:
    """Undamped natural frequencies (Hz) of ``K, M``, sorted."""
    omega2 = np.linalg.eigvals(np.linalg.solve(M, K)).real
    return np.sort(np.sqrt(omega2)) / (2 * np.pi)


def test_paper_model_linear_modes():
    model = paper_model()
    # Stuck contact: x1 = x2, i.e. u restricted to the null space of B.
    B = model.relative_map()
    T = np.linalg.svd(B)[2][B.shape[0] :].T  # basis of ker B, shape (2, 1)
    stuck = natural_frequencies(T.T @ model.K @ T, T.T @ model.M @ T)
    np.testing.assert_allclose(stuck, [1.0], rtol=1e-12)
    # Contact slipping freely (no friction force): mass 1 alone.
    np.testing.assert_allclose(natural_frequencies(model.K[:1, :1], model.M[:1, :1]), [0.5], rtol=1e-12)
    np.testing.assert_allclose(natural_frequencies(model.K, model.M), [0.5, np.sqrt(7) / 2], rtol=1e-12)


def test_paper_model_parameters():
    model = paper_model(fex=6.0, mu=0.5, normal_load=20.0, kn=2e7, damping_ratio=0.0)
    np.testing.assert_array_equal(model.force_cos, [6.0, 0.0])
    np.testing.assert_array_equal(model.C, np.zeros((2, 2)))
    (contact,) = model.friction
    assert (contact.mu, contact.kn) == (0.5, 2e7)
    assert contact.u0 == pytest.approx(1e-6, rel=1e-15)
    assert contact.slip_force() == pytest.approx(10.0, rel=1e-15)


def test_jenkins_oscillator_values():
    model = jenkins_oscillator(m=2.0, c=0.1, k=3.0, kt=5.0, slip_force=0.4, force=0.2)
    np.testing.assert_array_equal(model.M, np.diag([2.0, 0.0]))
    np.testing.assert_array_equal(model.C, np.diag([0.1, 0.0]))
    np.testing.assert_array_equal(model.K, [[8.0, -5.0], [-5.0, 5.0]])
    np.testing.assert_array_equal(model.force_cos, [0.2, 0.0])
    (contact,) = model.friction
    assert (contact.dof, contact.other) == (1, None)
    assert contact.slip_force() == pytest.approx(0.4, rel=1e-15)


# -- contact laws -------------------------------------------------------------------
def test_normal_load_clips_at_zero_when_worn_through():
    contact = paper_model().friction[0]
    assert contact.normal_load(0.5e-6) == pytest.approx(5.0, rel=1e-12)
    assert contact.normal_load(1e-6) == 0.0
    assert contact.normal_load(3e-6) == 0.0
    assert contact.slip_force(3e-6) == 0.0
    np.testing.assert_array_equal(paper_model().normal_loads([2e-6]), [0.0])


def test_normal_loads_checks_shape():
    with pytest.raises(ValueError, match="wear must have one entry per friction contact"):
        paper_model().normal_loads([0.0, 0.0])


@given(
    kn=st.floats(1e-3, 1e12),
    u0=st.floats(0.0, 1e-2),
    wear=st.lists(st.floats(0.0, 2e-2), min_size=2, max_size=2),
)
def test_normal_load_law(kn, u0, wear):
    contact = FrictionContact(0, None, 0.7, kn, u0)
    w1, w2 = sorted(wear)
    f1, f2 = contact.normal_load(w1), contact.normal_load(w2)
    assert f1 >= f2 >= 0.0  # non-increasing in the wear depth, never tensile
    for w, f in ((w1, f1), (w2, f2)):
        assert f == (kn * (u0 - w) if w <= u0 else 0.0)
        assert contact.slip_force(w) == 0.7 * f


@given(normal_load=st.floats(0.0, 1e6), kn=st.floats(1.0, 1e12))
def test_from_normal_load_round_trip(normal_load, kn):
    contact = FrictionContact.from_normal_load(0, None, 1.0, normal_load, kn)
    assert contact.kn == kn
    assert contact.normal_load() == pytest.approx(normal_load, rel=1e-14, abs=1e-300)


# -- maps and symmetry ------------------------------------------------------------
def test_relative_map():
    np.testing.assert_array_equal(paper_model().relative_map(), [[1.0, -1.0]])
    np.testing.assert_array_equal(jenkins_oscillator().relative_map(), [[0.0, 1.0]])
    model = Model(
        M=np.eye(3),
        C=np.zeros((3, 3)),
        K=np.eye(3),
        force_cos=np.ones(3),
        friction=(FrictionContact(2, 0, 1.0, 1e7, 0.0),),
        normal=(NormalContact(1, None, 0.1), NormalContact(0, 2)),
    )
    assert model.contacts == model.friction + model.normal
    B = model.relative_map()
    np.testing.assert_array_equal(B, [[-1.0, 0.0, 1.0], [0.0, 1.0, 0.0], [1.0, 0.0, -1.0]])
    u = np.array([0.3, -0.2, 0.5])
    np.testing.assert_allclose(B @ u, [0.5 - 0.3, -0.2, 0.3 - 0.5])
    np.testing.assert_array_equal(model.relative_map(model.normal), B[1:])
    assert model.relative_map(()).shape == (0, 3)


def test_half_wave_symmetric():
    assert paper_model().half_wave_symmetric
    assert jenkins_oscillator().half_wave_symmetric
    assert two_dof(force_sin=np.array([0.0, 1.0])).half_wave_symmetric
    assert not two_dof(force_static=np.array([0.0, 1.0])).half_wave_symmetric
    assert not two_dof(normal=(NormalContact(0, None, 1e-3),)).half_wave_symmetric


# -- derived models -----------------------------------------------------------------
def test_scaled():
    model = two_dof(force_sin=np.array([0.5, 0.0]), force_static=np.array([0.0, -2.0]))
    half = model.scaled(0.5)
    np.testing.assert_array_equal(half.force_cos, [0.5, 0.0])
    np.testing.assert_array_equal(half.force_sin, [0.25, 0.0])
    np.testing.assert_array_equal(half.force_static, [0.0, -1.0])
    for name in ("M", "C", "K"):
        np.testing.assert_array_equal(getattr(half, name), getattr(model, name))
    np.testing.assert_array_equal(model.force_cos, [1.0, 0.0])  # the original is unchanged
    np.testing.assert_array_equal(model.scaled().force_cos, model.force_cos)
    with pytest.raises(ValueError, match="force must be a finite number"):
        model.scaled(np.inf)


@given(factor=st.floats(-1e3, 1e3))
def test_scaled_scales_every_force_only(factor):
    model = two_dof(force_sin=np.array([0.5, 0.0]), force_static=np.array([0.0, -2.0]))
    scaled = model.scaled(factor)
    for name in ("force_cos", "force_sin", "force_static"):
        np.testing.assert_array_equal(getattr(scaled, name), factor * getattr(model, name))
    for name in ("M", "C", "K"):
        np.testing.assert_array_equal(getattr(scaled, name), getattr(model, name))
    assert scaled.friction == model.friction and scaled.normal == model.normal


def test_with_friction():
    model = dataclasses.replace(
        paper_model(),
        friction=(FrictionContact(0, 1, 1.0, 1e7, 1e-6), FrictionContact(1, None, 0.3, 1e6, 2e-6)),
    )
    changed = model.with_friction(mu=0.5)
    assert [c.mu for c in changed.friction] == [0.5, 0.5]
    assert [c.u0 for c in changed.friction] == [1e-6, 2e-6]
    assert [c.mu for c in model.friction] == [1.0, 0.3]  # the original is unchanged
    np.testing.assert_array_equal(changed.K, model.K)
    assert changed.with_friction().friction == changed.friction
    with pytest.raises(ValueError, match="mu must be >= 0"):
        model.with_friction(mu=-1.0)
    with pytest.raises(ValueError, match=r"friction\[0\]\.dof must be a DOF"):
        model.with_friction(dof=7)


# -- one model type: pairs, sparse matrices, names ------------------------------
PAIR = dict(dofs_a=[[1, -1]], dofs_b=[[0, 2]], normal=[[0.0, 1.0]], area=[1.0], mu=0.5)


def test_sparse_matrices_stay_sparse_with_pairs_and_turn_dense_with_1d_contacts():
    K = sp.csr_matrix(np.diag([1.0, 2.0, 3.0]))
    with_pairs = Model(sp.eye(3), None, K, pairs=ContactPairs(**PAIR))
    assert with_pairs.sparse and sp.issparse(with_pairs.C) and with_pairs.C.nnz == 0
    assert with_pairs.n_pairs == 1 and not with_pairs.half_wave_symmetric
    with_friction = Model(
        sp.eye(3), None, K, force_cos=[1.0, 0, 0], friction=(FrictionContact(0, 1, 1, 1, 1),)
    )
    assert not with_friction.sparse and isinstance(with_friction.K, np.ndarray)
    np.testing.assert_array_equal(with_friction.K, K.toarray())
    np.testing.assert_array_equal(with_friction.C, np.zeros((3, 3)))


@pytest.mark.parametrize(
    ("changes", "match"),
    [
        (dict(friction=(FrictionContact(0, 1, 1.0, 1.0, 1.0),)), "pairs cannot be combined with friction"),
        (
            dict(pairs=ContactPairs(**{**PAIR, "dofs_b": [[0, 3]]})),
            r"pairs\.dofs_b\[0\] = \[0, 3\] is out of",
        ),
        (dict(names={"y": 3}), r"names\['y'\] = 3 is out of range: DOFs are 0 to 2"),
        (dict(K=sp.csr_matrix(np.array([[1.0, 1.0, 0], [0, 1, 0], [0, 0, 1]]))), "K must be symmetric"),
        (dict(M=sp.diags([1.0, -1.0, 1.0])), "M must have a non-negative diagonal"),
        (dict(pairs="pair"), "pairs must be a ContactPairs, got str"),
    ],
)
def test_pair_model_validation_names_the_parameter(changes, match):
    args = dict(M=np.eye(3), C=None, K=np.eye(3), pairs=ContactPairs(**PAIR))
    with pytest.raises(ValueError, match=match):
        Model(**{**args, **changes})


def test_named_dofs():
    model = Model(np.eye(3), None, np.eye(3), pairs=ContactPairs(**PAIR), names={"x1": 0, "y": 2})
    assert model.dof("y") == 2 and model.dof(1) == 1
    with pytest.raises(ValueError, match=r"unknown DOF name 'z'; named DOFs are \['x1', 'y'\]"):
        model.dof("z")
    with pytest.raises(ValueError, match=r"DOF must be a name or an index in \[0, 2\], got 3"):
        model.dof(3)


def _ring(n: int, m: float = 1.0, k: float = 1.0, kc: float = 0.3, c: float = 0.01, friction: bool = False):
    """``n`` masses on springs ``k`` to ground, neighbours coupled by ``kc`` in a ring (cyclic symmetry)."""
    K = (k + 2 * kc) * np.eye(n) - kc * (np.roll(np.eye(n), 1, axis=1) + np.roll(np.eye(n), -1, axis=1))
    contacts = (
        tuple(FrictionContact(dof=j, other=None, mu=1.0, kn=1.0, u0=0.05) for j in range(n))
        if friction
        else ()
    )
    return Model(M=m * np.eye(n), C=c * np.eye(n), K=K, force_cos=np.zeros(n), friction=contacts)


@pytest.mark.parametrize("engine_order", [0, 1, 2, 5, -1])
def test_a_travelling_wave_drives_a_ring_in_its_nodal_diameter_mode_exactly(engine_order):
    """Open contacts: mass j answers A e^{-i phi_j} / (k + 2 kc (1 - cos theta) - omega^2 m + i omega c)."""
    n, omega, amplitude = 6, 1.1, 0.7
    model = _ring(n).travelling_wave(np.arange(n), engine_order, amplitude)
    phase = 2 * np.pi * engine_order * np.arange(n) / n
    theta = 2 * np.pi * engine_order / n
    expected = (
        amplitude * np.exp(-1j * phase) / (1.0 + 2 * 0.3 * (1 - np.cos(theta)) - omega**2 + 1j * omega * 0.01)
    )
    U = fw.linear_frf(model, [omega], state="open")[0]
    assert np.allclose(U, expected, rtol=1e-12, atol=0)


def test_under_a_travelling_wave_every_sector_of_a_cyclic_structure_with_friction_repeats_the_first():
    """Cyclic symmetry: sector j's periodic response is sector 0's delayed by engine_order j / N periods.

    The DLFT time grid must hold that delay (samples a multiple of N): with 128 samples the symmetry holds
    only to the sampling error (0.9 % here), with 40 N it holds to the Newton tolerance.
    """
    n, engine_order, omega = 5, 2, 1.0
    model = _ring(n, friction=True).travelling_wave(np.arange(n), engine_order, 0.1)
    sol = fw.solve_periodic(model, omega, harmonics=5, samples=40 * n)
    assert sol.converged
    first = sol.dof_harmonics[:, 1] - 1j * sol.dof_harmonics[:, 2]  # cos - i sin: Re(X e^{i omega t})
    ratio = first / first[0]
    phase = 2 * np.pi * engine_order * np.arange(n) / n
    assert np.allclose(ratio, np.exp(-1j * phase), rtol=0, atol=1e-9)
    assert sol.path != "linear-stuck"  # the friction contacts slip: the nonlinear case


def test_a_travelling_wave_names_its_bad_inputs():
    model = _ring(4)
    with pytest.raises(ValueError, match="groups"):
        model.travelling_wave([0, 1, 4], 1)
    with pytest.raises(ValueError, match="groups"):
        model.travelling_wave([[0, 1], [1, 2]], 1)
    with pytest.raises(ValueError, match="engine_order"):
        model.travelling_wave([0, 1], 1.5)
    with pytest.raises(ValueError, match="amplitude"):
        model.travelling_wave([0, 1], 1, np.nan)
