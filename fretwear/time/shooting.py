"""Periodic solutions by shooting on the exact event-driven integrator.

:func:`shooting` solves ``y(T; y0) = y0`` by Newton's method with the exact
monodromy matrix of ``fretwear.time.integrator`` (compiled: every Newton
iteration and period march runs in :mod:`fretwear.time.periodic`);
:func:`steady_state` marches periods until the transient has died out;
:func:`shooting_sweep` follows a frequency grid, each solve seeded by its
predecessor. The result, :class:`ShootingSolution`, has the attributes of
:class:`fretwear.response.PeriodicResponse`.

Cold start (no guess): Newton from the linear steady state with every loaded
contact rigid (exact when it keeps the contacts inside their friction cones),
then, if that fails, from the state reached by marching periods from there
(the transient decays towards a stable orbit), with longer marches between
restarts. A solve that does not converge is reported (``converged=False``,
``message``), never raised.
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, partial

import numpy as np

from .._fields import item
from ..model import STICK, Model
from . import periodic
from .codes import DEGENERATE, NEED_PATTERN, NEED_SPACE, NONFINITE, OK
from .integrator import (
    ContactEvent,
    Records,
    Trajectory,
    check_state,
    engine,
    engine_loads,
    make_trajectory,
    recorded,
    slip_forces,
)
from .patterns import Table

__all__ = ["ShootingSolution", "shooting", "periodic_state", "steady_state", "shooting_sweep"]

_MARCHES = (20, 100, 400)  # periods marched before the second, third and fourth Newton starts
_MAX_PHASES = 1_000_000  # per period: more is a degenerate cascade
# the outputs of :func:`periodic.solve` per problem, in the order of its ``results``
_RESULTS = ("y0", "y1", "converged", "iterations", "J", "sliding", "work", "viscous", "fre", "fim", "hi",
            "lo", "neutral")  # fmt: skip


@dataclass(frozen=True, eq=False)
class ShootingSolution:
    """Periodic response found by :func:`shooting` (or :func:`steady_state`).

    Signals are sampled over one period on the uniform grid ``t_k = k T / N``
    (computed on first access, from the exact solution).

    Attributes
    ----------
    model : Model
    omega : float
        Excitation frequency (rad/s); ``period = 2 pi / omega`` (s).
    y0 : ndarray, shape (2 n,) or (2 n + n_friction,)
        Periodic state ``(u, v)`` at ``t = 0`` (also :attr:`unknowns`); with
        Jenkins contacts ``(u, v, lambda)``, their forces (N) included.
    converged : bool
    iterations : int
        Newton iterations (:func:`shooting`, summed over its starts) or
        periods marched (:func:`steady_state`).
    residual : float
        Periodicity residual ``|y(T) - y(0)| / |y(0)|`` with velocities scaled
        by ``1 / omega`` and Jenkins forces by ``1 / kt`` (dimension of a displacement).
    message : str
        Reason of a failure, empty on success.
    monodromy : ndarray, shape (len(y0), len(y0))
        ``dy(T)/dy(0)``, exact, including the saltation matrices of the events.
    floquet_multipliers : ndarray, shape (len(y0),)
        Eigenvalues of ``monodromy``, by decreasing modulus. A rigid contact
        that sticks during the period annihilates perturbations of its
        relative velocity, a Jenkins contact that slips those of its force
        (multiplier 0).
    neutral_multipliers : int
        How many of the multipliers are the neutral ``1`` of a stuck offset:
        each contact stuck during the whole period can stick at any offset (the
        periodic orbits then form a family), which leaves its relative
        displacement unchanged over a period.
    wear, normal_loads, slip_forces : ndarray, shape (n_friction,)
        Wear depth (m), normal load (N) and slip force ``mu F_N`` (N) per contact.
    samples : int
        Number ``N`` of uniform samples of the period in the time histories.
    first_harmonic : ndarray, shape (n, 2)
        Exact first Fourier coefficients ``(a1, b1)`` of each DOF (m),
        ``u ~ a1 cos(omega t) + b1 sin(omega t)``.
    half_peak_to_peak : ndarray, shape (n,)
        ``(max u - min u) / 2`` of each DOF over the period (m), exact extrema.
    relative_half_peak_to_peak : ndarray, shape (n_friction,)
        Same for the relative displacement of each friction contact (m).
    sliding_distance, friction_energy : ndarray, shape (n_friction,)
        Per period, exact (m, J).
    input_work, viscous_dissipation : float
        Per period (J); ``input_work = viscous_dissipation + friction_energy.sum()``
        on a periodic orbit.
    events : tuple of ContactEvent
        Contact state changes over one period.
    trajectory : Trajectory or None
        The exact motion over one period from ``y0`` (dense output:
        ``trajectory.evaluate(times)``); None when even that failed.
    """

    model: Model
    omega: float
    y0: np.ndarray
    converged: bool
    iterations: int
    residual: float
    message: str
    monodromy: np.ndarray
    neutral_multipliers: int
    wear: np.ndarray
    normal_loads: np.ndarray
    slip_forces: np.ndarray
    samples: int
    first_harmonic: np.ndarray
    half_peak_to_peak: np.ndarray
    relative_half_peak_to_peak: np.ndarray
    sliding_distance: np.ndarray
    friction_energy: np.ndarray
    input_work: float
    viscous_dissipation: float
    _orbit: Callable[[], Trajectory] | None = field(repr=False)

    @cached_property
    def trajectory(self) -> Trajectory | None:
        """The exact motion over one period from ``y0`` (built on first access); None if it failed."""
        return None if self._orbit is None else self._orbit()

    @property
    def events(self) -> tuple[ContactEvent, ...]:
        """Contact state changes over one period."""
        return () if self.trajectory is None else self.trajectory.events

    @property
    def period(self) -> float:
        """Excitation period ``2 pi / omega`` (s)."""
        return 2 * np.pi / self.omega

    @property
    def frequency(self) -> float:
        """Excitation frequency (Hz)."""
        return self.omega / (2 * np.pi)

    @property
    def path(self) -> str:
        """How the solution was found: ``"shooting"``."""
        return "shooting"

    @property
    def unknowns(self) -> np.ndarray:
        """The shooting unknowns, the state ``y0`` at ``t = 0``: the guess of a neighbouring solve."""
        return self.y0

    @property
    def amplitude(self) -> np.ndarray:
        """First-harmonic amplitude ``sqrt(a1^2 + b1^2)`` of each DOF (m), shape (n,)."""
        return np.hypot(self.first_harmonic[:, 0], self.first_harmonic[:, 1])

    @property
    def relative_amplitude(self) -> np.ndarray:
        """First-harmonic amplitude of the relative displacement of each contact (m), shape (n_friction,)."""
        rel = self.model.relative_map(self.model.friction) @ self.first_harmonic
        return np.hypot(rel[:, 0], rel[:, 1])

    @cached_property
    def floquet_multipliers(self) -> np.ndarray:
        """Eigenvalues of :attr:`monodromy`, by decreasing modulus, shape (2 n,)."""
        if not np.all(np.isfinite(self.monodromy)):
            return np.full(len(self.monodromy), np.nan + 0j)
        mult = np.linalg.eigvals(self.monodromy)
        return mult[np.argsort(-np.abs(mult), kind="stable")]

    @property
    def stable(self) -> bool:
        """True when every multiplier but the neutral ones lies strictly inside the unit circle."""
        mult = self.floquet_multipliers
        rest = np.delete(mult, np.argsort(np.abs(mult - 1))[: self.neutral_multipliers])
        return bool(np.abs(rest).max(initial=0.0) < 1.0)

    # -- time histories (computed on first access) ---------------------------------
    @cached_property
    def _histories(self) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        times = np.arange(self.samples) * (self.period / self.samples)
        nf, n = len(self.model.friction), self.model.n_dofs
        if self.trajectory is None:
            nan = np.full((2 * n, self.samples), np.nan)
            codes = np.full((nf, self.samples), STICK, np.int8)
            return times, nan, np.full((nf, self.samples), np.nan), codes
        states, forces, codes = self.trajectory.evaluate(times)
        return times, states, forces, codes

    time = item("_histories", 0, "Sample times ``k T / N`` (s), shape (N,).")

    def to_xarray(self):
        """The solution as an ``xarray.Dataset``, with units and long names.

        As :meth:`fretwear.hbm.PeriodicSolution.to_xarray` (``contact``: the friction contacts).
        """
        from .._xarray import periodic_dataset

        return periodic_dataset(self)

    def _repr_html_(self) -> str:
        from .._html import summary_html

        return summary_html(self)

    @property
    def displacement(self) -> np.ndarray:
        """DOF displacements (m), shape (n, N)."""
        return self._histories[1][: self.model.n_dofs]

    @property
    def velocity(self) -> np.ndarray:
        """DOF velocities (m/s), shape (n, N)."""
        return self._histories[1][self.model.n_dofs :]

    @property
    def relative_displacement(self) -> np.ndarray:
        """``u_r = B u`` of every contact (m), shape (n_friction, N)."""
        return self.model.relative_map(self.model.friction) @ self.displacement

    contact_force = item("_histories", 2, "Friction force of every contact (N), shape (n_friction, N).")
    state = item("_histories", 3, ":data:`~fretwear.model.STICK`, ``SLIP`` or ``OPEN`` of every contact, "
                 "shape (n_friction, N).")  # fmt: skip


# ---------------------------------------------------------------------------
# the solver
# ---------------------------------------------------------------------------
_STATUS = {
    DEGENERATE: "a cascade of contact events at one instant could not be resolved",
    NONFINITE: "the motion became unbounded (non-finite state)",
}
_START_NAMES = {
    periodic.GUESS_START: "the guess",
    periodic.EXTRAPOLATED_START: "the extrapolated neighbours",
    periodic.NEIGHBOUR_START: "the neighbour",
    periodic.RIGID_START: "the rigid linear state",
}


def _scaled_norm(n: int, omega: float, y: np.ndarray, kt: np.ndarray) -> float:
    """``|(u, v / omega, lambda / kt)|`` (m); ``lambda``: the forces of Jenkins contacts (else no ``kt``)."""
    u, v, f = y[:n], y[n : 2 * n] / omega, y[2 * n :] / kt
    return math.sqrt(float(u @ u + v @ v + f @ f))


def _rigid_states(table: Table, g: np.ndarray, at: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The linear steady states with every loaded contact rigid (``B u = 0``), one per problem.

    Problem ``p`` is frequency ``at[p]`` of ``table`` with slip forces ``g[p]``.
    Returns their states at ``t = 0``, shape (P, 2 n), and whether each is
    the periodic orbit: every loaded contact's force ``lambda_s + Re(Lambda
    exp(i omega t))`` stays within its slip limit, ``|lambda_s| + |Lambda| <= g``
    (``B^T lambda = F - Z(omega) U`` is solved exactly for ``lambda``). What
    does not depend on ``g`` is kept in ``table.rigid`` per set of loaded contacts.
    """
    states, ok = np.empty((len(at), table.ny)), np.empty(len(at), dtype=np.bool_)
    loaded = g > 0
    for row in np.unique(loaded, axis=0):  # problems with the same loaded contacts
        mine = np.all(loaded == row, axis=1)
        active = np.flatnonzero(row).tolist()
        mask = sum(1 << j for j in active)
        if mask not in table.rigid:
            table.rigid[mask] = _rigid_response(table, active)
        rigid, static, amplitude = table.rigid[mask]
        w = at[mine]
        states[mine] = rigid[w]
        if static is None:  # no stuck motion (ok False) or no loaded contact (ok True)
            ok[mine] = amplitude
        else:
            a = amplitude[w]
            ok[mine] = np.all(static + a <= g[mine][:, active], axis=1) & np.all(np.isfinite(a), axis=1)
    return states, ok


