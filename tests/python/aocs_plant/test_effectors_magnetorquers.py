"""The magnetorquers and the residual dipole (effectors/magnetorquers.py, residual_dipole.py; docs/spec.md
5.8.2, 5.8.3) against hand evaluations: m x A(q) B_N with A(q) written out here and B_N from the
environment's IGRF along the orbit; the per-rod saturation; the torque perpendicular to B at every
evaluation and in the momentum the body receives (issue 21 acceptance).
"""
import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load

ENV = {"epoch_utc": "2026-06-21T06:00:00Z", "magnetic_field": {"model": "igrf"},
       "orbit": {"radius_m": 6878137.0, "inclination_deg": 97.4, "raan_deg": 170.0, "arg_latitude0_deg": 20.0}}
MAX = [0.8, 1.0, 1.2]


def _A(q):
    """A(q) = (q4^2 - |v|^2) I + 2 v v^T - 2 q4 [v x] (Markley & Crassidis eq. 2.125), written out."""
    v, q4 = np.array(q[:3]), q[3]
    vx = np.array([[0, -v[2], v[1]], [v[2], 0, -v[0]], [-v[1], v[0], 0]])
    return (q4 * q4 - v @ v) * np.eye(3) + 2 * np.outer(v, v) - 2 * q4 * vx


def _plant(sid="irassi_large", env=ENV, w0=(0.002, -0.003, 0.001), **extra):
    ov = {"environment": env, "magnetorquers": {"max_dipole_am2": MAX}, "disturbances": None,
          "plant.w0": list(w0)}
    ov.update(extra)
    return Plant(load(sid, ov))


def _b_n(p, t):
    env = p.environment
    return np.array(env.magnetic_field(t, env.orbit_state(t)[0]))


def test_torque_against_a_hand_evaluation_and_the_rod_saturation():
    p = _plant()
    for _ in range(25):
        p.advance()
    u = (0.5, -1.7, 3.0)
    p.apply({"u_body": (0.0, 0.0, 0.0), "u_dipole_am2": u})
    tr = p.truth()["effectors"]
    m = np.array([0.5, -1.0, 1.2])                     # clipped at 0.8, 1.0, 1.2 per rod
    np.testing.assert_array_equal(tr["magnetorquers.dipole_am2"], m)
    assert tr["magnetorquers.saturated"] == (False, True, True)
    b_b = _A(p.body.q) @ _b_n(p, p.t)
    np.testing.assert_allclose(tr["magnetorquers.field_b_t"], b_b, rtol=1e-13, atol=1e-20)
    want = np.cross(m, b_b)
    np.testing.assert_allclose(tr["magnetorquers.torque_nm"], want, rtol=1e-12, atol=1e-20)
    assert np.linalg.norm(want) > 1e-6                 # ~1 A m^2 x ~3e-5 T


def test_skewed_rods():
    s = 1 / math.sqrt(2)
    axes = [s, s, 0.0, -s, s, 0.0, 0.0, 0.0, 1.0]
    p = _plant(magnetorquers={"max_dipole_am2": 2.0, "axes": axes})
    p.apply({"u_dipole_am2": (1.0, 0.5, -0.25)})
    tr = p.truth()["effectors"]
    m_b = 1.0 * np.array(axes[0:3]) + 0.5 * np.array(axes[3:6]) - 0.25 * np.array(axes[6:9])
    np.testing.assert_allclose(tr["magnetorquers.dipole_b_am2"], m_b, rtol=1e-15, atol=1e-16)
    np.testing.assert_allclose(tr["magnetorquers.torque_nm"], np.cross(m_b, _A(p.body.q) @ _b_n(p, 0.0)),
                               rtol=1e-12, atol=1e-20)


def test_the_torque_is_always_perpendicular_to_the_field():
    """Issue 21 acceptance. (1) The term the integrator calls, at 2000 random attitudes, times and dipoles:
    tau . B_B = 0 to rounding, B_B = A(q) B_N(t) with A written out here. (2) The momentum the body gets over
    a period (one substep, B_N frozen at its midpoint): Delta H_N = Delta(A^T J w) is perpendicular to
    B_N(mid) to RK4's tolerance, while it is not small."""
    p = _plant()
    e = next(x for x in p.effectors if x.kind == "magnetorquers")
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(2000):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        t = rng.uniform(0.0, 5000.0)
        e.command({"u_dipole_am2": tuple(rng.uniform(-1.5, 1.5, size=3))})
        e.at_time(t)
        tau = np.array(e.term()(*q))
        b_b = _A(q) @ np.array(e.field(t))
        worst = max(worst, abs(tau @ b_b) / (np.linalg.norm(tau) * np.linalg.norm(b_b)))
    assert worst < 1e-14, worst
    # (2) in the body's motion, the field's direction swinging along the orbit
    sc = p.scenario
    J = np.array(sc.attitude.inertia)
    assert sc.substeps == 1
    worst = 0.0
    for k in range(300):
        t0 = p.t
        H0 = _A(p.body.q).T @ J @ np.array(p.body.w)
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_dipole_am2": tuple(rng.uniform(-1.0, 1.0, size=3))})
        p.advance()
        dH = _A(p.body.q).T @ J @ np.array(p.body.w) - H0
        b_mid = 0.5 * (_b_n(p, t0) + _b_n(p, t0 + p.dt))
        worst = max(worst, abs(dH @ b_mid) / (np.linalg.norm(dH) * np.linalg.norm(b_mid)))
        assert np.linalg.norm(dH) > 1e-8
    print(f"worst |cos| between the period's momentum change and B: {worst:.1e}")
    assert worst < 1e-6, worst


