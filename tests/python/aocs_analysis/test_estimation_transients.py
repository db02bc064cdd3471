"""The filter's transients (estimation_transients): the predicted rms history against Farrenkopf's closed form,
the predicted convergence against its definition evaluated by brute force, and an outage's report on a
synthetic error whose recovery time and rms can be worked out by hand."""
import math

import numpy as np
import pytest

from aocs_analysis.estimation import SensorSet
from aocs_analysis.estimation_bounds import between_updates, farrenkopf
from aocs_analysis.estimation_transients import (
    outage_report,
    predicted_convergence,
    predicted_rms_history,
    steady_rms_S_arcsec,
    time_inside_for_good,
    trailing_rms,
)
from aocs_core.conventions import ARCSEC_PER_RAD

SIGMA_N = 5.0 / ARCSEC_PER_RAD   # star tracker, rad
SIGMA_V = 1e-5                   # ARW, rad/s^0.5
SIGMA_U = 1e-7                   # RRW, rad/s^1.5


def test_the_predicted_history_settles_at_farrenkopfs_steady_state():
    """From no initial error the history is the filter's own covariance recursion (Joseph form with its
    gains, N_0 = 0 but the same fixed point): after enough updates, the value just after an update is
    Farrenkopf's post-update sigma (an independent closed form) and the rms over one update interval is
    between_updates' (the log at the control rate); between updates it grows."""
    dt, n = 0.1, 10
    out = predicted_rms_history(SIGMA_N, SIGMA_V, SIGMA_U, dt, n, 1e-3, 1e-5, 0.0, 0.0, 4001)
    post = farrenkopf(SIGMA_N, SIGMA_V, SIGMA_U, dt * n).attitude_post
    k = 4000                                    # an update step
    assert out[k] == pytest.approx(post, rel=1e-4)
    assert out[k - n] == pytest.approx(post, rel=1e-4)
    assert np.all(np.diff(out[k - n:k]) > 0.0)  # propagation only between the updates
    rms = math.sqrt(np.mean(out[k - n:k] ** 2))
    assert rms == pytest.approx(between_updates(SIGMA_N, SIGMA_V, SIGMA_U, dt * n, n), rel=1e-4)


def test_without_updates_a_bias_error_drifts_the_attitude_error_by_minus_its_integral():
    """Truth minus estimate: the filter integrates w_meas - b_est, so d(dth)/dt = -(b - b_est) (docs/spec.md 5.7):
    with a tracker that tells nothing (sigma_n 1e10 rad, the gain ~1e-26) and no process noise, the predicted
    rms is |e0_att - t e0_bias| exactly as worked out here, zero at t = e0_att / e0_bias."""
    dt, e_att, e_b = 0.1, 1e-3, 1e-5
    out = predicted_rms_history(1e10, 0.0, 0.0, dt, 10, 1e-3, 1e-5, e_att, e_b, 2001)
    t = np.arange(2001) * dt
    np.testing.assert_allclose(out, np.abs(e_att - t * e_b), rtol=1e-9, atol=1e-13)
    assert out[1000] < 1e-12 and out[2000] == pytest.approx(e_att, rel=1e-9)


