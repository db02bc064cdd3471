"""Estimation metrics (aocs_analysis/estimation.py, SPEC 5.7) against models written out here: quaternion
algebra from SPEC 1's formulas, a synthetic run whose error has a known covariance and a known AR(1) time
correlation, and the per-axis two-state Kalman filter of Farrenkopf (gyro ARW + RRW, star-tracker angles)
simulated step by step, whose steady state must match estimation_bounds."""
from __future__ import annotations

import json
import math
import struct

import numpy as np
import pytest

from aocs_analysis import estimation as E
from aocs_analysis import estimation_plots, plots
from aocs_analysis import estimation_transients as T
from aocs_analysis.estimation_bounds import between_updates, steady_state_per_axis
from figure_checks import x_extent

ARCSEC = 180.0 * 3600.0 / math.pi        # arcsec per rad
DEG_H = math.pi / 180.0 / 3600.0         # 1 deg/h in rad/s


# --------------------------------------------------------------------------- the test's own quaternion algebra
def qmul(q, p):
    """SPEC 1: q (x) p = [q4 pv + p4 qv - qv x pv ; q4 p4 - qv . pv], row-wise."""
    q, p = np.broadcast_arrays(np.asarray(q, float), np.asarray(p, float))
    qv, q4, pv, p4 = q[..., :3], q[..., 3:], p[..., :3], p[..., 3:]
    return np.concatenate([q4 * pv + p4 * qv - np.cross(qv, pv), q4 * p4 - np.sum(qv * pv, -1, keepdims=True)], -1)


def qexp(v):
    """Quaternion of the rotation vector v: [v/|v| sin(|v|/2); cos(|v|/2)], row-wise."""
    v = np.atleast_2d(np.asarray(v, float))
    a = np.linalg.norm(v, axis=1, keepdims=True)
    k = np.where(a > 0, np.sin(a / 2) / np.where(a > 0, a, 1), 0.5)
    return np.concatenate([v * k, np.cos(a / 2)], 1)


def dcm(q):
    """A(q) = (q4^2 - |v|^2) I + 2 v v^T - 2 q4 [v x] (maps N to B)."""
    v, s = q[:3], q[3]
    sk = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return (s * s - v @ v) * np.eye(3) + 2 * np.outer(v, v) - 2 * s * sk


def random_attitudes(rng, n):
    q = rng.standard_normal((n, 4))
    return q / np.linalg.norm(q, axis=1, keepdims=True)


# --------------------------------------------------------------------------- conventions
def test_the_covariance_is_the_row_major_upper_triangle():
    up = np.arange(21.0)[None, :]
    p = E.covariance_from_upper(up)[0]
    assert p[0, 0] == 0 and p[0, 5] == 5 and p[1, 1] == 6 and p[1, 5] == 10 and p[2, 2] == 11
    assert p[4, 5] == 19 and p[5, 5] == 20 and p[5, 0] == 5 and p[3, 1] == 8
    assert np.array_equal(p, p.T)
    for wrong in (np.zeros((1, 20)), np.zeros(21), np.zeros((2, 6, 5))):   # refused by name, not by numpy
        with pytest.raises(ValueError, match="est_p must be"):
            E.covariance_from_upper(wrong)


def test_a_known_rotation_about_x_shows_up_on_x_with_its_sign_in_b():
    """q_est = dq(-a x) (x) q_true: the truth is the estimate turned by +a about x, dth = (+a, 0, 0). From
    the matrices: A(q_true) A(q_est)^T = A(dq(dth)) ~ I - [dth x], whose (1, 2) element is +dth_x."""
    rng = np.random.default_rng(3)
    q_true = random_attitudes(rng, 5)
    for axis in range(3):
        a = 7.0 / ARCSEC
        v = np.zeros(3)
        v[axis] = -a
        q_est = qmul(qexp(v), q_true)
        dth = E.knowledge_error_rad(q_true, q_est)
        expect = np.zeros((5, 3))
        expect[:, axis] = a
        assert np.allclose(dth, expect, rtol=0, atol=1e-15)
        m = dcm(q_true[0]) @ dcm(q_est[0]).T
        dth_from_matrix = 0.5 * np.array([m[1, 2] - m[2, 1], m[2, 0] - m[0, 2], m[0, 1] - m[1, 0]])
        assert np.allclose(dth_from_matrix, expect[0], rtol=0, atol=1e-14)
        # the quaternions' sign and norm do not matter
        assert np.allclose(E.knowledge_error_rad(-2.0 * q_true, 0.5 * q_est), expect, rtol=0, atol=1e-15)


def test_a_large_error_is_its_exact_rotation_vector():
    rng = np.random.default_rng(4)
    q_true = random_attitudes(rng, 200)
    v = rng.normal(0.0, 1.0, (200, 3))
    v *= (rng.uniform(0.0, 3.1, 200) / np.linalg.norm(v, axis=1))[:, None]     # angles up to 3.1 rad
    q_est = qmul(qexp(-v), q_true)
    assert np.allclose(E.knowledge_error_rad(q_true, q_est), v, rtol=0, atol=1e-12)
    assert np.allclose(E.angle_rad(E.knowledge_error_rad(q_true, q_est)), np.linalg.norm(v, axis=1), atol=1e-12)
    assert np.array_equal(E.knowledge_error_rad(q_true, q_true), np.zeros((200, 3)))


def test_control_and_pointing_errors_are_the_angles_to_the_reference():
    """qd; the estimate 30 arcsec off about z (control error), the truth a further 4 arcsec about z
    (knowledge error): pointing error 34 arcsec; per axis 2 qe_z."""
    qd = random_attitudes(np.random.default_rng(5), 1)
    q_est = qmul(qexp([0.0, 0.0, 30.0 / ARCSEC]), qd)
    q_true = qmul(qexp([0.0, 0.0, 4.0 / ARCSEC]), q_est)
    ce, pe = E.control_error_arcsec(q_est, qd), E.pointing_error_arcsec(q_true, qd)
    assert ce["true_angle"][0] == pytest.approx(30.0, rel=1e-9)
    assert pe["true_angle"][0] == pytest.approx(34.0, rel=1e-9)
    assert pe["per_axis"][0, 2] == pytest.approx(34.0, rel=1e-6)
    assert E.knowledge_error_rad(q_true, q_est)[0, 2] * ARCSEC == pytest.approx(4.0, rel=1e-9)


def test_bias_error_is_estimate_minus_truth_in_deg_per_hour():
    est, true = np.array([[3.0, 0.0, -1.0]]) * DEG_H, np.array([[1.0, 0.5, 0.0]]) * DEG_H
    assert np.allclose(E.bias_error_deg_h(est, true), [[2.0, -0.5, -1.0]], rtol=1e-12)
    assert np.allclose(E.error_state(np.zeros((1, 3)), est, true)[0, 3:], (true - est)[0])


