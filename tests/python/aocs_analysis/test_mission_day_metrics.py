"""The run JSON's mission-day sections (aocs_analysis.holds, aocs_analysis.momentum; docs/spec.md 5.11) on
synthetic series and logs, against sums and windows written out here sample by sample."""
from __future__ import annotations

import math
from types import SimpleNamespace

import numpy as np
import pytest

from aocs_analysis import holds, momentum
from aocs_core.conventions import quat_to_dcm
from aocs_plant import load

PLAN = [{"euler321_deg": [14.0, 14.0, 14.0], "slew_s": 10.0, "hold_s": 20.0},
        {"euler321_deg": [30.0, -20.0, 1.0], "slew_s": 5.0, "hold_s": 15.0},
        {"euler321_deg": [31.0, -20.0, 1.0], "slew_s": 12.5, "hold_s": 7.5}]


def _sc(duration=70.0):
    return load("irassi_rw", {"target": None, "plan": PLAN, "duration_s": duration, "metrics.window_s": 10.0})


def _angles(t):
    """A pointing history: each observation starts far off and decays, with a late spike in observation 1."""
    ang = np.empty_like(t)
    for k, tk in enumerate(t):
        T = 0.0 if tk < 30.0 else (30.0 if tk < 50.0 else 50.0)
        ang[k] = 5000.0 * math.exp(-(tk - T)) + 0.01 * (1.0 + math.sin(tk))
        if 45.0 <= tk < 45.05:
            ang[k] = 0.5                              # above the 0.3 arcsec requirement, below the 10 settle
    return ang


def test_holds_windows_settle_and_requirement_by_hand():
    sc = _sc()
    t = np.round(np.arange(0, 701) * 0.1, 10)
    ang = _angles(t)
    inside = ang < 10.0
    out = holds.metrics(sc, {"t": t, "true_angle": ang}, inside)
    assert len(out) == 3
    for i, (T, a, b) in enumerate(((0.0, 10.0, 30.0), (30.0, 35.0, 50.0), (50.0, 62.5, 70.0))):
        h = out[i]
        assert (h["command_s"], h["hold_start_s"], h["target"]["index"]) == (T, a, i)
        sel = [x for tk, x in zip(t, ang) if a <= tk < b]
        assert h["pointing_max_arcsec"] == max(sel)
        assert h["pointing_rms_arcsec"] == pytest.approx(math.sqrt(sum(x * x for x in sel) / len(sel)), rel=1e-12)
        # settled: the first sample after which every one up to the hold's end is below 10 arcsec
        slot = [(tk, x) for tk, x in zip(t, ang) if T <= tk < b]
        last_out = max(k for k, (tk, x) in enumerate(slot) if x >= 10.0)
        assert h["settle_s"] == pytest.approx(slot[last_out + 1][0] - T, abs=1e-9)
        assert h["settle_s"] == pytest.approx(math.log(5000.0 / 10.0), abs=0.11)
    assert out[0]["complete"] and out[2]["complete"]
    assert [h["meets_requirement"] for h in out] == [True, False, True]     # the spike in observation 1
    # the slews from the matrices: arccos((trace(A2 A1^T) - 1) / 2)
    qs = [sc.attitude.q0] + [ob.qd for ob in sc.plan.observations]
    for i in range(3):
        a = np.array(quat_to_dcm(qs[i + 1])) @ np.array(quat_to_dcm(qs[i])).T
        assert out[i]["slew_deg"] == pytest.approx(math.degrees(math.acos(min(1.0, (np.trace(a) - 1) / 2))), abs=1e-6)
    assert out[1]["slew_deg"] == pytest.approx(39.31, abs=0.005)


def test_a_shortened_run_reports_the_observations_it_commanded_and_cuts_the_last_hold():
    sc = _sc(40.0)
    t = np.round(np.arange(0, 401) * 0.1, 10)
    ang = _angles(t)
    out = holds.metrics(sc, {"t": t, "true_angle": ang}, ang < 10.0)
    assert len(out) == 2 and out[0]["complete"] and not out[1]["complete"]
    assert out[1]["hold_end_s"] == 40.0
    sel = [x for tk, x in zip(t, ang) if 35.0 <= tk < 40.0]
    assert out[1]["pointing_max_arcsec"] == max(sel)
    assert holds.metrics(load("irassi_rw"), {"t": t, "true_angle": ang}, ang < 10.0) is None


def _log(on, dipole, unloading, events, dt):
    n = len(unloading)
    return SimpleNamespace(cmd={"tick": np.arange(n), "thruster_on_s": np.asarray(on, float),
                                "dipole_am2": np.asarray(dipole, float), "unloading": np.asarray(unloading),
                                "n_unload_events": np.asarray(events)})


