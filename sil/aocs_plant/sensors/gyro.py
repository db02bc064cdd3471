"""Gyro (issue 20): a three-axis rate-integrating gyro
sampled once per control period, with the angle random walk / rate random walk model of Farrenkopf
(1978) and its exact discretisation (Markley & Crassidis 2014, ch. 4 and 6; docs/spec.md 5.6).

Its section [sensors.gyro] builds it (absent: no gyro). Over the sample interval h = t_k - t_(k-1):

    true increment:  dtheta_k = the rotation vector of q_BN(t_k) (x) q_BN(t_(k-1))^-1   (rad, B; exact)
                     wbar_k = dtheta_k / h                                  (the mean true rate)
    bias:            beta_k = beta_(k-1) + sigma_u sqrt(h) N_u,k           (beta_0 = bias_rad_s)
    rate output:     w_k = (I + S + M) wbar_k + (beta_(k-1) + beta_k) / 2
                           + sqrt(sigma_v^2 / h + sigma_u^2 h / 12) N_v,k
    angle output:    dtheta_meas,k = w_k h

with S = diag(scale_factor_ppm) 1e-6 and M the misalignment (3 small angles d: M = -[d x], the gyro
axes rotated by d from B; or a 3x3 with zero diagonal, as given). The bias sequence and the
noise are the exact sampled form of the continuous model w = w_true + beta + eta_v, beta' = eta_u
(spectral densities sigma_v^2, sigma_u^2): integrated over h, the angle noise given the bias at both
ends has variance sigma_v^2 h + sigma_u^2 h^3 / 12 (the Brownian bridge of the bias), independent of
the bias increment. Then saturation clips w_k to +-saturation_rad_s per axis, and quantisation rounds:
rate mode to quantum_rad_s; angle mode to quantum_rad, carrying the remainder into the next sample
(the pulse count of a rate-integrating gyro: the summed angle is never off by more than half a quantum).

The first sample (no earlier period end) measures the true rate w(t_0) over one control period. It is
a delayed sensor (the suite's latency_periods applies, as to the ideal rate sensor). Sample: gyro_w
(rad/s, rate mode) or gyro_dtheta (rad, angle mode), gyro_valid. Faults: dropout, nan; the injected faults
(bias step, stuck axis, reduced range) of aocs_plant.faults.gyro act inside the measurement. Seeded stream
"gyro" (7), one draw of 6 normals (N_v, N_u) per sample when sigma_v or sigma_u is set.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from ..rng import NormalStream
from .base import ATTITUDE, ZERO3, Sensor, register

SECTION = "gyro"
MODES = ("rate", "angle")
KEYS = ("mode", "arw_rad_sqrt_s", "rrw_rad_s_sqrt_s", "bias_rad_s", "scale_factor_ppm", "misalignment_rad",
        "quantum_rad_s", "quantum_rad", "saturation_rad_s")
I3 = ((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0))


@dataclass(frozen=True)
class GyroConfig:
    mode: str = "rate"
    arw: float = 0.0                # sigma_v, rad/s^0.5
    rrw: float = 0.0                # sigma_u, rad/s^1.5
    bias_rad_s: tuple = ZERO3       # beta_0
    scale_factor_ppm: tuple = ZERO3
    misalignment: tuple = ((0.0,) * 3,) * 3   # M (3x3)
    quantum: float = 0.0            # rad/s (rate mode) or rad (angle mode); 0: none
    saturation_rad_s: float = 0.0   # 0: none

    @property
    def ideal(self) -> bool:
        return False

    @property
    def matrix(self) -> tuple:
        """I + S + M."""
        s = self.scale_factor_ppm
        return tuple(tuple(I3[i][j] + (s[i] * 1e-6 if i == j else 0.0) + self.misalignment[i][j] for j in range(3))
                     for i in range(3))


def _read(sec, ctx) -> GyroConfig:
    sec.only(KEYS)
    mode = sec.string("mode", required=False, default="rate", choices=MODES)
    arw = sec.number("arw_rad_sqrt_s", required=False, default=0.0, nonneg=True)
    rrw = sec.number("rrw_rad_s_sqrt_s", required=False, default=0.0, nonneg=True)
    bias = sec.vector("bias_rad_s", required=False, default=ZERO3)
    sf = sec.vector("scale_factor_ppm", required=False, default=ZERO3)
    mis = ((0.0,) * 3,) * 3
    raw = sec.data.get("misalignment_rad")
    if raw is not None:
        key = sec.key("misalignment_rad")
        if isinstance(raw, list) and raw and isinstance(raw[0], list):
            mis = sec.matrix3("misalignment_rad")
            if any(mis[i][i] != 0.0 for i in range(3)):
                sec.fail(key, "the diagonal of a 3x3 misalignment must be zero (scale_factor_ppm holds it)")
        else:
            d = sec.vector("misalignment_rad")
            mis = ((0.0, d[2], -d[1]), (-d[2], 0.0, d[0]), (d[1], -d[0], 0.0))   # -[d x]
        if max(abs(x) for row in mis for x in row) > 0.1:
            sec.fail(key, "must be small angles (|m| <= 0.1 rad)")
    other = {"rate": "quantum_rad", "angle": "quantum_rad_s"}[mode]
    if sec.has(other):
        sec.fail(sec.key(other), f'does not apply to mode = "{mode}" (its quantum is '
                                 f'{"quantum_rad_s" if mode == "rate" else "quantum_rad"})')
    quantum = sec.number("quantum_rad_s" if mode == "rate" else "quantum_rad", required=False, default=0.0,
                         nonneg=True)
    sat = sec.number("saturation_rad_s", required=False, default=0.0, nonneg=True)
    sec.done()
    return GyroConfig(mode, arw, rrw, bias, sf, mis, quantum, sat)


def rotation_vector(q) -> tuple:
    """The rotation vector of the unit quaternion q (angle in [0, pi])."""
    if q[3] < 0.0:
        q = (-q[0], -q[1], -q[2], -q[3])
    n = math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2])
    if n < 1e-300:
        return ZERO3
    k = 2.0 * math.atan2(n, q[3]) / n
    return (q[0] * k, q[1] * k, q[2] * k)


@register
class Gyro(Sensor):
    name = "gyro"
    stream_index = 7
    applies_to = (ATTITUDE,)
    keys = (SECTION,)
    value_field, valid_field = "gyro_w", "gyro_valid"
    extra_fields = ("gyro_dtheta",)     # reserved: the value field in angle mode
    truth_field = "w"
    fault_kinds = ("dropout", "nan")

    @classmethod
    def read(cls, sec, ctx):
        g = sec.table(SECTION, required=False)
        return None if g is None else _read(g, ctx)

    def __init__(self, config: GyroConfig, ctx):
        super().__init__(config, ctx)
        c = config
        if c.mode == "angle":
            self.value_field = "gyro_dtheta"
        self.dt = float(ctx.dt)
        self.angle = c.mode == "angle"
        self.sv2, self.su = c.arw * c.arw, c.rrw
        self.stream = NormalStream(ctx.seed, self.name, 1.0, width=6) if (c.arw > 0.0 or c.rrw > 0.0) else None
        self.m = c.matrix
        self.quantum = c.quantum
        self.sat = c.saturation_rad_s
        self.beta = tuple(c.bias_rad_s)
        self.residual = [0.0, 0.0, 0.0]
        self.prev = None                # (t, q) of the last sample's truth
        self.rate_true, self.bias_mean, self.h = ZERO3, self.beta, self.dt
        self.saturated = (False, False, False)
        self.fault_model = None         # injected faults (aocs_plant.faults.gyro), set by faults.attach
        self.t_sample = 0.0

    def source(self, plant):
        body = plant.body
        return lambda: (plant.t, body.q, body.w)

    def measure(self, value):
        t, q, w = value
        prev = self.prev
        if prev is None or t - prev[0] <= 1e-9 * self.dt:
            h, wbar = self.dt, tuple(w)
        else:
            h = t - prev[0]
            p = prev[1]
            dq = (  # q (x) p^-1 (Shuster product, SPEC 1)
                p[3] * q[0] - q[3] * p[0] + (q[1] * p[2] - q[2] * p[1]),
                p[3] * q[1] - q[3] * p[1] + (q[2] * p[0] - q[0] * p[2]),
                p[3] * q[2] - q[3] * p[2] + (q[0] * p[1] - q[1] * p[0]),
                q[3] * p[3] + q[0] * p[0] + q[1] * p[1] + q[2] * p[2])
            d = rotation_vector(dq)
            wbar = (d[0] / h, d[1] / h, d[2] / h)
        self.prev = (t, q)
        b0 = self.beta
        if self.stream is not None:
            x = self.stream.next()
            sn = math.sqrt(self.sv2 / h + self.su * self.su * h / 12.0)
            sb = self.su * math.sqrt(h)
            b1 = (b0[0] + sb * x[3], b0[1] + sb * x[4], b0[2] + sb * x[5])
            n = (sn * x[0], sn * x[1], sn * x[2])
        else:
            b1, n = b0, ZERO3
        self.beta = b1
        bm = (0.5 * (b0[0] + b1[0]), 0.5 * (b0[1] + b1[1]), 0.5 * (b0[2] + b1[2]))
        m = self.m
        y = [m[i][0] * wbar[0] + m[i][1] * wbar[1] + m[i][2] * wbar[2] + bm[i] + n[i] for i in range(3)]
        sat = [False, False, False]
        if self.sat > 0.0:
            for i in range(3):
                if abs(y[i]) > self.sat:
                    y[i] = math.copysign(self.sat, y[i])
                    sat[i] = True
        fm = self.fault_model
        if fm is not None:
            fm.rate(t, y, sat)
            self.t_sample = t
        qn = self.quantum
        if self.angle:
            y = [v * h for v in y]
            if qn > 0.0:
                r = self.residual
                out = []
                for i in range(3):
                    a = r[i] + y[i]
                    o = qn * round(a / qn)
                    r[i] = a - o
                    out.append(o)
                y = out
        elif qn > 0.0:
            y = [qn * round(v / qn) for v in y]
        self.rate_true, self.bias_mean, self.h, self.saturated = wbar, bm, h, tuple(sat)
        if fm is not None:
            return fm.output(t, (y[0], y[1], y[2]))
        return (y[0], y[1], y[2])

    def truth(self) -> dict:
        """Of the last sample: the true mean rate over it (rad/s, B), the true bias at its end and its
        mean over the sample (rad/s), the interval (s), which axes saturated; an injected bias step
        (aocs_plant.faults.gyro) is part of the true bias."""
        beta, bm = self.beta, self.bias_mean
        if self.fault_model is not None:
            d = self.fault_model.bias_step(self.t_sample)
            beta = tuple(a + b for a, b in zip(beta, d))
            bm = tuple(a + b for a, b in zip(bm, d))
        return {"rate_rad_s": self.rate_true, "bias_rad_s": beta, "bias_mean_rad_s": bm,
                "interval_s": self.h, "saturated": self.saturated}
