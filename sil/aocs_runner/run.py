"""One run in the loop (`aocs run`, `aocs compare`, the main job): plant and
flight software as separate processes talking LCM inside a private network
namespace.

execute runs three steps, one function each: plan_run (options and scenario
checked, gains chosen, fsw_node.cfg and run.json written, before anything
starts), flight.fly (plant_node, the recorder and the flight computer, fsw_node
or the PIL bridge with --target pil-*, supervised with bounded waits until the
log is ended) and judge (metrics from the log, verdict, plots, OUT/metrics.json
and --json). How a run works: docs/sil.md.
"""
from __future__ import annotations

import hashlib
import importlib.util
import json
import math
import os
import shlex
import sys
import time
from dataclasses import dataclass, field
from pathlib import Path

from aocs_analysis import day_timeline, estimation_plots, telemetry, verdict
from aocs_analysis import plots as plotmod
from aocs_analysis import run_metrics as results
from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant.faults import parse_options as parse_fault_options
from aocs_plant.scenario import document, load
from aocs_wire import lcmlog, netns

from . import events as evmod
from . import orchestrate, scenario_gains, scenario_opts
from .flight import Failure, Flight, RunFailed, fly
from .transport import LOCKSTEP_WAIT_SPIN_US, check_transport, lockstep_cpus

#: plant_node exit codes (plant_node.py)
PLANT_EXITS = {2: "bad arguments or scenario", 3: "no heartbeat from the flight computer",
               4: "the flight computer stopped answering", 5: "interrupted by a signal"}
TARGETS = ("host", "pil-m4f", "pil-m7")


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
    transport: str = "lcm"        # lcm | direct: how the plant reaches the flight computer (transport.py)
    seed: int | None = None
    guidance: str | None = None     # step | slew: guidance.mode override (aocs run --guidance)
    sets: list = field(default_factory=list)
    events: list = field(default_factory=list)
    faults: list = field(default_factory=list)   # --fault KIND@START[-END][:unit=N][:k=v] (aocs_plant.faults.option)
    reply_timeout: float | None = None
    label: str | None = None
    plots: bool = True
    quiet: bool = False
    recorder: str = "auto"        # auto | builtin | plant | lcm-logger (recorder_of)
    plant_lcm_lib: bool = False
    allow: tuple = ()             # verdict checks allowed to fail (aocs_analysis.verdict.CHECKS)
    telemetry_decimate: int = 1   # OUT/telemetry.parquet keeps every N-th tick (and the last)
    #: "always", or "failed": OUT/telemetry.parquet only when the verdict failed (a campaign deletes a passed run's
    #: folder: its table would be written to be thrown away)
    telemetry: str = "always"
    command: str | None = None    # the command line that started the run (run.json "command")
    # starts plant_node from its arguments instead of a new interpreter: (args, stdout_path, env) -> a
    # Popen-like child (aocs campaign forks it from a worker that has the plant's modules imported)
    plant_launcher: object = None
    # lockstep over LCM on the host, not in a campaign: the plant and fsw_node each pinned to a CPU of its own
    # (transport.lockstep_cpus; aocs run --no-pin-cpus leaves them to the scheduler)
    pin_cpus: bool = True


@dataclass
class RunResult:
    metrics: dict
    out_dir: Path
    plots: list
    table: str
    series: dict | None = None    # the metrics' time series (run_metrics.compute), for a campaign's overlay
    telemetry: Path | None = None  # OUT/telemetry.parquet


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
    check_transport(opts.transport)
    if opts.transport == "direct":
        for bad, what in ((opts.realtime, "--realtime"), (opts.target != "host", f"--target {opts.target}"),
                          (opts.plant_lcm_lib, "--plant-lcm-lib"),
                          (opts.recorder not in ("auto", "plant"), f"--recorder {opts.recorder}")):
            if bad:
                raise ValueError(f"--transport direct: lockstep on the host with the plant recording, not with "
                                 f"{what}")
    if opts.recorder not in RECORDERS:
        raise ValueError(f"--recorder {opts.recorder!r}: one of {', '.join(RECORDERS)}")
    if opts.recorder == "plant" and (opts.realtime or opts.plant_lcm_lib):
        raise ValueError("--recorder plant: the plant records the socket it reads itself, in lockstep only "
                         "(not with --realtime or --plant-lcm-lib)")
    if opts.out is not None and Path(opts.out).exists() and not Path(opts.out).is_dir():
        raise ValueError(f"--out {opts.out}: exists and is not a folder")
    td = opts.telemetry_decimate
    if isinstance(td, bool) or not isinstance(td, int) or td < 1:
        raise ValueError(f"--telemetry-decimate {td}: must be a whole number >= 1")
    if opts.telemetry not in ("always", "failed"):
        raise ValueError(f"telemetry {opts.telemetry!r}: 'always' or 'failed'")
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
    if opts.faults:
        ov["faults"] = with_faults(opts.scenario, ov, opts.faults)
    if opts.duration is not None and "metrics.window_s" not in ov:
        # a shortened run keeps the scenario's metric window where it fits, else the whole run
        base = load(opts.scenario, {k: v for k, v in ov.items() if k != "duration_s"})
        if base.metrics.window_s > opts.duration:
            ov["metrics.window_s"] = float(opts.duration)
    sc = load(opts.scenario, ov)
    law = scenario_opts.resolve_law(sc, opts.law)
    if sc.n_steps < 1:
        raise ValueError(f"scenario {sc.id}: a run of {sc.duration_s:g} s is shorter than one control "
                         f"period ({sc.dt:g} s)")
    out = Path(opts.out) if opts.out else Path("out") / f"{sc.id}-{law}"
    if out.exists() and not out.is_dir():
        raise ValueError(f"output folder {out}: exists and is not a folder")
    return sc, ov, law, out


