"""`aocs campaign SCENARIO`: a Monte Carlo campaign over the real SIL path, on Dask.

    aocs campaign irassi_large --law quat_pd --runs 1000 --seed 1 --set actuator.axis_limit=0.5 \\
        --disperse plant.w0=normal:0:1e-4 --disperse plant.euler321_deg=rotation:2 --out out/mc

SCENARIO is a scenario id or file, or a campaign file whose [campaign] table
gives the same options (docs/campaigns.md). The campaign is aocs_campaign
(dispersions, plan, execute on Dask, report); this module is its command line.
Exit: 0 every run completed and passed its verdict, 1 some run did not
(each recorded with its error), 2 bad input, 3 an I/O failure (a full disk:
aocs_api.errors.io_failure), 130 interrupted (what finished is kept; the same command
resumes).
"""
from __future__ import annotations

import os
import shutil
import subprocess
import sys
from pathlib import Path

from aocs_api import AocsError
from aocs_api import campaigns as api_campaign
from aocs_api.errors import check_output_file
from aocs_campaign import dispersions as D
from aocs_campaign import plan as P
from aocs_core import paths
from aocs_plant.scenario import ScenarioError

from . import command_line

EXIT_OK, EXIT_FAILED, EXIT_USAGE, EXIT_INTERRUPTED = 0, 1, 2, 130
#: set in the environment of a campaign re-executed in a user namespace of its own (non-root)
USERNS_ENV = "AOCS_CAMPAIGN_USERNS"


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id or file, or a campaign file with a [campaign] table")
    p.add_argument("--law", help="control law (default: the campaign file's, else the scenario's)")
    p.add_argument("--runs", type=int, help="number of runs (or the campaign file's campaign.runs)")
    p.add_argument("--seed", type=int, help="campaign seed: run i's values are a function of (seed, i)")
    p.add_argument("--disperse", action="append", default=[], metavar="KEY=DIST",
                   help="KEY=normal:MEAN:SIGMA | uniform:LO:HI | rotation:SIGMA_DEG, KEY any --set key, "
                        "KEY[i] one element (repeatable; docs/campaigns.md)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario override for every run, as aocs run --set (repeatable)")
    p.add_argument("--transport", default="lcm", metavar="lcm|direct",
                   help="lcm (default): each run's fsw_node over LCM; direct: the same node logic in the plant's "
                        "process (docs/sil.md Transports), and every --refly-every-th run flown again over LCM: "
                        "its command history must be the same bit for bit, or the run is an error")
    p.add_argument("--refly-every", type=int, default=P.REFLY_EVERY, metavar="N",
                   help=f"--transport direct: re-fly runs 0, N, 2N, ... over LCM and compare (default "
                        f"{P.REFLY_EVERY}; 0: none)")
    p.add_argument("--workers", type=int, help="local Dask worker processes (default: one per core)")
    p.add_argument("--scheduler", metavar="ADDRESS", help="an existing Dask scheduler, tcp://HOST:PORT")
    p.add_argument("--out", help="campaign folder (default out/campaign-<scenario>-<law>-s<seed>); rerunning "
                                 "into it skips the runs already done")
    p.add_argument("--json", help="also write the campaign JSON here")
    p.add_argument("--timeout", type=float, metavar="S", help="wall-clock bound of one run, s (default none: "
                   "each wait of the run is bounded already)")
    p.add_argument("--keep-logs", action="store_true", help="keep every run's folder (log, config); by default "
                   "only the runs that did not pass keep theirs")
    p.add_argument("--retry-errors", action="store_true", help="fly again the runs of OUT that did not complete "
                   "(status error: crashed, timed out); the others are kept")
    p.add_argument("--no-plots", action="store_true", help="skip the PNG plots")
    p.add_argument("--html", metavar="FILE", help="also write the campaign's interactive report here (one "
                   "self-contained HTML page: statistics, CDFs, scatter plots linked to each run's repeat command)")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress bar")


def _campaign(args) -> P.Campaign:
    sec = {}
    if Path(args.scenario).suffix == ".toml" or Path(args.scenario).is_file():
        sec = P.read_file_section(args.scenario)
    scenario = sec.get("scenario", args.scenario)
    runs = args.runs if args.runs is not None else sec.get("runs")
    seed = args.seed if args.seed is not None else sec.get("seed")
    if runs is None:
        raise P.CampaignError("--runs: missing (or campaign.runs in a campaign file)")
    if seed is None:
        raise P.CampaignError("--seed: missing (or campaign.seed in a campaign file)")
    law = args.law or sec.get("law")
    return P.Campaign(scenario, law, int(runs), int(seed), list(sec.get("set", [])) + list(args.set),
                      list(sec.get("disperse", [])) + list(args.disperse), transport=args.transport,
                      refly_every=args.refly_every, faults=sec.get("faults"))


