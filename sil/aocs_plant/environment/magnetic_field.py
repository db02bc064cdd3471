"""Geomagnetic field models (`[environment.magnetic_field] model`; docs/spec.md 5.5.1).

A model is a class with field_n_t(jd, r_n_m) -> the field (tesla, the Earth-centred inertial frame N)
at the spacecraft, registered in MODELS under its scenario name:

- "none": no field (None), which a magnetometer, a magnetorquer and a residual dipole treat as a zero
  field;
- "igrf": the International Geomagnetic Reference Field (IGRF-14, Alken et al. 2021 for the IGRF-13
  method, the IAGA V-MOD 2024 release for the coefficients), with the Gauss coefficients of the
  ppigrf package (its IGRF14.shc, read by ppigrf.ppigrf.read_shc; no coefficient is typed here) and
  ppigrf's linear-in-time interpolation between the 5-year model epochs. The synthesis is written out
  below in plain Python (ppigrf's igrf_gc reads and interpolates its coefficient file with pandas on
  every call, far too slow for one call per control period) and tested against ppigrf.igrf_gc itself and against two independent
  implementations (tests/python/aocs_plant/test_environment_igrf.py).

The field at a position r_N (m, N) at Julian date jd (UTC taken as UT1):

    theta_g = GMST(jd)                                    Meeus, Astronomical Algorithms, eq. 12.4
    r_E = R3(theta_g) r_N                                 the Earth-fixed frame E (no polar motion,
                                                          no equation of the equinoxes: < 1.2 s of
                                                          Earth rotation, N being of date)
    (r, theta, phi) = the geocentric radius, colatitude, east longitude of r_E
    B_r     =  sum_n (n+1) (a/r)^(n+2) sum_m (g_nm cos m phi + h_nm sin m phi) P_n^m(cos theta)
    B_theta = -sum_n (a/r)^(n+2) sum_m (g_nm cos m phi + h_nm sin m phi) dP_n^m/dtheta
    B_phi   = -1/sin theta sum_n (a/r)^(n+2) sum_m m (h_nm cos m phi - g_nm sin m phi) P_n^m
    B_E = B_r e_r + B_theta e_theta + B_phi e_phi,   B_N = R3(-theta_g) B_E,   nT -> T

a = 6371.2 km, n = 1..13, P_n^m Schmidt semi-normalised (Wertz 1978, app. H: the Gauss-normalised
recursion times S_nm, as ppigrf.get_legendre). Within 1e-12 rad of a pole the point is moved to
1e-12 rad (7 um) from it (B_phi's 1/sin theta).

FieldAlongOrbit samples a model on the grid of control periods t_j = j dt along the scenario's orbit
and interpolates linearly between two samples: one model evaluation per period for every effector and
sensor that asks (the model keeps its last few answers, so they share them). The interpolation error
is at most (omega dt)^2 / 8 |B| with omega <= 2 n_orbit (the dipole's period is half an orbit at most):
0.03 nT at dt = 1 s in LEO; a sample at t_j itself is the model's value.
"""
from __future__ import annotations

import bisect
import math
from datetime import timezone

from .epoch import J2000_JD, julian_date

REFERENCE_RADIUS_KM = 6371.2      # the IGRF's geomagnetic reference radius a
POLE_SIN_MIN = 1e-12              # sin(colatitude) below which the point is moved off the pole
NT = 1e-9                         # tesla per nanotesla


def gmst_rad(jd: float) -> float:
    """Greenwich mean sidereal time (rad, in [0, 2 pi)) at the Julian date jd (UT1), Meeus eq. 12.4:
    280.46061837 deg + 360.98564736629 deg d + 0.000387933 deg T^2 - T^3 / 38710000 deg,
    d = jd - 2451545.0, T = d / 36525 (360 d split off exactly as 360 (d mod 1))."""
    d = jd - J2000_JD
    t = d / 36525.0
    deg = 280.46061837 + 360.0 * (d % 1.0) + 0.98564736629 * d + t * t * (0.000387933 - t / 38710000.0)
    return math.radians(deg % 360.0)


def inertial_to_earth_fixed(theta_g: float, v) -> tuple:
    """R3(theta_g) v: N components -> E (Earth-fixed) components."""
    c, s = math.cos(theta_g), math.sin(theta_g)
    return (c * v[0] + s * v[1], -s * v[0] + c * v[1], v[2])


def earth_fixed_to_inertial(theta_g: float, v) -> tuple:
    """R3(-theta_g) v: E components -> N components."""
    c, s = math.cos(theta_g), math.sin(theta_g)
    return (c * v[0] - s * v[1], s * v[0] + c * v[1], v[2])


