"""Fast encoders / decoders of the aocs_lcm types for the plant's hot loop.

The generated Python classes (lcm-gen) encode through BytesIO and one
struct.pack per field group; a lockstep step sends a sensors_t and a truth_t
and reads an actuator_cmd_t, and at > 1000x real time every microsecond
counts. A Codec compiles ONE struct.Struct per type from the generated
class's own field list (__slots__, __typenames__, __dimensions__) and its
packed fingerprint, so it follows the .lcm files without a hand-written
layout: big-endian, fingerprint first, fixed-size arrays inline (the LCM
encoding; every aocs_lcm type is fixed size). tests/python/aocs_wire/test_wire.py
checks byte equality with the generated encode/decode.
"""
from __future__ import annotations

import functools
import struct

_FMT = {"int8_t": "b", "int16_t": "h", "int32_t": "i", "int64_t": "q", "float": "f",
        "double": "d", "boolean": "b", "byte": "B"}


class Codec:
    """pack(*values) -> bytes and unpack(bytes) -> tuple of one fixed-size LCM type.

    Values are the fields in declaration order with arrays flattened
    (sensors_t: protocol_version, frame, utime, tick, t_s, valid, q1..q4, ...).
    """

    def __init__(self, cls):
        self.cls = cls
        self.fields: list[tuple[str, int | None]] = []
        self._formats: list[str] = []   # each field's struct code, after the fingerprint
        for name, typ, dims in zip(cls.__slots__, cls.__typenames__, cls.__dimensions__):
            if typ not in _FMT:
                raise TypeError(f"{cls.__name__}.{name}: type {typ} not supported by the fast codec")
            if dims is None:
                self._formats.append(_FMT[typ])
                self.fields.append((name, None))
            else:
                if len(dims) != 1 or not isinstance(dims[0], int):
                    raise TypeError(f"{cls.__name__}.{name}: only fixed 1-D arrays are supported")
                self._formats.append(f"{dims[0]}{_FMT[typ]}")
                self.fields.append((name, dims[0]))
        self.struct = struct.Struct(">8s" + "".join(self._formats))
        self.size = self.struct.size
        self.fingerprint = cls._get_packed_fingerprint()
        #: pack(*values) -> bytes: the struct's own pack with the fingerprint bound (no Python frame per message)
        self.pack = self.packer()
        self._values = struct.Struct(">8x" + "".join(self._formats)).unpack   # the fingerprint skipped
        self._index = {}
        i = 0
        for name, n in self.fields:
            self._index[name] = (i, n)
            i += 1 if n is None else n

    def packer(self, *head):
        """pack with its first values bound (a hot loop's constant fields, e.g. the protocol version):
        packer(v)(*rest) == pack(v, *rest)."""
        return functools.partial(self.struct.pack, self.fingerprint, *head)

    def unpack(self, data: bytes) -> tuple | None:
        """Field values (flattened), or None if the payload is not exactly this type."""
        if len(data) != self.size or not data.startswith(self.fingerprint):
            return None
        return self._values(data)

    def unpacker(self, last: str):
        """unpack that decodes the fields up to `last` only (a hot loop reading the head of a message): the same
        check of the whole payload, the values a prefix of unpack's (index() holds), or None."""
        i = [name for name, _ in self.fields].index(last)
        head = struct.Struct(">8x" + "".join(self._formats[:i + 1])).unpack_from
        size, fingerprint = self.size, self.fingerprint

        def unpack_head(data: bytes) -> tuple | None:
            if len(data) != size or not data.startswith(fingerprint):
                return None
            return head(data)
        return unpack_head

    def index(self, field: str) -> int:
        """Position of a field in the flattened tuple (first element for arrays)."""
        return self._index[field][0]

    def layout(self, field: str) -> tuple[int, str]:
        """(byte offset in the payload, struct code) of a field (its first element for arrays): where a compiled
        loop reads or writes it (aocs_runner.compiled_loop)."""
        i = [name for name, _ in self.fields].index(field)
        return struct.calcsize(">8s" + "".join(self._formats[:i])), self._formats[i][-1]

    def to_dict(self, values) -> dict:
        out = {}
        for name, n in self.fields:
            i, _ = self._index[name]
            out[name] = values[i] if n is None else tuple(values[i:i + n])
        return out


class Codecs:
    """The codecs of every aocs_lcm type, from the imported bindings module."""

    def __init__(self, aocs_lcm):
        self.sensors = Codec(aocs_lcm.sensors_t)
        self.actuator = Codec(aocs_lcm.actuator_cmd_t)
        self.truth = Codec(aocs_lcm.truth_t)
        self.command = Codec(aocs_lcm.command_t)
        self.status = Codec(aocs_lcm.status_t)
        self.event = Codec(aocs_lcm.event_t)
        self.version = aocs_lcm.sensors_t.PROTOCOL_VERSION


#: channel names (docs/wire-contract.md)
SENSORS = "AOCS_SENSORS"
ACTUATOR = "AOCS_ACTUATOR_CMD"
TRUTH = "AOCS_TRUTH"
COMMAND = "AOCS_COMMAND"
STATUS = "AOCS_STATUS"
#: fault-management events, one event_t per event (fsw_node -> everyone)
EVENTS = "AOCS_EVENTS"
#: runner-only channel: a JSON marker (run start / end) written by the runner,
#: used to know that lcm-logger is recording before the run starts and has
#: everything before it stops; no aocs node subscribes to it
RUNNER = "AOCS_RUNNER"
