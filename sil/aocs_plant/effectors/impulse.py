"""Impulsive delta-v on the orbit plant (SPEC 3.3, a debris hit): `[disturbances.impulse]`.

The inertial velocity (u, v, w) jumps by scale * delta_v_m_s * direction at
time_s (inside the run). A DISCRETE effector: the plant splits the control
period that contains time_s there; the sensor sample at exactly time_s
precedes the hit.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import ORBIT, Effector, Form, onoff, register, unit_vector


@dataclass(frozen=True)
class ImpulseConfig:
    enabled: bool
    scale: float
    time_s: float
    delta_v_m_s: float
    direction: tuple                      # unit, Bryson's rotating frame

    @property
    def delta_v(self) -> tuple:
        return tuple(self.scale * self.delta_v_m_s * d for d in self.direction)


@register
class Impulse(Effector):
    kind = "impulse"
    applies_to = (ORBIT,)
    form = Form.DISCRETE

    @classmethod
    def read(cls, sec, ctx) -> ImpulseConfig:
        en, scale = onoff(sec)
        t = sec.number("time_s", nonneg=True)
        if t >= ctx.duration_s:
            sec.fail(sec.key("time_s"), f"{t} s is not inside the run (duration_s = {ctx.duration_s})")
        return ImpulseConfig(en, scale, t, sec.number("delta_v_m_s", positive=True), unit_vector(sec, "direction"))

    def __init__(self, config: ImpulseConfig, body):
        super().__init__(config, body)
        self.done = False

    def event_times(self) -> tuple:
        return (self.config.time_s,)

    def jump(self, t: float, body: tuple) -> tuple:
        dv = self.config.delta_v
        self.done = True
        return (body[0] + dv[0], body[1] + dv[1], body[2] + dv[2], body[3], body[4], body[5])

    def truth(self, t, body, x) -> dict:
        return {"applied": self.done}
