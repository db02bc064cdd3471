"""Helpers of one run's metrics (aocs_analysis.run_metrics) against the plant's own functions.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import math
import types

import numpy as np
import pytest

from aocs_analysis import run_metrics as results
from aocs_core import conventions as rot
from aocs_core.modes import mode_value
from aocs_plant import Plant
from aocs_plant.scenario import load
from synthetic_log import make_log


def test_target_path_matches_the_plant():
    sc = load("geo_hinf")
    plant = Plant(sc)
    t = np.array([0.0, 0.1, 37.3, 600.0, 1200.0])
    got = results.target_quat(sc, t)
    for i, ti in enumerate(t):
        ref = plant.target(float(ti))[0]
        assert np.allclose(got[i], ref, atol=1e-15, rtol=0), (ti, got[i], ref)
    # the LVLH frame turned by -w0 t about y (independent check of the sign)
    ang = -7.292115e-05 * 1200.0
    assert np.allclose(got[-1], [0.0, math.sin(ang / 2), 0.0, math.cos(ang / 2)], atol=1e-15)


def test_dcm_and_euler_match_the_plant_rotation_functions():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    a = results.dcm(q)
    e = results.euler321(q)
    for i in range(50):
        assert np.allclose(a[i], np.array(rot.quat_to_dcm(tuple(q[i]))), atol=1e-14)
        assert np.allclose(e[i], rot.quat_to_euler321(tuple(q[i])), atol=1e-12)
    # pinned example (conventions.md): 90 deg about z gives A = [[0,1,0],[-1,0,0],[0,0,1]]
    s = 1 / math.sqrt(2)
    assert np.allclose(results.dcm(np.array([[0, 0, s, s]]))[0], [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_settle_mask_uses_every_criterion():
    sc = load("rtc_ex2a")
    t = np.arange(6) * 1.0
    rho = np.array([[1, 0, 0], [1e-2, 0, 0], [5e-4, 0, 0], [5e-4, 0, 0], [2e-4, 0, 0], [1e-4, 0, 0]], float)
    we = np.zeros((6, 3))
    we[2, 1] = 2e-3            # rate still outside at t = 2
    s = {"t": t, "rho": rho, "we": we, "true_angle": np.zeros(6), "euler_err": np.zeros((6, 3)),
         "sigma": np.zeros((6, 3))}
    inside, used = results.settle_mask(sc, s)
    assert used == {"rho_norm_max": 1e-3, "w_norm_max_rad_s": 1e-3}
    assert inside.tolist() == [False, False, False, True, True, True]


def test_geo_hinf_settles_on_every_angle_and_rate_strictly_below_its_bound():
    """docs/spec.md 4.2: geo_hinf is settled when every angle < 1e-3 rad and every rate < 1e-5 rad/s; a value
    at its bound is outside (the limits are read from the scenario, the values at them built here)."""
    sc = load("geo_hinf")
    a, r = sc.settle.angle_abs_max_rad, sc.settle.rate_abs_max_rad_s
    assert (a, r) == (1e-3, 1e-5)
    t = np.arange(6) * 1.0
    euler = np.zeros((6, 3))
    we = np.zeros((6, 3))
    euler[1, 2] = -a                  # an angle at its bound
    euler[2, 0] = np.nextafter(a, 0.0)
    we[3, 1] = r                      # a rate at its bound
    we[4, 2] = -np.nextafter(r, 0.0)
    s = {"t": t, "rho": np.zeros((6, 3)), "we": we, "true_angle": np.zeros(6), "euler_err": euler,
         "sigma": np.zeros((6, 3))}
    inside, used = results.settle_mask(sc, s)
    assert used == {"angle_abs_max_rad": a, "rate_abs_max_rad_s": r}
    assert inside.tolist() == [True, False, True, False, True, True]


@pytest.mark.parametrize("name,key,series", [("irassi_large", "pointing_arcsec_max", "true_angle"),
                                              ("gao_mrp", "sigma_norm_max", "sigma"),
                                              ("rtc_ex2a", "rho_norm_max", "rho"),
                                              ("rtc_ex2a", "w_norm_max_rad_s", "we")])
def test_an_attitude_settles_on_each_norm_strictly_below_its_bound(name, key, series):
    """docs/spec.md 4.2: a pointing angle, |sigma|, |rho| or |w_e| at its bound is outside, one ulp below inside
    (the bound read from the scenario; the other criteria held at zero)."""
    sc = load(name)
    b = getattr(sc.settle, key)
    n = 4                             # samples: not 3, so that a norm over the wrong axis cannot pass
    s = {"t": np.arange(n) * 1.0, "rho": np.zeros((n, 3)), "we": np.zeros((n, 3)), "true_angle": np.zeros(n),
         "euler_err": np.zeros((n, 3)), "sigma": np.zeros((n, 3))}
    v = np.array([b, np.nextafter(b, 0.0), 0.0, b])
    s[series] = v if s[series].ndim == 1 else np.column_stack([np.zeros(n), v, np.zeros(n)])
    inside, used = results.settle_mask(sc, s)
    assert used[key] == b
    assert inside.tolist() == [False, True, True, False]


def test_an_orbit_settles_on_every_position_and_velocity_component_strictly_below_its_bound():
    """landsat8_q1 (docs/spec.md 4.2): settled when every |relative position| < 0.1 m and every |velocity| <
    0.01 m/s, per sample (one component outside is enough); the limits read from the scenario."""
    sc = load("landsat8_q1")
    pm, vm = sc.settle.pos_abs_max_m, sc.settle.vel_abs_max_m_s
    assert (pm, vm) == (0.1, 0.01)
    pos, vel = np.zeros((6, 3)), np.zeros((6, 3))
    pos[0] = (1.0, 2.0, 3.0)              # far out on every axis
    pos[1, 2] = -pm                       # one position component at its bound
    vel[2, 0] = vm                        # one velocity component at its bound
    pos[3] = (np.nextafter(pm, 0.0),) * 3
    vel[4, 1] = -np.nextafter(vm, 0.0)
    inside, used = results.settle_mask(sc, {"t": np.arange(6) * 1.0, "pos": pos, "vel": vel})
    assert used == {"pos_abs_max_m": pm, "vel_abs_max_m_s": vm}
    assert inside.tolist() == [False, False, False, True, True, True]


def test_a_run_started_later_lasts_the_span_of_its_samples():
    """A run from tick 50 (plant_node --start-tick): its duration_s is the span of its truth samples (19 periods
    of 0.1 s), not the time of the last one."""
    log = make_log(20, cmd_ticks=range(50, 69), sensor_ticks=range(50, 69), status_steps=[19])
    log.truth["tick"] = np.arange(50, 70)
    log.truth["t_s"] = 0.1 * log.truth["tick"]
    m, _ = results.compute(log, load("irassi_small"), {"law": "quat_pd"})
    assert m["duration_s"] == pytest.approx(1.9, abs=1e-12)


def test_safe_entries_count_a_run_that_starts_in_safe():
    """counters.safe_entries: every change into SAFE, the first command's mode counting as one when it is SAFE
    (modes by hand: SAFE, SAFE, NOMINAL, SAFE, NOMINAL, NOMINAL: two entries; from NOMINAL on: one; SAFE for the
    first command alone: two); final_mode is the last command's."""
    safe, nominal = mode_value("safe"), mode_value("nominal")
    for modes, entries, final in (((safe, safe, nominal, safe, nominal, nominal), 2, "nominal"),
                                  ((nominal, nominal, nominal, safe, nominal, nominal), 1, "nominal"),
                                  ((safe, nominal, nominal, safe, nominal, safe), 3, "safe")):
        log = make_log(7, cmd_ticks=range(6), sensor_ticks=range(6), status_steps=[6])
        log.cmd["mode"] = np.array(modes)
        m, _ = results.compute(log, load("irassi_small"), {"law": "quat_pd"})
        assert m["counters"]["safe_entries"] == entries
        assert m["final_mode"] == final


