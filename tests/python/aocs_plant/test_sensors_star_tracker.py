"""The star tracker (sensors/star_tracker.py) against a model written out here: the error rotation per axis of
its own frame S from A(q) built from the components (scalar last, A maps N to B), the mounting applied by
hand, the latency against the plant's own past attitudes, the exclusion geometry from the environment's
Sun and Earth directions, the outages, the seeded stream, and the one-line scenario errors."""
import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load

ARCSEC = 180.0 * 3600.0 / math.pi   # arcsec per rad
QUIET = {"disturbances.constant_torque.enabled": False, "disturbances.gravity_gradient_l2.enabled": False}


def _dcm(q):
    """A(q), scalar last (SPEC 1.2), independent of aocs_core."""
    q1, q2, q3, q4 = q
    return np.array([
        [q1 * q1 - q2 * q2 - q3 * q3 + q4 * q4, 2 * (q1 * q2 + q3 * q4), 2 * (q1 * q3 - q2 * q4)],
        [2 * (q1 * q2 - q3 * q4), -q1 * q1 + q2 * q2 - q3 * q3 + q4 * q4, 2 * (q2 * q3 + q1 * q4)],
        [2 * (q1 * q3 + q2 * q4), 2 * (q2 * q3 - q1 * q4), -q1 * q1 - q2 * q2 + q3 * q3 + q4 * q4]])


def _error(a_meas, a_true):
    """The rotation vector e of A(q_meas) A(q_true)^T = exp(-[e x]) (rad)."""
    d = a_meas @ a_true.T
    v = 0.5 * np.array([d[1, 2] - d[2, 1], d[2, 0] - d[0, 2], d[0, 1] - d[1, 0]])
    s = np.linalg.norm(v)
    if s == 0.0:
        return v
    th = math.atan2(s, 0.5 * (np.trace(d) - 1.0))
    return v * th / s


#: a mounting: S is B turned 90 deg about x_B, then 30 deg about the new y (q_SB, scalar last, by hand)
_qx = (math.sin(math.pi / 4), 0.0, 0.0, math.cos(math.pi / 4))
_A_SB = np.array([[math.cos(math.pi / 6), 0, -math.sin(math.pi / 6)], [0, 1, 0],
                  [math.sin(math.pi / 6), 0, math.cos(math.pi / 6)]]) @ _dcm(_qx)


def _quat_of(a):
    """The quaternion (scalar last, q4 >= 0) of the rotation matrix a (Shepperd's method, q4 branch)."""
    q4 = 0.5 * math.sqrt(1.0 + np.trace(a))
    return (a[1, 2] - a[2, 1]) / (4 * q4), (a[2, 0] - a[0, 2]) / (4 * q4), (a[0, 1] - a[1, 0]) / (4 * q4), q4


Q_SB = _quat_of(_A_SB)


def _plant(st: dict, **ov):
    o = {"seed": 11, "plant.w0": [0.002, -0.001, 0.0015], **QUIET, "sensors.star_tracker": st}
    o.update(ov)
    return Plant(load("irassi_large", o))


def test_the_error_per_axis_of_s_has_the_configured_sigmas():
    cross, about = 2.0, 10.0
    p = _plant({"mounting_q": list(Q_SB), "noise_cross_arcsec": cross, "noise_about_arcsec": about})
    errs, reported = [], []
    for _ in range(6000):
        s = p.sense()
        assert s["st_new"] and s["st_valid"] and s["st_t_meas"] == s["t"]
        a_true = _A_SB @ _dcm(p.truth()["q"])           # A(q_SN) = A(q_SB) A(q_BN)
        errs.append(_error(_dcm(s["st_q"]), a_true))
        reported.append(p.truth()["sensors"]["star_tracker.error_rad"])
        p.advance()
    e = np.array(errs) * ARCSEC
    np.testing.assert_allclose(e, np.array(reported) * ARCSEC, atol=1e-6)   # the truth field is that rotation
    std, n = e.std(axis=0), len(e)
    # the sample std of N normals has a relative std of 1/sqrt(2N) = 0.9 %: 5 sigma
    tol = 5.0 / math.sqrt(2 * n)
    np.testing.assert_allclose(std, [cross, cross, about], rtol=tol)
    assert np.all(np.abs(e.mean(axis=0)) < 5 * std / math.sqrt(n))
    assert abs(np.corrcoef(e.T)[0, 2]) < 5 / math.sqrt(n)
    print(f"star tracker 1-sigma per axis of S (arcsec): {std.round(4).tolist()} for {cross}, {cross}, {about}")


