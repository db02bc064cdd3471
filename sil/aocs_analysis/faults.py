"""The run JSON's `faults` list (issue 26; docs/spec.md 5.14.7): each injected fault joined with the flight
software's event log and the pointing error.

For each injected fault (aocs_plant.faults: kind, unit, start_s, end_s) and the run's `events` (the event log:
{"t_s", "id", "name", "severity" (info, warning, error, critical), "unit_kind", "unit", ...}):

- detected_s: the time of the first event at or after start_s of the fault's unit kind (catalogue: the kind the
  flight software isolates), of the same unit index where both the fault and the event have one (an event unit
  of -1 or none has none), with severity warning or above, or an event the catalogue lists in the kind's
  detected_by (the thrusters: momentum_inconsistent, which names no unit, and a stuck-open thruster's
  thruster_stuck_open, which may name its twin); None if none. An event of that kind before start_s
  is not a detection (it is counted in events_before_start: a false alarm, or an earlier fault's);
- isolated: an isolation event (ISOLATIONS: st_excluded, gyro_excluded, wheel_isolated,
  unload_actuator_switched, thruster_isolated) of that unit kind and unit at or after start_s;
- recovered_s: the first time t >= detected_s from which the true pointing error stays at or below the
  scenario's recovery figure ([metrics] recovery_arcsec, else requirement_arcsec, else [settle]
  pointing_arcsec_max) for the settle window
  ([metrics] window_s), or up to the end of the run when that comes first; a kind whose detection is not expected
  (st_outage: the sensor flags itself) is measured from start_s when not detected. None if never;
- detection_latency_s = detected_s - start_s; recovery_time_s = recovered_s - detected_s (from start_s when
  measured from there);
- handled: detected (where the catalogue expects a detection), isolated (where it expects an isolation) and
  recovered. The verdict's fault-management check fails a run with a fault that is not handled.
"""
from __future__ import annotations

import numpy as np

from aocs_core.fault_catalogue import KINDS

SEVERITIES = ("info", "warning", "error", "critical")
#: the event names that isolate a unit (the contract of issue 26; their unit kind is the event's own)
ISOLATIONS = ("st_excluded", "gyro_excluded", "wheel_isolated", "unload_actuator_switched", "thruster_isolated")


def _severity(e) -> int:
    s = e.get("severity")
    if isinstance(s, str):
        return SEVERITIES.index(s) if s in SEVERITIES else -1
    return int(s) if s is not None else -1


def _unit(u):
    return None if u is None or int(u) < 0 else int(u)


def _matches(e, unit_kind: str, unit) -> bool:
    if e.get("unit_kind") != unit_kind:
        return False
    eu = _unit(e.get("unit"))
    return unit is None or eu is None or eu == unit


def _as_dict(f) -> dict:
    return f.to_json() if hasattr(f, "to_json") else dict(f)


