"""The fast LCM codecs of aocs_wire.wire against the lcm-gen bindings.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import random

import pytest

from aocs_wire import wire


def _random_value(typ, rng):
    return {"int8_t": rng.randint(-128, 127), "int16_t": rng.randint(-32768, 32767),
            "int32_t": rng.randint(-2 ** 31, 2 ** 31 - 1), "int64_t": rng.randint(-2 ** 63, 2 ** 63 - 1),
            "double": rng.uniform(-1e6, 1e6), "boolean": rng.choice([True, False])}[typ]


@pytest.mark.parametrize("name", ["sensors_t", "actuator_cmd_t", "truth_t", "command_t", "status_t"])
def test_fast_codec_is_byte_identical_to_the_generated_bindings(aocs_lcm, name):
    cls = getattr(aocs_lcm, name)
    codec = wire.Codec(cls)
    rng = random.Random(3)
    for _ in range(20):
        msg = cls()
        flat = []
        for field, typ, dims in zip(cls.__slots__, cls.__typenames__, cls.__dimensions__):
            if dims is None:
                v = _random_value(typ, rng)
                setattr(msg, field, v)
                flat.append(v)
            else:
                v = [_random_value(typ, rng) for _ in range(dims[0])]
                setattr(msg, field, v)
                flat += v
        data = msg.encode()
        assert codec.pack(*flat) == data
        got = codec.unpack(data)
        dec = cls.decode(data)
        assert got == tuple(flat)
        # field view matches the generated decoder
        for field, value in codec.to_dict(got).items():
            ref = getattr(dec, field)
            assert (tuple(ref) if isinstance(value, tuple) else ref) == value
    # not exactly this type: rejected, never mis-decoded
    assert codec.unpack(data[:-1]) is None
    assert codec.unpack(data + b"\0") is None
    assert codec.unpack(b"\xff" * 8 + data[8:]) is None


@pytest.mark.parametrize("name, last", [("actuator_cmd_t", "u_wheels"), ("sensors_t", "tick"), ("truth_t", "q")])
def test_the_head_unpacker_and_the_bound_packer_agree_with_the_whole_codec(aocs_lcm, name, last):
    """unpacker(last) gives a prefix of unpack through `last` (index() holds) with the same checks; packer(*head)
    packs as pack with those values first."""
    cls = getattr(aocs_lcm, name)
    codec = wire.Codec(cls)
    rng = random.Random(5)
    flat = []
    for field, typ, dims in zip(cls.__slots__, cls.__typenames__, cls.__dimensions__):
        flat += [_random_value(typ, rng) for _ in range(1 if dims is None else dims[0])]
    data = codec.pack(*flat)
    assert codec.packer(*flat[:3])(*flat[3:]) == data
    head = codec.unpacker(last)(data)
    n = codec.index(last) + (dict(codec.fields)[last] or 1)   # the values through `last`
    assert head == codec.unpack(data)[:n] == tuple(flat[:n])
    for bad in (data[:-1], data + b"\0", b"\xff" * 8 + data[8:]):
        assert codec.unpacker(last)(bad) is None
