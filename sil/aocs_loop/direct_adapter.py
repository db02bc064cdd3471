"""The in-process transport (`--transport direct`): fsw_node's node logic loaded into the plant's process.

The shared library build/host/lib/libaocs_node_direct.so (sil/fsw_node/direct/aocs_node_direct.h) is the
same flight library and the same node logic as fsw_node (sil/fsw_node/node_core.c: configuration parsing,
sensors_t decoding and frame checks, the executive step, actuator_cmd_t encoding), called through a small
C ABI with the wire contract's bytes: a sensors_t payload in, the actuator_cmd_t payload fsw_node would
publish out. So a direct run and an LCM lockstep run of the same scenario and seed give the same command
history, bit for bit (tests/python/test_direct_transport.py; docs/sil.md, "Transports").

- DirectNode: one open node (ctypes over the C ABI);
- DirectFlightComputer: core.FlightComputer over a DirectNode (LcmCodec packing, as LcmFlightComputer);
- DirectBus: the LCM handle's interface (subscribe, subscribe_all, publish, handle_timeout) over a
  DirectNode, delivering the node's replies synchronously: plant_node's lockstep loop runs on it unchanged.
"""
from __future__ import annotations

import ctypes
import json
import time
from pathlib import Path

from aocs_core import paths
from aocs_wire import wire

from .frames import Reply, SensorFrame
from .lcm_adapter import LcmCodec

#: the C ABI version this module speaks (aocs_direct_abi_version)
ABI_VERSION = 2
LIB_NAME = "libaocs_node_direct.so"
#: reply buffer, bytes: above the largest actuator_cmd_t (782 bytes in protocol version 4) and status_t payload
REPLY_CAP = 2048
REPORT_CAP = 8192
ERR_CAP = 1024


class DirectError(RuntimeError):
    """The in-process node refused its configuration, or a call failed (the message says which)."""


def library_path() -> Path:
    return paths.build_dir() / "lib" / LIB_NAME


_lib = None


def library():
    """The loaded node library (once per process), its functions typed."""
    global _lib
    if _lib is not None:
        return _lib
    path = library_path()
    if not path.is_file():
        raise paths.SetupError(f"in-process node library not found at {path}; {paths.BUILD_HINT}")
    lib = ctypes.CDLL(str(path))
    i32, i64, u32, cp, vp = ctypes.c_int32, ctypes.c_int64, ctypes.c_uint32, ctypes.c_char_p, ctypes.c_void_p
    for name, res, args in (
            ("aocs_direct_abi_version", i32, ()),
            ("aocs_direct_open", i32, (cp, cp, vp, u32)),
            ("aocs_direct_sensors", i32, (i32, cp, u32, vp, u32)),
            ("aocs_direct_command", i32, (i32, cp, u32, i64, vp, u32)),
            ("aocs_direct_status", i32, (i32, i32, i64, vp, u32)),
            ("aocs_direct_event", i32, (i32, vp, u32)),
            ("aocs_direct_report", i32, (i32, cp, vp, u32)),
            ("aocs_direct_last_request", i32, (i32, ctypes.POINTER(i64), ctypes.POINTER(i32))),
            ("aocs_direct_close", i32, (i32,))):
        f = getattr(lib, name)
        f.restype, f.argtypes = res, args
    version = lib.aocs_direct_abi_version()
    if version != ABI_VERSION:
        raise paths.SetupError(f"{path}: C ABI version {version}, this checkout speaks {ABI_VERSION}; "
                               f"{paths.BUILD_HINT}")
    _lib = lib
    return lib


class DirectNode:
    """One in-process flight computer, configured from fsw_node's configuration text."""

    def __init__(self, config_text: str, name: str = "fsw_node.cfg"):
        self.lib = lib = library()
        err = ctypes.create_string_buffer(ERR_CAP)
        h = lib.aocs_direct_open(config_text.encode(), name.encode(), err, ERR_CAP)
        if h < 0:
            raise DirectError(f"config error: {err.value.decode(errors='replace')}")
        self.handle = h
        self._out = ctypes.create_string_buffer(REPLY_CAP)
        self._string_at = ctypes.string_at
        # the hot calls, once per control period: the same functions without argtypes (ctypes converts a bytes,
        # an int and the buffer natively; the typed call's conversions cost ~1.5 us of ~4 per period)
        untyped = ctypes.CDLL(str(library_path()))
        self._sensors = untyped.aocs_direct_sensors
        self._sensors.restype = ctypes.c_int32
        self._event = untyped.aocs_direct_event
        self._event.restype = ctypes.c_int32

    @classmethod
    def from_file(cls, path) -> "DirectNode":
        path = Path(path)
        return cls(path.read_text(), str(path))

    def sensors(self, data: bytes) -> bytes | None:
        """The actuator_cmd_t payload of one sensors_t payload's step; None when it got no reply (dropped,
        malformed, foreign: counted as fsw_node counts them)."""
        out = self._out
        n = self._sensors(self.handle, data, len(data), out, REPLY_CAP)
        if n > 0:
            return out.raw[:n]
        if n == 0:
            return None
        raise DirectError(f"aocs_direct_sensors failed ({n})")

    def command(self, data: bytes, utime_us: int) -> bytes | None:
        """The status_t acknowledgement of one command_t payload; None for a malformed or foreign one."""
        n = self.lib.aocs_direct_command(self.handle, data, len(data), utime_us, self._out, REPLY_CAP)
        if n < 0:
            raise DirectError(f"aocs_direct_command failed ({n})")
        return self._string_at(self._out, n) if n else None

    def events(self) -> list[bytes]:
        """The event_t payloads the steps since the last call raised (fault management), in order: the
        messages fsw_node publishes on AOCS_EVENTS."""
        out = []
        while True:
            n = self._event(self.handle, self._out, REPLY_CAP)   # untyped: the hot call (see __init__)
            if n < 0:
                raise DirectError(f"aocs_direct_event failed ({n})")
            if n == 0:
                return out
            out.append(self._string_at(self._out, n))

    def last_request(self) -> tuple[int, int]:
        """(request id, status) of the last command applied (status 0 = accepted)."""
        req, st = ctypes.c_int64(), ctypes.c_int32()
        self.lib.aocs_direct_last_request(self.handle, ctypes.byref(req), ctypes.byref(st))
        return req.value, st.value

    def status(self, exiting: bool, utime_us: int) -> bytes:
        n = self.lib.aocs_direct_status(self.handle, int(exiting), utime_us, self._out, REPLY_CAP)
        if n <= 0:
            raise DirectError(f"aocs_direct_status failed ({n})")
        return self._string_at(self._out, n)

    def report(self, reason: str) -> dict:
        """fsw_node's exit summary {"fsw_node": {...}} as a dict."""
        buf = ctypes.create_string_buffer(REPORT_CAP)
        n = self.lib.aocs_direct_report(self.handle, reason.encode(), buf, REPORT_CAP)
        if n <= 0:
            raise DirectError(f"aocs_direct_report failed ({n})")
        return json.loads(buf.value.decode())

    def close(self) -> None:
        if self.handle is not None:
            self.lib.aocs_direct_close(self.handle)
            self.handle = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()


