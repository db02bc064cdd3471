"""`make sil`: irassi_large with every IRASSI law, then the comparison table.

    python -m aocs_runner.demo [--scenario irassi_large] [--out out/sil] [--no-realistic] [--no-plots]

Each law runs three times through real processes (plant_node, fsw_node, the
recorder) in lockstep: with the reference actuator (no limit, as the IRASSI
report's runs), with the scenario's realistic reaction-wheel limit
(actuator.realistic_axis_limit, 0.5 N m per axis; SPEC 4) commanded as a
step, and with that limit flying the on-board slew guidance (SPEC 5.1,
`--guidance slew`; the table adds the eigenaxis bound and settle / bound). lqr_quat runs with
both compiled gain tables (lqr_quat_ref, lqr_quat_strong). Plots, logs and
metrics.json of every run go to OUT/<law>[-<table>]-<ref|limit>/, the table
to OUT/comparison.txt and stdout.
"""
from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from aocs_analysis import run_metrics as results
from aocs_core import registry
from aocs_plant.scenario import load
from aocs_wire import netns

from .run import RunFailed, RunOptions, execute


def runs_for(sc) -> list[tuple[str, str | None]]:
    """(law, gain table or None) for every law of the scenario in wire-id order, every table of table-based laws."""
    out = []
    for law in registry.law_names():
        if law not in sc.control.laws:
            continue
        lc = sc.control.laws[law]
        if lc.tables:
            out += [(law, t) for t in lc.tables]
        else:
            out.append((law, None))
    return out


def main(argv=None) -> int:
    p = argparse.ArgumentParser(prog="python -m aocs_runner.demo", description=__doc__.splitlines()[0])
    p.add_argument("--scenario", default="irassi_large")
    p.add_argument("--out", default="out/sil")
    p.add_argument("--no-realistic", action="store_true", help="only the reference (unlimited) runs")
    p.add_argument("--no-plots", action="store_true")
    args = p.parse_args(argv)
    netns.reexec_in_netns([sys.executable, "-m", "aocs_runner.demo", *sys.argv[1:]])

    sc = load(args.scenario)
    root = Path(args.out)
    root.mkdir(parents=True, exist_ok=True)
    variants = [("ref", None, None)]
    if not args.no_realistic and sc.actuator.realistic_axis_limit is not None:
        lim = sc.actuator.realistic_axis_limit
        variants += [(f"limit{lim:g}", lim, None), (f"limit{lim:g}-slew", lim, "slew")]
    tables = []
    failed = 0
    for vname, limit, guidance in variants:
        ms = []
        for law, table in runs_for(sc):
            name = f"{law}-{table}" if table else law
            sets = [f'laws.{law}.table="{table}"'] if table else []
            label = table
            print(f"sil: {sc.id} {name} ({'no limit' if limit is None else f'{limit:g} N m per axis'}"
                  f"{'' if guidance is None else ', slew guidance'})", file=sys.stderr, flush=True)
            try:
                res = execute(RunOptions(scenario=args.scenario, law=law, limit=limit, sets=sets,
                                         guidance=guidance, out=str(root / f"{name}-{vname}"), label=label,
                                         plots=not args.no_plots, quiet=True))
            except RunFailed as exc:
                print(f"sil: {name}: FAILED: {exc}", file=sys.stderr)
                failed += 1
                continue
            ms.append(res.metrics)
        title = (f"{sc.id}: reference actuator (no limit)" if limit is None
                 else f"{sc.id}: realistic reaction wheels, {limit:g} N m per axis"
                 + (", step command" if guidance is None else ", slew guidance (SPEC 5.1)"))
        tables.append(f"{title}\n{results.comparison_table(ms, bound=guidance == 'slew')}" if ms
                      else f"{title}\n(no run completed)")
        (root / f"metrics-{vname}.json").write_text(json.dumps(ms, indent=1) + "\n")
    req, goal = sc.metrics.requirement_arcsec, sc.metrics.goal_arcsec
    note = (f"final max = max true pointing angle 2 asin|qe_vec| over the last {sc.metrics.window_s:g} s "
            f"(requirement {req:g}, goal {goal:g} arcsec); |qe_i| max = the IRASSI report's figure "
            "(half the per-axis angle); safe s = time in safe mode")
    text = "\n\n".join(tables) + "\n\n" + note + "\n"
    (root / "comparison.txt").write_text(text)
    print()
    print(text)
    print(f"plots, logs and metrics.json of every run: {root}/<law>-<variant>/ (table: {root}/comparison.txt)")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
