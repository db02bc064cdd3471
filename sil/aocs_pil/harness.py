"""Closed-loop runs of one scenario against a flight computer on LCM.

The plant (aocs_plant.plant.Plant) runs in this process; the flight computer
is a separate process on LCM: fsw_node (target "host") or the PIL bridge
(targets "pil-m4f", "pil-m7") started with the same configuration file
(aocs_flightcfg.fsw_config.node_config). Each period: sense, publish
sensors_t, wait (bounded) for the actuator_cmd_t of that tick, apply its
u_sat (and wheel torques), integrate: the closed loop of aocs_loop.core with its
LCM adapter, as plant_node packs and applies. Every command and the true pointing
error are recorded, so runs on different targets can be compared step by step.
run_direct flies the same loop with the PIL adapter (aocs_pil.adapter): frames
straight to the image under QEMU, no LCM, no bridge.

    from aocs_pil import harness
    netns.enter_netns()                      # LCM only inside a private namespace
    host = harness.run("irassi_small", "quat_pd", "host", duration_s=60)
    m7 = harness.run("irassi_small", "quat_pd", "pil-m7", duration_s=60)
    harness.compare(host, m7)

`python -m aocs_pil.harness` prints the figures of docs/pil.md (equivalence,
float accuracy, instruction counts per law and target).
"""
from __future__ import annotations

import argparse
import json
import signal
import statistics
import struct
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

import lcm

from aocs_core import paths, registry
from aocs_flightcfg import fsw_config
from aocs_loop import core
from aocs_loop.frames import PlantPort, SensorFrame
from aocs_loop.lcm_adapter import LcmCodec, LcmFlightComputer
from aocs_plant.plant import Plant
from aocs_plant.scenario import load
from aocs_wire import netns, wire

from . import config as nodecfg
from . import frame
from .adapter import PilFlightComputer
from .qemu import TARGETS, Qemu


def fc_command(target: str) -> list[str]:
    """The flight computer's command line without the configuration file."""
    if target == "host":
        return [str(paths.fsw_node_exe())]
    return [sys.executable, "-m", "aocs_pil.bridge", "--target", target]


@dataclass
class RunResult:
    scenario: str
    law: str
    target: str
    dt: float
    u_sat: list = field(default_factory=list)          # per tick, 3-tuples
    u_wheels: list = field(default_factory=list)       # per tick, the wheel torques (() without a wheel array)
    u_unsat: list = field(default_factory=list)
    mode: list = field(default_factory=list)
    status: list = field(default_factory=list)
    law_id: list = field(default_factory=list)
    step_ns: list = field(default_factory=list)
    overrun: list = field(default_factory=list)
    pointing_arcsec: list = field(default_factory=list)  # true angle at t_k, k = 0 .. n (after the last period)
    qe_arcsec: list = field(default_factory=list)
    sensors: list = field(default_factory=list)        # aocs_loop.frames.SensorFrame per tick
    estimates: list = field(default_factory=list)      # aocs_loop.frames.Estimate per tick (the step's estimate)
    momentum: list = field(default_factory=list)       # aocs_loop.frames.Momentum per tick (the momentum stage's)
    stats: dict = field(default_factory=dict)          # the flight computer's final JSON ("fsw_node")
    returncode: int | None = None
    stderr: str = ""
    wall_s: float = 0.0

    def final_window_max(self, window_s: float) -> float:
        """max true pointing error over the last window_s of the run, arcsec."""
        n = int(round(window_s / self.dt))
        return max(self.pointing_arcsec[-(n + 1):])


class FlightComputer:
    """fsw_node or the bridge as a child process (in the caller's namespace)."""

    def __init__(self, target: str, cfg_path: Path, workdir: Path, extra_args=(), env=None):
        self.target = target
        self.out_path = workdir / f"{target}.stdout"
        self.err_path = workdir / f"{target}.stderr"
        self._out = open(self.out_path, "w")
        self._err = open(self.err_path, "w")
        cmd = fc_command(target) + list(extra_args) + [str(cfg_path)]
        self.proc = subprocess.Popen(cmd, stdout=self._out, stderr=self._err, env=env)

    def stderr(self) -> str:
        if not self._err.closed:
            self._err.flush()
        return self.err_path.read_text()

    def stop(self, timeout: float = 10.0) -> int:
        if self.proc.poll() is None:
            self.proc.send_signal(signal.SIGTERM)
        try:
            rc = self.proc.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            self.proc.kill()
            rc = self.proc.wait(timeout=5)
        self._out.close()
        self._err.close()
        return rc

    def stats(self) -> dict:
        lines = [ln for ln in self.out_path.read_text().splitlines() if ln.startswith("{")]
        return json.loads(lines[-1])["fsw_node"] if lines else {}