def test_thruster_propellant_and_events_by_hand():
    sc = load("irassi_day", {"duration_s": 4.0, "metrics.window_s": 1.0})
    on = np.zeros((4, 12))
    on[1, 2], on[2, 2], on[2, 6], on[3, 10] = 0.01, 0.013, 0.5, 1.0
    log = _log(on, np.zeros((4, 3)), [0, 1, 1, 0], [0, 1, 1, 1], sc.dt)
    u = momentum.unloading(log, sc, {"unloading_actuators": {"thrusters.propellant_kg": 1.0}})
    kg = (0.01 + 0.013 + 0.5 + 1.0) * 1.0 / (220.0 * 9.80665)
    assert u["propellant_kg"] == pytest.approx(kg, rel=1e-14)
    assert u["propellant_kg_per_day"] == pytest.approx(kg * 86400.0 / 4.0, rel=1e-14)
    assert (u["events"], u["time_s"], u["pulses"]) == (1, 2.0, 4)
    assert u["plant"] == {"thrusters.propellant_kg": 1.0}


def test_magnetorquer_dipole_integral_clips_at_the_rod_limits():
    sc = load("leo_day", {"duration_s": 3.0, "metrics.window_s": 1.0})
    m = [[0.1, -0.3, 0.0], [-0.05, 0.2, 0.25], [0.0, 0.0, -0.01]]
    log = _log(np.zeros((3, 12)), m, [1, 1, 1], [1, 1, 1], sc.dt)
    u = momentum.unloading(log, sc, None)
    per_rod = [0.1 + 0.05, 0.2 + 0.2, 0.2 + 0.01]          # |m| clipped at 0.2 A m^2, 1 s periods
    assert u["dipole_am2_s_per_rod"] == pytest.approx(per_rod, rel=1e-14)
    assert u["dipole_am2_s"] == pytest.approx(sum(per_rod), rel=1e-14)
    assert "propellant_kg" not in u and u["plant"] is None


def test_momentum_section_maxima_in_and_out_of_holds():
    sc = load("irassi_day", {"duration_s": 6.0, "metrics.window_s": 1.0})
    series = {"t": np.arange(7.0), "h_wheels_norm": np.array([1.0, 5.0, 2.0, 3.0, 9.0, 4.0, 2.5])}
    log = _log(np.zeros((6, 12)), np.zeros((6, 3)), [0] * 6, [0] * 6, sc.dt)
    m = momentum.metrics(log, sc, series, None, hold_windows=((2.0, 4.0), (5.0, 9.0)))
    assert (m["max_nms"], m["final_nms"], m["max_in_holds_nms"]) == (9.0, 2.5, 4.0)
    assert m["capacity_nms"] == [48.0] * 4 and m["policy"] == "thrusters" and m["trigger"] == "threshold"
    assert (m["h_start_nms"], m["h_stop_nms"]) == (20.0, 3.0)
    leo = momentum.metrics(log, load("leo_day", {"duration_s": 6.0, "metrics.window_s": 1.0}),
                           {**series, "h_wheels_norm": series["h_wheels_norm"] * 1e-3}, None)
    assert leo["trigger"] == "continuous" and leo["h_start_nms"] is None and leo["capacity_nms"] == [6e-3] * 4
    assert momentum.metrics(log, load("irassi_large"), {}, None) is None
    assert momentum.metrics(log, sc, {}, None) is None        # wheels, but no wheel series was logged
    # the summary line of the section names each figure with its unit
    rows = dict(momentum.table_rows(m))
    assert rows["wheel momentum |h_w|"] == ("max 9 N m s, max in holds 4, final 2.5 (capacity 48 N m s per "
                                            "wheel)")


def test_the_day_timeline_is_drawn_at_150_dpi_or_more(tmp_path):
    from PIL import Image

    from aocs_analysis import day_timeline
    sc = _sc()
    t = np.round(np.arange(0, 701) * 0.1, 10)
    ang = _angles(t)
    hs = holds.metrics(sc, {"t": t, "true_angle": ang}, ang < 10.0)
    speed = np.stack([100 + t, -100 - t, 50 + 0 * t, -50 + 0 * t], axis=1)
    series = {"t": t, "true_angle": ang, "t_cmd": t[:-1], "mode": np.ones(700, int),
              "wheels": {"t": t, "n": 4, "speed": speed, "speed_limit": [600.0] * 4,
                         "h_wheels_norm": np.abs(speed).sum(axis=1) * 0.08},
              "unloading": {"t": t[:-1], "flag": (t[:-1] > 20) & (t[:-1] < 30), "cumulative": np.cumsum(t[:-1]),
                            "cumulative_label": "propellant used (kg)"}}
    metrics = {"holds": hs, "momentum": {"policy": "thrusters", "h_start_nms": 20.0, "h_stop_nms": 3.0,
                                         "capacity_nms": [48.0] * 4},
               "pointing_error_arcsec": {"requirement_arcsec": 0.3}}
    assert day_timeline.applies(metrics) and not day_timeline.applies({"holds": None, "momentum": None})
    p = day_timeline.timeline(series, metrics, tmp_path / "day.png", "test")
    with Image.open(p) as im:
        assert im.info["dpi"][0] >= 150 and im.size[0] >= 1500


def test_a_log_without_a_command_has_no_unloading():
    """No command logged (a run stopped before its first period): no event, no time unloading, no propellant."""
    sc = load("irassi_day", {"duration_s": 4.0, "metrics.window_s": 1.0})
    u = momentum.unloading(_log(np.zeros((0, 12)), np.zeros((0, 3)), [], [], sc.dt), sc, None)
    assert (u["events"], u["time_s"], u["propellant_kg"]) == (0, 0.0, 0.0)
