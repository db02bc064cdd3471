"""The magnetometer (sensors/magnetometer.py, docs/spec.md 5.8.4): b_B = A(q) B_N(t) + bias + noise against
A(q) written out here, B_N from the environment's IGRF along the orbit, and the noise from numpy's
generator seeded as the stream of index 8 (written here without rng.py)."""
import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load

ENV = {"epoch_utc": "2026-06-21T06:00:00Z", "magnetic_field": {"model": "igrf"},
       "orbit": {"radius_m": 6878137.0, "inclination_deg": 97.4, "raan_deg": 170.0}}


def _A(q):
    v, q4 = np.array(q[:3]), q[3]
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return (q4 * q4 - v @ v) * np.eye(3) + 2 * np.outer(v, v) - 2 * q4 * vx


def _plant(mag, env=ENV, seed=5, **extra):
    ov = {"environment": env, "sensors": {"magnetometer": mag}, "seed": seed, "plant.w0": [0.001, 0.002, -0.003]}
    ov.update(extra)
    return Plant(load("irassi_large", ov))


def _true(p):
    env = p.environment
    return _A(p.body.q) @ np.array(env.magnetic_field(p.t, env.orbit_state(p.t)[0]))


def test_sample_against_a_hand_evaluation_with_bias_and_seeded_noise():
    bias, sigma, seed = [2e-7, -1e-7, 5e-8], 1e-7, 5
    p = _plant({"noise_t": sigma, "bias_t": bias}, seed=seed)
    ss = np.random.SeedSequence(entropy=seed, spawn_key=(8,))
    noise = np.random.Generator(np.random.PCG64(ss)).standard_normal((4096, 3)) * sigma
    for k in range(40):
        s = p.sense()
        want = _true(p) + np.array(bias) + noise[k]
        np.testing.assert_allclose(s["mag_b_t"], want, rtol=0, atol=1e-19)
        assert s["mag_valid"]
        tr = p.truth()["sensors"]
        np.testing.assert_allclose(tr["magnetometer.field_b_t"], _true(p), rtol=0, atol=1e-19)
        np.testing.assert_allclose(tr["magnetometer.error"], np.array(bias) + noise[k], rtol=0, atol=1e-21)
        p.apply({"u_body": (0.0, 0.0, 0.0)})
        p.advance()
    assert 1.5e-5 < np.linalg.norm(s["mag_b_t"]) < 6.5e-5


def test_noise_free_it_reads_the_field_and_other_streams_do_not_move():
    p = _plant({})
    np.testing.assert_allclose(p.sense()["mag_b_t"], _true(p), rtol=0, atol=1e-20)
    # adding the magnetometer leaves the attitude sensor's noise as it was
    a = Plant(load("irassi_large", {"sensors": {"attitude_noise_rad": 1e-5}, "seed": 5, "environment": ENV,
                                    "plant.w0": [0.001, 0.002, -0.003]}))
    b = _plant({"noise_t": 1e-7}, sensors={"attitude_noise_rad": 1e-5, "magnetometer": {"noise_t": 1e-7}})
    for _ in range(5):
        assert a.sense()["q"] == b.sense()["q"]
        a.advance()
        b.advance()


def test_without_a_field_it_reads_its_bias():
    p = _plant({"bias_t": [1e-6, 0.0, 0.0]}, env=None)
    assert p.sense()["mag_b_t"] == (1e-6, 0.0, 0.0)


def test_a_dropout_reaches_it():
    p = _plant({"noise_t": 0.0}, sensors={"magnetometer": {}, "faults": [
        {"channel": "magnetometer", "kind": "dropout", "start_s": 0.0, "end_s": 1.0}]})
    assert not p.sense()["mag_valid"]


def test_keys_refused_where_they_do_not_apply():
    with pytest.raises(ScenarioError, match=r"sensors.magnetometer: does not apply to a orbit scenario"):
        load("landsat8_q1", {"sensors": {"magnetometer": {"noise_t": 1e-7}}})
    with pytest.raises(ScenarioError, match=r"sensors.magnetometer.noise: unknown key"):
        load("irassi_large", {"sensors": {"magnetometer": {"noise": 1e-7}}})
    with pytest.raises(ScenarioError, match=r"sensors.magnetometer.noise_t: must be >= 0"):
        load("irassi_large", {"sensors": {"magnetometer": {"noise_t": -1.0}}})
