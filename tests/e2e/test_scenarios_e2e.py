"""End to end: reference scenarios through real processes (plant_node,
fsw_node, the recorder) over LCM in a private network namespace, judged from
the recorded log.

Every expected value is computed here, independently of the runner and the
plant: the SPEC 1 quaternion algebra, the SPEC 2.2 law, the SPEC 2.8 LQR gain
from scipy's Riccati solver, the settle criteria of SPEC 4. A wrong sign, unit,
frame or message field anywhere in plant -> LCM -> executive -> LCM -> plant
breaks one of these assertions.
"""
from __future__ import annotations

import json
import math
import os
import shutil
import signal
import struct
import subprocess
import sys
from pathlib import Path

import lcm
import numpy as np
import pytest
import scipy.linalg

from aocs import cmd_replay
from aocs_plant.scenario import ScenarioError
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog, wire

REPO = Path(__file__).resolve().parents[2]
ARCSEC = 180 * 3600 / math.pi

JSON_KEYS = {"scenario", "law", "duration_s", "control_rate_hz", "settle_time_s", "pointing_error_arcsec",
             "max_abs_torque_nm", "max_torque_norm_nm", "effort", "position_error_m", "max_abs_force_n",
             "timing", "wall_s"}
TIMING_KEYS = {"step_ns_median", "step_ns_p99", "step_ns_max", "budget_ns", "overruns"}
COUNTER_KEYS = {"invalid", "stale", "missing", "law_error", "lost", "duplicate", "foreign", "malformed",
                "mode_changes", "time_in_safe_mode_s", "time_in_saturation_s", "cmd_accepted", "cmd_rejected"}


# ---- independent SPEC 1 algebra ---------------------------------------------------------
def qmul(q, p):
    """Shuster product, scalar last: [q4 pv + p4 qv - qv x pv; q4 p4 - qv.pv] (rows of (n, 4))."""
    q, p = np.atleast_2d(q), np.atleast_2d(p)
    qv, q4, pv, p4 = q[:, :3], q[:, 3:], p[:, :3], p[:, 3:]
    return np.hstack([q4 * pv + p4 * qv - np.cross(qv, pv), q4 * p4 - np.sum(qv * pv, axis=1, keepdims=True)])


def conj(q):
    q = np.array(q, float)
    q[..., :3] *= -1
    return q


def elem(axis, ang):
    e = np.zeros(4)
    e[axis] = math.sin(ang / 2)
    e[3] = math.cos(ang / 2)
    return e


def euler321_quat(yaw_deg, pitch_deg, roll_deg):
    """A = R1(roll) R2(pitch) R3(yaw)  ->  q = q_x(roll) (x) q_y(pitch) (x) q_z(yaw)."""
    y, p, r = (math.radians(a) for a in (yaw_deg, pitch_deg, roll_deg))
    return qmul(qmul(elem(0, r), elem(1, p)), elem(2, y))[0]


def true_angle_arcsec(q, qd):
    e = qmul(q, conj(np.broadcast_to(qd, np.shape(q))))
    return 2 * np.arcsin(np.clip(np.linalg.norm(e[:, :3], axis=1), 0, 1)) * ARCSEC


# ---- fixtures ------------------------------------------------------------------------------
@pytest.fixture(scope="module")
def run(private_netns, fsw_node_bin, aocs_lcm):
    def go(scenario, out, **kw):
        kw.setdefault("plots", False)
        return execute(RunOptions(scenario=scenario, out=str(out), quiet=True, **kw))
    return go


@pytest.fixture(scope="module")
def irassi_small(run, tmp_path_factory):
    out = tmp_path_factory.mktemp("irassi_small")
    res = run("irassi_small", out, plots=True, json_path=str(out / "copy.json"))
    return res, lcmlog.read(out / "run.lcmlog")


