"""Issue 11, flight-software half: no single frame from the local LCM group can
latch the executive in SAFE, silence fsw_node, overflow a counter or a time
conversion, or pass limits and timeouts the node cannot honour.

Every test runs the fsw_node of the sanitizer build (preset host-sanitize:
ASan + UBSan, no recovery, so undefined behaviour aborts the node and fails
the test) inside the private network namespace, injects the forged frame
with the LCM Python bindings the way an attacker on the group would, then
plays the plant's legitimate frames and checks that the node answers them and
is NOMINAL again within the documented count (docs/wire-contract.md, "Frame
acceptance"): K - 1 + M answered frames, K = AOCS_EXEC_RESYNC_FRAMES (read
from aocs/exec/acceptance.h), M = recover_good_samples.
"""
from __future__ import annotations

import math
import re
import subprocess
import time
from pathlib import Path

import pytest

from conftest import BASE_CONFIG, REPO, Node

MODE_NOMINAL, MODE_SAFE = 1, 2
M_GOOD = int(BASE_CONFIG["recover_good_samples"])
PERIOD = float(BASE_CONFIG["control_period_s"])
SANITIZER_MARKS = ("runtime error", "AddressSanitizer", "UndefinedBehaviorSanitizer", "LeakSanitizer")
Q = (0.0, 0.0, 0.0871557427476582, 0.9961946980917455)  # 10 deg about z
W = (0.001, -0.002, 0.003)


def _header_constant(name: str) -> int:
    text = (REPO / "firmware/include/aocs/exec/acceptance.h").read_text()
    m = re.search(rf"^#define {name} (\d+)u$", text, re.M)
    assert m, f"{name} not found in aocs/exec/acceptance.h"
    return int(m.group(1))


K_RESYNC = _header_constant("AOCS_EXEC_RESYNC_FRAMES")
BOUND = K_RESYNC - 1 + M_GOOD  # answered good frames until NOMINAL, after any single bad frame


@pytest.fixture
def node(sanitized_fsw_node_bin, private_netns, tmp_path):
    """Factory: node(**overrides) starts the sanitized fsw_node with BASE_CONFIG + overrides."""
    nodes: list[Node] = []

    def start(**overrides) -> Node:
        cfg = dict(BASE_CONFIG)
        cfg.update({k.replace("__", "."): str(v) for k, v in overrides.items()})
        n = Node(sanitized_fsw_node_bin, tmp_path, cfg, f"integrity{len(nodes)}")
        nodes.append(n)
        return n

    yield start
    for n in nodes:
        n.kill()


def assert_clean_exit(n: Node) -> None:
    """SIGTERM: exit 0, and no sanitizer report on stderr."""
    rc = n.stop()
    err = n.err_path.read_text()
    assert not any(mark in err for mark in SANITIZER_MARKS), err
    assert rc == 0, err


class Plant:
    """The legitimate plant: frame = tick, t_s = tick * period (sil/aocs_runner/plant_node.py)."""

    def __init__(self, link):
        self.link = link
        self.tick = 0

    def send(self, tick=None):
        k = self.tick if tick is None else tick
        self.link.send_sensors(k, Q, W, frame=k, t_s=k * PERIOD)
        self.tick = k + 1
        return k

    def step(self, timeout=2.0):
        """One frame and its reply."""
        k = self.send()
        return self.link.wait_for("AOCS_ACTUATOR_CMD", 1, timeout, pred=lambda r: r.tick == k)[-1]

    def run(self, n):
        return [self.step() for _ in range(n)]


def nominal_within(plant: Plant, bound: int, limit: int = 3 * BOUND) -> int:
    """Plays good frames until a reply is NOMINAL; returns how many it took (asserts <= bound)."""
    for n in range(1, limit + 1):
        r = plant.step()
        assert all(abs(u) <= lim * (1 + 1e-9) for u, lim in zip(r.u_sat, (0.5, 0.6, 0.7))), r.u_sat
        if r.mode == MODE_NOMINAL:
            assert n <= bound, f"NOMINAL only after {n} good frames, documented bound {bound}"
            return n
    raise AssertionError(f"still not NOMINAL after {limit} good frames (documented bound {bound})")


def forge(link, *, frame, tick, t_s, q=Q, w=W):
    """The attacker's frame: any counter, tick and time, a well-formed payload."""
    m = link.sensors(tick, q, w, t_s=t_s, frame=frame)
    link.lc.publish("AOCS_SENSORS", m.encode())
    return m


def started(node, lcm_link, **overrides):
    n = node(**overrides)
    n.wait_ready(lcm_link)
    plant = Plant(lcm_link)
    replies = plant.run(5)
    assert all(r.mode == MODE_NOMINAL for r in replies)
    return n, plant


# ---- item 1: latching ------------------------------------------------------------------------
@pytest.mark.parametrize("t_forged", [5 * PERIOD + 1e9, 9.5e9, 1.7e10],
                         ids=["t_plus_1e9_s", "t_9.5e9_s_beyond_int64_ns", "t_1.7e10_s"])
