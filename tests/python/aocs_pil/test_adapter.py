"""aocs_pil.adapter: a SensorFrame's STEP payload (the bridge's and the direct path's one translation) and
the Reply of a STEP_REPLY, without an emulator."""
from __future__ import annotations

import dataclasses
import math

from aocs_loop.frames import Estimate, Momentum, SensorFrame, valid_bits
from aocs_pil import adapter, frame

Q = (0.1, 0.2, 0.3, 0.9273618495495703)
W = (1e-3, -2e-3, 3e-3)
Z = (0.0, 0.0, 0.0)


def _step(payload):
    v = frame.STEP.unpack(payload)
    return {"tick": v[0], "t_ns": v[1], "valid": v[2], "q": v[3:7], "w": v[7:10], "pos": v[10:13],
            "vel": v[13:16], "wheels": v[16:22], "st_q": v[22:26], "st_t_meas_ns": v[26], "gyro_w": v[27:30],
            "mag_b_t": v[30:33]}


def test_an_attitude_frame_with_tachometers(aocs_lcm):
    b = valid_bits()
    s = _step(adapter.step_payload(SensorFrame(12, 1.2, b.attitude | b.rate | b.wheels, Q, W, Z, Z, (1.0, -2.0))))
    assert (s["tick"], s["t_ns"], s["valid"]) == (12, 1_200_000_000, adapter.EXEC_VALID_ATT | adapter.EXEC_VALID_RATE)
    assert s["q"] == Q and s["w"] == W and s["wheels"][:2] == (1.0, -2.0)
    assert all(math.isnan(x) for x in s["wheels"][2:])          # the wheels it does not measure read NaN


def test_tachometers_without_their_bit_read_nan(aocs_lcm):
    b = valid_bits()
    s = _step(adapter.step_payload(SensorFrame(1, 0.1, b.attitude, Q, W, Z, Z, (1.0, -2.0))))
    assert s["valid"] == adapter.EXEC_VALID_ATT and all(math.isnan(x) for x in s["wheels"])


