"""Attitude sensor (SPEC 3.5): the measured quaternion, a small rotation away from the truth.

    q_meas = dq(e) (x) q_true,  e = bias + noise (rad, B),  then renormalised

dq(e) is the rotation by the rotation vector e, so A(q_meas) = A(dq) A(q_true) (SPEC 1, Shuster product).
Keys in [sensors]: attitude_noise_rad, attitude_bias_rad. Sample: q, q_valid. Faults: dropout, nan, and
nonunit (the quaternion times `factor`: the flight software's norm check). Seeded stream "attitude" (0).
"""
from __future__ import annotations

import math

from aocs_core.conventions import quat_from_rotvec, quat_mul

from .additive import ErrorStream, read_noise_bias
from .base import ATTITUDE, ZERO3, Sensor, register


def _identity(q):
    return q


@register
class AttitudeSensor(Sensor):
    name = "attitude"
    stream_index = 0
    applies_to = (ATTITUDE,)
    keys = ("attitude_noise_rad", "attitude_bias_rad")
    value_field, valid_field = "q", "q_valid"
    truth_field = "q"
    fault_kinds = ("dropout", "nan", "nonunit")
    initial_last = (0.0, 0.0, 0.0, 1.0)

    @classmethod
    def read(cls, sec, ctx):
        return read_noise_bias(sec, *cls.keys)

    def __init__(self, config, ctx):
        super().__init__(config, ctx)
        self.errors = ErrorStream(ctx.seed, self.name, config)
        self.error = ZERO3
        if config.ideal:          # dq = identity in every period: the truth as it is
            self.measure = _identity

    def source(self, plant):
        body = plant.body
        return lambda: body.q

    def measure(self, value):
        e = self.errors.next()
        self.error = e
        if e != ZERO3:
            q = quat_mul(quat_from_rotvec(e), value)
            s = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
            value = (q[0] * s, q[1] * s, q[2] * s, q[3] * s)
        return value

    def truth(self) -> dict:
        """The rotation vector of the last sample's error (rad, B; before faults)."""
        return {"error_rad": self.error}
