"""The PIL bridge on LCM, in a private network namespace, against fsw_node.

- Equivalence: irassi_small (quat_pd), gao_mrp (mrp_sat) and geo_hinf
  (hinf, rotating target) cut to 60 s, closed loop with the in-process
  plant: the M7 (double) image's commands are bit for bit the host SIL's at
  every tick where the step uses only correctly rounded operations (+ - * /
  sqrt), and within 1e-14 of the command range where newlib's sin / cos /
  atan2 differ from glibc's in the last bit (geo_hinf); the M4F (float)
  image's deviate by float rounding only (measured on the host run's own
  samples) and its closed loop tracks the host's.
- Budgets: the instruction counts in the bridge's JSON are exact, within
  the firmware budget table, without overrun.
- The wire: the same scripted message sequence (duplicates, lost, foreign
  and malformed frames, NaN, commands accepted and rejected) gets the same
  replies and acknowledgements from the bridge as from fsw_node.
- Failures end the bridge with exit status 1 and a message that says what
  happened, within bounded time: QEMU killed (mid-run and idle), QEMU
  stalled, a corrupted frame; configuration errors exit 2 like fsw_node.
"""
from __future__ import annotations

import json
import math
import os
import re
import signal
import subprocess
import sys
import time

import pytest

from aocs_core import registry
from aocs_pil import harness
from aocs_pil.qemu import TARGETS as QEMU_TARGETS
from pil_support import TARGETS, image

CUT = {"irassi_small": ("quat_pd", 60.0), "gao_mrp": ("mrp_sat", 60.0), "geo_hinf": ("hinf", 60.0)}
#: scenarios whose M7 commands are bit for bit the host's (no libm transcendental function in the step)
BITWISE = {"irassi_small", "gao_mrp"}
M7_LIBM_TOL = 1e-14   # |u_M7 - u_host| / max |u| where newlib and glibc round sin/cos/atan2 differently
F32_EPS = 2.0 ** -24   # unit roundoff of binary32
ARCSEC_PER_RAD = 206264.80624709636


def budget(law: str, target: str) -> int:
    """Instruction budget of the law's laws.def row on the target (the build's registry), plus fault
    management's allowance (fdir.enabled, the default)."""
    reg = registry.load()
    core = {"pil-m4f": "cortex-m4f", "pil-m7": "cortex-m7"}[target]
    return reg.law(law).budget_instructions[core] + reg.fdir_instructions[core]


@pytest.fixture(scope="module")
def env(aocs_build_dir):
    os.environ["AOCS_BUILD_DIR"] = str(aocs_build_dir)
    for t in TARGETS:
        image(t)
    return aocs_build_dir


@pytest.fixture(scope="module")
def runs(env, private_netns, aocs_lcm):
    """Closed loops on host, pil-m7 and pil-m4f, plus the M4F fed the host run's samples (open loop)."""
    out = {}
    for sid, (law, dur) in CUT.items():
        host = harness.run(sid, law, "host", duration_s=dur)
        out[sid] = {
            "host": host,
            "pil-m7": harness.run(sid, law, "pil-m7", duration_s=dur),
            "pil-m4f": harness.run(sid, law, "pil-m4f", duration_s=dur),
            "pil-m4f-replay": harness.run(sid, law, "pil-m4f", duration_s=dur, sensors=host.sensors),
        }
    return out


@pytest.mark.parametrize("sid", sorted(CUT))
def test_every_run_completed(runs, sid):
    for name, r in runs[sid].items():
        n = round(CUT[sid][1] / r.dt)
        assert r.returncode == 0, f"{name}: {r.stderr[-2000:]}"
        assert len(r.u_sat) == n and r.stats["steps"] == n and r.stats["reason"] == "signal"
        assert set(r.law_id) == {harness_law_id(CUT[sid][0])} and set(r.mode) == {1} and set(r.status) == {0}


def harness_law_id(law):
    return registry.law_ids()[law]


@pytest.mark.parametrize("sid", sorted(BITWISE))
def test_m7_commands_are_the_host_commands_bit_for_bit(runs, sid):
    host, m7 = runs[sid]["host"], runs[sid]["pil-m7"]
    c = harness.compare(host, m7)
    assert c["identical_steps"] == c["steps"] == len(host.u_sat), c
    # identical commands in a closed loop: identical trajectories
    assert m7.pointing_arcsec == host.pointing_arcsec
    assert m7.sensors == host.sensors


