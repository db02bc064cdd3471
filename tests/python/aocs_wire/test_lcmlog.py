"""The log reader's integrity checks (aocs_wire.lcmlog.scan, completeness_problems) on logs made here."""
from __future__ import annotations

import json

import pytest

from aocs_core import compiled
from aocs_wire import lcmlog
from aocs_wire.recorder import encode_event


@pytest.fixture(autouse=True, params=["compiled", "numpy"])
def walk(request, monkeypatch):
    """Every test twice: with the compiled walk and decoder (aocs_lcmlog_kernel, sil/wire_kernels/lcmlog_kernel.c)
    and with numpy's (AOCS_PLANT_KERNELS=python)."""
    if request.param == "numpy":
        monkeypatch.setenv(compiled.ENV, "python")
    else:
        monkeypatch.delenv(compiled.ENV, raising=False)
        assert compiled.module(compiled.LCMLOG) is not None, f"{compiled.LCMLOG} not built (cmake --build --preset host)"
    return request.param


def _write(path, events):
    path.write_bytes(b"".join(encode_event(i, 1000 * i, ch, data) for i, (ch, data) in enumerate(events)))
    return path


def _marker(what):
    return ("AOCS_RUNNER", json.dumps({"marker": what}).encode())


def test_scan_counts_a_whole_log(tmp_path):
    p = _write(tmp_path / "a.lcmlog", [_marker("start"), ("X", b"abc"), ("Y", b""), _marker("end")])
    s = lcmlog.scan(p)
    assert (s.events, s.first_event, s.last_event, s.size) == (4, 0, 3, p.stat().st_size)


def test_scan_names_the_byte_of_damage_and_truncation(tmp_path):
    p = _write(tmp_path / "a.lcmlog", [("CH", bytes(100))] * 10)
    data = p.read_bytes()
    one = len(encode_event(0, 0, "CH", bytes(100)))
    cases = {"cut in a header": (data[:3 * one + 10], "log truncated at byte %d" % (3 * one)),
             "cut in a payload": (data[:3 * one + 40], "log truncated at byte %d" % (3 * one)),
             "zeroed": (data[:2 * one] + bytes(one) + data[3 * one:], "log corrupt at byte %d" % (2 * one))}
    for what, (bad, message) in cases.items():
        (tmp_path / "b.lcmlog").write_bytes(bad)
        with pytest.raises(lcmlog.LogIntegrityError, match=message):
            lcmlog.scan(tmp_path / "b.lcmlog")
    # an event removed whole leaves every header valid: the event numbers show it
    (tmp_path / "c.lcmlog").write_bytes(data[:one] + data[2 * one:])
    with pytest.raises(lcmlog.LogIntegrityError, match=f"log corrupt at byte {one} .event 2 follows event 0"):
        lcmlog.scan(tmp_path / "c.lcmlog")


def test_read_carries_the_scan_of_a_clean_file_and_none_of_a_damaged_one(aocs_lcm, tmp_path):  # noqa: ARG001
    """Log.scan is scan()'s answer when the bulk reader found the file clean; for an event removed whole (every
    header valid, the numbering broken) it is None, and scan() names the byte."""
    p = _write(tmp_path / "a.lcmlog", [_marker("start"), ("X", b"abc"), ("Y", b""), _marker("end")])
    assert lcmlog.read(p).scan == lcmlog.scan(p)
    data = p.read_bytes()
    one = len(encode_event(0, 0, "AOCS_RUNNER", json.dumps({"marker": "start"}).encode()))
    (tmp_path / "c.lcmlog").write_bytes(data[:one] + data[one + len(encode_event(1, 1000, "X", b"abc")):])
    assert lcmlog.read(tmp_path / "c.lcmlog").scan is None
    with pytest.raises(lcmlog.LogIntegrityError, match="event 2 follows event 0"):
        lcmlog.scan(tmp_path / "c.lcmlog")


