"""PIL frame codec, the host side of firmware/pil/include/aocs/pil_frame.h.

Byte for byte the same layouts as the C codec (firmware/pil/src/pil_frame.c);
tests/python/aocs_pil/test_frame.py checks the constants against the header and the
bytes against golden vectors that tests/unit/test_pil_frame.c also checks.
The CONFIG field ids are the law registry's (aocs_core.registry), never a copy.

Frame: magic u32 ("APIL"), version u8, type u8, length u16, seq u32, payload,
CRC-32 (zlib.crc32) of everything before it; little-endian; reals binary64.
"""
from __future__ import annotations

import math
import struct
import zlib
from dataclasses import dataclass, field

from aocs_core import registry

MAGIC = 0x4C495041
VERSION = 2
HEADER_BYTES = 12
CRC_BYTES = 4
PAYLOAD_MAX = 1024
FRAME_MAX = HEADER_BYTES + PAYLOAD_MAX + CRC_BYTES
ICOUNT_SHIFT = 7
TABLE_NAME_MAX = 31

TARGET_HOST, TARGET_CORTEX_M4F, TARGET_CORTEX_M7 = 0, 1, 2
TARGET_NAMES = {TARGET_HOST: "host", TARGET_CORTEX_M4F: "cortex-m4f", TARGET_CORTEX_M7: "cortex-m7"}

# aocs_pil_type_t
T_HELLO, T_CONFIG, T_CONFIG_ACK, T_STEP, T_STEP_REPLY, T_SELECT, T_SELECT_ACK, T_BYE, T_ERROR = range(1, 10)
TYPE_NAMES = {T_HELLO: "HELLO", T_CONFIG: "CONFIG", T_CONFIG_ACK: "CONFIG_ACK", T_STEP: "STEP",
              T_STEP_REPLY: "STEP_REPLY", T_SELECT: "SELECT", T_SELECT_ACK: "SELECT_ACK", T_BYE: "BYE",
              T_ERROR: "ERROR"}

# aocs_pil_err_t
ERR_NAMES = ["AOCS_PIL_OK", "AOCS_PIL_ERR_NULL_ARG", "AOCS_PIL_ERR_MAGIC", "AOCS_PIL_ERR_VERSION",
             "AOCS_PIL_ERR_LENGTH", "AOCS_PIL_ERR_CRC", "AOCS_PIL_ERR_TYPE", "AOCS_PIL_ERR_PAYLOAD",
             "AOCS_PIL_ERR_BUFFER", "AOCS_PIL_ERR_FIELD", "AOCS_PIL_ERR_STATE"]
ERR_MEANING = {
    "AOCS_PIL_ERR_MAGIC": "the frame does not start with the magic",
    "AOCS_PIL_ERR_VERSION": "another protocol version",
    "AOCS_PIL_ERR_LENGTH": "payload length out of range",
    "AOCS_PIL_ERR_CRC": "CRC mismatch: the frame was corrupted on the link",
    "AOCS_PIL_ERR_TYPE": "a frame type the image does not accept",
    "AOCS_PIL_ERR_PAYLOAD": "payload size wrong for its type",
    "AOCS_PIL_ERR_FIELD": "a configuration field the image refused",
    "AOCS_PIL_ERR_STATE": "a step or command before the configuration",
}

def cfg_fields() -> dict[str, tuple[int, str, int]]:
    """aocs_pil_cfg_field_t: name -> (id, kind, count); kind 'f' binary64, 'u' uint64, 's' name.

    The executive's fields (AOCS_PIL_EXEC_FIELD_ROWS of pil_frame.h) and every law field of
    laws.def, from the build's law registry."""
    return registry.load().pil_fields()


def cfg_name_by_id() -> dict[int, str]:
    return {v[0]: k for k, v in cfg_fields().items()}

HELLO = struct.Struct("<7I")
STEP = struct.Struct("<IQI19d")
STEP_REPLY = struct.Struct("<I5i6d6I10II2i7dIi3dd")
SELECT = struct.Struct("<iI7d")
ACK = struct.Struct("<2iI2i4I")
BYE_REPLY = struct.Struct("<4I")
ERROR = struct.Struct("<i3I")
_HEADER = struct.Struct("<IBBHI")
assert (HELLO.size, STEP.size, STEP_REPLY.size, SELECT.size, ACK.size, BYE_REPLY.size, ERROR.size) == \
    (28, 168, 244, 64, 36, 16, 16)


class FrameError(Exception):
    """A frame from the image failed its checks (magic, version, length, CRC, type, size)."""


def err_name(code: int) -> str:
    return ERR_NAMES[code] if 0 <= code < len(ERR_NAMES) else f"AOCS_PIL_ERR_UNKNOWN({code})"


def crc32(data: bytes) -> int:
    return zlib.crc32(data) & 0xFFFFFFFF


