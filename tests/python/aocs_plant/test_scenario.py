"""Scenario files: every SPEC 4 id loads with the SPEC data, and the strict
loader rejects every class of malformed file with a message naming the file,
the dotted key and the problem."""
import math
import re

import numpy as np
import pytest

from aocs_core.conventions import quat_conj, quat_mul
from aocs_plant import ScenarioError, law_names, list_scenarios, load

SPEC_IDS = ["rtc_ex1a", "rtc_ex1b", "rtc_ex2a", "rtc_ex2b", "rtc_ex3a", "rtc_ex3b",
            "landsat8_q1", "landsat8_q01", "landsat8_q10", "landsat8_srp", "landsat8_debris",
            "irassi_large", "irassi_small", "geo_hinf", "gao_mrp"]
# SPEC 5: beyond the references (5.3: the IRASSI slew on the reference wheel array, and one wheel failed;
# 5.6: the IRASSI hold on a star tracker and a gyro through the MEKF, issue 20, and the slews and wheel
# scenarios on the same suite)
MEKF_IDS = ["irassi_small_mekf", "irassi_large_mekf", "irassi_rw_mekf", "irassi_rw_failed_mekf"]
# 5.11: the mission days (issue 21)
DAY_IDS = ["irassi_day", "irassi_day_mekf", "leo_day"]
# 5.14: injected faults (issue 26): a wheel losing its motor mid-slew
FAULT_IDS = ["irassi_rw_wheel_dies"]
SPEC5_IDS = ["irassi_rw", "irassi_rw_failed", "irassi_hold_mekf", *MEKF_IDS, *DAY_IDS, *FAULT_IDS]


def test_every_spec_scenario_has_a_file_and_nothing_else():
    assert sorted(list_scenarios()) == sorted(SPEC_IDS + SPEC5_IDS)


@pytest.mark.parametrize("sid,failed", [("irassi_rw", ()), ("irassi_rw_failed", (0,))])
def test_the_wheel_scenarios_fly_the_spec_5_3_reference_array(sid, failed):
    sc = load(sid)
    w = sc.effectors["wheels"]
    assert w.n == 4 and w.failed == failed and sc.duration_s == 1000.0
    assert w.spin_inertia_kg_m2 == (0.08,) * 4 and w.torque_limit_nm == (0.25,) * 4
    assert w.speed_limit_rad_s == (600.0,) * 4 and w.coulomb_nm > 0.0 and w.viscous_nms > 0.0
    G = np.array(w.axes)
    np.testing.assert_allclose(np.degrees(np.arccos(G[:, 0])), 54.7356, atol=1e-4)   # from body x
    # the rest of the problem is irassi_large's
    ref = load("irassi_large")
    assert sc.attitude == ref.attitude and sc.target == ref.target and sc.control == ref.control


#: the laws whose gains the realistic-suite scenarios choose for their sensors (docs/results.md)
SUITE_GAIN_LAWS = ("quat_pid", "lqr_quat_i")


@pytest.mark.parametrize("sid", MEKF_IDS)
def test_the_realistic_suite_scenarios_are_their_reference_with_the_holds_sensors(sid):
    """Each *_mekf file is its reference scenario (plant, target, disturbances, laws, gains, wheels) flown on
    irassi_hold_mekf's sensors and filter, the integral laws with the suite's gains (quat_pid's kp and ki twice
    the reference's, kd the same, lqr_quat_i's table lqr_quat_i_suite, as irassi_hold_mekf; on the wheels four
    times the reference's kp and ki and the table lqr_quat_i_rw_suite); the wheel ones with the slew guidance."""
    sc, ref, hold = load(sid), load(sid.removesuffix("_mekf")), load("irassi_hold_mekf")
    assert (sc.attitude, sc.target, sc.disturbances, sc.effectors, sc.duration_s, sc.metrics) == \
        (ref.attitude, ref.target, ref.disturbances, ref.effectors, ref.duration_s, ref.metrics)
    assert (sc.control.enabled, sc.control.law) == (ref.control.enabled, ref.control.law)
    assert {k: v for k, v in sc.control.laws.items() if k not in SUITE_GAIN_LAWS} == \
        {k: v for k, v in ref.control.laws.items() if k not in SUITE_GAIN_LAWS}
    on_wheels = bool(sc.effectors.get("wheels"))
    pid, pid_ref = sc.control.laws["quat_pid"].params, ref.control.laws["quat_pid"].params
    stiff = 4 if on_wheels else 2
    assert (pid["kp"], pid["ki"], pid["kd"]) == (stiff * pid_ref["kp"], stiff * pid_ref["ki"], pid_ref["kd"])
    assert sc.control.laws["lqr_quat_i"].table == ("lqr_quat_i_rw_suite" if on_wheels else "lqr_quat_i_suite")
    assert ref.control.laws["lqr_quat_i"].table == "lqr_quat_i_ref"
    if on_wheels:
        assert sc.control.laws["quat_pid"] == load("irassi_rw_mekf").control.laws["quat_pid"]
    else:
        for law in SUITE_GAIN_LAWS:
            assert sc.control.laws[law] == hold.control.laws[law]
    for name in ("star_tracker", "gyro"):
        assert sc.sensors.sensors[name] == hold.sensors.sensors[name]
        assert name not in ref.sensors.sensors
    assert sc.estimator == hold.estimator and sc.estimator.type == "mekf"
    assert ref.estimator is None or ref.estimator.type == "passthrough"
    assert sc.guidance.mode == ("slew" if sc.effectors.get("wheels") else "step")