def test_an_attitude_run_with_a_filter_has_the_estimation_section_and_one_without_none():
    """The run JSON's `estimation` section: present for an attitude scenario that flies a filter (irassi_hold_mekf,
    on a log built in memory, the estimate at the truth), null for the pass-through (irassi_small)."""
    log = make_log(30, cmd_ticks=range(29), sensor_ticks=range(29), status_steps=[29])
    sc = load("irassi_hold_mekf")
    m, _ = results.compute(log, sc, {"law": sc.control.law})
    assert m["estimation"] is not None and m["estimation"]["knowledge_error_arcsec"]["max"] == 0.0
    assert results.compute(log, load("irassi_small"), {"law": "quat_pd"})[0]["estimation"] is None


def test_the_passes_section_is_the_attitude_scenarios_with_targets():
    """The run JSON's `passes`: a list for an attitude scenario with target passes (leo_day; none reached in the
    3 s of a log built in memory, so empty), null for one without targets (irassi_small)."""
    log = make_log(30, cmd_ticks=range(29), sensor_ticks=range(29), status_steps=[29])
    sc = load("leo_day")
    assert results.compute(log, sc, {"law": sc.control.law})[0]["passes"] == []
    assert results.compute(log, load("irassi_small"), {"law": "quat_pd"})[0]["passes"] is None


def test_the_configured_filter_start_is_truth_minus_estimate():
    """_filter_start (docs/spec.md 5.6.10): P0 as configured and the initial errors truth minus estimate, the
    true bias less the prior bias0, and for a q0_BN turned 1e-3 rad about x from the truth an attitude error of
    1e-3 rad about x; nothing for a start from the first star-tracker sample."""
    a = 1e-3
    est = types.SimpleNamespace(init_mode="configured", init_q_BN=(math.sin(a / 2), 0.0, 0.0, math.cos(a / 2)),
                                p0_att_sigma_rad=0.01, p0_bias_sigma_radps=1e-4, bias0_radps=(1e-5, -2e-5, 0.0))
    start = results._filter_start(types.SimpleNamespace(estimator=est), (0.0, 0.0, 0.0, 1.0), (3e-5, 1e-5, -1e-5))
    assert (start["p0_att_rad"], start["p0_bias_radps"]) == (0.01, 1e-4)
    np.testing.assert_allclose(start["e0_bias_B_radps"], (2e-5, 3e-5, -1e-5), rtol=1e-12)
    np.testing.assert_allclose(np.abs(start["e0_att_B_rad"]), (a, 0.0, 0.0), rtol=1e-9, atol=1e-15)
    est.init_mode = "first_star_tracker"
    assert results._filter_start(types.SimpleNamespace(estimator=est), (0.0, 0.0, 0.0, 1.0), (0.0,) * 3) is None


