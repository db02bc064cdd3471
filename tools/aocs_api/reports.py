"""`aocs report FOLDER --html FILE`: the page of a run, compare or campaign folder, from the files it holds."""
from __future__ import annotations

from pathlib import Path

from aocs_compare import report_page as compare_page
from aocs_plant.scenario import ScenarioError
from aocs_report import run_report

from .errors import AocsError, check_output_file
from .runs import write_page

KINDS = ("run", "compare", "campaign")


def kind_of(folder: Path) -> str:
    """Which results the folder holds: campaign.json (a campaign), compare-plan.json (a comparison), run.json and
    metrics.json (a run)."""
    if not folder.is_dir():
        raise AocsError(f"{folder}: no such folder")
    if (folder / "campaign.json").is_file():
        return "campaign"
    if (folder / compare_page.PLAN_FILE).is_file():
        return "compare"
    if (folder / "run.json").is_file() and (folder / "metrics.json").is_file():
        return "run"
    raise AocsError(f"{folder}: not a run folder (run.json, metrics.json), a comparison folder "
                    f"({compare_page.PLAN_FILE}) or a campaign folder (campaign.json)")


def document(folder) -> tuple[str, object]:
    """(kind, Document) of the folder's page."""
    from aocs_campaign import report_page as campaign_page  # deferred: pyarrow and Dask's modules for a campaign only

    folder = Path(folder)
    kind = kind_of(folder)
    build = {"run": run_report.run_document, "compare": compare_page.compare_document,
             "campaign": campaign_page.campaign_document}[kind]
    try:
        return kind, build(folder)
    except (run_report.ReportError, ScenarioError, KeyError, ValueError) as exc:
        raise AocsError(f"{folder}: {exc}" if str(folder) not in str(exc) else str(exc)) from None


def report(folder, html) -> Path:
    """Writes the page of a run, compare or campaign folder to html (one self-contained file)."""
    check_output_file("--html", html)
    _, doc = document(folder)
    return write_page(doc, html)