def _rigid_response(table: Table, active: list[int]) -> tuple:
    """``(states, |lambda_s|, |Lambda|)`` of :func:`_rigid_states` for the loaded contacts ``active``."""
    if len(table.kt):
        return _jenkins_response(table, active)
    N, Kr, Mr, Cr, f, u_static = table.structure.rigid_basis(sum(1 << j for j in active))
    model, w = table.model, table.omegas
    W = len(w)
    if N.shape[1] == 0:
        return np.zeros((W, 2 * table.n)), None, False
    Z = Kr - w[:, None, None] ** 2 * Mr + 1j * w[:, None, None] * Cr
    try:
        U = np.linalg.solve(Z, np.broadcast_to(f, (W, len(f)))[..., None])[..., 0]
    except np.linalg.LinAlgError:  # resonance of the stuck structure without damping
        U = np.array([np.linalg.lstsq(Zi, f, rcond=None)[0] for Zi in Z])
    U = U @ N.T
    states = np.hstack([u_static + U.real, (1j * w[:, None] * U).real])
    if not active:
        return states, None, True
    Ba = table.B[active]
    solve = np.linalg.solve(Ba @ Ba.T, Ba)  # B_a^T lambda = r  ->  lambda = (B_a B_a^T)^-1 B_a r
    Zfull = model.K - w[:, None, None] ** 2 * model.M + 1j * w[:, None, None] * model.C
    r = (model.force_cos - 1j * model.force_sin) - np.einsum("wij,wj->wi", Zfull, U)
    amplitude = np.abs(r @ solve.T)
    static = np.abs(solve @ (model.force_static - model.K @ u_static))
    return states, static, amplitude