class Wire:
    """The plant's side of LCM: publish sensors_t, collect actuator_cmd_t and status_t."""

    def __init__(self, aocs_lcm):
        netns.require_netns()
        self.t = aocs_lcm
        self.lc = lcm.LCM(netns.LCM_URL)
        self.cmds: dict[int, object] = {}
        self.status: list = []
        self.codec = LcmCodec(wire.Codecs(aocs_lcm), aocs_lcm)
        self._cmd_sub = self.lc.subscribe("AOCS_ACTUATOR_CMD", self._on_cmd)
        self.lc.subscribe("AOCS_STATUS", lambda c, d: self.status.append(aocs_lcm.status_t.decode(d)))

    def _on_cmd(self, channel, data):
        m = self.t.actuator_cmd_t.decode(data)
        self.cmds[m.tick] = m

    def pump(self, seconds: float) -> None:
        end = time.monotonic() + seconds
        while (left := end - time.monotonic()) > 0:
            self.lc.handle_timeout(max(1, int(left * 1000)))

    def wait_ready(self, fc: FlightComputer, timeout: float = 60.0) -> None:
        end = time.monotonic() + timeout
        while not any(not s.exiting for s in self.status):
            if fc.proc.poll() is not None:
                raise RuntimeError(f"{fc.target} exited before its first heartbeat (status {fc.proc.returncode}): "
                                   f"{fc.stderr()}")
            if time.monotonic() > end:
                raise TimeoutError(f"{fc.target} sent no heartbeat within {timeout} s: {fc.stderr()}")
            self.lc.handle_timeout(50)
        self.status.clear()

    def send_sensors(self, tick: int, t_s: float, valid: int, q, w, pos, vel, frame_no: int | None = None,
                     wheel_speed=()):
        """wheel_speed: the tachometers of a wheel array (sensors_t.n_wheels of them; none without one)."""
        f = SensorFrame(tick, t_s, valid, tuple(q), tuple(w), tuple(pos), tuple(vel), tuple(wheel_speed))
        self.lc.publish("AOCS_SENSORS", self.codec.pack_sensors(f, frame_no))

    def loop_adapter(self, fc: FlightComputer, reply_timeout: float) -> LcmFlightComputer:
        """The closed loop's LCM adapter on this handle (this Wire then stops collecting commands)."""
        self.lc.unsubscribe(self._cmd_sub)

        def alive(tick):
            if fc.proc.poll() is not None:
                raise RuntimeError(f"{fc.target} exited at tick {tick} (status {fc.proc.returncode}): "
                                   f"{fc.stderr()[-2000:]}")
        return LcmFlightComputer(self.lc, self.codec, reply_timeout=reply_timeout, alive=alive, name=fc.target)

    def wait_cmd(self, tick: int, fc: FlightComputer, timeout: float):
        end = time.monotonic() + timeout
        while tick not in self.cmds:
            if fc.proc.poll() is not None:
                raise RuntimeError(f"{fc.target} exited at tick {tick} (status {fc.proc.returncode}): "
                                   f"{fc.stderr()[-2000:]}")
            left = end - time.monotonic()
            if left <= 0:
                raise TimeoutError(f"{fc.target}: no actuator_cmd_t for tick {tick} within {timeout} s")
            self.lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))
        return self.cmds.pop(tick)


def node_config_for(scenario, law: str) -> dict:
    return fsw_config.node_config(scenario, law, idle_timeout_s=10.0, status_period_s=0.05)


