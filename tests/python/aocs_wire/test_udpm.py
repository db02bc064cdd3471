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


# --- the bounded reassembly of fragmented messages (issue 25, item 2) ---------------------------------


def _send(datagrams):
    """Raw datagrams to the run's udpm group (a forger on the bus)."""
    import socket

    from aocs_wire import netns
    from aocs_wire.udpm import parse_url

    group, port, _ = parse_url(netns.LCM_URL)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    for d in datagrams:
        s.sendto(d, (group, port))
    s.close()


def _fragment(seq, size, offset, no, count, body):
    import struct

    from aocs_wire.udpm import MAGIC_LONG
    return struct.pack(">IIIIHH", MAGIC_LONG, seq, size, offset, no, count) + body


def _drain(link, until, timeout=5.0):
    end = time.monotonic() + timeout
    while not until() and time.monotonic() < end:
        link.handle_timeout(20)


def test_the_bound_is_derived_from_the_wire_types_and_above_lcm_fragmentation(private_netns):
    """The bound is BOUND_MARGIN x the largest aocs_lcm message, whose size the generated bindings give
    independently of the fast codecs; it is above LCM's fragmentation threshold (65,499 bytes)."""
    import io

    from aocs_core import paths
    from aocs_wire import udpm

    t = paths.import_bindings()
    sizes = []
    for cls in (t.sensors_t, t.actuator_cmd_t, t.truth_t, t.command_t, t.status_t):
        buf = io.BytesIO()
        cls()._encode_one(buf)
        sizes.append(8 + len(buf.getvalue()))   # fingerprint + fields
    assert udpm.largest_wire_message() == max(sizes)
    assert udpm.max_message_size() == udpm.BOUND_MARGIN * max(sizes) > 65499
    assert udpm.max_message_size() < 1 << 20


def test_a_forged_fragment_claiming_256_mib_allocates_nothing_and_is_counted(private_netns):
    import tracemalloc

    from aocs_wire import netns
    from aocs_wire.udpm import Udpm

    link = Udpm(netns.LCM_URL)
    got = []
    link.subscribe_all(lambda c, d: got.append((c, d)))
    tracemalloc.start()
    _send([_fragment(7, 256 << 20, 0, 0, 2, b"AOCS_X\0" + b"x" * 7)])
    _drain(link, lambda: link.fragments >= 1)
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    assert link.oversize == 1 and link.fragments == 1 and not got
    assert link.partial_bytes == 0 and link.counters["partial"] == 0
    assert peak < 1 << 20, peak
    link.close()


def test_never_completed_partials_are_bounded_aged_out_and_counted(private_netns, monkeypatch):
    from aocs_wire import netns, udpm

    link = udpm.Udpm(netns.LCM_URL)
    link.subscribe_all(lambda c, d: None)
    size = 100_000
    _send([_fragment(100 + i, size, 0, 0, 2, b"AOCS_X\0" + b"y" * 1000) for i in range(20)])
    _drain(link, lambda: link.fragments >= 20)
    assert link.fragments == 20
    assert link.counters["partial"] == udpm.MAX_PARTIAL and link.incomplete == 20 - udpm.MAX_PARTIAL
    assert link.partial_bytes == udpm.MAX_PARTIAL * size
    monkeypatch.setattr(udpm, "PARTIAL_MAX_AGE_S", 0.05)
    time.sleep(0.1)
    _send([_fragment(500, size, 0, 0, 2, b"AOCS_X\0" + b"z" * 10)])
    _drain(link, lambda: link.fragments >= 21)
    assert link.expired == udpm.MAX_PARTIAL and link.counters["partial"] == 1
    assert link.counters == {"fragments": 21, "garbage": 0, "incomplete": 4, "expired": 16, "oversize": 0,
                             "partial": 1}
    link.close()


def test_a_real_fragmented_message_of_the_lcm_library_still_reassembles(private_netns):
    import lcm

    from aocs_wire import netns
    from aocs_wire.udpm import Udpm

    link = Udpm(netns.LCM_URL)
    got = []
    link.subscribe_all(lambda c, d: got.append((c, d)))
    lib = lcm.LCM(netns.LCM_URL)
    payload = bytes(range(256)) * 400      # 102,400 bytes: fragmented by the library
    assert len(payload) < link.max_message
    lib.publish("AOCS_TEST_BIG", payload)
    lib.publish("AOCS_TEST_SMALL", b"after")
    _drain(link, lambda: len(got) >= 2)
    assert got == [(b"AOCS_TEST_BIG", payload), (b"AOCS_TEST_SMALL", b"after")]
    assert link.fragments >= 2 and link.oversize == link.garbage == link.incomplete == link.expired == 0
    assert link.counters["partial"] == 0
    link.close()


def test_a_spinning_wait_sees_a_message_that_comes_while_it_polls(private_netns):
    """spin_us: a wait polls before it sleeps. With a zero timeout (no sleeping wait at all) only the spin can
    see a message sent 20 ms later; without it the same call returns at once with nothing."""
    import threading

    from aocs_wire import netns
    from aocs_wire.udpm import Udpm

    tx = Udpm(netns.LCM_URL, receive=False)
    for spin_us, want in ((0.0, []), (2e6, [b"spun"])):
        rx = Udpm(netns.LCM_URL, spin_us=spin_us)
        got = []
        rx.subscribe("AOCS_SPIN", lambda c, d: got.append(d))   # noqa: B023 - used before the next loop
        timer = threading.Timer(0.02, tx.publish, ("AOCS_SPIN", b"spun"))
        timer.start()
        n = rx.handle_timeout(0)
        timer.join()
        assert (n, got) == (len(want), want), spin_us
    quiet = Udpm(netns.LCM_URL, spin_us=1000.0)
    assert quiet.handle_timeout(0) == 0         # nothing comes: the spin ends, nothing is invented


@pytest.mark.parametrize("spin_us", [-1.0, float("nan"), float("inf")])
def test_a_spin_that_is_not_a_finite_duration_is_refused(private_netns, spin_us):
    from aocs_wire import netns
    from aocs_wire.udpm import Udpm

    with pytest.raises(ValueError, match="spin_us"):
        Udpm(netns.LCM_URL, spin_us=spin_us)
