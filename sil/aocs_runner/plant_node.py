"""The plant as its own LCM process.

    python -m aocs_runner.plant_node SCENARIO [--set k=v ...] [--mode lockstep|realtime]
        [--reply-timeout S] [--ready-timeout S] [--start-tick K] [--event SPEC ...] [-q]

Per control tick k (time t_k = (start_tick + k) dt):
  1. scheduled events of tick k (events.py: commands, transport faults);
  2. publish sensors_t of tick k (AOCS_SENSORS), tick = frame = start_tick + k;
  3. publish truth_t of tick k (AOCS_TRUTH), while the flight computer
     computes: the true state at t_k, the disturbance at t_k and the actuator
     output applied over the previous period (Plant.truth's meaning; zero
     before the first command);
  4. lockstep: wait (bounded, --reply-timeout) for the actuator_cmd_t whose
     tick is k, apply its u_sat, integrate one period. Real time: sleep to the
     next absolute deadline t0 + (k+1) dt while receiving commands, then apply
     the newest command received and integrate (the command acts one period
     late at most, like a sampled actuator interface).
After the last period, truth_t of tick N (the final state) is published.

With --log PATH the plant is also the run's recorder (aocs run in lockstep, aocs campaign): its udpm
socket receives every message on the group, its own included, and it writes each one to PATH (the
lcm-logger format) in the order it received them (written every LOG_FLUSH_TICKS ticks over LCM, every
LOG_FLUSH_EVENTS events in process: what a killed plant can lose); with --truth log its truth samples go to that log
only, not on the bus (no other process reads them, and sending them cost the plant, the flight computer
and a recorder ~0.3 s of CPU per 500 s irassi_large run). After the last tick it writes --done-file and
records on until the runner's "end" marker (the runner stops the flight computer first, so its last
status is in the log), at most END_MARKER_TIMEOUT_S.

Before the first tick the node waits (bounded, --ready-timeout) for a
status_t heartbeat of the flight computer, so no sensor frame is sent before
it listens. Exit codes: 0 done, 2 bad arguments / scenario, 3 no flight
computer heartbeat, 4 the flight computer stopped answering (lockstep),
5 interrupted by a signal. Progress lines go to stderr (every 10 %), one JSON
summary line {"plant_node": {...}} to stdout.
"""
from __future__ import annotations

import time

import lcm

from aocs_core import paths
from aocs_loop.direct_adapter import DirectBus, DirectError, DirectNode
from aocs_loop.frames import ActuatorMismatch, PlantPort, SensorFrame, WheelMismatch
from aocs_loop.lcm_adapter import LcmCodec
from aocs_plant import Plant
from aocs_plant.integration_error import StepDoubling
from aocs_plant.scenario import ScenarioError, load
from aocs_wire import netns, wire
from aocs_wire.recorder import RUNNER_CHANNEL, EventLogWriter, marker_message, marker_of
from aocs_wire.udpm import Udpm

from . import compiled_loop
from . import events as evmod
from .scenario_opts import parse_sets
from .transport import TRANSPORTS

T_PROCESS = time.perf_counter()  # before the heavy imports: startup cost is measured from here

import argparse  # noqa: E402
import bisect  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import os  # noqa: E402
import signal  # noqa: E402
import sys  # noqa: E402
from array import array  # noqa: E402

from aocs_core.conventions import ARCSEC_PER_RAD, quat_mul, quat_to_dcm  # noqa: E402

EXIT_OK, EXIT_ARGS, EXIT_NOT_READY, EXIT_NO_REPLY, EXIT_SIGNAL = 0, 2, 3, 4, 5
#: --log: longest wait for the runner's end marker after the last tick, s
END_MARKER_TIMEOUT_S = 30.0
#: --log: events kept in memory before they are written
LOG_FLUSH_EVENTS = 1024
#: over LCM the lockstep loop writes the log every this many ticks (what a killed plant can lose at most)
LOG_FLUSH_TICKS = 16
#: the header whose AOCS_NODE_WAIT_SPIN_MAX_US bounds --wait-spin-us (fsw_node's wait_spin_us: one bound for both)
SPIN_HEADER = "sil/fsw_node/node_checks.h"
_TRUTH = b"AOCS_TRUTH"

_stop = False


def _on_signal(signum, frame):  # noqa: ARG001
    global _stop
    _stop = True