def run(scenario_id: str, law: str | None, target: str, *, duration_s: float | None = None,
        limit: float | None = None, overrides: dict | None = None, workdir: Path | None = None,
        extra_args=(), reply_timeout: float = 10.0, sensors=None) -> RunResult:
    """One closed-loop run (or, with `sensors` from an earlier run, an open-loop replay of those samples)."""
    ov = dict(overrides or {})
    if duration_s is not None:
        ov["duration_s"] = duration_s
        window = load(scenario_id).metrics.window_s
        if window > duration_s:
            ov["metrics.window_s"] = duration_s   # a cut run keeps a valid metric window
    if limit is not None:
        ov["actuator.axis_limit"] = limit   # the plant's actuator and the flight config's u_max_axis
    sc = load(scenario_id, ov or None)
    law = law or sc.control.law
    t_lcm = paths.import_bindings()
    own_tmp = None
    if workdir is None:
        own_tmp = tempfile.TemporaryDirectory(prefix="aocs-pil-")
        workdir = Path(own_tmp.name)
    cfg_path = fsw_config.write(workdir / f"{target}.cfg", node_config_for(sc, law))
    res = RunResult(scenario=sc.id, law=law, target=target, dt=sc.dt)
    wire = Wire(t_lcm)
    fc = FlightComputer(target, cfg_path, workdir, extra_args)
    t0 = time.monotonic()
    try:
        wire.wait_ready(fc)
        link = wire.loop_adapter(fc, reply_timeout)
        rec = _Record(res)
        if sensors is None:
            core.fly(PlantPort(Plant(sc)), link, sc.n_steps, hooks=[rec])
        else:
            core.replay(link, sensors, hooks=[rec])
    finally:
        res.wall_s = time.monotonic() - t0
        res.returncode = fc.stop()
        res.stderr = fc.err_path.read_text()
        res.stats = fc.stats()
        if own_tmp is not None:
            own_tmp.cleanup()
    return res


class _Record(core.Hook):
    """RunResult's record of each period: the frame, the reply's command and telemetry, the true pointing."""

    def __init__(self, res: RunResult):
        self.res = res

    def period(self, frame, reply, plant) -> None:
        res = self.res
        if plant is not None:
            self.truth(plant)
        res.sensors.append(frame)
        res.estimates.append(reply.estimate)
        res.momentum.append(reply.momentum)
        res.u_sat.append(tuple(reply.command.u))
        res.u_wheels.append(tuple(reply.command.u_wheels))
        res.u_unsat.append(tuple(reply.u_unsat))
        res.mode.append(reply.mode)
        res.status.append(reply.status)
        res.law_id.append(reply.law_id)
        res.step_ns.append(reply.step_ns)
        res.overrun.append(reply.overrun)

    def truth(self, plant) -> None:
        tr = plant.truth()
        self.res.pointing_arcsec.append(tr.get("pointing_arcsec", 0.0))
        self.res.qe_arcsec.append(tuple(tr.get("qe_arcsec", (0.0, 0.0, 0.0))))

    def end(self, plant) -> None:
        self.truth(plant)


@dataclass
class DirectResult:
    """A closed loop of the plant and the image without LCM (run_direct)."""
    scenario: str
    law: str
    target: str
    dt: float
    replies: list = field(default_factory=list)       # frame.StepReply per tick
    sensors: list = field(default_factory=list)       # aocs_loop.frames.SensorFrame per tick
    estimates: list = field(default_factory=list)     # aocs_loop.frames.Estimate per tick (the step's estimate)
    momentum: list = field(default_factory=list)      # aocs_loop.frames.Momentum per tick (the momentum stage's)
    u_sat: list = field(default_factory=list)         # per tick, the body torque (force) the plant took
    u_wheels: list = field(default_factory=list)      # per tick, the wheel torques the plant took
    pointing_arcsec: list = field(default_factory=list)
    hello: object = None
    bye: object = None

    @property
    def instructions(self) -> list:
        return [r.instructions for r in self.replies]

    def final_window_max(self, window_s: float) -> float:
        n = int(round(window_s / self.dt))
        return max(self.pointing_arcsec[-(n + 1):])