def test_the_mekf_day_is_irassi_day_on_the_holds_sensors_at_its_rate():
    """irassi_day_mekf: irassi_day (plant, plan, wheels, thrusters, unloading, guidance, rate) on
    irassi_hold_mekf's star tracker (at the 1 Hz control rate: a sensor samples at most at the control rate),
    gyro, filter and suite gains; its holds judged against the sensors' figure (docs/spec.md 5.11.6)."""
    import dataclasses
    sc, ref, hold = load("irassi_day_mekf"), load("irassi_day"), load("irassi_hold_mekf")
    assert (sc.attitude, sc.plan, sc.disturbances, sc.effectors, sc.duration_s, sc.guidance, sc.momentum,
            sc.control_rate_hz, sc.substeps) == (ref.attitude, ref.plan, ref.disturbances, ref.effectors,
                                                 ref.duration_s, ref.guidance, ref.momentum, ref.control_rate_hz,
                                                 ref.substeps)
    for law in SUITE_GAIN_LAWS:
        assert sc.control.laws[law] == hold.control.laws[law]
    assert sc.sensors.sensors["gyro"] == hold.sensors.sensors["gyro"]
    assert sc.sensors.sensors["star_tracker"] == dataclasses.replace(hold.sensors.sensors["star_tracker"],
                                                                     rate_hz=1.0)
    assert sc.estimator == hold.estimator and sc.estimator.type == "mekf"
    assert sc.metrics == dataclasses.replace(ref.metrics, hold_requirement="sensors")


@pytest.mark.parametrize("sid", SPEC_IDS)
def test_every_scenario_loads_and_is_consistent(sid):
    sc = load(sid)
    assert sc.id == sid
    assert sc.control_rate_hz == (100.0 if sid.startswith("rtc") else 10.0)
    assert sc.n_steps * sc.dt == pytest.approx(sc.duration_s)
    assert sc.metrics.window_s <= sc.duration_s
    assert sc.control.law in sc.control.laws
    assert sc.sensors.ideal  # reference runs use ideal sensors
    assert (sc.attitude is None) == (sc.kind == "orbit")


@pytest.mark.parametrize("sid,k1,k2,rho0,w0", [
    ("rtc_ex1a", 19, 13, (-10, 15, 15), (48, 30, -20)),
    ("rtc_ex1b", 19, 13, (-10, 15, 15), (48, 30, 20)),
    ("rtc_ex2a", 19, 13, (0.5, 0.1, 0.6), (0, 0.9, -0.5)),
    ("rtc_ex2b", 19, 13, (0.2, 0.7, 0.9), (0, 0.9, -0.5)),
    ("rtc_ex3a", 3, 2, (15, -9, 1), (-6, 4, -3)),
    ("rtc_ex3b", 6, 4, (15, -9, 1), (-6, 4, -3)),
])
def test_rtc_data(sid, k1, k2, rho0, w0):
    sc = load(sid)
    assert sc.law.name == "crp_linear" and sc.law.params["k1"] == k1 and sc.law.params["k2"] == k2
    # q0 = [rho0; 1] / sqrt(1 + |rho0|^2), computed here
    d = math.sqrt(1.0 + sum(r * r for r in rho0))
    np.testing.assert_allclose(sc.attitude.q0, [r / d for r in rho0] + [1.0 / d], rtol=1e-15)
    assert sc.attitude.w0 == tuple(map(float, w0))
    assert sc.attitude.inertia == ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
    d_ = sc.disturbances
    assert all(getattr(d_, n) is None for n in ("constant_torque", "gravity_gradient_l2", "srp_torque"))
    assert sc.settle.rho_norm_max == 1e-3 and sc.settle.w_norm_max_rad_s == 1e-3
    assert sc.target.qd0 == (0.0, 0.0, 0.0, 1.0)


