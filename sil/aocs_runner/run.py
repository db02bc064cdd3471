"""One run in the loop (`aocs run`, `aocs compare`, the main job): plant and
flight software as separate processes talking LCM inside a private network
namespace.

Three children: lcm-logger (records every channel to OUT/run.lcmlog),
the flight computer (fsw_node, or the PIL bridge with --target pil-*) and
plant_node. The runner supervises them with bounded waits, then computes
the metrics from the log, writes OUT/metrics.json (and --json), the plots
and prints the metrics table. How a run works: docs/sil.md.
"""
from __future__ import annotations

import importlib.util
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from aocs_analysis import plots as plotmod
from aocs_analysis import run_metrics as results
from aocs_analysis import verdict
from aocs_core import paths
from aocs_plant.scenario import load
from aocs_wire import fsw_config, lcmlog, netns
from aocs_wire.recorder import Recorder

from . import events as evmod
from . import orchestrate, plant_fork, scenario_gains, scenario_opts

#: plant_node exit codes (plant_node.py)
PLANT_EXITS = {2: "bad arguments or scenario", 3: "no heartbeat from the flight computer",
               4: "the flight computer stopped answering", 5: "interrupted by a signal"}
TARGETS = ("host", "pil-m4f", "pil-m7")


class RunFailed(RuntimeError):
    """A process died or stopped answering; the message names it, its exit and the last tick."""


@dataclass
class RunOptions:
    scenario: str
    law: str | None = None
    duration: float | None = None
    realtime: bool = False
    out: str | None = None
    json_path: str | None = None
    limit: float | None = None
    target: str = "host"
    seed: int | None = None
    guidance: str | None = None     # step | slew: guidance.mode override (aocs run --guidance)
    sets: list = field(default_factory=list)
    events: list = field(default_factory=list)
    reply_timeout: float | None = None
    label: str | None = None
    plots: bool = True
    quiet: bool = False
    recorder: str = "auto"        # auto | builtin | plant | lcm-logger (recorder_of)
    plant_lcm_lib: bool = False
    allow: tuple = ()             # verdict checks allowed to fail (aocs_analysis.verdict.CHECKS)
    # starts plant_node from its arguments instead of a new interpreter: (args, stdout_path, env) -> a
    # Popen-like child (aocs campaign forks it from a worker that has the plant's modules imported)
    plant_launcher: object = None


@dataclass
class RunResult:
    metrics: dict
    out_dir: Path
    plots: list
    table: str
    series: dict | None = None    # the metrics' time series (run_metrics.compute), for a campaign's overlay


def _say(opts: RunOptions, msg: str) -> None:
    if not opts.quiet:
        print(f"aocs run: {msg}", file=sys.stderr, flush=True)


def fc_command(target: str, cfg_path: Path) -> list[str]:
    """The flight computer process: fsw_node, or the PIL bridge (same behaviour on LCM)."""
    if target == "host":
        return [str(paths.fsw_node_exe()), str(cfg_path)]
    if target not in TARGETS:
        raise paths.SetupError(f"unknown target {target!r} (one of {', '.join(TARGETS)})")
    try:
        found = importlib.util.find_spec("aocs_pil.bridge") is not None
    except ModuleNotFoundError:
        found = False
    if not found:
        raise paths.SetupError(f"--target {target} needs the processor-in-the-loop bridge (Python module "
                               "aocs_pil.bridge), which is not installed in this environment")
    return [sys.executable, "-m", "aocs_pil.bridge", "--target", target, str(cfg_path)]


#: CMake preset that builds each PIL target's image (docs/pil.md)
PIL_PRESETS = {"pil-m4f": "cortex-m4f", "pil-m7": "cortex-m7"}


def pil_build_root(target: str) -> Path:
    """The build root holding this target's PIL image, exported to the bridge as AOCS_PIL_BUILD_ROOT.

    The bridge runs <root>/<preset>/aocs_pil.elf (docs/pil.md). Searched, in order:
    $AOCS_PIL_BUILD_ROOT when set (then only there), else the parent of the host build
    directory (AOCS_BUILD_DIR=<root>/host, the presets' layout), else <repo>/build. A
    missing image is a setup error before anything starts."""
    preset = PIL_PRESETS[target]
    roots = paths.pil_build_roots()
    for root in roots:
        if (root / preset / "aocs_pil.elf").is_file():
            return root.resolve()
    raise paths.SetupError(f"--target {target}: PIL image not found as {preset}/aocs_pil.elf under "
                           f"{', '.join(str(r) for r in roots)}; build it with `cmake --preset {preset} && "
                           f"cmake --build --preset {preset}` (or set AOCS_PIL_BUILD_ROOT)")