def test_the_bias_is_a_fixed_rotation_in_s_and_the_truth_is_q_sn():
    bias = [3.0, -2.0, 5.0]
    p = _plant({"mounting_q": list(Q_SB), "bias_arcsec": bias})
    for _ in range(5):
        s = p.sense()
        a_true = _A_SB @ _dcm(p.truth()["q"])
        np.testing.assert_allclose(_error(_dcm(s["st_q"]), a_true) * ARCSEC, bias, atol=1e-7)
        np.testing.assert_allclose(_dcm(p.truth()["sensors"]["star_tracker.q_sn"]), a_true, atol=1e-15)
        p.advance()


def test_latency_gives_the_attitude_at_t_meas():
    p = _plant({"latency_s": 0.3})
    past = {}
    for k in range(40):
        s = p.sense()
        past[k] = _dcm(p.truth()["q"])
        if k < 3:   # t - 0.3 < 0: no sample yet
            assert not s["st_new"] and not s["st_valid"] and s["st_q"] == (0.0, 0.0, 0.0, 1.0)
        else:
            assert s["st_new"] and s["st_valid"] and s["st_t_meas"] == pytest.approx(s["t"] - 0.3, abs=1e-12)
            np.testing.assert_allclose(_dcm(s["st_q"]), past[k - 3], atol=1e-14)
        p.advance()
    # between period ends: on the rotation from one to the next, at the fraction latency sets
    p = _plant({"latency_s": 0.25})
    past = {}
    for k in range(30):
        s = p.sense()
        past[k] = _dcm(p.truth()["q"])
        if k >= 3:
            assert s["st_t_meas"] == pytest.approx(s["t"] - 0.25, abs=1e-12)
            m = _dcm(s["st_q"])
            a, b = past[k - 3], past[k - 2]    # t - 0.3 and t - 0.2
            ea, eb, ab = _error(m, a), _error(b, m), _error(b, a)
            np.testing.assert_allclose(ea, 0.5 * ab, atol=1e-12)
            np.testing.assert_allclose(eb, 0.5 * ab, atol=1e-12)
        p.advance()


def test_the_attitude_before_the_oldest_record_is_the_oldest():
    """attitude_at: on a recorded period end its attitude, between two the slerp, before the oldest record the
    oldest (no extrapolation), after the newest the newest."""
    st, = [s for s in _plant({"latency_s": 0.3}).sensors if s.name == "star_tracker"]
    def about_z(a):
        return (0.0, 0.0, math.sin(a / 2), math.cos(a / 2))
    q = [about_z(a) for a in (1e-3, 2e-3, 3e-3)]
    st.records_tq[:] = [(1.0, q[0]), (1.1, q[1]), (1.2, q[2])]
    assert st.attitude_at(0.5) == q[0] and st.attitude_at(1.0) == q[0] and st.attitude_at(1.1) == q[1]
    assert st.attitude_at(2.0) == q[2]
    np.testing.assert_allclose(_dcm(st.attitude_at(1.05)), _dcm(about_z(1.5e-3)), atol=1e-15)


def test_its_own_rate_repeats_the_last_sample_between_samples():
    p = _plant({"rate_hz": 3.0, "noise_cross_arcsec": 1.0})   # control 10 Hz: due at j / 3 s
    new_at, last = [], None
    for k in range(100):
        s = p.sense()
        if s["st_new"]:
            new_at.append(k)
            assert s["st_valid"] and s["st_t_meas"] == s["t"]
            last = (s["st_q"], s["st_t_meas"])
        else:
            assert not s["st_valid"] and (s["st_q"], s["st_t_meas"]) == last
        p.advance()
    # the first tick at or after each j / 3 s
    assert new_at == [math.ceil(j / 3 * 10 - 1e-9) for j in range(len(new_at))] and len(new_at) == 30
    assert p.counters["invalid_samples"] == 0      # between samples is not invalid


