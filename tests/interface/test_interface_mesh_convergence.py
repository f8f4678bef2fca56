"""Mesh convergence of the worn area of the benchmark (8, 16, 32 contact pairs)."""

import numpy as np
import pytest

from fretwear.interface.fe import cylinder_on_flat
from fretwear.interface.periodic import InterfaceProblem
from fretwear.interface.reduction import ContactCondensation
from fretwear.interface.wear import wear_interface
from fretwear.model import craig_bampton

F_HZ, NH, KW, CYCLES = 50.0, 5, 1e-14, 3e5


@pytest.mark.slow  # the 32-pair history: 15-55 s on a loaded 2-core machine
def test_worn_area_converges_with_the_mesh():
    """Partial slip (Q0 = 0.5 mu P), worn area per unit length after 3e5 cycles on three meshes.

    Measured: 4.27e-11, 3.22e-11, 2.77e-11 m^2/m: successive differences 1.05e-11 then 4.5e-12 (ratio
    2.3 per halving of the spacing: first order, the Archard integrand has a kink at the stick-zone edge).
    """
    area = []
    for nodes in (8, 16, 32):
        model = cylinder_on_flat(contact_nodes=nodes, q_ratio=0.5)
        cond = ContactCondensation(craig_bampton(model, NH * F_HZ))
        hist = wear_interface(InterfaceProblem(cond, 2 * np.pi * F_HZ, harmonics=NH), KW, CYCLES, rtol=3e-2)
        assert hist.converged
        area.append(hist.worn_area[-1])
    d1, d2 = abs(area[1] - area[0]), abs(area[2] - area[1])
    assert d2 < 0.6 * d1  # errors shrink (first order or better)
    assert d2 < 0.2 * area[2]
