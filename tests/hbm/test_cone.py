"""The DLFT law with 2-D friction (:mod:`fretwear.hbm.cone`) against exact solutions, the 1-D law and
finite differences.

The exact anchor: a point mass ``m`` on an isotropic spring ``k`` and damper
``c`` in the plane, pressed on a rigid flat by a constant load ``N``, driven by
the rotating force ``F0 (cos wt, sin wt)``. In steady sliding it runs on a
circle ``z = r e^{i(wt - phi)}`` (complex plane coordinate) and the friction
force, of magnitude ``mu N``, is a rotating vector at a fixed angle to the
velocity ``i z``. Opposite the velocity (Coulomb, continuous time)
``(k - m w^2 + i c w) r + i mu N = F0 e^{i phi}``, so

    ((k - m w^2) r)^2 + (c w r + mu N)^2 = F0^2,   phi = atan2(c w r + mu N, (k - m w^2) r).

The DLFT's friction at sample ``n`` is parallel to its slip increment ``X^n -
X^{n-1}`` (eq. 23), the chord of the circle from ``t_{n-1}`` to ``t_n``: it opposes
the velocity at ``t_n - T / (2 N)``, a lag of ``delta = pi / N`` in angle, and the
DLFT solves ``(k - m w^2 + i c w) r + i e^{-i delta} mu N = F0 e^{i phi}``:

    ((k - m w^2) r + mu N sin delta)^2 + (c w r + mu N cos delta)^2 = F0^2,

the continuous closed form as ``N -> inf`` (error ``O(1 / N)``). With ``F0 < mu N``
the mass sticks: no motion, the friction force is the drive.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretwear.hbm import cone
from fretwear.hbm.cone_problem import ConeProblem, walk_kernel
from fretwear.hbm.harmonics import HarmonicBasis
from fretwear.interface.kernels import newton_kernel as coupled_newton
from fretwear.model.structure import OPEN, SLIP, STICK

M, K, C, W, MU, N = 1.0, 100.0, 0.5, 7.0, 0.3, 10.0


def _mass(basis: HarmonicBasis, F0: float, rotating: bool = True, kn: float = 1e4, normal=None):
    """``(Z, F)`` of the point mass on the flat (one pair): rotating (or, if not, straight along tangent 1)
    drive of amplitude ``F0`` (N) at ``W``; ``normal`` the normal force's full harmonics (default ``N``)."""
    nh, H = basis.harmonics, basis.size
    Z = np.zeros((3 * H, 3 * H))
    for o in (0, H):
        Z[o, o] = K
        for k in range(1, nh + 1):
            a, b = o + 2 * k - 1, o + 2 * k
            X, Y = K - M * (k * W) ** 2, C * k * W
            Z[a, a] = Z[b, b] = X
            Z[a, b], Z[b, a] = Y, -Y
    Z[2 * H :, 2 * H :] = kn * np.eye(H)
    F = np.zeros(3 * H)
    F[1] = F0  # F0 cos wt along tangent 1
    if rotating:
        F[H + 2] = F0  # F0 sin wt along tangent 2
    F[2 * H :] = [N] + [0.0] * (H - 1) if normal is None else normal
    return Z, F


def _circle(F0: float, delta: float) -> tuple[float, float]:
    """Radius (m) and phase lag (rad) of the steady circle; friction lagging the velocity by ``delta``."""
    A, B = K - M * W**2, C * W
    s, c = MU * N * np.sin(delta), MU * N * np.cos(delta)
    qa, qb, qc = A * A + B * B, 2 * (A * s + B * c), s * s + c * c - F0 * F0
    r = (-qb + np.sqrt(qb * qb - 4 * qa * qc)) / (2 * qa)
    return r, np.arctan2(B * r + c, A * r + s)


def _solve_circle(samples: int, F0: float = 5.0):
    basis = HarmonicBasis(3, samples)
    Z, F = _mass(basis, F0)
    sol = ConeProblem(Z, F, basis, np.array([MU])).solve(tol=1e-13)
    assert sol.converged, sol.message
    h = sol.harmonics[0]
    return sol, h, np.hypot(h[0, 1], h[0, 2]), np.arctan2(h[0, 2], h[0, 1])


