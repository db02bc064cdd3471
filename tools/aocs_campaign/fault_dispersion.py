"""A campaign's dispersed fault (issue 26; docs/campaigns.md): the `[campaign.faults]` table of a campaign file
adds one injected fault to every run, its kind, start, unit and length drawn per run:

    [campaign.faults]
    kinds = ["wheel_torque_loss", "wheel_stuck", "st_frozen"]   # drawn uniformly (aocs_plant.faults.KINDS)
    start_s = [40.0, 120.0]          # uniform on [lo, hi]
    duration_s = [10.0, 60.0]        # optional: end_s = start_s + a uniform draw (absent: to the end of the run)
    units = [0, 3]                   # optional: the unit, a uniform integer in [lo, hi] (kinds with units; default 0)
    [campaign.faults.params.st_bias_step]   # optional: the parameters of a kind that needs them
    bias_arcsec = 30.0

The draws are a pure function of (campaign seed, run index) (dispersions.generator, key "faults"), so adding
the table does not change the other dispersions' values. The entry is appended to the scenario's [[faults]];
the results columns are fault.kind_index (into kinds), fault.start_s, fault.duration_s, fault.unit.
"""
from __future__ import annotations

import math

from aocs_plant.faults import KINDS

from .dispersions import DispersionError, generator

KEYS = ("kinds", "start_s", "duration_s", "units", "params")
STREAM = "faults"


def _range(sec: dict, key: str, where: str, integer: bool = False) -> tuple | None:
    v = sec.get(key)
    if v is None:
        return None
    ok = isinstance(v, list) and len(v) == 2 and all(
        isinstance(x, int) if integer else isinstance(x, (int, float)) for x in v) and not any(
        isinstance(x, bool) for x in v)
    if not ok or not all(math.isfinite(float(x)) for x in v) or v[0] > v[1] or v[0] < 0:
        what = "integers" if integer else "numbers"
        raise DispersionError(f"{where}.{key}: expected [lo, hi], two {what} with 0 <= lo <= hi, got {v!r}")
    return (int(v[0]), int(v[1])) if integer else (float(v[0]), float(v[1]))


def check(sec, where: str = "campaign.faults") -> dict | None:
    """The validated table (None when absent); DispersionError naming the key."""
    if sec is None:
        return None
    if not isinstance(sec, dict):
        raise DispersionError(f"{where}: must be a table")
    for k in sec:
        if k not in KEYS:
            raise DispersionError(f"{where}.{k}: unknown key; known: {', '.join(KEYS)}")
    kinds = sec.get("kinds")
    if not isinstance(kinds, list) or not kinds or not all(isinstance(k, str) for k in kinds):
        raise DispersionError(f"{where}.kinds: expected a non-empty list of fault kinds")
    for k in kinds:
        if k not in KINDS:
            raise DispersionError(f"{where}.kinds: unknown kind {k!r} (one of {', '.join(KINDS)})")
    if _range(sec, "start_s", where) is None:
        raise DispersionError(f"{where}.start_s: missing ([lo, hi], s)")
    _range(sec, "duration_s", where)
    _range(sec, "units", where, integer=True)
    params = sec.get("params", {})
    if not isinstance(params, dict) or not all(isinstance(v, dict) for v in params.values()):
        raise DispersionError(f"{where}.params: expected tables of parameters per kind")
    for k in params:
        if k not in kinds:
            raise DispersionError(f"{where}.params.{k}: not one of the kinds drawn")
    return sec


def draw(sec: dict, seed: int, index: int) -> tuple[dict, dict]:
    """(the [[faults]] entry of run index, its results columns)."""
    rng = generator(seed, index, STREAM)
    kinds = sec["kinds"]
    ki = int(rng.integers(len(kinds)))
    kind = kinds[ki]
    lo, hi = _range(sec, "start_s", "")
    start = float(rng.uniform(lo, hi))
    entry = {"kind": kind, "start_s": start}
    inputs = {"fault.kind_index": ki, "fault.start_s": start}
    d = _range(sec, "duration_s", "")
    if d is not None:
        length = float(rng.uniform(*d))
        entry["end_s"] = start + length
        inputs["fault.duration_s"] = length
    u = _range(sec, "units", "", integer=True) or (0, 0)
    unit = int(rng.integers(u[0], u[1] + 1))
    if KINDS[kind].unit is not None:
        entry["unit"] = unit
        inputs["fault.unit"] = unit
    entry.update(sec.get("params", {}).get(kind, {}))
    return entry, inputs


def overrides(sec: dict | None, doc: dict, seed: int, index: int) -> tuple[dict, dict]:
    """({"faults": the scenario's [[faults]] plus the drawn one}, inputs), or ({}, {}) without a table."""
    if sec is None:
        return {}, {}
    entry, inputs = draw(sec, seed, index)
    base = doc.get("faults", [])
    return {"faults": list(base if isinstance(base, list) else [base]) + [entry]}, inputs