def test_the_orbit_bit_needs_position_and_velocity(aocs_lcm):
    b = valid_bits()
    one = SensorFrame(1, 0.1, b.position, (0.0, 0.0, 0.0, 1.0), Z, (1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    assert _step(adapter.step_payload(one))["valid"] == 0
    both = SensorFrame(1, 0.1, b.position | b.velocity, (0.0, 0.0, 0.0, 1.0), Z, (1.0, 2.0, 3.0), (4.0, 5.0, 6.0))
    s = _step(adapter.step_payload(both))
    assert s["valid"] == adapter.EXEC_VALID_ORBIT and s["pos"] == (1.0, 2.0, 3.0) and s["vel"] == (4.0, 5.0, 6.0)


def test_the_star_tracker_and_the_gyro(aocs_lcm):
    """Their bits become the executive's ST and GYRO; the tracker's time of measurement is converted as the
    sensor time is (fsw_node's lockstep), the values pass as they are."""
    b = valid_bits()
    f = SensorFrame(12, 1.2, b.attitude | b.rate | b.star_tracker | b.gyro, Q, W, Z, Z, (),
                    (0.5, -0.5, 0.5, -0.5), 1.0000000005, (1e-3, math.nan, -2e-3))
    s = _step(adapter.step_payload(f))
    assert s["valid"] == (adapter.EXEC_VALID_ATT | adapter.EXEC_VALID_RATE | adapter.EXEC_VALID_ST
                          | adapter.EXEC_VALID_GYRO)
    assert s["st_q"] == (0.5, -0.5, 0.5, -0.5) and s["st_t_meas_ns"] == 1_000_000_001 == f.st_t_meas_ns
    assert s["gyro_w"][0] == 1e-3 and math.isnan(s["gyro_w"][1])
    # the flags off: the values still travel (the last sample), the executive is not told they are new / usable
    s = _step(adapter.step_payload(SensorFrame(12, 1.2, b.attitude, Q, W, Z, Z, (), (0.5, -0.5, 0.5, -0.5), 0.9)))
    assert s["valid"] == adapter.EXEC_VALID_ATT and s["st_q"] == (0.5, -0.5, 0.5, -0.5)
    assert s["st_t_meas_ns"] == 900_000_000


def test_the_exec_valid_bits_are_io_h_s():
    from pil_support import REPO
    text = (REPO / "firmware/include/aocs/exec/io.h").read_text()
    for name, bit in (("ATT", adapter.EXEC_VALID_ATT), ("RATE", adapter.EXEC_VALID_RATE),
                      ("ORBIT", adapter.EXEC_VALID_ORBIT), ("ST", adapter.EXEC_VALID_ST),
                      ("GYRO", adapter.EXEC_VALID_GYRO), ("MAG", adapter.EXEC_VALID_MAG)):
        shift = int(text.split(f"#define AOCS_EXEC_VALID_{name} ")[1].split("<<")[1].split(")")[0])
        assert bit == 1 << shift, name


def test_the_reply_of_a_step_reply():
    r = dataclasses.replace(
        frame.StepReply.decode(bytes(frame.STEP_REPLY.size)), tick=7, step_status=0, law=3, mode=1, law_status=5,
        input_status=0, u_cmd=(0.1, 0.2, 0.3), u_unsat=(1.0, 2.0, 3.0), saturated=1, overrun=0, exact=1,
        instructions=21600, law_instructions=1000, budget=50000, exec_law=3, exec_mode=1,
        u_wheels=(0.01, 0.02, 0.03, 0.04, 0.0, 0.0), estimator=1, est_status=-4, q_est=(0.0, 0.6, 0.0, 0.8),
        w_est=(1e-3, 2e-3, 3e-3), bias_est=(-1e-6, 0.0, 1e-6), est_p=tuple(float(i) for i in range(21)),
        st_status=-9, n_st_used=10, n_st_gated=11, n_st_hostile=12, n_est_restarts=13)
    rep = adapter.reply_of(r, 7, 4, 216e6)
    assert rep.command.u == (0.1, 0.2, 0.3) and rep.command.u_wheels == (0.01, 0.02, 0.03, 0.04)
    assert (rep.law_id, rep.mode, rep.status, rep.step_ns, rep.overrun, rep.raw) == (3, 1, 5, 100_000, False, r)
    assert rep.estimate == Estimate(1, -4, (0.0, 0.6, 0.0, 0.8), (1e-3, 2e-3, 3e-3), (-1e-6, 0.0, 1e-6),
                                    tuple(float(i) for i in range(21)), -9, 10, 11, 12, 13)
    assert adapter.reply_of(r, 7, 0, 216e6).command.u_wheels == ()
    # policy none: no unloading command; the momentum telemetry as it came
    assert (rep.command.thruster_on_s, rep.command.u_dipole_am2) == ((), ())
    assert rep.momentum == Momentum(thruster_on_s=(0.0,) * 12)


def test_the_reply_carries_the_unloading_commands_of_the_policy():
    """Version 4: as LcmCodec reads actuator_cmd_t: thrusters policy (2) the first n_thrusters on-times,
    magnetorquers (1) the dipole."""
    base = dataclasses.replace(frame.StepReply.decode(bytes(frame.STEP_REPLY.size)), mom_status=-2, n_thrusters=8,
                               thruster_on_s=tuple(0.001 * (i + 1) for i in range(12)), dipole_am2=(1.5, -2.5, 0.5),
                               u_unload=(-0.1, 0.2, -0.3), h_wheels=(10.0, -5.0, 3.0), dh=(9.0, -5.0, 3.0),
                               unloading=1, n_unload_events=3)
    rep = adapter.reply_of(dataclasses.replace(base, mom_policy=2), 7, 0, 216e6)
    assert rep.command.thruster_on_s == tuple(0.001 * (i + 1) for i in range(8)) and rep.command.u_dipole_am2 == ()
    assert rep.momentum == Momentum(2, -2, 8, tuple(0.001 * (i + 1) for i in range(12)), (1.5, -2.5, 0.5),
                                    (-0.1, 0.2, -0.3), (10.0, -5.0, 3.0), (9.0, -5.0, 3.0), True, 3)
    rep = adapter.reply_of(dataclasses.replace(base, mom_policy=1), 7, 0, 216e6)
    assert rep.command.thruster_on_s == () and rep.command.u_dipole_am2 == (1.5, -2.5, 0.5)


def test_the_magnetometer(aocs_lcm):
    """Its bit becomes the executive's MAG; the field passes as it is, flag or not."""
    b = valid_bits()
    f = SensorFrame(3, 0.3, b.attitude | b.magnetometer, Q, W, Z, Z, (), (0.0, 0.0, 0.0, 1.0), 0.0, Z,
                    (2.5e-5, math.nan, -1e-6))
    s = _step(adapter.step_payload(f))
    assert s["valid"] == adapter.EXEC_VALID_ATT | adapter.EXEC_VALID_MAG
    assert s["mag_b_t"][0] == 2.5e-5 and math.isnan(s["mag_b_t"][1]) and s["mag_b_t"][2] == -1e-6
    s = _step(adapter.step_payload(SensorFrame(3, 0.3, b.attitude, Q, W, Z, Z, (), (0.0, 0.0, 0.0, 1.0), 0.0, Z,
                                               (2.5e-5, 0.0, 0.0))))
    assert s["valid"] == adapter.EXEC_VALID_ATT and s["mag_b_t"] == (2.5e-5, 0.0, 0.0)