# ---- irassi_small, quat_pd ---------------------------------------------------------------
def test_irassi_small_reaches_10_arcsec_and_reports_every_key(irassi_small):
    res, log = irassi_small
    m = res.metrics
    assert JSON_KEYS <= set(m)
    assert TIMING_KEYS <= set(m["timing"]) and COUNTER_KEYS <= set(m["counters"])
    assert set(m["pointing_error_arcsec"]) >= {"final_max", "per_axis_final_max", "qe_arcsec_final_max"}
    assert m["position_error_m"] is None and m["max_abs_force_n"] is None
    assert m["scenario"] == "irassi_small" and m["law"] == "quat_pd"
    assert m["duration_s"] == 500.0 and m["control_rate_hz"] == 10.0
    assert json.loads((res.out_dir / "copy.json").read_text()) == json.loads((res.out_dir / "metrics.json").read_text())
    # the true angle, recomputed here from the logged truth and the scenario's target (SPEC 4:
    # the small manoeuvre, Euler 3-2-1 [14 14 14] deg to [13 13 13] deg, 1.59 deg)
    qd = euler321_quat(13, 13, 13)
    ang = true_angle_arcsec(log.truth["q"], qd)
    q0 = euler321_quat(14, 14, 14)                               # the scenario's start, rebuilt here
    assert ang[0] == pytest.approx(true_angle_arcsec(q0[None], qd)[0], rel=1e-12)
    assert ang[0] == pytest.approx(1.59 * 3600, rel=0.01)        # 5724 arcsec within 1 %
    assert m["pointing_error_arcsec"]["initial"] == pytest.approx(ang[0], rel=1e-12)
    assert ang[-1] < 10.0
    window = log.truth["t_s"] >= 400.0
    assert m["pointing_error_arcsec"]["final_max"] == pytest.approx(ang[window].max(), rel=1e-9, abs=1e-9)
    # settle: first time after which the angle stays under 10 arcsec
    outside = np.flatnonzero(ang >= 10.0)
    assert m["settle_time_s"] == pytest.approx(log.truth["t_s"][outside[-1] + 1])
    assert 18.0 <= m["settle_time_s"] <= 26.0
    assert m["pointing_error_arcsec"]["final_max"] == pytest.approx(0.2108, abs=5e-5)   # d / kp (SPEC 5.2)
    # the plant's own pointing figure agrees with the independent one (frames, sign of qe)
    assert np.allclose(log.truth["pointing_err_arcsec"], ang, rtol=1e-9, atol=1e-6)
    assert m["log_complete"] and log.truth["tick"].size == 5001 and log.cmd["tick"].size == 5000
    assert m["counters"]["invalid"] == 0 and m["final_mode"] == "nominal"


def test_irassi_small_commands_are_the_spec_law_of_the_logged_samples(irassi_small):
    """u = -kp sign(qe4) qe_vec - kd w (SPEC 2.2) from each logged sensors_t, and the plant applies it."""
    _, log = irassi_small
    kp, kd = 4000.0, 8000.0
    qd = euler321_quat(13, 13, 13)
    s, c = log.sensors, log.cmd
    assert np.array_equal(s["tick"], c["tick"])
    qe = qmul(s["q"], conj(np.broadcast_to(qd, s["q"].shape)))
    sgn = np.where(qe[:, 3] < 0, -1.0, 1.0)[:, None]
    u = -kp * sgn * qe[:, :3] - kd * s["w"]
    assert np.allclose(c["u_unsat"], u, rtol=1e-9, atol=1e-9 * np.abs(u).max())
    assert np.array_equal(c["u_sat"], c["u_unsat"])                 # unlimited reference run
    assert np.all(c["law_id"] == 2) and np.all(c["mode"] == 1) and np.all(c["status"] == 0)
    # the plant applies command k over [t_k, t_k+1]: truth k+1 reports it (ZOH, no sign flip)
    assert np.array_equal(log.truth["torque_applied"][1:], c["u_sat"])
    assert np.all(log.truth["torque_applied"][0] == 0.0)
    # sensors are the truth (ideal sensors) at the same tick
    assert np.array_equal(s["q"], log.truth["q"][:-1]) and np.array_equal(s["w"], log.truth["w"][:-1])
    # the metric of torque: max |u_i| from the commands
    m = json.loads(Path(log.path).with_name("metrics.json").read_text())
    assert m["max_abs_torque_nm"] == pytest.approx(np.abs(c["u_sat"]).max(axis=0).tolist(), rel=1e-12)
    assert m["effort"] == pytest.approx(np.abs(c["u_sat"]).sum() * 0.1, rel=1e-9)


