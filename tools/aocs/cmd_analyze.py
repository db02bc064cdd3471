"""`aocs analyze SCENARIO --law LAW`: the stability margins of a law about its hold, predicted with the
sample-and-hold and the computation delay, and (--measure) measured in the SIL loop by input injection
(the work is in aocs_margins; this module is the command line)."""
from __future__ import annotations

import json
import sys
from pathlib import Path

from aocs_core import paths
from aocs_flightcfg import fsw_config
from aocs_plant.scenario import ScenarioError, load
from aocs_report import text
from aocs_report.document import Column, Table
from aocs_runner import orchestrate
from aocs_wire import netns

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id (aocs list) or path to a scenario file")
    p.add_argument("--law", default=None, help="law, or law:table (default the scenario's law); all: every "
                   "analysed law of the scenario")
    p.add_argument("--delay", type=int, default=1, metavar="PERIODS",
                   help="computation delay in control periods (default 1; the SIL runs of --measure use it "
                        "as [actuator] delay_periods)")
    p.add_argument("--measure", action="store_true",
                   help="also measure each axis loop in the SIL loop (one run per axis, multisine at the plant input)")
    p.add_argument("--verify", action="store_true",
                   help="two SIL runs with the loop gain at 0.9 and 1.1 x the predicted gain margin: the first "
                        "must converge, the second diverge")
    p.add_argument("--no-rates", action="store_true", help="skip the search of the lowest control rate")
    p.add_argument("--json", help="write the result here (a list when --law all)")
    p.add_argument("--out", help="output folder (runs and plots; default out/analyze/<scenario>)")
    p.add_argument("--plots", action="store_true", help="draw the Bode and Nichols plots (with --measure: "
                   "the measured points over the prediction)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


def _usage(msg: str) -> int:
    print(f"aocs analyze: error: {msg}", file=sys.stderr)
    return EXIT_USAGE


def run(args) -> int:
    if args.measure or args.verify:
        netns.reexec_in_netns(paths.self_argv())
    from aocs_margins import analyze, law_models, plots  # deferred: python-control and matplotlib

    if not 0 <= args.delay <= 100:
        return _usage(f"--delay {args.delay}: must be 0 to 100 control periods")
    try:
        sc = load(args.scenario)
        rows = law_models.law_rows(sc, "all" if args.law == "all" else (args.law or sc.control.law))
    except (ScenarioError, law_models.LawModelError, ValueError) as exc:
        return _usage(str(exc))
    out = Path(args.out) if args.out else Path("out") / "analyze" / Path(args.scenario).stem
    results = []
    failed = False
    for law, table in rows:
        try:
            res, big_l = analyze.analyse(sc, law, table, delay=args.delay, rates=not args.no_rates)
        except (law_models.LawModelError, ValueError) as exc:
            return _usage(f"{law}: {exc}")
        name = f"{law}-{table}" if table else law
        if args.measure:
            progress = None if args.quiet else (lambda s, _steps: print(f"measure: {s}", flush=True))
            try:
                analyze.measured(args.scenario, sc, res, big_l, out / name, progress)
            except (ScenarioError, fsw_config.ConfigError, paths.SetupError, netns.NetnsError) as exc:
                return _usage(f"{name}: {exc}")
            except (orchestrate.RunAborted, RuntimeError) as exc:
                print(f"aocs analyze: {name}: the SIL run failed: {exc}", file=sys.stderr)
                failed = True
                continue
            failed |= not res["agreement"]["within"]
        if args.verify:
            progress = None if args.quiet else (lambda s, _steps: print(f"verify: {s}", flush=True))
            try:
                res["gain_margin_verified"] = analyze.verify_gain_margin(args.scenario, sc, res, big_l, out / name,
                                                                         progress)
            except (ScenarioError, fsw_config.ConfigError, paths.SetupError, netns.NetnsError) as exc:
                return _usage(f"{name}: {exc}")
            failed |= res["gain_margin_verified"]["verified"] is False
        if args.plots:
            res["plots"] = [str(p) for p in plots.draw(res, big_l, out / name)]
        results.append(analyze.finite_json(res))
        _print(res)
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text(json.dumps(results[0] if len(results) == 1 and args.law != "all" else results,
                                              indent=1) + "\n")
    return EXIT_FAILED if failed else EXIT_OK


def _print(res: dict) -> None:
    from aocs_margins import analyze  # deferred: python-control, as in run()

    print(f"{res['scenario']} {res['law']}{':' + res['table'] if res['table'] else ''}: "
          f"{res['control_rate_hz']:g} Hz, zero-order hold, {res['delay_periods']} period(s) of delay, "
          f"loop broken at the plant input")
    print(text.table(Table((Column("loop"), Column("GM", "dB"), Column("PM", "deg"), Column("DM", "s"),
                            Column("modulus"), Column("w_c", "rad/s"), Column("disk")), analyze.summary_rows(res))))
    if res.get("lowest_rate_hz") is not None:
        print(f"  lowest control rate keeping {analyze.REQUIRED_GAIN_MARGIN_DB:g} dB / "
              f"{analyze.REQUIRED_PHASE_MARGIN_DEG:g} deg: {res['lowest_rate_hz']:.3g} Hz")
    v = res.get("gain_margin_verified")
    if v and v.get("runs"):
        print("  gain margin in SIL: " + "; ".join(
            f"k = {r['factor_of_margin']:g} x GM: {'diverged' if r['diverged'] else 'converged' if r['converged'] else '?'}"
            + (f" ({r['start_arcsec']:.3g} -> {r['end_arcsec']:.3g} arcsec)" if "end_arcsec" in r else "")
            for r in v["runs"]) + f": {'shown right' if v['verified'] else 'NOT shown'}")
    if "agreement" in res:
        a = res["agreement"]
        print(f"  measured in the SIL loop: worst |gain error| {a['worst_gain_db']:.3f} dB, worst |phase error| "
              f"{a['worst_phase_deg']:.2f} deg ({'within' if a['within'] else 'NOT within'} "
              f"{a['required_db']:g} dB / {a['required_deg']:g} deg); linear law against the C law's logged "
              f"commands: {a['worst_law_residual']:.2g} of their range")
