"""The sensor registry (aocs_plant/sensors/): every module registers its sensor with a fixed noise stream,
the loader selects the sensors a scenario has, and a new sensor module (the toy Sun sensor below, the
example of docs/extending.md "Adding a sensor") flies through the plant with nothing else changed."""
import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import pytest

import aocs_plant
from aocs_core.conventions import quat_to_dcm
from aocs_plant import Plant, ScenarioError, load, rng
from aocs_plant import sensors as sen
from aocs_plant.rng import NormalStream
from aocs_plant.sensors import ATTITUDE, REGISTRY, Sensor

PLANT_DIR = Path(aocs_plant.__file__).resolve().parent


# ----------------------------------------------------------------- the example module of docs/extending.md

@dataclass(frozen=True)
class SunSensorConfig:
    noise: float             # white noise std per axis, before renormalising


class ToySunSensor(Sensor):
    """[sensors] sun_noise: the Sun direction in B, s_B = A(q) s_N(t), with s_N from the environment
    (Plant.environment); measured as (s_B + n) / |s_B + n|, n white (stream 40)."""

    name = "toy_sun"
    stream_index = 40                  # its own seeded stream: a fixed index no other channel has
    applies_to = (ATTITUDE,)
    keys = ("sun_noise",)              # its keys in [sensors]
    value_field, valid_field = "sun_b", "sun_valid"
    truth_field = "sun_b"
    fault_kinds = ("dropout", "nan")

    @classmethod
    def read(cls, sec, ctx):
        return SunSensorConfig(sec.number("sun_noise", required=False, default=0.0, nonneg=True))

    def __init__(self, config, ctx):
        super().__init__(config, ctx)
        self.environment = ctx.environment
        self.stream = NormalStream(ctx.seed, self.name, config.noise) if config.noise > 0.0 else None

    def source(self, plant):
        body, env = plant.body, self.environment

        def sun_b():
            A = quat_to_dcm(body.q)
            s = env.sun_direction(plant.t)
            return tuple(A[i][0] * s[0] + A[i][1] * s[1] + A[i][2] * s[2] for i in range(3))
        return sun_b

    def measure(self, s):
        if self.stream is None:
            return s
        n = self.stream.next()
        v = (s[0] + n[0], s[1] + n[1], s[2] + n[2])
        k = 1.0 / math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        return (v[0] * k, v[1] * k, v[2] * k)
# end of the example


@pytest.fixture
def sun_sensor(monkeypatch):
    """Register the toy sensor for one test (registry and noise channel restored afterwards)."""
    monkeypatch.setitem(REGISTRY, ToySunSensor.name, ToySunSensor)
    monkeypatch.setitem(rng.CHANNELS, ToySunSensor.name, ToySunSensor.stream_index)
    return ToySunSensor


def _dcm(q):
    """A(q) written out (SPEC 1.2, scalar last), independent of aocs_core."""
    q1, q2, q3, q4 = q
    return np.array([
        [q1 * q1 - q2 * q2 - q3 * q3 + q4 * q4, 2 * (q1 * q2 + q3 * q4), 2 * (q1 * q3 - q2 * q4)],
        [2 * (q1 * q2 - q3 * q4), -q1 * q1 + q2 * q2 - q3 * q3 + q4 * q4, 2 * (q2 * q3 + q1 * q4)],
        [2 * (q1 * q3 + q2 * q4), 2 * (q2 * q3 - q1 * q4), -q1 * q1 - q2 * q2 + q3 * q3 + q4 * q4]])


def test_the_toy_sun_sensor_flies_through_the_plant(sun_sensor):
    plant = Plant(load("irassi_large", {"plant.w0": [0.01, -0.02, 0.015]}))
    assert [s.name for s in plant.sensors] == ["attitude", "rate", "toy_sun"]
    env = plant.environment
    for _ in range(30):
        s = plant.sense()
        s_n = np.array(env.sun_direction(plant.t))
        np.testing.assert_allclose(s["sun_b"], _dcm(plant.truth()["q"]) @ s_n, atol=1e-14)
        assert s["sun_valid"] and s["q_valid"]
        plant.advance()
    # the body turned: the Sun moved in B, and the sensor followed
    assert np.linalg.norm(np.subtract(plant.sense()["sun_b"], Plant(load("irassi_large")).sense()["sun_b"])) > 0.01


def test_the_toy_sun_sensor_has_its_seeded_stream_and_takes_faults(sun_sensor):
    ov = {"seed": 4, "sensors.sun_noise": 1e-3, "sensors.rate_noise_rad_s": 1e-6,
          "sensors.faults": [{"channel": "all", "kind": "dropout", "start_s": 1.0, "end_s": 1.2}]}
    a, b = Plant(load("irassi_large", ov)), Plant(load("irassi_large", ov))
    ref = Plant(load("irassi_large", {"seed": 4, "sensors.rate_noise_rad_s": 1e-6}))
    last = None
    for k in range(15):
        sa, sb, sr = a.sense(), b.sense(), ref.sense()
        assert sa["sun_b"] == sb["sun_b"]               # repeatable for a seed
        assert sa["w"] == sr["w"] or 10 <= k < 12        # it does not shift the other sensors' noise
        if 10 <= k < 12:
            assert not sa["sun_valid"] and not sa["w_valid"] and sa["sun_b"] == last
        else:
            last = sa["sun_b"]
            assert sa["sun_valid"]
        for p in (a, b, ref):
            p.advance()
    assert a.counters["invalid_samples"] == 2


