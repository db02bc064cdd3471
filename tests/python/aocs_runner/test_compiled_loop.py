"""The compiled loop of the in-process transport (aocs_runner.compiled_loop, sil/plant_kernels/direct_loop_kernel.c).

Its oracle is plant_node's Python loop, the same run with AOCS_PLANT_KERNELS=periods: every message of the log (the
sensors_t, truth_t and event_t bytes; the actuator_cmd_t bytes but its step timing), the plant_node summary but its
timing, and the run's end must be the same, for
- plain runs of every scenario it flies, with actuator limits that clip, a scale factor, and scheduled commands and
  link faults (the ticks it hands back to Python);
- a node whose replies are corrupted at one tick (a ctypes wrapper around the real node, the same corruption on
  both paths): a non-finite torque, a reply for another tick, another message type, wheels or magnetorquers the
  plant has not, no reply, a failing node call.
And which plants it refuses, with the reason plant_node reports.
"""
from __future__ import annotations

import argparse
import ctypes
import json
import math
import struct

import pytest

from aocs_loop import direct_adapter
from aocs_plant import Plant, kernels
from aocs_plant.integration_error import StepDoubling
from aocs_plant.scenario import load
from aocs_runner import compiled_loop, plant_node
from aocs_runner.run import RunOptions, execute
from aocs_runner.scenario_opts import parse_sets
from aocs_wire import wire

#: actuator_cmd_t fields the node fills from the clock
TIMING = ("step_ns", "overrun", "n_overrun")
#: event_t's: the node's monotonic clock when it sent it
EVENT_TIMING = ("utime",)
#: summary fields that are wall time, or the loop's own bookkeeping
SUMMARY_TIMING = ("startup_s", "startup_build_s", "loop_s", "loop_cpu_s", "roundtrip_ns", "compiled_loop", "cpus",
                  "handle_calls")


@pytest.fixture(scope="module")
def codecs(aocs_lcm):
    return wire.Codecs(aocs_lcm)


def _records(path):
    b = path.read_bytes()
    i, out = 0, []
    while i < len(b):
        _, num, _, cl, dl = struct.unpack_from(">IqqII", b, i)
        i += 28
        ch = b[i:i + cl]
        i += cl
        out.append((num, ch, b[i:i + dl]))
        i += dl
    return out


def _comparable(codecs, records):
    """The log's records without the wall clock: the runner's markers and status_t dropped, the actuator_cmd_t's
    timing fields zeroed."""
    a = codecs.actuator
    out = []
    for num, ch, data in records:
        if ch in (b"AOCS_RUNNER", b"AOCS_STATUS"):
            continue
        if ch == b"AOCS_ACTUATOR_CMD" and len(data) == a.size:   # a foreign fingerprint's too (a corrupted one)
            v = list(a.unpack(a.fingerprint + data[8:]))
            for f in TIMING:
                v[a.index(f)] = 0
            data = data[:8] + a.pack(*v)[8:]   # bytes: a NaN compares as itself
        elif ch == b"AOCS_EVENTS":
            e = codecs.event
            v = list(e.unpack(data))
            for f in EVENT_TIMING:
                v[e.index(f)] = 0
            data = e.pack(*v)
        out.append((num, ch, data))
    return out


@pytest.fixture(scope="module")
def fsw_cfg(aocs_build_dir, private_netns, tmp_path_factory):
    """fsw_node.cfg of irassi_large as the runner writes it, and the scenario override that goes with it."""
    out = tmp_path_factory.mktemp("cfg")
    execute(RunOptions(scenario="irassi_large", law="quat_pd", duration=3.0, out=str(out), plots=False, quiet=True,
                       transport="direct"))   # raises when the run fails
    return out / "fsw_node.cfg"


