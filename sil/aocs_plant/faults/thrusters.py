"""Thruster faults (docs/spec.md 5.14.5), on the on-times of each control period starting at t:

    thruster_stuck_closed (unit i):  tau_i = 0 whatever the command (no thrust)
    thruster_stuck_open (unit i):    tau_i = dt (full thrust over the whole period, its propellant counted
                                     by the thrusters' own mass-flow equation)
"""
from __future__ import annotations

from .fault import DeviceFaults


class ThrusterFaults(DeviceFaults):
    def on_times(self, t: float, on: tuple) -> tuple:
        return self.per_unit(t, on, lambda f: 0.0 if f.kind == "thruster_stuck_closed" else self.dt)
