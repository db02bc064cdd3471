"""The log reader's integrity checks (aocs_wire.lcmlog.scan, completeness_problems) on logs made here."""
from __future__ import annotations

import json

import pytest

from aocs_wire import lcmlog
from aocs_wire.recorder import encode_event


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


def test_tick_gaps_are_described():
    import numpy as np
    assert lcmlog._tick_gap(np.arange(5), 0, 4) is None
    assert lcmlog._tick_gap(np.array([0, 1, 3]), 0, None) == "tick 3 follows tick 1"
    assert lcmlog._tick_gap(np.array([1, 2]), 0, None) == "the first is 1, not 0"
    assert lcmlog._tick_gap(np.arange(3), 0, 9) == "the last is 2, not 9"
    assert lcmlog._tick_gap(np.zeros(0, int), 0, None) == "none at all"
    assert lcmlog._tick_gap(np.array([0, 1, 1, 2, 0]), 0, 2) is None   # duplicated / replayed frames
