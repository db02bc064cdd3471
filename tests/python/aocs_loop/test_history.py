"""aocs_loop.history: the command-history comparison a direct campaign's LCM re-flights rely on."""
from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from aocs_loop import history


def _log(n=5):
    rng = np.random.default_rng(3)
    cmd = {name: rng.normal(size=(n, 3)) for name in history.COMMAND_FIELDS}
    cmd.update(tick=np.arange(n), step_ns=rng.integers(0, 9999, n), utime=rng.integers(0, 9999, n),
               overrun=np.zeros(n, np.int8), n_overrun=np.zeros(n), log_utime=rng.integers(0, 9999, n))
    sensors = {name: rng.normal(size=(n, 4)) for name in history.SENSOR_FIELDS}
    sensors.update(tick=np.arange(n), valid=np.full(n, 31, np.int32), log_utime=rng.integers(0, 9999, n))
    return SimpleNamespace(cmd=cmd, sensors=sensors)


def _copy(log):
    return SimpleNamespace(cmd={k: v.copy() for k, v in log.cmd.items()},
                           sensors={k: v.copy() for k, v in log.sensors.items()})


def test_the_same_flight_with_other_timings_has_no_differences():
    a = _log()
    b = _copy(a)
    for k in ("step_ns", "utime", "log_utime"):
        b.cmd[k] = b.cmd[k] + 1
    b.sensors["log_utime"] = b.sensors["log_utime"] + 7
    b.cmd["overrun"][2] = 1
    assert history.differences(a, b) == []
    assert history.digest(a) == history.digest(b)


def test_one_bit_of_one_command_is_a_difference_naming_the_field_and_message():
    a = _log()
    b = _copy(a)
    u = b.cmd["u_wheels"]
    u.view(np.uint64)[3, 1] ^= 1            # the last bit of one wheel torque of message 3
    assert history.differences(a, b) == ["actuator_cmd_t.u_wheels: 1 messages differ, the first at index 3"]
    assert history.digest(a)["commands"] != history.digest(b)["commands"]


def test_minus_zero_is_not_zero_and_a_missing_message_is_a_difference():
    a = _log()
    b = _copy(a)
    a.sensors["q"][0, 0], b.sensors["q"][0, 0] = 0.0, -0.0
    assert history.differences(a, b) == ["sensors_t.q: 1 messages differ, the first at index 0"]
    c = _copy(a)
    c.cmd = {k: v[:-1] for k, v in c.cmd.items()}
    assert any(line.startswith("actuator_cmd_t.u_sat: shape") for line in history.differences(a, c))
