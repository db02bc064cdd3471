"""Sensors (SPEC 3.5): noise, bias, latency, faults; the pointing figures of the truth."""
import math

import numpy as np
import pytest

from aocs_core.conventions import ARCSEC_PER_RAD, quat_conj, quat_mul
from aocs_plant import Plant, load

# ----------------------------------------------------------------- sensors


def _noisy(seed=7, **extra):
    ov = {"seed": seed, "sensors.attitude_noise_rad": 1e-5, "sensors.rate_noise_rad_s": 2e-6}
    ov.update(extra)
    return Plant(load("irassi_large", ov))


def _samples(plant, n):
    out = []
    for _ in range(n):
        out.append(plant.sense())
        plant.advance()
    return out


def test_ideal_sensors_return_truth():
    plant = Plant(load("irassi_large"))
    s = plant.sense()
    assert s["q"] == plant.truth()["q"] and s["w"] == plant.truth()["w"]
    assert s["q_valid"] and s["w_valid"] and s["t"] == 0.0 and s["seq"] == 0


def test_an_ideal_sensor_reads_as_a_zero_error_would():
    """y = x + e with e = 0: a body rate of negative zeros is measured as +0.0 on every axis (-0.0 + 0.0), the
    bits the general path gives, whichever path the ideal sensor takes."""
    plant = Plant(load("irassi_large", {"plant.w0": [-0.0, -0.0, -0.0]}))
    assert [math.copysign(1.0, x) for x in plant.truth()["w"]] == [-1.0, -1.0, -1.0]
    assert [math.copysign(1.0, x) for x in plant.sense()["w"]] == [1.0, 1.0, 1.0]


def test_noise_is_repeatable_for_a_seed_and_differs_between_seeds():
    a = _samples(_noisy(7), 50)
    b = _samples(_noisy(7), 50)
    c = _samples(_noisy(8), 50)
    assert [s["q"] for s in a] == [s["q"] for s in b]
    assert [s["w"] for s in a] == [s["w"] for s in b]
    assert [s["w"] for s in a] != [s["w"] for s in c]


def test_noise_statistics_and_bias():
    n = 5000
    plant = _noisy(3, **{"sensors.rate_bias_rad_s": [1e-6, -2e-6, 0.0]})
    rate_err, att_err = [], []
    for _ in range(n):
        s = plant.sense()
        tr = plant.truth()
        rate_err.append(np.subtract(s["w"], tr["w"]))
        e = quat_mul(s["q"], quat_conj(tr["q"]))  # the small measurement rotation dq
        att_err.append(2.0 * np.array(e[:3]) * (1 if e[3] >= 0 else -1))
        plant.advance()
    rate_err, att_err = np.array(rate_err), np.array(att_err)
    # sample std of N = 5000 normal draws has a relative spread 1/sqrt(2N) = 1%: 5% is 5 sigma
    np.testing.assert_allclose(rate_err.std(axis=0), 2e-6, rtol=0.05)
    np.testing.assert_allclose(att_err.std(axis=0), 1e-5, rtol=0.05)
    # mean: bias within 5 standard errors (2e-6 / sqrt(5000) = 2.8e-8)
    np.testing.assert_allclose(rate_err.mean(axis=0), (1e-6, -2e-6, 0.0), atol=1.5e-7)
    np.testing.assert_allclose(att_err.mean(axis=0), 0.0, atol=5 * 1e-5 / math.sqrt(n))
    # the channels are independent
    assert abs(np.corrcoef(rate_err[:, 0], att_err[:, 0])[0, 1]) < 0.06


def test_latency_delays_the_measurement_by_whole_periods():
    plant = Plant(load("irassi_large", {"sensors.latency_periods": 3}))
    truths, samples = [], []
    plant.apply({"u_body": (1.0, 2.0, 3.0)})  # something that moves
    for _ in range(10):
        truths.append(plant.truth()["w"])
        samples.append(plant.sense()["w"])
        plant.advance()
    for k in range(10):
        assert samples[k] == truths[max(0, k - 3)]


def test_faults_dropout_nan_nonunit():
    ov = {"sensors.faults": [
        {"channel": "rate", "kind": "dropout", "start_s": 1.0, "end_s": 1.5},
        {"channel": "attitude", "kind": "nan", "start_s": 2.0, "end_s": 2.2},
        {"channel": "attitude", "kind": "nonunit", "start_s": 3.0, "end_s": 3.1, "factor": 1.2},
    ]}
    plant = Plant(load("irassi_large", ov))
    plant.apply({"u_body": (1.0, 1.0, 1.0)})
    by_t = {}
    for _ in range(40):
        by_t[round(plant.t, 6)] = (plant.sense(), plant.truth())
        plant.advance()
    s, _ = by_t[1.2]
    assert not s["w_valid"] and s["q_valid"]
    assert s["w"] == by_t[0.9][1]["w"]  # repeats the last good value
    s, _ = by_t[1.5]
    assert s["w_valid"]
    s, _ = by_t[2.1]
    assert s["q_valid"] and all(math.isnan(x) for x in s["q"]) and not any(map(math.isnan, s["w"]))
    s, tr = by_t[3.0]
    assert math.sqrt(sum(x * x for x in s["q"])) == pytest.approx(1.2, rel=1e-12)
    assert plant.counters["invalid_samples"] == 5
    # one sample per step sensed (40), one command applied, none refused
    assert (plant.counters["samples"], plant.counters["commands"], plant.counters["bad_commands"]) == (40, 1, 0)


def test_a_fault_does_not_shift_the_noise_sequence():
    clean = _samples(_noisy(11), 30)
    faulty = _samples(_noisy(11, **{"sensors.faults": [
        {"channel": "rate", "kind": "dropout", "start_s": 1.0, "end_s": 1.5}]}), 30)
    assert clean[25]["w"] == faulty[25]["w"]


def test_pointing_figures():
    a = 10.0 / ARCSEC_PER_RAD  # 10 arcsec about y
    q = (0.0, math.sin(a / 2), 0.0, math.cos(a / 2))
    from aocs_plant import pointing_error_arcsec, qe_arcsec
    assert pointing_error_arcsec(q, (0, 0, 0, 1.0)) == pytest.approx(10.0, rel=1e-9)
    np.testing.assert_allclose(qe_arcsec(q, (0, 0, 0, 1.0)), (0.0, 5.0, 0.0), rtol=1e-9, atol=1e-12)
