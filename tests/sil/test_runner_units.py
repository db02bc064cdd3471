"""The runner's pieces on their own: wire codecs, fsw_node configuration,
events, overrides, analysis helpers and the log recorder.

Expected values come from independent sources: the lcm-gen bindings, the
scenario loader, the firmware headers, the plant's own rotation functions,
or numbers worked out here.
"""
from __future__ import annotations

import math
import random
import re
import subprocess
import time
from pathlib import Path

import numpy as np
import pytest

from aocs_plant import Plant
from aocs_plant import rotation as rot
from aocs_plant.scenario import ScenarioError, list_scenarios, load
from aocs_runner import events, fsw_config, paths, results, scenario_opts, wire

REPO = Path(__file__).resolve().parents[2]


# ---------------------------------------------------------------------------- wire codecs
def _random_value(typ, rng):
    return {"int8_t": rng.randint(-128, 127), "int16_t": rng.randint(-32768, 32767),
            "int32_t": rng.randint(-2 ** 31, 2 ** 31 - 1), "int64_t": rng.randint(-2 ** 63, 2 ** 63 - 1),
            "double": rng.uniform(-1e6, 1e6), "boolean": rng.choice([True, False])}[typ]


@pytest.mark.parametrize("name", ["sensors_t", "actuator_cmd_t", "truth_t", "command_t", "status_t"])
def test_fast_codec_is_byte_identical_to_the_generated_bindings(aocs_lcm, name):
    cls = getattr(aocs_lcm, name)
    codec = wire.Codec(cls)
    rng = random.Random(3)
    for _ in range(20):
        msg = cls()
        flat = []
        for field, typ, dims in zip(cls.__slots__, cls.__typenames__, cls.__dimensions__):
            if dims is None:
                v = _random_value(typ, rng)
                setattr(msg, field, v)
                flat.append(v)
            else:
                v = [_random_value(typ, rng) for _ in range(dims[0])]
                setattr(msg, field, v)
                flat += v
        data = msg.encode()
        assert codec.pack(*flat) == data
        got = codec.unpack(data)
        dec = cls.decode(data)
        assert got == tuple(flat)
        # field view matches the generated decoder
        for field, value in codec.to_dict(got).items():
            ref = getattr(dec, field)
            assert (tuple(ref) if isinstance(value, tuple) else ref) == value
    # not exactly this type: rejected, never mis-decoded
    assert codec.unpack(data[:-1]) is None
    assert codec.unpack(data + b"\0") is None
    assert codec.unpack(b"\xff" * 8 + data[8:]) is None


# ---------------------------------------------------------------------------- firmware facts
def test_law_ids_follow_the_executive_enum_and_law_table():
    """The ids are the row order of the law registry (laws.def), as the build's registry JSON lists them."""
    import json  # only this test reads the registry JSON

    reg = json.loads((paths.build_dir() / "registry" / "aocs_registry.json").read_text())
    names = [reg["none"]["name"]] + [law["name"] for law in reg["laws"]]
    assert [reg["none"]["id"]] + [law["id"] for law in reg["laws"]] == list(range(len(names)))
    assert names == list(paths.LAW_IDS)
    assert [paths.LAW_IDS[n] for n in names] == list(range(len(names)))


def test_budgets_and_status_names_come_from_the_headers():
    for law in paths.LAW_IDS:
        assert paths.law_budget_ns(law) > 0
    assert paths.law_budget_ns("quat_nlpd_neg") == paths.law_budget_ns("quat_nlpd_pos")
    names = paths.status_names()
    assert names[0] == "AOCS_OK"
    assert "AOCS_ERR_UNKNOWN_LAW" in names.values() and "AOCS_ERR_INPUT_NOT_FINITE" in names.values()


# ---------------------------------------------------------------------------- fsw_node configuration
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
    tanh = load("gao_mrp", {"laws.mrp_sat_tanh.m3": 0.04})
    with pytest.raises(fsw_config.ConfigError, match="m3"):
        fsw_config.node_config(tanh, "mrp_sat_tanh")


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


