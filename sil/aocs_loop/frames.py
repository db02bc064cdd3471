"""What crosses the closed loop once per control period, defined once for every transport.

    port = PlantPort(plant)
    frame = port.sense(tick)           # from the plant side: the SensorFrame of tick k
    reply = flight_computer.step(frame)   # a transport adapter (core.FlightComputer)
    port.apply(reply.command)          # to the plant side: Plant.apply's command mapping
    plant.advance()

SensorFrame is what the flight software is given: the fields of the wire contract's sensors_t
(docs/wire-contract.md) without the transport's own (protocol version, frame counter, publication time).
Its `valid` bits are sensors_t's VALID_* bits, read from the generated bindings (valid_bits()); the
flight computer's node logic reads them (fsw_node's aocs_node_sensors_to_input, the PIL bridge's and
adapter's STEP payload). Command is what the plant takes back: the body torque (attitude) or force
(orbit), the wheel torques, one per wheel of the flight computer's array, and the momentum-management
stage's thruster on-times and magnetorquer dipole (sent only to a plant that has those actuators). Reply is the Command with
the step's telemetry (law, mode, status, timing, the attitude-determination stage's Estimate) and the
transport's own reply.

Every adapter packs a SensorFrame and unpacks its reply into a Command; only PlantPort makes a frame from
the plant and applies a command to it, so no path can pack a sensor or drop an actuator field on its own.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import NamedTuple

from aocs_core import paths

_Z3 = (0.0, 0.0, 0.0)
_Q1 = (0.0, 0.0, 0.0, 1.0)


class ValidBits(NamedTuple):
    """sensors_t's VALID_* bits (sil/lcmtypes/sensors_t.lcm), the meaning of SensorFrame.valid."""
    attitude: int
    rate: int
    position: int
    velocity: int
    wheels: int
    star_tracker: int   # st_q is a new sample of this period, measured at st_t_meas_s
    gyro: int
    magnetometer: int   # mag_b_t is a reading (protocol version 4)


@lru_cache(maxsize=1)
def valid_bits() -> ValidBits:
    """The bits of SensorFrame.valid, from the build's generated bindings (their one definition)."""
    s = paths.import_bindings().sensors_t
    return ValidBits(s.VALID_ATTITUDE, s.VALID_RATE, s.VALID_POSITION, s.VALID_VELOCITY, s.VALID_WHEELS,
                     s.VALID_STAR_TRACKER, s.VALID_GYRO, s.VALID_MAGNETOMETER)


def seconds_to_ns(t_s: float) -> int:
    """node_wire.c aocs_node_seconds_to_ns: llround(t_s * 1e9) for 0 < t_s < 1.8e10, else 0 (the flight
    software's sensor time, which fsw_node derives from sensors_t.t_s and the PIL STEP frame carries)."""
    if not (math.isfinite(t_s) and 0.0 < t_s < 1.8e10):
        return 0
    x = t_s * 1.0e9
    r = math.floor(x)
    return int(r + 1 if x - r >= 0.5 else r)   # round half away from zero, as llround


@dataclass(slots=True)
class SensorFrame:
    """The measurement of one control period, as the flight software gets it."""
    tick: int                 # control tick (echoed by the flight computer's reply)
    t_s: float                # sensor time, s (tick * dt; a stale-frame fault repeats the previous one)
    valid: int                # VALID_* bits (valid_bits())
    q: tuple                  # q_BN, scalar last ((0, 0, 0, 1) on an orbit plant)
    w: tuple                  # w_BN_B, rad/s (zeros on an orbit plant)
    pos: tuple                # orbit position error, m (zeros on an attitude plant)
    vel: tuple                # orbit velocity, m/s (zeros on an attitude plant)
    wheel_speed: tuple = ()   # tachometers, one per wheel of the array, rad/s (none without one)
    st_q: tuple = _Q1         # star tracker: q_SN of its last sample, scalar last (new: valid's star_tracker bit;
                              # identity before the first sample and without a tracker)
    st_t_meas_s: float = 0.0  # the sim time that sample measured, s (0 before the first)
    gyro_w: tuple = _Z3       # gyro: measured rate in B, rad/s, mean over the period (zeros without one)
    mag_b_t: tuple = _Z3      # magnetometer: geomagnetic field in B, T (valid's magnetometer bit; zeros without
                              # one: the plant has no sensor whose sample field is "mag_b_t")

    @property
    def t_ns(self) -> int:
        """The sensor time the flight software uses, ns (seconds_to_ns)."""
        return seconds_to_ns(self.t_s)

    @property
    def st_t_meas_ns(self) -> int:
        """The star tracker's time of measurement as the lockstep flight software gets it, ns: converted as t_s
        is (node_wire.c aocs_node_meas_time_ns with the sensor time t_ns)."""
        return seconds_to_ns(self.st_t_meas_s)

    @property
    def n_wheels(self) -> int:
        return len(self.wheel_speed)


