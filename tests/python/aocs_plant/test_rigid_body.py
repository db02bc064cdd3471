"""Rigid-body plant: conventions, conservation laws, accuracy and order of RK4.

Expected values come from independent evaluations (elementary rotation
matrices written out here, closed-form motions, scipy's adaptive integrator),
never from the implementation's own output.
"""
import math

import numpy as np
import pytest

from aocs_core.conventions import (
    crp_to_quat,
    euler321_deg_to_quat,
    mrp_to_quat,
    quat_from_rotvec,
    quat_mul,
    quat_normalize,
    quat_to_crp,
    quat_to_dcm,
    quat_to_euler321,
    quat_to_mrp,
)
from aocs_plant.rigid_body import RigidBody, body_derivative, reference_propagate, rk4_step, sum_terms

GAO_J = [[42.0, 1.8, -1.5], [1.8, 25.0, -1.2], [-1.5, -1.2, 61.8]]


def A1(a):  # frame rotation about x (attitude matrix, N -> B)
    c, s = math.cos(a), math.sin(a)
    return np.array([[1, 0, 0], [0, c, s], [0, -s, c]])


def A2(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0, -s], [0, 1, 0], [s, 0, c]])


def A3(a):
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, s, 0], [-s, c, 0], [0, 0, 1]])


def rand_quat(rng):
    return quat_normalize(tuple(rng.standard_normal(4)))


# ----------------------------------------------------------------- conventions (SPEC 1)

def test_dcm_of_elementary_rotation_matches_frame_rotation_matrix():
    a = 0.7
    q = (math.sin(a / 2), 0.0, 0.0, math.cos(a / 2))
    np.testing.assert_allclose(np.array(quat_to_dcm(q)), A1(a), atol=1e-15)
    q = (0.0, 0.0, math.sin(a / 2), math.cos(a / 2))
    np.testing.assert_allclose(np.array(quat_to_dcm(q)), A3(a), atol=1e-15)


def test_shuster_product_composes_attitude_matrices():
    rng = np.random.default_rng(1)
    for _ in range(20):
        q, p = rand_quat(rng), rand_quat(rng)
        lhs = np.array(quat_to_dcm(quat_mul(q, p)))
        rhs = np.array(quat_to_dcm(q)) @ np.array(quat_to_dcm(p))
        np.testing.assert_allclose(lhs, rhs, atol=1e-14)


def test_euler321_is_roll_pitch_yaw_product_and_round_trips():
    yaw, pitch, roll = 30.0, -20.0, 1.0
    q = euler321_deg_to_quat([yaw, pitch, roll])
    expected = A1(math.radians(roll)) @ A2(math.radians(pitch)) @ A3(math.radians(yaw))
    np.testing.assert_allclose(np.array(quat_to_dcm(q)), expected, atol=1e-15)
    back = np.degrees(quat_to_euler321(q))
    np.testing.assert_allclose(back, [yaw, pitch, roll], atol=1e-12)


def test_crp_and_mrp_conversions():
    rho = (-10.0, 15.0, 15.0)
    q = crp_to_quat(rho)
    d = math.sqrt(1 + 100 + 225 + 225)
    np.testing.assert_allclose(q, (-10 / d, 15 / d, 15 / d, 1 / d), rtol=1e-15)
    np.testing.assert_allclose(quat_to_crp(q), rho, rtol=1e-13)
    sigma = (-0.3, -0.4, 0.2)
    q = mrp_to_quat(sigma)
    assert abs(math.fsum(x * x for x in q) - 1.0) < 1e-15
    np.testing.assert_allclose(np.array(q[:3]) / (1 + q[3]), sigma, rtol=1e-15)
    np.testing.assert_allclose(quat_to_mrp(q), sigma, rtol=1e-15)
    # the other sign of the same attitude maps to the same |sigma| <= 1 set
    np.testing.assert_allclose(quat_to_mrp(tuple(-x for x in q)), sigma, rtol=1e-15)


