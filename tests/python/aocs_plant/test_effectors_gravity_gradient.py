"""Gravity-gradient torque, L2 and Earth-orbit forms (SPEC 3.3), against independent hand
evaluations: R from the attitude matrix written out here, R x J R with numpy."""
import math

import numpy as np
import pytest

from aocs_core.conventions import quat_to_dcm
from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors import gravity_gradient as gg
from aocs_plant.effectors.base import Form

# L2 data written out independently of the module's constants
MU_SUN = 1.32712440018e20
MU_EARTH = 3.986004418e14
R2 = 1.5e9
R1 = 1.495978707e11 + R2
K_L2 = MU_SUN / R1 ** 3 + MU_EARTH / R2 ** 3
GAO_J = ((42.0, 1.8, -1.5), (1.8, 25.0, -1.2), (-1.5, -1.2, 61.8))


def qx(angle):
    return (math.sin(angle / 2), 0.0, 0.0, math.cos(angle / 2))


def J9(d):
    return (d[0], 0.0, 0.0, 0.0, d[1], 0.0, 0.0, 0.0, d[2])


def hand(q, J, c, d):
    """c (R x J R), R = A(q) d, with numpy."""
    R = np.array(quat_to_dcm(q)) @ np.asarray(d, float)
    return c * np.cross(R, np.asarray(J, float).reshape(3, 3) @ R)


def test_l2_coefficient_from_the_spec_formula_with_the_textbook_sign():
    # SPEC 3.3: u_gg = +3 (mu1/r1^3 + mu2/r2^3) (R x J R) (the reference's leading minus is a misprint)
    assert gg.L2_GG_SIGN == 1.0
    assert gg.l2_gg_coefficient() == pytest.approx(3.0 * K_L2, rel=1e-14)
    assert gg.R1_L2 == pytest.approx(1.510978707e11, rel=1e-12)


def test_plant_l2_torque_is_the_textbook_one_at_the_irassi_start():
    """The whole plant (scenario -> effector -> disturbance truth) against +3 K (R x J R) evaluated here."""
    sc = load("irassi_small", {"disturbances.constant_torque.enabled": False})
    p = Plant(sc)
    J = np.array(sc.attitude.inertia, float).reshape(3, 3)
    want = hand(sc.attitude.q0, J, 3.0 * K_L2, (0.0, 0.0, 1.0))
    np.testing.assert_allclose(p.truth()["disturbance"], want, rtol=1e-12, atol=0.0)
    assert abs(want[1]) > 1e-10  # a real torque, so the sign is tested


def test_gravity_gradient_vanishes_for_symmetric_body_and_principal_alignment():
    c = -3.0 * K_L2
    rng = np.random.default_rng(0)
    q = tuple(rng.standard_normal(4))
    q = tuple(x / np.linalg.norm(q) for x in q)
    g, _ = gg.gg_term(J9((7.0, 7.0, 7.0)), c)
    # rounding only: |c| * 7 ~ 3e-12 N m is the scale of one non-vanishing term
    assert max(map(abs, g(*q))) < 1e-15 * abs(c) * 7.0
    # identity attitude: R = e3, a principal axis of a diagonal J
    g, _ = gg.gg_term(J9((1.0, 2.0, 3.0)), c)
    assert g(0.0, 0.0, 0.0, 1.0) == (0.0, 0.0, 0.0)


def test_gravity_gradient_for_a_45_degree_tilt():
    # rotation of 45 deg about x: R = A(q) e3 = (0, sin45, cos45); J = diag(1, 2, 3)
    # R x J R = (s * 3c - c * 2s, 0, 0) = (0.5, 0, 0)
    g, point = gg.gg_term(J9((1.0, 2.0, 3.0)), -3.0 * K_L2)
    np.testing.assert_allclose(g(*qx(math.pi / 4)), (-3.0 * K_L2 * 0.5, 0.0, 0.0), rtol=1e-12, atol=1e-30)
    # Earth-orbit form 3 n^2 (o3 x J o3) with o3 the nadir; at t = 0 the nadir is N's z axis
    n = 7.292115e-5
    g, point = gg.gg_term(J9((1.0, 2.0, 3.0)), gg.earth_gg_coefficient(n), gg.earth_nadir_inertial(n, 0.0))
    np.testing.assert_allclose(g(*qx(math.pi / 4)), (3 * n * n * 0.5, 0.0, 0.0), rtol=1e-12)


@pytest.mark.parametrize("J", [GAO_J, ((2059.5, 0, 0), (0, 5954.2, 0), (0, 0, 5974.3))])
def test_closure_against_numpy_for_full_and_diagonal_inertia(J):
    rng = np.random.default_rng(5)
    J9_ = tuple(float(v) for row in J for v in row)
    for _ in range(20):
        q = rng.standard_normal(4)
        q = tuple(q / np.linalg.norm(q))
        d = rng.standard_normal(3)
        d = tuple(d / np.linalg.norm(d))
        g, point = gg.gg_term(J9_, 2.5e-6, (0.0, 0.0, 1.0))
        point(d)
        np.testing.assert_allclose(g(*q), hand(q, J9_, 2.5e-6, d), rtol=1e-12, atol=1e-18)