def run_direct(scenario_id: str, law: str | None, target: str, *, duration_s: float | None = None,
               limit: float | None = None, overrides: dict | None = None, image=None, wrap=None) -> DirectResult:
    """Plant in process, image under QEMU, frames straight over the pipes (no LCM, no bridge): the closed
    loop of aocs_loop.core with the PIL adapter (aocs_pil.adapter.PilFlightComputer).

    The configuration goes the bridge's way (fsw_config -> config file -> aocs_pil.config -> CONFIG frame),
    so the image sees exactly what it would see behind the bridge; used for the per-law budget sweep.
    wrap: a function of the PIL adapter returning the adapter the loop flies instead (a test's fault
    injection between the plant and the image).
    """
    ov = dict(overrides or {})
    if duration_s is not None:
        ov["duration_s"] = duration_s
        if load(scenario_id).metrics.window_s > duration_s:
            ov["metrics.window_s"] = duration_s
    if limit is not None:
        ov["actuator.axis_limit"] = limit
    sc = load(scenario_id, ov or None)
    law = law or sc.control.law
    tgt = TARGETS[target]
    with tempfile.TemporaryDirectory(prefix="aocs-pil-") as tmp:
        path = fsw_config.write(Path(tmp) / "node.cfg", node_config_for(sc, law))
        cfg = nodecfg.load(path)
        payload = cfg.pil_payload(tgt.clock_hz)   # while the file exists
    res = DirectResult(scenario=sc.id, law=law, target=target, dt=sc.dt)
    with Qemu(tgt, image) as q:
        res.hello = q.start()
        _, p = q.request(frame.T_CONFIG, payload, frame.T_CONFIG_ACK)
        ack = frame.Ack.decode(p)
        if ack.pil_err or ack.status:
            raise RuntimeError(f"image refused the configuration: {ack}")
        fc = PilFlightComputer(q, cfg.n_wheels)
        core.fly(PlantPort(Plant(sc)), fc if wrap is None else wrap(fc), sc.n_steps,
                 hooks=[_DirectRecord(res, sc.kind == "attitude")])
        res.bye = q.stop()
    return res


class _DirectRecord(core.Hook):
    """DirectResult's record of each period: the image's reply, the frame, the command, the true pointing."""

    def __init__(self, res: DirectResult, attitude: bool):
        self.res, self.attitude = res, attitude

    def period(self, frame, reply, plant) -> None:
        res = self.res
        self.truth(plant)
        res.replies.append(reply.raw)
        res.sensors.append(frame)
        res.estimates.append(reply.estimate)
        res.momentum.append(reply.momentum)
        res.u_sat.append(tuple(reply.command.u))
        res.u_wheels.append(tuple(reply.command.u_wheels))

    def truth(self, plant) -> None:
        self.res.pointing_arcsec.append(plant.truth().get("pointing_arcsec", 0.0) if self.attitude else 0.0)

    def end(self, plant) -> None:
        self.truth(plant)


def compare(a: RunResult, b: RunResult) -> dict:
    """Step-by-step command differences of two runs of the same scenario."""
    n = min(len(a.u_sat), len(b.u_sat))
    abs_max = 0.0
    rel_max = 0.0
    identical = 0
    first_diff = None
    scale = max((abs(x) for u in a.u_sat[:n] for x in u), default=0.0) or 1.0
    for k in range(n):
        same = (a.u_sat[k] == b.u_sat[k] and a.u_unsat[k] == b.u_unsat[k] and a.mode[k] == b.mode[k]
                and a.status[k] == b.status[k] and a.law_id[k] == b.law_id[k])
        identical += same
        if not same and first_diff is None:
            first_diff = k
        for x, y in zip(a.u_sat[k], b.u_sat[k]):
            d = abs(x - y)
            abs_max = max(abs_max, d)
            rel_max = max(rel_max, d / max(abs(x), 1e-300) if d else 0.0)
    return {"steps": n, "identical_steps": identical, "first_difference_tick": first_diff,
            "u_sat_abs_max_diff": abs_max, "u_sat_max_diff_over_max_u": abs_max / scale,
            "u_sat_rel_max_diff": rel_max}


def ulp_diff(x: float, y: float) -> int:
    """Distance in units of the last place of binary64 (0 = identical)."""
    def key(v):
        i = struct.unpack("<q", struct.pack("<d", v))[0]
        return i if i >= 0 else -(i & 0x7FFFFFFFFFFFFFFF)
    return abs(key(x) - key(y))


# --------------------------------------------------------------------------- report (docs/pil.md)
#: closed loops compared host / pil-m7 / pil-m4f besides every law on its reference scenario
#: (scenario, law, scenario overrides): the other gain table, and a saturating actuator
EQUIVALENCE_EXTRA = [("irassi_small", "lqr_quat", {"laws.lqr_quat.table": "lqr_quat_strong"}),
                     ("irassi_small", "quat_pd", {"actuator.axis_limit": 0.5})]
#: instruction sweep: every law on its reference scenario, and these further full reference scenarios
SWEEP_EXTRA = [("rtc_ex2a", "crp_linear"), ("rtc_ex3a", "crp_linear"), ("irassi_large", "quat_pd"),
               ("irassi_large", "smc"), ("irassi_large", "lqr_quat"), ("landsat8_debris", "orbit_lqr"),
               ("irassi_large", "quat_pid"), ("irassi_large", "lqr_quat_i")]


