"""Transients of the attitude filter: convergence from a wrong start and recovery after a star-tracker outage
(issue 20; docs/spec.md 5.7, "Convergence and outages").

Both are judged on the knowledge error's trailing rms per axis of S (the star tracker's frame, where the
filter's axes decouple in a hold: x, y see the cross-boresight noise, z the about-boresight one),

    r_i(t) = sqrt( mean of dth_S,i^2 over the samples in (t - W, t] ),   W = 30 s by default,

against k times the steady-state rms per axis, `bound_S` (estimation_bounds.between_updates: the rms a
control-rate log has over an update interval). An rms over W rather than single samples: a consistent
filter's error exceeds 3 sigma at 0.27 % of its samples, which says nothing about convergence; and W = 30 s
because the about-boresight error decorrelates in about 9 s (the hold's 8 arcsec axis), so that one run's
rms over a shorter window scatters too much about its expectation to say "for good".

The predicted convergence time comes from the filter's own equations, not from a run: per axis of S the
two-state (angle, bias) Kalman filter of estimation_bounds (Farrenkopf's model, the MEKF's error dynamics
in a hold), started at P0 = diag(sigma_a0^2, sigma_b0^2) with the run's initial errors e0 = (dth_0, db_0),
stepped at the control period with an update every n steps:

    gains   K_k from the Riccati recursion of P (the filter's own),
    mean    m_k = E[e_k]:   m^- = Phi m,  m^+ = (I - K H) m^-            (the initial error, decaying)
    noise   N_k:            N^- = Phi N Phi^T + Q,  N^+ = (I - K H) N^- (I - K H)^T + K R K^T,  N_0 = 0,

so that E[e_k e_k^T] = m m^T + N (Joseph form: exact for any gain). The predicted r_i(t) is the root of the
mean of m_angle^2 + N_angle over the window. The STATED convergence time is the first t from which it stays
within PREDICTION_K = 1.5 times bound_S,i on every axis: half the 3 x of the rule, a factor 2 left for one
run's rms scattering about its expectation (the firmware test flies 8 runs against it; Gelb 1974, "Applied
Optimal Estimation", ch. 7, for the error covariance of a filter given its gains).
"""
from __future__ import annotations

import math

import numpy as np

from aocs_core.conventions import ARCSEC_PER_RAD, quat_to_dcm

from .estimation_bounds import between_updates, farrenkopf, process_noise

WINDOW_S = 30.0          # W: the trailing rms window, s (the about-boresight error decorrelates in ~9 s)
PREDICTION_K = 1.5       # the stated time: the expected rms inside this times the steady state (half the 3 x rule)


def to_tracker_frame(x_B, mounting_q) -> np.ndarray:
    """(n, 3) vectors in B -> S: A(q_SB) x."""
    a = np.asarray(quat_to_dcm(tuple(mounting_q)), float)
    return np.asarray(x_B, float) @ a.T


def trailing_rms(t_s, x, window_s: float = WINDOW_S) -> np.ndarray:
    """r(t_k) (n, m): the rms of each column of x over the samples with t in (t_k - window_s, t_k]; NaN
    samples left out (NaN where none)."""
    t = np.asarray(t_s, float)
    x = np.asarray(x, float)
    x2 = np.where(np.isfinite(x), x * x, 0.0)
    cnt = np.isfinite(x).astype(float)
    c2 = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(x2, axis=0)])
    cc = np.vstack([np.zeros((1, x.shape[1])), np.cumsum(cnt, axis=0)])
    lo = np.searchsorted(t, t - window_s, side="right")
    hi = np.arange(1, t.size + 1)
    with np.errstate(invalid="ignore", divide="ignore"):
        return np.sqrt((c2[hi] - c2[lo]) / (cc[hi] - cc[lo]))


def time_inside_for_good(t_s, r, limit, start_s: float | None = None, end_s: float | None = None) -> float | None:
    """The first time t in [start_s, end_s] from which every column of r stays <= its limit up to end_s;
    None when the last sample of that span is outside (or there is none)."""
    t = np.asarray(t_s, float)
    sel = np.ones(t.size, bool)
    if start_s is not None:
        sel &= t >= start_s
    if end_s is not None:
        sel &= t <= end_s
    idx = np.flatnonzero(sel)
    if idx.size == 0:
        return None
    inside = np.all(np.asarray(r, float)[idx] <= np.asarray(limit, float), axis=1)
    if not inside[-1]:
        return None
    out = np.flatnonzero(~inside)
    return float(t[idx[0]]) if out.size == 0 else float(t[idx[out[-1] + 1]])


def control_steps_per_update(sensors, control_rate_hz: float) -> int:
    """n: the control periods between two star-tracker updates (at least one; the loader holds the tracker's
    rate at or below the control rate)."""
    return max(1, int(round(control_rate_hz / sensors.rate_hz)))


