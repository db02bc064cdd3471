"""The IRASSI slew on reaction wheels through the real processes (plant_node, fsw_node, LCM in a
private namespace): the flight software allocates to the wheels of the scenario's one [wheels]
description, the plant applies those wheel torques, and the logs agree with SPEC 5.3 written out
here with numpy (minimum-norm allocation, uniform scale, limits, failed wheel, momentum).
"""
from __future__ import annotations

import json
import sys
import time

import numpy as np
import pytest

import pil_support
from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant import load
from aocs_runner import orchestrate
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog


@pytest.fixture(scope="module")
def run(private_netns, fsw_node_bin, aocs_lcm):
    def go(scenario, out, **kw):
        kw.setdefault("plots", False)
        res = execute(RunOptions(scenario=scenario, out=str(out), quiet=True, **kw))
        return res, lcmlog.read(out / "run.lcmlog")
    return go


def _friction(w, om):
    """The plant's bearing friction (docs/spec.md 5.3.1), the model of the flight software's feedforward."""
    om = np.clip(om, -np.array(w.speed_limit_rad_s), np.array(w.speed_limit_rad_s))
    return w.viscous_nms * om + w.coulomb_nm * np.tanh(om / w.coulomb_width_rad_s)


def _check_allocation(sc, log):
    w = sc.effectors["wheels"]
    n = w.n
    G = np.array(w.axes).T
    healthy = [i for i in range(n) if i not in w.failed]
    P = np.zeros((n, 3))
    P[healthy] = np.linalg.pinv(G[:, healthy])
    c = log.cmd
    u_w = c["u_wheels"][:, :n]
    assert np.all(c["n_wheels"] == n) and np.all(c["wheel_status"] == 0)
    # the friction feedforward from the tachometer speeds of the same tick (docs/spec.md 5.3.2)
    at = {int(t): k for k, t in enumerate(log.sensors["tick"])}
    om = log.sensors["wheel_speed"][[at[int(t)] for t in c["tick"]], :n]
    f = _friction(w, om)
    f[:, list(w.failed)] = 0.0
    net = u_w - f
    # the delivered body torque u_sat is -Gs (u_s - f) (the null-space torque gives none) ...
    np.testing.assert_allclose(c["u_sat"], -(G @ net.T).T, atol=1e-12)
    # ... the net torques are the minimum-norm allocation of u_sat plus a null-space part, a multiple of the
    # null-space torque k_n N Js (Omega* - Omega), N = I - Gs^+ Gs over the healthy wheels
    null = net + (P @ c["u_sat"].T).T
    if w.null_gain_per_s > 0.0 and len(healthy) > 3:
        N = np.eye(n) - P @ G
        e = np.array(w.spin_inertia_kg_m2) * (np.array(w.null_speed_rad_s) - om)
        full = w.null_gain_per_s * (N @ e.T).T
        # null = r full with one r in [0, 1] per step (the uniform scale)
        nz = np.abs(full).max(axis=1) > 1e-9
        r = np.einsum("ij,ij->i", null[nz], full[nz]) / np.einsum("ij,ij->i", full[nz], full[nz])
        assert np.all(r > -1e-9) and np.all(r <= 1.0 + 1e-9)
        np.testing.assert_allclose(null[nz], r[:, None] * full[nz], atol=1e-9)
        # it ran, with a good share of what it asked for in some steps (the slew mostly leaves it little room)
        assert r.max() > 0.3
    else:
        np.testing.assert_allclose(null, 0.0, atol=1e-9)
    # one uniform scale keeps the direction of the law's command
    np.testing.assert_allclose(c["u_sat"], c["wheel_scale"][:, None] * c["u_unsat"], rtol=1e-9, atol=1e-12)
    # no wheel beyond its torque limit, a failed wheel gets nothing
    assert np.abs(u_w).max() <= max(w.torque_limit_nm) * (1 + 1e-12)
    for i in w.failed:
        assert np.all(u_w[:, i] == 0.0)
    # the plant applied what the flight software commanded (held motor torques in the next truth sample)
    np.testing.assert_allclose(log.truth["wheel_torque"][1:, :n][:, healthy], u_w[:, healthy], atol=1e-12)
    # and no wheel ran beyond its speed limit (one RK4 step of overshoot at most)
    assert np.abs(log.truth["wheel_speed"][:, :n]).max() <= max(w.speed_limit_rad_s) * (1 + 1e-3)
    return P


