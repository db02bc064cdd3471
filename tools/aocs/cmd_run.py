"""`aocs run SCENARIO`: one scenario in the loop, plant and flight software as
separate processes talking LCM inside a private network namespace.

    aocs run irassi_large --law smc --limit 0.5 --json out.json

The run itself is aocs_runner.run (processes, log, metrics); this module is
its command line. How a run works: docs/sil.md.
"""
from __future__ import annotations

import sys

from aocs_analysis import verdict
from aocs_api import AocsError
from aocs_api.runs import run_options
from aocs_core import paths
from aocs_runner.run import RECORDERS, TARGETS, RunOptions
from aocs_wire import netns

from . import command_line

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2   # and aocs_api.errors.EXIT_IO = 3 (an I/O failure)


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id (aocs list) or path to a scenario file")
    p.add_argument("--law", help="control law (default: the scenario's)")
    p.add_argument("--duration", type=float, help="run length, s (whole control periods)")
    p.add_argument("--realtime", action="store_true", help="pace to the wall clock (default: lockstep)")
    p.add_argument("--out", help="output folder (default out/<scenario>-<law>)")
    p.add_argument("--json", help="also write the metrics JSON here")
    p.add_argument("--limit", type=float, metavar="NM",
                   help="per-axis actuator limit (N m, or N for orbit), plant and flight software")
    p.add_argument("--target", choices=TARGETS, default="host",
                   help="flight computer: host fsw_node, or processor in the loop (QEMU)")
    p.add_argument("--transport", default="lcm", metavar="lcm|direct",
                   help="lcm (default): fsw_node as its own process over LCM; direct: the same node logic loaded into "
                        "the plant's process (lockstep, bit-identical commands, docs/sil.md Transports)")
    p.add_argument("--seed", type=int, help="seed of the plant's random streams")
    p.add_argument("--guidance", metavar="MODE",
                   help="flight software guidance: step (the target at once) or slew (rest-to-rest eigenaxis "
                        "slew, the scenario's [guidance] settings); sets guidance.mode")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario override, e.g. control.enabled=false (repeatable)")
    p.add_argument("--event", action="append", default=[], metavar="T:WHAT",
                   help="scheduled command or transport fault, e.g. 100:law=smc, 5:malformed (docs/sil.md)")
    p.add_argument("--fault", action="append", default=[], metavar="KIND@START[-END][:unit=N][:KEY=VALUE]",
                   help="inject a fault of the catalogue, e.g. wheel_torque_loss@60:unit=1, st_bias_step@100-160:"
                        "bias_arcsec=30 (appended to the scenario's [[faults]]; docs/scenarios.md; repeatable)")
    p.add_argument("--reply-timeout", type=float, default=None,
                   help="lockstep: max wait for each command, s (default 2; 10 for pil targets)")
    p.add_argument("--recorder", choices=RECORDERS, default="auto",
                   help="what records the LCM log: the plant itself, its truth in the log only, not on the bus "
                        "(lockstep; the fastest), the runner's lossless recorder thread (real time), both "
                        "chosen by auto (default); builtin: the recorder thread, truth on the bus, in lockstep "
                        "too; lcm-logger, which can drop messages under load (docs/sil.md)")
    p.add_argument("--plant-lcm-lib", action="store_true",
                   help="plant_node receives through the LCM library's thread instead of reading udpm "
                        "directly (for comparison; docs/sil.md)")
    p.add_argument("--no-pin-cpus", action="store_true",
                   help="lockstep over LCM: leave plant_node and fsw_node to the scheduler instead of pinning each "
                        "to a CPU of its own (docs/sil.md)")
    p.add_argument("--allow", action="append", default=[], choices=verdict.CHECKS, metavar="CHECK",
                   help="let the run pass although this check fails, to study the case on purpose: "
                        + ", ".join(verdict.CHECKS) + " (docs/sil.md, Verdict; repeatable)")
    p.add_argument("--label", help="label of the run in tables and the JSON")
    p.add_argument("--html", metavar="FILE", help="also write the run's interactive report here (one self-contained "
                   "HTML page: time series, verdict, metrics, scenario, repeat command; docs/reports.md)")
    p.add_argument("--telemetry-decimate", type=int, default=1, metavar="N",
                   help="OUT/telemetry.parquet keeps every N-th control tick and the last (default 1: every tick)")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def options_from_args(args) -> RunOptions:
    return RunOptions(scenario=args.scenario, law=args.law, duration=args.duration, realtime=args.realtime,
                      out=args.out, json_path=args.json, limit=args.limit, target=args.target, seed=args.seed,
                      transport=args.transport,
                      guidance=args.guidance,
                      sets=args.set, events=args.event, faults=args.fault, reply_timeout=args.reply_timeout, label=args.label,
                      plots=not args.no_plots, quiet=args.quiet, recorder=args.recorder,
                      plant_lcm_lib=args.plant_lcm_lib, pin_cpus=not args.no_pin_cpus, allow=tuple(args.allow),
                      telemetry_decimate=args.telemetry_decimate, command=command_line.typed("run"))


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    opts = options_from_args(args)
    try:
        res = run_options(opts, html=args.html)
    except AocsError as exc:
        print(exc.line("run"), file=sys.stderr)
        return exc.exit_code
    print(res.table)
    if res.plots:
        print(f"  plots, log, config and metrics.json in {res.out_dir}/")
    if args.html:
        print(f"  report: {args.html}")
    ie = res.metrics.get("integration_error")
    if ie and ie["exceeds_tolerance"]:
        print("aocs run: warning: the plant's integration error is above the scenario's tolerance (see the "
              "'integration error' line); raise [integrator] substeps (--set integrator.substeps=N)", file=sys.stderr)
    v = res.metrics["verdict"]
    if not v["passed"]:
        print(f"aocs run: FAILED: {verdict.summary(v)} (metrics and log kept in {res.out_dir}/)", file=sys.stderr)
        return EXIT_FAILED
    if v["allowed"]:
        print(f"aocs run: allowed to pass although it failed: {', '.join(v['allowed'])}", file=sys.stderr)
    return EXIT_OK