@pytest.mark.parametrize("sid", sorted(set(CUT) - BITWISE))
def test_m7_commands_match_the_host_to_libm_rounding(runs, sid):
    host, m7 = runs[sid]["host"], runs[sid]["pil-m7"]
    c = harness.compare(host, m7)
    assert c["u_sat_max_diff_over_max_u"] <= M7_LIBM_TOL, c
    assert (m7.mode, m7.status, m7.law_id) == (host.mode, host.status, host.law_id)
    assert max(abs(a - b) for a, b in zip(host.pointing_arcsec, m7.pointing_arcsec)) <= 1e-9


@pytest.mark.parametrize("sid", sorted(CUT))
def test_m4f_deviation_is_float_rounding(runs, sid):
    host, m4f = runs[sid]["host"], runs[sid]["pil-m4f-replay"]
    assert m4f.sensors == host.sensors                 # the same samples in
    c = harness.compare(host, m4f)
    assert c["identical_steps"] < c["steps"]           # really a float computation
    u_max = max(abs(x) for u in host.u_unsat for x in u)
    # a few dozen binary32 roundings of the O(1) attitude terms, scaled by the law's command range
    bound = 64 * F32_EPS * u_max
    assert c["u_sat_abs_max_diff"] <= bound, (c, bound)
    assert c["u_sat_abs_max_diff"] > 0.0


@pytest.mark.parametrize("sid", sorted(CUT))
def test_m4f_closed_loop_tracks_the_host(runs, sid):
    """The float loop stays within the float resolution of an attitude (2^-23 rad of a quaternion component
    near 1, as a true angle) plus a few float roundings of the angle itself."""
    host, m4f = runs[sid]["host"], runs[sid]["pil-m4f"]
    resolution = 2.0 ** -23 * ARCSEC_PER_RAD
    for k, (a, b) in enumerate(zip(host.pointing_arcsec, m4f.pointing_arcsec)):
        assert abs(a - b) <= resolution + 8 * F32_EPS * a, f"tick {k}: host {a} arcsec, M4F {b} arcsec"


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("sid", sorted(CUT))
def test_instruction_counts_in_the_json_within_budget(runs, sid, target):
    law = CUT[sid][0]
    r = runs[sid][target]
    host = runs[sid]["host"]
    st = r.stats
    ins = st["instructions"]
    n = len(r.u_sat)
    assert st["target"] == target and st["clock_hz"] == QEMU_TARGETS[target].clock_hz
    assert ins["n"] == n and ins["inexact"] == 0
    assert ins["budget"] == budget(law, target)
    assert 500 < ins["median"] <= ins["p99"] <= ins["max"] <= ins["budget"]
    assert ins["overruns"] == st["overruns"] == 0 and not any(r.overrun)
    assert 0 < st["law_instructions"]["max"] < ins["max"]
    # step_ns is the instruction count at the nominal clock (1 instruction per cycle)
    clock = QEMU_TARGETS[target].clock_hz
    assert st["step_ns"]["max"] == round(ins["max"] * 1e9 / clock)
    assert max(r.step_ns) == st["step_ns"]["max"]
    # every key of fsw_node's JSON is there, with the same meaning for the counters
    assert set(host.stats) <= set(st)
    for key in ("law", "mode", "steps", "sensor_frames", "lost", "duplicate", "foreign", "malformed", "invalid",
                "stale", "missing", "law_error", "mode_transitions", "cmd_accepted", "cmd_rejected"):
        assert st[key] == host.stats[key], key
    assert st["image"]["stack_bytes"] > 0 and st["image"]["frame_errors"] == 0


