"""The fsw_node configuration file written from a scenario (aocs_flightcfg.fsw_config).

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import math
import subprocess

import pytest

from aocs_core import conventions as rot
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError, list_scenarios, load


def _vals(text):
    return [float(x) for x in text.split()]


def test_config_of_irassi_large_carries_the_scenario_values_exactly():
    sc = load("irassi_large")
    cfg = fsw_config.node_config(sc, "quat_pd")
    assert cfg["law"] == "quat_pd" and cfg["mode"] == "lockstep"
    assert float(cfg["control_period_s"]) == 0.1
    # bit-exact round trip of the target quaternion (Euler 3-2-1 [30 -20 1] deg)
    assert tuple(_vals(cfg["target_q"])) == sc.target.qd0
    qd = rot.euler321_deg_to_quat((30.0, -20.0, 1.0))
    assert max(abs(a - b) for a, b in zip(_vals(cfg["target_q"]), qd)) < 1e-15
    assert "target_rotation_rate" not in cfg and "target_w" not in cfg
    assert _vals(cfg["inertia"]) == [2059.5, 0, 0, 0, 5954.2, 0, 0, 0, 5974.3]
    assert _vals(cfg["quat_pd.kp"]) == [4000.0] and _vals(cfg["quat_pd.kd"]) == [8000.0]
    assert _vals(cfg["quat_nlpd.kp"]) == [4000.0]
    assert _vals(cfg["smc.lambda"]) == [1.0] * 3 and _vals(cfg["smc.eps"]) == [0.02] * 3
    assert cfg["lqr_quat.table"] == "lqr_quat_ref"          # the compiled firmware table flies
    assert "lqr_quat.k" not in cfg
    # no limit in the file (reference runs): effectively unlimited, one limit is required
    assert _vals(cfg["u_max_axis"]) == [fsw_config.UNLIMITED] * 3 and "u_max_norm" not in cfg
    assert _vals(fsw_config.node_config(sc, "quat_pd", limit=0.5)["u_max_axis"]) == [0.5] * 3
    # k_safe: 0.1 * mean principal inertia
    assert float(cfg["k_safe"]) == pytest.approx(0.1 * (2059.5 + 5954.2 + 5974.3) / 3, rel=1e-12)


def test_config_of_the_special_scenarios():
    geo = load("geo_hinf")
    cfg = fsw_config.node_config(geo, "hinf")
    assert _vals(cfg["target_rotation_rate"]) == [0.0, -7.292115e-05, 0.0]
    assert "target_w" not in cfg and cfg["hinf.table"] == "hinf_regional"
    gao = fsw_config.node_config(load("gao_mrp"), "mrp_sat")
    bound = 2 * 0.05 / math.sqrt(3)
    assert _vals(gao["mrp_sat.l2"]) == pytest.approx([bound] * 3, rel=1e-15)
    assert _vals(gao["mrp_sat.m2"]) == pytest.approx([bound] * 3, rel=1e-15)
    assert _vals(gao["mrp_sat.l1"]) == [0.05] * 3 and float(gao["mrp_sat.u_max"]) == 0.05
    orb = fsw_config.node_config(load("landsat8_q10"), "orbit_lqr")
    assert orb["orbit_lqr.table"] == "orbit_lqr_q10" and "target_q" not in orb and "inertia" not in orb
    with pytest.raises(fsw_config.ConfigError, match="no gains"):
        fsw_config.node_config(load("irassi_large"), "hinf")
    # an M3 the flight software's tanh variant cannot fly is refused when the scenario loads
    with pytest.raises(ScenarioError, match=r"laws\.mrp_sat_tanh\.m3: m3 = 0\.04 but the flight software"):
        load("gao_mrp", {"laws.mrp_sat_tanh.m3": 0.04})


def test_the_wheels_section_writes_the_friction_model_and_the_null_space_keys():
    """One [wheels] description: the flight software's friction feedforward gets the plant's own
    coefficients per wheel, the null-space management its gain and targets (docs/spec.md 5.3.2)."""
    sc = load("irassi_rw")
    w = sc.effectors["wheels"]
    cfg = fsw_config.node_config(sc, "quat_pid")
    assert cfg["wheels.count"] == "4"
    for i in range(4):
        assert float(cfg[f"wheel{i}.viscous_nms"]) == w.viscous_nms == 1.0e-5
        assert float(cfg[f"wheel{i}.coulomb_nm"]) == w.coulomb_nm == 2.0e-3
        assert float(cfg[f"wheel{i}.coulomb_width_radps"]) == w.coulomb_width_rad_s == 0.5
    assert float(cfg["wheels.null_gain"]) == 0.02
    assert [float(cfg[f"wheel{i}.null_speed_radps"]) for i in range(4)] == [50.0, -50.0, 50.0, -50.0]
    # a scenario override reaches both sides (the plant's friction is the same object)
    sc2 = load("irassi_rw", {"wheels.coulomb_nm": 0.0, "wheels.null_gain_per_s": 0.0})
    cfg2 = fsw_config.node_config(sc2, "quat_pid")
    assert float(cfg2["wheel3.coulomb_nm"]) == sc2.effectors["wheels"].coulomb_nm == 0.0
    assert "wheels.null_gain" not in cfg2 and "wheel0.null_speed_radps" not in cfg2
    # a model error on purpose: the flight software's b and c scaled, the plant's untouched; 0 = no feedforward
    sc3 = load("irassi_rw", {"wheels.fsw_friction_scale": 0.8})
    cfg3 = fsw_config.node_config(sc3, "quat_pid")
    assert sc3.effectors["wheels"].coulomb_nm == 2.0e-3
    assert float(cfg3["wheel1.coulomb_nm"]) == 0.8 * 2.0e-3 and float(cfg3["wheel2.viscous_nms"]) == 0.8 * 1.0e-5
    assert float(cfg3["wheel0.coulomb_width_radps"]) == 0.5
    cfg0 = fsw_config.node_config(load("irassi_rw", {"wheels.fsw_friction_scale": 0.0}), "quat_pid")
    assert float(cfg0["wheel0.coulomb_nm"]) == 0.0 == float(cfg0["wheel3.viscous_nms"])
    # the loader refuses what the flight software's init would refuse
    with pytest.raises(ScenarioError, match="not below the torque"):
        load("irassi_rw", {"wheels.coulomb_nm": 0.25})
    with pytest.raises(ScenarioError, match="not below the torque"):
        load("irassi_rw", {"wheels.fsw_friction_scale": 40.0})   # 40 x 8e-3 N m
    with pytest.raises(ScenarioError, match="null_gain_per_s"):
        load("irassi_rw", {"wheels.null_gain_per_s": 20.0})
    with pytest.raises(ScenarioError, match="null_speed_rad_s"):
        load("irassi_rw", {"wheels.null_speed_rad_s": [600.0, 0.0, 0.0, 0.0]})


def test_config_file_round_trip(tmp_path):
    cfg = fsw_config.node_config(load("rtc_ex1a"), "crp_linear")
    p = fsw_config.write(tmp_path / "a.cfg", cfg, header="hello\nworld")
    assert fsw_config.read(p) == cfg
    assert p.read_text().startswith("# fsw_node configuration")


def _all_configs():
    out = []
    for sid in list_scenarios():
        sc = load(sid)
        for law in sc.control.laws:
            out.append((sid, law))
    return out


def test_every_scenario_and_law_gives_a_config_fsw_node_accepts(fsw_node_bin, private_netns, tmp_path):
    """All configs at once (each node exits on its idle timeout): exit 0 and the right law."""
    procs = []
    for sid, law in _all_configs():
        cfg = fsw_config.node_config(load(sid), law, idle_timeout_s=0.3)
        p = fsw_config.write(tmp_path / f"{sid}-{law}.cfg", cfg)
        procs.append((sid, law, subprocess.Popen([str(fsw_node_bin), str(p)], stdout=subprocess.DEVNULL,
                                                 stderr=subprocess.PIPE, text=True)))
    assert len(procs) >= 20
    for sid, law, proc in procs:
        _, err = proc.communicate(timeout=20)
        assert proc.returncode == 0, f"{sid}/{law}: {err}"
        assert f"law {law}," in err, err


def test_the_lockstep_spin_is_written_only_when_asked():
    """wait_spin_us (fsw_node's node_checks.h): absent by default (the node's 0), the value when given."""
    sc = load("irassi_small")
    assert "wait_spin_us" not in fsw_config.node_config(sc, "quat_pd")
    assert float(fsw_config.node_config(sc, "quat_pd", wait_spin_us=200.0)["wait_spin_us"]) == 200.0