def add_arguments(p: argparse.ArgumentParser) -> None:
    p.add_argument("scenario", help="scenario id or path")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="scenario override")
    p.add_argument("--mode", choices=("lockstep", "realtime"), default="lockstep")
    p.add_argument("--reply-timeout", type=float, default=2.0,
                   help="lockstep: max wait for each actuator_cmd_t, s (default 2)")
    p.add_argument("--ready-timeout", type=float, default=10.0,
                   help="max wait for the flight computer's first heartbeat, s (default 10)")
    p.add_argument("--start-tick", type=int, default=0,
                   help="first tick / frame number (a restarted plant continues the sequence)")
    p.add_argument("--event", action="append", default=[], metavar="T:WHAT", help="see events.py")
    p.add_argument("--ready-file", default=None,
                   help="written once the node listens for the flight computer (the runner starts it then)")
    p.add_argument("--lcm-url", default=None, help="LCM URL (default: the namespace's udpm URL)")
    p.add_argument("--lcm-lib", action="store_true",
                   help="use the LCM library's receive thread instead of reading udpm directly (udpm.py)")
    p.add_argument("--log", default=None, metavar="PATH",
                   help="record every message on the bus to PATH (the plant is the run's recorder)")
    p.add_argument("--truth", choices=("bus", "log"), default="bus",
                   help="truth_t published on the bus (default) or written to the --log file only")
    p.add_argument("--done-file", default=None,
                   help="with --log: written after the last tick; the plant then records until the end marker")
    p.add_argument("--transport", choices=TRANSPORTS, default="lcm",
                   help="lcm (default): the flight computer is another process on the bus; direct: fsw_node's "
                        "node logic in this process (aocs_loop.direct_adapter), lockstep only")
    p.add_argument("--fsw-config", default=None, metavar="PATH",
                   help="--transport direct: the flight computer's configuration (fsw_node.cfg)")
    p.add_argument("--fsw-summary", default=None, metavar="PATH",
                   help="--transport direct: where the flight computer's exit summary goes (fsw_node.stdout)")
    p.add_argument("--wait-spin-us", type=float, default=0.0, metavar="US",
                   help="lockstep over udpm: each wait for the reply polls this long before it sleeps, us "
                        "(default 0; the runner passes transport.LOCKSTEP_WAIT_SPIN_US, aocs_wire/udpm.py)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


class _Link:
    """LCM handle, codecs and the publish counters of this node."""

    def __init__(self, url, lcm_lib=False, bus=None, spin_us=0.0):
        self.t = paths.import_bindings()
        self.codecs = wire.Codecs(self.t)
        self.codec = LcmCodec(self.codecs, self.t)   # the loop's sensors_t packing, actuator_cmd_t reading
        self.direct = bus is not None
        if bus is not None:
            self.lc = bus   # aocs_loop.direct_adapter.DirectBus: the node in this process, no socket
        else:
            if url is None:
                netns.require_netns()
                url = netns.LCM_URL
            # udpm: the same packets, read in this thread (udpm.py)
            self.lc = lcm.LCM(url) if lcm_lib or not url.startswith("udpm://") else Udpm(url, spin_us=spin_us)
        self.wire = wire
        self.frame_cmd = 0
        self.request = 0
        self.log = None           # EventLogWriter when the plant records the bus (--log)
        self.end_seen = False     # the runner's end marker has been recorded
        self.truth_on_bus = True

    def record(self, path: str, truth_on_bus: bool) -> None:
        """Record every message the socket receives (all channels) to path; truth_t to the bus or not."""
        self.log = log = EventLogWriter(path)
        self.truth_on_bus = truth_on_bus
        add = log.add

        def on_any(channel: bytes, data: bytes) -> None:   # every message, the hot path: names bound once
            add(channel, data)
            if channel == RUNNER_CHANNEL and (marker_of(data) or {}).get("marker") == "end":
                self.end_seen = True
            if log.pending >= LOG_FLUSH_EVENTS:   # lockstep over LCM: the loop writes every LOG_FLUSH_TICKS too
                log.flush()
        self.lc.subscribe_all(on_any)

    def publish_truth(self, data: bytes) -> None:
        if self.truth_on_bus:
            self.lc.publish("AOCS_TRUTH", data)
        else:
            self.log.add(_TRUTH, data)

    def marker(self, what: str, **info) -> None:
        """--transport direct: the runner's AOCS_RUNNER marker, published here (no runner on a bus)."""
        self.lc.publish(RUNNER_CHANNEL, marker_message(what, f"{what}-1", **info))

    def end_direct(self, reason: str, summary_path: str | None, sc) -> None:
        """--transport direct, after the last tick: the node's last status_t, its exit summary (as fsw_node
        prints it) written to summary_path, and the end marker (so the log is whole)."""
        bus = self.lc
        bus.heartbeat(exiting=True)
        bus.handle_timeout(0)
        rep = bus.node.report(reason)
        if summary_path:
            with open(summary_path, "w") as f:
                f.write(json.dumps(rep) + "\n")
        self.marker("end", scenario=sc.id)

    def record_until_end_marker(self, done_file: str | None) -> None:
        """After the last tick (--log): say so in done_file, then record until the runner's end marker."""
        if self.log is None:
            return
        if done_file:
            with open(done_file, "w") as f:
                f.write("done\n")
        end = time.monotonic() + END_MARKER_TIMEOUT_S
        while not self.end_seen and not _stop:
            left = end - time.monotonic()
            if left <= 0:
                print(f"plant_node: no end marker from the runner within {END_MARKER_TIMEOUT_S:g} s; "
                      "the log ends here", file=sys.stderr, flush=True)
                break
            self.lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))

    def close_log(self) -> None:
        if self.log is not None:
            self.log.close()

    def command(self, ev, utime):
        c = self.codecs.command
        k = self.t.command_t
        self.request += 1
        qd = ev.target if ev.target is not None else (0.0, 0.0, 0.0, 1.0)
        data = c.pack(k.PROTOCOL_VERSION, self.frame_cmd, utime, self.request,
                      ev.law_id if ev.kind == "law" else k.LAW_KEEP,
                      ev.mode if ev.kind == "mode" else k.MODE_KEEP,
                      ev.target is not None, *qd, 0.0, 0.0, 0.0)
        self.frame_cmd += 1
        self.lc.publish(self.wire.COMMAND, data)


