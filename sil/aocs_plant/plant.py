"""Plant facade: one object per run, stepped one control period at a time.

    plant = Plant(load("irassi_large"))
    for k in range(sc.n_steps):
        sample = plant.sense()        # measurement at t_k (dict: every sensor's fields)
        plant.apply({"u_body": u})    # the command: each actuator reads its own fields
        plant.advance()               # integrate [t_k, t_k + dt] with the command held (ZOH)
    plant.truth()                     # true state, disturbance and applied torque/force

Time is t_k = k * dt from the integer period counter (no accumulated
rounding). If apply() is not called in a period the actuator keeps the
previous held command (zero before the first one). A non-finite command is
refused: the previous held command stays and counters["bad_commands"] counts it.

The command is a mapping of named fields; every actuator declares the fields it
reads (`command_fields`): "u_body" (torque, N m, B) or "u_orbit" (force, N,
Bryson's frame) for the body actuator, "u_wheels" (N m, one per wheel) for a
wheel array. A field is a tuple of floats of its declared size, or one integer
bitmask where the declaration is a Mask (the thrusters' "thruster_latch_closed":
an int, or a float with an integral value, in range; anything else is refused
like a non-finite value). A field no actuator reads is an error (a misspelt name).

Every measurement comes from a sensor module (aocs_plant.sensors), sampled once
per period by a SensorSuite; the environment (aocs_plant.environment: orbit,
Sun, Earth, magnetic field) is one object that effectors and sensors query.

Everything that acts on the body is an effector (aocs_plant.effectors), built
from the scenario through the registry; the plant composes them by form, once:
CONSTANT ones are folded into one torque (force), HELD ones are read at every
period start, ATTITUDE closures are summed into the rigid body's right-hand
side, and GENERAL ones (state, or state-dependent) switch the period to one
RK4 over the concatenated state [body; effector states] (integrator.rk4).
Without a GENERAL effector the fast stepper of the body alone runs
(rigid_body.rk4_stepper, compiled when built: kernels.py; or the orbit model's own propagate). DISCRETE
effectors split the period at their event times and jump the body state.
"""
from __future__ import annotations

import math
import time

import numpy as np

from aocs_core.conventions import pointing_error_arcsec, pointing_error_rad, qe_arcsec, quat_from_rotvec, quat_mul

from . import effectors, faults, kernels, sensors
from .effectors import FORMS, BodyContext, Effector, Form, Mask
from .environment import Environment
from .integrator import rk4
from .orbit import LinearOrbit, NonlinearOrbit
from .rigid_body import RigidBody, _mat9, body_derivative, rk4_coupled_stepper, rk4_stepper, sum_terms

__all__ = ["Plant", "integrate_open_loop", "pointing_error_rad", "pointing_error_arcsec", "qe_arcsec"]

_Z3 = (0.0, 0.0, 0.0)


def _add(a, b):
    return (a[0] + b[0], a[1] + b[1], a[2] + b[2])