def _last_json(path: Path, key: str) -> dict | None:
    try:
        lines = path.read_text(errors="replace").splitlines()
    except FileNotFoundError:
        return None
    for line in reversed(lines):
        line = line.strip()
        if line.startswith("{"):
            try:
                return json.loads(line).get(key)
            except json.JSONDecodeError:
                continue
    return None


#: longest wait for one command in lockstep, s (a PIL target under a slow emulator needs ~10 s)
REPLY_TIMEOUT_MAX_S = 3600.0


RECORDERS = ("auto", "builtin", "plant", "lcm-logger")


def recorder_of(opts: RunOptions) -> str:
    """What records the run: `auto` is the plant itself in lockstep (plant_node --log, truth in the log
    only: the fastest, docs/sil.md) and the runner's recorder thread in real time or with --plant-lcm-lib
    (where the plant does not read the bus's socket itself)."""
    if opts.recorder != "auto":
        return opts.recorder
    return "builtin" if (opts.realtime or opts.plant_lcm_lib) else "plant"


def check_options(opts: RunOptions) -> None:
    """Refuses, before anything starts, what the run could not honour (ValueError naming the option)."""
    if opts.law is not None and not opts.law.strip():
        raise ValueError("--law: empty law name (aocs list shows the laws)")
    if opts.law is not None and not opts.law.isprintable():
        raise ValueError(f"--law {opts.law!r}: not a law name (aocs list shows the laws)")
    if opts.duration is not None and not (math.isfinite(opts.duration) and opts.duration > 0.0):
        raise ValueError(f"--duration {opts.duration:g}: must be a finite number of seconds above 0")
    rt = opts.reply_timeout
    if rt is not None and not (math.isfinite(rt) and 0.0 < rt <= REPLY_TIMEOUT_MAX_S):
        raise ValueError(f"--reply-timeout {rt:g}: must be a finite number of seconds in "
                         f"(0, {REPLY_TIMEOUT_MAX_S:g}]")
    if opts.recorder not in RECORDERS:
        raise ValueError(f"--recorder {opts.recorder!r}: one of {', '.join(RECORDERS)}")
    if opts.recorder == "plant" and (opts.realtime or opts.plant_lcm_lib):
        raise ValueError("--recorder plant: the plant records the socket it reads itself, in lockstep only "
                         "(not with --realtime or --plant-lcm-lib)")
    if opts.out is not None and Path(opts.out).exists() and not Path(opts.out).is_dir():
        raise ValueError(f"--out {opts.out}: exists and is not a folder")
    if opts.json_path is not None:
        jp = Path(opts.json_path)
        if jp.is_dir():
            raise ValueError(f"--json {jp}: is a folder, not a file")
        parent = jp.parent
        if not parent.is_dir():
            raise ValueError(f"--json {jp}: folder {parent} does not exist")
        if not os.access(parent, os.W_OK) or (jp.exists() and not os.access(jp, os.W_OK)):
            raise ValueError(f"--json {jp}: not writable")


def prepare(opts: RunOptions):
    """Scenario (with overrides), law and the run folder; raises on bad input."""
    check_options(opts)
    ov = scenario_opts.overrides(opts.sets, opts.duration, opts.seed, opts.limit, opts.guidance)
    if opts.duration is not None and "metrics.window_s" not in ov:
        # a shortened run keeps the scenario's metric window where it fits, else the whole run
        base = load(opts.scenario, {k: v for k, v in ov.items() if k != "duration_s"})
        if base.metrics.window_s > opts.duration:
            ov["metrics.window_s"] = float(opts.duration)
    sc = load(opts.scenario, ov)
    if not sc.control.enabled:
        if opts.law not in (None, "none"):
            raise ValueError(f"--law {opts.law}: control is disabled (control.enabled = false)")
        law = "none"
    else:
        law = opts.law or sc.control.law
        if law not in sc.control.laws:
            raise ValueError(f"--law {law}: scenario {sc.id} has no gains for it "
                             f"(applicable: {', '.join(sc.control.laws)})")
    if sc.n_steps < 1:
        raise ValueError(f"scenario {sc.id}: a run of {sc.duration_s:g} s is shorter than one control "
                         f"period ({sc.dt:g} s)")
    out = Path(opts.out) if opts.out else Path("out") / f"{sc.id}-{law}"
    if out.exists() and not out.is_dir():
        raise ValueError(f"output folder {out}: exists and is not a folder")
    return sc, ov, law, out