def test_the_nees_band_is_the_chi_square_table():
    """chi2 0.025 / 0.975 quantiles with 30 dof: 16.791, 46.979 (any chi-square table); 60 dof: 40.482, 83.298."""
    lo, hi = E.nees_band(3, 10)
    assert (lo, hi) == (pytest.approx(1.6791, abs=1e-4), pytest.approx(4.6979, abs=1e-4))
    lo, hi = E.nees_band(6, 10)
    assert (lo, hi) == (pytest.approx(4.0482, abs=1e-4), pytest.approx(8.3298, abs=1e-4))


def test_nees_of_a_known_error_and_a_broken_covariance():
    p = np.array([np.diag([4.0, 1.0, 1.0]), np.diag([1.0, -1.0, 1.0]), np.full((3, 3), np.nan)])
    e = np.array([[2.0, 1.0, 0.0], [1.0, 0.0, 0.0], [0.0, 0.0, 0.0]])
    eps = E.nees(e, p)
    assert eps[0] == pytest.approx(2.0) and np.isnan(eps[1]) and np.isnan(eps[2])
    pc = np.array([[[2.0, 1.0], [1.0, 2.0]]])       # e^T P^-1 e by hand: P^-1 = [[2, -1], [-1, 2]] / 3
    assert E.nees(np.array([[1.0, 1.0]]), pc)[0] == pytest.approx(2.0 / 3.0)
    # a P that is not quite symmetric (rounding in a filter's update) counts as its symmetric part (P + P^T) / 2,
    # not as whichever triangle the factorisation happens to read
    pa = np.array([[[2.0, 1.5], [0.5, 2.0]]])
    assert E.nees(np.array([[1.0, 1.0]]), pa)[0] == pytest.approx(2.0 / 3.0)


def test_autocorrelation_of_the_fewest_samples():
    """Two samples a, b about their mean +-d: rho(0) = 1, rho(1) = (-d^2 / 1) / (2 d^2 / 2) = -1, by hand;
    one sample (or one left by the mask and the NaNs) has no autocorrelation."""
    np.testing.assert_array_equal(E.autocorrelation([1.0, 3.0]), [1.0, -1.0])
    np.testing.assert_array_equal(E.autocorrelation([1.0, np.nan, 3.0]), [1.0, np.nan, -1.0])
    assert np.isnan(E.autocorrelation([2.0])).all()
    assert np.isnan(E.autocorrelation([1.0, np.nan, 3.0], mask=[True, True, False])).all()


def test_trailing_rms_over_its_window_only():
    """r(t_k) = rms over t in (t_k - W, t_k]: a constant 2 has rms 2 at every sample however long the run (the
    count of the window, not of the run so far); a NaN sample is left out; a step from 0 to 3 shows its rms
    sqrt(9 m / n) while the window holds m of the n samples after it."""
    from aocs_analysis.estimation_transients import trailing_rms
    t = np.arange(20) * 1.0
    np.testing.assert_allclose(trailing_rms(t, np.full((20, 1), 2.0), window_s=5.0)[:, 0], 2.0, rtol=1e-15)
    x = np.where(t >= 10, 3.0, 0.0)[:, None]
    x[12, 0] = np.nan
    r = trailing_rms(t, x, window_s=5.0)[:, 0]
    assert r[9] == 0.0
    assert r[11] == pytest.approx(math.sqrt(9.0 * 2 / 5))        # 7 .. 11: two samples of 3
    assert r[13] == pytest.approx(math.sqrt(9.0 * 3 / 4))        # 9 .. 13 without 12: 10, 11, 13
    assert r[19] == pytest.approx(3.0)


def test_the_sample_period_of_the_fewest_samples():
    assert E.sample_period_s([3.0, 3.25]) == 0.25
    for t in ([3.0], []):
        with pytest.raises(ValueError, match="need at least two samples"):
            E.sample_period_s(t)
    with pytest.raises(ValueError, match="uniform in time"):
        E.sample_period_s([0.0, 1.0, 3.0])
    # samples that do not advance in time have no period: refused, not a period of 0
    for t in ([5.0, 5.0], [5.0, 5.0, 5.0, 5.0], [2.0, 1.0, 0.0]):
        with pytest.raises(ValueError, match="uniform in time"):
            E.sample_period_s(t)


def test_rms_per_axis_by_hand_and_of_no_sample():
    """sqrt(mean x_i^2) per column over the masked rows; a mask that keeps no row gives one NaN per column (the
    figure is undefined), not an empty array."""
    x = np.array([[3.0, 0.0, 1.0], [4.0, 2.0, -1.0], [100.0, 100.0, 100.0]])
    np.testing.assert_allclose(E.rms_per_axis(x, [True, True, False]), [math.sqrt(12.5), math.sqrt(2.0), 1.0])
    none = E.rms_per_axis(x, [False, False, False])
    assert none.shape == (3,) and np.all(np.isnan(none))
    assert E.rms_per_axis(x, [False, True, False]).tolist() == [4.0, 2.0, 1.0]      # one row: |x_i|


def test_three_sigma_fraction_by_hand_on_each_attitude_axis():
    """(sample, axis) pairs inside 3 sigma over the attitude axes x, y, z by default: an error outside on y
    alone, then on z alone, of two samples with sigma 1 rad on every axis: 5 of 6 pairs each time; the bias
    axes when asked for (axes 3..5)."""
    p = np.tile(np.eye(6), (2, 1, 1))
    for axis in (1, 2):
        e = np.zeros((2, 6))
        e[0, axis] = 3.5
        assert E.three_sigma_fraction(e, p) == pytest.approx(5.0 / 6.0)
    e = np.zeros((2, 6))
    e[:, 4] = 10.0
    assert E.three_sigma_fraction(e, p) == 1.0 and E.three_sigma_fraction(e, p, axes=(3, 4, 5)) == pytest.approx(4 / 6)


def test_transients_need_both_the_sensors_and_the_control_rate():
    """The `transients` subsection predicts from the sensors at the control rate: none without either."""
    n = 200
    t, q, b = np.arange(n) * 0.1, np.tile([0.0, 0.0, 0.0, 1.0], (n, 1)), np.zeros((n, 3))
    p = np.tile((1e-10 * np.eye(6))[np.triu_indices(6)], (n, 1))
    sensors = E.SensorSet(5.0, 20.0, 2.0, 1e-5, 5e-7)
    assert E.analyse(t, q, q, b, b, p, q, sensors=sensors, control_rate_hz=10.0)[0]["transients"] is not None
    assert E.analyse(t, q, q, b, b, p, q, sensors=sensors, control_rate_hz=None)[0].get("transients") is None
    assert E.analyse(t, q, q, b, b, p, q, sensors=None, control_rate_hz=10.0)[0].get("transients") is None


