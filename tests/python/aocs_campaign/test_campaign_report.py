"""aocs_campaign.report's page: built through the document model (aocs_report), the committed
campaign's report.md comes back word for word from its campaign.json, and the parts only a
failing or interrupted campaign has are there when they should be."""
from __future__ import annotations

import copy
import json
from pathlib import Path

import pytest

from aocs_campaign import report
from aocs_plant.scenario import load
from aocs_report import html
from aocs_runner import scenario_opts

CAMPAIGN = Path(__file__).resolve().parents[3] / "docs" / "campaigns" / "irassi_large-quat_pd-0.5Nm-slew"


@pytest.fixture(scope="module")
def committed():
    doc = json.loads((CAMPAIGN / "campaign.json").read_text())
    sc = load(doc["campaign"]["scenario"], scenario_opts.parse_sets(doc["campaign"]["sets"]))
    return doc, sc


def test_committed_report_regenerates_word_for_word(committed):
    doc, sc = committed
    assert report.report_md(doc, sc) == (CAMPAIGN / "report.md").read_text()


def test_failed_and_interrupted_campaign(committed):
    doc, sc = copy.deepcopy(committed[0]), committed[1]
    doc["complete"] = False
    doc["failed_runs"] = [{"index": i, "status": "error", "error": f"boom {i}\nmore", "repeat_command": f"aocs run x {i}"}
                          for i in range(report.FAILED_LISTED + 3)]
    md = report.report_md(doc, sc)
    assert "the campaign is INCOMPLETE" in md
    assert f"{report.FAILED_LISTED + 3} runs (logs kept in `runs/NNNNNN/`; the first {report.FAILED_LISTED} listed):" in md
    assert "- run 0 (error): boom 0\n  repeat: `aocs run x 0`\n" in md and "more" not in md
    assert f"run {report.FAILED_LISTED - 1} (error)" in md and f"run {report.FAILED_LISTED} (error)" not in md


def test_the_same_document_as_a_self_contained_page(committed):
    doc, sc = committed
    page = html.render(report.report_document(doc, sc), base=CAMPAIGN)
    assert page.count("data:image/png;base64,") == len(doc["plots"])
    assert "<h2>Requirements</h2>" in page and "Wilson score interval" in page


def test_false_alarms_are_counted_over_the_runs_and_fail_the_requirement(committed):
    def row(i, n):
        return {"index": i, "status": "passed", "metrics": None if n is None else {
            "events_false_alarms": n, "verdict": {"passed": True}, "settle_time_s": 1.0,
            "limits": {"commands_over_limit": 0, "commands_not_finite": 0}}}
    rows = [row(0, 0), row(1, 2), row(2, 0), row(3, None), row(4, 1)]
    fa = report.false_alarm_summary(rows)
    assert fa == {"runs": 4, "alarms": 3, "runs_with_alarm": [1, 4]}
    req = report.requirements(rows, None, None)["no_false_alarm"]
    # a run without metrics does not pass; 0 and 2 do
    assert req["passed"] == 2 and req["n"] == 5
    doc, sc = copy.deepcopy(committed[0]), committed[1]
    doc["false_alarms"] = fa
    assert "False alarms (fault management's warnings and above before any injected fault): 3 over 4 runs, " \
           "in 2 runs." in report.report_md(doc, sc)
