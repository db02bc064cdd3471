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
- over-limit: a command exceeded the actuator limit or was not finite: the body command u_sat
  against the flight software's limits and, with a [wheels] array, every wheel torque command
  u_wheels against that wheel's torque limit (u_s,max, [wheels] torque_limit_nm);
- non-finite: the plant's truth (q, w) or the pointing error is NaN or infinite somewhere: the
  simulation diverged, nothing after it means anything;
- unrequested-safe: the run ends in SAFE although no command of the run (scenario or --event,
  metrics["commands"]) asked for SAFE or STANDBY: the node gave up;
- invalid-inputs: the node rejected more than INVALID_MAX_FRACTION (1 %) of the steps' inputs as
  invalid, beyond the frames the run's own --event faults injected (each injected frame fault may
  cost one invalid input): a healthy run rejects none, a scripted fault a handful, 1 % is far above
  both and far below a diverged plant (the issue-25 run rejected 1795 of 2000);
- law-errors: the law returned an error on more than LAW_ERROR_MAX_FRACTION (1 %) of the steps
  (law-refused is the case "every step");
- fault-management: an injected fault (aocs_plant.faults, metrics["faults"]) was not handled: never detected
  where its kind expects a detection, no isolation where it expects one, or the pointing never back inside
  the requirement (aocs_analysis.faults); a run with faults the flight software cannot yet handle fails;
- integration-error: the plant's integration error exceeds its tolerance by more than
  INTEGRATION_MAX_FACTOR (100x): the truth itself is not trustworthy. Between 1x and 100x the run
  only warns (raise [integrator] substeps), as before;
- holds-missed: an observation the run judged against its pointing requirement missed it: a hold of the
  scenario's plan (`holds[].meets_requirement` false: not settled within its slew allowance, or its pointing
  beyond the figure it is held to, docs/spec.md 5.11.2) or a target pass (`passes[].meets_requirement`
  false, 5.11.4). A hold or pass the run did not reach (meets_requirement None) is not judged.
"""
from __future__ import annotations

import math

from .faults import not_handled as fault_reasons

CHECKS = ("incomplete-log", "unanswered", "law-refused", "over-limit", "non-finite", "unrequested-safe",
          "invalid-inputs", "law-errors", "integration-error", "holds-missed", "fault-management")
#: fraction of the steps whose input may be rejected as invalid / whose law may fail (see above)
INVALID_MAX_FRACTION = 0.01
LAW_ERROR_MAX_FRACTION = 0.01
#: how far above its tolerance the plant's integration error fails the run (see above)
INTEGRATION_MAX_FACTOR = 100.0
#: --event kinds that inject a frame fault (aocs_runner.events.KINDS)
FRAME_FAULTS = ("malformed", "foreign", "drop", "duplicate", "stale")
#: consecutive unanswered sensor frames a real-time run tolerates (see above)
SILENCE_MAX_PERIODS = 10


def _nonfinite(x) -> bool:
    try:
        return not math.isfinite(float(x))
    except (TypeError, ValueError):
        return False


def judge(metrics: dict, log_problems: list[str], *, realtime: bool, allow=(), injected: int = 0) -> dict:
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
    elif metrics.get("law") not in (None, "none") and int(c.get("law_error", 0)) > LAW_ERROR_MAX_FRACTION * steps:
        failed.append(("law-errors", f"the law failed on {c['law_error']} of the {steps} steps (more than "
                                     f"{LAW_ERROR_MAX_FRACTION:.0%})"))
    lim = metrics.get("limits") or {}
    over, nonfinite = int(lim.get("commands_over_limit", 0)), int(lim.get("commands_not_finite", 0))
    if over or nonfinite:
        failed.append(("over-limit", f"{over} body commands above the actuator limit, {nonfinite} not finite"))
    w = metrics.get("wheels") or {}
    wover, wnan = int(w.get("commands_over_limit", 0)), int(w.get("commands_not_finite", 0))
    if wover or wnan:
        failed.append(("over-limit", f"{wover} wheel torque commands above the wheel's torque limit, "
                                     f"{wnan} not finite"))
    truth_bad = int(metrics.get("truth_not_finite", 0))
    pe = metrics.get("pointing_error_arcsec") or {}
    pe_bad = metrics.get("kind", "attitude") == "attitude" and metrics.get("pointing_error_arcsec") is not None \
        and any(pe.get(k) is None or _nonfinite(pe.get(k)) for k in ("initial", "final_max", "final_rms"))
    if truth_bad or pe_bad:
        failed.append(("non-finite", f"the plant diverged: {truth_bad} truth samples with a non-finite q or w"
                                     + (", the pointing error is not finite" if pe_bad else "")))
    if metrics.get("final_mode") == "safe":
        if not any(cm.get("mode_name") in ("safe", "standby") for cm in metrics.get("commands") or []):
            failed.append(("unrequested-safe", "the node ended in SAFE although no command asked for it "
                                               f"({c.get('safe_entries', 0)} SAFE entries)"))
    invalid = int(c.get("invalid", 0))
    if steps > 0 and invalid > INVALID_MAX_FRACTION * steps + injected:
        failed.append(("invalid-inputs", f"{invalid} of the {steps} inputs were rejected as invalid (more than "
                                         f"{INVALID_MAX_FRACTION:.0%}" + (f" plus the {injected} injected frame faults"
                                                                          if injected else "") + ")"))
    ie = metrics.get("integration_error") or {}
    for unit in ("arcsec", "m"):
        key = "attitude_arcsec" if unit == "arcsec" else "position_m"
        tol, err = ie.get("tolerance_" + unit), ie.get(key + "_sum")
        if tol is None or key + "_sum" not in ie:
            continue
        if err is None or _nonfinite(err) or float(err) > INTEGRATION_MAX_FACTOR * float(tol):
            failed.append(("integration-error", f"the plant's integration error {err if err is not None else 'nan'}"
                                                f" {unit} is more than {INTEGRATION_MAX_FACTOR:g} times its "
                                                f"tolerance {tol:g} {unit}"))
    missed = _missed_observations(metrics)
    if missed:
        failed.append(("holds-missed", "; ".join(missed)))
    unhandled = fault_reasons(metrics.get("faults"))
    if unhandled:
        failed.append(("fault-management", "injected faults not handled: " + "; ".join(unhandled)))
    return {"passed": all(check in allow for check, _ in failed),
            "failures": [{"check": k, "reason": r} for k, r in failed if k not in allow],
            "allowed": [k for k, _ in failed if k in allow]}


def _missed_observations(metrics: dict) -> list[str]:
    """One phrase per section (holds, passes) with an entry whose meets_requirement is False."""
    out = []
    for key, noun, nouns, name in (("holds", "hold", "holds", lambda e: str(e["target"]["index"])),
                                   ("passes", "target pass", "target passes",
                                    lambda e: f"{e['target']['name']} at {e['start_s']:.0f} s")):
        entries = metrics.get(key) or []
        judged = [e for e in entries if e.get("meets_requirement") is not None]
        missed = [e for e in judged if e["meets_requirement"] is False]
        if missed:
            shown = ", ".join(name(e) for e in missed[:5]) + (", ..." if len(missed) > 5 else "")
            out.append(f"{len(missed)} of the {len(judged)} {nouns} judged missed their pointing requirement "
                       f"({noun} {shown})")
    return out


def summary(verdict: dict) -> str:
    """One line: why the run failed (empty when it passed)."""
    return "; ".join(f["reason"] for f in verdict["failures"])