def execute(opts: RunOptions) -> RunResult:
    """One run; raises RunFailed (process failure) or ValueError / SetupError (bad input)."""
    netns.require_netns()
    t_wall0 = time.monotonic()
    sc, ov, law, out = prepare(opts)
    rec_kind = recorder_of(opts)
    evmod.schedule(evmod.parse_all(opts.events), sc.dt, sc.n_steps)  # validate before starting anything
    paths.import_bindings()
    out.mkdir(parents=True, exist_ok=True)
    mode = "realtime" if opts.realtime else "lockstep"
    reply_timeout = opts.reply_timeout or (2.0 if opts.target == "host" else 10.0)
    # the gain each table law flies: its compiled table, or K designed for this scenario (item 6)
    gains = scenario_gains.resolve(sc)
    for choice in gains.values():
        for w in choice.warnings:
            print(f"aocs run: warning: {w}", file=sys.stderr, flush=True)
    cfg = fsw_config.node_config(sc, law, mode=mode, limit=opts.limit,
                                 run_timeout_s=(sc.duration_s + 30.0) if opts.realtime else 0.0,
                                 gains={n: c.k for n, c in gains.items() if c.k is not None})
    cfg_path = fsw_config.write(out / "fsw_node.cfg", cfg, header=f"scenario {sc.id}, law {law}, {mode}")
    fc_cmd = fc_command(opts.target, cfg_path)
    pil_root = pil_build_root(opts.target) if opts.target in PIL_PRESETS else None
    log_path = out / "run.lcmlog"
    meta = {"scenario": sc.id, "scenario_path": str(Path(sc.path).resolve()), "overrides": ov, "law": law,
            "mode": mode, "recorder": rec_kind, "plant_lcm_lib": opts.plant_lcm_lib, "target": opts.target, "events": list(opts.events), "label": opts.label,
            "fsw_config": cfg, "fsw_config_file": cfg_path.name, "fc_command": fc_cmd,
            "gains": {n: c.to_json() for n, c in gains.items()},
            "pil_image": str(pil_root / PIL_PRESETS[opts.target] / "aocs_pil.elf") if pil_root else None,
            "log": log_path.name,
            "n_steps": sc.n_steps, "dt": sc.dt, "created": time.strftime("%Y-%m-%dT%H:%M:%S")}
    (out / "run.json").write_text(json.dumps(meta, indent=1) + "\n")
    (out / "metrics.json").unlink(missing_ok=True)  # never leave a previous run's metrics behind

    # plant_node's arguments: the same for a fork, the campaign's plant server and a new interpreter
    plant_args = [sc.path, *scenario_opts.to_args(ov),
                  "--mode", mode, "--reply-timeout", repr(reply_timeout)]
    for e in opts.events:
        plant_args += ["--event", e]
    if opts.quiet:
        plant_args.append("-q")
    if opts.plant_lcm_lib:
        plant_args.append("--lcm-lib")
    plant_records = rec_kind == "plant"
    done = out / "plant_node.done"
    if plant_records:
        # the plant records the bus itself, its truth in the log only (plant_node.py, --log)
        done.unlink(missing_ok=True)
        plant_args += ["--log", str(log_path), "--truth", "log", "--done-file", str(done)]
    env = paths.python_env()
    if pil_root is not None:
        env["AOCS_PIL_BUILD_ROOT"] = str(pil_root)
    _say(opts, f"{sc.id} with {law}, {mode}, {sc.n_steps} steps of {sc.dt:g} s, flight computer "
               f"{opts.target}; output in {out}/")
    failure = None
    recorder = None
    with orchestrate.Processes() as procs:
        # the plant first: once it listens for the flight computer's heartbeat, the recorder and then the
        # flight computer start (so in real time no period of the node passes before the plant runs; the
        # plant publishes nothing before that heartbeat). Forked while this process has no other thread
        # (plant_fork.py), else a new interpreter or the campaign's plant server
        ready = out / "plant_node.ready"
        ready.unlink(missing_ok=True)
        plant_args += ["--ready-file", str(ready)]
        if opts.plant_launcher is not None:
            plant = procs.adopt("plant_node", opts.plant_launcher(plant_args, out / "plant_node.stdout", env))
        elif plant_fork.can_fork():
            plant = procs.adopt("plant_node", plant_fork.fork(plant_args, out / "plant_node.stdout"))
        else:
            plant = procs.start("plant_node", [sys.executable, "-m", "aocs_runner.plant_node", *plant_args],
                                stdout=out / "plant_node.stdout", stderr=None, env=env)
        if rec_kind == "lcm-logger":
            link = orchestrate.MarkerLink()
            logger = orchestrate.start_logger(procs, paths.lcm_logger_exe(), log_path, link,
                                              out / "lcm-logger.stderr", scenario=sc.id, law=law, mode=mode)
        elif plant_records:
            link = orchestrate.MarkerLink()
        else:
            recorder = Recorder(log_path).start(scenario=sc.id, law=law, mode=mode)
        try:
            fc_name = "fsw_node" if opts.target == "host" else f"pil bridge ({opts.target})"
            end = time.monotonic() + 30.0
            while not ready.is_file():
                if not plant.alive():
                    raise RunFailed(f"plant_node {orchestrate.describe_exit(plant.poll())} before it was ready")
                if time.monotonic() > end:
                    raise RunFailed("plant_node was not ready within 30 s")
                time.sleep(0.002)
            ready.unlink()
            if plant_records:
                link.publish("start", scenario=sc.id, law=law, mode=mode)   # the plant listens: recorded
            fc = procs.start(fc_name, fc_cmd, stdout=out / "fsw_node.stdout", stderr=out / "fsw_node.stderr",
                             env=env)
            hard_end = (time.monotonic() + sc.duration_s + 60.0) if opts.realtime else None
            while True:
                rc_p, rc_f = plant.poll(), fc.poll()
                if rc_p is not None:
                    if rc_p != 0:
                        failure = ("plant_node", rc_p, plant)
                    break
                if plant_records and done.is_file():
                    break   # the last tick is flown; the plant records on until the end marker
                if rc_f is not None:
                    failure = (fc_name, rc_f, fc)
                    plant.stop()
                    break
                if hard_end is not None and time.monotonic() > hard_end:
                    failure = ("plant_node", None, plant)
                    plant.stop()
                    break
                time.sleep(0.005)
            rc_fc = fc.stop()  # SIGTERM: the node publishes its last status and reports
            if failure is None and rc_fc != 0:
                failure = (fc_name, rc_fc, fc)
        finally:
            if recorder is not None:
                recorder.stop(scenario=sc.id)
            elif plant_records:
                try:   # the plant has recorded everything before the end marker, and ends
                    rc_p = orchestrate.end_plant_log(link, plant, scenario=sc.id)
                finally:
                    link.close()
                done.unlink(missing_ok=True)
                if failure is None and rc_p not in (None, 0):
                    failure = ("plant_node", rc_p, plant)
            else:
                orchestrate.stop_logger(logger, link, log_path, scenario=sc.id)
    wall = time.monotonic() - t_wall0

    plant_sum = _last_json(out / "plant_node.stdout", "plant_node")
    fsw_sum = _last_json(out / "fsw_node.stdout", "fsw_node")
    if failure is not None:
        name, rc, proc = failure
        last = _last_ticks(log_path)
        why = orchestrate.describe_exit(rc) if rc is not None else "did not finish in time"
        if name == "plant_node" and rc in PLANT_EXITS:
            why += f" ({PLANT_EXITS[rc]})"
        tail = proc.stderr_tail()
        raise RunFailed(f"{name} {why}; last tick sent {last[0]}, last tick answered {last[1]} "
                        f"(of {sc.n_steps}); log kept in {log_path}" + (f"\n{name} said: {tail}" if tail else ""))

    log = lcmlog.read(log_path)
    metrics, series = results.compute(log, sc, meta, wall_s=wall, plant=plant_sum, fsw=fsw_sum)
    if opts.label:
        metrics["label"] = opts.label
    if law in gains:
        metrics["gain"] = gains[law].to_json()
    dropped = evmod.dropped_ticks(opts.events, sc.dt, sc.n_steps)
    try:
        lcmlog.scan(log_path)
        log_problems = lcmlog.completeness_problems(
            log, sc.n_steps, replies_expected=None if opts.realtime else sc.n_steps - len(dropped),
            dropped_ticks=dropped)
    except lcmlog.LogIntegrityError as exc:
        log_problems = [str(exc)]
    if log_problems and rec_kind == "lcm-logger":
        log_problems.append("lcm-logger drops messages under load (docs/sil.md); the builtin recorder does not")
    elif log_problems:
        log_problems.append("the recorder could not keep up: was the runner paused or the machine overloaded?")
    metrics["log_complete"] = not log_problems
    metrics["verdict"] = verdict.judge(metrics, log_problems, realtime=opts.realtime, allow=opts.allow)
    plots = []
    if opts.plots:
        title = f"{sc.id} / {law}" + (f" ({opts.label})" if opts.label else "")
        plots = plotmod.run_plots(series, out, title, sc.metrics.requirement_arcsec, sc.metrics.goal_arcsec,
                                  settle=metrics["settle_criterion"]["criteria"],
                                  settle_time_s=metrics["settle_time_s"])
        metrics["plots"] = [p.name for p in plots]
    text = json.dumps(metrics, indent=1) + "\n"
    (out / "metrics.json").write_text(text)
    if opts.json_path:
        Path(opts.json_path).write_text(text)  # its folder was checked before the run (check_options)
    return RunResult(metrics, out, plots, results.table(metrics), series)


def _last_ticks(log_path: Path):
    """(last sensors tick, last answered tick) in a (possibly partial) log."""
    try:
        log = lcmlog.read(log_path)
    except Exception:  # noqa: BLE001 - best effort on a failure path
        return (None, None)
    s = log.sensors["tick"]
    c = log.cmd["tick"]
    return (int(s[-1]) if s.size else None, int(c[-1]) if c.size else None)


