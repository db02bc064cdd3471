"""The momentum-management keys of the fsw_node configuration (aocs_flightcfg.fsw_config.momentum_keys) and the
scenario's [momentum] section (aocs_plant.scenario), issue 21.

The actuator sections [thrusters] / [magnetorquers] are read by the plant's effector modules; the configs below
carry the same attributes (positions_m, directions, thrust_n, min_on_time_s, on_time_quantum_s; axes,
max_dipole_am2), so the writer is exercised without them. Expected arms are the cross products worked out here;
fsw_node itself (the real node, in a private network namespace) accepts the written files, which runs the
stage's init: the thruster set spans every signed axis, the rods are unit and spanning."""
from __future__ import annotations

import dataclasses
import subprocess
from types import MappingProxyType, SimpleNamespace

import pytest

from aocs_flightcfg import fsw_config
from aocs_plant.scenario import MomentumConfig, ScenarioError, list_scenarios, load
from thruster_layout import couples


def _vals(text):
    return [float(x) for x in text.split()]


def _l2_thrusters(thrust=1.0):
    """The 12 thrusters of tests/thruster_layout.py (couples 1.1 m from the centre of mass, offset 0.2 m)."""
    pos, dirs = couples(1.1, 0.2)
    return SimpleNamespace(positions_m=pos, directions=dirs, thrust_n=thrust, min_on_time_s=0.02,
                           on_time_quantum_s=0.001)


def _with(sc, momentum, **effectors):
    return dataclasses.replace(sc, momentum=momentum, effectors=MappingProxyType({**sc.effectors, **effectors}))


#: the mission days (issue 21) manage their momentum: the other scenarios must not
DAY_IDS = ("irassi_day", "irassi_day_mekf", "leo_day")


def test_no_reference_scenario_writes_a_momentum_key():
    for sid in list_scenarios():
        if sid in DAY_IDS:
            continue
        sc = load(sid)
        assert sc.momentum == MomentumConfig()
        for law in sc.control.laws:
            assert not [k for k in fsw_config.node_config(sc, law) if k.startswith("mom.")], (sid, law)


def test_thruster_keys_are_the_nominal_geometry():
    thr = _l2_thrusters()
    sc = _with(load("irassi_rw"), MomentumConfig("thrusters", "threshold", (0.0, 0.5, 0.0), 8.0, 2.0, 0.0, 0.4),
               thrusters=thr)
    cfg = fsw_config.node_config(sc, "quat_pid")
    assert (cfg["mom.policy"], cfg["mom.trigger"], cfg["mom.thr_count"]) == ("thrusters", "threshold", "12")
    assert _vals(cfg["mom.h_target_nms"]) == [0.0, 0.5, 0.0]
    assert (float(cfg["mom.h_start_nms"]), float(cfg["mom.h_stop_nms"])) == (8.0, 2.0)
    assert (float(cfg["mom.dump_torque_nm"]), float(cfg["mom.thr_thrust_n"])) == (0.4, 1.0)
    assert (float(cfg["mom.thr_min_on_s"]), float(cfg["mom.thr_quantum_s"])) == (0.02, 0.001)
    x, y, z = (_vals(cfg[f"mom.thr_arm_{a}_m"]) for a in "xyz")
    for i, (r, d) in enumerate(zip(thr.positions_m, thr.directions)):
        want = (r[1] * d[2] - r[2] * d[1], r[2] * d[0] - r[0] * d[2], r[0] * d[1] - r[1] * d[0])
        assert (x[i], y[i], z[i]) == pytest.approx(want, abs=1e-15)
    assert "mom.k_mtq_per_s" not in cfg


def test_the_latch_valve_mask_is_the_b_branch_of_each_thruster():
    """mom.thr_latch_b_mask: bit i set when thruster i is on branch B ([thrusters] latch_branch), always written
    with the thrusters policy: the reference day's twins apart (0b101010101010), an override, and 0 without."""
    assert fsw_config.momentum_keys(load("irassi_day_mekf"))["mom.thr_latch_b_mask"] == str(0b101010101010) == "2730"
    assert fsw_config.momentum_keys(load("irassi_day"))["mom.thr_latch_b_mask"] == "2730"
    branch = [1, 1, 0, 0, 0, 1, 1, 0, 0, 0, 0, 1]
    cfg = fsw_config.momentum_keys(load("irassi_day", {"thrusters.latch_branch": branch}))
    assert cfg["mom.thr_latch_b_mask"] == str(1 + 2 + 32 + 64 + 2048)
    assert fsw_config.momentum_keys(load("irassi_day", {"thrusters.latch_branch": [0] * 12}))[
        "mom.thr_latch_b_mask"] == "0"
    sc = _with(load("irassi_rw"), MomentumConfig("thrusters", "continuous", dump_torque_nm=0.4),
               thrusters=_l2_thrusters())                 # a config without latch_branch: every thruster on A
    assert fsw_config.node_config(sc, "quat_pid")["mom.thr_latch_b_mask"] == "0"