def test_the_longest_unanswered_run_counts_consecutive_unanswered_ticks():
    """counters.longest_unanswered_run (what the verdict's silence rule reads): the longest run of sensor
    ticks without a command, by hand."""
    f = results._longest_false_run
    assert f(np.array([True, False, False, True, False, False, False, True])) == 3
    assert f(np.array([False, True, True])) == 1 and f(np.array([True, True, False, False])) == 2
    assert f(np.ones(5, bool)) == 0 and f(np.zeros(4, bool)) == 4 and f(np.zeros(0, bool)) == 0


def test_only_sensor_frames_of_the_wire_contracts_version_await_an_answer():
    """counters.sensor_ticks_unanswered and longest_unanswered_run count the frames of this PROTOCOL_VERSION
    only: the node refuses (and never answers) another version's, so ticks 2 and 3 (version + 1) are not
    unanswered frames; of the others, tick 5 alone went unanswered."""
    log = make_log(6, cmd_ticks=[0, 1, 4], sensor_ticks=range(6), status_steps=[])
    log.sensors["protocol_version"][:] = results.paths_version()
    log.sensors["protocol_version"][2:4] = results.paths_version() + 1
    out = {}
    results._counters(out, log, 0.1)
    assert out["counters"]["sensor_ticks_unanswered"] == 1
    assert out["counters"]["longest_unanswered_run"] == 1


def test_an_orbit_runs_position_error_initial_and_over_the_window():
    """position_error_m of an orbit run: the initial figure is the first sample's largest |component|, the
    final ones the window's (landsat8_q1, its window set to the last 0.25 s of five samples at 0.1 s: the
    samples at 0.2, 0.3 and 0.4 s)."""
    sc = load("landsat8_q1", {"metrics.window_s": 0.25})
    log = make_log(5, cmd_ticks=[], sensor_ticks=[], status_steps=[])
    log.truth["pos"][:] = [[1.0, -3.0, 2.0], [0.5, 0.0, 0.0], [0.2, 0.1, 0.0], [0.0, -0.05, 0.01], [0.02, 0.0, 0.0]]
    log.truth["vel"][:] = [[0.1, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, 0.0], [0.0, 0.0, -0.004], [0.0, 0.002, 0.0]]
    out, series = {}, {}
    results._accuracy(out, series, log, sc)
    pe = out["position_error_m"]
    assert (pe["initial"], pe["final_max"], pe["velocity_final_max_m_s"]) == (3.0, 0.2, 0.004)
    assert pe["per_axis_final_max"] == [0.2, 0.1, 0.01]


def test_the_hinf_gain_is_measured_over_the_metric_window():
    """metrics["hinf"] of an H-infinity run: ||d||_2 over the last window_s seconds only (a unit disturbance on x
    from 0 to 5 s, a 1 s window: the central-difference samples at 4.0 .. 4.9 s, ||d||_2 = sqrt(10 dt)), with
    the flown table and its designed gamma."""
    from aocs_analysis.gain_tables import designed_gamma

    sc = load("geo_hinf", {"metrics.window_s": 1.0})
    log = make_log(51, cmd_ticks=[], sensor_ticks=[], status_steps=[])
    log.truth["torque_dist"][:, 0] = 1.0
    out = {"law": "hinf"}
    results._hinf(out, log, sc, {"hinf.table": "hinf_regional"})
    h = out["hinf"]
    assert (h["table"], h["gamma"], h["window_s"]) == ("hinf_regional", designed_gamma("hinf_regional"), 1.0)
    assert h["measured"]["d_l2"] == pytest.approx(math.sqrt(10 * sc.dt), rel=1e-12)


def test_the_run_info_carries_what_the_plant_and_the_node_reported():
    """_run_info (the run JSON's log, lockstep, integration_error, udpm, fsw_node and wall_s parts): the
    plant's own figures pass through as it reported them (the verdict reads integration_error), the lockstep
    speed is simulated time over the loop's wall time (100 steps of 0.1 s in 2 s: 5x); without a plant
    report nothing is made up."""
    log = types.SimpleNamespace(status={}, path="run.lcmlog", counts={"truth": 3, "cmd": 2},
                                truth={"t_s": np.arange(3) * 0.1}, cmd={"tick": np.arange(2)})
    ie = {"attitude_arcsec_sum": 1e-3, "attitude_arcsec_local_max": 1e-4, "tolerance_arcsec": 1.0,
          "exceeds_tolerance": False}
    udpm = {"fragments": 0, "garbage": 0, "dropped_partial": 0}
    plant = {"loop_s": 2.0, "startup_s": 0.5, "steps": 100, "roundtrip_ns": {"median": 1000.0, "p99": 2000.0},
             "integration_error": ie, "udpm": udpm}
    out = {}
    results._run_info(out, log, {"mode": "lockstep"}, 0.1, wall_s=3.25, plant=plant, fsw={"precision": "double"})
    assert out["log"] == {"path": "run.lcmlog", "messages": {"cmd": 2, "truth": 3}, "truth_samples": 3,
                          "commands": 2}
    assert out["run_mode"] == "lockstep" and out["target"] == "host" and out["transport"] == "lcm"
    assert out["lockstep"]["realtime_factor"] == pytest.approx(5.0) and out["lockstep"]["startup_s"] == 0.5
    assert out["integration_error"] == ie and out["udpm"] == udpm
    assert out["fsw_node"] == {"precision": "double"} and out["wall_s"] == 3.25
    bare = {}
    results._run_info(bare, log, {}, 0.1, wall_s=None, plant=None, fsw=None)
    assert bare["integration_error"] is None and bare["udpm"] is None and bare["wall_s"] is None
    assert "lockstep" not in bare and "fsw_node" not in bare
    # a real-time run: the node's largest jitter from its status messages, the plant's wake jitter as it said
    rt_log = types.SimpleNamespace(**{**vars(log), "status": {"steps": np.array([10, 20]),
                                                               "jitter_ns_max": np.array([1500, 900])}})
    rt = {}
    results._run_info(rt, rt_log, {"mode": "realtime"}, 0.1, wall_s=None, plant={**plant, "wake_jitter_ns_max": 4321},
                      fsw=None)
    assert rt["realtime"] == {"jitter_ns_max": 1500, "plant_wake_jitter_ns_max": 4321}
    assert rt["loop"]["realtime_factor"] == pytest.approx(5.0) and "lockstep" not in rt
    results._run_info(rt, rt_log, {"mode": "realtime"}, 0.1, wall_s=None, plant=None, fsw=None)
    assert rt["realtime"] == {"jitter_ns_max": 1500, "plant_wake_jitter_ns_max": None}


