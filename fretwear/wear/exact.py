"""Exact slow-time integration along the load path (one friction contact).

For a single friction contact, the DLFT response at normal load ``F_N0 / sigma``
is ``1 / sigma`` times the response at ``F_N0`` under forces scaled by
``sigma`` (homogeneity of Coulomb's law). One exact piecewise-linear walk in
``sigma`` (:func:`fretwear.hbm.periodic.walk`) therefore gives the sliding
distance along the whole wear history, and Archard's law ``dw/dN = K_w F_N s``
integrates in closed form on each piece: no slow-time error.
"""

from __future__ import annotations

import time

import numpy as np

from ..hbm.periodic import LOAD, Problem, solve_problem, walk
from ..model import Model
from .dynamics import DEFAULT_HARMONICS, observables, resolve_dynamics
from .result import WearHistory, check_wear_inputs, two_scale_warning
from .sliding import _shoot_at, cached_solves, sliding_table, sliding_tables, unit_forcing

__all__ = ["wear_exact", "exact_path_applies", "exact_wear_map"]

#: the tables meet their tolerance down to this fraction of the starting load ratio (w = 0.99 u0); below,
#: their cubic runs to the frictionless knot at rho = 0, checked there too
_DEEP = 1e-2


def exact_path_applies(model: Model) -> bool:
    """True when :func:`wear_exact` applies: one friction contact, no unilateral contact."""
    return len(model.friction) == 1 and not model.normal