def test_tick_gaps_are_described():
    import numpy as np
    assert lcmlog._tick_gap(np.arange(5), 0, 4) is None
    assert lcmlog._tick_gap(np.array([0, 1, 3]), 0, None) == "tick 3 follows tick 1"
    assert lcmlog._tick_gap(np.array([1, 2]), 0, None) == "the first is 1, not 0"
    assert lcmlog._tick_gap(np.arange(3), 0, 9) == "the last is 2, not 9"
    assert lcmlog._tick_gap(np.zeros(0, int), 0, None) == "none at all"
    assert lcmlog._tick_gap(np.array([0, 1, 1, 2, 0]), 0, 2) is None   # duplicated / replayed frames


def assert_same_log(a, b):
    """Two Log objects hold the same tables bit for bit (dtype, shape, bytes), markers, counts (and
    their key order) and raw events."""
    for name in ("truth", "cmd", "sensors", "status", "command"):
        ta, tb = getattr(a, name), getattr(b, name)
        assert list(ta) == list(tb), name
        for k in ta:
            assert (ta[k].dtype, ta[k].shape) == (tb[k].dtype, tb[k].shape), (name, k)
            assert ta[k].tobytes() == tb[k].tobytes(), (name, k)
    ea, eb = a.fault_events, b.fault_events
    assert list(ea) == list(eb)
    for k in ea:
        assert (ea[k].dtype, ea[k].shape, ea[k].tobytes()) == (eb[k].dtype, eb[k].shape, eb[k].tobytes()), k
    assert a.markers == b.markers
    assert list(a.counts.items()) == list(b.counts.items())
    assert a.events == b.events


def _mixed_events(aocs_lcm):
    """Every channel with values that stress the decoding (int64 beyond 2^53, negative ints, NaN, float32
    values, booleans), payloads of the wrong length and of a foreign fingerprint, a foreign channel."""
    import numpy as np

    from aocs_wire import wire

    codecs = wire.Codecs(aocs_lcm)
    rng = np.random.default_rng(7)
    ev = [_marker("start")]
    for k in range(300):
        for ch, codec in ((wire.SENSORS, codecs.sensors), (wire.TRUTH, codecs.truth),
                          (wire.ACTUATOR, codecs.actuator), (wire.STATUS, codecs.status),
                          (wire.COMMAND, codecs.command), (wire.EVENTS, codecs.event)):
            vals = []
            for (name, n), typ in zip(codec.fields, codec.cls.__typenames__):
                for _ in range(1 if n is None else n):
                    if typ == "int64_t":
                        vals.append(int(rng.integers(-2**62, 2**62)) if k % 3 else 2**53 + 1 + k)
                    elif typ in ("int32_t",):
                        vals.append(int(rng.integers(-2**31, 2**31)))
                    elif typ in ("int16_t",):
                        vals.append(int(rng.integers(-2**15, 2**15)))
                    elif typ in ("int8_t", "boolean"):
                        vals.append(int(rng.integers(-128, 128)))
                    elif typ == "byte":
                        vals.append(int(rng.integers(0, 256)))
                    else:
                        vals.append(float("nan") if k == 5 else float(rng.normal(0, 1e3)))
            data = codec.pack(*vals)
            if k == 17:
                data = data[:-1]                     # malformed: one byte short
            if k == 23:
                data = b"\x01" * 8 + data[8:]        # foreign fingerprint
            ev.append((ch, data))
        if k % 100 == 0:
            ev.append(("OTHER_CH", bytes(rng.integers(0, 256, 37, dtype=np.uint8))))
            ev.append(("AOCS_RUNNER", b"not json"))
    ev.append(_marker("end"))
    return ev