@pytest.mark.parametrize("sid", ["irassi_rw", "irassi_rw_failed"])
def test_the_slew_on_wheels_is_allocated_as_spec_5_3(run, tmp_path, sid):
    res, log = run(sid, tmp_path, duration=300.0, plots=True)
    sc = load(sid)
    _check_allocation(sc, log)
    m = res.metrics["wheels"]
    assert m["removed"] == list(sc.effectors["wheels"].failed) and m["within_limits"]
    # the wheels really carried the slew: hundreds of rad/s, tens of N m s
    assert max(p["peak_speed_rad_s"] for p in m["per_wheel"]) > 100.0
    assert m["wheel_momentum_nms"]["peak"] > 10.0
    # the true total momentum changes only by the external torque: |dH/dt| <= |L| (constant 1.18e-3 N m per
    # axis plus a far smaller gravity gradient), although the wheels exchange tens of N m s with the body
    HN = log.truth["h_total_N"]
    dt = sc.dt
    rate = np.linalg.norm(np.diff(HN, axis=0), axis=1) / dt
    assert rate.max() < 1.18e-3 * np.sqrt(3) * 1.01, rate.max()
    assert {"wheel_speeds.png", "momentum.png"} <= set(res.metrics["plots"])
    env = m["envelope"]
    assert env["eigenaxis_bound_s"] == pytest.approx(186.84 if sid == "irassi_rw" else 252.98, abs=0.01)
    text = res.table
    assert "peak wheel speed" in text and ("removed: wheel 0" in text) == (sid == "irassi_rw_failed")


@pytest.mark.parametrize("target", ["pil-m7", "pil-m4f"])
def test_the_pil_image_flies_the_wheels_like_the_host(run, tmp_path, target, aocs_build_dir):
    """The same guided slew with the flight software on an emulated Cortex-M (the bridge between LCM and the
    image): the wheel torques of the image obey SPEC 5.3 as above, and follow the host's (M7 double: to
    libm rounding; M4F float: to float rounding of the 0.25 N m range)."""
    pil_support.image(target)
    host_res, host = run("irassi_rw", tmp_path / "host", duration=60.0, guidance="slew")
    res, log = run("irassi_rw", tmp_path / target, duration=60.0, guidance="slew", target=target)
    sc = load("irassi_rw")
    if target == "pil-m7":
        _check_allocation(sc, log)
    n = sc.effectors["wheels"].n
    assert np.all(log.cmd["n_wheels"] == n) and np.all(log.cmd["wheel_status"] == 0)
    # M4F: the float loop drifts from the double one by float rounding, a fraction of a percent of the range
    tol = 1e-9 if target == "pil-m7" else 2e-3
    np.testing.assert_allclose(log.cmd["u_wheels"][:, :n], host.cmd["u_wheels"][:, :n], atol=tol)
    np.testing.assert_allclose(log.cmd["h_total"], host.cmd["h_total"], atol=1e3 * tol)
    assert res.metrics["timing"]["instruction_overruns"] == 0 and res.metrics["timing"]["instructions_inexact"] == 0


def test_plant_node_refuses_a_flight_computer_with_another_wheel_count(private_netns, fsw_node_bin, aocs_lcm,
                                                                        tmp_path):
    """fsw_node configured for a 3-wheel pyramid, plant_node flying irassi_rw's 4 wheels: the plant applies
    none of the flight computer's commands, ends with its no-reply exit code and says why in one line
    (plant_node.wheels_disagree), and the flight computer's process is left to its idle timeout."""
    sc3 = load("irassi_rw", {"wheels.count": 3, "wheels.null_gain_per_s": 0.0, "wheels.null_speed_rad_s": 0.0})
    assert sc3.effectors["wheels"].n == 3 and load("irassi_rw").effectors["wheels"].n == 4
    cfg = fsw_config.node_config(sc3, "quat_pd", idle_timeout_s=3.0)
    cfg_path = fsw_config.write(tmp_path / "fsw_node.cfg", cfg)
    ready = tmp_path / "plant.ready"
    with orchestrate.Processes() as procs:
        plant = procs.start("plant_node", [sys.executable, "-m", "aocs_runner.plant_node", "irassi_rw", "-q",
                                           "--ready-file", str(ready)],
                            stdout=tmp_path / "plant.out", stderr=tmp_path / "plant.err", env=paths.python_env())
        end = time.monotonic() + 30
        while not ready.exists():
            assert plant.alive() and time.monotonic() < end, "plant_node not ready"
            time.sleep(0.01)
        fc = procs.start("fsw_node", [fsw_node_bin, cfg_path], stdout=tmp_path / "fsw.out",
                         stderr=tmp_path / "fsw.err")
        rc = plant.wait(30)
        fc.stop()
    assert rc == 4     # EXIT_NO_REPLY of plant_node.py: no command of that flight computer can be applied
    err = [ln for ln in (tmp_path / "plant.err").read_text().splitlines() if ln.strip()]
    assert len(err) == 1, err
    assert err[0] == ("plant_node: the flight computer commands 3 wheel(s), the plant has 4 (its configuration "
                      "was not written from this scenario's [wheels])")
    summary = json.loads((tmp_path / "plant.out").read_text().strip().splitlines()[-1])["plant_node"]
    assert summary["reason"] == "wheels_mismatch"
    # refused at the first reply: nothing was integrated with the foreign commands
    assert summary["steps"] == 0
