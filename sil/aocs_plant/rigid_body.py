"""Rigid-body attitude dynamics, fixed-step RK4 on plain Python floats.

    J wdot = -w x (J w) + u + u_d            (SPEC 1.6, full inertia J)
    qdot   = 0.5 Xi(q) w                     (SPEC 1.2, scalar-last quaternion)

The hot path works on tuples and local variables: numpy on 3-vectors costs
~15x more per step (TOOLCHAIN-NOTES "Plant integration cost"). The right-hand
side is a closure built once per inertia (body_derivative): the inertia
entries are closure constants and a diagonal J takes the variant without its
zero products; it calls at most one attitude-only torque closure (the
effectors of Form.ATTITUDE, summed into one by sum_terms). rk4_stepper() wraps
it into one RK4 step with the torque held; rk4_coupled_stepper() into one RK4
over [q, w, effector states] when effectors have state (Form.GENERAL). The
quaternion is renormalised after every step. Nothing is generated as source. reference_propagate()
integrates the same equations with scipy's adaptive DOP853 (rtol 1e-12) to
measure the RK4 integration error; it is never used to run a scenario.
"""
from __future__ import annotations

import functools
import math

import numpy as np

from aocs_core.conventions import quat_to_dcm


def _mat9(m) -> tuple:
    a = np.asarray(m, dtype=float)
    if a.shape != (3, 3):
        raise ValueError("inertia must be 3x3")
    return tuple(a.ravel().tolist())


def _is_diagonal(m) -> bool:
    return m[1] == 0.0 and m[2] == 0.0 and m[3] == 0.0 and m[5] == 0.0 and m[6] == 0.0 and m[7] == 0.0


def sum_terms(terms):
    """One closure (q1, q2, q3, q4) -> torque for a list of them (None when the list is empty)."""
    terms = tuple(terms)
    if not terms:
        return None
    if len(terms) == 1:
        return terms[0]

    def total(q1, q2, q3, q4):
        x = y = z = 0.0
        for g in terms:
            a, b, c = g(q1, q2, q3, q4)
            x += a
            y += b
            z += c
        return (x, y, z)
    return total


def body_derivative(J, Ji, term=None):
    """f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz) -> (qdot, wdot) as one 7-tuple.

    J, Ji: row-major 9-tuples of the inertia and its inverse; (tx, ty, tz) the
    torque held over the step; term: None or a closure (q1, q2, q3, q4) -> torque
    added at every evaluation (gravity gradient). The variant is chosen here,
    once: the diagonal one skips the products by exact zeros (same result).
    """
    j0, j1, j2, j3, j4, j5, j6, j7, j8 = J
    i0, i1, i2, i3, i4, i5, i6, i7, i8 = Ji
    g = term
    if _is_diagonal(J) and _is_diagonal(Ji):
        if g is None:
            def f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz):
                hx = j0 * w1
                hy = j4 * w2
                hz = j8 * w3
                mx = tx - (w2 * hz - w3 * hy)
                my = ty - (w3 * hx - w1 * hz)
                mz = tz - (w1 * hy - w2 * hx)
                return (0.5 * (q4 * w1 - q3 * w2 + q2 * w3), 0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
                        0.5 * (-q2 * w1 + q1 * w2 + q4 * w3), -0.5 * (q1 * w1 + q2 * w2 + q3 * w3),
                        i0 * mx, i4 * my, i8 * mz)
        else:
            def f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz):
                hx = j0 * w1
                hy = j4 * w2
                hz = j8 * w3
                gx, gy, gz = g(q1, q2, q3, q4)
                mx = tx - (w2 * hz - w3 * hy) + gx
                my = ty - (w3 * hx - w1 * hz) + gy
                mz = tz - (w1 * hy - w2 * hx) + gz
                return (0.5 * (q4 * w1 - q3 * w2 + q2 * w3), 0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
                        0.5 * (-q2 * w1 + q1 * w2 + q4 * w3), -0.5 * (q1 * w1 + q2 * w2 + q3 * w3),
                        i0 * mx, i4 * my, i8 * mz)
    elif g is None:
        def f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz):
            hx = j0 * w1 + j1 * w2 + j2 * w3
            hy = j3 * w1 + j4 * w2 + j5 * w3
            hz = j6 * w1 + j7 * w2 + j8 * w3
            mx = tx - (w2 * hz - w3 * hy)
            my = ty - (w3 * hx - w1 * hz)
            mz = tz - (w1 * hy - w2 * hx)
            return (0.5 * (q4 * w1 - q3 * w2 + q2 * w3), 0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
                    0.5 * (-q2 * w1 + q1 * w2 + q4 * w3), -0.5 * (q1 * w1 + q2 * w2 + q3 * w3),
                    i0 * mx + i1 * my + i2 * mz, i3 * mx + i4 * my + i5 * mz, i6 * mx + i7 * my + i8 * mz)
    else:
        def f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz):
            hx = j0 * w1 + j1 * w2 + j2 * w3
            hy = j3 * w1 + j4 * w2 + j5 * w3
            hz = j6 * w1 + j7 * w2 + j8 * w3
            gx, gy, gz = g(q1, q2, q3, q4)
            mx = tx - (w2 * hz - w3 * hy) + gx
            my = ty - (w3 * hx - w1 * hz) + gy
            mz = tz - (w1 * hy - w2 * hx) + gz
            return (0.5 * (q4 * w1 - q3 * w2 + q2 * w3), 0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
                    0.5 * (-q2 * w1 + q1 * w2 + q4 * w3), -0.5 * (q1 * w1 + q2 * w2 + q3 * w3),
                    i0 * mx + i1 * my + i2 * mz, i3 * mx + i4 * my + i5 * mz, i6 * mx + i7 * my + i8 * mz)
    return f


