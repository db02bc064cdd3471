"""`aocs run ... --fault KIND@START[-END][:unit=N][:key=value...]` (repeatable): one [[faults]] entry each.

    --fault wheel_torque_loss@60:unit=1
    --fault st_bias_step@100-160:bias_arcsec=30:axis=[0,0,1]
    --fault link_drop_burst@20-21.5

A value is TOML (a number, an array), as --set takes it. The entries are appended to the scenario's own
[[faults]] and validated by the scenario loader like the file's.
"""
from __future__ import annotations

import re
import tomllib

from aocs_core.fault_catalogue import KINDS

_NUM = r"\d+(?:\.\d*)?(?:[eE][+-]?\d+)?"
_WHEN = re.compile(rf"^({_NUM})(?:-({_NUM}))?$")


class FaultOptionError(ValueError):
    pass


def _value(text: str):
    try:
        return tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        raise FaultOptionError(f"{text!r} is not a TOML value (a number or an array)") from None


def parse(spec: str) -> dict:
    """One --fault text -> the [[faults]] entry (a dict); FaultOptionError naming the option."""
    def bad(what):
        raise FaultOptionError(f"--fault {spec!r}: {what}")
    kind, at, rest = spec.partition("@")
    kind = kind.strip()
    if not at:
        bad("expected KIND@START[-END][:unit=N][:key=value...], e.g. wheel_torque_loss@60:unit=1")
    if kind not in KINDS:
        bad(f"unknown kind {kind!r} (one of {', '.join(KINDS)})")
    parts = rest.split(":")
    m = _WHEN.match(parts[0].strip())
    if not m:
        bad(f"{parts[0]!r} is not START or START-END (seconds)")
    entry = {"kind": kind, "start_s": float(m.group(1))}
    if m.group(2) is not None:
        entry["end_s"] = float(m.group(2))
    for p in parts[1:]:
        key, eq, val = p.partition("=")
        key = key.strip()
        if not eq or not key:
            bad(f"{p!r}: expected key=value")
        if key in entry:
            bad(f"{key} given twice")
        try:
            entry[key] = _value(val.strip())
        except FaultOptionError as exc:
            bad(f"{key}: {exc}")
    return entry


def parse_all(specs) -> list[dict]:
    return [parse(s) for s in specs or ()]
