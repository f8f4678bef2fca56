"""The tuned bladed disk with its shroud solved on one sector: cyclic symmetry of harmonic balance.

Under a travelling wave of engine order ``EO`` a tuned disk answers with a
travelling wave: sector ``j`` repeats sector 0 delayed by ``j EO / N`` of a
period, so harmonic ``k`` of sector ``j`` is ``U_j,k = U_0,k e^{i j theta_k}``
with ``theta_k = -2 pi k EO / N`` (the standard cyclic condition of harmonic
balance). Per harmonic the sector obeys the dynamic stiffness of the nodal
diameter ``k EO mod N``,

    D_k = K0 + K1 e^{i theta_k} + K1^T e^{-i theta_k} - (k omega)^2 M0 + i k omega C(theta_k),

with ``C(theta) = M0 Phi diag(2 zeta omega_r) Phi^H M0`` over the sector's
mass-normalised modes at ``theta`` (the tuned disk's modal damping, exactly).
Shroud contact 0 joins tip 0 to tip 1: its relative displacement is ``x_k =
(1 - e^{i theta_k}) u_tip,k`` and the tip carries ``(1 - e^{-i theta_k})
Lambda_k`` (contact 0 and, delayed, contact ``N - 1``), so the one contact of
the sector obeys the receptance form of ``fretwear.hbm.receptance`` with

    g_k = |1 - e^{i theta_k}|^2 h_k,    u_lin,k = (1 - e^{i theta_k}) h_k F_ex [k = 1],

``h_k`` the tip receptance of ``D_k``. (Where ``k EO`` is a multiple of ``N``,
``g_k = 0``: every shroud moves alike and no contact moves.)

The sector's contact march is the full disk's, delayed, when the delay is a
whole number of time samples: with ``samples * EO / N`` an integer the sector
solve and the full-disk solve are the same discrete equations and agree to
round-off (:func:`samples_for` picks such a grid by default); on another grid
they differ by the march's time sampling.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, fields, replace

import numpy as np

from ..hbm.condensation import Receptance, _distinct_orders, _real_blocks, _real_vector
from ..hbm.continuation import Sweep, check_omegas
from ..hbm.dlft import JENKINS, evaluate
from ..hbm.harmonics import HarmonicBasis, default_samples
from ..hbm.periodic import solve_problem
from ..hbm.problem import Problem
from ..hbm.solution import PeriodicSolution
from ..model import DiskSector, Model, bladed_disk
from ..model.disk import modal_damping

__all__ = ["Sector", "solve_sector", "sweep_sector", "samples_for", "tuned_disk", "is_tuned_disk"]

_TIP = 2  # the tip's place in a sector's DOFs


def tuned_disk(model: Model) -> tuple[DiskSector, dict]:
    """The sector and the parameters of ``model`` if it is a tuned :func:`fretwear.bladed_disk` with its
    shroud, as built (checked against a rebuild); else ``ValueError``."""
    info = model.info
    names = [f.name for f in fields(DiskSector)]
    if info.get("contacts") != "shroud" or any(n not in info for n in names):
        raise ValueError("the cyclic sector solve needs a bladed_disk model with contacts='shroud'")
    if np.any(np.asarray(info.get("mistuning", ()))):
        raise ValueError("the cyclic sector solve needs a tuned disk (mistuning zero); solve the full disk")
    params = {n: info[n] for n in names if n != "sectors"}
    keys = ("damping_ratio", "engine_order", "fex", "mu", "kn", "u0", "kt")
    rebuilt = bladed_disk(info["sectors"], **{k: info[k] for k in keys}, **params)
    same = all(
        np.array_equal(getattr(model, a), getattr(rebuilt, a))
        for a in ("M", "C", "K", "force_cos", "force_sin", "force_static")
    )
    if not same or model.friction != rebuilt.friction or model.normal:
        raise ValueError("the model was changed after bladed_disk built it; solve the full disk")
    return DiskSector(info["sectors"], **params), info


def is_tuned_disk(model: Model) -> bool:
    """Whether ``model`` is a tuned shrouded :func:`fretwear.bladed_disk` as built (:func:`tuned_disk`)."""
    if model.info.get("contacts") != "shroud":
        return False
    try:
        tuned_disk(model)
    except ValueError:
        return False
    return True


def samples_for(sectors: int, engine_order: int, harmonics: int) -> int:
    """Samples per period: the smallest even multiple of ``N / gcd(EO, N)`` ``>= default_samples(Nh)``,
    so that the delay from one sector to the next is a whole number of samples (module text)."""
    step = sectors // math.gcd(engine_order, sectors)
    step *= 2 if step % 2 else 1
    return step * -(-default_samples(harmonics) // step)


@dataclass(frozen=True)
class Sector:
    """The tuned disk's sector: what every frequency and wear state of a sector solve shares (the disk, its
    parameters, the one-contact model, the nodal-diameter matrices per harmonic order ``0..Nh``).

    Built by :meth:`of`; :meth:`solve` answers at one frequency and wear depth.
    """

    model: Model
    info: dict
    one: Model
    samples: int
    theta: np.ndarray  # (Nh + 1,) phase from one sector to the next per order (rad)
    K: np.ndarray  # (Nh + 1, 3, 3) K0 + K1 e^{i theta} + K1^T e^{-i theta} (N/m)
    C: np.ndarray  # (Nh + 1, 3, 3) modal damping at theta (N s/m)
    M0: np.ndarray

    @classmethod
    def of(cls, model: Model, harmonics: int, samples: int | None = None) -> Sector:
        """The sector of ``model`` (a tuned shrouded :func:`fretwear.bladed_disk`, checked) for ``Nh``."""
        sector, info = tuned_disk(model)
        if samples is None:
            samples = samples_for(info["sectors"], info["engine_order"], harmonics)
        theta = -2 * np.pi * np.arange(harmonics + 1) * info["engine_order"] / info["sectors"]
        K0, K1 = sector.stiffness()
        M0 = sector.mass
        K = K0 + K1 * np.exp(1j * theta)[:, None, None] + K1.T * np.exp(-1j * theta)[:, None, None]
        # Nh + 1 eigenproblems of size 3, once per sweep
        C = np.array([modal_damping(M0, Ki, info["damping_ratio"]) for Ki in K])
        one = replace(model, friction=model.friction[:1])  # contact 0 stands for all (module text)
        return cls(model, info, one, samples, theta, K, C, M0)

    def dynamic_stiffness(self, omega: float, orders: np.ndarray) -> np.ndarray:
        """``D_k`` (len(orders), 3, 3) of the module text at ``omega`` (rad/s)."""
        w = (orders * omega)[:, None, None]
        return self.K[orders] - w**2 * self.M0 + 1j * w * self.C[orders]

    def receptance(self, omega: float, basis: HarmonicBasis) -> Receptance:
        """``g_k`` and ``u_lin,k`` of the sector's contact in the real basis (module text)."""
        orders = _distinct_orders(basis)
        h = np.linalg.inv(self.dynamic_stiffness(omega, orders))[:, _TIP, _TIP]
        shift = 1 - np.exp(1j * self.theta[orders])
        g = (np.abs(shift) ** 2 * h)[:, None, None]
        u = (shift * h * self.info["fex"] * (orders == 1))[:, None]
        return Receptance(_real_blocks(g, basis), _real_vector(u, basis))

    def fields(self, problem: Problem, x: np.ndarray):
        """The full disk's march (force, slider, state of every contact) and DOF harmonics from the
        sector's unknowns ``x``, as a provider of :meth:`PeriodicSolution.build`."""

        def fields_() -> tuple[tuple, np.ndarray]:
            b, n_sec, H = problem.basis, self.info["sectors"], problem.basis.size
            # (a, b) of order k rotated by j theta_k: the complex amplitude a - i b times e^{i j theta_k}
            rot = self.theta[b.orders][None, :] * np.arange(n_sec)[:, None]  # (N, H)
            pair = _partner(b)
            x_all = np.cos(rot) * x + np.where(b.is_sine, -1, 1) * np.sin(rot) * x[pair] * (b.orders > 0)
            Ns = b.marched_samples
            lam, X = np.empty((n_sec, Ns)), np.empty((n_sec, Ns))
            st = np.empty((n_sec, Ns), dtype=np.int8)
            n = n_sec * H
            evaluate(x_all.ravel(), np.zeros((n, n)), np.zeros(n), np.full(n_sec, problem.eps[0]),
                     np.full(n_sec, JENKINS), np.full(n_sec, problem.limits[0]), b.synthesis, b.analysis,
                     b.half_wave, False, np.empty(n), np.empty((n_sec, H, H)), lam, X, st)  # fmt: skip
            lam_h = b.to_full(lam @ b.analysis.T)
            if b.half_wave:
                lam, X, st = np.hstack([lam, -lam]), np.hstack([X, -X]), np.hstack([st, st])
            # sector 0's DOFs: U_0,k = D_k^{-1} (F_k - e_tip (1 - e^{-i theta_k}) Lambda_k), then rotated
            orders = np.arange(problem.harmonics + 1)
            L = np.concatenate([lam_h[0, :1], lam_h[0, 1::2] - 1j * lam_h[0, 2::2]])
            rhs = np.zeros((len(orders), 3), dtype=complex)
            rhs[1, _TIP] = self.info["fex"]
            rhs[:, _TIP] -= (1 - np.exp(-1j * self.theta)) * L
            U0 = np.linalg.solve(self.dynamic_stiffness(problem.omega, orders), rhs[..., None])[..., 0]
            U = U0[None] * np.exp(
                1j * np.arange(n_sec)[:, None, None] * self.theta[None, :, None]
            )  # (N, k, 3)
            U = np.swapaxes(U, 1, 2).reshape(3 * n_sec, len(orders))
            dof = np.empty((3 * n_sec, 2 * problem.harmonics + 1))
            dof[:, 0], dof[:, 1::2], dof[:, 2::2] = U[:, 0].real, U[:, 1:].real, -U[:, 1:].imag
            return (lam, X, st, lam_h), dof

        return fields_

    def solve(
        self,
        omega: float,
        harmonics: int,
        guess=None,
        tol: float = 1e-10,
        max_iter: int = 50,
        wear: float = 0.0,
    ) -> PeriodicSolution:
        """The sector's solve at ``omega`` (rad/s), every contact worn ``wear`` (m), returned as the full
        disk's solution."""
        wear = float(wear)
        if not np.isfinite(wear) or wear < 0:
            raise ValueError(f"wear must be a finite depth >= 0 m (one for every contact), got {wear!r}")
        cond = lambda B, basis: self.receptance(omega, basis)  # noqa: E731
        problem = Problem(self.one, omega, harmonics, self.samples, np.array([wear]), condensed=cond)
        sol = solve_problem(problem, guess, tol, max_iter)
        n = len(self.model.friction)
        full = PeriodicSolution(
            model=self.model, omega=sol.omega, harmonics=sol.harmonics, samples=sol.samples,
            half_wave=sol.half_wave, path=sol.path, converged=sol.converged, iterations=sol.iterations,
            residual=sol.residual, message=sol.message, wear=np.full(n, wear),
            normal_loads=np.full(n, sol.normal_loads[0]), unknowns=sol.unknowns, problem=problem,
        )  # fmt: skip
        if problem.n_active:
            full._fields = self.fields(problem, sol.unknowns)
        return full


