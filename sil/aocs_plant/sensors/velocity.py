"""Velocity sensor (SPEC 3.5, orbit plant): vel_meas = (u, v, w) + bias + noise (m/s): the inertial
velocity resolved in Bryson's rotating frame, as the orbit state holds it (SPEC 2.8).

Keys in [sensors]: velocity_noise_m_s, velocity_bias_m_s. Sample: vel, vel_valid. Faults: dropout, nan.
Seeded stream "velocity" (3).
"""
from __future__ import annotations

from .additive import AdditiveSensor
from .base import ORBIT, register


@register
class VelocitySensor(AdditiveSensor):
    name = "velocity"
    stream_index = 3
    applies_to = (ORBIT,)
    noise_key, bias_key = "velocity_noise_m_s", "velocity_bias_m_s"
    keys = (noise_key, bias_key)
    value_field, valid_field = "vel", "vel_valid"
    truth_field = "vel"
    fault_kinds = ("dropout", "nan")

    def source(self, plant):
        orbit = plant.orbit
        return lambda: (orbit.x[0], orbit.x[1], orbit.x[2])