def test_a_180_deg_error_never_counts_as_settled():
    """q4 = 0 exactly: rho = q_vec / q4 is not finite (inf, or NaN where a component of q_vec is 0 too); such a
    sample is outside the rho criterion however small the rate, the way every other criterion would see it."""
    sc = load("rtc_ex2a")
    qe = np.array([[1e-5, 0.0, 0.0, 1.0], [1.0, 0.0, 0.0, 0.0], [0.0, 1e-5, 0.0, 1.0], [0.6, 0.48, 0.64, 0.0],
                   [0.0, 0.0, 1e-5, 1.0]])
    qe /= np.linalg.norm(qe, axis=1)[:, None]
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = qe[:, :3] / qe[:, 3:]                    # the definition, as attitude_series computes it
    assert np.isnan(rho[1]).any() and np.isinf(rho[3]).all()
    s = {"t": np.arange(5) * 1.0, "rho": rho, "we": np.zeros((5, 3)), "true_angle": np.zeros(5),
         "euler_err": np.zeros((5, 3)), "sigma": np.zeros((5, 3))}
    inside, used = results.settle_mask(sc, s)
    assert "rho_norm_max" in used
    assert inside.tolist() == [True, False, True, False, True]


def test_a_requirement_is_met_at_equality_and_never_by_an_undefined_error():
    assert results.meets_limit(0.5, 0.5) is True
    assert results.meets_limit(0.5, math.nextafter(0.5, 0.0)) is False
    assert results.meets_limit(0.25, 0.5) is True
    assert results.meets_limit(None, 0.5) is False


def _summary_metrics(**kw):
    lim = {"axis": None, "norm": None, "unlimited": True, "commands_over_limit": 0, "plant_slew_rate_limit_per_s": None,
           "plant_lag_tau_s": None}
    lim.update(kw.pop("limits", {}))
    m = {"scenario": "x", "law": "quat_pd", "kind": "attitude", "run_mode": "lockstep", "target": "host",
         "settle_time_s": None, "limits": lim,
         "pointing_error_arcsec": {"initial": 100.0, "final_max": 50.0},
         "timing": {}}
    m.update(kw)
    return m


def test_hinf_measured_gain_against_an_analytic_error():
    """z = 1e-3 M q'' (SPEC 2.6) by central second differences of the logged error angles: a roll error
    phi(t) = A sin(w t) about the rotating target has q'' = -A w^2 sin(w t) exactly, so with a known disturbance
    d the gain ||z||_2 / ||d||_2 is known to the differences' O((w dt)^2 / 12) here 1e-4."""
    sc = load("geo_hinf")
    dt = sc.dt
    t = np.arange(2001) * dt
    amp, w = 1e-3, 2.0 * math.pi / (200.0 * dt)
    phi = amp * np.sin(w * t)
    qe = np.stack([np.sin(phi / 2), 0.0 * t, 0.0 * t, np.cos(phi / 2)], axis=1)
    q = rot.quat_mul_rows(qe, results.target_quat(sc, t))        # qe = q (x) qd^-1 (SPEC 1)
    d = np.tile([1e-4, 2e-4, -1e-4], (t.size, 1)) * (1.0 + 0.5 * np.cos(0.01 * t))[:, None]
    log = types.SimpleNamespace(truth={"t_s": t, "q": q, "w": np.zeros((t.size, 3)), "torque_dist": d})
    ixx = np.asarray(sc.attitude.inertia, float)[0, 0]
    for t_from in (None, t[1000]):              # None: the default, the whole run (as results_doc asks it)
        keep = t[1:-1] >= (t[0] if t_from is None else t_from)
        z = 1e-3 * ixx * (-amp * w * w * np.sin(w * t[1:-1]))[keep]
        z_l2 = math.sqrt(np.sum(z ** 2) * dt)
        d_l2 = math.sqrt(np.sum(d[1:-1][keep] ** 2) * dt)
        g = results.hinf_measured_gain(log, sc) if t_from is None else results.hinf_measured_gain(log, sc, t_from)
        assert g["z_l2"] == pytest.approx(z_l2, rel=1e-3)
        assert g["d_l2"] == pytest.approx(d_l2, rel=1e-12)
        assert g["gain"] == pytest.approx(z_l2 / d_l2, rel=1e-3)
        assert g["z_peak"] == pytest.approx(np.max(np.abs(z)), rel=1e-3)


