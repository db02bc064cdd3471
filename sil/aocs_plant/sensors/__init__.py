"""Sensors: every measurement channel of the plant, one module each (docs/extending.md "Adding a sensor").

Every module of this package (except base and the shared models) registers its Sensor class; the
scenario loader selects the ones the scenario has (read), the plant builds them (build) and samples
them once per period through a SensorSuite (latency, faults, validity). Adding one is adding a module.

- read(root, ctx): the [sensors] table -> SensorsConfig (each sensor reads its own keys; a key of a
  sensor that does not apply to the plant kind is refused, naming it);
- build(config, ctx): the sensor objects, in the registry's order.
"""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass, field
from types import MappingProxyType
from typing import Any, Mapping

from .base import ATTITUDE, ORBIT, REGISTRY, Sensor, SensorContext, SensorReadContext, register
from .faults import FAULT_KINDS, SensorFault, read_faults
from .suite import SensorSuite

__all__ = ["ATTITUDE", "ORBIT", "REGISTRY", "Sensor", "SensorContext", "SensorReadContext", "register",
           "FAULT_KINDS", "SensorFault", "SensorSuite", "SensorsConfig", "read", "build"]

_SHARED = {"base", "additive", "faults", "suite"}
for _m in sorted(pkgutil.iter_modules(__path__), key=lambda m: m.name):
    if _m.name not in _SHARED and not _m.name.startswith("_"):
        importlib.import_module(f"{__name__}.{_m.name}")


@dataclass(frozen=True)
class SensorsConfig:
    """[sensors]: the config of every sensor the scenario has (name -> config), and what they share."""

    sensors: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))
    latency_periods: int = 0      # the delayed sensors' samples of period k are the truth of k - latency
    faults: tuple = ()            # SensorFault

    def __getitem__(self, name: str):
        return self.sensors[name]

    @property
    def ideal(self) -> bool:
        return (self.latency_periods == 0 and not self.faults
                and all(getattr(c, "ideal", True) for c in self.sensors.values()))


def read(root, ctx: SensorReadContext) -> SensorsConfig:
    """The [sensors] table (absent: every sensor of the plant kind, ideal), validated."""
    sec = root.table("sensors", required=False)
    if sec is None:
        sec = type(root)(root.file, "sensors", {})
    for cls in REGISTRY.values():
        if ctx.kind not in cls.applies_to:
            for k in cls.keys:
                if sec.has(k):
                    sec.fail(sec.key(k), f"does not apply to a {ctx.kind} scenario")
    configs = {}
    for cls in REGISTRY.values():
        if ctx.kind in cls.applies_to:
            cfg = cls.read(sec, ctx)
            if cfg is not None:
                configs[cls.name] = cfg
    latency = sec.integer("latency_periods", required=False, default=0, minimum=0)
    faults = read_faults(sec, ctx.duration_s, [REGISTRY[n] for n in configs], REGISTRY)
    sec.done()
    return SensorsConfig(MappingProxyType(configs), latency, faults)


def build(config: SensorsConfig, ctx: SensorContext) -> list[Sensor]:
    return [REGISTRY[name](cfg, ctx) for name, cfg in config.sensors.items()]
