"""The verdict's holds-missed check (aocs_analysis.verdict; docs/spec.md 5.11.2, docs/sil.md Verdict): a run
whose observation-plan holds or target passes miss their pointing requirement does not pass. The holds come
from aocs_analysis.holds on a synthetic pointing history whose misses are placed by hand here."""
from __future__ import annotations

import math

import numpy as np

from aocs_analysis import holds, verdict
from aocs_plant import load

PLAN = [{"euler321_deg": [14.0, 14.0, 14.0], "slew_s": 10.0, "hold_s": 20.0},
        {"euler321_deg": [30.0, -20.0, 1.0], "slew_s": 5.0, "hold_s": 15.0}]


def _clean():
    return {"law": "quat_pid", "timing": {"steps": 500},
            "counters": {"law_error": 0, "status": {}, "longest_unanswered_run": 0, "sensor_ticks_unanswered": 0},
            "limits": {"commands_over_limit": 0, "commands_not_finite": 0}}


def _holds(spike_arcsec: float, duration: float = 50.0):
    """holds.metrics of two observations, each settling from 5000 arcsec, with one sample of spike_arcsec in
    the second hold (0.3 arcsec requirement)."""
    sc = load("irassi_rw", {"target": None, "plan": PLAN, "duration_s": duration, "metrics.window_s": 10.0})
    t = np.round(np.arange(0, int(duration * 10) + 1) * 0.1, 10)
    ang = np.array([5000.0 * math.exp(-3.0 * (tk - (0.0 if tk < 30.0 else 30.0))) + 0.01 for tk in t])
    ang[(t >= 45.0) & (t < 45.05)] = spike_arcsec
    return holds.metrics(sc, {"t": t, "true_angle": ang}, ang < 10.0)


def test_a_run_whose_hold_misses_its_requirement_fails_and_names_it():
    hs = _holds(0.5)                                   # above 0.3 arcsec, inside the 10 arcsec settle band
    assert [h["meets_requirement"] for h in hs] == [True, False]
    v = verdict.judge({**_clean(), "holds": hs}, [], realtime=False)
    assert not v["passed"] and [f["check"] for f in v["failures"]] == ["holds-missed"]
    assert "1 of the 2 holds judged" in verdict.summary(v) and "hold 1" in verdict.summary(v)
    allowed = verdict.judge({**_clean(), "holds": hs}, [], realtime=False, allow=["holds-missed"])
    assert allowed["passed"] and allowed["allowed"] == ["holds-missed"]


def test_holds_that_meet_it_or_were_not_reached_pass():
    hs = _holds(0.2)
    assert [h["meets_requirement"] for h in hs] == [True, True]
    assert verdict.judge({**_clean(), "holds": hs}, [], realtime=False)["passed"]
    # a run ended in observation 1's slew: its hold has no samples, meets_requirement None, not judged
    short = _holds(0.2, duration=32.0)
    assert [h["meets_requirement"] for h in short] == [True, None]
    assert verdict.judge({**_clean(), "holds": short}, [], realtime=False)["passed"]
    assert verdict.judge({**_clean(), "holds": None}, [], realtime=False)["passed"]


def test_a_missed_target_pass_fails_too():
    passes = [{"target": {"name": "Kiruna"}, "start_s": 1200.0, "meets_requirement": True},
              {"target": {"name": "Svalbard"}, "start_s": 7000.4, "meets_requirement": False}]
    v = verdict.judge({**_clean(), "passes": passes}, [], realtime=False)
    assert [f["check"] for f in v["failures"]] == ["holds-missed"]
    assert "1 of the 2 target passes judged" in verdict.summary(v)
    assert "target pass Svalbard at 7000 s" in verdict.summary(v)