def test_rotating_drive_slides_on_the_exact_circle():
    """Gross slip: the DLFT circle is its closed form (friction lagging by pi / N) to round-off, a pure
    first harmonic on both tangents a quarter period apart, and tends to the continuous closed form as
    1 / N (the radius's error halves as the samples double)."""
    errors = []
    for samples in (64, 128):
        sol, h, r, phi = _solve_circle(samples)
        r_dlft, phi_dlft = _circle(5.0, np.pi / samples)
        assert abs(r / r_dlft - 1) < 1e-9 and abs(phi - phi_dlft) < 1e-9
        assert np.allclose(h[1, 1:3], [-h[0, 2], h[0, 1]], rtol=0, atol=1e-12 * r)  # x2 = r sin(wt - phi)
        assert np.abs(h[:2, 3:]).max() < 1e-12 * r and np.abs(h[:2, 0]).max() < 1e-12 * r
        assert np.all(sol.state == SLIP)
        r_exact, phi_exact = _circle(5.0, 0.0)
        errors.append((abs(r / r_exact - 1), abs(phi - phi_exact)))
    (er64, ep64), (er128, ep128) = errors
    assert 3e-2 < er64 < 4e-2  # 3.6e-2 here: the DLFT's O(1/N), not a solver tolerance
    assert 1.9 < er64 / er128 < 2.1 and ep64 / ep128 > 1.9  # 1.98 and 2.3 here


def _integrate(F0: float, steps: int, periods: int) -> tuple[float, float]:
    """Radius (m) and phase (rad) of tangent 1 over the last of ``periods`` periods of the mass's motion in
    time, started on the closed-form circle: the implicit midpoint rule (second order) with Coulomb's law
    at the midpoint velocity, ``v = 0`` when the force it needs is within ``mu N`` (complex plane
    coordinate ``z``)."""
    dt = 2 * np.pi / W / steps
    r, phi = _circle(F0, 0.0)
    z = r * np.exp(-1j * phi)
    v = 1j * W * z
    a = 2 * M / dt + K * dt / 2 + C
    last = np.empty(steps, dtype=complex)
    for n in range(steps * periods):
        b = 2 * M * v / dt + F0 * np.exp(1j * W * (n + 0.5) * dt) - K * z  # a v_mid = b - friction
        vm = 0.0 if abs(b) <= MU * N else (b - MU * N * b / abs(b)) / a
        z, v = z + dt * vm, 2 * vm - v
        if n >= steps * (periods - 1):
            last[n - steps * (periods - 1)] = z
    wt = W * dt * np.arange(1, steps + 1)
    c, s = 2 / steps * np.sum(last.real * np.cos(wt)), 2 / steps * np.sum(last.real * np.sin(wt))
    return np.hypot(c, s), np.arctan2(s, c)


def test_closed_form_is_the_time_integrated_motion():
    """The continuous closed form, checked independently: direct time integration converges to it at
    second order (errors 4.1e-5 then 1.0e-5 at 512 and 1024 steps per period), and the Richardson
    extrapolation of the two lands on it to 1e-8."""
    r, phi = _circle(5.0, 0.0)
    (r1, p1), (r2, p2) = _integrate(5.0, 512, 10), _integrate(5.0, 1024, 10)
    assert abs(r1 / r - 1) / abs(r2 / r - 1) == pytest.approx(4.0, rel=0.01)
    assert abs((4 * r2 - r1) / 3 / r - 1) < 1e-8 and abs((4 * p2 - p1) / 3 - phi) < 1e-8