def test_irassi_data():
    # SPEC 4: both slews start at Euler 3-2-1 [14 14 14] deg; large to [30 -20 1] (39.31 deg),
    # small to [13 13 13] (1.59 deg); every triple [yaw, pitch, roll]
    for sid, target, angle_deg in (("irassi_large", (30.0, -20.0, 1.0), 39.31), ("irassi_small", (13.0,) * 3, 1.59)):
        sc = load(sid)
        assert sc.attitude.initial_input == ("euler321_deg", (14.0, 14.0, 14.0))
        assert sc.target.target_input == ("euler321_deg", target)
        qe = quat_mul(sc.attitude.q0, quat_conj(sc.target.qd0))
        assert math.degrees(2.0 * math.acos(min(1.0, abs(qe[3])))) == pytest.approx(angle_deg, abs=0.005)
        assert np.diag(sc.attitude.inertia).tolist() == [2059.5, 5954.2, 5974.3]
        assert sc.duration_s == 500.0
        laws = sc.control.laws
        assert set(laws) == {"quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat", "quat_pid",
                             "lqr_quat_i"}
        for name in ("quat_pd", "quat_nlpd_neg", "quat_nlpd_pos"):
            assert dict(laws[name].params) == {"kp": 4000.0, "kd": 8000.0}
        assert dict(laws["smc"].params) == {"lambda": (1.0,) * 3, "g": (0.05,) * 3, "eps": (0.02,) * 3}
        tabs = laws["lqr_quat"].tables
        assert tabs["lqr_quat_ref"]["q"] == (200.0,) * 6 and tabs["lqr_quat_ref"]["r"] == (0.001,) * 3
        assert tabs["lqr_quat_strong"]["q"] == (2000.0,) * 6 and tabs["lqr_quat_strong"]["r"] == (1e-5,) * 3
        # SPEC 5.2 (the product's own laws, beyond the report): the reference gains of tools/gains.toml
        assert dict(laws["quat_pid"].params) == {"kp": 400.0, "kd": 2000.0, "ki": 12.0, "z_max": 0.01}
        assert laws["lqr_quat_i"].table == "lqr_quat_i_ref" and dict(laws["lqr_quat_i"].params) == {"z_max": 0.01}
        tabs = laws["lqr_quat_i"].tables
        assert tabs["lqr_quat_i_ref"]["q"] == (144.0,) * 3 + (1e5,) * 3 + (1e6,) * 3
        assert tabs["lqr_quat_i_ref"]["r"] == (1.0,) * 3
        assert sc.disturbances.constant_torque.torque_nm == (1.18e-3,) * 3
        assert sc.disturbances.gravity_gradient_l2.enabled
        assert sc.actuator.axis_limit is None and 0.2 <= sc.actuator.realistic_axis_limit <= 1.0
        assert sc.settle.pointing_arcsec_max == 10.0 and sc.metrics.window_s == 100.0
        assert sc.metrics.requirement_arcsec == 0.3 and sc.metrics.goal_arcsec == 0.05


def test_landsat_data():
    for sid, table, q in (("landsat8_q1", "orbit_lqr_q1", 1.0), ("landsat8_q01", "orbit_lqr_q01", 0.1),
                          ("landsat8_q10", "orbit_lqr_q10", 10.0), ("landsat8_srp", "orbit_lqr_q1", 1.0),
                          ("landsat8_debris", "orbit_lqr_q1", 1.0)):
        sc = load(sid)
        assert sc.kind == "orbit" and sc.law.name == "orbit_lqr" and sc.law.table == table
        assert sc.law.tables[table]["q"] == (q,) * 6 and sc.law.tables[table]["r"] == (1.0,) * 3
        assert sc.orbit.mass_kg == 2623.0 and sc.orbit.orbit_radius_m == 7080e3
        assert sc.orbit.mu == 3.986004418e14
        assert sc.settle.pos_abs_max_m == 0.1 and sc.settle.vel_abs_max_m_s == 0.01
        if sid in ("landsat8_q1", "landsat8_q01", "landsat8_q10"):
            assert sc.orbit.x0 == (1.0, -1.0, -6.0, 50.0, -100.0, 350.0)
    srp = load("landsat8_srp").disturbances.srp_force
    assert srp.pressure_n_m2 == 4.4e-6 and srp.area_m2 == 3.0
    imp = load("landsat8_debris").disturbances.impulse
    assert imp.delta_v_m_s == 0.015424 and imp.time_s == 60.0
    assert load("landsat8_debris", {"control.enabled": False}).control.enabled is False


