"""The body-torque (or force) actuator (SPEC 3.4): `[actuator]`, present in every scenario.

Its command field is `u_body` (torque, N m, B) on the attitude plant and `u_orbit` (force, N, Bryson's
rotating frame, SPEC 2.8) on the orbit plant: the flight software's u (actuator_cmd_t.u). Once per
control period, on the command (zero-order hold):
  1. per-axis saturation |c_i| <= axis_limit;
  2. norm saturation |c| <= norm_limit (scales the vector, keeps its direction);
  3. slew-rate limit |c_i(k) - c_i(k-1)| <= slew_rate_limit_per_s * dt on the held value.
Every limit is None when absent (unlimited). Without a lag the held value is
what the body receives over the period (a HELD effector). With `lag_tau_s`
the delivered value y is the effector's state (3 floats), a first-order lag
    ydot = (c - y) / tau,
integrated by the same RK4 as the body, so the body feels y at every stage.
The period mean of y is then exactly c - tau (y(t_k+1) - y(t_k)) / dt for that
discretisation (RK4 is linear), which is what `applied` reports. The lag output
is a convex combination of saturated values up to the RK4 error, and the
loader requires tau >= the substep dt / substeps (RK4 is stable to ~2.8 h/tau;
at h/tau = 1 the step response is within 0.7 % of the exponential).
`realistic_axis_limit` is not applied: the runner's realistic-limit override.
`delay_periods` (integer, default 0): the command of tick k is held over period k + delay_periods
(zero until then): a computation delay of whole control periods at the actuator interface, what the
margin analysis (`aocs analyze`) models as z^-delay; the limits act on the delayed command.
`scale_factor` (> 0, default 1): the delivered torque is scale_factor times the limited command (an
effectiveness error; `aocs analyze --verify` raises the loop gain at the plant input with it).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from aocs_core import registry

from .base import ATTITUDE, ORBIT, ZERO3, Effector, Form, register

#: the command fields (Plant.apply): body torque on the attitude plant, force on the orbit plant
U_BODY = "u_body"
U_ORBIT = "u_orbit"

LIMIT_KEYS = ("axis_limit", "norm_limit", "slew_rate_limit_per_s", "lag_tau_s", "realistic_axis_limit")


@dataclass(frozen=True)
class ActuatorConfig:
    axis_limit: float | None = None
    norm_limit: float | None = None
    slew_rate_limit_per_s: float | None = None
    lag_tau_s: float | None = None
    realistic_axis_limit: float | None = None
    delay_periods: int = 0
    scale_factor: float = 1.0


#: the longest actuator delay the loader accepts, control periods
MAX_DELAY_PERIODS = 100


@register
class Actuator(Effector):
    kind = "actuator"
    group = None
    applies_to = (ATTITUDE, ORBIT)
    role = "actuator"

    @classmethod
    def read(cls, sec, ctx) -> ActuatorConfig:
        kw = {k: sec.number(k, required=False, positive=True) for k in LIMIT_KEYS}
        lim = registry.load().limits   # the executive refuses a limit outside its range (executive.h)
        for k in ("axis_limit", "norm_limit", "realistic_axis_limit"):
            if kw[k] is not None and not lim["u_limit_min"] <= kw[k] <= lim["u_limit_max"]:
                sec.fail(sec.key(k), f"{kw[k]:g} is outside [{lim['u_limit_min']:g}, {lim['u_limit_max']:g}] "
                                     "(N m or N: the flight software's accepted range, executive.h)")
        tau = kw["lag_tau_s"]
        h = ctx.dt / ctx.substeps
        if tau is not None and tau < h:
            sec.fail(sec.key("lag_tau_s"), f"{tau} s is shorter than the integration step dt / substeps = {h!r} s "
                     "(the lag is integrated by RK4 with the body): raise integrator.substeps")
        delay = sec.integer("delay_periods", required=False, default=0, minimum=0)
        if delay > MAX_DELAY_PERIODS:
            sec.fail(sec.key("delay_periods"), f"{delay} control periods: at most {MAX_DELAY_PERIODS}")
        scale = sec.number("scale_factor", required=False, default=1.0, positive=True)
        return ActuatorConfig(**kw, delay_periods=delay, scale_factor=scale)

    @classmethod
    def default(cls, ctx) -> ActuatorConfig:
        return ActuatorConfig()

    def __init__(self, config: ActuatorConfig, body):
        super().__init__(config, body)
        self.dt = float(body.dt)
        self.axis_limit = config.axis_limit
        self.norm_limit = config.norm_limit
        self.slew_rate_limit_per_s = config.slew_rate_limit_per_s
        self.lag_tau_s = config.lag_tau_s
        self.held = ZERO3                  # value after saturation, slew-rate limit and scale factor
        self._limited = ZERO3              # the same before the scale factor (the slew-rate limit's last value)
        self.saturated_count = 0           # periods where 1. or 2. clipped
        self.slew_rate_limited_count = 0
        self._applied = ZERO3
        self._y0 = ZERO3
        if self.lag_tau_s is None:
            self.form = Form.HELD
        else:
            self.form = Form.GENERAL
            self.state_size = 3
        self.period_hooks = self.state_size > 0   # the period mean of the lag output
        self._queue = [ZERO3] * config.delay_periods   # the commands still to be held, oldest first
        self.field = U_BODY if body.kind == ATTITUDE else U_ORBIT
        self.command_fields = {self.field: 3}

    # ---------------------------------------------------------------- the command
    def command(self, cmd) -> None:
        c = cmd.get(self.field)
        if c is not None:
            if self._queue:
                self._queue.append(c)
                c = self._queue.pop(0)
            self.hold(c)

    def hold(self, c) -> tuple[float, float, float]:
        """Limit a new command (3 floats) at the start of a control period; returns the held value."""
        c = (float(c[0]), float(c[1]), float(c[2]))
        clipped = False
        if self.axis_limit is not None:
            lim = self.axis_limit
            s = (min(lim, max(-lim, c[0])), min(lim, max(-lim, c[1])), min(lim, max(-lim, c[2])))
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
        if self.slew_rate_limit_per_s is not None:
            step = self.slew_rate_limit_per_s * self.dt
            p = self._limited
            r = (p[0] + min(step, max(-step, c[0] - p[0])), p[1] + min(step, max(-step, c[1] - p[1])),
                 p[2] + min(step, max(-step, c[2] - p[2])))
            if r != c:
                self.slew_rate_limited_count += 1
            c = r
        self._limited = c
        k = self.config.scale_factor
        if k != 1.0:
            c = (k * c[0], k * c[1], k * c[2])
        self.held = c
        return c

    # ---------------------------------------------------------------- contribution
    def value(self) -> tuple:
        return self.held

    def initial_state(self) -> tuple:
        return ZERO3 if self.state_size else ()

    def derivative(self, t, body, x):
        c = self.held
        tau = self.lag_tau_s
        return x, ((c[0] - x[0]) / tau, (c[1] - x[1]) / tau, (c[2] - x[2]) / tau)

    def begin_period(self, t, x) -> None:
        self._y0 = x

    def end_period(self, t, x) -> None:
        c, y0, tau, dt = self.held, self._y0, self.lag_tau_s, self.dt
        self._applied = (c[0] - tau * (x[0] - y0[0]) / dt, c[1] - tau * (x[1] - y0[1]) / dt,
                         c[2] - tau * (x[2] - y0[2]) / dt)

    # ---------------------------------------------------------------- truth
    @property
    def commanded(self) -> tuple:
        return self.held

    @property
    def applied(self) -> tuple:
        """With the lag: the mean of y over the last period (without it the plant reports the held value)."""
        return self._applied

    def truth(self, t, body, x) -> dict:
        out = {"commanded": self.held}
        if self.state_size:
            out["output"] = x
        return out
