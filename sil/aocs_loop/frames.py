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
(orbit) and the wheel torques, one per wheel of the flight computer's array. Reply is the Command with
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


@lru_cache(maxsize=1)
def valid_bits() -> ValidBits:
    """The bits of SensorFrame.valid, from the build's generated bindings (their one definition)."""
    s = paths.import_bindings().sensors_t
    return ValidBits(s.VALID_ATTITUDE, s.VALID_RATE, s.VALID_POSITION, s.VALID_VELOCITY, s.VALID_WHEELS,
                     s.VALID_STAR_TRACKER, s.VALID_GYRO)


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


class WheelMismatch(ValueError):
    """The flight computer commands another number of wheels than the plant has (a setup error: both are
    built from the scenario's [wheels])."""

    def __init__(self, commanded: int, plant: int):
        super().__init__(f"the flight computer commands {commanded} wheel(s), the plant has {plant}")
        self.commanded, self.plant = commanded, plant


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

    def sense(self, tick: int, t_s: float | None = None) -> SensorFrame:
        """The plant's measurement of this period (Plant.sense) as the frame of `tick`; t_s defaults to
        tick * dt (a stale-frame fault gives the previous tick's)."""
        return SensorFrame(*self.fields(tick, t_s))

    def fields(self, tick: int, t_s: float | None = None) -> tuple:
        """sense() without the object: the SensorFrame's fields in their order (tick, t_s, valid, q, w, pos, vel,
        wheel_speed, st_q, st_t_meas_s, gyro_w), what LcmCodec.pack_fields takes (plant_node's loop, one
        sensors_t per tick)."""
        s = self.plant.sense()
        if t_s is None:
            t_s = tick * self.dt
        if not self.attitude:
            return (tick, t_s, (self._pos if s["pos_valid"] else 0) | (self._vel if s["vel_valid"] else 0),
                    _Q1, _Z3, s["pos"], s["vel"], (), _Q1, 0.0, _Z3)
        valid = (self._att if s["q_valid"] else 0) | (self._rate if s["w_valid"] else 0) | self._wheels
        ws = s["wheel_speed"] if self._wheels else ()
        if not (self._st or self._gyro):
            return tick, t_s, valid, s["q"], s["w"], _Z3, _Z3, ws, _Q1, 0.0, _Z3
        st_q, st_t, gyro_w = _Q1, 0.0, _Z3
        if self._st:
            st_q, st_t = tuple(s["st_q"]), s["st_t_meas"]
            if s["st_new"] and s["st_valid"]:   # a new sample, usable: the flag of this period only
                valid |= self._st
        if self._gyro:
            dt = self.dt
            gyro_w = tuple(x / dt for x in s["gyro_dtheta"]) if self._gyro_angle else tuple(s["gyro_w"])
            if s["gyro_valid"]:
                valid |= self._gyro
        return tick, t_s, valid, s["q"], s["w"], _Z3, _Z3, ws, st_q, st_t, gyro_w

    def command(self, cmd: Command) -> dict:
        """Plant.apply's mapping of a Command: the body field, and the wheel torques when the plant has a
        wheel array (WheelMismatch when the flight computer's array is another size)."""
        nw = self.n_wheels
        if len(cmd.u_wheels) != nw:
            raise WheelMismatch(len(cmd.u_wheels), nw)
        if nw:
            return {self.u_field: cmd.u, "u_wheels": cmd.u_wheels}
        return {self.u_field: cmd.u}

    def apply(self, cmd: Command) -> dict:
        """Apply a Command to the plant for this period (the mapping of command()); returns the mapping."""
        uw = cmd.u_wheels
        if len(uw) != self.n_wheels:
            raise WheelMismatch(len(uw), self.n_wheels)
        m = {self.u_field: cmd.u, "u_wheels": uw} if uw else {self.u_field: cmd.u}
        self.plant.apply(m)
        return m
