"""Issue 25, acceptance: a hostile-sensor campaign against a live fsw_node flying the reaction wheel array.

The sanitized fsw_node (preset host-sanitize: ASan + UBSan abort on undefined behaviour) is configured for
irassi_rw (four wheels in a pyramid, quat_pd, its flight configuration from aocs_flightcfg, as `aocs run`
writes it) and fed a stream of sensors_t frames in lockstep order (each frame the next tick, so the frame
acceptance lets every one through to the executive) whose payloads are drawn, seeded, from the extremes a
broken or hostile sensor gives: tachometers at NaN, +-inf, +-1e308, the smallest subnormal, exactly at and
one ulp past the physical range 2 Omega_max, uniform over +-3 Omega_max; body rates at NaN, +-1e308, past the
gyro range; quaternions off the unit sphere, zero, NaN; random valid bits; and good frames between them so
the node keeps recovering. Every reply is checked:

- the body command u_sat finite and within the per-axis limit exactly, the wheel motor commands finite and
  within +-u_max exactly (no tolerance: issue 25 item 6 was one ulp);
- no step says OK (status 0) while its wheel commands were refused or replaced (wheel_status != 0);
- a frame with a tachometer outside its range never reaches the law: its reply's status is not OK;
- the node answers every frame and recovers: the stream alternates hostile stretches (three frames in four
  hostile) with good ones of SEGMENT frames, longer than the recovery bound (AOCS_EXEC_RESYNC_FRAMES - 1 +
  recover_good_samples good frames after any bad one), and every good stretch ends in NOMINAL; it exits
  cleanly with no sanitizer report.

AOCS_HOSTILE_FRAMES sets the number of frames: 4000 in `make test`, 100,000 for the acceptance figure
(`make hostile`, which prints the counts).
"""
from __future__ import annotations

import math
import os
import sys

import numpy as np
import pytest
from test_integrity import K_RESYNC as RESYNC_FRAMES
from test_integrity import SANITIZER_MARKS, assert_clean_exit

from aocs_core import registry
from aocs_flightcfg import fsw_config
from aocs_plant import load
from conftest import Node

N_FRAMES = int(os.environ.get("AOCS_HOSTILE_FRAMES", "4000"))
SEED = int(os.environ.get("AOCS_HOSTILE_SEED", "2025"))
MODE_NOMINAL = 1
RANGE_FACTOR = 2.0          # AOCS_WHEEL_SPEED_RANGE_FACTOR (wheel_array.h): readings beyond are not physical
SEGMENT = 40                # frames of a hostile stretch, then of a good one (above the recovery bound)


@pytest.fixture
def wheel_node(sanitized_fsw_node_bin, private_netns, tmp_path, lcm_link):
    sc = load("irassi_rw")
    cfg = fsw_config.node_config(sc, "quat_pd", idle_timeout_s=5.0)
    for i in (0, 1):     # the spin inertia of issue 25 item 1: Js Omega overflows for a wild reading
        cfg[f"wheel{i}.js_kgm2"] = "10"
    # the stream's tachometers are random draws, not a wheel answering its commands: fault management
    # (docs/spec.md 5.15.2) would rightly isolate the wheels and, at the fourth, latch SAFE, and the good
    # stretches below would never return to NOMINAL; this test is about the acceptance and the command guards
    cfg["fdir.enabled"] = "0"
    node = Node(sanitized_fsw_node_bin, tmp_path, cfg, "hostile")
    node.wait_ready(lcm_link)
    yield node, sc, cfg
    node.kill()


def _floats(text: str) -> list[float]:
    return [float(x) for x in text.split()]


class Stream:
    """Seeded hostile frames: tick k is frame k, sent at t = k T."""

    def __init__(self, rng: np.random.Generator, n_wheels: int, omega_max: list[float], period_s: float):
        self.rng, self.n, self.omega_max, self.period = rng, n_wheels, omega_max, period_s

    def tach(self, i: int) -> float:
        om = self.omega_max[i]
        edge = RANGE_FACTOR * om
        pool = (math.nan, math.inf, -math.inf, 1e308, -1e308, 5e-324, -5e-324, edge, -edge,
                math.nextafter(edge, math.inf), -math.nextafter(edge, math.inf), om, -om, 0.999 * om)
        r = self.rng.random()
        if r < 0.5:
            return pool[self.rng.integers(len(pool))]
        if r < 0.8:
            return float(self.rng.uniform(-3.0 * om, 3.0 * om))
        return float(self.rng.choice((-1.0, 1.0)) * 10.0 ** self.rng.uniform(-300, 300))

    def frame(self, t, k: int, hostile: bool):
        """(message, a tachometer outside its range or not finite); hostile False: a good frame."""
        rng = self.rng
        q = [0.0, 0.0, 0.0871557427476582, 0.9961946980917455]
        w = [float(x) for x in rng.normal(0.0, 1e-3, 3)]
        speeds = [float(x) for x in rng.uniform(-0.5, 0.5, self.n)] + [0.0] * (t.MAX_WHEELS - self.n)
        valid = t.VALID_ATTITUDE | t.VALID_RATE | t.VALID_WHEELS
        if hostile and rng.random() < 0.75:       # a hostile frame: one or more fields at an extreme
            for i in range(self.n):
                if rng.random() < 0.5:
                    speeds[i] = self.tach(i)
            if rng.random() < 0.2:
                w[rng.integers(3)] = float(rng.choice((math.nan, 1e308, -1e308, 50.0, -3.0, 1e-310)))
            if rng.random() < 0.1:
                q = [float(x) for x in rng.choice(((0.0, 0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 1.001),
                                                    (math.nan, 0.0, 0.0, 1.0), (1e308, 0.0, 0.0, 1.0)))]
            if rng.random() < 0.05:
                valid = int(rng.integers(0, 128))
        wild = any(not (abs(s) <= RANGE_FACTOR * om) for s, om in zip(speeds[: self.n], self.omega_max))
        m = t()
        m.protocol_version = t.PROTOCOL_VERSION
        m.frame = k
        m.utime = 1000 + k * 100000
        m.tick = k
        m.t_s = k * self.period
        m.valid = valid
        m.q, m.w = q, w
        m.pos, m.vel = [0.0] * 3, [0.0] * 3
        m.n_wheels = self.n
        m.wheel_speed = speeds
        m.st_q, m.st_t_meas_s, m.gyro_w = [0.0, 0.0, 0.0, 1.0], 0.0, [0.0] * 3
        return m, wild and (valid & t.VALID_WHEELS) != 0