def test_3d_model_condensed_on_its_pairs_slides_on_the_circle():
    """The point mass as a 3-D model (node B free, node A grounded, normal +z, tangent +x: the binormal is
    +y) through :class:`~fretwear.interface.ContactCondensation`: the same circle; the rest of a two-mass
    model is condensed out (a light mass tied by a stiff spring: the first mass carrying both)."""
    from fretwear.interface import ContactCondensation
    from fretwear.model import ContactPairs, Model

    pairs = ContactPairs(dofs_a=[[-1, -1, -1]], dofs_b=[[0, 1, 2]], normal=[[0, 0, 1]], area=[1.0], mu=MU,
                         tangent=[[1, 0, 0]])  # fmt: skip
    one = Model(M=M * np.eye(3), C=C * np.eye(3), K=np.diag([K, K, 1e4]), force_cos=[5.0, 0, 0],
                force_sin=[0, 5.0, 0], force_static=[0, 0, -N], pairs=pairs)  # fmt: skip
    problem = ConeProblem.from_condensation(ContactCondensation(one), W, harmonics=3, samples=64)
    sol = problem.solve(tol=1e-13)
    r, phi = np.hypot(*sol.harmonics[0, 0, 1:3]), np.arctan2(sol.harmonics[0, 0, 2], sol.harmonics[0, 0, 1])
    assert sol.converged and np.all(sol.state == SLIP)
    r_dlft, phi_dlft = _circle(5.0, np.pi / 64)
    assert abs(r / r_dlft - 1) < 1e-9 and abs(phi - phi_dlft) < 1e-9
    # a second, much lighter mass tied to the first by a stiff isotropic spring: condensed, not a pair
    kc, m2 = 1e7, 1e-6
    K2 = np.zeros((6, 6))
    K2[:3, :3], K2[3:, 3:] = np.diag([K, K, 1e4]) + kc * np.eye(3), kc * np.eye(3)
    K2[:3, 3:] = K2[3:, :3] = -kc * np.eye(3)
    two = Model(M=np.diag([M] * 3 + [m2] * 3), C=np.diag([C] * 3 + [0.0] * 3), K=K2,
                force_cos=[5.0, 0, 0, 0, 0, 0], force_sin=[0, 5.0, 0, 0, 0, 0],
                force_static=[0, 0, -N, 0, 0, 0], pairs=pairs)  # fmt: skip
    heavy = Model(M=(M + m2) * np.eye(3), C=C * np.eye(3), K=np.diag([K, K, 1e4]), force_cos=[5.0, 0, 0],
                  force_sin=[0, 5.0, 0], force_static=[0, 0, -N], pairs=pairs)  # fmt: skip
    sol2, sol1 = (ConeProblem.from_condensation(ContactCondensation(m), W, 3, 64).solve(tol=1e-13)
                  for m in (two, heavy))  # fmt: skip
    assert sol2.converged and sol1.converged
    assert np.abs(sol2.harmonics - sol1.harmonics).max() < 1e-9 * r  # the spring's compliance: 5e-12


def test_weak_rotating_drive_sticks():
    """``F0 < mu N``: the mass sticks where it was (X_ref = 0), the friction force is the drive."""
    basis = HarmonicBasis(3, 64)
    Z, F = _mass(basis, 0.9 * MU * N)
    sol = ConeProblem(Z, F, basis, np.array([MU])).solve(tol=1e-13)
    assert sol.converged
    assert np.abs(sol.harmonics[0, :2]).max() < 1e-14
    assert np.all(sol.state == STICK)
    wt = basis.phases
    drive = 0.9 * MU * N * np.column_stack([np.cos(wt), np.sin(wt)])
    assert np.abs(sol.tangential_force[0] - drive).max() < 1e-12 * N


def test_friction_energy_per_cycle_is_the_circle_s():
    """Dissipated energy per cycle: ``oint lambda_T . du`` from the harmonics is ``2 pi r mu N cos(pi / N)``
    (friction lagging the velocity), the march's ``mu sum lambda_N |dX|`` is ``mu N`` times the inscribed
    polygon's perimeter ``2 N r sin(pi / N)``; both tend to the continuous ``2 pi r mu N``."""
    samples = 64
    sol, _, r, _ = _solve_circle(samples)
    assert sol.contact_work[0] == pytest.approx(2 * np.pi * r * MU * N * np.cos(np.pi / samples), rel=1e-10)
    perimeter = 2 * samples * r * np.sin(np.pi / samples)
    assert sol.friction_energy[0] == pytest.approx(MU * N * perimeter, rel=1e-10)
    assert sol.friction_energy[0] == pytest.approx(2 * np.pi * r * MU * N, rel=2e-3)


