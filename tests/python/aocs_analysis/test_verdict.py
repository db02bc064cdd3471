"""The verdict of a run (aocs_analysis.verdict): each check fails on its own case, --allow lets it pass."""
from __future__ import annotations

from aocs_analysis import verdict


def _metrics(**over):
    m = {"law": "quat_pd", "timing": {"steps": 100},
         "counters": {"law_error": 0, "status": {}, "longest_unanswered_run": 0, "sensor_ticks_unanswered": 0},
         "limits": {"commands_over_limit": 0, "commands_not_finite": 0}}
    for k, v in over.items():
        m[k].update(v)
    return m


def test_a_clean_run_passes():
    v = verdict.judge(_metrics(), [], realtime=True)
    assert v == {"passed": True, "failures": [], "allowed": []} and verdict.summary(v) == ""


def test_each_check_fails_on_its_case():
    cases = {
        "incomplete-log": (_metrics(), ["log truncated: no end marker of the recorder"], False),
        "unanswered": (_metrics(counters={"longest_unanswered_run": verdict.SILENCE_MAX_PERIODS + 1}), [], True),
        "law-refused": (_metrics(counters={"law_error": 100, "status": {"AOCS_ERR_CRP_SINGULAR": 100}}), [], False),
        "over-limit": (_metrics(limits={"commands_over_limit": 1}), [], False),
    }
    for check, (m, problems, realtime) in cases.items():
        v = verdict.judge(m, problems, realtime=realtime)
        assert not v["passed"] and [f["check"] for f in v["failures"]] == [check], (check, v)
        allowed = verdict.judge(m, problems, realtime=realtime, allow=[check])
        assert allowed["passed"] and allowed["allowed"] == [check] and not allowed["failures"]
    assert "AOCS_ERR_CRP_SINGULAR" in verdict.summary(verdict.judge(*cases["law-refused"][:2], realtime=False))


def test_thresholds_are_where_they_are_stated():
    at_limit = _metrics(counters={"longest_unanswered_run": verdict.SILENCE_MAX_PERIODS})
    assert verdict.judge(at_limit, [], realtime=True)["passed"]
    # lockstep: the plant itself stops the run on a missing reply, so silence is not judged here
    assert verdict.judge(_metrics(counters={"longest_unanswered_run": 50}), [], realtime=False)["passed"]
    assert verdict.judge(_metrics(counters={"law_error": 99}), [], realtime=False)["passed"]
    assert verdict.judge(_metrics(limits={"commands_not_finite": 1}), [], realtime=False)["failures"]
    standby = _metrics(counters={"law_error": 100})
    standby["law"] = "none"
    assert verdict.judge(standby, [], realtime=False)["passed"]
