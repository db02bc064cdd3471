"""The injected faults' models (aocs_plant/faults, docs/spec.md 5.14) against independent evaluations written
here: the star tracker's error rotation with numpy rotation matrices, the noise fault against the tracker's
own model at a larger sigma (same seeded draws), the gyro's output differences, a stuck / dead / rubbing wheel
against a one-axis ODE integrated by scipy and the total momentum of the array, the thrusters' torque and
propellant on hand values, the link's dropped ticks; a run without faults unchanged, one with faults repeatable.
"""
import math

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_plant import Plant, load
from aocs_plant.faults.link import drop_ticks

ST = {"mounting_q": [0.0, 0.0, 0.0, 1.0], "rate_hz": 10.0, "noise_cross_arcsec": 1.0, "noise_about_arcsec": 8.0}
GYRO = {"mode": "rate", "arw_rad_sqrt_s": 1.45e-6, "rrw_rad_s_sqrt_s": 1.0e-10, "bias_rad_s": [4.8e-7, -4.8e-7, 2.4e-7]}


def _plant(faults=(), sid="irassi_rw", **ov):
    o = {"sensors.star_tracker": dict(ST), "sensors.gyro": dict(GYRO), "faults": list(faults)}
    o.update(ov)
    return Plant(load(sid, o))


def _fly(p, n, u_wheels=None, w_cmd=None):
    """n periods with a constant command; the samples and truths at each tick."""
    out = []
    nw = p.wheel_array.n if p.wheel_array is not None else 0
    for _ in range(n):
        s = p.sense()
        out.append((dict(s), p.truth()))
        cmd = {"u_body": (0.0, 0.0, 0.0)}
        if nw:
            cmd["u_wheels"] = tuple(u_wheels) if u_wheels is not None else (0.0,) * nw
        p.apply(cmd)
        p.advance()
    return out


def _dcm(q):
    """A(q) of SPEC 1 (Shuster, scalar last), written out: (q4^2 - |v|^2) I + 2 v v^T - 2 q4 [v x]."""
    v, q4 = np.asarray(q[:3], float), float(q[3])
    vx = np.array([[0.0, -v[2], v[1]], [v[2], 0.0, -v[0]], [-v[1], v[0], 0.0]])
    return (q4 * q4 - v @ v) * np.eye(3) + 2.0 * np.outer(v, v) - 2.0 * q4 * vx


def _rotation_between(q_meas, q_true):
    """The rotation vector of A(q_meas) A(q_true)^T (rad), from the matrices (not the quaternion algebra)."""
    R = _dcm(q_meas) @ _dcm(q_true).T
    ang = math.acos(max(-1.0, min(1.0, (np.trace(R) - 1.0) / 2.0)))
    ax = np.array([R[1, 2] - R[2, 1], R[2, 0] - R[0, 2], R[0, 1] - R[1, 0]])
    return ax / np.linalg.norm(ax) * ang if ang > 0 else np.zeros(3)


# ------------------------------------------------------------------ star tracker
def test_st_bias_step_adds_its_rotation_about_its_axis():
    axis = np.array([1.0, 2.0, 2.0]) / 3.0
    f = {"kind": "st_bias_step", "start_s": 1.0, "bias_arcsec": 30.0, "axis": [1.0, 2.0, 2.0]}
    p = _plant([f], **{"sensors.star_tracker.noise_cross_arcsec": 0.0, "sensors.star_tracker.noise_about_arcsec": 0.0})
    rows = _fly(p, 20)
    for s, tr in rows:
        e = _rotation_between(s["st_q"], tr["sensors"]["star_tracker.q_sn"])
        expect = axis * 30.0 / ARCSEC_PER_RAD if s["t"] >= 1.0 - 1e-9 else np.zeros(3)
        np.testing.assert_allclose(e, expect, atol=1e-10)
    assert rows[15][0]["st_valid"] and rows[15][1]["faults_active"] == (True,)


