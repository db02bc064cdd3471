"""State-space models of the designed laws, exactly as SPEC 2.5, 2.6, 2.8 list them."""
from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np


def lqr_quat_model(inertia) -> tuple[np.ndarray, np.ndarray]:
    """SPEC 2.5: x = [qe_vec; we], A = [[0, 0.5 I], [0, 0]], B = [[0], [J^-1]].
    inertia: the diagonal (3 numbers) or the full 3x3 J, kg m^2."""
    j = np.asarray(inertia, dtype=float)
    j = np.diag(j) if j.ndim == 1 else j.reshape(3, 3)
    a = np.zeros((6, 6))
    a[0:3, 3:6] = 0.5 * np.eye(3)
    b = np.zeros((6, 3))
    b[3:6, :] = np.linalg.inv(j)
    return a, b


def lqr_quat_i_model(inertia) -> tuple[np.ndarray, np.ndarray]:
    """SPEC 5.2: x = [z; qe_vec; we], z' = qe_vec, qe_vec' = 0.5 we, J we' = u:
    A = [[0, I, 0], [0, 0, 0.5 I], [0, 0, 0]], B = [[0], [0], [J^-1]] (the SPEC 2.5 model
    with the integral of the attitude error in front). inertia: as lqr_quat_model."""
    a6, b6 = lqr_quat_model(inertia)
    a = np.zeros((9, 9))
    a[0:3, 3:6] = np.eye(3)
    a[3:9, 3:9] = a6
    b = np.zeros((9, 3))
    b[3:9, :] = b6
    return a, b


def mean_motion(mu: float, radius: float) -> float:
    """n = sqrt(g / R) = sqrt(mu / R^3) (SPEC 2.8)."""
    return math.sqrt(mu / radius**3)


def orbit_model(mass: float, radius: float, mu: float) -> tuple[np.ndarray, np.ndarray]:
    """SPEC 2.8 (Bryson): x = [du dv dw dx dy dz], B = [I3 / m; 0]."""
    n = mean_motion(mu, radius)
    a = np.zeros((6, 6))
    # du' = n dw - n^2 dx
    a[0, 2] = n
    a[0, 3] = -n * n
    # dv' = -n^2 dy
    a[1, 4] = -n * n
    # dw' = -n du + 2 n^2 dz
    a[2, 0] = -n
    a[2, 5] = 2.0 * n * n
    # dx' = du + n dz
    a[3, 0] = 1.0
    a[3, 5] = n
    # dy' = dv
    a[4, 1] = 1.0
    # dz' = dw - n dx
    a[5, 2] = 1.0
    a[5, 3] = -n
    b = np.zeros((6, 3))
    b[0:3, :] = np.eye(3) / mass
    return a, b


@dataclass(frozen=True)
class HinfPlant:
    """SPEC 2.6 generalised plant: xdot = A x + B1 u + B2 d, z = C1 x + D1 u + D2 d."""

    a: np.ndarray
    b1: np.ndarray
    b2: np.ndarray
    c1: np.ndarray
    d1: np.ndarray
    d2: np.ndarray


def hinf_model(ix: float, iy: float, iz: float, w0: float, z_scale: float = 1.0e-3) -> HinfPlant:
    """Linearised Earth-pointing attitude (SPEC 2.6, corrected yaw line).

    x = [phi theta psi phidot thetadot psidot]; z = z_scale M q''.
    """
    m = np.diag([ix, iy, iz])
    a = np.zeros((6, 6))
    a[0:3, 3:6] = np.eye(3)
    # Ix phi'' + 4 (Iy - Iz) w0^2 phi + (Iy - Iz - Ix) w0 psi' = Tx + dx
    a[3, 0] = -4.0 * (iy - iz) * w0**2 / ix
    a[3, 5] = -(iy - iz - ix) * w0 / ix
    # Iy theta'' + 3 (Ix - Iz) w0^2 theta = Ty + dy
    a[4, 1] = -3.0 * (ix - iz) * w0**2 / iy
    # Iz psi'' + (Iy - Ix) w0^2 psi + (Ix + Iz - Iy) w0 phi' = Tz + dz
    a[5, 2] = -(iy - ix) * w0**2 / iz
    a[5, 3] = -(ix + iz - iy) * w0 / iz
    b = np.zeros((6, 3))
    b[3:6, :] = np.linalg.inv(m)
    c1 = z_scale * m @ a[3:6, :]
    d = z_scale * np.eye(3)
    return HinfPlant(a=a, b1=b, b2=b.copy(), c1=c1, d1=d, d2=d.copy())