def test_gao_and_geo_data():
    sc = load("gao_mrp")
    p = sc.law.params
    assert (p["u_max"], p["lambda"], p["k"], p["l1"], p["m1"]) == (0.05, 0.6, 50.0, (0.05,) * 3, (0.05,) * 3)
    assert p["l2"] == pytest.approx((2 * 0.05 / math.sqrt(3),) * 3, rel=1e-15) and p["m2"] == p["l2"]
    assert sc.control.laws["mrp_sat_tanh"].params["m3"] == 0.05
    assert sc.attitude.inertia == ((42.0, 1.8, -1.5), (1.8, 25.0, -1.2), (-1.5, -1.2, 61.8))
    assert sc.attitude.initial_input == ("sigma", (-0.3, -0.4, 0.2))
    assert sc.settle.sigma_norm_max == 1e-3
    sc = load("geo_hinf")
    assert np.diag(sc.attitude.inertia).tolist() == [1030.17, 3015.65, 3030.43]
    assert sc.law.name == "hinf" and set(sc.law.tables) == {"hinf_min", "hinf_regional", "hinf_bounded"}
    assert sc.disturbances.gravity_gradient_earth.orbit_rate_rad_s == 7.292115e-5
    assert sc.settle.angle_abs_max_rad == 1e-3 and sc.settle.rate_abs_max_rad_s == 1e-5


def test_law_names_are_the_spec_list():
    """The scenario's laws are the flight software's registry rows, in wire-id order."""
    assert law_names() == ("none", "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc",
                           "lqr_quat", "hinf", "mrp_sat", "mrp_sat_tanh", "orbit_lqr", "quat_pid",
                           "lqr_quat_i")[1:]
    assert law_names("orbit") == ("orbit_lqr",)
    assert "orbit_lqr" not in law_names("attitude") and len(law_names("attitude")) == 11


def test_a_table_must_be_a_compiled_one(tmp_path):
    bad = VALID_ORB.replace("orbit_lqr_q1", "orbit_lqr_q7")
    expect_error(tmp_path, "t_orb", bad, r"laws\.orbit_lqr\.tables\.orbit_lqr_q7",
                 "not a compiled gain table of orbit_lqr .*orbit_lqr_q1, orbit_lqr_q01, orbit_lqr_q10")


# ----------------------------------------------------------------- malformed files

VALID_ATT = """\
id = "t_att"
description = "test"
reference = "none"
kind = "attitude"
control_rate_hz = 10.0
duration_s = 20.0

[control]
law = "quat_pd"

[laws.quat_pd]
kp = 1.0
kd = 2.0

[plant]
inertia = [[2.0, 0.0, 0.0], [0.0, 3.0, 0.0], [0.0, 0.0, 4.0]]
euler321_deg = [1.0, 2.0, 3.0]
w0 = [0.0, 0.0, 0.0]

[target]
quaternion = [0.0, 0.0, 0.0, 1.0]

[settle]
pointing_arcsec_max = 10.0

[metrics]
window_s = 10.0
"""

VALID_ORB = """\
id = "t_orb"
description = "test"
reference = "none"
kind = "orbit"
control_rate_hz = 10.0
duration_s = 100.0

[control]
law = "orbit_lqr"

[laws.orbit_lqr]
table = "orbit_lqr_q1"

[laws.orbit_lqr.tables.orbit_lqr_q1]
q = 1.0
r = 1.0

[plant]
model = "linear"
mass_kg = 2623.0
orbit_radius_m = 7080e3
x0 = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0]

[settle]
pos_abs_max_m = 0.1
"""


def write(tmp_path, name, text):
    p = tmp_path / f"{name}.toml"
    p.write_text(text)
    return p


def expect_error(tmp_path, name, text, key, what):
    p = write(tmp_path, name, text)
    with pytest.raises(ScenarioError) as err:
        load(p)
    msg = str(err.value)
    assert str(p) in msg, msg
    assert re.search(f": {key}:", msg), msg
    assert re.search(what, msg), msg
    return msg


def test_valid_minimal_files_load(tmp_path):
    sc = load(write(tmp_path, "t_att", VALID_ATT))
    assert sc.kind == "attitude" and sc.substeps == 1 and sc.seed == 0 and sc.actuator.axis_limit is None
    sc = load(write(tmp_path, "t_orb", VALID_ORB))
    assert sc.kind == "orbit" and sc.metrics.window_s == 100.0