def _jenkins_response(table: Table, active: list[int]) -> tuple:
    """:func:`_rigid_response` of a Jenkins model: the loaded contacts stuck, their springs ``k_t``.

    The stuck forces are ``lambda = k_t B u`` (the sliders at zero), the state
    ``(u, v, lambda)``; ``|lambda_s|`` and ``|Lambda|`` of the loaded contacts.
    """
    model, w, n = table.model, table.omegas, table.n
    kt = np.zeros(table.nf)
    kt[active] = table.kt[active]
    Ks = model.K + table.B.T @ (kt[:, None] * table.B)
    Z = Ks - w[:, None, None] ** 2 * model.M + 1j * w[:, None, None] * model.C
    f = model.force_cos - 1j * model.force_sin
    try:
        U = np.linalg.solve(Z, np.broadcast_to(f, (len(w), n))[..., None])[..., 0]
    except np.linalg.LinAlgError:  # resonance of the stuck structure without damping
        U = np.array([np.linalg.lstsq(Zi, f, rcond=None)[0] for Zi in Z])
    u_static = np.linalg.lstsq(Ks, model.force_static, rcond=None)[0]
    lam_static, Lam = kt * (table.B @ u_static), (kt * (table.B @ U.T).T)
    states = np.hstack([u_static + U.real, (1j * w[:, None] * U).real, lam_static + Lam.real])
    if not active:
        return states, None, True
    return states, np.abs(lam_static[active]), np.abs(Lam[:, active])


