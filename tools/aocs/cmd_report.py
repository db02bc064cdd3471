"""`aocs report FOLDER --html FILE`: the interactive page (one self-contained HTML file) of a run, comparison or
campaign folder, rebuilt from the files it holds (aocs_api.report; docs/reports.md)."""
from __future__ import annotations

import sys

from aocs_api import AocsError
from aocs_api import report as api_report  # the function (aocs_api.reports.report)

EXIT_OK, EXIT_USAGE = 0, 2


def add_arguments(p) -> None:
    p.add_argument("folder", metavar="RUN_OR_CAMPAIGN_FOLDER",
                   help="a run folder (aocs run --out), a comparison folder (aocs compare --out) or a campaign folder")
    p.add_argument("--html", metavar="FILE", required=True, help="the page to write")


def run(args) -> int:
    try:
        path = api_report(args.folder, args.html)
    except AocsError as exc:
        print(exc.line("report"), file=sys.stderr)
        return exc.exit_code
    size = path.stat().st_size
    print(f"report: {path} ({size / 1e6:.2f} MB)")
    return EXIT_OK