@dataclass(slots=True)
class Command:
    """What the plant takes back from one flight computer step."""
    tick: int                 # the tick of the frame it answers
    u: tuple                  # body torque, N m, B (attitude) or force, N (orbit): actuator_cmd_t.u_sat
    u_wheels: tuple = ()      # wheel motor torques, N m, one per wheel of the flight computer's array
    thruster_on_s: tuple = () # thruster on-times of this period, s, one per thruster of the flight computer's
                              # configuration (mom.thr_count; none when its momentum policy is not thrusters)
    u_dipole_am2: tuple = ()  # magnetorquer dipole of each rod, A m^2 (3; none when the policy is not
                              # magnetorquers)
    thruster_latch_closed: int = 0  # bit b: the latch valve of thruster branch b closed (0 A, 1 B; protocol 6)


@dataclass(slots=True)
class Momentum:
    """The momentum-management stage's telemetry of one step (firmware momentum.h aocs_mom_output_t, the
    momentum fields of actuator_cmd_t and of the PIL STEP_REPLY); zero with policy none."""
    policy: int = 0           # momentum.def row (0 none, 1 magnetorquers, 2 thrusters)
    status: int = 0           # aocs_status_t of the stage's step
    n_thrusters: int = 0
    thruster_on_s: tuple = (0.0,) * 12
    dipole_am2: tuple = _Z3   # per rod, A m^2
    u_unload: tuple = _Z3     # body torque the unloading actuators are expected to apply, N m (taken off the wheels)
    h_wheels: tuple = _Z3     # wheel momentum the stage used, N m s, B
    dh: tuple = _Z3           # h_wheels - h_target, N m s
    unloading: bool = False   # a dump in progress this step
    n_events: int = 0         # unloads started so far
    latch_closed: int = 0     # bit b: the latch valve of thruster branch b closed (protocol version 6)

    def command_fields(self) -> tuple[tuple, tuple, int]:
        """(thruster_on_s, u_dipole_am2, thruster_latch_closed) of the Command: the first n_thrusters on-times
        and the latch valves with the thrusters policy, the dipole with the magnetorquers policy, else empty
        and 0 (the momentum.def row ids)."""
        n = max(0, min(int(self.n_thrusters), len(self.thruster_on_s)))
        thrusters = self.policy == POLICY_THRUSTERS
        thr = tuple(self.thruster_on_s[:n]) if thrusters else ()
        mtq = tuple(self.dipole_am2) if self.policy == POLICY_MAGNETORQUERS else ()
        return thr, mtq, (int(self.latch_closed) if thrusters else 0)


#: momentum.def row ids (the configuration key mom.policy)
POLICY_NONE, POLICY_MAGNETORQUERS, POLICY_THRUSTERS = 0, 1, 2


@dataclass(slots=True)
class Estimate:
    """The attitude-determination stage's estimate of one step (firmware estimate.h aocs_det_output_t, the
    estimate fields of actuator_cmd_t and of the PIL STEP_REPLY); a filter's telemetry is zero for the
    passthrough."""
    estimator: int = 0        # the determination row (estimation/determination.def; 0 = passthrough)
    status: int = 0           # aocs_status_t of the estimate (0: it drove the law)
    q: tuple = _Q1            # q_BN estimate, scalar last
    w: tuple = _Z3            # w_BN_B estimate, rad/s
    bias: tuple = _Z3         # gyro bias estimate in B, rad/s
    p_upper: tuple = (0.0,) * 21   # covariance of [dth; db], upper triangle row by row (P00 P01 .. P55)
    st_status: int = 0        # this step's star-tracker sample: 0 used, AOCS_ERR_INPUT_MISSING none, else why not
    n_st_used: int = 0
    n_st_gated: int = 0
    n_st_hostile: int = 0
    n_restarts: int = 0


