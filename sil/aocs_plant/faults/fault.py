"""One injected fault: its kind, unit, interval and parameters, and the one rule of when it is active."""
from __future__ import annotations

from dataclasses import dataclass

from aocs_core.fault_catalogue import KINDS
from aocs_core.ticks import first_tick


@dataclass(frozen=True)
class Fault:
    kind: str
    unit: int | None
    start_s: float
    end_s: float              # the end of the run when the entry gives none
    params: tuple = ()        # ((key, value), ...) in the catalogue's order, defaults filled in

    def param(self, key: str):
        return dict(self.params)[key]

    @property
    def spec(self):
        """Its catalogue row (catalogue.Kind)."""
        return KINDS[self.kind]

    def ticks(self, dt: float) -> tuple[int, int]:
        """[first, end) control ticks of the fault: active at tick k when first_tick(start) <= k <
        first_tick(end), the rule of every scheduled event (aocs_core.ticks)."""
        return first_tick(self.start_s, dt), first_tick(self.end_s, dt)

    def active(self, t: float, dt: float) -> bool:
        """Active at plant time t (a tick time k dt, or the start of the period k)."""
        k = first_tick(t, dt)
        a, b = self.ticks(dt)
        return a <= k < b

    def to_json(self) -> dict:
        out = {"kind": self.kind, "unit": self.unit, "start_s": self.start_s, "end_s": self.end_s}
        out.update({k: (list(v) if isinstance(v, tuple) else v) for k, v in self.params})
        return out


class DeviceFaults:
    """The faults acting on one device, and which of them are active at a time (the device models' base)."""

    def __init__(self, faults, dt: float):
        self.faults = tuple(faults)
        self.dt = dt

    def active_at(self, t: float) -> list:
        return [f for f in self.faults if f.active(t, self.dt)]

    def per_unit(self, t: float, values: tuple, value_of) -> tuple:
        """values with the element of each active fault's unit replaced by value_of(fault)."""
        on = self.active_at(t)
        if not on:
            return values
        v = list(values)
        for f in on:
            v[f.unit] = value_of(f)
        return tuple(v)
