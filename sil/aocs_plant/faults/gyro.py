"""Gyro faults (docs/spec.md 5.14.2), inside the gyro's measurement (sensors/gyro.py), at the sample's time t:

    gyro_bias_step (db, rad/s):        w_k += db before saturation and quantisation; the true bias of the
                                       truth is beta + db (what an estimate is judged against)
    gyro_saturation (s_f, rad/s):      w_k,i = sign(w_k,i) min(|w_k,i|, s_f) (after the sensor's own range)
    gyro_stuck_axis (unit i):          the output of axis i (rate, or angle increment in angle mode) holds its
                                       value of the last sample before the fault
"""
from __future__ import annotations

import math

from .fault import DeviceFaults


class GyroFaults(DeviceFaults):
    def __init__(self, faults, dt: float):
        super().__init__(faults, dt)
        self.last = None          # the last output delivered
        self.held = {}            # axis -> held output of an active stuck-axis fault

    def bias_step(self, t: float) -> tuple:
        """The sum of the active bias steps at t (rad/s, B)."""
        b = [0.0, 0.0, 0.0]
        for f in self.active_at(t):
            if f.kind == "gyro_bias_step":
                b = [x + y for x, y in zip(b, f.param("bias_rad_s"))]
        return tuple(b)

    def rate(self, t: float, y: list, sat: list) -> None:
        """The rate before quantisation (in place): the bias steps added, the reduced ranges applied."""
        for f in self.active_at(t):
            if f.kind == "gyro_bias_step":
                b = f.param("bias_rad_s")
                for i in range(3):
                    y[i] += b[i]
        for f in self.active_at(t):
            if f.kind == "gyro_saturation":
                s = f.param("saturation_rad_s")
                for i in range(3):
                    if abs(y[i]) > s:
                        y[i] = math.copysign(s, y[i])
                        sat[i] = True

    def output(self, t: float, out: tuple) -> tuple:
        """The delivered output: a stuck axis holds its last value."""
        stuck = {f.unit for f in self.active_at(t) if f.kind == "gyro_stuck_axis"}
        for i in list(self.held):
            if i not in stuck:
                del self.held[i]
        if stuck:
            o = list(out)
            for i in stuck:
                if i not in self.held:
                    self.held[i] = self.last[i] if self.last is not None else o[i]
                o[i] = self.held[i]
            out = tuple(o)
        self.last = out
        return out