def steady_rms_S_arcsec(sensors, control_rate_hz: float) -> np.ndarray:
    """bound_S: the steady-state rms per axis of S of a control-rate log (estimation_bounds.between_updates)."""
    s = sensors
    n = control_steps_per_update(s, control_rate_hz)
    per = (s.noise_cross_arcsec, s.noise_cross_arcsec, s.noise_about_arcsec)
    return np.array([between_updates(a / ARCSEC_PER_RAD, s.arw_rad_sqrt_s, s.rrw_rad_s_sqrt_s, 1.0 / s.rate_hz, n)
                     for a in per]) * ARCSEC_PER_RAD


def predicted_rms_history(sigma_n: float, sigma_v: float, sigma_u: float, dt_control: float, n_update: int,
                          p0_att: float, p0_bias: float, e0_att: float, e0_bias: float, steps: int) -> np.ndarray:
    """E[dth^2]^(1/2) (rad) of one axis at the control steps 0 .. steps-1 (module docstring): the filter
    starts at step 0 with P0 = diag(p0_att^2, p0_bias^2) and the error (e0_att rad, e0_bias rad/s, truth
    minus estimate), takes an update at step 0 and every n_update steps, and propagates dt_control between
    steps."""
    phi = np.array([[1.0, -dt_control], [0.0, 1.0]])
    q = process_noise(sigma_v, sigma_u, dt_control)
    h = np.array([[1.0, 0.0]])
    r = sigma_n * sigma_n
    p = np.diag([p0_att * p0_att, p0_bias * p0_bias])
    m = np.array([e0_att, e0_bias])
    nn = np.zeros((2, 2))
    out = np.empty(steps)
    for k in range(steps):
        if k > 0:
            p = phi @ p @ phi.T + q
            m = phi @ m
            nn = phi @ nn @ phi.T + q
        if k % n_update == 0:
            kg = p @ h.T / (p[0, 0] + r)
            a = np.eye(2) - kg @ h
            p = a @ p @ a.T + r * (kg @ kg.T)
            m = a @ m
            nn = a @ nn @ a.T + r * (kg @ kg.T)
        out[k] = math.sqrt(m[0] * m[0] + nn[0, 0])
    return out


def predicted_convergence(sensors, control_rate_hz: float, p0_att_rad: float, p0_bias_radps: float,
                          e0_att_B_rad, e0_bias_B_radps, duration_s: float, k: float = 3.0,
                          window_s: float = WINDOW_S) -> dict:
    """The predicted convergence (module docstring): {"time_s", "rms_S_arcsec" (steps, 3), "t_s",
    "bound_S_arcsec", "k"}; time_s None when the prediction does not enter within duration_s."""
    s = sensors
    dt = 1.0 / control_rate_hz
    n = control_steps_per_update(s, control_rate_hz)
    steps = int(round(duration_s * control_rate_hz))
    e_att = to_tracker_frame(np.asarray(e0_att_B_rad, float)[None, :], s.mounting_q)[0]
    e_b = to_tracker_frame(np.asarray(e0_bias_B_radps, float)[None, :], s.mounting_q)[0]
    per = (s.noise_cross_arcsec, s.noise_cross_arcsec, s.noise_about_arcsec)
    rms2 = np.column_stack([
        predicted_rms_history(per[i] / ARCSEC_PER_RAD, s.arw_rad_sqrt_s, s.rrw_rad_s_sqrt_s, dt, n, p0_att_rad,
                              p0_bias_radps, e_att[i], e_b[i], steps) ** 2 for i in range(3)])
    t = np.arange(steps) * dt
    # the window mean of the expected squares (a window holds round(window_s / dt) samples)
    w = max(1, int(round(window_s / dt)))
    c = np.vstack([np.zeros((1, 3)), np.cumsum(rms2, axis=0)])
    lo = np.maximum(np.arange(1, steps + 1) - w, 0)
    r = np.sqrt((c[1:] - c[lo]) / (np.arange(1, steps + 1) - lo)[:, None]) * ARCSEC_PER_RAD
    bound = steady_rms_S_arcsec(s, control_rate_hz)
    return {"time_s": time_inside_for_good(t, r, k * bound), "rms_S_arcsec": r, "t_s": t,
            "bound_S_arcsec": bound, "k": k}


def convergence(t_s, dth_B_rad, sensors, control_rate_hz: float, k: float = 3.0, window_s: float = WINDOW_S,
                valid=None) -> dict:
    """The measured convergence: the first time from which the trailing rms of every axis of S stays
    within k bound_S (invalid samples left out of the rms): {"time_s", "k", "window_s", "bound_S_arcsec",
    "frame"}."""
    e = to_tracker_frame(dth_B_rad, sensors.mounting_q) * ARCSEC_PER_RAD
    if valid is not None:
        e = np.where(np.asarray(valid, bool)[:, None], e, np.nan)
    bound = steady_rms_S_arcsec(sensors, control_rate_hz)
    r = trailing_rms(t_s, e, window_s)
    r = np.where(np.isfinite(r), r, np.inf)
    return {"time_s": time_inside_for_good(t_s, r, k * bound), "k": k, "window_s": window_s,
            "bound_S_arcsec": [float(b) for b in bound], "frame": "S"}