def _pointing_at(v_n):
    """A quaternion q_BN whose +z_B is the unit vector v_n (N)."""
    z = np.asarray(v_n) / np.linalg.norm(v_n)
    x = np.cross([0.0, 0.0, 1.0], z) if abs(z[2]) < 0.9 else np.cross([1.0, 0.0, 0.0], z)
    x /= np.linalg.norm(x)
    a = np.array([x, np.cross(z, x), z])             # rows: the body axes in N
    return list(_quat_of(a))


def test_the_sun_exclusion_flags_the_sample_when_the_boresight_sees_the_sun():
    env = Plant(load("irassi_large")).environment
    sun = np.array(env.sun_direction(0.0))
    ov = {"plant.euler321_deg": None, "plant.quaternion": _pointing_at(sun), "plant.w0": [0.0, 0.0, 0.0]}
    p = _plant({"sun_exclusion_deg": 30.0, "earth_exclusion_deg": 20.0}, **ov)
    s = p.sense()
    tr = p.truth()["sensors"]
    assert s["st_new"] and not s["st_valid"] and tr["star_tracker.sun_excluded"]
    assert tr["star_tracker.sun_angle_deg"] < 1e-3 and tr["star_tracker.earth_angle_deg"] is None   # no orbit
    assert p.counters["invalid_samples"] == 1
    # 40 deg from the Sun: outside a 30 deg exclusion, inside a 45 deg one
    off = np.cos(np.radians(40)) * sun + np.sin(np.radians(40)) * np.cross(sun, [0, 0, 1]) / np.linalg.norm(
        np.cross(sun, [0, 0, 1]))
    ov["plant.quaternion"] = _pointing_at(off)
    for angle, valid in ((30.0, True), (45.0, False)):
        p = _plant({"sun_exclusion_deg": angle}, **ov)
        s = p.sense()
        assert s["st_valid"] is valid
        assert p.truth()["sensors"]["star_tracker.sun_angle_deg"] == pytest.approx(40.0, abs=1e-6)


def test_the_earth_exclusion_uses_the_orbit_of_the_environment():
    orbit = {"radius_m": 7.0e6, "inclination_deg": 50.0}
    env = Plant(load("irassi_large", {"environment.orbit": orbit})).environment
    r = np.array(env.orbit_state(0.0)[0])
    ov = {"plant.euler321_deg": None, "plant.quaternion": _pointing_at(-r), "plant.w0": [0.0, 0.0, 0.0],
          "environment.orbit": orbit}
    p = _plant({"earth_exclusion_deg": 70.0}, **ov)
    s = p.sense()
    tr = p.truth()["sensors"]
    assert not s["st_valid"] and tr["star_tracker.earth_excluded"] and not tr["star_tracker.sun_excluded"]
    assert tr["star_tracker.earth_angle_deg"] < 1e-3
    # the body holds its attitude while the spacecraft moves on: the Earth leaves the boresight
    n = math.sqrt(3.986004418e14 / 7.0e6 ** 3)
    k = int(math.ceil(math.radians(75.0) / n / p.dt))       # 75 deg of orbit later
    for _ in range(k):
        p.advance()
    s = p.sense()
    assert s["st_valid"] and p.truth()["sensors"]["star_tracker.earth_angle_deg"] > 70.0


def test_outages_take_no_sample():
    p = _plant({"outages": [[1.0, 2.0], [3.05, 3.25]]})
    for k in range(40):
        s = p.sense()
        t = s["t"]
        out = 1.0 - 1e-9 <= t < 2.0 - 1e-9 or 3.05 <= t < 3.25
        assert s["st_new"] is not out and s["st_valid"] is not out
        assert p.truth()["sensors"]["star_tracker.outage"] is out
        if out:
            assert s["st_t_meas"] == pytest.approx(0.9 if t < 2 else 3.0)
        p.advance()
    assert p.counters["invalid_samples"] == 12


