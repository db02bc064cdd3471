"""aocs_loop.lcm_adapter: sensors_t from a SensorFrame byte for byte the generated encode, the Command and
Reply of an actuator_cmd_t, and the adapter's exchange over a fake LCM handle."""
from __future__ import annotations

import pytest

from aocs_loop.frames import Estimate, Momentum, SensorFrame
from aocs_loop.lcm_adapter import LcmCodec, LcmFlightComputer
from aocs_wire import wire


@pytest.fixture
def codec(aocs_lcm):
    return LcmCodec(wire.Codecs(aocs_lcm), aocs_lcm)


FRAME = SensorFrame(12, 1.2, 1 | 2 | 16, (0.1, 0.2, 0.3, 0.9273618495495703), (1e-3, -2e-3, 3e-3),
                    (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (10.0, -20.0, 30.5, -40.25))


def _sensors_msg(aocs_lcm, f, frame_no=None):
    st = aocs_lcm.sensors_t
    m = st()
    m.protocol_version, m.frame, m.utime, m.tick, m.t_s, m.valid = (
        st.PROTOCOL_VERSION, f.tick if frame_no is None else frame_no, int(round(f.t_s * 1e6)), f.tick, f.t_s, f.valid)
    m.q, m.w, m.pos, m.vel = list(f.q), list(f.w), list(f.pos), list(f.vel)
    m.n_wheels = len(f.wheel_speed)
    m.wheel_speed = list(f.wheel_speed) + [0.0] * (st.MAX_WHEELS - len(f.wheel_speed))
    m.st_q, m.st_t_meas_s, m.gyro_w = list(f.st_q), f.st_t_meas_s, list(f.gyro_w)
    m.mag_b_t = list(f.mag_b_t)
    return m


#: a frame with a new star-tracker sample and a gyro rate (protocol version 3)
FRAME_ST = SensorFrame(13, 1.3, 1 | 2 | 32 | 64, (0.1, 0.2, 0.3, 0.9273618495495703), (1e-3, -2e-3, 3e-3),
                       (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (), (0.5, -0.5, 0.5, -0.5), 1.2, (1.5e-3, -2.5e-3, 3.5e-3))


#: with a magnetometer reading (protocol version 4)
FRAME_MAG = SensorFrame(14, 1.4, 1 | 2 | 128, (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0),
                        (1.0, 2.0, 3.0), (0.0, 0.0, 0.0, 1.0), 0.0, (0.0, 0.0, 0.0), (2.5e-5, -1.5e-5, 4.0e-6))


@pytest.mark.parametrize("f", [FRAME, FRAME_ST, FRAME_MAG, SensorFrame(0, 0.0, 4 | 8, (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0),
                                                            (1.0, 2.0, 3.0), (-1.0, -2.0, -3.0))])
def test_pack_sensors_is_the_generated_encode(aocs_lcm, codec, f):
    assert codec.pack_sensors(f) == _sensors_msg(aocs_lcm, f).encode()
    assert codec.pack_sensors(f, frame_no=99) == _sensors_msg(aocs_lcm, f, 99).encode()


def _actuator(aocs_lcm, n_wheels=4, policy=0, n_thrusters=0):
    a = aocs_lcm.actuator_cmd_t()
    a.protocol_version = a.PROTOCOL_VERSION
    a.tick, a.law_id, a.mode, a.status, a.step_ns, a.overrun = 12, 3, 1, 0, 567, True
    a.u_sat, a.u_unsat = [0.1, -0.2, 0.3], [1.0, -2.0, 3.0]
    a.n_wheels = n_wheels
    a.u_wheels = [0.01, 0.02, 0.03, 0.04, 0.05, 0.06]
    a.estimator, a.est_status, a.q_est, a.w_est, a.bias_est = 1, -7, [0.0, 0.6, 0.0, 0.8], [4e-3, 5e-3, 6e-3], [
        -1e-6, 2e-6, -3e-6]
    a.est_p = [0.5 + i for i in range(21)]
    a.st_status, a.n_st_used, a.n_st_gated, a.n_st_hostile, a.n_est_restarts = -3, 2**40, 5, 6, 7
    a.mom_policy, a.mom_status, a.n_thrusters = policy, -2, n_thrusters
    a.thruster_on_s = [0.001 * (i + 1) for i in range(12)]
    a.dipole_am2, a.u_unload, a.h_wheels, a.dh = [1.5, -2.5, 0.5], [-0.1, 0.2, -0.3], [10.0, -5.0, 3.0], [9.0, -5.0, 3.0]
    a.unloading, a.n_unload_events = True, 2**33
    a.thruster_latch_closed = 2
    return a.encode()


def test_command_and_reply_of_an_actuator_cmd(aocs_lcm, codec):
    v = codec.unpack(_actuator(aocs_lcm))
    c = codec.command(v)
    assert (c.tick, c.u, c.u_wheels) == (12, (0.1, -0.2, 0.3), (0.01, 0.02, 0.03, 0.04))
    r = codec.reply(v)
    assert r.command == c and r.u_unsat == (1.0, -2.0, 3.0) and r.raw is v
    assert (r.law_id, r.mode, r.status, r.step_ns, r.overrun) == (3, 1, 0, 567, True)
    assert r.estimate == codec.estimate(v) == Estimate(1, -7, (0.0, 0.6, 0.0, 0.8), (4e-3, 5e-3, 6e-3),
                                                       (-1e-6, 2e-6, -3e-6), tuple(0.5 + i for i in range(21)),
                                                       -3, 2**40, 5, 6, 7)
    assert codec.command(codec.unpack(_actuator(aocs_lcm, 0))).u_wheels == ()
    assert len(codec.command(codec.unpack(_actuator(aocs_lcm, 9))).u_wheels) == 6   # clamped to the array
    # policy none: no unloading command, whatever the fields hold; the telemetry as it came
    assert (c.thruster_on_s, c.u_dipole_am2) == ((), ())
    assert r.momentum == codec.momentum(v) == Momentum(0, -2, 0, tuple(0.001 * (i + 1) for i in range(12)),
                                                       (1.5, -2.5, 0.5), (-0.1, 0.2, -0.3), (10.0, -5.0, 3.0),
                                                       (9.0, -5.0, 3.0), True, 2**33, 2)


def test_the_command_carries_the_unloading_actuators_of_the_policy(aocs_lcm, codec):
    """Protocol version 4: thrusters policy (2): the first n_thrusters on-times (and, version 6, the latch
    valves); magnetorquers (1): the dipole."""
    c = codec.command(codec.unpack(_actuator(aocs_lcm, 4, policy=2, n_thrusters=8)))
    assert c.thruster_on_s == tuple(0.001 * (i + 1) for i in range(8)) and c.u_dipole_am2 == ()
    assert c.thruster_latch_closed == 2
    # plant_node's loop reads the head of the message only: it holds the latch valves
    assert codec.command(codec.unpack_command(_actuator(aocs_lcm, 4, policy=2, n_thrusters=8))) == c
    assert len(codec.command(codec.unpack(_actuator(aocs_lcm, 4, policy=2, n_thrusters=40))).thruster_on_s) == 12
    c = codec.command(codec.unpack(_actuator(aocs_lcm, 4, policy=1, n_thrusters=8)))
    assert c.thruster_on_s == () and c.u_dipole_am2 == (1.5, -2.5, 0.5) and c.thruster_latch_closed == 0
    r = codec.reply(codec.unpack(_actuator(aocs_lcm, 4, policy=1)))
    assert r.command == c and r.momentum.command_fields() == ((), c.u_dipole_am2, 0)


class _FakeLcm:
    """Answers each sensors_t with a stale reply, garbage, then the reply of its tick."""

    def __init__(self, aocs_lcm):
        self.t, self.subs, self.sent, self.queue = aocs_lcm, {}, [], []

    def subscribe(self, channel, cb):
        self.subs[channel] = cb
        return channel

    def unsubscribe(self, sub):
        del self.subs[sub]

    def publish(self, channel, data):
        self.sent.append((channel, data))
        tick = self.t.sensors_t.decode(data).tick
        for t in (tick - 1, None, tick):
            if t is None:
                self.queue.append(b"garbage")
                continue
            a = self.t.actuator_cmd_t()
            a.protocol_version, a.tick, a.u_sat = a.PROTOCOL_VERSION, t, [float(t), 0.0, 0.0]
            self.queue.append(a.encode())

    def handle_timeout(self, ms):
        if self.queue:
            self.subs[wire.ACTUATOR](wire.ACTUATOR, self.queue.pop(0))
            return 1
        return 0


def test_the_adapter_publishes_the_frame_and_returns_the_reply_of_its_tick(aocs_lcm, codec):
    lc = _FakeLcm(aocs_lcm)
    fc = LcmFlightComputer(lc, codec, reply_timeout=1.0)
    r = fc.step(FRAME)
    assert lc.sent == [(wire.SENSORS, codec.pack_sensors(FRAME))]
    assert r.command.tick == 12 and r.command.u == (12.0, 0.0, 0.0)
    assert fc.stale_replies == 1 and fc.bad_replies == 1
    fc.close()
    assert wire.ACTUATOR not in lc.subs


def test_the_adapter_gives_up_after_its_timeout_and_when_the_computer_died(aocs_lcm, codec):
    lc = _FakeLcm(aocs_lcm)
    lc.publish = lambda channel, data: None     # nobody answers
    with pytest.raises(TimeoutError, match="no actuator_cmd_t for tick 12"):
        LcmFlightComputer(lc, codec, reply_timeout=0.05).step(FRAME)

    def dead(tick):
        raise RuntimeError(f"gone at tick {tick}")
    with pytest.raises(RuntimeError, match="gone at tick 12"):
        LcmFlightComputer(_FakeLcm(aocs_lcm), codec, alive=dead).step(FRAME)
