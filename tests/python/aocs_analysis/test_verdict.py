"""The verdict of a run (aocs_analysis.verdict): each check fails on its own case, --allow lets it pass."""
from __future__ import annotations

import math

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
    # 99 of 100 is not "every step" (law-refused) but far more than 1 % (law-errors)
    most = verdict.judge(_metrics(counters={"law_error": 99}), [], realtime=False)
    assert [f["check"] for f in most["failures"]] == ["law-errors"]
    assert verdict.judge(_metrics(limits={"commands_not_finite": 1}), [], realtime=False)["failures"]
    standby = _metrics(counters={"law_error": 100})
    standby["law"] = "none"
    assert verdict.judge(standby, [], realtime=False)["passed"]
    # no control step at all: no law was refused (the law-refused check needs at least one step)
    no_steps = verdict.judge(_metrics(timing={"steps": 0}), [], realtime=False)
    assert "law-refused" not in [f["check"] for f in no_steps["failures"]]


def _diverged(**extra):
    m = _metrics()
    m.update(extra)
    return m


def test_a_run_that_did_not_fly_fails_with_its_reason():
    """issue 25, item 3: each of these failed to fail before."""
    cases = {
        "non-finite": _diverged(truth_not_finite=5),
        "unrequested-safe": _diverged(final_mode="safe", commands=[{"mode": -1, "mode_name": None}]),
        "invalid-inputs": _diverged(counters={"invalid": 2, "law_error": 0, "status": {},
                                              "longest_unanswered_run": 0}),
        "law-errors": _diverged(counters={"invalid": 0, "law_error": 2, "status": {},
                                          "longest_unanswered_run": 0}),
        "integration-error": _diverged(integration_error={"attitude_arcsec_sum": 1e9, "tolerance_arcsec": 1.0}),
        "over-limit": _diverged(wheels={"commands_over_limit": 0, "commands_not_finite": 3}),
    }
    for check, m in cases.items():
        v = verdict.judge(m, [], realtime=False)
        assert not v["passed"] and [f["check"] for f in v["failures"]] == [check], (check, v)
        assert "\n" not in verdict.summary(v) and verdict.summary(v)
        assert verdict.judge(m, [], realtime=False, allow=[check])["passed"]
    nan_pointing = _diverged(pointing_error_arcsec={"initial": 10.0, "final_max": None, "final_rms": None})
    assert [f["check"] for f in verdict.judge(nan_pointing, [], realtime=False)["failures"]] == ["non-finite"]
    # an integration error that is not a number (NaN, or null in the metrics JSON) fails like a huge one
    for err in (float("nan"), None):
        ie = _diverged(integration_error={"attitude_arcsec_sum": err, "tolerance_arcsec": 1.0})
        assert [f["check"] for f in verdict.judge(ie, [], realtime=False)["failures"]] == ["integration-error"]


def test_requested_safe_injected_faults_and_small_errors_pass():
    assert verdict.judge(_diverged(final_mode="safe", commands=[{"mode": 2, "mode_name": "safe"}]), [],
                         realtime=False)["passed"]
    one_pct = _diverged(counters={"invalid": 1, "law_error": 1, "status": {}, "longest_unanswered_run": 0})
    assert verdict.judge(one_pct, [], realtime=False)["passed"]
    injected = _diverged(counters={"invalid": 4, "law_error": 0, "status": {}, "longest_unanswered_run": 0})
    assert not verdict.judge(injected, [], realtime=False)["passed"]
    assert verdict.judge(injected, [], realtime=False, injected=3)["passed"]
    ie = {"attitude_arcsec_sum": 50.0, "tolerance_arcsec": 1.0}
    assert verdict.judge(_diverged(integration_error=ie), [], realtime=False)["passed"]   # only a warning
    # the factor is a bound: an error of exactly INTEGRATION_MAX_FACTOR tolerances passes, one ulp more fails
    edge = verdict.INTEGRATION_MAX_FACTOR * 0.5
    for err, passed in ((edge, True), (math.nextafter(edge, math.inf), False)):
        ie = {"attitude_arcsec_sum": err, "tolerance_arcsec": 0.5}
        assert verdict.judge(_diverged(integration_error=ie), [], realtime=False)["passed"] is passed, err
