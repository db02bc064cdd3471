"""Failed runs never report success: real runs (`python -m aocs.cli`, real processes in a private
network namespace) with the flight computer frozen, the log recorder paused, the law refused, and
logs truncated or damaged before `aocs replay`. Each must exit non-zero with one line saying why
(and the reason in the run JSON); `--allow CHECK` lets the run pass on purpose."""
from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from aocs_wire import lcmlog, netns

CLI = [sys.executable, "-m", "aocs.cli"]


def _pids_matching(text: str) -> list[int]:
    pids = []
    for d in Path("/proc").iterdir():
        if d.name.isdigit():
            try:
                cmd = (d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
            except OSError:
                continue
            if text in cmd and str(os.getpid()) != d.name:
                pids.append(int(d.name))
    return pids


def _signal_when_running(proc, needle: str, sig, after_s: float, timeout_s: float = 20.0) -> list[int]:
    """Wait until a process whose command line contains needle exists, wait after_s, send sig."""
    end = time.monotonic() + timeout_s
    while time.monotonic() < end and proc.poll() is None:
        pids = [p for p in _pids_matching(needle) if p != proc.pid]
        if pids:
            time.sleep(after_s)
            for p in pids:
                os.kill(p, sig)
            return pids
        time.sleep(0.02)
    pytest.fail(f"no process with {needle!r} appeared")


def _failed_line(stderr: str) -> str:
    lines = [ln for ln in stderr.splitlines() if ln.startswith("aocs run: FAILED:")]
    assert len(lines) == 1, stderr
    return lines[0]


def test_a_frozen_flight_computer_fails_a_real_time_run(tmp_path):
    out = tmp_path / "rt"
    cmd = CLI + ["run", "irassi_small", "--realtime", "--duration", "3", "-q", "--no-plots", "--out", str(out),
                 "--json", str(tmp_path / "m.json")]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    pids = _signal_when_running(proc, f"{out}/fsw_node.cfg", signal.SIGSTOP, 1.0)
    try:
        _, err = proc.communicate(timeout=60)
    finally:
        for p in pids:
            try:
                os.kill(p, signal.SIGCONT)
            except ProcessLookupError:
                pass
    assert proc.returncode == 1, err
    assert "consecutive sensor frames unanswered" in _failed_line(err)
    m = json.loads((tmp_path / "m.json").read_text())
    assert not m["verdict"]["passed"] and m["verdict"]["failures"][0]["check"] == "unanswered"
    assert m["counters"]["longest_unanswered_run"] > 10


def test_a_paused_recorder_fails_the_run_and_allow_lets_it_pass(tmp_path):
    """lcm-logger stopped for 2 s of a lockstep run loses messages: the log is incomplete."""
    for allow in ([], ["--allow", "incomplete-log"]):
        out = tmp_path / f"lg{len(allow)}"
        cmd = CLI + ["run", "irassi_large", "--duration", "3000", "--recorder", "lcm-logger", "-q", "--no-plots",
                     "--out", str(out), *allow]
        proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        pids = _signal_when_running(proc, f"{out}/run.lcmlog", signal.SIGSTOP, 0.3)
        time.sleep(2.0)
        for p in pids:
            os.kill(p, signal.SIGCONT)
        _, err = proc.communicate(timeout=120)
        m = json.loads((out / "metrics.json").read_text())
        assert m["log_complete"] is False
        if allow:
            assert proc.returncode == 0, err
            assert m["verdict"]["passed"] and m["verdict"]["allowed"] == ["incomplete-log"]
        else:
            assert proc.returncode == 1, err
            line = _failed_line(err)
            assert "the log is incomplete" in line and "lcm-logger drops messages" in line


def test_a_law_refused_throughout_fails_the_run(tmp_path):
    """crp_linear at the Gibbs singularity (q4 ~ 1e-9) with no rate: refused on every step."""
    cmd = CLI + ["run", "rtc_ex1a", "--set", "plant.rho=[1e9, 0.0, 0.0]", "--set", "plant.w0=[0.0, 0.0, 0.0]",
                 "--duration", "1", "-q", "--no-plots", "--out", str(tmp_path / "lr")]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=60)
    assert res.returncode == 1, res.stderr
    line = _failed_line(res.stderr)
    assert "crp_linear was refused on every one of the 100 steps" in line and "AOCS_ERR_CRP_SINGULAR" in line