def test_commanded_torque_figures_by_hand_and_without_any_command():
    """_commands: the largest |u| per axis and |u|_2, and the effort sum |u|_1 dt (each command held one period);
    a run in which the flight software never commanded has zeros, not the figures of some other run."""
    sc = load("irassi_small")
    dt = sc.dt
    u = np.array([[1.0, -2.0, 0.5], [0.0, 0.0, 3.0]])

    def log_of(u, applied):
        n = u.shape[0]
        cmd = {"tick": np.arange(n, dtype=np.int64), "u_sat": u, "u_unsat": u, "mode": np.zeros(n),
               "step_ns": np.zeros(n)}
        return types.SimpleNamespace(truth={"torque_applied": applied}, cmd=cmd)

    out, series = {}, {}
    applied = np.array([[0.5, -1.0, 0.0], [0.2, 0.3, -0.4], [0.0, 0.0, 0.0]])
    results._commands(out, series, log_of(u, applied), sc)
    assert out["max_abs_torque_nm"] == [1.0, 2.0, 3.0]
    assert out["max_torque_norm_nm"] == 3.0          # |u_1| = 3 > |u_0| = sqrt(5.25)
    assert out["effort"] == pytest.approx((3.5 + 3.0) * dt, rel=1e-15)
    assert out["max_abs_applied"] == [0.5, 1.0, 0.4]
    # nothing commanded, and (a run stopped before its first period) nothing applied either
    for applied in (np.zeros((3, 3)), np.zeros((0, 3))):
        out = {}
        results._commands(out, series, log_of(np.zeros((0, 3)), applied), sc)
        assert out["max_abs_torque_nm"] == [0.0, 0.0, 0.0]
        assert out["max_torque_norm_nm"] == 0.0 and out["effort"] == 0.0
        assert out["max_abs_applied"] == [0.0, 0.0, 0.0]


def test_commands_over_the_flight_limits_are_counted_within_1e_12():
    """_limits: the flight software's axis and norm limits from its configuration, a command counted over a
    limit only beyond it by more than 1e-12 relative, a non-finite command counted apart; an axis limit at or
    above UNLIMITED means no limit."""
    sc = load("irassi_small")
    u = np.array([[0.5, 0.0, 0.0], [0.5 * (1 + 2e-12), 0.0, 0.0], [0.5 * (1 + 1e-13), 0.0, 0.0],
                  [0.3, 0.3, 0.3], [np.nan, 0.0, 0.0]])
    out = {}
    results._limits(out, {}, u, {"u_max_axis": "0.5 0.5 0.5", "u_max_norm": "0.5"}, sc)
    lim = out["limits"]
    assert (lim["axis"], lim["norm"], lim["unlimited"]) == (0.5, 0.5, False)
    # over the axis limit: row 1; over the norm limit: row 1 and row 3 (|u| = 0.52); row 2 is within 1e-12
    assert lim["commands_over_limit"] == 3 and lim["commands_not_finite"] == 1
    out = {}
    results._limits(out, {}, u[:1], {"u_max_axis": f"{results.UNLIMITED:g} 0 0"}, sc)
    assert out["limits"]["unlimited"] is True and out["limits"]["axis"] is None
    out = {}
    results._limits(out, {}, u[:1], {}, sc)
    assert out["limits"]["unlimited"] is False and out["limits"]["axis"] is None
    assert out["limits"]["commands_over_limit"] == 0


def test_step_budget_in_slew_and_step_modes_and_a_step_of_exactly_its_budget():
    """_timing: a NOMINAL attitude step's budget is the law's plus the estimator's, plus the slew allowance
    (timing.h AOCS_EXEC_SLEW_BUDGET_NS = 2000 ns) in guidance mode slew only (executive.c step_budget); a step
    of exactly its budget is not over it, one nanosecond more is."""
    from aocs_core import registry
    from aocs_core.modes import mode_value

    law = registry.law_ids()["quat_pd"]
    base = registry.law_budget_ns("quat_pd") + registry.estimator_budget_ns("passthrough")
    assert registry.law_budget_ns("quat_pd") == 2000        # laws.def BUDGET_NS (test_executive_timing.c too)
    for cfg, budget in (({"guidance.mode": "slew"}, base + 2000), ({"guidance.mode": "step"}, base), ({}, base)):
        steps = np.array([budget, budget + 1, 0], dtype=np.int64)
        cmd = {"tick": np.arange(3), "law_id": np.full(3, law), "mode": np.full(3, mode_value("nominal")),
               "step_ns": steps, "overrun": np.zeros(3)}
        out, series = {}, {}
        results._timing(out, series, cmd, {"law": "quat_pd"}, cfg, None)
        np.testing.assert_array_equal(series["budget_ns"], [budget] * 3)
        assert out["timing"]["over_step_budget"] == 1, cfg
    # the MEKF adds its own budget to every step's: NOMINAL (the law's) and SAFE (standby's) alike
    mekf = registry.estimator_budget_ns("mekf")
    assert mekf > 0
    cmd = {"tick": np.arange(2), "law_id": np.full(2, law), "mode": np.array([mode_value("nominal"), mode_value("safe")]),
           "step_ns": np.zeros(2, np.int64), "overrun": np.zeros(2)}
    out, series = {}, {}
    results._timing(out, series, cmd, {"law": "quat_pd"}, {"estimator": "mekf"}, None)
    np.testing.assert_array_equal(series["budget_ns"], [2000 + mekf, registry.law_budget_ns("none") + mekf])
    assert out["timing"]["budget_ns"] == 2000 + mekf


