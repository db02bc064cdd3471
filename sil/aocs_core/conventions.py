"""The attitude conventions of the project (SPEC 1), once in Python.

The C twin is firmware/src/math (quat.c, attitude.c); tests pin the two
against each other (tests/python/aocs_core/test_conventions.py).

Quaternions are 4-tuples, scalar LAST: q = (q1, q2, q3, q4), q4 = cos(phi/2).
A(q) maps N-components to B-components; the product is the Markley-Crassidis
(Shuster) product, so that A(q (x) p) = A(q) A(p) (Markley & Crassidis 2014,
eq. 2.82). Plain floats, not numpy: these run in the plant's hot path.
The `*_rows` forms at the end are the same formulas on (N, 4) / (N, 3)
numpy arrays, for the analysis of whole logs.
"""
from __future__ import annotations

import math

import numpy as np

ARCSEC_PER_RAD = 206264.80624709636  # 180 * 3600 / pi

Vec3 = tuple[float, float, float]
Quat = tuple[float, float, float, float]


def quat_mul(q: Quat, p: Quat) -> Quat:
    """q (x) p = [q4 p_v + p4 q_v - q_v x p_v ; q4 p4 - q_v . p_v] (SPEC 1)."""
    q1, q2, q3, q4 = q
    p1, p2, p3, p4 = p
    return (
        q4 * p1 + p4 * q1 - (q2 * p3 - q3 * p2),
        q4 * p2 + p4 * q2 - (q3 * p1 - q1 * p3),
        q4 * p3 + p4 * q3 - (q1 * p2 - q2 * p1),
        q4 * p4 - (q1 * p1 + q2 * p2 + q3 * p3),
    )


def quat_conj(q: Quat) -> Quat:
    return (-q[0], -q[1], -q[2], q[3])


def quat_norm(q) -> float:
    return math.sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3])


def quat_normalize(q) -> Quat:
    n = quat_norm(q)
    if not (n > 0.0) or not math.isfinite(n):
        raise ValueError(f"quaternion {q!r} cannot be normalised")
    return (q[0] / n, q[1] / n, q[2] / n, q[3] / n)


def quat_to_dcm(q: Quat) -> tuple[Vec3, Vec3, Vec3]:
    """A(q) = (q4^2 - |v|^2) I + 2 v v^T - 2 q4 [v x] (Markley & Crassidis eq. 2.125)."""
    q1, q2, q3, q4 = q
    s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
    return (
        (s + 2 * q1 * q1, 2 * (q1 * q2 + q3 * q4), 2 * (q1 * q3 - q2 * q4)),
        (2 * (q2 * q1 - q3 * q4), s + 2 * q2 * q2, 2 * (q2 * q3 + q1 * q4)),
        (2 * (q3 * q1 + q2 * q4), 2 * (q3 * q2 - q1 * q4), s + 2 * q3 * q3),
    )


def quat_rotate(q: Quat, d) -> Vec3:
    """A(q) d: the N-vector d in B components."""
    q1, q2, q3, q4 = q
    d1, d2, d3 = d
    s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
    vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
    c = 2.0 * q4
    return (
        s * d1 + vd * q1 - c * (q2 * d3 - q3 * d2),
        s * d2 + vd * q2 - c * (q3 * d1 - q1 * d3),
        s * d3 + vd * q3 - c * (q1 * d2 - q2 * d1),
    )


def quat_from_axis_angle(axis, angle: float) -> Quat:
    s = math.sin(0.5 * angle)
    return (axis[0] * s, axis[1] * s, axis[2] * s, math.cos(0.5 * angle))


def quat_from_rotvec(v) -> Quat:
    """Quaternion of the rotation by |v| about v/|v| (identity for v = 0)."""
    a = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2])
    if a < 1e-300:
        return (0.0, 0.0, 0.0, 1.0)
    return quat_from_axis_angle((v[0] / a, v[1] / a, v[2] / a), a)


def euler321_to_quat(yaw: float, pitch: float, roll: float) -> Quat:
    """3-2-1 sequence (SPEC 1): A = A1(roll) A2(pitch) A3(yaw), so q = q1 (x) q2 (x) q3."""
    qz = quat_from_axis_angle((0.0, 0.0, 1.0), yaw)
    qy = quat_from_axis_angle((0.0, 1.0, 0.0), pitch)
    qx = quat_from_axis_angle((1.0, 0.0, 0.0), roll)
    return quat_mul(qx, quat_mul(qy, qz))


def euler321_deg_to_quat(angles_deg) -> Quat:
    """angles_deg = [yaw psi, pitch theta, roll phi] in degrees (scenario files)."""
    yaw, pitch, roll = (math.radians(a) for a in angles_deg)
    return euler321_to_quat(yaw, pitch, roll)


def quat_to_euler321(q: Quat) -> Vec3:
    """(yaw, pitch, roll) in rad from A(q) = A1(roll) A2(pitch) A3(yaw)."""
    a = quat_to_dcm(q)
    yaw = math.atan2(a[0][1], a[0][0])
    pitch = -math.asin(max(-1.0, min(1.0, a[0][2])))
    roll = math.atan2(a[1][2], a[2][2])
    return (yaw, pitch, roll)