def equivalence_specs() -> list[tuple[str, str, dict]]:
    """Every law of the registry on its reference scenario, then EQUIVALENCE_EXTRA."""
    return [(law.reference_scenario, law.name, {}) for law in registry.load().laws] + EQUIVALENCE_EXTRA


def sweep_specs() -> list[tuple[str, str]]:
    """Every law of the registry on its reference scenario, then SWEEP_EXTRA."""
    return [(law.reference_scenario, law.name) for law in registry.load().laws] + SWEEP_EXTRA


def _label(sid, law, ov):
    extra = ",".join(f"{k.split('.')[-1]}={v}" for k, v in ov.items())
    return f"{sid} {law}" + (f" ({extra})" if extra else "")


def _clock(s: float) -> str:
    s = max(0, int(round(s)))
    return f"{s // 60}:{s % 60:02d}"


class Progress:
    """A readable progress line per item with an ETA (the mean time per item so far)."""

    def __init__(self, phase: str, total: int, log):
        self.phase, self.total, self.log, self.t0, self.done = phase, max(total, 1), log, time.monotonic(), 0

    def step(self, text: str) -> None:
        self.done += 1
        el = time.monotonic() - self.t0
        eta = _clock(el / self.done * (self.total - self.done))
        self.log(f"pil-report: {self.phase} {self.done}/{self.total}: {text}; {_clock(el)} elapsed, ETA {eta}")


def equivalence_rows(specs=None, duration_s=None, log=print, into=None) -> list[dict]:
    rows = [] if into is None else into
    specs = equivalence_specs() if specs is None else specs
    prog = Progress("equivalence", len(specs), log)
    for sid, law, ov in specs:
        runs = {t: run(sid, law, t, overrides=ov, duration_s=duration_s) for t in ("host", "pil-m7", "pil-m4f")}
        replay = run(sid, law, "pil-m4f", overrides=ov, duration_s=duration_s, sensors=runs["host"].sensors)
        row = {"scenario": sid, "law": law, "overrides": ov, "steps": len(runs["host"].u_sat)}
        for t, r in runs.items():
            if r.returncode != 0:
                raise RuntimeError(f"{t} failed on {sid}/{law}: {r.stderr[-2000:]}")
            d = {"final_arcsec": r.pointing_arcsec[-1], "wall_s": round(r.wall_s, 2)}
            if sid.startswith("irassi"):
                n = int(round(100.0 / r.dt))
                d["final_window_max_arcsec"] = max(r.pointing_arcsec[-(n + 1):])
                d["final_window_qe_arcsec_max"] = max(max(q) for q in r.qe_arcsec[-(n + 1):])
            row[t] = d
        for t in ("pil-m7", "pil-m4f"):
            c = compare(runs["host"], runs[t])
            c["u_sat_max_ulps"] = max(ulp_diff(x, y) for u, v in zip(runs["host"].u_sat, runs[t].u_sat)
                                      for x, y in zip(u, v))
            c["pointing_max_abs_diff_arcsec"] = max(abs(a - b) for a, b in zip(runs["host"].pointing_arcsec,
                                                                               runs[t].pointing_arcsec))
            row["host_vs_" + t] = c
        c = compare(runs["host"], replay)
        c["u_max"] = max(abs(x) for u in runs["host"].u_sat for x in u)
        row["host_vs_pil-m4f_same_samples"] = c
        rows.append(row)
        m7, m4 = row["host_vs_pil-m7"], row["host_vs_pil-m4f_same_samples"]
        prog.step(f"{_label(sid, law, ov)}, {row['steps']} steps: M7 identical to the host on "
                  f"{m7['identical_steps']}/{m7['steps']} steps, M4F (same samples) within "
                  f"{m4['u_sat_abs_max_diff']:.3g} of the host command")
    return rows


def sweep_rows(specs=None, duration_s=None, log=print, into=None) -> list[dict]:
    rows = [] if into is None else into
    specs = sweep_specs() if specs is None else specs
    prog = Progress("instruction counts", 2 * len(specs), log)
    for sid, law in specs:
        for t in ("pil-m4f", "pil-m7"):
            r = run_direct(sid, law, t, duration_s=duration_s)
            ins = r.instructions
            lw = [x.law_instructions for x in r.replies]
            row = {"scenario": sid, "law": law, "target": t, "steps": len(ins), "median": statistics.median(ins),
                   "max": max(ins), "law_median": statistics.median(lw), "law_max": max(lw),
                   "budget": r.replies[-1].budget, "overruns": r.replies[-1].pil_overruns,
                   "inexact": sum(1 for x in r.replies if not x.exact), "stack_bytes": r.bye.stack_bytes}
            rows.append(row)
            prog.step(f"{sid} {law} on {t}: median {row['median']:.0f} instructions, worst {row['max']}, "
                      f"budget {row['budget']}, {row['overruns']} overruns")
    return rows


