"""Sinusoidal disturbance torque in B: `[disturbances.sinusoidal_torque]` (SPEC 3.3, 2.6).

u_d,i(t) = scale * amplitude_nm_i * sin(frequency_rad_s_i * t + phase_rad_i), per body axis.
The disturbance that shows an H-infinity design's attenuation (a constant one is
rejected by the loop and cannot): `aocs compare geo_hinf --sweep` drives it
across the band. Evaluated at the exact time of every RK4 stage (GENERAL form,
no state), so it is integrated to RK4 accuracy whatever its frequency relative
to the substep: frequency * dt / substeps must stay below 0.5 rad (about 12
substeps a cycle), which the reader enforces.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .base import ATTITUDE, Effector, Form, onoff, register

#: largest phase advance of the sinusoid over one RK4 substep, rad (RK4 resolves it well below 1)
MAX_PHASE_PER_SUBSTEP_RAD = 0.5


@dataclass(frozen=True)
class SinusoidalTorqueConfig:
    enabled: bool
    scale: float
    amplitude_nm: tuple                   # per body axis, N m, >= 0
    frequency_rad_s: tuple                # per body axis, rad/s, >= 0
    phase_rad: tuple                      # per body axis, rad


@register
class SinusoidalTorque(Effector):
    kind = "sinusoidal_torque"
    applies_to = (ATTITUDE,)
    form = Form.GENERAL

    @classmethod
    def read(cls, sec, ctx) -> SinusoidalTorqueConfig:
        en, scale = onoff(sec)
        amp = sec.vector("amplitude_nm", nonneg=True)
        freq = sec.vector("frequency_rad_s", nonneg=True)
        phase = sec.vector("phase_rad", required=False, default=(0.0, 0.0, 0.0))
        h = ctx.dt / ctx.substeps
        fastest = max(freq)
        if fastest * h > MAX_PHASE_PER_SUBSTEP_RAD:
            sec.fail(sec.key("frequency_rad_s"),
                     f"{fastest:g} rad/s advances {fastest * h:.3g} rad per RK4 substep of {h:g} s, more than "
                     f"{MAX_PHASE_PER_SUBSTEP_RAD:g}: raise [integrator] substeps to at least "
                     f"{math.ceil(fastest * ctx.dt / MAX_PHASE_PER_SUBSTEP_RAD)}")
        return SinusoidalTorqueConfig(en, scale, amp, freq, phase)

    def __init__(self, config: SinusoidalTorqueConfig, body):
        super().__init__(config, body)
        s = config.scale
        self._a = tuple(s * a for a in config.amplitude_nm)
        self._w = config.frequency_rad_s
        self._p = config.phase_rad

    def torque(self, t: float) -> tuple:
        a, w, p, sin = self._a, self._w, self._p, math.sin
        return (a[0] * sin(w[0] * t + p[0]), a[1] * sin(w[1] * t + p[1]), a[2] * sin(w[2] * t + p[2]))

    def derivative(self, t: float, body: tuple, x: tuple) -> tuple:
        return self.torque(t), ()