def test_st_noise_increase_is_the_trackers_own_model_at_factor_times_sigma():
    """Same seed, same draws: the faulted tracker reads what a tracker of k sigma reads."""
    k = 7.0
    p = _plant([{"kind": "st_noise_increase", "start_s": 0.0, "factor": k}])
    q = _plant(**{"sensors.star_tracker.noise_cross_arcsec": k * 1.0, "sensors.star_tracker.noise_about_arcsec": k * 8.0})
    for (a, _), (b, _) in zip(_fly(p, 30), _fly(q, 30)):
        np.testing.assert_allclose(a["st_q"], b["st_q"], atol=1e-15)


def test_st_frozen_repeats_the_last_attitude_flagged_valid_then_returns():
    p = _plant([{"kind": "st_frozen", "start_s": 1.0, "end_s": 2.0}])
    ref = _fly(_plant(), 30)
    rows = _fly(p, 30)
    last = rows[9][0]["st_q"]          # t = 0.9 s, the last sample before the fault
    for (s, _), (r, _) in zip(rows, ref):
        if 1.0 - 1e-9 <= s["t"] < 2.0 - 1e-9:
            assert s["st_q"] == last and s["st_valid"] and s["st_new"]
            assert s["st_q"] != r["st_q"]
        else:
            assert s["st_q"] == r["st_q"]          # before and after: the unfaulted tracker, noise not shifted


def test_st_outage_delivers_nothing_and_does_not_shift_the_noise():
    p = _plant([{"kind": "st_outage", "start_s": 1.0, "end_s": 1.5}])
    ref = _fly(_plant(), 25)
    rows = _fly(p, 25)
    for (s, _), (r, _) in zip(rows, ref):
        if 1.0 - 1e-9 <= s["t"] < 1.5 - 1e-9:
            assert not s["st_valid"] and not s["st_new"] and s["st_q"] == rows[9][0]["st_q"]
        else:
            assert s["st_q"] == r["st_q"] and s["st_valid"]
    assert p.counters["invalid_samples"] == 5


# ------------------------------------------------------------------ gyro
def test_gyro_bias_step_adds_the_step_to_the_output_and_to_the_true_bias():
    db = (2e-5, -1e-5, 3e-6)
    rows = _fly(_plant([{"kind": "gyro_bias_step", "start_s": 1.0, "bias_rad_s": list(db)}]), 20)
    ref = _fly(_plant(), 20)
    for (s, tr), (r, rt) in zip(rows, ref):
        on = s["t"] >= 1.0 - 1e-9
        np.testing.assert_allclose(np.subtract(s["gyro_w"], r["gyro_w"]), db if on else (0, 0, 0), atol=1e-18)
        np.testing.assert_allclose(np.subtract(tr["sensors"]["gyro.bias_rad_s"], rt["sensors"]["gyro.bias_rad_s"]),
                                   db if on else (0, 0, 0), atol=1e-18)


def test_gyro_stuck_axis_holds_the_last_value_of_that_axis_only():
    ov = {"plant.w0": [1e-3, -2e-3, 3e-3]}
    rows = _fly(_plant([{"kind": "gyro_stuck_axis", "unit": 1, "start_s": 1.0, "end_s": 2.0}], **ov), 30)
    ref = _fly(_plant(**ov), 30)
    held = ref[9][0]["gyro_w"][1]
    for (s, _), (r, _) in zip(rows, ref):
        on = 1.0 - 1e-9 <= s["t"] < 2.0 - 1e-9
        assert s["gyro_w"][1] == (held if on else r["gyro_w"][1])
        assert (s["gyro_w"][0], s["gyro_w"][2]) == (r["gyro_w"][0], r["gyro_w"][2])


def test_gyro_saturation_clips_every_axis_to_the_reduced_range():
    ov = {"plant.w0": [1e-3, -2e-3, 3e-4]}
    rows = _fly(_plant([{"kind": "gyro_saturation", "start_s": 0.5, "saturation_rad_s": 5e-4}], **ov), 15)
    ref = _fly(_plant(**ov), 15)
    for (s, tr), (r, _) in zip(rows, ref):
        expect = np.clip(r["gyro_w"], -5e-4, 5e-4) if s["t"] >= 0.5 - 1e-9 else r["gyro_w"]
        np.testing.assert_array_equal(s["gyro_w"], expect)
    assert rows[-1][1]["sensors"]["gyro.saturated"] == (True, True, False)


