"""Link faults (docs/spec.md 5.14.6): link_drop_burst drops every sensor message of its interval, carried out by
the transport's `drop` event (aocs_runner.events) at each tick of the interval: the plant holds the previous
command, the flight software counts the frames missing."""
from __future__ import annotations


def drop_ticks(faults, dt: float, n_steps: int, start_tick: int = 0) -> list[int]:
    """The ticks whose sensor message a link_drop_burst drops, sorted, inside [start_tick, start_tick + n_steps)."""
    out = set()
    for f in faults:
        if f.kind == "link_drop_burst":
            a, b = f.ticks(dt)
            out.update(range(max(a, start_tick), min(b, start_tick + n_steps)))
    return sorted(out)