def markdown(eq: list[dict], sweep: list[dict]) -> str:
    """The tables of docs/pil.md."""
    out = ["| scenario, law | steps | M7 vs host: identical steps | M4F vs host (same samples): max abs diff / "
           "max abs u | M4F closed loop: max pointing diff, arcsec |",
           "|---|---|---|---|---|"]
    for r in eq:
        m7, m4s, m4 = r["host_vs_pil-m7"], r["host_vs_pil-m4f_same_samples"], r["host_vs_pil-m4f"]
        pointing = "- (orbit)" if r["scenario"].startswith("landsat") else f"{m4['pointing_max_abs_diff_arcsec']:.3g}"
        out.append(f"| {_label(r['scenario'], r['law'], r['overrides'])} | {r['steps']} | "
                   f"{m7['identical_steps']}/{m7['steps']} (max {m7['u_sat_max_ulps']} ulp) | "
                   f"{m4s['u_sat_abs_max_diff']:.3g} / {m4s['u_max']:.3g} | {pointing} |")
    out += ["", "| IRASSI run | double (host = M7): max true angle over the last 100 s, arcsec | float (M4F) | "
            "double: max qe_i | float: max qe_i |", "|---|---|---|---|---|"]
    for r in eq:
        if r["scenario"].startswith("irassi"):
            out.append(f"| {_label(r['scenario'], r['law'], r['overrides'])} | "
                       f"{r['host']['final_window_max_arcsec']:.4f} | {r['pil-m4f']['final_window_max_arcsec']:.4f} | "
                       f"{r['host']['final_window_qe_arcsec_max']:.4f} | "
                       f"{r['pil-m4f']['final_window_qe_arcsec_max']:.4f} |")
    out += ["", "| law | target | scenarios (steps) | instructions median | worst | budget | us at clock "
            "(median / worst) | executive window median / worst | stack (painted), bytes |",
            "|---|---|---|---|---|---|---|---|---|"]
    by = {}
    for r in sweep:
        by.setdefault((r["law"], r["target"]), []).append(r)
    for (law, t), rs in by.items():
        mhz = TARGETS[t].clock_hz / 1e6
        med = max(r["median"] for r in rs)
        worst = max(r["max"] for r in rs)
        out.append(f"| {law} | {t} | {', '.join(r['scenario'] for r in rs)} ({sum(r['steps'] for r in rs)}) | "
                   f"{med:.0f} | {worst} | {rs[0]['budget']} | {med / mhz:.1f} / {worst / mhz:.1f} | "
                   f"{max(r['law_median'] for r in rs):.0f} / {max(r['law_max'] for r in rs)} | "
                   f"{max(r['stack_bytes'] for r in rs)} |")
    return "\n".join(out)


def _main(argv=None) -> int:
    ap = argparse.ArgumentParser(prog="python -m aocs_pil.harness",
                                 description="The PIL figures of docs/pil.md: equivalence with the host SIL, float "
                                             "accuracy, instructions per law and target.")
    ap.add_argument("--duration", type=float, default=None, help="cut every run to this many seconds")
    ap.add_argument("--skip-equivalence", action="store_true")
    ap.add_argument("--skip-sweep", action="store_true")
    ap.add_argument("--json", help="write the raw rows here")
    args = ap.parse_args(argv)
    netns.reexec_in_netns([sys.executable, "-m", "aocs_pil.harness", *sys.argv[1:]])

    eq: list[dict] = []
    sw: list[dict] = []

    def save():
        if args.json:   # after every row: a run that fails late keeps the rows measured before it
            Path(args.json).write_text(json.dumps({"equivalence": eq, "sweep": sw}, indent=1))

    def log(line):
        print(line, file=sys.stderr, flush=True)
        save()
    if not args.skip_equivalence:
        eq = equivalence_rows(duration_s=args.duration, log=log, into=eq)
    if not args.skip_sweep:
        sw = sweep_rows(duration_s=args.duration, log=log, into=sw)
    save()
    print(markdown(eq, sw))
    return 0


if __name__ == "__main__":
    sys.exit(_main())