# ------------------------------------------------------------------ wheels
JS = 0.08
AX3 = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]


def _wheel_plant(faults, speed0, b=1e-5, c=2e-3, **ov):
    """irassi_rw's body with three wheels on its principal axes (wheel 0 on x), no disturbances: with the other
    wheels still, the motion is about x alone."""
    w = {"array": "explicit", "axes": AX3, "spin_inertia_kg_m2": JS, "torque_limit_nm": 0.25,
         "speed_limit_rad_s": 600.0, "viscous_nms": b, "coulomb_nm": c, "coulomb_width_rad_s": 0.5,
         "speed0_rad_s": speed0}
    return Plant(load("irassi_rw", {"wheels": w, "disturbances": None, "faults": list(faults), **ov}))


def _one_axis(t_end, h0, w0, torque, jx=2059.5):
    """Independent model of wheel 0 on body axis x (the other wheels still): J_b,x wdot = -tau,
    hdot = tau(Omega), Omega = h / Js - w (docs/spec.md 5.3), by scipy at tight tolerance."""
    jb = jx - JS

    def f(t, y):
        h, w = y
        tau = torque(h / JS - w)
        return [tau, -tau / jb]
    return solve_ivp(f, (0.0, t_end), [h0, w0], rtol=1e-11, atol=1e-13, dense_output=True, method="DOP853")


def _x_state(p):
    tr = p.truth()
    return tr["effectors"]["wheels.momentum_nms"][0], tr["w"][0], tr["effectors"]["wheels.speed_rad_s"][0]


def test_wheel_torque_loss_keeps_friction_the_wheel_coasts_down():
    b, c = 1e-5, 2e-3
    p = _wheel_plant([{"kind": "wheel_torque_loss", "unit": 0, "start_s": 0.0}], [100.0, 0, 0], b, c)
    _fly(p, 300, u_wheels=(0.2, 0.0, 0.0))     # commanded, but the motor is dead
    sol = _one_axis(30.0, JS * 100.0, 0.0, lambda om: -(b * om + c * math.tanh(om / 0.5)))
    h, w, _ = _x_state(p)
    np.testing.assert_allclose([h, w], sol.sol(30.0), rtol=1e-8, atol=1e-13)
    assert p.truth()["effectors"]["wheels.motor_torque_nm"][0] == 0.0
    assert h < JS * 100.0 - 30.0 * c * 0.99     # friction took momentum out of the wheel


def test_wheel_friction_increase_multiplies_the_friction():
    b, c, k = 1e-5, 2e-3, 6.0
    p = _wheel_plant([{"kind": "wheel_friction_increase", "unit": 0, "start_s": 0.0, "factor": k}],
                     [100.0, 0, 0], b, c)
    _fly(p, 300, u_wheels=(0.05, 0.0, 0.0))
    sol = _one_axis(30.0, JS * 100.0, 0.0, lambda om: 0.05 - k * (b * om + c * math.tanh(om / 0.5)))
    np.testing.assert_allclose(_x_state(p)[:2], sol.sol(30.0), rtol=1e-8, atol=1e-13)


@pytest.mark.parametrize("faults", [[], [{"kind": "wheel_friction_increase", "unit": 1, "start_s": 0.0, "factor": 2.0}]],
                         ids=["nominal", "under_a_fault"])
def test_the_speed_limit_cuts_only_a_torque_that_drives_the_wheel_further(faults):
    """A wheel at +Omega_max: a torque pushing it further is cut (at_speed_limit), none or a braking one is not
    a cut; the same with a fault elsewhere in the array (the fault model's own derivative)."""
    for u, cut in ((0.1, True), (0.0, False), (-0.1, False)):
        p = _wheel_plant(faults, [600.0, 0, 0])
        _fly(p, 1, u_wheels=(u, 0.0, 0.0))
        assert p.truth()["effectors"]["wheels.at_speed_limit"] == (cut, False, False), u