def with_faults(scenario, ov: dict, specs) -> list:
    """The scenario's [[faults]] (after the overrides ov) with the --fault entries appended: the value of the
    `faults` override (aocs_plant.faults.option; FaultOptionError, a ValueError, names a bad --fault)."""
    added = parse_fault_options(specs)
    base = document(scenario, ov).get("faults", [])
    return list(base if isinstance(base, list) else [base]) + added


@dataclass
class RunPlan:
    """Everything decided before any process starts (plan_run), and written to the run folder."""
    sc: object                    # the scenario with the run's overrides (aocs_plant.scenario.Scenario)
    overrides: dict
    law: str
    out: Path
    mode: str                     # lockstep | realtime
    recorder: str                 # builtin | plant | lcm-logger (recorder_of)
    gains: dict                   # law -> scenario_gains.GainChoice
    fsw_config: dict
    fc_cmd: list
    pil_root: Path | None
    meta: dict                    # run.json

    @property
    def log_path(self) -> Path:
        return self.out / "run.lcmlog"


def execute(opts: RunOptions) -> RunResult:
    """One run; raises RunFailed (process failure) or ValueError / SetupError (bad input)."""
    if opts.transport != "direct":
        netns.require_netns()
    t_wall0 = time.monotonic()
    plan = plan_run(opts)
    failure = fly(flight_of(opts, plan))
    wall = time.monotonic() - t_wall0
    plant_sum = _last_json(plan.out / "plant_node.stdout", "plant_node")
    fsw_sum = _last_json(plan.out / "fsw_node.stdout", "fsw_node")
    if failure is not None:
        raise RunFailed(failure_message(failure, plan))
    return judge(opts, plan, wall, plant_sum, fsw_sum)


def plan_run(opts: RunOptions) -> RunPlan:
    """Checks the options and the scenario, chooses the gains, writes fsw_node.cfg and run.json (before
    anything starts: a bad input is refused here)."""
    sc, ov, law, out = prepare(opts)
    rec_kind = recorder_of(opts)
    evmod.schedule(evmod.parse_all(opts.events), sc.dt, sc.n_steps)  # validate before starting anything
    paths.import_bindings()
    out.mkdir(parents=True, exist_ok=True)
    mode = "realtime" if opts.realtime else "lockstep"
    gains = flying_gains(sc)
    cfg, cfg_path = write_fsw_config(opts, sc, law, mode, gains, out)
    fc_cmd = fc_command(opts.target, cfg_path)
    pil_root = pil_build_root(opts.target) if opts.target in PIL_PRESETS else None
    plan = RunPlan(sc, ov, law, out, mode, rec_kind, gains, cfg, fc_cmd, pil_root, meta={})
    plan.meta = run_record(opts, plan, cfg_path)
    (out / "run.json").write_text(json.dumps(plan.meta, indent=1) + "\n")
    (out / "metrics.json").unlink(missing_ok=True)  # never leave a previous run's metrics behind
    return plan


def flying_gains(sc) -> dict:
    """The gain each table law flies: its compiled table, or K designed for this scenario (issue 10
    item 6); the choices' warnings printed."""
    gains = scenario_gains.resolve(sc)
    for choice in gains.values():
        for w in choice.warnings:
            print(f"aocs run: warning: {w}", file=sys.stderr, flush=True)
    return gains


