"""The reaction wheel array (aocs_plant/effectors/reaction_wheels.py, SPEC 5.3) against independent
evaluations: the pyramid geometry written out, conservation of the total inertial momentum
H_N = A(q)^T (J_b w + Gs h) and of the kinetic energy, the friction's dissipation, the limits.
"""
import math

import numpy as np
import pytest

from aocs_core.conventions import quat_to_dcm
from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors.reaction_wheels import PYRAMID_CANT_DEG, ReactionWheels

GAO_J = np.array([[42.0, 1.8, -1.5], [1.8, 25.0, -1.2], [-1.5, -1.2, 61.8]])
JS = 0.08
WMAX = 600.0
UMAX = 0.25


def _wheels(**kw):
    sec = {"array": "pyramid", "pyramid_axis": "z", "spin_inertia_kg_m2": JS, "torque_limit_nm": UMAX,
           "speed_limit_rad_s": WMAX}
    sec.update(kw)
    return {k: v for k, v in sec.items() if v is not None}


def _plant(substeps=4, w0=(0.05, -0.08, 0.12), **kw):
    return Plant(load("gao_mrp", {"wheels": _wheels(**kw), "plant.w0": list(w0), "integrator.substeps": substeps}))


def _gs(plant):
    return np.array(plant.actuator.g).T          # 3 x N


def _state(plant):
    e = plant.actuator
    return np.array(plant.body.q), np.array(plant.body.w), np.array(plant.effector_state(e))


def _H_N(plant):
    q, w, h = _state(plant)
    J_b = np.array(plant.body.J).reshape(3, 3)
    return np.array(quat_to_dcm(tuple(q))).T @ (J_b @ w + _gs(plant) @ h)


def _energy(plant):
    """T = 1/2 w^T J_b w + sum h_i^2 / (2 Js_i) (body plus wheels, Schaub & Junkins 4.5)."""
    _, w, h = _state(plant)
    J_b = np.array(plant.body.J).reshape(3, 3)
    return 0.5 * w @ J_b @ w + 0.5 * np.sum(h * h / np.array(plant.actuator.js))


def test_the_reference_pyramid_is_spec_5_3():
    p = _plant()
    G = _gs(p)
    assert G.shape == (3, 4)
    np.testing.assert_allclose(np.linalg.norm(G, axis=0), 1.0, rtol=0, atol=1e-15)
    # 54.7356 deg from the pyramid (z) axis ...
    np.testing.assert_allclose(np.degrees(np.arccos(G[2])), 54.7356, atol=1e-4)
    assert abs(PYRAMID_CANT_DEG - math.degrees(math.acos(1 / math.sqrt(3)))) < 1e-12
    # ... 90 deg apart around it, the first at azimuth 0 from x
    az = np.degrees(np.arctan2(G[1], G[0])) % 360.0
    np.testing.assert_allclose(az, [0.0, 90.0, 180.0, 270.0], atol=1e-9)
    # J_b = J - sum Js g g^T is the body's inertia
    np.testing.assert_allclose(np.array(p.body.J).reshape(3, 3), GAO_J - JS * G @ G.T, rtol=1e-15)
    # it replaces the plain actuator
    assert [e.kind for e in p.effectors] == ["wheels"]


def test_wheel_speeds_are_relative_to_the_body():
    p = _plant(speed0_rad_s=[100.0, -50.0, 20.0, 0.0])
    _, w, h = _state(p)
    G = _gs(p)
    np.testing.assert_allclose(h, JS * (G.T @ w + np.array([100.0, -50.0, 20.0, 0.0])), rtol=1e-15)
    tr = p.truth()["effectors"]
    np.testing.assert_allclose(tr["wheels.speed_rad_s"], [100.0, -50.0, 20.0, 0.0], rtol=1e-13)
    # total momentum H = J w + sum Js g Omega (the scenario's J includes the wheels)
    np.testing.assert_allclose(tr["wheels.momentum_total_nms"],
                               GAO_J @ w + JS * G @ np.array([100.0, -50.0, 20.0, 0.0]), rtol=1e-13)


def _drive(p, periods, every=100):
    """Free tumbling, the motors driven by a varying internal command (no external torque)."""
    H0, T0 = _H_N(p), _energy(p)
    drift = 0.0
    for k in range(periods):
        t = p.t
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.2 * math.sin(0.05 * t), -0.15 * math.cos(0.031 * t),
                                                         0.1 * math.sin(0.017 * t + 1.0), 0.05)})
        p.advance()
        if k % every == 0 or k == periods - 1:
            drift = max(drift, abs(np.linalg.norm(_H_N(p)) - np.linalg.norm(H0)) / np.linalg.norm(H0))
    return H0, T0, drift


