"""Tests of ``fretwear.wear.dynamics.observables``: the response quantities of DLFT contact forces.

Oracle: :func:`fretwear.hbm.condensation.recover` called once per response (the DOF harmonics of each
set of contact-force harmonics), whose first harmonic and exact extrema must be what ``observables``
gives from its one batched recovery of the affine map.
"""

from __future__ import annotations

import numpy as np
import pytest

import fretwear as fw
from fretwear.hbm.condensation import recover
from fretwear.hbm.harmonics import amplitude, extrema, full_synthesis
from fretwear.hbm.periodic import Problem
from fretwear.wear.dynamics import observables


@pytest.mark.parametrize(("fex", "harmonics", "f_hz"), [(10.0, 9, 0.7), (6.0, 3, 1.1), (14.0, 13, 0.45)])
def test_observables_are_the_responses_recovered_one_by_one(fex, harmonics, f_hz):
    model = fw.paper_model(fex=fex)
    problem = Problem(model, 2 * np.pi * f_hz, harmonics, None)
    lam = np.random.default_rng(harmonics).normal(scale=3.0, size=(6, problem.size))
    amp, half, rel = observables(problem, lam)
    b, nh = problem.basis, problem.basis.harmonics
    synthesis = full_synthesis(nh, 8 * nh + 8)
    for k, row in enumerate(lam):
        U = recover(model, problem.B, problem.omega, nh, b.to_full(row.reshape(problem.n_active, b.size)))
        np.testing.assert_allclose(amp[k], amplitude(U), rtol=1e-12, atol=1e-12 * np.abs(U).max())
        rows = np.concatenate([U, model.relative_map() @ U])
        hi, lo = extrema(rows, rows @ synthesis.T)
        scale = np.abs(U).max()
        np.testing.assert_allclose(half[k], ((hi - lo) / 2)[: model.n_dofs], rtol=1e-10, atol=1e-12 * scale)
        np.testing.assert_allclose(rel[k], ((hi - lo) / 2)[model.n_dofs :], rtol=1e-10, atol=1e-12 * scale)
