"""The plant's integration error of a run, estimated by step doubling on a shadow state.

Every period a shadow plant (the same scenario with twice the substeps) starts
from the main plant's state at the beginning of the period, takes the same
command and integrates the same period; the main plant's fixed-step RK4 is
fourth order, so the difference of the two end states is the main plant's
local error of that period times (1 - 2^-4) to leading order (Richardson):

    local error(h) ~ (x_h - x_h/2) * 16 / 15

Reported for the whole run (SPEC 4.3): the largest local error of one period,
and their sum, the global error the run would have if no error ever decayed
(an upper bound for the closed loop, which damps what it is given). Attitude:
the true angle between the two end attitudes (arcsec) and the rate difference
(rad/s); orbit: position (m) and velocity (m/s). When the sum exceeds the
scenario's tolerance ([integrator] tolerance_arcsec / tolerance_m) the run
summary warns and suggests more substeps. The linear orbit model is
propagated exactly: its estimate is zero by construction.

To keep the lockstep loop fast, a period is checked when its index is a
multiple of CHECK_EVERY, or when the last checked period's local error could
matter (above tolerance / n_steps: n_steps such errors would add up to the
tolerance); an unchecked period counts with the last checked error in the sum
(held). Where the error is large (fast motion, too few substeps) every period
is checked; where it is negligible one in CHECK_EVERY is. One checked period
costs one more integration at twice the substeps (about 2 x 7 us at one
substep), so a well-integrated run pays about 1.5 us per period on average
(docs/benchmarks.md).
"""
from __future__ import annotations

import dataclasses
import math

from aocs_core.conventions import ARCSEC_PER_RAD, pointing_error_rad

from .plant import Plant

#: RK4 is fourth order: error(h) = (x_h - x_{h/2}) * 2^4 / (2^4 - 1)
RICHARDSON_RK4 = 16.0 / 15.0
#: one period in CHECK_EVERY is integrated again (see above)
CHECK_EVERY = 10


class StepDoubling:
    """begin(main) before main.advance(), end(main) after it; apply(u) with every command."""

    def __init__(self, scenario, every: int = CHECK_EVERY):
        self.every = max(1, int(every))
        self.kind = scenario.kind
        self.substeps = scenario.substeps
        self.tolerance = scenario.integrator_tolerance
        # a local error above this could matter: n_steps of them would add up to the tolerance
        self.threshold = (scenario.integrator_tolerance or 0.0) / max(1, scenario.n_steps)
        self._last = (0.0, 0.0)
        self.shadow = Plant(dataclasses.replace(scenario, substeps=2 * scenario.substeps))
        self.periods = 0
        self.checked = 0
        self.local_max = [0.0, 0.0]       # attitude: arcsec, rad/s; orbit: m, m/s
        self.local_sum = [0.0, 0.0]
        self.worst_t = 0.0
        self._start = None

    def apply(self, command) -> None:
        """The command the main plant was given for this period (the same mapping, Plant.apply)."""
        self.shadow.apply(command)

    def take(self, taken: dict) -> None:
        """apply() of the command as the main plant took it (its Plant.taken, already checked: not again)."""
        self.shadow.take(taken)

    def begin(self, main: Plant) -> None:
        due = main.k % self.every == 0 or self._last[0] > self.threshold
        self._start = (main.body_state(), main._x, main.k, main.fault_state() if main.faults else None) \
            if due else None

    def end(self, main: Plant) -> None:
        self.periods += 1
        if self._start is None:   # not checked: it counts with the last checked error
            self.local_sum[0] += self._last[0]
            self.local_sum[1] += self._last[1]
            return
        body, x, k, faults = self._start
        s = self.shadow
        s._set_body(body)
        s._x = x
        s.k = k
        if faults:                # an injected fault's state (a stuck wheel's held speed) as the main plant's
            s.set_fault_state(faults)
        s.advance()
        if self.kind == "attitude":
            a = pointing_error_rad(main.body.q, s.body.q) * ARCSEC_PER_RAD
            w1, w2 = main.body.w, s.body.w
            b = math.sqrt((w1[0] - w2[0]) ** 2 + (w1[1] - w2[1]) ** 2 + (w1[2] - w2[2]) ** 2)
        else:
            x1, x2 = main.orbit.x, s.orbit.x
            a = math.sqrt((x1[3] - x2[3]) ** 2 + (x1[4] - x2[4]) ** 2 + (x1[5] - x2[5]) ** 2)
            b = math.sqrt((x1[0] - x2[0]) ** 2 + (x1[1] - x2[1]) ** 2 + (x1[2] - x2[2]) ** 2)
        a *= RICHARDSON_RK4
        b *= RICHARDSON_RK4
        self.checked += 1
        if a > self.local_max[0]:
            self.local_max[0], self.worst_t = a, main.t
        self.local_max[1] = max(self.local_max[1], b)
        self.local_sum[0] += a
        self.local_sum[1] += b
        self._last = (a, b)

    def summary(self) -> dict:
        unit = ("arcsec", "rad_s") if self.kind == "attitude" else ("m", "m_s")
        what = ("attitude", "rate") if self.kind == "attitude" else ("position", "velocity")
        return {
            "method": f"step doubling: a period again at {2 * self.substeps} substeps from the same state, "
                      f"difference x 16/15 (RK4, {self.substeps} substeps); every period while the error could "
                      f"matter, else one in {self.every}, the others counted with the last checked error",
            f"{what[0]}_{unit[0]}_local_max": self.local_max[0],
            f"{what[0]}_{unit[0]}_sum": self.local_sum[0],
            f"{what[1]}_{unit[1]}_local_max": self.local_max[1],
            f"tolerance_{unit[0]}": self.tolerance,
            "worst_period_end_s": self.worst_t, "periods": self.periods, "checked_periods": self.checked,
            "exceeds_tolerance": bool(self.tolerance is not None and self.local_sum[0] > self.tolerance),
        }