#: the flight computer's configuration in the run folder
FSW_CFG = "fsw_node.cfg"


def node_config_of(opts: RunOptions, sc, law: str, mode: str, gains: dict) -> dict:
    """The flight computer's configuration of a run (what write_fsw_config writes). A host node in lockstep
    polls before it sleeps (transport.LOCKSTEP_WAIT_SPIN_US; the direct node never waits and ignores it)."""
    spin = LOCKSTEP_WAIT_SPIN_US if (mode == "lockstep" and opts.target == "host") else 0.0
    return fsw_config.node_config(sc, law, mode=mode, limit=opts.limit,
                                  run_timeout_s=(sc.duration_s + 30.0) if opts.realtime else 0.0,
                                  gains={n: c.k for n, c in gains.items() if c.k is not None},
                                  wait_spin_us=spin)


def planned_record(opts: RunOptions) -> dict:
    """What run.json will say of these options' scenario and flight configuration (scenario_sha256,
    fsw_config), without writing or starting anything: `aocs results --reuse` reuses a run only when its
    record says the same."""
    sc, _, law, _ = prepare(opts)
    cfg = node_config_of(opts, sc, law, "realtime" if opts.realtime else "lockstep", scenario_gains.resolve(sc))
    return {"scenario_sha256": scenario_digest(sc), "fsw_config": cfg}


def scenario_digest(sc) -> str:
    """SHA-256 of the scenario file's bytes (a run folder says which version of its scenario it flew)."""
    return hashlib.sha256(Path(sc.path).read_bytes()).hexdigest()


def write_fsw_config(opts: RunOptions, sc, law: str, mode: str, gains: dict, out: Path) -> tuple[dict, Path]:
    """The flight computer's configuration, and the file it was written to (OUT/fsw_node.cfg)."""
    cfg = node_config_of(opts, sc, law, mode, gains)
    cfg_path = fsw_config.write(out / FSW_CFG, cfg, header=f"scenario {sc.id}, law {law}, {mode}")
    return cfg, cfg_path


def run_record(opts: RunOptions, plan: RunPlan, cfg_path: Path) -> dict:
    """run.json: what was flown, how and with what (the metrics carry it on)."""
    sc = plan.sc
    return {"scenario": sc.id, "scenario_path": str(Path(sc.path).resolve()), "scenario_sha256": scenario_digest(sc),
            "overrides": plan.overrides,
            "law": plan.law, "mode": plan.mode, "recorder": plan.recorder, "plant_lcm_lib": opts.plant_lcm_lib,
            "target": opts.target, "transport": opts.transport, "events": list(opts.events), "label": opts.label,
            "pinned_cpus": dict(zip(("plant_node", "fsw_node"), cpus)) if (cpus := cpus_of(opts, plan)) else None,
            "faults": [f.to_json() for f in sc.faults],
            "fsw_config": plan.fsw_config, "fsw_config_file": cfg_path.name, "fc_command": plan.fc_cmd,
            "gains": {n: c.to_json() for n, c in plan.gains.items()},
            "pil_image": (str(plan.pil_root / PIL_PRESETS[opts.target] / "aocs_pil.elf") if plan.pil_root
                          else None),
            "log": plan.log_path.name, "telemetry": TELEMETRY_FILE, "telemetry_decimate": opts.telemetry_decimate,
            "command": opts.command, "repeat_command": repeat_command(opts, plan),
            "n_steps": sc.n_steps, "dt": sc.dt, "created": time.strftime("%Y-%m-%dT%H:%M:%S")}


def repeat_command(opts: RunOptions, plan: RunPlan) -> str:
    """The `aocs run` command line that flies this run again: the scenario file, the law, every override as
    --set (the --limit, --duration, --seed and --guidance shorthands included), the events, the target and
    the recording choices; the metrics of the two runs are the same in lockstep."""
    words = ["aocs", "run", opts.scenario] + (["--law", plan.law] if plan.law != "none" else [])
    words += scenario_opts.to_args(plan.overrides)
    for e in opts.events:
        words += ["--event", e]
    if opts.target != "host":
        words += ["--target", opts.target]
    if opts.transport != "lcm":
        words += ["--transport", opts.transport]
    if opts.realtime:
        words.append("--realtime")
    if opts.recorder != "auto":
        words += ["--recorder", opts.recorder]
    if opts.plant_lcm_lib:
        words.append("--plant-lcm-lib")
    if not opts.pin_cpus:
        words.append("--no-pin-cpus")
    for a in opts.allow:
        words += ["--allow", a]
    if opts.reply_timeout is not None:
        words += ["--reply-timeout", repr(opts.reply_timeout)]
    if opts.telemetry_decimate != 1:
        words += ["--telemetry-decimate", str(opts.telemetry_decimate)]
    return shlex.join(words)