# ---------------------------------------------------------------------------- events and overrides
def test_events_parse_and_schedule():
    ev = events.parse_all(["5.05:malformed", "10:law=smc", "0:drop", "3:law=bogus", "7:law=42",
                           "8:target=0,0,0,2", "9:mode=standby", "1:stale"])
    by = {e.text: e for e in ev}
    assert by["10:law=smc"].law_id == 5 and by["10:law=smc"].is_command
    assert by["3:law=bogus"].law_id == events.UNKNOWN_LAW_ID
    assert by["7:law=42"].law_id == 42
    assert by["8:target=0,0,0,2"].target == (0.0, 0.0, 0.0, 2.0)
    assert by["9:mode=standby"].mode == 0
    sched = events.schedule(ev, 0.1, 200)
    # first tick with t_k >= T: 5.05 s -> tick 51; 10 s -> tick 100 (no rounding drift)
    assert [e.kind for e in sched[51]] == ["malformed"]
    assert [e.kind for e in sched[100]] == ["law"]
    assert [e.kind for e in sched[0]] == ["drop"]
    assert events.schedule(events.parse_all(["2:drop"]), 0.1, 50, start_tick=100) == {100: [ev[0].__class__(
        2.0, "drop", text="2:drop")]}
    for bad in ("x:drop", "5", "5:explode", "5:drop=1", "5:target=1,2,3", "-1:drop", "5:mode=weird"):
        with pytest.raises(events.EventError):
            events.parse(bad)
    with pytest.raises(events.EventError, match="after the end"):
        events.schedule(events.parse_all(["20:drop"]), 0.1, 200)


def test_overrides_parse_toml_values_and_round_trip():
    ov = scenario_opts.overrides(["control.enabled=false", "actuator.axis_limit=0.5", "plant.model=nonlinear",
                                  'sensors.faults=[{channel="rate", kind="nan", start_s=1.0, end_s=2.0}]'],
                                 duration=30, seed=4, limit=0.2)
    assert ov["control.enabled"] is False and ov["plant.model"] == "nonlinear"
    assert ov["actuator.axis_limit"] == 0.2          # --limit wins over --set
    assert ov["duration_s"] == 30.0 and ov["seed"] == 4
    assert ov["sensors.faults"][0]["kind"] == "nan"
    assert scenario_opts.parse_sets(scenario_opts.to_args(ov)[1::2]) == ov
    sc = load("irassi_small", ov | {"plant.model": None, "metrics.window_s": 30.0})
    assert sc.duration_s == 30 and sc.actuator.axis_limit == 0.2 and not sc.control.enabled
    with pytest.raises(ScenarioError):
        load("irassi_large", {"laws.quat_pd.kp": -4000.0})   # a negative gain is refused
    with pytest.raises(ValueError):
        scenario_opts.parse_sets(["novalue"])


# ---------------------------------------------------------------------------- analysis helpers
def test_target_path_matches_the_plant():
    sc = load("geo_hinf")
    plant = Plant(sc)
    t = np.array([0.0, 0.1, 37.3, 600.0, 1200.0])
    got = results.target_quat(sc, t)
    for i, ti in enumerate(t):
        ref = plant.target(float(ti))[0]
        assert np.allclose(got[i], ref, atol=1e-15, rtol=0), (ti, got[i], ref)
    # the LVLH frame turned by -w0 t about y (independent check of the sign)
    ang = -7.292115e-05 * 1200.0
    assert np.allclose(got[-1], [0.0, math.sin(ang / 2), 0.0, math.cos(ang / 2)], atol=1e-15)


def test_dcm_and_euler_match_the_plant_rotation_functions():
    rng = np.random.default_rng(5)
    q = rng.normal(size=(50, 4))
    q /= np.linalg.norm(q, axis=1, keepdims=True)
    a = results.dcm(q)
    e = results.euler321(q)
    for i in range(50):
        assert np.allclose(a[i], np.array(rot.quat_to_dcm(tuple(q[i]))), atol=1e-14)
        assert np.allclose(e[i], rot.quat_to_euler321(tuple(q[i])), atol=1e-12)
    # pinned example (conventions.md): 90 deg about z gives A = [[0,1,0],[-1,0,0],[0,0,1]]
    s = 1 / math.sqrt(2)
    assert np.allclose(results.dcm(np.array([[0, 0, s, s]]))[0], [[0, 1, 0], [-1, 0, 0], [0, 0, 1]], atol=1e-15)


def test_settle_mask_uses_every_criterion():
    sc = load("rtc_ex2a")
    t = np.arange(6) * 1.0
    rho = np.array([[1, 0, 0], [1e-2, 0, 0], [5e-4, 0, 0], [5e-4, 0, 0], [2e-4, 0, 0], [1e-4, 0, 0]], float)
    we = np.zeros((6, 3))
    we[2, 1] = 2e-3            # rate still outside at t = 2
    s = {"t": t, "rho": rho, "we": we, "true_angle": np.zeros(6), "euler_err": np.zeros((6, 3)),
         "sigma": np.zeros((6, 3))}
    inside, used = results.settle_mask(sc, s)
    assert used == {"rho_norm_max": 1e-3, "w_norm_max_rad_s": 1e-3}
    assert inside.tolist() == [False, False, False, True, True, True]