def test_a_seized_wheel_gives_its_momentum_to_the_body():
    """speed_rad_s = 0: the stop drives the rotor to the body's rate; one axis: J_x w_final = Js Omega_0 (the
    total momentum, conserved), and the history is the stop's ODE."""
    T = 0.5
    p = _wheel_plant([{"kind": "wheel_stuck", "unit": 0, "start_s": 0.0, "speed_rad_s": 0.0, "stop_time_s": T}],
                     [300.0, 0, 0], **{"integrator.substeps": 10})
    _fly(p, 100, u_wheels=(0.25, 0.0, 0.0))     # the motor pushes; the rotor does not follow
    sol = _one_axis(10.0, JS * 300.0, 0.0, lambda om: -JS * om / T)
    h, w, om = _x_state(p)
    np.testing.assert_allclose([h, w], sol.sol(10.0), rtol=1e-7, atol=1e-12)
    assert abs(om) < 300.0 * math.exp(-10.0 / T) * 1.01 + 1e-9
    np.testing.assert_allclose(w, JS * 300.0 / 2059.5, rtol=1e-6)   # all of its momentum is the body's


def test_a_stuck_wheel_holds_its_speed_and_the_total_momentum_is_conserved():
    """Default speed: the speed at the fault's start; the pyramid with every wheel commanded and spinning,
    the body tumbling: H in N (A(q)^T H_B) unchanged to rounding, the stuck wheel's speed held."""
    p = Plant(load("irassi_rw", {"disturbances": None, "plant.w0": [1e-3, -5e-4, 2e-4],
                                 "wheels.speed0_rad_s": [120.0, -80.0, 60.0, -40.0],
                                 "faults": [{"kind": "wheel_stuck", "unit": 2, "start_s": 2.0, "stop_time_s": 0.5}],
                                 "integrator.substeps": 5}))

    def h_n():
        tr = p.truth()
        return _dcm(tr["q"]).T @ np.asarray(tr["effectors"]["wheels.momentum_total_nms"])
    h0 = h_n()
    rows = _fly(p, 220, u_wheels=(0.1, -0.1, 0.1, -0.1))
    held = rows[20][1]["effectors"]["wheels.speed_rad_s"][2]      # its speed at the fault's start (t = 2 s)
    assert abs(held - 60.0) > 1.0                                  # its motor had moved it before
    np.testing.assert_allclose(h_n(), h0, rtol=0, atol=1e-10 * np.linalg.norm(h0))
    speeds = [tr["effectors"]["wheels.speed_rad_s"][2] for _, tr in rows[20:]]
    assert max(abs(s - held) for s in speeds) < 1e-3 * abs(held)
    others = rows[-1][1]["effectors"]["wheels.speed_rad_s"]
    assert abs(others[0] - 120.0) > 1.0                      # the healthy wheels follow their motors


def test_tach_failure_reads_its_value_the_others_read_the_truth():
    p = _wheel_plant([{"kind": "wheel_tach_failure", "unit": 2, "start_s": 0.5, "value_rad_s": 7.0}],
                     [100.0, 50.0, -20.0])
    for s, tr in _fly(p, 10):
        truth = tr["effectors"]["wheels.speed_rad_s"]
        expect = list(truth)
        if s["t"] >= 0.5 - 1e-9:
            expect[2] = 7.0
        np.testing.assert_array_equal(s["wheel_speed"], expect)


# ------------------------------------------------------------------ thrusters
POSITIONS = [0, 1.2, 0, 0, -1.2, 0]
DIRECTIONS = [0, 0, 1, 0, 0, -1]


def _thrusters_flown(fault, n, on):
    """Two thrusters of 1 N (a +-z pair on +-y arms), the fault, n periods of the on-times `on`: the truth."""
    thr = {"thrust_n": 1.0, "positions_m": POSITIONS, "directions": DIRECTIONS, "isp_s": 220.0}
    p = Plant(load("irassi_large", {"thrusters": thr, "disturbances": None, "faults": [fault]}))
    for _ in range(n):
        p.sense()
        p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": on})
        p.advance()
    return p.truth()["effectors"]


