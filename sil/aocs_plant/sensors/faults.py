"""Sensor faults (`[[sensors.faults]]`, SPEC 3.5): read and validated against the sensors the scenario has.

Each fault is active for start_s <= t < end_s on one sensor's channel, or on "all" (every sensor that
takes faults). What it does to a sample (SensorSuite):
- dropout: valid flag False; the value repeats the last unfaulted value delivered (the sensor's
  initial_last before the first one);
- nan: every component NaN, valid flag True (the flight software must catch it);
- nonunit: the value multiplied by `factor`, valid flag True (the attitude quaternion's norm check).
A sensor ignores a kind it does not list in fault_kinds (its value passes, but does not count as an
unfaulted sample either).
"""
from __future__ import annotations

from dataclasses import dataclass

FAULT_KINDS = ("dropout", "nan", "nonunit")
ALL = "all"


@dataclass(frozen=True)
class SensorFault:
    channel: str
    kind: str
    start_s: float
    end_s: float
    factor: float


def read_faults(sec, duration_s: float, built: list, registry: dict) -> tuple:
    """The [[sensors.faults]] tables of `sec`; channels are the names of the `built` sensor classes that
    take faults, and "all"."""
    channels = tuple(c.name for c in built if c.fault_kinds) + (ALL,)
    faults = []
    for f in sec.table_list("faults"):
        ch = f.string("channel", choices=channels)
        fk = f.string("kind", choices=FAULT_KINDS)
        t0 = f.number("start_s", nonneg=True)
        t1 = f.number("end_s", positive=True)
        if not t1 > t0:
            f.fail(f.key("end_s"), f"must be after start_s ({t1} <= {t0})")
        if t0 >= duration_s:
            f.fail(f.key("start_s"), f"{t0} s is not inside the run (duration_s = {duration_s})")
        factor = f.number("factor", required=False, default=1.5, positive=True)
        takers = [c.name for c in built if fk in c.fault_kinds]
        if (ch == ALL and not takers) or (ch != ALL and ch not in takers):
            every = [c.name for c in registry.values() if fk in c.fault_kinds]
            f.fail(f.key("kind"), f"{fk} applies to the {' and '.join(every)} channel only")
        if fk == "nonunit" and abs(factor - 1.0) < 1e-6:
            f.fail(f.key("factor"), "a nonunit fault needs factor != 1")
        f.done()
        faults.append(SensorFault(ch, fk, t0, t1, factor))
    return tuple(faults)
