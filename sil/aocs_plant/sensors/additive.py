"""White noise plus a constant bias on a 3-vector (SPEC 3.5): the error model of the attitude, rate,
position and velocity sensors, and the base of the ones that add it to the truth.

    e_k = bias + n_k,  n_k ~ N(0, sigma^2 I3)   (one draw per period from the sensor's own stream)
    y_k = x_k + e_k                              (AdditiveSensor)

The draw happens in every period whether or not a fault hides the sample, so a fault never shifts
the later noise (SensorSuite).
"""
from __future__ import annotations

from dataclasses import dataclass

from ..rng import NormalStream
from .base import ZERO3, Sensor


@dataclass(frozen=True)
class NoiseBiasConfig:
    noise: float = 0.0          # sigma per axis, in the sensor's unit
    bias: tuple = ZERO3         # constant, same unit

    @property
    def ideal(self) -> bool:
        return self.noise == 0.0 and not any(self.bias)


def read_noise_bias(sec, noise_key: str, bias_key: str) -> NoiseBiasConfig:
    """The pair of keys `<x>_noise_<unit>` (>= 0, default 0) and `<x>_bias_<unit>` (3-array, default 0)."""
    return NoiseBiasConfig(sec.number(noise_key, required=False, default=0.0, nonneg=True),
                           sec.vector(bias_key, required=False, default=ZERO3))


class ErrorStream:
    """e_k = bias + n_k, the noise from the seeded stream of `channel` (none when sigma = 0)."""

    def __init__(self, seed: int, channel: str, config: NoiseBiasConfig):
        self.bias = config.bias
        self.stream = NormalStream(seed, channel, config.noise) if config.noise > 0.0 else None

    def next(self) -> tuple:
        b = self.bias
        n = self.stream.next() if self.stream is not None else ZERO3
        return (b[0] + n[0], b[1] + n[1], b[2] + n[2])


def _plus_zero(v):
    return (v[0] + 0.0, v[1] + 0.0, v[2] + 0.0)


class AdditiveSensor(Sensor):
    """A sensor measuring a 3-vector as y = x + bias + noise; subclasses name the keys and the truth."""

    noise_key: str = ""
    bias_key: str = ""

    @classmethod
    def read(cls, sec, ctx) -> NoiseBiasConfig:
        return read_noise_bias(sec, cls.noise_key, cls.bias_key)

    def __init__(self, config: NoiseBiasConfig, ctx):
        super().__init__(config, ctx)
        self.errors = ErrorStream(ctx.seed, self.name, config)
        self.error = ZERO3
        if config.ideal:          # e = 0 in every period: skip the stream (y = x + 0.0, as the general case)
            self.measure = _plus_zero

    def measure(self, value):
        e = self.errors.next()
        self.error = e
        return (value[0] + e[0], value[1] + e[1], value[2] + e[2])

    def truth(self) -> dict:
        """The error of the last sample (bias + noise, before faults)."""
        return {"error": self.error}
