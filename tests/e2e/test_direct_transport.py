"""The in-process transport (`--transport direct`, issue 24): fsw_node's node logic in the plant's process.

- every reference case of scripts/command-history.py flown over LCM (plant_node + fsw_node) and direct: the
  two logs' actuator_cmd_t (all but the timing fields) and sensors_t, bit for bit, and the same digest;
- a run with scheduled commands and transport faults (malformed, foreign, duplicated and dropped frames):
  the node's counters and replies the same on both transports (the shared node logic, not a copy);
- the C ABI on its own: configuration errors named with their line, real time refused, a malformed payload
  counted, the static slots bounded;
- the command line: a bad --transport is one line and exit 2.
"""
from __future__ import annotations

import importlib.util
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from aocs_loop import history
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog

REPO = Path(__file__).resolve().parents[2]
#: s of each reference case: the slews and transients of every case are under way (the whole history is
#: compared at the scenarios' full length by `scripts/command-history.py check DIR --transport direct`)
DURATION_S = 12.0
#: cases whose scenario schedules something later: long enough to fly it (the debris impulse at 60 s)
DURATIONS = {"landsat8_debris": 70.0}


def _cases():
    spec = importlib.util.spec_from_file_location("command_history", REPO / "scripts" / "command-history.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod.CASES


CASES = _cases()


@pytest.fixture(scope="module")
def env(aocs_build_dir):
    os.environ["AOCS_BUILD_DIR"] = str(aocs_build_dir)
    return aocs_build_dir


def _options(scenario, law, extra, out, transport, **kw) -> RunOptions:
    ex = dict(zip(extra[::2], extra[1::2]))
    return RunOptions(scenario=scenario, law=law, duration=DURATIONS.get(scenario, DURATION_S), seed=7, out=str(out), plots=False,
                      quiet=True, limit=float(ex["--limit"]) if "--limit" in ex else None,
                      guidance=ex.get("--guidance"), transport=transport, **kw)


def _fly_both(tmp_path, scenario, law, extra, **kw):
    res = {}
    for transport in ("lcm", "direct"):
        r = execute(_options(scenario, law, extra, tmp_path / transport, transport, **kw))
        res[transport] = (r, lcmlog.read(tmp_path / transport / "run.lcmlog"))
    return res


@pytest.mark.parametrize("case", CASES, ids=[" ".join([s, law or "default", *x]) for s, law, x in CASES])
def test_every_reference_case_flies_the_same_commands_in_process(env, private_netns, aocs_lcm, tmp_path, case):
    scenario, law, extra = case
    runs = _fly_both(tmp_path, scenario, law, extra)
    (m_lcm, log_lcm), (m_dir, log_dir) = runs["lcm"], runs["direct"]
    assert log_lcm.cmd["tick"].size == log_lcm.sensors["tick"].size > 0
    assert history.differences(log_lcm, log_dir) == []
    assert history.digest(log_lcm) == history.digest(log_dir)
    assert m_dir.metrics["transport"] == "direct" and m_lcm.metrics["transport"] == "lcm"
    assert m_dir.metrics["log_complete"], m_dir.metrics["verdict"]
    assert m_dir.metrics["lockstep"]["realtime_factor"] > 0
    # the node's own summary, written by the library as fsw_node prints it: the same counts
    for key in ("steps", "sensor_frames", "invalid", "stale", "missing", "law_error", "mode_transitions",
                "saturated", "law", "mode", "guidance"):
        assert m_dir.metrics["fsw_node"][key] == m_lcm.metrics["fsw_node"][key], key


def test_commands_and_transport_faults_go_through_the_same_node_logic(env, private_netns, aocs_lcm, tmp_path):
    """A law change, a target, a malformed and a foreign payload, a duplicated, a dropped and a stale frame:
    the replies (counters n_malformed, n_foreign, n_duplicate, n_lost, n_cmd_accepted included) and the
    acknowledgements are the same in process."""
    events = ["1:law=quat_pid", "2:malformed", "2.5:foreign", "3:duplicate", "4:drop", "5:stale",
              "6:mode=standby", "7:mode=nominal"]
    runs = _fly_both(tmp_path, "irassi_small", "quat_pd", [], events=events,
                     allow=("frames", "pointing", "settle"))
    (_, log_lcm), (_, log_dir) = runs["lcm"], runs["direct"]
    assert history.differences(log_lcm, log_dir) == []
    c = log_dir.cmd
    assert c["n_malformed"][-1] == 1 and c["n_foreign"][-1] == 1 and c["n_duplicate"][-1] == 1
    assert c["n_cmd_accepted"][-1] == 3
    assert set(c["law_id"].tolist()) == set(log_lcm.cmd["law_id"].tolist()) and len(set(c["law_id"].tolist())) >= 2
    # the acknowledgements (status_t after each command): the same requests and results
    for key in ("last_request", "last_request_status", "n_cmd_accepted"):
        acks_lcm = [v for v, e in zip(log_lcm.status[key], log_lcm.status["exiting"]) if not e]
        acks_dir = [v for v, e in zip(log_dir.status[key], log_dir.status["exiting"]) if not e]
        assert max(acks_dir) == max(acks_lcm), key


# ---- the C ABI ------------------------------------------------------------------------------------------
@pytest.fixture
def cfg_text(env, tmp_path):
    """fsw_node's configuration of a short irassi_small run, as the runner writes it."""
    from aocs_flightcfg import fsw_config
    from aocs_plant.scenario import load

    sc = load("irassi_small", {"duration_s": 1.0, "metrics.window_s": 1.0})
    cfg = fsw_config.node_config(sc, "quat_pd", mode="lockstep")
    return fsw_config.write(tmp_path / "fsw_node.cfg", cfg).read_text()


def test_the_library_names_a_bad_key_with_its_line(cfg_text):
    from aocs_loop.direct_adapter import DirectError, DirectNode

    text = cfg_text + "no_such_key = 1\n"
    line = text.count("\n")
    with pytest.raises(DirectError, match=rf"my.cfg:{line}: .*no_such_key"):
        DirectNode(text, "my.cfg")


def test_the_library_is_lockstep_only(cfg_text):
    from aocs_loop.direct_adapter import DirectError, DirectNode

    with pytest.raises(DirectError, match="lockstep only"):
        DirectNode(cfg_text.replace("mode = lockstep", "mode = realtime"), "rt.cfg")


def test_malformed_and_foreign_payloads_get_no_reply_and_are_counted(cfg_text, aocs_lcm):
    from aocs_loop.direct_adapter import DirectNode

    with DirectNode(cfg_text) as node:
        assert node.sensors(b"\x00\x01garbage") is None
        rep = node.report("done")["fsw_node"]
        assert rep["malformed"] == 1 and rep["sensor_frames"] == 1 and rep["steps"] == 0


def test_the_slots_are_static_and_bounded(cfg_text):
    from aocs_loop.direct_adapter import DirectError, DirectNode

    a, b = DirectNode(cfg_text), DirectNode(cfg_text)
    try:
        with pytest.raises(DirectError, match="slots are open"):
            DirectNode(cfg_text)
        b.close()
        DirectNode(cfg_text).close()       # a freed slot is used again
    finally:
        a.close()
        b.close()


# ---- the command line -----------------------------------------------------------------------------------
@pytest.mark.parametrize("argv, needle", [
    (["run", "irassi_small", "--transport", "udp"], "--transport 'udp': not a transport"),
    (["run", "irassi_small", "--transport", "direct", "--realtime"], "--transport direct: lockstep"),
    (["compare", "irassi_small", "--transport", "pigeon"], "--transport 'pigeon': not a transport"),
    (["campaign", "irassi_small", "--runs", "2", "--seed", "1", "--transport", "tcp"],
     "--transport 'tcp': not a transport"),
    (["campaign", "irassi_small", "--runs", "2", "--seed", "1", "--transport", "direct", "--refly-every", "-1"],
     "--refly-every -1: must be a whole number >= 0"),
])
def test_a_bad_transport_is_one_line_and_exit_2(env, tmp_path, argv, needle):
    p = subprocess.run([sys.executable, "-m", "aocs.cli", *argv, "--out", str(tmp_path / "o")], capture_output=True,
                       text=True, timeout=120)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and needle in lines[0], p.stderr


def test_the_run_record_names_the_transport(env, private_netns, aocs_lcm, tmp_path):
    r = execute(RunOptions(scenario="irassi_small", duration=2.0, out=str(tmp_path), plots=False, quiet=True,
                           transport="direct"))
    meta = json.loads((tmp_path / "run.json").read_text())
    assert meta["transport"] == "direct" and "--transport direct" in meta["repeat_command"]
    assert r.metrics["transport"] == "direct"


def test_the_loop_core_flies_the_direct_adapter_like_the_lcm_run(env, private_netns, aocs_lcm, tmp_path):
    """aocs_loop.core.fly over DirectFlightComputer (the adapter beside LcmFlightComputer), on the configuration
    file the LCM run's fsw_node read: irassi_rw's body and wheel torques of the slew, bit for bit."""
    import numpy as np

    from aocs_core import paths
    from aocs_loop import core
    from aocs_loop.direct_adapter import DirectFlightComputer, DirectNode
    from aocs_loop.frames import PlantPort
    from aocs_loop.lcm_adapter import LcmCodec
    from aocs_plant import Plant
    from aocs_plant.scenario import load
    from aocs_wire import wire

    out = tmp_path / "lcm"
    execute(RunOptions(scenario="irassi_rw", duration=20.0, guidance="slew", out=str(out), plots=False, quiet=True))
    log = lcmlog.read(out / "run.lcmlog")
    sc = load("irassi_rw", json.loads((out / "run.json").read_text())["overrides"])
    t = paths.import_bindings()
    got = {"u": [], "uw": []}

    class Rec(core.Hook):
        def period(self, frame, reply, plant):
            got["u"].append(reply.command.u)
            got["uw"].append(reply.command.u_wheels)

    with DirectNode.from_file(out / "fsw_node.cfg") as node:
        n = core.fly(PlantPort(Plant(sc)), DirectFlightComputer(node, LcmCodec(wire.Codecs(t), t)), sc.n_steps,
                     hooks=[Rec()])
    nw = int(log.cmd["n_wheels"][0])
    assert n == log.cmd["tick"].size == 200 and nw == 4
    assert np.abs(log.cmd["u_wheels"][:, :nw]).max() > 0.05          # the wheels torque the slew
    bits = lambda a: np.ascontiguousarray(np.asarray(a, np.float64)).view(np.uint64)  # noqa: E731
    assert np.array_equal(bits(got["u"]), bits(log.cmd["u_sat"]))
    assert np.array_equal(bits(got["uw"]), bits(log.cmd["u_wheels"][:, :nw]))


def test_compare_flies_every_law_in_process(env, tmp_path):
    """`aocs compare --transport direct`: each law's run is a direct run (run.json), the plan records it."""
    out = tmp_path / "cmp"
    p = subprocess.run([sys.executable, "-m", "aocs.cli", "compare", "irassi_small", "--laws", "quat_pd,smc",
                        "--duration", "5", "--transport", "direct", "--out", str(out), "-q"],
                       capture_output=True, text=True, timeout=600)
    assert p.returncode == 0, p.stderr
    for law in ("quat_pd", "smc"):
        meta = json.loads((out / law / "run.json").read_text())
        assert meta["transport"] == "direct" and meta["law"] == law
        assert not (out / law / "fsw_node.stderr").exists()      # no fsw_node process was started
    plan = json.loads(next(out.glob("*plan*.json")).read_text())
    assert plan["transport"] == "direct"
