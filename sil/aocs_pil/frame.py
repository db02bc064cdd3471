"""PIL frame codec, the host side of firmware/pil/include/aocs/pil_frame.h.

The fixed payloads are the rows of pil_frame.h (AOCS_PIL_PAYLOAD_ROWS) as the build's
registry lists them (aocs_core.registry): their struct formats, sizes and field names are
derived here, never typed; the CONFIG field ids are the configuration registry's.
tests/python/aocs_pil/test_frame.py checks the constants against the header, every layout
against the C codec (encoded here, decoded by it) and the bytes against golden vectors that
tests/unit/test_pil_frame.c also checks.

Frame: magic u32 ("APIL"), version u8, type u8, length u16, seq u32, payload,
CRC-32 (zlib.crc32) of everything before it; little-endian; reals binary64.
"""
from __future__ import annotations

import math
import struct
import zlib
from collections import namedtuple
from dataclasses import dataclass, field, make_dataclass

from aocs_core import registry

MAGIC = 0x4C495041
VERSION = 5
HEADER_BYTES = 12
CRC_BYTES = 4
PAYLOAD_MAX = 1024
ICOUNT_SHIFT = 7
TABLE_NAME_MAX = 31

TARGET_HOST, TARGET_CORTEX_M4F, TARGET_CORTEX_M7 = 0, 1, 2
TARGET_NAMES = {TARGET_HOST: "host", TARGET_CORTEX_M4F: "cortex-m4f", TARGET_CORTEX_M7: "cortex-m7"}

# aocs_pil_type_t: value -> name (AOCS_PIL_T_<name>), and a T_<name> per value
TYPE_NAMES = dict(enumerate(("HELLO", "CONFIG", "CONFIG_ACK", "STEP", "STEP_REPLY", "SELECT", "SELECT_ACK", "BYE",
                             "ERROR"), start=1))
T_HELLO, T_CONFIG, T_CONFIG_ACK, T_STEP, T_STEP_REPLY, T_SELECT, T_SELECT_ACK, T_BYE, T_ERROR = TYPE_NAMES

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

    The configuration registry's rows (config_fields.def and every law field of laws.def), from
    the build's registry."""
    return registry.load().pil_fields()


_HEADER = struct.Struct("<IBBHI")


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


Header = namedtuple("Header", "version type length seq")   # a frame's header fields after its magic


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


# ---- the fixed payloads: the rows of pil_frame.h, as the build's registry lists them ----
_REG = registry.load()
_LAYOUTS = _REG.pil_payloads
_FORMAT = {"u32": "I", "i32": "i", "u64": "Q", "f64": "d"}
COUNTER_NAMES = tuple(f.name for f in _REG.pil_counters)
WHEELS_MAX = _REG.wheels_max   # tachometers in STEP, wheel torques in STEP_REPLY


def _struct(name: str) -> struct.Struct:
    layout = _LAYOUTS[name]
    s = struct.Struct("<" + "".join(f"{f.count}{_FORMAT[f.wire]}" for f in layout.fields))
    assert s.size == layout.bytes, f"{name}: rows of {s.size} bytes, AOCS_PIL_{name}_BYTES {layout.bytes}"
    return s


STRUCTS = {name: _struct(name) for name in _LAYOUTS}
HELLO, STEP, STEP_REPLY, SELECT, ACK, BYE_REPLY, ERROR = (
    STRUCTS[n] for n in ("HELLO", "STEP", "STEP_REPLY", "SELECT", "ACK", "BYE_REPLY", "ERROR"))


def pack(name: str, values: dict) -> bytes:
    """The payload `name` of its rows' values by row name (several values: a sequence; counters: a dict)."""
    flat = []
    for f in _LAYOUTS[name].fields:
        v = values[f.name]
        v = [v[n] for n in COUNTER_NAMES] if f.kind == "counters" else list(v) if f.count > 1 else [v]
        if len(v) != f.count:
            raise ValueError(f"{name} {f.name}: {len(v)} values, {f.count} expected")
        flat += v
    return STRUCTS[name].pack(*flat)


def unpack(name: str, p: bytes) -> dict:
    """Row name -> value (a tuple for several values, a dict for the counters); FrameError on a wrong size."""
    s = STRUCTS[name]
    if len(p) != s.size:
        raise FrameError(f"{name} payload of {len(p)} bytes, {s.size} expected")
    vals, out, i = s.unpack(p), {}, 0
    for f in _LAYOUTS[name].fields:
        v = vals[i:i + f.count]
        out[f.name] = dict(zip(COUNTER_NAMES, v)) if f.kind == "counters" else v if f.count > 1 else v[0]
        i += f.count
    return out


class _Payload:
    """A fixed payload: one attribute per row of its layout LAYOUT."""
    LAYOUT = ""

    @classmethod
    def decode(cls, p: bytes):
        return cls(**unpack(cls.LAYOUT, p))

    def encode(self) -> bytes:
        return pack(self.LAYOUT, vars(self))


class _ErrorPayload(_Payload):
    def describe(self) -> str:
        name = err_name(self.pil_err)
        what = ERR_MEANING.get(name, "")
        tname = TYPE_NAMES.get(self.type, f"type {self.type}")
        return f"{name} ({what}) on a {tname} frame, seq {self.seq}, detail {self.detail}"


def _payload_class(cls_name: str, layout: str, base: type = _Payload) -> type:
    cls = make_dataclass(cls_name, [f.name for f in _LAYOUTS[layout].fields], bases=(base,), frozen=True,
                         namespace={"LAYOUT": layout})
    cls.__module__ = __name__
    return cls


Hello = _payload_class("Hello", "HELLO")
StepReply = _payload_class("StepReply", "STEP_REPLY")   # counters: a dict by COUNTER_NAMES
Ack = _payload_class("Ack", "ACK")                      # CONFIG_ACK and SELECT_ACK
Bye = _payload_class("Bye", "BYE_REPLY")
Error = _payload_class("Error", "ERROR", _ErrorPayload)


def encode_step(tick: int, t_sensor_ns: int, valid: int, q, w, pos, vel, wheel_speed=None, *,
                st_q=(0.0, 0.0, 0.0, 1.0), st_t_meas_ns: int = 0, gyro_w=(0.0, 0.0, 0.0),
                mag_b_t=(0.0, 0.0, 0.0)) -> bytes:
    """wheel_speed: up to WHEELS_MAX tachometer speeds (rad/s); the wheels not given read NaN, as fsw_node
    reads a wheel the sensor message does not measure. st_q, st_t_meas_ns: the star tracker's last sample and
    its time of measurement (ns, the clock of t_sensor_ns); gyro_w: the gyro's rate (rad/s); mag_b_t: the
    magnetometer's field in B (T)."""
    ws = [float(x) for x in (wheel_speed or ())]
    if len(ws) > WHEELS_MAX:
        raise ValueError(f"{len(ws)} wheel speeds, at most {WHEELS_MAX}")
    return pack("STEP", dict(tick=tick & 0xFFFFFFFF, t_sensor_ns=t_sensor_ns, valid=valid & 0xFFFFFFFF, q=q, w=w,
                             pos=pos, vel=vel, wheel_speed=ws + [math.nan] * (WHEELS_MAX - len(ws)), st_q=st_q,
                             st_t_meas_ns=st_t_meas_ns, gyro_w=gyro_w, mag_b_t=mag_b_t))


def encode_select(law: int, qd=None, wd=(0.0, 0.0, 0.0)) -> bytes:
    has = qd is not None
    return pack("SELECT", dict(law=law, has_target=int(has), qd=qd if has else (0.0, 0.0, 0.0, 1.0), wd=wd))


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
