"""Wire contract v3 end to end (issue 20): the star tracker and the gyro on the wire, the estimate back.

tests/python/aocs_plant/data/sensors_st_gyro.toml (irassi_large with the [sensors.star_tracker] and
[sensors.gyro] examples of docs/scenarios.md: the tracker at 5 Hz with 0.1 s latency, a gyro with bias, noise,
scale factor, misalignment and quantisation), 30 s, with a tracker outage from 10 to 12 s and a gyro dropout
from 20 to 21 s, flown

- in lockstep through `aocs run` (plant_node + fsw_node over LCM): its log's sensors_t carry the tracker's
  samples, flagged only on the periods with a new valid one, with their time of measurement, and the gyro's
  rate; fsw_node's own lockstep path (the host tool aocs_node_input, node_wire.c on the logged messages) gives
  the executive the same values bit for bit, the flags as ST / GYRO and the measurement time converted as the
  sensor time is; actuator_cmd_t carries the passthrough's estimate; truth_t the gyro's true bias;
- directly on the Cortex-M7 image (aocs_pil.harness.run_direct: the loop's PIL adapter, STEP frames to QEMU):
  the same commands and estimates bit for bit, and its STEP payloads read by the image's decoder (pil_frame.c,
  through aocs_registry_dump --pil-payload) are the inputs fsw_node made.
"""
from __future__ import annotations

import json
import math
import os
import subprocess

import numpy as np
import pytest

from aocs_core.conventions import ARCSEC_PER_RAD, quat_mul
from aocs_loop.frames import seconds_to_ns, valid_bits
from aocs_pil import adapter, harness
from aocs_runner.run import RunOptions, execute
from aocs_runner.scenario_opts import toml_value
from aocs_wire import lcmlog
from pil_support import REPO, image

SCENARIO = str(REPO / "tests/python/aocs_plant/data/sensors_st_gyro.toml")
DURATION_S = 30.0
OVERRIDES = {"metrics.window_s": DURATION_S, "sensors.star_tracker.outages": [[10.0, 12.0]],
             "sensors.faults": [{"channel": "gyro", "kind": "dropout", "start_s": 20.0, "end_s": 21.0}]}
LATENCY_S = 0.1           # the scenario's [sensors.star_tracker] latency_s and rate_hz
RATE_HZ = 5.0
EXEC_ST, EXEC_GYRO = adapter.EXEC_VALID_ST, adapter.EXEC_VALID_GYRO


def _bits(a) -> np.ndarray:
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


