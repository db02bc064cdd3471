"""`aocs replay LOG`: feed the recorded inputs of a lockstep run through a fresh
flight computer and check that its commands match the recorded ones bit for bit.

    aocs replay out/irassi_large-quat_pd/run.lcmlog [--target host|pil-m4f|pil-m7]

The flight computer is started with the configuration saved next to the log
(fsw_node.cfg, named in run.json). Every AOCS_SENSORS and AOCS_COMMAND
payload of the log is published again, byte for byte and in the logged
order (malformed and foreign frames included); after each one the replay
waits (bounded) for as many actuator_cmd_t as the original run had produced
by then. Each new command is compared with the recorded one: tick, law_id,
mode, saturated, status, the bits of u_sat and u_unsat, and the
deterministic counters (invalid, stale, missing, law_error, lost, duplicate,
foreign, malformed, cmd_accepted, cmd_rejected); never the timing (step_ns,
overrun, n_overrun, utime). Exit 0 when identical, 1 at the first mismatch
(printed), 2 on a usage error. The regression harness for any firmware change.
"""
from __future__ import annotations

import json
import struct
import sys
import time
from pathlib import Path

import lcm

from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_runner import events as evmod
from aocs_runner import orchestrate
from aocs_runner.run import fc_command
from aocs_wire import lcmlog, netns, wire

EXIT_OK, EXIT_MISMATCH, EXIT_USAGE = 0, 1, 2

#: compared fields (flattened actuator_cmd_t names); arrays compared by their bits
COMPARED = ("tick", "law_id", "mode", "u_sat", "u_unsat", "saturated", "status", "n_invalid", "n_stale",
            "n_missing", "n_law_error", "n_lost", "n_duplicate", "n_foreign", "n_malformed", "n_cmd_accepted",
            "n_cmd_rejected")


def add_arguments(p) -> None:
    p.add_argument("log", help="run.lcmlog of a lockstep `aocs run` (its folder holds run.json and the config)")
    p.add_argument("--target", choices=("host", "pil-m4f", "pil-m7"), default="host",
                   help="flight computer to replay through (default host fsw_node)")
    p.add_argument("--config", help="fsw_node configuration (default: the one saved next to the log)")
    p.add_argument("--reply-timeout", type=float, default=None, help="max wait per reply, s (default 2; pil 10)")
    p.add_argument("-q", "--quiet", action="store_true")


class ReplayError(RuntimeError):
    pass


def _bits(x: float) -> str:
    return struct.pack(">d", x).hex()


def compare(codec, recorded: tuple, replayed: tuple) -> str | None:
    """First difference between two actuator_cmd_t value tuples, as text; None if identical."""
    for name, n in codec.fields:
        if name not in COMPARED:
            continue
        i = codec.index(name)
        if n is None:
            if recorded[i] != replayed[i]:
                return f"{name}: recorded {recorded[i]!r}, replayed {replayed[i]!r}"
        else:
            for j in range(n):
                a, b = recorded[i + j], replayed[i + j]
                if struct.pack(">d", a) != struct.pack(">d", b):
                    return (f"{name}[{j}]: recorded {a!r} (0x{_bits(a)}), replayed {b!r} (0x{_bits(b)}), "
                            f"difference {b - a:.3e}")
    return None


def _config_path(log_path: Path, explicit: str | None) -> tuple[Path, dict]:
    meta_path = log_path.parent / "run.json"
    meta = json.loads(meta_path.read_text()) if meta_path.is_file() else {}
    if explicit:
        return Path(explicit), meta
    cfg = log_path.parent / meta.get("fsw_config_file", "fsw_node.cfg")
    if not cfg.is_file():
        raise ReplayError(f"no fsw_node configuration next to {log_path} (expected {cfg}); give --config")
    return cfg, meta


