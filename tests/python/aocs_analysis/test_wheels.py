"""The wheel section of a run's metrics (aocs_analysis.wheels.metrics) on a hand-made log of irassi_rw's four
wheels: every wheel torque command against its wheel's limit (1e-9 relative allowed), non-finite ones apart,
the peaks and the time scaled."""
from __future__ import annotations

import types

import numpy as np
import pytest

from aocs_analysis import wheels
from aocs_plant.scenario import load


def test_wheel_commands_over_their_limit_and_not_finite():
    sc = load("irassi_rw")
    n, umax = 4, 0.25
    assert list(sc.effectors["wheels"].torque_limit_nm) == [umax] * n
    u = np.zeros((5, 6))
    u[0, 0] = umax                       # at the limit: within
    u[1, 1] = -umax * (1 + 1e-10)        # inside the 1e-9 allowance
    u[2, 2] = umax * (1 + 2e-9)          # beyond it: over
    u[3, 3] = np.nan                     # not finite (and not counted over)
    u[4, 1] = -0.1
    # wheel 2 ends the second period within the 1e-6 relative allowance of its 600 rad/s limit: at the limit
    truth = {"t_s": np.arange(3) * sc.dt,
             "wheel_speed": np.array([[0, 0, 0, 0], [10, -20, 0, 0], [5, 0, 600.0 * (1 - 5e-7), -300.0]]),
             "wheel_torque": np.array([[0, 0, 0, 0], [0.1, -0.2, 0, 0], [0, 0, 0.25, 0]]),
             "wheel_at_limit": np.array([0, 0b100, 0]),
             "h_total": np.array([[1.0, 0.0, 0.0], [0.0, 3.0, 4.0], [0.0, 0.0, 2.0]])}
    cmd = {"tick": np.arange(5), "u_wheels": u, "wheel_speed_margin": np.array([0.9, 0.5, 0.8, 0.7, 0.6]),
           "wheel_scale": np.array([1.0, 1.0, 0.5, 1.0, 0.25])}
    out, series = wheels.metrics(types.SimpleNamespace(truth=truth, cmd=cmd), sc)
    assert out["commands_over_limit"] == 1 and out["commands_not_finite"] == 1
    assert [p["peak_speed_rad_s"] for p in out["per_wheel"]] == [10.0, 20.0, 600.0 * (1 - 5e-7), 300.0]
    assert [p["time_at_speed_limit_s"] for p in out["per_wheel"]] == pytest.approx([0.0, 0.0, sc.dt, 0.0])
    assert [p["peak_motor_torque_nm"] for p in out["per_wheel"]] == [0.1, 0.2, 0.25, 0.0]
    assert out["per_wheel"][2]["time_at_torque_limit_s"] == pytest.approx(sc.dt)
    assert out["min_speed_margin"] == 0.5
    # the total momentum |H| (truth): its peak and its last sample (not the first)
    assert out["total_momentum_nms"] == {"peak": 5.0, "final": 2.0}
    # the wheels' own momentum |sum Js g_i Omega_i| (speeds relative to the body): its peak and its last sample
    w = sc.effectors["wheels"]
    h_w = [np.linalg.norm(np.array(w.axes).T @ (np.array(sp) * np.array(w.spin_inertia_kg_m2)))
           for sp in truth["wheel_speed"]]
    assert out["wheel_momentum_nms"]["final"] == pytest.approx(h_w[-1], rel=1e-14) and h_w[-1] != h_w[1]
    assert out["wheel_momentum_nms"]["peak"] == pytest.approx(max(h_w), rel=1e-14)
    assert out["time_scaled_s"] == pytest.approx(2 * sc.dt)
    assert series["n"] == n
    # the summary lines: the wheels, and a limit exceeded said in capitals
    rows = dict(wheels.table_rows(out))
    assert rows["wheels"] == "4 wheels, removed: none" + ("" if out["within_limits"] else "; A LIMIT WAS EXCEEDED")
    assert rows["peak wheel speed"] == "[10 20 600 300] rad/s (limit 600)"
    out["within_limits"], out["removed"] = False, [2]
    assert dict(wheels.table_rows(out))["wheels"] == "4 wheels, removed: wheel 2; A LIMIT WAS EXCEEDED"


