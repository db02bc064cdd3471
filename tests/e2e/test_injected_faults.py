"""Injected faults through the real processes (issue 26): irassi_rw_wheel_dies flown briefly by plant_node and
fsw_node over LCM in the private namespace, and in process (--transport direct): the fault's truth in the log
(wheel 1's motor torque zero from t = 60 s although commanded), in the telemetry, and the run JSON's `faults`
entry; the two transports fly the same run bit for bit; a link drop burst over LCM drops exactly its frames.
"""
from __future__ import annotations

import numpy as np
import pytest

from aocs_analysis import telemetry
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog

DURATION_S = 80.0     # the slew is under way at 60 s (its profile runs to 217 s)


@pytest.fixture(scope="module")
def flown(private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    out = {}
    for transport in ("lcm", "direct"):
        d = tmp_path_factory.mktemp(f"wheel_dies_{transport}")
        res = execute(RunOptions("irassi_rw_wheel_dies", duration=DURATION_S, out=str(d), quiet=True, plots=False,
                                 transport=transport, allow=("fault-management",)))
        out[transport] = (res, lcmlog.read(d / "run.lcmlog"), d)
    return out


def test_the_wheels_fault_is_in_the_truth_log_and_the_telemetry(flown):
    res, log, d = flown["lcm"]
    tick = log.truth["tick"]
    torque = np.asarray(log.truth["wheel_torque"])[:, 1]
    cmd_tick = log.cmd["tick"]
    u1 = np.asarray(log.cmd["u_wheels"])[:, 1]
    # the flight software commands wheel 1 before and after the fault (nothing told it yet) ...
    assert np.abs(u1[(cmd_tick >= 100) & (cmd_tick < 600)]).max() > 1e-3
    assert np.abs(u1[cmd_tick >= 600]).max() > 1e-3
    # ... the plant applies it before (truth of tick k: the torque held over period k - 1) and not after
    before = (tick >= 101) & (tick <= 600)
    np.testing.assert_allclose(torque[before], u1[(cmd_tick >= 100) & (cmd_tick < 600)], atol=1e-12)
    assert np.all(torque[tick >= 601] == 0.0)
    cols = telemetry.read(d / "telemetry.parquet")
    active = cols["fault_1_wheel_torque_loss_active"].to_numpy()
    k = cols["tick"].to_numpy()
    np.testing.assert_array_equal(active, (k >= 600) & (k < 800))   # [start, end): the run's end is the fault's


def test_the_run_json_has_the_faults_entry(flown):
    res, _, _ = flown["lcm"]
    (f,) = res.metrics["faults"]
    assert (f["kind"], f["unit"], f["start_s"], f["end_s"]) == ("wheel_torque_loss", 1, 60.0, DURATION_S)
    assert f["unit_kind"] == "wheel" and f["detection_expected"] and f["isolation_expected"]
    events = res.metrics.get("events") or []
    if not events:     # the flight software has no fault management yet: never detected, and not handled
        assert f["detected_s"] is None and f["recovered_s"] is None and not f["handled"]
        assert res.metrics["verdict"]["allowed"] == ["fault-management"]
    else:
        assert f["detected_s"] is None or f["detected_s"] >= 60.0
    assert "fault 1: wheel_torque_loss wheel 1" in res.table


def test_both_transports_fly_the_faulted_run_the_same(flown):
    (_, a, _), (_, b, _) = flown["lcm"], flown["direct"]
    for key in ("q", "w", "wheel_speed", "wheel_torque"):
        np.testing.assert_array_equal(a.truth[key], b.truth[key])
    np.testing.assert_array_equal(a.cmd["u_wheels"], b.cmd["u_wheels"])
    assert flown["lcm"][0].metrics["faults"] == flown["direct"][0].metrics["faults"]


def test_a_link_drop_burst_drops_its_frames_over_lcm(private_netns, fsw_node_bin, aocs_lcm, tmp_path):
    res = execute(RunOptions("irassi_rw_mekf", duration=6.0, out=str(tmp_path), quiet=True, plots=False,
                             faults=["link_drop_burst@2-2.5"], allow=("fault-management",)))
    log = lcmlog.read(tmp_path / "run.lcmlog")
    sent = set(int(k) for k in log.sensors["tick"])
    assert sent == set(range(60)) - {20, 21, 22, 23, 24}
    assert res.metrics["log_complete"] and res.metrics["counters"]["lost"] >= 1
    assert not [x for x in res.metrics["verdict"]["failures"] if x["check"] == "incomplete-log"]