def crp_to_quat(rho) -> Quat:
    """q = [rho; 1] / sqrt(1 + |rho|^2) (SPEC 4, rtc scenarios). Where |rho|^2 would overflow
    (|rho| near 1e154 and beyond: within 1e-154 rad of 180 deg) the same vector is normalised
    scaled by its largest component, so q stays unit and finite (q4 -> 0)."""
    ss = rho[0] * rho[0] + rho[1] * rho[1] + rho[2] * rho[2]
    if ss < 1e300:
        d = math.sqrt(1.0 + ss)
        return (rho[0] / d, rho[1] / d, rho[2] / d, 1.0 / d)
    m = max(abs(rho[0]), abs(rho[1]), abs(rho[2]))
    v = (rho[0] / m, rho[1] / m, rho[2] / m, 1.0 / m)
    n = math.sqrt(v[0] * v[0] + v[1] * v[1] + v[2] * v[2] + v[3] * v[3])
    return (v[0] / n, v[1] / n, v[2] / n, v[3] / n)


def mrp_to_quat(sigma) -> Quat:
    """q = [2 sigma; 1 - s.s] / (1 + s.s) (inverse of sigma = q_vec / (1 + q4)). Where s.s would
    overflow, the shadow set -sigma / s.s (the same attitude, SPEC 1) is converted instead."""
    ss = sigma[0] * sigma[0] + sigma[1] * sigma[1] + sigma[2] * sigma[2]
    if not ss < 1e300:
        m = max(abs(sigma[0]), abs(sigma[1]), abs(sigma[2]))
        u = (sigma[0] / m, sigma[1] / m, sigma[2] / m)
        k = -1.0 / (m * (u[0] * u[0] + u[1] * u[1] + u[2] * u[2]))   # -sigma / s.s without forming s.s
        sigma = (u[0] * k, u[1] * k, u[2] * k)
        ss = sigma[0] * sigma[0] + sigma[1] * sigma[1] + sigma[2] * sigma[2]
    d = 1.0 + ss
    return (2 * sigma[0] / d, 2 * sigma[1] / d, 2 * sigma[2] / d, (1.0 - ss) / d)


def quat_to_crp(q: Quat) -> Vec3:
    """rho = q_vec / q4 of the short-rotation representative; inf components at q4 = 0."""
    q4 = q[3]
    if q4 == 0.0:
        return (math.copysign(math.inf, q[0]) if q[0] else 0.0,
                math.copysign(math.inf, q[1]) if q[1] else 0.0,
                math.copysign(math.inf, q[2]) if q[2] else 0.0)
    return (q[0] / q4, q[1] / q4, q[2] / q4)


def quat_to_mrp(q: Quat) -> Vec3:
    """sigma = q_vec / (1 + q4) with q4 >= 0 chosen, so |sigma| <= 1 (SPEC 1 shadow set)."""
    if q[3] < 0.0:
        q = (-q[0], -q[1], -q[2], -q[3])
    d = 1.0 + q[3]
    return (q[0] / d, q[1] / d, q[2] / d)


def quat_error(q: Quat, qd: Quat) -> Quat:
    """qe = q (x) qd^-1 (SPEC 1)."""
    return quat_mul(q, quat_conj(qd))


def pointing_error_rad(q: Quat, qd: Quat) -> float:
    """True pointing angle 2 asin(|qe_vec|) in rad, in [0, pi] (SPEC 1)."""
    e = quat_error(q, qd)
    n = math.sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2])
    return 2.0 * math.asin(min(1.0, n))


def pointing_error_arcsec(q: Quat, qd: Quat) -> float:
    return pointing_error_rad(q, qd) * ARCSEC_PER_RAD


def qe_arcsec(q: Quat, qd: Quat) -> Vec3:
    """|qe_i| in arcsec, the IRASSI report's figure (half the per-axis angle, SPEC 1)."""
    e = quat_error(q, qd)
    return (abs(e[0]) * ARCSEC_PER_RAD, abs(e[1]) * ARCSEC_PER_RAD, abs(e[2]) * ARCSEC_PER_RAD)


# --------------------------------------------------------------------------- numpy row forms (logs)
def quat_mul_rows(q, p):
    """Shuster product q (x) p, row-wise for (..., 4) arrays (SPEC 1; same formula as quat_mul)."""
    qv, q4 = q[..., :3], q[..., 3:4]
    pv, p4 = p[..., :3], p[..., 3:4]
    vec = q4 * pv + p4 * qv - np.cross(qv, pv)
    sca = q4 * p4 - np.sum(qv * pv, axis=-1, keepdims=True)
    return np.concatenate([vec, sca], axis=-1)


def quat_conj_rows(q):
    """Conjugate (inverse of a unit quaternion), row-wise."""
    out = np.array(q, dtype=float, copy=True)
    out[..., :3] *= -1.0
    return out


def quat_error_rows(q, qd):
    """qe = q (x) qd^-1 row-wise, sign chosen so qe4 >= 0 (short rotation; SPEC 1)."""
    qe = quat_mul_rows(np.asarray(q, float), quat_conj_rows(np.broadcast_to(qd, np.shape(q))))
    sign = np.where(qe[..., 3:4] < 0.0, -1.0, 1.0)
    return qe * sign


def quat_from_rotvec_rows(v):
    """[e sin(|v|/2); cos(|v|/2)] row-wise, exact at |v| = 0 (same as quat_from_rotvec)."""
    v = np.asarray(v, float)
    ang = np.linalg.norm(v, axis=-1, keepdims=True)
    half = 0.5 * ang
    # sin(|v|/2)/|v| -> 1/2 as |v| -> 0
    k = np.where(ang > 1e-300, np.sin(half) / np.where(ang > 1e-300, ang, 1.0), 0.5)
    return np.concatenate([v * k, np.cos(half)], axis=-1)
