"""Actuator model (SPEC 3): torque (or force) 3-vector.

Order, once per control period (zero-order hold of the command):
  1. per-axis saturation |c_i| <= axis_limit;
  2. norm saturation |c| <= norm_limit (scales the vector, keeps its direction);
  3. rate limit |c_i(k) - c_i(k-1)| <= rate_limit * dt on the held value.
Then, per integration substep h, an optional first-order lag of time constant
tau on the delivered value: y <- c + (y - c) exp(-h / tau), the exact response
to the constant held command; within a substep the plant applies the mean of
that response, c + (y - c) (tau / h)(1 - exp(-h / tau)), so the delivered
impulse is exact. Every
limit is None when absent (unlimited). The lag output is a convex combination
of saturated values, so it never exceeds the limits.
"""
from __future__ import annotations

import math


class Actuator:
    def __init__(self, dt: float, axis_limit=None, norm_limit=None, rate_limit=None,
                 lag_tau_s=None):
        self.dt = float(dt)
        self.axis_limit = axis_limit
        self.norm_limit = norm_limit
        self.rate_limit = rate_limit
        self.lag_tau_s = lag_tau_s
        self.held = (0.0, 0.0, 0.0)      # value after saturation and rate limit
        self.output = (0.0, 0.0, 0.0)    # delivered value (after the lag)
        self.saturated_count = 0          # periods where 1. or 2. clipped
        self.rate_limited_count = 0

    def command(self, c) -> tuple[float, float, float]:
        """Take a new command at the start of a control period; returns the held value."""
        c = (float(c[0]), float(c[1]), float(c[2]))
        clipped = False
        if self.axis_limit is not None:
            lim = self.axis_limit
            s = tuple(min(lim, max(-lim, x)) for x in c)
            clipped = s != c
            c = s
        if self.norm_limit is not None:
            n = math.sqrt(c[0] * c[0] + c[1] * c[1] + c[2] * c[2])
            if n > self.norm_limit:
                k = self.norm_limit / n
                c = (c[0] * k, c[1] * k, c[2] * k)
                clipped = True
        if clipped:
            self.saturated_count += 1
        if self.rate_limit is not None:
            step = self.rate_limit * self.dt
            p = self.held
            r = tuple(p[i] + min(step, max(-step, c[i] - p[i])) for i in range(3))
            if r != c:
                self.rate_limited_count += 1
            c = r
        self.held = c
        if self.lag_tau_s is None:
            self.output = c
        return c

    def substep(self, h: float) -> tuple[float, float, float]:
        """Delivered value to use over the next substep of length h (then advances the lag)."""
        if self.lag_tau_s is None:
            return self.held
        y = self.output
        c = self.held
        e = math.exp(-h / self.lag_tau_s)
        # mean of the exact lag response over the substep, so the impulse it delivers is exact
        k = self.lag_tau_s / h * (1.0 - e)
        self.output = tuple(c[i] + (y[i] - c[i]) * e for i in range(3))
        return tuple(c[i] + (y[i] - c[i]) * k for i in range(3))
