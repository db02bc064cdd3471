"""The spacecraft's orbit in the Earth-centred inertial frame: a circular reference orbit, and the
relative state of the orbit plant about it (SPEC 5.5, 2.8).

Reference (the chief of the orbit plant; the spacecraft itself in an attitude scenario): radius R,
mu, inclination i, right ascension of the ascending node Omega, argument of latitude u(t) = u0 + n t,
n = sqrt(mu / R^3) (orbit.mean_motion). With the perifocal-to-inertial rotation of a circular orbit
(Vallado, Fundamentals of Astrodynamics, 4th ed., eq. 2-99 with the argument of latitude for nu + omega):

    r_c = R (cos u cos Om - sin u cos i sin Om,  cos u sin Om + sin u cos i cos Om,  sin u sin i)
    v_c = R n (-sin u cos Om - cos u cos i sin Om, -sin u sin Om + cos u cos i cos Om, cos u sin i)

Bryson's rotating frame L of the orbit plant (orbit.py): z toward nadir, y = minus the orbit normal,
x = y x z along-track; its axes in N are the columns of C_NL = [o1 o2 o3]:

    o3 = -r_c / R,   o2 = -h_hat = -(sin i sin Om, -sin i cos Om, cos i),   o1 = o2 x o3 = v_c / (R n)

The plant's state [u v w x y z] is the relative position rho in L and d/dt_N rho resolved in L, so

    r = r_c + C_NL (x, y, z),    v = v_c + C_NL (u, v, w).
"""
from __future__ import annotations

import math

from ..orbit import mean_motion


class CircularOrbit:
    def __init__(self, radius_m: float, mu: float, inclination_rad: float, raan_rad: float, arg_latitude0_rad: float):
        self.radius_m = float(radius_m)
        self.mu = float(mu)
        self.n = mean_motion(self.mu, self.radius_m)
        self.u0 = float(arg_latitude0_rad)
        ci, si = math.cos(inclination_rad), math.sin(inclination_rad)
        co, so = math.cos(raan_rad), math.sin(raan_rad)
        self._p = (co, so, 0.0)                   # r_c / R at u = 0: the ascending node
        self._q = (-ci * so, ci * co, si)         # v_c / (R n) at u = 0
        self._h = (si * so, -si * co, ci)         # unit orbit normal

    def reference(self, t: float) -> tuple:
        """(r_c, v_c): the reference orbit's position (m) and velocity (m/s) in N at t."""
        u = self.u0 + self.n * t
        cu, su = math.cos(u), math.sin(u)
        p, q, R, Rn = self._p, self._q, self.radius_m, self.radius_m * self.n
        r = tuple(R * (cu * p[i] + su * q[i]) for i in range(3))
        v = tuple(Rn * (-su * p[i] + cu * q[i]) for i in range(3))
        return r, v

    def frame(self, t: float) -> tuple:
        """(o1, o2, o3): Bryson's rotating axes in N at t (along-track, minus orbit normal, nadir)."""
        u = self.u0 + self.n * t
        cu, su = math.cos(u), math.sin(u)
        p, q, h = self._p, self._q, self._h
        o1 = tuple(-su * p[i] + cu * q[i] for i in range(3))
        o2 = (-h[0], -h[1], -h[2])
        o3 = tuple(-(cu * p[i] + su * q[i]) for i in range(3))
        return o1, o2, o3

    def state(self, t: float, relative=None) -> tuple:
        """(r, v) of the spacecraft in N (m, m/s): the reference, plus the orbit plant's relative state
        [u v w x y z] when given."""
        r, v = self.reference(t)
        if relative is None:
            return r, v
        o1, o2, o3 = self.frame(t)
        du, dv, dw, x, y, z = relative
        r = tuple(r[i] + o1[i] * x + o2[i] * y + o3[i] * z for i in range(3))
        v = tuple(v[i] + o1[i] * du + o2[i] * dv + o3[i] * dw for i in range(3))
        return r, v
