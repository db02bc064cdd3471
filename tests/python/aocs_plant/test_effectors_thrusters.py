"""The thrusters (aocs_plant/effectors/thrusters.py, docs/spec.md 5.8.1) against independent evaluations:
force and torque written out with numpy, the rate change of a pure couple, on-time quantisation and the
minimum impulse bit on hand-picked values, the propellant and impulse integrals, the seeded noise and
misalignment, and the momentum of body plus wheels with the thrusters off (issue 21 acceptance).
"""
import math
import re
import tomllib
from pathlib import Path

import numpy as np
import pytest

from aocs_core.conventions import quat_to_dcm
from aocs_plant import Plant, ScenarioError, load
from aocs_plant.effectors.thrusters import quantise_on_time

L = 1.2          # m, moment arm of the example layout
# the 12-thruster layout of docs/scenarios.md: six couples, two thrusters each, +x -x +y -y +z -z
POSITIONS = [0, L, 0, 0, -L, 0, 0, L, 0, 0, -L, 0,
             0, 0, L, 0, 0, -L, 0, 0, L, 0, 0, -L,
             L, 0, 0, -L, 0, 0, L, 0, 0, -L, 0, 0]
DIRECTIONS = [0, 0, 1, 0, 0, -1, 0, 0, -1, 0, 0, 1,
              1, 0, 0, -1, 0, 0, -1, 0, 0, 1, 0, 0,
              0, 1, 0, 0, -1, 0, 0, -1, 0, 0, 1, 0]
G0 = 9.80665


def _section(**kw):
    sec = {"thrust_n": 1.0, "positions_m": POSITIONS, "directions": DIRECTIONS, "min_on_time_s": 0.02,
           "on_time_quantum_s": 0.001, "isp_s": 220.0}
    sec.update(kw)
    return {k: v for k, v in sec.items() if v is not None}


def _plant(sid="irassi_large", seed=None, **kw):
    ov = {"thrusters": _section(**kw), "disturbances": None}
    if seed is not None:
        ov["seed"] = seed
    return Plant(load(sid, ov))


def _thrusters(p):
    return next(e for e in p.effectors if e.kind == "thrusters")


def _on(*pairs, n=12):
    c = [0.0] * n
    for i, v in pairs:
        c[i] = v
    return tuple(c)


def test_the_example_layout_gives_a_pure_couple_about_each_axis():
    """Hand evaluation: the pair (2k, 2k+1) gives torque +-2 L F on axis k and no force."""
    r = np.array(POSITIONS, float).reshape(12, 3)
    d = np.array(DIRECTIONS, float).reshape(12, 3)
    for k, (axis, sign) in enumerate([(0, 1), (0, -1), (1, 1), (1, -1), (2, 1), (2, -1)]):
        a, b = 2 * k, 2 * k + 1
        np.testing.assert_array_equal(d[a] + d[b], 0.0)
        want = np.zeros(3)
        want[axis] = sign * 2 * L
        np.testing.assert_allclose(np.cross(r[a], d[a]) + np.cross(r[b], d[b]), want, atol=1e-15)


def test_the_example_of_docs_scenarios_is_this_layout_and_loads():
    """docs/scenarios.md's [thrusters] example, parsed from the page: the layout tested here."""
    text = (Path(__file__).resolve().parents[3] / "docs" / "scenarios.md").read_text()
    block = re.search(r"```toml\n(\[thrusters\]\n.*?)```", text, re.S).group(1)
    sec = tomllib.loads(block)["thrusters"]
    assert sec["positions_m"] == POSITIONS and sec["directions"] == DIRECTIONS and sec["thrust_n"] == 1.0
    assert sec["latch_branch"] == TWINS_APART
    p = Plant(load("irassi_large", {"thrusters": sec}))
    assert p.command_fields["thruster_on_s"] == 12