def _message(kinds, codes, residuals, tol: float) -> str:
    """Why a solve failed, from its log of Newton starts."""
    tried = []
    for kind, code, residual in zip(kinds, codes, residuals, strict=True):
        name = _START_NAMES.get(int(kind), f"{_MARCHES[int(kind) - periodic.MARCH_START]} periods marched")
        why = f"residual {residual:.2e}" if code == periodic.NOT_CONVERGED else _STATUS.get(int(code), "")
        tried.append(f"from {name}: {why}")
    return f"Newton on the period map did not reach the tolerance {tol:.1e} ({'; '.join(tried)})"


def _solution(table: Table, i: int, g, loads, wear, y0, y1, converged: bool, iterations: int, message: str,
              samples: int, J, neutral: int, fourier, hi, lo, sliding, work: float, viscous: float,
              orbit: Callable[[], Trajectory] | None) -> ShootingSolution:  # fmt: skip
    """The :class:`ShootingSolution` at frequency ``i`` of ``table`` (NaN quantities without ``orbit``)."""
    n, nf = table.n, table.nf
    omega = float(table.omegas[i])
    wear = np.zeros(nf) if wear is None else np.asarray(wear, dtype=float)
    if orbit is None:
        nan, fnan = np.full(n, np.nan), np.full(nf, np.nan)
        return ShootingSolution(
            model=table.model, omega=omega, y0=y0, converged=False, iterations=int(iterations),
            residual=np.inf, message=message, monodromy=np.full((table.ny, table.ny), np.nan),
            neutral_multipliers=0, wear=wear, normal_loads=loads, slip_forces=g, samples=samples,
            first_harmonic=np.full((n, 2), np.nan), half_peak_to_peak=nan, relative_half_peak_to_peak=fnan,
            sliding_distance=fnan, friction_energy=fnan, input_work=np.nan, viscous_dissipation=np.nan,
            _orbit=None,
        )  # fmt: skip
    coef = 2 / table.periods[i] * fourier
    hpp = (hi - lo) / 2
    kt = table.kt
    return ShootingSolution(
        model=table.model,
        omega=omega,
        y0=y0,
        converged=converged,
        iterations=int(iterations),
        residual=_scaled_norm(n, omega, y1 - y0, kt) / max(_scaled_norm(n, omega, y0, kt), 1e-300),
        message=message,
        monodromy=J,
        neutral_multipliers=int(neutral),
        wear=wear,
        normal_loads=loads,
        slip_forces=g,
        samples=samples,
        first_harmonic=np.column_stack([coef.real, -coef.imag]),
        half_peak_to_peak=hpp[:n],
        relative_half_peak_to_peak=hpp[n:],
        sliding_distance=sliding,
        friction_energy=g * sliding,
        input_work=float(work),
        viscous_dissipation=float(viscous),
        _orbit=orbit,
    )


