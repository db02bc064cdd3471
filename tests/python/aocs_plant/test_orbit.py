"""Orbit plants: SPEC 2.8 linear model against the textbook Clohessy-Wiltshire
solution (Hill frame) mapped to Bryson's frame, and the nonlinear two-body plant.
The orbit disturbances are effectors: test_effectors_srp_force.py, test_effectors_impulse.py.

Frame map used by the tests (derived in aocs_plant/orbit.py's docstring):
Hill (x_H radial out, y_H along-track, z_H orbit normal) -> Bryson
x = y_H, y = -z_H, z = -x_H; u = xdot - n z, v = ydot, w = zdot + n x.
"""
import math

import numpy as np
import pytest

from aocs_plant.orbit import LinearOrbit, NonlinearOrbit, bryson_matrices, mean_motion

MU = 3.986004418e14
R = 7080e3
MASS = 2623.0
N = math.sqrt(MU / R ** 3)


def cw_hill(t, r0, v0, n=N):
    """Clohessy-Wiltshire closed form (Vallado/Curtis), Hill frame, relative velocity."""
    x0, y0, z0 = r0
    xd0, yd0, zd0 = v0
    s, c = math.sin(n * t), math.cos(n * t)
    x = (4 - 3 * c) * x0 + s / n * xd0 + 2 / n * (1 - c) * yd0
    y = 6 * (s - n * t) * x0 + y0 - 2 / n * (1 - c) * xd0 + (4 * s - 3 * n * t) / n * yd0
    z = c * z0 + s / n * zd0
    xd = 3 * n * s * x0 + c * xd0 + 2 * s * yd0
    yd = -6 * n * (1 - c) * x0 - 2 * s * xd0 + (4 * c - 3) * yd0
    zd = -n * s * z0 + c * zd0
    return (x, y, z), (xd, yd, zd)


def hill_to_bryson(r, v, n=N):
    xb, yb, zb = r[1], -r[2], -r[0]
    xdb, ydb, zdb = v[1], -v[2], -v[0]
    return (xdb - n * zb, ydb, zdb + n * xb, xb, yb, zb)


def bryson_to_hill(x, n=N):
    u, v, w, xb, yb, zb = x
    xd, yd, zd = u + n * zb, v, w - n * xb
    return (-zb, xb, -yb), (-zd, xd, -yd)


def test_mean_motion_is_sqrt_g_over_r():
    g = MU / R ** 2
    assert mean_motion(MU, R) == pytest.approx(math.sqrt(g / R), rel=1e-15)
    assert 2 * math.pi / N == pytest.approx(5929.4, abs=1.0)  # ~98.8 min period


def test_state_matrix_is_spec_2_8_as_written():
    A, B = bryson_matrices(N, MASS)
    x = np.array([0.3, -0.2, 0.1, 50.0, -100.0, 350.0])
    du, dv, dw, dx, dy, dz = x
    n2 = N * N
    expected = [N * dw - n2 * dx, -n2 * dy, -N * du + 2 * n2 * dz, du + N * dz, dv, dw - N * dx]
    np.testing.assert_allclose(A @ x, expected, rtol=1e-15, atol=1e-18)
    np.testing.assert_allclose(B, np.vstack([np.eye(3) / MASS, np.zeros((3, 3))]))


def test_the_derivative_is_the_state_equation_with_the_force():
    """derivative(x, F) (the RK4 path when an effector has state) = A x + B F of bryson_matrices (SPEC 2.8),
    with a force on every axis."""
    A, B = bryson_matrices(N, MASS)
    x = np.array([0.3, -0.2, 0.1, 50.0, -100.0, 350.0])
    force = np.array([0.4, -0.7, 0.9])
    got = LinearOrbit(N, MASS, tuple(x)).derivative(tuple(x), tuple(force))
    np.testing.assert_allclose(got, A @ x + B @ force, rtol=1e-14, atol=1e-18)


def test_the_nonlinear_derivative_takes_the_force_as_b_f_and_is_the_linear_model_near_the_chief():
    """NonlinearOrbit.derivative(x, F): the force enters as B F of bryson_matrices (SPEC 2.8: F / m on u, v, w),
    whatever the state; 350 m from the chief the two-body terms are A x to first order (the rest is of
    relative size |r| / R = 5e-5)."""
    A, B = bryson_matrices(N, MASS)
    model = NonlinearOrbit(MU, R, MASS, (0.0,) * 6)
    for x in (np.array([0.3, -0.2, 0.1, 50.0, -100.0, 350.0]), np.array([-2.0, 1.5, 3.0, 4e4, 2e4, -3e4])):
        force = np.array([0.4, -0.7, 0.9])
        free = np.array(model.derivative(tuple(x), (0.0, 0.0, 0.0)))
        pushed = np.array(model.derivative(tuple(x), tuple(force)))
        np.testing.assert_allclose(pushed - free, B @ force, rtol=1e-9, atol=1e-15)
    x = np.array([0.3, -0.2, 0.1, 50.0, -100.0, 350.0])
    free = np.array(model.derivative(tuple(x), (0.0, 0.0, 0.0)))
    np.testing.assert_allclose(free, A @ x, rtol=1e-3, atol=1e-12)