def test_kinematics_for_constant_rate_is_the_closed_form_rotation():
    # w along a principal axis stays constant without torque; then
    # A(t) = exp(-[w x] t) A(0), i.e. q(t) = dq(w t) (x) q0 (SPEC 1 qdot = 0.5 Xi(q) w)
    J = [[2.0, 0, 0], [0, 3.0, 0], [0, 0, 4.0]]
    q0 = quat_normalize((0.1, -0.3, 0.5, 0.8))
    w = (0.0, 0.8, 0.0)
    body = RigidBody(J, q0, w)
    body.propagate(5.0, 500)
    expected = quat_mul(quat_from_rotvec((0.0, 0.8 * 5.0, 0.0)), q0)
    np.testing.assert_allclose(body.q, expected, atol=1e-11)
    np.testing.assert_allclose(body.w, w, atol=1e-15)
    # and the sense of rotation: dA/dt = -[w x] A, checked by a finite difference
    h = 1e-6
    b2 = RigidBody(J, q0, w)
    b2.propagate(h, 1)
    dA = (np.array(quat_to_dcm(b2.q)) - np.array(quat_to_dcm(q0))) / h
    wx = np.array([[0, -w[2], w[1]], [w[2], 0, -w[0]], [-w[1], w[0], 0]])
    np.testing.assert_allclose(dA, -wx @ np.array(quat_to_dcm(q0)), atol=1e-6)


# ----------------------------------------------------------------- dynamics

def test_constant_torque_gives_wdot_equal_to_inverse_inertia_times_torque():
    # full J at rest: wdot = J^-1 u (the gyroscopic term vanishes at w = 0)
    u = (0.02, -0.01, 0.03)
    body = RigidBody(GAO_J, (0, 0, 0, 1), (0, 0, 0))
    _, wdot = body.derivative((0, 0, 0, 1), (0, 0, 0), u)
    np.testing.assert_allclose(wdot, np.linalg.solve(np.array(GAO_J), u), rtol=1e-14)
    # principal-axis torque on a diagonal J: w x J w stays 0, so w(T) = u T / J_i exactly
    J = [[2059.5, 0, 0], [0, 5954.2, 0], [0, 0, 5974.3]]
    body = RigidBody(J, (0, 0, 0, 1), (0, 0, 0))
    body.propagate(10.0, 10, torque=(0.0, 1.18e-3, 0.0))
    np.testing.assert_allclose(body.w, (0.0, 1.18e-3 * 10.0 / 5954.2, 0.0), rtol=1e-13, atol=1e-20)


def test_torque_free_body_conserves_energy_and_inertial_momentum():
    q0 = quat_normalize((0.2, -0.4, 0.1, 0.8))
    body = RigidBody(GAO_J, q0, (0.3, -0.2, 0.5))  # tumbling, |w| ~ 0.6 rad/s
    T0, H0 = body.kinetic_energy(), body.momentum_inertial()
    body.propagate(1000.0, 50000)                  # h = 0.02 s, ~100 revolutions
    # RK4 is not conservative: the drift is its truncation error, ~6e-11 here
    assert abs(body.kinetic_energy() - T0) / T0 < 1e-9
    assert np.linalg.norm(body.momentum_inertial() - H0) / np.linalg.norm(H0) < 1e-9
    assert abs(math.fsum(x * x for x in body.q) - 1.0) < 1e-14


def _error(J, q0, w0, duration, n, qr, wr):
    body = RigidBody(J, q0, w0)
    body.propagate(duration, n)
    q = np.array(body.q)
    return min(np.linalg.norm(q - qr), np.linalg.norm(q + qr)) + np.linalg.norm(np.array(body.w) - wr)


