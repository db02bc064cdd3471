"""The observation plan ([[plan]], aocs_plant.observation_plan; docs/scenarios.md, docs/spec.md 5.11): the loader,
the command times and hold windows, the plant's target along the plan, the runner's commands of it, and the
mission-day scenarios' plans and orbits against independent evaluations written here."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_analysis import run_metrics
from aocs_core.conventions import euler321_deg_to_quat, quat_to_dcm
from aocs_plant import Plant, ScenarioError, load
from aocs_runner import events

PLAN = [{"euler321_deg": [14.0, 14.0, 14.0], "slew_s": 10.0, "hold_s": 20.0},
        {"quaternion": [0.0, 0.0, math.sin(0.1), math.cos(0.1)], "slew_s": 5.0, "hold_s": 15.0},
        {"euler321_deg": [30.0, -20.0, 1.0], "slew_s": 7.5, "hold_s": 12.5}]


def _plan_sc(plan=PLAN, **ov):
    return load("irassi_rw", {"target": None, "plan": plan, **ov})


def test_times_windows_and_the_first_target():
    sc = _plan_sc()
    p = sc.plan
    assert p.command_times_s == (0.0, 30.0, 50.0)
    assert p.hold_windows_s() == ((10.0, 30.0), (35.0, 50.0), (57.5, 70.0))
    assert p.end_s == 70.0
    # observation 0 is the flight software's initial target ([target] of the run)
    assert sc.target.qd0 == pytest.approx(euler321_deg_to_quat([14.0, 14.0, 14.0]), abs=1e-15)
    assert sc.target.wd == (0.0, 0.0, 0.0)
    assert p.observations[1].qd == pytest.approx((0.0, 0.0, math.sin(0.1), math.cos(0.1)), abs=1e-15)


def test_plant_and_metrics_follow_the_commanded_target():
    sc = _plan_sc()
    plant = Plant(sc)
    t = np.array([0.0, 29.9, 30.0, 30.1, 49.9, 50.0, 999.0])
    want_index = [0, 0, 1, 1, 1, 2, 2]
    got = run_metrics.target_quat(sc, t)
    for ti, i, g in zip(t, want_index, got):
        want = sc.plan.observations[i].qd
        assert tuple(plant.target(float(ti))[0]) == want
        assert plant.target(float(ti))[1] == (0.0, 0.0, 0.0)   # each observation's target is inertially fixed
        np.testing.assert_array_equal(g, want)


def test_the_runner_commands_each_later_observation_at_its_time_inside_the_run():
    sc = _plan_sc(duration_s=40.0, **{"metrics.window_s": 10.0})
    evs = events.plan_events(sc)
    assert [(e.t, e.kind, e.target) for e in evs] == [(30.0, "target", sc.plan.observations[1].qd)]
    sched = events.schedule(evs, sc.dt, sc.n_steps)
    assert list(sched) == [300]                # before the sensors of tick 300 (t = 30 s at 10 Hz)
    assert events.plan_events(load("irassi_rw")) == []
    full = _plan_sc()
    assert [e.t for e in events.plan_events(full)] == [30.0, 50.0]


@pytest.mark.parametrize("ov, key, words", [
    ({}, "target", "give the first target as the first [[plan]] entry"),
    ({"target": None, "plan": [{"slew_s": 1.0, "hold_s": 1.0}]}, "plan[0]", "give exactly one target attitude"),
    ({"target": None, "plan": [{"euler321_deg": [0, 0, 0], "hold_s": 1.0}]}, "plan[0].slew_s", "missing"),
    ({"target": None, "plan": [{"euler321_deg": [0, 0, 0], "slew_s": 1.0, "hold_s": -1.0}]}, "plan[0].hold_s", ""),
    ({"target": None, "plan": [{"euler321_deg": [0, 0, 0], "slew_s": 1.0, "hold_s": 1.0, "dwell": 2}]},
     "plan[0].dwell", "unknown key"),
    ({"target": None, "plan": "soon"}, "plan", "expected an array of tables"),
])
def test_bad_plans_are_refused_with_one_line_naming_the_key(ov, key, words):
    with pytest.raises(ScenarioError) as exc:
        load("irassi_rw", {"plan": PLAN, **ov})
    msg = str(exc.value)
    assert f": {key}" in msg and words in msg and "\n" not in msg


def _angle_deg(q1, q2) -> float:
    """The rotation between two attitudes from their matrices: arccos((trace(A2 A1^T) - 1) / 2)."""
    a = np.array(quat_to_dcm(q2)) @ np.array(quat_to_dcm(q1)).T
    return math.degrees(math.acos(max(-1.0, min(1.0, (np.trace(a) - 1.0) / 2.0))))


def test_irassi_day_plan_is_a_day_of_at_least_12_targets_with_slews_of_10_to_60_deg():
    sc = load("irassi_day")
    p = sc.plan
    assert len(p.observations) >= 12 and sc.duration_s == 86400.0
    assert p.end_s <= sc.duration_s
    prev = sc.attitude.q0
    slews = []
    for ob in p.observations:
        slews.append(_angle_deg(prev, ob.qd))
        prev = ob.qd
    assert min(slews) >= 10.0 and max(slews) <= 60.0
    # the figures the file states
    np.testing.assert_allclose(slews, [39.31, 36.27, 41.30, 34.17, 10.63, 44.30, 50.44, 54.80, 53.03, 34.94, 37.00,
                                       37.77, 25.26], atol=0.006)
    assert sc.momentum.policy == "thrusters" and sc.guidance.mode == "slew"


def test_leo_day_target_is_the_nadir_frame_of_its_orbit():
    """A(qd(t)) against the LVLH axes of the circular orbit written out here (x along-track, y minus the
    orbit normal, z nadir), at several times over the day."""
    sc = load("leo_day")
    o = sc.environment.orbit
    mu, R = o.mu, o.radius_m
    n = math.sqrt(mu / R ** 3)
    i, raan = math.radians(o.inclination_deg), math.radians(o.raan_deg)
    node = np.array([math.cos(raan), math.sin(raan), 0.0])
    h = np.array([math.sin(i) * math.sin(raan), -math.sin(i) * math.cos(raan), math.cos(i)])
    plant = Plant(sc)
    for t in (0.0, 600.0, 2838.5, 40000.0, 86400.0):
        u = n * t
        r = math.cos(u) * node + math.sin(u) * np.cross(h, node)
        o3, o2 = -r, -h
        o1 = np.cross(o2, o3)
        A = np.array(quat_to_dcm(plant.target(t)[0]))
        np.testing.assert_allclose(A, np.vstack([o1, o2, o3]), atol=1e-12)
    assert sc.momentum.policy == "magnetorquers" and sc.environment.magnetic_field == "igrf"
