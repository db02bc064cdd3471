"""A run's decoded time series as one table, one row per control tick (issue 23; docs/sil.md, Telemetry):
truth, sensors, the flight software's command and status, its estimator, the wheels, the reference.

    cols = columns(log, scenario)            # name -> numpy array, every column of one length
    write(path, cols, meta, decimate=10)     # OUT/telemetry.parquet (every 10th tick and the last)
    read(path)                               # -> pandas.DataFrame

Every name carries its unit and frame: `t_s`, `q_true_1` .. `q_true_4` (q_BN scalar last, SPEC 1),
`w_true_x_rad_s` (B), `torque_cmd_x_nm` (actuator_cmd_t u_sat; `force_cmd_x_n` on an orbit scenario),
`wheel_speed_true_1_rad_s`, `est_sigma_att_x_arcsec` (sqrt of the filter's P diagonal). A row is the truth
sample of tick k; the sensors and the command of the same tick are on it (NaN where the log has none, e.g. a
dropped frame); the flight computer's status_t (about once a second) is carried forward to the ticks after it.
Without a wheel array there are no wheel columns; without a filter (estimator passthrough) no estimator columns.
Each injected fault i (1-based, the scenario's [[faults]] then --fault) has `fault_<i>_<kind>_active`.
The table's key-value metadata `aocs` holds the scenario, law, control period and decimation (JSON).
"""
from __future__ import annotations

import json
from pathlib import Path

import numpy as np

from . import estimation as E
from . import run_metrics as RM

AXES = ("x", "y", "z")
#: the Parquet key-value metadata key of the run's description
META_KEY = b"aocs"


def _vec(out: dict, prefix: str, unit: str, a, names=AXES) -> None:
    a = np.asarray(a, float)
    for i, n in enumerate(names):
        out[f"{prefix}_{n}{'_' + unit if unit else ''}"] = a[:, i]


def _quat(out: dict, prefix: str, q) -> None:
    q = np.asarray(q, float)
    for i in range(4):
        out[f"{prefix}_{i + 1}"] = q[:, i]


