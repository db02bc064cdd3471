"""The PIL bridge: an LCM node that behaves like fsw_node, with the flight
executive running in the Cortex-M image under QEMU.

    python -m aocs_pil.bridge --target pil-m4f|pil-m7 CONFIG_FILE

Same channels, same configuration file and same frame checks as fsw_node
(docs/wire-contract.md): each accepted AOCS_SENSORS frame becomes one STEP
frame to the image, whose reply becomes one AOCS_ACTUATOR_CMD with the same
tick; AOCS_COMMAND becomes a SELECT frame (aocs_exec_select in the image);
AOCS_STATUS heartbeats, acknowledgements and the exiting message as fsw_node
sends them. Lockstep only (mode = realtime is a configuration error: the
emulator has no real-time clock worth scheduling on).

Differences, all in the timing fields: step_ns is the instruction count of the
whole executive step divided by the target's nominal clock (168 MHz M4F,
216 MHz M7; a lower bound of the silicon time, one instruction per cycle),
overrun / n_overrun mean "above the instruction budget of aocs/budget.h".
The final JSON line adds "target", "instructions" and "law_instructions"
(docs/pil.md).

Exit status: 0 after a normal end (signal, idle timeout, run timeout), 2 on
a configuration error (message naming file, line and key, or the
executive's status), 1 when the target failed (QEMU exited or stalled, a
frame failed its checks) or LCM failed; the message says which.
"""
from __future__ import annotations

import argparse
import json
import math
import signal
import sys
import time

import lcm

from aocs_core import paths, registry
from aocs_loop.frames import SensorFrame
from aocs_wire import netns, wire

from . import config as nodecfg
from . import frame
from .adapter import step_payload, step_status
from .qemu import TARGETS, ImageError, Qemu, QemuError, describe_exit
from .sequence import FrameSequence

PROG = "aocs_pil.bridge"
CH_SENSORS, CH_ACTUATOR, CH_COMMAND, CH_STATUS = wire.SENSORS, wire.ACTUATOR, wire.COMMAND, wire.STATUS
EXIT_OK, EXIT_RUNTIME, EXIT_CONFIG = 0, 1, 2
LCM_WAIT_MAX_MS = 100
STATS_WINDOW = 65536


def log(msg: str) -> None:
    print(f"{PROG}: {msg}", file=sys.stderr, flush=True)


class Fatal(Exception):
    """Ends the run with a message and exit status 1."""


