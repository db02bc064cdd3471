"""The wheel tachometers (sensors/tachometer.py): built from the [wheels] array, read at the sample time,
noise from the seeded "tachometer" stream (index 5, one draw of N values per period), then quantised."""
import numpy as np

from aocs_plant import Plant, load

RW = {"wheels.speed0_rad_s": [10.0, -20.0, 0.04, 300.0]}


def _plant(**wheels):
    ov = dict(RW)
    ov.update({f"wheels.{k}": v for k, v in wheels.items()})
    ov["seed"] = 12
    return Plant(load("irassi_rw", ov))


def test_exact_without_noise_or_quantum():
    p = _plant()
    assert p.sense()["wheel_speed"] == p.truth()["effectors"]["wheels.speed_rad_s"]
    assert load("irassi_rw").sensors["tachometer"].ideal


def test_noise_is_the_seeded_stream_then_quantised():
    p = _plant(tach_noise_rad_s=0.5, tach_quantum_rad_s=0.25)
    true = p.truth()["effectors"]["wheels.speed_rad_s"]
    g = np.random.Generator(np.random.PCG64(np.random.SeedSequence(entropy=12, spawn_key=(5,))))
    n = (g.standard_normal((4096, 4)) * 0.5)[0].tolist()
    expect = tuple(0.25 * round((a + b) / 0.25) for a, b in zip(true, n))
    assert p.sense()["wheel_speed"] == expect
    assert all(abs(v / 0.25 - round(v / 0.25)) < 1e-12 for v in expect)
    assert not load("irassi_rw", {"wheels.tach_quantum_rad_s": 0.1}).sensors.ideal


def test_it_reads_the_speed_now_not_with_the_latency():
    p = Plant(load("irassi_rw", dict(RW, **{"sensors.latency_periods": 3})))
    for _ in range(5):
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.2, 0.2, 0.2, 0.2)})
        p.advance()
    assert p.sense()["wheel_speed"] == p.truth()["effectors"]["wheels.speed_rad_s"]
