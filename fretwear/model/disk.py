"""The lumped bladed disk of Laxalde, Thouverez, Sinou and Lombard (Eur. J. Mech. A/Solids 26, 2007).

``N`` identical sectors in a ring, three DOFs each (one ``x`` per mass, in
order disk, blade root, blade tip):

* the disk mass ``m0`` on a spring ``kG`` to the ground and a spring ``k0`` to
  the next sector's disk mass (the ring closes: sector ``N - 1`` to sector 0);
* the blade masses ``mb1`` (spring ``kb1`` to the disk) and ``mb2`` (spring
  ``kb2`` to ``mb1``).

With the default values (24 sectors) the natural frequencies start at
88.2637, 169.3441 (x2), 189.3019 (x2), 193.0496 (x2) Hz and end at 2045.4706 (x2),
2062.9757 Hz. Mistuning scales blade ``i``'s springs: ``kb1 (1 + delta_i)`` and
``kb2 (1 + delta_i)``. Damping is modal, one ratio for every mode of the tuned
or mistuned disk.

Contacts (``contacts="shroud"``, the default): a Jenkins contact (tangential
stiffness ``kt`` in series with Coulomb friction) between the tips of
neighbouring blades, ``i`` to ``i + 1`` round the ring, each under the normal
load of an interference ``u0`` that relaxes with wear, ``F_N,i = kn (u0 -
w_i)`` clipped at zero (eq. 30). They are not in ``M`` and ``K``, which keep the
frequencies above. The ring's relative coordinates sum to zero, so the
contacts are solved in the receptance form (``fretwear.hbm.receptance``).
A rigid shroud would lock every tip to its neighbours: under an engine order
``EO != 0`` the stuck disk would not move; ``kt`` is what lets it.

Cyclic symmetry (:class:`~fretwear.model.DiskSector`): a tuned disk's modes have ``nd`` nodal
diameters, the sector's motion repeated with the phase ``exp(i 2 pi nd / N)``
from one sector to the next; per ``nd`` the sector's three frequencies solve
``(K0 + K1 e^{i theta} + K1^T e^{-i theta}) phi = omega^2 M0 phi`` with
``theta = 2 pi nd / N``.
"""

from __future__ import annotations

from dataclasses import asdict, dataclass, fields

import numpy as np
import scipy.linalg as sl

from .structure import FrictionContact, Model, _finite

__all__ = ["DiskSector", "bladed_disk", "modal_damping"]

#: DOFs of one sector, in order
SECTOR_DOFS = ("disk", "root", "tip")

#: contact layouts of :func:`bladed_disk`
LAYOUTS = ("shroud", "ring", "none")


