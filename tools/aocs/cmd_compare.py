"""`aocs compare SCENARIO`: every applicable law of a scenario in its own SIL run, side by side
(the work is in aocs_compare.compare; this module is the command line)."""
from __future__ import annotations

import json
import math
import sys
from pathlib import Path

from aocs_api import AocsError, compare
from aocs_compare import sweep as sweep_mod
from aocs_compare.compare import comparison_table_for, estimation_table
from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError
from aocs_report import text
from aocs_wire import netns

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id (aocs list) or path to a scenario file")
    p.add_argument("--laws", default="all", help="all (default) or a comma list, e.g. quat_pd,smc; "
                   "law:table selects one gain table, e.g. lqr_quat:lqr_quat_strong")
    p.add_argument("--limit", type=float, metavar="NM", help="per-axis actuator limit for every run (N m, or N)")
    p.add_argument("--duration", type=float, help="run length, s")
    p.add_argument("--guidance", metavar="MODE",
                   help="flight software guidance for every run (sets guidance.mode); slew also prints the "
                        "eigenaxis bang-bang bound and settle / bound per law")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario override for every run (repeatable)")
    p.add_argument("--transport", default="lcm", metavar="lcm|direct",
                   help="lcm (default): fsw_node as its own process over LCM; direct: the same node logic loaded into "
                        "the plant's process (lockstep, bit-identical commands, docs/sil.md Transports)")
    p.add_argument("--json", help="also write the list of metrics here")
    p.add_argument("--out", help="output folder (default out/compare/<scenario>)")
    p.add_argument("--html", metavar="FILE", help="also write the comparison's interactive report here (one "
                   "self-contained HTML page, every law overlaid; docs/reports.md)")
    p.add_argument("--telemetry-decimate", type=int, default=1, metavar="N",
                   help="each run's telemetry.parquet keeps every N-th control tick (default 1)")
    p.add_argument("--run-plots", action="store_true", help="also draw each run's own plots")
    p.add_argument("--sweep", action="store_true",
                   help="H-infinity scenarios: measure the disturbance-to-output gain of the SIL loop across "
                        "frequencies (a sinusoidal disturbance per run) against the design's Gzd(jw)")
    p.add_argument("--freqs", type=lambda s: [float(x) for x in s.split(",")], default=None, metavar="W1,W2,...",
                   help=f"--sweep frequencies, rad/s (default {','.join(f'{w:g}' for w in sweep_mod.FREQUENCIES)})")
    p.add_argument("--table", help="--sweep: the gain table (default the scenario's)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def run_sweep(args, out: Path) -> int:
    freqs = args.freqs or sweep_mod.FREQUENCIES
    if not freqs or not all(math.isfinite(w) and 1e-5 <= w <= 10.0 for w in freqs):
        print(f"aocs compare: error: --freqs {freqs}: every frequency must be within [1e-5, 10] rad/s", file=sys.stderr)
        return EXIT_USAGE
    try:
        points, summary = sweep_mod.sweep(out, scenario=args.scenario, table=args.table, freqs=freqs,
                                          quiet=args.quiet)
    except (ScenarioError, ValueError, KeyError, fsw_config.ConfigError, paths.SetupError, netns.NetnsError) as exc:
        print(f"aocs compare: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    (out / "sweep.json").write_text(json.dumps(summary, indent=1) + "\n")
    if args.json:
        Path(args.json).write_text((out / "sweep.json").read_text())
    png = sweep_mod.plot(points, summary, out / "sweep.png") if any(p.measured for p in points) else None
    print(f"{summary['scenario']} ({summary['table']}): gamma of K = {summary['gamma']:.6g}, "
          f"amplitude {summary['amplitude_nm']:g} N m along {[round(x, 4) for x in summary['direction']]}")
    print(f"  {'w (rad/s)':>10}  {'measured':>11}  {'|Gzd e|':>11}  {'sigma_max':>11}  {'meas/design':>11}")
    for p in points:
        if p.measured is None:
            print(f"  {p.w_rad_s:>10g}  FAILED: {p.error}")
        else:
            print(f"  {p.w_rad_s:>10g}  {p.measured:>11.4g}  {p.design:>11.4g}  {p.sigma_max:>11.4g}  "
                  f"{p.measured / p.design:>11.3f}")
    print(f"  within a factor 2 of the design: {'yes' if summary['within_factor_2'] else 'NO'}; "
          f"never above gamma: {'yes' if summary['below_gamma'] else 'NO'}"
          + (f"; plot {png}" if png else ""))
    return EXIT_FAILED if summary["failed"] else EXIT_OK


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    out = Path(args.out) if args.out else Path("out") / "compare" / Path(args.scenario).stem
    out.mkdir(parents=True, exist_ok=True)
    if args.sweep:
        return run_sweep(args, out)
    try:
        res = compare(args.scenario, out=out, laws=args.laws, limit=args.limit, duration=args.duration,
                      guidance=args.guidance, sets=args.set, run_plots=args.run_plots, quiet=args.quiet,
                      telemetry_decimate=args.telemetry_decimate, html=args.html, transport=args.transport)
    except AocsError as exc:
        print(exc.line("compare"), file=sys.stderr)
        return exc.exit_code
    sc, rows = res.scenario, res.rows
    plots = [out / p for p in ("pointing_error.png", "torque_norm.png", "position_error.png", "force_norm.png")
             if (out / p).is_file()]
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text((out / "compare.json").read_text())
    slew = args.guidance == "slew"
    table = comparison_table_for(sc, rows, bound=slew)
    print(f"{sc.id}: {len(rows)} laws" + ("" if args.limit is None else f", limit {args.limit:g} per axis")
          + (", guidance slew" if slew else ""))
    bounds = {r.metrics.get("slew_bound_s") for r in rows if r.metrics}
    if slew and bounds - {None}:
        print(f"eigenaxis bang-bang bound (SPEC 5.1, margin 1, no rate limit): "
              f"{', '.join(f'{b:.1f} s' for b in sorted(bounds - {None}))}")
    print(text.table(table))
    est = estimation_table(rows, sc.metrics.requirement_arcsec if sc.kind == "attitude" else None)
    if est is not None:   # the runs flew a filter: what it knew, what the law saw, what the mission got
        print("attitude knowledge (truth - estimate), control (estimate - reference), pointing (truth - reference):")
        print(text.table(est))
    print(f"report: {out / 'report.md'}; plots: {', '.join(p.name for p in plots)}"
          + (f"; page: {args.html}" if args.html else ""))
    return EXIT_FAILED if any(r.error for r in rows) else EXIT_OK

