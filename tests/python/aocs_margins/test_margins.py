"""Margins of aocs_margins against cases derived by hand in this file: a double integrator with a PD law,
continuous (closed form), sampled with a zero-order hold (Jury's test on the closed-loop polynomial) and
with one period of delay (root locus of the closed-loop polynomial, and the loop's transfer function
written out here), never through python-control."""
from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.optimize import brentq

from aocs_margins import loop_model, margins
from aocs_margins.law_models import LinearLaw

J = np.diag([2000.0, 6000.0, 6000.0])
KP, KD = 1500.0, 6000.0      # u = -KP theta - KD w (KP on the angle itself)
T = 0.1


def pd_law(kp=KP, kd=KD) -> LinearLaw:
    return LinearLaw("pd", None, np.zeros((0, 6)), np.zeros((3, 0)),
                     np.hstack([-kp * np.eye(3), -kd * np.eye(3)]), "rotation", "linear")


def rigid_body() -> loop_model.Plant:
    a = np.zeros((6, 6))
    a[0:3, 3:6] = np.eye(3)
    return loop_model.Plant(a, np.vstack([np.zeros((3, 3)), np.linalg.inv(J)]), "rotation")


def l_hand(w, j, delay, kp=KP, kd=KD):
    """L(e^{jwT}) of one axis: ZOH double integrator read as angle T^2 (z + 1) / (2 j (z - 1)^2) and rate
    T / (j (z - 1)), times the PD gains, times z^-delay."""
    z = np.exp(1j * w * T)
    return z ** -delay * (kp * T ** 2 * (z + 1) / (2 * j * (z - 1) ** 2) + kd * T / (j * (z - 1)))


def k_critical(j, delay, kp=KP, kd=KD) -> float:
    """The loop gain at which a root of 2 j z^d (z - 1)^2 + k [kp T^2 (z + 1) + 2 kd T (z - 1)] leaves the unit
    disc (bisection on the roots)."""
    base = np.polymul([1.0] + [0.0] * delay, np.polymul([1, -1], [1, -1])) * 2 * j
    ctrl = np.array([kp * T ** 2 + 2 * kd * T, kp * T ** 2 - 2 * kd * T])

    def stable(k):
        return np.max(np.abs(np.roots(np.polyadd(base, k * ctrl)))) < 1.0

    lo, hi = 1.0, 1e3
    assert stable(lo) and not stable(hi)
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if stable(mid) else (lo, mid)
    return lo


def test_sampled_gain_margin_is_jurys_bound():
    # delay 0: z^2 + a1 z + a0 with a1 = -2 + k (kp T^2 + 2 kd T) / 2j, a0 = 1 + k (kp T^2 - 2 kd T) / 2j;
    # Jury: |a0| < 1 and 1 - a1 + a0 > 0 give k < 4 j / (2 kd T - kp T^2) and k < 2 j / (kd T)
    m = margins.loops(loop_model.loop(rigid_body(), pd_law(), T, delay=0))
    for ax, j in zip("xyz", np.diag(J)):
        k = min(4 * j / (2 * KD * T - KP * T ** 2), 2 * j / (KD * T))
        assert m[ax]["gain_margin_db"] == pytest.approx(20 * math.log10(k), abs=1e-6)
    assert m["mimo"]["gain_margin_db"] == pytest.approx(20 * math.log10(2 * J[0, 0] / (KD * T)), abs=1e-6)


def test_delayed_loop_margins_against_the_hand_model():
    m = margins.loops(loop_model.loop(rigid_body(), pd_law(), T, delay=1))
    for ax, j in zip("xyz", np.diag(J)):
        assert m[ax]["gain_margin_db"] == pytest.approx(20 * math.log10(k_critical(j, 1)), abs=1e-6)
        wc = brentq(lambda w: abs(l_hand(w, j, 1)) - 1.0, 1e-3, 0.999 * math.pi / T)
        pm = 180.0 + math.degrees(np.angle(l_hand(wc, j, 1)))
        assert m[ax]["crossover_rad_s"] == pytest.approx(wc, rel=1e-6)
        assert m[ax]["phase_margin_deg"] == pytest.approx(pm, abs=1e-4)
        assert m[ax]["delay_margin_s"] == pytest.approx(math.radians(pm) / wc, rel=1e-5)
        w = np.linspace(1e-3, 0.999 * math.pi / T, 200001)
        assert m[ax]["modulus_margin"] == pytest.approx(np.min(np.abs(1 + l_hand(w, j, 1))), rel=1e-4)
        # balanced disk margin (skew 0): 1 / max |(S - T) / 2| = 1 / max |(1 - L) / (2 (1 + L))|
        h = l_hand(w, j, 1)
        assert m[ax]["disk_margin"] == pytest.approx(1 / np.max(np.abs((1 - h) / (2 * (1 + h)))), rel=1e-3)
    # the same three decoupled axes: the MIMO uniform margins are the weakest axis's
    assert m["mimo"]["gain_margin_db"] == pytest.approx(m["x"]["gain_margin_db"], abs=1e-6)
    assert m["mimo"]["phase_margin_deg"] == pytest.approx(m["x"]["phase_margin_deg"], abs=1e-3)
    assert m["mimo"]["delay_margin_s"] == pytest.approx(m["x"]["delay_margin_s"], rel=1e-4)


