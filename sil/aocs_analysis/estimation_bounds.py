"""The steady-state attitude knowledge a gyro + star-tracker filter can reach (issue 20; docs/spec.md 5.6).

Per axis, the attitude filter is the two-state (angle, gyro bias) Kalman filter of Farrenkopf (1978),
"Analytic Steady-State Accuracy Solutions for Two Common Spacecraft Attitude Estimators", J. Guidance
and Control 1(4), 282-284; also Markley & Crassidis 2014, "Fundamentals of Spacecraft Attitude
Determination and Control", ch. 6 (their Farrenkopf expressions); docs/spec.md 5.6. Continuous gyro model
w_meas = w + beta + eta_v, beta' = eta_u (spectral densities sigma_v^2, sigma_u^2); an angle measurement
of white noise sigma_n every dt. Over dt the state transition and process noise are exact:

    Phi = [[1, -dt], [0, 1]],
    Q   = [[sigma_v^2 dt + sigma_u^2 dt^3 / 3, -sigma_u^2 dt^2 / 2], [-sigma_u^2 dt^2 / 2, sigma_u^2 dt]],
    H = [1, 0],  R = sigma_n^2.

Closed form (Farrenkopf's result; derived again in docs/spec.md). With
S_v = sigma_v dt^(1/2) / sigma_n and S_u = sigma_u dt^(3/2) / sigma_n,

    y = S_u / 2 + sqrt(4 + S_v^2 + S_u^2 / 12),    x = (y + sqrt(y^2 - 4)) / 2   (x + 1/x = y, x >= 1)
    pre-update angle variance    P_a(-) = sigma_n^2 (x^2 - 1)
    post-update angle variance   P_a(+) = sigma_n^2 (1 - 1 / x^2)
    post-update bias variance    P_b(+) = (sigma_u sigma_n dt^(1/2) (x^2 - 1) / x - sigma_u^2 dt^2 / 2) / dt
    pre-update bias variance     P_b(-) = P_b(+) + sigma_u^2 dt

The same from the discrete algebraic Riccati equation (scipy.linalg.solve_discrete_are), `riccati`.
The three axes decouple for a hold (small rates): the bound of an axis of S uses that axis' star-tracker
noise (cross-boresight on x and y, about-boresight on z). Nothing of the star tracker's bias or
low-frequency error enters: those are not white, and the filter cannot see them.
"""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

ARCSEC_PER_RAD = 206264.80624709636


@dataclass(frozen=True)
class SteadyState:
    """1-sigma steady-state figures of one axis (rad for the angle, rad/s for the bias)."""

    attitude_pre: float      # just before a star-tracker update
    attitude_post: float     # just after it
    bias_pre: float
    bias_post: float
    s_v: float               # Farrenkopf's S_v = sigma_v dt^(1/2) / sigma_n
    s_u: float               # S_u = sigma_u dt^(3/2) / sigma_n

    @property
    def attitude_pre_arcsec(self) -> float:
        return self.attitude_pre * ARCSEC_PER_RAD

    @property
    def attitude_post_arcsec(self) -> float:
        return self.attitude_post * ARCSEC_PER_RAD


def _check(sigma_n, sigma_v, sigma_u, dt):
    if not (sigma_n > 0.0 and dt > 0.0 and sigma_v >= 0.0 and sigma_u >= 0.0):
        raise ValueError(f"need sigma_n > 0, dt > 0, sigma_v >= 0, sigma_u >= 0 (got {sigma_n}, {dt}, {sigma_v}, "
                         f"{sigma_u})")


def process_noise(sigma_v: float, sigma_u: float, dt: float) -> np.ndarray:
    """Q of the (angle, bias) state over dt (exact for the ARW + RRW model)."""
    su2 = sigma_u * sigma_u
    return np.array([[sigma_v * sigma_v * dt + su2 * dt ** 3 / 3.0, -0.5 * su2 * dt * dt],
                     [-0.5 * su2 * dt * dt, su2 * dt]])