def test_force_and_torque_against_a_hand_evaluation():
    p = _plant(thrust_n=[1.0, 1.1, 0.9, 1.0, 1.0, 1.0, 1.2, 1.0, 1.0, 0.8, 1.0, 1.0])
    dt = p.dt
    on = _on((0, 0.05), (1, 0.03), (6, 0.1), (9, 0.021))
    p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": on})
    p.advance()
    tr = p.truth()["effectors"]
    F = np.array([1.0, 1.1, 0.9, 1.0, 1.0, 1.0, 1.2, 1.0, 1.0, 0.8, 1.0, 1.0])
    r = np.array(POSITIONS, float).reshape(12, 3)
    d = np.array(DIRECTIONS, float).reshape(12, 3)
    tau = np.array(on)
    force = (F * tau / dt) @ d
    torque = (F * tau / dt) @ np.cross(r, d)
    np.testing.assert_allclose(tr["thrusters.force_b_n"], force, rtol=1e-14, atol=1e-16)
    np.testing.assert_allclose(tr["thrusters.torque_nm"], torque, rtol=1e-14, atol=1e-16)
    # by hand for one component: thrusters 0 and 1 (+x couple) and 6 (-y couple half), 9 (+z couple half)
    assert torque[0] == pytest.approx(L * (1.0 * 0.05 + 1.1 * 0.03) / dt, rel=1e-14)
    # the torque is the actuator output of the period
    np.testing.assert_allclose(p.truth()["applied"], torque, rtol=1e-14, atol=1e-16)


def test_a_pure_couple_spins_the_body_up_by_its_angular_impulse():
    """From rest with a diagonal J, a couple about x gives w_x(dt) = 2 L F tau / Jxx exactly (w x Jw = 0)."""
    sc = load("irassi_large", {"thrusters": _section(), "disturbances": None, "plant.w0": [0.0, 0.0, 0.0]})
    J = np.array(sc.attitude.inertia)
    assert np.count_nonzero(J - np.diag(np.diag(J))) == 0
    p = Plant(sc)
    p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((0, 0.04), (1, 0.04))})
    p.advance()
    assert p.body.w[0] == pytest.approx(2 * L * 1.0 * 0.04 / J[0, 0], rel=1e-12)
    assert p.body.w[1] == 0.0 and p.body.w[2] == 0.0


@pytest.mark.parametrize("cmd,flown", [
    (0.0234, 0.023),      # to the 1 ms quantum
    (0.0236, 0.024),
    (0.0199, 0.020),      # rounds up to the minimum on-time: kept
    (0.0149, 0.0),        # 15 ms < 20 ms minimum impulse bit: dropped
    (0.0004, 0.0),
    (0.5, 0.1),           # at most the period (0.1 s)
    (-0.3, 0.0),
    (0.1, 0.1),
])
def test_on_time_quantisation_and_minimum_impulse_bit(cmd, flown):
    assert quantise_on_time(cmd, 0.1, 0.001, 0.02) == pytest.approx(flown, abs=1e-15)
    p = _plant()
    assert p.dt == 0.1
    p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((4, cmd))})
    p.advance()
    tr = p.truth()["effectors"]
    assert tr["thrusters.on_time_s"][4] == pytest.approx(flown, abs=1e-15)
    assert tr["thrusters.on_time_cmd_s"][4] == cmd
    # the impulse bit delivered: F tau along thruster 4's direction (+x)
    assert tr["thrusters.force_b_n"][0] * p.dt == pytest.approx(1.0 * flown, abs=1e-15)
    assert tr["thrusters.pulses"][4] == (1 if flown > 0 else 0)


def test_without_quantum_or_minimum_the_on_time_is_flown_as_commanded():
    assert quantise_on_time(0.0123456, 0.1, 0.0, 0.0) == 0.0123456


@pytest.mark.parametrize("d5", [(-1.0, 0.0, 0.0), (0.48, -0.6, 0.64)])
def test_propellant_and_impulse_integrals(d5):
    """Thruster 5 fires through the centre of mass (r parallel to d): no torque, so the attitude stays
    and the impulse in N is A(q0)^T (F tau K) along its direction; the propellant is F tau K / (Isp g0).
    Along -x, then along an oblique direction (every term of A(q)^T f at work)."""
    pos, dirs = list(POSITIONS), list(DIRECTIONS)
    pos[15:18] = [0.7 * x for x in d5]     # thruster 5 at 0.7 d, firing along d: through the CoM
    dirs[15:18] = list(d5)
    p = _plant(positions_m=pos, directions=dirs, mass_kg=2500.0)
    q0 = np.array(p.body.q)
    w0 = np.array(p.body.w)
    K, tau, F = 40, 0.037, 1.0
    for _ in range(K):
        p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((5, tau))})
        p.advance()
    tr = p.truth()["effectors"]
    np.testing.assert_array_equal(tr["thrusters.torque_nm"], (0.0, 0.0, 0.0))
    assert tr["thrusters.propellant_kg"] == pytest.approx(F * tau * K / (220.0 * G0), rel=1e-13)
    assert tr["thrusters.on_time_total_s"][5] == pytest.approx(tau * K, rel=1e-13)
    assert tr["thrusters.pulses"][5] == K
    if not np.any(w0):
        A0 = np.array(quat_to_dcm(tuple(q0)))
        want = A0.T @ (F * tau * K * np.array(d5))
        np.testing.assert_allclose(tr["thrusters.impulse_n_ns"], want, rtol=1e-12, atol=1e-14)
        np.testing.assert_allclose(tr["thrusters.delta_v_n_m_s"], want / 2500.0, rtol=1e-12, atol=1e-17)
    else:   # the body turns: the magnitude of the impulse is still F tau K (a force fixed in B)
        assert np.linalg.norm(tr["thrusters.impulse_n_ns"]) == pytest.approx(F * tau * K, rel=1e-6)


