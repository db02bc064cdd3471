"""The flight software's fault-management events of a run (issue 26; docs/spec.md 5.15): the event_t messages
recorded on AOCS_EVENTS (sil/lcmtypes/event_t.lcm) as the run JSON's `events` list, names from the build's
event table (firmware/include/aocs/fdir/events.def through the registry JSON, never a hand copy).

Each entry: {"t_s", "seq", "id", "name", "severity" (its name), "unit_kind" (its name), "unit" (None for -1),
"value", "threshold"}, in sequence order, each seq once (a message recorded twice is one event).
"""
from __future__ import annotations

import math

import numpy as np

from aocs_core import registry

#: severities at or above this one are alarms (the false-alarm count of a nominal run)
ALARM_SEVERITY = "warning"


def _num(x) -> float | None:
    x = float(x)
    return x if math.isfinite(x) else None


def events(log) -> list[dict]:
    """The run's events from log.fault_events (aocs_wire.lcmlog), in seq order."""
    tab = getattr(log, "fault_events", None) or {}
    if not tab or len(tab.get("seq", ())) == 0:
        return []
    reg = registry.load()
    seq = np.asarray(tab["seq"], dtype=np.int64)
    _, first = np.unique(seq, return_index=True)       # sorted by seq, each once
    out = []
    for i in first.tolist():
        eid = int(tab["id"][i])
        row = reg.events.get(eid)
        unit = int(tab["unit"][i])
        out.append({
            "t_s": _num(tab["t_s"][i]),
            "seq": int(seq[i]),
            "id": eid,
            "name": row.name if row is not None else f"event {eid}",
            "severity": registry.event_severity_name(int(tab["severity"][i])),
            "unit_kind": registry.event_unit_kind_name(int(tab["unit_kind"][i])),
            "unit": None if unit < 0 else unit,
            "value": _num(tab["value"][i]),
            "threshold": _num(tab["threshold"][i]),
        })
    return out


def alarms(evs: list[dict], before_s: float | None = None) -> int:
    """Events of severity warning or above; with before_s, only those before it (t_s < before_s)."""
    reg = registry.load()
    rank = {name: value for value, name in reg.event_severities.items()}
    floor = rank.get(ALARM_SEVERITY, 1)
    return sum(1 for e in evs if rank.get(e["severity"], 0) >= floor and (before_s is None or e["t_s"] < before_s))


def false_alarms(evs: list[dict], fault_starts_s) -> int:
    """Alarms raised before the first injected fault (every alarm of a run without one): nothing had failed,
    so each is a false alarm (docs/spec.md 5.15.7)."""
    starts = [float(s) for s in fault_starts_s]
    return alarms(evs, min(starts) if starts else None)