class Plant:
    def __init__(self, scenario):
        self.scenario = sc = scenario
        self.kind = sc.kind
        self.dt = sc.dt
        self.substeps = sc.substeps
        self.k = 0
        self.counters = {"steps": 0, "commands": 0, "bad_commands": 0, "samples": 0,
                         "invalid_samples": 0}
        #: the last command apply() took, as its actuators read it ({field: floats}); None before the first or
        #: after one it refused (non-finite)
        self.taken: dict | None = None
        attitude = self.kind == "attitude"
        self.environment = env = Environment(sc.environment)
        if attitude:
            J = _mat9(sc.attitude.inertia)
            ctx = BodyContext(self.kind, self.dt, self.substeps, sc.seed, inertia=J, w0=tuple(sc.attitude.w0),
                              environment=env)
        else:
            ctx = BodyContext(self.kind, self.dt, self.substeps, sc.seed, mass_kg=sc.orbit.mass_kg, environment=env)
        self.effectors = effs = effectors.build(sc.effectors, ctx)
        self.actuators = [e for e in effs if e.role == "actuator"]
        # the body actuator (u_body / u_orbit: [actuator], or the wheels standing in for it) is the one whose
        # command truth()["commanded"] reports; magnetorquers and thrusters read fields of their own
        self.actuator = next((a for a in self.actuators if {"u_body", "u_orbit"} & set(a.command_fields)),
                             self.actuators[0] if self.actuators else None)
        self._command_sizes = self._command_fields(self.actuators)
        self._compose(effs)
        if attitude:
            p = sc.attitude
            offsets = [e for e in effs if e.inertia_offset is not None]
            for e in offsets:  # rotating parts whose momentum is an effector state (reaction wheels)
                J = tuple(J[i] - float(e.inertia_offset[i]) for i in range(9))
            if offsets and not np.linalg.eigvalsh(np.reshape(J, (3, 3)))[0] > 0.0:
                raise ValueError("the inertia less the effectors' inertia_offset ("
                                 f"{', '.join(e.kind for e in offsets)}) is not positive definite")
            self.body = RigidBody([J[0:3], J[3:6], J[6:9]], p.q0, p.w0)
            term = sum_terms(e.term() for e in self._terms)
            self._f = body_derivative(self.body.J, self.body.Ji, term)
            self._step = rk4_stepper(self._f)
            self._coupled = None
            if self._general:
                self._coupled = rk4_coupled_stepper(self._f, self._effector_rhs(self._general))
            self._qd0 = sc.target.qd0
            self._wd = sc.target.wd
            self._plan = sc.plan
        else:
            p = sc.orbit
            if p.model == "linear":
                self.orbit = LinearOrbit(p.n, p.mass_kg, p.x0)
            else:
                self.orbit = NonlinearOrbit(p.mu, p.orbit_radius_m, p.mass_kg, p.x0)
        self._applied = _Z3
        self.sensors = sensors.build(sc.sensors, sensors.SensorContext(self.kind, self.dt, sc.seed, env))
        self.faults = tuple(getattr(sc, "faults", ()))   # injected faults (faults/, [[faults]], --fault)
        hooks = faults.attach(self, self.faults) if self.faults else None
        self._suite = sensors.SensorSuite(self.sensors, sc.sensors.latency_periods, sc.sensors.faults, self, hooks)
        # the attitude period compiled (kernels.py: the same doubles), when built and the terms and effectors allow
        # it; after faults.attach, which may give the wheels a fault model. A kernel freezes its terms: never with a
        # time-varying one
        self._compiled_period = self._coupled_kernel = None
        if attitude and not self._time_varying:
            terms = [e.compiled_term() for e in self._terms]
            if self._general:
                self._coupled_kernel = kernels.coupled_period(self.body.J, self.body.Ji, terms,
                                                              [e for e, _, _ in self._general])
            else:
                self._compiled_period = kernels.rigid_body_period(self.body.J, self.body.Ji, terms)
        self._suite.record()
        self._sample = None

    @staticmethod
    def _command_fields(actuators) -> dict:
        """{field: number of floats, or its Mask} over every actuator; two actuators reading one field must
        agree on its size."""
        sizes: dict = {}
        for a in actuators:
            for name, n in a.command_fields.items():
                n = n if isinstance(n, Mask) else int(n)
                if sizes.setdefault(name, n) != n:
                    raise ValueError(f"command field {name!r}: actuator {a.kind!r} reads {n} values, "
                                     f"another {sizes[name]}")
        return sizes

    def _compose(self, effs) -> None:
        """Sort the effectors by form, once (the hot path then never asks)."""
        const = _Z3
        self._held, self._terms, self._time_varying, self._general = [], [], [], []
        self._hooked, self._pending, self._slices = [], [], {}
        self._dist_terms, self._dist_other = [], []
        lo = 0
        x0 = []
        for e in effs:
            f = e.form
            if f not in FORMS:
                raise ValueError(f"effector {e.kind!r}: unknown form {f!r}")
            n = int(e.state_size)
            if n and f != Form.GENERAL:
                raise ValueError(f"effector {e.kind!r}: only a GENERAL effector may have state")
            s0 = tuple(float(v) for v in e.initial_state())
            if len(s0) != n:
                raise ValueError(f"effector {e.kind!r}: initial_state() has {len(s0)} values, state_size {n}")
            self._slices[id(e)] = (lo, lo + n)
            x0.extend(s0)
            if f == Form.CONSTANT:
                const = _add(const, e.value())
            elif f == Form.HELD:
                self._held.append(e)
            elif f == Form.ATTITUDE:
                if self.kind != "attitude":
                    raise ValueError(f"effector {e.kind!r}: an attitude-only term on the orbit plant")
                self._terms.append(e)
                if e.time_varying:
                    self._time_varying.append(e)
            elif f == Form.GENERAL:
                self._general.append((e, lo, lo + n))
            else:
                self._pending.extend((float(t), e) for t in e.event_times())
            hooks = e.period_hooks
            if hooks is None:
                hooks = type(e).begin_period is not Effector.begin_period \
                    or type(e).end_period is not Effector.end_period
            if hooks:
                self._hooked.append((e, lo, lo + n))
            if e.role == "disturbance" and f != Form.CONSTANT and f != Form.DISCRETE:
                (self._dist_terms if f == Form.ATTITUDE else self._dist_other).append(e)
            lo += n
        self._pending.sort(key=lambda p: p[0])
        self._const = const
        self._const_dist = self._fold(e for e in effs if e.form == Form.CONSTANT and e.role == "disturbance")
        self._x = tuple(x0)
        self._held_actuators = [e for e in self._held if e.role == "actuator"]
        self._general_actuators = [e for e, _, _ in self._general if e.role == "actuator"]

    @staticmethod
    def _fold(effs):
        c = _Z3
        for e in effs:
            c = _add(c, e.value())
        return c

    @property
    def wheel_array(self):
        """The actuator that takes wheel torque commands ("u_wheels": the [wheels] array), or None."""
        return next((a for a in self.actuators if "u_wheels" in a.command_fields), None)

    @property
    def command_fields(self) -> dict:
        """The command fields this plant's actuators read: {name: number of floats}, or {name: Mask(bits)} for
        a field that is one integer bitmask."""
        return dict(self._command_sizes)

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
        """(qd, wd) at t: qd(t) = dq(wd t) (x) qd0, the solution of qd' = 0.5 Xi(qd) wd; with an observation
        plan, the target of the observation commanded at t (observation_plan.py)."""
        t = self.t if t is None else t
        if self.kind != "attitude":
            raise ValueError("an orbit scenario has no attitude target")
        if self._plan is not None:
            return self._plan.observations[self._plan.index_at(t, self.dt)].qd, (0.0, 0.0, 0.0)
        wd = self._wd
        if wd == (0.0, 0.0, 0.0):
            return self._qd0, wd
        return quat_mul(quat_from_rotvec((wd[0] * t, wd[1] * t, wd[2] * t)), self._qd0), wd

    # ------------------------------------------------------------------ state
    def body_state(self) -> tuple:
        """The body state as effectors see it: q + w (attitude) or [u v w x y z] (orbit)."""
        if self.kind == "attitude":
            return self.body.q + self.body.w
        return self.orbit.x

    def effector_state(self, e) -> tuple:
        """Effector e's own state now (() when it has none)."""
        lo, hi = self._slices[id(e)]
        return self._x[lo:hi]

    # ------------------------------------------------------------------ sensing
    def sense(self, t: float | None = None) -> dict:
        """Measurement of the current period (cached: a second call returns the same sample)."""
        if t is not None and abs(t - self.t) > 1e-9 * max(1.0, abs(self.t)):
            raise ValueError(f"sense({t}) but the plant is at t = {self.t}")
        if self._sample is not None and self._sample["seq"] == self.k:
            return self._sample
        m, ok = self._suite.sample(self.t)
        s: dict = {"t": self.t, "seq": self.k}
        s.update(m)
        self.counters["samples"] += 1
        if not ok:
            self.counters["invalid_samples"] += 1
        self._sample = s
        return s

    # ------------------------------------------------------------------ actuation
    def apply(self, command) -> bool:
        """Take the command for the current period: a mapping {field: values} (command_fields), e.g.
        {"u_body": (tx, ty, tz)} or, with a wheel array, {"u_body": ..., "u_wheels": (u1, ..., un)}.
        False (and the whole command ignored) if any value is not finite, or a Mask field's value is not an
        integer in its range. Each actuator reads its own fields; one the command does not carry keeps its
        held value."""
        items = getattr(command, "items", None)   # a mapping (cheaper than isinstance(.., Mapping) per step)
        if items is None:
            raise ValueError(f"the command must be a mapping of fields ({', '.join(self._command_sizes)}), "
                             f"got {type(command).__name__}")
        sizes = self._command_sizes
        cmd = {}
        bad = False
        isfinite = math.isfinite
        for name, values in items():
            n = sizes.get(name)
            if n is None:
                raise ValueError(f"command field {name!r}: no actuator of this plant reads it "
                                 f"(fields: {', '.join(sizes) or 'none'})")
            if n.__class__ is not int:     # a Mask: one integer bitmask
                m = n.value(values)
                if m is None:
                    bad = True
                cmd[name] = m
                continue
            v = tuple(map(float, values))
            if len(v) != n:
                raise ValueError(f"command field {name!r}: {len(v)} values, its actuator takes {n}")
            if not all(map(isfinite, v)):
                bad = True
            cmd[name] = v
        if bad:
            self.counters["commands"] += 1
            self.counters["bad_commands"] += 1
            self.taken = None
            return False
        self.take(cmd)
        return True

    def take(self, taken: dict) -> None:
        """A command already checked and converted by apply() (this plant's, or the `taken` of another plant of
        the same scenario: the integration check's shadow follows the main plant so, StepDoubling.take), given to
        the actuators without checking it again."""
        self.counters["commands"] += 1
        for a in self.actuators:
            a.command(taken)
        self.taken = taken

    # ------------------------------------------------------------------ integration
    def advance(self) -> None:
        """Integrate one control period with the held command (ZOH)."""
        t0 = self.k * self.dt
        hooked = self._hooked
        x = self._x
        for e, lo, hi in hooked:
            e.begin_period(t0, x[lo:hi])
        T = self._const
        applied = _Z3
        for e in self._held:
            v = e.value()
            T = (T[0] + v[0], T[1] + v[1], T[2] + v[2])
        for e in self._held_actuators:
            v = e.value()
            applied = (applied[0] + v[0], applied[1] + v[1], applied[2] + v[2])
        if self._pending:
            self._period_with_events(t0, T)
        elif self.kind == "attitude":
            if self._general:
                self._segment_general(t0, self.dt, T)
            else:
                self._segment_body(t0, self.dt, T)
        else:
            self._segment_orbit(t0, self.dt, T)
        x = self._x
        for e, lo, hi in hooked:
            e.end_period(t0, x[lo:hi])
        for e in self._general_actuators:
            v = e.applied
            applied = (applied[0] + v[0], applied[1] + v[1], applied[2] + v[2])
        self._applied = applied
        self.k += 1
        self.counters["steps"] = self.k
        self._suite.record()

    def _segment(self, t: float, length: float, T) -> None:
        if self.kind == "orbit":
            self._segment_orbit(t, length, T)
        elif self._general:
            self._segment_general(t, length, T)
        else:
            self._segment_body(t, length, T)

    def _segment_body(self, t: float, length: float, T) -> None:
        """The rigid body alone over [t, t + length], the torque held: the compiled period when there is one, else
        the substeps in Python, the time-varying terms frozen at each substep's midpoint."""
        n = self.substeps
        h = length / n
        body = self.body
        if self._compiled_period is not None:
            body.q, body.w = self._compiled_period(body.q, body.w, h, n, T)
            return
        q, w = body.q, body.w
        step, tv = self._step, self._time_varying
        for i in range(n):
            for e in tv:
                e.at_time(t + (i + 0.5) * h)
            q, w = step(q, w, h, T)
        body.q, body.w = q, w

    def _segment_orbit(self, t: float, length: float, T) -> None:
        n = self.substeps
        h = length / n
        if self._general:
            y = self.orbit.x + self._x
            F = self._orbit_rhs
            for i in range(n):
                y = rk4(F, t + i * h, y, h, T)
            self.orbit.x, self._x = y[:6], y[6:]
        else:
            prop = self.orbit.propagate
            for _ in range(n):
                prop(h, T)

    def _orbit_rhs(self, t, y, T):
        body = y[:6]
        fx, fy, fz = T
        xdot = []
        for e, lo, hi in self._general:
            (a, b, c), d = e.derivative(t, body, y[6 + lo:6 + hi])
            fx += a
            fy += b
            fz += c
            xdot.extend(d)
        return self.orbit.derivative(body, (fx, fy, fz)) + tuple(xdot)

    def _segment_general(self, t: float, length: float, T) -> None:
        """Attitude with effector state: one RK4 over [q, w, effector states] per substep."""
        n = self.substeps
        h = length / n
        body = self.body
        q, w, x = body.q, body.w, self._x
        k = self._coupled_kernel
        if k is not None:
            out = k.period(q, w, x, h, n, T)
            if out is not None:
                body.q, body.w, self._x = out
                return
        step = self._coupled
        tv = self._time_varying
        for i in range(n):
            for e in tv:
                e.at_time(t + (i + 0.5) * h)
            q, w, x = step(q, w, x, t + i * h, h, T)
        body.q, body.w, self._x = q, w, x

    @staticmethod
    def _effector_rhs(general):
        """G(t, body, x) -> (the effectors' torque, their state derivative) for rk4_coupled_stepper."""
        if len(general) == 1:
            return general[0][0].derivative  # its state is all of x

        def many(t, body, x):
            tx = ty = tz = 0.0
            xdot = []
            for e, lo, hi in general:
                (a, b, c), xd = e.derivative(t, body, x[lo:hi])
                tx += a
                ty += b
                tz += c
                xdot.extend(xd)
            return (tx, ty, tz), tuple(xdot)
        return many

    def _period_with_events(self, t0: float, T) -> None:
        """Split the period at the DISCRETE effectors' events inside it and apply their jumps."""
        dt = self.dt
        due = []
        for te, e in self._pending:
            a = te - t0
            if -1e-9 * dt < a < dt * (1.0 - 1e-9):
                due.append((max(0.0, a), te, e))
        pos = 0.0
        for a, te, e in due:
            if a - pos > 1e-9 * dt:
                self._segment(t0 + pos, a - pos, T)
            self._set_body(e.jump(te, self.body_state()))
            self._pending.remove((te, e))
            pos = a
        self._segment(t0 + pos, dt - pos, T)

    def _set_body(self, state) -> None:
        if self.kind == "attitude":
            self.body.q, self.body.w = tuple(state[:4]), tuple(state[4:7])
        else:
            self.orbit.x = tuple(state)

    # ------------------------------------------------------------------ truth
    def disturbance(self):
        """Disturbance torque (N m, B) or force (N) acting now: the sum over the effectors
        of role "disturbance"."""
        c = self._const_dist
        if not (self._dist_terms or self._dist_other):
            return c
        t = self.t
        body = self.body_state()
        for e in self._dist_terms:
            if e.time_varying:
                e.at_time(t)
            g = e.term()(body[0], body[1], body[2], body[3])
            c = (c[0] + g[0], c[1] + g[1], c[2] + g[2])
        for e in self._dist_other:
            c = _add(c, e.contribution(t, body, self.effector_state(e)))
        return c

    def effector_truth(self) -> dict:
        """Every effector's truth fields now, as {"<kind>.<name>": value}."""
        t, body = self.t, self.body_state()
        out = {}
        for e in self.effectors:
            for name, v in e.truth(t, body, self.effector_state(e)).items():
                out[f"{e.kind}.{name}"] = v
        return out

    def sensor_truth(self) -> dict:
        """Every sensor's truth fields (of its last sample), as {"<name>.<field>": value}."""
        return {f"{s.name}.{k}": v for s in self.sensors for k, v in s.truth().items()}

    def environment_state(self) -> dict:
        """The environment now (Environment.at): the spacecraft's orbit in N (the orbit plant's relative
        state added), the Sun and Earth directions, the magnetic field."""
        return self.environment.at(self.t, self.orbit.x if self.kind == "orbit" else None)

    def faults_active(self, t: float | None = None) -> tuple:
        """Which injected faults are active at t (default now), in the order of the fault list."""
        t = self.t if t is None else t
        return tuple(f.active(t, self.dt) for f in self.faults)

    def fault_state(self) -> dict:
        """The effectors' fault models' state carried between periods ({effector kind: state}; the wheels' held
        speeds): a shadow plant integrating the same period (integration_error.StepDoubling) takes it."""
        return {e.kind: e.fault_model.state() for e in self.effectors
                if getattr(e, "fault_model", None) is not None and hasattr(e.fault_model, "state")}

    def set_fault_state(self, state: dict) -> None:
        for e in self.effectors:
            if e.kind in state:
                e.fault_model.set_state(state[e.kind])

    def truth(self) -> dict:
        act = self.actuator
        out = {"t": self.t, "seq": self.k, "commanded": act.commanded if act is not None else _Z3,
               "applied": self._applied, "disturbance": self.disturbance(), "effectors": self.effector_truth(),
               "sensors": self.sensor_truth()}
        if self.faults:
            out["faults_active"] = self.faults_active()
        if self.kind == "attitude":
            q, w = self.body.q, self.body.w
            qd, wd = self.target()
            out.update(q=q, w=w, q_target=qd, w_target=wd,
                       pointing_rad=pointing_error_rad(q, qd),
                       pointing_arcsec=pointing_error_arcsec(q, qd),
                       qe_arcsec=qe_arcsec(q, qd))
        else:
            x = self.orbit.x
            out.update(x=x, pos=(x[3], x[4], x[5]), vel=(x[0], x[1], x[2]))
        return out


def integrate_open_loop(scenario, steps: int | None = None) -> float:
    """Wall time (s) of `steps` periods of sense / apply(0) / advance, in process.

    The plant's own cost per lockstep period, without transport; steps defaults
    to the scenario's n_steps.
    """
    plant = Plant(scenario)
    steps = scenario.n_steps if steps is None else int(steps)
    zero = {f: (0.0,) * n for f, n in plant.command_fields.items() if not isinstance(n, Mask)}
    t0 = time.perf_counter()
    for _ in range(steps):
        plant.sense()
        plant.apply(zero)
        plant.advance()
    return time.perf_counter() - t0
