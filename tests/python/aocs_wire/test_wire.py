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