def test_straight_line_motion_is_the_1d_law():
    """A drive along tangent 1 with a normal load that swings enough to open the contact: the same
    harmonics as the 1-D coupled law (:mod:`fretwear.hbm.coupled`) on the same problem, tangent 2 at rest."""
    basis = HarmonicBasis(5, 64)
    H = basis.size
    normal = np.zeros(H)
    normal[0], normal[1], normal[4] = N, 1.3 * N, 0.2 * N  # opens part of the period
    Z3, F3 = _mass(basis, 4.0, rotating=False, normal=normal)
    problem = ConeProblem(Z3, F3, basis, np.array([MU]), xref=np.array([[1e-3, 0.0]]))
    sol = problem.solve(tol=1e-13)
    assert sol.converged
    assert np.any(sol.state == OPEN) and np.any(sol.state == SLIP) and np.any(sol.state == STICK)
    keep = np.r_[0:H, 2 * H : 3 * H]  # tangent 1 and normal
    eps2 = problem.eps[[0, 2]]
    x, ok, *_ = coupled_newton(np.zeros(2 * H), Z3[np.ix_(keep, keep)], F3[keep], eps2, np.zeros(1),
                               np.array([MU]), np.array([1e-3]), basis.synthesis, basis.analysis,
                               1e-13 * N, 50)  # fmt: skip
    assert ok
    h = sol.harmonics[0]
    scale = np.abs(x).max()
    assert np.abs(h[0] - x[:H]).max() < 1e-10 * scale and np.abs(h[2] - x[H:]).max() < 1e-10 * scale
    assert np.abs(h[1]).max() == 0.0


def _march(c1, c2, uN, xref, eps=(2.0, 3.0, 1.0), mu=0.5):
    """March one pair with the samples themselves as inputs: returns the forces and ``d lambda_T / d
    (c1, c2, uN)`` (2, Ns, 3 Ns)."""
    Ns = c1.size
    I = np.eye(Ns)
    D1, D2, DN = (np.zeros((Ns, 3 * Ns)) for _ in range(3))
    D1[:, :Ns], D2[:, Ns : 2 * Ns], DN[:, 2 * Ns :] = I, I, I
    out = [np.empty(Ns) for _ in range(5)]
    state = np.empty(Ns, dtype=np.int8)
    Y = np.empty((Ns, 2, 3 * Ns))
    cone.march_pair(c1, c2, uN, 0.0, mu, *eps, *xref, D1, D2, DN, True, *out, state, Y)
    return out[0], out[1], state, np.stack([D1 - Y[:, 0], D2 - Y[:, 1]])


@pytest.mark.parametrize(
    "centres, radius, opens",
    [(0.5, 0.2, False), (0.5, 0.9, False), (0.5, 2.0, False), (0.5, 5.0, False),  # stuck, projected
     (1.5, 1.0, False), (3.0, 1.0, False), (1.2, 1.0, True)],  # slip cycles, separation
)  # fmt: skip
def test_march_derivative_equals_finite_differences(centres, radius, opens):
    """The slip variable's sensitivity through every start: stuck at the reference, projected on one disk
    or a corner of two, a slip cycle (through (I - T)^-1), after a separation."""
    Ns = 32
    rng = np.random.default_rng(int(10 * centres + radius))
    t = 2 * np.pi * np.arange(Ns) / Ns
    c1 = centres * np.cos(t) + 0.05 * rng.standard_normal(Ns)
    c2 = centres * np.sin(2 * t if centres > 1 else t) + 0.05 * rng.standard_normal(Ns)
    uN = 2.0 + 0.1 * rng.standard_normal(Ns) - (2.5 * np.cos(t) if opens else 0.0)
    ang = rng.uniform(0, 2 * np.pi)
    xref = (radius * np.cos(ang) / 2.0, radius * np.sin(ang) / 3.0)
    l1, l2, state, G = _march(c1, c2, uN, xref)
    assert (OPEN in state) == opens
    v, h = np.concatenate([c1, c2, uN]), 1e-7
    fd = np.empty_like(G)
    for j in range(3 * Ns):
        e = np.zeros(3 * Ns)
        e[j] = h
        p, m = _march(*np.split(v + e, 3), xref), _march(*np.split(v - e, 3), xref)
        fd[0, :, j], fd[1, :, j] = (p[0] - m[0]) / (2 * h), (p[1] - m[1]) / (2 * h)
    assert np.abs(G - fd).max() < 1e-7