def encode(ftype: int, seq: int, payload: bytes = b"") -> bytes:
    if len(payload) > PAYLOAD_MAX:
        raise ValueError(f"payload of {len(payload)} bytes exceeds {PAYLOAD_MAX}")
    body = _HEADER.pack(MAGIC, VERSION, ftype, len(payload), seq & 0xFFFFFFFF) + payload
    return body + struct.pack("<I", crc32(body))


@dataclass(frozen=True)
class Header:
    version: int
    type: int
    length: int
    seq: int


def decode_header(buf: bytes) -> Header:
    """Checks magic, version and length of the first HEADER_BYTES (FrameError otherwise)."""
    if len(buf) < HEADER_BYTES:
        raise FrameError(f"header of {len(buf)} bytes, {HEADER_BYTES} expected")
    magic, version, ftype, length, seq = _HEADER.unpack_from(buf)
    if magic != MAGIC:
        raise FrameError(f"bad magic 0x{magic:08x} (expected 0x{MAGIC:08x}): not a PIL frame "
                         f"(first bytes {bytes(buf[:HEADER_BYTES]).hex()})")
    if version != VERSION:
        raise FrameError(f"protocol version {version}, this bridge speaks {VERSION}")
    if length > PAYLOAD_MAX:
        raise FrameError(f"payload length {length} above {PAYLOAD_MAX}")
    return Header(version, ftype, length, seq)


def check_frame(buf: bytes) -> tuple[Header, bytes]:
    """Whole frame -> (header, payload); FrameError on any failed check."""
    h = decode_header(buf)
    total = HEADER_BYTES + h.length + CRC_BYTES
    if len(buf) != total:
        raise FrameError(f"frame of {len(buf)} bytes, header says {total}")
    (crc,) = struct.unpack_from("<I", buf, HEADER_BYTES + h.length)
    if crc != crc32(buf[:HEADER_BYTES + h.length]):
        raise FrameError(f"CRC mismatch on a {TYPE_NAMES.get(h.type, h.type)} frame (seq {h.seq}): "
                         f"received 0x{crc:08x}, computed 0x{crc32(buf[:HEADER_BYTES + h.length]):08x}")
    return h, bytes(buf[HEADER_BYTES:HEADER_BYTES + h.length])


# ---- payloads ---------------------------------------------------------------
@dataclass(frozen=True)
class Hello:
    target: int
    real_bytes: int
    icount_shift: int
    calib_ok: int
    calib_measured: int
    calib_expected: int
    overhead: int

    @classmethod
    def decode(cls, p: bytes) -> "Hello":
        _need(p, HELLO, "HELLO")
        return cls(*HELLO.unpack(p))

    def encode(self) -> bytes:
        return HELLO.pack(self.target, self.real_bytes, self.icount_shift, self.calib_ok, self.calib_measured,
                          self.calib_expected, self.overhead)


WHEELS_MAX = 6   # AOCS_WHEELS_MAX (wheel_array.h): tachometers in STEP, wheel torques in STEP_REPLY


def encode_step(tick: int, t_sensor_ns: int, valid: int, q, w, pos, vel, wheel_speed=None) -> bytes:
    """wheel_speed: up to WHEELS_MAX tachometer speeds (rad/s); the wheels not given read NaN, as fsw_node
    reads a wheel the sensor message does not measure."""
    vals = [float(x) for x in (*q, *w, *pos, *vel)]
    if len(vals) != 13:
        raise ValueError("q needs 4 values, w, pos and vel 3 each")
    ws = [float(x) for x in (wheel_speed or ())]
    if len(ws) > WHEELS_MAX:
        raise ValueError(f"{len(ws)} wheel speeds, at most {WHEELS_MAX}")
    ws += [math.nan] * (WHEELS_MAX - len(ws))
    return STEP.pack(tick & 0xFFFFFFFF, t_sensor_ns, valid & 0xFFFFFFFF, *vals, *ws)


COUNTER_NAMES = ("steps", "invalid", "stale", "missing", "law_error", "overrun", "mode_transitions", "saturated",
                 "select_accepted", "select_rejected")


