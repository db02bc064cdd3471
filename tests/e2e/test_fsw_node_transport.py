"""fsw_node's transport (sil/fsw_node/node_udpm.c): a udpm:// URL is read and written in the node's own thread,
any other URL through the LCM library. Both speak the library's datagrams: the test's side here is the LCM
library itself (lcm.LCM, tests/conftest.py Link), and raw datagrams a reader must survive."""
from __future__ import annotations

import socket
import struct

import pytest

from aocs_wire import netns
from aocs_wire.udpm import MAGIC_LONG, MAGIC_SHORT, parse_url


def _raw_sender():
    group, port, _ = parse_url(netns.LCM_URL)
    s = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    s.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
    return s, (group, port)


@pytest.mark.parametrize("spin", [None, "200", "10000"], ids=["sleeps", "spins_200us", "spins_10ms"])
def test_every_datagram_that_is_not_a_subscribed_message_is_skipped_and_the_node_answers_on(fsw_node, lcm_link,
                                                                                            spin):
    """Between lockstep frames: datagrams too short, of another magic, without the channel's NUL, a fragment
    (LC03, never an aocs message), a message on a channel the node does not read, an empty payload on
    AOCS_SENSORS (malformed: counted) -- every frame is still answered, in order, and nothing else counted;
    the same when the node's waits poll before they sleep (wait_spin_us, node_udpm.h)."""
    node = fsw_node() if spin is None else fsw_node(wait_spin_us=spin)
    node.wait_ready(lcm_link)
    s, dest = _raw_sender()
    junk = [b"", b"LC02", struct.pack(">II", 0x12345678, 1) + b"AOCS_SENSORS\0xx",
            struct.pack(">II", MAGIC_SHORT, 2) + b"AOCS_SENSORS_WITHOUT_NUL",
            struct.pack(">IIIIHH", MAGIC_LONG, 3, 40, 0, 0, 2) + b"AOCS_SENSORS\0" + b"\0" * 8,
            struct.pack(">II", MAGIC_SHORT, 4) + b"AOCS_OTHER\0payload"]
    try:
        for k in range(6):
            s.sendto(junk[k], dest)
            lcm_link.send_sensors(k, (0.0, 0.0, 0.0, 1.0), (0.01, 0.0, 0.0))
            lcm_link.wait_for("AOCS_ACTUATOR_CMD", k + 1)
        s.sendto(struct.pack(">II", MAGIC_SHORT, 5) + b"AOCS_SENSORS\0", dest)   # a sensors_t of no bytes
        lcm_link.send_sensors(6, (0.0, 0.0, 0.0, 1.0), (0.01, 0.0, 0.0))
        replies = lcm_link.wait_for("AOCS_ACTUATOR_CMD", 7)
    finally:
        s.close()
    assert [r.tick for r in replies] == list(range(7))
    assert node.stop() == 0
    st = node.stats()
    assert st["steps"] == 7 and st["sensor_frames"] == 8   # the empty one too
    assert st["malformed"] == 1 and st["foreign"] == 0


def test_a_url_that_is_not_udpm_goes_through_the_lcm_library(fsw_node, lcm_link):
    """memq:// (the library's in-process queue): the node starts on it, hears nothing from the group (the test's
    link gets no heartbeat) and ends on its idle timeout, a clean exit."""
    node = fsw_node(lcm_url="memq://", idle_timeout_s="0.5")
    assert node.proc.wait(timeout=10) == 0
    assert "ready" in node.stderr()
    assert node.stats()["reason"] == "idle"
    lcm_link.pump(0.05)
    assert not lcm_link.inbox["AOCS_STATUS"]


def test_a_udpm_url_the_node_cannot_read_is_refused_with_one_line(fsw_node, lcm_link):  # noqa: ARG001
    """A udpm URL whose address is not a multicast group cannot be joined: exit 1 with the URL named."""
    node = fsw_node(lcm_url="udpm://127.0.0.1:7667?ttl=0")
    assert node.proc.wait(timeout=10) == 1
    err = node.stderr()
    assert "udpm://127.0.0.1:7667" in err and "Traceback" not in err