def test_noise_and_misalignment_are_seeded_and_reproducible():
    def run(seed):
        p = _plant(seed=seed, thrust_noise_frac=0.05, misalignment_deg=0.5)
        e = _thrusters(p)
        thrusts = []
        for _ in range(200):
            p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((0, 0.05))})
            p.advance()
            thrusts.append(p.truth()["effectors"]["thrusters.thrust_n"])
        return np.array(e.directions), np.array(thrusts)
    d1, f1 = run(3)
    d2, f2 = run(3)
    np.testing.assert_array_equal(d1, d2)
    np.testing.assert_array_equal(f1, f2)
    d3, f3 = run(4)
    assert not np.array_equal(d1, d3) and not np.array_equal(f1, f3)
    # the thrust noise: 1-sigma 5 % (2400 draws)
    assert np.std(f1 / 1.0 - 1.0) == pytest.approx(0.05, rel=0.1)
    # the misalignment: a tilt of independent N(0, s^2) about two axes across d, so E[angle^2] = 2 s^2
    nominal = np.array(DIRECTIONS, float).reshape(12, 3)
    angles = []
    for seed in range(20):
        d = np.array(_thrusters(_plant(seed=seed, misalignment_deg=0.5)).directions)
        np.testing.assert_allclose(np.linalg.norm(d, axis=1), 1.0, atol=1e-15)
        angles.extend(np.arccos(np.clip(np.sum(d * nominal, axis=1), -1, 1)))
    s = math.radians(0.5)
    assert np.mean(np.square(angles)) == pytest.approx(2 * s * s, rel=0.2)
    # the torque follows the misaligned directions
    p = _plant(seed=3, misalignment_deg=0.5)
    e = _thrusters(p)
    p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((2, 0.1))})
    p.advance()
    r = np.array(POSITIONS, float).reshape(12, 3)
    np.testing.assert_allclose(p.truth()["effectors"]["thrusters.torque_nm"], np.cross(r[2], e.directions[2]),
                               rtol=1e-14, atol=1e-16)


def _gao(thrusters=True, seed=0):
    ov = {"wheels": {"array": "pyramid", "pyramid_axis": "z", "spin_inertia_kg_m2": 0.08, "torque_limit_nm": 0.25,
                     "speed_limit_rad_s": 600.0, "speed0_rad_s": [300.0, -200.0, 150.0, 50.0]},
          "plant.w0": [0.05, -0.08, 0.12], "integrator.substeps": 4}
    if thrusters:
        ov["thrusters"] = _section(thrust_noise_frac=0.05, misalignment_deg=1.0)
    return Plant(load("gao_mrp", ov))


def _H_N(p):
    """A(q)^T H_B, H_B = J w + sum Js g Omega: the wheels' momentum_total_nms, in N."""
    H_B = np.array(p.truth()["effectors"]["wheels.momentum_total_nms"])
    return np.array(quat_to_dcm(p.body.q)).T @ H_B