def test_the_predicted_convergence_is_its_definition_by_brute_force():
    """rms_S_arcsec: per axis of S, the root of the mean of the predicted squares over the window's samples
    (the samples so far at the start); time_s: the first t from which every axis stays inside k bound_S."""
    sensors = SensorSet(5.0, 40.0, 1.0, SIGMA_V, SIGMA_U)
    rate, window, k = 10.0, 30.0, 3.0
    e0_att, e0_b = (2e-3, -1e-3, 5e-3), (2e-5, 0.0, -1e-5)
    p = predicted_convergence(sensors, rate, 1e-2, 1e-4, e0_att, e0_b, 100.0, k=k, window_s=window)
    w = int(round(window * rate))
    per = (5.0, 5.0, 40.0)
    h2 = np.column_stack([predicted_rms_history(per[i] / ARCSEC_PER_RAD, SIGMA_V, SIGMA_U, 1.0 / rate, 10, 1e-2,
                                                1e-4, e0_att[i], e0_b[i], 1000) ** 2 for i in range(3)])
    r = np.array([np.sqrt(h2[max(0, j - w + 1):j + 1].mean(axis=0)) for j in range(h2.shape[0])]) * ARCSEC_PER_RAD
    np.testing.assert_allclose(p["rms_S_arcsec"], r, rtol=1e-9)
    inside = np.all(r <= k * steady_rms_S_arcsec(sensors, rate), axis=1)
    first = next(j for j in range(inside.size) if inside[j:].all())
    assert 0 < first < inside.size - 1
    assert p["time_s"] == pytest.approx(first / rate, abs=1e-9)


def test_inside_for_good_with_one_sample_or_none():
    """One sample in the span: its time if inside, None if outside; no sample in the span: None."""
    t = np.array([0.0, 1.0, 2.0])
    r = np.array([[5.0], [5.0], [0.5]])
    assert time_inside_for_good(t, r, [1.0], start_s=2.0) == 2.0
    assert time_inside_for_good(t, r, [1.0], start_s=0.5, end_s=1.5) is None
    assert time_inside_for_good(t, r, [1.0], start_s=3.0) is None
    assert time_inside_for_good(t, r, [1.0]) == 2.0


def test_an_outage_report_by_hand():
    """1 Hz log, outage [200, 300): the error is 5 bound_S during it, 20 bound_S for the first 60 s after it,
    then 0.5 bound_S up to 460 s, 1 bound_S up to 560 s and 2 bound_S to the end (999 s); the filter's sigma
    is at its pre-update steady state throughout. The trailing rms (30 s) of the samples since the end first
    stays inside 3 bound_S at t = 389 (the window 360 .. 389; at 388 it still holds t = 359:
    sqrt((400 + 29 x 0.25) / 30) = 3.68 bound_S), so the recovery takes 89 s; the rms over [end + 60,
    end + 260] = [360, 560] (100 samples of 0.5, 101 of 1) is sqrt((25 + 101) / 201) bound_S; the largest
    ratio to 3 sigma during it is 5 bound_S / (3 sigma). A last sample far outside: never recovered."""
    sensors = SensorSet(3.0, 20.0, 1.0, SIGMA_V, SIGMA_U)
    bound = steady_rms_S_arcsec(sensors, 1.0)
    t = np.arange(1000.0)
    level = np.select([t < 200, t < 300, t < 360, t < 460, t <= 560], [0.5, 5.0, 20.0, 0.5, 1.0], 2.0)
    dth = level[:, None] * bound[None, :] / ARCSEC_PER_RAD
    pre = np.array([farrenkopf(a / ARCSEC_PER_RAD, SIGMA_V, SIGMA_U, 1.0).attitude_pre for a in (3.0, 3.0, 20.0)])
    p_att = np.broadcast_to(np.diag(pre ** 2), (t.size, 3, 3))
    (rep,) = outage_report(t, dth, p_att, [(200.0, 300.0)], sensors, 1.0)
    assert rep["recovery_time_s"] == 89.0
    assert rep["rms_span_s"] == [360.0, 560.0]
    np.testing.assert_allclose(rep["rms_over_bound"], math.sqrt((25.0 + 101.0) / 201.0), rtol=1e-12)
    assert rep["max_ratio_to_3sigma_per_axis"] == pytest.approx(list(5.0 * bound / (3.0 * pre * ARCSEC_PER_RAD)))
    assert rep["inside_3sigma_fraction"] == float(np.mean(5.0 * bound <= 3.0 * pre * ARCSEC_PER_RAD))
    # the recovery rule as trailing_rms sees it: 388 outside, 389 inside
    r = trailing_rms(t, np.where((t >= 300)[:, None], dth * ARCSEC_PER_RAD, np.nan), 30.0)
    assert np.any(r[388] > 3.0 * bound) and np.all(r[389:] <= 3.0 * bound)
    # the sample at the outage's end is the first of the recovery: 20 bound_S there alone keeps the 30 s
    # trailing rms outside 3 bound_S (20 / sqrt(30) = 3.65) until the window has let it go, at t = 330
    spike = np.where(t == 300.0, 20.0, np.where((t >= 200) & (t < 300), 5.0, 0.5))
    (first,) = outage_report(t, spike[:, None] * bound[None, :] / ARCSEC_PER_RAD, p_att, [(200.0, 300.0)],
                             sensors, 1.0)
    assert first["recovery_time_s"] == 30.0
    # the recovery must hold up to the last sample
    dth[-1] *= 1000.0
    (late,) = outage_report(t, dth, p_att, [(200.0, 300.0)], sensors, 1.0)
    assert late["recovery_time_s"] is None


