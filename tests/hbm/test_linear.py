"""Linear stuck and open FRFs against closed forms."""

import numpy as np
import pytest

from fretwear import paper_model
from fretwear.hbm.linear import linear_frf


def test_paper_model_closed_forms():
    model = paper_model(fex=10)
    w = 2 * np.pi * np.array([0.3, 0.7, 1.3])
    k1, k2 = np.pi**2, 7 * np.pi**2
    c1, c2 = np.diag(model.C)
    D1, D2 = k1 - w**2 + 1j * c1 * w, k2 - w**2 + 1j * c2 * w
    stuck = linear_frf(model, w, "stuck")
    np.testing.assert_allclose(stuck[:, 0], 10 / (D1 + D2), rtol=1e-12)  # x1 = x2, masses and springs add
    np.testing.assert_allclose(stuck[:, 1], stuck[:, 0], rtol=1e-12)
    opened = linear_frf(model, w, "open")
    np.testing.assert_allclose(opened[:, 0], 10 / D1, rtol=1e-12)
    np.testing.assert_allclose(opened[:, 1], 0, atol=1e-15)


@pytest.mark.parametrize("omegas,state,match", [([0.0], "stuck", "omegas"), ([np.nan], "open", "omegas"),
                                                ([1.0], "sliding", "state")])  # fmt: skip
def test_bad_input(omegas, state, match):
    with pytest.raises(ValueError, match=match):
        linear_frf(paper_model(), omegas, state)
