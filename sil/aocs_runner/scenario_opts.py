"""Scenario overrides from the command line, shared by `aocs run` and plant_node.

`--set key=value` takes a dotted scenario key and a TOML value
(`control.enabled=false`, `actuator.axis_limit=0.5`,
`sensors.faults=[{channel="attitude", kind="nan", start_s=10.0, end_s=11.0}]`);
a value that is not valid TOML is taken as a string (`plant.model=nonlinear`).
`--duration`, `--seed`, `--limit` and `--guidance` are shorthands for
`duration_s`, `seed`, `actuator.axis_limit` and `guidance.mode`. Everything goes through aocs_plant.scenario.load,
so an override is validated exactly like the file.
"""
from __future__ import annotations

import tomllib
from typing import Any, Iterable


def parse_value(text: str) -> Any:
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        return text


def parse_sets(items: Iterable[str] | None) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for item in items or ():
        if "=" not in item:
            raise ValueError(f"--set {item!r}: expected key=value")
        k, v = item.split("=", 1)
        k = k.strip()
        if not k:
            raise ValueError(f"--set {item!r}: empty key")
        out[k] = parse_value(v.strip())
    return out


def overrides(sets: Iterable[str] | None = None, duration: float | None = None, seed: int | None = None,
              limit: float | None = None, guidance: str | None = None) -> dict[str, Any]:
    out = parse_sets(sets)
    if duration is not None:
        out["duration_s"] = float(duration)
    if seed is not None:
        out["seed"] = int(seed)
    if limit is not None:
        out["actuator.axis_limit"] = float(limit)
    if guidance is not None:
        out["guidance.mode"] = str(guidance)  # validated by the scenario loader ([guidance] mode)
    return out


def to_args(ov: dict[str, Any]) -> list[str]:
    """The same overrides as `--set` arguments (for a child process)."""
    args = []
    for k, v in ov.items():
        args += ["--set", f"{k}={toml_value(v)}"]
    return args


def toml_value(v: Any) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
    if isinstance(v, (list, tuple)):
        return "[" + ", ".join(toml_value(x) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{k} = {toml_value(x)}" for k, x in v.items()) + "}"
    raise TypeError(f"cannot write {v!r} as TOML")


def resolve_law(sc, law: str | None) -> str:
    """The law a run of scenario sc flies with --law law (None: the scenario's; "none" with control disabled);
    ValueError naming --law when the scenario cannot fly it (aocs run and aocs campaign alike)."""
    if not sc.control.enabled:
        if law not in (None, "none"):
            raise ValueError(f"--law {law}: control is disabled (control.enabled = false)")
        return "none"
    law = law or sc.control.law
    if law not in sc.control.laws:
        raise ValueError(f"--law {law}: scenario {sc.id} has no gains for it "
                         f"(applicable: {', '.join(sc.control.laws)})")
    return law
