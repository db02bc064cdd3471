"""A Monte Carlo campaign on Dask (aocs_campaign), as a result object: the per-run rows as a DataFrame, the campaign
JSON (statistics, requirement pass fractions) as a dict, the page as HTML."""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

from aocs_campaign import dispersions as D
from aocs_campaign import plan as P
from aocs_campaign import report_page
from aocs_plant.scenario import ScenarioError

from .errors import AocsError, check_output_file, io_failure, usage
from .runs import write_page
from .scenario import sets_of


@dataclass
class CampaignResult:
    out_dir: Path
    summary: dict            # campaign.json: statistics, requirements, failed runs
    outcome: object = None   # aocs_campaign.execute.Outcome of this call (None: read from a folder)

    @property
    def rows(self):
        """One row per run: index, status, error, repeat_command, the drawn inputs (in.*), every metric (m.*)."""
        return report_page.read_table(self.out_dir)

    @property
    def complete(self) -> bool:
        return bool(self.summary["complete"])

    @property
    def passed(self) -> bool:
        s = self.summary["status"]
        return self.complete and s["failed"] + s["error"] == 0

    def html(self, path) -> Path:
        return write_page(report_page.campaign_document(self.out_dir), path)


def default_out(c: P.Campaign) -> Path:
    return Path("out") / f"campaign-{Path(c.scenario).stem}-{c.law or 'default'}-s{c.seed}"


def check(c: P.Campaign, *, workers: int | None = None, scheduler: str | None = None,
          timeout: float | None = None) -> list:
    """The campaign's dispersions, or AocsError naming what is wrong (before anything runs)."""
    try:
        disps = P.check(c)
        if workers is not None and not 1 <= workers <= 256:
            raise P.CampaignError(f"--workers {workers}: must be in [1, 256]")
        if scheduler is not None:
            from aocs_campaign import scheduler_probe  # deferred: Dask only once the input is valid

            scheduler_probe.parse_address(scheduler)
        if workers is not None and scheduler:
            raise P.CampaignError("--workers: not with --scheduler (the cluster has its own workers)")
        if timeout is not None and not (timeout > 0 and timeout < 1e6):
            raise P.CampaignError(f"--timeout {timeout:g}: must be a number of seconds above 0")
    except (P.CampaignError, D.DispersionError, ScenarioError, ValueError) as exc:
        raise usage(exc) from None
    return disps


def run_campaign(c: P.Campaign, *, out=None, workers: int | None = None, scheduler: str | None = None,
                 keep_logs: bool = False, timeout: float | None = None, retry_errors: bool = False,
                 progress: bool = False, plots: bool = True, html=None, command: str | None = None,
                 commit: str | None = None) -> CampaignResult:
    """Flies the campaign's runs not yet in out and writes its results (aocs_campaign.report.build)."""
    from aocs_campaign import execute, report  # deferred: Dask and pyarrow only once the input is valid
    from aocs_campaign import worker as W  # deferred: see above

    disps = check(c, workers=workers, scheduler=scheduler, timeout=timeout)
    check_output_file("--html", html)
    folder = Path(out) if out is not None else default_out(c)
    why = None if scheduler is not None else W.netns_check()
    if why is not None:
        raise AocsError(f"cannot give each run a private network namespace: {why}")
    try:
        outcome = execute.run(c, disps, folder, workers=workers, scheduler=scheduler, keep_logs=keep_logs,
                              timeout_s=timeout, progress=progress, retry_errors=retry_errors)
        rows = execute.read_rows(folder, c.runs)
        doc = report.build(folder, c, rows, outcome=outcome, command=command, commit=commit, plots=plots)
    except P.CampaignError as exc:
        raise usage(exc) from None
    except OSError as exc:   # a full disk, a vanished folder: the machine's failure, not bad input
        raise io_failure(exc, folder, f"; what finished is kept in {folder}/runs/") from None
    res = CampaignResult(folder, doc, outcome)
    if html is not None:
        res.html(html)
    return res


def campaign(scenario, *, runs: int, seed: int, law: str | None = None, overrides: dict | None = None, sets=(),
             disperse=(), out=None, workers: int | None = None, keep_logs: bool = False, timeout: float | None = None,
             progress: bool = False, plots: bool = True, html=None, transport: str = "lcm",
             refly_every: int = P.REFLY_EVERY, faults: dict | None = None) -> CampaignResult:
    """`aocs campaign`: runs dispersed runs of scenario (disperse: "KEY=normal:MEAN:SIGMA" texts as --disperse);
    transport direct re-flies every refly_every-th run over LCM and compares; faults: a [campaign.faults] table
    (one injected fault per run, its kind and times drawn; docs/campaigns.md)."""
    try:
        name, s = sets_of(scenario, sets, overrides)
    except TypeError as exc:
        raise usage(exc) from None
    c = P.Campaign(name, law, int(runs), int(seed), s, list(disperse), transport=transport, refly_every=refly_every,
                   faults=faults)
    return run_campaign(c, out=out, workers=workers, keep_logs=keep_logs, timeout=timeout, progress=progress,
                        plots=plots, html=html)


def load_campaign(folder) -> CampaignResult:
    folder = Path(folder)
    try:
        return CampaignResult(folder, json.loads((folder / "campaign.json").read_text()))
    except (OSError, ValueError) as exc:
        raise AocsError(f"{folder / 'campaign.json'}: {exc}") from None