def _wait_ready(link: _Link, timeout: float, ready_file: str | None = None) -> bool:
    seen = []
    st = link.codecs.status
    i_exit = st.index("exiting")

    def on_status(ch, data):  # noqa: ARG001
        v = st.unpack(data)
        if v is not None and not v[i_exit]:
            seen.append(v)

    sub = link.lc.subscribe(link.wire.STATUS, on_status)
    if ready_file:
        # listening now: the runner may start the flight computer
        with open(ready_file, "w") as f:
            f.write("listening\n")
    end = time.monotonic() + timeout
    while not seen and not _stop:
        left = end - time.monotonic()
        if left <= 0:
            break
        link.lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))
    link.lc.unsubscribe(sub)
    return bool(seen)


def _pctl(sorted_vals, p):
    if not sorted_vals:
        return 0
    i = min(len(sorted_vals) - 1, max(0, int(math.ceil(p / 100.0 * len(sorted_vals))) - 1))
    return sorted_vals[i]


def run(args) -> int:
    global _stop
    _stop = False   # a process that flies one run after another (plant_fork.run_here) starts each afresh
    signal.signal(signal.SIGTERM, _on_signal)
    signal.signal(signal.SIGINT, _on_signal)
    try:
        sc = load(args.scenario, parse_sets(args.set))
        # the --event commands and faults, the observation plan's targets (events.plan_events) and the drops of
        # the injected link faults (events.fault_events)
        evs = evmod.schedule(sorted(evmod.parse_all(args.event) + evmod.plan_events(sc)
                                    + evmod.fault_events(sc.faults, sc.dt, sc.n_steps, args.start_tick),
                                    key=lambda e: e.t),
                             sc.dt, sc.n_steps, args.start_tick)
    except (ScenarioError, evmod.EventError, ValueError) as exc:
        print(f"plant_node: {exc}", file=sys.stderr)
        return EXIT_ARGS
    if args.truth == "log" and args.log is None:
        print("plant_node: --truth log needs --log PATH (the log the truth samples go to)", file=sys.stderr)
        return EXIT_ARGS
    if args.log is not None and (args.lcm_lib or not (args.lcm_url or netns.LCM_URL).startswith("udpm://")):
        print("plant_node: --log records the udpm socket the plant reads itself: not with --lcm-lib or "
              "another transport", file=sys.stderr)
        return EXIT_ARGS
    spin_max = paths.header_number(SPIN_HEADER, "AOCS_NODE_WAIT_SPIN_MAX_US")
    if not 0.0 <= args.wait_spin_us <= spin_max:
        print(f"plant_node: --wait-spin-us {args.wait_spin_us:g}: must be in [0, {spin_max:g}] us", file=sys.stderr)
        return EXIT_ARGS
    node = None
    if args.transport == "direct":
        try:
            node = _direct_node(args)
        except (ValueError, OSError, DirectError) as exc:
            print(f"plant_node: --transport direct: {exc}", file=sys.stderr)
            return EXIT_ARGS
    plant = Plant(sc)
    check = StepDoubling(sc)   # the run's integration error (SPEC 4.3)
    link = _Link(args.lcm_url, args.lcm_lib, bus=None if node is None else DirectBus(node),
                 spin_us=args.wait_spin_us if args.mode == "lockstep" else 0.0)
    if args.log is not None:
        link.record(args.log, truth_on_bus=args.truth == "bus")
    try:
        if node is not None:
            link.marker("start", scenario=sc.id, mode=args.mode, transport="direct")
            link.lc.heartbeat()   # the flight computer's first heartbeat, as fsw_node's
        return _fly(args, sc, plant, check, link, evs)
    finally:
        link.close_log()
        if node is not None:
            node.close()


