"""Rate sensor (SPEC 3.5): w_meas = w_true + bias + noise (rad/s, B).

Keys in [sensors]: rate_noise_rad_s, rate_bias_rad_s. Sample: w, w_valid. Faults: dropout, nan.
Seeded stream "rate" (1).
"""
from __future__ import annotations

from .additive import AdditiveSensor
from .base import ATTITUDE, register


@register
class RateSensor(AdditiveSensor):
    name = "rate"
    stream_index = 1
    applies_to = (ATTITUDE,)
    noise_key, bias_key = "rate_noise_rad_s", "rate_bias_rad_s"
    keys = (noise_key, bias_key)
    value_field, valid_field = "w", "w_valid"
    truth_field = "w"
    fault_kinds = ("dropout", "nan")

    def source(self, plant):
        body = plant.body
        return lambda: body.w