@pytest.mark.parametrize("name,old,new,key,what", [
    # unknown keys, at every level
    ("t_att", 'kind = "attitude"', 'kind = "attitude"\ncolour = "red"', "colour", "unknown key"),
    ("t_att", "kd = 2.0", "kd = 2.0\nki = 1.0", "laws.quat_pd.ki", "unknown key"),
    ("t_att", "[metrics]", "[metric]\nwindow_s = 1.0\n[metrics]", "metric", "unknown key"),
    # missing keys
    ("t_att", 'reference = "none"\n', "", "reference", "missing required key"),
    ("t_att", "kd = 2.0\n", "", "laws.quat_pd.kd", "missing required key"),
    ("t_att", "w0 = [0.0, 0.0, 0.0]\n", "", "plant.w0", "missing required key"),
    ("t_att", "[settle]\npointing_arcsec_max = 10.0\n", "", "settle", "missing required key"),
    ("t_att", "euler321_deg = [1.0, 2.0, 3.0]\n", "", "plant", "exactly one initial attitude"),
    ("t_att", "euler321_deg = [1.0, 2.0, 3.0]", "euler321_deg = [1.0, 2.0, 3.0]\nrho = [0.0, 0.0, 0.0]",
     "plant", r"exactly one .*found euler321_deg, rho"),
    # wrong types
    ("t_att", "control_rate_hz = 10.0", 'control_rate_hz = "10"', "control_rate_hz", "expected a number"),
    ("t_att", "kp = 1.0", "kp = true", "laws.quat_pd.kp", "expected a number, got a boolean"),
    ("t_att", "w0 = [0.0, 0.0, 0.0]", "w0 = [0.0, 0.0]", "plant.w0", "expected 3 numbers"),
    ("t_att", "w0 = [0.0, 0.0, 0.0]", 'w0 = [0.0, "x", 0.0]', r"plant.w0\[1\]", "expected a number"),
    ("t_att", 'law = "quat_pd"', "law = 3", "control.law", "expected a string"),
    ("t_att", "[control]", "[control]\nenabled = 1", "control.enabled", "expected true or false"),
    # non-finite numbers
    ("t_att", "kp = 1.0", "kp = nan", "laws.quat_pd.kp", "must be finite"),
    ("t_att", "w0 = [0.0, 0.0, 0.0]", "w0 = [0.0, inf, 0.0]", r"plant.w0\[1\]", "must be finite"),
    # non-positive values
    ("t_att", "kp = 1.0", "kp = -1.0", "laws.quat_pd.kp", "must be > 0"),
    ("t_att", "duration_s = 20.0", "duration_s = 0.0", "duration_s", "must be > 0"),
    # inertia
    ("t_att", "[0.0, 3.0, 0.0]", "[0.0, -3.0, 0.0]", "plant.inertia", "positive definite"),
    ("t_att", "[[2.0, 0.0, 0.0], [0.0, 3.0, 0.0]", "[[2.0, 0.1, 0.0], [0.0, 3.0, 0.0]",
     "plant.inertia", "symmetric"),
    ("t_att", "[0.0, 0.0, 4.0]]", "[0.0, 0.0, 40.0]]", "plant.inertia", "J1 \\+ J2 >= J3"),
    ("t_att", "[0.0, 0.0, 4.0]]", "[0.0, 0.0]]", r"plant.inertia\[2\]", "expected 3 numbers"),
    # laws
    ("t_att", "[laws.quat_pd]", "[laws.quat_pdi]", "laws.quat_pdi", "unknown law 'quat_pdi'"),
    ("t_att", 'law = "quat_pd"', 'law = "pid"', "control.law", "unknown law 'pid'"),
    ("t_att", 'law = "quat_pd"', 'law = "smc"', "control.law", r"no gains under \[laws.smc\]"),
    ("t_orb", "[laws.orbit_lqr]\n", "[laws.quat_pd]\nkp = 1.0\nkd = 1.0\n[laws.orbit_lqr]\n",
     "laws.quat_pd", "does not apply to a orbit scenario"),
    ("t_orb", 'table = "orbit_lqr_q1"', 'table = "orbit_lqr_q01"', "laws.orbit_lqr.table", "not defined"),
    # inconsistent content
    ("t_att", "window_s = 10.0", "window_s = 30.0", "metrics.window_s", "longer than duration_s"),
    ("t_att", "duration_s = 20.0", "duration_s = 20.05", "duration_s", "whole number of control periods"),
    ("t_att", "pointing_arcsec_max = 10.0", "pos_abs_max_m = 0.1", "settle.pos_abs_max_m",
     "does not apply to a attitude scenario"),
    ("t_orb", "[settle]", "[target]\nquaternion = [0.0, 0.0, 0.0, 1.0]\n[settle]", "target",
     "orbit scenario has no"),
    ("t_att", 'kind = "attitude"', 'kind = "attitud"', "kind", "unknown value"),
    ("t_att", 'id = "t_att"', 'id = "other"', "id", "does not match the file name"),
    ("t_att", "quaternion = [0.0, 0.0, 0.0, 1.0]", "quaternion = [0.0, 0.0, 0.0, 2.0]",
     "target.quaternion", "norm must be 1"),
    ("t_orb", 'model = "linear"', 'model = "kepler"', "plant.model", "unknown value 'kepler'"),
])
def test_loader_rejects(tmp_path, name, old, new, key, what):
    base = VALID_ATT if name == "t_att" else VALID_ORB
    assert old in base
    expect_error(tmp_path, name, base.replace(old, new, 1), key, what)