@dataclass(frozen=True)
class DiskSector:
    """One sector of the tuned disk and its cyclic-symmetry matrices.

    Parameters
    ----------
    sectors : int
        Number of sectors ``N >= 3``.
    m0, mb1, mb2 : float
        Disk, blade-root and blade-tip masses (kg), > 0.
    kG, k0, kb1, kb2 : float
        Springs (N/m), > 0: disk to ground, disk to the next disk, disk to root, root to tip.
    """

    sectors: int = 24
    m0: float = 1.2
    mb1: float = 0.35
    mb2: float = 0.25
    kG: float = 6e5
    k0: float = 5e7
    kb1: float = 1e6
    kb2: float = 2e6

    def __post_init__(self) -> None:
        if (
            isinstance(self.sectors, bool)
            or not isinstance(self.sectors, (int, np.integer))
            or self.sectors < 3
        ):
            raise ValueError(f"sectors must be an integer >= 3, got {self.sectors!r}")
        for name in ("m0", "mb1", "mb2", "kG", "k0", "kb1", "kb2"):
            object.__setattr__(self, name, _finite(name, getattr(self, name), 0.0, strict=True))

    @classmethod
    def of(cls, sectors: int, properties: dict, caller: str) -> DiskSector:
        """The sector with ``properties`` (its masses and springs), each name checked: a misspelled one
        is a ``ValueError`` naming ``caller`` and the sector's parameters."""
        names = [f.name for f in fields(cls)][1:]
        unknown = sorted(set(properties) - set(names))
        if unknown:
            raise ValueError(
                f"{unknown[0]!r} is not a parameter of {caller}; the sector has {', '.join(names)}"
            )
        return cls(sectors, **properties)

    @property
    def mass(self) -> np.ndarray:
        """Sector mass matrix ``M0`` (kg), diagonal (3, 3)."""
        return np.diag([self.m0, self.mb1, self.mb2])

    def stiffness(self, kb1: float | None = None, kb2: float | None = None) -> tuple[np.ndarray, np.ndarray]:
        """``K0`` (the sector's own springs) and ``K1`` (its coupling to the next sector), (3, 3) each, N/m.

        ``kb1``, ``kb2`` replace the blade springs (a mistuned blade).
        """
        kb1 = self.kb1 if kb1 is None else kb1
        kb2 = self.kb2 if kb2 is None else kb2
        K0 = np.array([
            [self.kG + kb1 + 2 * self.k0, -kb1, 0.0],
            [-kb1, kb1 + kb2, -kb2],
            [0.0, -kb2, kb2],
        ])  # fmt: skip
        K1 = np.zeros((3, 3))
        K1[0, 0] = -self.k0  # this disk to the next one
        return K0, K1

    def assemble(self, mistuning: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Mass and stiffness matrices of the whole disk (kg, N/m), (3 N, 3 N) each.

        ``mistuning``: ``delta_i`` per blade (checked by :func:`bladed_disk`);
        blade ``i``'s springs are ``kb1 (1 + delta_i)`` and ``kb2 (1 + delta_i)``.
        """
        n_sec = self.sectors
        n = 3 * n_sec
        M = np.kron(np.eye(n_sec), self.mass)
        K = np.zeros((n, n))
        for i in range(n_sec):  # assembly, once per model (3 N DOFs)
            K0, K1 = self.stiffness(self.kb1 * (1 + mistuning[i]), self.kb2 * (1 + mistuning[i]))
            j, nxt = 3 * i, 3 * ((i + 1) % n_sec)
            K[j : j + 3, j : j + 3] += K0
            K[j : j + 3, nxt : nxt + 3] += K1
            K[nxt : nxt + 3, j : j + 3] += K1.T
        return M, K

    def frequencies(self, nodal_diameter: int) -> np.ndarray:
        """The sector's three natural frequencies (Hz) with ``nodal_diameter`` nodal diameters, ascending."""
        if isinstance(nodal_diameter, bool) or not isinstance(nodal_diameter, (int, np.integer)):
            raise ValueError(f"nodal_diameter must be an integer, got {nodal_diameter!r}")
        theta = 2 * np.pi * nodal_diameter / self.sectors
        K0, K1 = self.stiffness()
        K = K0 + K1 * np.exp(1j * theta) + K1.T * np.exp(-1j * theta)  # Hermitian
        return np.sqrt(sl.eigh(K, self.mass, eigvals_only=True)) / (2 * np.pi)

    def zzenf(self) -> np.ndarray:
        """Frequencies (Hz) against nodal diameter ``0 .. N // 2``, shape (N // 2 + 1, 3): the ZZENF
        diagram."""
        return np.array([self.frequencies(nd) for nd in range(self.sectors // 2 + 1)])


def modal_damping(M: np.ndarray, K: np.ndarray, damping_ratio: float) -> np.ndarray:
    """Modal damping ``C = M Phi diag(2 zeta omega_r) Phi^H M`` (N s/m): the ratio ``zeta`` in every mode.

    ``Phi`` are the mass-normalised modes of ``(K, M)`` (``K`` may be Hermitian: a sector at a nodal
    diameter); the result is Hermitian to round-off (symmetrised).
    """
    w2, phi = sl.eigh(K, M)
    MPhi = M @ phi
    C = MPhi @ np.diag(2 * damping_ratio * np.sqrt(np.maximum(w2, 0.0))) @ MPhi.conj().T
    return 0.5 * (C + C.conj().T)


def bladed_disk(
    sectors: int = 24,
    *,
    damping_ratio: float = 1e-3,
    mistuning=None,
    engine_order: int = 1,
    fex: float = 1.0,
    contacts: str = "shroud",
    mu: float | None = None,
    kn: float = 1e7,
    u0: float = 1e-6,
    kt: float = 5e5,
    **properties: float,
) -> Model:
    """The lumped bladed disk (module docstring) under a travelling wave on the blade tips.

    Parameters
    ----------
    sectors : int
        Number of sectors ``N >= 3``.
    damping_ratio : float
        Modal damping ratio of every mode (-), in [0, 1).
    mistuning : array_like, shape (sectors,), optional
        ``delta_i``: blade ``i``'s springs are ``kb1 (1 + delta_i)`` and ``kb2 (1 + delta_i)``; each
        ``delta_i > -1``. Default: tuned.
    engine_order : int
        Engine order ``EO`` of the excitation: tip ``i`` is forced by ``fex cos(omega t - 2 pi EO i / N)``.
    fex : float
        Force amplitude on each tip (N), finite.
    contacts : {"shroud", "ring", "none"}
        ``"shroud"``: a Jenkins contact between the tips of blades ``i`` and
        ``i + 1`` (mod ``N``), friction contact ``i``; ``"ring"``: pyHarm's
        friction ring damper under the tuned disk
        (``fretwear.model.ring.ring_damper_disk()``, its parameters
        ``rotation_speed``, ``mr``, ``radius``, ``kr`` among ``properties``);
        ``"none"``: the linear disk.
    mu : float, optional
        Friction coefficient of the contacts (-), >= 0; default 0.3 (shroud), 0.1 (ring, the tutorial's).
    kn : float
        Normal stiffness of the shroud contacts (N/m), > 0.
    u0 : float
        Interference of the shroud contacts (m), >= 0: ``F_N = kn u0`` unworn.
    kt : float
        Tangential stiffness of the shroud contacts (N/m), > 0.
    **properties : float
        The masses ``m0, mb1, mb2`` (kg) and springs ``kG, k0, kb1, kb2`` (N/m) of
        :class:`~fretwear.model.DiskSector`, its defaults for those not given.

    Returns
    -------
    Model
        ``3 N`` DOFs, sector ``i``'s at ``3 i`` (disk), ``3 i + 1`` (root), ``3 i + 2`` (tip), named
        ``disk{i}``, ``root{i}``, ``tip{i}``; ``info`` holds the parameters (the cyclic solve of
        ``fretwear.disk.cyclic`` reads them).
    """
    if contacts == "ring":
        from .ring import ring_damper_disk

        if mistuning is not None:
            raise ValueError(
                "the ring damper's disk is tuned: mistuning applies to contacts 'shroud' or 'none'"
            )
        given = {} if mu is None else {"mu": mu}
        return ring_damper_disk(sectors, engine_order=engine_order, fex=fex, damping_ratio=damping_ratio,
                                **given, **properties)  # fmt: skip
    mu = 0.3 if mu is None else mu
    sector = DiskSector.of(sectors, properties, "bladed_disk")
    n_sec = sector.sectors
    delta = np.zeros(n_sec) if mistuning is None else np.array(mistuning, dtype=float)
    if delta.shape != (n_sec,) or not np.all(np.isfinite(delta)) or np.any(delta <= -1):
        raise ValueError(f"mistuning must hold {n_sec} finite numbers > -1, got shape {delta.shape}")
    if not (0 <= damping_ratio < 1):
        raise ValueError(f"damping_ratio must lie in [0, 1), got {damping_ratio!r}")
    M, K = sector.assemble(delta)
    C = modal_damping(M, K, damping_ratio)
    if contacts not in LAYOUTS:
        raise ValueError(f"contacts must be one of {', '.join(LAYOUTS)}, got {contacts!r}")
    tips = np.arange(n_sec) * 3 + 2
    shroud = []
    if contacts == "shroud":
        shroud = [
            FrictionContact(int(tips[i]), int(tips[(i + 1) % n_sec]), mu, kn, u0, kt) for i in range(n_sec)
        ]
    dof_names = {f"{part}{i}": 3 * i + k for i in range(n_sec) for k, part in enumerate(SECTOR_DOFS)}
    info = {**asdict(sector), "damping_ratio": damping_ratio, "engine_order": engine_order, "fex": fex,
            "contacts": contacts, "mistuning": tuple(delta.tolist())}  # fmt: skip
    if shroud:
        info.update(mu=shroud[0].mu, kn=shroud[0].kn, u0=shroud[0].u0, kt=shroud[0].kt)
    model = Model(M=M, C=C, K=K, friction=shroud, names=dof_names, info=info)
    return model.travelling_wave(tips, engine_order, fex)
