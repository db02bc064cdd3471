"""Wire contract v4 end to end: fsw_node with a wheel array and a momentum-management policy, its actuator_cmd_t
checked field by field against an independent evaluation in the test (issue 21).

Thrusters: the on-times are non-negative, within the period and whole quanta; the unloading torque the node reports
is the torque of those on-times (F sum t_i (r_i x d_i) / dt, the geometry written here), it opposes the wheel
momentum, and the wheels deliver the law's torque minus it (u_sat + u_unload = u_unsat, unsaturated). The dump
starts above h_start and counts one event. Magnetorquers: the dipole is perpendicular to the magnetometer's field
and its torque m x B is the unloading torque; without the magnetometer flag nothing is commanded."""
from __future__ import annotations

import math

import pytest

from thruster_layout import arms as thruster_arms
from thruster_layout import couples
from thruster_layout import cross as _cross

JS = 0.1
WHEELS = {"wheels.count": "3", **{f"wheel{i}.{k}": v for i in range(3) for k, v in (
    ("axis_B", " ".join("1" if j == i else "0" for j in range(3))), ("js_kgm2", str(JS)), ("u_max_nm", "2.0"),
    ("omega_max_radps", "600"))}, "inertia": "10 10 10", "u_max_axis": "2 2 2"}


def _dot(a, b):
    return sum(x * y for x, y in zip(a, b))


def _send(link, aocs_lcm, tick, speeds, mag=None):
    t = aocs_lcm.sensors_t
    m = link.sensors(tick, (0.0, 0.0, 0.0, 1.0), (0.0, 0.0, 0.0))
    m.valid = t.VALID_ATTITUDE | t.VALID_RATE | t.VALID_WHEELS | (t.VALID_MAGNETOMETER if mag is not None else 0)
    m.n_wheels = 3
    m.wheel_speed = list(speeds) + [0.0] * (t.MAX_WHEELS - 3)
    m.mag_b_t = list(mag) if mag is not None else [0.0, 0.0, 0.0]
    link.lc.publish("AOCS_SENSORS", m.encode())
    return link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda r: r.tick == tick)[0]


def test_thruster_dumping_on_the_wire(fsw_node, lcm_link, aocs_lcm):
    arms = thruster_arms(*couples(1.2))
    thrust, dt, quantum, min_on = 1.0, 0.1, 0.001, 0.01
    cfg = dict(WHEELS)
    cfg.update({"mom.policy": "thrusters", "mom.trigger": "threshold", "mom.h_start_nms": "5",
                "mom.h_stop_nms": "1", "mom.dump_torque_nm": "0.8", "mom.thr_count": "12",
                "mom.thr_thrust_n": str(thrust), "mom.thr_min_on_s": str(min_on), "mom.thr_quantum_s": str(quantum)})
    for c, key in enumerate(("x", "y", "z")):
        cfg[f"mom.thr_arm_{key}_m"] = " ".join(repr(a[c]) for a in arms)
    node = fsw_node(**cfg)
    node.wait_ready(lcm_link)
    # h = Js Omega = (3, -2, 1): below h_start = 5, no dump
    r = _send(lcm_link, aocs_lcm, 0, (30.0, -20.0, 10.0))
    assert (r.protocol_version, r.mom_policy, r.n_thrusters, bool(r.unloading), r.n_unload_events) == (6, 2, 12,
                                                                                                      False, 0)
    assert r.thruster_latch_closed == 0     # protocol version 6: every latch valve open
    assert list(r.thruster_on_s) == [0.0] * 12 and list(r.u_unload) == [0.0] * 3
    assert r.h_wheels == pytest.approx([3.0, -2.0, 1.0], rel=1e-12)
    # h = (10, -5, 3): above, the dump starts
    for tick in (1, 2, 3):
        r = _send(lcm_link, aocs_lcm, tick, (100.0, -50.0, 30.0))
        assert bool(r.unloading) and r.n_unload_events == 1 and r.mom_status == 0
        h = (10.0, -5.0, 3.0)
        assert r.h_wheels == pytest.approx(h, rel=1e-12) and r.dh == pytest.approx(h, rel=1e-12)
        on = r.thruster_on_s
        assert all(0.0 <= t <= dt for t in on) and any(t > 0.0 for t in on)
        assert all(t == 0.0 or (t >= min_on - 1e-12 and abs(t / quantum - round(t / quantum)) < 1e-6) for t in on)
        u = tuple(sum(thrust * on[i] * arms[i][c] for i in range(12)) / dt for c in range(3))
        assert r.u_unload == pytest.approx(u, rel=1e-9, abs=1e-12)
        assert _dot(u, h) < 0.0                                          # opposes the wheel momentum
        # |u| within one quantum per thruster of the requested 0.8 N m
        assert abs(math.sqrt(_dot(u, u)) - 0.8) <= 12 * 1.2 * thrust * quantum / dt
        # the wheels deliver the law's torque minus the unloading torque (no saturation here)
        assert [a + b for a, b in zip(r.u_sat, r.u_unload)] == pytest.approx(list(r.u_unsat), rel=1e-9, abs=1e-12)
    # h = (0.5, 0, 0): below h_stop, the dump ends
    r = _send(lcm_link, aocs_lcm, 4, (5.0, 0.0, 0.0))
    assert not r.unloading and r.n_unload_events == 1 and list(r.thruster_on_s) == [0.0] * 12


def test_magnetorquer_unloading_on_the_wire(fsw_node, lcm_link, aocs_lcm):
    k = 0.01
    cfg = dict(WHEELS)
    cfg.update({"mom.policy": "magnetorquers", "mom.trigger": "continuous", "mom.k_mtq_per_s": str(k),
                "mom.mtq_max_dipole_am2": "1000 1000 1000", "mom.h_target_nms": "0 1 0"})
    node = fsw_node(**cfg)
    node.wait_ready(lcm_link)
    b = (2.0e-5, -1.0e-5, 3.0e-5)
    r = _send(lcm_link, aocs_lcm, 0, (20.0, 30.0, -10.0), mag=b)
    dh = (2.0, 2.0, -1.0)                                      # Js Omega - (0, 1, 0)
    assert r.mom_policy == 1 and r.n_thrusters == 0 and bool(r.unloading) and r.mom_status == 0
    assert r.dh == pytest.approx(dh, rel=1e-12)
    m = r.dipole_am2                                          # rods along x, y, z
    assert abs(_dot(m, b)) <= 1e-9 * math.sqrt(_dot(m, m) * _dot(b, b))
    bb = _dot(b, b)
    want = tuple(k * x / bb for x in _cross(dh, b))            # m = k (dh x B) / |B|^2
    assert m == pytest.approx(want, rel=1e-9)
    tau = _cross(m, b)
    assert r.u_unload == pytest.approx(tau, rel=1e-9, abs=1e-15)
    # m x B = -k dh_perp
    perp = tuple(dh[i] - _dot(dh, b) / bb * b[i] for i in range(3))
    assert tau == pytest.approx(tuple(-k * x for x in perp), rel=1e-9)
    # no magnetometer reading: no dipole, and the stage says why
    r = _send(lcm_link, aocs_lcm, 1, (20.0, 30.0, -10.0))
    assert list(r.dipole_am2) == [0.0] * 3 and r.mom_status != 0