def test_irassi_small_plots_are_small_pngs(irassi_small):
    res, _ = irassi_small
    names = {p.name for p in res.plots}
    assert names == {"attitude_error.png", "rates.png", "torques.png", "step_time.png"}
    for p in res.plots:
        data = p.read_bytes()
        assert data[:8] == b"\x89PNG\r\n\x1a\n" and 5_000 < len(data) < 200_000


def test_replay_matches_bit_for_bit_and_catches_a_one_bit_change(irassi_small, tmp_path, capsys):
    res, log = irassi_small
    assert cmd_replay.replay(Path(log.path), quiet=False) == 0
    assert "5000 commands identical" in capsys.readouterr().out
    # the same run with one bit of one recorded command flipped
    for name in ("run.json", "fsw_node.cfg"):
        shutil.copy(res.out_dir / name, tmp_path / name)
    src = lcm.EventLog(str(log.path), "r")
    dst = lcm.EventLog(str(tmp_path / "run.lcmlog"), "w", overwrite=True)
    off = struct.calcsize(">8siqqqhb")   # fingerprint, version, frame, utime, tick, law_id, mode: u_sat[0]
    n_cmd = 0
    for e in src:
        data = e.data
        if e.channel == wire.ACTUATOR:
            if n_cmd == 1234:
                b = bytearray(data)
                b[off + 7] ^= 1                       # last bit of u_sat[0] (big-endian double)
                data = bytes(b)
            n_cmd += 1
        dst.write_event(e.timestamp, e.channel, data)
    src.close()
    dst.close()
    assert cmd_replay.replay(tmp_path / "run.lcmlog") == 1
    out = capsys.readouterr().out
    assert "MISMATCH at command #1234 (tick 1234): u_sat[0]" in out


# ---- other reference scenarios --------------------------------------------------------
def test_rtc_ex2a_settles_within_its_window(run, tmp_path):
    res = run("rtc_ex2a", tmp_path, duration=25.0)
    log = lcmlog.read(tmp_path / "run.lcmlog")
    q, w = log.truth["q"], log.truth["w"]
    q = q * np.where(q[:, 3:] < 0, -1, 1)
    rho = np.linalg.norm(q[:, :3] / q[:, 3:], axis=1)
    inside = (rho < 1e-3) & (np.linalg.norm(w, axis=1) < 1e-3)
    assert inside[-1] and not inside[0]
    t_settle = log.truth["t_s"][np.flatnonzero(~inside)[-1] + 1]
    assert res.metrics["settle_time_s"] == pytest.approx(t_settle)
    assert 10.0 < t_settle < 25.0
    # crp_linear (SPEC 2.1): u = -19 w - 13 rho, short representative, target identity
    s, c = log.sensors, log.cmd
    qs = s["q"] * np.where(s["q"][:, 3:] < 0, -1, 1)
    u = -19.0 * s["w"] - 13.0 * qs[:, :3] / qs[:, 3:]
    assert np.allclose(c["u_unsat"], u, rtol=1e-9, atol=1e-9)
    assert res.metrics["control_rate_hz"] == 100.0 and log.cmd["tick"].size == 2500


def test_landsat8_q1_settles_with_the_lqr_gain_of_the_spec_model(run, tmp_path):
    res = run("landsat8_q1", tmp_path, duration=800.0)
    log = lcmlog.read(tmp_path / "run.lcmlog")
    m = res.metrics
    assert m["pointing_error_arcsec"] is None and m["max_abs_torque_nm"] is None
    assert m["settle_time_s"] is not None and 400.0 < m["settle_time_s"] < 700.0
    pos, vel = log.truth["pos"], log.truth["vel"]
    assert np.abs(pos[-1]).max() < 0.1 and np.abs(vel[-1]).max() < 0.01
    # metric window: the scenario's last 600 s, i.e. t >= 200 s of this shortened run
    t = log.truth["t_s"]
    assert m["position_error_m"]["final_max"] == pytest.approx(np.abs(pos[t >= 200.0]).max(), rel=1e-12)
    # F = -K x with K from the continuous ARE of SPEC 2.8 (Q = R = I), solved here
    n = math.sqrt(3.986004418e14 / 7080e3 ** 3)
    mass = 2623.0
    A = np.array([[0, 0, n, -n * n, 0, 0], [0, 0, 0, 0, -n * n, 0], [-n, 0, 0, 0, 0, 2 * n * n],
                  [1, 0, 0, 0, 0, n], [0, 1, 0, 0, 0, 0], [0, 0, 1, -n, 0, 0]])
    B = np.vstack([np.eye(3) / mass, np.zeros((3, 3))])
    S = scipy.linalg.solve_continuous_are(A, B, np.eye(6), np.eye(3))
    K = B.T @ S
    x = np.hstack([log.sensors["vel"], log.sensors["pos"]])          # [du dv dw dx dy dz]
    assert np.allclose(x[0], [1, -1, -6, 50, -100, 350])
    F = -(K @ x.T).T
    assert np.allclose(log.cmd["u_unsat"], F, rtol=1e-6, atol=1e-6 * np.abs(F).max())
    assert m["max_abs_force_n"] == pytest.approx(np.abs(log.cmd["u_sat"]).max(axis=0).tolist())
    assert np.all(log.cmd["law_id"] == 10)


