"""aocs_loop.frames: the sensor frame made from the plant and the command applied to it, once for every path."""
from __future__ import annotations

import math

import pytest

from aocs_loop.frames import (
    ActuatorMismatch,
    Command,
    Momentum,
    PlantPort,
    SensorFrame,
    WheelMismatch,
    seconds_to_ns,
    valid_bits,
)
from aocs_plant import Plant
from aocs_plant.scenario import load


def test_valid_bits_are_the_wire_contract_s(aocs_lcm):
    s = aocs_lcm.sensors_t
    assert valid_bits() == (s.VALID_ATTITUDE, s.VALID_RATE, s.VALID_POSITION, s.VALID_VELOCITY, s.VALID_WHEELS,
                            s.VALID_STAR_TRACKER, s.VALID_GYRO, s.VALID_MAGNETOMETER)
    assert valid_bits().magnetometer == 128


def test_seconds_to_ns_rounds_like_llround_and_refuses_what_fsw_node_refuses():
    assert seconds_to_ns(0.1) == 100_000_000 and seconds_to_ns(2.5e-9) == 3 and seconds_to_ns(1.5e-9) == 2
    for bad in (0.0, -1.0, math.nan, math.inf, 1.8e10):
        assert seconds_to_ns(bad) == 0
    assert SensorFrame(1, 0.1, 0, (0, 0, 0, 1), (0, 0, 0), (0, 0, 0), (0, 0, 0)).t_ns == 100_000_000


def test_an_attitude_frame_carries_the_sample_and_the_tachometers(aocs_lcm):
    plant = Plant(load("irassi_rw"))
    port = PlantPort(plant)
    s = plant.sense()
    b = valid_bits()
    f = port.sense(7)
    assert (f.tick, f.t_s) == (7, 7 * plant.dt)
    assert f.valid == b.attitude | b.rate | b.wheels
    assert f.q is s["q"] and f.w is s["w"] and f.wheel_speed is s["wheel_speed"] and f.n_wheels == 4
    assert f.pos == f.vel == (0.0, 0.0, 0.0)
    assert port.sense(7, t_s=0.6).t_s == 0.6          # a stale frame's time


def test_an_attitude_frame_without_wheels_has_no_wheel_bit(aocs_lcm):
    f = PlantPort(Plant(load("irassi_small"))).sense(0)
    assert f.valid == valid_bits().attitude | valid_bits().rate and f.wheel_speed == ()
    # nor a star tracker or a gyro: their fields hold the defaults
    assert (f.st_q, f.st_t_meas_s, f.gyro_w) == ((0.0, 0.0, 0.0, 1.0), 0.0, (0.0, 0.0, 0.0)) and f.st_t_meas_ns == 0


ST_GYRO = {"sensors.star_tracker.rate_hz": 2.5, "sensors.star_tracker.latency_s": 0.2,
           "sensors.star_tracker.noise_cross_arcsec": 1.0, "sensors.gyro.arw_rad_sqrt_s": 1e-6,
           "sensors.gyro.bias_rad_s": [1e-5, -2e-5, 3e-5], "duration_s": 3.0, "metrics.window_s": 1.0}


def test_the_star_tracker_flag_marks_its_new_samples_only(aocs_lcm):
    """Each period's frame carries the tracker's last sample and its time of measurement; the flag only in the
    periods that took a new, valid one (2.5 Hz at 10 Hz: ticks 0, 4, 8, ... but the first, whose
    measurement would precede the run by the latency); the gyro's rate and flag every period."""
    plant = Plant(load("irassi_small", ST_GYRO))
    port = PlantPort(plant)
    b = valid_bits()
    flagged = []
    for k in range(25):
        f = port.sense(k)
        s = plant.sense()
        assert f.st_q == s["st_q"] and f.st_t_meas_s == s["st_t_meas"] and f.gyro_w == s["gyro_w"]
        assert f.valid & b.gyro and f.valid & b.attitude
        if f.valid & b.star_tracker:
            flagged.append(k)
            assert s["st_new"] and s["st_valid"]
            assert f.st_t_meas_s == pytest.approx(k * plant.dt - 0.2, abs=1e-12)
            assert f.st_t_meas_ns == seconds_to_ns(f.st_t_meas_s)
        else:
            assert not (s["st_new"] and s["st_valid"])
        plant.apply({"u_body": (0.0, 0.0, 0.0)})
        plant.advance()
    assert flagged == [4, 8, 12, 16, 20, 24]


def test_the_gyro_in_angle_mode_sends_the_mean_rate(aocs_lcm):
    ov = {"sensors.gyro.mode": "angle", "sensors.gyro.bias_rad_s": [1e-3, -2e-3, 3e-3], "duration_s": 1.0,
          "metrics.window_s": 1.0}
    plant = Plant(load("irassi_small", ov))
    port = PlantPort(plant)
    f = port.sense(0)
    d = plant.sense()["gyro_dtheta"]
    assert f.gyro_w == tuple(x / plant.dt for x in d) and f.valid & valid_bits().gyro
    assert f.gyro_w == pytest.approx((1e-3, -2e-3, 3e-3), rel=1e-12)   # at rest: the bias alone