def sigma_S_rad(p_att_B, mounting_q) -> np.ndarray:
    """(n, 3) the filter's 1-sigma per axis of S from its attitude covariance in B (n, 3, 3): sqrt(diag(A P A^T))."""
    a = np.asarray(quat_to_dcm(tuple(mounting_q)), float)
    p = np.asarray(p_att_B, float)
    with np.errstate(invalid="ignore"):
        return np.sqrt(np.einsum("ij,njk,ik->ni", a, p, a))


def outage_report(t_s, dth_B_rad, p_att_B, outages, sensors, control_rate_hz: float, k_error: float = 3.0,
                  k_sigma: float = 1.1, window_s: float = WINDOW_S, after_s: float = 60.0, rms_span_s: float = 200.0,
                  valid=None) -> list[dict]:
    """Per star-tracker outage [start_s, end_s) inside the run (axes of S, sigma the filter's own):

    - during it: the largest |dth_i| / (3 sigma_i), the fraction of (sample, axis) pairs inside 3 sigma,
      the 3 sigma reached at its end (arcsec);
    - the recovery time, from end_s: the first time from which, up to the next outage or the end of the run,
      (a) the filter's sigma_i is within k_sigma of the steady state before an update (Farrenkopf, `pre`:
      the largest of an update cycle) and (b) the trailing rms of dth_i over window_s (the samples since
      end_s only) within k_error times the steady-state rms bound_S (the convergence rule); None when
      never;
    - `rms_over_bound`: the rms per axis of dth over [end_s + after_s, end_s + after_s + rms_span_s] (cut at
      the next outage or the end) divided by bound_S: the steady state regained, about 1."""
    t = np.asarray(t_s, float)
    ok = np.ones(t.size, bool) if valid is None else np.asarray(valid, bool)
    e_S = np.where(ok[:, None], to_tracker_frame(dth_B_rad, sensors.mounting_q), np.nan)
    sig = sigma_S_rad(p_att_B, sensors.mounting_q)
    bound = steady_rms_S_arcsec(sensors, control_rate_hz)
    per = (sensors.noise_cross_arcsec, sensors.noise_cross_arcsec, sensors.noise_about_arcsec)
    pre = np.array([farrenkopf(a / ARCSEC_PER_RAD, sensors.arw_rad_sqrt_s, sensors.rrw_rad_s_sqrt_s,
                               1.0 / sensors.rate_hz).attitude_pre for a in per])
    starts = sorted(float(a) for a, _ in outages)
    out = []
    for a, b in sorted((float(a), float(b)) for a, b in outages):
        during = (t >= a) & (t < b) & ok
        if not np.any(during) or t[-1] < b:
            continue
        with np.errstate(invalid="ignore", divide="ignore"):
            ratio = np.abs(e_S[during]) / (3.0 * sig[during])
        nxt = [x for x in starts if x > a]
        end = (nxt[0] - 1e-9) if nxt else float(t[-1])
        since = (t >= b)[:, None]
        r = trailing_rms(t, np.where(since, e_S * ARCSEC_PER_RAD, np.nan), window_s)
        r = np.where(np.isfinite(r), r, np.inf)
        s_ok = np.where(np.isfinite(sig), sig, np.inf) <= k_sigma * pre
        both = np.where(s_ok, r, np.inf)
        rec = time_inside_for_good(t, both, k_error * bound, start_s=b, end_s=end)
        span = ok & (t >= b + after_s) & (t <= min(end, b + after_s + rms_span_s))
        rms = np.sqrt(np.mean(e_S[span] ** 2, axis=0)) * ARCSEC_PER_RAD if np.any(span) else np.full(3, np.nan)
        last = np.flatnonzero(during)[-1]
        out.append({"start_s": a, "end_s": b, "frame": "S",
                    "max_ratio_to_3sigma": float(np.nanmax(ratio)),
                    "max_ratio_to_3sigma_per_axis": [float(v) for v in np.nanmax(ratio, axis=0)],
                    "inside_3sigma_fraction": float(np.mean(ratio <= 1.0)),
                    "three_sigma_at_end_arcsec": [float(v) for v in 3.0 * sig[last] * ARCSEC_PER_RAD],
                    "recovery_time_s": None if rec is None else rec - b,
                    "recovery_rule": {"k_error": k_error, "k_sigma": k_sigma, "window_s": window_s},
                    "rms_over_bound": [float(v) for v in rms / bound],
                    "rms_span_s": [b + after_s, float(min(end, b + after_s + rms_span_s))],
                    "bound_S_arcsec": [float(v) for v in bound]})
    return out
