"""The paper's 2-DOF example (Salles et al., section 3, Fig. 4) as a one-pair contact interface.

Mass 1 (``x1``) is excited and rubs on mass 2 (``x2``) through one node pair;
a third DOF ``y`` presses the pair closed with the normal load ``F_N`` through
a spring of stiffness ``k_n``. Wear opens the pair's gap, ``y`` follows and
the spring unloads: ``F_N(w) = k_n (u0 - w)`` with ``u0 = F_N / k_n``, the
paper's normal-load relaxation (eq. 30). With the load held constant the
pair's coupled DLFT law (eq. 17-23) is fretwear's single friction contact
(:func:`fretwear.paper_model`), to round-off (tests).
"""

from __future__ import annotations

import numpy as np

from ..model import ContactPairs, Model, paper_model

__all__ = ["paper_interface"]


def paper_interface(fex: float = 10.0, mu: float = 1.0, normal_load: float = 10.0, kn: float = 1e7) -> Model:
    """The paper's 2-DOF model as a :class:`~fretwear.model.Model` with one contact pair.

    Parameters
    ----------
    fex : float
        Excitation amplitude on mass 1 (N).
    mu : float
        Friction coefficient, >= 0.
    normal_load : float
        Initial normal load ``F_N0`` (N), > 0.
    kn : float
        Normal stiffness of the pressing spring (N/m), > 0: ``u0 = F_N0 / k_n``.

    Returns
    -------
    Model
        DOFs ``x1``, ``x2`` (the paper's masses and springs) and ``y`` (1 kg, stiffness ``k_n``);
        the pair has unit area, so its pressure is the normal force (N).
    """
    if not (np.isfinite(kn) and kn > 0):
        raise ValueError(f"kn must be a finite normal stiffness > 0 (N/m), got {kn!r}")
    pm = paper_model(fex=fex, mu=mu, normal_load=normal_load, kn=kn)
    pairs = ContactPairs(dofs_a=[[1, -1]], dofs_b=[[0, 2]], normal=[[0.0, 1.0]], area=[1.0], mu=mu)
    return Model(
        M=np.diag([pm.M[0, 0], pm.M[1, 1], 1.0]),
        C=np.diag([pm.C[0, 0], pm.C[1, 1], 1.0]),
        K=np.diag([pm.K[0, 0], pm.K[1, 1], kn]),
        pairs=pairs,
        force_static=[0.0, 0.0, -normal_load],
        force_cos=[fex, 0.0, 0.0],
        names={"x1": 0, "x2": 1, "y": 2},
        info={"normal_load": normal_load, "mu": mu, "kn": kn, "u0": normal_load / kn},
    )
