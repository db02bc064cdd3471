"""The LCM adapter: a SensorFrame published as sensors_t (AOCS_SENSORS), the flight computer's
actuator_cmd_t of the same tick (AOCS_ACTUATOR_CMD) read back as a Reply (docs/wire-contract.md).

LcmCodec is the packing and unpacking, shared by every LCM path: plant_node's hand-tuned recording loop
(aocs_runner.plant_node), this module's LcmFlightComputer (aocs_pil.harness.run against fsw_node or the
PIL bridge), the test helpers. It packs through aocs_wire.wire's one-struct codecs (byte for byte the
generated encode).
"""
from __future__ import annotations

import time

from aocs_wire import wire

from .frames import POLICY_MAGNETORQUERS, POLICY_THRUSTERS, Command, Estimate, Momentum, Reply, SensorFrame


class LcmCodec:
    """sensors_t from a SensorFrame, Command / Reply from an actuator_cmd_t (aocs_wire.wire.Codecs)."""

    def __init__(self, codecs: wire.Codecs, bindings):
        self.codecs = codecs
        st = bindings.sensors_t
        self.version = st.PROTOCOL_VERSION
        self.max_wheels = wmax = st.MAX_WHEELS
        self._pads = tuple((0.0,) * (wmax - n) for n in range(wmax + 1))   # unused wheel_speed slots
        self._pack_v = codecs.sensors.packer(self.version)   # this protocol version's frames: one call each
        a = codecs.actuator
        self.unpack = a.unpack
        #: unpack of actuator_cmd_t's head only, through thruster_latch_closed (the last field command() reads:
        #: the unloading actuators' commands of protocol versions 4 and 6): plant_node's loop
        self.unpack_command = a.unpacker("thruster_latch_closed")
        self.i_tick = a.index("tick")
        self.i_u = a.index("u_sat")
        self.i_uw = a.index("u_wheels")
        self.i_nw = a.index("n_wheels")
        self.i_unsat = a.index("u_unsat")
        self.i_law = a.index("law_id")
        self.i_mode = a.index("mode")
        self.i_status = a.index("status")
        self.i_step_ns = a.index("step_ns")
        self.i_overrun = a.index("overrun")
        # the estimate (protocol version 3): each field's index, Estimate's order
        self.i_est = tuple(a.index(n) for n in ("estimator", "est_status", "q_est", "w_est", "bias_est", "est_p",
                                                 "st_status", "n_st_used", "n_st_gated", "n_st_hostile",
                                                 "n_est_restarts"))
        self.n_p = a.fields[[n for n, _ in a.fields].index("est_p")][1]
        # the momentum-management stage (protocol version 4): each field's index, Momentum's order
        self.i_mom = tuple(a.index(n) for n in ("mom_policy", "mom_status", "n_thrusters", "thruster_on_s",
                                                 "dipole_am2", "u_unload", "h_wheels", "dh", "unloading",
                                                 "n_unload_events", "thruster_latch_closed"))
        self.max_thrusters = bindings.actuator_cmd_t.MAX_THRUSTERS

    def pack_sensors(self, f: SensorFrame, frame_no: int | None = None, version: int | None = None) -> bytes:
        """sensors_t of a frame: frame counter = tick unless given, utime = t_s in us, n_wheels = the
        tachometers it carries (the other slots zero), then the star tracker's, the gyro's and the
        magnetometer's fields."""
        return self.pack_fields(f.tick, f.t_s, f.valid, f.q, f.w, f.pos, f.vel, f.wheel_speed, f.st_q, f.st_t_meas_s,
                                f.gyro_w, f.mag_b_t, frame_no, version)

    def pack_fields(self, tick, t_s, valid, q, w, pos, vel, ws, st_q, st_t_meas_s, gyro_w, mag_b_t, frame_no=None,
                    version=None) -> bytes:
        """pack_sensors of a frame given as its fields (PlantPort.fields: plant_node's loop packs them without
        making a SensorFrame)."""
        n = len(ws)
        pack = self._pack_v if version is None else self.codecs.sensors.packer(version)
        return pack(tick if frame_no is None else frame_no, int(round(t_s * 1e6)), tick, t_s, valid, *q, *w, *pos,
                    *vel, n, *ws, *self._pads[n], *st_q, st_t_meas_s, *gyro_w, *mag_b_t)

    def command(self, v: tuple) -> Command:
        """The Command of actuator_cmd_t values (unpack, or unpack_command's head): u_sat, the first n_wheels
        wheel torques, and with the thrusters policy the first n_thrusters on-times and the latch valves, with
        the magnetorquers policy the dipole."""
        i, iw, n = self.i_u, self.i_uw, v[self.i_nw]
        if not 0 <= n <= self.max_wheels:
            n = min(max(n, 0), self.max_wheels)
        ip = self.i_mom[0]
        policy = v[ip]
        if policy == POLICY_THRUSTERS:
            it, nt = self.i_mom[3], min(max(v[self.i_mom[2]], 0), self.max_thrusters)
            return Command(v[self.i_tick], v[i:i + 3], v[iw:iw + n], v[it:it + nt], (), v[self.i_mom[10]])
        if policy == POLICY_MAGNETORQUERS:
            idp = self.i_mom[4]
            return Command(v[self.i_tick], v[i:i + 3], v[iw:iw + n], (), v[idp:idp + 3])
        return Command(v[self.i_tick], v[i:i + 3], v[iw:iw + n])

    def momentum(self, v: tuple) -> Momentum:
        """The Momentum of actuator_cmd_t values (the momentum fields, in the message's order)."""
        pol, st, nt, thr, dip, unl, hw, dh, on, ev, latch = self.i_mom
        m = self.max_thrusters
        return Momentum(v[pol], v[st], v[nt], v[thr:thr + m], v[dip:dip + 3], v[unl:unl + 3], v[hw:hw + 3],
                        v[dh:dh + 3], bool(v[on]), v[ev], v[latch])

    def estimate(self, v: tuple) -> Estimate:
        """The Estimate of actuator_cmd_t values (estimator, est_status, q_est, w_est, bias_est, est_p,
        st_status and the counts, in the message's order)."""
        est, st, q, w, b, p, ss, used, gated, hostile, restarts = self.i_est
        return Estimate(v[est], v[st], v[q:q + 4], v[w:w + 3], v[b:b + 3], v[p:p + self.n_p], v[ss], v[used],
                        v[gated], v[hostile], v[restarts])

    def reply(self, v: tuple) -> Reply:
        """The Reply of actuator_cmd_t values: the Command and the step's telemetry; raw = the values."""
        iu = self.i_unsat
        return Reply(self.command(v), v[iu:iu + 3], v[self.i_law], v[self.i_mode], v[self.i_status],
                     v[self.i_step_ns], bool(v[self.i_overrun]), v, self.estimate(v), self.momentum(v))