def test_bulk_decoder_equals_the_eventlog_decoder(aocs_lcm, tmp_path):
    path = _write(tmp_path / "mixed.lcmlog", _mixed_events(aocs_lcm))
    fast = lcmlog._read_fast(path, keep_raw=True)
    assert fast is not None                                  # a clean file: the bulk path decodes it
    assert_same_log(fast, lcmlog._read_eventlog(path, keep_raw=True))
    assert fast.counts["AOCS_SENSORS.undecodable"] == 2 and fast.sensors["tick"].size == 298
    assert_same_log(lcmlog.read(path), lcmlog._read_eventlog(path))
    empty = _write(tmp_path / "empty.lcmlog", [])
    assert_same_log(lcmlog.read(empty), lcmlog._read_eventlog(empty))


def test_a_damaged_log_is_read_by_the_eventlog_decoder(aocs_lcm, tmp_path):
    good = _write(tmp_path / "g.lcmlog", _mixed_events(aocs_lcm)).read_bytes()
    cases = {"truncated": good[:-5], "garbage_inside": good[:5000] + b"\x00" * 13 + good[5000:],
             "garbage_first": b"xx" + good}
    for name, blob in cases.items():
        p = tmp_path / f"{name}.lcmlog"
        p.write_bytes(blob)
        assert lcmlog._read_fast(p, keep_raw=False) is None, name
        assert_same_log(lcmlog.read(p, keep_raw=True), lcmlog._read_eventlog(p, keep_raw=True))


def test_covariance_of_the_upper_triangle():
    import numpy as np
    P = np.arange(36, dtype=float).reshape(6, 6)
    P = P + P.T                                   # symmetric
    upper = P[np.triu_indices(6)]                 # row by row: P00 P01 .. P05 P11 .. P55 (estimate.h)
    assert upper[:7].tolist() == [P[0, 0], P[0, 1], P[0, 2], P[0, 3], P[0, 4], P[0, 5], P[1, 1]]
    assert np.array_equal(lcmlog.covariance(upper), P)
    both = lcmlog.covariance(np.stack([upper, 2 * upper]))
    assert both.shape == (2, 6, 6) and np.array_equal(both[1], 2 * P)


def test_the_version_3_fields_are_columns(aocs_lcm, tmp_path):
    """The star tracker, gyro, estimate and truth fields of protocol version 3, decoded by name with their shapes
    (both decoders)."""
    from aocs_wire import wire
    codecs = wire.Codecs(aocs_lcm)
    ev = []
    for k in range(3):
        s = aocs_lcm.sensors_t()
        s.protocol_version, s.tick, s.t_s = s.PROTOCOL_VERSION, k, 0.1 * k
        s.valid = s.VALID_STAR_TRACKER | s.VALID_GYRO if k == 1 else s.VALID_GYRO
        s.st_q, s.st_t_meas_s, s.gyro_w = [0.0, 0.0, 0.6, 0.8], 0.05 * k, [1e-3 * k, 0.0, -1e-3]
        a = aocs_lcm.actuator_cmd_t()
        a.protocol_version, a.tick, a.estimator, a.est_status = a.PROTOCOL_VERSION, k, 1, -k
        a.q_est, a.w_est, a.bias_est = [0.0, 0.0, 0.0, 1.0], [0.0, k, 0.0], [1e-6, 0.0, 0.0]
        a.est_p = [float(i + k) for i in range(21)]
        a.st_status, a.n_st_used, a.n_st_gated, a.n_st_hostile, a.n_est_restarts = -1, 2**53 + k, 1, 2, 3
        tr = aocs_lcm.truth_t()
        tr.protocol_version, tr.tick, tr.gyro_bias = tr.PROTOCOL_VERSION, k, [1e-7, -2e-7, 3e-7]
        ev += [(wire.SENSORS, s.encode()), (wire.ACTUATOR, a.encode()), (wire.TRUTH, tr.encode())]
    assert len(ev[0][1]) == codecs.sensors.size
    path = _write(tmp_path / "v3.lcmlog", ev)
    for log in (lcmlog.read(path), lcmlog._read_eventlog(path)):
        s, c, tr = log.sensors, log.cmd, log.truth
        assert s["st_q"].shape == (3, 4) and s["st_t_meas_s"].tolist() == [0.0, 0.05, 0.1]
        assert s["gyro_w"][:, 0].tolist() == [0.0, 1e-3, 2e-3]
        assert ((s["valid"] & aocs_lcm.sensors_t.VALID_STAR_TRACKER) != 0).tolist() == [False, True, False]
        assert c["estimator"].tolist() == [1, 1, 1] and c["est_status"].tolist() == [0, -1, -2]
        assert c["q_est"].shape == (3, 4) and c["w_est"][:, 1].tolist() == [0.0, 1.0, 2.0]
        assert c["bias_est"].shape == (3, 3) and c["est_p"].shape == (3, 21)
        assert c["n_st_used"].tolist() == [2**53, 2**53 + 1, 2**53 + 2]     # int64 exact
        assert (c["st_status"].tolist(), c["n_st_gated"].tolist(), c["n_st_hostile"].tolist(),
                c["n_est_restarts"].tolist()) == ([-1] * 3, [1] * 3, [2] * 3, [3] * 3)
        assert lcmlog.covariance(c["est_p"]).shape == (3, 6, 6)
        assert tr["gyro_bias"].tolist() == [[1e-7, -2e-7, 3e-7]] * 3


