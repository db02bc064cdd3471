"""Constant disturbance torque in B (SPEC 3.3): `[disturbances.constant_torque]`.

u_d = scale * torque_nm, the same in every period; the integrator folds it
(with every other CONSTANT effector) into one constant torque.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import ATTITUDE, Effector, Form, onoff, register


@dataclass(frozen=True)
class ConstantTorqueConfig:
    enabled: bool
    scale: float
    torque_nm: tuple                      # body frame, N m


@register
class ConstantTorque(Effector):
    kind = "constant_torque"
    applies_to = (ATTITUDE,)
    form = Form.CONSTANT

    @classmethod
    def read(cls, sec, ctx) -> ConstantTorqueConfig:
        en, scale = onoff(sec)
        return ConstantTorqueConfig(en, scale, sec.vector("torque_nm"))

    def __init__(self, config: ConstantTorqueConfig, body):
        super().__init__(config, body)
        s = config.scale
        self._torque = tuple(s * t for t in config.torque_nm)

    def value(self) -> tuple:
        return self._torque
