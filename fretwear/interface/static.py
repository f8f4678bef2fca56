"""Quasi-static contact of an interface: Hertz and Cattaneo-Mindlin anchors.

The static problem is eq. 12 at ``omega = 0``: ``Z_0 q + lambda = F`` on the
contact coordinates (:class:`~fretwear.interface.reduction.ContactCondensation`),
with the node law of the DLFT (eq. 19-23) applied once per load increment
instead of once per time sample: for pair ``i``, with ``lambda_u = F - Z_0 q +
eps q``,

* normal: the predicted force ``lambda_u,N - eps_N g_i`` (``g_i`` the gap plus
  wear) closes the pair when compressive, else the pair separates (eq. 21);
* tangential: stick is predicted, ``lambda_u,T - eps_T X_i`` with ``X_i`` the
  slip variable of the previous increment; beyond the friction limit ``mu
  lambda_N`` of the same increment the pair slips (eq. 23) and ``X_i`` moves.

Each increment is solved by Newton's method on this piecewise-linear
residual (exact Jacobian). The load path is the one of the fretting test: the
normal load ``P`` in ``normal_steps`` increments, then the tangential load
``Q`` from 0 in ``tangential_steps`` increments. With identical pad and flat
materials the converged solution reproduces:

* Hertz: ``a = sqrt(4 P R / (pi E*))``, ``p(x) = p0 sqrt(1 - x^2 / a^2)``,
  ``p0 = 2 P / (pi a)``;
* Cattaneo-Mindlin: stick zone ``|x| < c`` with ``c = a sqrt(1 - Q / (mu P))``;
  for ``Q >= mu P`` no static equilibrium exists (gross slip).

Half-widths are measured from the nodal forces by second moments, which are
exact for the elliptical distributions of the theory and use every node
(node counting would only bracket them to within one spacing): ``a = 2
sqrt(sum F_i (x_i - xbar)^2 / sum F_i)`` on the normal forces, and ``c`` the
same on the stick-zone deficit ``mu F_N,i - sign(Q) F_T,i`` (zero in the slip
zone, ``mu p0 (c / a) sqrt(1 - x^2 / c^2)`` per unit length in the stick zone).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from ..model import Model, craig_bampton
from ..model.structure import OPEN, SLIP, STICK
from .fe import CylinderOnFlat, cylinder_on_flat, hertz_half_width, hertz_peak_pressure
from .interrupt import check_interrupt
from .reduction import ContactCondensation

__all__ = [
    "StaticState",
    "StaticResult",
    "solve_static",
    "check_q_ratio",
    "second_moment_half_width",
    "second_moment_radius",
    "static_anchors",
    "static_benchmark",
]


@dataclass
class StaticState:
    """Converged state of one load increment.

    Attributes
    ----------
    q : ndarray, shape (2 nc,)
        Contact coordinates ``(u_T, u_N)`` per pair (m).
    normal_force, tangential_force : ndarray, shape (nc,)
        ``lambda_N >= 0`` and ``lambda_T`` per pair (N, or N/m per unit thickness).
    slip_variable : ndarray, shape (nc,)
        ``X_T`` per pair (m).
    state : ndarray of int, shape (nc,)
        STICK, SLIP or OPEN.
    iterations : int
    residual : float
        Final ``max |R|`` relative to the load scale.
    load : tuple of float
        The increment's load factors ``(static, tangential)`` (-): multiples of
        the static load and of the ``cos`` pattern.
    """

    q: np.ndarray
    normal_force: np.ndarray
    tangential_force: np.ndarray
    slip_variable: np.ndarray
    state: np.ndarray
    iterations: int
    residual: float
    load: tuple[float, float] = (0.0, 0.0)


@dataclass
class StaticResult:
    """Outcome of a quasi-static load path.

    Attributes
    ----------
    states : list of StaticState
        The converged increments (normal ones, then tangential ones).
    converged : bool
        Whether every increment converged.
    message : str
        Why the path stopped, when it did (``"gross slip: ..."`` when the
        tangential load exceeds what friction can hold).
    gross_slip : bool
        The path stopped because every closed pair slipped.
    """

    states: list[StaticState]
    converged: bool
    message: str
    gross_slip: bool

    @property
    def final(self) -> StaticState:
        return self.states[-1]


def _residual(x, Z, F, eps, gap, mu, X_prev):
    """Residual, Jacobian and fields of the node law at unknowns ``x``."""
    lu = F - Z @ x + eps * x
    luT, luN = lu[0::2], lu[1::2]
    eT, eN = eps[0::2], eps[1::2]
    predN = luN - eN * gap
    closed = predN > 0
    lamN = np.where(closed, predN, 0.0)
    limit = mu * lamN
    predT = luT - eT * X_prev
    slip = closed & (np.abs(predT) >= limit)
    stick = closed & ~slip
    sgn = np.sign(predT)
    lamT = np.where(stick, predT, np.where(slip, sgn * limit, 0.0))
    X = (luT - lamT) / eT
    lam = np.empty_like(x)
    lam[0::2], lam[1::2] = lamT, lamN
    R = Z @ x + lam - F
    EZ = np.diag(eps) - Z  # d lambda_u / d x
    J = Z.copy()
    J[0::2] += stick[:, None] * EZ[0::2] + (slip * sgn * mu)[:, None] * EZ[1::2]
    J[1::2] += closed[:, None] * EZ[1::2]
    state = np.where(stick, STICK, np.where(slip, SLIP, OPEN))
    return R, J, lamT, lamN, X, state


def _increment(x0, Z, F, eps, gap, mu, X_prev, tol, max_iter):
    """Newton on one increment: returns (state, converged, all_slip).

    Full steps for the first half of the budget (the active set settles), then
    a backtracking line search on ``max |R|`` from the best iterate.
    """
    scale = max(np.abs(F).max(), 1e-300)
    x = x0.copy()
    best = (np.inf, x)
    it = 0
    for it in range(max_iter + 1):  # noqa: B007 - the count is reported
        R, J, lamT, lamN, X, state = _residual(x, Z, F, eps, gap, mu, X_prev)
        r = np.abs(R).max() / scale
        if r < best[0]:
            best = (r, x)
        if r <= tol or it == max_iter:
            break
        try:
            dx = np.linalg.solve(J, -R)
        except np.linalg.LinAlgError:
            break
        if not np.all(np.isfinite(dx)):
            break
        if it < max_iter // 2:
            x = x + dx
            continue
        x = best[1]
        step = 1.0
        for _ in range(20):
            trial = x + step * dx
            if np.abs(_residual(trial, Z, F, eps, gap, mu, X_prev)[0]).max() / scale < (1 - 1e-4 * step) * r:
                break
            step *= 0.5
        x = trial
    R, J, lamT, lamN, X, state = _residual(best[1], Z, F, eps, gap, mu, X_prev)
    closed = state != OPEN
    all_slip = bool(np.any(closed) and np.all(state[closed] == SLIP))
    return StaticState(best[1], lamN, lamT, X, state, it, best[0]), best[0] <= tol, all_slip


def solve_static(
    condensation: ContactCondensation,
    tangential_scale: float | Sequence[float] = 1.0,
    normal_steps: int = 4,
    tangential_steps: int = 8,
    wear: np.ndarray | None = None,
    eps: np.ndarray | None = None,
    tol: float = 1e-10,
    max_iter: int = 60,
) -> StaticResult:
    """Quasi-static load path: the static load in increments, then the ``cos`` load pattern.

    Parameters
    ----------
    condensation : ContactCondensation
    tangential_scale : float or sequence of float
        Final multiple of the excitation pattern ``force_cos`` applied
        statically after the static load (-); 0 for the normal load alone. A
        sequence is a load path visited in turn from 0, e.g. ``(s, -s, s)``:
        a cycle of tangential load after the first loading.
    normal_steps, tangential_steps : int
        Increments of each stage (of each leg of a path), >= 1.
    wear : ndarray, shape (nc,), optional
        Worn depth per pair (m), added to the initial gaps.
    eps : ndarray, shape (2 nc,), optional
        Penalty per contact coordinate (N/m); default ``|diag Z_0|``. The
        converged static solution does not depend on it.
    tol : float
        Relative residual tolerance per increment.
    max_iter : int
        Newton iterations per increment.
    """
    for name, v in (("normal_steps", normal_steps), ("tangential_steps", tangential_steps)):
        if not isinstance(v, (int, np.integer)) or v < 1:
            raise ValueError(f"{name} must be an integer >= 1, got {v!r}")
    Z, Fs, Fc = condensation.static
    contact = condensation.model.pairs
    nc = contact.count
    gap = contact.gap + (np.zeros(nc) if wear is None else np.asarray(wear, dtype=float))
    eps = np.abs(np.diag(Z)).copy() if eps is None else np.asarray(eps, dtype=float)
    x = np.zeros(2 * nc)
    x[1::2] = max(gap.min(), 0.0)  # approach that closes the smallest gap (a body held by the contact only)
    X = np.zeros(nc)
    states = []
    path = [(s / normal_steps, 0.0) for s in range(1, normal_steps + 1)]
    legs = np.atleast_1d(np.asarray(tangential_scale, dtype=float))
    if not (legs.ndim == 1 and np.all(np.isfinite(legs))):
        raise ValueError(
            f"tangential_scale must be a finite number or sequence of numbers, got {tangential_scale!r}"
        )
    start = 0.0
    for end in legs[legs != 0] if len(legs) == 1 else legs:
        path += [(1.0, start + (end - start) * s / tangential_steps) for s in range(1, tangential_steps + 1)]
        start = end
    done = (0.0, 0.0)
    targets = path[::-1]  # a stack: failed increments are halved
    while targets:
        check_interrupt()
        sn, st = targets[-1]
        F = sn * Fs + st * Fc
        state, ok, all_slip = _increment(x, Z, F, eps, gap, contact.mu, X, tol, max_iter)
        if not ok:
            if all_slip and st != 0:
                msg = (f"gross slip: every closed pair slips at tangential load factor {st:.6g}; friction "
                       f"cannot hold the tangential load (no static equilibrium)")  # fmt: skip
                return StaticResult(states, False, msg, True)
            if len(targets) < len(path) + 12:  # halve the increment
                targets.append((0.5 * (done[0] + sn), 0.5 * (done[1] + st)))
                continue
            msg = f"increment ({sn:.4g}, {st:.4g}) did not converge: residual {state.residual:.3g}"
            return StaticResult(states, False, msg, False)
        targets.pop()
        done = (sn, st)
        state.load = (sn, st)
        states.append(state)
        x, X = state.q, state.slip_variable
    return StaticResult(states, True, "", False)


def second_moment_radius(points: np.ndarray, weights: np.ndarray) -> float:
    """Radius of a semi-ellipsoidal distribution from its second moment (m).

    For ``w(p) = sqrt(1 - |p - pbar|^2 / a^2)`` over a ball of ``d`` dimensions,
    ``<|p - pbar|^2>_w = d a^2 / (d + 3)`` (``a^2 / 4`` on a line, ``2 a^2 / 5``
    on a disk: ``int_0^1 u sqrt(1 - u) du / int_0^1 sqrt(1 - u) du = 2 / 5``
    with ``u = r^2 / a^2``), so this returns ``sqrt((d + 3) / d <|p - pbar|^2>_w)``;
    0 for no weight.

    Parameters
    ----------
    points : ndarray, shape (n,) or (n, d)
        Positions (m).
    weights : ndarray, shape (n,)
        Non-negative weights (negative ones count as 0), e.g. nodal forces (N).
    """
    p = np.asarray(points, dtype=float)
    p = p[:, None] if p.ndim == 1 else p
    w = np.clip(weights, 0.0, None)
    total = w.sum()
    if total <= 0:
        return 0.0
    pbar = w @ p / total
    d = p.shape[1]
    return float(np.sqrt((d + 3) / d * np.sum(w * np.sum((p - pbar) ** 2, axis=1)) / total))


def second_moment_half_width(x: np.ndarray, weights: np.ndarray) -> float:
    """``2 sqrt(sum w (x - xbar)^2 / sum w)``: the half-width of an elliptical distribution (m).

    For ``w(x) = sqrt(1 - (x - xbar)^2 / a^2)`` this is exactly ``a``; 0 for no weight.
    """
    return second_moment_radius(x, weights)


def static_anchors(
    cond: ContactCondensation,
    q_ratio: float,
    points: np.ndarray,
    theory: dict,
    size: str,
    tangential_scale: float,
    symmetry_factor: float = 1.0,
) -> dict:
    """Solve the quasi-static test at ``Q / (mu P) = q_ratio`` and measure its contact and stick sizes.

    The part shared by the cylinder's and the sphere's benchmarks.

    Parameters
    ----------
    cond : ContactCondensation
    q_ratio : float
        ``Q / (mu P)`` (-), >= 0 (its sign gives the direction of the stick-zone deficit).
    points : ndarray, shape (nc,) or (m nc, d)
        Pair positions for :func:`second_moment_radius` (m); ``m`` copies of the
        pairs (a model mirrored by its symmetry planes) repeat their forces.
    theory : dict
        ``contact``, ``peak`` and ``stick`` of the theory (m, Pa, m).
    size : str
        Name of the sizes in the keys, ``"half_width"`` or ``"radius"``.
    tangential_scale : float
        Multiple of the model's ``cos`` pattern applied statically (-).
    symmetry_factor : float
        The whole contact's forces over the model's (2 for a half model).

    Returns
    -------
    dict
        ``converged``, ``message``, ``regime``, ``contact_<size>``,
        ``stick_<size>``, ``peak_pressure``, the relative errors
        ``error_contact_<size>``, ``error_stick_<size>``, ``error_peak_pressure``
        and the force sums ``normal_force_sum``, ``tangential_force_sum`` of
        the whole contact (N).
    """
    res = solve_static(cond, tangential_scale=tangential_scale)
    contact = cond.model.pairs
    copies = len(points) // contact.count

    def measure(weights: np.ndarray) -> float:
        return second_moment_radius(points, np.tile(weights, copies))

    a_h, p0_h, c_h = theory["contact"], theory["peak"], theory["stick"]
    out = dict(converged=res.converged, message=res.message)
    if res.gross_slip:
        last = res.states[-1]
        out.update(regime="gross slip", **{f"stick_{size}": 0.0, f"error_stick_{size}": None})
    elif not res.converged:
        out.update(
            regime="not converged", **{f"contact_{size}": None, f"stick_{size}": None}, peak_pressure=None
        )
        return out
    else:
        last = res.final
        stick = last.state == STICK
        deficit = np.where(
            stick, contact.mu * last.normal_force - np.sign(q_ratio or 1.0) * last.tangential_force, 0.0
        )
        c = measure(deficit) if q_ratio > 0 else None
        regime = "stick" if q_ratio == 0 else ("partial slip" if np.any(stick) else "gross slip")
        error = None if c is None or c_h == 0 else (c - c_h) / c_h
        out.update(regime=regime, **{f"stick_{size}": c, f"error_stick_{size}": error})
    a = measure(last.normal_force)
    p_peak = float(np.max(last.normal_force / contact.area))
    out[f"contact_{size}"] = a
    out["peak_pressure"] = p_peak
    out[f"error_contact_{size}"] = (a - a_h) / a_h
    out.update(
        error_peak_pressure=(p_peak - p0_h) / p0_h,
        normal_force_sum=symmetry_factor * float(last.normal_force.sum()),
        tangential_force_sum=symmetry_factor * float(last.tangential_force.sum()),
    )
    return out


def check_q_ratio(q_ratio: float) -> None:
    """``ValueError`` unless ``q_ratio`` is a finite number >= 0."""
    if not (np.isfinite(q_ratio) and q_ratio >= 0):
        raise ValueError(f"q_ratio must be a finite number >= 0, got {q_ratio!r}")


def static_benchmark(
    q_ratio: float = 0.5,
    params: CylinderOnFlat | None = None,
    model: Model | None = None,
    condensation: ContactCondensation | None = None,
    **changes,
) -> dict:
    """Quasi-static cylinder-on-flat test at ``Q0 / (mu P) = q_ratio`` against Hertz and Cattaneo-Mindlin.

    Parameters
    ----------
    q_ratio : float
        Tangential load ``Q0 / (mu P)`` (-), >= 0.
    params : CylinderOnFlat, optional
        Benchmark parameters (``q_ratio`` here overrides theirs).
    model : Model, optional
        A benchmark model already built (its ``info`` gives ``P``, ``R``, ``E*``,
        ``mu``); the excitation pattern is rescaled to ``q_ratio``.
    condensation : ContactCondensation, optional
        The static condensation of such a model, to reuse over several ``q_ratio``.
    **changes
        Parameters to change, e.g. ``contact_nodes=64``.

    Returns
    -------
    dict
        SI values: ``contact_half_width`` (m), ``stick_half_width`` (m),
        ``peak_pressure`` (Pa), ``normal_load_per_length`` and
        ``tangential_load_per_length`` (N/m, as applied), ``radius`` (m),
        ``effective_modulus`` (Pa), ``mu``, ``q_ratio``, ``regime``
        (``"partial slip"``, ``"gross slip"`` or ``"stick"``), the contact
        force sums ``normal_force_sum`` and ``tangential_force_sum`` (N/m), the
        theory (``hertz_half_width``, ``hertz_peak_pressure``,
        ``mindlin_stick_half_width``, m and Pa), the relative errors
        ``error_contact_half_width``, ``error_peak_pressure``,
        ``error_stick_half_width`` (-), ``contact_nodes``, ``node_spacing`` (m),
        ``converged`` and ``message``.
    """
    check_q_ratio(q_ratio)
    if condensation is not None:
        model = condensation.full
    elif model is None:
        model = cylinder_on_flat(params, **{**changes, "q_ratio": max(q_ratio, 1e-3)})
    info = model.info
    if not {"normal_load", "radius", "effective_modulus", "mu", "tangential_load"} <= set(info):
        raise ValueError("static_benchmark needs a cylinder-on-flat model (its info names P, R, E*, mu, Q0)")
    P, R, e_star, mu = info["normal_load"], info["radius"], info["effective_modulus"], info["mu"]
    q_model = info["tangential_load"] / (mu * P)
    cond = condensation or ContactCondensation(craig_bampton(model, 0.0))
    contact = model.pairs
    a_h = hertz_half_width(P, R, e_star)
    p0_h = hertz_peak_pressure(P, a_h)
    c_h = a_h * np.sqrt(max(1.0 - q_ratio, 0.0))
    out = dict(
        normal_load_per_length=P, tangential_load_per_length=q_ratio * mu * P, radius=R,
        effective_modulus=e_star, mu=mu, q_ratio=q_ratio, hertz_half_width=a_h, hertz_peak_pressure=p0_h,
        mindlin_stick_half_width=c_h, contact_nodes=contact.count, node_spacing=float(np.min(contact.area)),
    )  # fmt: skip
    theory = dict(contact=a_h, peak=p0_h, stick=c_h)
    scale = q_ratio / q_model if q_ratio else 0.0
    out.update(static_anchors(cond, q_ratio, contact.position, theory, "half_width", scale))
    return out
