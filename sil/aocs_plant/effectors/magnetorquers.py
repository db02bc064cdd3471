"""Magnetorquers (docs/spec.md 5.8.2): `[magnetorquers]`, command field `u_dipole_am2`.

Three rods with unit axes a_i in B (`axes`, 9 numbers) and a saturation each (`max_dipole_am2`). The
command is the dipole along each rod (A m^2), clipped per rod and held over the control period:

    m_i = min(max_i, max(-max_i, u_i)),   m_B = sum_i m_i a_i
    tau_B = m_B x B_B,   B_B = A(q) B_N(t)                (Wertz 1978; Markley & Crassidis 2014, ch. 3 and 7)

B_N(t) is the environment's field model along the orbit (environment.magnetic_field.FieldAlongOrbit, linear
between the control periods' grid values) at the time of each RK4 stage, rotated by the stage's q: the
torque is perpendicular to the field the body is in at that stage. A GENERAL-form effector whose state is
the angular impulse it gave, integral of tau_B dt (N m s, B components), so that its mean torque over a
period, the state's change over dt, is exactly what the body received (`applied`, as the wheels'). Without
a field model or an orbit the field is zero and so is the torque. Truth: the rod dipoles (after the clip),
m_B, the field in B and the torque now, which rods are saturated, and the dipole-seconds flown (the
integral of |m_i| per rod, the unloading's effort, with the held dipole over each period).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from aocs_core.conventions import quat_rotate

from ..environment.magnetic_field import FieldAlongOrbit
from .base import ATTITUDE, ZERO3, Effector, Form, register

U_DIPOLE = "u_dipole_am2"


@dataclass(frozen=True)
class MagnetorquersConfig:
    axes: tuple                  # three unit rod axes a_i in B
    max_dipole_am2: tuple        # per rod, A m^2


def read_axes(sec, key: str, n: int) -> tuple:
    """n unit 3-vectors given flat (3 n numbers) under key; each checked to be unit (1e-9)."""
    flat = sec.vector(key, n=3 * n)
    out = []
    for i in range(n):
        v = flat[3 * i:3 * i + 3]
        norm = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
        if abs(norm - 1.0) > 1e-9:
            sec.fail(sec.key(key), f"vector {i} ({', '.join(f'{x:g}' for x in v)}) is not a unit vector "
                                   f"(norm {norm!r})")
        out.append(v)
    return tuple(out)


def cross(a, b) -> tuple:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


def dipole_torque(m_b, b_n, q) -> tuple:
    """m_B x A(q) b_N (N m): a dipole fixed in B in the field b_N (T, N); zero without a field (None)."""
    return ZERO3 if b_n is None else cross(m_b, quat_rotate(q, b_n))


def dipole_torque_term(field, m_b):
    """(term, at_time) of an ATTITUDE-form effector: term(q1..q4) = m_b x A(q) b_N with b_N frozen by
    at_time(t) at field(t) (None: zero field)."""
    b = [None]

    def at_time(t):
        b[0] = field(t)

    def term(q1, q2, q3, q4):
        return dipole_torque(m_b, b[0], (q1, q2, q3, q4))
    return term, at_time


def field_b(field, t, q) -> tuple:
    """A(q) B_N(t) (T), zeros without a field."""
    v = field(t)
    return ZERO3 if v is None else quat_rotate(q, v)


@register
class Magnetorquers(Effector):
    kind = "magnetorquers"
    group = None                     # a top-level section [magnetorquers]
    applies_to = (ATTITUDE,)
    role = "actuator"
    form = Form.GENERAL              # state: its angular impulse, N m s (B components)
    state_size = 3
    period_hooks = True

    @classmethod
    def read(cls, sec, ctx) -> MagnetorquersConfig:
        sec.only(("axes", "max_dipole_am2"))
        axes = read_axes(sec, "axes", 3) if sec.has("axes") else ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))
        det = (axes[0][0] * (axes[1][1] * axes[2][2] - axes[1][2] * axes[2][1])
               - axes[0][1] * (axes[1][0] * axes[2][2] - axes[1][2] * axes[2][0])
               + axes[0][2] * (axes[1][0] * axes[2][1] - axes[1][1] * axes[2][0]))
        if abs(det) < 1e-6:
            sec.fail(sec.key("axes"), "the three rod axes do not span the three body axes")
        mx = sec.scalar_or_vector("max_dipole_am2", n=3, positive=True)
        return MagnetorquersConfig(axes, tuple(mx))

    def __init__(self, config: MagnetorquersConfig, body):
        super().__init__(config, body)
        self.command_fields = {U_DIPOLE: 3}
        self.dt = float(body.dt)
        self.field = FieldAlongOrbit(body.environment, body.dt)
        self.field(0.0)                     # a model outside its range fails here, at construction
        self.u_cmd = ZERO3                  # the command as received
        self.m_rods = ZERO3                 # after the clip
        self.m_b = ZERO3
        self.saturated = (False, False, False)
        self.dipole_s = [0.0, 0.0, 0.0]     # integral of |m_i| dt, A m^2 s
        self._x0 = ZERO3
        self._applied = ZERO3

    def command(self, cmd) -> None:
        u = cmd.get(U_DIPOLE)
        if u is None:
            return
        mx, a = self.config.max_dipole_am2, self.config.axes
        m = tuple(min(mx[i], max(-mx[i], float(u[i]))) for i in range(3))
        self.u_cmd = tuple(float(v) for v in u)
        self.m_rods = m
        self.saturated = tuple(abs(float(u[i])) > mx[i] for i in range(3))
        self.m_b = tuple(a[0][k] * m[0] + a[1][k] * m[1] + a[2][k] * m[2] for k in range(3))

    def initial_state(self) -> tuple:
        return ZERO3

    def derivative(self, t, body, x):
        tau = dipole_torque(self.m_b, self.field(t), body[:4])
        return tau, tau

    def begin_period(self, t, x) -> None:
        self._x0 = x

    def end_period(self, t, x) -> None:
        """The mean torque of the period: the angular impulse's change over dt (RK4 sums its stages
        linearly, so it is exactly what the body received)."""
        x0, dt = self._x0, self.dt
        self._applied = ((x[0] - x0[0]) / dt, (x[1] - x0[1]) / dt, (x[2] - x0[2]) / dt)
        for i in range(3):
            self.dipole_s[i] += abs(self.m_rods[i]) * dt

    @property
    def applied(self) -> tuple:
        return self._applied

    def truth(self, t, body, x) -> dict:
        b = field_b(self.field, t, body[:4])
        return {"dipole_am2": self.m_rods, "dipole_b_am2": self.m_b, "field_b_t": b,
                "torque_nm": cross(self.m_b, b), "saturated": self.saturated,
                "dipole_s_am2s": tuple(self.dipole_s), "impulse_b_nms": tuple(x)}
