"""Contract of the shared compiled solvers (:mod:`fretwear.hbm.newton`) over both contact laws.

Each problem is built around a known solution: with ``Z = 0`` the law's
residual at ``x = 0`` gives the contact forces of any augmented Lagrangian
``u`` (harmonics, N), and ``x* = E^-1 (u - Psi lam)`` is the solution of the
DLFT equations under the forces ``F = u + (Z - E) x*`` for every stiffness
``Z`` (eq. 12, 18): ``lambda_u(x*) = F - Z x* + E x* = u``.
"""

from __future__ import annotations

import numpy as np
import pytest

from fretwear.hbm import newton as nw
from fretwear.hbm.dlft import FRICTION, UNILATERAL
from fretwear.hbm.harmonics import HarmonicBasis

BASIS = HarmonicBasis(3, 64)
PHI, PSI = BASIS.synthesis, BASIS.analysis
H = PHI.shape[1]


def _dlft():
    """Two contacts, one friction (limit 1 N) and one unilateral (gap 1e-3 m)."""
    law = nw.dlft_law(np.array([FRICTION, UNILATERAL]), np.array([1.0, 1e-3]), PHI, PSI, False)
    return law, np.array([1e3, 2e3])


def _coupled():
    """Two node pairs: gap 1e-4 m, friction coefficients 0.5 and 0.3."""
    law = nw.coupled_law(np.array([1e-4, 1e-4]), np.array([0.5, 0.3]), np.zeros(2), PHI, PSI)
    return law, np.array([1e3, 2e3, 1.5e3, 3e3])


def _stiffness(n: int, seed: int) -> np.ndarray:
    """A dynamic stiffness (N/m): diagonally dominant, coupled, not symmetric."""
    rng = np.random.default_rng(seed)
    return np.diag(rng.uniform(300.0, 600.0, n)) + 20.0 * rng.standard_normal((n, n))


def _residual(law, x, Z, F, eps):
    """The law's residual (N) at ``x`` and the states of its samples."""
    R = np.empty(x.size)
    A, lam, lamN, X, state = nw._buffers(law)
    nw._evaluate(law, x, Z, F, eps, True, R, A, lam, lamN, X, state)
    return R, state


def _problem(make, seed: int = 0):
    """``(law, Z, F, eps, x*)``: a problem with the known solution ``x*`` (m); slip, stick and separation."""
    law, eps = make()
    n = eps.size * H
    rng = np.random.default_rng(seed)
    u = np.zeros(n)
    for c in range(eps.size):  # a mean and a first harmonic per coordinate, large enough to slip and open
        u[c * H] = (0.5 if c % 2 else 0.0) * eps[c] * 1e-3
        u[c * H + 1 : c * H + 3] = rng.uniform(1.0, 3.0, 2)
    if law[0] == nw.COUPLED:  # normal coordinates: a compressive mean, a swing that opens the pairs
        for c in range(1, eps.size, 2):
            u[c * H] = eps[c] * 1e-4 + 1.5
    R, state = _residual(law, np.zeros(n), np.zeros((n, n)), u, eps)
    E = np.repeat(eps, H)
    x_star = -R / E  # R = Psi lam - u at Z = 0
    Z = _stiffness(n, seed)
    F = u + (Z - np.diag(E)) @ x_star
    assert len(set(state.ravel().tolist())) >= 2  # the known solution is on a kink-rich piece
    return law, Z, F, eps, x_star


LAWS = pytest.mark.parametrize("make", [_dlft, _coupled], ids=["dlft", "coupled"])


@LAWS
def test_newton_converges_to_the_known_solution(make):
    law, Z, F, eps, x_star = _problem(make)
    target = 1e-11 * np.abs(F).max()
    start = x_star + 0.2 * np.abs(x_star).max() * np.random.default_rng(1).standard_normal(x_star.size)
    x, ok, it, r, code = nw.newton(law, start, Z, F, eps, target, 50)
    assert ok and code == nw.CONVERGED and r <= target and it >= 1
    assert np.abs(x - x_star).max() <= 1e-9 * np.abs(x_star).max()


@LAWS
def test_newton_reports_non_convergence_with_its_status_and_residual(make):
    law, Z, F, eps, x_star = _problem(make)
    start = np.zeros_like(x_star)
    x, ok, it, r, code = nw.newton(law, start, Z, F, eps, 1e-30, 1)
    assert not ok and code == nw.BUDGET and it == 1
    R = _residual(law, x, Z, F, eps)[0]
    assert r == pytest.approx(np.abs(R).max(), rel=1e-12) and r > 0  # the residual at the returned point


def test_newton_reports_a_singular_jacobian():
    """The 1-D law with no stiffness and a unilateral contact open all period: its rows of ``J = Z + A (E -
    Z)`` are zero (``A = 0``)."""
    law, eps = _dlft()
    n = eps.size * H
    x0 = np.zeros(n)
    F = np.zeros(n)
    F[1], F[H] = 100.0, -1.0  # friction far past its limit; the unilateral contact open
    x, ok, it, r, code = nw.newton(law, x0, np.zeros((n, n)), F, eps, 1e-12, 10)
    assert code == nw.SINGULAR and not ok and it == 0 and r == np.inf and np.array_equal(x, x0)


WALKS = [(_dlft, False), (_dlft, True), (_coupled, True)]


@pytest.mark.parametrize("make, homotopy", WALKS, ids=["dlft-load", "dlft-newton", "coupled"])
def test_the_walk_reaches_p_end_on_the_known_solution(make, homotopy):
    """From ``x = 0`` at ``p = 0``: the global Newton homotopy (``r0 = R(0)``), or the load continuation
    (1-D law: with no force ``x = 0`` solves it, the friction contact stuck and the unilateral one open)."""
    law, Z, F, eps, x_star = _problem(make)
    n = x_star.size
    x0, zero = np.zeros(n), np.zeros(n)
    if homotopy:
        F0, F1, r0 = F, zero, _residual(law, x0, Z, F, eps)[0]
    else:
        F0, F1, r0 = zero, F, zero
    rec = np.empty((50_000, n)), np.empty(50_000), np.empty(50_000)
    x, p, pieces, arrived, k = nw.walk(law, x0, 0.0, 1.0, Z, F0, F1, r0, eps, 50_000, *rec)
    assert arrived and p == 1.0 and pieces >= 2
    # on the last piece, up to the nudges past the kinks: one full Newton step lands on the solution
    target = 1e-11 * np.abs(F).max()
    xp, ok, it, r, code = nw.newton(law, x, Z, F, eps, target, 50)
    assert ok and it <= 2 and np.abs(xp - x_star).max() <= 1e-9 * np.abs(x_star).max()
    assert k == pieces + 1 and rec[1][0] == 0.0 and rec[1][k - 1] == 1.0
    assert np.array_equal(rec[0][k - 1], x)
    # too few pieces: not arrived, and says how far it went
    x1, p1, pieces1, arrived1, _ = nw.walk(law, x0, 0.0, 1.0, Z, F0, F1, r0, eps, 1, *rec)
    assert not arrived1 and pieces1 == 1 and 0.0 < p1 < 1.0
