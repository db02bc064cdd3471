"""`aocs compare SCENARIO`: every applicable law of a scenario in its own SIL run, side by side
(the work is in aocs_compare.compare; this module is the command line)."""
from __future__ import annotations

import sys
from pathlib import Path

from aocs_compare.compare import compare, table_rows, text_table
from aocs_core import paths
from aocs_plant.scenario import ScenarioError
from aocs_runner import orchestrate
from aocs_wire import fsw_config, netns

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id (aocs list) or path to a scenario file")
    p.add_argument("--laws", default="all", help="all (default) or a comma list, e.g. quat_pd,smc; "
                   "law:table selects one gain table, e.g. lqr_quat:lqr_quat_strong")
    p.add_argument("--limit", type=float, metavar="NM", help="per-axis actuator limit for every run (N m, or N)")
    p.add_argument("--duration", type=float, help="run length, s")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario override for every run (repeatable)")
    p.add_argument("--json", help="also write the list of metrics here")
    p.add_argument("--out", help="output folder (default out/compare/<scenario>)")
    p.add_argument("--run-plots", action="store_true", help="also draw each run's own plots")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def run(args) -> int:
    netns.reexec_in_netns(paths.self_argv())
    out = Path(args.out) if args.out else Path("out") / "compare" / Path(args.scenario).stem
    out.mkdir(parents=True, exist_ok=True)
    try:
        sc, rows, plots = compare(args.scenario, out, laws=args.laws, limit=args.limit, duration=args.duration,
                                  sets=args.set, run_plots=args.run_plots, quiet=args.quiet)
    except (ScenarioError, ValueError, fsw_config.ConfigError, paths.SetupError, netns.NetnsError) as exc:
        print(f"aocs compare: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except orchestrate.RunAborted as exc:
        print(f"aocs compare: aborted: {exc}", file=sys.stderr)
        return EXIT_FAILED
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text((out / "compare.json").read_text())
    head, body = table_rows(rows, sc.kind)
    print(f"{sc.id}: {len(rows)} laws" + ("" if args.limit is None else f", limit {args.limit:g} per axis"))
    print(text_table(head, body))
    print(f"report: {out / 'report.md'}; plots: {', '.join(p.name for p in plots)}")
    return EXIT_FAILED if any(r.error for r in rows) else EXIT_OK