def test_future_time_frame_does_not_latch_safe(node, lcm_link, t_forged):
    n, plant = started(node, lcm_link)
    # the forged frame takes the plant's next frame and tick, with a time far in the future
    forge(lcm_link, frame=plant.tick, tick=plant.tick, t_s=t_forged)
    r = lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda m: m.tick == plant.tick)[-1]
    assert r.mode == MODE_SAFE and r.n_stale == 1
    plant.tick += 1  # the plant's own frame of that counter is now a duplicate (documented)
    took = nominal_within(plant, BOUND)
    r = plant.step()
    assert r.mode == MODE_NOMINAL and r.status == 0 and r.n_stale == 1
    assert took <= M_GOOD  # the forged frame did not continue the reference: M good frames suffice
    assert_clean_exit(n)


def test_tick_far_ahead_does_not_latch_safe(node, lcm_link):
    n, plant = started(node, lcm_link)
    far = plant.tick + (1 << 30)
    forge(lcm_link, frame=plant.tick, tick=far, t_s=far * PERIOD)  # tick and time agree with each other
    r = lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda m: m.tick == far)[-1]
    assert r.mode == MODE_SAFE
    assert r.n_missing == 0  # not 2^30 missing samples either
    plant.tick += 1
    nominal_within(plant, BOUND)
    assert_clean_exit(n)


def test_bad_first_frame_resynchronises(node, lcm_link):
    """The very first frame is forged: the plant's frames resynchronise node and executive."""
    n = node()
    n.wait_ready(lcm_link)
    forge(lcm_link, frame=5_000_000, tick=5_000_000, t_s=1e9)
    lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda m: m.tick == 5_000_000)
    plant = Plant(lcm_link)
    # the node drops the plant's first K - 1 frames (behind the forged counter), then resynchronises
    for _ in range(K_RESYNC - 1):
        plant.send()
    lcm_link.pump(0.3)
    assert not [m for m in lcm_link.inbox["AOCS_ACTUATOR_CMD"] if m.tick < 5_000_000]
    nominal_within(plant, BOUND)
    assert_clean_exit(n)
    assert "seq_resync=1 exec_resync=1" in n.err_path.read_text()


# ---- item 2: silencing ------------------------------------------------------------------------
def test_frame_counter_int64_max_does_not_silence(node, lcm_link):
    n, plant = started(node, lcm_link)
    before = plant.step()
    forge(lcm_link, frame=2**63 - 1, tick=plant.tick, t_s=plant.tick * PERIOD)
    # the next legitimate frame is answered at once, in NOMINAL: the forged one never reached the executive
    r = plant.step()
    assert r.mode == MODE_NOMINAL and r.status == 0
    assert r.n_lost == before.n_lost == 0
    # a replayed old frame is still a duplicate: no reply, counted
    lcm_link.clear()
    plant.send(tick=2)
    lcm_link.pump(0.3)
    assert not lcm_link.inbox["AOCS_ACTUATOR_CMD"]
    plant.tick = r.tick + 1
    r = plant.step()
    assert r.n_duplicate == 1 and r.mode == MODE_NOMINAL
    assert_clean_exit(n)


def test_frame_counter_int64_min_then_max_no_overflow(node, lcm_link):
    """INT64_MIN then INT64_MAX: the old counter arithmetic overflowed (UBSan aborts the sanitized node)."""
    n = node()
    n.wait_ready(lcm_link)
    forge(lcm_link, frame=-(2**63), tick=0, t_s=0.0)
    lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda m: m.tick == 0)
    forge(lcm_link, frame=2**63 - 1, tick=1, t_s=PERIOD)
    lcm_link.pump(0.3)
    assert n.proc.poll() is None, n.stderr()
    plant = Plant(lcm_link)
    plant.tick = 1
    # the plant's counters are far from INT64_MIN: K frames resynchronise the node's sequence
    for _ in range(K_RESYNC - 1):
        plant.send()
    nominal_within(plant, BOUND)
    assert_clean_exit(n)


def test_llround_range_timestamps_keep_node_answering(node, lcm_link):
    """t_s around 1e10 s (ns beyond INT64_MAX): converted without overflow, refused, node recovers."""
    n, plant = started(node, lcm_link)
    times = (9.3e9, 1.0e10, 1.79e10, 1.0e300, -5.0, float("nan"))
    for k, t in enumerate(times):
        forge(lcm_link, frame=plant.tick + k, tick=plant.tick + k, t_s=t)
    lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, pred=lambda m: m.tick == plant.tick + len(times) - 1)
    assert n.proc.poll() is None, n.stderr()
    plant.tick += len(times)  # the forged frames took these counters and ticks
    nominal_within(plant, BOUND)
    assert_clean_exit(n)