def rk4_stepper(f):
    """step(q, w, h, torque) -> (q, w): one RK4 step of f with the torque held, q renormalised."""
    sqrt = math.sqrt

    def step(q, w, h, torque):
        tx, ty, tz = torque
        q1, q2, q3, q4 = q
        w1, w2, w3 = w
        hh = 0.5 * h
        a0, a1, a2, a3, a4, a5, a6 = f(q1, q2, q3, q4, w1, w2, w3, tx, ty, tz)
        b0, b1, b2, b3, b4, b5, b6 = f(q1 + hh * a0, q2 + hh * a1, q3 + hh * a2, q4 + hh * a3,
                                       w1 + hh * a4, w2 + hh * a5, w3 + hh * a6, tx, ty, tz)
        c0, c1, c2, c3, c4, c5, c6 = f(q1 + hh * b0, q2 + hh * b1, q3 + hh * b2, q4 + hh * b3,
                                       w1 + hh * b4, w2 + hh * b5, w3 + hh * b6, tx, ty, tz)
        d0, d1, d2, d3, d4, d5, d6 = f(q1 + h * c0, q2 + h * c1, q3 + h * c2, q4 + h * c3,
                                       w1 + h * c4, w2 + h * c5, w3 + h * c6, tx, ty, tz)
        h6 = h / 6.0
        q1 += h6 * (a0 + 2.0 * (b0 + c0) + d0)
        q2 += h6 * (a1 + 2.0 * (b1 + c1) + d1)
        q3 += h6 * (a2 + 2.0 * (b2 + c2) + d2)
        q4 += h6 * (a3 + 2.0 * (b3 + c3) + d3)
        w1 += h6 * (a4 + 2.0 * (b4 + c4) + d4)
        w2 += h6 * (a5 + 2.0 * (b5 + c5) + d5)
        w3 += h6 * (a6 + 2.0 * (b6 + c6) + d6)
        n = 1.0 / sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
        return (q1 * n, q2 * n, q3 * n, q4 * n), (w1, w2, w3)
    return step


def rk4_coupled_stepper(f, G):
    """step(q, w, x, t, h, torque) -> (q, w, x): one RK4 over the concatenated state [q, w, x].

    x: the effector states (a tuple); G(t, body, x) -> ((ex, ey, ez), xdot): the effectors' torque,
    added to the held one, and their state derivative at the stage, body = (q1..q4, w1..w3). The
    same stage arithmetic and weights as rk4_stepper and integrator.rk4 (so with G adding zero the
    body part is rk4_stepper's, bit for bit); q renormalised at the end.
    """
    sqrt = math.sqrt

    def step(q, w, x, t, h, torque):
        tx, ty, tz = torque
        q1, q2, q3, q4 = q
        w1, w2, w3 = w
        hh = 0.5 * h
        (ex, ey, ez), ka = G(t, (q1, q2, q3, q4, w1, w2, w3), x)
        a0, a1, a2, a3, a4, a5, a6 = f(q1, q2, q3, q4, w1, w2, w3, tx + ex, ty + ey, tz + ez)
        s1, s2, s3, s4 = q1 + hh * a0, q2 + hh * a1, q3 + hh * a2, q4 + hh * a3
        v1, v2, v3 = w1 + hh * a4, w2 + hh * a5, w3 + hh * a6
        (ex, ey, ez), kb = G(t + hh, (s1, s2, s3, s4, v1, v2, v3), tuple([v + hh * k for v, k in zip(x, ka)]))
        b0, b1, b2, b3, b4, b5, b6 = f(s1, s2, s3, s4, v1, v2, v3, tx + ex, ty + ey, tz + ez)
        s1, s2, s3, s4 = q1 + hh * b0, q2 + hh * b1, q3 + hh * b2, q4 + hh * b3
        v1, v2, v3 = w1 + hh * b4, w2 + hh * b5, w3 + hh * b6
        (ex, ey, ez), kc = G(t + hh, (s1, s2, s3, s4, v1, v2, v3), tuple([v + hh * k for v, k in zip(x, kb)]))
        c0, c1, c2, c3, c4, c5, c6 = f(s1, s2, s3, s4, v1, v2, v3, tx + ex, ty + ey, tz + ez)
        s1, s2, s3, s4 = q1 + h * c0, q2 + h * c1, q3 + h * c2, q4 + h * c3
        v1, v2, v3 = w1 + h * c4, w2 + h * c5, w3 + h * c6
        (ex, ey, ez), kd = G(t + h, (s1, s2, s3, s4, v1, v2, v3), tuple([v + h * k for v, k in zip(x, kc)]))
        d0, d1, d2, d3, d4, d5, d6 = f(s1, s2, s3, s4, v1, v2, v3, tx + ex, ty + ey, tz + ez)
        h6 = h / 6.0
        q1 += h6 * (a0 + 2.0 * (b0 + c0) + d0)
        q2 += h6 * (a1 + 2.0 * (b1 + c1) + d1)
        q3 += h6 * (a2 + 2.0 * (b2 + c2) + d2)
        q4 += h6 * (a3 + 2.0 * (b3 + c3) + d3)
        w1 += h6 * (a4 + 2.0 * (b4 + c4) + d4)
        w2 += h6 * (a5 + 2.0 * (b5 + c5) + d5)
        w3 += h6 * (a6 + 2.0 * (b6 + c6) + d6)
        x = tuple([v + h6 * (k1 + 2.0 * (k2 + k3) + k4) for v, k1, k2, k3, k4 in zip(x, ka, kb, kc, kd)])
        n = 1.0 / sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
        return (q1 * n, q2 * n, q3 * n, q4 * n), (w1, w2, w3), x
    return step


