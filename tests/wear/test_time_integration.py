"""Tests of fretwear.wear.time_integration: direct time integration of wear with cycle jumps.

Oracles:

* frozen dynamics: a contact whose friction is dynamically negligible slides a
  distance per cycle fixed by the linear response, ``s = 4 F |H(omega)|``, so
  ``w = u0 (1 - exp(-K_w k_n s N))`` (continuous Archard law) and
  ``u0 (1 - (1 - K_w k_n s)^N)`` (per-period rule), with an a-priori bound on
  the effect of the tiny friction force;
* full stick never wears; slipping contacts wear monotonically with
  ``0 <= w < u0`` and ``F_N > 0``;
* scaling: ``w(N; K_w) = w(N / 2; 2 K_w)``;
* cycle jumps against every period integrated (``dN = 1``);
* bad input.
"""

from dataclasses import replace

import numpy as np
import pytest

from fretwear.model import FrictionContact, Model, paper_model
from fretwear.wear.time_integration import integrate_wear

TWO_PI = 2 * np.pi
OMEGA_PAPER = TWO_PI * 0.7  # the paper's frequency for its wear histories (F_ex = 10 N)

# frozen dynamics: m = k = 1, c = 0.1, F = 1 N at omega = 0.5 rad/s, friction to ground
M_, K_, C_, F_, OMEGA = 1.0, 1.0, 0.1, 1.0, 0.5
MU, KN, U0 = 1e-7, 1e7, 1e-6


def frozen_model() -> Model:
    return Model(
        M=[[M_]], C=[[C_]], K=[[K_]], force_cos=[F_], friction=(FrictionContact(0, None, MU, KN, U0),)
    )


def frozen_sliding() -> tuple[float, float]:
    """Sliding distance per cycle ``s`` (m) and a bound on its relative change by friction.

    The friction force is a load of magnitude ``g <= mu kn u0`` added to the
    linear system (superposition), so it moves the periodic response by at
    most ``g * integral |h|`` with the impulse response ``h``, and
    ``integral |h| <= 1 / (m omega_d zeta omega_n)``. The mass reverses twice
    per period, so ``s = 2 (max u - min u)`` changes by at most four times that.
    """
    s = 4 * F_ / abs(K_ - M_ * OMEGA**2 + 1j * C_ * OMEGA)
    wn = np.sqrt(K_ / M_)
    zeta = C_ / (2 * np.sqrt(K_ * M_))
    wd = wn * np.sqrt(1 - zeta**2)
    return s, 4 * MU * KN * U0 / (M_ * wd * zeta * wn) / s


def check_physical(history) -> None:
    """Monotone wear, 0 <= w < u0, F_N = kn (u0 - w) > 0, non-negative rates and sliding."""
    w, u0 = history.wear, history.u0
    assert np.all(np.diff(w, axis=0) >= 0)
    assert np.all(w >= 0) and np.all(w < u0)
    assert np.all(history.normal_load > 0)
    assert history.normal_load == pytest.approx(history.kn * (u0 - w), rel=1e-12, abs=1e-12)
    assert np.all(history.rate >= 0) and np.all(history.sliding_distance >= 0)


# ---------------------------------------------------------------------------
# 1. frozen dynamics: exact solutions
# ---------------------------------------------------------------------------
def test_frozen_dynamics_every_period():
    """``dN = 1``: the per-period rule exactly, and the continuous law within ``a / (2 e)``."""
    s, eps = frozen_sliding()
    a = 2e-3  # wear of the gap u0 - w per cycle: K_w kn s
    kw = a / (KN * s)
    hist = integrate_wear(frozen_model(), OMEGA, 1000, kw=kw, max_jump=0, record_every=25)
    assert hist.status == "horizon" and hist.cycles[-1] == 1000 and hist.info["periods"] == 1001
    N = hist.cycles
    assert np.all(hist.sliding_distance == pytest.approx(s, rel=eps))
    # with s within (1 +- eps), w deviates by at most u0 eps max(x exp(-x)) < u0 eps
    assert hist.wear[:, 0] == pytest.approx(U0 * (1 - (1 - a) ** N), abs=eps * U0)
    # per-period rule vs continuous law: |(1 - a)^N - exp(-a N)| <= a / (2 e) (1 + a)
    bound = (eps + a / (2 * np.e) * (1 + a)) * U0
    assert hist.wear[:, 0] == pytest.approx(U0 * (1 - np.exp(-a * N)), abs=bound)
    check_physical(hist)