def test_continuous_pd_closed_form():
    # L(s) = (kd s + kp) / (j s^2): |L| = 1 at w^2 = (kd^2 + sqrt(kd^4 + 4 j^2 kp^2)) / (2 j^2),
    # phase margin atan(kd w / kp), no phase crossover (infinite gain margin)
    m = margins.loops(loop_model.loop(rigid_body(), pd_law(), None), margins.grid(None, w_max=1e3))
    for ax, j in zip("xyz", np.diag(J)):
        wc = math.sqrt((KD ** 2 + math.sqrt(KD ** 4 + 4 * j ** 2 * KP ** 2)) / (2 * j ** 2))
        pm = math.degrees(math.atan(KD * wc / KP))
        assert m[ax]["crossover_rad_s"] == pytest.approx(wc, rel=1e-6)
        assert m[ax]["phase_margin_deg"] == pytest.approx(pm, abs=1e-4)
        assert m[ax]["delay_margin_s"] == pytest.approx(math.radians(pm) / wc, rel=1e-5)
        assert m[ax]["gain_margin_db"] is None


def test_a_delay_past_the_delay_margin_destabilises():
    big_l = loop_model.loop(rigid_body(), pd_law(), T, delay=1)
    dm = margins.loops(big_l)["mimo"]["delay_margin_s"]
    periods = int(dm / T)            # whole extra periods inside the margin, and one more past it
    assert loop_model.is_stable(loop_model.loop(rigid_body(), pd_law(), T, delay=1 + periods))
    assert not loop_model.is_stable(loop_model.loop(rigid_body(), pd_law(), T, delay=2 + periods))


def test_loop_at_one_axis_is_what_an_injection_there_measures():
    # coupled loop: e = S d, u_applied = -L S d, so with d on axis i only, -U_i / E_i = (L S)_ii / S_ii
    rng = np.random.default_rng(1)
    law = pd_law()
    law = LinearLaw("c", None, law.bc, law.cc, law.dc + 50.0 * rng.standard_normal((3, 6)), "rotation", "")
    big_l = loop_model.loop(rigid_body(), law, T, delay=1)
    w = np.array([0.05, 0.5, 2.0])
    fr = loop_model.response(big_l, w)
    for i in range(3):
        li = loop_model.response(loop_model.loop_at(big_l, i), w)[0, 0]
        for k in range(len(w)):
            s = np.linalg.inv(np.eye(3) + fr[:, :, k])
            assert li[k] == pytest.approx((fr[:, :, k] @ s)[i, i] / s[i, i], rel=1e-5)   # poles at z = 1


def test_mu_of_three_scalar_blocks_is_the_largest_spectral_radius_over_phases():
    # Doyle 1982: mu = max over diagonal unitary U of rho(U M) (the lower bound is tight); here by brute force
    # over a phase grid, against the D-scaled upper bound the margins use (equal for <= 3 complex blocks)
    rng = np.random.default_rng(3)
    ph = np.linspace(0.0, 2 * math.pi, 241)
    for _ in range(3):
        m = rng.standard_normal((3, 3)) + 1j * rng.standard_normal((3, 3))
        lower = max(np.max(np.abs(np.linalg.eigvals(np.diag([1.0, np.exp(1j * a), np.exp(1j * b)]) @ m)))
                    for a in ph for b in ph)
        mu = margins.mu_diagonal(m)
        assert lower <= mu * (1 + 1e-9) and mu == pytest.approx(lower, rel=2e-3)
    d = np.diag([0.3 + 0.4j, -2.0, 1.0j])
    assert margins.mu_diagonal(d) == pytest.approx(2.0, rel=1e-9)


def test_disk_margins_siso_formula_and_multiloop_bounds():
    big_l = loop_model.loop(rigid_body(), pd_law(), T, delay=1)
    m = margins.loops(big_l)
    # decoupled axes: the multiloop disk margin is the weakest axis's
    assert m["mimo"]["disk_margin"] == pytest.approx(min(m[a]["disk_margin"] for a in "xyz"), rel=1e-6)
    alpha, gain, phase = margins.disk_of(m["x"]["disk_margin"])
    assert 20 * math.log10(gain) == pytest.approx(m["x"]["disk_gain_margin_db"], rel=1e-9)
    assert phase == pytest.approx(m["x"]["disk_phase_margin_deg"], rel=1e-9)
    # coupled: the unstructured bound 1 / max sigma_max(S - I/2) <= multiloop <= every loop-at-a-time margin
    rng = np.random.default_rng(1)
    law = pd_law()
    law = LinearLaw("c", None, law.bc, law.cc, law.dc + 200.0 * rng.standard_normal((3, 6)), "rotation", "")
    big_l = loop_model.loop(rigid_body(), law, T, delay=1)
    assert loop_model.is_stable(big_l)
    m = margins.loops(big_l)
    w = margins.grid(T, n=3000)
    fr = loop_model.response(big_l, w)
    unstructured = 1 / max(np.linalg.svd(np.linalg.inv(np.eye(3) + fr[:, :, k]) - 0.5 * np.eye(3),
                                         compute_uv=False)[0] for k in range(len(w)))
    assert unstructured <= m["mimo"]["disk_margin"] * (1 + 1e-6)
    assert m["mimo"]["disk_margin"] <= min(m[a]["disk_margin"] for a in "xyz") * (1 + 1e-6)