def _pairs(seed: int = 3):
    """Three coupled pairs with stick, slip and separation at a point ``x`` (not a solution)."""
    basis = HarmonicBasis(3, 32)
    H = basis.size
    rng = np.random.default_rng(seed)
    n = 9 * H
    Z = np.diag(rng.uniform(300.0, 600.0, n)) + 20.0 * rng.standard_normal((n, n))
    F = np.zeros(n)
    for i in range(3):
        F[(3 * i + 2) * H] = 5.0
    problem = ConeProblem(Z, F, basis, np.array([0.5, 0.3, 0.4]), gap=np.array([0.0, 1e-3, 0.0]),
                          xref=rng.standard_normal((3, 2)) * 1e-3)  # fmt: skip
    x = 1e-3 * rng.standard_normal(n)
    x[2 * H :: 3 * H] = 0.0  # normal means: contact, swings open some samples
    x[2 * H : 3 * H] *= 0.05  # but pair 0 stays closed: it slips every period (a slip cycle)
    return problem, x


def test_jacobian_equals_finite_differences():
    """``J = Z + blockdiag(A) (E - Z)`` with the exact 3H x 3H blocks, against central differences."""
    problem, x = _pairs()
    state = problem.evaluate(x)[5]
    assert {STICK, SLIP, OPEN} <= set(state.ravel().tolist())
    assert OPEN not in state[0] and SLIP in state[0] and STICK in state[0]
    J = problem.jacobian(x)
    h = 1e-9
    fd = np.empty_like(J)
    for j in range(x.size):
        e = np.zeros(x.size)
        e[j] = h
        fd[:, j] = (problem.evaluate(x + e)[0] - problem.evaluate(x - e)[0]) / (2 * h)
    assert np.abs(J - fd).max() < 1e-6 * np.abs(J).max()


def test_forces_never_leave_the_cone():
    """At a converged solution of coupled pairs: ``|lambda_T| <= mu lambda_N``, ``lambda_N >= 0``, slip on
    the cone's surface, nothing through an open pair."""
    problem, _ = _pairs(5)
    H = problem.basis.size
    problem.F[1::H] = 3.0  # drive every coordinate's first harmonic
    sol = problem.solve(tol=1e-12)
    assert sol.converged, sol.message
    lamT = np.linalg.norm(sol.tangential_force, axis=2)
    limit = problem.mu[:, None] * sol.normal_force
    assert np.all(sol.normal_force >= 0) and np.all(lamT <= limit * (1 + 1e-12))
    assert np.allclose(lamT[sol.state == SLIP], limit[sol.state == SLIP], rtol=1e-12)
    assert np.all(lamT[sol.state == OPEN] == 0)


def test_walk_reaches_newton_s_solution():
    """The walk in the drive's amplitude from the pressed, resting mass (exact there), through stick into
    sliding: a predictor along tangents for this smooth law, polished by Newton, ends at the circle."""
    basis = HarmonicBasis(3, 64)
    Z, F = _mass(basis, 5.0)
    problem = ConeProblem(Z, F, basis, np.array([MU]))
    static = np.where(np.arange(F.size) == 2 * basis.size, F, 0.0)
    zero = np.zeros(problem.size)
    x, p, pieces, arrived = walk_kernel(zero, 0.0, Z, static, F - static, zero, problem.eps, problem.gap,
                                        problem.mu, problem.xref, basis.synthesis, basis.analysis,
                                        5000)  # fmt: skip
    assert arrived and p == 1.0 and pieces > 10
    r_walk = np.hypot(x[1], x[2])
    r_exact = _circle(5.0, np.pi / 64)[0]
    assert abs(r_walk / r_exact - 1) < 5e-2  # the predictor's drift: 2.6e-2 in 20 pieces here
    polished = problem.solve(x, tol=1e-13)
    assert polished.converged and polished.iterations <= 6
    assert np.hypot(*polished.harmonics[0, 0, 1:3]) == pytest.approx(r_exact, rel=1e-9)


@pytest.mark.parametrize(
    "kwargs, match",
    [({"mu": [-0.1]}, "mu must be"), ({"gap": [0.0, 1.0]}, "gap must be"),
     ({"xref": [0.0]}, r"xref must be \(1, 2\)"), ({"eps": [1.0, 1.0, 0.0]}, "eps must be")],
)  # fmt: skip
def test_bad_input_is_refused(kwargs, match):
    basis = HarmonicBasis(2, 16)
    Z, F = _mass(basis, 1.0)
    args = {"mu": [MU], **kwargs}
    with pytest.raises(ValueError, match=match):
        ConeProblem(Z, F, basis, **args)
