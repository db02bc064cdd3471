"""Disturbance models (SPEC 3). Every model is on/off and scalable in the scenario.

Gravity gradient, both forms written as c * (R x J R) with R = A(q) d, d a
unit vector in N (rigid_body.rk4_step evaluates that at every RK4 stage):

- Sun-Earth L2, restricted three-body form as SPEC 3 writes it:
      u_gg = -3 (mu1/r1^3 + mu2/r2^3) (R x J R),
  R = third column of A(q) = A(q) e3: the N frame's z axis (the orbital
  frame's z axis, taken along the Sun-Earth-L2 line) in B; d = e3 fixed.
  NOTE: the textbook gravity-gradient torque 3 mu/r^3 (R x J R) (Markley &
  Crassidis eq. 3.155) has the opposite sign; SPEC 3 is followed. At L2 the
  magnitude is ~1e-9 N m for the IRASSI inertia, six orders below the
  1.18e-3 N m constant torque.
- Earth orbit: u_gg = 3 (mu/r^3) (o3 x J o3) with mu/r^3 = n^2 (circular
  orbit of rate n). The orbital frame O is Bryson's/LVLH (x along-track,
  z nadir, y = -orbit normal) and coincides with N at t = 0, so
  A_ON(t) = A2(-n t) and the nadir in N is o3_N(t) = (-sin nt, 0, cos nt).

Solar radiation pressure: F = (Pe/c)(1 + Y) A (1 AU / r)^2 along a fixed
direction in B, torque F x h with h the offset FROM the centre of pressure TO
the centre of mass (equivalently r_cp x F with r_cp = -h). Constant SRP force
on the orbit plant: pressure * area along a fixed rotating-frame direction.
"""
from __future__ import annotations

import math

# L2 data (documented in docs/scenarios.md)
MU_SUN = 1.32712440018e20      # m^3/s^2
MU_EARTH = 3.986004418e14      # m^3/s^2
AU = 1.495978707e11            # m
R2_L2 = 1.5e9                  # m, Earth to Sun-Earth L2
R1_L2 = AU + R2_L2             # m, Sun to L2
SOLAR_FLUX_1AU = 1361.0        # W/m^2 (total solar irradiance)
SPEED_OF_LIGHT = 299792458.0   # m/s


def l2_gg_coefficient(mu1=MU_SUN, mu2=MU_EARTH, r1=R1_L2, r2=R2_L2) -> float:
    """c of u_gg = c (R x J R) at L2: -3 (mu1/r1^3 + mu2/r2^3) (SPEC 3)."""
    return -3.0 * (mu1 / r1 ** 3 + mu2 / r2 ** 3)


def earth_gg_coefficient(orbit_rate: float) -> float:
    """c of u_gg = c (o3 x J o3): 3 mu/r^3 = 3 n^2."""
    return 3.0 * orbit_rate * orbit_rate


def earth_nadir_inertial(orbit_rate: float, t: float):
    """o3_N(t) = (-sin nt, 0, cos nt): nadir of the LVLH frame (= N at t = 0)."""
    a = orbit_rate * t
    return (-math.sin(a), 0.0, math.cos(a))


def srp_force_magnitude(area_m2: float, reflectivity: float, distance_au: float = 1.0,
                        flux_w_m2: float = SOLAR_FLUX_1AU) -> float:
    """F = (Pe / c)(1 + Y) A (1 AU / r)^2 (SPEC 3), N."""
    return flux_w_m2 / SPEED_OF_LIGHT * (1.0 + reflectivity) * area_m2 / (distance_au ** 2)


def srp_torque(force_b, h_b):
    """F x h (SPEC 3), h from the centre of pressure to the centre of mass, B frame."""
    f, h = force_b, h_b
    return (f[1] * h[2] - f[2] * h[1], f[2] * h[0] - f[0] * h[2], f[0] * h[1] - f[1] * h[0])
