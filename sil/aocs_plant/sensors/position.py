"""Relative position sensor (SPEC 3.5, orbit plant): pos_meas = (x, y, z) + bias + noise (m, Bryson's
rotating frame, SPEC 2.8).

Keys in [sensors]: position_noise_m, position_bias_m. Sample: pos, pos_valid. Faults: dropout, nan.
Seeded stream "position" (2).
"""
from __future__ import annotations

from .additive import AdditiveSensor
from .base import ORBIT, register


@register
class PositionSensor(AdditiveSensor):
    name = "position"
    stream_index = 2
    applies_to = (ORBIT,)
    noise_key, bias_key = "position_noise_m", "position_bias_m"
    keys = (noise_key, bias_key)
    value_field, valid_field = "pos", "pos_valid"
    truth_field = "pos"
    fault_kinds = ("dropout", "nan")

    def source(self, plant):
        orbit = plant.orbit
        return lambda: (orbit.x[3], orbit.x[4], orbit.x[5])
