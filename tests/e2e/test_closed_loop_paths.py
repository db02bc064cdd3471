"""One scenario through every closed-loop path, the command histories compared bit for bit (issue 19, item 5).

irassi_rw (four reaction wheels, tachometers) with the on-board slew guidance, 30 s (300 periods, the slew
under way: wheel torques up to ~0.2 N m), its own law and seed, with a star tracker (2 Hz, 0.3 s latency) and
a gyro on the wire too (protocol version 3), flown through:

- lcm:        `aocs run` in lockstep: plant_node (the recording plant) + fsw_node over LCM;
- lcm-harness: the PIL harness's run against fsw_node: aocs_loop.core with the LCM adapter;
- pil-bridge: the same against the PIL bridge with the Cortex-M7 image (double, bit-identical to the host);
- pil-direct: the harness's direct run on the M7: aocs_loop.core with the PIL adapter, frames to QEMU.

Every path must give the same body torque and wheel torques at every tick, bit for bit, the same estimate
(the attitude-determination stage's telemetry), and the same sensor frames (the packed sensors_t of the
harness paths byte for byte the ones plant_node recorded: the tracker's samples and the gyro's rates
included). A path that
dropped the wheel torques or packed a sensor differently changes the trajectory, hence the commands: the
last tests fly the direct path with such a fault injected between the plant and the image and check that
the comparison catches it.
"""
from __future__ import annotations

import os

import numpy as np
import pytest

from aocs_loop.frames import Reply, SensorFrame, valid_bits
from aocs_loop.lcm_adapter import LcmCodec
from aocs_pil import harness
from aocs_runner.run import RunOptions, execute
from aocs_runner.scenario_opts import toml_value
from aocs_wire import lcmlog, wire
from pil_support import image

SCENARIO = "irassi_rw"
DURATION_S = 30.0
OVERRIDES = {"guidance.mode": "slew", "metrics.window_s": DURATION_S,
             "sensors.star_tracker.rate_hz": 2.0, "sensors.star_tracker.latency_s": 0.3,
             "sensors.star_tracker.noise_cross_arcsec": 1.0, "sensors.star_tracker.noise_about_arcsec": 8.0,
             "sensors.gyro.arw_rad_sqrt_s": 5.8e-7, "sensors.gyro.bias_rad_s": [4.8e-7, -4.8e-7, 2.4e-7]}
#: the estimate's fields compared across the paths (aocs_loop.frames.Estimate; actuator_cmd_t's names)
ESTIMATE = (("estimator", "estimator"), ("status", "est_status"), ("q", "q_est"), ("w", "w_est"),
            ("bias", "bias_est"), ("p_upper", "est_p"), ("st_status", "st_status"), ("n_st_used", "n_st_used"),
            ("n_st_gated", "n_st_gated"), ("n_st_hostile", "n_st_hostile"), ("n_restarts", "n_est_restarts"))


def _bits(a) -> np.ndarray:
    """float64 values as their bit patterns (NaN-safe, -0.0 distinct from 0.0)."""
    return np.ascontiguousarray(np.asarray(a, dtype=np.float64)).view(np.uint64)


def _history(u_sat, u_wheels) -> dict:
    return {"u": _bits(u_sat), "u_wheels": _bits(u_wheels)}


def _estimates_of_log(cmd) -> dict:
    """The estimate columns of a log's actuator_cmd_t, as exact bits (integers as float64 bits too)."""
    return {wire_name: _bits(cmd[wire_name]) for _, wire_name in ESTIMATE}


def _estimates_of_run(estimates) -> dict:
    return {wire_name: _bits([getattr(e, name) for e in estimates]) for name, wire_name in ESTIMATE}


def differences(ref: dict, other: dict) -> list[str]:
    """What differs between two command histories ({"u": (N, 3), "u_wheels": (N, n)}), bit for bit."""
    out = []
    for key in ("u", "u_wheels"):
        a, b = ref[key], other[key]
        if a.shape != b.shape:
            out.append(f"{key}: shape {b.shape}, reference {a.shape}")
            continue
        rows = np.nonzero(np.any(a != b, axis=1))[0]
        if rows.size:
            out.append(f"{key}: {rows.size} ticks differ, first at tick {rows[0]}: "
                       f"{b[rows[0]].view(np.float64)} against {a[rows[0]].view(np.float64)}")
    return out


@pytest.fixture(scope="module")
def env(aocs_build_dir):
    os.environ["AOCS_BUILD_DIR"] = str(aocs_build_dir)
    image("pil-m7")
    return aocs_build_dir