def farrenkopf(sigma_n: float, sigma_v: float, sigma_u: float, dt: float) -> SteadyState:
    """Farrenkopf's closed form: sigma_n (rad) the star tracker's noise on this axis, sigma_v (rad/s^0.5)
    the angle random walk, sigma_u (rad/s^1.5) the rate random walk, dt (s) the update interval."""
    _check(sigma_n, sigma_v, sigma_u, dt)
    s_v = sigma_v * math.sqrt(dt) / sigma_n
    s_u = sigma_u * dt ** 1.5 / sigma_n
    y = 0.5 * s_u + math.sqrt(4.0 + s_v * s_v + s_u * s_u / 12.0)
    x = 0.5 * (y + math.sqrt(y * y - 4.0))
    r = sigma_n * sigma_n
    pa_pre = r * (x * x - 1.0)
    pa_post = r * (1.0 - 1.0 / (x * x))
    pb_post = (sigma_u * sigma_n * math.sqrt(dt) * (x * x - 1.0) / x - 0.5 * sigma_u * sigma_u * dt * dt) / dt
    pb_pre = pb_post + sigma_u * sigma_u * dt
    return SteadyState(math.sqrt(pa_pre), math.sqrt(pa_post), math.sqrt(max(pb_pre, 0.0)),
                       math.sqrt(max(pb_post, 0.0)), s_v, s_u)


def _predicted(sigma_n, sigma_v, sigma_u, dt) -> np.ndarray:
    """The steady predicted (pre-update) covariance: the DARE with Phi^T, H^T, Q, R."""
    phi = np.array([[1.0, -dt], [0.0, 1.0]])
    h = np.array([[1.0, 0.0]])
    from scipy.linalg import solve_discrete_are  # deferred: scipy.linalg costs ~0.2 s of every run's start
    return solve_discrete_are(phi.T, h.T, process_noise(sigma_v, sigma_u, dt), np.array([[sigma_n * sigma_n]]))


def riccati(sigma_n: float, sigma_v: float, sigma_u: float, dt: float) -> SteadyState:
    """The same from the discrete algebraic Riccati equation of the filter (sigma_u > 0: with no rate
    random walk the bias becomes known exactly, and the equation has no stabilising solution)."""
    _check(sigma_n, sigma_v, sigma_u, dt)
    if not sigma_u > 0.0:
        raise ValueError("riccati needs sigma_u > 0 (use farrenkopf for sigma_u = 0)")
    pre = _predicted(sigma_n, sigma_v, sigma_u, dt)
    h = np.array([[1.0, 0.0]])
    k = pre @ h.T / (h @ pre @ h.T + sigma_n * sigma_n)
    post = (np.eye(2) - k @ h) @ pre
    return SteadyState(math.sqrt(pre[0, 0]), math.sqrt(post[0, 0]), math.sqrt(pre[1, 1]), math.sqrt(post[1, 1]),
                       sigma_v * math.sqrt(dt) / sigma_n, sigma_u * dt ** 1.5 / sigma_n)


def between_updates(sigma_n: float, sigma_v: float, sigma_u: float, dt: float, n: int) -> float:
    """The rms 1-sigma angle (rad) over the n control periods of one update interval dt (sampled just
    after the update, then every dt / n): what a log sampled at the control rate measures."""
    if n < 1:
        raise ValueError("n must be >= 1")
    _check(sigma_n, sigma_v, sigma_u, dt)
    if sigma_u > 0.0:
        pre = _predicted(sigma_n, sigma_v, sigma_u, dt)
        p = pre - pre[:, :1] @ pre[:1, :] / (pre[0, 0] + sigma_n * sigma_n)
    else:   # sigma_u = 0: the bias known, the post-update covariance diagonal
        p = np.diag([farrenkopf(sigma_n, sigma_v, 0.0, dt).attitude_post ** 2, 0.0])
    total = 0.0
    for j in range(n):
        tau = j * dt / n
        f = np.array([[1.0, -tau], [0.0, 1.0]])
        total += (f @ p @ f.T + process_noise(sigma_v, sigma_u, tau))[0, 0]
    return math.sqrt(total / n)


def steady_state_per_axis(noise_cross_arcsec: float, noise_about_arcsec: float, rate_hz: float,
                          arw_rad_sqrt_s: float, rrw_rad_s_sqrt_s: float, when: str = "post") -> tuple:
    """The analytic 1-sigma knowledge per axis of S (arcsec): x, y from the cross-boresight noise, z from
    the about-boresight noise; `when` "post" (after each update) or "pre" (before it)."""
    if when not in ("pre", "post"):
        raise ValueError(f"when must be 'pre' or 'post', got {when!r}")
    dt = 1.0 / rate_hz
    out = []
    for arcsec in (noise_cross_arcsec, noise_cross_arcsec, noise_about_arcsec):
        ss = farrenkopf(arcsec / ARCSEC_PER_RAD, arw_rad_sqrt_s, rrw_rad_s_sqrt_s, dt)
        out.append((ss.attitude_post_arcsec if when == "post" else ss.attitude_pre_arcsec))
    return tuple(out)