def test_a_gyro_dropout_clears_its_flag(aocs_lcm):
    ov = {"sensors.gyro.arw_rad_sqrt_s": 1e-6, "duration_s": 1.0, "metrics.window_s": 1.0,
          "sensors.faults": [{"channel": "gyro", "kind": "dropout", "start_s": 0.0, "end_s": 0.25}]}
    plant = Plant(load("irassi_small", ov))
    port = PlantPort(plant)
    flags = []
    for k in range(5):
        flags.append(bool(port.sense(k).valid & valid_bits().gyro))
        plant.apply({"u_body": (0.0, 0.0, 0.0)})
        plant.advance()
    assert flags == [False, False, False, True, True]


def test_an_orbit_frame(aocs_lcm):
    plant = Plant(load("landsat8_q1"))
    f = PlantPort(plant).sense(0)
    s = plant.sense()
    assert f.valid == valid_bits().position | valid_bits().velocity
    assert (f.pos, f.vel, f.q, f.w) == (s["pos"], s["vel"], (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0))


def test_a_command_reaches_every_actuator_field(aocs_lcm):
    plant = Plant(load("irassi_rw"))
    port = PlantPort(plant)
    m = port.apply(Command(0, (0.0, 0.0, 0.0), (0.01, -0.02, 0.03, -0.04)))
    assert m == {"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.01, -0.02, 0.03, -0.04)}
    assert port.command(Command(0, (0.0, 0.0, 0.0), (0.01, -0.02, 0.03, -0.04))) == m
    plant.apply(m)
    assert plant.counters["commands"] == 2 and plant.wheel_array.u_cmd == m["u_wheels"]   # the wheels got them
    orbit = PlantPort(Plant(load("landsat8_q1")))
    assert orbit.apply(Command(0, (1.0, 2.0, 3.0))) == {"u_orbit": (1.0, 2.0, 3.0)}


@pytest.mark.parametrize("scenario, wheels", [("irassi_rw", (0.1, 0.2, 0.3)), ("irassi_rw", ()),
                                              ("irassi_small", (0.1,))])
def test_a_wheel_count_mismatch_is_refused(aocs_lcm, scenario, wheels):
    plant = Plant(load(scenario))
    with pytest.raises(WheelMismatch, match=f"commands {len(wheels)} wheel"):
        PlantPort(plant).apply(Command(0, (0.0, 0.0, 0.0), wheels))
    assert plant.counters["commands"] == 0


def test_a_plant_without_unloading_actuators_gets_no_unloading_fields(aocs_lcm):
    """Protocol version 4: a plant without [thrusters] / [magnetorquers] (Plant.command_fields has neither) is
    sent neither field (the plant refuses a field no actuator reads), and a command with them is refused in
    one line naming them."""
    plant = Plant(load("irassi_rw"))
    port = PlantPort(plant)
    assert "thruster_on_s" not in plant.command_fields and "u_dipole_am2" not in plant.command_fields
    assert (port.n_thrusters, port.magnetorquers) == (0, False)
    assert port.apply(Command(0, (0.0, 0.0, 0.0), (0.0,) * 4)) == {"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.0,) * 4}
    with pytest.raises(ActuatorMismatch, match="commands 12 thruster.*no \\[thrusters\\]"):
        port.apply(Command(0, (0.0, 0.0, 0.0), (0.0,) * 4, (0.01,) * 12))
    with pytest.raises(ActuatorMismatch, match="magnetorquers.*no \\[magnetorquers\\]"):
        port.command(Command(0, (0.0, 0.0, 0.0), (0.0,) * 4, (), (1.0, 0.0, 0.0)))
    assert plant.counters["commands"] == 1


def test_momentum_telemetry_gives_the_command_fields_of_its_policy():
    m = Momentum(2, 0, 3, tuple(0.01 * i for i in range(12)), (1.0, 2.0, 3.0), latch_closed=2)
    assert m.command_fields() == ((0.0, 0.01, 0.02), (), 2)
    # the latch valves are the thrusters': another policy sends none
    assert Momentum(1, 0, 3, (0.5,) * 12, (1.0, 2.0, 3.0), latch_closed=2).command_fields() == \
        ((), (1.0, 2.0, 3.0), 0)
    assert Momentum().command_fields() == ((), (), 0)


def test_no_magnetometer_no_field_and_no_flag(aocs_lcm):
    """Until the plant has a magnetometer (a sensor whose sample field is mag_b_t) the frame's field is zero and
    its flag off: the clearly marked absence."""
    plant = Plant(load("irassi_rw"))
    assert all(s.value_field != "mag_b_t" for s in plant.sensors)
    f = PlantPort(plant).sense(0)
    assert f.mag_b_t == (0.0, 0.0, 0.0) and not f.valid & valid_bits().magnetometer