# --------------------------------------------------------------------------- helpers
class Stats:
    """node_stats.c: nearest-rank median / p99 over the last STATS_WINDOW values, max over all."""

    def __init__(self):
        self.ring: list[int] = []
        self.count = 0
        self.max = 0

    def add(self, v: int) -> None:
        if len(self.ring) < STATS_WINDOW:
            self.ring.append(v)
        else:
            self.ring[self.count % STATS_WINDOW] = v
        self.count += 1
        self.max = max(self.max, v)

    def summary(self) -> dict:
        n = len(self.ring)
        if n == 0:
            return {"n": 0, "median": 0, "p99": 0, "max": self.max}
        s = sorted(self.ring)

        def rank(p):
            return s[max(1, (n * p + 99) // 100) - 1]
        return {"n": n, "median": rank(50), "p99": rank(99), "max": self.max}


def load_lcm_types():
    """The generated bindings (aocs_core.paths), a setup error as this node's Fatal."""
    try:
        return paths.import_bindings()
    except paths.SetupError as exc:
        raise Fatal(str(exc)) from exc


# --------------------------------------------------------------------------- the node
class Bridge:
    def __init__(self, args, cfg: nodecfg.NodeConfig):
        self.args = args
        self.cfg = cfg
        self.target = TARGETS[args.target]
        self.q = Qemu(self.target, args.image, boot_timeout=args.boot_timeout, reply_timeout=args.reply_timeout)
        self.lc = None
        self.t = None
        self.stop = False
        self.fatal: str | None = None
        # executive state as last reported by the image
        self.exec_law = registry.law_ids()[cfg.law]
        self.exec_mode = 0
        self.nominal_law = self.exec_law
        self.counters = {n: 0 for n in frame.COUNTER_NAMES}
        self.pil_overruns = 0
        self.budget = 0
        # the wheel array of the configuration (wheels.count; 0 = none), as fsw_node's cfg.exec.wheels.n
        self.n_wheels = cfg.n_wheels
        # wire bookkeeping (fsw_node's node_t)
        self.frame_cmd = 0
        self.frame_status = 0
        self.sensor_frames = 0
        self.seq = FrameSequence()
        self.n_foreign = 0
        self.n_malformed = 0
        self.n_cmd_accepted = 0
        self.n_cmd_rejected = 0
        self.last_request = -1
        self.last_request_status = 0
        self.t_start = 0.0
        self.t_last_sensor = 0.0
        # measurements
        self.step_ns = Stats()
        self.instr = Stats()
        self.law_instr = Stats()
        self.instr_max_budget = 0
        self.inexact = 0
        self.steps_sent = 0
        self.bye = None

    # ---------------------------------------------------------------- target
    def start_target(self) -> None:
        hello = self.q.start()
        payload = self.cfg.pil_payload(self.target.clock_hz)
        _, p = self.q.request(frame.T_CONFIG, payload, frame.T_CONFIG_ACK)
        ack = frame.Ack.decode(p)
        if ack.pil_err != 0:
            key = nodecfg.key_of_pil_id(ack.field)
            detail = f": {registry.status_name(ack.status)}" if ack.status else ""
            raise nodecfg.ConfigError(f"{self.cfg.path}:{self.cfg.lines.get(key, 0)}: key '{key}': the image "
                                      f"refused the value ({frame.err_name(ack.pil_err)}{detail})")
        if ack.status != 0:
            st = registry.status_name(ack.status)
            raise nodecfg.ConfigError(f"{self.cfg.path}: the executive rejected the configuration of law "
                                      f"'{self.cfg.law}': {st} (check {nodecfg.status_hint(st, self.cfg.law)})")
        self.exec_law, self.exec_mode, self.budget = ack.exec_law, ack.exec_mode, ack.budget
        self.nominal_law = self.exec_law
        log(f"target {self.target.name}: {self.target.preset} ({'float' if hello.real_bytes == 4 else 'double'}) "
            f"on QEMU {self.target.machine}, pid {self.q.pid}, image {self.q.image}, "
            f"instruction counter calibrated ({hello.calib_measured}/{hello.calib_expected})")

    # ---------------------------------------------------------------- LCM
    def open_lcm(self) -> None:
        self.t = load_lcm_types()
        if not self.cfg.lcm_url:
            netns.require_netns()   # udpm multicast never leaves the machine
        try:
            self.lc = lcm.LCM(self.cfg.lcm_url) if self.cfg.lcm_url else lcm.LCM()
        except Exception as exc:  # lcm raises RuntimeError / IOError
            raise Fatal(f"lcm_create({self.cfg.lcm_url or 'default'}) failed: {exc}") from exc
        self.lc.subscribe(CH_SENSORS, self.on_sensors)
        self.lc.subscribe(CH_COMMAND, self.on_command)
        self.sensors_size = len(self.t.sensors_t().encode())
        self.command_size = len(self.t.command_t().encode())

    def publish_status(self, exiting: bool) -> None:
        t = self.t
        m = t.status_t()
        s = self.step_ns.summary()
        m.protocol_version = t.status_t.PROTOCOL_VERSION
        m.frame = self.frame_status
        self.frame_status += 1
        m.utime = int(time.monotonic() * 1e6)
        m.run_mode = t.status_t.RUN_LOCKSTEP
        m.law_id = self.exec_law
        m.mode = self.exec_mode
        m.steps = self.step_ns.count
        m.n_overrun = self.pil_overruns
        m.step_ns_median, m.step_ns_p99, m.step_ns_max = s["median"], s["p99"], s["max"]
        m.jitter_ns_max = 0
        m.last_request = self.last_request
        m.last_request_status = self.last_request_status
        m.n_cmd_accepted = self.n_cmd_accepted
        m.n_cmd_rejected = self.n_cmd_rejected
        m.n_foreign = self.n_foreign
        m.n_malformed = self.n_malformed
        m.exiting = exiting
        self.lc.publish(CH_STATUS, m.encode())

    # ---------------------------------------------------------------- AOCS_SENSORS
    def on_sensors(self, channel, data) -> None:
        self.sensor_frames += 1
        self.t_last_sensor = time.monotonic()
        if self.fatal is not None:
            return
        st = self.t.sensors_t
        try:
            if len(data) != self.sensors_size:
                raise ValueError("size")
            msg = st.decode(data)
        except Exception:  # wrong fingerprint, truncated, trailing bytes
            self.n_malformed += 1
            return
        if msg.protocol_version != st.PROTOCOL_VERSION:
            self.n_foreign += 1
            return
        # frame sequence: fsw_node's rule (node_wire.c aocs_node_seq_check, aocs_pil.sequence)
        if not FrameSequence.accepted(self.seq.check(msg.frame)):
            return
        self.step(msg)

    def step(self, msg) -> None:
        # the message as the loop's SensorFrame (the wheels it says it measures), then the one STEP payload
        # of a frame (aocs_pil.adapter.step_payload, which the direct path uses too)
        n = max(0, min(msg.n_wheels, frame.WHEELS_MAX, len(msg.wheel_speed)))
        payload = step_payload(SensorFrame(msg.tick, msg.t_s, msg.valid, msg.q, msg.w, msg.pos, msg.vel,
                                           tuple(msg.wheel_speed[:n]), tuple(msg.st_q), msg.st_t_meas_s,
                                           tuple(msg.gyro_w), tuple(msg.mag_b_t)))
        try:
            seq = self.q.next_seq()
            raw = frame.encode(frame.T_STEP, seq, payload)
            if self.args.fault_corrupt_step is not None and self.steps_sent == self.args.fault_corrupt_step:
                raw = bytearray(raw)
                raw[frame.HEADER_BYTES + 20] ^= 0x10   # one bit of the payload, after the CRC was computed
                raw = bytes(raw)
                log(f"fault injection: STEP frame {self.steps_sent} (tick {msg.tick}) corrupted on purpose")
            self.steps_sent += 1
            self.q.send_raw(raw)
            _, p = self.q.read_reply(seq, frame.T_STEP_REPLY)
            r = frame.StepReply.decode(p)
        except ImageError as exc:
            self.fail(f"frame error at tick {msg.tick}: {exc}")
            return
        except frame.FrameError as exc:
            self.fail(f"frame error at tick {msg.tick}: reply from the image failed its checks: {exc}")
            return
        except QemuError as exc:
            self.fail(f"target failure at tick {msg.tick}: {exc}")
            return
        if r.tick != (msg.tick & 0xFFFFFFFF):
            self.fail(f"frame error: reply for tick {r.tick}, request was tick {msg.tick}")
            return
        self.exec_law, self.exec_mode = r.exec_law, r.exec_mode
        self.counters = r.counters
        self.pil_overruns = r.pil_overruns
        step_ns = int(round(r.instructions * 1e9 / self.target.clock_hz))
        if r.step_status == 0:
            self.step_ns.add(step_ns)
            self.instr.add(r.instructions)
            self.law_instr.add(r.law_instructions)
            if r.instructions >= self.instr.max:
                self.instr_max_budget = r.budget
            if not r.exact:
                self.inexact += 1
        self.publish_actuator(r, msg, step_ns)

    def publish_actuator(self, r: frame.StepReply, msg, step_ns: int) -> None:
        t = self.t
        m = t.actuator_cmd_t()
        m.protocol_version = t.actuator_cmd_t.PROTOCOL_VERSION
        m.frame = self.frame_cmd
        self.frame_cmd += 1
        m.utime = msg.utime
        m.tick = msg.tick
        m.law_id = r.law
        m.mode = r.mode
        m.u_sat = list(r.u_cmd)
        m.u_unsat = list(r.u_unsat)
        m.saturated = bool(r.saturated)
        m.step_ns = step_ns
        m.overrun = bool(r.overrun)
        # fsw_node step_status(): the step's return code, else the input status, else the law status, else the wheel allocation's
        m.status = step_status(r)
        c = r.counters
        m.n_invalid, m.n_stale, m.n_missing, m.n_law_error = c["invalid"], c["stale"], c["missing"], c["law_error"]
        m.n_overrun = r.pil_overruns
        m.n_lost = self.seq.lost
        m.n_duplicate = self.seq.duplicate
        m.n_foreign = self.n_foreign
        m.n_malformed = self.n_malformed
        m.n_cmd_accepted = self.n_cmd_accepted
        m.n_cmd_rejected = self.n_cmd_rejected
        # the wheel array's allocation of this step (all zero without one), as fsw_node publishes it
        m.n_wheels = self.n_wheels
        m.u_wheels = list(r.u_wheels[:len(m.u_wheels)])
        m.wheel_scale = r.wheel_scale
        m.wheel_limited = r.wheel_limited
        m.wheel_status = r.wheel_status
        m.h_total = list(r.h_total)
        m.wheel_speed_margin = r.speed_margin
        # the attitude-determination stage's estimate of this step, as fsw_node publishes it
        # (node_wire.c aocs_node_estimate_to_cmd)
        m.estimator = min(r.estimator, 127)
        m.est_status = r.est_status
        m.q_est = list(r.q_est)
        m.w_est = list(r.w_est)
        m.bias_est = list(r.bias_est)
        m.est_p = list(r.est_p)
        m.st_status = r.st_status
        m.n_st_used, m.n_st_gated, m.n_st_hostile = r.n_st_used, r.n_st_gated, r.n_st_hostile
        m.n_est_restarts = r.n_est_restarts
        # the momentum-management stage of this step, as fsw_node publishes it (node_wire.c
        # aocs_node_momentum_to_cmd)
        m.mom_policy = min(r.mom_policy, 127)
        m.mom_status = r.mom_status
        m.n_thrusters = min(r.n_thrusters, 127)
        m.thruster_on_s = list(r.thruster_on_s)
        m.dipole_am2 = list(r.dipole_am2)
        m.u_unload = list(r.u_unload)
        m.h_wheels = list(r.h_wheels)
        m.dh = list(r.dh)
        m.unloading = bool(r.unloading)
        m.n_unload_events = r.n_unload_events
        m.thruster_latch_closed = min(r.thruster_latch_closed, 3)
        self.lc.publish(CH_ACTUATOR, m.encode())

    # ---------------------------------------------------------------- AOCS_COMMAND
    def apply_command(self, c) -> int:
        """fsw_node apply_command(), the executive call made in the image. Returns an aocs_status_t code."""
        ct = self.t.command_t
        unknown_law = registry.status_code("AOCS_ERR_UNKNOWN_LAW")
        mode_invalid = registry.status_code("AOCS_ERR_MODE_INVALID")
        law = self.exec_law
        if c.law_id != ct.LAW_KEEP:
            if c.law_id < 0 or c.law_id >= len(registry.law_names()):
                return unknown_law
            law = c.law_id
        if c.mode == ct.MODE_STANDBY:
            law = 0
        elif c.mode == ct.MODE_NOMINAL:
            if law == 0:
                law = self.nominal_law
            if law == 0:
                return mode_invalid
        elif c.mode != ct.MODE_KEEP:
            return mode_invalid
        if c.law_id == ct.LAW_KEEP and c.mode == ct.MODE_KEEP and not c.set_target:
            return 0
        payload = frame.encode_select(law, list(c.qd) if c.set_target else None,
                                      list(c.wd) if c.set_target else (0.0, 0.0, 0.0))
        _, p = self.q.request(frame.T_SELECT, payload, frame.T_SELECT_ACK)
        ack = frame.Ack.decode(p)
        self.exec_law, self.exec_mode = ack.exec_law, ack.exec_mode
        self.counters = dict(self.counters, select_accepted=ack.select_accepted,
                             select_rejected=ack.select_rejected)
        return ack.status

    def on_command(self, channel, data) -> None:
        if self.fatal is not None:
            return
        ct = self.t.command_t
        try:
            if len(data) != self.command_size:
                raise ValueError("size")
            msg = ct.decode(data)
        except Exception:
            self.n_malformed += 1
            return
        if msg.protocol_version != ct.PROTOCOL_VERSION:
            self.n_foreign += 1
            return
        try:
            st = self.apply_command(msg)
        except (QemuError, frame.FrameError) as exc:
            self.fail(f"target failure on command {msg.request}: {exc}")
            return
        self.last_request = msg.request
        self.last_request_status = st
        if st == 0:
            self.n_cmd_accepted += 1
            if self.exec_law != 0:
                self.nominal_law = self.exec_law
        else:
            self.n_cmd_rejected += 1
            log(f"command {msg.request} rejected: {registry.status_name(st)}")
        self.publish_status(False)

    # ---------------------------------------------------------------- loop
    def fail(self, message: str) -> None:
        if self.fatal is None:
            self.fatal = message
            log(message)

    def run(self) -> str:
        cfg = self.cfg
        idle, run_limit, status_period = cfg.idle_timeout_s, cfg.run_timeout_s, cfg.status_period_s
        self.t_start = time.monotonic()
        self.t_last_sensor = self.t_start
        next_status = self.t_start + status_period
        errors = 0
        while not self.stop:
            if self.fatal is not None:
                return "pil_error"
            code = self.q.returncode()
            if code is not None:
                self.fail(f"target failure: QEMU exited while waiting for sensors: {describe_exit(code)}"
                          + (f"; stderr: {self.q.stderr_tail()}" if self.q.stderr_tail() else ""))
                return "pil_error"
            now = time.monotonic()
            if run_limit > 0 and now >= self.t_start + run_limit:
                return "run_timeout"
            idle_end = self.t_last_sensor + idle
            if now >= idle_end:
                return "idle"
            if now >= next_status:
                self.publish_status(False)
                next_status = now + status_period
            wait_ms = min(LCM_WAIT_MAX_MS, max(1, int(math.ceil((idle_end - now) * 1000))))
            err = "negative return"
            try:
                rc = self.lc.handle_timeout(wait_ms)
            except Exception as exc:  # noqa: BLE001 - LCM reports failures as exceptions
                rc = -1
                err = exc
            if rc < 0 and not self.stop:
                errors += 1
                if errors > 100:
                    self.fail(f"lcm_handle_timeout keeps failing: {err}")
                    return "lcm_error"
            else:
                errors = 0
        return "signal"

    # ---------------------------------------------------------------- report
    def report(self, reason: str) -> None:
        s = self.step_ns.summary()
        ins = self.instr.summary()
        law_ins = self.law_instr.summary()
        c = self.counters
        budget = self.instr_max_budget or self.budget
        log(f"lockstep end ({reason}): target={self.target.name} steps={self.step_ns.count} "
            f"overruns={self.pil_overruns} instructions median={ins['median']} max={ins['max']} budget={budget} "
            f"step_ns median={s['median']} p99={s['p99']} max={s['max']} lost={self.seq.lost} dup={self.seq.duplicate} "
            f"foreign={self.n_foreign} malformed={self.n_malformed}")
        reg = registry.load()
        law = reg.law_by_id(self.exec_law)
        law_name = law.name if law is not None else "unknown"
        mode_name = reg.mode_names.get(self.exec_mode, "unknown")
        out = {
            "reason": reason, "run_mode": "lockstep", "law": law_name, "mode": mode_name,
            "steps": self.step_ns.count, "overruns": self.pil_overruns, "slips": 0,
            "step_ns": s, "jitter_ns": {"max_abs": 0, "rms": 0.0},
            "sensor_frames": self.sensor_frames, "lost": self.seq.lost, "duplicate": self.seq.duplicate,
            "foreign": self.n_foreign, "malformed": self.n_malformed,
            "invalid": c["invalid"], "stale": c["stale"], "missing": c["missing"], "law_error": c["law_error"],
            "mode_transitions": c["mode_transitions"], "saturated": c["saturated"],
            "cmd_accepted": self.n_cmd_accepted, "cmd_rejected": self.n_cmd_rejected,
            # fsw_node's key; the image does not report its slew plan, so its times are unknown here
            "guidance": ({"mode": "slew", "slew_start_s": None, "profile_end_s": None}
                         if self.cfg.guidance_mode == "slew" else {"mode": "step"}),
            "target": self.target.name,
            "precision": "float" if self.target.real_bytes == 4 else "double",
            "clock_hz": self.target.clock_hz,
            "instructions": dict(ins, budget=budget, overruns=self.pil_overruns, inexact=self.inexact,
                                 unit="instructions per aocs_exec_step (whole step, exact under QEMU -icount)"),
            "law_instructions": law_ins,
            "image": {"path": str(self.q.image),
                      "stack_bytes": self.bye.stack_bytes if self.bye else None,
                      "frame_errors": self.bye.frame_errors if self.bye else None},
        }
        if self.fatal is not None:
            out["error"] = self.fatal
        print(json.dumps({"fsw_node": out}), flush=True)


def parse_args(argv=None):
    ap = argparse.ArgumentParser(prog=f"python -m {PROG}", description=__doc__.split("\n\n")[0])
    ap.add_argument("--target", required=True, choices=sorted(TARGETS), help="emulated flight computer")
    ap.add_argument("config", metavar="CONFIG_FILE", help="fsw_node configuration file (docs/wire-contract.md)")
    ap.add_argument("--image", help="PIL image ELF (default $AOCS_PIL_BUILD_ROOT/<preset>/aocs_pil.elf, "
                                    "AOCS_PIL_BUILD_ROOT defaulting to <repo>/build)")
    ap.add_argument("--reply-timeout", type=float, default=2.0,
                    help="longest wait for the image's reply to one frame, s (default 2): a stalled QEMU ends "
                         "the run")
    ap.add_argument("--boot-timeout", type=float, default=10.0, help="longest wait for the image's HELLO, s")
    ap.add_argument("--fault-corrupt-step", type=int, default=None, metavar="N",
                    help="test hook: flip one bit of the N-th STEP frame (0-based) after its CRC")
    return ap.parse_args(argv)


def main(argv=None) -> int:
    args = parse_args(argv)
    try:
        cfg = nodecfg.load(args.config)
        if cfg.run_mode != "lockstep":
            raise nodecfg.ConfigError(f"{args.config}:{cfg.lines.get('mode', 0)}: key 'mode': realtime is not "
                                      "supported by the PIL bridge (lockstep only: the emulator has no real-time "
                                      "clock to schedule on)")
    except nodecfg.ConfigError as exc:
        log(f"config error: {exc}")
        return EXIT_CONFIG

    bridge = Bridge(args, cfg)
    signal.signal(signal.SIGINT, lambda *_: setattr(bridge, "stop", True))
    signal.signal(signal.SIGTERM, lambda *_: setattr(bridge, "stop", True))
    status = EXIT_OK
    reason = "signal"
    try:
        bridge.start_target()
        bridge.open_lcm()
        log(f"lockstep, law {cfg.law}, period {cfg.period_s:.6f} s, target {args.target}, ready")
        reason = bridge.run()
    except nodecfg.ConfigError as exc:
        log(f"config error: {exc}")
        bridge.q.kill()
        return EXIT_CONFIG
    except (QemuError, frame.FrameError) as exc:
        bridge.fail(f"target failure: {exc}")
        reason = "pil_error"
    except Fatal as exc:
        bridge.fail(str(exc))
        reason = "pil_error"
    if bridge.fatal is not None:
        status = EXIT_RUNTIME
    if bridge.lc is not None:
        try:
            bridge.publish_status(True)
        except Exception:  # noqa: BLE001 - the last status is best effort
            pass
    if bridge.q.proc is not None:
        if bridge.fatal is None:
            bridge.bye = bridge.q.stop()
        else:
            bridge.q.kill()
    bridge.report(reason)
    return status


if __name__ == "__main__":
    sys.exit(main())