def _fly(tmp_path, name, cfg, capsys, python: bool, extra=(), duration=120.0):
    """plant_node in this process, direct, with the compiled loop (python: without); (exit code, log, summary)."""
    with pytest.MonkeyPatch.context() as m:
        m.setenv("AOCS_PLANT_KERNELS", "periods" if python else "all")
        log = tmp_path / f"{name}-{'python' if python else 'compiled'}.lcmlog"
        argv = ["irassi_large", "--transport", "direct", "--fsw-config", str(cfg), "--fsw-summary",
                str(tmp_path / "fsw.json"), "--log", str(log), "--set", f"duration_s={duration}", "--reply-timeout",
                "0.2", "-q", *extra]
        capsys.readouterr()
        try:
            rc = plant_node.main(argv)
        except direct_adapter.DirectError as exc:
            rc = f"DirectError: {exc}"
    lines = [json.loads(s)["plant_node"] for s in capsys.readouterr().out.splitlines() if s.startswith('{"plant_node"')]
    return rc, log, (lines[0] if lines else None)


def _same(codecs, a, b):
    rc_a, log_a, sum_a = a
    rc_b, log_b, sum_b = b
    assert rc_a == rc_b
    ra, rb = _comparable(codecs, _records(log_a)), _comparable(codecs, _records(log_b))
    assert len(ra) == len(rb)
    for x, y in zip(ra, rb):
        assert x == y, f"record {x[0]} ({x[1]}) differs"
    if sum_a is not None or sum_b is not None:
        assert {k: v for k, v in sum_a.items() if k not in SUMMARY_TIMING} == \
               {k: v for k, v in sum_b.items() if k not in SUMMARY_TIMING}


@pytest.mark.parametrize("extra", [
    (),
    # limits that clip most of the slew, and a scale factor
    ("--set", "actuator.axis_limit=0.05", "--set", "actuator.norm_limit=0.06", "--set", "actuator.scale_factor=0.9"),
    # commands and link faults: the ticks handed back to Python, and the periods around them compiled
    ("--event", "2.05:law=smc", "--event", "3:malformed", "--event", "3.5:duplicate", "--event", "4:drop",
     "--event", "4.5:stale", "--event", "5:foreign", "--event", "6:mode=safe"),
], ids=["plain", "limits", "events"])
def test_the_compiled_loop_flies_what_the_python_loop_flies(fsw_cfg, codecs, tmp_path, capsys, extra):
    py = _fly(tmp_path, "a", fsw_cfg, capsys, True, extra)
    c = _fly(tmp_path, "a", fsw_cfg, capsys, False, extra)
    assert py[0] == 0 and py[2]["compiled_loop"]["periods"] == 0
    assert c[2]["compiled_loop"]["why_not"] is None
    events = sum(1 for e in extra if ":" in e and not e.startswith("actuator"))
    assert c[2]["steps"] - events <= c[2]["compiled_loop"]["periods"] < c[2]["steps"] or not events
    _same(codecs, py, c)
    if "actuator.axis_limit=0.05" in extra:   # the limits did clip (the comparison covers them)
        a = codecs.actuator
        i = a.index("u_sat")
        assert any(abs(a.unpack(r[2])[i]) > 0.05 for r in _records(py[1]) if r[1] == b"AOCS_ACTUATOR_CMD")


# ---- a node whose reply is corrupted at one tick: the same corruption on both paths ----

BAD_TICK = 30
_SENSORS_T = ctypes.CFUNCTYPE(ctypes.c_int32, ctypes.c_int32, ctypes.c_void_p, ctypes.c_uint32, ctypes.c_void_p,
                              ctypes.c_uint32)


def _corruptions(codecs):
    a = codecs.actuator

    def field(name, value):
        def f(reply):
            v = list(a.unpack(reply))
            v[a.index(name)] = value
            return a.pack(*v)
        return f

    def torque_nan(reply):
        v = list(a.unpack(reply))
        v[a.index("u_sat") + 1] = math.nan
        return a.pack(*v)
    return {
        "nan_torque": torque_nan,
        "stale": field("tick", BAD_TICK - 1),
        "foreign_type": lambda reply: b"\x00" * 8 + reply[8:],
        "wheels": field("n_wheels", 2),
        "magnetorquers": field("mom_policy", 1),
        "dropped": lambda reply: None,
        "node_error": lambda reply: -3,
    }


