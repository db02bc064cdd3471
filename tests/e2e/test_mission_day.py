"""The mission day's loop closed end to end (issue 21; docs/spec.md 5.11) through the real processes (plant_node,
fsw_node, LCM in a private namespace): the momentum-management stage's commands reach the plant's thrusters and
magnetorquers and remove wheel momentum, and without them it stays. Shortened versions of irassi_day and
leo_day (--duration); the checks are written out here with numpy from the logs:

- the thrusters: the change of the true total angular momentum H_B (truth_t h_total; the body held at its
  target, A(q) constant) equals the constant disturbance's impulse plus the angular impulse of the on-times the
  flight software commanded, sum_k sum_i F (r_i x d_i) tau_ik, with the layout typed here; without unloading
  only the disturbance's;
- the run JSON's propellant against sum F tau / (Isp g0) of the logged on-times and the plant's own integral;
- the magnetorquers: every commanded dipole perpendicular to the field the magnetometer measured that tick;
  the wheel momentum brought down from its preload, and not without unloading;
- the wheels' time at the speed limit per wheel against the truth's speeds at the limit.
"""
from __future__ import annotations

import numpy as np
import pytest

from aocs_plant import load
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog

#: irassi_day's thrusters typed independently: for each body axis k and sign s two thrusters at +-1.2 m along
#: axis k + 1 firing along -+ axis k + 2 (docs/scenarios.md [thrusters]); torque per newton r x d
_POS = np.array([[0, 1.2, 0], [0, -1.2, 0], [0, 1.2, 0], [0, -1.2, 0], [0, 0, 1.2], [0, 0, -1.2], [0, 0, 1.2],
                 [0, 0, -1.2], [1.2, 0, 0], [-1.2, 0, 0], [1.2, 0, 0], [-1.2, 0, 0]], float)
_DIR = np.array([[0, 0, 1], [0, 0, -1], [0, 0, -1], [0, 0, 1], [1, 0, 0], [-1, 0, 0], [-1, 0, 0], [1, 0, 0],
                 [0, 1, 0], [0, -1, 0], [0, -1, 0], [0, 1, 0]], float)
THRUST_N, ISP_S, G0 = 1.0, 220.0, 9.80665
TAU_DIST = np.array([1.18e-3, 1.18e-3, 1.18e-3])

#: irassi_day held at its start attitude (one observation, no slew) with the wheels preloaded to 27.7 N m s
#: along x ([300 0 300 0] rad/s: 150 x [1 1 1 1] along x plus 150 x the null vector), above h_start (20 N m s)
HOLD = {"plan": [{"euler321_deg": [14.0, 14.0, 14.0], "slew_s": 100.0, "hold_s": 1900.0}],
        "wheels.speed0_rad_s": [300.0, 0.0, 300.0, 0.0]}


def _sets(d: dict) -> list[str]:
    from aocs_runner.scenario_opts import toml_value
    return [f"{k}={toml_value(v)}" for k, v in d.items()]