def test_comparison_table_columns_with_and_without_the_slew_bound():
    m = {"law": "smc", "label": "slew", "limits": {"unlimited": False, "axis": 1.0}, "settle_time_s": 150.0,
         "slew_bound_s": 120.0, "pointing_error_arcsec": {"final_max": 0.25, "qe_arcsec_final_max": [0.1, 0.2, 0.05]},
         "max_torque_norm_nm": 1.5, "effort": 42.0, "timing": {"step_ns_p99": 812.4}, "counters": {"time_in_safe_mode_s": 0.0}}
    plain, guided = results.comparison_table([m]).splitlines(), results.comparison_table([m], bound=True).splitlines()
    assert plain[0].split() == ["law", "limit", "settle", "s", "final", "max", "as", "|qe_i|", "max", "as", "max", "|u|",
                                "N", "m", "effort", "step", "ns", "p99", "safe", "s"]
    assert plain[2].split() == ["smc", "(slew)", "1", "150.0", "0.25", "0.2", "1.5", "42", "812", "0"]
    assert guided[0].split()[4:8] == ["bound", "s", "settle/bound", "final"]
    assert guided[2].split()[4:6] == ["120.0", "1.250"]
    assert len(guided) == len(plain) == 3 and set(plain[1]) == {"-", " "}


def test_limit_line_reads_as_english():
    assert results.limit_text(_summary_metrics()) == "none: the reference actuator (no saturation)"
    m = _summary_metrics(limits={"axis": 0.5, "unlimited": False, "commands_over_limit": 0})
    assert results.limit_text(m) == "|u_i| <= 0.5 N m per axis; no command beyond it"
    m = _summary_metrics(limits={"axis": 0.5, "norm": 0.6, "unlimited": False, "commands_over_limit": 2,
                                 "plant_slew_rate_limit_per_s": 0.1, "plant_lag_tau_s": 0.4})
    assert results.limit_text(m) == ("|u_i| <= 0.5 N m per axis and |u| <= 0.6 N m; 2 commands beyond it; the "
                                     "plant's actuator adds a slew-rate limit 0.1 N m/s and a first-order lag 0.4 s")
    m = _summary_metrics(kind="orbit", limits={"axis": 2.0, "unlimited": False, "commands_over_limit": 1})
    assert results.limit_text(m) == "|u_i| <= 2 N per axis; 1 command beyond it"


def _attitude_run_metrics(**kw):
    """The metrics of an attitude run, figures chosen here (the run table's tests)."""
    counters = {"invalid": 1, "stale": 2, "missing": 3, "law_error": 0, "lost": 4, "duplicate": 5, "foreign": 6,
                "malformed": 7, "cmd_accepted": 990, "cmd_rejected": 10, "status": {}, "mode_changes": 1,
                "time_in_safe_mode_s": 0.0, "time_in_saturation_s": 2.5}
    return _summary_metrics(
        duration_s=100.0, control_rate_hz=10.0, settle_time_s=12.34,
        settle_criterion={"criteria": {"pointing_arcsec_max": 10.0}},
        limits={"axis": 0.5, "unlimited": False},
        pointing_error_arcsec={"initial": 7200.0, "final_max": 0.25, "window_s": 60.0, "requirement_arcsec": 0.3,
                               "meets_requirement": True, "per_axis_final_max": [0.1, 0.2, 0.05],
                               "qe_arcsec_final_max": [0.05, 0.1, 0.025]},
        max_abs_torque_nm=[0.1, 0.2, 0.25], max_torque_norm_nm=0.3354, effort=42.5,
        timing={"step_ns_median": 800.0, "step_ns_p99": 900.0, "step_ns_max": 1500.0, "budget_ns": 2000.0,
                "overruns": 0},
        counters=counters, final_mode="NOMINAL", **kw)


