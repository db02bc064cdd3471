"""A campaign folder belongs to one campaign (issue 25, item 4): its identity is recorded in
campaign-plan.json and checked before anything resumes into it; a folder whose plan is missing or
corrupt while it holds rows is refused (it cannot be told whose rows they are); a row file that is
unreadable, corrupt, empty (`{}`) or not this run's is flown again, never counted as done, and never
a traceback, with or without --retry-errors."""
from __future__ import annotations

import json
import os
import subprocess
import sys

import pytest

from aocs_campaign import execute as E
from aocs_campaign import plan as P

SHORT = ["duration_s=20.0"]


def _campaign(**kw):
    d = {"scenario": "irassi_large", "law": "quat_pd", "runs": 4, "seed": 5, "sets": list(SHORT),
         "disperse": ["plant.w0=normal:0:1e-4"]}
    d.update(kw)
    return P.Campaign(d["scenario"], d["law"], d["runs"], d["seed"], d["sets"], d["disperse"])


def _row(i, status="passed"):
    return {"index": i, "status": status, "error": None if status == "passed" else "boom", "metrics": {},
            "series": None, "wall_s": 1.0, "worker_pid": 1, "inputs": {}, "overrides": {}}


def _write_rows(out, rows):
    E.runs_dir(out).mkdir(parents=True, exist_ok=True)
    for i, text in rows.items():
        E.row_path(out, i).write_text(text if isinstance(text, str) else json.dumps(text))


def test_identity_recorded_and_another_campaign_refused(tmp_path):
    c = _campaign()
    E.prepare_dir(c, tmp_path)
    plan = json.loads((tmp_path / "campaign-plan.json").read_text())
    for k in ("fingerprint", "scenario", "scenario_sha256", "law", "seed", "sets", "disperse", "runs"):
        assert k in plan, k
    E.prepare_dir(_campaign(runs=9), tmp_path)            # more runs of the same campaign: the same folder
    for other in (_campaign(seed=6), _campaign(law="quat_pid"), _campaign(disperse=[]),
                  _campaign(sets=["duration_s=30.0"]), _campaign(scenario="irassi_small")):
        with pytest.raises(P.CampaignError, match="holds another campaign"):
            E.prepare_dir(other, tmp_path)


def test_the_scenario_file_s_content_is_part_of_the_identity(tmp_path):
    from aocs_plant import scenario as scmod

    src = scmod.resolve("irassi_large").read_text()
    f = tmp_path / "mine.toml"
    f.write_text(src)
    out = tmp_path / "mc"
    E.prepare_dir(_campaign(scenario=str(f)), out)
    f.write_text(src + "\n# edited\n")
    E.prepare_dir(_campaign(scenario=str(f)), out)        # a comment does not change the rows
    assert "\nseed = 0\n" in src
    f.write_text(src.replace("\nseed = 0\n", "\nseed = 1\n", 1))   # the same path, other rows
    with pytest.raises(P.CampaignError, match="holds another campaign"):
        E.prepare_dir(_campaign(scenario=str(f)), out)


@pytest.mark.parametrize("plan_text", [None, "", "{not json", "{}", "[]", '{"fingerprint": 3}', "\x00\xff"])
def test_rows_without_a_readable_plan_are_refused(tmp_path, plan_text):
    _write_rows(tmp_path, {0: _row(0), 1: _row(1)})
    if plan_text is not None:
        (tmp_path / "campaign-plan.json").write_bytes(plan_text.encode("latin-1"))
    with pytest.raises(P.CampaignError, match="campaign-plan.json") as exc:
        E.prepare_dir(_campaign(), tmp_path)
    assert "\n" not in str(exc.value)
    assert not plan_text or (tmp_path / "campaign-plan.json").read_bytes() == plan_text.encode("latin-1")


def test_a_folder_without_rows_may_be_taken_even_with_a_broken_plan(tmp_path):
    (tmp_path / "campaign-plan.json").write_text("{broken")
    E.prepare_dir(_campaign(), tmp_path)
    assert json.loads((tmp_path / "campaign-plan.json").read_text())["fingerprint"] == _campaign().fingerprint()


def test_corrupt_empty_or_foreign_rows_are_not_done(tmp_path):
    c = _campaign(runs=8)
    E.prepare_dir(c, tmp_path)
    _write_rows(tmp_path, {0: _row(0), 1: "{}", 2: "{\"index\": 2, \"stat", 3: "", 4: _row(7),
                           5: _row(5, "error"), 6: "[1, 2]", 7: {"index": 7, "status": "maybe"}})
    E.row_path(tmp_path, 3).chmod(0)                      # unreadable (root reads it anyway: then it is empty)
    assert E.finished_indices(tmp_path) == {0, 5}
    assert E.resumable(tmp_path, range(8), retry_errors=False) == {0, 5}
    assert E.resumable(tmp_path, range(8), retry_errors=True) == {0}
    rows = E.read_rows(tmp_path, 8)
    assert [r["index"] for r in rows] == [0, 5]


def test_cli_refuses_a_folder_with_rows_and_no_plan_in_one_line(tmp_path):
    out = tmp_path / "mc"
    _write_rows(out, {0: _row(0)})
    p = subprocess.run([sys.executable, "-m", "aocs.cli", "campaign", "irassi_large", "--runs", "2", "--seed", "1",
                        "--scheduler", "tcp://127.0.0.1:9", "--out", str(out), "-q"],
                       capture_output=True, text=True, timeout=120, env={**os.environ, "AOCS_CAMPAIGN_USERNS": "1"})
    lines = p.stderr.strip().splitlines()
    assert p.returncode == 2, p.stderr
    assert len(lines) == 1 and "campaign-plan.json" in lines[0] and lines[0].startswith("aocs campaign: error:")
    assert not (out / "campaign-plan.json").exists()
