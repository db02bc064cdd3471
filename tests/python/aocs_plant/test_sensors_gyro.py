"""The gyro (sensors/gyro.py) against models written out here: the Allan variance of its output against the
ARW + RRW law sigma_A^2(tau) = sigma_v^2 / tau + sigma_u^2 tau / 3, the variance of its bias increments
(sigma_u^2 h) and of its rate noise (sigma_v^2 / h + sigma_u^2 h / 12), the true mean rate from the plant's
own attitudes, scale factor and misalignment as matrices written here, quantisation, saturation, the
angle mode, the seeded stream, and the one-line scenario errors."""
import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.sensors import SensorContext
from aocs_plant.sensors.gyro import Gyro

QUIET = {"disturbances.constant_torque.enabled": False, "disturbances.gravity_gradient_l2.enabled": False}
H = 0.1    # irassi_large's control period


def _gyro(cfg: dict, seed: int = 5) -> Gyro:
    config = load("irassi_large", {"sensors.gyro": cfg}).sensors["gyro"]
    return Gyro(config, SensorContext("attitude", H, seed))


def _quat_mul(q, p):
    """Shuster's product, scalar last (SPEC 1), written out."""
    qv, pv = np.asarray(q[:3]), np.asarray(p[:3])
    v = q[3] * pv + p[3] * qv - np.cross(qv, pv)
    return (*v, q[3] * p[3] - qv @ pv)


def _constant_rate(gyro, w, n):
    """Feed n samples of a constant body rate w: q_k = dq (x) q_(k-1), dq the rotation by w h."""
    w = np.asarray(w, float)
    a = np.linalg.norm(w) * H
    e = w / np.linalg.norm(w) if a > 0 else np.zeros(3)
    dq = (*(e * math.sin(a / 2)), math.cos(a / 2))
    q = (0.0, 0.0, 0.0, 1.0)
    out, truth = [], []
    wt = tuple(w.tolist())
    for k in range(n):
        out.append(gyro.measure((k * H, q, wt)))
        truth.append(gyro.truth())
        if a > 0:
            q = _quat_mul(dq, q)
            q = tuple((np.asarray(q) / np.linalg.norm(q)).tolist())
    return np.array(out), truth


def _allan(y, h, m):
    """Overlapping Allan variance of the rate samples y (N x 3) at tau = m h (IEEE Std 952)."""
    theta = np.concatenate([np.zeros((1, 3)), np.cumsum(y, axis=0) * h])
    tau = m * h
    d = theta[2 * m:] - 2 * theta[m:-m] + theta[:-2 * m]
    return (d * d).mean(axis=0) / (2 * tau * tau)


def test_the_allan_variance_follows_arw_and_rrw():
    sv, su = 1e-5, 1e-5       # crossover tau = sqrt(3) sv / su = 1.7 s
    y, _ = _constant_rate(_gyro({"arw_rad_sqrt_s": sv, "rrw_rad_s_sqrt_s": su}), (0.0, 0.0, 0.0), 200_000)
    rows = []
    for m, tol in ((1, 0.03), (10, 0.06), (100, 0.15)):
        tau = m * H
        model = sv * sv / tau + su * su * tau / 3
        avar = _allan(y, H, m)
        rows.append((tau, np.sqrt(avar).round(9).tolist(), math.sqrt(model)))
        np.testing.assert_allclose(avar, model, rtol=tol)
    print("Allan deviation (tau s, measured per axis, model):", rows)


def test_the_noise_and_the_bias_increments_have_the_discrete_variances():
    # sigma_u dominates the rate noise here: sigma_v^2 / h = 1e-13, sigma_u^2 h / 12 = 8.3e-13
    sv, su = 1e-7, 1e-5
    y, truth = _constant_rate(_gyro({"arw_rad_sqrt_s": sv, "rrw_rad_s_sqrt_s": su}), (0.0, 0.0, 0.0), 100_000)
    b = np.array([t["bias_rad_s"] for t in truth])
    bm = np.array([t["bias_mean_rad_s"] for t in truth])
    n = len(y)
    tol = 5 * math.sqrt(2 / n)          # 5 sigma of a sample variance
    db = np.diff(b, axis=0)
    np.testing.assert_allclose(db.var(axis=0), su * su * H, rtol=tol)
    np.testing.assert_allclose(bm[1:], 0.5 * (b[:-1] + b[1:]), rtol=1e-12)   # the mean bias over the sample
    noise = y - bm
    model = sv * sv / H + su * su * H / 12
    np.testing.assert_allclose(noise.var(axis=0), model, rtol=tol)
    assert np.all(np.abs(noise.var(axis=0) / (su * su * H / 4) - 1) > 0.5)   # not the mid-point-free form
    print(f"rate noise variance {noise.var(axis=0).tolist()} (model {model:.4g}); bias increment variance "
          f"{db.var(axis=0).tolist()} (model {su * su * H:.4g})")


