"""LCM's UDP multicast transport (udpm), spoken directly from Python, for the
plant's lockstep hot loop.

Same packets as the LCM library (interoperable both ways, tested against it in
tests/python/aocs_wire/test_udpm.py): a short message is ONE datagram sent to the
multicast group,

    uint32 magic 0x4c433032 ("LC02") | uint32 sequence number | channel | NUL | payload

(big-endian). Every aocs_lcm type is far below the 64 kB datagram limit, so
the fragmented form ("LC03") is never sent; received fragments are counted
and, for a catch-all subscription (the run's recorder), put back together
(the library's format: a 20-byte header magic | sequence | message size |
fragment offset | uint16 fragment number | uint16 fragment count, the channel
and its NUL in fragment 0 only). The reassembly is bounded (issue 25): a
message of at most max_message bytes (BOUND_MARGIN x the largest aocs_lcm
type), at most MAX_PARTIAL partial messages, each for at most
PARTIAL_MAX_AGE_S; what it drops is counted (counters).

Why: the LCM library receives on a background thread and hands each message
to the caller's thread through a pipe, two thread switches per message on a
2-core machine whose other core runs the flight computer. Reading the socket
directly in the plant's own thread saved ~10 us of the ~60 us Python <->
fsw_node round trip (measured, 5000 ping-pongs). Publishing is a plain
sendto, as in the library. The recorder reads with this class too, and fsw_node
with its own C reader (sil/fsw_node/node_udpm.c, the same reasons); lcm-logger
and every LCM tool keep using the library; none can tell the difference. handle_timeout asks the
socket with a zero-timeout poll before each read instead of reading until a
recv fails: a failed non-blocking recv (and its exception) costs several times
an empty poll, and a lockstep tick ended three reads that way.

spin_us (the plant's lockstep wait, like fsw_node's `wait_spin_us`): a wait polls the socket this long, giving
the CPU up between tries (os.sched_yield), before it sleeps in poll: on a virtual machine a process asleep on
an idle CPU takes some 20 us to wake, as long as the flight computer's whole answer (docs/benchmarks.md,
"Waiting without sleeping").
"""
from __future__ import annotations

import functools
import os
import select
import socket
import struct
import time
from urllib.parse import parse_qs, urlparse

MAGIC_SHORT = 0x4C433032   # "LC02"
MAGIC_LONG = 0x4C433033    # "LC03" (fragment)
_HEAD = struct.Struct(">II")
_FRAG = struct.Struct(">IIIIHH")
#: messages being put together from fragments at once (the oldest is dropped when a 17th starts, counted
#: as incomplete)
MAX_PARTIAL = 16
#: a partial message whose first fragment came longer ago than this is dropped (counted as expired): LCM
#: sends a message's fragments back to back, so a real one completes within milliseconds
PARTIAL_MAX_AGE_S = 1.0
#: the largest message reassembled is BOUND_MARGIN times the largest aocs_lcm message (max_message_size):
#: room for the wire contract to grow and for other LCM traffic on the group, and above LCM's
#: fragmentation threshold (a message is fragmented only from ~65,500 bytes on), so a real fragmented
#: message still goes through (the recorder's test records a 256 kB one); a fragment claiming more is
#: dropped before anything is allocated. 1024 x 575 bytes (actuator_cmd_t, protocol 3) = 588,800 bytes;
#: at most MAX_PARTIAL of them held: ~9.4 MB, where a forger could make the reader hold 16 x 4 GiB
BOUND_MARGIN = 1024


@functools.lru_cache(maxsize=None)
def largest_wire_message() -> int:
    """Encoded size in bytes of the largest aocs_lcm type (every one is fixed size: aocs_wire.wire.Codec)."""
    from aocs_core import paths  # deferred: the generated bindings are imported only when a reader is built

    from .wire import Codecs  # deferred: wire imports the bindings too; udpm stays importable without a build

    c = Codecs(paths.import_bindings())
    return max(x.size for x in (c.sensors, c.actuator, c.truth, c.command, c.status))