def test_a_diverged_run_fails_and_allow_accepts_it(tmp_path):
    """issue 25, item 3: gains past the sampled loop's gain margin blow the plant up; it used to pass."""
    cmd = CLI + ["run", "irassi_small", "--law", "quat_pd", "--set", "laws.quat_pd.kp=21200",
                 "--set", "laws.quat_pd.kd=42400", "-q", "--no-plots", "--out", str(tmp_path / "d")]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert res.returncode == 1, res.stderr
    line = _failed_line(res.stderr)
    for reason in ("the plant diverged", "ended in SAFE although no command asked for it",
                   "rejected as invalid", "integration error"):
        assert reason in line, line
    allow = sum((["--allow", c] for c in ("non-finite", "unrequested-safe", "invalid-inputs",
                                          "integration-error")), [])
    res = subprocess.run(cmd + allow + ["--json", str(tmp_path / "m.json")], capture_output=True, text=True,
                         timeout=120)
    assert res.returncode == 0, res.stderr
    assert set(json.loads((tmp_path / "m.json").read_text())["verdict"]["allowed"]) == {
        "non-finite", "unrequested-safe", "invalid-inputs", "integration-error"}


def test_a_wild_tachometer_fails_the_run(tmp_path):
    """issue 25, items 1 and 3: a tachometer of 1e308 gave NaN wheel commands and the run passed. Now every
    such frame is rejected as an invalid input (no command is allocated on it) and the run fails on that."""
    cmd = CLI + ["run", "irassi_rw", "--duration", "5", "--set", "wheels.spin_inertia_kg_m2=10",
                 "--set", "wheels.tach_noise_rad_s=1e308", "-q", "--no-plots", "--out", str(tmp_path / "w")]
    res = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
    assert res.returncode == 1, res.stderr
    line = _failed_line(res.stderr)
    assert "inputs were rejected as invalid" in line and "SAFE" in line, line


def _record(tmp_path_factory, duration_s: str):
    out = tmp_path_factory.mktemp("rec") / "run"
    res = subprocess.run(CLI + ["run", "irassi_small", "--duration", duration_s, "-q", "--no-plots", "--out", str(out)],
                         capture_output=True, text=True, timeout=60)
    assert res.returncode == 0, res.stderr
    return out


@pytest.fixture(scope="module")
def recorded_run(tmp_path_factory):
    return _record(tmp_path_factory, "20")


def _event_bounds(data: bytes) -> list[int]:
    off, bounds = 0, []
    while off < len(data):
        _, _, _, cl, dl = lcmlog._HEAD.unpack_from(data, off)
        off += lcmlog._HEAD.size + cl + dl
        bounds.append(off)
    return bounds


@pytest.mark.parametrize("damage,message", [
    ("cut_mid_event", "log truncated at byte"),
    ("cut_at_event_60", "log truncated: no end marker of the recorder"),
    ("zero_4k", "log corrupt at byte"),
])
def test_replay_refuses_a_truncated_or_corrupt_log(recorded_run, tmp_path, damage, message):
    data = (recorded_run / "run.lcmlog").read_bytes()
    bounds = _event_bounds(data)
    cut = next(b for b in bounds if b > 0.6 * len(data))
    bad = {"cut_mid_event": data[:cut - 7], "cut_at_event_60": data[:cut],
           "zero_4k": data[:4096] + bytes(4096) + data[8192:]}[damage]
    d = tmp_path / "copy"
    d.mkdir()
    for name in ("run.json", "fsw_node.cfg"):
        (d / name).write_bytes((recorded_run / name).read_bytes())
    (d / "run.lcmlog").write_bytes(bad)
    res = subprocess.run(CLI + ["replay", str(d / "run.lcmlog")], capture_output=True, text=True, timeout=60)
    assert res.returncode == 2, res.stdout + res.stderr
    assert "identical" not in res.stdout
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("aocs replay: error:") and message in lines[0], res.stderr


def test_replay_of_the_whole_log_is_identical(recorded_run):
    res = subprocess.run(CLI + ["replay", str(recorded_run / "run.lcmlog")], capture_output=True, text=True,
                         timeout=60)
    assert res.returncode == 0 and "identical" in res.stdout, res.stdout + res.stderr


