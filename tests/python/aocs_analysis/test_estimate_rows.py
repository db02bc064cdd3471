"""The estimation section's rows (run_metrics._estimate_rows): one per control step from the first answered tick
to the last, a tick whose frame was dropped (no reply) holding the previous reply, flagged held; without gaps the
rows are the answered ticks as before."""
import numpy as np

from aocs_analysis.run_metrics import _estimate_rows


def test_no_gap_pairs_every_answered_tick():
    it, ic, held = _estimate_rows(np.arange(11), np.arange(10))    # truth 0..10, replies 0..9 (the last tick none)
    np.testing.assert_array_equal(it, np.arange(10))
    np.testing.assert_array_equal(ic, np.arange(10))
    assert not held.any()


def test_dropped_ticks_hold_the_previous_reply_and_are_flagged():
    replies = np.array([0, 1, 2, 5, 6])          # ticks 3 and 4 dropped
    it, ic, held = _estimate_rows(np.arange(8), replies)
    np.testing.assert_array_equal(it, np.arange(7))
    np.testing.assert_array_equal(ic, [0, 1, 2, 2, 2, 3, 4])
    np.testing.assert_array_equal(held, [False, False, False, True, True, False, False])


def test_no_reply_at_all():
    it, ic, held = _estimate_rows(np.arange(5), np.zeros(0, np.int64))
    assert it.size == ic.size == held.size == 0