def _align(ticks_row: np.ndarray, ticks_src: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(rows, source index) pairs: for each row tick, the last source message of that tick."""
    if ticks_src.size == 0:
        return np.zeros(0, np.int64), np.zeros(0, np.int64)
    rev = ticks_src[::-1]
    uniq, first_rev = np.unique(rev, return_index=True)
    last = ticks_src.size - 1 - first_rev            # last occurrence of each unique tick
    pos = np.searchsorted(uniq, ticks_row)
    pos_c = np.minimum(pos, uniq.size - 1)
    hit = uniq[pos_c] == ticks_row
    return np.flatnonzero(hit), last[pos_c[hit]]


def _take(n: int, rows: np.ndarray, src: np.ndarray, a) -> np.ndarray:
    """a[src] placed at rows of an n-row column, NaN elsewhere (float)."""
    a = np.asarray(a, float)
    out = np.full((n,) + a.shape[1:], np.nan)
    out[rows] = a[src]
    return out


def columns(log, scenario) -> dict:
    """Every column of the run's table (name -> array), in a fixed order."""
    sc = scenario
    tr, cmd, sen = log.truth, log.cmd, log.sensors
    tick = np.asarray(tr["tick"], np.int64)
    n = tick.size
    t = np.asarray(tr["t_s"], float)
    out: dict = {"t_s": t, "tick": tick}
    attitude = sc.kind == "attitude"
    wheels = sc.effectors.get("wheels") if hasattr(sc, "effectors") else None
    nw = wheels.n if wheels is not None else 0
    wn = tuple(str(i + 1) for i in range(nw))

    # truth
    _quat(out, "q_true", tr["q"])
    _vec(out, "w_true", "rad_s", tr["w"])
    if attitude:
        _quat(out, "q_target", RM.target_quat(sc, t))
        out["pointing_err_arcsec"] = np.asarray(tr["pointing_err_arcsec"], float)
        _vec(out, "qe", "arcsec", tr["qe_arcsec"])
        _vec(out, "torque_applied", "nm", tr["torque_applied"])
        _vec(out, "torque_dist", "nm", tr["torque_dist"])
        _vec(out, "gyro_bias_true", "rad_s", tr["gyro_bias"])
    else:
        _vec(out, "pos_true", "m", tr["pos"])
        _vec(out, "vel_true", "m_s", tr["vel"])
        _vec(out, "force_applied", "n", tr["force_applied"])
        _vec(out, "force_dist", "n", tr["force_dist"])
    _vec(out, "h_total_true", "nms", tr["h_total"])
    if nw:
        _vec(out, "wheel_speed_true", "rad_s", np.asarray(tr["wheel_speed"])[:, :nw], wn)
        _vec(out, "wheel_momentum_true", "nms", np.asarray(tr["wheel_momentum"])[:, :nw], wn)
        _vec(out, "wheel_torque_true", "nm", np.asarray(tr["wheel_torque"])[:, :nw], wn)
        out["wheel_at_limit_bits"] = np.asarray(tr["wheel_at_limit"], np.int64)

    # the injected faults' truth: fault_<i>_<kind>_active, True on the ticks the plant applies fault i (the plant's
    # own rule, aocs_plant.faults.fault.Fault.ticks)
    for i, f in enumerate(getattr(sc, "faults", ())):
        a, b = f.ticks(sc.dt)
        out[f"fault_{i + 1}_{f.kind}_active"] = (tick >= a) & (tick < b)

    # sensors of the same tick
    rows, src = _align(tick, np.asarray(sen["tick"], np.int64))
    out["sensor_valid_bits"] = _take(n, rows, src, sen["valid"])
    if attitude:
        _quat(out, "q_meas", _take(n, rows, src, sen["q"]))
        _vec(out, "w_meas", "rad_s", _take(n, rows, src, sen["w"]))
        _quat(out, "st_q_meas", _take(n, rows, src, sen["st_q"]))
        out["st_t_meas_s"] = _take(n, rows, src, sen["st_t_meas_s"])
        _vec(out, "gyro_w_meas", "rad_s", _take(n, rows, src, sen["gyro_w"]))
    else:
        _vec(out, "pos_meas", "m", _take(n, rows, src, sen["pos"]))
        _vec(out, "vel_meas", "m_s", _take(n, rows, src, sen["vel"]))
    if nw:
        _vec(out, "wheel_speed_meas", "rad_s", _take(n, rows, src, np.asarray(sen["wheel_speed"])[:, :nw]), wn)

    # the flight software's answer to the tick
    rows, src = _align(tick, np.asarray(cmd["tick"], np.int64))
    out["answered"] = np.isin(np.arange(n), rows)
    out["law_id"] = _take(n, rows, src, cmd["law_id"])
    out["mode"] = _take(n, rows, src, cmd["mode"])
    u_name, u_unit = ("torque", "nm") if attitude else ("force", "n")
    _vec(out, f"{u_name}_cmd", u_unit, _take(n, rows, src, cmd["u_sat"]))
    _vec(out, f"{u_name}_unsat", u_unit, _take(n, rows, src, cmd["u_unsat"]))
    out["saturated"] = _take(n, rows, src, cmd["saturated"])
    out["step_ns"] = _take(n, rows, src, cmd["step_ns"])
    out["overrun"] = _take(n, rows, src, cmd["overrun"])
    out["fsw_status"] = _take(n, rows, src, cmd["status"])
    if nw:
        _vec(out, "wheel_torque_cmd", "nm", _take(n, rows, src, np.asarray(cmd["u_wheels"])[:, :nw]), wn)
        out["wheel_scale"] = _take(n, rows, src, cmd["wheel_scale"])
        out["wheel_limited_bits"] = _take(n, rows, src, cmd["wheel_limited"])
        out["wheel_speed_margin"] = _take(n, rows, src, cmd["wheel_speed_margin"])
        _vec(out, "h_total_fsw", "nms", _take(n, rows, src, cmd["h_total"]))
    est = getattr(sc, "estimator", None)
    if attitude and est is not None and est.type != "passthrough" and cmd["tick"].size:
        _estimator(out, n, rows, src, cmd)

    # the flight computer's status, carried forward (its `steps` counts the ticks answered)
    stt = log.status
    if stt["steps"].size:
        order = np.argsort(np.asarray(stt["steps"]), kind="stable")
        steps = np.asarray(stt["steps"])[order]
        k = np.searchsorted(steps, tick + 1, side="right") - 1
        ok = k >= 0
        for key, name in (("steps", "status_steps"), ("n_overrun", "status_n_overrun"),
                          ("step_ns_p99", "status_step_ns_p99"), ("step_ns_max", "status_step_ns_max"),
                          ("n_cmd_accepted", "status_n_cmd_accepted"), ("n_cmd_rejected", "status_n_cmd_rejected")):
            col = np.full(n, np.nan)
            col[ok] = np.asarray(stt[key], float)[order][k[ok]]
            out[name] = col
    return out


def _estimator(out: dict, n: int, rows, src, cmd) -> None:
    """The filter's estimate and its 1-sigma (sqrt of P's diagonal) of the tick, and the knowledge and control
    errors against the truth and the reference of the same row (estimation.py's definitions)."""
    q_est = _take(n, rows, src, cmd["q_est"])
    out["estimator_id"] = _take(n, rows, src, cmd["estimator"])
    out["est_status"] = _take(n, rows, src, cmd["est_status"])
    _quat(out, "q_est", q_est)
    _vec(out, "w_est", "rad_s", _take(n, rows, src, cmd["w_est"]))
    _vec(out, "bias_est", "rad_s", _take(n, rows, src, cmd["bias_est"]))
    p = E.covariance_from_upper(_take(n, rows, src, cmd["est_p"]))
    sig = E.sigma_from_covariance(p)
    _vec(out, "est_sigma_att", "arcsec", sig[:, :3] * E.ARCSEC_PER_RAD)
    _vec(out, "est_sigma_bias", "rad_s", sig[:, 3:])
    q_true = np.stack([out[f"q_true_{i}"] for i in range(1, 5)], axis=1)
    qd = np.stack([out[f"q_target_{i}"] for i in range(1, 5)], axis=1)
    with np.errstate(invalid="ignore"):
        _vec(out, "knowledge_err", "arcsec", E.knowledge_error_rad(q_true, q_est) * E.ARCSEC_PER_RAD)
        out["control_err_arcsec"] = E.control_error_arcsec(q_est, qd)["true_angle"]
    for k in ("n_st_used", "n_st_gated", "n_st_hostile", "n_est_restarts"):
        out[k] = _take(n, rows, src, cmd[k])


def decimated(cols: dict, every: int) -> dict:
    """Every `every`-th row from the first, and the last row (the end of the run stays in the table)."""
    if every < 1:
        raise ValueError(f"--telemetry-decimate {every}: must be a whole number >= 1")
    n = len(cols["t_s"])
    if every == 1 or n == 0:
        return cols
    idx = np.arange(0, n, every)
    if idx[-1] != n - 1:
        idx = np.append(idx, n - 1)
    return {k: np.asarray(v)[idx] for k, v in cols.items()}


#: numpy dtype kind -> arrow type of a column
_ARROW_TYPES = {"f": "float64", "i": "int64", "b": "bool_"}


def _arrow(pa, v: np.ndarray):
    """The column as an arrow array built on its own buffer (pa.array would first import pandas, ~0.5 s a
    process, to check whether v is a pandas object)."""
    kind = v.dtype.kind
    if kind not in _ARROW_TYPES:
        raise TypeError(f"telemetry column of dtype {v.dtype}")
    if kind == "b":
        data = np.packbits(v, bitorder="little")
    else:
        data = np.ascontiguousarray(v, dtype=np.float64 if kind == "f" else np.int64)
    return pa.Array.from_buffers(getattr(pa, _ARROW_TYPES[kind])(), len(v), [None, pa.py_buffer(data)])


def write(path, cols: dict, meta: dict, decimate: int = 1) -> Path:
    """The table as Parquet (snappy, pyarrow's default: the quickest to read back), with meta (JSON) under the `aocs`
    key of its metadata."""
    import pyarrow as pa  # deferred: ~0.2 s, only when the table is written
    import pyarrow.parquet as pq  # deferred: see above

    cols = decimated(cols, decimate)
    table = pa.Table.from_arrays([_arrow(pa, np.asarray(v)) for v in cols.values()], names=list(cols))
    table = table.replace_schema_metadata({META_KEY: json.dumps({**meta, "decimate": decimate}).encode()})
    path = Path(path)
    pq.write_table(table, path, compression="snappy")
    return path


def read(path):
    """The table as a pandas DataFrame (pyarrow engine)."""
    import pyarrow.parquet as pq  # deferred: see write

    return pq.read_table(path).to_pandas()


def read_meta(path) -> dict:
    """The run description written with the table (scenario, law, dt, decimate)."""
    import pyarrow.parquet as pq  # deferred: see write

    md = pq.read_schema(path).metadata or {}
    return json.loads(md.get(META_KEY, b"{}"))