def replay(log_path: Path, target: str = "host", config: str | None = None, reply_timeout: float | None = None,
           quiet: bool = False, out=None) -> int:
    netns.require_netns()
    out = sys.stdout if out is None else out
    log_path = Path(log_path)
    cfg_path, meta = _config_path(log_path, config)
    try:
        cfg = fsw_config.read(cfg_path)
    except FileNotFoundError:
        raise ReplayError(f"{cfg_path}: no such configuration file") from None
    except IsADirectoryError:
        raise ReplayError(f"{cfg_path}: is a folder, not a configuration file") from None
    except UnicodeDecodeError as exc:
        raise ReplayError(f"{cfg_path}: not UTF-8 text (byte {exc.start})") from None
    except (OSError, fsw_config.ConfigError) as exc:
        raise ReplayError(str(exc)) from None
    if cfg.get("mode", "lockstep") != "lockstep":
        raise ReplayError(f"{cfg_path}: mode = {cfg.get('mode')}: only lockstep runs replay deterministically")
    # a damaged or partial log is refused, never compared as far as it goes
    try:
        lcmlog.scan(log_path)
        log = lcmlog.read(log_path, keep_raw=True)
    except lcmlog.LogIntegrityError as exc:
        raise ReplayError(str(exc)) from None
    dropped = (evmod.dropped_ticks(meta.get("events"), meta["dt"], meta["n_steps"], meta.get("faults"))
               if "dt" in meta and "n_steps" in meta else ())
    problems = lcmlog.completeness_problems(log, meta.get("n_steps"), dropped_ticks=dropped)
    if problems:
        raise ReplayError(f"{log_path}: " + "; ".join(problems))
    codecs = wire.Codecs(paths.import_bindings())
    act = codecs.actuator
    inputs = []          # (channel, data, expected cumulative replies after it)
    recorded = []
    for ch, data, _ in log.events:
        if ch == wire.ACTUATOR:
            v = act.unpack(data)
            if v is not None:
                recorded.append(v)
                if inputs:
                    inputs[-1][2] = len(recorded)
        elif ch in (wire.SENSORS, wire.COMMAND):
            inputs.append([ch, data, len(recorded)])
    if not inputs:
        raise ReplayError(f"{log_path}: no AOCS_SENSORS / AOCS_COMMAND messages to replay")
    timeout = reply_timeout or (2.0 if target == "host" else 10.0)
    got: list = []
    bad = [0]

    def on_cmd(ch, data):  # noqa: ARG001
        v = act.unpack(data)
        if v is None:
            bad[0] += 1
        else:
            got.append(v)

    ready = []
    st = codecs.status

    def on_status(ch, data):  # noqa: ARG001
        v = st.unpack(data)
        if v is not None and not v[st.index("exiting")]:
            ready.append(v)

    lc = lcm.LCM(netns.LCM_URL)
    lc.subscribe(wire.ACTUATOR, on_cmd)
    sub = lc.subscribe(wire.STATUS, on_status)
    workdir = log_path.parent
    t0 = time.monotonic()
    with orchestrate.Processes() as procs:
        fc = procs.start("flight computer", fc_command(target, cfg_path), stdout=workdir / "replay-fsw.stdout",
                         stderr=workdir / "replay-fsw.stderr", env=paths.python_env())
        end = time.monotonic() + 10.0
        while not ready:
            if not fc.alive():
                raise ReplayError(f"flight computer {orchestrate.describe_exit(fc.poll())}: {fc.stderr_tail()}")
            if time.monotonic() > end:
                raise ReplayError("no heartbeat from the flight computer within 10 s")
            lc.handle_timeout(50)
        lc.unsubscribe(sub)
        for ch, data, want in inputs:
            lc.publish(ch, data)
            deadline = time.monotonic() + timeout
            while len(got) < want:
                left = deadline - time.monotonic()
                if left <= 0:
                    rec = recorded[len(got)]
                    print(f"replay: MISMATCH: no reply for recorded command #{len(got)} (tick "
                          f"{rec[act.index('tick')]}) within {timeout} s", file=out)
                    return EXIT_MISMATCH
                if not fc.alive():
                    print(f"replay: MISMATCH: flight computer {orchestrate.describe_exit(fc.poll())} before "
                          f"command #{len(got)}: {fc.stderr_tail()}", file=out)
                    return EXIT_MISMATCH
                lc.handle_timeout(max(1, int(min(left, 0.1) * 1000)))
        # late or extra replies
        end = time.monotonic() + 0.2
        while time.monotonic() < end:
            lc.handle_timeout(20)
        fc.stop()
    wall = time.monotonic() - t0
    for i, (a, b) in enumerate(zip(recorded, got)):
        diff = compare(act, a, b)
        if diff is not None:
            print(f"replay: MISMATCH at command #{i} (tick {a[act.index('tick')]}): {diff}", file=out)
            return EXIT_MISMATCH
    if len(got) != len(recorded):
        print(f"replay: MISMATCH: {len(got)} commands replayed, {len(recorded)} recorded", file=out)
        return EXIT_MISMATCH
    if bad[0]:
        print(f"replay: MISMATCH: {bad[0]} undecodable actuator_cmd_t payloads", file=out)
        return EXIT_MISMATCH
    if not quiet:
        print(f"replay: {len(recorded)} commands identical to the recording (tick, law_id, mode, u_sat and "
              f"u_unsat bits, saturated, status, counters; timing not compared); {len(inputs)} inputs replayed "
              f"through {target} in {wall:.2f} s", file=out)
    return EXIT_OK


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    try:
        return replay(Path(args.log), args.target, args.config, args.reply_timeout, args.quiet)
    except (ReplayError, paths.SetupError, FileNotFoundError, netns.NetnsError) as exc:
        print(f"aocs replay: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except orchestrate.RunAborted as exc:
        print(f"aocs replay: {exc}", file=sys.stderr)
        return EXIT_USAGE
