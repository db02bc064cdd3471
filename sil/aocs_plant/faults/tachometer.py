"""Tachometer failure (docs/spec.md 5.14.3): while a wheel_tach_failure of wheel i is active at the sample time,
the tachometer's reading of wheel i is the fault's value_rad_s (0 by default: a dead tachometer), whatever the
speed; the other wheels read as before."""
from __future__ import annotations

from .fault import DeviceFaults


class TachometerFaults(DeviceFaults):
    def __call__(self, t: float, value: tuple) -> tuple:
        return self.per_unit(t, value, lambda f: f.param("value_rad_s"))