def test_window_errors_by_hand():
    """Knowledge, control and pointing errors over the last window: small rotations about x by known angles
    (true angle 2 asin |qe_vec| = the angle), valid samples only, the window's first and last sample."""
    t = np.arange(10) * 1.0
    asec = math.pi / 180.0 / 3600.0

    def about_x(arcsec):
        a = np.asarray(arcsec, float) * asec
        return np.stack([np.sin(a / 2), 0 * a, 0 * a, np.cos(a / 2)], axis=1)

    qd = about_x(np.zeros(10))
    q_true = about_x(np.full(10, 3.0))
    q_est = about_x(np.arange(10.0))             # the estimate walks from 0 to 9 arcsec
    valid = np.ones(10, bool)
    valid[8] = False
    w = E.window_errors(t, q_true, q_est, qd, valid, window_s=3.0)    # t = 6, 7, 9 (8 not valid)
    assert (w["samples"], w["start_s"], w["end_s"]) == (3, 6.0, 9.0)
    assert w["pointing_arcsec"]["max"] == pytest.approx(3.0, rel=1e-6)
    assert w["control_arcsec"]["max"] == pytest.approx(9.0, rel=1e-6)
    assert w["control_arcsec"]["rms"] == pytest.approx(math.sqrt((36 + 49 + 81) / 3), rel=1e-6)
    assert w["knowledge_arcsec"]["max"] == pytest.approx(6.0, rel=1e-6)      # |3 - 9|


def test_steady_state_window_and_convergence_time():
    t = np.arange(100) * 0.5
    ang = np.r_[np.linspace(10.0, 0.5, 40), np.full(60, 0.5)]
    ang[30] = 0.1                                       # dips inside, then out again
    assert E.convergence_time_s(t, ang, 1.0, k=1.0) == pytest.approx(t[np.flatnonzero(ang > 1.0)[-1] + 1])
    assert E.convergence_time_s(t, ang, 1.0, k=1.0, valid=t < 49.0) is None   # invalid at the end: never
    m = E.steady_state_mask(t)
    assert t[m][0] == 25.0 and m[-1]          # t >= 49.5 - 24.75
    m = E.steady_state_mask(t, window_s=10.0, start_s=45.0, valid=t != 47.0)
    assert t[m][0] == 45.0 and 47.0 not in t[m] and np.count_nonzero(m) == 9
    # the fraction is in (0, 1]: the whole run at 1, nothing at or below 0 or above 1
    assert E.steady_state_mask(t, fraction=1.0).all()
    # the last half of the run's own span, for a log that starts late too: 5049.5 s on for 5000 s to 5099 s
    late = 5000.0 + np.arange(100) * 1.0
    assert late[E.steady_state_mask(late)].tolist() == (5050.0 + np.arange(50)).tolist()
    for bad in (0.0, -0.5, math.nextafter(1.0, 2.0)):
        with pytest.raises(ValueError, match=r"fraction must be in \(0, 1\]"):
            E.steady_state_mask(t, fraction=bad)


def test_bounds_in_b_follow_the_mounting():
    """A tracker turned 90 deg about x (q_SB): its boresight z_S is -y_B, so the about-boresight bound lands on
    y of B and a cross-boresight one on z."""
    cross, about = 2.0, 15.0
    s = np.sqrt(0.5)
    base = dict(noise_cross_arcsec=cross, noise_about_arcsec=about, rate_hz=4.0, arw_rad_sqrt_s=1e-6,
                rrw_rad_s_sqrt_s=1e-9)
    plain = E.steady_state_bounds(E.SensorSet(**base))
    turned = E.steady_state_bounds(E.SensorSet(**base, mounting_q=(s, 0.0, 0.0, s)))
    ref = steady_state_per_axis(cross, about, 4.0, 1e-6, 1e-9)
    assert np.allclose(plain["post_arcsec"], ref, rtol=1e-12)
    assert np.allclose(turned["post_arcsec"], [ref[0], ref[2], ref[1]], rtol=1e-12)
    for zero in ("noise_cross_arcsec", "noise_about_arcsec", "rate_hz"):   # no steady state without it
        assert E.steady_state_bounds(E.SensorSet(**{**base, zero: 0.0})) is None, zero


# --------------------------------------------------------------------------- synthetic run: known covariance, AR(1)
DT = 0.1
SIGMA = np.r_[np.array([2.0, 3.0, 8.0]) / ARCSEC, np.array([1.0, 2.0, 1.5]) * 1e-6]


def _covariance():
    r = np.eye(6)
    for i in range(3):
        r[i, i + 3] = r[i + 3, i] = -0.8          # attitude and bias errors strongly anti-correlated
    r[0, 1] = r[1, 0] = 0.3
    return np.outer(SIGMA, SIGMA) * r


def _synthetic_run(tau_s=5.0, n=200_000, seed=11):
    """e_k = a e_{k-1} + sqrt(1 - a^2) L w_k (stationary from k = 0), a = exp(-dt / tau): covariance C,
    correlation exp(-|lag| / tau). q_est = dq(-dth) (x) q_true, bias_est = bias_true - db."""
    rng = np.random.default_rng(seed)
    c = _covariance()
    w = rng.standard_normal((n, 6)) @ np.linalg.cholesky(c).T
    a = math.exp(-DT / tau_s)
    e = np.empty((n, 6))
    e[0] = w[0]
    b = math.sqrt(1.0 - a * a)
    for k in range(1, n):               # written out (no filter routine), 0.2 s
        e[k] = a * e[k - 1] + b * w[k]
    t = np.arange(n) * DT
    q_true = qmul(qexp(np.outer(t, [1e-4, -2e-4, 5e-5])), random_attitudes(rng, 1))   # a slow rotation
    q_est = qmul(qexp(-e[:, :3]), q_true)
    bias_true = np.array([1.0, -2.0, 0.5]) * DEG_H + np.outer(np.sin(t / 500.0), [1e-6, 0.0, 0.0])
    bias_est = bias_true - e[:, 3:]
    qd = q_true
    return t, e, q_true, q_est, bias_true, bias_est, qd, c


@pytest.fixture(scope="module")
def synthetic():
    return _synthetic_run()


def _upper(p):
    iu = np.triu_indices(6)
    return np.broadcast_to(p, (1, 6, 6))[:, iu[0], iu[1]]


def test_synthetic_run_rms_max_and_three_sigma(synthetic):
    t, e, q_true, q_est, bias_true, bias_est, qd, c = synthetic
    n = t.size
    est_p = np.repeat(_upper(c), n, axis=0)
    s = E.summary(t, q_true, q_est, bias_est, bias_true, est_p, qd)
    w = t >= t[-1] - 0.5 * (t[-1] - t[0])           # the default window: the last half
    ke = s["knowledge_error_arcsec"]
    assert ke["frame"] == "B"
    assert np.allclose(ke["rms_per_axis"], np.sqrt(np.mean(e[w, :3] ** 2, axis=0)) * ARCSEC, rtol=1e-9)
    assert ke["max"] == pytest.approx(np.max(np.linalg.norm(e[w, :3], axis=1)) * ARCSEC, rel=1e-9)
    # per axis of B over the window: the largest |dth_i| and the mean dth_i (three numbers each)
    assert np.allclose(ke["max_abs_per_axis"], np.max(np.abs(e[w, :3]), axis=0) * ARCSEC, rtol=1e-9)
    assert np.allclose(ke["mean_per_axis"], np.mean(e[w, :3], axis=0) * ARCSEC, rtol=0.0,
                       atol=1e-9 * np.max(np.abs(e[w, :3])) * ARCSEC)
    # the sample rms is the model's sigma (10^5 samples, ~10^4 independent: a few 0.1 %)
    assert np.allclose(ke["rms_per_axis"], SIGMA[:3] * ARCSEC, rtol=0.04)
    assert np.allclose(s["bias_error_deg_h"]["rms_per_axis"], SIGMA[3:] / DEG_H, rtol=0.04)
    assert s["three_sigma_fraction"] == pytest.approx(0.9973, abs=0.002)
    assert s["samples"] == {"total": n, "valid": n, "in_window": int(np.count_nonzero(w)),
                            "covariance_not_positive_definite": 0}
    # P four times too small: 3 sigma of the filter is 1.5 true sigma, 2 Phi(1.5) - 1 = 0.866
    s4 = E.summary(t, q_true, q_est, bias_est, bias_true, est_p / 4.0, qd)
    assert s4["three_sigma_fraction"] == pytest.approx(0.8664, abs=0.01)
    # the truth is the reference: the pointing error is 0, the control error is the knowledge error
    assert s["pointing_error_arcsec"]["max"] == pytest.approx(0.0, abs=1e-6)
    assert s["control_error_arcsec"]["max"] == pytest.approx(ke["max"], rel=1e-6)


