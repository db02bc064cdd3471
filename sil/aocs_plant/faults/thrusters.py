"""Thruster faults (docs/spec.md 5.12.5), on the on-times of each control period starting at t:

    thruster_stuck_closed (unit i):  tau_i = 0 whatever the command (no thrust)
    thruster_stuck_open (unit i):    tau_i = dt (full thrust over the whole period, its propellant counted
                                     by the thrusters' own mass-flow equation)
"""
from __future__ import annotations


class ThrusterFaults:
    def __init__(self, faults, dt: float):
        self.faults = tuple(faults)
        self.dt = dt

    def on_times(self, t: float, on: tuple) -> tuple:
        active = [f for f in self.faults if f.active(t, self.dt)]
        if not active:
            return on
        v = list(on)
        for f in active:
            v[f.unit] = 0.0 if f.kind == "thruster_stuck_closed" else self.dt
        return tuple(v)
