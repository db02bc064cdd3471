"""Rigid-body attitude dynamics, fixed-step RK4 on plain Python floats.

    J wdot = -w x (J w) + u + u_d            (SPEC 1, full inertia J)
    qdot   = 0.5 Xi(q) w                     (SPEC 1, scalar-last quaternion)

The hot path works on tuples and local variables: numpy on 3-vectors costs
~15x more per step (TOOLCHAIN-NOTES "Plant integration cost"). The RK4 step is
written once, as the source template make_stepper() specialises to one inertia
(constants bound, zeros of a diagonal J dropped: the Plant's hot path);
rk4_step is the same template with every inertia term kept.
The quaternion is renormalised after every step. An optional gravity-gradient
term c (R x J R), R = A(q) d (d a unit vector in N), is evaluated at every RK4
stage because it depends on the attitude. reference_propagate() integrates the
same equations with scipy's adaptive DOP853 (rtol 1e-12) to measure the RK4
integration error; it is never used to run a scenario.
"""
from __future__ import annotations

import functools
import math
import time

import numpy as np

from aocs_core.conventions import quat_to_dcm


def _mat9(m) -> tuple:
    a = np.asarray(m, dtype=float)
    if a.shape != (3, 3):
        raise ValueError("inertia must be 3x3")
    return tuple(a.ravel().tolist())


def rk4_step(q, w, h, torque, J, Ji, ggc=0.0, gd=(0.0, 0.0, 1.0)):
    """One RK4 step of length h with constant external torque (3-tuple).

    J, Ji: row-major 9-tuples of the inertia and its inverse. ggc, gd: optional
    gravity-gradient torque ggc * (R x J R), R = A(q) gd; ggc = 0 disables it.
    Returns (q, w) with q renormalised. This is the generic form of the one
    stepper make_stepper() generates (every inertia term kept), built once per
    inertia and cached.
    """
    return _generic_stepper(tuple(J), tuple(Ji), ggc != 0.0)(q, w, h, torque, ggc, gd)


@functools.lru_cache(maxsize=64)
def _generic_stepper(J: tuple, Ji: tuple, gravity_gradient: bool):
    return make_stepper(J, Ji, gravity_gradient, drop_zeros=False)


def gg_torque(q, J, ggc, gd):
    """ggc * (R x J R), R = A(q) gd (the same term rk4_step integrates)."""
    j0, j1, j2, j3, j4, j5, j6, j7, j8 = J
    q1, q2, q3, q4 = q
    d1, d2, d3 = gd
    s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
    vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
    c = 2.0 * q4
    r1 = s * d1 + vd * q1 - c * (q2 * d3 - q3 * d2)
    r2 = s * d2 + vd * q2 - c * (q3 * d1 - q1 * d3)
    r3 = s * d3 + vd * q3 - c * (q1 * d2 - q2 * d1)
    g1 = j0 * r1 + j1 * r2 + j2 * r3
    g2 = j3 * r1 + j4 * r2 + j5 * r3
    g3 = j6 * r1 + j7 * r2 + j8 * r3
    return (ggc * (r2 * g3 - r3 * g2), ggc * (r3 * g1 - r1 * g3), ggc * (r1 * g2 - r2 * g1))


_STEPPER_TEMPLATE = """
def f(q1, q2, q3, q4, w1, w2, w3):
    hx = {Jw0}
    hy = {Jw1}
    hz = {Jw2}
    mx = tx - (w2 * hz - w3 * hy)
    my = ty - (w3 * hx - w1 * hz)
    mz = tz - (w1 * hy - w2 * hx)
{GG}
    return (0.5 * (q4 * w1 - q3 * w2 + q2 * w3), 0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
            0.5 * (-q2 * w1 + q1 * w2 + q4 * w3), -0.5 * (q1 * w1 + q2 * w2 + q3 * w3),
            {Jim0}, {Jim1}, {Jim2})
"""

_GG_TEMPLATE = """
    s = q4 * q4 - (q1 * q1 + q2 * q2 + q3 * q3)
    vd = 2.0 * (q1 * d1 + q2 * d2 + q3 * d3)
    c = 2.0 * q4
    r1 = s * d1 + vd * q1 - c * (q2 * d3 - q3 * d2)
    r2 = s * d2 + vd * q2 - c * (q3 * d1 - q1 * d3)
    r3 = s * d3 + vd * q3 - c * (q1 * d2 - q2 * d1)
    g1 = {Jr0}
    g2 = {Jr1}
    g3 = {Jr2}
    mx += ggc * (r2 * g3 - r3 * g2)
    my += ggc * (r3 * g1 - r1 * g3)
    mz += ggc * (r1 * g2 - r2 * g1)
"""