def test_linear_model_free_motion_matches_clohessy_wiltshire():
    x0 = (1.0, -1.0, -6.0, 50.0, -100.0, 350.0)  # SPEC 4 landsat initial state
    r0, v0 = bryson_to_hill(x0)
    orbit = LinearOrbit(N, MASS, x0)
    period = 2 * math.pi / N
    t, h = 0.0, 10.0
    while t < period:
        orbit.propagate(h, (0.0, 0.0, 0.0))
        t += h
        expected = hill_to_bryson(*cw_hill(t, r0, v0))
        np.testing.assert_allclose(orbit.x, expected, rtol=1e-9, atol=1e-9 * 1000)


def test_radial_offset_drifts_along_track_by_12_pi_per_orbit():
    d = 10.0  # 10 m above the chief (z = -d), zero relative velocity
    x0 = (N * d, 0.0, 0.0, 0.0, 0.0, -d)  # u = xdot - n z = n d, w = zdot + n x = 0
    orbit = LinearOrbit(N, MASS, x0)
    period = 2 * math.pi / N
    orbit.propagate(period, (0.0, 0.0, 0.0))
    assert orbit.x[3] == pytest.approx(-12 * math.pi * d, rel=1e-9)  # falls behind
    assert orbit.x[5] == pytest.approx(-d, rel=1e-9)


def _one_orbit(model, x0, h=1.0):
    period = 2 * math.pi / N
    steps = int(round(period / h))
    for _ in range(steps):
        model.propagate(period / steps, (0.0, 0.0, 0.0))
    return np.array(model.x)


@pytest.mark.parametrize("x0", [
    (0.0, 0.0, 0.0, 10.0, 0.0, 0.0),       # along-track offset (an equilibrium of the linear model)
    (0.0, 0.0, 0.0, 0.0, 10.0, 0.0),       # cross-track offset
    (0.0, 0.0, 0.0, 0.0, 0.0, 10.0),       # radial offset at rest in the inertial sense
])
def test_nonlinear_agrees_with_linear_for_10_m_offsets_over_one_orbit(x0):
    lin = _one_orbit(LinearOrbit(N, MASS, x0), x0)
    non = _one_orbit(NonlinearOrbit(MU, R, MASS, x0), x0)
    # Bound: the neglected terms are ~ (3/2) n^2 rho^2 / R ~ 3e-11 m/s^2 for rho = 10 m,
    # i.e. ~0.5 mm over one orbit before the CW secular growth (x ~ 10): 1 cm.
    assert np.max(np.abs(lin[3:] - non[3:])) < 1e-2
    assert np.max(np.abs(lin[:3] - non[:3])) < 1e-5
    # the difference is the second-order term: doubling the offset quadruples it
    x2 = tuple(2 * v for v in x0)
    d1 = np.max(np.abs(lin[3:] - non[3:]))
    d2 = np.max(np.abs(_one_orbit(LinearOrbit(N, MASS, x2), x2)[3:]
                       - _one_orbit(NonlinearOrbit(MU, R, MASS, x2), x2)[3:]))
    assert 3.5 < d2 / d1 < 4.5


def test_nonlinear_same_circular_orbit_phase_offset_stays_fixed():
    # A deputy on the chief's circular orbit, 1 km ahead (phase delta): in the
    # rotating frame it does not move (exact for the nonlinear plant). The
    # linear model sees z = R (1 - cos delta) != 0 and drifts.
    delta = 1000.0 / R
    x, z = R * math.sin(delta), R * (1 - math.cos(delta))
    x0 = (-N * z, 0.0, N * x, x, 0.0, z)  # zero relative velocity: u = -n z, w = n x
    non = _one_orbit(NonlinearOrbit(MU, R, MASS, x0), x0)
    np.testing.assert_allclose(non, x0, atol=1e-6)
    lin = _one_orbit(LinearOrbit(N, MASS, x0), x0)
    assert abs(lin[3] - x) > 1.0


def test_chief_point_is_an_equilibrium_of_the_nonlinear_plant():
    model = NonlinearOrbit(MU, R, MASS, (0.0,) * 6)
    d = model.derivative((0.0,) * 6, (0.0, 0.0, 0.0))
    assert max(abs(v) for v in d) < 1e-15 * MU / R ** 2
