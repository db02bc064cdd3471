"""Gravity-gradient torque (SPEC 3.3), both forms written as c (R x J R), R = A(q) d:

- `[disturbances.gravity_gradient_l2]`: Sun-Earth L2, restricted three-body
  form, c = L2_GG_SIGN * 3 (mu1/r1^3 + mu2/r2^3), d = e3 fixed: R is the third
  column of A(q), N's z axis (the orbital frame's z axis, taken along the
  Sun-Earth-L2 line) in B.
- `[disturbances.gravity_gradient_earth]`: Earth orbit, c = 3 mu/r^3 = 3 n^2
  (circular orbit of rate n), d = o3_N(t) the nadir of the LVLH frame O
  (Bryson's: x along-track, z nadir, y = -orbit normal), which coincides with
  N at t = 0: A_ON(t) = A2(-n t), o3_N(t) = (-sin nt, 0, cos nt). Not together
  with the L2 form. Without `orbit_rate_rad_s` it follows the environment's
  orbit ([environment.orbit], needed then): d = o3_N(t) = -r_c(t) / R of that
  circular orbit (its nadir), c = 3 mu / R^3.

Both are ATTITUDE-form effectors: a closure of q evaluated at every RK4 stage.
The Earth form's direction moves with time; it is frozen at the midpoint of
each substep (at_time), an O((n h)^2) approximation, n h ~ 1e-5 here.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from .base import ATTITUDE, Effector, Form, onoff, register

# L2 data (documented in docs/scenarios.md)
MU_SUN = 1.32712440018e20      # m^3/s^2
MU_EARTH = 3.986004418e14      # m^3/s^2
AU = 1.495978707e11            # m
R2_L2 = 1.5e9                  # m, Earth to Sun-Earth L2
R1_L2 = AU + R2_L2             # m, Sun to L2

# Sign of the L2 torque: PLUS, the textbook 3 mu/r^3 (R x J R) (SPEC 3.3, SPEC 1.9 item 6;
# Schaub & Junkins, Basilisk's GravityGradientEffector). The IRASSI report prints a leading
# minus, a misprint: R x J R is even in R, so the sign cannot be a frame convention. At the
# IRASSI inertia the torque is ~1e-10 N m, far below the 1.18e-3 N m constant disturbance.
L2_GG_SIGN = 1.0


def l2_gg_coefficient(mu1=MU_SUN, mu2=MU_EARTH, r1=R1_L2, r2=R2_L2) -> float:
    """c of u_gg = c (R x J R) at L2: L2_GG_SIGN * 3 (mu1/r1^3 + mu2/r2^3) (SPEC 3.3)."""
    return L2_GG_SIGN * 3.0 * (mu1 / r1 ** 3 + mu2 / r2 ** 3)


def earth_gg_coefficient(orbit_rate: float) -> float:
    """c of u_gg = c (o3 x J o3): 3 mu/r^3 = 3 n^2."""
    return 3.0 * orbit_rate * orbit_rate


def earth_nadir_inertial(orbit_rate: float, t: float):
    """o3_N(t) = (-sin nt, 0, cos nt): nadir of the LVLH frame (= N at t = 0)."""
    a = orbit_rate * t
    return (-math.sin(a), 0.0, math.cos(a))


def gg_term(J, c: float, d=(0.0, 0.0, 1.0)):
    """(g, point): g(q1, q2, q3, q4) = c (R x J R), R = A(q) d, J a row-major 9-tuple;
    point(d) moves d. The closure drops the products by the zeros of a diagonal J."""
    j0, j1, j2, j3, j4, j5, j6, j7, j8 = (float(v) for v in J)
    d1, d2, d3 = d

    def point(direction):
        nonlocal d1, d2, d3
        d1, d2, d3 = direction

    if j1 == 0.0 and j2 == 0.0 and j3 == 0.0 and j5 == 0.0 and j6 == 0.0 and j7 == 0.0:
        def g(q1, q2, q3, q4):
            s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
            vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
            k = 2.0 * q4
            r1 = s * d1 + vd * q1 - k * (q2 * d3 - q3 * d2)
            r2 = s * d2 + vd * q2 - k * (q3 * d1 - q1 * d3)
            r3 = s * d3 + vd * q3 - k * (q1 * d2 - q2 * d1)
            g1 = j0 * r1
            g2 = j4 * r2
            g3 = j8 * r3
            return (c * (r2 * g3 - r3 * g2), c * (r3 * g1 - r1 * g3), c * (r1 * g2 - r2 * g1))
    else:
        def g(q1, q2, q3, q4):
            s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
            vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
            k = 2.0 * q4
            r1 = s * d1 + vd * q1 - k * (q2 * d3 - q3 * d2)
            r2 = s * d2 + vd * q2 - k * (q3 * d1 - q1 * d3)
            r3 = s * d3 + vd * q3 - k * (q1 * d2 - q2 * d1)
            g1 = j0 * r1 + j1 * r2 + j2 * r3
            g2 = j3 * r1 + j4 * r2 + j5 * r3
            g3 = j6 * r1 + j7 * r2 + j8 * r3
            return (c * (r2 * g3 - r3 * g2), c * (r3 * g1 - r1 * g3), c * (r1 * g2 - r2 * g1))
    return g, point


@dataclass(frozen=True)
class GravityGradientL2Config:
    enabled: bool
    scale: float
    mu1: float
    mu2: float
    r1_m: float
    r2_m: float

    @property
    def coefficient(self) -> float:
        return self.scale * l2_gg_coefficient(self.mu1, self.mu2, self.r1_m, self.r2_m)


@register
class GravityGradientL2(Effector):
    kind = "gravity_gradient_l2"
    applies_to = (ATTITUDE,)
    form = Form.ATTITUDE

    @classmethod
    def read(cls, sec, ctx) -> GravityGradientL2Config:
        en, scale = onoff(sec)
        return GravityGradientL2Config(
            en, scale, sec.number("mu1", required=False, default=MU_SUN, positive=True),
            sec.number("mu2", required=False, default=MU_EARTH, positive=True),
            sec.number("r1_m", required=False, default=R1_L2, positive=True),
            sec.number("r2_m", required=False, default=R2_L2, positive=True))

    def __init__(self, config: GravityGradientL2Config, body):
        super().__init__(config, body)
        J, c, d = tuple(float(v) for v in body.inertia), config.coefficient, (0.0, 0.0, 1.0)
        self._g, _ = gg_term(J, c, d)
        self._compiled = ("gravity_gradient", c, d, J)   # the same term, as the compiled kernel takes it

    def term(self):
        return self._g

    def compiled_term(self):
        return self._compiled


@dataclass(frozen=True)
class GravityGradientEarthConfig:
    enabled: bool
    scale: float
    orbit_rate_rad_s: float | None    # None: the environment's orbit (its rate and its nadir)

    @property
    def coefficient(self) -> float:
        return self.scale * earth_gg_coefficient(self.orbit_rate_rad_s)


@register
class GravityGradientEarth(Effector):
    kind = "gravity_gradient_earth"
    applies_to = (ATTITUDE,)
    conflicts = ("gravity_gradient_l2",)
    form = Form.ATTITUDE
    time_varying = True

    @classmethod
    def read(cls, sec, ctx) -> GravityGradientEarthConfig:
        en, scale = onoff(sec)
        return GravityGradientEarthConfig(en, scale, sec.number("orbit_rate_rad_s", required=False, positive=True))

    def __init__(self, config: GravityGradientEarthConfig, body):
        super().__init__(config, body)
        self._orbit = None
        if config.orbit_rate_rad_s is None:
            env = getattr(body, "environment", None)
            self._orbit = None if env is None else env.orbit
            if self._orbit is None:
                raise ValueError("gravity_gradient_earth without orbit_rate_rad_s needs [environment.orbit]")
            c = config.scale * earth_gg_coefficient(self._orbit.n)
            self._g, self._point = gg_term(body.inertia, c, self._orbit.frame(0.0)[2])
        else:
            self._n = config.orbit_rate_rad_s
            self._g, self._point = gg_term(body.inertia, config.coefficient, earth_nadir_inertial(self._n, 0.0))

    def term(self):
        return self._g

    def at_time(self, t: float) -> None:
        if self._orbit is not None:
            self._point(self._orbit.frame(t)[2])
        else:
            self._point(earth_nadir_inertial(self._n, t))