def test_unequal_thrusts_scale_the_arms_by_the_largest():
    thr = _l2_thrusters()
    thr.thrust_n = tuple(2.0 if i == 3 else 1.0 for i in range(12))
    sc = _with(load("irassi_rw"), MomentumConfig("thrusters", "continuous", dump_torque_nm=0.4), thrusters=thr)
    cfg = fsw_config.momentum_keys(sc)
    assert float(cfg["mom.thr_thrust_n"]) == 2.0
    r, d = thr.positions_m[0], thr.directions[0]
    assert _vals(cfg["mom.thr_arm_y_m"])[0] == pytest.approx(0.5 * (r[2] * d[0] - r[0] * d[2]), abs=1e-15)


def test_magnetorquer_keys():
    mtq = SimpleNamespace(axes=((1.0, 0.0, 0.0), (0.0, 0.6, 0.8), (0.0, -0.8, 0.6)), max_dipole_am2=(30.0, 30.0, 20.0))
    sc = _with(load("irassi_rw"), MomentumConfig("magnetorquers", "continuous", k_mtq_per_s=0.002),
               magnetorquers=mtq)
    cfg = fsw_config.momentum_keys(sc)
    assert cfg["mom.policy"] == "magnetorquers" and float(cfg["mom.k_mtq_per_s"]) == 0.002
    assert _vals(cfg["mom.mtq_axes"]) == [1.0, 0.0, 0.0, 0.0, 0.6, 0.8, 0.0, -0.8, 0.6]
    assert _vals(cfg["mom.mtq_max_dipole_am2"]) == [30.0, 30.0, 20.0]
    assert not [k for k in cfg if k.startswith("mom.thr")]


def test_fsw_node_accepts_the_momentum_configurations(fsw_node_bin, private_netns, tmp_path):
    """The real node reads the files and initialises the stage (exit 0 on its idle timeout)."""
    base = load("irassi_rw")
    mtq = SimpleNamespace(axes=((1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 1.0)), max_dipole_am2=(30.0, 30.0, 30.0))
    cases = {"thrusters": _with(base, MomentumConfig("thrusters", "threshold", (0.0, 0.0, 0.0), 8.0, 2.0, 0.0, 0.4),
                                thrusters=_l2_thrusters()),
             "magnetorquers": _with(base, MomentumConfig("magnetorquers", "continuous", k_mtq_per_s=0.002),
                                    magnetorquers=mtq)}
    for name, sc in cases.items():
        p = fsw_config.write(tmp_path / f"{name}.cfg", fsw_config.node_config(sc, "quat_pid", idle_timeout_s=0.3))
        r = subprocess.run([str(fsw_node_bin), str(p)], capture_output=True, text=True, timeout=20)
        assert r.returncode == 0, f"{name}: {r.stderr}"
    # three thrusters about +x, +y, +z only: the stage's init refuses them, the node says so in one line
    bad = SimpleNamespace(positions_m=((0.0, 1.0, 0.0), (0.0, 0.0, 1.0), (1.0, 0.0, 0.0)),
                          directions=((0.0, 0.0, 1.0), (1.0, 0.0, 0.0), (0.0, 1.0, 0.0)), thrust_n=1.0,
                          min_on_time_s=0.0, on_time_quantum_s=0.0)
    sc = _with(base, MomentumConfig("thrusters", "continuous", dump_torque_nm=0.4), thrusters=bad)
    p = fsw_config.write(tmp_path / "bad.cfg", fsw_config.node_config(sc, "quat_pid", idle_timeout_s=0.3))
    r = subprocess.run([str(fsw_node_bin), str(p)], capture_output=True, text=True, timeout=20)
    assert r.returncode != 0 and "AOCS_ERR_MOMENTUM_THRUSTERS_NOT_SPANNING" in r.stderr, r.stderr


@pytest.mark.parametrize("overrides, needle", [
    ({"momentum.policy": "warp"}, "momentum.policy"),
    ({"momentum.policy": "thrusters", "momentum.dump_torque_nm": 0.5}, '"thrusters" needs a [thrusters] section'),
    ({"momentum.policy": "magnetorquers", "momentum.k_mtq_per_s": 0.01}, '"magnetorquers" needs a [magnetorquers]'),
    ({"momentum.h_start_nms": -1.0}, "momentum.h_start_nms"),
    ({"momentum.dump": 1.0}, "momentum.dump"),
])
def test_the_momentum_section_names_what_is_wrong(overrides, needle):
    with pytest.raises(ScenarioError, match=None) as e:
        load("irassi_rw", overrides)
    assert needle in str(e.value) and "\n" not in str(e.value)


def test_momentum_applies_to_attitude_scenarios_only():
    with pytest.raises(ScenarioError, match="attitude scenarios only"):
        load("landsat8_q1", {"momentum.policy": "thrusters", "momentum.dump_torque_nm": 0.5})
    assert load("irassi_rw", {"momentum.policy": "none", "momentum.trigger": "continuous"}).momentum.trigger == \
        "continuous"
