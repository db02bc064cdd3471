"""The spacecraft's environment at time t (SPEC 5.5; docs/scenarios.md `[environment]`).

One Environment per run, built from the scenario's `[environment]` table; effectors get it through
their BodyContext, sensors through their SensorContext, and Plant.environment_state() reports it.

- epoch (epoch.py): the calendar instant of t = 0 (default J2000.0);
- orbit (reference_orbit.py): the spacecraft's position and velocity in N, the Earth-centred inertial
  frame. An attitude scenario has one when it gives [environment.orbit] (a circular orbit); an orbit
  scenario always has one: the circular orbit of its chief ([plant] orbit_radius_m and mu, oriented by
  [environment.orbit]) plus the plant's relative state. A scenario with both plants later passes both:
  nothing here depends on the plant kind but where the radius comes from;
- Sun (sun.py): the low-precision solar ephemeris; the direction from the spacecraft (from the Earth's
  centre when there is no orbit) and the distance;
- Earth: the direction from the spacecraft to the Earth's centre (None without an orbit);
- magnetic field (magnetic_field.py): a model slot, "none" today (None).

N here is the Earth-centred equatorial frame of the solar formula (mean equator and equinox of
date); an attitude scenario's inertial frame N is taken to be this frame.
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from datetime import datetime

from ..orbit import MU_EARTH
from . import epoch as _epoch
from .magnetic_field import MODELS
from .reference_orbit import CircularOrbit
from .sun import AU_M, sun_position_au

__all__ = ["Environment", "EnvironmentConfig", "OrbitConfig", "read", "MODELS", "AU_M"]


@dataclass(frozen=True)
class OrbitConfig:
    radius_m: float
    mu: float
    inclination_deg: float = 0.0
    raan_deg: float = 0.0
    arg_latitude0_deg: float = 0.0


@dataclass(frozen=True)
class EnvironmentConfig:
    epoch_utc: datetime = _epoch.J2000
    orbit: OrbitConfig | None = None        # None: no orbit (an attitude scenario without [environment.orbit])
    magnetic_field: str = "none"


ORBIT_ANGLES = ("inclination_deg", "raan_deg", "arg_latitude0_deg")


def read(root, kind: str, plant) -> EnvironmentConfig:
    """[environment] of a scenario; plant is the validated [plant] config (the orbit plant's chief radius)."""
    sec = root.table("environment", required=False)
    if sec is None:
        sec = type(root)(root.file, "environment", {})
    sec.only(("epoch_utc", "orbit", "magnetic_field"))
    epoch = _epoch.J2000
    if sec.has("epoch_utc"):
        raw, _ = sec._pop("epoch_utc", True, None)
        try:
            epoch = _epoch.parse(raw)
        except ValueError as exc:
            sec.fail(sec.key("epoch_utc"), str(exc))
    orbit = _read_orbit(sec.table("orbit", required=False), kind, plant)
    model = "none"
    msec = sec.table("magnetic_field", required=False)
    if msec is not None:
        model = msec.string("model", required=False, default="none", choices=tuple(MODELS))
        msec.done()
    sec.done()
    return EnvironmentConfig(epoch, orbit, model)


def _read_orbit(sec, kind: str, plant) -> OrbitConfig | None:
    if sec is None:
        return OrbitConfig(plant.orbit_radius_m, plant.mu) if kind == "orbit" else None
    if kind == "orbit":
        for k in ("radius_m", "mu"):
            if sec.has(k):
                sec.fail(sec.key(k), "an orbit scenario's reference orbit is its chief's: [plant] orbit_radius_m "
                                     "and mu")
        radius, mu = plant.orbit_radius_m, plant.mu
    else:
        radius = sec.number("radius_m", positive=True)
        mu = sec.number("mu", required=False, default=MU_EARTH, positive=True)
    angles = {k: sec.number(k, required=False, default=0.0) for k in ORBIT_ANGLES}
    i = angles["inclination_deg"]
    if not 0.0 <= i <= 180.0:
        sec.fail(sec.key("inclination_deg"), f"{i:g} deg is outside [0, 180] deg")
    sec.done()
    return OrbitConfig(radius, mu, **angles)


def _unit(v) -> tuple:
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    return (v[0] / n, v[1] / n, v[2] / n)


class Environment:
    """The environment's quantities at time t (s from the epoch); vectors in N, SI units."""

    def __init__(self, config: EnvironmentConfig):
        self.config = config
        self.jd0 = _epoch.julian_date(config.epoch_utc)
        o = config.orbit
        self.orbit = None if o is None else CircularOrbit(
            o.radius_m, o.mu, math.radians(o.inclination_deg), math.radians(o.raan_deg),
            math.radians(o.arg_latitude0_deg))
        self.magnetic_model = MODELS[config.magnetic_field]()

    def julian_date(self, t: float) -> float:
        return self.jd0 + t / _epoch.SECONDS_PER_DAY

    def orbit_state(self, t: float, relative=None):
        """(r_n_m, v_n_m_s) of the spacecraft, or None without an orbit; relative: the orbit plant's
        state [u v w x y z] about the reference (SPEC 2.8)."""
        if self.orbit is None:
            return None
        return self.orbit.state(t, relative)

    def sun_position_m(self, t: float) -> tuple:
        """The Sun from the Earth's centre (m, N)."""
        s = sun_position_au(self.julian_date(t))
        return (s[0] * AU_M, s[1] * AU_M, s[2] * AU_M)

    def sun_direction(self, t: float, r_n_m=None) -> tuple:
        """Unit vector from the spacecraft at r_n_m (the Earth's centre when None) to the Sun, in N."""
        s = self.sun_position_m(t)
        if r_n_m is not None:
            s = (s[0] - r_n_m[0], s[1] - r_n_m[1], s[2] - r_n_m[2])
        return _unit(s)

    @staticmethod
    def earth_direction(r_n_m):
        """Unit vector from the spacecraft to the Earth's centre, in N (None without a position)."""
        if r_n_m is None:
            return None
        return _unit((-r_n_m[0], -r_n_m[1], -r_n_m[2]))

    def magnetic_field(self, t: float, r_n_m):
        """The geomagnetic field at the spacecraft (T, N), or None: no model (the "none" model) or no orbit."""
        if r_n_m is None:
            return None
        return self.magnetic_model.field_n_t(self.julian_date(t), r_n_m)

    def at(self, t: float, relative=None) -> dict:
        """Everything at t: r_n_m, v_n_m_s (None without an orbit), sun_n, sun_distance_m, earth_n,
        b_n_t."""
        st = self.orbit_state(t, relative)
        r, v = (None, None) if st is None else st
        s = self.sun_position_m(t)
        d = s if r is None else (s[0] - r[0], s[1] - r[1], s[2] - r[2])
        dist = math.sqrt(d[0] * d[0] + d[1] * d[1] + d[2] * d[2])
        return {"r_n_m": r, "v_n_m_s": v, "sun_n": (d[0] / dist, d[1] / dist, d[2] / dist), "sun_distance_m": dist,
                "earth_n": self.earth_direction(r), "b_n_t": self.magnetic_field(t, r)}
