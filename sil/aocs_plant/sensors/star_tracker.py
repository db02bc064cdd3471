"""Star tracker (issue 20; docs/spec.md 5.6): the attitude of its own frame S.

Its section [sensors.star_tracker] builds it (absent: no star tracker). It measures the quaternion of S
with respect to N at the time of measurement t_meas = t - latency_s:

    q_SN,true = q_SB (x) q_BN(t_meas)                       (q_SB: the mounting, Shuster product, SPEC 1)
    e = b + n + l(t_meas)        (rad, in S: a small rotation vector)
        b = bias_arcsec                                      fixed misalignment
        n = (s_c N1, s_c N2, s_a N3)                         white: cross-boresight s_c on x, y, about s_a on z
        l = low-frequency error, per axis:
            "gauss_markov":  l_j+1 = exp(-h/tau) l_j + A sqrt(1 - exp(-2h/tau)) N   (stationary std A, l_0 ~ N(0, A^2))
            "sinusoid":      l = A sin(2 pi t_meas / P + phase)
    q_meas = dq(e) (x) q_SN,true, renormalised               A(q_meas) = A(dq(e)) A(q_SN)

dq(e) is the rotation by the rotation vector e, so e is the error angle per axis of S.

Timing: the tracker takes a sample at the first control tick t >= j / rate_hz (j = 0, 1, ...), measuring
the attitude at t_meas = t - latency_s (the body's attitude at the recorded period ends, slerp between
them: exact when latency_s is a multiple of the control period); a sample whose t_meas < 0 is not taken.
Between samples the message carries the last sample and its t_meas, st_new and st_valid false.
A sample is valid unless the boresight +z_S is within sun_exclusion_deg of the Sun direction or
earth_exclusion_deg of the Earth's centre (environment at t_meas; no Earth without an orbit); during a
scheduled outage ([start_s, end_s)) no sample is taken. Sample: st_q, st_valid, st_new, st_t_meas.
Faults: dropout, nan, nonunit. Seeded stream "star_tracker" (6), one draw of 6 normals per sample taken
(3 white, 3 Gauss-Markov), whatever the configuration, so that a key never shifts another's numbers.
The suite's latency_periods does not apply: its latency is latency_s.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from aocs_core.conventions import ARCSEC_PER_RAD, quat_from_rotvec, quat_mul

from ..rng import NormalStream
from .base import ATTITUDE, ZERO3, Sensor, register

SECTION = "star_tracker"
LOW_FREQUENCY = ("none", "gauss_markov", "sinusoid")
IDENTITY = (0.0, 0.0, 0.0, 1.0)
KEYS = ("mounting_q", "rate_hz", "latency_s", "noise_cross_arcsec", "noise_about_arcsec", "bias_arcsec",
        "low_frequency", "low_frequency_amplitude_arcsec", "low_frequency_time_s", "low_frequency_phase_deg",
        "sun_exclusion_deg", "earth_exclusion_deg", "outages")


@dataclass(frozen=True)
class StarTrackerConfig:
    """The [sensors.star_tracker] figures, built only by _read (its defaults are the keys' defaults there)."""
    mounting_q: tuple                      # q_SB, scalar last
    rate_hz: float                         # its sample rate (<= the control rate)
    latency_s: float
    noise_cross_arcsec: float              # 1-sigma about x_S and y_S
    noise_about_arcsec: float              # 1-sigma about z_S (the boresight)
    bias_arcsec: tuple                     # fixed misalignment rotation, per axis of S
    low_frequency: str
    low_frequency_amplitude_arcsec: tuple  # gauss_markov: stationary std; sinusoid: amplitude
    low_frequency_time_s: tuple            # gauss_markov: correlation time; sinusoid: period
    low_frequency_phase_deg: tuple         # sinusoid only
    sun_exclusion_deg: float               # 0: no exclusion
    earth_exclusion_deg: float
    outages: tuple                         # ((start_s, end_s), ...)

    @property
    def ideal(self) -> bool:
        return False


def _read(sec, ctx) -> StarTrackerConfig:
    sec.only(KEYS)
    q = sec.vector("mounting_q", n=4, required=False, default=IDENTITY)
    n = math.sqrt(sum(x * x for x in q))
    if abs(n - 1.0) > 1e-9:
        sec.fail(sec.key("mounting_q"), f"must be a unit quaternion (x, y, z, w), its norm is {n:.12g}")
    control_hz = 1.0 / ctx.dt
    rate = sec.number("rate_hz", required=False, default=control_hz, positive=True)
    if rate > control_hz * (1.0 + 1e-9):
        sec.fail(sec.key("rate_hz"), f"{rate:g} Hz is above the control rate ({control_hz:g} Hz)")
    latency = sec.number("latency_s", required=False, default=0.0, nonneg=True)
    if latency >= ctx.duration_s:
        sec.fail(sec.key("latency_s"), f"{latency:g} s is not shorter than the run (duration_s = {ctx.duration_s:g})")
    cross = sec.number("noise_cross_arcsec", required=False, default=0.0, nonneg=True)
    about = sec.number("noise_about_arcsec", required=False, default=0.0, nonneg=True)
    bias = sec.vector("bias_arcsec", required=False, default=ZERO3)
    lf = sec.string("low_frequency", required=False, default="none", choices=LOW_FREQUENCY)
    lf_keys = ("low_frequency_amplitude_arcsec", "low_frequency_time_s", "low_frequency_phase_deg")
    if lf == "none":
        for k in lf_keys:
            if sec.has(k):
                sec.fail(sec.key(k), 'needs low_frequency = "gauss_markov" or "sinusoid"')
        amp, time_s, phase = ZERO3, (1.0, 1.0, 1.0), ZERO3
    else:
        amp = sec.scalar_or_vector("low_frequency_amplitude_arcsec")
        if any(a < 0.0 for a in amp):
            sec.fail(sec.key("low_frequency_amplitude_arcsec"), f"must be >= 0, got {list(amp)}")
        time_s = sec.scalar_or_vector("low_frequency_time_s", positive=True)
        if lf == "gauss_markov" and sec.has("low_frequency_phase_deg"):
            sec.fail(sec.key("low_frequency_phase_deg"), 'applies to low_frequency = "sinusoid" only')
        phase = sec.scalar_or_vector("low_frequency_phase_deg", required=False, default=ZERO3)
    excl = {}
    for k in ("sun_exclusion_deg", "earth_exclusion_deg"):
        a = sec.number(k, required=False, default=0.0, nonneg=True)
        if a >= 180.0:
            sec.fail(sec.key(k), f"{a:g} deg must be below 180 deg")
        excl[k] = a
    outages = []
    raw, present = sec._pop("outages", False, [])
    if present and not isinstance(raw, list):
        sec.fail(sec.key("outages"), "expected an array of [start_s, end_s] pairs")
    for i, o in enumerate(raw):
        key = f"{sec.key('outages')}[{i}]"
        t0, t1 = sec._check_vector(key, o, 2)
        if t0 < 0.0:
            sec.fail(key, f"starts before the run ({t0:g} s)")
        if not t1 > t0:
            sec.fail(key, f"ends before it starts ({t1:g} <= {t0:g} s)")
        if t0 >= ctx.duration_s:
            sec.fail(key, f"starts at {t0:g} s, not inside the run (duration_s = {ctx.duration_s:g})")
        outages.append((t0, t1))
    sec.done()
    return StarTrackerConfig(tuple(q), rate, latency, cross, about, bias, lf, tuple(amp), tuple(time_s),
                             tuple(phase), excl["sun_exclusion_deg"], excl["earth_exclusion_deg"], tuple(outages))


def _slerp(qa, qb, f):
    """The rotation a fraction f of the way from qa to qb (shortest path)."""
    d = qa[0] * qb[0] + qa[1] * qb[1] + qa[2] * qb[2] + qa[3] * qb[3]
    if d < 0.0:
        qb, d = tuple(-x for x in qb), -d
    if d > 1.0 - 1e-12:
        q = tuple(a + f * (b - a) for a, b in zip(qa, qb))
    else:
        th = math.acos(d)
        s = math.sin(th)
        wa, wb = math.sin((1.0 - f) * th) / s, math.sin(f * th) / s
        q = tuple(wa * a + wb * b for a, b in zip(qa, qb))
    k = 1.0 / math.sqrt(sum(x * x for x in q))
    return tuple(x * k for x in q)


def _angle_deg(u, v) -> float:
    c = u[0] * v[0] + u[1] * v[1] + u[2] * v[2]
    return math.degrees(math.acos(max(-1.0, min(1.0, c))))


@register
class StarTracker(Sensor):
    name = "star_tracker"
    stream_index = 6
    applies_to = (ATTITUDE,)
    keys = (SECTION,)
    value_field, valid_field = "st_q", "st_valid"
    extra_fields = ("st_new", "st_t_meas")
    truth_field = "q"
    delayed = False           # its own latency (latency_s), from the periods it records
    records = True
    own_validity = True
    fault_kinds = ("dropout", "nan", "nonunit")
    initial_last = IDENTITY

    @classmethod
    def read(cls, sec, ctx):
        st = sec.table(SECTION, required=False)
        return None if st is None else _read(st, ctx)

    def __init__(self, config: StarTrackerConfig, ctx):
        super().__init__(config, ctx)
        c = config
        self.dt = float(ctx.dt)
        self.environment = ctx.environment
        self.q_sb = tuple(c.mounting_q)
        self.period = 1.0 / c.rate_hz
        self.latency = c.latency_s
        self.sigma = (c.noise_cross_arcsec / ARCSEC_PER_RAD,) * 2 + (c.noise_about_arcsec / ARCSEC_PER_RAD,)
        self.bias = tuple(b / ARCSEC_PER_RAD for b in c.bias_arcsec)
        self.lf_kind = c.low_frequency
        self.lf_amp = tuple(a / ARCSEC_PER_RAD for a in c.low_frequency_amplitude_arcsec)
        self.lf_time = c.low_frequency_time_s
        self.lf_phase = tuple(math.radians(p) for p in c.low_frequency_phase_deg)
        self.cos_sun = math.cos(math.radians(c.sun_exclusion_deg)) if c.sun_exclusion_deg > 0.0 else None
        self.cos_earth = math.cos(math.radians(c.earth_exclusion_deg)) if c.earth_exclusion_deg > 0.0 else None
        self.outages = c.outages
        self.stream = NormalStream(ctx.seed, self.name, 1.0, width=6)
        self.tol = 1e-9 * self.dt
        self.keep = int(math.ceil(self.latency / self.dt)) + 2
        self.records_tq: list = []      # (t, q_BN) of the latest period ends
        self.j = 0                      # index of the next sample due (due at j * period)
        self.lf = None                  # the Gauss-Markov state (rad), drawn at the first sample
        self.lf_t = None
        # the last sample
        self.q_meas, self.t_meas, self.new = IDENTITY, 0.0, False
        self.valid, self.available = False, True
        self.q_true, self.error = IDENTITY, ZERO3
        self.white = ZERO3              # the white part n of the last sample's error (the injected noise fault's)
        self.sun_angle = self.earth_angle = None
        self.sun_excluded = self.earth_excluded = self.in_outage = False

    def source(self, plant):
        body = plant.body
        return lambda: (plant.t, body.q)

    def record(self, value) -> None:
        r = self.records_tq
        r.append(value)
        if len(r) > self.keep:
            del r[0]

    def attitude_at(self, t: float) -> tuple:
        """q_BN at time t from the recorded period ends (slerp between them)."""
        r = self.records_tq
        if t >= r[-1][0] - self.tol:
            return r[-1][1]
        for i in range(len(r) - 1, 0, -1):
            ta, qa = r[i - 1]
            tb, qb = r[i]
            if ta - self.tol <= t:
                if abs(t - ta) <= self.tol:
                    return qa
                return _slerp(qa, qb, (t - ta) / (tb - ta))
        return r[0][1]

    def _outage(self, t: float) -> bool:
        return any(a <= t < b for a, b in self.outages)

    def _low_frequency(self, t_meas: float, n) -> tuple:
        if self.lf_kind == "sinusoid":
            return tuple(a * math.sin(2.0 * math.pi * t_meas / p + ph)
                         for a, p, ph in zip(self.lf_amp, self.lf_time, self.lf_phase))
        if self.lf_kind == "gauss_markov":
            if self.lf is None:
                self.lf = tuple(a * x for a, x in zip(self.lf_amp, n))
            else:
                h = t_meas - self.lf_t
                out = []
                for a, tau, x, l0 in zip(self.lf_amp, self.lf_time, n, self.lf):
                    phi = math.exp(-h / tau)
                    out.append(phi * l0 + a * math.sqrt(max(0.0, 1.0 - phi * phi)) * x)
                self.lf = tuple(out)
            self.lf_t = t_meas
            return self.lf
        return ZERO3

    def measure(self, value):
        t = value[0]
        self.new = False
        self.in_outage = self._outage(t)
        self.available = not self.in_outage
        due = self.j * self.period
        if t + self.tol >= due:
            # the sample due now (a late call takes the latest due one; samples skipped are not drawn)
            self.j = int(math.floor((t + self.tol) / self.period)) + 1
            t_meas = t - self.latency
            if t_meas >= -self.tol and not self.in_outage:
                self._sample(max(0.0, t_meas))
        self.valid = self.new and not (self.sun_excluded or self.earth_excluded)
        if self.new:
            self.available = self.valid
        return self.q_meas

    def _sample(self, t_meas: float) -> None:
        x = self.stream.next()
        q_sn = quat_mul(self.q_sb, self.attitude_at(t_meas))
        lf = self._low_frequency(t_meas, x[3:])
        s, b = self.sigma, self.bias
        e = (b[0] + s[0] * x[0] + lf[0], b[1] + s[1] * x[1] + lf[1], b[2] + s[2] * x[2] + lf[2])
        q = quat_mul(quat_from_rotvec(e), q_sn)
        k = 1.0 / math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])
        self.q_meas = (q[0] * k, q[1] * k, q[2] * k, q[3] * k)
        self.q_true, self.error, self.t_meas, self.new = q_sn, e, t_meas, True
        self.white = (s[0] * x[0], s[1] * x[1], s[2] * x[2])
        # the boresight +z_S in N: the third row of A(q_SN)
        q1, q2, q3, q4 = q_sn
        z = (2.0 * (q1 * q3 + q2 * q4), 2.0 * (q2 * q3 - q1 * q4), q4 * q4 - q1 * q1 - q2 * q2 + q3 * q3)
        env = self.environment
        st = env.orbit_state(t_meas) if env is not None else None
        r = None if st is None else st[0]
        sun = env.sun_direction(t_meas, r) if env is not None else None
        earth = env.earth_direction(r) if env is not None else None
        self.sun_angle = None if sun is None else _angle_deg(z, sun)
        self.earth_angle = None if earth is None else _angle_deg(z, earth)
        self.sun_excluded = self.cos_sun is not None and self.sun_angle is not None and \
            sum(a * b for a, b in zip(z, sun)) > self.cos_sun
        self.earth_excluded = self.cos_earth is not None and self.earth_angle is not None and \
            sum(a * b for a, b in zip(z, earth)) > self.cos_earth

    def extra(self) -> dict:
        return {"st_new": self.new, "st_t_meas": self.t_meas}

    def truth(self) -> dict:
        """Of the last sample taken: the true q_SN at its t_meas, the error rotation (rad, S, before faults)
        and its angle (arcsec), the boresight's angles to the Sun and the Earth (deg, None: no direction),
        and why the current period is invalid."""
        e = self.error
        return {"q_sn": self.q_true, "t_meas": self.t_meas, "error_rad": e,
                "error_arcsec": math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]) * ARCSEC_PER_RAD,
                "sun_angle_deg": self.sun_angle, "earth_angle_deg": self.earth_angle,
                "sun_excluded": self.sun_excluded, "earth_excluded": self.earth_excluded,
                "outage": self.in_outage, "new": self.new}