def test_the_toy_sun_sensor_keys_are_refused_where_it_does_not_apply(sun_sensor):
    with pytest.raises(ScenarioError, match=r"landsat8_q1.toml: sensors.sun_noise: does not apply to a orbit "
                                            r"scenario"):
        load("landsat8_q1", {"sensors.sun_noise": 1e-3})
    with pytest.raises(ScenarioError, match=r"sensors.faults\[0\].channel: unknown value 'toy_sun'"):
        load("landsat8_q1", {"sensors.faults": [{"channel": "toy_sun", "kind": "nan", "start_s": 1, "end_s": 2}]})


def test_docs_extending_shows_this_sensor_verbatim():
    here = Path(__file__)
    doc = (here.parents[3] / "docs" / "extending.md").read_text()
    marker = "<!-- verbatim: tests/python/aocs_plant/test_sensors_base.py -->\n```python\n"
    assert marker in doc
    block = doc.split(marker, 1)[1].split("```", 1)[0]
    assert "class ToySunSensor(Sensor):" in block and "def measure(" in block
    assert block in here.read_text()


# ----------------------------------------------------------------- the registry

#: the seeded stream of every sensor, by hand: renumbering one would change every seeded run
STREAMS = {"attitude": 0, "rate": 1, "position": 2, "velocity": 3, "tachometer": 5, "star_tracker": 6, "gyro": 7,
           "magnetometer": 8}


def test_every_module_registers_its_sensor_with_its_fixed_stream():
    modules = {p.stem for p in (PLANT_DIR / "sensors").glob("*.py")} - {"__init__", "base", "additive", "faults",
                                                                       "suite"}
    assert modules == {c.__module__.rsplit(".", 1)[1] for c in REGISTRY.values()}
    assert {n: c.stream_index for n, c in REGISTRY.items()} == STREAMS
    assert all(rng.CHANNELS[n] == i for n, i in STREAMS.items())


@pytest.mark.parametrize("name,index", [("rate", 1), ("position", 2), ("velocity", 3)])
def test_a_sensor_draws_the_seed_sequence_of_its_index(name, index):
    """The stream is numpy's PCG64 seeded by SeedSequence(seed, spawn_key=(index,)), drawn in blocks of 4096:
    the noise of the first sample is its first normal triple times sigma (written here without rng.py)."""
    sid, key = ("irassi_large", "rate_noise_rad_s") if name == "rate" else \
        ("landsat8_q1", f"{name}_noise_{'m' if name == 'position' else 'm_s'}")
    p = Plant(load(sid, {"seed": 9, f"sensors.{key}": 0.25}))
    field = {"rate": "w", "position": "pos", "velocity": "vel"}[name]
    truth = p.truth()[field]
    g = np.random.Generator(np.random.PCG64(np.random.SeedSequence(entropy=9, spawn_key=(index,))))
    draw = (g.standard_normal((4096, 3)) * 0.25)[0].tolist()
    assert p.sense()[field] == tuple(x + e for x, e in zip(truth, draw))     # y = x + (0 + n), bit for bit


def test_the_plant_kind_and_the_effectors_select_the_sensors():
    assert [s.name for s in Plant(load("irassi_large")).sensors] == ["attitude", "rate"]
    assert [s.name for s in Plant(load("landsat8_q1")).sensors] == ["position", "velocity"]
    assert [s.name for s in Plant(load("irassi_rw")).sensors] == ["attitude", "rate", "tachometer"]


def test_register_refuses_a_name_a_stream_or_a_sample_field_twice(monkeypatch):
    class Twice(Sensor):
        name = "rate"
        stream_index = 1
    with pytest.raises(ValueError, match="registered twice"):
        sen.register(Twice)

    class Stream(Sensor):
        name, stream_index, value_field = "new_a", 4, "new_a"   # 4: the wheels' motor torque noise
    with pytest.raises(ValueError, match=r"index 4 is negative or taken by 'wheel_torque'"):
        sen.register(Stream)

    class Field(Sensor):
        name, stream_index, value_field = "new_b", 41, "w"
    with pytest.raises(ValueError, match="sample field taken by sensor 'rate'"):
        sen.register(Field)
    assert "new_a" not in REGISTRY and "new_b" not in REGISTRY and "new_b" not in rng.CHANNELS


def test_sensor_truth_fields_report_the_error_of_the_last_sample():
    bias = (2e-6, -1e-6, 3e-6)
    p = Plant(load("irassi_large", {"sensors.attitude_bias_rad": list(bias), "sensors.rate_bias_rad_s": list(bias)}))
    p.sense()
    tr = p.truth()["sensors"]
    assert tr["attitude.error_rad"] == bias and tr["rate.error"] == bias
    # the attitude error is the small rotation from the truth to the measurement, A(q_m) A(q)^T = A(dq(bias))
    d = _dcm(p.sense()["q"]) @ _dcm(p.truth()["q"]).T
    np.testing.assert_allclose([d[1, 2] - d[2, 1], d[2, 0] - d[0, 2], d[0, 1] - d[1, 0]], 2 * np.array(bias),
                               rtol=1e-6, atol=1e-16)