def plant_arguments(opts: RunOptions, plan: RunPlan) -> list[str]:
    """plant_node's arguments: the same for a fork, the campaign's plant server and a new interpreter."""
    reply_timeout = opts.reply_timeout or (2.0 if opts.target == "host" else 10.0)
    args = [plan.sc.path, *scenario_opts.to_args(plan.overrides),
            "--mode", plan.mode, "--reply-timeout", repr(reply_timeout)]
    if plan.mode == "lockstep" and opts.transport == "lcm" and opts.target == "host" and not opts.plant_lcm_lib:
        args += ["--wait-spin-us", repr(LOCKSTEP_WAIT_SPIN_US)]
    for e in opts.events:
        args += ["--event", e]
    if opts.quiet:
        args.append("-q")
    if opts.plant_lcm_lib:
        args.append("--lcm-lib")
    if plan.recorder == "plant":
        # the plant records the bus itself, its truth in the log only (plant_node.py, --log)
        args += ["--log", str(plan.log_path), "--truth", "log", "--done-file", str(plan.out / "plant_node.done")]
    if opts.transport == "direct":
        # the flight computer in the plant's process, on the file fsw_node would read (plant_node.py)
        args += ["--transport", "direct", "--fsw-config", str(plan.out / plan.meta.get("fsw_config_file", FSW_CFG)),
                 "--fsw-summary", str(plan.out / "fsw_node.stdout")]
    return args + ["--ready-file", str(plan.out / "plant_node.ready")]


def flight_of(opts: RunOptions, plan: RunPlan) -> Flight:
    """The processes to start for the plan (flight.py), announced on stderr."""
    env = paths.python_env()
    if netns.in_netns():
        # the children check that they run in one of our namespaces by this variable: it names the namespace of
        # the thread that starts them (another thread of this process may have entered a fresh one since, and
        # the process-wide variable names only the last: the API's run thread, a campaign worker's runs)
        env[netns.ENV_VAR] = netns.current_netns_id()
    if plan.pil_root is not None:
        env["AOCS_PIL_BUILD_ROOT"] = str(plan.pil_root)
    sc = plan.sc
    _say(opts, f"{sc.id} with {plan.law}, {plan.mode}, {sc.n_steps} steps of {sc.dt:g} s, flight computer "
               f"{opts.target}; output in {plan.out}/")
    fc_name = "fsw_node" if opts.target == "host" else f"pil bridge ({opts.target})"
    return Flight(sc.id, plan.law, plan.mode, sc.duration_s, plan.out, plan.log_path, plan.recorder,
                  plant_arguments(opts, plan), fc_name, plan.fc_cmd, env, opts.plant_launcher, opts.transport,
                  _pinned(plan.meta.get("pinned_cpus")))


def _pinned(record: dict | None) -> tuple[int, int] | None:
    """Flight.cpus from run.json's pinned_cpus (what the plan chose, cpus_of, recorded once)."""
    return (record["plant_node"], record["fsw_node"]) if record else None


def cpus_of(opts: RunOptions, plan: RunPlan) -> tuple[int, int] | None:
    """The CPUs the plant and fsw_node are pinned to (flight.Flight.cpus): a lockstep run over LCM on the host, by
    itself (a campaign runs several at once: its runs are left to the scheduler), unless --no-pin-cpus."""
    if not (opts.pin_cpus and plan.mode == "lockstep" and opts.transport == "lcm" and opts.target == "host"
            and opts.plant_launcher is None):
        return None
    return lockstep_cpus()


def failure_message(failure: Failure, plan: RunPlan) -> str:
    """Which process failed and how, the log's last ticks, and what it said last."""
    last = _last_ticks(plan.log_path)
    why = failure.why or (orchestrate.describe_exit(failure.rc) if failure.rc is not None
                          else "did not finish in time")
    if failure.name == "plant_node" and failure.rc in PLANT_EXITS:
        why += f" ({PLANT_EXITS[failure.rc]})"
    tail = failure.proc.stderr_tail()
    return (f"{failure.name} {why}; last tick sent {last[0]}, last tick answered {last[1]} "
            f"(of {plan.sc.n_steps}); log kept in {plan.log_path}" + (f"\n{failure.name} said: {tail}" if tail else ""))


