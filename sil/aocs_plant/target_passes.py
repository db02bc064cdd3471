"""Target passes of an orbiting scenario ([passes], docs/scenarios.md; docs/spec.md 5.11.4): ground targets
imaged while the spacecraft points at nadir, and the windows in which each is in view.

A target at geocentric latitude phi and longitude lambda on a spherical Earth of radius R_E sits at

    r_T,E = R_E (cos phi cos lambda, cos phi sin lambda, sin phi)       (Earth-fixed E)
    r_T,N = R3(-theta_g(t)) r_T,E                                       (N; theta_g the GMST, Meeus eq. 12.4)

and the spacecraft at r_c(t) of [environment.orbit] (reference_orbit.py). With d = r_T - r_c, it is in a
pass at t when it is above the horizon and inside the imager's field of regard about nadir:

    elevation  eps = asin( (-d) . r_T / (|d| |r_T|) ) > min_elevation_deg  (the spacecraft seen from the target)
    off-nadir  eta = acos( d . (-r_c) / (|d| |r_c|) ) <= max_off_nadir_deg

(Wertz and Larson, Space Mission Analysis and Design, 3rd ed., sec. 5.2: eta, eps and the Earth central
angle add to 90 deg). A pass is a maximal run of consecutive control ticks in view; the pointing over it is
the nadir pointing of the [target] (run metrics: aocs_analysis.passes). No scenario I/O beyond the reader.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from .environment import Environment, EnvironmentConfig
from .environment.magnetic_field import gmst_rad

#: the spherical Earth of the target positions: the WGS-84 equatorial radius (m); the latitude is taken as
#: geocentric (geodetic and geocentric latitude differ by at most 0.19 deg, about 21 km on the ground)
EARTH_RADIUS_M = 6378137.0


@dataclass(frozen=True)
class GroundTarget:
    name: str
    lat_deg: float            # geocentric latitude, deg
    lon_deg: float            # east longitude, deg

    def earth_fixed_m(self) -> np.ndarray:
        phi, lam = math.radians(self.lat_deg), math.radians(self.lon_deg)
        return EARTH_RADIUS_M * np.array([math.cos(phi) * math.cos(lam), math.cos(phi) * math.sin(lam),
                                          math.sin(phi)])


@dataclass(frozen=True)
class PassesConfig:
    targets: tuple                     # GroundTarget, in the file's order
    max_off_nadir_deg: float           # the imager's field of regard about nadir (half-angle), deg
    min_elevation_deg: float = 0.0     # the target's elevation mask, deg
    environment: EnvironmentConfig | None = None   # the scenario's (epoch, orbit): where the spacecraft is

    def windows_at(self, t) -> list[dict]:
        """windows() in the scenario's own environment (for the analysis, which does not build one)."""
        return windows(self, Environment(self.environment), t)


def read(root, kind: str, environment) -> PassesConfig | None:
    """[passes] with [[passes.targets]] (name, lat_deg, lon_deg); needs [environment.orbit] (the spacecraft's
    position) of an attitude scenario."""
    sec = root.table("passes", required=False)
    if sec is None:
        return None
    if kind != "attitude":
        sec.fail(sec.path, "target passes apply to attitude scenarios only")
    if environment.orbit is None:
        sec.fail(sec.path, "needs [environment.orbit] (where the spacecraft is)")
    eta = sec.number("max_off_nadir_deg", positive=True)
    if eta >= 90.0:
        sec.fail(sec.key("max_off_nadir_deg"), f"{eta:g} deg is not below 90 deg")
    eps = sec.number("min_elevation_deg", required=False, default=0.0)
    if not 0.0 <= eps < 90.0:
        sec.fail(sec.key("min_elevation_deg"), f"{eps:g} deg is outside [0, 90) deg")
    subs = sec.table_list("targets")
    if not subs:
        sec.fail(sec.key("targets"), "at least one [[passes.targets]] entry (name, lat_deg, lon_deg)")
    targets, names = [], set()
    for t in subs:
        name = t.string("name")
        if name in names:
            t.fail(t.key("name"), f"{name!r} is given twice")
        names.add(name)
        lat, lon = t.number("lat_deg"), t.number("lon_deg")
        if not -90.0 <= lat <= 90.0:
            t.fail(t.key("lat_deg"), f"{lat:g} deg is outside [-90, 90] deg")
        if not -180.0 <= lon <= 360.0:
            t.fail(t.key("lon_deg"), f"{lon:g} deg is outside [-180, 360] deg")
        t.done()
        targets.append(GroundTarget(name, lat, lon))
    sec.done()
    return PassesConfig(tuple(targets), eta, eps, environment)


def geometry(config: PassesConfig, environment, t: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(off-nadir eta, elevation eps), deg, each (n_targets, n) at the times t (s from the epoch)."""
    t = np.asarray(t, float)
    rc = np.array([environment.orbit.reference(float(tk))[0] for tk in t]).reshape(-1, 3)
    th = np.array([gmst_rad(environment.julian_date(float(tk))) for tk in t])
    c, s = np.cos(th), np.sin(th)
    eta = np.empty((len(config.targets), t.size))
    eps = np.empty_like(eta)
    for j, tg in enumerate(config.targets):
        e = tg.earth_fixed_m()
        rt = np.stack([c * e[0] - s * e[1], s * e[0] + c * e[1], np.full_like(c, e[2])], axis=1)
        d = rt - rc
        dn = np.linalg.norm(d, axis=1)
        cos_eta = -np.einsum("ij,ij->i", d, rc) / (dn * np.linalg.norm(rc, axis=1))
        sin_eps = -np.einsum("ij,ij->i", d, rt) / (dn * np.linalg.norm(rt, axis=1))
        eta[j] = np.degrees(np.arccos(np.clip(cos_eta, -1.0, 1.0)))
        eps[j] = np.degrees(np.arcsin(np.clip(sin_eps, -1.0, 1.0)))
    return eta, eps


def windows(config: PassesConfig, environment, t: np.ndarray) -> list[dict]:
    """Every pass inside the samples t, in time order: {"target" index, "i0", "i1" (the samples [i0, i1) in
    view), "closest_i" (least off-nadir sample), "min_off_nadir_deg", "max_elevation_deg"}."""
    eta, eps = geometry(config, environment, t)
    out = []
    for j in range(len(config.targets)):
        inside = (eta[j] <= config.max_off_nadir_deg) & (eps[j] > config.min_elevation_deg)
        edges = np.flatnonzero(np.diff(np.concatenate([[0], inside.astype(np.int8), [0]])))
        for i0, i1 in zip(edges[::2], edges[1::2]):
            k = int(i0 + np.argmin(eta[j, i0:i1]))
            out.append({"target": j, "i0": int(i0), "i1": int(i1), "closest_i": k,
                        "min_off_nadir_deg": float(eta[j, k]), "max_elevation_deg": float(eps[j, i0:i1].max())})
    return sorted(out, key=lambda p: (p["i0"], p["target"]))
