"""The direct udpm reader (aocs_wire.udpm) against the LCM library.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import time

import pytest


def test_direct_udpm_interoperates_with_the_lcm_library(private_netns):
    """plant_node's socket-level udpm (udpm.py) and the LCM library understand each other."""
    import lcm

    from aocs_wire import netns
    from aocs_wire.udpm import Udpm, parse_url

    assert parse_url(netns.LCM_URL) == ("239.255.76.67", 7667, 0)
    with pytest.raises(ValueError):
        parse_url("tcpq://localhost:7700")
    lib = lcm.LCM(netns.LCM_URL)
    got_lib = []
    # unbounded queue: the burst below is far beyond LCM's default of 30 queued messages
    lib.subscribe("AOCS_X", lambda c, d: got_lib.append((c, d))).set_queue_capacity(0)
    direct = Udpm(netns.LCM_URL)
    got_direct = []
    tok = direct.subscribe("AOCS_Y", lambda c, d: got_direct.append((c, d)))
    payloads = [bytes([i % 256]) * (i * 37 % 1400) for i in range(200)]
    # in bursts of 10 (interoperability, not throughput: the library's socket buffer is small)
    for i, p in enumerate(payloads):           # direct -> library
        direct.publish("AOCS_X", p)
        end = time.monotonic() + 5
        while (i + 1) % 10 == 0 and len(got_lib) < i + 1 and time.monotonic() < end:
            lib.handle_timeout(50)
    assert got_lib == [("AOCS_X", p) for p in payloads]
    for i, p in enumerate(payloads):           # library -> direct; other channels ignored
        lib.publish("AOCS_Y", p)
        lib.publish("AOCS_Z", b"not subscribed")
        end = time.monotonic() + 5
        while (i + 1) % 10 == 0 and len(got_direct) < i + 1 and time.monotonic() < end:
            direct.handle_timeout(50)
    assert got_direct == [("AOCS_Y", p) for p in payloads]
    assert direct.handle_timeout(10) == 0      # nothing left, a bounded wait
    direct.unsubscribe(tok)
    lib.publish("AOCS_Y", b"after unsubscribe")
    assert direct.handle_timeout(50) == 0 and len(got_direct) == len(payloads)
    assert direct.garbage == 0 and direct.fragments == 0
    direct.close()