def test_a_thruster_stuck_open_fires_the_whole_period_and_burns_propellant():
    tr = _thrusters_flown({"kind": "thruster_stuck_open", "unit": 0, "start_s": 0.0}, 50, (0.0, 0.0))
    # r x d = (1.2, 0, 0) x ... : (0, 1.2, 0) x (0, 0, 1) = (1.2, 0, 0) N m with 1 N
    np.testing.assert_allclose(tr["thrusters.torque_nm"], (1.2, 0.0, 0.0), atol=1e-15)
    np.testing.assert_allclose(tr["thrusters.propellant_kg"], 1.0 * 5.0 / (220.0 * 9.80665), rtol=1e-12)


def test_a_thruster_stuck_closed_gives_nothing_whatever_its_command():
    tr = _thrusters_flown({"kind": "thruster_stuck_closed", "unit": 1, "start_s": 0.0}, 10, (0.05, 0.1))
    assert tr["thrusters.on_time_s"] == (0.05, 0.0)
    np.testing.assert_allclose(tr["thrusters.propellant_kg"], 10 * 0.05 / (220.0 * 9.80665), rtol=1e-12)


# ------------------------------------------------------------------ link, determinism, no change without faults
def test_a_link_drop_burst_drops_every_tick_of_its_interval():
    sc = load("irassi_rw", {"faults": [{"kind": "link_drop_burst", "start_s": 20.0, "end_s": 21.5}]})
    assert drop_ticks(sc.faults, sc.dt, sc.n_steps) == list(range(200, 215))
    assert drop_ticks(sc.faults, sc.dt, 205) == list(range(200, 205))


def test_faults_are_deterministic_and_a_run_without_faults_is_unchanged():
    fs = [{"kind": "st_noise_increase", "start_s": 0.3, "factor": 3.0},
          {"kind": "gyro_bias_step", "start_s": 0.5, "bias_rad_s": [1e-5, 0.0, 0.0]},
          {"kind": "wheel_stuck", "unit": 1, "start_s": 0.2}]
    a = _fly(_plant(fs), 20, u_wheels=(0.1, 0.1, -0.1, 0.05))
    b = _fly(_plant(fs), 20, u_wheels=(0.1, 0.1, -0.1, 0.05))
    assert [(s, tr["q"], tr["w"]) for s, tr in a] == [(s, tr["q"], tr["w"]) for s, tr in b]
    plain = _fly(_plant(), 20, u_wheels=(0.1, 0.1, -0.1, 0.05))
    empty = _fly(_plant([]), 20, u_wheels=(0.1, 0.1, -0.1, 0.05))
    assert [(s, tr) for s, tr in plain] == [(s, tr) for s, tr in empty]
    assert "faults_active" not in plain[0][1]


def test_the_integration_error_check_holds_the_stuck_wheel_where_the_plant_does():
    """The step-doubling shadow plant checks every 10th period: it takes the main plant's held speed, so its
    period differs from the main one's by the integration error only (not by another held speed)."""
    from aocs_plant.integration_error import StepDoubling

    sc = load("irassi_rw", {"disturbances": None, "wheels.speed0_rad_s": [120.0, -80.0, 60.0, -40.0],
                            "faults": [{"kind": "wheel_stuck", "unit": 2, "start_s": 0.35}]})
    p, check = Plant(sc), StepDoubling(sc, every=10)
    for _ in range(60):
        p.sense()
        cmd = {"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.1, -0.1, 0.2, -0.1)}   # wheel 2 accelerates until 0.35 s
        p.apply(cmd)
        check.apply(cmd)
        check.begin(p)
        p.advance()
        check.end(p)
    held = p.effectors[[e.kind for e in p.effectors].index("wheels")].fault_model.stuck[2][0]
    shadow = check.shadow.effectors[[e.kind for e in check.shadow.effectors].index("wheels")].fault_model.stuck
    assert shadow[2][0] == held
    assert check.local_max[0] < 1e-6    # arcsec: an RK4 error, not a model difference
