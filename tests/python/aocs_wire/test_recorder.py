"""The runner's log recorder and the log reader (aocs_wire.recorder, aocs_wire.lcmlog).

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import time

import numpy as np

from aocs_wire import wire


def test_recorder_writes_a_standard_lcm_log_without_dropping(private_netns, aocs_lcm, tmp_path):
    import lcm

    from aocs_wire import lcmlog
    from aocs_wire.recorder import Recorder

    path = tmp_path / "r.lcmlog"
    rec = Recorder(path).start(note="test")
    lc = lcm.LCM(__import__("aocs_wire.netns", fromlist=["LCM_URL"]).LCM_URL)
    codecs = wire.Codecs(aocs_lcm)
    sent = []
    # every field after the header (tick, t_s): 0.5 for doubles, 0 for integers
    tail = [v for (_, n), typ in list(zip(codecs.truth.fields, aocs_lcm.truth_t.__typenames__))[5:]
            for v in [0.5 if typ == "double" else 0] * (1 if n is None else n)]
    for k in range(1000):       # a burst far above LCM's default 30-message queue
        data = codecs.truth.pack(1, k, k, k, 0.1 * k, *tail)
        lc.publish(wire.TRUTH, data)
        sent.append(data)
        if k % 500 == 0:
            lc.publish("OTHER", b"raw bytes")
    rec.stop()
    log = lcm.EventLog(str(path), "r")
    got = [(e.channel, e.data) for e in log]
    log.close()
    truth = [d for c, d in got if c == wire.TRUTH]
    assert truth == sent
    assert sum(1 for c, _ in got if c == "OTHER") == 2
    assert [c for c, _ in got if c == wire.RUNNER][0:1] == [wire.RUNNER]
    parsed = lcmlog.read(path)
    assert parsed.truth["tick"].tolist() == list(range(1000))
    assert parsed.truth["t_s"][7] == 0.1 * 7
    assert [m["marker"] for m in parsed.markers][0] == "start" and parsed.markers[-1]["marker"] == "end"
    # event timestamps are receive times (us since the epoch), non-decreasing
    assert np.all(np.diff(parsed.truth["log_utime"]) >= 0)
    assert abs(parsed.truth["log_utime"][0] / 1e6 - time.time()) < 600


def _fds_and_threads() -> tuple[int, int]:
    import os

    return len(os.listdir("/proc/self/fd")), len(os.listdir("/proc/self/task"))


def _no_more(now, before):
    """Not one descriptor or thread more than before (fewer: another test's ends in between). A joined
    Python thread may still be listed in /proc for a moment (join returns when its Python part is done,
    before the kernel task is gone): the thread count gets up to 1 s to come down."""
    end = time.monotonic() + 1.0
    while now[1] > before[1] and time.monotonic() < end:
        time.sleep(0.01)
        now = (now[0], _fds_and_threads()[1])
    return now[0] <= before[0] and now[1] <= before[1]


def test_recorder_frees_its_lcm_handles_after_its_thread_stops(private_netns, tmp_path):
    """A campaign worker records hundreds of runs in one process: every recorder must give back its
    sockets, pipes and LCM receive thread. Before the fix each start/stop leaked 9 descriptors and a
    thread (pylcm objects are not freed by Python's cycle collector); past FD_SETSIZE (1024) LCM's
    select() overran its fd_set and the worker segfaulted in _lcm.so."""
    from aocs_wire.recorder import Recorder

    Recorder(tmp_path / "warm.lcmlog").start().stop()   # one-time state (imports, glib) out of the count
    before = _fds_and_threads()
    for k in range(20):
        Recorder(tmp_path / f"{k}.lcmlog").start().stop()
    assert _no_more(_fds_and_threads(), before), (_fds_and_threads(), before)
    # never started: stop() itself frees the handle (no thread reads it)
    Recorder(tmp_path / "idle.lcmlog").stop()
    assert _no_more(_fds_and_threads(), before), (_fds_and_threads(), before)


def test_recorder_sockets_are_closed_by_their_reader_thread_not_under_it(private_netns, tmp_path):
    """The sockets are closed by the thread that reads them, after its last read: held in its handler
    while stop() gives up waiting, the thread still has open sockets, and closes them itself once it
    leaves."""
    import threading

    from aocs_wire.recorder import Recorder

    Recorder(tmp_path / "warm.lcmlog").start().stop()
    before = _fds_and_threads()
    rec = Recorder(tmp_path / "held.lcmlog").start()
    gate = threading.Event()
    inner = rec._on_message

    def held(channel, data):   # the reader thread blocks inside a handle_timeout call
        inner(channel, data)
        if channel == b"PING":
            gate.wait(30)

    link = rec._link
    link.subscribe_all(held)
    link.publish("PING", b"x")
    time.sleep(0.2)
    rec._stop.set()
    rec._thread.join(0.2)
    assert rec._thread.is_alive() and rec._link is link and link._rx.fileno() >= 0   # not closed under it
    gate.set()
    rec._thread.join(10)
    assert not rec._thread.is_alive() and rec._link is None and link._rx.fileno() == -1
    del link
    rec.stop()
    assert _no_more(_fds_and_threads(), before), (_fds_and_threads(), before)


def test_recorder_records_a_fragmented_message_whole(private_netns, tmp_path):
    """A message above one datagram (the library sends it as LC03 fragments) is recorded as one event."""
    import lcm

    from aocs_wire import lcmlog, netns
    from aocs_wire.recorder import Recorder

    path = tmp_path / "f.lcmlog"
    rec = Recorder(path).start()
    big = bytes(range(256)) * 1000          # 256 kB: five fragments of the library's 64 kB
    lc = lcm.LCM(netns.LCM_URL)
    lc.publish("BIG", big)
    lc.publish("SMALL", b"after")
    rec.stop()
    events = [(e.channel, e.data) for e in lcm.EventLog(str(path), "r")]
    assert ("BIG", big) in events and ("SMALL", b"after") in events
    assert [c for c, _ in events].index("BIG") < [c for c, _ in events].index("SMALL")
    assert lcmlog.scan(path).events == len(events)
