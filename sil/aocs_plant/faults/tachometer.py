"""Tachometer failure (docs/spec.md 5.12.3): while a wheel_tach_failure of wheel i is active at the sample time,
the tachometer's reading of wheel i is the fault's value_rad_s (0 by default: a dead tachometer), whatever the
speed; the other wheels read as before."""
from __future__ import annotations


class TachometerFaults:
    def __init__(self, faults, dt: float):
        self.faults = tuple(faults)
        self.dt = dt

    def __call__(self, t: float, value: tuple) -> tuple:
        on = [f for f in self.faults if f.active(t, self.dt)]
        if not on:
            return value
        v = list(value)
        for f in on:
            v[f.unit] = f.param("value_rad_s")
        return tuple(v)
