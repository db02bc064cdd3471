"""Sensor models (SPEC 3): white noise, bias, latency, dropouts and invalid values.

One sample per control period k, from the truth of period k - latency
(clamped at 0). Noise: zero-mean Gaussian per axis, drawn from the seeded
per-channel streams of rng.py, one draw per period whether or not the
channel is faulted, so a fault never shifts later noise.

- attitude: q_meas = dq(bias + noise) (x) q_true, dq the small rotation by
  that rotation vector in B (A(q_meas) = A(dq) A(q_true)); renormalised.
- rate: w_meas = w_true + bias + noise (rad/s, B).
- position / velocity (orbit): truth + bias + noise, Bryson frame.

Faults, active for start_s <= t < end_s on one channel or on "all":
- dropout: valid flag False; the value repeats the last unfaulted value
  delivered (identity / zeros before the first one);
- nan: every component NaN, valid flag True (the flight software must catch it);
- nonunit: the attitude quaternion multiplied by `factor`, valid flag True.
"""
from __future__ import annotations

import math

from aocs_core.conventions import quat_from_rotvec, quat_mul

from .rng import NormalStream

_NAN3 = (math.nan, math.nan, math.nan)


class Sensors:
    def __init__(self, scenario):
        c = scenario.sensors
        self.cfg = c
        self.kind = scenario.kind
        self.dt = scenario.dt
        seed = scenario.seed
        if self.kind == "attitude":
            self.channels = ("attitude", "rate")
            spec = {"attitude": (c.attitude_noise_rad, c.attitude_bias_rad),
                    "rate": (c.rate_noise_rad_s, c.rate_bias_rad_s)}
        else:
            self.channels = ("position", "velocity")
            spec = {"position": (c.position_noise_m, c.position_bias_m),
                    "velocity": (c.velocity_noise_m_s, c.velocity_bias_m_s)}
        self.noise = {ch: (NormalStream(seed, ch, spec[ch][0]) if spec[ch][0] > 0.0 else None)
                      for ch in self.channels}
        self.bias = {ch: spec[ch][1] for ch in self.channels}
        self.latency = c.latency_periods
        self.history: list = []          # truth per period, trimmed to latency + 1
        first = (0.0, 0.0, 0.0, 1.0) if self.kind == "attitude" else (0.0, 0.0, 0.0)
        self.last = {self.channels[0]: first, self.channels[1]: (0.0, 0.0, 0.0)}
        self.faults = c.faults

    def record(self, truth_pair) -> None:
        """Store the truth (two tuples: q, w or pos, vel) of the current period."""
        self.history.append(truth_pair)
        if len(self.history) > self.latency + 1:
            del self.history[0]

    def _active(self, channel, t):
        for f in self.faults:
            if (f.channel == channel or f.channel == "all") and f.start_s <= t < f.end_s:
                return f
        return None

    def sample(self, t: float):
        """Measured values and validity flags at time t (after record() of this period)."""
        truth = self.history[0]  # period k - latency, or period 0 early in the run
        out = {}
        for i, ch in enumerate(self.channels):
            value = truth[i]
            b = self.bias[ch]
            stream = self.noise[ch]
            n = stream.next() if stream is not None else (0.0, 0.0, 0.0)
            e = (b[0] + n[0], b[1] + n[1], b[2] + n[2])
            if ch == "attitude":
                if e != (0.0, 0.0, 0.0):
                    q = quat_mul(quat_from_rotvec(e), value)
                    s = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
                    value = (q[0] * s, q[1] * s, q[2] * s, q[3] * s)
            else:
                value = (value[0] + e[0], value[1] + e[1], value[2] + e[2])
            valid = True
            f = self._active(ch, t)
            if f is not None:
                if f.kind == "dropout":
                    value, valid = self.last[ch], False
                elif f.kind == "nan":
                    value = (math.nan,) * len(value)
                elif f.kind == "nonunit" and ch == "attitude":
                    value = tuple(x * f.factor for x in value)
            else:
                self.last[ch] = value
            out[ch] = (value, valid)
        return out


class Tachometer:
    """Wheel speed readings (SPEC 5.3 "wheel speeds from tachometers"): the true speed relative to the
    body at the sample time (no latency), plus white noise (std noise_rad_s, seeded channel
    "tachometer", one draw per wheel and period), then rounded to a multiple of quantum_rad_s (0 = none)."""

    def __init__(self, seed: int, n: int, noise_rad_s: float, quantum_rad_s: float):
        self.n = int(n)
        self.stream = NormalStream(seed, "tachometer", noise_rad_s, width=self.n) if noise_rad_s > 0.0 else None
        self.quantum = float(quantum_rad_s)

    def read(self, speeds) -> tuple:
        v = tuple(float(s) for s in speeds)
        if self.stream is not None:
            e = self.stream.next()
            v = tuple(a + b for a, b in zip(v, e))
        q = self.quantum
        if q > 0.0:
            v = tuple(q * round(a / q) for a in v)
        return v