@dataclass(frozen=True)
class StepReply:
    tick: int
    step_status: int
    law: int
    mode: int
    law_status: int
    input_status: int
    u_cmd: tuple
    u_unsat: tuple
    saturated: int
    overrun: int
    exact: int
    instructions: int
    law_instructions: int
    budget: int
    counters: dict
    pil_overruns: int
    exec_law: int
    exec_mode: int
    # the wheel array (all zero without one): what fsw_node publishes in actuator_cmd_t
    u_wheels: tuple = (0.0,) * WHEELS_MAX
    wheel_scale: float = 0.0
    wheel_limited: int = 0       # torque-limited mask | speed-limited mask << 8
    wheel_status: int = 0
    h_total: tuple = (0.0, 0.0, 0.0)
    speed_margin: float = 0.0

    @classmethod
    def decode(cls, p: bytes) -> "StepReply":
        _need(p, STEP_REPLY, "STEP_REPLY")
        v = STEP_REPLY.unpack(p)
        return cls(tick=v[0], step_status=v[1], law=v[2], mode=v[3], law_status=v[4], input_status=v[5],
                   u_cmd=tuple(v[6:9]), u_unsat=tuple(v[9:12]), saturated=v[12], overrun=v[13], exact=v[14],
                   instructions=v[15], law_instructions=v[16], budget=v[17],
                   counters=dict(zip(COUNTER_NAMES, v[18:28])), pil_overruns=v[28], exec_law=v[29],
                   exec_mode=v[30], u_wheels=tuple(v[31:37]), wheel_scale=v[37], wheel_limited=v[38],
                   wheel_status=v[39], h_total=tuple(v[40:43]), speed_margin=v[43])

    def encode(self) -> bytes:
        return STEP_REPLY.pack(self.tick, self.step_status, self.law, self.mode, self.law_status,
                               self.input_status, *self.u_cmd, *self.u_unsat, self.saturated, self.overrun,
                               self.exact, self.instructions, self.law_instructions, self.budget,
                               *(self.counters[n] for n in COUNTER_NAMES), self.pil_overruns, self.exec_law,
                               self.exec_mode, *self.u_wheels, self.wheel_scale, self.wheel_limited,
                               self.wheel_status, *self.h_total, self.speed_margin)


def encode_select(law: int, qd=None, wd=(0.0, 0.0, 0.0)) -> bytes:
    has = qd is not None
    q = [float(x) for x in (qd if has else (0.0, 0.0, 0.0, 1.0))]
    return SELECT.pack(law, 1 if has else 0, *q, *(float(x) for x in wd))


@dataclass(frozen=True)
class Ack:
    pil_err: int
    status: int
    field: int
    exec_law: int
    exec_mode: int
    select_accepted: int
    select_rejected: int
    budget: int
    reserved: int

    @classmethod
    def decode(cls, p: bytes) -> "Ack":
        _need(p, ACK, "ACK")
        return cls(*ACK.unpack(p))


@dataclass(frozen=True)
class Bye:
    stack_bytes: int
    steps: int
    instructions_max: int
    frame_errors: int

    @classmethod
    def decode(cls, p: bytes) -> "Bye":
        _need(p, BYE_REPLY, "BYE")
        return cls(*BYE_REPLY.unpack(p))


@dataclass(frozen=True)
class Error:
    pil_err: int
    type: int
    seq: int
    detail: int

    @classmethod
    def decode(cls, p: bytes) -> "Error":
        _need(p, ERROR, "ERROR")
        return cls(*ERROR.unpack(p))

    def describe(self) -> str:
        name = err_name(self.pil_err)
        what = ERR_MEANING.get(name, "")
        tname = TYPE_NAMES.get(self.type, f"type {self.type}")
        return f"{name} ({what}) on a {tname} frame, seq {self.seq}, detail {self.detail}"


def _need(p: bytes, s: struct.Struct, what: str) -> None:
    if len(p) != s.size:
        raise FrameError(f"{what} payload of {len(p)} bytes, {s.size} expected")


# ---- CONFIG field list ------------------------------------------------------
@dataclass
class ConfigFields:
    """Ordered CONFIG entries: (field name, values) as aocs_pil_config_decode applies them."""
    entries: list = field(default_factory=list)

    def add(self, name: str, values) -> None:
        if name not in cfg_fields():
            raise KeyError(f"unknown PIL config field {name}")
        self.entries.append((name, values))

    def encode(self) -> bytes:
        out = bytearray()
        fields = cfg_fields()
        for name, values in self.entries:
            fid, kind, count = fields[name]
            if kind == "s":
                raw = str(values).encode("ascii")
                if not 1 <= len(raw) <= TABLE_NAME_MAX:
                    raise ValueError(f"{name}: table name of {len(raw)} characters (1..{TABLE_NAME_MAX})")
                out += bytes([fid, len(raw)]) + raw
                continue
            vals = list(values) if isinstance(values, (list, tuple)) else [values]
            if len(vals) != count:
                raise ValueError(f"{name}: {len(vals)} values, {count} expected")
            out += bytes([fid, count])
            if kind == "u":
                out += struct.pack("<Q", int(vals[0]))
            else:
                for x in vals:
                    x = float(x)
                    if not math.isfinite(x):
                        raise ValueError(f"{name}: non-finite value")
                    out += struct.pack("<d", x)
        if len(out) > PAYLOAD_MAX:
            raise ValueError(f"CONFIG payload of {len(out)} bytes exceeds {PAYLOAD_MAX}")
        return bytes(out)
