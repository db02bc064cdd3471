"""The magnetorquers and the residual dipole (effectors/magnetorquers.py, residual_dipole.py; docs/spec.md
5.8.2, 5.8.3) against hand evaluations: m x A(q) B_N with A(q) written out here and B_N from the
environment's IGRF along the orbit; the per-rod saturation; the torque perpendicular to B at every
evaluation and in the momentum the body receives (issue 21 acceptance).
"""
import math

import numpy as np
import pytest

from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors.magnetorquers import Magnetorquers

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


def test_the_torque_is_always_perpendicular_to_the_field(monkeypatch):
    """Issue 21 acceptance. (1) The torque the integrator gets (derivative), at 2000 random attitudes, times
    and dipoles: tau . B_B = 0 to rounding, B_B = A(q) B_N(t) with A written out here. (2) In a run with the
    field swinging along the orbit, at every RK4 stage the integrator evaluated: tau . A(q) B_N(t) with the
    environment's exact field at the stage's time (the model between grid points is linear: 1e-6 of |B|)."""
    p = _plant()
    e = next(x for x in p.effectors if x.kind == "magnetorquers")
    rng = np.random.default_rng(7)
    worst = 0.0
    for _ in range(2000):
        q = rng.normal(size=4)
        q /= np.linalg.norm(q)
        t = rng.uniform(0.0, 5000.0)
        e.command({"u_dipole_am2": tuple(rng.uniform(-1.5, 1.5, size=3))})
        tau, xdot = e.derivative(t, tuple(q) + (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        assert xdot == tau
        b_b = _A(q) @ np.array(e.field(t))
        worst = max(worst, abs(np.dot(tau, b_b)) / (np.linalg.norm(tau) * np.linalg.norm(b_b)))
    assert worst < 1e-14, worst
    # (2) the stages of a run: the class's derivative wrapped before the plant binds it
    stages = []
    inner = Magnetorquers.derivative

    def recorded(self, t, body, x):
        tau, xdot = inner(self, t, body, x)
        stages.append((t, np.array(body[:4]), np.array(tau)))
        return tau, xdot
    monkeypatch.setattr(Magnetorquers, "derivative", recorded)
    p = _plant()
    for _ in range(300):
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_dipole_am2": tuple(rng.uniform(-1.0, 1.0, size=3))})
        p.advance()
    assert len(stages) == 4 * 300
    worst = 0.0
    for t, q, tau in stages:
        b_b = _A(q / np.linalg.norm(q)) @ _b_n(p, t)
        worst = max(worst, abs(tau @ b_b) / (np.linalg.norm(tau) * np.linalg.norm(b_b)))
    print(f"worst |cos(tau, B)| over {len(stages)} RK4 stages: {worst:.1e}")
    assert worst < 1e-7, worst        # the linear field between grid points: (2 n dt)^2 / 8 = 6e-9


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


def test_applied_is_the_mean_torque_the_body_received():
    """From rest, one period: w(dt) = J^-1 (mean torque) dt to second order; the mean torque is the truth's
    "applied" (the magnetorquers' share of it) and the midpoint torque m x A(q) B_N(mid) to 1e-6."""
    sc = load("irassi_large", {"environment": ENV, "magnetorquers": {"max_dipole_am2": 50.0}, "disturbances": None,
                               "plant.w0": [0.0, 0.0, 0.0]})
    p = Plant(sc)
    m = np.array([30.0, -20.0, 45.0])
    p.apply({"u_body": (0.0, 0.0, 0.0), "u_dipole_am2": tuple(m)})
    p.advance()
    applied = np.array(p.truth()["applied"])
    J = np.array(sc.attitude.inertia)
    np.testing.assert_allclose(np.array(p.body.w), np.linalg.solve(J, applied) * p.dt, rtol=1e-9, atol=1e-22)
    mid = np.cross(m, _A(sc.attitude.q0) @ (0.5 * (_b_n(p, 0.0) + _b_n(p, p.dt))))
    np.testing.assert_allclose(applied, mid, rtol=1e-6)
    # the next period's mean torque is that period's (the impulse's change, not its running total)
    w1 = np.array(p.body.w)
    p.advance()
    applied2 = np.array(p.truth()["applied"])
    np.testing.assert_allclose(np.array(p.body.w) - w1, np.linalg.solve(J, applied2) * p.dt, rtol=1e-6, atol=1e-22)
    np.testing.assert_allclose(applied2, applied, rtol=1e-2)          # the field barely moved in one period


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


def test_rod_axes_are_refused_exactly_when_they_do_not_span():
    """Generic axes (no zero entry, so every term of the determinant counts): three rods in one plane are
    refused, three independent ones accepted, against numpy's determinant."""
    rng = np.random.default_rng(21)
    for _ in range(5):
        r0, r1 = (v / np.linalg.norm(v) for v in rng.normal(size=(2, 3)))
        r2 = 0.6 * r0 - 0.8 * r1
        r2 /= np.linalg.norm(r2)
        assert abs(np.linalg.det(np.array([r0, r1, r2]))) < 1e-12
        with pytest.raises(ScenarioError, match=r"magnetorquers.axes: the three rod axes do not span"):
            load("irassi_large", {"magnetorquers": {"max_dipole_am2": 1.0, "axes": [*r0, *r1, *r2]}})
        q, _ = np.linalg.qr(rng.normal(size=(3, 3)))
        sc = load("irassi_large", {"magnetorquers": {"max_dipole_am2": 1.0, "axes": [float(x) for x in q.T.ravel()]}})
        assert sc is not None


def test_residual_dipole_section_errors():
    with pytest.raises(ScenarioError, match=r"residual_dipole.dipole_am2: expected 3 numbers"):
        load("irassi_large", {"residual_dipole": {"dipole_am2": [1.0, 2.0]}})
    with pytest.raises(ScenarioError, match=r"\[residual_dipole\] does not apply to a orbit scenario"):
        load("landsat8_q1", {"residual_dipole": {"dipole_am2": [1.0, 2.0, 3.0]}})