def test_a_run_with_no_command_has_no_wheel_command_over_its_limit_or_not_finite():
    """A log whose node sent no command (the truth was logged): nothing was commanded, so nothing is over
    the limit or not finite, and no command was scaled."""
    sc = load("irassi_rw")
    truth = {"t_s": np.arange(3) * sc.dt, "wheel_speed": np.zeros((3, 4)), "wheel_torque": np.zeros((3, 4)),
             "wheel_at_limit": np.zeros(3, int), "h_total": np.zeros((3, 3))}
    cmd = {"tick": np.zeros(0, int), "u_wheels": np.zeros((0, 6)), "wheel_speed_margin": np.zeros(0),
           "wheel_scale": np.zeros(0)}
    out, _ = wheels.metrics(types.SimpleNamespace(truth=truth, cmd=cmd), sc)
    assert out["commands_over_limit"] == 0 and out["commands_not_finite"] == 0
    assert out["time_scaled_s"] == 0.0
    assert out["min_speed_margin"] is None                  # no margin was reported, none is made up
    assert "speed margin" not in dict(wheels.table_rows(out))


@pytest.mark.parametrize("samples", [0, 1, 3])
def test_the_times_at_a_limit_count_the_periods_after_the_first_sample(samples):
    """Truth sample k reports the period before it: bits 0 (wheel 1 at its torque limit) and 9 (wheel 2's motor
    cut at its speed limit) set on every sample count one period each after the first, none for a log of one
    sample or none; wheel 3 held exactly at the flight software's margin below its limit, (1 - SPEED_LIMIT_REL)
    Omega_max, is at its speed limit too."""
    sc = load("irassi_rw")
    bits = np.full(samples, (1 << 0) | (1 << 9), np.int64)
    speed = np.zeros((samples, 4))
    speed[:, 2] = -sc.effectors["wheels"].speed_limit_rad_s[2] * (1.0 - wheels.SPEED_LIMIT_REL)
    truth = {"t_s": np.arange(samples) * sc.dt, "wheel_speed": speed,
             "wheel_torque": np.zeros((samples, 4)), "wheel_at_limit": bits, "h_total": np.zeros((samples, 3))}
    cmd = {"tick": np.zeros(0, int), "u_wheels": np.zeros((0, 6)), "wheel_speed_margin": np.zeros(0),
           "wheel_scale": np.zeros(0)}
    out, _ = wheels.metrics(types.SimpleNamespace(truth=truth, cmd=cmd), sc)
    periods = max(samples - 1, 0) * sc.dt
    per = out["per_wheel"]
    assert [p["time_at_torque_limit_s"] for p in per] == pytest.approx([periods, 0.0, 0.0, 0.0])
    assert [p["time_speed_cut_s"] for p in per] == pytest.approx([0.0, periods, 0.0, 0.0])
    assert [p["time_at_speed_limit_s"] for p in per] == pytest.approx([0.0, periods, periods, 0.0])


@pytest.mark.parametrize("speed_rel,torque_rel,within", [(1.0, 1.0, True), (1.0 + 5e-4, 1.0 + 5e-10, True),
                                                          (1.0 + 1e-3, 1.0 + 1e-9, True),
                                                          (1.0 + 2e-3, 1.0, False), (1.0, 1.0 + 2e-9, False)])
def test_within_limits_allows_the_plants_overshoot_of_the_speed_limit_and_nothing_more(speed_rel, torque_rel, within):
    """The plant cuts a motor at the speed limit stage by stage, so a wheel can end a period a little past it
    (600.05 rad/s for 600 in test_faults_models' speed-limit case, 9e-5 relative): a peak speed within 1e-3
    relative of the limit and a peak motor torque within 1e-9 are within the limits, at either tolerance too;
    beyond either, not."""
    sc = load("irassi_rw")
    speed = np.zeros((3, 4))
    speed[2, 1] = -600.0 * speed_rel
    torque = np.zeros((3, 4))
    torque[1, 3] = 0.25 * torque_rel
    truth = {"t_s": np.arange(3) * sc.dt, "wheel_speed": speed, "wheel_torque": torque,
             "wheel_at_limit": np.zeros(3, int), "h_total": np.zeros((3, 3))}
    cmd = {"tick": np.arange(2), "u_wheels": np.zeros((2, 6)), "wheel_speed_margin": np.ones(2),
           "wheel_scale": np.ones(2)}
    out, _ = wheels.metrics(types.SimpleNamespace(truth=truth, cmd=cmd), sc)
    assert out["within_limits"] is within
    assert dict(wheels.table_rows(out))["wheels"].endswith("; A LIMIT WAS EXCEEDED") is not within
