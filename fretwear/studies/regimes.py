"""Stick/slip regimes over frequency x load ratio ``r = F_ex / (mu F_N)`` (paper section 2.1)."""

from __future__ import annotations

import numpy as np

from ..hbm.continuation import sweep
from ..hbm.periodic import Problem
from ..model import SLIP, Model

__all__ = ["stick_limit", "regime_map"]


def stick_limit(model: Model, frequencies, harmonics: int = 1) -> np.ndarray:
    """Largest load ratio ``r = F_ex / (mu F_N)`` that keeps every contact stuck, per frequency (Hz).

    Exact: the linear stuck solution at load factor ``s`` needs the stick force
    ``s * Lambda_stuck``; it stays in the friction cone while ``s <= 1 / stick_ratio``,
    i.e. while ``r <= model.load_ratio / stick_ratio``. ``inf`` where no friction
    contact is active. Does not depend on the model's ``F_ex``.
    """
    out = []
    for f in np.atleast_1d(np.asarray(frequencies, dtype=float)):
        p = Problem(model, 2 * np.pi * f, harmonics)
        out.append(np.inf if p.n_active == 0 else model.load_ratio / p.stick_ratio())
    return np.array(out)


def regime_map(model: Model, frequencies, ratios, harmonics: int = 7) -> dict[str, np.ndarray]:
    """Stick/slip regime over frequency (Hz) x load ratio ``r = F_ex / (mu F_N)``.

    The model's forcing is scaled to each ratio of ``ratios`` (its own ``F_ex``
    does not matter: by homogeneity of Coulomb's law, ``r`` alone sets the
    regime). Returns, shape (len(ratios), len(frequencies)), the fraction of the
    period spent slipping by the first friction contact, its sliding distance
    per period (m) and the first-harmonic amplitude of DOF 1 (m) at that
    forcing, and per frequency the exact stick boundary :func:`~fretwear.studies.stick_limit`.
    """
    frequencies = np.asarray(frequencies, dtype=float)
    ratios = np.asarray(ratios, dtype=float)
    r0 = model.load_ratio
    if not (np.isfinite(r0) and r0 > 0):
        raise ValueError(f"regime_map needs a forced model whose contact can stick (0 < r < inf), got {r0}")
    slip = np.zeros((len(ratios), len(frequencies)))
    slid = np.zeros_like(slip)
    amp = np.zeros_like(slip)
    for i, r in enumerate(ratios):
        sw = sweep(model.scaled(r / r0), 2 * np.pi * frequencies, harmonics)
        for j, sol in enumerate(sw.solutions):
            slip[i, j] = np.mean(sol.state[0] == SLIP)
            slid[i, j] = sol.sliding_distance[0]
            amp[i, j] = sol.amplitude[0]
    return {"slip_fraction": slip, "sliding_distance": slid, "amplitude": amp,
            "stick_limit": stick_limit(model, frequencies)}  # fmt: skip
