"""The executive's modes (aocs_exec_mode_t) by name: the values actuator_cmd_t.mode,
command_t.mode and status_t.mode carry. They are read from the build's registry, which the
firmware wrote, so no mode number is typed again in Python; callers name the mode
("nominal") and get the firmware's number."""
from __future__ import annotations

from aocs_core import registry


def mode_values() -> dict[str, int]:
    """Mode name -> value, in value order ("standby", "nominal", "safe" today)."""
    return {name: value for value, name in sorted(registry.load().mode_names.items())}


def mode_value(name: str) -> int:
    """The value of a mode name; KeyError naming the modes the firmware has when it has no such mode."""
    known = mode_values()
    if name not in known:
        raise KeyError(f"no executive mode named {name!r} (the firmware has {', '.join(known)})")
    return known[name]
