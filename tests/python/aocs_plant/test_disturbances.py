"""Disturbance torques against independent hand evaluations (SPEC 3)."""
import math

import numpy as np
import pytest

from aocs_plant import Plant, load
from aocs_plant import disturbances as dist
from aocs_plant.rigid_body import gg_torque

# L2 data written out independently of the module's constants
MU_SUN = 1.32712440018e20
MU_EARTH = 3.986004418e14
R2 = 1.5e9
R1 = 1.495978707e11 + R2
K_L2 = MU_SUN / R1 ** 3 + MU_EARTH / R2 ** 3


def qx(angle):
    return (math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2))


def J9(d):
    return (d[0], 0.0, 0.0, 0.0, d[1], 0.0, 0.0, 0.0, d[2])


def test_l2_coefficient_from_the_spec_formula():
    assert dist.l2_gg_coefficient() == pytest.approx(-3.0 * K_L2, rel=1e-14)
    assert dist.R1_L2 == pytest.approx(1.510978707e11, rel=1e-12)


def test_gravity_gradient_vanishes_for_symmetric_body_and_principal_alignment():
    c = -3.0 * K_L2
    rng = np.random.default_rng(0)
    q = tuple(rng.standard_normal(4))
    q = tuple(x / np.linalg.norm(q) for x in q)
    # rounding only: |c| * 7 ~ 3e-12 N m is the scale of one non-vanishing term
    assert max(map(abs, gg_torque(q, J9((7.0, 7.0, 7.0)), c, (0.0, 0.0, 1.0)))) < 1e-15 * abs(c) * 7.0
    # identity attitude: R = e3, a principal axis of a diagonal J
    assert gg_torque((0, 0, 0, 1.0), J9((1.0, 2.0, 3.0)), c, (0.0, 0.0, 1.0)) == (0.0, 0.0, 0.0)


def test_gravity_gradient_for_a_45_degree_tilt():
    # rotation of 45 deg about x: R = A(q) e3 = (0, sin45, cos45); J = diag(1, 2, 3)
    # R x J R = (s * 3c - c * 2s, 0, 0) = (0.5, 0, 0)
    tq = gg_torque(qx(math.pi / 4), J9((1.0, 2.0, 3.0)), -3.0 * K_L2, (0.0, 0.0, 1.0))
    np.testing.assert_allclose(tq, (-3.0 * K_L2 * 0.5, 0.0, 0.0), rtol=1e-12, atol=1e-30)
    # Earth-orbit form 3 n^2 (o3 x J o3) with o3 the nadir; at t = 0 the nadir is N's z axis
    n = 7.292115e-5
    tq = gg_torque(qx(math.pi / 4), J9((1.0, 2.0, 3.0)), dist.earth_gg_coefficient(n),
                   dist.earth_nadir_inertial(n, 0.0))
    np.testing.assert_allclose(tq, (3 * n * n * 0.5, 0.0, 0.0), rtol=1e-12)


def test_earth_nadir_rotates_with_the_orbit():
    # chief at -R z_N moving along +x_N: a quarter orbit later the Earth is along -x_N
    n = 1e-3
    np.testing.assert_allclose(dist.earth_nadir_inertial(n, 0.25 * 2 * math.pi / n), (-1.0, 0.0, 0.0),
                               atol=1e-15)


def test_irassi_plant_disturbance_is_constant_plus_l2_gradient():
    sc = load("irassi_large")
    plant = Plant(sc)
    q = plant.body.q
    # independent: R = third column of A(q), written from the quaternion
    q1, q2, q3, q4 = q
    Rv = np.array([2 * (q1 * q3 - q2 * q4), 2 * (q2 * q3 + q1 * q4), q4 ** 2 - q1 ** 2 - q2 ** 2 + q3 ** 2])
    J = np.diag([2059.5, 5954.2, 5974.3])
    expected = 1.18e-3 * np.ones(3) - 3.0 * K_L2 * np.cross(Rv, J @ Rv)
    np.testing.assert_allclose(plant.truth()["disturbance"], expected, rtol=1e-12)
    # and the rigid body feels it: from rest, w(dt) = J^-1 u_d dt to first order
    plant.advance()
    np.testing.assert_allclose(plant.truth()["w"], np.linalg.solve(J, expected) * sc.dt, rtol=1e-6)


def test_disturbance_scale_and_enable_flags():
    base = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False}))
    assert base.truth()["disturbance"] == pytest.approx((1.18e-3,) * 3, rel=1e-15)
    half = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                       "disturbances.constant_torque.scale": 0.5}))
    assert half.truth()["disturbance"] == pytest.approx((0.59e-3,) * 3, rel=1e-15)
    off = Plant(load("irassi_large", {"disturbances.gravity_gradient_l2.enabled": False,
                                      "disturbances.constant_torque.enabled": False}))
    assert off.truth()["disturbance"] == (0.0, 0.0, 0.0)


def test_srp_force_and_torque():
    # F = (Pe / c)(1 + Y) A (1 AU / r)^2
    F = 1361.0 / 299792458.0 * (1 + 0.6) * 10.0
    assert dist.srp_force_magnitude(10.0, 0.6) == pytest.approx(F, rel=1e-15)
    assert dist.srp_force_magnitude(10.0, 0.6, distance_au=2.0) == pytest.approx(F / 4, rel=1e-15)
    # F x h for F along z and h = 0.1 m along x: (0, 0.1 F, 0)
    np.testing.assert_allclose(dist.srp_torque((0, 0, F), (0.1, 0, 0)), (0, 0.1 * F, 0), rtol=1e-15)


def test_srp_torque_enters_the_attitude_plant():
    sc = load("irassi_large", {
        "disturbances.gravity_gradient_l2.enabled": False,
        "disturbances.constant_torque.enabled": False,
        "disturbances.srp_torque": {"enabled": True, "area_m2": 10.0, "reflectivity": 0.6,
                                    "direction_b": [0.0, 0.0, 1.0], "cp_offset_m": [0.1, 0.0, 0.0]},
    })
    F = 1361.0 / 299792458.0 * 1.6 * 10.0
    np.testing.assert_allclose(Plant(sc).truth()["disturbance"], (0.0, 0.1 * F, 0.0), rtol=1e-14)