def wear_exact(
    model: Model,
    omega: float,
    *,
    kw: float = 1e-11,
    cycles: float = 1e5,
    harmonics: int | None = None,
    samples: int | None = None,
    dynamics: str = "auto",
    stop_fraction: float = 0.99,
    max_records: int = 100,
) -> WearHistory:
    """Wear evolution with no slow-time discretisation error, for one friction contact.

    ``dynamics="shooting"`` (what ``"auto"`` runs unless ``harmonics`` or
    ``samples`` are given) integrates Archard's law on the exact sliding
    distance of the event-driven dynamics (``fretwear.wear.sliding.sliding_table()``):
    no harmonic truncation and no slow-time error, the reference of every
    other method; its history follows the wear past ``stop_fraction u0`` to the
    horizon (status ``"worn"``), and the response of each record is a shooting
    solution at its wear. ``dynamics="dlft"`` follows the DLFT load path (below):
    an exact slow time on approximate dynamics (truncated at ``Nh = harmonics``,
    default 21).

    With one friction contact and no unilateral contact the DLFT equations are
    positively homogeneous in the forces and the friction limit, so the
    response at normal load ``F_N = F_N0 / sigma`` is ``1 / sigma`` times the
    response at ``F_N0`` under the forces scaled by ``sigma``. Wear relaxes the
    load along ``sigma = u0 / (u0 - w)``, and Archard's law becomes

        dN = d sigma / (K_w k_n s(sigma)),

    with ``s(sigma)`` the distance slid per cycle at load factor ``sigma`` and
    ``F_N0``. The exact piecewise-linear load walk gives the whole path from
    ``sigma = 1`` to ``1 / (1 - stop_fraction)`` in one pass; ``s`` is linear on
    each piece, so ``N(sigma)`` integrates in closed form (a logarithm per
    piece). This is stepping in the limit of zero tolerance, at the cost of one
    walk. Records are ``max_records`` points evenly spread in wear plus up to
    as many of the path's breakpoints (where the stick/slip pattern changes);
    ``x`` being linear in ``sigma`` on each piece, every record is exact.

    Parameters are those of :func:`wear_stepping`.
    """
    check_wear_inputs(model, kw, cycles)
    if not exact_path_applies(model):
        raise ValueError("wear_exact needs exactly one friction contact and no unilateral contact")
    if not 0 < stop_fraction < 1:
        raise ValueError(f"stop_fraction must be in (0, 1), got {stop_fraction!r}")
    if resolve_dynamics(model, dynamics, harmonics, samples) == "shooting":
        hist = _wear_on_table(model, omega, kw, cycles, stop_fraction, max_records)
        hist.dynamics = "shooting"
        return hist
    harmonics = harmonics or DEFAULT_HARMONICS
    start = time.perf_counter()
    contact = model.friction[0]
    u0, kn = contact.u0, contact.kn
    problem = Problem(model, omega, harmonics, samples)
    sol0 = solve_problem(problem)
    if not sol0.converged:
        raise RuntimeError(f"the periodic solve of the unworn structure failed: {sol0.message}")
    arrays = dict(u0=np.array([u0]), kn=np.array([kn]), kw=kw, dynamics="dlft", harmonics=harmonics)
    if sol0.path in ("linear-stuck", "linear-open") or sol0.sliding_distance[0] == 0:
        lam0 = problem.F - problem.Z @ sol0.unknowns
        rows = observables(problem, np.repeat(lam0[None], 2, axis=0))
        load0 = np.full((2, 1), contact.normal_load())
        return WearHistory(omega, "exact", np.array([0.0, cycles]), np.zeros((2, 1)), load0,
                           np.zeros((2, 1)), np.zeros((2, 1)), *rows, **arrays, status="stuck", solves=1,
                           wall_time=time.perf_counter() - start)  # fmt: skip
    sigma_end = 1.0 / (1.0 - stop_fraction)
    _, _, pieces, arrived, xs, sig, slid = walk(problem, sol0.unknowns, 1.0, sigma_end, LOAD, problem.F0,
                                                  np.zeros(0), 200_000, record=200_001)  # fmt: skip
    if len(sig) < 2:
        raise RuntimeError("the load walk of the wearing contact failed at its start")
    # N(sigma): exact integral of d sigma / (kw kn s) with s linear between breakpoints
    ds, dslid = np.diff(sig), np.diff(slid)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio = slid[1:] / slid[:-1]
        dn = np.where(np.abs(dslid) > 1e-12 * slid[:-1], ds * np.log(ratio) / dslid, ds / slid[:-1])
    N = np.concatenate([[0.0], np.cumsum(dn)]) / (kw * kn)
    status = "worn" if arrived else f"load walk stopped after {pieces} pieces"
    sigma_stop = sig[-1]
    if N[-1] > cycles:  # the horizon comes first: sigma at N = cycles, by bisection on the piece's law
        k = int(np.searchsorted(N, cycles))
        a, b = sig[k - 1], sig[k]
        for _ in range(60):
            m = 0.5 * (a + b)
            n_m = N[k - 1] + _piece_cycles(sig[k - 1], m, slid[k - 1], _lerp(sig, slid, k - 1, m)) / (kw * kn)
            a, b = (m, b) if n_m < cycles else (a, m)
        sigma_stop, status = 0.5 * (a + b), "horizon"
    # records: evenly spread in wear, plus the breakpoints where the stick/slip pattern changes
    w_stop = 1.0 - 1.0 / sigma_stop
    targets = 1.0 / (1.0 - np.linspace(0.0, w_stop, max_records))
    breaks = sig[sig <= sigma_stop]
    targets = np.unique(np.concatenate([targets, breaks[_spread(1.0 - 1.0 / breaks, max_records)]]))
    k = np.clip(np.searchsorted(sig, targets, side="right") - 1, 0, len(sig) - 2)
    t = ((targets - sig[k]) / (sig[k + 1] - sig[k]))[:, None]
    xs = (1 - t) * xs[k] + t * xs[k + 1]  # exact: x is linear in sigma on each piece
    slid_t = (1 - t[:, 0]) * slid[k] + t[:, 0] * slid[k + 1]
    N = N[k] + np.array(
        [_piece_cycles(sig[j], s, slid[j], st) for j, s, st in zip(k, targets, slid_t, strict=True)]
    ) / (kw * kn)
    sig, slid = targets, slid_t
    wear = u0 * (1.0 - 1.0 / sig)
    load = kn * (u0 - wear)
    s_w = slid / sig  # homogeneity: distance slid at the actual load
    rate = kw * load * s_w
    notes = two_scale_warning(rate[:1], np.array([u0]))
    rows = observables(problem, problem.F[None, :] - (xs / sig[:, None]) @ problem.Z.T)  # x / sigma: unscaled
    return WearHistory(omega, "exact", N, wear[:, None], load[:, None], rate[:, None], s_w[:, None], *rows,
                       **arrays, status=status, solves=1, wall_time=time.perf_counter() - start,
                       warnings=notes,
                       info={"pieces": pieces})  # fmt: skip