@pytest.fixture(scope="module")
def fly(private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    def go(scenario, name, duration, sets):
        out = tmp_path_factory.mktemp(name)
        res = execute(RunOptions(scenario=scenario, out=str(out), quiet=True, plots=False, duration=duration,
                                 sets=_sets(sets)))
        return res.metrics, lcmlog.read(out / "run.lcmlog"), load(scenario, {"duration_s": duration, **sets})
    return go


@pytest.fixture(scope="module")
def irassi_pair(fly):
    return (fly("irassi_day", "thr", 2000.0, HOLD),
            fly("irassi_day", "none", 2000.0, {**HOLD, "momentum.policy": "none"}))


def _h_wheels(sc, log) -> np.ndarray:
    """|sum Js g Omega| per truth sample, from the true speeds and the scenario's axes."""
    w = sc.effectors["wheels"]
    G = np.array(w.axes).T
    om = np.asarray(log.truth["wheel_speed"])[:, :w.n]
    return np.linalg.norm(om * np.array(w.spin_inertia_kg_m2) @ G.T, axis=1)


def test_thruster_unloading_removes_the_wheel_momentum_with_the_commanded_impulse(irassi_pair):
    (m, log, sc), _ = irassi_pair
    h = _h_wheels(sc, log)
    assert h[0] == pytest.approx(0.08 * 150.0 * 4.0 / np.sqrt(3.0), rel=1e-6)   # the preload, 27.7 N m s
    assert m["momentum"]["unloading"]["events"] >= 1
    # dumped to the stop threshold: the unload ends at the first tick below it (truth sample k + 1 is the state
    # after command k), then the disturbance adds |tau| per second again
    on_flag = np.flatnonzero(np.asarray(log.cmd["unloading"]) != 0)
    k_end = int(log.cmd["tick"][on_flag[-1]]) + 1
    assert k_end < len(h) - 100
    assert h[k_end] < sc.momentum.h_stop_nms + 0.05
    assert h[-1] <= h[k_end] + np.linalg.norm(TAU_DIST) * (len(h) - 1 - k_end) * sc.dt * (1 + 1e-3)
    assert m["momentum"]["max_nms"] == pytest.approx(h.max(), rel=1e-12)
    assert m["momentum"]["final_nms"] == pytest.approx(h[-1], rel=1e-12)
    # the angular impulse of the commanded on-times (held over their period) and of the disturbance
    on = np.asarray(log.cmd["thruster_on_s"], float)[:, :12]
    arms = np.cross(_POS, _DIR) * THRUST_N
    T = log.truth["t_s"][-1] - log.truth["t_s"][0]
    dH = np.asarray(log.truth["h_total"])[-1] - np.asarray(log.truth["h_total"])[0]
    want = TAU_DIST * T + on.sum(axis=0) @ arms
    assert np.linalg.norm(on.sum(axis=0) @ arms) > 20.0           # the dump is most of it
    np.testing.assert_allclose(dH, want, atol=1e-6 * np.linalg.norm(want))
    # the propellant of those on-times, in the JSON and the plant's own integral
    kg = on.sum() * THRUST_N / (ISP_S * G0)
    u = m["momentum"]["unloading"]
    assert u["propellant_kg"] == pytest.approx(kg, rel=1e-12)
    assert u["plant"]["thrusters.propellant_kg"] == pytest.approx(kg, rel=1e-9)
    assert u["propellant_kg_per_day"] == pytest.approx(kg * 86400.0 / T, rel=1e-9)
    # the wheels absorbed every pulse: the hold met its pointing requirement while dumping
    (hold,) = m["holds"]
    assert hold["meets_requirement"] and hold["pointing_max_arcsec"] <= 0.3
    assert m["verdict"]["passed"]


def test_without_unloading_the_momentum_stays_and_only_the_disturbance_adds(irassi_pair):
    (m_on, _, _), (m, log, sc) = irassi_pair
    h = _h_wheels(sc, log)
    assert m["momentum"]["unloading"]["events"] == 0
    assert np.all(np.asarray(log.cmd["thruster_on_s"]) == 0.0)
    assert h[-1] > h[0]                                          # the disturbance adds to the preload
    T = log.truth["t_s"][-1] - log.truth["t_s"][0]
    dH = np.asarray(log.truth["h_total"])[-1] - np.asarray(log.truth["h_total"])[0]
    np.testing.assert_allclose(dH, TAU_DIST * T, atol=1e-6 * np.linalg.norm(TAU_DIST * T))
    assert m["momentum"]["final_nms"] > 5.0 * m_on["momentum"]["final_nms"]


def test_without_unloading_a_wheel_reaches_its_speed_limit_and_the_time_is_reported(fly):
    # preloaded close to the limit (590 rad/s of 600, 109 N m s along x of the 111 the array holds there): the
    # disturbance drives them onto it
    sets = {**HOLD, "wheels.speed0_rad_s": [590.0, 590.0, 590.0, 590.0], "momentum.policy": "none"}
    m, log, sc = fly("irassi_day", "limit", 2000.0, sets)
    per = m["wheels"]["time_at_speed_limit_s"]
    assert len(per) == 4 and max(per) > 0.0
    om = np.abs(np.asarray(log.truth["wheel_speed"])[1:, :4])
    at = (om >= 600.0 * (1 - 1e-6)).sum(axis=0) * sc.dt        # periods that end at the limit (the truth's speeds)
    assert at.max() > 1000.0                                     # most of the run: the array is saturated
    for i in range(4):
        # at the limit: the plant cut the motor, or the flight software holds the wheel there
        assert per[i] >= at[i] and per[i] <= at[i] + m["wheels"]["per_wheel"][i]["time_speed_cut_s"]
        assert per[i] == m["wheels"]["per_wheel"][i]["time_at_speed_limit_s"]
    # and the pointing is lost: the test can fail, and so does the run's verdict (holds-missed)
    assert m["holds"][0]["meets_requirement"] is False
    assert not m["verdict"]["passed"]
    assert [f["check"] for f in m["verdict"]["failures"]] == ["holds-missed"]


#: leo_day with its wheels preloaded to 3.5e-3 N m s along z (150 rad/s common mode, 4 x 1e-5 x 150 / sqrt 3,
#: plus 250 x the null vector): far above what the disturbances add in 3000 s
LEO = {"wheels.speed0_rad_s": [400.0, -100.0, 400.0, -100.0]}


@pytest.fixture(scope="module")
def leo_pair(fly):
    return (fly("leo_day", "mtq", 3000.0, LEO), fly("leo_day", "mtq_none", 3000.0, {**LEO, "momentum.policy": "none"}))


def test_magnetorquers_unload_the_wheels_with_a_dipole_perpendicular_to_the_measured_field(leo_pair):
    (m, log, sc), (m0, log0, sc0) = leo_pair
    h, h0 = _h_wheels(sc, log), _h_wheels(sc0, log0)
    assert h[0] == pytest.approx(h0[0]) and h[0] == pytest.approx(4e-5 * 150.0 / np.sqrt(3.0), rel=1e-6)
    assert h[-1] < 0.3 * h[0]                                    # unloaded by the magnetorquers alone
    assert h0[-1] > 0.8 * h0[0]                                  # and not without them
    # every commanded dipole (rods along the body axes) is perpendicular to the field measured that tick
    rows = {int(k): i for i, k in enumerate(log.sensors["tick"])}
    b = np.asarray(log.sensors["mag_b_t"])[[rows[int(k)] for k in log.cmd["tick"]]]
    mm = np.asarray(log.cmd["dipole_am2"], float)
    assert np.abs(mm).max() > 0.1 and np.abs(mm).max() <= 0.2 * (1 + 1e-12)
    cos = np.einsum("ij,ij->i", mm, b) / np.maximum(np.linalg.norm(mm, axis=1) * np.linalg.norm(b, axis=1), 1e-30)
    assert np.abs(cos).max() < 1e-9
    # the dipole integral of the JSON from the same commands
    assert m["momentum"]["unloading"]["dipole_am2_s"] == pytest.approx(np.abs(mm).sum() * sc.dt, rel=1e-12)
    assert m["momentum"]["unloading"]["plant"]["magnetorquers.dipole_s_am2s"] == pytest.approx(
        list(np.abs(mm).sum(axis=0) * sc.dt), rel=1e-6)
    assert m["pointing_error_arcsec"]["meets_requirement"] and m0["momentum"]["unloading"]["events"] == 0


def test_the_pass_over_singapore_is_reported_from_the_plants_own_pointing_error(leo_pair):
    """leo_day's first target pass (Singapore, 2762-2887 s, inside the 3000 s run; its window checked against an
    independent geometry in tests/python/aocs_plant/test_target_passes.py): the run JSON's pass figures are the
    plant's own pointing error (truth_t pointing_err_arcsec) over the pass's ticks."""
    from aocs_plant import target_passes
    from aocs_plant.environment import Environment
    (m, log, sc), (m0, log0, _) = leo_pair
    t = np.asarray(log.truth["t_s"], float)
    (w,) = target_passes.windows(sc.passes, Environment(sc.environment), t)
    assert sc.passes.targets[w["target"]].name == "Singapore" and (t[w["i0"]], t[w["i1"] - 1]) == (2762.0, 2887.0)
    for metrics, lg in ((m, log), (m0, log0)):
        (p,) = metrics["passes"]
        pe = np.asarray(lg.truth["pointing_err_arcsec"], float)[w["i0"]:w["i1"]]
        assert (p["start_s"], p["end_s"], p["target"]["name"]) == (2762.0, 2887.0, "Singapore")
        assert p["pointing_max_arcsec"] == pytest.approx(pe.max(), rel=1e-9)
        assert p["pointing_rms_arcsec"] == pytest.approx(np.sqrt(np.mean(pe * pe)), rel=1e-9)
        assert p["meets_requirement"] == bool(pe.max() <= 36.0) and p["settle_s"] == 0.0
