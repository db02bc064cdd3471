"""Reaction wheel faults (docs/spec.md 5.14.4), in the wheel array's dynamics (effectors/reaction_wheels.py),
per control period starting at t (the array's hdot_i = tau_i, its reaction -g_i tau_i on the body):

    wheel_torque_loss (i):        u_i = 0 (the motor is dead), friction stays: tau_i = -f_i(Omega_i)
    wheel_friction_increase (i, k): tau_i = u_i - k f_i(Omega_i)
    wheel_stuck (i, Omega_h, T):  tau_i = -(Js_i / T) (Omega_i - Omega_h): the stop holds the rotor at Omega_h
                                  relative to the body (default: its speed at the fault's start; 0: a seized
                                  bearing) whatever the motor; the body takes the reaction -g_i tau_i, so the
                                  total momentum J_b w + Gs h is unchanged (the stop is internal)

T (stop_time_s) must be at least two integration steps (the RK4 of the body and wheels resolves it).
"""
from __future__ import annotations

import math

from .fault import DeviceFaults


class WheelFaults(DeviceFaults):
    def __init__(self, faults, dt: float, n: int):
        super().__init__(faults, dt)
        self.n = n
        self.dead = (False,) * n             # motor lost, this period
        self.friction = (1.0,) * n           # friction factor, this period
        self.stuck = {}                      # wheel -> (held speed or None until captured, stop time)
        self.active = ()

    def begin(self, t: float) -> None:
        """The faults of the period starting at t."""
        on = self.active_at(t)
        self.active = tuple(on)
        dead = [False] * self.n
        fr = [1.0] * self.n
        stuck = {}
        for f in on:
            if f.kind == "wheel_torque_loss":
                dead[f.unit] = True
            elif f.kind == "wheel_friction_increase":
                fr[f.unit] *= f.param("factor")
            elif f.kind == "wheel_stuck":
                held = self.stuck.get(f.unit)
                speed = f.param("speed_rad_s")
                if speed is None and held is not None:
                    speed = held[0]          # captured at the fault's start, held since
                stuck[f.unit] = (speed, f.param("stop_time_s"))
        self.dead, self.friction, self.stuck = tuple(dead), tuple(fr), stuck

    def state(self) -> dict:
        """What the model carries from period to period (the held speeds), for a shadow plant (set_state)."""
        return dict(self.stuck)

    def set_state(self, state: dict) -> None:
        self.stuck = dict(state)

    def motor(self, u: tuple) -> tuple:
        """The motor torques held over the period (a dead motor gives none)."""
        if not any(self.dead):
            return u
        return tuple(0.0 if d else v for d, v in zip(self.dead, u))

    def axial_torques(self, w, om) -> tuple:
        """tau_i of the array w (ReactionWheels) at the relative speeds om, with the period's faults."""
        tanh = math.tanh
        b, c, eps = w.b, w.c, w.eps
        out = []
        for i in range(w.n):
            o = om[i]
            st = self.stuck.get(i)
            if st is not None:
                if st[0] is None:            # the first evaluation of the fault's first period: its start state
                    st = (o, st[1])
                    self.stuck[i] = st
                out.append(-w.js[i] * (o - st[0]) / st[1])
                continue
            u = w.u[i]
            if u * o > 0.0 and abs(o) >= w.wmax[i]:
                u = 0.0
                w.at_speed_limit[i] = True
            out.append(u - self.friction[i] * (b * o + c * tanh(o / eps)))
        return tuple(out)
