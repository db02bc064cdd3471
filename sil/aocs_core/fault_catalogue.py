"""The fault catalogue (issue 26; docs/spec.md 5.14): every kind the plant can inject (aocs_plant.faults), what
it affects, its parameters, and what the flight software is expected to do about it (aocs_analysis.faults).

One row per kind: the device it acts on (the scenario must have it), whether it takes a unit index (wheel,
thruster, gyro axis), the unit kind the flight software isolates (the event table's unit kinds:
star_tracker, gyro, wheel, thruster, link), whether a detection and an isolation are expected, and its
parameters with their defaults and rules. The models are in the device modules of aocs_plant.faults; the
table is here, below both the plant and the analysis that reads it.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

#: the devices a fault acts on (the scenario must have the device)
STAR_TRACKER, GYRO, WHEELS, THRUSTERS, LINK = "star_tracker", "gyro", "wheels", "thrusters", "link"


@dataclass(frozen=True)
class Param:
    key: str
    kind: str                 # "number" | "vector" | "axis" (a non-zero 3-vector, normalised when read)
    default: object = None    # None: required (a number / vector), or "none" for an optional one (OPTIONAL)
    rule: str = ""            # "positive" | "nonneg" | "" (any finite)
    meaning: str = ""


OPTIONAL = "optional"         # a parameter that may be absent (the model then says what it does)


@dataclass(frozen=True)
class Kind:
    name: str
    device: str               # STAR_TRACKER | GYRO | WHEELS | THRUSTERS | LINK
    unit: str | None          # what `unit` indexes: "wheel", "thruster", "axis"; None: no unit
    isolate_kind: str         # the unit kind the flight software isolates (events.def unit kinds)
    detect_expected: bool
    isolate_expected: bool
    params: tuple = ()
    meaning: str = ""
    #: events that also detect this kind whatever unit they name (the momentum test cannot tell a stuck-open
    #: thruster from its twin: thruster_stuck_open may name either, momentum_inconsistent names none)
    detected_by: tuple = ()

    def isolation_unit(self, unit):
        """The unit index the flight software's events name for this fault (None: the device has one)."""
        return unit if self.unit in ("wheel", "thruster") else None


def _k(name, device, unit, isolate_kind, detect, isolate, params=(), meaning="", detected_by=()):
    return Kind(name, device, unit, isolate_kind, detect, isolate, tuple(params), meaning, tuple(detected_by))


KINDS = {k.name: k for k in (
    _k("st_outage", STAR_TRACKER, None, "star_tracker", False, False, (),
       "no sample is delivered: st_valid and st_new false, the last delivered attitude repeated (the sensor flags "
       "itself: nothing to detect or isolate)"),
    _k("st_frozen", STAR_TRACKER, None, "star_tracker", True, True, (),
       "the attitude of the last sample before the fault repeated, flagged valid and new at the sample rate"),
    _k("st_bias_step", STAR_TRACKER, None, "star_tracker", True, True,
       (Param("bias_arcsec", "number", None, "", "rotation angle of the step, arcsec"),
        Param("axis", "axis", (1.0, 0.0, 0.0), "", "its axis in the tracker frame S (normalised)")),
       "the error rotation of every sample gains bias_arcsec about axis: e' = e + b a"),
    _k("st_noise_increase", STAR_TRACKER, None, "star_tracker", True, False,
       (Param("factor", "number", 10.0, "positive", "multiplies the white noise (its standard deviation)"),),
       "the white part n of the error rotation multiplied by factor: e' = b + factor n + l"),
    _k("gyro_bias_step", GYRO, None, "gyro", True, False,
       (Param("bias_rad_s", "vector", None, "", "the step added to the true bias, rad/s, B"),),
       "the true bias jumps by bias_rad_s: beta' = beta + db (the truth's bias too)"),
    _k("gyro_stuck_axis", GYRO, "axis", "gyro", True, True, (),
       "the output of axis `unit` (0 x, 1 y, 2 z) holds its last value before the fault"),
    _k("gyro_saturation", GYRO, None, "gyro", True, False,
       (Param("saturation_rad_s", "number", None, "positive", "the reduced range, rad/s per axis"),),
       "every axis clipped to +-saturation_rad_s (below the sensor's own range)"),
    _k("wheel_stuck", WHEELS, "wheel", "wheel", True, True,
       (Param("speed_rad_s", "number", OPTIONAL, "", "the speed the rotor is held at relative to the body "
                                                         "(default: its speed at the fault's start; 0: seized)"),
        Param("stop_time_s", "number", 1.0, "positive", "time constant of the stop that holds it, s")),
       "the rotor no longer follows its motor: the stop's torque -Js (Omega - Omega_held) / T_stop holds its "
       "speed; motor and friction have no effect; the body takes the reaction"),
    _k("wheel_torque_loss", WHEELS, "wheel", "wheel", True, True, (),
       "the motor torque is zero (the motor is dead); friction stays: the wheel coasts down"),
    _k("wheel_tach_failure", WHEELS, "wheel", "wheel", True, True,
       (Param("value_rad_s", "number", 0.0, "", "what the tachometer reads, rad/s"),),
       "the wheel's tachometer reads value_rad_s whatever the speed"),
    _k("wheel_friction_increase", WHEELS, "wheel", "wheel", True, False,
       (Param("factor", "number", 5.0, "positive", "multiplies the wheel's friction (viscous and Coulomb)"),),
       "the wheel's friction f(Omega) multiplied by factor"),
    _k("thruster_stuck_closed", THRUSTERS, "thruster", "thruster", True, True, (),
       "the thruster gives no thrust whatever its command", ("momentum_inconsistent",)),
    _k("thruster_stuck_open", THRUSTERS, "thruster", "thruster", True, True, (),
       "the thruster fires continuously (on-time the whole period, propellant counted)",
       ("momentum_inconsistent", "thruster_stuck_open")),
    _k("link_drop_burst", LINK, None, "link", True, False, (),
       "every sensor message of the interval is dropped (the transport's drop event at each tick)"),
)}


def check_param(p: Param, value, fail) -> object:
    """The value of parameter p checked (fail(what) raises naming the key); a vector as a tuple."""
    def number(x, where=""):
        if isinstance(x, bool) or not isinstance(x, (int, float)) or not math.isfinite(float(x)):
            fail(f"{where}expected a finite number, got {x!r}")
        x = float(x)
        if p.rule == "positive" and not x > 0.0:
            fail(f"{where}must be > 0, got {x!r}")
        if p.rule == "nonneg" and x < 0.0:
            fail(f"{where}must be >= 0, got {x!r}")
        return x
    if p.kind == "number":
        return number(value)
    if not isinstance(value, (list, tuple)) or len(value) != 3:
        fail(f"expected an array of 3 numbers, got {value!r}")
    v = tuple(number(x, f"[{i}] ") for i, x in enumerate(value))
    if p.kind == "axis":
        n = math.sqrt(sum(x * x for x in v))
        if not n > 0.0:
            fail("the axis must not be zero")
        v = tuple(x / n for x in v)
    return v