class DirectFlightComputer:
    """core.FlightComputer in process: step() packs the frame's sensors_t (LcmCodec, as LcmFlightComputer),
    runs the node on it and reads its actuator_cmd_t back. Raises DirectError when the node gives no reply
    (a frame it dropped): the loop does not invent a command. The events each step raised are kept in
    `events` (event_t payloads, in order)."""

    def __init__(self, node: DirectNode, codec: LcmCodec):
        self.node, self.codec = node, codec
        self.events: list[bytes] = []

    def step(self, frame: SensorFrame) -> Reply:
        data = self.node.sensors(self.codec.pack_sensors(frame))
        if data is None:
            raise DirectError(f"no actuator_cmd_t for tick {frame.tick}: the node dropped its sensors_t")
        self.events.extend(self.node.events())
        return self.codec.reply(self.codec.unpack(data))

    def close(self) -> None:
        self.node.close()


def _utime() -> int:
    return time.time_ns() // 1000


class DirectBus:
    """The LCM handle's interface over a DirectNode, for plant_node's loop (aocs_runner.plant_node).

    publish(channel, data) hands every message to the subscribe_all handler first (the recording plant
    logs its own messages, as it does from the udpm socket), then to the node: a sensors_t payload comes
    back as the node's actuator_cmd_t, a command_t as its status_t acknowledgement, each delivered at once
    to subscribe_all and to the channel's handler. heartbeat() queues a status_t that the next
    handle_timeout() delivers (the flight computer's first heartbeat). Channels are given to the handlers
    as bytes (as aocs_wire.udpm.Udpm does)."""

    def __init__(self, node: DirectNode):
        self.node = node
        self._handlers: dict[bytes, object] = {}
        self._every = None
        self._queue: list[tuple[bytes, bytes]] = []
        self._sensors = node.sensors
        self._ch_sensors, self._ch_actuator = wire.SENSORS.encode(), wire.ACTUATOR.encode()
        self._ch_command, self._ch_status = wire.COMMAND.encode(), wire.STATUS.encode()
        self._ch_events = wire.EVENTS.encode()

    def subscribe(self, channel: str, handler) -> str:
        self._handlers[channel.encode()] = handler
        return channel

    def subscribe_all(self, handler) -> str:
        self._every = handler
        return "*"

    def unsubscribe(self, token: str) -> None:
        if token == "*":
            self._every = None
        self._handlers.pop(token.encode(), None)

    def _deliver(self, ch: bytes, data: bytes) -> None:
        if self._every is not None:
            self._every(ch, data)
        h = self._handlers.get(ch)
        if h is not None:
            h(ch, data)

    def publish(self, channel: str | bytes, data: bytes) -> None:
        ch = channel.encode() if isinstance(channel, str) else channel
        every = self._every
        if every is not None:
            every(ch, data)
        if ch == self._ch_sensors:
            reply = self._sensors(data)
            if reply is not None:
                self._deliver(self._ch_actuator, reply)
                for ev in self.node.events():       # after the reply, as fsw_node publishes them
                    self._deliver(self._ch_events, ev)
        elif ch == self._ch_command:
            ack = self.node.command(data, _utime())
            if ack is not None:
                self._deliver(self._ch_status, ack)

    def heartbeat(self, exiting: bool = False) -> None:
        """The node's status_t, delivered by the next handle_timeout (exiting: its last one)."""
        self._queue.append((self._ch_status, self.node.status(exiting, _utime())))

    def handle_timeout(self, timeout_ms: int) -> int:  # noqa: ARG002 - nothing to wait for in process
        q, self._queue = self._queue, []
        for ch, data in q:
            self._deliver(ch, data)
        return len(q)