def test_synthetic_run_nees_consistent_and_over_confident(synthetic):
    t, e, q_true, q_est, bias_true, bias_est, qd, c = synthetic
    est_p = np.repeat(_upper(c), t.size, axis=0)
    good = E.summary(t, q_true, q_est, bias_est, bias_true, est_p, qd)
    assert good["nees"]["mean"] == pytest.approx(6.0, rel=0.05)
    assert good["nees_attitude"]["mean"] == pytest.approx(3.0, rel=0.05)
    assert good["nees_in_band_fraction"] >= 0.9
    assert good["nees_attitude_in_band_fraction"] >= 0.9
    # the NEES of an AR(1) error of time constant tau decorrelates as exp(-2 |lag| / tau): its integrated
    # autocorrelation time is (1 + a^2) / (1 - a^2) dt ~ tau = 5 s; the spacing is twice that
    assert good["nees"]["autocorrelation_time_s"] == pytest.approx(5.0, rel=0.25)
    assert good["nees"]["autocorrelation_reliable"] is True
    assert good["nees"]["spacing_s"] == pytest.approx(2.0 * good["nees"]["autocorrelation_time_s"], abs=DT)
    assert good["nees"]["independent_windows"] >= 50
    # the band a window's mean is tested against, low then high: the chi-square quantiles of M x 6 dof over M
    m = good["nees"]["samples_per_window"]
    assert good["nees"]["band_of_window_mean"] == pytest.approx(list(E.nees_band(6, m)), rel=1e-12)
    assert good["nees"]["band_of_window_mean"][0] < 6.0 < good["nees"]["band_of_window_mean"][1]
    for scale in (0.25, 4.0):          # over-confident (P / 4) and under-confident (P x 4) both fail
        bad = E.summary(t, q_true, q_est, bias_est, bias_true, est_p * scale, qd)
        assert bad["nees_in_band_fraction"] <= 0.5 and bad["nees_attitude_in_band_fraction"] <= 0.5
    # the bias error's sign matters: with the attitude-bias correlation of -0.8, the wrong sign is inconsistent
    flipped = E.summary(t, q_true, q_est, 2 * bias_true - bias_est, bias_true, est_p, qd)
    assert flipped["nees"]["mean"] > 20.0 and flipped["nees_in_band_fraction"] <= 0.5


def test_consecutive_samples_are_not_independent_draws(synthetic):
    """The same consistent run, tested as if consecutive samples were independent (spacing one sample):
    the band of 10 samples is far too narrow for 10 correlated values, and most windows fail."""
    t, e, q_true, q_est, bias_true, bias_est, qd, c = synthetic
    eps = E.nees(e, np.broadcast_to(c, (t.size, 6, 6)))
    naive = E.nees_window_test(t, eps, 6, spacing_s=DT)
    honest = E.nees_window_test(t, eps, 6)
    assert naive.in_band_fraction < 0.6 < 0.9 <= honest.in_band_fraction


def test_invalid_samples_are_left_out(synthetic):
    t, e, q_true, q_est, bias_true, bias_est, qd, c = synthetic
    n = t.size
    est_p = np.repeat(_upper(c), n, axis=0)
    valid = np.ones(n, bool)
    bad = slice(int(0.7 * n), int(0.72 * n))
    valid[bad] = False
    q_junk = q_est.copy()
    q_junk[bad] = [0.0, 0.0, 1.0, 0.0]                         # 180 deg off where invalid
    s = E.summary(t, q_true, q_junk, bias_est, bias_true, est_p, qd, valid)
    w = (t >= t[-1] - 0.5 * (t[-1] - t[0])) & valid
    assert s["samples"]["in_window"] == int(np.count_nonzero(w))
    assert np.allclose(s["knowledge_error_arcsec"]["rms_per_axis"], np.sqrt(np.mean(e[w, :3] ** 2, 0)) * ARCSEC)
    assert s["knowledge_error_arcsec"]["max"] < 100.0
    assert s["three_sigma_fraction"] == pytest.approx(0.9973, abs=0.002)
    assert s["nees_in_band_fraction"] >= 0.9


# --------------------------------------------------------------------------- Farrenkopf's filter, simulated
def _farrenkopf_filter_runs(runs, duration_s, dt, every, sigma_n, sv, su, seed=7):
    """Per axis (3 axes x `runs` runs at once), the two-state (angle, bias) Kalman filter of a gyro with
    ARW sv and RRW su and an angle measurement of white noise sigma_n[axis] every `every` control periods
    dt; the body holds (true angle 0). The truth over a period, exactly: bias increment su dt^0.5 N1, its
    integral beta dt + su dt^1.5 (N1 / 2 + N2 / (2 sqrt 3)), ARW sv dt^0.5 N3. Returns t (n,), the error
    truth - estimate (n, runs, 6) as [angle x y z, bias x y z] and P (n, 6, 6) after each period."""
    rng = np.random.default_rng(seed)
    n = int(round(duration_s / dt))
    shape = (runs, 3)
    p11, p12, p22 = np.full(3, (60.0 / ARCSEC) ** 2), np.zeros(3), np.full(3, (2e-5) ** 2)
    th_hat = rng.normal(0.0, 60.0 / ARCSEC, shape)       # initial errors drawn from P0
    beta = rng.normal(0.0, 2e-5, shape)
    b_hat = np.zeros(shape)
    q11, q12, q22 = sv * sv * dt + su * su * dt ** 3 / 3, -su * su * dt * dt / 2, su * su * dt
    err = np.empty((n, runs, 6))
    cov = np.zeros((n, 6, 6))
    for k in range(n):
        n1, n2, n3 = rng.standard_normal((3,) + shape)
        integral = beta * dt + su * dt ** 1.5 * (n1 / 2 + n2 / (2 * math.sqrt(3)))
        beta = beta + su * math.sqrt(dt) * n1
        th_hat = th_hat + (integral + sv * math.sqrt(dt) * n3) - b_hat * dt      # gyro angle minus the bias
        p11, p12, p22 = p11 - 2 * dt * p12 + dt * dt * p22 + q11, p12 - dt * p22 + q12, p22 + q22
        if (k + 1) % every == 0:
            y = sigma_n * rng.standard_normal(shape) - th_hat                   # z = 0 + noise
            s = p11 + sigma_n ** 2
            k1, k2 = p11 / s, p12 / s
            th_hat, b_hat = th_hat + k1 * y, b_hat + k2 * y
            p11, p12, p22 = (1 - k1) * p11, (1 - k1) * p12, p22 - k2 * p12
        err[k, :, :3], err[k, :, 3:] = -th_hat, beta - b_hat
        i = np.arange(3)
        cov[k, i, i], cov[k, i, i + 3], cov[k, i + 3, i], cov[k, i + 3, i + 3] = p11, p12, p12, p22
    return np.arange(1, n + 1) * dt, err, cov, beta