def _direct_node(args):
    """--transport direct: the in-process node on --fsw-config (ValueError: what is missing)."""
    if args.mode != "lockstep":
        raise ValueError("lockstep only (not with --mode realtime)")
    if args.fsw_config is None:
        raise ValueError("needs --fsw-config PATH (the flight computer's configuration)")
    if args.lcm_lib or args.lcm_url:
        raise ValueError("no bus: not with --lcm-lib or --lcm-url")
    return DirectNode.from_file(args.fsw_config)


def _fly(args, sc, plant, check, link, evs) -> int:
    t_built = time.perf_counter()
    if not _wait_ready(link, args.ready_timeout, args.ready_file):
        if _stop:
            return EXIT_SIGNAL
        print(f"plant_node: no heartbeat from the flight computer on {link.wire.STATUS} within "
              f"{args.ready_timeout} s", file=sys.stderr)
        return EXIT_NOT_READY
    t_ready = time.perf_counter()
    cpu_ready = time.process_time()
    loop = _Loop(plant, sc, link, evs, args, check)
    reason, code = loop.run_realtime() if args.mode == "realtime" else loop.run_lockstep()
    t_end = time.perf_counter()
    cpu_loop = time.process_time() - cpu_ready
    rt = sorted(loop.rt_ns)
    summary = {
        "reason": reason, "mode": args.mode, "scenario": sc.id, "steps": loop.steps,
        "n_steps": sc.n_steps, "start_tick": args.start_tick, "last_tick": loop.last_tick,
        "last_answered_tick": loop.last_answered,
        "startup_s": t_ready - T_PROCESS, "startup_build_s": t_built - T_PROCESS,
        "loop_s": t_end - t_ready,
        # this process's CPU time in the loop (a loaded machine's wall time is not the loop's cost; in process
        # the flight computer's step is in it too)
        "loop_cpu_s": cpu_loop,
        "roundtrip_ns": {"n": len(rt), "median": _pctl(rt, 50), "p99": _pctl(rt, 99),
                         "max": rt[-1] if rt else 0},
        "stale_replies": loop.stale_replies, "bad_replies": loop.bad_replies,
        "plant_counters": plant.counters,
        "wake_jitter_ns_max": loop.jitter_max_ns,
        "handle_calls": loop.handle_calls,
        "integration_error": check.summary(),
        # the unloading actuators' own integrals at the end (run JSON momentum.unloading.plant)
        "unloading_actuators": _unloading_totals(plant),
        # what the direct udpm reader dropped (fragments beyond its bounds, garbage): udpm.Udpm.counters
        "udpm": getattr(link.lc, "counters", None),
        "transport": "direct" if link.direct else "lcm",
        "cpus": sorted(os.sched_getaffinity(0)),   # where the loop ran (aocs run may pin it: flight._pin)
        # in process: the periods the compiled loop flew (compiled_loop), or why it did not
        "compiled_loop": {"periods": loop.compiled_periods, "why_not": loop.compiled_why_not},
    }
    print(json.dumps({"plant_node": summary}), flush=True)
    if link.direct:
        link.end_direct(reason, args.fsw_summary, sc)
    link.record_until_end_marker(args.done_file)
    return code


