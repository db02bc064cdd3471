"""Wheel tachometers (SPEC 5.3 "wheel speeds from tachometers"): one reading per wheel of a [wheels]
array, the true speed relative to the body at the sample time (no latency), plus white noise, then
rounded to a multiple of the quantum:

    Omega_meas,i = quantum * round((Omega_i + n_i) / quantum),  n_i ~ N(0, noise^2)   (quantum 0: no rounding)

Its keys are in the array's own section (one description of the array, as the flight software's wheel
configuration is): [wheels] tach_noise_rad_s, tach_quantum_rad_s. Built only when the scenario has an
enabled [wheels] section. Sample: wheel_speed (no validity flag, no faults). Seeded stream "tachometer"
(5), one draw of N values per period.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..rng import NormalStream
from .base import ATTITUDE, Sensor, register

WHEELS = "wheels"   # the effector kind whose speeds it reads


@dataclass(frozen=True)
class TachometerConfig:
    n: int                    # wheels
    noise_rad_s: float        # white noise std (0 = none)
    quantum_rad_s: float      # quantisation step (0 = none)

    @property
    def ideal(self) -> bool:
        return self.noise_rad_s == 0.0 and self.quantum_rad_s == 0.0


@register
class Tachometer(Sensor):
    name = "tachometer"
    stream_index = 5
    applies_to = (ATTITUDE,)
    keys = ()
    value_field, valid_field = "wheel_speed", None
    truth_field = "wheels.speed_rad_s"
    delayed = False

    @classmethod
    def read(cls, sec, ctx):
        w = ctx.effectors.get(WHEELS)
        if w is None or not getattr(w, "enabled", True):
            return None
        return TachometerConfig(w.n, w.tach_noise_rad_s, w.tach_quantum_rad_s)

    def __init__(self, config: TachometerConfig, ctx):
        super().__init__(config, ctx)
        self.n = int(config.n)
        self.stream = NormalStream(ctx.seed, self.name, config.noise_rad_s, width=self.n) \
            if config.noise_rad_s > 0.0 else None
        self.quantum = float(config.quantum_rad_s)

    def source(self, plant):
        wheels = next(e for e in plant.effectors if e.kind == WHEELS)
        return lambda: wheels.speeds(plant.body_state(), plant.effector_state(wheels))

    def measure(self, speeds) -> tuple:
        v = tuple(float(s) for s in speeds)
        if self.stream is not None:
            e = self.stream.next()
            v = tuple(a + b for a, b in zip(v, e))
        q = self.quantum
        if q > 0.0:
            v = tuple(q * round(a / q) for a in v)
        return v