def test_frozen_dynamics_cycle_jumps_reach_a_million_cycles():
    """The rate of ``z = -ln(1 - w / u0)`` is constant: jumps are exact and grow to the horizon."""
    s, eps = frozen_sliding()
    a = 1e-5
    kw = a / (KN * s)
    hist = integrate_wear(frozen_model(), OMEGA, 1e6, kw=kw, stop_fraction=0.999)
    assert hist.status == "worn" and hist.wear[-1, 0] >= 0.999 * U0
    assert hist.info["periods"] < 200 and hist.info["rejected_jumps"] == 0
    N = hist.cycles
    assert hist.wear[:, 0] == pytest.approx(U0 * (1 - (1 - a) ** N), abs=eps * U0)
    bound = (eps + a / (2 * np.e) * (1 + a)) * U0
    assert hist.wear[:, 0] == pytest.approx(U0 * (1 - np.exp(-a * N)), abs=bound)
    check_physical(hist)


# ---------------------------------------------------------------------------
# 2. stick never wears; slip wears monotonically
# ---------------------------------------------------------------------------
@pytest.mark.parametrize("f", [0.3, 1.5])
def test_full_stick_never_wears(f):
    hist = integrate_wear(paper_model(fex=10), TWO_PI * f, 1e5, kw=1e-11)
    assert hist.status == "stuck" and hist.converged
    assert np.array_equal(hist.cycles, [0.0, 1e5])
    assert np.all(hist.wear == 0) and np.all(hist.rate == 0) and np.all(hist.sliding_distance == 0)
    assert hist.normal_load == pytest.approx(10.0)
    assert hist.info["periods"] == 1 and hist.wall_time < 1.0


def test_slipping_contact_wears_monotonically_to_u0():
    hist = integrate_wear(paper_model(fex=10), OMEGA_PAPER, 1e5, kw=1e-11)
    assert hist.status == "worn" and hist.method == "time" and hist.converged
    assert hist.cycles[0] == 0 and hist.wear[0, 0] == 0
    assert 0.99 * hist.u0[0] <= hist.wear[-1, 0] < hist.u0[0]
    check_physical(hist)
    # wear relaxes the load: the contact slides more and the relative motion grows
    assert hist.sliding_distance[-1, 0] > 5 * hist.sliding_distance[0, 0]
    assert hist.relative_half_peak_to_peak[-1, 0] > 2 * hist.relative_half_peak_to_peak[0, 0]
    # records describe the cycle after N: rate = K_w F_N s
    assert hist.rate == pytest.approx(hist.kw * hist.normal_load * hist.sliding_distance, rel=1e-12)


def test_two_contacts_wear_monotonically():
    base = paper_model(fex=10)
    model = replace(base, friction=base.friction + (FrictionContact.from_normal_load(1, None, 1.0, 2.0),))
    hist = integrate_wear(model, TWO_PI * 0.6, 2e4, kw=1e-11, tol=1e-2)
    assert hist.status == "horizon" and hist.converged and hist.cycles[-1] == 2e4
    assert np.all(hist.wear[-1] > 0.2 * hist.u0)
    check_physical(hist)


def test_no_wear_coefficient_jumps_to_the_horizon():
    hist = integrate_wear(paper_model(fex=10), OMEGA_PAPER, 1e6, kw=0.0)
    assert hist.status == "horizon" and hist.cycles[-1] == 1e6
    assert np.all(hist.wear == 0) and hist.info["periods"] < 100


def test_absurd_wear_coefficient_is_flagged_and_stays_physical():
    """The paper's K_w = 1e-6 wears the contact through within the first cycle."""
    with pytest.warns(RuntimeWarning, match="wear per cycle"):
        hist = integrate_wear(paper_model(fex=10), OMEGA_PAPER, 100, kw=1e-6)
    assert hist.status == "worn" and hist.warnings
    assert np.all(hist.wear <= hist.u0) and np.all(hist.normal_load >= 0)


def test_failed_integration_keeps_the_history(monkeypatch):
    from fretwear.wear import time_integration as wear_time

    calls = {"n": 0}
    period_map = wear_time.period_map

    def failing(*args, **kwargs):
        calls["n"] += 1
        if calls["n"] > 40:
            raise RuntimeError("contact states could not be resolved")
        return period_map(*args, **kwargs)

    monkeypatch.setattr(wear_time, "period_map", failing)
    hist = integrate_wear(paper_model(fex=10), OMEGA_PAPER, 1e5, kw=1e-11)
    assert not hist.converged and hist.status.startswith("failed: contact states")
    assert len(hist.cycles) > 5 and hist.cycles[-1] > 100
    check_physical(hist)


# ---------------------------------------------------------------------------
# 3. scaling: w depends on K_w N only
# ---------------------------------------------------------------------------
def test_wear_depends_on_kw_times_cycles():
    """``w(N; K_w) = w(N / 2; 2 K_w)`` up to the two-scale error.

    Exact for the slow-time law; the per-period rule (``K_w k_n s`` <= 1e-3
    per cycle) and the lag of the dynamics behind the drifting orbit (its
    relative effect on the rate is about 2e-4 per 1e-11 of ``K_w``) break it
    slightly (measured: 3.6e-4 on the cycle counts, the same with tol = 1e-4),
    and each run carries its jump tolerance 1e-3 (measured error 1e-5).
    """
    model = paper_model(fex=10)
    one = integrate_wear(model, OMEGA_PAPER, 1e5, kw=1e-11)
    two = integrate_wear(model, OMEGA_PAPER, 5e4, kw=2e-11)
    for fraction in (0.1, 0.3, 0.5, 0.7, 0.9):
        assert one.cycles_to(fraction) == pytest.approx(2 * two.cycles_to(fraction), rel=1e-3)
    N = np.linspace(0, one.cycles[-1], 50)
    assert one.at(N)["wear"] == pytest.approx(two.at(N / 2)["wear"], abs=1e-3 * one.u0[0])


