"""Residual magnetic dipole (docs/spec.md 5.8.3): `[residual_dipole]`, a disturbance.

The spacecraft's own uncompensated dipole m_B (A m^2, fixed in B: currents in harnesses, magnetised
parts) in the geomagnetic field:

    tau_B = m_B x B_B,   B_B = A(q) B_N(t)                 (Wertz 1978)

with B_N(t) the environment's field model along the orbit, frozen at the midpoint of each substep (an
ATTITUDE-form term, as the magnetorquers'). Without a field model or an orbit the torque is zero.
Truth: the torque now (the default truth of a disturbance).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..environment.magnetic_field import FieldAlongOrbit
from .base import ATTITUDE, Effector, Form, register
from .magnetorquers import dipole_torque_term


@dataclass(frozen=True)
class ResidualDipoleConfig:
    dipole_am2: tuple            # m_B, A m^2
    enabled: bool = True


@register
class ResidualDipole(Effector):
    kind = "residual_dipole"
    group = None                 # a top-level section [residual_dipole]
    applies_to = (ATTITUDE,)
    role = "disturbance"
    form = Form.ATTITUDE
    time_varying = True

    @classmethod
    def read(cls, sec, ctx) -> ResidualDipoleConfig:
        sec.only(("dipole_am2", "enabled"))
        return ResidualDipoleConfig(sec.vector("dipole_am2"), sec.boolean("enabled", required=False, default=True))

    def __init__(self, config: ResidualDipoleConfig, body):
        super().__init__(config, body)
        self.field = FieldAlongOrbit(body.environment, body.dt)
        self.field(0.0)
        m = tuple(config.dipole_am2)
        self._term, self.at_time = dipole_torque_term(self.field, m)

    def term(self):
        return self._term