def test_an_outage_reports_the_three_sigma_its_last_sample_reached():
    """sigma grows linearly through the outage [200, 300) (1 Hz, from pre to 2 pre at t = 299) and falls back
    after it: the 3 sigma at its end is that of t = 299, 3 x 2 pre per axis (arcsec), not the first sample's nor
    the recovered one's; the largest ratio is the first sample's (the error held at 5 bound_S)."""
    sensors = SensorSet(3.0, 20.0, 1.0, SIGMA_V, SIGMA_U)
    bound = steady_rms_S_arcsec(sensors, 1.0)
    t = np.arange(1000.0)
    level = np.where((t >= 200) & (t < 300), 5.0, 0.5)
    dth = level[:, None] * bound[None, :] / ARCSEC_PER_RAD
    pre = np.array([farrenkopf(a / ARCSEC_PER_RAD, SIGMA_V, SIGMA_U, 1.0).attitude_pre for a in (3.0, 3.0, 20.0)])
    grow = np.where((t >= 200) & (t < 300), 1.0 + (t - 200.0) / 99.0, 1.0)
    p_att = (grow ** 2)[:, None, None] * np.diag(pre ** 2)[None, :, :]
    (rep,) = outage_report(t, dth, p_att, [(200.0, 300.0)], sensors, 1.0)
    np.testing.assert_allclose(rep["three_sigma_at_end_arcsec"], 3.0 * 2.0 * pre * ARCSEC_PER_RAD, rtol=1e-12)
    assert rep["max_ratio_to_3sigma_per_axis"] == pytest.approx(list(5.0 * bound / (3.0 * pre * ARCSEC_PER_RAD)))


def test_an_outage_the_log_does_not_see_whole_is_not_reported():
    """No report for an outage that ends after the log's last sample (its recovery cannot be judged), nor for
    one without a valid sample during it; the same log reports an outage inside it."""
    sensors = SensorSet(3.0, 20.0, 1.0, SIGMA_V, SIGMA_U)
    bound = steady_rms_S_arcsec(sensors, 1.0)
    t = np.arange(1000.0)
    dth = np.where(((t >= 200) & (t < 300))[:, None], 5.0, 0.5) * bound[None, :] / ARCSEC_PER_RAD
    pre = np.array([farrenkopf(a / ARCSEC_PER_RAD, SIGMA_V, SIGMA_U, 1.0).attitude_pre for a in (3.0, 3.0, 20.0)])
    p_att = np.broadcast_to(np.diag(pre ** 2), (t.size, 3, 3))
    assert len(outage_report(t, dth, p_att, [(200.0, 300.0)], sensors, 1.0)) == 1
    assert outage_report(t, dth, p_att, [(900.0, 1200.0)], sensors, 1.0) == []        # ends after the log
    valid = ~((t >= 200) & (t < 300))
    assert outage_report(t, dth, p_att, [(200.0, 300.0)], sensors, 1.0, valid=valid) == []   # nothing valid in it