def test_momentum_of_body_and_wheels_is_conserved_with_the_thrusters_off():
    """Issue 21 acceptance: no disturbance (gao_mrp has none), thrusters configured but off, the wheels
    exchanging momentum with the body: H_N of body + wheels constant over 1500 s to RK4's tolerance
    (the wheels alone: 1e-8 over 1000 s, test_effectors_reaction_wheels.py)."""
    p = _gao()
    assert [e.kind for e in p.effectors] == ["wheels", "thrusters"] and not p.scenario.disturbances
    H0 = _H_N(p)
    h0 = np.array(p.effector_state(p.actuator))
    worst = 0.0
    for k in range(15000):
        t = p.t
        p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": (0.0,) * 12,
                 "u_wheels": (0.2 * math.sin(0.05 * t), -0.15 * math.cos(0.031 * t), 0.1 * math.sin(0.017 * t + 1.0),
                              0.05)})
        p.advance()
        if k % 500 == 0:
            worst = max(worst, np.linalg.norm(_H_N(p) - H0) / np.linalg.norm(H0))
    worst = max(worst, np.linalg.norm(_H_N(p) - H0) / np.linalg.norm(H0))
    print(f"relative drift of H_N over {p.t:g} s: {worst:.2e}")
    assert worst < 1e-8, worst
    assert np.abs(np.array(p.effector_state(p.actuator)) - h0).max() > 1.0     # the exchange was real
    assert p.truth()["effectors"]["thrusters.propellant_kg"] == 0.0
    # firing a couple changes H_N by its angular impulse: the check can fail
    p = _gao()
    H0 = _H_N(p)
    for _ in range(10):
        p.apply({"u_body": (0.0, 0.0, 0.0), "thruster_on_s": _on((8, 0.05), (9, 0.05)),
                 "u_wheels": (0.0, 0.0, 0.0, 0.0)})
        p.advance()
    dH = np.linalg.norm(_H_N(p) - H0)
    assert dH == pytest.approx(10 * 2 * L * 0.05, rel=0.1)     # |angular impulse| of 10 pulses, noise 5 %


@pytest.mark.parametrize("kw,match", [
    (dict(directions=DIRECTIONS[:-3]), r"thrusters.directions: 11 directions for 12 thrusters"),
    (dict(positions_m=POSITIONS[:-1]), r"thrusters.positions_m: expected a flat array of 3 N numbers"),
    (dict(directions=[0, 0, 2] + DIRECTIONS[3:]), r"thrusters.directions: thruster 0: not a unit vector"),
    (dict(min_on_time_s=0.2), r"thrusters.min_on_time_s: 0.2 s is longer than the control period"),
    (dict(thrust_n=-1.0), r"thrusters.thrust_n: must be > 0"),
    (dict(misalignment_deg=20.0), r"thrusters.misalignment_deg: 20 deg is above 10 deg"),
    (dict(colour="red"), r"thrusters.colour: unknown key"),
    (dict(latch_branch=[0, 1] * 5 + [0]), r"thrusters.latch_branch: expected an array of 12 integers .* 11 values"),
    (dict(latch_branch=[0, 1] * 7), r"thrusters.latch_branch: expected an array of 12 integers .* got 14 values"),
    (dict(latch_branch=1), r"thrusters.latch_branch: expected an array of 12 integers .* got an integer"),
    (dict(latch_branch="AB"), r"thrusters.latch_branch: expected an array of 12 integers .* got a string"),
    (dict(latch_branch=[0] * 11 + [2]), r"thrusters.latch_branch\[11\]: expected 0 \(branch A\) or 1 \(branch B\), "
                                        r"got 2"),
    (dict(latch_branch=[0, -1] + [0] * 10), r"thrusters.latch_branch\[1\]: expected 0 .* got -1"),
    (dict(latch_branch=[0.0] * 12), r"thrusters.latch_branch\[0\]: expected 0 .* got 0.0"),
    (dict(latch_branch=[True] * 12), r"thrusters.latch_branch\[0\]: expected 0 .* got a boolean"),
    (dict(latch_branch=["B"] * 12), r"thrusters.latch_branch\[0\]: expected 0 .* got a string"),
    (dict(latch_branch=[[0]] * 12), r"thrusters.latch_branch\[0\]: expected 0 .* got an array"),
])
def test_section_errors_name_the_key(kw, match):
    with pytest.raises(ScenarioError, match=match) as e:
        load("irassi_large", {"thrusters": _section(**kw)})
    assert "\n" not in str(e.value)


def test_thrusters_do_not_apply_to_an_orbit_scenario():
    with pytest.raises(ScenarioError, match=r"\[thrusters\] does not apply to a orbit scenario"):
        load("landsat8_q1", {"thrusters": _section()})


def test_a_command_of_the_wrong_size_is_refused():
    p = _plant()
    with pytest.raises(ValueError, match="thruster_on_s"):
        p.apply({"thruster_on_s": (0.0,) * 11})