def _orbits(table: Table, at: np.ndarray, g: np.ndarray, guesses: list, chain: bool, tol: float,
            max_iter: int, transient_periods: int, path: np.ndarray | None = None,
            reuse: float | np.ndarray = 0.0) -> dict:  # fmt: skip
    """Periodic orbits of the problems ``(at[p], g[p])`` in one compiled call (:func:`periodic.solve`).

    Problem ``p``: frequency ``at[p]`` of ``table`` with slip forces ``g[p]``
    (N, shape (nf,)); ``guesses[p]``: the states tried first; ``chain``: then
    the orbits extrapolated along ``path`` (default the frequencies) and the
    previous orbit; ``reuse`` (per problem or one for all): a converged Newton
    whose last step is at most this (relative) keeps its last evaluated period
    as the recorded one (default 0: only a verified state). Returns the kernel's
    outputs per problem (arrays with a first axis of length P) and the
    records (``rec``, ``offsets``).
    """
    P, n, nf, D = len(at), table.n, table.nf, table.dim
    n2 = table.ny  # the size of the state y
    at = np.ascontiguousarray(at, dtype=np.int64)
    g = np.ascontiguousarray(g, dtype=float)
    path = table.omegas[at] if path is None else np.ascontiguousarray(path, dtype=float)
    reuse = np.ascontiguousarray(np.broadcast_to(reuse, (P,)), dtype=float)
    G = max((len(q) for q in guesses), default=0)
    guess_array = np.zeros((P, max(G, 1), n2))
    for p, q in enumerate(guesses):
        for k, y in enumerate(q):
            guess_array[p, k] = y
    n_guesses = np.array([len(q) for q in guesses], dtype=np.int64)
    marches = np.array([m for m in _MARCHES if m <= transient_periods], dtype=np.int64)
    A = G + 3 + len(marches)
    out = {
        "y0": np.zeros((P, n2)), "y1": np.zeros((P, n2)), "converged": np.zeros(P, dtype=np.bool_),
        "iterations": np.zeros(P, dtype=np.int64), "att_kind": np.zeros((P, A), np.int64),
        "att_code": np.zeros((P, A), np.int64), "att_res": np.zeros((P, A)), "n_att": np.zeros(P, np.int64),
        "J": np.zeros((P, n2, n2)), "sliding": np.zeros((P, nf)), "work": np.zeros(P), "viscous": np.zeros(P),
        "fre": np.zeros((P, n)), "fim": np.zeros((P, n)), "hi": np.zeros((P, len(table.extrema_rows))),
        "lo": np.zeros((P, len(table.extrema_rows))), "neutral": np.zeros(P, dtype=np.int64),
    }  # fmt: skip
    offsets = tuple(np.zeros(P + 1, dtype=np.int64) for _ in range(3))
    per_period = int(1.5 * np.max(table.periods[:, None] / table.step[:, : table.count])) + 16
    rec = Records.empty(P * per_period, P * 8 + 16, D, nf)
    rigid, rigid_ok = _rigid_states(table, g, at)
    starts = (guess_array, n_guesses, rigid, rigid_ok, marches)
    options = (bool(chain), float(tol), int(max_iter), _MAX_PHASES)
    results = tuple(out[k] for k in _RESULTS)
    attempts = tuple(out[k] for k in ("att_kind", "att_code", "att_res", "n_att"))
    start = 0
    while True:
        status, need, start = periodic.solve(
            table.model_arrays, table.omegas, table.stacked(), (at, path, g, reuse), starts, options,
            table.extrema_rows, start, results, attempts, offsets, rec.packed(),
        )  # fmt: skip
        if status == NEED_PATTERN:
            table.require(int(need))
        elif status == NEED_SPACE:
            rec = rec.grown(2)
        else:
            break
    out["rec"], out["offsets"] = rec, offsets
    return out