def test_the_angle_mode_is_the_rate_times_the_interval():
    cfg = {"arw_rad_sqrt_s": 1e-5, "rrw_rad_s_sqrt_s": 1e-6, "bias_rad_s": [1e-4, 0, -1e-4]}
    w, _ = _constant_rate(_gyro(cfg), (0.01, -0.02, 0.005), 200)
    d, _ = _constant_rate(_gyro({**cfg, "mode": "angle"}), (0.01, -0.02, 0.005), 200)
    np.testing.assert_allclose(d, w * H, rtol=1e-12, atol=0)   # h = t_k - t_(k-1) in floating point


def test_the_true_rate_is_the_mean_over_the_sample_from_the_plants_attitudes():
    p = Plant(load("irassi_large", {**QUIET, "plant.w0": [0.03, -0.02, 0.01],
                                    "sensors.gyro": {"bias_rad_s": [1e-5, -2e-5, 3e-5]}}))
    prev_q, prev_w = None, None
    for k in range(50):
        s = p.sense()
        q, w = np.asarray(p.truth()["q"]), np.asarray(p.truth()["w"])
        if prev_q is None:
            np.testing.assert_allclose(s["gyro_w"], w + [1e-5, -2e-5, 3e-5], atol=1e-17)
        else:
            dq = _quat_mul(q, (-prev_q[0], -prev_q[1], -prev_q[2], prev_q[3]))
            v = np.asarray(dq[:3])
            rotvec = 2 * math.atan2(np.linalg.norm(v), dq[3]) * v / np.linalg.norm(v)
            np.testing.assert_allclose(s["gyro_w"], rotvec / H + [1e-5, -2e-5, 3e-5], rtol=1e-12, atol=1e-17)
            # and the mean rate is close to the trapezoid of the body rates (the body tumbles slowly)
            np.testing.assert_allclose(rotvec / H, 0.5 * (w + prev_w), atol=1e-6)
        prev_q, prev_w = q, w
        p.advance()


def test_a_sample_at_the_time_of_the_last_reads_the_rate_it_is_given():
    """Two samples at t = 3 s (no time between them, the plant sampled twice): the second has no interval to
    average over, so it reads the body rate given, like the first sample, not a rotation over 0 s."""
    g = _gyro({"arw_rad_sqrt_s": 0.0, "rrw_rad_s_sqrt_s": 0.0})
    w = (0.01, -0.02, 0.005)
    q = (0.0, 0.0, 0.0, 1.0)
    first = g.measure((3.0, q, w))
    again = g.measure((3.0, q, w))
    np.testing.assert_allclose(again, first, rtol=0, atol=0)
    np.testing.assert_allclose(first, w, rtol=1e-12)


def test_scale_factor_and_misalignment():
    w = np.array([0.01, -0.02, 0.03])
    sf, d = [100.0, -200.0, 300.0], [1e-3, -2e-3, 0.5e-3]
    y, _ = _constant_rate(_gyro({"scale_factor_ppm": sf, "misalignment_rad": d}), w, 3)
    cross = np.array([[0, -d[2], d[1]], [d[2], 0, -d[0]], [-d[1], d[0], 0]])
    expected = (np.eye(3) + np.diag(np.asarray(sf) * 1e-6) - cross) @ w
    np.testing.assert_allclose(y[1:], [expected] * 2, rtol=1e-9)
    m = [[0.0, 1e-3, 2e-3], [-1e-3, 0.0, 3e-3], [4e-3, 5e-3, 0.0]]
    y, _ = _constant_rate(_gyro({"misalignment_rad": m}), w, 3)
    np.testing.assert_allclose(y[1:], [(np.eye(3) + np.asarray(m)) @ w] * 2, rtol=1e-9)


def test_quantisation_and_saturation():
    cfg = {"arw_rad_sqrt_s": 1e-4, "rrw_rad_s_sqrt_s": 0.0}
    w = (0.01, -0.02, 0.05)
    raw, _ = _constant_rate(_gyro(cfg), w, 500)
    q = 1e-4
    y, _ = _constant_rate(_gyro({**cfg, "quantum_rad_s": q}), w, 500)
    np.testing.assert_allclose(y / q, np.round(y / q), atol=1e-6)
    assert np.all(np.abs(y - raw) <= q / 2 + 1e-15)
    # angle mode: every increment a whole number of quanta, the running sum within half a quantum
    qa = 1e-5
    a_raw, _ = _constant_rate(_gyro({**cfg, "mode": "angle"}), w, 500)
    a, _ = _constant_rate(_gyro({**cfg, "mode": "angle", "quantum_rad": qa}), w, 500)
    np.testing.assert_allclose(a / qa, np.round(a / qa), atol=1e-6)
    err = np.cumsum(a, axis=0) - np.cumsum(a_raw, axis=0)
    assert np.abs(err).max() <= qa / 2 + 1e-12
    assert np.abs(a - a_raw).max() > 0.2 * qa     # it did round
    # saturation: z beyond 0.03 rad/s clips, the others pass
    y, truth = _constant_rate(_gyro({"saturation_rad_s": 0.03}), w, 3)
    np.testing.assert_allclose(y[-1], [0.01, -0.02, 0.03], rtol=1e-9)
    assert truth[-1]["saturated"] == (False, False, True)
    y, _ = _constant_rate(_gyro({"saturation_rad_s": 0.03}), (-0.05, 0.0, 0.0), 2)
    assert y[-1][0] == -0.03