def _install(monkeypatch, codecs, corrupt, bad_tick=BAD_TICK):
    """Both paths' node calls wrapped: the reply of bad_tick's sensors_t goes through corrupt (bytes, None: no
    reply, an int: the call's failure code)."""
    s_codec = codecs.sensors
    i_tick = s_codec.index("tick")

    def tick_of(data: bytes):
        v = s_codec.unpack(data)
        return v[i_tick] if v is not None else None

    real_sensors = direct_adapter.DirectNode.sensors

    def py_sensors(self, data):
        reply = real_sensors(self, data)
        if tick_of(data) != bad_tick or reply is None:
            return reply
        r = corrupt(reply)
        if isinstance(r, int):
            raise direct_adapter.DirectError(f"aocs_direct_sensors failed ({r})")
        return r
    monkeypatch.setattr(direct_adapter.DirectNode, "sensors", py_sensors)

    lib = ctypes.CDLL(str(direct_adapter.library_path()))
    real = lib.aocs_direct_sensors
    real.restype = ctypes.c_int32
    real.argtypes = (ctypes.c_int32, ctypes.c_void_p, ctypes.c_uint32, ctypes.c_void_p, ctypes.c_uint32)

    def c_sensors(h, data, n, out, cap):
        m = real(h, data, n, out, cap)
        if m <= 0 or tick_of(ctypes.string_at(data, n)) != bad_tick:
            return m
        r = corrupt(ctypes.string_at(out, m))
        if r is None:
            return 0
        if isinstance(r, int):
            return r
        ctypes.memmove(out, r, len(r))
        return len(r)
    fn = _SENSORS_T(c_sensors)
    event = ctypes.cast(lib.aocs_direct_event, ctypes.c_void_p).value
    orig_build = compiled_loop.build

    def build(loop):
        seg, why = orig_build(loop)
        return (None if seg is None else compiled_loop.CompiledLoop(
            loop, (ctypes.cast(fn, ctypes.c_void_p).value, event))), why
    monkeypatch.setattr(compiled_loop, "build", build)
    return fn   # kept alive by the caller


@pytest.mark.parametrize("kind", ["nan_torque", "stale", "foreign_type", "wheels", "magnetorquers", "dropped",
                                  "node_error"])
def test_a_corrupted_reply_ends_or_goes_on_as_in_python(fsw_cfg, codecs, tmp_path, capsys, kind):
    corrupt = _corruptions(codecs)[kind]
    results = []
    for python in (True, False):
        with pytest.MonkeyPatch.context() as m:
            keep = _install(m, codecs, corrupt)   # noqa: F841 - the callback must outlive the run
            results.append(_fly(tmp_path, kind, fsw_cfg, capsys, python))
    py, c = results
    _same(codecs, py, c)
    if kind == "nan_torque":   # refused and counted, the run goes on
        assert py[0] == 0 and py[2]["plant_counters"]["bad_commands"] == 1
        assert c[2]["compiled_loop"]["periods"] == c[2]["steps"]
    elif kind == "node_error":
        assert c[0] == "DirectError: aocs_direct_sensors failed (-3)"
    else:
        assert py[0] != 0 and py[2]["last_tick"] == BAD_TICK
        assert (c[2]["stale_replies"], c[2]["bad_replies"]) == {"stale": (1, 0), "foreign_type": (0, 1)}.get(kind,
                                                                                                           (0, 0))


def test_plants_it_does_not_fly_are_named(aocs_build_dir, private_netns, tmp_path):
    """A plant with wheels, a noisy sensor or an actuator lag stays in the Python loop, and plant_node says why."""
    for scenario, sets, why in (("irassi_rw", (), "effectors with state"),
                                ("irassi_large_mekf", (), "sensors other than ideal"),
                                ("irassi_large", ("actuator.slew_rate_limit_per_s=0.5",), "slew-rate limit"),
                                ("irassi_large", ("sensors.attitude_noise_rad=1e-6",), "sensors other than ideal")):
        out = tmp_path / scenario
        execute(RunOptions(scenario=scenario, law=None, duration=2.0, out=str(out), plots=False, quiet=True,
                           transport="direct", sets=list(sets)))
        line = next(s for s in (out / "plant_node.stdout").read_text().splitlines() if s.startswith('{"plant_node"'))
        cl = json.loads(line)["plant_node"]["compiled_loop"]
        assert cl["periods"] == 0 and why in cl["why_not"]