def _solve(table: Table, g: np.ndarray, loads: np.ndarray, wear, guesses: list, chain: bool, tol: float,
           max_iter: int, samples: int, transient_periods: int) -> list[ShootingSolution]:  # fmt: skip
    """Periodic orbits at every frequency of ``table`` with slip forces ``g`` (:func:`_orbits`).

    ``guesses[i]``: the states tried first at frequency ``i``; ``chain``: then
    the extrapolated and the previous orbits of the sweep.
    """
    W = len(table.omegas)
    o = _orbits(table, np.arange(W), np.tile(g, (W, 1)), guesses, chain, tol, max_iter, transient_periods)
    rec, y0, y1, conv, J, slid = o["rec"], o["y0"], o["y1"], o["converged"], o["J"], o["sliding"]
    fourier = o["fre"] + 1j * o["fim"]
    out = []
    for i in range(W):
        n_att = o["n_att"][i]
        message = "" if conv[i] else _message(o["att_kind"][i, :n_att], o["att_code"][i, :n_att],
                                              o["att_res"][i, :n_att], tol)  # fmt: skip
        (s0, s1), (p0, p1), (e0, e1) = (off[i : i + 2] for off in o["offsets"])
        orbit = None
        if s1 > s0:
            orbit = partial(make_trajectory, table, i, rec, slice(s0, s1), slice(p0, p1), slice(e0, e1),
                            t0=0.0, t1=table.periods[i], times=None, y=y1[i], J=J[i], sliding=slid[i], g=g,
                            work=o["work"][i], viscous=o["viscous"][i], fourier=fourier[i])  # fmt: skip
        else:
            message = f"{message}; the orbit could not be evaluated (its period march failed)".lstrip("; ")
        out.append(_solution(table, i, g, loads, wear, y0[i], y1[i], bool(conv[i]), o["iterations"][i],
                             message, samples, J[i], o["neutral"][i], fourier[i], o["hi"][i], o["lo"][i],
                             slid[i], o["work"][i], o["viscous"][i], orbit))  # fmt: skip
    return out


def _check_samples(samples: int) -> int:
    if isinstance(samples, bool) or not isinstance(samples, (int, np.integer)) or samples < 4:
        raise ValueError(f"samples must be an integer >= 4, got {samples!r}")
    return int(samples)


def _check_options(tol: float, max_iter: int, transient_periods: int) -> None:
    if isinstance(tol, bool) or not (isinstance(tol, (int, float, np.floating)) and 0 < tol < 1):
        raise ValueError(f"tol (relative periodicity residual) must be in (0, 1), got {tol!r}")
    for name, value in (("max_iter", max_iter), ("transient_periods", transient_periods)):
        if isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 0:
            raise ValueError(f"{name} must be an integer >= 0, got {value!r}")