def test_it_is_seeded_and_leaves_the_other_streams_alone():
    g = {"arw_rad_sqrt_s": 1e-5, "rrw_rad_s_sqrt_s": 1e-7}
    ov = {"seed": 2, "plant.w0": [0.001, 0.0, 0.0], "sensors.rate_noise_rad_s": 1e-6}
    a = Plant(load("irassi_large", {**ov, "sensors.gyro": g}))
    b = Plant(load("irassi_large", {**ov, "sensors.gyro": g}))
    c = Plant(load("irassi_large", {**ov, "seed": 3, "sensors.gyro": g}))
    ref = Plant(load("irassi_large", ov))
    for _ in range(20):
        sa, sb, sc, sr = a.sense(), b.sense(), c.sense(), ref.sense()
        assert sa["gyro_w"] == sb["gyro_w"] and sa["gyro_w"] != sc["gyro_w"] and sa["w"] == sr["w"]
        assert "gyro_dtheta" not in sa
        for p in (a, b, c, ref):
            p.advance()
    # the stream: numpy's PCG64 seeded by SeedSequence(seed, spawn_key=(7,)), 6 normals per sample
    gen = np.random.Generator(np.random.PCG64(np.random.SeedSequence(entropy=2, spawn_key=(7,))))
    x = gen.standard_normal((4096, 6))[0]
    p = Plant(load("irassi_large", {**ov, "sensors.gyro": g}))
    sn = math.sqrt(1e-10 / H + 1e-14 * H / 12)
    bu = 1e-7 * math.sqrt(H)
    expected = np.asarray(p.truth()["w"]) + 0.5 * bu * x[3:] + sn * x[:3]
    np.testing.assert_allclose(p.sense()["gyro_w"], expected, rtol=1e-12)


def test_angle_mode_writes_gyro_dtheta_and_faults_reach_it():
    p = Plant(load("irassi_large", {**QUIET, "plant.w0": [0.001, 0.0, 0.0], "sensors.gyro": {"mode": "angle"},
                                    "sensors.faults": [{"channel": "gyro", "kind": "nan", "start_s": 0.2,
                                                        "end_s": 0.3}]}))
    for k in range(4):
        s = p.sense()
        assert "gyro_w" not in s
        if k == 2:
            assert all(math.isnan(v) for v in s["gyro_dtheta"])
        else:
            assert s["gyro_dtheta"][0] == pytest.approx(0.001 * H, rel=1e-9) and s["gyro_valid"]
        p.advance()


@pytest.mark.parametrize("g,message", [
    ({"arw_rad_sqrt_s": -1e-6}, "sensors.gyro.arw_rad_sqrt_s: must be >= 0, got -1e-06"),
    ({"rrw_rad_s_sqrt_s": -1.0}, "sensors.gyro.rrw_rad_s_sqrt_s: must be >= 0"),
    ({"mode": "integrating"}, "sensors.gyro.mode: unknown value 'integrating'"),
    ({"quantum_rad": 1e-6}, r'sensors.gyro.quantum_rad: does not apply to mode = "rate"'),
    ({"mode": "angle", "quantum_rad_s": 1e-6}, r'sensors.gyro.quantum_rad_s: does not apply to mode = "angle"'),
    ({"misalignment_rad": [[1e-3, 0, 0], [0, 0, 0], [0, 0, 0]]},
     "sensors.gyro.misalignment_rad: the diagonal of a 3x3 misalignment must be zero"),
    ({"misalignment_rad": [0.5, 0, 0]}, r"sensors.gyro.misalignment_rad: must be small angles"),
    ({"saturation_rad_s": -1.0}, "sensors.gyro.saturation_rad_s: must be >= 0"),
    ({"bias_rad_s": [1.0, 2.0]}, "sensors.gyro.bias_rad_s: expected 3 numbers, got 2"),
    ({"arw": 1.0}, "sensors.gyro.arw: unknown key"),
])
def test_bad_input_is_one_line_naming_file_and_key(g, message):
    with pytest.raises(ScenarioError, match=r"irassi_large.toml: " + message) as exc:
        load("irassi_large", {"sensors.gyro": g})
    assert "\n" not in str(exc.value)


def test_it_does_not_apply_to_an_orbit_scenario():
    with pytest.raises(ScenarioError, match=r"landsat8_q1.toml: sensors.gyro: does not apply to a orbit scenario"):
        load("landsat8_q1", {"sensors.gyro": {}})