def _commit() -> str | None:
    try:
        r = subprocess.run(["git", "-C", str(paths.REPO), "rev-parse", "--short", "HEAD"], capture_output=True,
                           text=True, timeout=5)
        dirty = subprocess.run(["git", "-C", str(paths.REPO), "status", "--porcelain", "--untracked-files=no"],
                               capture_output=True, text=True, timeout=5).stdout.strip()
        return (r.stdout.strip() + ("+local changes" if dirty else "")) if r.returncode == 0 else None
    except (OSError, subprocess.SubprocessError):
        return None


def _userns_reexec(args) -> str | None:
    """Non-root with a local cluster: re-execute in a user namespace of our own (unprivileged), where
    the workers may make their network namespaces. Returns why not, or does not return."""
    if os.geteuid() == 0 or args.scheduler or os.environ.get(USERNS_ENV):
        return None
    if shutil.which("unshare") is None:
        return "not root and no `unshare` (util-linux) for an unprivileged user namespace"
    probe = subprocess.run(["unshare", "--user", "--map-root-user", "true"], capture_output=True, text=True)
    if probe.returncode != 0:
        return (f"not root, and unprivileged user namespaces are not allowed here ({probe.stderr.strip()}); "
                "run as root")
    argv = paths.self_argv() or [sys.executable, *sys.argv]
    os.environ[USERNS_ENV] = "1"
    sys.stdout.flush()
    sys.stderr.flush()
    os.execvp("unshare", ["unshare", "--user", "--map-root-user", *argv])
    return None  # not reached


def run(args) -> int:
    try:
        c = _campaign(args)
        api_campaign.check(c, workers=args.workers, scheduler=args.scheduler, timeout=args.timeout)
        check_output_file("--html", args.html)
        if args.json and Path(args.json).is_dir():
            raise P.CampaignError(f"--json {args.json}: is a folder, not a file")
        if args.json and not Path(args.json).resolve().parent.is_dir():
            raise P.CampaignError(f"--json {args.json}: folder {Path(args.json).parent} does not exist")
    except (P.CampaignError, D.DispersionError, ScenarioError, ValueError) as exc:
        print(f"aocs campaign: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except AocsError as exc:
        print(exc.line("campaign"), file=sys.stderr)
        return exc.exit_code
    why = _userns_reexec(args)
    if why is not None:
        print(f"aocs campaign: error: cannot give each run a private network namespace: {why}", file=sys.stderr)
        return EXIT_USAGE
    out = Path(args.out) if args.out else api_campaign.default_out(c)
    try:
        res = api_campaign.run_campaign(c, out=out, workers=args.workers, scheduler=args.scheduler,
                                        keep_logs=args.keep_logs, timeout=args.timeout, progress=not args.quiet,
                                        retry_errors=args.retry_errors, plots=not args.no_plots, html=args.html,
                                        command=command_line.typed("campaign"), commit=_commit())
    except AocsError as exc:
        print(exc.line("campaign"), file=sys.stderr)
        return exc.exit_code
    doc, outcome = res.summary, res.outcome
    if args.json:
        Path(args.json).write_text((out / "campaign.json").read_text())
    _print_summary(doc, out)
    if args.html:
        print(f"  page: {args.html}")
    if outcome.interrupted or not doc["complete"]:
        print(f"aocs campaign: INCOMPLETE: {doc['rows']} of {c.runs} runs recorded; the same command resumes",
              file=sys.stderr)
        return EXIT_INTERRUPTED if outcome.interrupted else EXIT_FAILED
    refly = doc.get("refly") or {}
    if refly.get("differ"):
        print(f"aocs campaign: FAILED: the LCM re-flight of run(s) {', '.join(map(str, refly['differ']))} differs "
              f"from the direct run (the two transports must fly the same commands; rows in {out}/runs/)",
              file=sys.stderr)
        return EXIT_FAILED
    bad = doc["status"]["failed"] + doc["status"]["error"]
    if bad:
        print(f"aocs campaign: FAILED: {bad} of {c.runs} runs did not pass (listed in {out}/report.md, logs in "
              f"{out}/runs/)", file=sys.stderr)
        return EXIT_FAILED
    return EXIT_OK


def _print_summary(doc: dict, out: Path) -> None:
    c = doc["campaign"]
    t = doc.get("throughput") or {}
    print(f"campaign {c['scenario']} / {c['law']}: {doc['rows']} of {c['runs']} runs "
          f"(passed {doc['status']['passed']}, failed {doc['status']['failed']}, error {doc['status']['error']})"
          + (f"; {t['runs_this_call']} runs this call at {t['runs_per_minute']:.1f} runs/min"
             if t.get("runs_per_minute") else ""))
    for r in doc["requirements"].values():
        w = r["wilson95"]
        print(f"  {r['what']}: {r['passed']}/{r['n']}" + (f" = {r['fraction']:.4f}, 95 % Wilson [{w[0]:.4f}, "
                                                          f"{w[1]:.4f}]" if w else ""))
    refly = doc.get("refly")
    if refly:
        print(f"  transport {doc.get('transport')}: {refly['identical']} of {refly['sampled']} LCM re-flights "
              f"bit-identical" + (f"; DIFFERENT: runs {refly['differ']}" if refly["differ"] else ""))
    print(f"  results.parquet, results.csv, campaign.json, report.md and plots in {out}/")
