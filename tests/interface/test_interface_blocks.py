"""The interface's linear part by harmonic blocks (issue 25, scale): ``Z x`` and the residual without the
dense ``Z``, against the dense path."""

import numpy as np
import pytest

from fretwear.hbm.newton import block_matvec
from fretwear.hbm.structured import dense_from_blocks, harmonic_blocks
from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.sphere import sphere_dynamic_model
from fretwear.model import craig_bampton


def _problems(cond: ContactCondensation, omega: float, nh: int) -> tuple[InterfaceProblem, InterfaceProblem]:
    dense = InterfaceProblem(cond, omega, harmonics=nh, linear="dense")
    return dense, InterfaceProblem(cond, omega, harmonics=nh, xref=dense.xref, eps=dense.eps)


@pytest.fixture(scope="module", params=["cylinder", "sphere"])
def pair(request):
    """The dense and the block problem of one interface: the 1-D law (cylinder), the cone (sphere)."""
    if request.param == "cylinder":
        cond = ContactCondensation(craig_bampton(cylinder_on_flat(contact_nodes=16), 5 * 50.0))
        return _problems(cond, 2 * np.pi * 50.0, 5)
    cond = ContactCondensation(sphere_dynamic_model(divisions=2, size=2.0, q_ratio=0.6))
    return _problems(cond, 2 * np.pi * 100.0, 3)


def test_block_product_is_the_dense_product(pair):
    """``Z x`` from the blocks equals the dense ``Z @ x`` for random ``x`` (to rounding)."""
    dense, blocks = pair
    rng = np.random.default_rng(3)
    for _ in range(3):
        x = rng.standard_normal(dense.size)
        ref = dense.Z @ x
        assert np.allclose(block_matvec(blocks.blocks, x), ref, rtol=0, atol=1e-12 * np.abs(ref).max())


def test_block_residual_is_the_dense_residual(pair):
    """At the start and at a perturbed state (stick, slip and separation in the period), the residual,
    its blocks and the time fields of the block path equal the dense path's."""
    dense, blocks = pair
    rng = np.random.default_rng(4)
    x0 = dense.start()
    for x in (x0, x0 + 0.3 * np.abs(x0).max() * rng.standard_normal(dense.size)):
        ref, got = dense.evaluate(x, jacobian=True), blocks.evaluate(x, jacobian=True)
        scale = np.abs(ref[0]).max()
        assert np.allclose(got[0], ref[0], rtol=0, atol=1e-10 * scale)
        for a, b in zip(got[1:], ref[1:], strict=True):
            assert np.allclose(a, b, rtol=1e-10, atol=1e-12 * max(np.abs(b).max(), 1e-300))


def test_dense_from_blocks_inverts_harmonic_blocks(pair):
    """``dense_from_blocks`` and ``harmonic_blocks`` are inverse: exactly, both ways (random blocks, the
    interface's ``Z``), and the block problem's ``Z`` is the dense problem's."""
    dense, blocks = pair
    q, H = dense.per_pair * dense.n_pairs, dense.basis.size
    Zb = np.random.default_rng(5).standard_normal(blocks.blocks.shape)
    Zb[0, q:, :] = Zb[0, :, q:] = 0.0  # not part of Z (the mean has one slot)
    assert np.array_equal(harmonic_blocks(dense_from_blocks(Zb), q, H), Zb)
    assert np.array_equal(dense_from_blocks(harmonic_blocks(dense.Z, q, H)), dense.Z)
    assert np.array_equal(blocks.Z, dense.Z)