# ------------------------------------------------------------------ latch valves (issue 26, docs/spec.md 5.8.1)
TWINS_APART = [0, 1] * 6      # each couple's twins on different branches: thrusters 1, 3, ..., 11 on branch B
LATCH = "thruster_latch_closed"


def _fly(p, n=1, **cmd):
    """n periods of the command cmd (thruster_on_s=..., thruster_latch_closed=...); the effector truth."""
    c = {"u_body": (0.0, 0.0, 0.0)}
    c.update({"thruster_on_s" if k == "on" else LATCH: v for k, v in cmd.items()})
    for _ in range(n):
        assert p.apply(c)
        p.advance()
    return p.truth()["effectors"]


def _expected(on, flying, dt, F=1.0, isp=220.0):
    """force, torque and propellant flow of one period with only the thrusters in `flying` on (numpy)."""
    r = np.array(POSITIONS, float).reshape(12, 3)
    d = np.array(DIRECTIONS, float).reshape(12, 3)
    tau = np.array([on[i] if i in flying else 0.0 for i in range(12)])
    w = F * tau / dt
    return w @ d, w @ np.cross(r, d), w.sum() / (isp * G0)


def test_latch_branch_defaults_to_branch_a_and_is_read():
    assert _plant().scenario.effectors["thrusters"].latch_branch == (0,) * 12
    assert _plant(latch_branch=TWINS_APART).scenario.effectors["thrusters"].latch_branch == tuple(TWINS_APART)


def test_a_closed_latch_valve_stops_its_branch_and_the_other_still_fires():
    """All twelve commanded: with A's valve closed only the odd thrusters (branch B) fly, with B's only the even
    ones, with both none; force, torque and the propellant of the period against numpy over the flying ones."""
    on = (0.031, 0.047, 0.022, 0.064, 0.053, 0.028, 0.071, 0.039, 0.044, 0.025, 0.058, 0.036)
    for mask, flying in ((0, set(range(12))), (1, set(range(1, 12, 2))), (2, set(range(0, 12, 2))), (3, set())):
        p = _plant(latch_branch=TWINS_APART)
        tr = _fly(p, on=on, thruster_latch_closed=mask)
        force, torque, mdot = _expected(on, flying, p.dt)
        np.testing.assert_allclose(tr["thrusters.force_b_n"], force, rtol=1e-14, atol=1e-16)
        np.testing.assert_allclose(tr["thrusters.torque_nm"], torque, rtol=1e-14, atol=1e-16)
        assert tr["thrusters.propellant_kg"] == pytest.approx(mdot * p.dt, rel=1e-13, abs=0.0)
        tau = [on[i] if i in flying else 0.0 for i in range(12)]
        assert tr["thrusters.on_time_s"] == pytest.approx(tuple(tau), abs=1e-15)
        assert tr["thrusters.pulses"] == tuple(1 if i in flying else 0 for i in range(12))
        assert tr["thrusters.latch_closed"] == mask
        assert tr["thrusters.on_time_cmd_s"] == on          # the command itself is not altered
        if mask == 3:
            assert tr["thrusters.torque_nm"] == (0.0, 0.0, 0.0) and tr["thrusters.propellant_kg"] == 0.0


def test_with_every_thruster_on_branch_a_closing_b_changes_nothing():
    on = _on((0, 0.05), (7, 0.03))
    tr_b = _fly(_plant(), on=on, thruster_latch_closed=2)
    tr_open = _fly(_plant(), on=on, thruster_latch_closed=0)
    assert tr_b["thrusters.torque_nm"] == tr_open["thrusters.torque_nm"] != (0.0, 0.0, 0.0)
    assert _fly(_plant(), on=on, thruster_latch_closed=1)["thrusters.torque_nm"] == (0.0, 0.0, 0.0)