def test_total_inertial_momentum_is_conserved_over_1000_s_of_free_tumbling():
    """SPEC 5.3 acceptance: relative drift of |H| < 1e-8 over 1000 s; RK4, 10 Hz, 4 substeps (h = 0.025 s)."""
    p = _plant(speed0_rad_s=[300.0, -200.0, 150.0, 50.0])
    h_start = np.array(p.effector_state(p.actuator))
    H0, _, drift = _drive(p, 10000)
    assert drift < 1e-8, drift
    # the components too, not only the norm
    assert np.linalg.norm(_H_N(p) - H0) / np.linalg.norm(H0) < 1e-8
    # the exchange was real: wheel momenta moved by N m s
    assert np.abs(np.array(p.effector_state(p.actuator)) - h_start).max() > 1.0
    # it is RK4's error: a coarser step (1 substep, h = 0.1 s) drifts more
    _, _, coarse = _drive(_plant(substeps=1, speed0_rad_s=[300.0, -200.0, 150.0, 50.0]), 10000)
    assert coarse > drift


def test_energy_is_conserved_with_the_motors_off_and_friction_dissipates_it():
    p = _plant(speed0_rad_s=[300.0, -200.0, 150.0, 50.0])
    T0, H0 = _energy(p), _H_N(p)
    for _ in range(5000):
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.0, 0.0, 0.0, 0.0)})
        p.advance()
    assert abs(_energy(p) - T0) / T0 < 1e-9
    # friction on: the energy falls, the momentum stays (friction is internal)
    p = _plant(speed0_rad_s=[300.0, -200.0, 150.0, 50.0], viscous_nms=1e-4, coulomb_nm=2e-3)
    T0, H0 = _energy(p), _H_N(p)
    last = T0
    for _ in range(50):
        for _ in range(100):
            p.advance()
        T = _energy(p)
        assert T < last
        last = T
    assert (T0 - last) / T0 > 1e-3
    assert np.linalg.norm(_H_N(p) - H0) / np.linalg.norm(H0) < 1e-8


def test_friction_is_viscous_plus_smooth_coulomb():
    p = _plant(viscous_nms=2e-4, coulomb_nm=3e-3, coulomb_width_rad_s=0.5)
    e = p.actuator
    om = (100.0, -0.2, 0.0, -40.0)
    tau = e.axial_torques(om)
    expect = [-(2e-4 * o + 3e-3 * math.tanh(o / 0.5)) for o in om]
    np.testing.assert_allclose(tau, expect, rtol=1e-15, atol=0)


def test_applied_torque_is_the_reaction_of_the_motors():
    """Motors only (no friction, body at rest): over a period the body receives -Gs u exactly."""
    p = _plant(w0=(0.0, 0.0, 0.0))
    u = np.array([0.1, -0.2, 0.05, 0.3])             # the last one beyond the 0.25 N m limit
    p.apply({"u_body": (1.0, 2.0, 3.0), "u_wheels": tuple(u)})
    p.advance()
    clipped = np.array([0.1, -0.2, 0.05, 0.25])
    np.testing.assert_allclose(p.applied, -_gs(p) @ clipped, rtol=1e-12, atol=1e-15)
    tr = p.truth()
    assert tr["commanded"] == (1.0, 2.0, 3.0)
    assert tr["effectors"]["wheels.at_torque_limit"] == (False, False, False, True)
    np.testing.assert_allclose(tr["effectors"]["wheels.motor_torque_nm"], clipped)
    # the same from spinning wheels: the period's mean torque is the change of h over it, not h itself
    p = _plant(w0=(0.0, 0.0, 0.0), speed0_rad_s=[100.0, -50.0, 20.0, 0.0])
    p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": tuple(u)})
    p.advance()
    np.testing.assert_allclose(p.applied, -_gs(p) @ clipped, rtol=1e-9, atol=1e-12)


def test_a_failed_wheel_gives_no_torque():
    p = _plant(w0=(0.0, 0.0, 0.0), failed=[1])
    p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (0.1, 0.2, 0.1, 0.1)})
    p.advance()
    np.testing.assert_allclose(p.applied, -_gs(p) @ np.array([0.1, 0.0, 0.1, 0.1]), rtol=1e-12, atol=1e-15)