def test_rk4_matches_adaptive_reference_and_converges_with_order_four():
    q0 = quat_normalize((0.2, -0.4, 0.1, 0.8))
    w0 = (0.3, -0.2, 0.5)
    u = (0.01, 0.02, -0.01)
    duration = 10.0
    qr, wr = reference_propagate(GAO_J, q0, w0, duration)
    body = RigidBody(GAO_J, q0, w0)
    body.propagate(duration, 100, torque=u)  # a torque changes the answer: the reference must see it
    qu, _ = reference_propagate(GAO_J, q0, w0, duration, torque=u)
    assert min(np.linalg.norm(np.array(body.q) - qu), np.linalg.norm(np.array(body.q) + qu)) < 1e-6
    errs = [_error(GAO_J, q0, w0, duration, n, qr, wr) for n in (25, 50, 100, 200)]
    assert errs[2] < 1e-6          # h = 0.1 s at |w| ~ 0.6 rad/s
    orders = [math.log2(errs[i] / errs[i + 1]) for i in range(3)]
    for p in orders:
        assert 3.6 < p < 4.4, orders


def _xi(q):
    q1, q2, q3, q4 = q
    return np.array([[q4, -q3, q2], [q3, q4, -q1], [-q2, q1, q4], [-q1, -q2, -q3]])


def _hand_rhs(J, term):
    """SPEC 1.2 and 1.6 with numpy: qdot = 0.5 Xi(q) w, wdot = J^-1 (u + g(q) - w x J w)."""
    J = np.asarray(J, float)

    def rhs(y, u):
        q, w = y[:4], y[4:]
        g = np.array(term(*q)) if term is not None else 0.0
        return np.concatenate([0.5 * _xi(q) @ w, np.linalg.solve(J, u + g - np.cross(w, J @ w))])
    return rhs


def _torque_term(q1, q2, q3, q4):  # some attitude-only torque
    return (0.01 * q1 * q4, -0.02 * q2 * q3, 0.005 * (q3 - q1))


@pytest.mark.parametrize("J", [GAO_J, [[2059.5, 0, 0], [0, 5954.2, 0], [0, 0, 5974.3]], np.eye(3).tolist()])
@pytest.mark.parametrize("term", [None, _torque_term])
def test_derivative_and_rk4_step_against_a_hand_evaluation(J, term):
    """Every variant of the closure (diagonal / full inertia, with / without an attitude term)."""
    rng = np.random.default_rng(3)
    body = RigidBody(J, (0, 0, 0, 1), (0, 0, 0))
    f = body_derivative(body.J, body.Ji, term)
    rhs = _hand_rhs(J, term)
    for _ in range(10):
        q, w = rand_quat(rng), tuple(rng.standard_normal(3))
        u = rng.standard_normal(3)
        y = np.array(q + w)
        np.testing.assert_allclose(f(*q, *w, *u), rhs(y, u), rtol=1e-13, atol=1e-15)
        h = 0.05
        k1 = rhs(y, u)
        k2 = rhs(y + h / 2 * k1, u)
        k3 = rhs(y + h / 2 * k2, u)
        k4 = rhs(y + h * k3, u)
        yn = y + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        qn, wn = rk4_step(q, w, h, tuple(u), body.J, body.Ji, term)
        np.testing.assert_allclose(qn, yn[:4] / np.linalg.norm(yn[:4]), rtol=0, atol=1e-14)
        np.testing.assert_allclose(wn, yn[4:], rtol=1e-13, atol=1e-15)


def test_sum_terms_adds_the_closures():
    assert sum_terms([]) is None
    assert sum_terms([_torque_term]) is _torque_term
    both = sum_terms([_torque_term, lambda a, b, c, d: (1.0, 2.0, 3.0)])
    q = (0.1, 0.2, 0.3, math.sqrt(0.86))
    np.testing.assert_allclose(both(*q), np.array(_torque_term(*q)) + (1.0, 2.0, 3.0), rtol=1e-15)


@pytest.mark.parametrize("n", [1, 3])
def test_propagate_with_substeps_equals_repeated_steps(n):
    body = RigidBody(GAO_J, (0, 0, 0, 1), (0.1, 0.0, -0.1))
    q, w = body.q, body.w
    for _ in range(n):
        q, w = rk4_step(q, w, 0.1 / n, (0, 0, 0), body.J, body.Ji)
    body.propagate(0.1, n)
    assert body.q == q and body.w == w