def max_message_size() -> int:
    """The bound on a reassembled message's size, bytes: BOUND_MARGIN x largest_wire_message()."""
    return BOUND_MARGIN * largest_wire_message()


def parse_url(url: str) -> tuple[str, int, int]:
    """(group, port, ttl) of a udpm:// URL."""
    u = urlparse(url)
    if u.scheme != "udpm":
        raise ValueError(f"{url}: only udpm:// URLs are supported")
    ttl = int(parse_qs(u.query).get("ttl", ["0"])[0])
    return u.hostname, int(u.port), ttl


class Udpm:
    """Publish and receive LCM messages on one udpm group, in the caller's thread."""

    def __init__(self, url: str, recv_buf: int = 4 * 1024 * 1024, receive: bool = True,
                 max_message: int | None = None, spin_us: float = 0.0):
        """receive=False: a publisher only (no socket joins the group, so no message is queued for it).
        max_message: the largest fragmented message put back together, bytes (default max_message_size()).
        spin_us: how long a wait polls before it sleeps (module docstring), us; 0 sleeps at once."""
        group, port, ttl = parse_url(url)
        self.dest = (group, port)
        rx = None
        if receive:
            rx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
            rx.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
            if hasattr(socket, "SO_REUSEPORT"):
                rx.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
            rx.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, recv_buf)
            rx.bind(("", port))
            mreq = struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0"))
            rx.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP, mreq)
            rx.setblocking(False)
        tx = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
        tx.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, ttl)
        tx.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_LOOP, 1)
        self._rx, self._tx = rx, tx
        self._seq = 0
        if not (0.0 <= spin_us < float("inf")):
            raise ValueError(f"spin_us {spin_us!r}: must be a finite number of us, at least 0")
        self._spin_ns = int(spin_us * 1000.0)
        self._poll = select.poll()
        if rx is not None:
            self._poll.register(rx, select.POLLIN)
        self.fragments = 0     # LC03 datagrams received (never sent by aocs types)
        self.garbage = 0       # datagrams that are not LCM at all
        self.incomplete = 0    # partial messages dropped for MAX_PARTIAL newer ones
        self.expired = 0       # partial messages dropped PARTIAL_MAX_AGE_S after their first fragment
        self.oversize = 0      # fragments claiming a message above max_message (nothing allocated)
        self.max_message = (max_message if max_message is not None
                            else max_message_size() if receive else 0)
        self._handlers: dict[bytes, object] = {}
        self._every = None     # handler(channel bytes, data) of every message, whatever its channel
        self._partial: dict[tuple, list] = {}

    @property
    def counters(self) -> dict:
        """What the reader received outside the short-message path, and what it dropped."""
        return {"fragments": self.fragments, "garbage": self.garbage, "incomplete": self.incomplete,
                "expired": self.expired, "oversize": self.oversize, "partial": len(self._partial)}

    @property
    def partial_bytes(self) -> int:
        """Bytes held by the partial messages."""
        return sum(len(p[1]) for p in self._partial.values())

    def fileno(self) -> int:
        return self._rx.fileno()

    def publish(self, channel: str | bytes, data: bytes) -> None:
        ch = channel.encode() if isinstance(channel, str) else channel
        self._tx.sendto(_HEAD.pack(MAGIC_SHORT, self._seq & 0xFFFFFFFF) + ch + b"\0" + data, self.dest)
        self._seq += 1

    def subscribe(self, channel: str, handler) -> str:
        """handler(channel, data) for exactly this channel (no regex: the hot loop needs speed).
        Returns the token for unsubscribe (as lcm.LCM.subscribe does)."""
        self._handlers[channel.encode()] = handler
        return channel

    def unsubscribe(self, token: str) -> None:
        if token == "*":
            self._every = None
        self._handlers.pop(token.encode(), None)

    def subscribe_all(self, handler) -> str:
        """handler(channel, data) for every message on the group, whatever its channel, called before
        the channel's own handler, the channel as the datagram's bytes (no decoding: a recorder writes
        them as they are); fragmented messages are put together first. Token "*"."""
        self._every = handler
        return "*"

    def _fragment(self, d: bytes):
        """(channel bytes, data) once the last fragment of a message has come, else None."""
        if len(d) < _FRAG.size:
            self.garbage += 1
            return None
        _, seq, size, offset, no, count = _FRAG.unpack_from(d)
        body = d[_FRAG.size:]
        if size > self.max_message:          # checked before anything is allocated
            self.oversize += 1
            return None
        if no >= count or (no != 0 and offset + len(body) > size):
            self.garbage += 1
            return None
        now = time.monotonic()
        partial = self._partial
        while partial:                       # oldest first (insertion order)
            k = next(iter(partial))
            if now - partial[k][3] <= PARTIAL_MAX_AGE_S:
                break
            del partial[k]
            self.expired += 1
        key = (seq, size, count)
        part = partial.get(key)
        if no == 0:
            end = body.find(b"\0")
            if end < 0:
                self.garbage += 1
                return None
            if offset + len(body) - (end + 1) > size:
                self.garbage += 1
                return None
        if part is None:
            part = partial[key] = [None, bytearray(size), 0, now]
        if no == 0:
            part[0] = body[:end]
            body = body[end + 1:]
        part[1][offset:offset + len(body)] = body
        part[2] += 1
        if len(partial) > MAX_PARTIAL:
            del partial[next(iter(partial))]
            self.incomplete += 1
        if part[2] == count and part[0] is not None and key in partial:
            del partial[key]
            return part[0], bytes(part[1])
        return None

    def _spin(self, poll) -> bool:
        """Polls without sleeping for at most spin_us, yielding the CPU between tries; True when a datagram came."""
        clock, yield_cpu = time.perf_counter_ns, os.sched_yield
        end = clock() + self._spin_ns
        while True:
            yield_cpu()
            if poll(0):
                return True
            if clock() >= end:
                return False

    def handle_timeout(self, timeout_ms: int) -> int:
        """Dispatch every datagram already queued, waiting at most timeout_ms for the first.

        Returns the number of handled (subscribed) messages, like lcm's
        handle_timeout (0 on timeout)."""
        handled = 0
        recv = self._rx.recv
        poll = self._poll.poll
        handlers = self._handlers
        waited = False
        while True:
            # asked before each read (module docstring): every call ends on an empty queue, found by a poll
            if not poll(0):
                if handled or waited:
                    return handled
                if not (self._spin_ns and self._spin(poll)) and not poll(max(0, int(timeout_ms))):
                    return 0
                waited = True
            try:
                d = recv(65536)
            except BlockingIOError:   # readiness without a datagram: ask again
                continue
            if len(d) < 9:
                self.garbage += 1
                continue
            magic = _HEAD.unpack_from(d)[0]
            if magic != MAGIC_SHORT:
                if magic == MAGIC_LONG:
                    self.fragments += 1
                    if self._every is not None:
                        whole = self._fragment(d)
                        if whole is not None:
                            self._every(*whole)
                            handled += 1
                else:
                    self.garbage += 1
                continue
            end = d.find(b"\0", 8)
            if end < 0:
                self.garbage += 1
                continue
            ch = d[8:end]
            h = handlers.get(ch)
            every = self._every   # read per datagram: a subscription made meanwhile (another thread) takes effect
            if every is not None:
                data = d[end + 1:]
                every(ch, data)
                if h is not None:
                    h(ch.decode(), data)
                handled += 1
            elif h is not None:
                h(ch.decode(), d[end + 1:])
                handled += 1

    def close(self) -> None:
        if self._rx is not None:
            self._rx.close()
        self._tx.close()