class LcmFlightComputer:
    """core.FlightComputer over LCM: step() publishes the frame's sensors_t and waits (bounded) for the
    actuator_cmd_t of its tick. Replies for another tick are counted (stale), undecodable ones too (bad).

    lc: an lcm.LCM (or aocs_wire.udpm.Udpm) handle; alive(tick): called while waiting, raises when the
    flight computer is gone (a process that exited)."""

    def __init__(self, lc, codec: LcmCodec, *, reply_timeout: float = 10.0, alive=None,
                 name: str = "flight computer"):
        self.lc, self.codec, self.reply_timeout, self.alive, self.name = lc, codec, reply_timeout, alive, name
        self.stale_replies = 0
        self.bad_replies = 0
        self._want = None
        self._box = None
        self._sub = lc.subscribe(wire.ACTUATOR, self._on_cmd)

    def _on_cmd(self, channel, data) -> None:  # noqa: ARG002
        v = self.codec.unpack(data)
        if v is None:
            self.bad_replies += 1
        elif v[self.codec.i_tick] == self._want:
            self._box = v
        else:
            self.stale_replies += 1

    def step(self, frame: SensorFrame) -> Reply:
        self._want, self._box = frame.tick, None
        self.lc.publish(wire.SENSORS, self.codec.pack_sensors(frame))
        end = time.monotonic() + self.reply_timeout
        while self._box is None:
            if self.alive is not None:
                self.alive(frame.tick)
            left = end - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"{self.name}: no actuator_cmd_t for tick {frame.tick} within "
                                   f"{self.reply_timeout} s")
            self.lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))
        return self.codec.reply(self._box)

    def close(self) -> None:
        self.lc.unsubscribe(self._sub)
