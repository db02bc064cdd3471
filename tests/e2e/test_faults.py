"""Faults the SIL loop must survive: sensor NaN, non-unit quaternion, dropouts,
stale time stamps, lost / duplicated / foreign / malformed frames, commands
selecting an unknown law or an invalid target, and (real time) the plant killed
mid-run and restarted.

Each: no crash, the command never beyond the actuator limit (checked from the
log), the event counted, visible in the log and in the metrics JSON. Expected
counts are worked out here from the injected faults.
"""
from __future__ import annotations

import json
import math
import signal
import sys
import time
from pathlib import Path

import numpy as np
import pytest

from aocs import cmd_replay
from aocs_analysis import run_metrics as results
from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import load
from aocs_runner import orchestrate
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog
from aocs_wire.recorder import Recorder

LIMIT = 0.5
MODE_NOMINAL, MODE_SAFE = 1, 2

SENSOR_FAULTS = ('sensors.faults=['
                 '{channel="rate", kind="nan", start_s=20.0, end_s=21.0}, '
                 '{channel="attitude", kind="nonunit", factor=1.5, start_s=30.0, end_s=30.5}, '
                 '{channel="all", kind="dropout", start_s=40.0, end_s=41.0}]')
EVENTS = ["50:malformed", "51:foreign", "52:drop", "53:duplicate", "54:stale",
          "60:law=bogus", "61:target=0,0,0,2", "62:law=smc", "63:mode=safe"]