def test_the_low_frequency_errors():
    # a sinusoid: e_x = A sin(2 pi t_meas / P + phase), exactly
    p = _plant({"low_frequency": "sinusoid", "low_frequency_amplitude_arcsec": [3.0, 0.0, 1.0],
                "low_frequency_time_s": [10.0, 5.0, 4.0], "low_frequency_phase_deg": [0.0, 0.0, 90.0]})
    for _ in range(50):
        s = p.sense()
        e = np.array(p.truth()["sensors"]["star_tracker.error_rad"]) * ARCSEC
        t = s["st_t_meas"]
        np.testing.assert_allclose(e, [3.0 * math.sin(2 * math.pi * t / 10.0), 0.0,
                                       math.sin(2 * math.pi * t / 4.0 + math.pi / 2)], atol=1e-12)
        p.advance()
    # a first-order Gauss-Markov: stationary std A, lag-one autocorrelation exp(-h / tau)
    p = _plant({"low_frequency": "gauss_markov", "low_frequency_amplitude_arcsec": 4.0,
                "low_frequency_time_s": 2.0}, **{"plant.w0": [0.0, 0.0, 0.0]})
    e = []
    for _ in range(20000):
        p.sense()
        e.append(p.truth()["sensors"]["star_tracker.error_rad"])
        p.advance()
    e = np.array(e) * ARCSEC
    rho = math.exp(-0.1 / 2.0)
    # effective sample count of an AR(1) sequence: N (1 - rho) / (1 + rho); 5 sigma on the std
    n_eff = len(e) * (1 - rho) / (1 + rho)
    np.testing.assert_allclose(e.std(axis=0), 4.0, rtol=5.0 / math.sqrt(2 * n_eff))
    lag1 = [np.corrcoef(e[:-1, i], e[1:, i])[0, 1] for i in range(3)]
    np.testing.assert_allclose(lag1, rho, atol=5.0 * (1 - rho * rho) / math.sqrt(len(e)))
    print(f"Gauss-Markov: std {e.std(axis=0).round(3).tolist()} arcsec (4.0), lag-1 {np.round(lag1, 4).tolist()} "
          f"({rho:.4f})")


def test_it_is_seeded_and_leaves_the_other_streams_alone():
    st = {"noise_cross_arcsec": 1.0, "noise_about_arcsec": 5.0}
    ov = {"sensors.rate_noise_rad_s": 1e-6, "sensors.attitude_noise_rad": 1e-6}
    a, b = _plant(st, **ov), _plant(st, **ov)
    c = _plant(st, seed=12, **ov)
    ref = Plant(load("irassi_large", {"seed": 11, "plant.w0": [0.002, -0.001, 0.0015], **QUIET, **ov}))
    for _ in range(20):
        sa, sb, sc, sr = a.sense(), b.sense(), c.sense(), ref.sense()
        assert sa["st_q"] == sb["st_q"] and sa["st_q"] != sc["st_q"]
        assert (sa["w"], sa["q"]) == (sr["w"], sr["q"])     # the ideal-sensor streams do not move
        for p in (a, b, c, ref):
            p.advance()


def test_faults_reach_it():
    p = _plant({"rate_hz": 5.0}, **{"sensors.faults": [
        {"channel": "star_tracker", "kind": "dropout", "start_s": 0.4, "end_s": 0.6},
        {"channel": "star_tracker", "kind": "nonunit", "start_s": 1.0, "end_s": 1.1, "factor": 2.0}]})
    for k in range(12):
        s = p.sense()
        if k in (4, 5):
            assert not s["st_valid"]
        if k == 10:
            assert s["st_valid"] and math.isclose(np.linalg.norm(s["st_q"]), 2.0)
        p.advance()