def test_no_motor_torque_drives_a_wheel_beyond_its_speed_limit():
    p = _plant(w0=(0.0, 0.0, 0.0), speed0_rad_s=[590.0, 0.0, 0.0, 0.0])
    h = 0.1 / 4
    peak = 0.0
    for _ in range(300):                              # 0.25 N m on a 0.08 kg m^2 wheel: 3 rad/s^2
        p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (UMAX, 0.0, 0.0, 0.0)})
        p.advance()
        peak = max(peak, abs(p.truth()["effectors"]["wheels.speed_rad_s"][0]))
    # the motor is cut at the stage where |Omega| reaches the limit: at most one step's increment past it
    assert WMAX - 1.0 < peak <= WMAX + UMAX / JS * h, peak
    assert p.truth()["effectors"]["wheels.at_speed_limit"][0]
    # braking is still allowed
    p.apply({"u_body": (0.0, 0.0, 0.0), "u_wheels": (-UMAX, 0.0, 0.0, 0.0)})
    p.advance()
    assert p.truth()["effectors"]["wheels.speed_rad_s"][0] < peak - 0.2


def test_the_motor_is_cut_at_exactly_the_speed_limit_in_either_direction():
    """axial_torques at |Omega| = Omega_max exactly: a motor torque that would speed the wheel up is cut (the
    bearing alone acts), one that brakes it is not; just below the limit the motor acts."""
    p = _plant(viscous_nms=2e-4, coulomb_nm=3e-3, coulomb_width_rad_s=0.5)
    e = p.actuator

    def friction(o):
        return 2e-4 * o + 3e-3 * math.tanh(o / 0.5)

    e.u = (0.2, -0.2, 0.2, -0.2)
    om = (WMAX, -WMAX, -WMAX, WMAX)                   # the first two speed up, the last two brake
    np.testing.assert_allclose(e.axial_torques(om), [-friction(o) for o in om[:2]] +
                               [0.2 - friction(om[2]), -0.2 - friction(om[3])], rtol=1e-15, atol=0)
    below = math.nextafter(WMAX, 0.0)
    om = (below, -below, 0.0, 0.0)
    np.testing.assert_allclose(e.axial_torques(om)[:2], [0.2 - friction(below), -0.2 + friction(below)],
                               rtol=1e-15, atol=0)


def test_tachometers_in_the_sensor_sample():
    p = _plant(speed0_rad_s=[123.456, -7.0, 0.0, 1.0], tach_quantum_rad_s=0.1)
    s = p.sense()
    np.testing.assert_allclose(s["wheel_speed"], [123.5, -7.0, 0.0, 1.0], atol=1e-12)
    p = _plant(speed0_rad_s=[10.0, 0.0, 0.0, 0.0], tach_noise_rad_s=0.5)
    reads = []
    for _ in range(400):
        reads.append(p.sense()["wheel_speed"])
        p.advance()
    r = np.array(reads)
    assert 0.4 < r[:, 1].std() < 0.6 and abs(r[:, 1].mean()) < 0.1
    # seeded: the same run gives the same readings
    p2 = _plant(speed0_rad_s=[10.0, 0.0, 0.0, 0.0], tach_noise_rad_s=0.5)
    assert p2.sense()["wheel_speed"] == tuple(reads[0])


def test_the_plain_scenarios_have_no_wheels():
    p = Plant(load("irassi_large"))
    assert not any(isinstance(e, ReactionWheels) for e in p.effectors)
    assert "wheel_speed" not in p.sense()


def test_a_body_lighter_than_its_wheels_is_refused_and_a_light_one_is_not():
    """J - sum Js g g^T must be positive definite (the plant integrates with it). The reference pyramid has
    sum g g^T = (4/3) I, so with Js = 0.08 the margin is J_ii - 0.1067 kg m^2 on a diagonal J: a small
    positive margin (0.49 kg m^2, below 1) loads and flies; a negative one is refused by key."""
    sum_ggT = 4.0 / 3.0 * JS
    light = [[0.6, 0.0, 0.0], [0.0, 0.7, 0.0], [0.0, 0.0, 0.8]]
    p = Plant(load("gao_mrp", {"wheels": _wheels(), "plant.inertia": light}))
    less = np.array(p.body.J).reshape(3, 3) - sum_ggT * np.eye(3)
    assert 0.0 < np.min(np.linalg.eigvalsh(less)) < 1.0
    too_light = [[0.1, 0.0, 0.0], [0.0, 0.7, 0.0], [0.0, 0.0, 0.8]]
    assert 0.1 - sum_ggT < 0.0
    with pytest.raises(ScenarioError, match=r"wheels.spin_inertia_kg_m2: 0.08 kg m\^2: the body inertia less the "
                                            r"wheels' spin inertia .* not positive definite"):
        load("gao_mrp", {"wheels": _wheels(), "plant.inertia": too_light})