@pytest.fixture(scope="module")
def fault_run(private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    out = tmp_path_factory.mktemp("faults")
    res = execute(RunOptions(scenario="irassi_small", duration=120.0, limit=LIMIT, sets=[SENSOR_FAULTS],
                             events=EVENTS, out=str(out), quiet=True, plots=False))
    return res, lcmlog.read(out / "run.lcmlog")


def _by_tick(log):
    return {int(t): i for i, t in enumerate(log.cmd["tick"])}


def test_every_fault_is_counted_in_the_metrics(fault_run):
    res, _ = fault_run
    c = res.metrics["counters"]
    # sensor faults at 10 Hz: NaN 10 samples, non-unit 5, dropout 10 (all rejected as invalid)
    assert c["invalid"] == 10 + 5 + 10
    assert (c["malformed"], c["foreign"], c["lost"], c["duplicate"], c["stale"]) == (1, 1, 1, 1, 1)
    # the dropped tick, and the stale one: a stale sample does not move the executive's tick
    # reference, so the next tick is seen as a gap of one (executive.c sample_timing_check)
    assert c["missing"] == 2
    assert (c["cmd_rejected"], c["cmd_accepted"]) == (3, 1)   # bogus law, bad target, SAFE; smc accepted
    assert c["status"] == {"AOCS_ERR_INPUT_NOT_FINITE": 10, "AOCS_ERR_QUAT_NOT_UNIT": 5,
                           "AOCS_ERR_INPUT_INVALID": 10, "AOCS_ERR_INPUT_STALE": 1}
    assert c["safe_entries"] == 4 and c["time_in_safe_mode_s"] > 4 * 1.0
    assert [x["status"] for x in res.metrics["commands"]] == [
        "AOCS_ERR_UNKNOWN_LAW", "AOCS_ERR_TARGET_INVALID", "AOCS_OK", "AOCS_ERR_MODE_INVALID"]
    assert res.metrics["limits"]["commands_over_limit"] == 0 and res.metrics["limits"]["axis"] == LIMIT
    assert res.metrics["final_mode"] == "nominal"
    saved = json.loads((res.out_dir / "metrics.json").read_text())
    assert saved["counters"] == c


def test_faults_are_visible_in_the_log_and_the_torque_stays_within_the_limit(fault_run, status_codes):
    _, log = fault_run
    u = log.cmd["u_sat"]
    assert np.all(np.isfinite(u)) and np.abs(u).max() <= LIMIT * (1 + 1e-12)
    assert np.abs(log.truth["torque_applied"]).max() <= LIMIT * (1 + 1e-12)
    assert np.abs(u).max() == pytest.approx(LIMIT)               # the limit is reached
    i = _by_tick(log)
    st, mode = log.cmd["status"], log.cmd["mode"]
    assert st[i[200]] == status_codes["AOCS_ERR_INPUT_NOT_FINITE"] and mode[i[200]] == MODE_SAFE
    assert st[i[300]] == status_codes["AOCS_ERR_QUAT_NOT_UNIT"] and mode[i[300]] == MODE_SAFE
    assert st[i[400]] == status_codes["AOCS_ERR_INPUT_INVALID"] and mode[i[400]] == MODE_SAFE
    assert st[i[540]] == status_codes["AOCS_ERR_INPUT_STALE"] and mode[i[540]] == MODE_SAFE
    for t in (260, 360, 460, 600, 1199):                      # recovered after 10 good samples
        assert mode[i[t]] == MODE_NOMINAL, t
    # safe mode on a NaN rate: the executive cannot damp a NaN rate, the command is zero or
    # the damping term; never NaN, never beyond the limit (checked above)
    assert 520 not in i                                       # dropped tick: no command
    assert log.counts["AOCS_SENSORS.undecodable"] == 1        # the malformed payload
    assert np.count_nonzero(log.sensors["protocol_version"] == 99) == 1
    assert np.count_nonzero(log.sensors["tick"] == 530) == 2  # duplicate frame on the wire
    stale = log.sensors["t_s"][log.sensors["tick"] == 540]
    assert stale.tolist() == [pytest.approx(53.9)]            # the previous tick's time stamp
    assert np.all(log.cmd["law_id"][log.cmd["tick"] >= 620] == 5)   # smc after the accepted command
    assert np.all(log.cmd["law_id"][log.cmd["tick"] < 620] == 2)
    # the nan samples reached the flight software as NaN with the valid flag set
    s = log.sensors
    k = np.flatnonzero(s["tick"] == 205)[0]
    assert np.all(np.isnan(s["w"][k])) and s["valid"][k] == 3
    k = np.flatnonzero(s["tick"] == 302)[0]
    assert np.linalg.norm(s["q"][k]) == pytest.approx(1.5)


def test_the_fault_run_replays_bit_for_bit(fault_run):
    _, log = fault_run
    assert cmd_replay.replay(Path(log.path), quiet=True) == 0


def test_realtime_plant_killed_then_restarted(private_netns, fsw_node_bin, aocs_lcm, tmp_path, status_codes):
    """fsw_node keeps stepping without a plant (SAFE after 3 missing periods, torque within
    the limit) and returns to NOMINAL once a new plant publishes again."""
    sc = load("irassi_small", {"actuator.axis_limit": LIMIT, "duration_s": 30.0, "metrics.window_s": 30.0})
    cfg = fsw_config.node_config(sc, "quat_pd", mode="realtime", limit=LIMIT, run_timeout_s=30.0)
    cfg_path = fsw_config.write(tmp_path / "fsw_node.cfg", cfg)
    log_path = tmp_path / "run.lcmlog"
    env = paths.python_env()

    def plant_cmd(ready, *extra):
        return [sys.executable, "-m", "aocs_runner.plant_node", "irassi_small", "--mode", "realtime", "-q",
                "--set", f"actuator.axis_limit={LIMIT}", "--ready-file", str(ready), *extra]

    def wait_file(p, proc):
        end = time.monotonic() + 20
        while not p.exists():
            assert proc.alive() and time.monotonic() < end, "plant_node not ready"
            time.sleep(0.01)

    rec = Recorder(log_path).start()
    try:
        with orchestrate.Processes() as procs:
            a = procs.start("plant A", plant_cmd(tmp_path / "a.ready"), stdout=tmp_path / "a.out",
                            stderr=tmp_path / "a.err", env=env)
            wait_file(tmp_path / "a.ready", a)
            fc = procs.start("fsw_node", [fsw_node_bin, cfg_path], stdout=tmp_path / "fsw.out",
                             stderr=tmp_path / "fsw.err")
            time.sleep(2.0)
            a.stop(signal.SIGKILL)
            assert a.popen.returncode == -signal.SIGKILL
            time.sleep(1.5)                                   # no plant: ~15 periods of the node
            b = procs.start("plant B", plant_cmd(tmp_path / "b.ready", "--start-tick", "1000",
                                                 "--set", "duration_s=2.5", "--set", "metrics.window_s=2.5"),
                            stdout=tmp_path / "b.out", stderr=tmp_path / "b.err", env=env)
            assert b.wait(30) == 0, b.stderr_tail()
            assert fc.alive()
            assert fc.stop() == 0
    finally:
        rec.stop()
    log = lcmlog.read(log_path)
    fsw = json.loads([ln for ln in (tmp_path / "fsw.out").read_text().splitlines() if ln.startswith("{")][-1])
    fsw = fsw["fsw_node"]
    assert fsw["reason"] == "signal" and fsw["run_mode"] == "realtime"
    c = log.cmd
    u = c["u_sat"]
    assert np.all(np.isfinite(u)) and np.abs(u).max() <= LIMIT * (1 + 1e-12)
    ticks_a = log.sensors["tick"][log.sensors["tick"] < 1000]
    last_a = int(ticks_a.max())
    t_kill = log.sensors["log_utime"][log.sensors["tick"] == last_a][0]
    t_back = log.sensors["log_utime"][log.sensors["tick"] == 1000][0]
    gap = (c["log_utime"] > t_kill) & (c["log_utime"] < t_back)
    # the node kept stepping without samples (step_no_input), holding the tick of the last sample
    assert np.count_nonzero(gap) >= 5
    assert np.all(c["tick"][gap] == last_a)
    # (the first one may still use plant A's last sample, received just before the kill)
    assert c["mode"][gap][-1] == MODE_SAFE
    assert np.all(c["status"][gap][1:] == status_codes["AOCS_ERR_INPUT_MISSING"])
    assert np.all(u[gap][-3:] == 0.0)                          # SAFE without a rate: zero torque
    # plant B: the node recovered to NOMINAL with its samples (the commands answering B's samples:
    # once B has ended the node steps without input again and goes back to SAFE, for as long as the
    # test takes to stop it, which depends on the machine's load)
    after = (c["tick"] >= 1000) & (c["log_utime"] <= log.sensors["log_utime"].max())
    assert np.any(after) and c["mode"][after][-1] == MODE_NOMINAL
    assert c["mode"][c["tick"] < last_a].tolist()[-1] == MODE_NOMINAL   # nominal before the kill
    # the frame jump of the restarted plant: counted as lost frames
    assert c["n_lost"][-1] == 1000 - last_a - 1
    # and the metrics from this log say the same
    meta = {"law": "quat_pd", "mode": "realtime", "target": "host", "fsw_config": cfg}
    m, _ = results.compute(log, sc, meta)
    assert m["counters"]["missing"] >= np.count_nonzero(gap) - 1
    assert m["counters"]["safe_entries"] >= 1 and m["counters"]["time_in_safe_mode_s"] > 0
    assert m["counters"]["lost"] == 1000 - last_a - 1
    assert m["realtime"]["jitter_ns_max"] is not None and m["limits"]["commands_over_limit"] == 0
    assert fsw["steps"] > log.sensors["tick"].size              # it stepped without input too
    assert math.isfinite(fsw["jitter_ns"]["rms"])


def test_the_bulk_log_decoder_equals_the_eventlog_decoder_on_a_real_log(fault_run):
    """A real run's log, with its malformed and foreign-fingerprint payloads: lcmlog.read (bulk numpy
    decode) gives what lcm.EventLog and the codec give, bit for bit."""
    import sys
    from pathlib import Path

    sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "python" / "aocs_wire"))
    from test_lcmlog import assert_same_log

    _, log = fault_run
    assert lcmlog._read_fast(log.path, keep_raw=True) is not None
    assert sum(c for k, c in log.counts.items() if k.endswith(".undecodable")) >= 1
    assert_same_log(lcmlog.read(log.path, keep_raw=True), lcmlog._read_eventlog(log.path, keep_raw=True))