def test_gao_mrp_torque_norm_never_above_um_and_sigma_decreases(run, tmp_path):
    res = run("gao_mrp", tmp_path, duration=900.0)
    log = lcmlog.read(tmp_path / "run.lcmlog")
    um = 0.05
    norms = np.linalg.norm(log.cmd["u_sat"], axis=1)
    assert norms.max() <= um * (1 + 1e-12)
    assert norms.max() > 0.5 * um                                     # the bound is actually used
    assert res.metrics["max_torque_norm_nm"] == pytest.approx(norms.max())
    q = log.truth["q"] * np.where(log.truth["q"][:, 3:] < 0, -1, 1)
    sigma = np.linalg.norm(q[:, :3] / (1 + q[:, 3:]), axis=1)
    assert sigma[0] == pytest.approx(math.sqrt(0.09 + 0.16 + 0.04), rel=1e-12)
    blocks = sigma[: (sigma.size // 500) * 500].reshape(-1, 500).max(axis=1)   # 50 s blocks
    assert np.all(np.diff(blocks) <= 1e-12), blocks
    assert sigma[-1] < 1e-3 and res.metrics["settle_time_s"] is not None
    assert np.all(log.cmd["law_id"] == 8)


def test_geo_hinf_tracks_the_rotating_lvlh_target(run, tmp_path):
    res = run("geo_hinf", tmp_path, duration=600.0)
    log = lcmlog.read(tmp_path / "run.lcmlog")
    t = log.truth["t_s"]
    w0 = 7.292115e-05
    # LVLH target: identity turned by -w0 t about y, computed here
    qd = np.stack([np.zeros_like(t), np.sin(-w0 * t / 2), np.zeros_like(t), np.cos(-w0 * t / 2)], axis=1)
    err = qmul(log.truth["q"], conj(qd))
    err *= np.where(err[:, 3:] < 0, -1, 1)
    ang = 2 * np.arcsin(np.linalg.norm(err[:, :3], axis=1))
    assert ang[0] > 0.01 and ang[-1] < 1e-3                      # 0.5 deg errors removed
    assert np.all(ang[t > 300] < 2e-3)                           # and kept small: stable
    # the body followed the target: ~w0 * 600 s = 0.044 rad of pitch about -y from N
    body_pitch = 2 * math.atan2(log.truth["q"][-1, 1], log.truth["q"][-1, 3])
    assert body_pitch == pytest.approx(-w0 * t[-1], abs=2e-3)
    assert res.metrics["settle_time_s"] is not None
    assert np.all(log.cmd["law_id"] == 7) and np.all(log.cmd["status"] == 0)


# ---- wrong signs are caught -------------------------------------------------------------
def test_a_negative_gain_is_refused_before_anything_flies(run, tmp_path, fsw_node_bin):
    with pytest.raises(ScenarioError, match="laws.quat_pd.kp"):
        run("irassi_small", tmp_path, sets=["laws.quat_pd.kp=-4000.0"])
    assert not (tmp_path / "run.lcmlog").exists()
    # and the flight software refuses it too (configuration error, exit 2, key named)
    p = tmp_path / "neg.cfg"
    p.write_text("law = quat_pd\nquat_pd.kp = -4000\nquat_pd.kd = 8000\nu_max_axis = 1 1 1\n")
    r = subprocess.run([str(fsw_node_bin), str(p)], capture_output=True, text=True, timeout=10)
    assert r.returncode == 2 and "quat_pd.kp" in r.stderr


def test_metrics_judge_against_the_scenario_not_the_flight_software_view(run, tmp_path):
    """Command the conjugate target (the classic scalar-first / inverse mix-up): the flight
    software converges to it happily, the log-based metrics report the miss."""
    qd = euler321_quat(30, -20, 1)
    wrong = conj(qd)
    res = run("irassi_small", tmp_path, duration=200.0,
              events=["0:target=" + ",".join(repr(float(x)) for x in wrong)])
    m = res.metrics
    assert m["commands"] and m["commands"][0]["status"] == "AOCS_OK"
    log = lcmlog.read(tmp_path / "run.lcmlog")
    to_wrong = true_angle_arcsec(log.truth["q"], wrong)
    assert to_wrong[-1] < 10.0                                   # it went where it was told
    assert m["settle_time_s"] is None
    assert m["pointing_error_arcsec"]["final_max"] > 1e5         # ~2 x 30 deg from the real target


# ---- processes that die or stop answering (lockstep): a clear error, never a hang ----------
def _children(pid):
    out = []
    for tid in os.listdir(f"/proc/{pid}/task"):
        with open(f"/proc/{pid}/task/{tid}/children") as f:
            out += [int(x) for x in f.read().split()]
    return out


def _find_child(pid, needle):
    """The child whose command line or name (/proc/PID/comm: a plant forked by the runner keeps the
    runner's command line and is named plant_node, aocs_runner.plant_fork) contains needle."""
    for c in _children(pid):
        try:
            with open(f"/proc/{c}/cmdline", "rb") as f, open(f"/proc/{c}/comm", "rb") as g:
                if needle in f.read() or needle in g.read():
                    return c
        except FileNotFoundError:
            continue
    raise AssertionError(f"no child process of {pid} matches {needle!r}")


@pytest.mark.parametrize("victim,action,expect", [
    (b"fsw_node", signal.SIGKILL, "fsw_node killed by SIGKILL"),
    (b"plant_node", signal.SIGKILL, "plant_node killed by SIGKILL"),
    (b"fsw_node", signal.SIGSTOP, "plant_node exit code 4 (the flight computer stopped answering)"),
    # a frozen plant is the plant's failure, not the flight computer's (issue 25, item 9)
    (b"plant_node", signal.SIGSTOP, "plant_node stopped sending sensor frames"),
])
def test_a_dead_or_silent_process_ends_the_run_with_a_clear_message(tmp_path, fsw_node_bin, victim, action, expect):
    env = dict(os.environ)
    cmd = [sys.executable, "-m", "aocs.cli", "run", "landsat8_q1", "--out", str(tmp_path), "--no-plots",
           "--reply-timeout", "1.0"]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, env=env)
    victim_pid = None
    try:
        lines = []
        for line in proc.stderr:                     # progress lines of the plant (every 10 %)
            lines.append(line)
            if "20% tick" in line:
                victim_pid = _find_child(proc.pid, victim)
                os.kill(victim_pid, action)
                break
        assert victim_pid is not None, "".join(lines)
        out, err = proc.communicate(timeout=60)      # bounded: the run must end by itself
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
    err = "".join(lines) + err
    assert proc.returncode == 1, err
    assert expect in err, err
    last = int(err.split("last tick answered ")[1].split()[0])
    assert 5999 <= last < 30000                              # at or after the 20 % line
    if action == signal.SIGSTOP and victim == b"fsw_node":
        assert "stopped answering" in err
    if victim == b"plant_node":
        assert "FAILED: fsw_node" not in err
    assert not os.path.exists(f"/proc/{victim_pid}")         # reaped: nothing left behind


def test_realtime_run_paces_to_the_clock_and_reports_jitter(run, tmp_path):
    res = run("irassi_small", tmp_path, duration=2.0, realtime=True, limit=0.5)
    m = res.metrics
    log = lcmlog.read(tmp_path / "run.lcmlog")
    assert m["run_mode"] == "realtime" and m["fsw_node"]["run_mode"] == "realtime"
    assert m["realtime"]["jitter_ns_max"] is not None and m["realtime"]["plant_wake_jitter_ns_max"] is not None
    assert log.truth["tick"].tolist() == list(range(21)) and log.sensors["tick"].size == 20
    # the node steps on its own clock: ~one command per period, each naming the sample it used
    assert log.cmd["tick"].size >= 15 and np.all(np.diff(log.cmd["tick"]) >= 0)
    assert np.abs(log.cmd["u_sat"]).max() <= 0.5 * (1 + 1e-12)
    # paced, not as fast as possible: 2 s of simulation span at least ~2 s of receive time
    # (a lower bound only: a slow machine cannot fail it)
    span = (log.truth["log_utime"][-1] - log.truth["log_utime"][0]) / 1e6
    assert span >= 1.9
    assert m["counters"]["invalid"] == 0


# ---- processor in the loop: the runner drives the real bridge and QEMU ------------------
def _cli_run(out: Path, *args) -> dict:
    """`aocs run ... --json F` as a real process (inside this test's private namespace)."""
    js = out / "m.json"
    r = subprocess.run([sys.executable, "-m", "aocs.cli", "run", *args, "--json", str(js), "--out", str(out),
                        "--no-plots", "-q"], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr
    return json.loads(js.read_text())


@pytest.fixture(scope="module")
def irassi_60s_host(private_netns, fsw_node_bin, aocs_lcm, tmp_path_factory):
    out = tmp_path_factory.mktemp("irassi_60s_host")
    m = _cli_run(out, "irassi_small", "--duration", "60", "--target", "host")
    return m, lcmlog.read(out / "run.lcmlog")


# quat_pd's laws.def row + fault management's allowance (aocs/budget.h, fdir.enabled by default)
@pytest.mark.parametrize("target,budget,clock_hz", [("pil-m4f", 2500 + 8500, 168e6), ("pil-m7", 2900 + 12100, 216e6)])
def test_pil_run_reports_instruction_timing_and_matches_the_host(irassi_60s_host, tmp_path, target, budget,
                                                                  clock_hz):
    """docs/pil.md: instruction figures in timing, overruns from the bridge's flags, and the
    M7 (double) commands equal to the host double run's bit for bit (quat_pd: + - * / sqrt only);
    the M4F (float) ones within float rounding of the command range."""
    m = _cli_run(tmp_path, "irassi_small", "--duration", "60", "--target", target)
    log = lcmlog.read(tmp_path / "run.lcmlog")
    tm = m["timing"]
    assert m["target"] == target and tm["target"] == target and tm["clock_hz"] == clock_hz
    # the runner told the bridge where the image is, and recorded it
    run_json = json.loads((tmp_path / "run.json").read_text())
    assert m["fsw_node"]["image"]["path"] == run_json["pil_image"]
    assert Path(run_json["pil_image"]).is_file() and Path(run_json["pil_image"]).parent.name == \
        {"pil-m4f": "cortex-m4f", "pil-m7": "cortex-m7"}[target]
    assert TIMING_KEYS <= set(tm) and tm["steps"] == 600
    ins = m["fsw_node"]["instructions"]                      # the bridge's own final JSON
    assert (tm["instructions_median"], tm["instructions_p99"], tm["instructions_max"]) == \
        (ins["median"], ins["p99"], ins["max"])
    assert tm["instructions_budget"] == budget == ins["budget"]  # firmware budget.h row of quat_pd
    assert 500 < tm["instructions_median"] <= tm["instructions_p99"] <= tm["instructions_max"] < budget
    assert tm["instruction_overruns"] == 0 and tm["overruns"] == 0 and tm["over_step_budget"] == 0
    assert tm["budget_ns"] == pytest.approx(budget * 1e9 / clock_hz)
    # step_ns on the wire is instructions / nominal clock: the max matches the bridge's count
    assert tm["step_ns_max"] == pytest.approx(ins["max"] * 1e9 / clock_hz, abs=1.0)
    assert not np.any(log.cmd["overrun"]) and np.all(log.cmd["n_overrun"] == 0)
    # the loop closed: true angle recomputed from the logged truth, under 10 arcsec at 60 s
    ang = true_angle_arcsec(log.truth["q"], euler321_quat(13, 13, 13))
    assert ang[0] > 3600 and ang[-1] < 10.0
    assert m["counters"]["invalid"] == 0 and m["final_mode"] == "nominal" and m["log_complete"]
    hm, hlog = irassi_60s_host
    assert np.array_equal(log.cmd["tick"], hlog.cmd["tick"])
    if target == "pil-m7":
        assert np.array_equal(log.cmd["u_sat"].view(np.uint64), hlog.cmd["u_sat"].view(np.uint64))
        assert np.array_equal(log.truth["q"], hlog.truth["q"])
    else:
        u_range = np.abs(hlog.cmd["u_sat"]).max()
        assert np.abs(log.cmd["u_sat"] - hlog.cmd["u_sat"]).max() < 1e-5 * u_range
        assert not np.array_equal(log.cmd["u_sat"], hlog.cmd["u_sat"])   # float really flew
        assert abs(ang[-1] - true_angle_arcsec(hlog.truth["q"][-1:], euler321_quat(13, 13, 13))[0]) < 0.05


def test_orbit_scenario_with_control_disabled_counts_no_invalid_sample(run, tmp_path):
    """law none (STANDBY) accepts orbit samples (executive input check, mode.c): 0 invalid, and
    the vehicle drifts with zero commanded force."""
    res = run("landsat8_debris", tmp_path, duration=120.0, sets=["control.enabled=false"])  # impulse at 60 s
    log = lcmlog.read(tmp_path / "run.lcmlog")
    m = res.metrics
    assert m["law"] == "none" and m["kind"] == "orbit" and log.cmd["tick"].size > 0
    assert m["counters"]["invalid"] == 0 and np.all(log.cmd["n_invalid"] == 0)
    assert np.all(log.cmd["status"] == 0) and np.all(log.cmd["mode"] == 0) and m["final_mode"] == "standby"
    assert np.all(log.cmd["u_sat"] == 0.0) and np.all(log.truth["force_applied"] == 0.0)


def test_plant_applied_is_the_period_mean_of_the_actuator_output():
    """Plant.applied (public): zero before any step, then the applied command of the period,
    the same value truth() reports."""
    from aocs_plant import Plant, load

    sc = load("irassi_small")
    plant = Plant(sc)
    assert plant.applied == (0.0, 0.0, 0.0) == plant.truth()["applied"]
    u = (0.125, -0.25, 0.0625)                              # exact binary fractions, no lag, unlimited
    plant.apply({"u_body": u})
    plant.advance()
    assert plant.applied == u and plant.truth()["applied"] == u


def test_pil_image_location_passed_to_the_bridge(monkeypatch, tmp_path):
    """AOCS_PIL_BUILD_ROOT when set (only there), else the host build dir's parent, else <repo>/build."""
    from aocs_core import paths
    from aocs_runner import run as cmd_run

    for preset in ("cortex-m4f", "cortex-m7"):
        (tmp_path / "root" / preset).mkdir(parents=True)
        (tmp_path / "root" / preset / "aocs_pil.elf").write_bytes(b"\x7fELF")
    (tmp_path / "root" / "host").mkdir()
    monkeypatch.delenv("AOCS_PIL_BUILD_ROOT", raising=False)
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path / "root" / "host"))
    assert cmd_run.pil_build_root("pil-m7") == (tmp_path / "root").resolve()
    monkeypatch.setenv("AOCS_BUILD_DIR", str(tmp_path / "elsewhere" / "host"))
    if (REPO / "build" / "cortex-m4f" / "aocs_pil.elf").is_file():
        assert cmd_run.pil_build_root("pil-m4f") == (REPO / "build").resolve()
    else:
        with pytest.raises(paths.SetupError, match="cortex-m4f/aocs_pil.elf"):
            cmd_run.pil_build_root("pil-m4f")
    monkeypatch.setenv("AOCS_PIL_BUILD_ROOT", str(tmp_path / "root"))
    assert cmd_run.pil_build_root("pil-m4f") == (tmp_path / "root").resolve()
    monkeypatch.setenv("AOCS_PIL_BUILD_ROOT", str(tmp_path / "empty"))
    with pytest.raises(paths.SetupError, match="cortex-m4f/aocs_pil.elf"):
        cmd_run.pil_build_root("pil-m4f")