def _matvec_expr(m, names, x, drop_zeros=True):
    """Source of the three rows of m @ x, dropping exact zeros (diagonal inertia) unless told not to."""
    rows = []
    for r in range(3):
        terms = [f"{names[3 * r + c]} * {x[c]}" for c in range(3)
                 if not (drop_zeros and m[3 * r + c] == 0.0)]
        rows.append(" + ".join(terms) if terms else "0.0")
    return rows


def make_stepper(J, Ji, gravity_gradient: bool, drop_zeros: bool = True):
    """Specialised rk4_step(q, w, h, torque, ggc, gd) for one inertia (same arithmetic).

    The inertia entries become closure constants and, with drop_zeros,
    structural zeros of a diagonal J are dropped, which roughly halves the
    per-step cost of the generic rk4_step (hot path of a lockstep run). Equal to
    rk4_step up to rounding (tested).
    """
    jn = [f"j{i}" for i in range(9)]
    inn = [f"i{i}" for i in range(9)]
    jw = _matvec_expr(J, jn, ("w1", "w2", "w3"), drop_zeros)
    jim = _matvec_expr(Ji, inn, ("mx", "my", "mz"), drop_zeros)
    gg = ""
    if gravity_gradient:
        jr = _matvec_expr(J, jn, ("r1", "r2", "r3"), drop_zeros)
        gg = _GG_TEMPLATE.format(Jr0=jr[0], Jr1=jr[1], Jr2=jr[2])
    body = _STEPPER_TEMPLATE.format(Jw0=jw[0], Jw1=jw[1], Jw2=jw[2], Jim0=jim[0], Jim1=jim[1],
                                    Jim2=jim[2], GG=gg)
    outer = "def make(j0, j1, j2, j3, j4, j5, j6, j7, j8, i0, i1, i2, i3, i4, i5, i6, i7, i8, sqrt):\n"
    outer += "    def step(q, w, h, torque, ggc=0.0, gd=(0.0, 0.0, 1.0)):\n"
    outer += "        tx, ty, tz = torque\n        d1, d2, d3 = gd\n"
    outer += "".join("        " + line + "\n" for line in body.splitlines())
    outer += _STEP_BODY
    outer += "    return step\n"
    ns: dict = {}
    exec(compile(outer, "<aocs_plant.rigid_body stepper>", "exec"), ns)  # noqa: S102 - generated from the templates above only
    return ns["make"](*J, *Ji, math.sqrt)


_STEP_BODY = """        q1, q2, q3, q4 = q
        w1, w2, w3 = w
        hh = 0.5 * h
        a = f(q1, q2, q3, q4, w1, w2, w3)
        b = f(q1 + hh * a[0], q2 + hh * a[1], q3 + hh * a[2], q4 + hh * a[3],
              w1 + hh * a[4], w2 + hh * a[5], w3 + hh * a[6])
        c_ = f(q1 + hh * b[0], q2 + hh * b[1], q3 + hh * b[2], q4 + hh * b[3],
               w1 + hh * b[4], w2 + hh * b[5], w3 + hh * b[6])
        d = f(q1 + h * c_[0], q2 + h * c_[1], q3 + h * c_[2], q4 + h * c_[3],
              w1 + h * c_[4], w2 + h * c_[5], w3 + h * c_[6])
        h6 = h / 6.0
        q1 += h6 * (a[0] + 2.0 * (b[0] + c_[0]) + d[0])
        q2 += h6 * (a[1] + 2.0 * (b[1] + c_[1]) + d[1])
        q3 += h6 * (a[2] + 2.0 * (b[2] + c_[2]) + d[2])
        q4 += h6 * (a[3] + 2.0 * (b[3] + c_[3]) + d[3])
        w1 += h6 * (a[4] + 2.0 * (b[4] + c_[4]) + d[4])
        w2 += h6 * (a[5] + 2.0 * (b[5] + c_[5]) + d[5])
        w3 += h6 * (a[6] + 2.0 * (b[6] + c_[6]) + d[6])
        n = 1.0 / sqrt(q1 * q1 + q2 * q2 + q3 * q3 + q4 * q4)
        return (q1 * n, q2 * n, q3 * n, q4 * n), (w1, w2, w3)
"""


