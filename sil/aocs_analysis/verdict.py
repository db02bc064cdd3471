"""The verdict of one run: a run that did not do what was asked fails, with the reason.

A run fails (docs/sil.md, "Verdict") when any of these checks does, unless the
user allowed it on purpose (`aocs run --allow CHECK`, to study the case):

- incomplete-log: the log is damaged, lacks the recorder's end marker, or
  misses a sensor frame, a truth sample or (lockstep) a flight-computer reply:
  what was recorded is not the run that happened;
- unanswered: in real time, the flight computer left more than
  SILENCE_MAX_PERIODS consecutive sensor frames without a reply (frozen,
  crashed or starved): 1 s at 10 Hz, ten times the executive's default
  missing-sample threshold, far beyond scheduling jitter;
- law-refused: the selected law returned an error on every step (for example
  crp_linear at the Gibbs singularity): nothing was controlled by it;
- over-limit: a command exceeded the actuator limit or was not finite.
"""
from __future__ import annotations

CHECKS = ("incomplete-log", "unanswered", "law-refused", "over-limit")
#: consecutive unanswered sensor frames a real-time run tolerates (see above)
SILENCE_MAX_PERIODS = 10


def judge(metrics: dict, log_problems: list[str], *, realtime: bool, allow=()) -> dict:
    """{"passed", "failures": [{"check", "reason"}], "allowed": [checks that failed but were allowed]}."""
    allow = set(allow)
    failed: list[tuple[str, str]] = []
    if log_problems:
        failed.append(("incomplete-log", "the log is incomplete: " + "; ".join(log_problems)))
    c = metrics.get("counters") or {}
    silent = int(c.get("longest_unanswered_run", 0))
    if realtime and silent > SILENCE_MAX_PERIODS:
        failed.append(("unanswered", f"the flight computer left {silent} consecutive sensor frames unanswered "
                                     f"(more than {SILENCE_MAX_PERIODS}; {c.get('sensor_ticks_unanswered', 0)} "
                                     "in all)"))
    steps = int((metrics.get("timing") or {}).get("steps", 0))
    if metrics.get("law") not in (None, "none") and steps > 0 and int(c.get("law_error", 0)) >= steps:
        statuses = ", ".join(sorted((c.get("status") or {}).keys())) or "an error"
        failed.append(("law-refused", f"the law {metrics['law']} was refused on every one of the {steps} steps "
                                      f"({statuses})"))
    lim = metrics.get("limits") or {}
    over, nonfinite = int(lim.get("commands_over_limit", 0)), int(lim.get("commands_not_finite", 0))
    if over or nonfinite:
        failed.append(("over-limit", f"{over} commands above the actuator limit, {nonfinite} not finite"))
    return {"passed": all(check in allow for check, _ in failed),
            "failures": [{"check": k, "reason": r} for k, r in failed if k not in allow],
            "allowed": [k for k, _ in failed if k in allow]}


def summary(verdict: dict) -> str:
    """One line: why the run failed (empty when it passed)."""
    return "; ".join(f["reason"] for f in verdict["failures"])