@pytest.mark.parametrize("st,message", [
    ({"noise_cross_arcsec": -1.0}, "sensors.star_tracker.noise_cross_arcsec: must be >= 0, got -1.0"),
    ({"rate_hz": 20.0}, r"sensors.star_tracker.rate_hz: 20 Hz is above the control rate \(10 Hz\)"),
    ({"mounting_q": [0.0, 0.0, 0.1, 1.0]}, "sensors.star_tracker.mounting_q: must be a unit quaternion"),
    ({"outages": [[5.0, 4.0]]}, r"sensors.star_tracker.outages\[0\]: ends before it starts \(4 <= 5 s\)"),
    ({"outages": [[-1.0, 4.0]]}, r"sensors.star_tracker.outages\[0\]: starts before the run"),
    ({"outages": [[600.0, 700.0]]}, r"sensors.star_tracker.outages\[0\]: starts at 600 s, not inside the run"),
    ({"outages": [5.0]}, r"sensors.star_tracker.outages\[0\]: expected an array of 2 numbers"),
    ({"sun_exclusion_deg": 180.0}, "sensors.star_tracker.sun_exclusion_deg: 180 deg must be below 180 deg"),
    ({"latency_s": -0.1}, "sensors.star_tracker.latency_s: must be >= 0"),
    ({"low_frequency_time_s": 3.0}, 'sensors.star_tracker.low_frequency_time_s: needs low_frequency = '),
    ({"low_frequency": "gauss_markov", "low_frequency_amplitude_arcsec": 1.0},
     "sensors.star_tracker.low_frequency_time_s: missing required key"),
    ({"low_frequency": "pink"}, "sensors.star_tracker.low_frequency: unknown value 'pink'"),
    ({"noise_arcsec": 1.0}, "sensors.star_tracker.noise_arcsec: unknown key"),
])
def test_bad_input_is_one_line_naming_file_and_key(st, message):
    with pytest.raises(ScenarioError, match=r"irassi_large.toml: " + message) as exc:
        load("irassi_large", {"sensors.star_tracker": st})
    assert "\n" not in str(exc.value)


def test_a_rate_at_the_control_rate_within_rounding_is_the_control_rate():
    """rate_hz is compared with 1 / dt to 1e-9 relative: the control rate written with its rounding (10 Hz
    plus 1e-12 relative, as 1 / dt can come out) is accepted; 1e-8 above it is refused."""
    assert load("irassi_large", {"sensors.star_tracker": {"rate_hz": 10.0 * (1.0 + 1e-12)}}) is not None
    with pytest.raises(ScenarioError, match="is above the control rate"):
        load("irassi_large", {"sensors.star_tracker": {"rate_hz": 10.0 * (1.0 + 1e-8)}})


def test_it_does_not_apply_to_an_orbit_scenario_and_is_absent_by_default():
    with pytest.raises(ScenarioError, match=r"landsat8_q1.toml: sensors.star_tracker: does not apply to a orbit"):
        load("landsat8_q1", {"sensors.star_tracker": {}})
    assert "star_tracker" not in load("irassi_large").sensors.sensors
    assert [s.name for s in Plant(load("irassi_large", {"sensors.star_tracker": {}})).sensors] == [
        "attitude", "rate", "star_tracker"]


def test_the_latency_interpolation_is_the_shortest_path_slerp():
    """_slerp (the attitude between two records) against scipy's Slerp on random pairs, the pairs given with
    either sign of the second quaternion (the same rotation): the rotation a fraction f along the shortest path."""
    from scipy.spatial.transform import Rotation, Slerp

    from aocs_plant.sensors.star_tracker import _slerp
    rng = np.random.default_rng(5)
    for _ in range(40):
        qa, qb = (tuple(r.as_quat()) for r in Rotation.random(2, random_state=rng))
        d = Rotation.from_quat(qb) * Rotation.from_quat(qa).inv()
        if d.magnitude() < 1e-3:
            continue
        ref = Slerp([0.0, 1.0], Rotation.from_quat([qa, qb]))
        for sign in (1.0, -1.0):
            for f in (0.0, 0.25, 0.5, 0.9, 1.0):
                q = np.array(_slerp(qa, tuple(sign * x for x in qb), f))
                assert abs(float(q @ ref([f]).as_quat()[0])) == pytest.approx(1.0, abs=1e-12), (qa, qb, f)