class NoField:
    """No magnetic field model: every query answers None."""

    name = "none"

    def field_n_t(self, jd: float, r_n_m):
        return None


def _igrf_table():
    """ppigrf's IGRF coefficients: (epochs as Julian dates, [(n, m)], rows of g, rows of h), nT."""
    from ppigrf import ppigrf as _pp  # deferred: only a scenario with model = "igrf" needs it (and pandas)

    g, h = _pp.read_shc(_pp.shc_fn)
    keys = [(int(n), int(m)) for n, m in g.columns]
    epochs = [julian_date(ts.to_pydatetime().replace(tzinfo=timezone.utc)) for ts in g.index]
    return (tuple(epochs), tuple(keys), tuple(tuple(float(v) for v in row) for row in g.values),
            tuple(tuple(float(v) for v in row) for row in h.values), _pp.shc_fn)


class Igrf:
    """The IGRF through ppigrf's coefficient file: field_n_t(jd, r_n_m) in tesla, N."""

    name = "igrf"
    _table = None          # read once per process
    CACHE = 8              # answers kept: the effectors and sensors of one period ask for the same point

    def __init__(self):
        if Igrf._table is None:
            Igrf._table = _igrf_table()
        self.epochs_jd, self.keys, self._g, self._h, self.source = Igrf._table
        self.nmax = nmax = max(n for n, _ in self.keys)
        # Schmidt factors S_nm (ppigrf.get_legendre / Wertz app. H), folded into the coefficients
        S = {(0, 0): 1.0}
        for n in range(1, nmax + 1):
            for m in range(n + 1):
                S[n, m] = S[n - 1, 0] * (2.0 * n - 1.0) / n if m == 0 else \
                    S[n, m - 1] * math.sqrt((n - m + 1) * (2.0 if m == 1 else 1.0) / (n + m))
        self._S = tuple(S[k] for k in self.keys)
        # the recursion's plan, row by row: (n, m, slot, slot of (n-1, m-1) or (n-1, m), slot of (n-2, m)
        # or -1, K_nm, index of (n, m) in keys or -1); P and dP are flat lists over the slots
        index = {k: i for i, k in enumerate(self.keys)}

        def slot(n, m):
            return n * (n + 1) // 2 + m
        plan = []
        for n in range(1, nmax + 1):
            for m in range(n + 1):
                if n == m:
                    plan.append((n, m, slot(n, m), slot(n - 1, m - 1), -1, 0.0, index.get((n, m), -1)))
                else:
                    two = slot(n - 2, m) if n >= 2 and m <= n - 2 else -1
                    k = ((n - 1) ** 2 - m * m) / ((2 * n - 1) * (2 * n - 3)) if n >= 2 else 0.0
                    plan.append((n, m, slot(n, m), slot(n - 1, m), two, k, index.get((n, m), -1)))
        self._plan = tuple(plan)
        self._slots = slot(nmax, nmax) + 1
        self._coef_jd = None
        self._coef = None
        self._cache: dict = {}

    # ------------------------------------------------------------ coefficients
    def coefficients(self, jd: float) -> tuple:
        """(g, h) at jd (nT, in the order of keys): linear in time between the bracketing model epochs,
        as ppigrf (pandas' "time" interpolation). ValueError outside the file's epochs."""
        if jd == self._coef_jd:
            return self._coef
        e = self.epochs_jd
        if not e[0] <= jd <= e[-1]:
            raise ValueError(f"the IGRF coefficients of {self.source.rsplit('/', 1)[-1]} cover Julian dates "
                             f"{e[0]:.1f} to {e[-1]:.1f}; {jd:.1f} is outside")
        i = min(len(e) - 2, bisect.bisect_right(e, jd) - 1)     # e[i] <= jd < e[i + 1] (the last: <=)
        f = (jd - e[i]) / (e[i + 1] - e[i])
        g0, g1, h0, h1 = self._g[i], self._g[i + 1], self._h[i], self._h[i + 1]
        g = tuple([a + f * (b - a) for a, b in zip(g0, g1)])
        h = tuple([a + f * (b - a) for a, b in zip(h0, h1)])
        self._coef_jd, self._coef = jd, (g, h)
        return g, h

    # ------------------------------------------------------------ synthesis
    def field_spherical_nt(self, jd: float, r_km: float, colat_rad: float, lon_rad: float) -> tuple:
        """(B_r, B_theta, B_phi) in nT at geocentric radius r_km, colatitude, east longitude (rad)."""
        g, h = self.coefficients(jd)
        S = self._S
        st, ct = math.sin(colat_rad), math.cos(colat_rad)
        if abs(st) < POLE_SIN_MIN:
            st = POLE_SIN_MIN
            ct = math.copysign(math.sqrt(1.0 - st * st), ct)
        cp, sp = math.cos(lon_rad), math.sin(lon_rad)
        cm, sm = [1.0], [0.0]
        for m in range(1, self.nmax + 1):
            cm.append(cm[-1] * cp - sm[-1] * sp)
            sm.append(sm[-1] * cp + cm[-2] * sp)
        # Gauss-normalised P^{n,m} and dP/dtheta (Wertz app. H), row by row
        P = [0.0] * self._slots
        dP = [0.0] * self._slots
        P[0] = 1.0
        ar = REFERENCE_RADIUS_KM / r_km
        arn = ar * ar        # (a/r)^(n+2) at n = 0
        last = 0
        br = bt = bp = 0.0
        for n, m, k, one, two, K, i in self._plan:
            if n != last:
                arn *= ar
                last = n
            if n == m:
                p = st * P[one]
                dp = st * dP[one] + ct * P[one]
            elif two < 0:
                p = ct * P[one]
                dp = ct * dP[one] - st * P[one]
            else:
                p = ct * P[one] - K * P[two]
                dp = ct * dP[one] - st * P[one] - K * dP[two]
            P[k] = p
            dP[k] = dp
            if i < 0:
                continue
            s = S[i]
            gnm, hnm = g[i] * s, h[i] * s
            a = gnm * cm[m] + hnm * sm[m]
            br += (n + 1) * arn * a * p
            bt -= arn * a * dp
            bp -= arn * m * (hnm * cm[m] - gnm * sm[m]) * p
        return br, bt, bp / st

    def field_e_nt(self, jd: float, r_e_m) -> tuple:
        """The field in the Earth-fixed frame E (nT) at the Earth-fixed position r_e_m (m)."""
        x, y, z = r_e_m
        rho = math.hypot(x, y)
        r = math.sqrt(rho * rho + z * z)
        colat = math.atan2(rho, z)
        lon = math.atan2(y, x) if rho > 0.0 else 0.0
        br, bt, bp = self.field_spherical_nt(jd, r * 1e-3, colat, lon)
        st, ct = math.sin(colat), math.cos(colat)
        cp, sp = math.cos(lon), math.sin(lon)
        return (br * st * cp + bt * ct * cp - bp * sp,
                br * st * sp + bt * ct * sp + bp * cp,
                br * ct - bt * st)

    def field_n_t(self, jd: float, r_n_m):
        key = (jd, r_n_m[0], r_n_m[1], r_n_m[2])
        hit = self._cache.get(key)
        if hit is not None:
            return hit
        th = gmst_rad(jd)
        b = earth_fixed_to_inertial(th, self.field_e_nt(jd, inertial_to_earth_fixed(th, r_n_m)))
        out = (b[0] * NT, b[1] * NT, b[2] * NT)
        if len(self._cache) >= self.CACHE:
            self._cache.pop(next(iter(self._cache)))
        self._cache[key] = out
        return out