def test_the_run_table_of_an_attitude_run_states_each_figure_with_its_unit():
    """table_rows / table (what `aocs run` prints and the run report shows) of an attitude run, figures chosen
    here: each line reads its figure with its unit (2 deg = 7200 arcsec)."""
    m = _attitude_run_metrics()
    rows = dict(results.table_rows(m))
    assert rows["duration"] == "100 s at 10 Hz" and rows["settle time"] == "12.3 s"
    assert rows["settle criterion"] == "pointing_arcsec_max < 10"
    assert rows["initial pointing error"] == "7200 arcsec (2 deg)"
    assert rows["pointing, last 60 s (true angle)"] == "max 0.25 arcsec (requirement 0.3: met)"
    assert rows["per-axis 2 qe_i max"] == "[0.1 0.2 0.05] arcsec"
    assert rows["|qe_i| max (IRASSI figure)"] == "[0.05 0.1 0.025] arcsec"
    assert rows["max |torque| per axis"] == "[0.1 0.2 0.25] N m"
    assert rows["max torque norm"] == "0.3354 N m"
    assert rows["effort (int |u|_1 dt)"] == "42.5 N m s"
    assert rows["limit"] == "|u_i| <= 0.5 N m per axis; no command beyond it"
    assert rows["step time"] == "median 800 ns, p99 900, max 1500, budget 2000, overruns 0"
    assert rows["modes"] == "changes 1, safe 0 s, saturated 2.5 s, final NOMINAL"
    text = results.table(m).splitlines()
    assert len(text) == len(results.table_rows(m))
    assert any(line.split() == ["max", "|torque|", "per", "axis", "[0.1", "0.2", "0.25]", "N", "m"] for line in text)
    # target passes are judged against the run's pointing requirement, which their line names
    m["passes"] = [{"target": {"name": "T1"}, "start_s": 30.0, "settle_s": 0.0, "pointing_max_arcsec": 0.2,
                    "meets_requirement": True}]
    assert dict(results.table_rows(m))["target passes"] == ("1 passes of 1 targets, 1 meet the requirement "
                                                           "(0.3 arcsec); worst pass max 0.2 arcsec")
    # a sub-second slew bound has its ratio too (12.34 s / 0.5 s)
    m["slew_bound_s"] = 0.5
    assert dict(results.table_rows(m))["slew bound (eigenaxis bang-bang)"] == "0.5 s (settle / bound 24.680)"
    # the guidance line: the mode alone in step mode, the slew's profile, margin and planned end in slew mode
    m["guidance"] = {"mode": "step", "profile": None, "margin": None, "profile_end_s": None}
    assert dict(results.table_rows(m))["guidance"] == "step"
    m["guidance"] = {"mode": "slew", "profile": "trapezoid", "margin": 0.9, "profile_end_s": 118.25}
    assert dict(results.table_rows(m))["guidance"] == "slew, trapezoid, margin 0.9, profile end 118.2 s"
    m["guidance"]["profile_end_s"] = None
    assert dict(results.table_rows(m))["guidance"] == "slew, trapezoid, margin 0.9, profile end unknown"
    # the momentum section's lines are the table's too, after the wheels' and before the holds'
    m["momentum"] = {"max_nms": 9.0, "final_nms": 2.5, "capacity_nms": [48.0] * 4, "policy": "thrusters",
                     "unloading": {"events": 2, "time_s": 120.0}}
    names = [k for k, _ in results.table_rows(m)]
    assert names.index("momentum unloading") == names.index("wheel momentum |h_w|") + 1
    assert dict(results.table_rows(m))["momentum unloading"] == "thrusters: 2 unloads, 120 s unloading"


@pytest.mark.parametrize("name,mode", [("irassi_large", "step"), ("irassi_rw_mekf", "slew"), ("landsat8_q1", None)])
def test_the_guidance_section_is_the_attitude_scenarios_own_and_none_for_an_orbit(name, mode):
    """metrics["guidance"]: the scenario's [guidance] mode for an attitude run (the slew's settings only in slew
    mode), None for an orbit run (its loader gives it the default guidance all the same)."""
    sc = load(name)
    assert sc.guidance is not None
    out = {}
    results._guidance(out, sc, None)
    if mode is None:
        assert out["guidance"] is None
    else:
        assert out["guidance"]["mode"] == mode
        assert (out["guidance"]["margin"] is None) is (mode != "slew")
        assert out["guidance"]["profile_end_s"] is None            # no flight-software report given


def test_the_run_table_of_an_orbit_run_states_position_velocity_and_force():
    """table_rows of an orbit run: the position and velocity errors over the window and the force figures,
    each with its unit, in place of the attitude lines."""
    m = _summary_metrics(
        kind="orbit", pointing_error_arcsec=None, duration_s=100.0, control_rate_hz=10.0, settle_time_s=None,
        settle_criterion={"criteria": {"position_m_max": 1.0}}, limits={"axis": 2.0, "unlimited": False},
        position_error_m={"window_s": 50.0, "final_max": 0.125, "velocity_final_max_m_s": 0.0025},
        max_abs_force_n=[0.5, 1.0, 2.0], effort=12.5,
        timing={"step_ns_median": 800.0, "step_ns_p99": 900.0, "step_ns_max": 1500.0, "budget_ns": 2000.0,
                "overruns": 0}, final_mode="NOMINAL",
        counters={"invalid": 0, "stale": 0, "missing": 0, "law_error": 0, "lost": 0, "duplicate": 0, "foreign": 0,
                  "malformed": 0, "cmd_accepted": 0, "cmd_rejected": 0, "status": {}, "mode_changes": 0,
                  "time_in_safe_mode_s": 0.0, "time_in_saturation_s": 0.0})
    rows = dict(results.table_rows(m))
    assert rows["settle time"] == "never"
    assert rows["position error, last 50 s"] == "max 0.125 m"
    assert rows["velocity error, same window"] == "max 0.0025 m/s"
    assert rows["max |force| per axis"] == "[0.5 1 2] N"
    assert rows["effort (int |F|_1 dt)"] == "12.5 N s"
    assert "max |torque| per axis" not in rows


def test_a_diverging_run_is_named_diverging():
    assert results.divergence(_summary_metrics()) is None                       # error fell: not diverging
    grew = _summary_metrics(pointing_error_arcsec={"initial": 100.0, "final_max": 5000.0})
    assert "diverges" in results.divergence(grew) and "100 arcsec" in results.divergence(grew)
    assert results.divergence(dict(grew, settle_time_s=12.0)) is None          # settled: not diverging
    orbit = _summary_metrics(kind="orbit", pointing_error_arcsec=None,
                             position_error_m={"initial": 10.0, "final_max": 1e4})
    assert "1e+04 m" in results.divergence(orbit)


def test_pil_target_precision_in_the_run_line():
    m = _summary_metrics(target="pil-m4f", timing={"precision": "float", "clock_hz": 168e6})
    assert results._run_text(m) == ("lockstep on pil-m4f (float, image under QEMU, step time from instructions "
                                    "at 168 MHz)")
    assert results._run_text(_summary_metrics()) == "lockstep on host (double)"


