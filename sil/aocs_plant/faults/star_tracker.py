"""Star tracker faults (docs/spec.md 5.14.1), applied to each sample after the tracker's own model.

The tracker keeps, of its last sample, the true q_SN, the error rotation e = b + n + l and its white part n
(sensors/star_tracker.py). With the faults active at the sample time t:

    st_noise_increase (factor k):  e' = e + (k - 1) n                 (the white noise k times larger)
    st_bias_step (b_f arcsec, a):  e' = e + b_f a                     (a step of the misalignment)
    q_meas' = dq(e') (x) q_SN, renormalised                             (the tracker's own measurement equation)
    st_frozen:  q_meas' = the attitude delivered at the last sample before the fault, flagged valid and new as
                the tracker's timing says (a frozen output that claims to be fresh)
    st_outage:  no sample: st_valid and st_new false, the last delivered attitude repeated

The tracker draws its noise whatever the faults (a fault never shifts later numbers).
"""
from __future__ import annotations

import math

from aocs_core.conventions import ARCSEC_PER_RAD, quat_from_rotvec, quat_mul

from .fault import DeviceFaults


class StarTrackerFaults(DeviceFaults):
    def __init__(self, faults, dt: float, sensor):
        super().__init__(faults, dt)
        self.sensor = sensor
        self.last_out = sensor.initial_last     # the attitude delivered by the last sample
        self.frozen = None                      # the attitude held by an active st_frozen

    def __call__(self, t: float, value: tuple) -> tuple:
        s = self.sensor
        on = self.active_at(t)
        kinds = {f.kind for f in on}
        if "st_frozen" not in kinds:
            self.frozen = None
        if not on:
            if s.new:
                self.last_out = value
            return value
        if "st_outage" in kinds:
            s.new = s.valid = s.available = False
            return self.last_out
        extra = [0.0, 0.0, 0.0]
        for f in on:
            if f.kind == "st_noise_increase":
                k = f.param("factor") - 1.0
                extra = [a + k * n for a, n in zip(extra, s.white)]
            elif f.kind == "st_bias_step":
                b = f.param("bias_arcsec") / ARCSEC_PER_RAD
                extra = [a + b * x for a, x in zip(extra, f.param("axis"))]
        if extra != [0.0, 0.0, 0.0]:
            e = s.error
            q = quat_mul(quat_from_rotvec((e[0] + extra[0], e[1] + extra[1], e[2] + extra[2])), s.q_true)
            k = 1.0 / math.sqrt(sum(x * x for x in q))
            value = (q[0] * k, q[1] * k, q[2] * k, q[3] * k)
        if "st_frozen" in kinds:
            if self.frozen is None:
                self.frozen = self.last_out
            value = self.frozen
        if s.new:
            self.last_out = value
        return value