def test_explicit_axes_and_section_errors():
    axes = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]
    r2 = math.sqrt(0.5)
    p = _plant(array="explicit", pyramid_axis=None, axes=axes)
    np.testing.assert_array_equal(_gs(p), np.eye(3))
    cases = [
        (dict(array="explicit", pyramid_axis=None, axes=[[1.0, 1.0, 0.0], [0, 1.0, 0], [0, 0, 1.0]]),
         r"wheels.axes\[0\]: must be a unit vector"),
        (dict(array="explicit", pyramid_axis=None, axes=[[1.0, 0, 0], [0, 1.0, 0], [0, 1.0, 0]]),
         r"wheels.axes: the spin axes do not span the three body axes"),
        # three axes in the plane x + y + z = 0 (none along a body axis: every term of det(Gs Gs^T) is non-zero)
        (dict(array="explicit", pyramid_axis=None, axes=[[r2, -r2, 0.0], [0.0, r2, -r2], [r2, 0.0, -r2]]),
         r"wheels.axes: the spin axes do not span the three body axes"),
        (dict(failed=[0, 2]), r"wheels.failed: the healthy wheels left do not span"),
        (dict(failed=[7]), r"wheels.failed: wheel 7 does not exist"),
        (dict(count=7), r"wheels.count: 7 wheels: the flight software holds at most 6"),
        (dict(speed0_rad_s=700.0), r"wheels.speed0_rad_s: wheel 0: \|700.0\| rad/s is beyond"),
        (dict(colour="red"), r"wheels.colour: unknown key"),
        (dict(torque_limit_nm=None), r"wheels.torque_limit_nm: missing required key"),
        (dict(axes=axes), r'wheels.axes: only with array = "explicit"'),
    ]
    for kw, msg in cases:
        with pytest.raises(ScenarioError, match=r"gao_mrp.toml: " + msg):
            _plant(**kw)
    with pytest.raises(ScenarioError, match=r"\[wheels\] does not apply to a orbit scenario"):
        load("landsat8_q1", {"wheels": _wheels()})


def test_derivative_is_the_reaction_of_the_axial_torques_bit_for_bit():
    """derivative() (speeds and axial torques fused in one loop for speed) against the equations written with
    numpy, -(w x Gs h) - Gs tau and dh/dt = tau, and exactly (==) the composition axial_torques(speeds()) that it
    replaced, over random states, one wheel at its speed limit (the motor cut, its flag set) and a failed one."""
    rng = np.random.default_rng(7)
    p = _plant(viscous_nms=2e-4, coulomb_nm=3e-3, coulomb_width_rad_s=0.5, failed=[2])
    e = p.actuator
    G = _gs(p)
    js = np.array(e.js)
    cuts = 0
    for k in range(200):
        q = rng.normal(size=4)
        w = rng.normal(scale=0.1, size=3)
        body = tuple(q / np.linalg.norm(q)) + tuple(w)
        om = rng.normal(scale=300.0, size=4)
        if k % 4 == 0:
            om[0] = WMAX + 1.0                           # beyond the limit, the motor pushing it further: cut
        e.command_wheels(tuple(rng.uniform(-0.3, 0.3, size=4)) if k % 4 else (0.2, 0.1, 0.1, -0.1))
        h = tuple(js * (om + G.T @ w))                    # Omega = h / Js - g . w, solved for h
        e.at_speed_limit = [False] * 4
        torque, tau = e.derivative(0.0, body, h)
        flags = list(e.at_speed_limit)
        e.at_speed_limit = [False] * 4
        assert tau == e.axial_torques(e.speeds(body, h))  # bit for bit, the flags too
        assert flags == e.at_speed_limit
        u = np.array(e.u)
        om = np.array(e.speeds(body, h))
        cut = (u * om > 0.0) & (np.abs(om) >= WMAX)
        assert flags == list(cut)
        cuts += int(cut[0])
        expect_tau = np.where(cut, 0.0, u) - (2e-4 * om + 3e-3 * np.tanh(om / 0.5))
        np.testing.assert_allclose(tau, expect_tau, rtol=1e-9, atol=1e-15)
        np.testing.assert_allclose(torque, -np.cross(w, G @ np.array(h)) - G @ expect_tau, rtol=1e-9, atol=1e-12)
    assert cuts >= 50                                     # every fourth state (at least) cut wheel 0's motor