def test_loader_rejects_disturbance_and_sensor_errors(tmp_path):
    expect_error(tmp_path, "t_orb", VALID_ORB + "[disturbances.impulse]\nenabled = true\ntime_s = 200.0\n"
                 "delta_v_m_s = 0.01\ndirection = [1.0, 0.0, 0.0]\n",
                 "disturbances.impulse.time_s", "not inside the run")
    expect_error(tmp_path, "t_orb", VALID_ORB + "[disturbances.srp_force]\nenabled = true\n"
                 "pressure_n_m2 = 4.4e-6\narea_m2 = 3.0\ndirection = [1.0, 1.0, 0.0]\n",
                 "disturbances.srp_force.direction", "unit vector")
    expect_error(tmp_path, "t_orb", VALID_ORB + "[disturbances.constant_torque]\nenabled = true\n"
                 "torque_nm = [0.0, 0.0, 0.0]\n", "disturbances.constant_torque", "does not apply")
    expect_error(tmp_path, "t_att", VALID_ATT + "[disturbances.gravity_gradient_l2]\nenabled = true\n"
                 "[disturbances.gravity_gradient_earth]\nenabled = true\norbit_rate_rad_s = 1e-4\n",
                 "disturbances.gravity_gradient_earth", "together with gravity_gradient_l2")
    expect_error(tmp_path, "t_att", VALID_ATT + "[sensors]\nposition_noise_m = 1.0\n",
                 "sensors.position_noise_m", "does not apply to a attitude scenario")
    expect_error(tmp_path, "t_att", VALID_ATT + "[[sensors.faults]]\nchannel = \"rate\"\nkind = \"dropout\"\n"
                 "start_s = 5.0\nend_s = 4.0\n", r"sensors.faults\[0\].end_s", "must be after start_s")
    expect_error(tmp_path, "t_att", VALID_ATT + "[[sensors.faults]]\nchannel = \"gps\"\nkind = \"dropout\"\n"
                 "start_s = 1.0\nend_s = 4.0\n", r"sensors.faults\[0\].channel", "unknown value 'gps'")
    expect_error(tmp_path, "t_att", VALID_ATT + "[actuator]\naxis_limit = -1.0\n",
                 "actuator.axis_limit", "must be > 0")
    expect_error(tmp_path, "t_att", VALID_ATT + "[integrator]\nsubsteps = 0\n",
                 "integrator.substeps", "must be >= 1")


def test_gao_condition_is_enforced_with_the_inequality_named(tmp_path):
    base = load("gao_mrp").path
    text = open(base).read()
    bad = text.replace("l1 = 0.05\nm1 = 0.05\n", "l1 = 0.05\nm1 = 0.05\nl2 = 0.06\nm2 = 0.06\n", 1)
    assert bad != text
    msg = expect_error(tmp_path, "gao_mrp", bad, "laws.mrp_sat.m2", r"M2 <= \(2/sqrt 3\) uM")
    assert "0.0577" in msg
    bad = text.replace("l1 = 0.05\nm1 = 0.05\n", "l1 = 0.05\nm1 = 0.04\n", 1)
    expect_error(tmp_path, "gao_mrp", bad, "laws.mrp_sat.m1", "L1 = M1")
    # L1 = M1 within 1e-12 x max(1, |M1|), the bound itself included: M1 = 2^-60 and L1 = M1 + 1e-12 (both exact, so
    # L1 - M1 is the double 1e-12 exactly) is accepted, one more 2^-60 is not
    m1 = 2.0 ** -60
    assert (1e-12 + m1) - m1 == 1e-12
    assert load("gao_mrp", {"laws.mrp_sat.l1": 1e-12 + m1, "laws.mrp_sat.m1": m1}).control.laws["mrp_sat"]
    with pytest.raises(ScenarioError, match="L1 = M1"):
        load("gao_mrp", {"laws.mrp_sat.l1": 1e-12 + 2.0 * m1, "laws.mrp_sat.m1": m1})
    # M2 <= (2/sqrt 3) uM within 1e-12 relative, the bound itself included; the next double above is refused
    top = 2.0 * 0.05 / math.sqrt(3.0) * (1.0 + 1e-12)
    assert load("gao_mrp", {"laws.mrp_sat.l2": top, "laws.mrp_sat.m2": top}).control.laws["mrp_sat"]
    up = math.nextafter(top, math.inf)
    with pytest.raises(ScenarioError, match=r"M2 <= \(2/sqrt 3\) uM"):
        load("gao_mrp", {"laws.mrp_sat.l2": up, "laws.mrp_sat.m2": up})