def shooting(
    model: Model,
    omega: float,
    y_guess=None,
    *,
    wear=None,
    tol: float = 1e-12,
    max_iter: int = 30,
    samples: int = 512,
    transient_periods: int = 400,
) -> ShootingSolution:
    """Periodic response by shooting: Newton on ``y0 - P(y0) = 0``, ``P`` the period map.

    The Jacobian is the exact monodromy matrix (step propagators and event
    saltation matrices). Newton steps are least-squares steps (the Jacobian
    is singular on orbits stuck during the whole period, whose stuck offset is
    arbitrary) with backtracking on the periodicity residual; a start whose
    residual has not halved over 6 iterations is abandoned for the next one.

    Parameters
    ----------
    model, omega
        As :func:`~fretwear.time.integrate` (friction contacts only, rad/s).
    y_guess : array_like, shape (2 n,), optional
        Guess of the state at ``t = 0`` (e.g. the :attr:`~ShootingSolution.unknowns`
        of a neighbouring solution). Without one, or if Newton fails from it,
        the cold start of the module docstring follows.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    tol : float
        Target periodicity residual (see :attr:`ShootingSolution.residual`), in (0, 1).
    max_iter : int
        Largest number of Newton iterations per start.
    samples : int
        Number ``N`` of uniform samples of the period in the time histories.
    transient_periods : int
        Largest number of periods marched before a restart (marches of 20,
        100 and 400 periods, up to this number; 0: no marching).

    Returns
    -------
    ShootingSolution
        ``iterations`` counts the Newton iterations of every start; a solve
        that fails has ``converged=False`` and says why in ``message``.
    """
    eng, g, loads = engine_loads(model, omega, wear)
    samples = _check_samples(samples)
    _check_options(tol, max_iter, transient_periods)
    guesses = [[] if y_guess is None else [check_state(eng, y_guess, "y_guess")]]
    return _solve(eng, g, loads, wear, guesses, False, tol, max_iter, samples, transient_periods)[0]


def shooting_sweep(model: Model, omegas, **options) -> list[ShootingSolution]:
    """Exact periodic responses by :func:`shooting` at ``omegas`` (rad/s), each seeded by its predecessors.

    At ``omega_k``, the rigid linear state is taken when it is periodic (a
    stuck orbit: the member of the family without offset, as a cold solve
    gives). Otherwise Newton starts from the linear extrapolation in
    ``omega`` of the :attr:`~ShootingSolution.unknowns` of the two previous
    solutions (when both converged with the same, non-zero number of events),
    then from the previous unknowns themselves, then cold as :func:`shooting`. A solve that
    fails is kept in the list (``converged=False``, with its ``message``). The
    whole sweep runs in one compiled call.

    Parameters
    ----------
    model : Model
    omegas : array_like
        Excitation frequencies (rad/s), in the order of the sweep.
    **options
        Keyword arguments of :func:`shooting` but ``y_guess``: ``wear``,
        ``tol``, ``max_iter``, ``samples``, ``transient_periods``.
    """
    unknown = set(options) - {"wear", "tol", "max_iter", "samples", "transient_periods"}
    if unknown:
        raise TypeError(f"shooting_sweep got unexpected options {sorted(unknown)}")
    if not isinstance(model, Model):
        raise TypeError(f"model must be a fretwear.model.Model, got {type(model).__name__}")
    omegas = np.atleast_1d(np.asarray(omegas, dtype=float))
    if omegas.ndim != 1 or omegas.size == 0 or not np.all(np.isfinite(omegas) & (omegas > 0)):
        raise ValueError(
            "omegas must be a non-empty 1-D array of finite positive angular frequencies (rad/s)"
        )
    wear = options.get("wear")
    g, loads = slip_forces(model, wear)
    tol, max_iter = options.get("tol", 1e-12), options.get("max_iter", 30)
    transient_periods = options.get("transient_periods", 400)
    samples = _check_samples(options.get("samples", 512))
    _check_options(tol, max_iter, transient_periods)
    table = Table(model, omegas)
    return _solve(
        table, g, loads, wear, [[] for _ in omegas], True, tol, max_iter, samples, transient_periods
    )