def rk4_step(q, w, h, torque, J, Ji, term=None):
    """One RK4 step of length h with constant external torque (3-tuple) and an optional
    attitude-only torque closure; J, Ji row-major 9-tuples. Returns (q, w), q renormalised."""
    if term is not None:
        return rk4_stepper(body_derivative(J, Ji, term))(q, w, h, torque)
    return _stepper(tuple(J), tuple(Ji))(q, w, h, torque)


@functools.lru_cache(maxsize=64)
def _stepper(J: tuple, Ji: tuple):
    return rk4_stepper(body_derivative(J, Ji))


class RigidBody:
    """State (q, w) of one rigid body with full inertia J (kg m^2)."""

    def __init__(self, inertia, q0, w0):
        self.J = _mat9(inertia)
        self.Ji = tuple(np.linalg.inv(np.asarray(inertia, dtype=float)).ravel().tolist())
        self.q = tuple(float(x) for x in q0)
        self.w = tuple(float(x) for x in w0)

    def derivative(self, q, w, torque):
        """(qdot, wdot) for external torque u + u_d (tuples); for tests and tools."""
        d = body_derivative(self.J, self.Ji)(*q, *w, *torque)
        return d[:4], d[4:]

    def propagate(self, duration, substeps, torque=(0.0, 0.0, 0.0), term=None):
        """Advance by `duration` with `substeps` RK4 steps, a constant torque and an optional
        attitude-only torque closure (q1, q2, q3, q4) -> torque."""
        h = duration / substeps
        q, w = self.q, self.w
        step = rk4_stepper(body_derivative(self.J, self.Ji, term))
        for _ in range(substeps):
            q, w = step(q, w, h, torque)
        self.q, self.w = q, w

    def kinetic_energy(self) -> float:
        w = self.w
        j = self.J
        return 0.5 * sum(w[r] * (j[3 * r] * w[0] + j[3 * r + 1] * w[1] + j[3 * r + 2] * w[2])
                         for r in range(3))

    def momentum_inertial(self):
        """H_N = A(q)^T J w (conserved without external torque)."""
        a = np.array(quat_to_dcm(self.q))
        return a.T @ (np.array(self.J).reshape(3, 3) @ np.array(self.w))


def reference_propagate(inertia, q0, w0, duration, torque=(0.0, 0.0, 0.0), term=None,
                        rtol=1e-12, atol=1e-13):
    """Adaptive high-order reference (scipy DOP853) of the same equations.

    Used only to measure the fixed-step integration error. term: an optional
    attitude-only torque closure (q1, q2, q3, q4) -> torque. Returns (q, w) as
    numpy arrays with q normalised (sign as integrated).
    """
    from scipy.integrate import solve_ivp  # deferred: scipy only for this reference integrator, not the hot path

    body = RigidBody(inertia, q0, w0)
    f = body_derivative(body.J, body.Ji, term)
    tx, ty, tz = torque

    def rhs(_t, y):
        return list(f(*(float(v) for v in y), tx, ty, tz))

    y0 = list(q0) + list(w0)
    sol = solve_ivp(rhs, (0.0, duration), y0, method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"reference integration failed: {sol.message}")
    y = sol.y[:, -1]
    q = y[:4] / np.linalg.norm(y[:4])
    return q, y[4:].copy()