# ---------------------------------------------------------------------------
# 4. cycle jumps against every period integrated
# ---------------------------------------------------------------------------
def test_cycle_jumps_agree_with_every_period_integrated():
    """Paper model, F_ex = 10 N, f = 0.7 Hz, K_w = 1e-10 (wear per cycle 5e-4 u0 at the start), to 0.5 u0.

    ``tol`` bounds the relative error of each jump's increment, hence about
    ``tol`` or less on the cycle count at which a depth is reached, and the
    error on ``w`` stays below ``tol u0``; the jumps save more periods the
    slower the wear (56x at K_w = 1e-11 and tol = 1e-3 over the whole history).
    """
    model = paper_model(fex=10)
    exact = integrate_wear(model, OMEGA_PAPER, 520, kw=1e-10, max_jump=0, record_every=1)
    assert exact.info["periods"] == 521 and exact.wear[-1, 0] > 0.5 * exact.u0[0]
    check_physical(exact)
    for tol, saving in ((1e-2, 5), (1e-3, 2)):
        jumped = integrate_wear(model, OMEGA_PAPER, 520, kw=1e-10, tol=tol)
        assert jumped.info["jumps"] > 0 and jumped.info["periods"] < exact.info["periods"] / saving
        check_physical(jumped)
        # measured: 0.05 tol and 0.01 tol on w / u0, 0.06 tol and 0.01 tol on the cycle counts
        assert jumped.at(exact.cycles)["wear"] == pytest.approx(exact.wear, abs=0.2 * tol * exact.u0[0])
        for fraction in (0.1, 0.3, 0.5):
            assert jumped.cycles_to(fraction) == pytest.approx(exact.cycles_to(fraction), rel=0.2 * tol)


def test_start_from_rest_settles_before_jumping():
    """From rest the start-up transient is integrated in full; the history then joins the periodic start."""
    model = paper_model(fex=10)
    rest = integrate_wear(model, OMEGA_PAPER, 1e5, kw=1e-11, start="rest", tol=1e-2)
    periodic = integrate_wear(model, OMEGA_PAPER, 1e5, kw=1e-11, tol=1e-2)
    settle = rest.info["settle_periods"]
    assert settle > 100 and rest.info["periods"] > settle
    assert np.all(np.diff(rest.cycles)[rest.cycles[1:] <= settle] <= 3)  # no jump before settle
    assert rest.cycles_to(0.5) == pytest.approx(periodic.cycles_to(0.5), rel=0.01)
    check_physical(rest)


# ---------------------------------------------------------------------------
# 5. bad input
# ---------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"kw": -1e-11}, "kw"),
        ({"kw": float("nan")}, "kw"),
        ({"cycles": 0}, "cycles"),
        ({"cycles": -5}, "cycles"),
        ({"cycles": 10.5}, "cycles"),
        ({"omega": 0.0}, "omega"),
        ({"omega": -1.0}, "omega"),
        ({"omega": float("inf")}, "omega"),
        ({"tol": 0.0}, "tol"),
        ({"tol": -1e-3}, "tol"),
        ({"tol": 1.0}, "tol"),
        ({"stop_fraction": 0.0}, "stop_fraction"),
        ({"stop_fraction": 1.5}, "stop_fraction"),
        ({"max_jump": -1}, "max_jump"),
        ({"block": 0}, "block"),
        ({"settle_periods": -1}, "settle_periods"),
        ({"record_every": 0}, "record_every"),
        ({"samples": 3}, "samples"),
        ({"start": "cold"}, "start"),
        ({"wear0": [1e-6]}, "wear0"),
        ({"wear0": [-1e-9]}, "wear0"),
        ({"wear0": [0.0, 0.0]}, "wear0"),
    ],
)
def test_bad_input(kwargs, match):
    args = {"omega": OMEGA_PAPER, "cycles": 100, "kw": 1e-11} | kwargs
    with pytest.raises(ValueError, match=match):
        integrate_wear(paper_model(fex=10), args.pop("omega"), args.pop("cycles"), **args)


def test_bad_models():
    with pytest.raises(ValueError, match="u0"):
        integrate_wear(paper_model(normal_load=0.0), OMEGA_PAPER, 100, kw=1e-11)
    with pytest.raises(ValueError, match="mu"):
        integrate_wear(paper_model(mu=0.0), OMEGA_PAPER, 100, kw=1e-11)