# ---- in process: the Python objects after the run, and bad arguments ----

def _loop(cfg, sets=()):
    """plant_node's lockstep loop over the in-process node, built as plant_node.run builds it (no log)."""
    sc = load("irassi_large", parse_sets(["duration_s=120", *sets]))
    node = direct_adapter.DirectNode.from_file(cfg)
    link = plant_node._Link(None, bus=direct_adapter.DirectBus(node))
    args = argparse.Namespace(start_tick=0, reply_timeout=0.2, quiet=True)
    return plant_node._Loop(Plant(sc), sc, link, {}, args, StepDoubling(sc)), node


def _objects(loop):
    p, a, c = loop.plant, loop.plant.actuator, loop.check
    return (p.body.q, p.body.w, p.k, dict(p.counters), p.taken, p.applied, a.held, a._limited, a.saturated_count,
            c.summary(), c._last, loop.frame_truth, loop.steps, loop.last_tick, loop.last_answered,
            c.shadow.actuator.held, len(loop.rt_ns), p._suite.history)


def test_the_objects_after_a_compiled_run_are_the_python_loops(fsw_cfg, monkeypatch):
    """Plant, actuator (its saturation count too), integration check and loop as the Python loop leaves them."""
    sets = ("actuator.axis_limit=0.05", "actuator.norm_limit=0.06")
    out = []
    for mode in ("periods", "all"):
        monkeypatch.setenv("AOCS_PLANT_KERNELS", mode)
        loop, node = _loop(fsw_cfg, sets)
        with node:
            assert loop.run_lockstep() == ("done", 0)
            out.append(_objects(loop))
            assert loop.compiled_periods == (0 if mode == "periods" else loop.steps)
    assert out[0][8] > 0   # the limits clipped
    assert out[0] == out[1]


def test_a_command_refused_in_the_last_period_leaves_the_objects_as_python_does(fsw_cfg, codecs):
    """A NaN torque in the last period: Plant.taken None, the refusal counted, the held torque kept."""
    out = []
    for mode in ("periods", "all"):
        with pytest.MonkeyPatch.context() as m:
            m.setenv("AOCS_PLANT_KERNELS", mode)
            keep = _install(m, codecs, _corruptions(codecs)["nan_torque"], bad_tick=1199)  # noqa: F841
            loop, node = _loop(fsw_cfg)
            with node:
                assert loop.run_lockstep() == ("done", 0)
                out.append(_objects(loop))
    assert out[0][4] is None and out[0][3]["bad_commands"] == 1
    assert out[0] == out[1]


def test_bad_arguments_are_named(fsw_cfg):
    loop, node = _loop(fsw_cfg)
    with node:
        good = compiled_loop.config(loop)
        mod = kernels.module(kernels.DIRECT_LOOP)
        J, Ji = loop.plant.body.J, loop.plant.body.Ji
        for i, bad, msg in ((0, -0.1, "dt > 0"), (13, 0, "null"), (18, ((0, "d"),), "sensors_t fields"),
                            (18, tuple((o, "x") for o, _ in good[18]), "codes"), (17, b"\x00" * 8, "outside"),
                            (23, b"1234", "fingerprint"), (28, (b"A", b"B", b"C", b""), "channel")):
            cfg = list(good)
            cfg[i] = bad
            with pytest.raises((ValueError, TypeError), match=msg):
                mod.DirectLoop(J, Ji, None, tuple(cfg))
        k = mod.DirectLoop(J, Ji, None, good)
        with pytest.raises(ValueError, match="37"):
            k.run((0.0,) * 5, 0, 1)
        state = compiled_loop.CompiledLoop(loop)._state()
        with pytest.raises(ValueError, match=">= 0"):
            k.run(state, 0, -1)
        with pytest.raises(TypeError, match=r"state\[0\]: not a number"):
            k.run(("x",) + state[1:], 0, 1)
        with pytest.raises(TypeError, match=r"state\[7\]: not an integer"):
            k.run(state[:7] + (0.5,) + state[8:], 0, 1)
