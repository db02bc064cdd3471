"""Holds judged against the pointing their sensors allow (irassi_day_mekf, [metrics] hold_requirement =
"sensors"; aocs_analysis.holds; docs/spec.md 5.11.6). The figure against the steady state of the per-axis
(angle, bias) Kalman filter iterated here step by step (Farrenkopf's model, no closed form), the judging
against hand-made pointing histories."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_analysis import holds
from aocs_plant import ScenarioError, load

ARCSEC = math.pi / 180.0 / 3600.0


def _kf_post_sigma(sigma_n, sigma_v, sigma_u, dt, steps=150000):
    """The post-update angle sigma of the two-state filter, its covariance recursion iterated to steady state
    (Phi = [[1, -dt], [0, 1]], Q of the ARW and RRW, H = [1, 0], R = sigma_n^2; scalars for speed)."""
    q11 = sigma_v ** 2 * dt + sigma_u ** 2 * dt ** 3 / 3.0
    q12, q22, r = -sigma_u ** 2 * dt ** 2 / 2.0, sigma_u ** 2 * dt, sigma_n ** 2
    a = b = c = 0.0                                   # P = [[a, b], [b, c]] after an update
    for _ in range(steps):
        m11 = a - 2.0 * dt * b + dt * dt * c + q11    # M = Phi P Phi^T + Q
        m12 = b - dt * c + q12
        m22 = c + q22
        g = 1.0 / (m11 + r)
        a, b, c = m11 - m11 * m11 * g, m12 - m11 * m12 * g, m22 - m12 * m12 * g
    return math.sqrt(a)


def test_the_sensor_figure_is_one_and_a_half_times_the_filters_steady_knowledge():
    sc = load("irassi_day_mekf")
    fig = holds.requirement_figure(sc)
    st, gy = sc.sensors.sensors["star_tracker"], sc.sensors.sensors["gyro"]
    assert st.rate_hz == sc.control_rate_hz == 1.0          # one update per control period: the post figure
    per = [_kf_post_sigma(s * ARCSEC, gy.arw, gy.rrw, 1.0) / ARCSEC
           for s in (st.noise_cross_arcsec, st.noise_cross_arcsec, st.noise_about_arcsec)]
    assert fig["knowledge_rms_per_axis_arcsec"] == pytest.approx(per, rel=1e-8)
    assert fig["knowledge_rms_arcsec"] == pytest.approx(math.sqrt(sum(x * x for x in per)), rel=1e-6)
    assert fig["limit_arcsec"] == pytest.approx(1.5 * fig["knowledge_rms_arcsec"], rel=1e-12)
    assert (fig["basis"], fig["on"], fig["requirement_arcsec"]) == ("sensors", "rms", 0.3)
    assert holds.requirement_figure(load("irassi_day")) == {"basis": "requirement", "on": "max", "limit_arcsec": 0.3}


PLAN = [{"euler321_deg": [14.0, 14.0, 14.0], "slew_s": 10.0, "hold_s": 20.0},
        {"euler321_deg": [30.0, -20.0, 1.0], "slew_s": 5.0, "hold_s": 15.0}]


def test_holds_are_judged_on_their_rms_against_the_figure():
    sc = load("irassi_day_mekf", {"plan": PLAN, "duration_s": 50.0, "control_rate_hz": 10.0,
                                  "sensors.star_tracker.rate_hz": 10.0, "metrics.window_s": 10.0})
    lim = holds.requirement_figure(sc)["limit_arcsec"]
    t = np.round(np.arange(0, 501) * 0.1, 10)
    # hold 0 (10-30 s): a square wave of amplitude 0.99 lim, rms 0.99 lim, max above 0.3 arcsec;
    # hold 1 (35-50 s): amplitude 1.01 lim
    ang = np.where(t < 30.0, 0.99 * lim, 1.01 * lim) * np.where(np.arange(t.size) % 2 == 0, 1.0, -1.0)
    ang = np.abs(ang)
    ang[(t < 2.0) | ((t >= 30.0) & (t < 32.0))] = 100.0     # each slew settles 2 s after its command
    out = holds.metrics(sc, {"t": t, "true_angle": ang}, ang < 10.0)
    assert [h["settle_s"] for h in out] == [2.0, 2.0]
    assert out[0]["pointing_rms_arcsec"] == pytest.approx(0.99 * lim) and out[0]["pointing_max_arcsec"] > 0.3
    assert [h["meets_requirement"] for h in out] == [True, False]
    assert [h["requirement"]["meets_requirement_arcsec"] for h in out] == [False, False]
    rows = dict(holds.table_rows(out, 0.3))
    assert "1 meet the sensors' figure" in rows["holds"] and "0 the requirement" in rows["holds"]


def test_a_sensors_requirement_needs_the_filter():
    with pytest.raises(ScenarioError, match="hold_requirement"):
        load("irassi_day", {"metrics.hold_requirement": "sensors"})
    with pytest.raises(ScenarioError, match="hold_requirement"):
        load("irassi_day", {"metrics.hold_requirement": "loose"})
