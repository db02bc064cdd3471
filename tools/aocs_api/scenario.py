"""A scenario and its overrides, checked by the scenario loader (docs/scenarios.md) as the command line's --set."""
from __future__ import annotations

from dataclasses import dataclass, field

from aocs_plant.scenario import ScenarioError, load
from aocs_runner import scenario_opts

from .errors import usage


@dataclass(frozen=True)
class Scenario:
    """A scenario id (aocs list) or file, and keys overridden (dotted keys as --set takes them: "duration_s",
    "actuator.axis_limit", "laws.quat_pd.kp")."""
    name: str
    overrides: dict = field(default_factory=dict)

    def with_overrides(self, overrides: dict | None = None, **keys) -> Scenario:
        """A copy with more keys overridden (a dict for dotted keys; keyword arguments for plain ones)."""
        return Scenario(self.name, {**self.overrides, **(overrides or {}), **keys})

    def sets(self) -> list[str]:
        """The overrides as --set KEY=VALUE texts (TOML values)."""
        return [f"{k}={scenario_opts.toml_value(v)}" for k, v in self.overrides.items()]

    def load(self):
        """The scenario as the plant and the flight software see it (aocs_plant.scenario.Scenario); raises
        AocsError for an unknown scenario or a bad override."""
        try:
            return load(self.name, scenario_opts.parse_sets(self.sets()))
        except (ScenarioError, ValueError, TypeError) as exc:
            raise usage(exc) from None

    @property
    def laws(self) -> list[str]:
        """The laws this scenario has gains for."""
        return list(self.load().control.laws)

    @property
    def description(self) -> str:
        return self.load().description


def scenario(name: str, overrides: dict | None = None) -> Scenario:
    """The scenario `name` with overrides; checked at once (AocsError names a bad key or value)."""
    sc = Scenario(str(name), dict(overrides or {}))
    sc.load()
    return sc


def sets_of(sc, sets=(), overrides: dict | None = None) -> tuple[str, list[str]]:
    """(scenario name, --set texts) of a name or Scenario plus more overrides."""
    if isinstance(sc, Scenario):
        name, base = sc.name, sc.sets()
    else:
        name, base = str(sc), []
    extra = [f"{k}={scenario_opts.toml_value(v)}" for k, v in (overrides or {}).items()]
    return name, base + list(sets) + extra
