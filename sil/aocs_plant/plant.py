"""Plant facade: one object per run, stepped one control period at a time.

    plant = Plant(load("irassi_large"))
    for k in range(sc.n_steps):
        sample = plant.sense()        # measurement at t_k (dict)
        plant.apply(command)          # torque (N m, B) or force (N, Bryson frame)
        plant.advance()               # integrate [t_k, t_k + dt] with the command held (ZOH)
    plant.truth()                     # true state, disturbance and applied torque/force

Time is t_k = k * dt from the integer period counter (no accumulated
rounding). If apply() is not called in a period the actuator keeps the
previous held command (zero before the first one). A non-finite command is
refused: the previous held command stays and counters["bad_commands"] counts it.
"""
from __future__ import annotations

import math
import time

from aocs_core.conventions import pointing_error_arcsec, pointing_error_rad, qe_arcsec, quat_from_rotvec, quat_mul

from . import disturbances as dist
from .actuators import Actuator
from .orbit import LinearOrbit, NonlinearOrbit
from .rigid_body import RigidBody, gg_torque, make_stepper
from .sensors import Sensors

__all__ = ["Plant", "integrate_open_loop", "pointing_error_rad", "pointing_error_arcsec", "qe_arcsec"]


class Plant:
    def __init__(self, scenario):
        self.scenario = sc = scenario
        self.kind = sc.kind
        self.dt = sc.dt
        self.substeps = sc.substeps
        self.k = 0
        a = sc.actuator
        self.actuator = Actuator(self.dt, a.axis_limit, a.norm_limit, a.rate_limit, a.lag_tau_s)
        self.counters = {"steps": 0, "commands": 0, "bad_commands": 0, "samples": 0,
                         "invalid_samples": 0}
        d = sc.disturbances
        self._applied = (0.0, 0.0, 0.0)
        if self.kind == "attitude":
            p = sc.attitude
            self.body = RigidBody(p.inertia, p.q0, p.w0)
            tq = [0.0, 0.0, 0.0]
            ct = d.active("constant_torque")
            if ct is not None:
                tq = [tq[i] + ct.scale * ct.torque_nm[i] for i in range(3)]
            srp = d.active("srp_torque")
            if srp is not None:
                st = srp.torque_nm
                tq = [tq[i] + st[i] for i in range(3)]
            self._const_torque = tuple(tq)
            self._ggc, self._gg_rate = 0.0, 0.0
            l2 = d.active("gravity_gradient_l2")
            ge = d.active("gravity_gradient_earth")
            if l2 is not None:
                self._ggc = l2.coefficient
            elif ge is not None:
                self._ggc = ge.scale * dist.earth_gg_coefficient(ge.orbit_rate_rad_s)
                self._gg_rate = ge.orbit_rate_rad_s
            self._step = make_stepper(self.body.J, self.body.Ji, self._ggc != 0.0)
            self._qd0 = sc.target.qd0
            self._wd = sc.target.wd
        else:
            p = sc.orbit
            if p.model == "linear":
                self.orbit = LinearOrbit(p.n, p.mass_kg, p.x0)
            else:
                self.orbit = NonlinearOrbit(p.mu, p.orbit_radius_m, p.mass_kg, p.x0)
            f = d.active("srp_force")
            self._const_force = f.force_n if f is not None else (0.0, 0.0, 0.0)
            self._impulse = d.active("impulse")
            self._impulse_done = False
        self.sensors = Sensors(sc)
        self.sensors.record(self._truth_pair())
        self._sample = None

    # ------------------------------------------------------------------ time
    @property
    def t(self) -> float:
        return self.k * self.dt

    @property
    def applied(self) -> tuple[float, float, float]:
        """Actuator output applied over the last period (torque N m, or force N for orbit):
        the period mean of the lagged/limited output, (0, 0, 0) before the first advance.
        The same value as truth()["applied"], without building the truth dict."""
        return self._applied

    # ------------------------------------------------------------------ target
    def target(self, t: float | None = None):
        """(qd, wd) at t: qd(t) = dq(wd t) (x) qd0, the solution of qd' = 0.5 Xi(qd) wd."""
        t = self.t if t is None else t
        if self.kind != "attitude":
            raise ValueError("an orbit scenario has no attitude target")
        wd = self._wd
        if wd == (0.0, 0.0, 0.0):
            return self._qd0, wd
        return quat_mul(quat_from_rotvec((wd[0] * t, wd[1] * t, wd[2] * t)), self._qd0), wd

    # ------------------------------------------------------------------ sensing
    def _truth_pair(self):
        if self.kind == "attitude":
            return (self.body.q, self.body.w)
        x = self.orbit.x
        return ((x[3], x[4], x[5]), (x[0], x[1], x[2]))

    def sense(self, t: float | None = None) -> dict:
        """Measurement of the current period (cached: a second call returns the same sample)."""
        if t is not None and abs(t - self.t) > 1e-9 * max(1.0, abs(self.t)):
            raise ValueError(f"sense({t}) but the plant is at t = {self.t}")
        if self._sample is not None and self._sample["seq"] == self.k:
            return self._sample
        m = self.sensors.sample(self.t)
        s: dict = {"t": self.t, "seq": self.k}
        if self.kind == "attitude":
            (s["q"], s["q_valid"]), (s["w"], s["w_valid"]) = m["attitude"], m["rate"]
            ok = s["q_valid"] and s["w_valid"]
        else:
            (s["pos"], s["pos_valid"]), (s["vel"], s["vel_valid"]) = m["position"], m["velocity"]
            ok = s["pos_valid"] and s["vel_valid"]
        self.counters["samples"] += 1
        if not ok:
            self.counters["invalid_samples"] += 1
        self._sample = s
        return s

    # ------------------------------------------------------------------ actuation
    def apply(self, command) -> bool:
        """Take the command for the current period; False (and ignored) if not finite."""
        c = tuple(float(x) for x in command)
        if len(c) != 3:
            raise ValueError("command must have 3 components")
        self.counters["commands"] += 1
        if not all(math.isfinite(x) for x in c):
            self.counters["bad_commands"] += 1
            return False
        self.actuator.command(c)
        return True

    # ------------------------------------------------------------------ integration
    def advance(self) -> None:
        """Integrate one control period with the held command (ZOH)."""
        if self.kind == "attitude":
            self._advance_attitude()
        else:
            self._advance_orbit()
        self.k += 1
        self.counters["steps"] = self.k
        self.sensors.record(self._truth_pair())

    def _advance_attitude(self):
        n = self.substeps
        h = self.dt / n
        body = self.body
        q, w = body.q, body.w
        step = self._step
        c = self._const_torque
        ggc = self._ggc
        gd = (0.0, 0.0, 1.0)
        act = self.actuator
        lag = act.lag_tau_s is not None
        u = act.held
        total = (u[0] + c[0], u[1] + c[1], u[2] + c[2])
        s0 = s1 = s2 = 0.0
        t0 = self.t
        for i in range(n):
            if lag:
                u = act.substep(h)
                total = (u[0] + c[0], u[1] + c[1], u[2] + c[2])
                s0 += u[0]
                s1 += u[1]
                s2 += u[2]
            if self._gg_rate != 0.0:
                gd = dist.earth_nadir_inertial(self._gg_rate, t0 + (i + 0.5) * h)
            q, w = step(q, w, h, total, ggc, gd)
        body.q, body.w = q, w
        self._applied = (s0 / n, s1 / n, s2 / n) if lag else u

    def _orbit_segment(self, length: float):
        n = self.substeps
        h = length / n
        act = self.actuator
        f = self._const_force
        s = [0.0, 0.0, 0.0]
        for _ in range(n):
            u = act.substep(h)
            self.orbit.propagate(h, (u[0] + f[0], u[1] + f[1], u[2] + f[2]))
            for i in range(3):
                s[i] += u[i] * h
        return s

    def _advance_orbit(self):
        imp = self._impulse
        dt = self.dt
        split = None
        if imp is not None and not self._impulse_done:
            a = imp.time_s - self.t
            if -1e-9 * dt < a < dt * (1.0 - 1e-9):
                split = max(0.0, a)
        if split is None:
            s = self._orbit_segment(dt)
        else:
            s = [0.0, 0.0, 0.0]
            if split > 1e-9 * dt:
                s = self._orbit_segment(split)
            dv = imp.delta_v
            x = self.orbit.x
            self.orbit.x = (x[0] + dv[0], x[1] + dv[1], x[2] + dv[2], x[3], x[4], x[5])
            self._impulse_done = True
            s2 = self._orbit_segment(dt - split)
            s = [s[i] + s2[i] for i in range(3)]
        self._applied = (s[0] / dt, s[1] / dt, s[2] / dt)

    # ------------------------------------------------------------------ truth
    def disturbance(self):
        """Disturbance torque (N m, B) or force (N) acting now."""
        if self.kind != "attitude":
            return self._const_force
        c = self._const_torque
        if self._ggc == 0.0:
            return c
        gd = (0.0, 0.0, 1.0)
        if self._gg_rate != 0.0:
            gd = dist.earth_nadir_inertial(self._gg_rate, self.t)
        g = gg_torque(self.body.q, self.body.J, self._ggc, gd)
        return (c[0] + g[0], c[1] + g[1], c[2] + g[2])

    def truth(self) -> dict:
        out = {"t": self.t, "seq": self.k, "commanded": self.actuator.held,
               "applied": self._applied, "disturbance": self.disturbance()}
        if self.kind == "attitude":
            q, w = self.body.q, self.body.w
            qd, wd = self.target()
            out.update(q=q, w=w, q_target=qd, w_target=wd,
                       pointing_rad=pointing_error_rad(q, qd),
                       pointing_arcsec=pointing_error_arcsec(q, qd),
                       qe_arcsec=qe_arcsec(q, qd))
        else:
            x = self.orbit.x
            out.update(x=x, pos=(x[3], x[4], x[5]), vel=(x[0], x[1], x[2]),
                       impulse_applied=self._impulse_done)
        return out


def integrate_open_loop(scenario, steps: int | None = None) -> float:
    """Wall time (s) of `steps` periods of sense / apply(0) / advance, in process.

    The plant's own cost per lockstep period, without transport; steps defaults
    to the scenario's n_steps.
    """
    plant = Plant(scenario)
    steps = scenario.n_steps if steps is None else int(steps)
    zero = (0.0, 0.0, 0.0)
    t0 = time.perf_counter()
    for _ in range(steps):
        plant.sense()
        plant.apply(zero)
        plant.advance()
    return time.perf_counter() - t0
