"""The PIL bridge's frame-counter rule (aocs_pil.sequence) is fsw_node's (node_wire.c): the cases of
tests/unit/test_node_wire.c, and the attack of issue 11 (one INT64_MAX frame must not silence it)."""
from __future__ import annotations

from aocs_pil.sequence import FrameSequence

INT64_MAX, INT64_MIN = 2 ** 63 - 1, -2 ** 63


def _feed(frames):
    s = FrameSequence()
    return s, [s.check(f) for f in frames]


def test_in_order_gaps_duplicates():
    s, r = _feed([0, 1, 2, 5, 5, 3, 6])
    assert r == ["ok", "ok", "ok", "gap", "duplicate", "duplicate", "ok"]
    assert (s.lost, s.duplicate) == (2, 2)


def test_one_forged_frame_far_ahead_is_dropped_and_the_next_legitimate_frame_accepted():
    s, r = _feed([10, 11, INT64_MAX, 12, 13])
    assert r == ["ok", "ok", "jump", "ok", "ok"] and s.jump == 1 and s.lost == 0


def test_int64_min_after_int64_max_is_no_overflow():
    s, r = _feed([INT64_MAX, INT64_MIN, INT64_MIN + 1])   # wraps by one: a continuation modulo 2^64
    assert r == ["ok", "ok", "ok"]


def test_a_real_restart_resynchronises_after_k_consistent_frames():
    w, k = FrameSequence().window, FrameSequence().resync_frames
    far = 10 + 10 * w
    s, r = _feed([10, 11] + [far + i for i in range(k)] + [far + k])
    assert r[2:2 + k - 1] == ["jump"] * (k - 1) and r[1 + k] == "resync" and r[-1] == "ok"
    assert s.resyncs == 1 and w == 1024 and k == 3
