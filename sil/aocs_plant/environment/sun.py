"""The Sun's geocentric position, low precision (SPEC 5.5; The Astronomical Almanac, section C,
"Low-precision formulas for the Sun"; in Julian centuries, Vallado, Fundamentals of Astrodynamics and
Applications, 4th ed., algorithm 29). Precision 0.01 deg in direction between 1950 and 2050.

With n = JD - 2451545.0 (days from J2000.0, TT):

    L = 280.460 deg + 0.9856474 deg n        mean longitude, corrected for aberration
    g = 357.528 deg + 0.9856003 deg n        mean anomaly
    lambda = L + 1.915 deg sin g + 0.020 deg sin 2g      ecliptic longitude (latitude 0)
    eps = 23.439 deg - 0.0000004 deg n       obliquity of the ecliptic
    R = 1.00014 - 0.01671 cos g - 0.00014 cos 2g         distance, AU

    r_sun = R (cos lambda, cos eps sin lambda, sin eps sin lambda)   equator and equinox of date
"""
from __future__ import annotations

import math

from .epoch import J2000_JD

AU_M = 149597870700.0   # IAU 2012 Resolution B2, exact


def sun_position_au(jd: float) -> tuple:
    """The Sun's geocentric position (AU, Earth-centred equatorial frame) at Julian date jd."""
    n = jd - J2000_JD
    L = math.radians((280.460 + 0.9856474 * n) % 360.0)
    g = math.radians((357.528 + 0.9856003 * n) % 360.0)
    lam = L + math.radians(1.915) * math.sin(g) + math.radians(0.020) * math.sin(2.0 * g)
    eps = math.radians(23.439 - 0.0000004 * n)
    R = 1.00014 - 0.01671 * math.cos(g) - 0.00014 * math.cos(2.0 * g)
    return (R * math.cos(lam), R * math.cos(eps) * math.sin(lam), R * math.sin(eps) * math.sin(lam))
