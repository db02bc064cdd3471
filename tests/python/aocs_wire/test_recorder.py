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