@dataclass(slots=True)
class Reply:
    """A flight computer's answer to one SensorFrame: the Command and the step's telemetry."""
    command: Command
    u_unsat: tuple = _Z3      # the law's output before saturation
    law_id: int = 0
    mode: int = 0
    status: int = 0           # aocs_status_t of the step (0 = AOCS_OK)
    step_ns: int = 0          # the executive step's time (the PIL images: instructions over the clock)
    overrun: bool = False
    raw: object = None        # the transport's own reply (actuator_cmd_t values, frame.StepReply, ...)
    estimate: Estimate | None = None   # the step's attitude estimate (None: the transport gave none)
    momentum: Momentum | None = None   # the step's momentum-management telemetry (None: the transport gave none)


class WheelMismatch(ValueError):
    """The flight computer commands another number of wheels than the plant has (a setup error: both are
    built from the scenario's [wheels])."""

    def __init__(self, commanded: int, plant: int):
        super().__init__(f"the flight computer commands {commanded} wheel(s), the plant has {plant}")
        self.commanded, self.plant = commanded, plant


class ActuatorMismatch(ValueError):
    """The flight computer commands an actuator the plant does not have, or another number of them (a setup
    error: both are built from the scenario's [thrusters] / [magnetorquers])."""


class PlantPort:
    """The plant's end of the loop: the one place a SensorFrame is made from the plant (sense) and a
    Command applied to it (apply). Built once per run (the plant's kind and wheel count are fixed)."""

    def __init__(self, plant):
        self.plant = plant
        self.dt = plant.dt
        self.attitude = plant.kind == "attitude"
        wheels = plant.wheel_array
        self.n_wheels = wheels.n if wheels is not None else 0
        #: the command field of the body actuator (Plant.apply): torque in B, or force on the orbit plant
        self.u_field = "u_body" if self.attitude else "u_orbit"
        b = valid_bits()
        self.bits = b
        # the bits as plain ints, and the wheel bit of every frame of a plant with a wheel array (its
        # tachometers have no validity flag of their own): sense() is on every run's hot path
        self._att, self._rate, self._pos, self._vel = b.attitude, b.rate, b.position, b.velocity
        self._wheels = b.wheels if self.n_wheels else 0
        # the star tracker and the gyro, when the scenario has them (their sample fields in Plant.sense(): st_q,
        # st_valid, st_new, st_t_meas; gyro_w, or gyro_dtheta in the angle-increment mode, and gyro_valid)
        fields = {s.value_field for s in plant.sensors}
        self._st = b.star_tracker if "st_q" in fields else 0
        self._gyro = b.gyro if fields & {"gyro_w", "gyro_dtheta"} else 0
        self._gyro_angle = "gyro_dtheta" in fields   # angle increments: divided by the period, the mean rate
        # the magnetometer (protocol version 4), when the scenario has one: its sample fields mag_b_t, mag_valid
        self._mag = b.magnetometer if "mag_b_t" in fields else 0
        # the unloading actuators the plant has (Plant.command_fields: thruster_on_s N, u_dipole_am2 3). Plant.apply
        # holds a field a command leaves out, so a plant that has them is always sent them (zeros when the
        # flight computer commands none); one without them is never sent them
        cf = getattr(plant, "command_fields", {})
        self.n_thrusters = int(cf.get("thruster_on_s", 0))
        self.magnetorquers = "u_dipole_am2" in cf
        self._thr_zero = (0.0,) * self.n_thrusters

    def sense(self, tick: int, t_s: float | None = None) -> SensorFrame:
        """The plant's measurement of this period (Plant.sense) as the frame of `tick`; t_s defaults to
        tick * dt (a stale-frame fault gives the previous tick's)."""
        return SensorFrame(*self.fields(tick, t_s))

    def fields(self, tick: int, t_s: float | None = None) -> tuple:
        """sense() without the object: the SensorFrame's fields in their order (tick, t_s, valid, q, w, pos, vel,
        wheel_speed, st_q, st_t_meas_s, gyro_w, mag_b_t), what LcmCodec.pack_fields takes (plant_node's loop, one
        sensors_t per tick)."""
        s = self.plant.sense()
        if t_s is None:
            t_s = tick * self.dt
        if not self.attitude:
            return (tick, t_s, (self._pos if s["pos_valid"] else 0) | (self._vel if s["vel_valid"] else 0),
                    _Q1, _Z3, s["pos"], s["vel"], (), _Q1, 0.0, _Z3, _Z3)
        valid = (self._att if s["q_valid"] else 0) | (self._rate if s["w_valid"] else 0) | self._wheels
        ws = s["wheel_speed"] if self._wheels else ()
        if not (self._st or self._gyro or self._mag):
            return tick, t_s, valid, s["q"], s["w"], _Z3, _Z3, ws, _Q1, 0.0, _Z3, _Z3
        st_q, st_t, gyro_w, mag = _Q1, 0.0, _Z3, _Z3
        if self._st:
            st_q, st_t = tuple(s["st_q"]), s["st_t_meas"]
            if s["st_new"] and s["st_valid"]:   # a new sample, usable: the flag of this period only
                valid |= self._st
        if self._gyro:
            dt = self.dt
            gyro_w = tuple(x / dt for x in s["gyro_dtheta"]) if self._gyro_angle else tuple(s["gyro_w"])
            if s["gyro_valid"]:
                valid |= self._gyro
        if self._mag:
            mag = tuple(s["mag_b_t"])
            if s["mag_valid"]:
                valid |= self._mag
        return tick, t_s, valid, s["q"], s["w"], _Z3, _Z3, ws, st_q, st_t, gyro_w, mag

    def _unloading(self, cmd: Command, m: dict) -> None:
        """The unloading actuators' fields into m: thruster_on_s (with thruster_latch_closed) and u_dipole_am2
        when the plant has them (zeros when the command has none); ActuatorMismatch when the command has them
        and the plant does not, or another number of thrusters."""
        thr, mtq = cmd.thruster_on_s, cmd.u_dipole_am2
        n = self.n_thrusters
        if n:
            if thr and len(thr) != n:
                raise ActuatorMismatch(f"the flight computer commands {len(thr)} thruster(s), the plant has {n}")
            m["thruster_on_s"] = thr or self._thr_zero
            m["thruster_latch_closed"] = cmd.thruster_latch_closed
        elif thr:
            raise ActuatorMismatch(f"the flight computer commands {len(thr)} thruster(s), the plant has none "
                                   f"(no [thrusters])")
        if self.magnetorquers:
            m["u_dipole_am2"] = mtq or _Z3
        elif mtq:
            raise ActuatorMismatch("the flight computer commands magnetorquers, the plant has none "
                                   "(no [magnetorquers])")

    def command(self, cmd: Command) -> dict:
        """Plant.apply's mapping of a Command: the body field, the wheel torques when the plant has a wheel
        array (WheelMismatch when the flight computer's array is another size), the thruster on-times and the
        magnetorquer dipole when the plant has those actuators (ActuatorMismatch when they disagree)."""
        nw = self.n_wheels
        if len(cmd.u_wheels) != nw:
            raise WheelMismatch(len(cmd.u_wheels), nw)
        m = {self.u_field: cmd.u, "u_wheels": cmd.u_wheels} if nw else {self.u_field: cmd.u}
        if self.n_thrusters or self.magnetorquers or cmd.thruster_on_s or cmd.u_dipole_am2:
            self._unloading(cmd, m)
        return m

    def apply(self, cmd: Command) -> dict:
        """Apply a Command to the plant for this period (the mapping of command()); returns the mapping."""
        uw = cmd.u_wheels
        if len(uw) != self.n_wheels:
            raise WheelMismatch(len(uw), self.n_wheels)
        m = {self.u_field: cmd.u, "u_wheels": uw} if uw else {self.u_field: cmd.u}
        if self.n_thrusters or self.magnetorquers or cmd.thruster_on_s or cmd.u_dipole_am2:
            self._unloading(cmd, m)
        self.plant.apply(m)
        return m
