"""A run's log built in memory from the wire contract's own fields (aocs_wire.wire codecs of the generated bindings):
every column of every channel present, zeros unless a test sets it. Shared by the tests of the analysis package
(test_telemetry, test_run_metrics). No tests here."""
from __future__ import annotations

from pathlib import Path

import numpy as np

from aocs_core import paths
from aocs_wire import wire
from aocs_wire.lcmlog import Log


def table(codec: wire.Codec, n: int) -> dict:
    """n rows of one channel: each field of the codec as zeros (arrays as (n, k)), and the receive time."""
    out = {}
    for name, k in codec.fields:
        out[name] = np.zeros((n,) if k is None else (n, k))
    out["log_utime"] = np.zeros(n, np.int64)
    return out


def make_log(n: int, cmd_ticks, sensor_ticks, status_steps) -> Log:
    """n truth samples (ticks 0 .. n-1 at 10 Hz, identity attitude), the given commands, sensor frames (by tick)
    and status messages (by steps)."""
    c = wire.Codecs(paths.import_bindings())
    tr = table(c.truth, n)
    tr["tick"] = np.arange(n)
    tr["t_s"] = 0.1 * np.arange(n)
    tr["q"][:, 3] = 1.0
    sen = table(c.sensors, len(sensor_ticks))
    sen["tick"] = np.asarray(sensor_ticks)
    cmd = table(c.actuator, len(cmd_ticks))
    cmd["tick"] = np.asarray(cmd_ticks)
    cmd["q_est"][:, 3] = 1.0
    st = table(c.status, len(status_steps))
    st["steps"] = np.asarray(status_steps)
    return Log(Path("synthetic.lcmlog"), tr, cmd, sen, st, table(c.command, 0))