MODELS = {NoField.name: NoField, Igrf.name: Igrf}


class FieldAlongOrbit:
    """B_N(t) along the scenario's orbit (T, N), or None (no model or no orbit): the model at the grid
    t_j = j dt, linear between t_j and t_(j+1) (module docstring)."""

    def __init__(self, environment, dt: float):
        self.env = environment
        self.dt = float(dt)
        self.active = environment is not None and environment.orbit is not None \
            and environment.magnetic_model.name != NoField.name
        self._j = None
        self._b0 = self._b1 = None

    def at_grid(self, j: int):
        env = self.env
        t = j * self.dt
        return env.magnetic_field(t, env.orbit_state(t)[0])

    def __call__(self, t: float):
        if not self.active:
            return None
        x = t / self.dt
        j = math.floor(x + 1e-9)
        f = x - j
        if j != self._j:
            if self._j is not None and j == self._j + 1:
                self._b0 = self._b1
            else:
                self._b0 = self.at_grid(j)
            self._b1 = self.at_grid(j + 1)
            self._j = j
        b0 = self._b0
        if f <= 1e-9:
            return b0
        b1 = self._b1
        return (b0[0] + f * (b1[0] - b0[0]), b0[1] + f * (b1[1] - b0[1]), b0[2] + f * (b1[2] - b0[2]))