# ---------------------------------------------------------------------------- recorder and log reader
def test_recorder_writes_a_standard_lcm_log_without_dropping(private_netns, aocs_lcm, tmp_path):
    import lcm

    from aocs_runner import lcmlog
    from aocs_runner.recorder import Recorder

    path = tmp_path / "r.lcmlog"
    rec = Recorder(path).start(note="test")
    lc = lcm.LCM(__import__("aocs_runner.netns", fromlist=["LCM_URL"]).LCM_URL)
    codecs = wire.Codecs(aocs_lcm)
    sent = []
    for k in range(1000):       # a burst far above LCM's default 30-message queue
        data = codecs.truth.pack(1, k, k, k, 0.1 * k, *([0.5] * 29))
        lc.publish(wire.TRUTH, data)
        sent.append(data)
        if k % 500 == 0:
            lc.publish("OTHER", b"raw bytes")
    rec.stop()
    log = lcm.EventLog(str(path), "r")
    got = [(e.channel, e.data) for e in log]
    log.close()
    truth = [d for c, d in got if c == wire.TRUTH]
    assert truth == sent
    assert sum(1 for c, _ in got if c == "OTHER") == 2
    assert [c for c, _ in got if c == wire.RUNNER][0:1] == [wire.RUNNER]
    parsed = lcmlog.read(path)
    assert parsed.truth["tick"].tolist() == list(range(1000))
    assert parsed.truth["t_s"][7] == 0.1 * 7
    assert [m["marker"] for m in parsed.markers][0] == "start" and parsed.markers[-1]["marker"] == "end"
    # event timestamps are receive times (us since the epoch), non-decreasing
    assert np.all(np.diff(parsed.truth["log_utime"]) >= 0)
    assert abs(parsed.truth["log_utime"][0] / 1e6 - time.time()) < 600


# ---------------------------------------------------------------------------- direct udpm transport
def test_direct_udpm_interoperates_with_the_lcm_library(private_netns):
    """plant_node's socket-level udpm (udpm.py) and the LCM library understand each other."""
    import lcm

    from aocs_runner import netns
    from aocs_runner.udpm import Udpm, parse_url

    assert parse_url(netns.LCM_URL) == ("239.255.76.67", 7667, 0)
    with pytest.raises(ValueError):
        parse_url("tcpq://localhost:7700")
    lib = lcm.LCM(netns.LCM_URL)
    got_lib = []
    # unbounded queue: the burst below is far beyond LCM's default of 30 queued messages
    lib.subscribe("AOCS_X", lambda c, d: got_lib.append((c, d))).set_queue_capacity(0)
    direct = Udpm(netns.LCM_URL)
    got_direct = []
    tok = direct.subscribe("AOCS_Y", lambda c, d: got_direct.append((c, d)))
    payloads = [bytes([i % 256]) * (i * 37 % 1400) for i in range(200)]
    # in bursts of 10 (interoperability, not throughput: the library's socket buffer is small)
    for i, p in enumerate(payloads):           # direct -> library
        direct.publish("AOCS_X", p)
        end = time.monotonic() + 5
        while (i + 1) % 10 == 0 and len(got_lib) < i + 1 and time.monotonic() < end:
            lib.handle_timeout(50)
    assert got_lib == [("AOCS_X", p) for p in payloads]
    for i, p in enumerate(payloads):           # library -> direct; other channels ignored
        lib.publish("AOCS_Y", p)
        lib.publish("AOCS_Z", b"not subscribed")
        end = time.monotonic() + 5
        while (i + 1) % 10 == 0 and len(got_direct) < i + 1 and time.monotonic() < end:
            direct.handle_timeout(50)
    assert got_direct == [("AOCS_Y", p) for p in payloads]
    assert direct.handle_timeout(10) == 0      # nothing left, a bounded wait
    direct.unsubscribe(tok)
    lib.publish("AOCS_Y", b"after unsubscribe")
    assert direct.handle_timeout(50) == 0 and len(got_direct) == len(payloads)
    assert direct.garbage == 0 and direct.fragments == 0
    direct.close()