def _piece_cycles(s1: float, s2: float, slid1: float, slid2: float) -> float:
    """``integral d sigma / s`` over one piece where ``s`` is linear (times kw kn)."""
    if abs(slid2 - slid1) <= 1e-12 * slid1:
        return (s2 - s1) / slid1
    return (s2 - s1) * np.log(slid2 / slid1) / (slid2 - slid1)


def _lerp(x: np.ndarray, y: np.ndarray, k: int, xi: float) -> float:
    """Linear interpolation of ``y`` on ``[x[k], x[k + 1]]`` at ``xi``."""
    return y[k] + (y[k + 1] - y[k]) * (xi - x[k]) / (x[k + 1] - x[k])


def _spread(w: np.ndarray, count: int) -> np.ndarray:
    """Indices of about ``count`` points spread evenly in ``w``, always keeping both ends."""
    if len(w) <= count:
        return np.arange(len(w))
    targets = np.linspace(w[0], w[-1], count)
    idx = np.unique(np.clip(np.searchsorted(w, targets), 0, len(w) - 1))
    return np.unique(np.concatenate([[0], idx, [len(w) - 1]]))


def _wear_on_table(
    model: Model, omega: float, kw: float, cycles: float, stop_fraction: float, max_records: int
) -> WearHistory:
    """:func:`wear_exact` on the exact dynamics: Archard's law integrated on the sliding table.

    The wear follows its true value up to the horizon, past ``stop_fraction u0``
    too (then the status is ``"worn"``): ``max_records`` records evenly spread
    in wear up to the horizon or ``stop_fraction u0``, with the table's samples
    in that range, then 20 records geometric in ``N`` up to the horizon. The
    response of every record (sliding distance, amplitudes) comes from a
    shooting solve at its load ratio, seeded by the table's orbits.
    """
    start = time.perf_counter()
    contact = model.friction[0]
    u0, kn, mu = contact.u0, contact.kn, contact.mu
    fex = unit_forcing(model)
    rho0 = mu * contact.normal_load() / fex
    arrays = dict(u0=np.array([u0]), kn=np.array([kn]), kw=kw)
    solves0 = cached_solves(model, omega)
    table = sliding_table(model, omega, _DEEP * rho0, rho0)

    def history(rho: np.ndarray, N: np.ndarray, **status) -> WearHistory:
        at, solves = _shoot_at(model, table, rho)
        wear = u0 - rho * fex / (mu * kn)
        load = kn * (u0 - wear)
        slid = fex * at["s_hat"]
        return WearHistory(omega, "exact", N, wear[:, None], load[:, None], (kw * load * slid)[:, None],
                           slid[:, None], fex * at["amplitude"], fex * at["half_peak_to_peak"],
                           fex * at["relative_half_peak_to_peak"], **arrays,
                           solves=table.solves - solves0 + solves, wall_time=time.perf_counter() - start,
                           info={"dynamics": "shooting", "table_size": len(table.rho),
                                 "rho_stick": table.rho_stick}, **status)  # fmt: skip

    if rho0 >= table.rho_stick:  # stuck for good: no slip, no wear
        return history(np.array([rho0, rho0]), np.array([0.0, cycles]), status="stuck")
    scale = 1.0 / (kw * kn * fex)
    floor = _floor(table, rho0)
    rho_end = float(table.load_ratio(rho0, np.array([cycles / scale]), floor)[0])  # at the horizon
    rho_worn = max(rho0 * (1.0 - stop_fraction), floor)
    worn = rho_end <= rho_worn
    # records evenly spread in wear (rho is affine in w), plus the samples of the table in range
    rho = np.linspace(rho0, max(rho_end, rho_worn), max_records)
    inside = table.rho[(table.rho < rho0) & (table.rho > rho[-1])]
    rho = np.unique(np.concatenate([rho, inside[_spread(inside, max_records)] if len(inside) else []]))[::-1]
    N = scale * table.cycles(rho0, rho)
    if worn and table.free is not None and N[-1] < cycles:  # past the worn state, geometric in N
        tail = np.geomspace(N[-1], cycles, 21)[1:]
        rho, N = np.append(rho, table.load_ratio(rho0, tail / scale, floor)), np.append(N, tail)
    notes = [f"shooting failed at {len(table.failures)} load ratios (left out)"] if table.failures else []
    hist = history(rho, N, status="worn" if worn else "horizon")
    hist.warnings = two_scale_warning(hist.rate[:1, 0], np.array([u0])) + notes
    return hist


