"""telemetry.py: the run's table, one row per truth tick, the other channels placed on the tick they carry, checked
against values set by hand in a log built from the wire contract's own fields (every column of every channel
present, zeros unless a test sets it), and the Parquet round trip."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_analysis import telemetry as T
from aocs_plant.scenario import load
from synthetic_log import make_log

ARCSEC = math.degrees(1.0) * 3600.0


def test_every_channel_lands_on_the_tick_it_carries():
    sc = load("irassi_rw")
    log = make_log(5, cmd_ticks=[0, 1, 3, 3, 4], sensor_ticks=[0, 1, 3, 4], status_steps=[4, 1])
    log.sensors["w"][:, 0] = [10.0, 11.0, 13.0, 14.0]            # value = 10 + tick
    log.cmd["u_sat"][:, 1] = [0.0, 1.0, 3.0, 3.5, 4.0]             # tick 3 answered twice: the last one counts
    log.status["n_overrun"][:] = [7, 5]                            # steps 4 -> 7, steps 1 -> 5
    log.truth["wheel_speed"][:, 2] = 100.0 + np.arange(5)
    cols = T.columns(log, sc)
    assert len({len(v) for v in cols.values()}) == 1
    assert cols["t_s"].tolist() == pytest.approx([0.0, 0.1, 0.2, 0.3, 0.4])
    w = cols["w_meas_x_rad_s"]
    assert w[[0, 1, 3, 4]].tolist() == [10.0, 11.0, 13.0, 14.0] and math.isnan(w[2])   # tick 2: no sensors
    assert cols["answered"].tolist() == [True, True, False, True, True]
    u = cols["torque_cmd_y_nm"]
    assert u[[0, 1, 3, 4]].tolist() == [0.0, 1.0, 3.5, 4.0] and math.isnan(u[2])
    # status_t after `steps` answered ticks: tick k sees the last status with steps <= k + 1
    ov = cols["status_n_overrun"]
    assert ov[:3].tolist() == [5.0, 5.0, 5.0] and ov[3:].tolist() == [7.0, 7.0]
    # irassi_rw flies four wheels: a column per wheel, none for the two unused wire slots
    assert cols["wheel_speed_true_3_rad_s"].tolist() == [100.0, 101.0, 102.0, 103.0, 104.0]
    assert "wheel_speed_true_4_rad_s" in cols and "wheel_speed_true_5_rad_s" not in cols
    assert "q_est_1" not in cols                                   # passthrough: no estimator columns


def test_a_scenario_without_wheels_has_no_wheel_columns():
    """irassi_large flies the reference's unlimited actuator: the wire's wheel slots (zeros) give no column."""
    sc = load("irassi_large")
    assert sc.effectors.get("wheels") is None
    cols = T.columns(make_log(3, cmd_ticks=[0, 1, 2], sensor_ticks=[0, 1, 2], status_steps=[]), sc)
    assert "torque_cmd_x_nm" in cols
    assert [k for k in cols if "wheel" in k] == []


def test_estimator_columns_knowledge_error_and_sigma():
    sc = load("irassi_hold_mekf")
    n = 4
    log = make_log(n, cmd_ticks=range(n), sensor_ticks=range(n), status_steps=[])
    a = np.array([2.0, 5.0, -3.0, 0.5]) / ARCSEC                  # estimate rotated about x by a (rad)
    log.cmd["q_est"][:] = np.stack([np.sin(a / 2), 0 * a, 0 * a, np.cos(a / 2)], axis=1)
    log.cmd["est_p"][:, 0] = (1.5 / ARCSEC) ** 2                   # P00: 1.5 arcsec 1-sigma about x
    log.cmd["est_p"][:, 15] = (4.0e-6) ** 2                        # P33 (row-major upper triangle: 6 + 5 + 4): bias x
    cols = T.columns(log, sc)
    # dth = rotation vector of q_true (x) q_est^-1 with q_true = identity: -a about x
    assert cols["knowledge_err_x_arcsec"] == pytest.approx(-a * ARCSEC, rel=1e-9)
    assert cols["knowledge_err_y_arcsec"] == pytest.approx(0.0, abs=1e-12)
    assert cols["est_sigma_att_x_arcsec"] == pytest.approx(1.5, rel=1e-12)
    assert cols["est_sigma_bias_x_rad_s"] == pytest.approx(4.0e-6, rel=1e-12)
    # control error: the angle between q_est and the target, 2 acos |q_est . qd| (unit quaternions)
    qd = np.stack([cols[f"q_target_{i}"] for i in range(1, 5)], axis=1)
    q_est = np.asarray(log.cmd["q_est"])
    expect = 2.0 * np.arccos(np.clip(np.abs(np.sum(q_est * qd, axis=1)), 0.0, 1.0)) * ARCSEC
    assert cols["control_err_arcsec"] == pytest.approx(expect, rel=1e-6, abs=1e-6)


def test_an_injected_fault_is_active_from_its_start_tick_to_before_its_end_tick():
    """fault_<i>_<kind>_active: True on the ticks [start, end) the plant applies the fault (Fault.ticks): a
    wheel dying from 0.2 s to 0.4 s is active on ticks 2 and 3, not on tick 4."""
    sc = load("irassi_rw", {"faults": [{"kind": "wheel_torque_loss", "unit": 1, "start_s": 0.2, "end_s": 0.4}]})
    log = make_log(6, cmd_ticks=list(range(6)), sensor_ticks=list(range(6)), status_steps=[6])
    cols = T.columns(log, sc)
    assert cols["fault_1_wheel_torque_loss_active"].tolist() == [False, False, True, True, False, False]


def test_decimation_keeps_every_nth_and_the_last_row():
    cols = {"t_s": np.arange(10.0), "x": np.arange(10) * 2}
    assert T.decimated(cols, 3)["t_s"].tolist() == [0.0, 3.0, 6.0, 9.0]
    assert T.decimated(cols, 4)["t_s"].tolist() == [0.0, 4.0, 8.0, 9.0]
    assert T.decimated(cols, 4)["x"].tolist() == [0, 8, 16, 18]
    with pytest.raises(ValueError, match="--telemetry-decimate 0"):
        T.decimated(cols, 0)
    # every row: the table itself, not a copy of a long run's columns; an empty table stays empty
    assert T.decimated(cols, 1) is cols
    empty = {"t_s": np.zeros(0), "x": np.zeros(0)}
    assert T.decimated(empty, 4) is empty


def test_parquet_round_trip_with_its_description(tmp_path):
    sc = load("irassi_rw")
    log = make_log(7, cmd_ticks=[0, 1, 2, 4, 5, 6], sensor_ticks=range(7), status_steps=[3])
    log.truth["w"][:, 2] = np.linspace(-1.0, 1.0, 7)
    cols = T.columns(log, sc)
    path = T.write(tmp_path / "telemetry.parquet", cols, {"scenario": "irassi_rw", "law": "quat_pid"}, decimate=2)
    df = T.read(path)
    assert df["t_s"].tolist() == pytest.approx([0.0, 0.2, 0.4, 0.6])
    assert df["w_true_z_rad_s"].to_numpy() == pytest.approx(np.linspace(-1.0, 1.0, 7)[[0, 2, 4, 6]])
    assert list(df.columns) == list(cols)
    assert df["answered"].dtype == bool and df["answered"].tolist() == [True, True, True, True]
    assert T.read(T.write(tmp_path / "all.parquet", cols, {}))["answered"].tolist() == [True] * 3 + [False] + [True] * 3
    assert df["tick"].dtype == "int64" and df["tick"].tolist() == [0, 2, 4, 6]
    assert T.read_meta(path) == {"scenario": "irassi_rw", "law": "quat_pid", "decimate": 2}


def test_alignment_takes_the_last_message_of_a_tick_and_leaves_rows_outside_the_source():
    """_align: for each row tick the last source message carrying it; rows whose tick no message carries are
    left out, those before the first and after the last source tick included (a command stream that stops
    early)."""
    rows, src = T._align(np.array([0, 1, 2, 3, 4, 5]), np.array([1, 1, 3, 2, 3]))
    assert rows.tolist() == [1, 2, 3] and src.tolist() == [1, 3, 4]
    rows, src = T._align(np.array([7, 8]), np.array([1, 2]))
    assert rows.size == 0 and src.size == 0