@pytest.fixture(scope="module")
def lcm_run(env, private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    """The LCM lockstep run (plant_node + fsw_node): its log."""
    out = tmp_path_factory.mktemp("lcm")
    sets = [f"{k}={toml_value(v)}" for k, v in OVERRIDES.items() if k != "guidance.mode"]
    execute(RunOptions(scenario=SCENARIO, out=str(out), duration=DURATION_S, guidance="slew", sets=sets,
                       plots=False, quiet=True))
    return lcmlog.read(out / "run.lcmlog", keep_raw=True)


@pytest.fixture(scope="module")
def paths_flown(env, private_netns, aocs_lcm, lcm_run):
    """Every path's command history, and its sensor frames."""
    n = int(lcm_run.cmd["n_wheels"][0])
    runs = {
        "lcm-harness": harness.run(SCENARIO, None, "host", duration_s=DURATION_S, overrides=OVERRIDES),
        "pil-bridge": harness.run(SCENARIO, None, "pil-m7", duration_s=DURATION_S, overrides=OVERRIDES),
        "pil-direct": harness.run_direct(SCENARIO, None, "pil-m7", duration_s=DURATION_S, overrides=OVERRIDES),
    }
    hist = {"lcm": _history(lcm_run.cmd["u_sat"], lcm_run.cmd["u_wheels"][:, :n])}
    for name, r in runs.items():
        hist[name] = _history(r.u_sat, r.u_wheels)
    return hist, runs


def test_the_scenario_exercises_the_wheels(lcm_run):
    c = lcm_run.cmd
    n = int(c["n_wheels"][0])
    assert n == 4 and np.all(c["n_wheels"] == n) and len(c["tick"]) == round(DURATION_S / 0.1)
    assert np.abs(c["u_wheels"][:, :n]).max() > 0.1            # the wheels torque the slew
    s = lcm_run.sensors
    assert np.all(s["n_wheels"] == n) and np.all(s["valid"] & valid_bits().wheels)
    assert np.ptp(s["wheel_speed"][:, :n], axis=0).min() > 0.0     # the tachometers see the speeds change


def test_the_scenario_has_the_star_tracker_and_the_gyro_on_the_wire(lcm_run):
    """2 Hz at 10 Hz, 0.3 s latency: a new sample every fifth period from t = 0.5 s (the first whose time of
    measurement is in the run), flagged there only; the gyro every period."""
    s = lcm_run.sensors
    b = valid_bits()
    ticks = np.flatnonzero(s["valid"] & b.star_tracker)
    assert ticks.tolist() == list(range(5, round(DURATION_S / 0.1), 5))
    np.testing.assert_allclose(s["st_t_meas_s"][ticks], s["t_s"][ticks] - 0.3, atol=1e-12)
    assert np.all(s["valid"] & b.gyro) and np.abs(s["gyro_w"]).max() > 1e-3


@pytest.mark.parametrize("path", ["lcm-harness", "pil-bridge", "pil-direct"])
def test_every_path_sends_back_the_estimate_of_the_lcm_lockstep_run_bit_for_bit(paths_flown, lcm_run, path):
    _, runs = paths_flown
    ref, got = _estimates_of_log(lcm_run.cmd), _estimates_of_run(runs[path].estimates)
    assert ref["q_est"].shape == (round(DURATION_S / 0.1), 4)
    for key in ref:
        assert np.array_equal(ref[key], got[key]), (path, key)


@pytest.mark.parametrize("path", ["lcm-harness", "pil-bridge", "pil-direct"])
def test_every_path_commands_the_lcm_lockstep_run_bit_for_bit(paths_flown, path):
    hist, _ = paths_flown
    assert differences(hist["lcm"], hist[path]) == [], path


def test_the_harness_paths_pack_the_sensors_plant_node_recorded(paths_flown, lcm_run, aocs_lcm):
    """The frames of every in-process path, packed as sensors_t, are the bytes plant_node published."""
    _, runs = paths_flown
    recorded = [data for ch, data, _ in lcm_run.events if ch == wire.SENSORS]
    codec = LcmCodec(wire.Codecs(aocs_lcm), aocs_lcm)
    for name, r in runs.items():
        packed = [codec.pack_sensors(f) for f in r.sensors]
        assert len(packed) == len(recorded), name
        first = next((k for k, (a, b) in enumerate(zip(packed, recorded)) if a != b), None)
        assert first is None, f"{name}: the sensors_t of tick {first} differs from plant_node's"


# ---- the comparison catches a path that drops the wheel torques or packs a sensor differently ---------------
class _Tamper:
    """An adapter between the plant and the image that changes what crosses (a faulty transport)."""

    def __init__(self, fc, frame=None, reply=None):
        self.fc, self.frame, self.reply = fc, frame, reply

    def step(self, f: SensorFrame) -> Reply:
        r = self.fc.step(self.frame(f) if self.frame else f)
        return self.reply(r) if self.reply else r


def _drop_wheels(r: Reply) -> Reply:
    r.command.u_wheels = (0.0,) * len(r.command.u_wheels)
    return r


def _tachometers_in_single_precision(f: SensorFrame) -> SensorFrame:
    f.wheel_speed = tuple(float(np.float32(x)) for x in f.wheel_speed)
    return f


@pytest.mark.parametrize("fault, frame, reply", [("wheel torques dropped", None, _drop_wheels),
                                                 ("tachometers packed as float", _tachometers_in_single_precision,
                                                  None)])
def test_a_faulty_path_fails_the_comparison(paths_flown, fault, frame, reply):
    """Not only the tampered field: the flight computer's body torques move too (the plant flew another
    trajectory), so the comparison of the commands alone catches either fault."""
    hist, _ = paths_flown
    r = harness.run_direct(SCENARIO, None, "pil-m7", duration_s=DURATION_S, overrides=OVERRIDES,
                           wrap=lambda fc: _Tamper(fc, frame, reply))
    found = differences(hist["lcm"], _history(r.u_sat, r.u_wheels))
    assert any(d.startswith("u:") for d in found), (fault, found)
