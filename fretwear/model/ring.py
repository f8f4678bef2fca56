"""The lumped bladed disk with a friction ring damper: pyHarm's tutorial 006 (Laxalde et al. 2007).

``fretwear.bladed_disk(contacts="ring", ...)`` builds it. The disk is
:func:`fretwear.bladed_disk`'s (:class:`~fretwear.model.DiskSector`:
``N`` sectors, disk, blade-root and blade-tip masses, tuned). Under it a ring
of ``N`` sectors, one DOF each, as in pyHarm's tutorial 006 "Lumped bladed disk
study with a ring damper" (QUICKguils/pyHarm, ``Tutorials/``):

* ring sector ``i``: mass ``mr`` (kg) on a spring ``kr_ground = 1e-3 kr`` to
  the ground (the tutorial's spring against the ring's rigid-body motion) and a
  spring ``kr`` to ring sector ``i + 1`` (the ring closes);
* a Jenkins contact (tangential stiffness ``kt = 10 kr`` in series with
  Coulomb friction ``mu``) between ring sector ``i`` and the disk mass of
  sector ``i``: friction contact ``i``, relative coordinate ``u_ring,i -
  u_disk,i``. It is not in ``K``; with it stuck it is the tutorial's linear
  spring ``kr * 1e1``;
* its normal load is the ring's centrifugal load ``N = mr R Omega^2`` (``R``
  the ring's radius, ``Omega`` the rotation speed). The tutorial holds
  ``Omega`` fixed over its whole sweep, at half the disk's first one-nodal-
  diameter frequency (``Omega = pi f_1``, ``f_1 = 169.344 Hz``, ``N = 56.6 N``),
  not at a multiple of the excitation frequency: the model does not depend on
  the excitation frequency and is built once per sweep.

Damping: modal on the disk (``C = M Phi diag(2 zeta omega_r) Phi^T M`` over the
disk's mass-normalised modes, as :func:`fretwear.bladed_disk`), none on the
ring (the tutorial's ring has ``C = 0``). The tutorial's own disk damping,
``Phi diag(2 zeta omega_r) Phi^T`` with the unit-norm eigenvectors of ``M^-1
K`` from ``numpy.linalg.eig``, is not modal damping (``Phi`` is not
mass-normalised) and depends, in each pair of double modes, on the basis
LAPACK returns; it is not reproduced.

Excitation as the tutorial's: blade tip ``i`` is forced by ``fex cos(omega t -
2 pi EO i / N)`` (pyHarm's ``GOForcing`` with the phase ``phi = 2 pi n_diam i /
N``, amplitude 1 N). Its sweep runs over 0.95 to 1.1 times the one-nodal-diameter frequency, so the
default engine order is 1 (inferred from that band).
"""

from __future__ import annotations

from dataclasses import asdict

import numpy as np
import scipy.linalg as sl

from .disk import DiskSector, modal_damping
from .structure import FrictionContact, Model, _finite

__all__ = ["ring_damper_disk", "tutorial_rotation_speed"]

#: the tutorial's ring: sector mass (kg), radius (m), ring spring (N/m), friction coefficient (-)
TUTORIAL_RING = {"mr": 2e-3, "radius": 0.1, "kr": 1e7, "mu": 0.1}


def tutorial_rotation_speed(sector: DiskSector | None = None) -> float:
    """The tutorial's rotation speed ``Omega = 2 pi f_1 / 2`` (rad/s), ``f_1`` the disk's first
    one-nodal-diameter frequency (169.344 Hz for the default disk): 531.99 rad/s."""
    sector = DiskSector() if sector is None else sector
    return float(2 * np.pi * sector.frequencies(1)[0] / 2.0)