def test_syntax_error_and_missing_file(tmp_path):
    p = write(tmp_path, "bad", "id = \n")
    with pytest.raises(ScenarioError, match=re.escape(str(p)) + ": <syntax>"):
        load(p)
    with pytest.raises(ScenarioError, match="no such scenario file"):
        load("no_such_scenario")


def test_overrides_are_validated_like_the_file():
    sc = load("irassi_large", {"actuator.axis_limit": 0.5})
    assert sc.actuator.axis_limit == 0.5
    with pytest.raises(ScenarioError, match=r"actuator.axis_limit: must be > 0"):
        load("irassi_large", {"actuator.axis_limit": 0.0})
    with pytest.raises(ScenarioError, match=r"actuator.limit: unknown key"):
        load("irassi_large", {"actuator.limit": 0.5})


def test_scenario_is_frozen():
    sc = load("rtc_ex1a")
    with pytest.raises(Exception):
        sc.duration_s = 1.0  # type: ignore[misc]
    with pytest.raises(TypeError):
        sc.control.laws["x"] = None  # type: ignore[index]


def test_unreadable_files_give_one_line_naming_the_file(tmp_path, monkeypatch):
    """Not UTF-8, nested beyond any sane depth, a folder: a ScenarioError naming the file, never a traceback."""
    cases = {"latin.toml": (b'id = "latin"\n\xff\xfe = 1\n', "not UTF-8 text (byte 13)"),
             "deep.toml": (b"a = " + b"[" * 50000 + b"]" * 50000 + b"\n", "nested too deeply")}
    for name, (data, message) in cases.items():
        (tmp_path / name).write_bytes(data)
        with pytest.raises(ScenarioError) as ei:
            load(tmp_path / name)
        assert str(ei.value).startswith(f"{tmp_path / name}: ") and message in str(ei.value)
        assert "\n" not in str(ei.value)
    (tmp_path / "adir.toml").mkdir()
    with pytest.raises(ScenarioError, match="is a folder, not a scenario file"):
        load(tmp_path / "adir.toml")