# ---- the wire, message for message ------------------------------------------------------------
def _script(link, aocs_lcm, collect):
    """A fixed sequence of sensors and commands; returns what came back."""
    import random
    rng = random.Random(5)
    q0 = [0.1, -0.2, 0.3, 0.9273618495495703]

    def unit(v):
        n = math.sqrt(sum(x * x for x in v))
        return [x / n for x in v]

    def sample(k, **kw):
        q = unit([q0[i] + 0.05 * rng.uniform(-1, 1) for i in range(4)])
        w = [0.02 * rng.uniform(-1, 1) for _ in range(3)]
        return link.send_sensors(k, q, w, **kw)

    sent = 0
    for k in range(4):
        sample(k)
        sent += 1
        collect(sent)
    sample(3, frame=3)                                   # duplicate
    sample(4, frame=4, version=99)                       # foreign
    raw = link.sensors(4, q0, [0, 0, 0], frame=4).encode()
    link.frame = 4
    for bad in (b"", b"\x01\x02", raw[:-8], raw + b"\x00"):
        link.lc.publish("AOCS_SENSORS", bad)             # malformed
    sample(6, frame=6)                                   # frames 4 and 5 lost
    sent += 1
    collect(sent)
    link.send_sensors(7, q0, [float("nan"), 0, 0])       # invalid: SAFE
    sent += 1
    collect(sent)
    link.send_sensors(8, q0, [0, 0, 0], valid=aocs_lcm.sensors_t.VALID_ATTITUDE)
    sent += 1
    collect(sent)
    acks = []
    for req, kw in ((1, dict(law_id=1)), (2, dict(qd=unit([0.0, 0.1, 0.0, 1.0]), wd=(0.0, 0.01, 0.0))),
                    (3, dict(mode=aocs_lcm.command_t.MODE_STANDBY)), (4, dict(mode=aocs_lcm.command_t.MODE_NOMINAL)),
                    (5, dict(law_id=99)), (6, dict(mode=aocs_lcm.command_t.MODE_SAFE)),
                    (7, dict(qd=[0.0, 0.0, 0.0, 2.0])), (8, dict(law_id=2))):
        link.clear()
        link.send_command(req, **kw)
        st = link.wait_for("AOCS_STATUS", 1, 5.0, pred=lambda s, r=req: s.last_request == r)[0]
        acks.append((st.last_request, st.last_request_status, st.n_cmd_accepted, st.n_cmd_rejected, st.law_id,
                     st.mode))
        link.clear()
        for j in range(3):
            sample(9 + 3 * (req - 1) + j)
            link.wait_for("AOCS_ACTUATOR_CMD", j + 1, 5.0)
        acks.append(tuple((m.tick, m.law_id, m.mode, m.status, tuple(m.u_sat))
                          for m in link.inbox["AOCS_ACTUATOR_CMD"]))
    return acks


def _run_script(cmd, cfg_path, link, aocs_lcm, tmp_path, name):
    out, err = tmp_path / f"{name}.out", tmp_path / f"{name}.err"
    with open(out, "w") as fo, open(err, "w") as fe:
        p = subprocess.Popen(cmd + [str(cfg_path)], stdout=fo, stderr=fe)
        try:
            link.pump(0.05)
            link.clear()
            link.wait_for("AOCS_STATUS", 1, 20.0, pred=lambda s: not s.exiting)
            link.clear()
            link.frame = 0
            replies = []

            def collect(n):
                replies[:] = link.wait_for("AOCS_ACTUATOR_CMD", n, 5.0)

            acks = _script(link, aocs_lcm, collect)
            replies = list(replies)
            p.send_signal(signal.SIGTERM)
            assert p.wait(timeout=10) == 0, err.read_text()
        finally:
            if p.poll() is None:
                p.kill()
    stats = json.loads([ln for ln in out.read_text().splitlines() if ln.startswith("{")][-1])["fsw_node"]
    return replies, acks, stats


def test_wire_behaviour_is_fsw_nodes(env, fsw_node_bin, lcm_link, aocs_lcm, node_config, tmp_path):
    cfg, write = node_config
    path = write(tmp_path / "wire.cfg", cfg)
    host = _run_script([str(fsw_node_bin)], path, lcm_link, aocs_lcm, tmp_path, "host")
    pil = _run_script([sys.executable, "-m", "aocs_pil.bridge", "--target", "pil-m7"], path, lcm_link, aocs_lcm,
                      tmp_path, "pil")
    (h_rep, h_acks, h_st), (p_rep, p_acks, p_st) = host, pil
    assert len(h_rep) == len(p_rep) == 7
    fields = ("tick", "law_id", "mode", "u_sat", "u_unsat", "saturated", "status", "n_invalid", "n_stale",
              "n_missing", "n_law_error", "n_lost", "n_duplicate", "n_foreign", "n_malformed", "n_cmd_accepted",
              "n_cmd_rejected", "utime", "frame")
    for a, b in zip(h_rep, p_rep):
        for f in fields:
            assert getattr(a, f) == getattr(b, f), (f, a.tick)
    # frames 0-3 accepted, 3 again (duplicate), 4 foreign (dropped before the sequence check), then 6: 4, 5 lost
    assert (p_rep[-1].n_duplicate, p_rep[-1].n_foreign, p_rep[-1].n_malformed, p_rep[-1].n_lost) == (1, 1, 4, 2)
    assert p_rep[-2].mode == 2 and p_rep[-1].mode == 2            # NaN and a validity flag off: SAFE
    assert p_acks == h_acks                                       # commands, acks and the replies after them
    statuses = [a[1] for a in p_acks[::2]]
    assert statuses[:4] == [0, 0, 0, 0] and all(s != 0 for s in statuses[4:7]) and statuses[7] == 0
    for key in ("law", "mode", "steps", "sensor_frames", "lost", "duplicate", "foreign", "malformed", "invalid",
                "stale", "missing", "law_error", "mode_transitions", "saturated", "cmd_accepted", "cmd_rejected"):
        assert p_st[key] == h_st[key], key