# ---- item 1, real time ---------------------------------------------------------------------------
def test_realtime_tick_far_ahead_does_not_latch(node, lcm_link):
    period = 0.02
    n = node(mode="realtime", control_period_s=period, run_timeout_s=6.0, stale_timeout_s=0.1,
             missing_max_periods=10)
    n.wait_ready(lcm_link)
    tick = [0]

    def publish_for(seconds):
        end = time.monotonic() + seconds
        t_next = time.monotonic()
        while time.monotonic() < end:
            if time.monotonic() >= t_next:
                k = tick[0]
                lcm_link.send_sensors(k, Q, W, frame=k, t_s=k * period)
                tick[0] += 1
                t_next += period
            lcm_link.lc.handle_timeout(2)

    publish_for(0.5)
    assert lcm_link.inbox["AOCS_ACTUATOR_CMD"][-1].mode == MODE_NOMINAL
    far = tick[0] + (1 << 30)
    lcm_link.clear()
    forge(lcm_link, frame=tick[0], tick=far, t_s=far * period)
    tick[0] += 1
    # the plant pauses a few periods, so the forged sample is the newest one at a deadline
    lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, 2.0, pred=lambda c: c.tick == far)
    publish_for(1.5)
    cmds = lcm_link.inbox["AOCS_ACTUATOR_CMD"]
    stepped = [c for c in cmds if c.tick == far]
    assert stepped and stepped[0].mode == MODE_SAFE
    assert cmds[-1].mode == MODE_NOMINAL, [(c.tick, c.mode) for c in cmds[-10:]]
    # NOMINAL again within the documented count of the plant's samples (distinct ticks stepped after it)
    after = cmds[cmds.index(stepped[0]) + 1:]
    ticks_until = []
    for c in after:
        if c.tick != far and c.tick not in ticks_until:
            ticks_until.append(c.tick)
        if c.mode == MODE_NOMINAL:
            break
    assert len(ticks_until) <= BOUND, [(c.tick, c.mode) for c in after[:12]]
    assert_clean_exit(n)


# ---- item 3: limits and timeouts the node cannot honour -------------------------------------------------
def _run_config(exe: Path, tmp_path: Path, **overrides) -> subprocess.CompletedProcess:
    cfg = dict(BASE_CONFIG, **{k.replace("__", "."): str(v) for k, v in overrides.items()})
    path = tmp_path / "bad.cfg"
    path.write_text("".join(f"{k} = {v}\n" for k, v in cfg.items()))
    return subprocess.run([str(exe), str(path)], capture_output=True, text=True, timeout=10)


@pytest.mark.parametrize("key, value", [
    ("idle_timeout_s", "2e10"), ("idle_timeout_s", "1e300"), ("idle_timeout_s", "1e-10"),
    ("run_timeout_s", "1e300"), ("run_timeout_s", "1e-10"),
    ("status_period_s", "2e10"), ("status_period_s", "1e-10"),
    ("wait_spin_us", "10001"), ("wait_spin_us", "1e300"),
])
def test_implausible_timeouts_refused_with_one_line(sanitized_fsw_node_bin, tmp_path, key, value):
    res = _run_config(sanitized_fsw_node_bin, tmp_path, **{key: value})
    assert res.returncode == 2, (res.returncode, res.stderr)
    lines = res.stderr.strip().splitlines()
    assert len(lines) == 1, res.stderr
    assert "config error" in lines[0] and f"'{key}'" in lines[0] and "outside" in lines[0], lines[0]


@pytest.mark.parametrize("overrides", [
    {"u_max_axis": "1e150 1e-170 1e150", "u_max_norm": "1e150"},
    {"u_max_axis": "0 0 0", "u_max_norm": "1e-160"},
    {"u_max_axis": "0 0 0", "u_max_norm": "1e-20"},
    {"u_max_axis": "1 1e10 1"},
], ids=["axis_1e150_1e-170", "norm_1e-160", "norm_1e-20", "axis_1e10"])
def test_limits_outside_the_exact_range_refused(sanitized_fsw_node_bin, tmp_path, overrides):
    res = _run_config(sanitized_fsw_node_bin, tmp_path, **overrides)
    assert res.returncode == 2, (res.returncode, res.stderr)
    assert "AOCS_ERR_SAT_LIMIT_NOT_POSITIVE" in res.stderr and "check u_max_axis (" in res.stderr \
        and ", u_max_norm (" in res.stderr, res.stderr


def test_limit_edges_accepted_and_honoured(node, lcm_link):
    """The edges of the range run, and a huge command is held within both limits."""
    n = node(u_max_axis="1e-09 1e+09 1e-09", u_max_norm="1e-09")
    n.wait_ready(lcm_link)
    plant = Plant(lcm_link)
    lcm_link.send_sensors(0, Q, (1e30, -1e-30, 3e20), frame=0, t_s=0.0)
    r = lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1)[-1]
    assert r.saturated
    assert abs(r.u_sat[0]) <= 1e-9 and abs(r.u_sat[2]) <= 1e-9
    assert math.sqrt(sum(x * x for x in r.u_sat)) <= 1e-9
    plant.tick = 1
    assert_clean_exit(n)
