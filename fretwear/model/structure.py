"""Linear structures with contacts of every kind the library solves (paper eq. 5, 17-23, 30).

A :class:`~fretwear.model.Model` is a linear structure of ``n`` degrees of freedom (DOFs),

    M u'' + C u' + K u + B^T lambda(t) = F_s + F_c cos(omega t) + F_sn sin(omega t),

where ``lambda`` gathers the contact forces and ``B`` maps the DOFs to the
relative contact coordinates ``u_r = B u`` (for a contact between DOFs ``i`` and
``j``, ``u_r = u_i - u_j``; for a contact to ground, ``u_r = u_i``). The force
``lambda`` acts with ``+`` on DOF ``i`` and ``-`` on DOF ``j``.

Three contact kinds exist:

* :class:`FrictionContact`: tangential Coulomb friction under a normal load
  that relaxes with wear, ``F_N(w) = k_n (u0 - w)`` clipped at zero (eq. 30d);
  rigid, or with a tangential stiffness ``kt`` in series (a Jenkins contact).
* :class:`NormalContact`: rigid unilateral (Signorini) contact across a gap
  (eq. 2, 21): ``u_r <= gap`` and ``lambda >= 0``, separation when the
  predicted force is not compressive. A negative gap is an interference
  (preload).
* :class:`~fretwear.model.pairs.ContactPairs`: node pairs of an interface with
  the coupled normal/tangential law (eq. 17-23), a gap and a tributary area per
  pair; wear opens the gaps.

A model holds 1-D contacts (``friction``, ``normal``) or ``pairs``, not both: no
solver treats the two together. Its matrices are dense arrays or, for a model
with pairs, ``scipy.sparse`` matrices (finite-element models); the 1-D contact
solvers are dense, so a model with 1-D contacts stores dense matrices.

All quantities are in SI units: kg, N/m, N s/m, N, m, rad/s.
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import scipy.sparse as sp

from .pairs import ContactPairs, finite_array

__all__ = [
    "STICK",
    "SLIP",
    "OPEN",
    "FrictionContact",
    "NormalContact",
    "Model",
    "paper_model",
    "jenkins_oscillator",
]

#: contact state codes of every solver: stuck (or closed), slipping, open (separated or unloaded)
STICK, SLIP, OPEN = 0, 1, 2


def _check_dof(name: str, value: int | None, n_dofs: int, allow_none: bool) -> None:
    if value is None and allow_none:
        return
    if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or not 0 <= value < n_dofs:
        raise ValueError(
            f"{name} must be a DOF index in [0, {n_dofs - 1}]"
            + (" or None (ground)" if allow_none else "")
            + f", got {value!r}"
        )


def _finite(name: str, value: float, low: float | None = None, strict: bool = False) -> float:
    if isinstance(value, bool) or not isinstance(value, (int, float, np.integer, np.floating)):
        raise ValueError(f"{name} must be a number, got {value!r}")
    value = float(value)
    if not np.isfinite(value):
        raise ValueError(f"{name} must be a finite number, got {value!r}")
    if low is not None and (value <= low if strict else value < low):
        op = ">" if strict else ">="
        raise ValueError(f"{name} must be {op} {low}, got {value!r}")
    return value


@dataclass(frozen=True)
class FrictionContact:
    """Tangential Coulomb friction contact with a wear-dependent normal load.

    Parameters
    ----------
    dof : int
        Index of the first DOF (0-based).
    other : int or None
        Index of the second DOF, or ``None`` for a contact with ground.
    mu : float
        Coulomb friction coefficient (-), ``mu >= 0``.
    kn : float
        Normal contact stiffness (N/m), ``kn > 0``.
    u0 : float
        Initial normal interference (m), ``u0 >= 0``. The initial normal load
        is ``kn * u0``.
    kt : float or None
        Tangential contact stiffness (N/m), ``kt > 0``, in series with the
        Coulomb slider (a Jenkins contact): the force is ``kt (u_r - s)``,
        ``|kt (u_r - s)| <= mu F_N``, the slider ``s`` moving only at the limit.
        ``None`` (default): a rigid contact.
    """

    dof: int
    other: int | None
    mu: float
    kn: float
    u0: float
    kt: float | None = None

    def __post_init__(self) -> None:
        _finite("mu", self.mu, 0.0)
        _finite("kn", self.kn, 0.0, strict=True)
        _finite("u0", self.u0, 0.0)
        if self.kt is not None:
            _finite("kt", self.kt, 0.0, strict=True)

    @classmethod
    def from_normal_load(
        cls,
        dof: int,
        other: int | None,
        mu: float,
        normal_load: float,
        kn: float = 1e7,
        kt: float | None = None,
    ) -> FrictionContact:
        """Contact with initial normal load ``normal_load`` (N), ``u0 = F_N / kn``."""
        _finite("normal_load", normal_load, 0.0)
        _finite("kn", kn, 0.0, strict=True)
        return cls(dof, other, mu, kn, normal_load / kn, kt)

    def normal_load(self, wear: float = 0.0) -> float:
        """Normal load ``F_N(w) = kn (u0 - w)`` clipped at 0 (N), eq. 30d."""
        return max(self.kn * (self.u0 - wear), 0.0)

    def slip_force(self, wear: float = 0.0) -> float:
        """Friction limit ``mu F_N(w)`` (N)."""
        return self.mu * self.normal_load(wear)


@dataclass(frozen=True)
class NormalContact:
    """Rigid unilateral contact: ``u_r <= gap``, compressive force ``lambda >= 0``.

    Parameters
    ----------
    dof, other : int, int or None
        DOFs as in :class:`FrictionContact`.
    gap : float
        Initial gap (m). Negative values are an interference (preload).
    """

    dof: int
    other: int | None
    gap: float = 0.0

    def __post_init__(self) -> None:
        _finite("gap", self.gap)


#: largest dense model whose matrices are checked positive semi-definite by an eigenvalue solve
EIGEN_CHECK_SIZE = 500

#: largest sparse model with 1-D contacts converted to dense matrices (their solvers are dense)
DENSE_LIMIT = 2000


def _matrix(name: str, value: Any, sparse: bool) -> np.ndarray | sp.csr_matrix:
    """``value`` as a finite, square, symmetric, positive semi-definite matrix (dense or CSR)."""
    if sparse:
        a = sp.csr_matrix(value, dtype=float)
        data = a.data
    else:
        a = np.array(value, dtype=float)
        data = a
    if a.ndim != 2 or a.shape[0] != a.shape[1] or a.shape[0] == 0:
        raise ValueError(f"{name} must be a non-empty square matrix, got shape {a.shape}")
    if not np.all(np.isfinite(data)):
        raise ValueError(f"{name} must contain finite numbers only")
    scale = float(np.abs(data).max(initial=0.0))
    if sparse:
        asym = abs(a - a.T).max() if a.nnz else 0.0
        if asym > 1e-10 * scale:
            raise ValueError(f"{name} must be symmetric (max |{name} - {name}^T| = {asym:.3g})")
        if np.any(a.diagonal() < 0):
            raise ValueError(f"{name} must have a non-negative diagonal (no negative mass or stiffness)")
        return a
    if not np.allclose(a, a.T, rtol=1e-12, atol=1e-14 * scale):
        raise ValueError(f"{name} must be symmetric")
    psd = (
        np.linalg.eigvalsh(a).min() >= -1e-12 * max(scale, 1e-300)
        if a.shape[0] <= EIGEN_CHECK_SIZE
        else np.all(np.diag(a) >= 0)
    )
    if not psd:
        raise ValueError(f"{name} must be positive semi-definite (no negative mass, damping or stiffness)")
    a.setflags(write=False)
    return a


@dataclass(frozen=True, eq=False)
class Model:
    """Linear structure with contacts, under static and harmonic loads.

    Parameters
    ----------
    M, C, K : ndarray or scipy.sparse matrix, shape (n, n)
        Mass (kg), viscous damping (N s/m) and stiffness (N/m) matrices,
        symmetric. ``C = None`` is no damping. ``M`` may be singular (massless
        DOFs) as long as the dynamic stiffness ``K - (k omega)^2 M + i k omega C``
        is regular. Sparse matrices are kept sparse (CSR) for a model with
        ``pairs`` and converted to dense ones for a model with 1-D contacts.
    force_cos : ndarray, shape (n,), optional
        Amplitude of the ``cos(omega t)`` part of the excitation (N). Default zero.
    force_sin : ndarray, shape (n,), optional
        Amplitude of the ``sin(omega t)`` part (N). Default zero.
    force_static : ndarray, shape (n,), optional
        Static load (N). Default zero.
    friction : sequence of FrictionContact
        1-D friction contacts whose normal load relaxes with wear (eq. 30).
    normal : sequence of NormalContact
        1-D unilateral contacts.
    pairs : ContactPairs, optional
        Contact node pairs of an interface (eq. 17-23); exclusive with
        ``friction`` and ``normal``.
    names : dict, optional
        Named DOFs (``name -> index``), e.g. ``{"pad_x": 12, "pad_y": 13}``.
    info : dict, optional
        Descriptive data of a bundled benchmark (radius, loads, moduli; SI).
    reduction : Reduction, optional
        Set on a reduced model (:func:`~fretwear.model.craig_bampton`):
        how its coordinates give the DOFs of the full model.
    """

    M: np.ndarray | sp.csr_matrix
    C: np.ndarray | sp.csr_matrix | None
    K: np.ndarray | sp.csr_matrix
    force_cos: np.ndarray | None = None
    force_sin: np.ndarray | None = None
    force_static: np.ndarray | None = None
    friction: tuple[FrictionContact, ...] = ()
    normal: tuple[NormalContact, ...] = field(default_factory=tuple)
    pairs: ContactPairs | None = None
    names: dict[str, int] = field(default_factory=dict)
    info: dict[str, Any] = field(default_factory=dict)
    # a fretwear.model.reduction.Reduction: that module builds models, so it is not imported here
    reduction: Any = field(default=None, repr=False)

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "friction", tuple(self.friction))
        set_(self, "normal", tuple(self.normal))
        if self.pairs is not None and (self.friction or self.normal):
            raise ValueError(
                "pairs cannot be combined with friction or normal contacts (no solver treats both); "
                f"got {self.pairs.count} pairs, {len(self.friction)} friction and {len(self.normal)} normal"
            )
        given = [getattr(self, k) for k in ("M", "C", "K")]
        sparse = any(sp.issparse(a) for a in given)
        if sparse and self.pairs is None:
            n = given[0].shape[0]
            if n > DENSE_LIMIT:
                raise ValueError(
                    f"M, C, K: a model with 1-D contacts is solved with dense matrices; {n} DOFs is more "
                    f"than {DENSE_LIMIT} (reduce the model first)"
                )
            sparse = False
            given = [a.toarray() if sp.issparse(a) else a for a in given]
        if given[1] is None:
            shape = np.shape(given[0]) if not sp.issparse(given[0]) else given[0].shape
            given[1] = sp.csr_matrix(shape) if sparse else np.zeros(shape)
        n = None
        for name, a in zip(("M", "C", "K"), given, strict=True):
            a = _matrix(name, a, sparse)
            n = a.shape[0] if n is None else n
            if a.shape != (n, n):
                raise ValueError(f"{name} must have shape ({n}, {n}) like M, got {a.shape}")
            set_(self, name, a)
        for name in ("force_cos", "force_sin", "force_static"):
            v = getattr(self, name)
            set_(self, name, finite_array(name, np.zeros(n) if v is None else v, (n,)))
        for kind, cls, contacts in (
            ("friction", FrictionContact, self.friction),
            ("normal", NormalContact, self.normal),
        ):
            for j, c in enumerate(contacts):
                if not isinstance(c, cls):
                    raise ValueError(f"{kind}[{j}] must be a {cls.__name__}, got {type(c).__name__}")
                _check_dof(f"{kind}[{j}].dof", c.dof, n, allow_none=False)
                _check_dof(f"{kind}[{j}].other", c.other, n, allow_none=True)
                if c.other == c.dof:
                    raise ValueError(f"{kind}[{j}]: dof and other must differ, both are {c.dof}")
        if self.pairs is not None:
            if not isinstance(self.pairs, ContactPairs):
                raise ValueError(f"pairs must be a ContactPairs, got {type(self.pairs).__name__}")
            for side in ("dofs_a", "dofs_b"):
                d = getattr(self.pairs, side)
                if np.any(d >= n):
                    i = int(np.argmax(d.max(axis=1)))
                    raise ValueError(
                        f"pairs.{side}[{i}] = {d[i].tolist()} is out of range: DOFs are 0 to {n - 1}"
                    )
        set_(self, "names", dict(self.names))
        for name, i in self.names.items():
            if isinstance(i, bool) or not isinstance(i, (int, np.integer)) or not 0 <= i < n:
                raise ValueError(f"names[{name!r}] = {i!r} is out of range: DOFs are 0 to {n - 1}")
        set_(self, "info", dict(self.info))

    # -- sizes and maps -------------------------------------------------
    @property
    def n_dofs(self) -> int:
        """Number of DOFs ``n``."""
        return self.M.shape[0]

    @property
    def sparse(self) -> bool:
        """True when the matrices are ``scipy.sparse`` (a finite-element model with pairs)."""
        return sp.issparse(self.K)

    @property
    def n_pairs(self) -> int:
        """Number of contact pairs ``nc`` (0 without :attr:`pairs`)."""
        return 0 if self.pairs is None else self.pairs.count

    @property
    def loaded_dofs(self) -> np.ndarray:
        """DOFs with a non-zero static or harmonic load."""
        return np.flatnonzero((self.force_static != 0) | (self.force_cos != 0) | (self.force_sin != 0))

    def dof(self, key: int | str) -> int:
        """DOF index of a name in :attr:`names` or of an index (checked)."""
        if isinstance(key, str):
            if key not in self.names:
                raise ValueError(f"unknown DOF name {key!r}; named DOFs are {sorted(self.names)}")
            return self.names[key]
        if isinstance(key, bool) or not isinstance(key, (int, np.integer)) or not 0 <= key < self.n_dofs:
            raise ValueError(f"DOF must be a name or an index in [0, {self.n_dofs - 1}], got {key!r}")
        return int(key)

    @property
    def contacts(self) -> tuple[FrictionContact | NormalContact, ...]:
        """All contacts, friction contacts first."""
        return self.friction + self.normal

    def relative_map(self, contacts=None) -> np.ndarray:
        """Matrix ``B`` (n_contacts, n) with ``u_r = B u`` for ``contacts``."""
        contacts = self.contacts if contacts is None else contacts
        B = np.zeros((len(contacts), self.n_dofs))
        for row, c in enumerate(contacts):
            B[row, c.dof] = 1.0
            if c.other is not None:
                B[row, c.other] = -1.0
        return B

    @property
    def half_wave_symmetric(self) -> bool:
        """True when odd harmonics alone describe the response.

        Holds with no static load and no unilateral contact or pair (Coulomb
        friction under a constant normal load is an odd law); the excitation is
        at the fundamental only by construction.
        """
        return not np.any(self.force_static) and not self.normal and self.pairs is None

    # -- derived models -------------------------------------------------
    def normal_loads(self, wear=None) -> np.ndarray:
        """Normal loads ``F_N`` (N) of the friction contacts for wear depths ``wear`` (m)."""
        wear = np.zeros(len(self.friction)) if wear is None else np.asarray(wear, dtype=float)
        if wear.shape != (len(self.friction),):
            raise ValueError(
                f"wear must have one entry per friction contact ({len(self.friction)}), got {wear.shape}"
            )
        if not np.all(np.isfinite(wear)) or np.any(wear < 0):
            raise ValueError(f"wear depths must be finite and >= 0 m, got {wear}")
        return np.array([c.normal_load(w) for c, w in zip(self.friction, wear, strict=True)])

    def slip_forces(self, wear=None) -> np.ndarray:
        """Slip forces ``mu F_N(w)`` (N) of the friction contacts for wear depths ``wear`` (m)."""
        return np.array([c.mu for c in self.friction]) * self.normal_loads(wear)

    @property
    def load_ratio(self) -> float:
        """``r = F_ex / (mu F_N)`` (-) of the unworn first friction contact (paper section 2.1).

        ``F_ex`` is the largest amplitude of the harmonic forcing over the DOFs. By
        the positive homogeneity of Coulomb's law, the response to the forcing
        scaled by ``s`` is the response at ``r s`` scaled by ``s``: ``r`` alone sets
        the stick/slip regime. ``inf`` when the contact cannot stick (``mu F_N = 0``).
        """
        if not self.friction:
            raise ValueError("load_ratio needs a friction contact; the model has none")
        fex = float(np.max(np.hypot(self.force_cos, self.force_sin)))
        slip = float(self.slip_forces()[0])
        return fex / slip if slip > 0 else np.inf

    def scaled(self, force: float = 1.0) -> Model:
        """Copy with every external force scaled by ``force`` (-)."""
        _finite("force", force)
        return replace(
            self,
            force_cos=force * self.force_cos,
            force_sin=force * self.force_sin,
            force_static=force * self.force_static,
        )

    def travelling_wave(self, groups, engine_order: int, amplitude: float = 1.0) -> Model:
        """Copy excited by a travelling wave over ``groups``, replacing the harmonic forcing.

        Group ``j`` of ``N`` (e.g. the DOFs of blade ``j`` of a bladed disk) is
        forced by ``amplitude cos(omega t - phi_j)`` with the phase
        ``phi_j = 2 pi engine_order j / N`` (a wave of ``engine_order`` nodal
        diameters travelling forward). The static load is kept.

        Parameters
        ----------
        groups : array_like of int, shape (N,) or (N, m)
            The DOFs of each group (one row per group, ``N >= 1``); each DOF in a
            row gets the group's force.
        engine_order : int
            Number of excitation periods around the ``N`` groups (-), any integer.
        amplitude : float
            Force amplitude on each DOF (N), finite.
        """
        rows = np.asarray(groups)
        rows = rows[:, None] if rows.ndim == 1 else rows
        if rows.ndim != 2 or rows.size == 0 or not np.issubdtype(rows.dtype, np.integer):
            raise ValueError(f"groups must be integer DOF indices of shape (N,) or (N, m), got {rows.shape}")
        if rows.min() < 0 or rows.max() >= self.n_dofs:
            raise ValueError(
                f"groups must hold DOFs in [0, {self.n_dofs - 1}], got {rows.min()} to {rows.max()}"
            )
        if np.unique(rows).size != rows.size:
            raise ValueError("groups must not repeat a DOF (each DOF has one phase)")
        if isinstance(engine_order, bool) or not isinstance(engine_order, (int, np.integer)):
            raise ValueError(f"engine_order must be an integer, got {engine_order!r}")
        amplitude = _finite("amplitude", amplitude)
        phase = 2 * np.pi * engine_order * np.arange(len(rows)) / len(rows)
        force_cos, force_sin = np.zeros(self.n_dofs), np.zeros(self.n_dofs)
        # cos(omega t - phi) = cos(phi) cos(omega t) + sin(phi) sin(omega t)
        force_cos[rows] = amplitude * np.cos(phase)[:, None]
        force_sin[rows] = amplitude * np.sin(phase)[:, None]
        return replace(self, force_cos=force_cos, force_sin=force_sin)

    def with_friction(self, **changes) -> Model:
        """Copy with the same change (e.g. ``mu=0.5``) applied to every friction contact."""
        return replace(self, friction=tuple(replace(c, **changes) for c in self.friction))


def paper_model(
    fex: float = 10.0,
    mu: float = 1.0,
    normal_load: float = 10.0,
    kn: float = 1e7,
    damping_ratio: float = 1e-3,
) -> Model:
    """The 2-DOF example of Salles et al., section 2.1 (eq. 30, Fig. 4).

    Unit masses, ``k1 = pi^2``, ``k2 = 7 pi^2`` (N/m), ``c_i = 2 zeta sqrt(k_i m_i)``,
    friction between the masses (``x_r = x1 - x2``), ``kn = 1e7`` N/m and
    ``u0 = F_N / kn`` (1e-6 m for 10 N), excitation ``fex cos(omega t)`` on mass 1.
    The stuck mode is at 1 Hz and the mode with mass 1 free at 0.5 Hz.

    Parameters
    ----------
    fex : float
        Excitation amplitude on mass 1 (N).
    mu : float
        Friction coefficient (-).
    normal_load : float
        Initial normal load ``F_N = kn u0`` (N).
    kn : float
        Normal stiffness (N/m).
    damping_ratio : float
        Viscous damping ratio of each mass-spring pair (-).
    """
    _finite("fex", fex)
    _finite("damping_ratio", damping_ratio, 0.0)
    k1, k2 = np.pi**2, 7 * np.pi**2
    c1, c2 = 2 * damping_ratio * np.sqrt(k1), 2 * damping_ratio * np.sqrt(k2)
    return Model(
        M=np.eye(2),
        C=np.diag([c1, c2]),
        K=np.diag([k1, k2]),
        force_cos=np.array([fex, 0.0]),
        friction=(FrictionContact.from_normal_load(0, 1, mu, normal_load, kn),),
    )


def jenkins_oscillator(
    m: float = 1.0,
    c: float = 0.02,
    k: float = 1.0,
    kt: float = 1.0,
    slip_force: float = 0.1,
    force: float = 0.1,
) -> Model:
    """1-DOF oscillator with a Jenkins element (benchmark (b) of the core solver).

    DOF 0 is the mass; DOF 1 is massless, tied to the mass by a spring ``kt``
    (N/m) and to ground by a friction contact of slip force ``slip_force`` (N).
    The excitation ``force cos(omega t)`` (N) acts on the mass.
    """
    return Model(
        M=np.diag([m, 0.0]),
        C=np.diag([c, 0.0]),
        K=np.array([[k + kt, -kt], [-kt, kt]]),
        force_cos=np.array([force, 0.0]),
        friction=(FrictionContact.from_normal_load(1, None, 1.0, slip_force),),
    )