def test_a_stuck_open_thruster_is_stopped_by_its_latch_valve_and_fires_again_when_reopened():
    """thruster_stuck_open on thruster 4 (branch A, +y half couple): with no on-time commanded it flies the whole
    period; closing A stops it (after the fault model: the latch valve is upstream of its valve), closing B does
    not, reopening A lets it fly again. Each period's torque and propellant against the hand value F (r4 x d4)."""
    sc = load("irassi_large", {"thrusters": _section(latch_branch=TWINS_APART), "disturbances": None,
                               "faults": [{"kind": "thruster_stuck_open", "unit": 4, "start_s": 0.0}]})
    p = Plant(sc)
    dt = p.dt
    full = (0.0, L, 0.0)                           # r4 x d4 = (0, 0, L) x (1, 0, 0), 1 N
    flow = 1.0 / (220.0 * G0)                      # kg/s with thruster 4 open all period
    prop = 0.0
    for mask, fires in ((0, True), (1, False), (1, False), (2, True), (3, False), (0, True)):
        tr = _fly(p, on=(0.0,) * 12, thruster_latch_closed=mask)
        prop += flow * dt if fires else 0.0
        np.testing.assert_allclose(tr["thrusters.torque_nm"], full if fires else (0.0, 0.0, 0.0), atol=1e-15)
        assert tr["thrusters.on_time_s"][4] == (dt if fires else 0.0)
        assert tr["thrusters.propellant_kg"] == pytest.approx(prop, rel=1e-12)
    assert tr["thrusters.pulses"][4] == 3
    assert p.truth()["faults_active"] == (True,)


def test_the_valves_keep_their_state_until_a_command_carries_the_field():
    """Open at the start (a command without the field flies both branches); closed by one command, A stays
    closed through commands without the field (and through a refused one that would open it); a command with the
    field opens it."""
    p = _plant(latch_branch=TWINS_APART)
    on = _on((0, 0.05), (1, 0.05))                 # the +x couple: thruster 0 on A, thruster 1 on B
    tr = _fly(p, on=on)                            # no latch field yet: every valve open
    assert tr["thrusters.on_time_s"][:2] == (0.05, 0.05) and tr["thrusters.latch_closed"] == 0
    tr = _fly(p, on=on, thruster_latch_closed=1)
    assert tr["thrusters.on_time_s"][:2] == (0.0, 0.05)
    tr = _fly(p, 3, on=on)                         # no latch field: A stays closed
    assert tr["thrusters.on_time_s"][:2] == (0.0, 0.05) and tr["thrusters.latch_closed"] == 1
    assert tr["thrusters.pulses"][:2] == (1, 5)
    p.apply({"u_body": (0.0, 0.0, 0.0)})           # neither thruster field: the on-times and the valves hold
    p.advance()
    assert p.truth()["effectors"]["thrusters.pulses"][:2] == (1, 6)
    assert not p.apply({"thruster_on_s": on, LATCH: 0, "u_body": (math.nan, 0.0, 0.0)})   # refused whole
    p.advance()
    assert p.truth()["effectors"]["thrusters.on_time_s"][:2] == (0.0, 0.05)
    assert p.truth()["effectors"]["thrusters.pulses"][:2] == (1, 7)
    tr = _fly(p, on=on, thruster_latch_closed=0)
    assert tr["thrusters.on_time_s"][:2] == (0.05, 0.05) and tr["thrusters.latch_closed"] == 0
    np.testing.assert_allclose(tr["thrusters.torque_nm"], (2 * L * 0.05 / p.dt, 0.0, 0.0), rtol=1e-14)
    tr = _fly(p, 2, on=on)                         # and open it stays
    assert tr["thrusters.pulses"][:2] == (4, 10)


def _positive_span(arms) -> bool:
    """Every signed body axis a non-negative combination of the torque arms (NNLS residual 0)."""
    from scipy.optimize import nnls
    A = np.array(arms, float).T
    return bool(A.size) and all(nnls(A, s * np.eye(3)[k])[1] < 1e-9 for k in range(3) for s in (1.0, -1.0))


def test_each_branch_of_the_reference_scenarios_spans_every_signed_axis():
    """Every scenario with [thrusters] gives twins (thrusters of the same torque r x d) different branches when
    it has them, so that each branch alone still spans +-x, +-y, +-z (a branch isolated keeps the dumping)."""
    from aocs_plant.scenario import list_scenarios
    with_thrusters = [sid for sid in list_scenarios() if "thrusters" in load(sid).effectors]
    assert {"irassi_day", "irassi_day_mekf"} <= set(with_thrusters)
    for sid in with_thrusters:
        t = load(sid).effectors["thrusters"]
        arms = [tuple(np.cross(r, d)) for r, d in zip(t.positions_m, t.directions)]
        for i in range(len(arms)):
            for j in range(i + 1, len(arms)):
                if np.allclose(arms[i], arms[j], atol=1e-12):
                    assert t.latch_branch[i] != t.latch_branch[j], (sid, i, j)
        for b in (0, 1):
            assert _positive_span([a for a, br in zip(arms, t.latch_branch) if br == b]), (sid, b)
