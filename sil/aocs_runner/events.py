"""Scheduled events of a run: ground commands and transport faults.

`aocs run --event SPEC` (repeatable); plant_node carries them out at the
first control tick whose time t_k >= T, BEFORE that tick's sensor message, so
in lockstep they are deterministic and a replay of the log reproduces them.

    T:law=NAME|ID           command_t selecting a law (an unknown name or
                            id is sent as is: the node must refuse it)
    T:mode=standby|nominal|safe|ID
    T:target=q1,q2,q3,q4    command_t with set_target (wd = 0)
    T:malformed             garbage bytes on AOCS_SENSORS (n_malformed)
    T:foreign               a sensors_t with protocol_version 99 (n_foreign)
    T:drop                  this tick's sensors_t is not sent (n_lost, n_missing;
                            the plant holds the previous command)
    T:duplicate             this tick's sensors_t is sent twice (n_duplicate)
    T:stale                 this tick's sensors_t carries the previous tick's time
                            stamp t_s (time not advancing: n_stale, safe mode)

T is in seconds of simulation time.

An injected link_drop_burst fault (aocs_plant.faults.link; [[faults]], --fault) is carried out by the same
`drop` at every tick of its interval (fault_events).
"""
from __future__ import annotations

import math
from dataclasses import dataclass

from aocs_core import registry
from aocs_core.modes import mode_value, mode_values
from aocs_core.ticks import first_tick
from aocs_plant.faults.fault import Fault
from aocs_plant.faults.link import drop_ticks

KINDS = ("law", "mode", "target", "malformed", "foreign", "drop", "duplicate", "stale")
#: law id sent for a law name the flight software does not know
UNKNOWN_LAW_ID = 99


class EventError(ValueError):
    pass


@dataclass(frozen=True)
class Event:
    t: float
    kind: str
    law_id: int = -1
    mode: int = -1
    target: tuple | None = None
    text: str = ""

    @property
    def is_command(self) -> bool:
        return self.kind in ("law", "mode", "target")


def parse(spec: str) -> Event:
    if ":" not in spec:
        raise EventError(f"--event {spec!r}: expected T:what (e.g. 10:law=smc, 5:malformed)")
    ts, what = spec.split(":", 1)
    try:
        t = float(ts)
    except ValueError:
        raise EventError(f"--event {spec!r}: time {ts!r} is not a number") from None
    if not (math.isfinite(t) and t >= 0.0):
        raise EventError(f"--event {spec!r}: time must be >= 0")
    key, _, val = what.partition("=")
    key = key.strip()
    if key not in KINDS:
        raise EventError(f"--event {spec!r}: unknown event {key!r} (one of {', '.join(KINDS)})")
    if key == "law":
        v = val.strip()
        if v.lstrip("-").isdigit():
            law_id = int(v)
        else:
            law_id = registry.law_ids().get(v, UNKNOWN_LAW_ID)
        return Event(t, key, law_id=law_id, text=spec)
    if key == "mode":
        v = val.strip()
        if v.lstrip("-").isdigit():
            mode = int(v)
        elif v in mode_values():
            mode = mode_value(v)
        else:
            raise EventError(f"--event {spec!r}: mode must be {', '.join(mode_values())} or a number")
        return Event(t, key, mode=mode, text=spec)
    if key == "target":
        try:
            q = tuple(float(x) for x in val.split(","))
        except ValueError:
            raise EventError(f"--event {spec!r}: target must be 4 numbers q1,q2,q3,q4") from None
        if len(q) != 4:
            raise EventError(f"--event {spec!r}: target must be 4 numbers q1,q2,q3,q4")
        # sent as given (a non-unit target is a legitimate fault to inject)
        return Event(t, key, target=q, text=spec)
    if val:
        raise EventError(f"--event {spec!r}: {key} takes no value")
    return Event(t, key, text=spec)


def plan_events(sc) -> list[Event]:
    """The observation plan's commands (docs/scenarios.md [[plan]]): a set_target of observation i >= 1 at its
    command time T_i (observation 0 is the flight software's initial target), those inside the run only."""
    plan = getattr(sc, "plan", None)
    if plan is None:
        return []
    return [Event(t, "target", target=tuple(ob.qd), text=f"plan[{i}]")
            for i, (t, ob) in enumerate(zip(plan.command_times_s, plan.observations))
            if i > 0 and first_tick(t, sc.dt) < sc.n_steps]


def parse_all(specs) -> list[Event]:
    return sorted((parse(s) for s in specs or ()), key=lambda e: e.t)


def schedule(events: list[Event], dt: float, n_steps: int, start_tick: int = 0) -> dict[int, list[Event]]:
    """tick -> events fired before that tick's sensors (first tick with t_k >= T)."""
    out: dict[int, list[Event]] = {}
    for e in events:
        k = max(start_tick, first_tick(e.t, dt))
        if k >= start_tick + n_steps:
            raise EventError(f"--event {e.text!r}: t = {e.t} s is after the end of the run")
        out.setdefault(k, []).append(e)
    return out


def _as_fault(f) -> Fault:
    """A Fault, or its run-JSON form ({"kind", "start_s", "end_s", ...}: run.json "faults")."""
    if isinstance(f, Fault):
        return f
    return Fault(f["kind"], f.get("unit"), float(f["start_s"]), float(f["end_s"]))


def fault_events(faults, dt: float, n_steps: int, start_tick: int = 0) -> list[Event]:
    """The `drop` events of the injected link_drop_burst faults: one at each tick of their intervals."""
    return [Event(k * dt, "drop", text="fault link_drop_burst")
            for k in drop_ticks([_as_fault(f) for f in faults or ()], dt, n_steps, start_tick)]


def dropped_ticks(specs, dt: float, n_steps: int, faults=()) -> set[int]:
    """Ticks whose sensor frame a `drop` event (--event, or an injected link_drop_burst fault) keeps from the
    wire (absent from the log on purpose)."""
    out = {tick for tick, evs in schedule(parse_all(specs), dt, n_steps).items()
           if any(e.kind == "drop" for e in evs)}
    return out | set(drop_ticks([_as_fault(f) for f in faults or ()], dt, n_steps))
