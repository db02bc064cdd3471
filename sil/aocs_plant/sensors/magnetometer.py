"""Three-axis magnetometer (docs/spec.md 5.8.4): the geomagnetic field in B.

Its section [sensors.magnetometer] builds it (absent: no magnetometer). At each sample (period k):

    b_B = A(q_k) B_N(t_k) + bias_t + n_k,   n_k ~ N(0, noise_t^2 I3)      (tesla)

with B_N the environment's field model along the orbit (environment.magnetic_field.FieldAlongOrbit: the
model's own value at t_k) and A(q) = R_BN; without a field model or an orbit the true field is zero. It
is a delayed sensor (the suite's latency_periods applies). Sample: mag_b_t (T, B), mag_valid. Faults:
dropout, nan. Seeded stream "magnetometer" (8), one draw of 3 normals per sample when noise_t > 0.
Truth: the true field in B of the last sample and its error (bias + noise).
"""
from __future__ import annotations

from aocs_core.conventions import quat_rotate

from ..environment.magnetic_field import FieldAlongOrbit
from .additive import AdditiveSensor, NoiseBiasConfig, read_noise_bias
from .base import ATTITUDE, ZERO3, register

SECTION = "magnetometer"


class MagnetometerConfig(NoiseBiasConfig):
    @property
    def ideal(self) -> bool:       # not the ideal sensor set: a magnetometer is an added sensor
        return False


@register
class Magnetometer(AdditiveSensor):
    name = "magnetometer"
    stream_index = 8
    applies_to = (ATTITUDE,)
    keys = (SECTION,)
    value_field, valid_field = "mag_b_t", "mag_valid"
    truth_field = "mag_b_t"
    fault_kinds = ("dropout", "nan")

    @classmethod
    def read(cls, sec, ctx):
        m = sec.table(SECTION, required=False)
        if m is None:
            return None
        m.only(("noise_t", "bias_t"))
        c = read_noise_bias(m, "noise_t", "bias_t")
        m.done()
        return MagnetometerConfig(c.noise, c.bias)

    def __init__(self, config, ctx):
        super().__init__(config, ctx)
        self.field = FieldAlongOrbit(ctx.environment, ctx.dt)
        self.field(0.0)
        self.true_b = ZERO3

    def source(self, plant):
        body, field = plant.body, self.field

        def b_b():
            b = field(plant.t)
            return ZERO3 if b is None else quat_rotate(body.q, b)
        return b_b

    def measure(self, value):
        self.true_b = tuple(value)
        return super().measure(value)

    def truth(self) -> dict:
        """Of the last sample: the true field in B (T) and the error (bias + noise)."""
        return {"field_b_t": self.true_b, "error": self.error}
