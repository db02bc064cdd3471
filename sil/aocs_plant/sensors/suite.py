"""The plant's sensors sampled together, once per control period (SPEC 3.5).

The delayed sensors measure the truth of period k - latency_periods (clamped at period 0): the suite
records their true values at the start and after every period and keeps latency + 1 of them. The
others (tachometers) measure the truth at the sample time. Each sensor draws its noise in every
period whether or not a fault hides the sample, so a fault never shifts later noise; faults
(faults.py) are applied after the measurement model.
"""
from __future__ import annotations

import math
from operator import itemgetter


class SensorSuite:
    def __init__(self, sensors: list, latency_periods: int, faults: tuple, plant, hooks: dict | None = None):
        self.sensors = list(sensors)
        # injected faults acting on a sensor's measured value (aocs_plant.faults): {name: hook(t, value)}
        self.hooks = dict(hooks or {})
        self.latency = int(latency_periods)
        self.faults = tuple(faults)
        self._delayed = [s for s in self.sensors if s.delayed]
        sources = tuple(s.source(plant) for s in self._delayed)
        if len(sources) == 2:   # the usual pair (q, w or pos, vel): one closure, no generator on the hot path
            a, b = sources
            self._snapshot = lambda: (a(), b())
        else:
            self._snapshot = lambda: tuple([f() for f in sources])
        self._now = [(s, s.source(plant)) for s in self.sensors if not s.delayed]
        # what each sensor measures, from the period's recorded truth: a delayed sensor its entry of the
        # history's oldest period, a current one its source now (one loop in sample, no per-step generator)
        self._measured = ([(s, itemgetter(i)) for i, s in enumerate(self._delayed)]
                          + [(s, lambda _truth, src=src: src()) for s, src in self._now])
        # sensors with their own timing (the star tracker): their own record, flags and extra fields
        self._recorders = [(s, s.source(plant)) for s in self.sensors if s.records]
        self._flagged = [s for s in self.sensors if s.own_validity or s.extra_fields]
        self.history: list = []          # the delayed sensors' true values per period, latency + 1 kept
        self.last = {s.name: s.initial_last for s in self.sensors}

    def record(self) -> None:
        """Store the true values of the current period (after the plant's state is set)."""
        self.history.append(self._snapshot())
        if len(self.history) > self.latency + 1:
            del self.history[0]
        for s, src in self._recorders:
            s.record(src())

    def _active(self, channel, t):
        for f in self.faults:
            if (f.channel == channel or f.channel == "all") and f.start_s <= t < f.end_s:
                return f
        return None

    def sample(self, t: float) -> tuple[dict, bool]:
        """({sample field: value}, every validity flag true) at time t, after record() of this period."""
        out: dict = {}
        ok = True
        truth = self.history[0]  # period k - latency, or period 0 early in the run
        faulty = bool(self.faults)
        hooks = self.hooks
        for s, get in self._measured:   # the delayed sensors, then the current ones
            value = s.measure(get(truth))
            if hooks and s.name in hooks:
                value = hooks[s.name](t, value)
            if faulty:
                ok = self._fault(s, value, t, out) and ok
            else:
                out[s.value_field] = value
                if s.valid_field is not None:
                    out[s.valid_field] = True
        for s in self._flagged:   # own validity (ANDed with the faults'), and the extra fields
            if s.own_validity:
                if s.valid_field is not None:
                    out[s.valid_field] = out[s.valid_field] and s.valid
                ok = ok and s.available
            out.update(s.extra())
        return out, ok

    def _fault(self, s, value, t, out) -> bool:
        """Put sensor s's measured value into out through the faults active at t; its validity."""
        valid = True
        if s.fault_kinds:
            f = self._active(s.name, t)
            if f is not None:
                if f.kind not in s.fault_kinds:
                    pass
                elif f.kind == "dropout":
                    value, valid = self.last[s.name], False
                elif f.kind == "nan":
                    value = (math.nan,) * len(value)
                elif f.kind == "nonunit":
                    value = tuple(x * f.factor for x in value)
            else:
                self.last[s.name] = value
        out[s.value_field] = value
        if s.valid_field is not None:
            out[s.valid_field] = valid
        return valid