def test_a_hostile_sensor_stream_never_gets_a_bad_command(wheel_node, lcm_link, aocs_lcm):
    node, sc, cfg = wheel_node
    n = int(cfg["wheels.count"])
    u_max_axis = _floats(cfg["u_max_axis"])
    u_max_wheel = [float(cfg[f"wheel{i}.u_max_nm"]) for i in range(n)]
    omega_max = [float(cfg[f"wheel{i}.omega_max_radps"]) for i in range(n)]
    t = aocs_lcm.sensors_t
    stream = Stream(np.random.default_rng(SEED), n, omega_max, float(cfg["control_period_s"]))
    recover = int(cfg.get("recover_good_samples", registry.load().config_field("recover_good_samples").default))
    bound = RESYNC_FRAMES - 1 + recover
    assert bound < SEGMENT, (bound, SEGMENT)
    counts = {"frames": 0, "wild_tach": 0, "not_ok": 0, "wheel_refused": 0, "nominal": 0,
              "body_over_limit": 0, "body_not_finite": 0, "wheel_over_limit": 0, "wheel_not_finite": 0,
              "ok_with_refused_wheels": 0, "wild_tach_ok": 0, "good_stretches": 0, "recovered": 0}
    for k in range(N_FRAMES):
        hostile = (k // SEGMENT) % 2 == 0
        m, wild = stream.frame(t, k, hostile)
        lcm_link.lc.publish("AOCS_SENSORS", m.encode())
        r = lcm_link.wait_for("AOCS_ACTUATOR_CMD", 1, 5.0, pred=lambda x, k=k: x.tick == k)[-1]
        lcm_link.clear()
        counts["frames"] += 1
        counts["wild_tach"] += wild
        counts["not_ok"] += r.status != 0
        counts["wheel_refused"] += r.wheel_status != 0
        counts["nominal"] += r.mode == MODE_NOMINAL
        counts["body_not_finite"] += not all(math.isfinite(u) for u in r.u_sat)
        counts["body_over_limit"] += any(not (abs(u) <= lim) for u, lim in zip(r.u_sat, u_max_axis))
        counts["wheel_not_finite"] += not all(math.isfinite(u) for u in r.u_wheels)
        counts["wheel_over_limit"] += (any(not (abs(u) <= lim) for u, lim in zip(r.u_wheels[:n], u_max_wheel))
                                       or any(u != 0.0 for u in r.u_wheels[n:]))
        counts["ok_with_refused_wheels"] += r.status == 0 and r.wheel_status != 0
        counts["wild_tach_ok"] += wild and r.status == 0
        if not hostile and k % SEGMENT == SEGMENT - 1:   # the last frame of a good stretch: back in NOMINAL
            counts["good_stretches"] += 1
            counts["recovered"] += r.mode == MODE_NOMINAL
    print(f"\nhostile sensor campaign: seed {SEED}, " + ", ".join(f"{k} {v}" for k, v in counts.items()),
          file=sys.stderr)
    for bad in ("body_over_limit", "body_not_finite", "wheel_over_limit", "wheel_not_finite",
                "ok_with_refused_wheels", "wild_tach_ok"):
        assert counts[bad] == 0, counts
    # the stream did what it is for: many wild readings, refused steps, and recoveries in between
    assert counts["wild_tach"] > N_FRAMES // 8 and counts["not_ok"] >= counts["wild_tach"], counts
    assert counts["good_stretches"] >= N_FRAMES // (2 * SEGMENT) and counts["recovered"] == counts["good_stretches"], \
        counts
    assert_clean_exit(node)
    assert not any(mark in node.err_path.read_text() for mark in SANITIZER_MARKS)