FK = dict(dt=0.25, every=2, cross=5.0, about=20.0, sv=1e-5, su=5e-7)


def _farrenkopf_analysis():
    """8 runs of 4000 s: each run's (estimation section, the same with P / 4, the plot series)."""
    sn = np.array([FK["cross"], FK["cross"], FK["about"]]) / ARCSEC
    runs = 8
    t, err, cov, _ = _farrenkopf_filter_runs(runs, 4000.0, FK["dt"], FK["every"], sn, FK["sv"], FK["su"])
    rng = np.random.default_rng(8)
    sensors = E.SensorSet(FK["cross"], FK["about"], 1.0 / (FK["dt"] * FK["every"]), FK["sv"], FK["su"])
    out = []
    for r in range(runs):
        q_true = qmul(qexp(np.outer(t, [2e-4, 0.0, -1e-4])), random_attitudes(rng, 1))
        q_est = qmul(qexp(-err[:, r, :3]), q_true)
        bias_true = np.full((t.size, 3), 0.3 * DEG_H) + err[:, r, 3:]          # any truth: only the error counts
        bias_est = bias_true - err[:, r, 3:]
        est_p = cov[:, np.triu_indices(6)[0], np.triu_indices(6)[1]]
        sec, series = E.analyse(t, q_true, q_est, bias_est, bias_true, est_p, q_true, sensors=sensors,
                                control_rate_hz=1.0 / FK["dt"])
        over = E.summary(t, q_true, q_est, bias_est, bias_true, est_p / 4.0, q_true, sensors=sensors,
                         control_rate_hz=1.0 / FK["dt"])
        out.append((sec, over, series))
    return t, err, out


@pytest.fixture(scope="module")
def farrenkopf_runs():
    return _farrenkopf_analysis()


def test_farrenkopf_filter_steady_state_matches_the_bound(farrenkopf_runs):
    """Pooled over 8 runs x 2000 s of steady state, the knowledge error's rms per axis is estimation_bounds'
    rms over the control periods of an update interval (between_updates) within 3 %; the filter's own
    sigma is the bound (the simulated filter is the bound's filter); post- and pre-update bounds bracket it."""
    t, err, out = farrenkopf_runs
    sn = np.array([FK["cross"], FK["cross"], FK["about"]]) / ARCSEC
    log_rms = np.array([between_updates(s, FK["sv"], FK["su"], FK["dt"] * FK["every"], FK["every"]) for s in sn])
    rms = np.sqrt(np.mean([np.square(sec["knowledge_error_arcsec"]["rms_per_axis"]) for sec, _, _ in out], axis=0))
    assert np.allclose(rms, log_rms * ARCSEC, rtol=0.03)
    sec = out[0][0]
    assert np.allclose(sec["steady_state_bound_log_rms_arcsec"], log_rms * ARCSEC, rtol=1e-12)
    assert np.allclose(sec["knowledge_error_arcsec"]["filter_sigma_rms_per_axis"], log_rms * ARCSEC, rtol=1e-3)
    post = steady_state_per_axis(FK["cross"], FK["about"], 2.0, FK["sv"], FK["su"])
    assert np.allclose(sec["steady_state_bound_arcsec"], post, rtol=1e-12)
    assert np.all(np.array(post) < rms) and np.all(rms < np.array(sec["steady_state_bound_pre_arcsec"]))
    bias_rms = np.sqrt(np.mean([np.square(s["bias_error_deg_h"]["rms_per_axis"]) for s, _, _ in out], axis=0))
    assert np.allclose(bias_rms, sec["bias_error_deg_h"]["steady_state_bound"], rtol=0.12)
    assert sec["convergence_time_s"] is not None and sec["convergence_time_s"] < 200.0
    assert sec["window"]["start_s"] == pytest.approx(t[-1] / 2, abs=FK["dt"])


def test_farrenkopf_filter_is_consistent_and_its_over_confident_twin_is_not(farrenkopf_runs):
    _, _, out = farrenkopf_runs
    for key, sub in (("nees_in_band_fraction", "nees"), ("nees_attitude_in_band_fraction", "nees_attitude")):
        # the spacing follows the slowest component (the bias error's, tens of s here): a run whose tested half
        # spans fewer than 50 of its autocorrelation times has no fraction, and says why (1 of these 8, 6 dof)
        have = [sec[key] for sec, _, _ in out if sec[key] is not None]
        assert len(have) >= 6, key
        assert all(sec[sub]["none_because"] for sec, _, _ in out if sec[key] is None)
        assert np.mean(have) >= 0.93, (key, have)       # 0.956 (6 dof) and 0.952 (3 dof) on this seed
        assert max(over[key] or 0.0 for _, over, _ in out) <= 0.5, key
    assert np.mean([sec["nees"]["mean"] for sec, _, _ in out]) == pytest.approx(6.0, rel=0.05)
    assert np.mean([sec["nees_attitude"]["mean"] for sec, _, _ in out]) == pytest.approx(3.0, rel=0.05)
    assert np.mean([sec["three_sigma_fraction"] for sec, _, _ in out]) == pytest.approx(0.9973, abs=0.002)
    assert max(over["three_sigma_fraction"] for _, over, _ in out) < 0.9


def test_the_section_has_the_names_scripts_look_for(farrenkopf_runs):
    t, sec = farrenkopf_runs[0], farrenkopf_runs[2][0][0]
    assert {"knowledge_error_arcsec", "steady_state_bound_arcsec", "nees_in_band_fraction", "three_sigma_fraction",
            "sensors"} <= set(sec)
    # the transients' times are from the first sample of the series, which the section names
    assert sec["transients"]["convergence"]["measured_from_s"] == t[0] and t[1] > t[0]
    assert {"rms_per_axis", "frame", "max"} <= set(sec["knowledge_error_arcsec"])
    assert len(sec["knowledge_error_arcsec"]["rms_per_axis"]) == 3 and len(sec["steady_state_bound_arcsec"]) == 3
    assert sec["sensors"] == {"star_tracker": {"noise_cross_arcsec": 5.0, "noise_about_arcsec": 20.0, "rate_hz": 2.0,
                                               "mounting_q": [0.0, 0.0, 0.0, 1.0]},
                              "gyro": {"arw_rad_sqrt_s": 1e-5, "rrw_rad_s_sqrt_s": 5e-7}}
    json.dumps(sec, allow_nan=False)         # JSON-safe as it is


