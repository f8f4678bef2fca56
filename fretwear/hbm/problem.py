"""The DLFT problem at one frequency: condensed dynamics, Fourier basis, penalties (paper eq. 11, 17-18).

:class:`Problem` holds everything that depends on the frequency and the wear
state only (condensation on the active contacts, DFT matrices, penalties) and
evaluates the DLFT residual ``R(x) = eps (x - X(x))`` and its Jacobian; the
solvers of ``fretwear.hbm.periodic`` and the sweeps of
:mod:`fretwear.hbm.continuation` reuse it. A problem is never changed in
place: :meth:`Problem.at_load` and :meth:`Problem.with_wear` return copies.
"""

from __future__ import annotations

import copy
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from ..model import Model
from . import dlft
from .condensation import Condensed, Receptance, condense, condense_sweep, receptance
from .harmonics import HarmonicBasis, default_samples

__all__ = ["Problem", "EPS_FACTOR"]

#: default penalty, as a multiple of the condensed dynamic stiffness scale
EPS_FACTOR = 10.0


@dataclass
class Problem:
    """DLFT problem at one frequency, for a model in a given wear state.

    Parameters
    ----------
    model, omega, harmonics, samples, wear, eps, half_wave
        As :func:`fretwear.solve_periodic`; the default ``eps`` is ``EPS_FACTOR``
        times the largest diagonal entry of the condensed dynamic stiffness over
        the retained harmonics (a Jenkins contact's entry is its stiffness ``k_t``:
        it has no penalty), ``half_wave`` is used when the model allows it.
    force_scale : float
        Load factor applied to every external force (used by load continuation).
    condensed : Condensed, Receptance or callable, optional
        The condensation at ``omega`` on the active contacts, when already known,
        or a function of ``(B, basis)`` that returns it (sweeps condense every
        frequency at once). A :class:`~fretwear.hbm.condensation.Receptance` sets the receptance form.
    march : tuple, optional
        ``(x, R, lam, X, state)``: the residual and the march of :meth:`evaluate`
        at unknowns ``x``, when a solver already has them (the compiled sweep);
        :meth:`evaluate` then answers at ``x`` without marching again.

    Notes
    -----
    ``form`` is ``"stiffness"`` (eq. 12, ``R = Z_r x + Lambda - F_r``) or, for
    Jenkins contacts whose relative coordinates are dependent (a closed ring)
    or a given :class:`~fretwear.hbm.condensation.Receptance`, ``"receptance"``
    (``fretwear.hbm.receptance``): ``Z``/``F0`` are then replaced by the
    receptance ``G`` and the linear relative displacement ``U0``, ``F0`` being
    ``k_t U0`` (the force scale of the residual).
    """

    model: Model
    omega: float
    harmonics: int = 7
    samples: int | None = None
    wear: np.ndarray | None = None
    eps: float | np.ndarray | None = None
    half_wave: bool | None = None
    force_scale: float = 1.0
    derivative: bool = False
    condensed: Condensed | Callable[[np.ndarray, HarmonicBasis], Condensed] | None = field(
        default=None, repr=False
    )
    march: tuple | None = field(default=None, repr=False)
    basis: HarmonicBasis = field(init=False)

    def __post_init__(self) -> None:
        m = self.model
        if m.pairs is not None:  # would be solved as a linear structure, silently
            raise ValueError(
                "model has contact pairs, which this solver of 1-D friction and normal contacts does not "
                "treat; use fretwear.solve_periodic, fretwear.sweep or fretwear.wear_history"
            )
        if not np.isfinite(self.omega) or self.omega <= 0:
            raise ValueError(f"omega must be a finite frequency > 0 rad/s, got {self.omega!r}")
        samples = default_samples(self.harmonics) if self.samples is None else self.samples
        if self.half_wave is None:
            self.half_wave = m.half_wave_symmetric and samples % 2 == 0
        elif self.half_wave and not m.half_wave_symmetric:
            raise ValueError(
                "half_wave=True needs a half-wave symmetric model (no static load, no unilateral contact)"
            )
        self.basis = HarmonicBasis(self.harmonics, samples, bool(self.half_wave))
        self.samples = samples
        self.normal_loads = m.normal_loads(self.wear)
        self.wear = np.zeros(len(m.friction)) if self.wear is None else np.asarray(self.wear, float)
        if np.any(self.wear < 0):
            raise ValueError(f"wear must be >= 0 m, got {self.wear}")
        active_f = [i for i, c in enumerate(m.friction) if c.mu * self.normal_loads[i] > 0]
        self.active_index = active_f + [len(m.friction) + j for j in range(len(m.normal))]
        self.active = [m.contacts[i] for i in self.active_index]
        self.kinds = np.array(
            [dlft.FRICTION if m.friction[i].kt is None else dlft.JENKINS for i in active_f]
            + [dlft.UNILATERAL] * len(m.normal),
            dtype=np.int64,
        )
        self.limits = np.array(
            [m.friction[i].mu * self.normal_loads[i] for i in active_f] + [c.gap for c in m.normal],
            dtype=float,
        )
        self.B = m.relative_map(self.active)
        self.form = "stiffness"
        if self.active:
            cond = self.condensed
            if self._dependent():  # no stiffness form exists: a given one cannot be asked for
                self._receptance(cond if isinstance(cond, Receptance) else None)
                return
            if callable(cond):
                cond = cond(self.B, self.basis)
            if isinstance(cond, Receptance):
                self._receptance(cond)
                return
            if cond is None and self.derivative:
                cond = condense(m, self.B, self.omega, self.basis, True)
            elif cond is None:  # the compiled loop of sweeps, for one frequency
                batch = condense_sweep(m, self.B, np.array([float(self.omega)]), self.basis)
                cond = Condensed(batch.Z[0], batch.F[0])
            self.Z, self.F0, self.dZ, self.dF0 = cond.Z, cond.F, cond.dZ, cond.dF
            self.eps = self._penalty(self.eps)

    def _dependent(self) -> bool:
        """Whether the active contact coordinates are dependent (``B`` rank-deficient: no ``Z_r``)."""
        return bool(np.linalg.matrix_rank(self.B) < self.n_active)

    def _receptance(self, cond: Receptance | None) -> None:
        """Set up the receptance form (class notes); only Jenkins contacts are solved in it."""
        if np.any(self.kinds != dlft.JENKINS):
            raise ValueError(
                "the contacts' relative coordinates are dependent (a closed ring of contacts), so the "
                "condensed dynamic stiffness does not exist; such contacts must all be Jenkins contacts "
                "(FrictionContact with kt) with a normal load > 0"
            )
        if cond is None:
            cond = receptance(self.model, self.B, self.omega, self.basis)
        self.form, self.G, self.U0 = "receptance", cond.G, cond.U
        self.eps = self._penalty(self.eps if self.eps is not None else 1.0)
        self.F0 = np.repeat(self.eps, self.basis.size) * self.U0
        self.Z = self.dZ = self.dF0 = None
        self.no_stiffness = np.zeros((self.size, self.size))

    def at_load(self, force_scale: float) -> Problem:
        """The same problem with the external forces scaled by ``force_scale`` (a copy, same condensation)."""
        new = copy.copy(self)
        new.force_scale, new.march = float(force_scale), None
        return new

    def at_frequency(
        self, omega: float, Z: np.ndarray, F: np.ndarray, eps: np.ndarray, march=None
    ) -> Problem:
        """The same problem at ``omega`` (rad/s), given its condensation ``Z``, ``F`` and penalties there.

        A copy: sweeps condense every frequency at once and choose each penalty
        ``eps`` (N/m, per active contact) as :class:`Problem` would, or take the
        user's; ``march`` as the parameter of :class:`Problem`.
        """
        new = object.__new__(Problem)
        new.__dict__.update(self.__dict__)
        new.omega, new.condensed, new.march, new.Z, new.F0, new.eps = omega, None, march, Z, F, eps
        if self.dZ is not None:  # no derivatives at the new frequency
            new.dZ = new.dF0 = None
            new.deps = np.zeros(len(eps))
        return new

    def with_wear(self, wear) -> Problem:
        """The same problem at wear depths ``wear`` (m): wear changes only the friction limits.

        Reuses the condensation and the penalty when the set of active contacts
        is unchanged (it changes only when a normal load reaches zero).
        """
        wear = np.asarray(wear, dtype=float)
        loads = self.model.normal_loads(wear)
        nf = len(self.model.friction)
        active_f = [i for i in range(nf) if self.model.friction[i].mu * loads[i] > 0]
        if active_f != [i for i in self.active_index if i < nf]:
            return Problem(
                self.model, self.omega, self.harmonics, self.samples, wear, None, self.basis.half_wave,
                self.force_scale,
            )  # fmt: skip
        new = copy.copy(self)
        new.wear, new.normal_loads, new.march = wear, loads, None
        new.limits = self.limits.copy()
        new.limits[: len(active_f)] = [self.model.friction[i].mu * loads[i] for i in active_f]
        return new

    # -- sizes ----------------------------------------------------------------
    @property
    def n_active(self) -> int:
        return len(self.active)

    @property
    def size(self) -> int:
        """Number of unknowns ``nc H``."""
        return self.n_active * self.basis.size

    @property
    def F(self) -> np.ndarray:
        """Reduced force at the current load factor (N)."""
        return self.force_scale * self.F0

    def _penalty(self, eps) -> np.ndarray:
        """Penalty per contact (N/m); sets ``deps``, its derivative in omega (N s/m).

        A Jenkins contact has no penalty: its slot holds its stiffness ``k_t``
        (``fretwear.hbm.dlft``), whatever ``eps`` says.
        """
        H, nc = self.basis.size, self.n_active
        self.deps = np.zeros(nc)
        if eps is None:
            diag = np.diag(self.Z).reshape(nc, H)
            j = np.argmax(np.abs(diag), axis=1)
            if self.dZ is not None:
                dd = np.diag(self.dZ).reshape(nc, H)[np.arange(nc), j]
                self.deps = EPS_FACTOR * np.sign(diag[np.arange(nc), j]) * dd
            eps = EPS_FACTOR * np.abs(diag[np.arange(nc), j])
        else:
            eps = np.broadcast_to(np.asarray(eps, dtype=float), (self.n_active,)).copy()
            if np.any(~np.isfinite(eps)) or np.any(eps <= 0):
                raise ValueError(f"eps must be finite and > 0 N/m, got {eps}")
        jenkins = self.kinds == dlft.JENKINS
        eps[jenkins] = [self.active[c].kt for c in np.flatnonzero(jenkins)]
        self.deps[jenkins] = 0.0
        return eps

    # -- DLFT -------------------------------------------------------------------
    def evaluate(self, x: np.ndarray, jacobian: bool = True):
        """Residual (N), Jacobian (N/m) or None, and the time-domain fields of the march."""
        if self.form == "receptance":
            return self._evaluate_receptance(x, jacobian)
        nc, H = self.n_active, self.basis.size
        Ns = self.basis.marched_samples
        if not jacobian and self.march is not None and np.array_equal(x, self.march[0]):
            return self.march[1], None, np.empty((nc, H, H)), *self.march[2:]
        R = np.empty(nc * H)
        A = np.empty((nc, H, H))
        lam = np.empty((nc, Ns))
        X = np.empty((nc, Ns))
        state = np.empty((nc, Ns), dtype=np.int8)
        dlft.evaluate(
            x, self.Z, self.F, self.eps, self.kinds, self.limits, self.basis.synthesis, self.basis.analysis,
            self.basis.half_wave, jacobian, R, A, lam, X, state,
        )  # fmt: skip
        J = None
        if jacobian:
            J = np.empty((nc * H, nc * H))
            if np.any(self.kinds == dlft.JENKINS):
                dlft.jacobian_of_kinds(self.Z, self.eps, A, self.kinds, J)
            else:  # the kernel fretwear.compile warms up and checks in the cache
                dlft.jacobian_from_blocks(self.Z, self.eps, A, J)
        return R, J, A, lam, X, state

    def _evaluate_receptance(self, x: np.ndarray, jacobian: bool):
        """:meth:`evaluate` in the receptance form (``fretwear.hbm.receptance``):
        ``R = k_t (x - s u_lin + G Lambda(x))`` (N), ``J = k_t (I + G k_t A)`` (N/m)."""
        nc, H = self.n_active, self.basis.size
        Ns, b = self.basis.marched_samples, self.basis
        Lam, A = np.empty(nc * H), np.empty((nc, H, H))
        lam, X = np.empty((nc, Ns)), np.empty((nc, Ns))
        state = np.empty((nc, Ns), dtype=np.int8)
        # with Z = 0 and F = 0 the DLFT residual is the Jenkins force Lambda(x) itself
        dlft.evaluate(x, self.no_stiffness, np.zeros(nc * H), self.eps, self.kinds, self.limits, b.synthesis,
                      b.analysis, b.half_wave, jacobian, Lam, A, lam, X, state)  # fmt: skip
        kt = np.repeat(self.eps, H)
        R = kt * (x - self.force_scale * self.U0 + self.G @ Lam)
        J = None
        if jacobian:  # d Lambda_c / d x_c = k_t A_c, block-diagonal
            GdLam = np.einsum("ich,chk->ick", self.G.reshape(nc * H, nc, H), self.eps[:, None, None] * A)
            J = kt[:, None] * (np.eye(nc * H) + GdLam.reshape(nc * H, nc * H))
        return R, J, A, lam, X, state

    def residual_scale(self) -> float:
        """Force scale (N) against which residuals are judged: the largest external force or slip force.

        A Jenkins contact's force never exceeds its spring's, which the external force sets: its slip
        force counts up to that scale only (a slip force of 1e10 N would accept a stuck guess).
        """
        force = np.abs(self.F).max(initial=0.0)
        rigid = np.abs(self.limits[self.kinds == dlft.FRICTION]).max(initial=0.0)
        jenkins = min(np.abs(self.limits[self.kinds == dlft.JENKINS]).max(initial=0.0), force)
        scale = max(force, rigid, jenkins)
        return scale if scale > 0 else 1.0

    # -- linear solutions -------------------------------------------------------
    def stuck_guess(self) -> np.ndarray:
        """Stuck friction contacts (x = 0) and unilateral contacts closed at their gap."""
        x = np.zeros(self.size)
        if not self.basis.half_wave:
            H = self.basis.size
            for c in np.flatnonzero(self.kinds == dlft.UNILATERAL):
                x[c * H] = self.limits[c]
        return x

    def stick_ratio(self) -> float:
        """Largest ratio ``(stick force half-range) / (mu F_N)`` of the exact stuck solution.

        Only for friction-only problems: the stuck solution has ``x = 0`` on
        every harmonic but the mean, chosen so that each stick force is centred
        in its cone, and its force is ``Lambda = F_r - Z_r x``. Values ``<= 1``
        mean the stuck solution is exact.
        """
        H = self.basis.size
        F = self.F.reshape(self.n_active, H)
        amp = np.sqrt(np.sum(F[:, self.basis.orders == 1] ** 2, axis=1))  # forcing is at the fundamental
        return float(np.max(amp / self.limits))

    def stuck_solution(self) -> np.ndarray:
        """Unknowns of the centred stuck solution (friction-only problems)."""
        x = np.zeros(self.size)
        if not self.basis.half_wave:
            H = self.basis.size
            means = np.arange(self.n_active) * H
            # centred stick: the mean stick force Lambda_0 = F_0 - Z_0 x_0 is zero
            x[means] = np.linalg.solve(self.Z[np.ix_(means, means)], self.F[means])
        return x