def test_earth_nadir_rotates_with_the_orbit():
    # chief at -R z_N moving along +x_N: a quarter orbit later the Earth is along -x_N
    n = 1e-3
    np.testing.assert_allclose(gg.earth_nadir_inertial(n, 0.25 * 2 * math.pi / n), (-1.0, 0.0, 0.0), atol=1e-15)


def test_irassi_plant_disturbance_is_constant_plus_l2_gradient():
    sc = load("irassi_large")
    plant = Plant(sc)
    q = plant.body.q
    # independent: R = third column of A(q), written from the quaternion
    q1, q2, q3, q4 = q
    Rv = np.array([2 * (q1 * q3 - q2 * q4), 2 * (q2 * q3 + q1 * q4), q4 ** 2 - q1 ** 2 - q2 ** 2 + q3 ** 2])
    J = np.diag([2059.5, 5954.2, 5974.3])
    expected_gg = 3.0 * K_L2 * np.cross(Rv, J @ Rv)   # SPEC 3.3: the textbook plus sign
    np.testing.assert_allclose(plant.truth()["disturbance"], 1.18e-3 * np.ones(3) + expected_gg, rtol=1e-12)
    np.testing.assert_allclose(plant.truth()["effectors"]["gravity_gradient_l2.torque_nm"], expected_gg, rtol=1e-12)
    assert [e.form for e in plant.effectors if e.kind == "gravity_gradient_l2"] == [Form.ATTITUDE]
    # and the rigid body feels it: from rest, w(dt) = J^-1 u_d dt to first order
    plant.advance()
    np.testing.assert_allclose(plant.truth()["w"], np.linalg.solve(J, 1.18e-3 + expected_gg) * sc.dt, rtol=1e-6)


def test_earth_form_follows_the_nadir_in_time():
    sc = load("geo_hinf", {"disturbances.constant_torque.enabled": False})
    plant = Plant(sc)
    n = 7.292115e-5
    J = tuple(float(v) for row in sc.attitude.inertia for v in row)
    for _ in range(3000):  # 300 s
        plant.advance()
    t = plant.t
    expected = hand(plant.body.q, J, 3 * n * n, (-math.sin(n * t), 0.0, math.cos(n * t)))
    np.testing.assert_allclose(plant.disturbance(), expected, rtol=1e-12)


def test_the_two_forms_are_exclusive_and_only_for_attitude(tmp_path):
    with pytest.raises(ScenarioError, match=r"irassi_large.toml: disturbances.gravity_gradient_earth: "
                                            r"cannot be enabled together with gravity_gradient_l2"):
        load("irassi_large", {"disturbances.gravity_gradient_earth": {"enabled": True, "orbit_rate_rad_s": 1e-4}})
    sc = load("irassi_large", {"disturbances.gravity_gradient_earth": {"enabled": False, "orbit_rate_rad_s": 1e-4}})
    assert not sc.disturbances.gravity_gradient_earth.enabled
    with pytest.raises(ScenarioError, match=r"disturbances.gravity_gradient_l2: disturbance 'gravity_gradient_l2' "
                                            r"does not apply to a orbit scenario"):
        load("landsat8_q1", {"disturbances.gravity_gradient_l2": {"enabled": True}})
    with pytest.raises(ScenarioError, match=r"disturbances.gravity_gradient_earth.orbit_rate_rad_s: must be > 0"):
        load("geo_hinf", {"disturbances.gravity_gradient_earth.orbit_rate_rad_s": 0.0})


def test_earth_form_follows_the_environment_orbit_without_a_rate():
    """leo_day's gravity gradient (no orbit_rate_rad_s): 3 mu / R^3 (o3 x J o3) with o3 = A(q) (-r / R), r the
    circular orbit of [environment.orbit] written out here, at t = 0 and after 300 periods of flight."""
    sc = load("leo_day", {"disturbances.constant_torque.enabled": False, "residual_dipole.enabled": False})
    assert sc.disturbances.gravity_gradient_earth.orbit_rate_rad_s is None
    o = sc.environment.orbit
    n = math.sqrt(o.mu / o.radius_m ** 3)
    i, raan = math.radians(o.inclination_deg), math.radians(o.raan_deg)
    node = np.array([math.cos(raan), math.sin(raan), 0.0])
    h = np.array([math.sin(i) * math.sin(raan), -math.sin(i) * math.cos(raan), math.cos(i)])
    J = np.array(sc.attitude.inertia, float).reshape(3, 3)
    p = Plant(sc)
    zero = {f: (0.0,) * k for f, k in p.command_fields.items()}
    for steps in (0, 300):
        for _ in range(steps):
            p.apply(zero)
            p.advance()
        u = n * p.t
        nadir = -(math.cos(u) * node + math.sin(u) * np.cross(h, node))
        want = hand(p.body.q, J, 3.0 * n * n, nadir)
        assert np.linalg.norm(want) > 1e-9          # the start is 2.7 deg off nadir: a real torque
        np.testing.assert_allclose(p.disturbance(), want, rtol=1e-9, atol=1e-20)


def test_earth_form_without_a_rate_needs_an_orbit():
    with pytest.raises(ScenarioError, match=r"disturbances.gravity_gradient_earth.orbit_rate_rad_s: required without "
                                            r"\[environment.orbit\]"):
        load("geo_hinf", {"disturbances.gravity_gradient_earth.orbit_rate_rad_s": None})