def test_replay_with_a_bad_config_says_so_in_one_line(recorded_run, tmp_path):
    bad = tmp_path / "bad.cfg"
    bad.write_bytes(b"law = quat_pd\n\xff = 1\n")
    for cfg, message in ((bad, "not UTF-8 text"), (tmp_path / "none.cfg", "no such configuration file"),
                         (tmp_path, "is a folder")):
        res = subprocess.run(CLI + ["replay", str(recorded_run / "run.lcmlog"), "--config", str(cfg)],
                             capture_output=True, text=True, timeout=60)
        lines = res.stderr.strip().splitlines()
        assert res.returncode == 2 and len(lines) == 1 and message in lines[0], res.stderr


def test_play_publishes_every_event_paced_by_simulation_time(recorded_run, private_netns, aocs_lcm):
    """`aocs play` in this (private) namespace: a subscriber here receives every payload of the log,
    byte for byte and in order, and 20 s of simulation at 40x take at least 0.5 s of wall time."""
    import threading

    import lcm as lcm_mod

    from aocs import cmd_play

    log = lcmlog.read(recorded_run / "run.lcmlog", keep_raw=True)
    got, stop = [], threading.Event()
    lc = lcm_mod.LCM(netns.LCM_URL)
    # unbounded queue: LCM's default of 30 queued messages drops some when the machine is loaded
    lc.subscribe(".*", lambda ch, data: got.append((ch, bytes(data)))).set_queue_capacity(0)

    def pump():
        while not stop.is_set():
            lc.handle_timeout(20)
    th = threading.Thread(target=pump, daemon=True)
    th.start()
    t0 = time.monotonic()
    assert cmd_play.play(recorded_run / "run.lcmlog", speed=40.0, quiet=True) == 0
    wall = time.monotonic() - t0
    time.sleep(0.3)
    stop.set()
    th.join(timeout=5)
    assert wall >= 20.0 / 40.0 * 0.95
    assert got == [(ch, data) for ch, data, _ in log.events]


def test_play_refuses_bad_speed_and_damaged_logs(recorded_run, tmp_path, private_netns):
    from aocs import cmd_play

    with pytest.raises(cmd_play.PlayError, match="--speed 0"):
        cmd_play.play(recorded_run / "run.lcmlog", speed=0.0)
    bad = tmp_path / "bad.lcmlog"
    bad.write_bytes((recorded_run / "run.lcmlog").read_bytes()[:1000])
    with pytest.raises(cmd_play.PlayError, match="log truncated at byte"):
        cmd_play.play(bad, speed=1.0)


@pytest.fixture(scope="module")
def short_recorded_run(tmp_path_factory):
    return _record(tmp_path_factory, "2")


#: bit-flipped copies of a log given to `aocs replay` (issue 25, item 9: one of four gave a traceback)
FLIP_SEEDS = 64


def test_replay_of_bit_flipped_logs_never_gives_a_traceback(short_recorded_run, private_netns, tmp_path, capsys):
    """Each seed flips 1 to 16 random bits of the log (anywhere: headers, channel names, payloads); the
    replay, run in this process as the command line runs it, ends with an exit code (0 identical, 1
    mismatch, 2 refused in one line), never with an exception."""
    import argparse
    import random

    from aocs import cmd_replay

    data = (short_recorded_run / "run.lcmlog").read_bytes()
    d = tmp_path / "copy"
    d.mkdir()
    for name in ("run.json", "fsw_node.cfg"):
        (d / name).write_bytes((short_recorded_run / name).read_bytes())
    seen = {}
    for seed in range(FLIP_SEEDS):
        rng = random.Random(seed)
        bad = bytearray(data)
        for _ in range(rng.randint(1, 16)):
            bit = rng.randrange(8 * len(bad))
            bad[bit // 8] ^= 1 << (bit % 8)
        (d / "run.lcmlog").write_bytes(bytes(bad))
        args = argparse.Namespace(log=str(d / "run.lcmlog"), target="host", config=None, reply_timeout=0.5,
                                  quiet=True)
        rc = cmd_replay.run(args)          # an exception here is the traceback the command would print
        err = capsys.readouterr().err.strip().splitlines()
        assert rc in (0, 1, 2), (seed, rc)
        if rc == 2:
            assert len(err) == 1 and err[0].startswith("aocs replay: error:"), (seed, err)
        seen[rc] = seen.get(rc, 0) + 1
    print(f"{FLIP_SEEDS} bit-flipped logs: exit codes {seen}")
    assert seen.get(2, 0) > 0