def periodic_state(
    model: Model, omega: float, y_guess, *, wear=None, tol: float = 1e-12, max_iter: int = 30
) -> tuple[np.ndarray, bool]:
    """State at ``t = 0`` of the periodic orbit reached by Newton from ``y_guess``.

    The Newton iterations of :func:`shooting` from one start, without its
    post-processing (extrema, Floquet multipliers): a cheap projection of a
    nearby state onto the periodic orbit, e.g. to follow an orbit that drifts
    with wear.

    Parameters
    ----------
    model, omega, wear
        As :func:`shooting`.
    y_guess : array_like, shape (2 n,)
        Starting state ``(u, v)`` at ``t = 0`` (m, m/s).
    tol : float
        Target periodicity residual (see :attr:`ShootingSolution.residual`).
    max_iter : int
        Largest number of Newton iterations.

    Returns
    -------
    y0 : ndarray, shape (2 n,)
        Periodic state (the last iterate when Newton fails).
    converged : bool
    """
    eng, g = engine(model, omega, wear)
    _check_options(tol, max_iter, 0)
    y = check_state(eng, y_guess, "y_guess")
    while True:
        status, need, y1, converged, *_ = periodic.newton(
            eng.model_arrays, eng.omega, eng.arrays(), g, y, tol, max_iter, _MAX_PHASES, 0.0,
            periodic.no_records(),
        )  # fmt: skip
        if status != NEED_PATTERN:
            return (y1, converged) if status == OK else (y, False)
        eng.require(int(need))


def steady_state(
    model: Model,
    omega: float,
    y_guess=None,
    *,
    wear=None,
    max_periods: int = 20_000,
    tol: float = 1e-10,
    samples: int = 512,
) -> ShootingSolution:
    """Periodic response by plain time marching, period after period.

    Independent of :func:`shooting` (no Newton, no Jacobian). With light
    damping the transient decays slowly: seed it with a good guess. The
    marching stops when the change over one period falls below ``tol``
    (relative, velocities scaled by ``1 / omega``); the distance to the
    periodic orbit is then about ``tol / (1 - |mu_max|)``, ``mu_max`` the
    largest Floquet multiplier.

    Parameters
    ----------
    model : Model
    omega : float
        Excitation angular frequency (rad/s), > 0.
    y_guess : array_like, shape (2 n,), optional
        Initial state at ``t = 0``; default the linear steady state with
        every loaded contact rigid.
    wear : array_like, shape (n_friction,), optional
        Wear depth of each friction contact (m).
    max_periods : int
        Largest number of periods marched.
    tol : float
        Convergence tolerance on the change over one period.
    samples : int
        Number of uniform samples of the period in the time histories.

    Returns
    -------
    ShootingSolution
        With ``iterations`` the number of periods marched.
    """
    eng, g, loads = engine_loads(model, omega, wear)
    samples = _check_samples(samples)
    if y_guess is None:
        y = _rigid_states(eng, g[None], np.zeros(1, np.int64))[0][0]
    else:
        y = check_state(eng, y_guess, "y_guess").copy()
    while True:
        status, need, y, marched, change = periodic.settle(
            eng.model_arrays, eng.omega, eng.arrays(), g, y, int(max_periods), float(tol), _MAX_PHASES
        )
        if status != NEED_PATTERN:
            break
        eng.require(int(need))
    converged = status == OK and change <= tol
    if status != OK:
        message = _STATUS[status]
    elif not converged:
        message = f"the change over one period is {change:.2e} > tol = {tol:.1e} after {marched} periods"
    else:
        message = ""
    try:
        traj, hi, lo = recorded(eng, g, y, 0.0, eng.period, None, jacobian=True, rows=eng.extrema_rows)
    except RuntimeError as exc:
        message = f"{message}; the orbit could not be evaluated: {exc}".lstrip("; ")
        return _solution(eng, 0, g, loads, wear, y, y, False, marched, message, samples, None, 0, None, None,
                         None, None, np.nan, np.nan, None)  # fmt: skip
    neutral = int(np.sum(np.all(traj.segment_state == STICK, axis=0) & (g > 0)))
    return _solution(eng, 0, g, loads, wear, y, traj.y, converged, marched, message, samples, traj.jacobian,
                     neutral, traj.fourier, hi, lo, traj.sliding_distance, traj.input_work,
                     traj.viscous_dissipation, partial(lambda t: t, traj))  # fmt: skip