@pytest.fixture(scope="module")
def lcm_run(private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    out = tmp_path_factory.mktemp("st_gyro")
    execute(RunOptions(scenario=SCENARIO, out=str(out), duration=DURATION_S, plots=False, quiet=True,
                       sets=[f"{k}={toml_value(v)}" for k, v in OVERRIDES.items()]))
    return out / "run.lcmlog", lcmlog.read(out / "run.lcmlog")


@pytest.fixture(scope="module")
def node_inputs(lcm_run, aocs_build_dir) -> list[dict]:
    """fsw_node's executive input of every logged sensors_t (aocs_node_input), in the log's order."""
    exe = aocs_build_dir / "bin" / "aocs_node_input"
    assert exe.is_file() and os.access(exe, os.X_OK), f"{exe} missing: build the host preset"
    res = subprocess.run([str(exe), str(lcm_run[0])], capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    return [json.loads(line) for line in res.stdout.splitlines()]


def test_the_tracker_flag_marks_each_new_sample_once_with_its_time(lcm_run, aocs_lcm):
    s = lcm_run[1].sensors
    b = valid_bits()
    n = round(DURATION_S * 10)
    assert np.array_equal(s["tick"], np.arange(n))
    t = s["t_s"]
    flagged = (s["valid"] & b.star_tracker) != 0
    # 5 Hz at 10 Hz: every second period; not at t = 0 (its measurement would precede the run), none in the
    # outage [10, 12) s
    due = (np.arange(n) % 2 == 0) & (np.arange(n) > 0) & ~((t >= 10.0 - 1e-9) & (t < 12.0 - 1e-9))
    assert np.array_equal(flagged, due)
    assert flagged.sum() == DURATION_S * RATE_HZ - 1 - 2 * RATE_HZ
    np.testing.assert_allclose(s["st_t_meas_s"][flagged], t[flagged] - LATENCY_S, atol=1e-12)
    # between samples the message holds the last one and its time, flag off
    last = None
    for k in range(n):
        if flagged[k]:
            last = k
        elif last is not None and t[k] < 10.0:
            assert s["st_t_meas_s"][k] == s["st_t_meas_s"][last] and np.array_equal(s["st_q"][k], s["st_q"][last])
    assert np.array_equal(s["st_q"][0], [0.0, 0.0, 0.0, 1.0]) and s["st_t_meas_s"][0] == 0.0


def test_the_tracker_measures_the_attitude_at_its_time_of_measurement(lcm_run):
    """q_SN = q_SB (x) q_BN(t_meas), mounting identity: within its bias (2, -1, 5 arcsec), noise and
    low-frequency error of the true attitude one period (its latency) before the message."""
    log = lcm_run[1]
    s, tr = log.sensors, log.truth
    flagged = np.flatnonzero((s["valid"] & valid_bits().star_tracker) != 0)
    q_true = {int(k): q for k, q in zip(tr["tick"], tr["q"])}
    angles = []
    for k in flagged:
        qm, qt = s["st_q"][k], q_true[int(s["tick"][k]) - 1]
        assert abs(np.linalg.norm(qm) - 1.0) < 1e-12
        e = quat_mul(tuple(qm), (-qt[0], -qt[1], -qt[2], qt[3]))
        angles.append(2.0 * math.asin(min(1.0, math.sqrt(e[0] ** 2 + e[1] ** 2 + e[2] ** 2))) * ARCSEC_PER_RAD)
    assert 2.0 < np.median(angles) and max(angles) < 40.0     # the 5.5 arcsec bias plus noise, not 0, not off


def test_the_gyro_rate_is_the_mean_true_rate_plus_its_errors(lcm_run):
    log = lcm_run[1]
    s, tr = log.sensors, log.truth
    g = (s["valid"] & valid_bits().gyro) != 0
    t = s["t_s"]
    assert np.array_equal(~g, (t >= 20.0 - 1e-9) & (t < 21.0 - 1e-9))     # the dropout only
    w = tr["w"]
    mean = 0.5 * (w[:-2] + w[1:-1])                                        # over [t_(k-1), t_k], k >= 1
    err = np.abs(s["gyro_w"][1:] - mean)[g[1:]]
    assert np.abs(w).max() > 1e-2 and err.max() < 5e-5                    # a slew, measured to 5e-5 rad/s
    # the truth's bias is the gyro's: its initial value moved by the rate random walk (1e-11 rad/s^1.5)
    bias = tr["gyro_bias"]
    np.testing.assert_allclose(bias, np.broadcast_to([4.8e-7, -4.8e-7, 2.4e-7], bias.shape), atol=1e-9)
    assert np.ptp(bias, axis=0).max() > 0.0


def test_fsw_node_decodes_the_sensor_fields_bit_for_bit(lcm_run, node_inputs, aocs_lcm):
    s = lcm_run[1].sensors
    st = aocs_lcm.sensors_t
    assert len(node_inputs) == len(s["tick"]) and all(x["decode"] == "ok" and x["accepted"] for x in node_inputs)
    for k, x in enumerate(node_inputs):
        v = int(s["valid"][k])
        assert x["tick"] == int(s["tick"][k]) and x["t_sensor_ns"] == seconds_to_ns(float(s["t_s"][k]))
        assert bool(x["valid"] & EXEC_ST) == bool(v & st.VALID_STAR_TRACKER), k
        assert bool(x["valid"] & EXEC_GYRO) == bool(v & st.VALID_GYRO), k
        assert np.array_equal(_bits(x["st_q"]), _bits(s["st_q"][k])), k
        assert np.array_equal(_bits(x["gyro_w"]), _bits(s["gyro_w"][k])), k
        assert x["st_t_meas_ns"] == seconds_to_ns(float(s["st_t_meas_s"][k])), k
    # the times the flight software gets: the latency exactly, in ns
    got = [(x["t_sensor_ns"] - x["st_t_meas_ns"]) for x in node_inputs if x["valid"] & EXEC_ST]
    assert got and set(got) == {100_000_000}


def test_the_estimate_is_on_the_wire(lcm_run):
    """The passthrough: estimator 0, the sample's attitude and rate as the estimate (bit for bit), no filter
    telemetry (bias, covariance and counts zero)."""
    log = lcm_run[1]
    c, s = log.cmd, log.sensors
    assert np.array_equal(c["tick"], s["tick"]) and np.all(c["estimator"] == 0) and np.all(c["est_status"] == 0)
    assert np.array_equal(_bits(c["q_est"]), _bits(s["q"])) and np.array_equal(_bits(c["w_est"]), _bits(s["w"]))
    assert not c["bias_est"].any() and not c["est_p"].any()
    for name in ("n_st_used", "n_st_gated", "n_st_hostile", "n_est_restarts"):
        assert not c[name].any(), name


@pytest.fixture(scope="module")
def direct(lcm_run, aocs_build_dir):
    os.environ["AOCS_BUILD_DIR"] = str(aocs_build_dir)
    image("pil-m7")
    return harness.run_direct(SCENARIO, None, "pil-m7", duration_s=DURATION_S, overrides=OVERRIDES)


def test_the_pil_direct_path_flies_the_same_commands_and_estimates(lcm_run, direct):
    c = lcm_run[1].cmd
    assert np.array_equal(_bits(direct.u_sat), _bits(c["u_sat"]))
    est = direct.estimates
    assert np.array_equal(_bits([e.q for e in est]), _bits(c["q_est"]))
    assert np.array_equal(_bits([e.w for e in est]), _bits(c["w_est"]))
    assert [e.estimator for e in est] == c["estimator"].tolist()
    assert [e.status for e in est] == c["est_status"].tolist()
    assert [e.st_status for e in est] == c["st_status"].tolist()


def test_the_image_reads_the_step_frames_as_fsw_node_reads_the_messages(direct, node_inputs, aocs_build_dir,
                                                                        tmp_path):
    """The STEP payload the direct path sent for a tick, decoded by pil_frame.c (the image's decoder), is the
    executive input fsw_node made of the logged sensors_t of that tick: a new tracker sample, a period between
    samples, the outage, the gyro dropout."""
    exe = aocs_build_dir / "bin" / "aocs_registry_dump"
    for tick in (2, 3, 105, 204, 250):
        payload = adapter.step_payload(direct.sensors[tick])
        path = tmp_path / f"step{tick}.bin"
        path.write_bytes(payload)
        res = subprocess.run([str(exe), "--pil-payload", "STEP", str(path)], capture_output=True, text=True,
                             timeout=20)
        out = json.loads(res.stdout)
        assert out["pil_err"] == "AOCS_PIL_OK", out
        f, x = out["fields"], node_inputs[tick]
        assert f["tick"] == [x["tick"]] and f["t_sensor_ns"] == [x["t_sensor_ns"]] and f["valid"] == [x["valid"]]
        assert f["st_t_meas_ns"] == [x["st_t_meas_ns"]], tick
        for row, key in (("q", "q"), ("w", "w"), ("st_q", "st_q"), ("gyro_w", "gyro_w")):
            assert np.array_equal(_bits(f[row]), _bits(x[key])), (tick, row)
        assert np.array_equal(_bits(f["wheel_speed"]), _bits(x["wheel_speed"])), tick     # NaN: no wheels