# --------------------------------------------------------------------------- plots
def _png_size_and_dpi(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    w, h = struct.unpack(">II", data[16:24])
    dpi, off = None, 8
    while off < len(data):
        n, kind = struct.unpack(">I4s", data[off:off + 8])
        if kind == b"pHYs":
            ppm_x, _, unit = struct.unpack(">IIB", data[off + 8:off + 17])
            dpi = ppm_x * 0.0254 if unit == 1 else None
        off += 12 + n
    return w, h, dpi


def test_plots_are_written_with_their_axes_labels_and_bands(farrenkopf_runs, tmp_path, monkeypatch):
    series = farrenkopf_runs[2][0][2]
    seen, spans, lines, ylims, ticks, boxes, bands = {}, {}, {}, {}, {}, {}, {}
    real_save = estimation_plots.save

    def spy(fig, path):
        ylims[path.name] = [ax.get_ylim() for ax in fig.axes]
        ticks[path.name] = [t.label1.get_fontsize() for ax in fig.axes for t in ax.yaxis.get_major_ticks()]
        seen[path.name] = [(ax.get_ylabel(), ax.get_xlabel(), [t.get_text() for t in ax.get_legend().get_texts()])
                           for ax in fig.axes]
        spans[path.name] = [[x_extent(p) for p in ax.patches if p.get_label() == "tested window"] for ax in fig.axes]
        bands[path.name] = [c.get_linewidth() for ax in fig.axes for c in ax.collections if "3 sigma" in c.get_label()]
        lines[path.name] = [ln for ax in fig.axes for ln in ax.lines]     # labelled or not (the -3 sigma line)
        r = fig.canvas.get_renderer()   # (Agg; closed by save) the extents after save: its tight_layout done
        out = real_save(fig, path)
        boxes[path.name] = [(ax.get_legend().get_window_extent(r), ax.get_window_extent(r), fig.bbox)
                            for ax in fig.axes]
        return out

    monkeypatch.setattr(estimation_plots, "save", spy)
    files = estimation_plots.run_plots(series, tmp_path, "test")
    assert [f.name for f in files] == ["knowledge_error.png", "bias_estimate.png", "nees.png"]
    for f in files:
        w, h, dpi = _png_size_and_dpi(f)
        assert w >= 1200 and h >= 1000 and dpi is not None and dpi >= 150, (f.name, w, h, dpi)
    ke = seen["knowledge_error.png"]
    assert [y for y, _, _ in ke] == ["dth_x (arcsec)", "dth_y (arcsec)", "dth_z (arcsec)"] and ke[-1][1] == "t (s)"
    assert all("filter +-3 sigma (P)" in lab and any(s.startswith("analytic +-3 sigma") for s in lab)
               and any(s.startswith("converged at") for s in lab) for _, _, lab in ke)
    assert [y for y, _, _ in seen["bias_estimate.png"]] == ["b_x (deg/h)", "b_y (deg/h)", "b_z (deg/h)"]
    assert all({"estimate b_" + a, "truth b_" + a} <= set(lab) for a, (_, _, lab) in zip("xyz", seen["bias_estimate.png"]))
    nees = seen["nees.png"]
    assert [y for y, _, _ in nees] == ["NEES, 6 dof (-)", "NEES, 3 dof (-)"]
    assert all(any(s.startswith("95 % band of the mean") for s in lab) and any(s.startswith("expected") for s in lab)
               for _, _, lab in nees)
    # every panel shades the tested window from its first to its last sample, and every line is drawn, in a
    # legend or not (a line of width 0 without a marker is not on the figure)
    ts = np.asarray(series["t"])[np.asarray(series["steady"], dtype=bool)]
    for name, per_axes in spans.items():
        assert per_axes == [[pytest.approx((ts[0], ts[-1]), rel=1e-9)]] * len(per_axes), name
    for name, drawn in lines.items():
        invisible = [ln.get_label() for ln in drawn
                     if not (ln.get_linewidth() > 0.0 and ln.get_linestyle() not in ("None", "", " "))
                     and ln.get_marker() in (None, "None", "", " ")]
        assert not invisible, (name, invisible)
    # the +-3 sigma bands are shading only (no edge line reads as a bound), one per axis on the bias plot
    assert len(bands["bias_estimate.png"]) == 3
    assert all(np.all(np.asarray(w) == 0.0) for ws in bands.values() for w in ws), bands
    # every legend outside its axes on the right (the traces stay visible) and whole on the figure
    for name, per_axes in boxes.items():
        for leg, ax, fig in per_axes:
            assert leg.x0 >= ax.x1 and leg.x1 <= fig.x1 and leg.y0 >= fig.y0 and leg.y1 <= fig.y1, (name, leg, ax, fig)
    # the house style of plots.py: tick labels as plots.new_axes makes them
    fig0, ax0 = plots.new_axes("house style", "y")
    house = ax0.yaxis.get_major_ticks()[0].label1.get_fontsize()
    plots._plt().close(fig0)
    for name, sizes in ticks.items():
        assert sizes and set(sizes) == {house}, (name, set(sizes), house)
    # knowledge_error.png: a range symmetric about 0 that is the tested window's (module docstring): it holds
    # every steady sample, its 3 sigma and the analytic 3 sigma, and not much more
    steady, valid = np.asarray(series["steady"], bool), np.asarray(series["valid"], bool)
    for i, (lo, hi) in enumerate(ylims["knowledge_error.png"]):
        sel = steady & valid
        need = max(np.max(np.abs(series["knowledge_arcsec"][sel, i])), np.max(3.0 * series["sigma_arcsec"][sel, i]),
                   3.0 * series["bound_post_arcsec"][i])
        assert lo == pytest.approx(-hi, rel=1e-12) and need <= hi <= 1.5 * need, (i, lo, hi, need)
    # the analytic bound at +3 sigma and at -3 sigma on each axis
    for i in range(3):
        at = sorted(float(ln.get_ydata()[0]) for ln in lines["knowledge_error.png"]
                    if ln.axes is not None and ln.get_color() == "red" and len(ln.get_ydata()) == 2
                    and ln.axes.get_ylabel() == f"dth_{'xyz'[i]} (arcsec)")
        assert at == pytest.approx([-3.0 * series["bound_post_arcsec"][i], 3.0 * series["bound_post_arcsec"][i]])


def test_a_run_too_short_for_its_correlation_time_gives_no_fraction():
    """tau = 200 s and a 1000 s window: 5 correlation times, not the 50 the autocorrelation estimate needs."""
    t, e, q_true, q_est, bias_true, bias_est, qd, c = _synthetic_run(tau_s=200.0, n=20_000, seed=12)
    s = E.summary(t, q_true, q_est, bias_est, bias_true, np.repeat(_upper(c), t.size, axis=0), qd)
    assert s["nees_in_band_fraction"] is None and s["nees_attitude_in_band_fraction"] is None
    assert s["nees"]["autocorrelation_reliable"] is False and "50 autocorrelation times" in s["nees"]["none_because"]
    assert s["three_sigma_fraction"] is not None      # still counted: it needs no independence


def _mixed_time_scale_errors(n, taus_s, seed):
    """An independent generator: three unit-variance AR(1) errors of their own time constants (the hold's
    attitude error: about 1 s across the boresight, 8.5 s about it), written out here."""
    rng = np.random.default_rng(seed)
    a = np.exp(-DT / np.asarray(taus_s, float))
    b = np.sqrt(1.0 - a * a)
    w = rng.standard_normal((n, len(taus_s)))
    e = np.empty_like(w)
    e[0] = w[0]
    for k in range(1, n):
        e[k] = a * e[k - 1] + b * w[k]
    return e


def test_the_spacing_follows_the_slowest_component_of_the_nees():
    """A consistent error whose axes decorrelate at 1, 1 and 8.5 s (P = I): spaced by the NEES's own tau (the
    weighted mean of its parts) the windows scatter beyond the band (0.93 of them inside on these seeds); spaced
    by the slowest component's tau about 0.95 are; the same errors 1.5 times too large (the filter
    over-confident by 1.5) fall far below (about 0.1)."""
    fractions, old, bad = [], [], []
    for seed in (1, 2, 3):
        e = _mixed_time_scale_errors(200_000, (1.0, 1.0, 8.5), seed)
        t = np.arange(e.shape[0]) * DT
        p = np.broadcast_to(np.eye(3), (t.size, 3, 3))
        eps = E.nees(e, p)
        new = E.nees_window_test(t, eps, 3, components=e)
        # the slow axis' square decorrelates in tau = 8.5 s (its integrated time): the spacing is twice that
        assert new.tau_s == pytest.approx(8.5, rel=0.2) and new.spacing_s >= 2.0 * new.tau_s - DT
        fractions.append(new.in_band_fraction)
        old.append(E.nees_window_test(t, eps, 3).in_band_fraction)
        bad.append(E.nees_window_test(t, E.nees(1.5 * e, p), 3, components=1.5 * e).in_band_fraction)
    assert 0.935 <= np.mean(fractions) <= 0.965, fractions
    assert np.mean(old) < np.mean(fractions) - 0.01, (old, fractions)
    assert max(bad) < 0.3, bad


def test_the_ensemble_nees_of_independent_runs_is_in_its_band_95_percent_of_the_time():
    """Bar-Shalom's Monte Carlo test: 8 independent runs of a consistent error (own generator, correlated in
    time within a run): the ensemble mean at each instant is in the chi2(8 n) / 8 band at about 95 % of the
    instants; errors 1.5 times too large (an over-confident filter) almost never."""
    runs = [_mixed_time_scale_errors(20_000, (1.0, 1.0, 8.5, 300.0, 300.0, 300.0), seed) for seed in range(8)]
    eps = np.array([np.sum(e * e, axis=1) for e in runs])           # P = I: the NEES is |e|^2
    good = E.nees_ensemble_test(eps, 6)
    assert good["band"] == pytest.approx(list(E.nees_band(6, 8)))
    assert 0.92 <= good["in_band_fraction"] <= 0.98, good
    assert E.nees_ensemble_test(2.25 * eps, 6)["in_band_fraction"] < 0.2


def test_a_mean_at_either_edge_of_the_band_is_inside():
    """The band is closed: window means (two samples, so that the mean of equal values is exact) at exactly
    its upper quantile, and ensemble means (two runs) at exactly its lower one, are in band."""
    t = np.arange(20) * 0.1
    lo, hi = E.nees_band(3, 2)
    w = E.nees_window_test(t, np.full(t.size, hi), 3, samples_per_window=2, spacing_s=0.1)
    assert w.windows == 10 and w.in_band_fraction == 1.0
    assert E.nees_window_test(t, np.full(t.size, np.nextafter(hi, 2 * hi)), 3, samples_per_window=2,
                              spacing_s=0.1).in_band_fraction == 0.0
    assert E.nees_ensemble_test(np.full((2, 5), lo), 3)["in_band_fraction"] == 1.0     # 2 runs: the same band
    assert E.nees_ensemble_test(np.full((2, 5), np.nextafter(lo, 0.0)), 3)["in_band_fraction"] == 0.0


def test_the_fewest_samples_that_make_a_window():
    """Windows of M = 10 samples spaced s = 2 samples apart: 19 tested samples (indices 0, 2, .., 18) hold one
    window, on the first phase; 20 one on each phase; 18 none, and the test says so."""
    t = np.arange(20) * 0.1
    eps = np.full(t.size, 3.0)
    for n, windows in ((20, 2), (19, 1)):
        w = E.nees_window_test(t[:n], eps[:n], 3, samples_per_window=10, spacing_s=0.2)
        assert (w.spacing_samples, w.windows, w.in_band_fraction) == (2, windows, 1.0), n
    short = E.nees_window_test(t[:18], eps[:18], 3, samples_per_window=10, spacing_s=0.2)
    assert short.windows == 0 and short.in_band_fraction is None and "fewer than 10 samples" in short.reason


def test_the_ensemble_test_takes_runs_by_instants_only():
    """eps_runs is (runs, n): one run given as a flat series, no run at all, or a third axis is refused."""
    for bad in (np.ones(5), np.zeros((0, 5)), np.ones((2, 5, 3))):
        with pytest.raises(ValueError, match="eps_runs must be"):
            E.nees_ensemble_test(bad, 3)
    one = E.nees_ensemble_test(np.full((1, 4), 3.0), 3)      # one run of mean 3 = dof: inside its band
    assert (one["runs"], one["instants"], one["in_band_fraction"], one["mean"]) == (1, 4, 1.0, 3.0)


def test_the_predicted_convergence_is_looked_for_over_the_runs_own_span():
    """A log that starts late (t0 = 5000 s, the filter's start): the prediction runs over the log's span, t_end -
    t0 plus one period, whatever t0 is: a span shorter than the predicted time gives none, a longer one the
    time predicted from the start."""
    sensors = E.SensorSet(5.0, 20.0, 2.0, 1e-5, 5e-7)
    start = {"p0_att_rad": 1e-2, "p0_bias_radps": 1e-5, "e0_att_B_rad": np.array([5e-3, -4e-3, 2e-3]),
             "e0_bias_B_radps": np.array([2e-6, 0.0, -1e-6])}
    full = T.predicted_convergence(sensors, 10.0, start["p0_att_rad"], start["p0_bias_radps"], start["e0_att_B_rad"],
                                   start["e0_bias_B_radps"], 2000.0, k=T.PREDICTION_K)["time_s"]
    assert full is not None and 5.0 < full < 1000.0
    for span, want in ((0.5 * full, None), (2.0 * full, full)):
        t = 5000.0 + np.arange(0.0, span, 0.1)
        n = t.size
        rep = E._transients(t, np.zeros((n, 3)), np.broadcast_to(np.eye(6) * 1e-12, (n, 6, 6)), np.ones(n, bool),
                            sensors, 10.0, [], start)
        got = rep["convergence"]["predicted_time_s"]
        assert got == (None if want is None else pytest.approx(want)), (span, got)


def test_the_measured_convergence_is_timed_from_the_logs_first_sample():
    """The same knowledge error (1 arcsec decaying with a 30 s time constant) in a log from 0 s and in one from
    5000 s: the measured convergence is the same time after the first sample in both, and some time at all."""
    sensors = E.SensorSet(5.0, 20.0, 2.0, 1e-5, 5e-7)
    rel = np.arange(0.0, 1500.0, 0.1)
    n = rel.size
    dth = np.exp(-rel / 30.0)[:, None] * np.array([1.0, -1.0, 0.5]) * (1000.0 / ARCSEC)
    got = []
    for t0 in (0.0, 5000.0):
        rep = E._transients(t0 + rel, dth, np.broadcast_to(np.eye(6) * 1e-12, (n, 6, 6)), np.ones(n, bool),
                            sensors, 10.0, [], None)
        assert rep["convergence"]["measured_from_s"] == t0
        got.append(rep["convergence"]["time_s"])
    assert got[0] is not None and 0.0 < got[0] < 1000.0
    assert got[1] == pytest.approx(got[0], abs=1e-6)


def _drawn_axes(plot, series, tmp_path, monkeypatch):
    """The panels of the figure `plot` (a function of estimation_plots) draws from series."""
    figs = []
    real_save = estimation_plots.save
    monkeypatch.setattr(estimation_plots, "save", lambda fig, path: (figs.append(fig), real_save(fig, path))[1])
    plot(series, tmp_path / "plot.png", "test")
    (fig,) = figs
    return fig.axes


def _knowledge_series(e, valid):
    t = np.arange(0.0, 100.0, 1.0)
    return {"t": t, "steady": t >= 50.0, "valid": valid, "knowledge_arcsec": e,
            "sigma_arcsec": np.full((t.size, 3), 0.1), "bound_post_arcsec": None, "convergence_time_s": None}


@pytest.mark.parametrize("peak,noted", [(1.3, False), (1.3000001, True)])
def test_the_clipped_note_only_when_a_sample_is_beyond_the_range_drawn(tmp_path, monkeypatch, peak, noted):
    """knowledge_error.png's range is 1.3 times the tested window's largest figure (here an error of 1 arcsec):
    a transient before the window at exactly that range is drawn at its edge (no note), one beyond it is
    clipped and the panel says so."""
    e = np.zeros((100, 3))
    e[5, :] = peak
    e[60:, :] = 1.0
    for ax in _drawn_axes(estimation_plots.knowledge_error_plot, _knowledge_series(e, np.ones(100, bool)), tmp_path, monkeypatch):
        assert ax.get_ylim() == pytest.approx((-1.3, 1.3))
        assert any("clipped" in a.get_text() for a in ax.texts) is noted


def test_an_invalid_sample_is_never_the_clipped_transient(tmp_path, monkeypatch):
    """A sample without an estimate (valid false) is not drawn, so it clips nothing, whatever its stored error:
    the window's 0.5 arcsec give a range of +-0.65 and the invalid 50 arcsec at 5 s no note."""
    e = np.zeros((100, 3))
    e[5, :] = 50.0
    e[60:, :] = 0.5
    valid = np.ones(100, bool)
    valid[5] = False
    for ax in _drawn_axes(estimation_plots.knowledge_error_plot, _knowledge_series(e, valid), tmp_path, monkeypatch):
        assert ax.get_ylim() == pytest.approx((-0.65, 0.65))
        assert not any("clipped" in a.get_text() for a in ax.texts)


def _band_extents(plot, series, tmp_path, monkeypatch) -> list[tuple[float, float]]:
    """(lowest, highest) y of the "3 sigma" band on each panel of the figure `plot` draws from series."""
    out = []
    for ax in _drawn_axes(plot, series, tmp_path, monkeypatch):
        (band,) = [c for c in ax.collections if "3 sigma" in c.get_label()]
        y = np.concatenate([p.vertices[:, 1] for p in band.get_paths()])
        out.append((float(y.min()), float(y.max())))
    return out


def test_the_knowledge_band_is_plus_and_minus_three_sigma(tmp_path, monkeypatch):
    """knowledge_error.png: on each axis the filter's band runs from -3 sigma to +3 sigma about zero (sigma 0.1,
    0.2, 0.3 arcsec)."""
    t = np.arange(0.0, 10.0, 1.0)
    n = t.size
    series = {"t": t, "steady": t >= 5.0, "valid": np.ones(n, bool), "knowledge_arcsec": np.zeros((n, 3)),
              "sigma_arcsec": np.tile([0.1, 0.2, 0.3], (n, 1)), "bound_post_arcsec": None,
              "convergence_time_s": None}
    got = _band_extents(estimation_plots.knowledge_error_plot, series, tmp_path, monkeypatch)
    np.testing.assert_allclose(got, [(-0.3, 0.3), (-0.6, 0.6), (-0.9, 0.9)], rtol=1e-12)


def test_the_bias_band_is_the_estimate_plus_and_minus_three_sigma(tmp_path, monkeypatch):
    """gyro_bias.png: on each axis the shaded band runs from b_est - 3 sigma to b_est + 3 sigma (estimate 1, 2, 3
    deg/h, sigma 0.1 deg/h: [0.7, 1.3], [1.7, 2.3], [2.7, 3.3])."""
    t = np.arange(0.0, 10.0, 1.0)
    n = t.size
    series = {"t": t, "valid": np.ones(n, bool), "steady": t >= 5.0,
              "bias_est_deg_h": np.tile([1.0, 2.0, 3.0], (n, 1)), "bias_true_deg_h": np.tile([1.0, 2.0, 3.0], (n, 1)),
              "sigma_bias_deg_h": np.full((n, 3), 0.1)}
    got = _band_extents(estimation_plots.bias_plot, series, tmp_path, monkeypatch)
    np.testing.assert_allclose(got, [(0.7, 1.3), (1.7, 2.3), (2.7, 3.3)], rtol=1e-12)


def test_a_half_turn_keeps_the_axis_it_is_given():
    """q4 = 0 exactly (a half turn): both signs of q are the short representative (q4 >= 0), so the rotation
    vector is pi times the given axis, not flipped: +pi x for (1, 0, 0, 0), -pi x for (-1, 0, 0, 0)."""
    np.testing.assert_allclose(E.rotation_vector_rad(np.array([[1.0, 0.0, 0.0, 0.0], [-1.0, 0.0, 0.0, 0.0],
                                                                [0.0, 0.6, -0.8, 0.0]])),
                               [[math.pi, 0.0, 0.0], [-math.pi, 0.0, 0.0], [0.0, 0.6 * math.pi, -0.8 * math.pi]],
                               rtol=0, atol=1e-15)
