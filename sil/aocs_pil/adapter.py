"""The PIL adapter of the closed loop (aocs_loop.core): a SensorFrame as one STEP frame to the flight image
under QEMU, its STEP_REPLY as a Reply.

step_payload is the one translation of a SensorFrame into the image's executive input, shared with the
bridge (aocs_pil.bridge turns each sensors_t into a SensorFrame, then into this payload), so the bridge path
and the direct path (harness.run_direct) feed the image the same bytes. It reads the frame as fsw_node reads
a sensors_t (node_wire.c aocs_node_sensors_to_input): attitude and rate bits as they are, the orbit bit when
both position and velocity are valid, a wheel the frame does not measure as NaN, the star tracker's and the
gyro's bits as they are, the tracker's time of measurement converted as the sensor time is, the
magnetometer's bit and field as they are.
"""
from __future__ import annotations

import math

from aocs_loop.frames import Command, Estimate, Momentum, Reply, SensorFrame, valid_bits

from . import frame
from .qemu import Qemu

#: the executive input's validity bits of the STEP frame (aocs_exec_input_t.valid, exec/io.h: ATT, RATE, ORBIT,
#: ST, GYRO, MAG)
EXEC_VALID_ATT, EXEC_VALID_RATE, EXEC_VALID_ORBIT, EXEC_VALID_ST, EXEC_VALID_GYRO, EXEC_VALID_MAG = 1, 2, 4, 8, 16, 32


def step_payload(f: SensorFrame) -> bytes:
    """The STEP payload of a SensorFrame."""
    b = valid_bits()
    v = f.valid
    valid = ((EXEC_VALID_ATT if v & b.attitude else 0) | (EXEC_VALID_RATE if v & b.rate else 0)
             | (EXEC_VALID_ORBIT if (v & b.position) and (v & b.velocity) else 0)
             | (EXEC_VALID_ST if v & b.star_tracker else 0) | (EXEC_VALID_GYRO if v & b.gyro else 0)
             | (EXEC_VALID_MAG if v & b.magnetometer else 0))
    ws = f.wheel_speed if v & b.wheels else ()
    wheels = [ws[i] if i < len(ws) else math.nan for i in range(frame.WHEELS_MAX)]
    return frame.encode_step(f.tick, f.t_ns, valid, f.q, f.w, f.pos, f.vel, wheels, st_q=f.st_q,
                             st_t_meas_ns=f.st_t_meas_ns, gyro_w=f.gyro_w, mag_b_t=f.mag_b_t)


def step_status(r: frame.StepReply) -> int:
    """The status of a step as fsw_node reports it (step_status()): the step's return code, else the input
    status, else the law status, else the wheel allocation's status."""
    return r.step_status or r.input_status or r.law_status or r.wheel_status


def estimate_of(r: frame.StepReply) -> Estimate:
    """The Estimate of a STEP_REPLY (its estimate rows)."""
    return Estimate(r.estimator, r.est_status, r.q_est, r.w_est, r.bias_est, r.est_p, r.st_status, r.n_st_used,
                    r.n_st_gated, r.n_st_hostile, r.n_est_restarts)


def momentum_of(r: frame.StepReply) -> Momentum:
    """The Momentum of a STEP_REPLY (its momentum rows)."""
    return Momentum(r.mom_policy, r.mom_status, r.n_thrusters, tuple(r.thruster_on_s), tuple(r.dipole_am2),
                    tuple(r.u_unload), tuple(r.h_wheels), tuple(r.dh), bool(r.unloading), r.n_unload_events,
                    r.thruster_latch_closed)


def reply_of(r: frame.StepReply, tick: int, n_wheels: int, clock_hz: float) -> Reply:
    """The Reply of a STEP_REPLY: u_cmd and the first n_wheels wheel torques (the configuration's array;
    the frame carries WHEELS_MAX), the unloading actuators' commands of the momentum policy (as LcmCodec
    reads them), step_ns = the step's instructions at the target's nominal clock, the estimate and the
    momentum telemetry."""
    mom = momentum_of(r)
    thr, mtq, latch = mom.command_fields()
    cmd = Command(tick, r.u_cmd, r.u_wheels[:n_wheels], thr, mtq, latch)
    return Reply(cmd, r.u_unsat, r.law, r.mode, step_status(r), int(round(r.instructions * 1e9 / clock_hz)),
                 bool(r.overrun), r, estimate_of(r), mom)


class PilFlightComputer:
    """aocs_loop.core.FlightComputer over the PIL frames: one STEP / STEP_REPLY exchange per period with
    a started and configured image (q: a Qemu after start() and CONFIG); n_wheels: the configuration's
    wheel count (wheels.count)."""

    def __init__(self, q: Qemu, n_wheels: int):
        self.q, self.n_wheels = q, int(n_wheels)
        self.clock_hz = q.target.clock_hz

    def step(self, f: SensorFrame) -> Reply:
        _, p = self.q.request(frame.T_STEP, step_payload(f), frame.T_STEP_REPLY)
        r = frame.StepReply.decode(p)
        if r.tick != (f.tick & 0xFFFFFFFF):
            raise frame.FrameError(f"reply for tick {r.tick}, request was tick {f.tick}")
        return reply_of(r, f.tick, self.n_wheels, self.clock_hz)