# ---- failures: clear, bounded, exit status 1 --------------------------------------------------
def _bridge(tmp_path, target, extra=(), law="quat_pd"):
    from aocs_flightcfg import fsw_config
    from aocs_plant.scenario import load
    sc = load("irassi_small")
    cfg = fsw_config.write(tmp_path / "f.cfg", harness.node_config_for(sc, law))
    return harness.FlightComputer(target, cfg, tmp_path, extra_args=list(extra))


def _qemu_pid(fc, timeout=20.0):
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        m = re.search(r"pid (\d+)", fc.stderr())
        if m:
            return int(m.group(1))
        assert fc.proc.poll() is None, fc.stderr()
        time.sleep(0.05)
    raise AssertionError(f"no QEMU pid in the bridge's stderr: {fc.stderr()}")


def _drive(wire, fc, ticks, q=(0.1, 0.1, 0.1, 0.98488578017961), timeout=10.0):
    for k in ticks:
        wire.send_sensors(k, 0.1 * k, 3, q, (0.0, 0.0, 0.0), (0.0, 0.0, 0.0), (0.0, 0.0, 0.0))
        wire.wait_cmd(k, fc, timeout)


def _ends_with_failure(fc, timeout):
    t0 = time.monotonic()
    try:
        rc = fc.proc.wait(timeout=timeout)
    except subprocess.TimeoutExpired:
        fc.proc.kill()
        raise AssertionError(f"the bridge did not end within {timeout} s: {fc.stderr()}")
    elapsed = time.monotonic() - t0
    fc.stop()
    return rc, elapsed, fc.stderr(), fc.stats()


