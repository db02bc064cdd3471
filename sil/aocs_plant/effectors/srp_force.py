"""Constant solar radiation pressure force on the orbit plant (SPEC 3.3): `[disturbances.srp_force]`.

F = scale * pressure * area along a fixed rotating-frame direction (the
reference: 4.4e-6 N/m^2 on 3 m^2, 1.32e-5 N). Constant: folded once.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import ORBIT, Effector, Form, onoff, register, unit_vector


@dataclass(frozen=True)
class SrpForceConfig:
    enabled: bool
    scale: float
    pressure_n_m2: float
    area_m2: float
    direction: tuple                      # unit, Bryson's rotating frame

    @property
    def force_n(self) -> tuple:
        f = self.scale * self.pressure_n_m2 * self.area_m2
        return tuple(f * d for d in self.direction)


@register
class SrpForce(Effector):
    kind = "srp_force"
    applies_to = (ORBIT,)
    form = Form.CONSTANT

    @classmethod
    def read(cls, sec, ctx) -> SrpForceConfig:
        en, scale = onoff(sec)
        return SrpForceConfig(en, scale, sec.number("pressure_n_m2", positive=True),
                              sec.number("area_m2", positive=True), unit_vector(sec, "direction"))

    def __init__(self, config: SrpForceConfig, body):
        super().__init__(config, body)
        self._force = config.force_n

    def value(self) -> tuple:
        return self._force