class RigidBody:
    """State (q, w) of one rigid body with full inertia J (kg m^2)."""

    def __init__(self, inertia, q0, w0):
        self.J = _mat9(inertia)
        self.Ji = tuple(np.linalg.inv(np.asarray(inertia, dtype=float)).ravel().tolist())
        self.q = tuple(float(x) for x in q0)
        self.w = tuple(float(x) for x in w0)

    def derivative(self, q, w, torque):
        """(qdot, wdot) for external torque u + u_d (tuples); for tests and tools."""
        j = self.J
        hx = j[0] * w[0] + j[1] * w[1] + j[2] * w[2]
        hy = j[3] * w[0] + j[4] * w[1] + j[5] * w[2]
        hz = j[6] * w[0] + j[7] * w[1] + j[8] * w[2]
        m = (torque[0] - (w[1] * hz - w[2] * hy),
             torque[1] - (w[2] * hx - w[0] * hz),
             torque[2] - (w[0] * hy - w[1] * hx))
        ji = self.Ji
        wdot = (ji[0] * m[0] + ji[1] * m[1] + ji[2] * m[2],
                ji[3] * m[0] + ji[4] * m[1] + ji[5] * m[2],
                ji[6] * m[0] + ji[7] * m[1] + ji[8] * m[2])
        q1, q2, q3, q4 = q
        w1, w2, w3 = w
        qdot = (0.5 * (q4 * w1 - q3 * w2 + q2 * w3),
                0.5 * (q3 * w1 + q4 * w2 - q1 * w3),
                0.5 * (-q2 * w1 + q1 * w2 + q4 * w3),
                -0.5 * (q1 * w1 + q2 * w2 + q3 * w3))
        return qdot, wdot

    def propagate(self, duration, substeps, torque=(0.0, 0.0, 0.0), ggc=0.0, gd=(0.0, 0.0, 1.0)):
        """Advance by `duration` with `substeps` RK4 steps and a constant torque."""
        h = duration / substeps
        q, w = self.q, self.w
        J, Ji = self.J, self.Ji
        for _ in range(substeps):
            q, w = rk4_step(q, w, h, torque, J, Ji, ggc, gd)
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


def reference_propagate(inertia, q0, w0, duration, torque=(0.0, 0.0, 0.0),
                        ggc=0.0, gd=(0.0, 0.0, 1.0), rtol=1e-12, atol=1e-13):
    """Adaptive high-order reference (scipy DOP853) of the same equations.

    Used only to measure the fixed-step integration error. Returns (q, w) as
    numpy arrays with q normalised (sign as integrated).
    """
    from scipy.integrate import solve_ivp  # deferred: scipy only for this reference integrator, not the hot path

    body = RigidBody(inertia, q0, w0)
    J = body.J

    def rhs(_t, y):
        q = tuple(y[:4])
        w = tuple(y[4:])
        tq = torque
        if ggc != 0.0:
            g = gg_torque(q, J, ggc, gd)
            tq = (torque[0] + g[0], torque[1] + g[1], torque[2] + g[2])
        qd, wd = body.derivative(q, w, tq)
        return list(qd) + list(wd)

    y0 = list(q0) + list(w0)
    sol = solve_ivp(rhs, (0.0, duration), y0, method="DOP853", rtol=rtol, atol=atol)
    if not sol.success:
        raise RuntimeError(f"reference integration failed: {sol.message}")
    y = sol.y[:, -1]
    q = y[:4] / np.linalg.norm(y[:4])
    return q, y[4:].copy()


def benchmark_rk4(steps: int = 10000) -> float:
    """Mean wall time of one RK4 step (s) on the IRASSI inertia, no disturbance."""
    J = (2059.5, 0, 0, 0, 5954.2, 0, 0, 0, 5974.3)
    Ji = (1 / 2059.5, 0, 0, 0, 1 / 5954.2, 0, 0, 0, 1 / 5974.3)
    q, w = (0.1, 0.2, 0.3, math.sqrt(1 - 0.14)), (1e-3, -2e-3, 3e-3)
    t0 = time.perf_counter()
    for _ in range(steps):
        q, w = rk4_step(q, w, 0.1, (1e-3, 1e-3, 1e-3), J, Ji)
    return (time.perf_counter() - t0) / steps
