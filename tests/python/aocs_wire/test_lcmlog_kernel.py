"""The compiled walk and decoder of the log reader (aocs_lcmlog_kernel, sil/wire_kernels/lcmlog_kernel.c) against
numpy's (aocs_wire.lcmlog with AOCS_PLANT_KERNELS=python): the same events of every file, clean, damaged or hostile,
and its arguments checked. test_lcmlog.py runs the reader's own tests both ways."""
from __future__ import annotations

import numpy as np
import pytest

from aocs_core import compiled
from aocs_wire import lcmlog
from aocs_wire.recorder import encode_event


@pytest.fixture
def kernel(monkeypatch):
    monkeypatch.delenv(compiled.ENV, raising=False)
    k = compiled.module(compiled.LCMLOG)
    assert k is not None, f"{compiled.LCMLOG} not built (cmake --build --preset host)"
    return k


def _numpy_index(blob: bytes, monkeypatch):
    with monkeypatch.context() as m:
        m.setenv(compiled.ENV, "python")
        return lcmlog._index(np.frombuffer(blob, dtype=np.uint8))


def _same(blob: bytes, kernel, monkeypatch) -> bool:
    """The compiled index of blob equals numpy's: both None, or the same events (start, number, receive time,
    payload, data length) on the same channel names. Returns whether the file was clean."""
    ref = _numpy_index(blob, monkeypatch)
    got = lcmlog._index(np.frombuffer(blob, dtype=np.uint8))
    assert (got is None) == (ref is None)
    if ref is None:
        return False
    for f in ("starts", "num", "utime", "payload", "data_len"):
        assert np.array_equal(getattr(got, f), getattr(ref, f)), f
    assert [got.names[i] for i in got.chan_id] == [ref.names[i] for i in ref.chan_id]
    assert got.names == list(dict.fromkeys(got.names[i] for i in got.chan_id))   # in order of first appearance
    return True


def _log(events) -> bytes:
    return b"".join(encode_event(i, 1000 * i + 7, ch, data) for i, (ch, data) in enumerate(events))


def test_clean_logs_index_the_same(kernel, monkeypatch):
    rng = np.random.default_rng(3)
    assert _same(b"", kernel, monkeypatch)
    # 40 channels (the name table grows past its first 16 slots), payloads of 0 to 300 bytes, names of 1 to 63 bytes
    names = ["C" * (1 + i % 63) + str(i) for i in range(40)] + ["x", "A" * 63, "é"]
    events = [(names[int(rng.integers(len(names)))], bytes(rng.integers(0, 256, int(rng.integers(0, 300)),
                                                                          dtype=np.uint8))) for _ in range(2000)]
    blob = _log(events)
    assert _same(blob, kernel, monkeypatch)
    ix = lcmlog._index(np.frombuffer(blob, dtype=np.uint8))
    assert [ix.names[i] for i in ix.chan_id] == [e[0] for e in events]
    assert ix.utime.tolist() == [1000 * i + 7 for i in range(len(events))]


def test_damaged_and_hostile_files_index_the_same(kernel, monkeypatch):
    """Byte flips, cuts, inserted bytes and forged headers: the two walks agree on every one (None for any file
    that is not clean)."""
    rng = np.random.default_rng(11)
    good = _log([("AOCS_SENSORS", bytes(40)), ("AOCS_TRUTH", bytes(60)), ("Y", b"")] * 30)
    head = encode_event(0, 0, "AB", b"zz")[:28]
    cases = [good[:k] for k in (1, 27, 28, 29, len(good) - 1)]
    cases += [good + b"\x00", b"\x00" + good, good[:100] + good[101:]]
    cases.append(head[:20] + (0).to_bytes(4, "big") + head[24:] + b"zz")                  # channel length 0
    cases.append(head[:20] + (64).to_bytes(4, "big") + head[24:] + b"A" * 64 + b"zz")      # channel length 64
    cases.append(head[:24] + (2**32 - 1).to_bytes(4, "big") + b"ABzz")                     # data length past the end
    cases.append(encode_event(0, 0, "ok", b"") + head[:20] + (2).to_bytes(4, "big") + (0).to_bytes(4, "big")
                 + b"\xff\xfe")                                                               # a name that is not UTF-8
    cases.append(encode_event(0, 0, "a\x00b", b"1") + encode_event(1, 0, "a\x00b", b"2"))   # a NUL inside a name
    for _ in range(300):
        b = bytearray(good)
        for _ in range(int(rng.integers(1, 4))):
            b[int(rng.integers(len(b)))] = int(rng.integers(256))
        cases.append(bytes(b))
    clean = [_same(c, kernel, monkeypatch) for c in cases]
    assert clean[5] is False and clean[-301] is True and sum(clean) > 50   # both kinds were exercised