def ring_damper_disk(
    sectors: int = 24,
    *,
    rotation_speed: float | None = None,
    engine_order: int = 1,
    fex: float = 1.0,
    damping_ratio: float = 1e-3,
    mr: float = TUTORIAL_RING["mr"],
    radius: float = TUTORIAL_RING["radius"],
    kr: float = TUTORIAL_RING["kr"],
    mu: float = TUTORIAL_RING["mu"],
    **properties: float,
) -> Model:
    """The tuned lumped bladed disk with pyHarm's friction ring damper (module docstring).

    Parameters
    ----------
    sectors : int
        Number of sectors ``N >= 3``.
    rotation_speed : float, optional
        Rotation speed ``Omega`` (rad/s), >= 0, of the ring's centrifugal normal load ``N = mr R Omega^2``
        (N). Default: the tutorial's, :func:`tutorial_rotation_speed` of the disk (531.99 rad/s, 56.6 N).
    engine_order : int
        Engine order ``EO``: tip ``i`` is forced by ``fex cos(omega t - 2 pi EO i / N)``.
    fex : float
        Force amplitude on each tip (N), finite; the tutorial's is 1 N.
    damping_ratio : float
        Modal damping ratio of every disk mode (-), in [0, 1); the ring is undamped.
    mr : float
        Mass of a ring sector (kg), > 0; the tutorial's 2e-3.
    radius : float
        Ring radius ``R`` (m), > 0; the tutorial's 0.1.
    kr : float
        Ring stiffness (N/m), > 0: ``kr`` between ring sectors, ``1e-3 kr`` from each to the ground and
        ``kt = 10 kr`` for the Jenkins contacts; the tutorial's 1e7.
    mu : float
        Friction coefficient of the ring-disk contacts (-), >= 0; the tutorial's 0.1.
    **properties : float
        The disk's masses ``m0, mb1, mb2`` (kg) and springs ``kG, k0, kb1, kb2`` (N/m) of
        :class:`~fretwear.model.DiskSector`, its defaults for those not given.

    Returns
    -------
    Model
        ``4 N`` DOFs: the disk's ``3 N`` first, as :func:`fretwear.bladed_disk` numbers them (sector ``i``
        at ``3 i`` disk, ``3 i + 1`` root, ``3 i + 2`` tip; ``disk{i}``, ``root{i}``, ``tip{i}``), then
        ring sector ``i`` at ``3 N + i`` (``ring{i}``). Friction contact ``i`` joins ``ring{i}`` to
        ``disk{i}``. ``info`` holds the parameters and the normal load ``normal_load`` (N).
    """
    sector = DiskSector.of(sectors, properties, "ring_damper_disk")
    n = sector.sectors
    mr = _finite("mr", mr, 0.0, strict=True)
    radius = _finite("radius", radius, 0.0, strict=True)
    kr = _finite("kr", kr, 0.0, strict=True)
    mu = _finite("mu", mu, 0.0)
    if rotation_speed is None:
        rotation_speed = tutorial_rotation_speed(sector)
    rotation_speed = _finite("rotation_speed", rotation_speed, 0.0)
    if not (0 <= damping_ratio < 1):
        raise ValueError(f"damping_ratio must lie in [0, 1), got {damping_ratio!r}")

    Md, Kd = sector.assemble(np.zeros(n))
    Cd = modal_damping(Md, Kd, damping_ratio)  # the disk alone: the tutorial damps the blisk, not the ring

    ring = 3 * n + np.arange(n)
    M = sl.block_diag(Md, mr * np.eye(n))
    C = sl.block_diag(Cd, np.zeros((n, n)))
    K = sl.block_diag(Kd, np.zeros((n, n)))
    # the ring: kr between neighbours (closed), 1e-3 kr to ground
    ring_k = np.roll(np.eye(n), 1, axis=1) + np.roll(np.eye(n), -1, axis=1)
    K[3 * n :, 3 * n :] = (2 * kr + 1e-3 * kr) * np.eye(n) - kr * ring_k

    normal_load = mr * radius * rotation_speed**2
    kt = 10 * kr
    contacts = [
        FrictionContact.from_normal_load(int(ring[i]), 3 * i, mu, normal_load, kt=kt) for i in range(n)
    ]
    dof_names = {f"{part}{i}": 3 * i + k for i in range(n) for k, part in enumerate(("disk", "root", "tip"))}
    dof_names.update({f"ring{i}": int(ring[i]) for i in range(n)})
    info = {**asdict(sector), "damping_ratio": damping_ratio, "engine_order": engine_order, "fex": fex,
            "contacts": "ring", "mr": mr, "radius": radius, "kr": kr, "kr_ground": 1e-3 * kr, "kt": kt,
            "mu": mu, "rotation_speed": rotation_speed, "normal_load": normal_load}  # fmt: skip
    model = Model(M=M, C=C, K=K, friction=contacts, names=dof_names, info=info)
    return model.travelling_wave(3 * np.arange(n) + 2, engine_order, fex)