def recovered_at(t, pointing_arcsec, t_from: float, requirement: float, window_s: float):
    """The first time t_r >= t_from from which pointing <= requirement holds for window_s, or to the end of the
    run when that comes first; None if never."""
    t = np.asarray(t, float)
    inside = np.asarray(pointing_arcsec, float) <= requirement
    idx = np.flatnonzero(t >= t_from - 1e-9)
    if idx.size == 0:
        return None
    i = int(idx[0])
    n = t.size
    while i < n:
        if not inside[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and inside[j + 1]:
            j += 1
        if j == n - 1 or t[j] - t[i] >= window_s - 1e-9:   # inside for the window, or to the end of the run
            return float(t[i])
        i = j + 1
    return None


def entry(fault, events: list, t, pointing_arcsec, requirement: float | None, window_s: float) -> dict:
    """The run JSON entry of one injected fault (a Fault or its JSON form)."""
    f = _as_dict(fault)
    kind = KINDS[f["kind"]]
    start = float(f["start_s"])
    unit = kind.isolation_unit(f.get("unit"))
    uk = kind.isolate_kind
    mine = [e for e in events if _matches(e, uk, unit)]
    warn = [e for e in mine + [e for e in events if e.get("name") in kind.detected_by] if _severity(e) >= 1]
    det = min((float(e["t_s"]) for e in warn if float(e["t_s"]) >= start - 1e-9), default=None)
    iso = any(e.get("name") in ISOLATIONS and float(e["t_s"]) >= start - 1e-9 for e in mine)
    before = sum(1 for e in warn if float(e["t_s"]) < start - 1e-9)
    ref = det if det is not None else (None if kind.detect_expected else start)
    rec = None
    if ref is not None and requirement is not None and len(t):
        rec = recovered_at(t, pointing_arcsec, ref, requirement, window_s)
    handled = ((det is not None or not kind.detect_expected) and (iso or not kind.isolate_expected)
               and (rec is not None or requirement is None))
    return {"kind": f["kind"], "unit": f.get("unit"), "start_s": start, "end_s": float(f["end_s"]),
            "detected_s": det, "isolated": bool(iso), "recovered_s": rec,
            "detection_latency_s": None if det is None else det - start,
            "recovery_time_s": None if rec is None else rec - ref,
            "unit_kind": uk, "detection_expected": kind.detect_expected,
            "isolation_expected": kind.isolate_expected, "events_before_start": before, "handled": bool(handled)}


def entries(faults, events, t, pointing_arcsec, requirement: float | None, window_s: float) -> list[dict]:
    """The run JSON `faults` list: one entry per injected fault, in the order they were given."""
    ev = sorted(events or [], key=lambda e: float(e["t_s"]))
    return [entry(f, ev, t, pointing_arcsec, requirement, window_s) for f in faults or ()]


def requirement_of(sc) -> float | None:
    """The pointing a recovery is judged against (arcsec): [metrics] recovery_arcsec (what the scenario's sensors
    reach, where that is short of the requirement), else the requirement, else the settle criterion."""
    rec = getattr(sc.metrics, "recovery_arcsec", None)
    if rec is not None:
        return rec
    req = sc.metrics.requirement_arcsec
    return req if req is not None else getattr(sc.settle, "pointing_arcsec_max", None)


def not_handled(faults: list[dict]) -> list[str]:
    """Why each fault that is not handled is not (the verdict's fault-management reasons)."""
    out = []
    for f in faults or ():
        if f.get("handled", True):
            continue
        what = f"{f['kind']}" + (f" unit {f['unit']}" if f.get("unit") is not None else "") + f" at {f['start_s']:g} s"
        why = []
        if f["detection_expected"] and f["detected_s"] is None:
            why.append("never detected")
        if f["isolation_expected"] and not f["isolated"]:
            why.append(f"no {f['unit_kind']} isolated")
        if f["recovered_s"] is None and not why:
            why.append("pointing never back inside the requirement")
        elif f["recovered_s"] is None:
            why.append("not recovered")
        out.append(f"{what}: {', '.join(why)}")
    return out


def _t(x) -> str:
    return "never" if x is None else f"{x:.1f} s"


def table_rows(faults: list[dict]) -> list[tuple[str, str]]:
    """The run summary's lines: one per injected fault with its times."""
    rows = []
    for i, f in enumerate(faults or ()):
        unit = f" {f['unit_kind']} {f['unit']}" if f.get("unit") is not None else ""
        det = _t(f["detected_s"]) + (f" (latency {f['detection_latency_s']:.2f} s)"
                                     if f["detection_latency_s"] is not None else "")
        rec = _t(f["recovered_s"]) + (f" ({f['recovery_time_s']:.1f} s after)" if f["recovery_time_s"] is not None
                                      else "")
        rows.append((f"fault {i + 1}: {f['kind']}{unit}",
                     f"{f['start_s']:g} to {f['end_s']:g} s; detected {det}; isolated "
                     f"{'yes' if f['isolated'] else 'no'}; recovered {rec}; "
                     + ("handled" if f["handled"] else "NOT handled")))
    return rows