def judge(opts: RunOptions, plan: RunPlan, wall: float, plant_sum: dict | None, fsw_sum: dict | None) -> RunResult:
    """The run's metrics from its log, its verdict and plots; OUT/metrics.json (and --json) written."""
    log = lcmlog.read(plan.log_path)
    metrics, series = results.compute(log, plan.sc, plan.meta, wall_s=wall, plant=plant_sum, fsw=fsw_sum)
    if opts.label:
        metrics["label"] = opts.label
    if plan.law in plan.gains:
        metrics["gain"] = plan.gains[plan.law].to_json()
    log_problems = log_completeness(opts, plan, log)
    metrics["log_complete"] = not log_problems
    metrics["verdict"] = verdict.judge(metrics, log_problems, realtime=opts.realtime, allow=opts.allow,
                                       injected=sum(e.kind in verdict.FRAME_FAULTS
                                                    for e in evmod.parse_all(opts.events))
                                       + len(evmod.fault_events(plan.sc.faults, plan.sc.dt, plan.sc.n_steps)))
    plots = draw_plots(opts, plan, metrics, series) if opts.plots else []
    text = json.dumps(metrics, indent=1) + "\n"
    (plan.out / "metrics.json").write_text(text)
    if opts.json_path:
        Path(opts.json_path).write_text(text)  # its folder was checked before the run (check_options)
    tel = write_telemetry(opts, plan, log) if opts.telemetry == "always" or not metrics["verdict"]["passed"] else None
    return RunResult(metrics, plan.out, plots, results.table(metrics), series, tel)


#: the decoded time series beside the log (aocs_analysis.telemetry; docs/sil.md, Telemetry)
TELEMETRY_FILE = "telemetry.parquet"


def write_telemetry(opts: RunOptions, plan: RunPlan, log) -> Path:
    """OUT/telemetry.parquet: every decoded series of the log, one row per tick (every N-th with
    --telemetry-decimate N)."""
    sc = plan.sc
    meta = {"scenario": sc.id, "law": plan.law, "kind": sc.kind, "dt_s": sc.dt, "log": plan.log_path.name}
    return telemetry.write(plan.out / TELEMETRY_FILE, telemetry.columns(log, sc), meta,
                           decimate=opts.telemetry_decimate)


def log_completeness(opts: RunOptions, plan: RunPlan, log) -> list[str]:
    """What the log misses (empty: every tick recorded), with the likely reason."""
    sc = plan.sc
    dropped = evmod.dropped_ticks(opts.events, sc.dt, sc.n_steps, sc.faults)
    try:
        if log.scan is None:   # the bulk reader found the file clean (Log.scan): no second walk of it
            lcmlog.scan(plan.log_path)
        problems = lcmlog.completeness_problems(
            log, sc.n_steps, replies_expected=None if opts.realtime else sc.n_steps - len(dropped),
            dropped_ticks=dropped)
    except lcmlog.LogIntegrityError as exc:
        problems = [str(exc)]
    if problems and plan.recorder == "lcm-logger":
        problems.append("lcm-logger drops messages under load (docs/sil.md); the builtin recorder does not")
    elif problems:
        problems.append("the recorder could not keep up: was the runner paused or the machine overloaded?")
    return problems


def draw_plots(opts: RunOptions, plan: RunPlan, metrics: dict, series: dict) -> list[Path]:
    """The run's plots in OUT/, named in the metrics."""
    sc = plan.sc
    title = f"{sc.id} / {plan.law}" + (f" ({opts.label})" if opts.label else "")
    plots = plotmod.run_plots(series, plan.out, title, sc.metrics.requirement_arcsec, sc.metrics.goal_arcsec,
                              settle=metrics["settle_criterion"]["criteria"],
                              settle_time_s=metrics["settle_time_s"], faults=metrics.get("faults"))
    if series.get("estimation") is not None:   # a filter flew: knowledge error with its 3 sigma, bias, NEES
        plots = list(plots) + list(estimation_plots.run_plots(series["estimation"], plan.out, title))
    if day_timeline.applies(metrics):          # an observation plan or momentum management: the day's timeline
        series["unloading"] = day_timeline.unloading_series(lcmlog.read(plan.log_path), sc)
        plots = list(plots) + [day_timeline.timeline(series, metrics, plan.out / day_timeline.FILE, title)]
    metrics["plots"] = [p.name for p in plots]
    return plots


def _last_ticks(log_path: Path):
    """(last sensors tick, last answered tick) in a (possibly partial) log."""
    try:
        log = lcmlog.read(log_path)
    except Exception:  # noqa: BLE001 - best effort on a failure path
        return (None, None)
    s = log.sensors["tick"]
    c = log.cmd["tick"]
    return (int(s[-1]) if s.size else None, int(c[-1]) if c.size else None)


