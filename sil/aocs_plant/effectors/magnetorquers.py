"""Magnetorquers (docs/spec.md 5.8.2): `[magnetorquers]`, command field `u_dipole_am2`.

Three rods with unit axes a_i in B (`axes`, 9 numbers) and a saturation each (`max_dipole_am2`). The
command is the dipole along each rod (A m^2), clipped per rod and held over the control period:

    m_i = min(max_i, max(-max_i, u_i)),   m_B = sum_i m_i a_i
    tau_B = m_B x B_B,   B_B = A(q) B_N(t)                (Wertz 1978; Markley & Crassidis 2014, ch. 3 and 7)

B_N(t) is the environment's field model along the orbit (environment.magnetic_field.FieldAlongOrbit),
frozen at the midpoint of each substep (an ATTITUDE-form term of q, evaluated at every RK4 stage, so
the torque is perpendicular to the field the body is in at that stage). Without a field model or an
orbit the field is zero and so is the torque. Truth: the rod dipoles (after the clip), m_B, the field
in B and the torque now, which rods are saturated, and the dipole-seconds flown (the integral of
|m_i| per rod, the unloading's effort, with the held dipole over each period).
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


def dipole_torque_term(field, m_b):
    """(term, b_n_at): term(q1..q4) = m x (A(q) b_N) with m_b() the dipole (B) and b_N frozen by
    b_n_at(t) (the field function's value at t; None: zero field)."""
    b = [0.0, 0.0, 0.0]

    def b_n_at(t):
        v = field(t)
        b[0], b[1], b[2] = (0.0, 0.0, 0.0) if v is None else v

    def term(q1, q2, q3, q4):
        d1, d2, d3 = b
        s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
        vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
        k = 2.0 * q4
        b1 = s * d1 + vd * q1 - k * (q2 * d3 - q3 * d2)
        b2 = s * d2 + vd * q2 - k * (q3 * d1 - q1 * d3)
        b3 = s * d3 + vd * q3 - k * (q1 * d2 - q2 * d1)
        m1, m2, m3 = m_b()
        return (m2 * b3 - m3 * b2, m3 * b1 - m1 * b3, m1 * b2 - m2 * b1)
    return term, b_n_at


def field_b(field, t, q) -> tuple:
    """A(q) B_N(t) (T), zeros without a field."""
    v = field(t)
    return ZERO3 if v is None else quat_rotate(q, v)


def cross(a, b) -> tuple:
    return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])


@register
class Magnetorquers(Effector):
    kind = "magnetorquers"
    group = None                     # a top-level section [magnetorquers]
    applies_to = (ATTITUDE,)
    role = "actuator"
    form = Form.ATTITUDE
    time_varying = True
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
        self._term, self.at_time = dipole_torque_term(self.field, lambda: self.m_b)

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

    def term(self):
        return self._term

    def end_period(self, t, x) -> None:
        for i in range(3):
            self.dipole_s[i] += abs(self.m_rods[i]) * self.dt

    def truth(self, t, body, x) -> dict:
        b = field_b(self.field, t, body[:4])
        return {"dipole_am2": self.m_rods, "dipole_b_am2": self.m_b, "field_b_t": b,
                "torque_nm": cross(self.m_b, b), "saturated": self.saturated,
                "dipole_s_am2s": tuple(self.dipole_s)}