@pytest.mark.parametrize("target", TARGETS)
def test_qemu_killed_mid_run(env, private_netns, aocs_lcm, tmp_path, target):
    fc = _bridge(tmp_path, target)
    wire = harness.Wire(aocs_lcm)
    wire.wait_ready(fc)
    _drive(wire, fc, range(5))
    os.kill(_qemu_pid(fc), signal.SIGKILL)
    wire.send_sensors(5, 0.5, 3, (0, 0, 0, 1), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    rc, elapsed, err, stats = _ends_with_failure(fc, 10.0)
    assert rc == 1 and elapsed < 5.0
    assert "QEMU exited" in err and "killed by signal SIGKILL" in err
    assert stats["reason"] == "pil_error" and stats["steps"] == 5 and "QEMU exited" in stats["error"]
    wire.pump(0.1)
    assert 5 not in wire.cmds                                # no command invented for the failed tick


def test_qemu_killed_while_idle(env, private_netns, aocs_lcm, tmp_path):
    fc = _bridge(tmp_path, "pil-m4f")
    wire = harness.Wire(aocs_lcm)
    wire.wait_ready(fc)
    os.kill(_qemu_pid(fc), signal.SIGKILL)
    rc, elapsed, err, stats = _ends_with_failure(fc, 10.0)
    assert rc == 1 and elapsed < 3.0
    assert "QEMU exited while waiting for sensors" in err


def test_qemu_stalled(env, private_netns, aocs_lcm, tmp_path):
    fc = _bridge(tmp_path, "pil-m7", extra=["--reply-timeout", "1.0"])
    wire = harness.Wire(aocs_lcm)
    wire.wait_ready(fc)
    _drive(wire, fc, range(3))
    pid = _qemu_pid(fc)
    os.kill(pid, signal.SIGSTOP)
    try:
        wire.send_sensors(3, 0.3, 3, (0, 0, 0, 1), (0, 0, 0), (0, 0, 0), (0, 0, 0))
        rc, elapsed, err, stats = _ends_with_failure(fc, 10.0)
    finally:
        try:
            os.kill(pid, signal.SIGCONT)
        except ProcessLookupError:
            pass
    assert rc == 1 and 0.9 < elapsed < 5.0
    assert "did not answer within the timeout" in err and "stalled" in err and "tick 3" in err
    assert stats["reason"] == "pil_error" and stats["steps"] == 3
    time.sleep(0.2)
    with pytest.raises(ProcessLookupError):                 # the bridge killed the stalled QEMU
        os.kill(pid, 0)


@pytest.mark.parametrize("target", TARGETS)
def test_corrupted_frame(env, private_netns, aocs_lcm, tmp_path, target):
    fc = _bridge(tmp_path, target, extra=["--fault-corrupt-step", "3"])
    wire = harness.Wire(aocs_lcm)
    wire.wait_ready(fc)
    _drive(wire, fc, range(3))
    wire.send_sensors(3, 0.3, 3, (0, 0, 0, 1), (0, 0, 0), (0, 0, 0), (0, 0, 0))
    rc, elapsed, err, stats = _ends_with_failure(fc, 10.0)
    assert rc == 1 and elapsed < 5.0
    assert "frame error at tick 3" in err and "AOCS_PIL_ERR_CRC" in err and "corrupted" in err
    assert stats["reason"] == "pil_error" and stats["steps"] == 3


# ---- configuration errors: exit 2 and fsw_node's words ----------------------------------------
@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("cfg_text", [
    "law = quat_pd\nquat_pd.kp = 1\nquat_pd.kd = 1\n",                                   # no actuator limit
    "law = mrp_sat\nu_max_axis = 1 1 1\nmrp_sat.k = 1\nmrp_sat.lambda = 1\nmrp_sat.u_max = 0.05\n"
    "mrp_sat.l1 = 0.05 0.05 0.05\nmrp_sat.m1 = 0.05 0.05 0.05\nmrp_sat.l2 = 0.06 0.06 0.06\n"
    "mrp_sat.m2 = 0.06 0.06 0.06\n",                                                     # M2 > 2 uM / sqrt 3
    "law = smc\nu_max_axis = 1 1 1\ninertia = 1 2 3 4 5 6 7 8 9\nsmc.lambda = 1 1 1\nsmc.g = 1 1 1\n"
    "smc.eps = 1 1 1\n",                                                                 # inertia not symmetric
    "law = lqr_quat\nu_max_axis = 1 1 1\n",                                              # no gain given
])
def test_executive_config_errors_like_fsw_node(env, fsw_node_bin, tmp_path, target, cfg_text):
    from aocs_wire import netns
    path = tmp_path / "bad.cfg"
    path.write_text(cfg_text)
    node = subprocess.run(netns.wrap([str(fsw_node_bin), str(path)]), capture_output=True, text=True, timeout=20)
    pil = subprocess.run(netns.wrap([sys.executable, "-m", "aocs_pil.bridge", "--target", target, str(path)]),
                         capture_output=True, text=True, timeout=30)
    assert node.returncode == 2 and pil.returncode == 2
    node_msg = node.stderr.strip().splitlines()[-1].replace("fsw_node: ", "", 1)
    pil_msg = pil.stderr.strip().splitlines()[-1].replace("aocs_pil.bridge: ", "", 1)
    assert pil_msg == node_msg and "the executive rejected the configuration" in pil_msg


def test_realtime_and_missing_image_are_refused(env, tmp_path):
    from aocs_wire import netns
    path = tmp_path / "rt.cfg"
    path.write_text("law = none\nmode = realtime\nu_max_axis = 1 1 1\n")
    r = subprocess.run(netns.wrap([sys.executable, "-m", "aocs_pil.bridge", "--target", "pil-m7", str(path)]),
                       capture_output=True, text=True, timeout=30)
    assert r.returncode == 2 and "lockstep only" in r.stderr
    path.write_text("law = none\nu_max_axis = 1 1 1\n")
    r = subprocess.run(netns.wrap([sys.executable, "-m", "aocs_pil.bridge", "--target", "pil-m7", "--image",
                                   str(tmp_path / "none.elf"), str(path)]), capture_output=True, text=True,
                       timeout=30)
    assert r.returncode == 1 and "none.elf not found" in r.stderr
