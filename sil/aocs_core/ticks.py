"""Simulation time to control ticks: the one rule of when something scheduled at a time acts."""
from __future__ import annotations

import math


def first_tick(t_s: float, dt: float) -> int:
    """The first control tick k with t_k = k dt >= t_s (within 1e-9 of a period): an event, a command of the
    observation plan, fires before that tick's sensors (aocs_runner.events.schedule)."""
    return int(math.ceil(t_s / dt - 1e-9))