def test_without_a_field_the_torque_is_zero():
    p = _plant(env=None)                              # no orbit, no model
    p.apply({"u_dipole_am2": (1.0, 1.0, 1.0)})
    tr = p.truth()["effectors"]
    assert tr["magnetorquers.torque_nm"] == (0.0, 0.0, 0.0) and tr["magnetorquers.field_b_t"] == (0.0, 0.0, 0.0)
    p.advance()
    free = _plant(env=None, magnetorquers=None)        # the same body with no magnetorquers: bit for bit
    free.advance()
    assert p.body.w == free.body.w and p.body.q == free.body.q


def test_dipole_seconds_and_the_plain_actuator_keeps_its_command():
    p = _plant()
    for _ in range(10):
        p.apply({"u_body": (0.1, 0.2, 0.3), "u_dipole_am2": (0.5, -0.25, 2.0)})
        p.advance()
    tr = p.truth()
    assert tr["commanded"] == (0.1, 0.2, 0.3)        # truth's "commanded" is the body actuator's
    np.testing.assert_allclose(tr["effectors"]["magnetorquers.dipole_s_am2s"], [0.5, 0.25, 1.2], rtol=1e-14)


def test_residual_dipole_torque_against_a_hand_evaluation():
    m = np.array([0.05, -0.02, 0.1])
    p = _plant(residual_dipole={"dipole_am2": m.tolist()}, magnetorquers=None)
    for _ in range(13):
        p.advance()
    want = np.cross(m, _A(p.body.q) @ _b_n(p, p.t))
    np.testing.assert_allclose(p.truth()["effectors"]["residual_dipole.torque_nm"], want, rtol=1e-12, atol=1e-22)
    np.testing.assert_allclose(p.disturbance(), want, rtol=1e-12, atol=1e-22)
    # the plant feels it: from rest, one period, w(dt) = J^-1 tau dt with tau at the period's midpoint field
    sc = load("irassi_large", {"environment": ENV, "residual_dipole": {"dipole_am2": [5.0, 0.0, 0.0]},
                               "disturbances": None, "plant.w0": [0.0, 0.0, 0.0]})
    p = Plant(sc)
    tau = np.cross([5.0, 0.0, 0.0], _A(p.body.q) @ (0.5 * (_b_n(p, 0.0) + _b_n(p, p.dt))))
    p.advance()
    J = np.array(sc.attitude.inertia)
    np.testing.assert_allclose(np.array(p.body.w), np.linalg.solve(J, tau) * p.dt, rtol=1e-6, atol=1e-20)
    # disabled, or without a field: nothing
    p = _plant(residual_dipole={"dipole_am2": [1.0, 0.0, 0.0], "enabled": False}, magnetorquers=None)
    assert "residual_dipole" not in [e.kind for e in p.effectors]
    p = _plant(env=None, residual_dipole={"dipole_am2": [1.0, 0.0, 0.0]}, magnetorquers=None)
    assert p.disturbance() == (0.0, 0.0, 0.0)


@pytest.mark.parametrize("sec,match", [
    ({"max_dipole_am2": [1.0, -1.0, 1.0]}, r"magnetorquers.max_dipole_am2\[1\]: must be > 0"),
    ({}, r"magnetorquers.max_dipole_am2: missing required key"),
    ({"max_dipole_am2": 1.0, "axes": [1, 0, 0, 0, 1, 0, 0, 0, 2]},
     r"magnetorquers.axes: vector 2 \(0, 0, 2\) is not a unit vector"),
    ({"max_dipole_am2": 1.0, "axes": [1, 0, 0, 0, 1, 0, 1, 0, 0]}, r"magnetorquers.axes: the three rod axes do not span"),
    ({"max_dipole_am2": 1.0, "rods": 3}, r"magnetorquers.rods: unknown key"),
])
def test_section_errors_name_the_key(sec, match):
    with pytest.raises(ScenarioError, match=match):
        load("irassi_large", {"magnetorquers": sec})


def test_residual_dipole_section_errors():
    with pytest.raises(ScenarioError, match=r"residual_dipole.dipole_am2: expected 3 numbers"):
        load("irassi_large", {"residual_dipole": {"dipole_am2": [1.0, 2.0]}})
    with pytest.raises(ScenarioError, match=r"\[residual_dipole\] does not apply to a orbit scenario"):
        load("landsat8_q1", {"residual_dipole": {"dipole_am2": [1.0, 2.0, 3.0]}})
