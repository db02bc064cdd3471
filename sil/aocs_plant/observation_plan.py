"""The observation plan of a scenario ([[plan]], docs/scenarios.md; docs/spec.md 5.11): a list of inertial targets,
each with the time allowed for its slew and settling and the time it is held.

Observation i is commanded at T_i = sum_{j < i} (slew_s_j + hold_s_j) (T_0 = 0: observation 0 is the flight
software's initial target, written to its configuration like a [target]); its hold, the window its pointing
is judged over, is [T_i + slew_s_i, T_i + slew_s_i + hold_s_i). The plant side sends observation i >= 1 on the
command channel (command_t set_target) before the sensors of the first tick with t_k >= T_i (the runner's
events, aocs_runner.events.plan_events); the flight software's slew guidance flies from one target to the next.
No scenario I/O here: the reader is aocs_plant.scenario._read_plan.
"""
from __future__ import annotations

import bisect
from dataclasses import dataclass

from aocs_core.ticks import first_tick


@dataclass(frozen=True)
class Observation:
    qd: tuple                 # target q_DN, scalar last, unit
    slew_s: float             # time allowed for the slew and settling, from the command, s
    hold_s: float             # the observation: pointing judged over this window, s
    target_input: tuple       # (key, value) as the file gave it (euler321_deg, quaternion, ...)


@dataclass(frozen=True)
class ObservationPlan:
    observations: tuple       # Observation, in the order flown

    @property
    def command_times_s(self) -> tuple:
        """T_i: when observation i is commanded (T_0 = 0)."""
        out, t = [], 0.0
        for ob in self.observations:
            out.append(t)
            t += ob.slew_s + ob.hold_s
        return tuple(out)

    @property
    def end_s(self) -> float:
        """The end of the last hold."""
        return sum(ob.slew_s + ob.hold_s for ob in self.observations)

    def hold_windows_s(self) -> tuple:
        """((start, end), ...) of every hold."""
        return tuple((t + ob.slew_s, t + ob.slew_s + ob.hold_s)
                     for t, ob in zip(self.command_times_s, self.observations))

    def index_at(self, t: float, dt: float) -> int:
        """The observation commanded at simulation time t (the command of T_i acts from the first tick with
        t_k >= T_i, as the events fire: k = ceil(T_i / dt - 1e-9))."""
        cache = self.__dict__.setdefault("_ticks_by_dt", {})   # once per dt: truth_t asks at every tick
        ticks = cache.get(dt)
        if ticks is None:
            ticks = cache[dt] = [first_tick(T, dt) for T in self.command_times_s]
        k = int(round(t / dt))
        return max(0, bisect.bisect_right(ticks, k) - 1)