def test_attitude_series_against_the_error_rotation_by_hand():
    """The truth is the target turned by theta about a fixed unit axis n (qe = q (x) qd^-1, SPEC 1): the
    true angle is theta, the Gibbs vector rho = tan(theta / 2) n, the MRP sigma = tan(theta / 4) n (Schaub
    and Junkins, "Analytical Mechanics of Space Systems", 3.6 and 3.7), and the rate error is w minus the
    target's rate in B, w_e = w - A(qe) w_d. theta up to 170 deg, where rho and sigma differ most."""
    sc = load("geo_hinf")
    t = np.arange(5) * sc.dt
    theta = np.radians([0.5, 30.0, 90.0, 120.0, 170.0])
    n = np.array([2.0, -1.0, 2.0]) / 3.0
    qe = np.column_stack([np.sin(theta / 2)[:, None] * n, np.cos(theta / 2)])
    q = rot.quat_mul_rows(qe, results.target_quat(sc, t))
    wd = np.asarray(sc.target.wd, float)
    dw = np.array([[1e-4, 0.0, -2e-4]] * 5)
    wd_b = np.array([np.asarray(rot.quat_to_dcm(tuple(e)), float) @ wd for e in qe])
    log = types.SimpleNamespace(truth={"t_s": t, "q": q, "w": wd_b + dw})
    s = results.attitude_series(sc, log)
    np.testing.assert_allclose(s["true_angle"], np.degrees(theta) * 3600.0, rtol=1e-9)
    np.testing.assert_allclose(s["rho"], np.tan(theta / 2)[:, None] * n, rtol=1e-9)
    np.testing.assert_allclose(s["sigma"], np.tan(theta / 4)[:, None] * n, rtol=1e-9)
    np.testing.assert_allclose(s["we"], dw, rtol=1e-9, atol=1e-15)


def test_plan_index_is_the_observation_commanded_at_each_time():
    """Commands at 0, 10.05 and 20 s with a 0.1 s period act from the ticks 0, 101 and 200: the observation at
    each time by hand, and ObservationPlan.index_at sample by sample."""
    from aocs_plant.observation_plan import ObservationPlan
    plan = types.SimpleNamespace(command_times_s=[0.0, 10.05, 20.0])
    t = np.array([0.0, 5.0, 10.0, 10.1, 19.9, 20.0, 30.0])
    np.testing.assert_array_equal(results.plan_index(plan, t, 0.1), [0, 0, 0, 1, 1, 2, 2])
    dense = np.round(np.arange(0, 301) * 0.1, 9)
    ref = [ObservationPlan.index_at(plan, x, 0.1) for x in dense]
    np.testing.assert_array_equal(results.plan_index(plan, dense, 0.1), ref)


def test_the_lockstep_line_states_the_round_trip_it_measured():
    m = _attitude_run_metrics(lockstep={"realtime_factor": 812.4, "loop_s": 0.6155, "startup_s": 0.41,
                                   "roundtrip_ns": {"median": 33400.0, "p99": 61250.0}})
    rows = dict(results.table_rows(m))
    assert rows["lockstep speed"] == ("812x real time, loop 0.616 s, round trip median 33.4 us p99 61.2 us, "
                                      "startup 0.41 s")
    m["lockstep"]["roundtrip_ns"] = None                     # a direct run: no round trip, zeros
    assert "round trip median 0.0 us p99 0.0 us" in dict(results.table_rows(m))["lockstep speed"]


@pytest.mark.parametrize("bound_s,settle_s,ratio", [(0.5, 0.6, "1.200"), (1.0, 0.75, "0.750"), (0.0, 3.0, "-"),
                                                    (None, 3.0, "-"), (2.0, None, "-")])
def test_the_settle_over_bound_ratio_for_any_positive_bound(bound_s, settle_s, ratio):
    """settle / bound for every positive bound, sub-second ones too; none (-) without a bound, a positive one,
    or a settle time."""
    m = {"law": "smc", "limits": {"unlimited": True}, "settle_time_s": settle_s, "slew_bound_s": bound_s,
         "pointing_error_arcsec": {}, "max_torque_norm_nm": 1.0, "effort": 1.0, "timing": {"step_ns_p99": 1.0},
         "counters": {"time_in_safe_mode_s": 0.0}}
    assert results.comparison_table([m], bound=True).splitlines()[2].split()[4] == ratio   # settle/bound


def test_distinct_pairs_index_every_row():
    """run_metrics._distinct_pairs (the step budgets' (law, mode) pairs) against a dict of the rows: each pair once,
    in order of first appearance, each row's index to its own pair; long runs, single rows, values beyond 2^32."""
    rng = np.random.default_rng(4)
    for trial in range(100):
        n = int(rng.integers(1, 400))
        a = rng.integers(-3, 3, n) * (2**40 if trial % 2 else 1)
        b = rng.integers(0, 4, n)
        if trial % 3 == 0:     # runs of equal rows, as a flight's law and mode hold
            a, b = np.repeat(a[:6], n // 6 + 1)[:n], np.repeat(b[:6], n // 6 + 1)[:n]
        rows = list(zip(a.tolist(), b.tolist()))
        pairs, inverse = results._distinct_pairs(a, b)
        assert pairs == list(dict.fromkeys(rows))
        assert [pairs[i] for i in inverse] == rows
    pairs, inverse = results._distinct_pairs(np.zeros(0, int), np.zeros(0, int))
    assert pairs == [] and inverse.size == 0