#: the plant's effector truth fields reported in the summary (the unloading actuators' integrals)
_UNLOADING_TOTALS = ("thrusters.propellant_kg", "thrusters.pulses", "magnetorquers.dipole_s_am2s")


def _unloading_totals(plant) -> dict | None:
    """The thrusters' propellant and pulses and the magnetorquers' dipole integral at the end, None without them."""
    if not ({"thruster_on_s", "u_dipole_am2"} & set(getattr(plant, "command_fields", {}))):
        return None
    tr = plant.effector_truth()
    return {k: (list(tr[k]) if isinstance(tr[k], tuple) else tr[k]) for k in _UNLOADING_TOTALS if k in tr}


class _Loop:
    def __init__(self, plant, sc, link: _Link, evs, args, check):
        self.plant, self.sc, self.link, self.evs, self.args = plant, sc, link, evs, args
        self.dt = sc.dt
        self.check = check
        self.steps = 0
        self.last_tick = -1
        self.last_answered = -1
        self.stale_replies = 0
        self.bad_replies = 0
        self.rt_ns = array("q")
        self.jitter_max_ns = 0
        self.handle_calls = 0
        self.frame_truth = 0
        self.compiled_periods = 0
        self.compiled_why_not = "not in lockstep"
        c = link.codecs
        self.v = link.t.sensors_t.PROTOCOL_VERSION
        self.pack_t = c.truth.packer(self.v)   # truth_t after its protocol version, one call per tick
        # the closed loop's one definition of the sensor frame and of the command (aocs_loop.frames): the
        # frame made from the plant and the command applied to it by the PlantPort, the frame packed into
        # sensors_t and the command read from actuator_cmd_t by the LcmCodec; this loop is hand-tuned around
        # them (truth, recording, events) instead of aocs_loop.core.fly
        self.port = PlantPort(plant)
        self.codec = link.codec
        self.sense_fields, self.pack_fields = self.port.fields, self.codec.pack_fields   # sensors(): no SensorFrame
        self.attitude = sc.kind == "attitude"
        # the wheel array (SPEC 5.3), when the scenario has one: tachometers in sensors_t, its state in
        # truth_t, the flight computer's wheel torques (actuator_cmd_t.u_wheels) applied to it
        self.wheels = plant.wheel_array
        self.nw = self.wheels.n if self.wheels is not None else 0
        self.wmax = link.t.sensors_t.MAX_WHEELS
        self.progress_every = max(1, sc.n_steps // 10)
        self.t_loop0 = time.perf_counter()   # the progress lines' elapsed wall time and ETA
        self._zero_wheel_truth = (0,) + (0.0,) * (3 * self.wmax) + (0,) + (0.0,) * 6
        # what an attitude estimate is judged against (truth_t, protocol version 3): the gyro's true bias, from
        # its truth fields (Plant.truth()["sensors"]["gyro.bias_rad_s"]); zero without a gyro
        self.gyro = next((s for s in plant.sensors if s.name == "gyro"), None)
        # truth_t's wheel and estimation fields when both are constant (no wheel array, no gyro): built once
        self._truth_tail = (self._zero_wheel_truth + (0.0, 0.0, 0.0)
                            if self.wheels is None and self.gyro is None else None)
        if self.attitude:
            qd0 = sc.target.qd0
            self.qd0_inv = (-qd0[0], -qd0[1], -qd0[2], qd0[3])   # truth(): the fixed target's inverse, once
            self.fixed_target = not any(sc.target.wd) and sc.plan is None

    # -------------------------------------------------------------- messages
    def truth(self, tick):
        """truth_t of tick k: the state at t_k, the disturbance at t_k and the actuator
        output applied over the previous period (Plant.truth's meaning), on plain floats."""
        plant = self.plant
        t_s = tick * self.dt
        z3 = (0.0, 0.0, 0.0)
        applied = plant.applied  # mean actuator output over the last period (Plant.applied)
        dist = plant.disturbance()
        if self.attitude:
            q, w = plant.body.q, plant.body.w
            if self.fixed_target:
                qd_inv = self.qd0_inv
            else:
                qd = plant.target(plant.t)[0]
                qd_inv = (-qd[0], -qd[1], -qd[2], qd[3])
            # qe = q (x) qd^-1 (SPEC 1), one product for both error figures
            e1, e2, e3, _ = quat_mul(q, qd_inv)
            ang = 2.0 * math.asin(min(1.0, math.sqrt(e1 * e1 + e2 * e2 + e3 * e3))) * ARCSEC_PER_RAD
            tail = self._truth_tail or (*self.truth_wheels(), *self.truth_estimation())
            data = self.pack_t(self.frame_truth, int(round(t_s * 1e6)), tick, t_s,
                               *q, *w, *z3, *z3, *applied, *z3, *dist, *z3,
                               ang, abs(e1) * ARCSEC_PER_RAD, abs(e2) * ARCSEC_PER_RAD, abs(e3) * ARCSEC_PER_RAD,
                               *tail)
        else:
            x = plant.orbit.x
            data = self.pack_t(self.frame_truth, int(round(t_s * 1e6)), tick, t_s,
                               0.0, 0.0, 0.0, 1.0, *z3, x[3], x[4], x[5], x[0], x[1], x[2],
                               *z3, *applied, *z3, *dist, 0.0, *z3, *self.truth_wheels(), *z3)
        self.frame_truth += 1
        self.link.publish_truth(data)

    def _pad(self, v):
        v = tuple(v)
        return v + (0.0,) * (self.wmax - len(v))

    def truth_wheels(self):
        """truth_t's wheel fields (SPEC 5.3): n_wheels, speeds, momenta, motor torques, limit bits,
        total momentum in B and in N (zeros without a wheel array)."""
        e = self.wheels
        if e is None:
            return self._zero_wheel_truth
        plant = self.plant
        speed, momentum, motor, _, at_torque, at_speed, H = e.truth_fields(plant.body_state(), plant.effector_state(e))
        bits = 0
        for i, (a, b) in enumerate(zip(at_torque, at_speed)):
            bits |= (1 << i if a else 0) | (1 << (8 + i) if b else 0)
        A = quat_to_dcm(plant.body.q)
        HN = tuple(A[0][r] * H[0] + A[1][r] * H[1] + A[2][r] * H[2] for r in range(3))
        return (self.nw, *self._pad(speed), *self._pad(momentum), *self._pad(motor), bits, *H, *HN)

    def truth_estimation(self):
        """truth_t's fields an attitude estimate is judged against: the gyro's true bias in B at the end of its
        last sample, rad/s (zeros without a gyro)."""
        g = self.gyro
        return (0.0, 0.0, 0.0) if g is None else g.truth()["bias_rad_s"]

    def sensors(self, tick, stale=False):
        """sensors_t of tick k (stale: with the sensor time of tick k - 1)."""
        return self.pack_fields(*self.sense_fields(tick, (tick - 1) * self.sc.dt if stale else None))

    def fire(self, tick, evs):
        """Events before this tick's sensors; returns (drop, duplicate, stale)."""
        drop = dup = stale = False
        lc = self.link.lc
        utime = int(round(tick * self.sc.dt * 1e6))
        for e in evs:
            if e.is_command:
                self.link.command(e, utime)
            elif e.kind == "malformed":
                lc.publish("AOCS_SENSORS", b"\x00\x01garbage-not-a-sensors_t")
            elif e.kind == "foreign":
                lc.publish("AOCS_SENSORS", self.codec.pack_sensors(
                    SensorFrame(tick, tick * self.sc.dt, 0, (0.0, 0.0, 0.0, 1.0), *((0.0, 0.0, 0.0),) * 3), version=99))
            elif e.kind == "drop":
                drop = True
            elif e.kind == "duplicate":
                dup = True
            elif e.kind == "stale":
                stale = True
        return drop, dup, stale

    def wheels_disagree(self, exc: WheelMismatch):
        """The flight computer allocates to another number of wheels than the plant has: no command
        of it can be applied (the scenario's [wheels] builds both, so this is a setup error)."""
        print(f"plant_node: {exc} (its configuration was not written from this scenario's [wheels])",
              file=sys.stderr, flush=True)
        return "wheels_mismatch", EXIT_NO_REPLY

    def actuators_disagree(self, exc: ActuatorMismatch):
        """The flight computer commands unloading actuators the plant does not have (or another number of
        thrusters): a setup error, as wheels_disagree."""
        print(f"plant_node: {exc} (its configuration was not written from this scenario's [thrusters] / "
              f"[magnetorquers])", file=sys.stderr, flush=True)
        return "actuators_mismatch", EXIT_NO_REPLY

    def progress(self, k, flush_log=None):
        if not self.args.quiet and (k + 1) % self.progress_every == 0:
            if flush_log is not None:
                flush_log()   # what a progress line reports is in the log
            n = self.sc.n_steps
            # elapsed wall time and the rest at this pace (a day-long run's ETA)
            wall = time.perf_counter() - self.t_loop0
            eta = wall * (n - k - 1) / (k + 1)
            print(f"plant_node: {100 * (k + 1) // n:3d}% tick {k + 1}/{n} t = {(k + 1) * self.sc.dt:.1f} s, "
                  f"wall {wall:.1f} s, ETA {eta:.1f} s", file=sys.stderr, flush=True)

    # -------------------------------------------------------------- lockstep
    def run_lockstep(self):
        lc = self.link.lc
        plant, check = self.plant, self.check
        n = self.sc.n_steps
        k0 = self.args.start_tick
        timeout = self.args.reply_timeout
        unpack, i_tick = self.codec.unpack_command, self.codec.i_tick
        command, apply = self.codec.command, self.port.apply
        box = [None]
        want = [k0]
        rt = self.rt_ns
        evs = self.evs
        perf = time.perf_counter_ns
        handle = lc.handle_timeout
        publish = lc.publish
        timeout_ns = int(timeout * 1e9)

        def on_cmd(ch, data):  # noqa: ARG001
            v = unpack(data)
            if v is None:
                self.bad_replies += 1
            elif v[i_tick] == want[0]:
                box[0] = v
            else:
                self.stale_replies += 1

        lc.subscribe("AOCS_ACTUATOR_CMD", on_cmd)
        flush_log = self.link.log.flush if self.link.log is not None else (lambda: None)
        # over LCM the log is written every LOG_FLUSH_TICKS ticks while the flight computer computes (a write
        # per tick cost ~10 us of the period: measured, docs/benchmarks.md); in process nothing runs meanwhile:
        # the recorder writes every LOG_FLUSH_EVENTS events (_Link.record); both at the end
        flush_ticks = LOG_FLUSH_TICKS if not self.link.direct else 0
        progress_every = self.progress_every
        waits = 0
        # the integration check of the last period (StepDoubling: the command to its shadow plant, the period
        # again at twice the substeps, the difference) needs the plant at t_k only: it runs while the flight
        # computer computes tick k, off the path from its reply to the next sensors_t: (its command,) or None
        checking = None
        # in process, the periods between events run compiled when the plant allows it (compiled_loop: the same
        # messages and state as this loop's statements)
        compiled, self.compiled_why_not = compiled_loop.build(self)
        event_ticks = sorted(t for t in evs if t >= k0)
        k = -1
        while k + 1 < n:
            k += 1
            if _stop:
                self._check_end(checking)
                return "signal", EXIT_SIGNAL
            tick = k0 + k
            if compiled is not None and tick not in evs:
                checking = self._check_end(checking)
                end = min(n, (k // progress_every + 1) * progress_every, k + compiled_loop.MAX_PERIODS)
                i = bisect.bisect_left(event_ticks, tick)
                if i < len(event_ticks):
                    end = min(end, event_ticks[i] - k0)
                status, done, extra = compiled.run(tick, end - k)
                if status != compiled_loop.DONE:
                    return self._compiled_stop(status, tick + done, extra)
                k = end - 1
                if end % progress_every == 0:
                    self.progress(k, flush_log)
                continue
            drop = dup = stale = False
            if tick in evs:
                drop, dup, stale = self.fire(tick, evs[tick])
            data = self.sensors(tick, stale)
            self.last_tick = tick
            if drop:
                checking = self._check_end(checking)
                self.truth(tick)
            else:
                want[0] = tick
                box[0] = None
                t0 = perf()
                publish("AOCS_SENSORS", data)
                # the last period's check, the truth of this tick and what the plant recorded written (one
                # write per LOG_FLUSH_TICKS ticks: a plant killed loses that many at most), while the flight
                # computer computes
                checking = self._check_end(checking)
                self.truth(tick)
                if flush_ticks and k % flush_ticks == 0:
                    flush_log()
                while box[0] is None:
                    left = timeout_ns - (perf() - t0)
                    if left <= 0 or _stop:
                        break
                    handle(min(100, left // 1000000 + 1))
                    waits += 1
                v = box[0]
                if v is None:
                    if _stop:
                        return "signal", EXIT_SIGNAL
                    print(f"plant_node: no actuator_cmd_t for tick {tick} within {timeout} s: the flight "
                          f"computer stopped answering (last answered tick {self.last_answered})",
                          file=sys.stderr, flush=True)
                    return "no_reply", EXIT_NO_REPLY
                rt.append(perf() - t0)
                self.last_answered = tick
                try:
                    apply(command(v))   # Plant.apply's mapping, applied (Plant.taken)
                except WheelMismatch as exc:
                    return self.wheels_disagree(exc)
                except ActuatorMismatch as exc:
                    return self.actuators_disagree(exc)
                if dup:
                    publish("AOCS_SENSORS", data)
            check.begin(plant)
            plant.advance()
            checking = (None if drop else plant.taken,)   # the command as the plant took it (None: refused)
            self.steps += 1
            if (k + 1) % progress_every == 0:
                self.progress(k, flush_log)
        self._check_end(checking)
        self.truth(k0 + n)
        self.handle_calls = waits
        return "done", EXIT_OK

    def _compiled_stop(self, status, tick, extra):
        """The end of a run the compiled loop stopped at tick (compiled_loop.CompiledLoop.run): as the Python loop
        ends it."""
        if status == compiled_loop.NODE_ERROR:
            raise DirectError(extra)
        if status == compiled_loop.MISMATCH:
            self.last_answered = tick
            try:
                self.port.apply(self.codec.command(self.codec.unpack_command(extra)))
            except WheelMismatch as exc:
                return self.wheels_disagree(exc)
            except ActuatorMismatch as exc:
                return self.actuators_disagree(exc)
            raise AssertionError(f"tick {tick}: the compiled loop refused a command the plant takes")
        print(f"plant_node: no actuator_cmd_t for tick {tick}: the in-process flight computer gave no answer "
              f"(last answered tick {self.last_answered})", file=sys.stderr, flush=True)
        return "no_reply", EXIT_NO_REPLY

    def _check_end(self, checking):
        """The integration check of the period just flown, if one is pending (checking: (the command the plant
        took, Plant.taken,), None when no command came or the plant refused it); returns None (nothing pending)."""
        if checking is not None:
            if checking[0] is not None:
                self.check.take(checking[0])
            self.check.end(self.plant)
        return None

    # -------------------------------------------------------------- real time
    def run_realtime(self):
        lc = self.link.lc
        plant, check = self.plant, self.check
        n = self.sc.n_steps
        k0 = self.args.start_tick
        dt = self.sc.dt
        unpack, i_tick = self.codec.unpack_command, self.codec.i_tick
        command, apply = self.codec.command, self.port.apply
        latest = [None]

        def on_cmd(ch, data):  # noqa: ARG001
            v = unpack(data)
            if v is None:
                self.bad_replies += 1
            else:
                latest[0] = v

        lc.subscribe("AOCS_ACTUATOR_CMD", on_cmd)
        t0 = time.monotonic()
        for k in range(n + 1):
            deadline = t0 + k * dt
            while True:  # receive until 1 ms before the deadline, then sleep to it
                left = deadline - time.monotonic()
                if left <= 0.001 or _stop:
                    break
                lc.handle_timeout(max(1, int(min(left - 0.001, 0.1) * 1000)))
            if _stop:
                return "signal", EXIT_SIGNAL
            left = deadline - time.monotonic()
            if left > 0:
                time.sleep(left)
            self.jitter_max_ns = max(self.jitter_max_ns, int((time.monotonic() - deadline) * 1e9))
            if k > 0:
                v = latest[0]
                if v is not None:
                    try:
                        apply(command(v))
                    except WheelMismatch as exc:
                        return self.wheels_disagree(exc)
                    except ActuatorMismatch as exc:
                        return self.actuators_disagree(exc)
                    if plant.taken is not None:
                        check.take(plant.taken)
                    self.last_answered = v[i_tick]
                check.begin(plant)
                plant.advance()
                check.end(plant)
                self.steps += 1
                self.progress(k - 1)
            tick = k0 + k
            self.truth(tick)
            if k == n:
                break
            drop = dup = stale = False
            if tick in self.evs:
                drop, dup, stale = self.fire(tick, self.evs[tick])
            data = self.sensors(tick, stale)
            self.last_tick = tick
            if not drop:
                lc.publish("AOCS_SENSORS", data)
                if dup:
                    lc.publish("AOCS_SENSORS", data)
        return "done", EXIT_OK


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m aocs_runner.plant_node", description=__doc__.splitlines()[0])
    add_arguments(p)
    return run(p.parse_args(argv))


if __name__ == "__main__":
    sys.exit(main())
