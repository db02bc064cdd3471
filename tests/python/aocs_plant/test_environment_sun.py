"""The low-precision Sun (environment/sun.py, SPEC 5.5) against published
values and against an independent formula written here, within the formula's stated 0.01 deg."""
import math
from datetime import datetime, timedelta, timezone

import numpy as np
import pytest

from aocs_plant.environment import epoch
from aocs_plant.environment.sun import AU_M, sun_position_au

PRECISION_DEG = 0.01      # The Astronomical Almanac, section C: the formula's precision, 1950 to 2050


def _ra_dec_r(s):
    r = math.sqrt(s[0] ** 2 + s[1] ** 2 + s[2] ** 2)
    return math.degrees(math.atan2(s[1], s[0])) % 360.0, math.degrees(math.asin(s[2] / r)), r


def _angle_deg(a, b):
    a, b = np.asarray(a) / np.linalg.norm(a), np.asarray(b) / np.linalg.norm(b)
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), a @ b))


def test_meeus_example_25a():
    """Meeus, Astronomical Algorithms (2nd ed.), example 25.a: 1992 October 13.0 TD (JDE 2448908.5),
    apparent alpha = 13h13m31.4s, delta = -7 deg 47' 06", R = 0.99760775 AU (the full theory)."""
    ra, dec, r = _ra_dec_r(sun_position_au(2448908.5))
    ra_ref = 15.0 * (13 + 13 / 60 + 31.4 / 3600)
    dec_ref = -(7 + 47 / 60 + 6 / 3600)
    sep = math.hypot((ra - ra_ref) * math.cos(math.radians(dec_ref)), dec - dec_ref)
    assert sep < PRECISION_DEG, sep
    assert r == pytest.approx(0.99760775, abs=1e-4)


#: the mean obliquity in 2026 (IAU 1980: 23.439291 deg - 0.0130042 deg T, T = 0.26 Julian centuries)
EPS_2026 = 23.439291 - 0.0130042 * 0.26
# the 2026 equinoxes and solstices (UTC; US Naval Observatory / timeanddate, to the minute: 0.0007 deg of Sun)
SEASONS_2026 = [("2026-03-20T14:46:00Z", 0.0, 0.0), ("2026-06-21T08:24:00Z", 90.0, EPS_2026),
                ("2026-09-23T00:05:00Z", 180.0, 0.0), ("2026-12-21T20:50:00Z", 270.0, -EPS_2026)]


@pytest.mark.parametrize("when,ra_ref,dec_ref", SEASONS_2026)
def test_equinoxes_and_solstices_of_2026(when, ra_ref, dec_ref):
    """At an equinox the Sun crosses the equator at right ascension 0 or 180 deg; at a solstice it is at
    90 or 270 deg with the declination +-obliquity."""
    ra, dec, _ = _ra_dec_r(sun_position_au(epoch.julian_date(epoch.parse(when))))
    assert abs((ra - ra_ref + 180.0) % 360.0 - 180.0) < PRECISION_DEG
    assert abs(dec - dec_ref) < PRECISION_DEG


def _vallado_sun_au(jd):
    """Vallado, Fundamentals of Astrodynamics and Applications (4th ed.), algorithm 29 (SUN): the same
    theory with its own coefficients, in Julian centuries."""
    T = (jd - 2451545.0) / 36525.0
    lam_m = math.radians(280.460 + 36000.771 * T)
    M = math.radians(357.5291092 + 35999.05034 * T)
    lam = lam_m + math.radians(1.914666471) * math.sin(M) + math.radians(0.019994643) * math.sin(2 * M)
    r = 1.000140612 - 0.016708617 * math.cos(M) - 0.000139589 * math.cos(2 * M)
    eps = math.radians(23.439291 - 0.0130042 * T)
    return (r * math.cos(lam), r * math.cos(eps) * math.sin(lam), r * math.sin(eps) * math.sin(lam))


def test_agrees_with_vallado_over_1950_to_2050():
    rng = np.random.default_rng(1)
    t0 = datetime(1950, 1, 1, tzinfo=timezone.utc)
    worst = 0.0
    for days in rng.uniform(0.0, 36500.0, 400):
        jd = epoch.julian_date(t0 + timedelta(days=float(days)))
        a, b = sun_position_au(jd), _vallado_sun_au(jd)
        worst = max(worst, _angle_deg(a, b))
        assert np.linalg.norm(a) == pytest.approx(np.linalg.norm(b), abs=2e-5)
    assert worst < PRECISION_DEG / 2, worst


def test_one_year_is_one_turn_and_the_distance_swings_with_the_eccentricity():
    jd0 = epoch.julian_date(epoch.parse("2026-01-01T00:00:00Z"))
    r = [np.linalg.norm(sun_position_au(jd0 + d)) for d in range(366)]
    assert 0.9832 < min(r) < 0.9834 and 1.0166 < max(r) < 1.0168        # perihelion early January, aphelion July
    assert int(np.argmin(r)) in (1, 2, 3) and 180 <= int(np.argmax(r)) <= 186
    assert _angle_deg(sun_position_au(jd0), sun_position_au(jd0 + 365.2422)) < 0.01   # a tropical year
    assert AU_M == 149597870700.0
