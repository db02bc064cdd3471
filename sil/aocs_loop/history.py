"""A run's command history, for comparing two flights of the same case bit for bit.

- digest(log): the reference digest of scripts/command-history.py (the fields every protocol version since 2
  has, so histories recorded on older checkouts stay comparable);
- differences(a, b): every actuator_cmd_t and sensors_t column of two logs compared as exact bits, but the
  timing fields (TIMING_FIELDS: they measure the machine, not the flight); what differs, one line each.

The in-process transport is checked with both: its runs against the LCM lockstep runs of the same cases
(tests/e2e/test_direct_transport.py, `scripts/command-history.py check DIR --transport direct`) and a
campaign's sampled LCM re-flights (aocs_campaign.worker).
"""
from __future__ import annotations

import hashlib

import numpy as np

#: sensors_t fields of protocol version 2 (sil/lcmtypes/sensors_t.lcm) in the digest; valid masked to its bits
SENSOR_FIELDS = ("tick", "t_s", "valid", "q", "w", "pos", "vel", "n_wheels", "wheel_speed")
VALID_V2 = 31   # VALID_ATTITUDE | RATE | POSITION | VELOCITY | WHEELS
#: actuator_cmd_t fields of protocol version 2 in the digest: every one but the timing fields (utime, step_ns,
#: overrun, n_overrun) and protocol_version (its value is the version)
COMMAND_FIELDS = ("frame", "tick", "law_id", "mode", "u_sat", "u_unsat", "saturated", "status", "n_invalid",
                  "n_stale", "n_missing", "n_law_error", "n_lost", "n_duplicate", "n_foreign", "n_malformed",
                  "n_cmd_accepted", "n_cmd_rejected", "n_wheels", "u_wheels", "wheel_scale", "wheel_limited",
                  "wheel_status", "h_total", "wheel_speed_margin")
#: actuator_cmd_t fields that measure the machine (the step's wall time, the node's clock): never compared
TIMING_FIELDS = ("utime", "step_ns", "overrun", "n_overrun")
#: the recorder's receive time of every message (aocs_wire.lcmlog): the log's, not the flight's
LOG_FIELDS = ("log_utime",)


def _hash(table: dict, names, masks=None) -> str:
    """SHA-256 of the named columns of a log table, in the given order, as exact bits (name, then bytes)."""
    h = hashlib.sha256()
    for name in names:
        col = table[name]
        if masks and name in masks:
            col = col & masks[name]
        h.update(name.encode())
        h.update(col.tobytes())
    return h.hexdigest()


def digest(log) -> dict:
    """The command history's digest of a read log (aocs_wire.lcmlog.read): commands, sensors and their counts."""
    return {"commands": _hash(log.cmd, COMMAND_FIELDS), "n_commands": int(len(log.cmd["tick"])),
            "sensors": _hash(log.sensors, SENSOR_FIELDS, {"valid": VALID_V2}),
            "n_sensors": int(len(log.sensors["tick"]))}


def _column_differences(kind: str, a: dict, b: dict, skip=()) -> list[str]:
    out = []
    for name in sorted(set(a) | set(b)):
        if name in skip:
            continue
        if name not in a or name not in b:
            out.append(f"{kind}.{name}: only in {'the first' if name in a else 'the second'} log")
            continue
        x, y = np.ascontiguousarray(a[name]), np.ascontiguousarray(b[name])
        if x.shape != y.shape or x.dtype != y.dtype:
            out.append(f"{kind}.{name}: shape {x.shape} {x.dtype} against {y.shape} {y.dtype}")
            continue
        if x.tobytes() != y.tobytes():   # exact bits: NaN equal to itself, -0.0 not equal to 0.0
            xb, yb = x.view(np.uint8).reshape(x.shape[0], -1), y.view(np.uint8).reshape(y.shape[0], -1)
            rows = np.nonzero(np.any(xb != yb, axis=1))[0]
            out.append(f"{kind}.{name}: {rows.size} messages differ, the first at index {rows[0]}")
    return out


def differences(a, b) -> list[str]:
    """Every column of actuator_cmd_t (but TIMING_FIELDS) and of sensors_t of two read logs compared bit for
    bit; one line per column that differs (empty: the same flight)."""
    return (_column_differences("actuator_cmd_t", a.cmd, b.cmd, TIMING_FIELDS + LOG_FIELDS)
            + _column_differences("sensors_t", a.sensors, b.sensors, LOG_FIELDS))
