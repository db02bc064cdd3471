"""A multisine added at the plant input, held over each control period: `[disturbances.input_injection]`.

    d(k) = scale * direction * sum_i amplitude_nm * sin(frequency_rad_s_i * t_k + phase_i),   t_k = k dt,

held (zero-order hold, like the command) over period k, so the plant input is e(k) = u_applied(k) + d(k),
a sequence the loop transfer L(z) at the plant input acts on exactly (`aocs analyze --measure`: the
loop broken at the plant input, measured from the log as L = -U_applied / E at every tone). The phases
default to Schroeder's, phase_i = -pi i (i - 1) / n, which keep the peak of the sum low (M. R. Schroeder,
"Synthesis of low-peak-factor signals and binary sequences with low autocorrelation", IEEE Trans.
Information Theory 16(1), 1970). The tones must stay below the Nyquist frequency pi / dt.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .base import ATTITUDE, Effector, Form, onoff, register, unit_vector


@dataclass(frozen=True)
class InputInjectionConfig:
    enabled: bool
    scale: float
    amplitude_nm: float                # per tone, N m
    frequency_rad_s: tuple             # the tones, rad/s
    phase_rad: tuple                   # per tone
    direction: tuple                   # unit vector in B


def multisine(config: InputInjectionConfig, t: float) -> float:
    """The scalar multisine at t, N m (times config.direction it is the held torque)."""
    a = config.scale * config.amplitude_nm
    return a * sum(math.sin(w * t + p) for w, p in zip(config.frequency_rad_s, config.phase_rad))


def schroeder_phases(n: int) -> tuple:
    return tuple(-math.pi * i * (i - 1) / n for i in range(1, n + 1))


@register
class InputInjection(Effector):
    kind = "input_injection"
    applies_to = (ATTITUDE,)
    form = Form.HELD

    @classmethod
    def read(cls, sec, ctx) -> InputInjectionConfig:
        en, scale = onoff(sec)
        amp = sec.number("amplitude_nm", nonneg=True)
        freq = sec.array("frequency_rad_s", positive=True)
        nyquist = math.pi / ctx.dt
        if max(freq) >= nyquist:
            sec.fail(sec.key("frequency_rad_s"), f"{max(freq):g} rad/s is not below the Nyquist frequency "
                     f"pi / dt = {nyquist:g} rad/s of the {ctx.dt:g} s control period")
        if sec.has("phase_rad"):
            phase = sec.array("phase_rad")
            if len(phase) != len(freq):
                sec.fail(sec.key("phase_rad"), f"{len(phase)} phases for {len(freq)} frequencies")
        else:
            phase = schroeder_phases(len(freq))
        return InputInjectionConfig(en, scale, amp, freq, phase, unit_vector(sec, "direction"))

    def __init__(self, config: InputInjectionConfig, body):
        super().__init__(config, body)
        self._held = (0.0, 0.0, 0.0)

    def begin_period(self, t: float, x: tuple) -> None:
        s = multisine(self.config, t)
        e = self.config.direction
        self._held = (s * e[0], s * e[1], s * e[2])

    def value(self) -> tuple:
        return self._held
