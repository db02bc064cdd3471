"""Relative orbit plants in Bryson's rotating frame (SPEC 2.8 and 3).

State x = [u v w x y z] (velocities first, then positions), the convention
of law 8: x along-track, y cross-track, z toward nadir; (u, v, w) is the
INERTIAL velocity resolved in the rotating frame, not the relative velocity:
    xdot = u + n z,  ydot = v,  zdot = w - n x.
The frame rotates with angular velocity omega = (0, -n, 0) (y is minus the
orbit normal), so omega x r = (-n z, 0, n x) and the velocity equations are
    V' = a - omega x V = a + (n w, 0, -n u),
with a the gravitational acceleration relative to the chief plus F/m.

- LinearOrbit: SPEC 2.8 exactly (a = (-n^2 x, -n^2 y, 2 n^2 z) + F/m),
  propagated with the EXACT discretisation (matrix exponential of the
  augmented system, force held constant over the step), not RK4.
- NonlinearOrbit: the same frame with the full two-body relative
  acceleration for a circular chief (exact, no linearisation):
  a = -mu (x, y, z - R)/|(x, y, z - R)|^3 - (0, 0, mu/R^2) + F/m,
  the chief being at (0, 0, -R) from the Earth's centre. RK4, plain floats.
"""
from __future__ import annotations

import math

import numpy as np

MU_EARTH = 3.986004418e14  # m^3/s^2


def mean_motion(mu: float, radius: float) -> float:
    """n = sqrt(g / R) with g = mu / R^2 (SPEC 2.8)."""
    return math.sqrt(mu / radius ** 3)


def bryson_matrices(n: float, mass: float):
    """(A, B) of SPEC 2.8: xdot = A x + B F, x = [du dv dw dx dy dz]."""
    n2 = n * n
    A = np.array([
        [0, 0, n, -n2, 0, 0],
        [0, 0, 0, 0, -n2, 0],
        [-n, 0, 0, 0, 0, 2 * n2],
        [1, 0, 0, 0, 0, n],
        [0, 1, 0, 0, 0, 0],
        [0, 0, 1, -n, 0, 0],
    ], dtype=float)
    B = np.vstack([np.eye(3) / mass, np.zeros((3, 3))])
    return A, B


class LinearOrbit:
    """SPEC 2.8 linear model, exact zero-order-hold discretisation."""

    def __init__(self, n: float, mass: float, x0):
        self.n = float(n)
        self.mass = float(mass)
        self.x = tuple(float(v) for v in x0)
        self.A, self.B = bryson_matrices(self.n, self.mass)
        self._cache: dict[float, tuple] = {}

    def _disc(self, h: float):
        d = self._cache.get(h)
        if d is None:
            m = np.zeros((9, 9))
            m[:6, :6] = self.A
            m[:6, 6:] = self.B
            from scipy.linalg import expm  # deferred: scipy.linalg costs ~0.2 s of every plant start, orbit runs only

            e = expm(m * h)
            d = (tuple(tuple(r) for r in e[:6, :6].tolist()),
                 tuple(tuple(r) for r in e[:6, 6:].tolist()))
            self._cache[h] = d
        return d

    def derivative(self, x, force):
        """xdot = A x + B F (SPEC 2.8) on floats: for the RK4 over the plant's concatenated
        state when an effector has state (the plain run uses the exact propagate())."""
        n, m = self.n, self.mass
        n2 = n * n
        u, v, w, px, py, pz = x
        return (n * w - n2 * px + force[0] / m, -n2 * py + force[1] / m, -n * u + 2.0 * n2 * pz + force[2] / m,
                u + n * pz, v, w - n * px)

    def propagate(self, h: float, force, substeps: int = 1) -> None:
        """Advance by h with the force (N, rotating frame) held constant (exact)."""
        del substeps  # exact: substeps do not change the result
        ad, bd = self._disc(h)
        x = self.x
        f0, f1, f2 = force
        self.x = tuple(
            ad[i][0] * x[0] + ad[i][1] * x[1] + ad[i][2] * x[2] + ad[i][3] * x[3]
            + ad[i][4] * x[4] + ad[i][5] * x[5] + bd[i][0] * f0 + bd[i][1] * f1 + bd[i][2] * f2
            for i in range(6))


class NonlinearOrbit:
    """Two-body relative motion about a circular chief, RK4 with substeps."""

    def __init__(self, mu: float, radius: float, mass: float, x0):
        self.mu = float(mu)
        self.radius = float(radius)
        self.n = mean_motion(self.mu, self.radius)
        self.mass = float(mass)
        self.x = tuple(float(v) for v in x0)

    def derivative(self, x, force):
        n, mu, R, m = self.n, self.mu, self.radius, self.mass
        u, v, w, px, py, pz = x
        rz = pz - R
        r2 = px * px + py * py + rz * rz
        k = mu / (r2 * math.sqrt(r2))
        ax = -k * px + force[0] / m
        ay = -k * py + force[1] / m
        az = -k * rz - mu / (R * R) + force[2] / m
        return (n * w + ax, ay, -n * u + az, u + n * pz, v, w - n * px)

    def propagate(self, h: float, force, substeps: int = 1) -> None:
        x = self.x
        dt = h / substeps
        f = self.derivative
        for _ in range(substeps):
            a = f(x, force)
            b = f(tuple(x[i] + 0.5 * dt * a[i] for i in range(6)), force)
            c = f(tuple(x[i] + 0.5 * dt * b[i] for i in range(6)), force)
            d = f(tuple(x[i] + dt * c[i] for i in range(6)), force)
            x = tuple(x[i] + dt / 6.0 * (a[i] + 2.0 * (b[i] + c[i]) + d[i]) for i in range(6))
        self.x = x
