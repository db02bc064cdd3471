"""The sensor interface: one measurement channel of the plant (docs/extending.md "Adding a sensor").

A sensor is one module in this package. It owns

- its keys in the scenario: `read(sec, ctx)` takes them from the `[sensors]`
  table (or from the section of the effector it measures, `ctx.effectors`)
  and returns a frozen config, or None when the scenario has nothing for it
  to measure (no wheels: no tachometer); errors go through `sec.fail`, so they
  name file and key;
- its seeded noise stream (`stream_index`, a fixed index of rng.CHANNELS that
  is never renumbered: a new sensor takes a new one);
- the truth it measures (`source(plant)`: a closure returning the true value
  now, bound once) and its measurement model (`measure(value)`);
- the fields it writes into the sample (`value_field`, `valid_field`) and its
  truth fields (`truth()`: Plant.truth()["sensors"] reports them as
  "<name>.<field>").

The plant never names a sensor: sensors.read selects them from the scenario,
sensors.build makes them, and the SensorSuite samples them once per period
(latency, faults, validity).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Any, Callable, ClassVar

from .. import rng

ATTITUDE = "attitude"
ORBIT = "orbit"
ZERO3 = (0.0, 0.0, 0.0)


@dataclass(frozen=True)
class SensorReadContext:
    """What a sensor's reader may check its keys against."""

    file: str
    kind: str            # "attitude" | "orbit"
    duration_s: float
    dt: float            # control period, s
    effectors: Any       # {kind: config} of the scenario's effector sections (the wheels' for the tachometer)


@dataclass(frozen=True)
class SensorContext:
    """What a sensor is built with."""

    kind: str
    dt: float
    seed: int
    environment: Any = None   # aocs_plant.environment.Environment: Sun, Earth, orbit, magnetic field at t


class Sensor:
    """Base class of a sensor module; the defaults are a perfect sensor of nothing."""

    name: ClassVar[str] = ""                 # its channel: registry key, [[sensors.faults]] channel, noise stream
    stream_index: ClassVar[int] = -1         # the fixed index of its seeded stream (rng.CHANNELS)
    applies_to: ClassVar[tuple] = (ATTITUDE,)  # plant kinds that have the truth it measures
    keys: ClassVar[tuple] = ()               # its keys in [sensors] (refused on other plant kinds)
    value_field: ClassVar[str] = ""          # key of the measured value in Plant.sense()
    valid_field: ClassVar[str | None] = None  # key of its validity flag there (None: no flag)
    truth_field: ClassVar[str] = ""          # what it measures, as Plant.truth() or the effector truth names it
    delayed: ClassVar[bool] = True           # True: the sample of period k measures period k - latency_periods
    fault_kinds: ClassVar[tuple] = ()        # [[sensors.faults]] kinds it takes (dropout, nan, nonunit); () none
    initial_last: ClassVar[tuple] = ZERO3    # what a dropout repeats before the first unfaulted sample
    extra_fields: ClassVar[tuple] = ()       # further sample fields it writes (extra()), reserved like value_field
    own_validity: ClassVar[bool] = False     # True: it sets its own flags after measure() (valid, available)
    records: ClassVar[bool] = False          # True: record(value) gets its true value after every period

    @classmethod
    def read(cls, sec, ctx: SensorReadContext):
        """Its config from the [sensors] table `sec` (the registry refuses what is left), or None."""
        raise NotImplementedError

    def __init__(self, config, ctx: SensorContext):
        self.config = config
        self.kind = ctx.kind

    def source(self, plant) -> Callable[[], tuple]:
        """A closure giving the true value it measures now (read at every period end when delayed,
        at every sample otherwise)."""
        raise NotImplementedError

    def measure(self, value: tuple) -> tuple:
        """The measurement of the true value `value`, before faults; draws its noise once per call."""
        return value

    def truth(self) -> dict:
        """Its truth fields {name: value} (default none)."""
        return {}

    # only for sensors with their own timing (own_validity / records / extra_fields: the star tracker)
    valid: bool = True        # own_validity: its valid flag of the last sample (ANDed with the faults')
    available: bool = True    # own_validity: False when unusable (outage, exclusion): counted as invalid

    def record(self, value: tuple) -> None:
        """records: the true value (source()) after every period, and once at the start."""

    def extra(self) -> dict:
        """extra_fields: their values for the last sample."""
        return {}


REGISTRY: dict[str, type[Sensor]] = {}


def register(cls: type[Sensor]) -> type[Sensor]:
    """Class decorator: make a sensor known to the scenario loader and the plant, and reserve its stream."""
    if not cls.name or cls.name in REGISTRY and REGISTRY[cls.name] is not cls:
        raise ValueError(f"sensor {cls.name!r} is empty or registered twice")
    fields = {cls.value_field, cls.valid_field, *cls.extra_fields} - {None}
    for other in REGISTRY.values():
        if other is not cls and fields & {other.value_field, other.valid_field, *other.extra_fields}:
            raise ValueError(f"sensor {cls.name!r}: sample field taken by sensor {other.name!r}")
    rng.claim(cls.name, cls.stream_index)
    REGISTRY[cls.name] = cls
    return cls