def test_decode_and_gather_refuse_bad_arguments(kernel):
    data = bytes(range(64))
    at = np.array([0, 8], dtype=np.int64)
    out = np.empty(2)
    assert kernel.gather(data, at, 4) == data[0:4] + data[8:12]
    with pytest.raises(ValueError, match="offset 61 .row 1. outside the 64 bytes"):
        kernel.gather(data, np.array([0, 61], dtype=np.int64), 4)
    with pytest.raises(TypeError, match="native int64"):
        kernel.gather(data, np.array([0, 8], dtype=np.int32), 4)
    with pytest.raises(ValueError, match="width must be >= 0"):
        kernel.gather(data, at, -1)
    with pytest.raises(ValueError, match="record 1 at byte 60 runs outside the 64 bytes"):
        kernel.decode(data, np.array([0, 60], dtype=np.int64), [(0, "d", 1, 0, out)])
    with pytest.raises(ValueError, match="field 0: bad offset, code, count or kind"):
        kernel.decode(data, at, [(0, "x", 1, 0, out)])
    with pytest.raises(ValueError, match="field 0: bad offset, code, count or kind"):
        kernel.decode(data, at, [(0, "d", 1, 2, out)])                      # a double as an integer
    with pytest.raises(ValueError, match="field 1: output of 8 bytes for 2 rows"):
        kernel.decode(data, at, [(0, "d", 1, 0, out), (8, "i", 1, 1, np.empty(1, dtype=np.int64))])
    with pytest.raises(ValueError, match="not C-contiguous"):
        kernel.decode(data, at, [(0, "d", 1, 0, np.empty(4)[::2])])
    kernel.decode(data, at, [(0, "d", 1, 0, out)])
    assert out.tolist() == [np.frombuffer(data[0:8], ">f8")[0], np.frombuffer(data[8:16], ">f8")[0]]


def test_decode_converts_as_numpy_does(kernel):
    """Each struct code and kind against numpy's big-endian view and astype (lcmlog._convert): int64 beyond 2^53
    through float64, the extremes of each width, NaN and infinities of float and double."""
    rng = np.random.default_rng(5)
    cols = {"b": np.array([-128, 127, 0, -1], ">i1"), "B": np.array([0, 255, 128, 1], "u1"),
            "h": np.array([-2**15, 2**15 - 1, 0, -2], ">i2"), "i": np.array([-2**31, 2**31 - 1, 7, -9], ">i4"),
            "q": np.array([-2**63, 2**63 - 1, 2**53 + 1, -(2**53) - 3], ">i8"),
            "f": np.array([np.nan, -np.inf, 1e-40, 3.4e38], ">f4"), "d": np.array([np.nan, np.inf, -0.0, 1e-310], ">f8")}
    n = 4
    rec = np.zeros(n, dtype=[(c, v.dtype) for c, v in cols.items()])
    for c, v in cols.items():
        rec[c] = v
    pad = bytes(rng.integers(0, 256, 5, dtype=np.uint8))
    data = pad + rec.tobytes()
    at = np.arange(n, dtype=np.int64) * rec.dtype.itemsize + len(pad)
    for c, v in cols.items():
        offset = rec.dtype.fields[c][1]
        kinds = [0] if c in "fd" else [0, 1, 2]
        for kind in kinds:
            out = np.empty(n, dtype=np.float64 if kind == 0 else np.int64)
            kernel.decode(data, at, [(offset, c, 1, kind, out)])
            with np.errstate(invalid="ignore"):    # 2^63 - 1 through float64 is out of range: numpy's INT64_MIN
                want = v.astype(np.float64) if kind == 0 else (v.astype(np.int64) if kind == 1 else
                                                                v.astype(np.float64).astype(np.int64))
            assert out.tobytes() == want.astype(out.dtype).tobytes(), (c, kind)