def test_the_version_4_fields_are_columns(aocs_lcm, tmp_path):
    """The magnetometer and the momentum-management fields of protocol version 4, decoded by name with their
    shapes (both decoders); unload_events() finds the steps an unload started."""
    from aocs_wire import wire
    ev = []
    unloading = [False, True, True, False, True]
    for k in range(5):
        s = aocs_lcm.sensors_t()
        s.protocol_version, s.tick, s.t_s = s.PROTOCOL_VERSION, k, 0.1 * k
        s.valid = s.VALID_MAGNETOMETER if k % 2 else 0
        s.mag_b_t = [2e-5, -0.25e-5 * k, 3e-6]
        a = aocs_lcm.actuator_cmd_t()
        a.protocol_version, a.tick, a.mom_policy, a.mom_status, a.n_thrusters = a.PROTOCOL_VERSION, k, 2, -k, 12
        a.thruster_on_s = [0.001 * k] * 12
        a.dipole_am2, a.u_unload, a.h_wheels, a.dh = [0.0, 0.0, 0.5 * k], [-0.1, 0.0, 0.0], [k, 0.0, 0.0], [k, 1, 0]
        a.unloading = unloading[k]
        a.n_unload_events = sum(1 for i in range(k + 1) if unloading[i] and (i == 0 or not unloading[i - 1]))
        ev += [(wire.SENSORS, s.encode()), (wire.ACTUATOR, a.encode())]
    path = _write(tmp_path / "v4.lcmlog", ev)
    for log in (lcmlog.read(path), lcmlog._read_eventlog(path)):
        s, c = log.sensors, log.cmd
        assert s["mag_b_t"].shape == (5, 3) and s["mag_b_t"][:, 1].tolist() == [-0.25e-5 * k for k in range(5)]
        assert ((s["valid"] & aocs_lcm.sensors_t.VALID_MAGNETOMETER) != 0).tolist() == [False, True, False, True,
                                                                                          False]
        assert c["mom_policy"].tolist() == [2] * 5 and c["mom_status"].tolist() == [0, -1, -2, -3, -4]
        assert c["thruster_on_s"].shape == (5, 12) and c["thruster_on_s"][:, 3].tolist() == [0.0, 0.001, 0.002,
                                                                                             0.003, 0.004]
        for name in ("dipole_am2", "u_unload", "h_wheels", "dh"):
            assert c[name].shape == (5, 3), name
        assert c["unloading"].tolist() == [0, 1, 1, 0, 1] and c["n_unload_events"].tolist() == [0, 1, 1, 1, 2]
        assert lcmlog.unload_events(c).tolist() == [1, 4]