def test_a_folder_named_like_an_id_does_not_shadow_the_scenario(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    (tmp_path / "irassi_small").mkdir()
    assert load("irassi_small").id == "irassi_small"


@pytest.mark.parametrize("key,value,message", [
    ("control_rate_hz", 1e308, "outside [0.001, 1e+06] Hz"),
    ("control_rate_hz", 1e9, "outside [0.001, 1e+06] Hz"),
    ("control_rate_hz", 1e-4, "outside [0.001, 1e+06] Hz"),
    ("duration_s", 1e308, "longer than 1e+07 s"),
    ("duration_s", 1e-300, "shorter than one control period"),
    ("integrator.substeps", 100000, "more than 10000"),
])
def test_run_timing_is_bounded_where_the_flight_software_and_the_wire_can_follow(key, value, message):
    """Values the executive (period 1 us .. 1000 s) or the tick and time arithmetic could not honour
    are refused by the loader with the key named, never an OverflowError later (aocs_core.limits)."""
    with pytest.raises(ScenarioError, match=re.escape(f"{key}: ") + ".*" + re.escape(message)):
        load("irassi_large", {key: value})


def test_run_timing_edges_that_are_accepted():
    sc = load("irassi_large", {"control_rate_hz": 1e6, "duration_s": 1.0, "metrics.window_s": 1.0})
    assert sc.n_steps == 1_000_000
    sc = load("irassi_large", {"duration_s": 0.1, "metrics.window_s": 0.1})
    assert sc.n_steps == 1


def test_a_misspelt_gain_key_is_named_not_reported_as_the_missing_one():
    with pytest.raises(ScenarioError, match=re.escape("laws.quat_pd.kq: unknown key (did you mean 'kp'?); known: kp, kd")):
        load("irassi_small", {"laws.quat_pd.kq": 4000.0, "laws.quat_pd.kp": None})
    with pytest.raises(ScenarioError, match=re.escape("laws.smc.lamda: unknown key (did you mean 'lambda'?)")):
        load("irassi_small", {"laws.smc.lamda": 1.0})


def test_loader_and_executive_share_the_limit_and_rate_ranges():
    """The loader's bounds are the executive's (read from the build's registry, executive.h), so a scenario
    the loader accepts is one fsw_node accepts (tests/e2e/test_integrity.py checks the node at the edges)."""
    from aocs_core import registry
    lim = registry.load().limits
    assert (lim["u_limit_min"], lim["u_limit_max"], lim["period_min_s"], lim["period_max_s"]) == (1e-9, 1e9, 1e-6, 1e3)
    assert load("irassi_large", {"actuator.axis_limit": lim["u_limit_min"]}).actuator.axis_limit == 1e-9
    assert load("irassi_large", {"actuator.norm_limit": lim["u_limit_max"]}).actuator.norm_limit == 1e9
    for key, value in (("actuator.axis_limit", 0.99e-9), ("actuator.norm_limit", 1.01e9)):
        with pytest.raises(ScenarioError, match=re.escape(f"{key}: ") + ".*flight software's accepted range"):
            load("irassi_large", {key: value})
    assert load("irassi_large", {"control_rate_hz": 1.0 / lim["period_max_s"], "duration_s": 1000.0}).dt == 1000.0


@pytest.mark.parametrize("value", [5e-324, 1e-39, 1e39])
def test_a_law_parameter_must_fly_in_both_precisions(value):
    """5e-324 was accepted by the loader and refused by fsw_node (issue 11): the loader now refuses what
    either precision of the flight software cannot represent as a normal number."""
    with pytest.raises(ScenarioError, match=re.escape("laws.quat_pd.kp: ") + ".*both precisions"):
        load("irassi_small", {"laws.quat_pd.kp": value})


def test_an_integer_is_read_over_the_whole_64_bit_range_and_refused_beyond_it():
    """-2^63 and 2^63 - 1 are 64-bit integers (here refused by the seed's own minimum, or accepted), one beyond
    either end is refused as out of range: each in one line naming the key."""
    for v, msg in ((-2 ** 63, r"seed: must be >= 0, got -9223372036854775808"),
                   (-2 ** 63 - 1, r"seed: an integer of 19 digits is beyond the range of a 64-bit integer"),
                   (2 ** 63, r"seed: an integer of 19 digits is beyond the range of a 64-bit integer")):
        with pytest.raises(ScenarioError, match=msg):
            load("gao_mrp", {"seed": v})
    assert load("gao_mrp", {"seed": 2 ** 63 - 1}).seed == 2 ** 63 - 1


def test_a_law_field_is_read_with_its_own_sign_rule():
    """_read_field applies a registry field's rule: pos refuses 0, nonneg takes 0 and refuses a negative, any
    takes a negative (today's real and vec3 law fields are all pos; laws.def allows the other two)."""
    import dataclasses

    from aocs_core import registry
    from aocs_plant.scenario import _read_field, _Section

    kp = registry.load().fields_of("quat_pd")[0]
    assert kp.param == "kp" and kp.rule == "pos"

    def read(rule, v):
        return _read_field(_Section("x.toml", "laws.quat_pd", {"kp": v}), dataclasses.replace(kp, rule=rule))

    with pytest.raises(ScenarioError, match=r"x.toml: laws.quat_pd.kp: must be > 0, got 0.0"):
        read("pos", 0.0)
    assert read("nonneg", 0.0) == 0.0
    with pytest.raises(ScenarioError, match=r"laws.quat_pd.kp: must be >= 0, got -2.0"):
        read("nonneg", -2.0)
    assert read("any", -2.0) == -2.0


def test_an_mrp_on_the_unit_sphere_is_accepted_and_one_outside_refused():
    """|sigma| = 1 is a rotation by 180 deg (the shadow set's boundary, still the set |sigma| <= 1): sigma =
    (1, 0, 0) is q = (1, 0, 0, 0); |sigma| > 1 is refused in one line naming the key."""
    sc = load("gao_mrp", {"plant.sigma": [1.0, 0.0, 0.0]})
    np.testing.assert_allclose(sc.attitude.q0, (1.0, 0.0, 0.0, 0.0), atol=1e-15)
    with pytest.raises(ScenarioError, match=r"gao_mrp.toml: plant.sigma: use the MRP set with \|sigma\| <= 1$"):
        load("gao_mrp", {"plant.sigma": [0.8, 0.8, 0.0]})


@pytest.mark.parametrize("section", [None, {"policy": "none"}, {"policy": "none", "trigger": "continuous"}])
def test_the_momentum_keys_left_out_are_the_flight_registrys_defaults(section):
    """[momentum] absent, or with its keys left out: each value the flight software's own default
    (config_fields.def, as fsw_node would take it without the key), read here from the registry."""
    from aocs_core import registry
    f = {x.key: x for x in registry.load().config_fields}
    sc = load("irassi_rw", {} if section is None else {"momentum": section})
    m = sc.momentum
    given = section or {}
    assert m.policy == given.get("policy", f["mom.policy"].names[f["mom.policy"].default])
    assert m.trigger == given.get("trigger", f["mom.trigger"].names[f["mom.trigger"].default])
    assert m.h_target_nms == tuple(float(x) for x in f["mom.h_target_nms"].default)
    for attr in ("h_start_nms", "h_stop_nms", "k_mtq_per_s", "dump_torque_nm"):
        assert getattr(m, attr) == float(f["mom." + attr].default[0]), attr