def _partner(basis: HarmonicBasis) -> np.ndarray:
    """Slot of the other member (cos <-> sin) of each slot's order; the mean is its own partner."""
    slots = np.arange(basis.size)
    key = {(int(k), bool(s)): i for i, (k, s) in enumerate(zip(basis.orders, basis.is_sine, strict=True))}
    return np.array([key.get((int(k), not s), i) for i, k, s in zip(slots, basis.orders, basis.is_sine,
                                                                    strict=True)])  # fmt: skip


def solve_sector(
    model: Model,
    omega: float,
    harmonics: int = 7,
    *,
    samples: int | None = None,
    wear: float = 0.0,
    guess: np.ndarray | None = None,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> PeriodicSolution:
    """Periodic response of the tuned shrouded disk at ``omega`` (rad/s) solved on one sector.

    Parameters
    ----------
    model : Model
        A tuned :func:`fretwear.bladed_disk` with ``contacts="shroud"`` (checked).
    omega : float
        Excitation frequency (rad/s), > 0.
    harmonics : int
        Highest harmonic ``Nh``.
    samples : int, optional
        Time samples per period; default :func:`samples_for` (module text).
    wear : float
        Worn depth of every shroud contact (m), >= 0: a tuned disk wears them alike.
    guess, tol, max_iter
        As :func:`fretwear.solve_periodic` (``guess``: the sector's unknowns).

    Returns
    -------
    PeriodicSolution
        The full disk's solution (every DOF and contact), as the full solve
        returns it; ``unknowns`` and ``problem`` are the sector's.
    """
    (omega,) = check_omegas([omega])
    return Sector.of(model, harmonics, samples).solve(omega, harmonics, guess, tol, max_iter, wear)


def sweep_sector(
    model: Model,
    omegas,
    harmonics: int = 7,
    *,
    samples: int | None = None,
    wear: float = 0.0,
    tol: float = 1e-10,
    max_iter: int = 50,
) -> Sweep:
    """:func:`solve_sector` at each of ``omegas`` (rad/s), each from the secant prediction of its two
    predecessors (as :func:`fretwear.sweep`); the options as :func:`solve_sector`."""
    omegas = check_omegas(omegas)
    sector = Sector.of(model, harmonics, samples)
    out, previous = [], []
    for omega in omegas:
        guess = None
        if len(previous) >= 2:
            (w0, x0), (w1, x1) = previous[-2:]
            guess = x1 + (omega - w1) / (w1 - w0) * (x1 - x0)
        elif previous:
            guess = previous[-1][1]
        sol = sector.solve(omega, harmonics, guess, tol, max_iter, wear)
        out.append(sol)
        if sol.converged and sol.unknowns.size:
            previous.append((omega, sol.unknowns))
    return Sweep(out)