def exact_wear_map(model: Model, omegas, cycles, *, kw: float, workers: int = 2) -> dict[str, np.ndarray]:
    """Wear and response over frequency x cycle count on the exact dynamics, all frequencies at once.

    The sliding table of each frequency (the missing ones built together,
    :func:`~fretwear.wear.sliding.sliding_tables`) gives ``rho(N)`` by inverting
    the closed-form Archard quadrature
    (:meth:`~fretwear.wear.sliding.SlidingTable.load_ratio`), then
    ``w = u0 - rho F_ex / (mu k_n)`` and the response per unit forcing
    interpolated at ``rho``: no history is recorded and nothing is
    interpolated in ``N``. The wear follows its true value to ``u0`` (the
    gross-slip tail of the tables: ``u0 - w`` decays exponentially in ``N``).

    Parameters
    ----------
    model : Model
        One friction contact, no unilateral contact.
    omegas : array_like, shape (nf,)
        Frequencies (rad/s), > 0.
    cycles : array_like, shape (nN,)
        Cycle counts, ascending, >= 0.
    kw : float
        Archard coefficient ``K_w`` (1/N), > 0.
    workers : int
        Threads that build missing tables.

    Returns
    -------
    dict of ndarray
        ``wear`` (nf, nN, 1) in m, ``amplitude`` and ``half_peak_to_peak`` (nf, nN, n),
        ``relative_half_peak_to_peak`` (nf, nN, n_contacts) in m, ``stuck`` (nf,) bool.
    """
    omegas = np.asarray(omegas, dtype=float)
    cycles = np.asarray(cycles, dtype=float)
    check_wear_inputs(model, kw, float(cycles.max()))
    if not exact_path_applies(model):
        raise ValueError("exact_wear_map needs exactly one friction contact and no unilateral contact")
    if not kw > 0:
        raise ValueError(f"kw must be > 0 for a wear map, got {kw!r}")
    contact = model.friction[0]
    u0, kn, mu = contact.u0, contact.kn, contact.mu
    fex = unit_forcing(model)
    rho0 = mu * contact.normal_load() / fex
    tables = sliding_tables(model, omegas, _DEEP * rho0, rho0, workers=workers)
    integral = kw * kn * fex * cycles  # K_w k_n F_ex N: the Archard integral reached after N cycles
    order = np.argsort(integral, kind="stable")
    rho = np.empty((len(omegas), len(cycles)))
    for i, t in enumerate(tables):
        rho[i, order] = t.load_ratio(rho0, integral[order], _floor(t, rho0))
    out = {"wear": (u0 - rho * fex / (mu * kn))[:, :, None]}
    rows = [t.interpolate(r) for t, r in zip(tables, rho, strict=True)]
    for name in ("amplitude", "half_peak_to_peak", "relative_half_peak_to_peak"):
        out[name] = fex * np.stack([row[name] for row in rows])
    out["stuck"] = np.array([rho0 >= t.rho_stick for t in tables])
    return out


def _floor(table, rho0: float) -> float:
    """The lowest load ratio the wear can reach on ``table``: 0 (worn through) from its frictionless knot."""
    if table.free is not None:
        return 0.0
    return min(table.rho[0], rho0) if len(table.rho) else rho0
