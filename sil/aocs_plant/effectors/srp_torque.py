"""Solar radiation pressure torque on the attitude (SPEC 3.3): `[disturbances.srp_torque]`.

F = (Pe/c)(1 + Y) A (1 AU / r)^2 along a direction fixed in B (a Sun
direction fixed in the body: adequate for the small motions of inertial
pointing), torque F x h with h the offset FROM the centre of pressure TO the
centre of mass (equivalently r_cp x F, r_cp = -h). Constant: folded once.
"""
from __future__ import annotations

from dataclasses import dataclass

from .base import ATTITUDE, Effector, Form, onoff, register, unit_vector

SOLAR_FLUX_1AU = 1361.0        # W/m^2 (total solar irradiance)
SPEED_OF_LIGHT = 299792458.0   # m/s


def srp_force_magnitude(area_m2: float, reflectivity: float, distance_au: float = 1.0,
                        flux_w_m2: float = SOLAR_FLUX_1AU) -> float:
    """F = (Pe / c)(1 + Y) A (1 AU / r)^2 (SPEC 3.3), N."""
    return flux_w_m2 / SPEED_OF_LIGHT * (1.0 + reflectivity) * area_m2 / (distance_au ** 2)


def srp_torque(force_b, h_b):
    """F x h (SPEC 3.3), h from the centre of pressure to the centre of mass, B frame."""
    f, h = force_b, h_b
    return (f[1] * h[2] - f[2] * h[1], f[2] * h[0] - f[0] * h[2], f[0] * h[1] - f[1] * h[0])


@dataclass(frozen=True)
class SrpTorqueConfig:
    enabled: bool
    scale: float
    area_m2: float
    reflectivity: float
    distance_au: float
    flux_w_m2: float
    direction_b: tuple
    cp_offset_m: tuple

    @property
    def torque_nm(self) -> tuple:
        f = self.scale * srp_force_magnitude(self.area_m2, self.reflectivity, self.distance_au, self.flux_w_m2)
        return srp_torque(tuple(f * d for d in self.direction_b), self.cp_offset_m)


@register
class SrpTorque(Effector):
    kind = "srp_torque"
    applies_to = (ATTITUDE,)
    form = Form.CONSTANT

    @classmethod
    def read(cls, sec, ctx) -> SrpTorqueConfig:
        en, scale = onoff(sec)
        return SrpTorqueConfig(
            en, scale, sec.number("area_m2", positive=True), sec.number("reflectivity", nonneg=True),
            sec.number("distance_au", required=False, default=1.0, positive=True),
            sec.number("flux_w_m2", required=False, default=SOLAR_FLUX_1AU, positive=True),
            unit_vector(sec, "direction_b"), sec.vector("cp_offset_m"))

    def __init__(self, config: SrpTorqueConfig, body):
        super().__init__(config, body)
        self._torque = config.torque_nm

    def value(self) -> tuple:
        return self._torque
