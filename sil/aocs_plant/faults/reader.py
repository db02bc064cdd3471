"""The scenario's top-level `[[faults]]` entries (docs/scenarios.md), validated against the devices the
scenario has: kind, unit (where the kind has units), start_s, optional end_s (default: the end of the run),
the kind's parameters (aocs_core.fault_catalogue). A bad entry fails in one line naming file, entry and key."""
from __future__ import annotations

from aocs_core.fault_catalogue import GYRO, KINDS, LINK, OPTIONAL, STAR_TRACKER, THRUSTERS, WHEELS, check_param

from .fault import Fault

BASE_KEYS = ("kind", "unit", "start_s", "end_s")


def _units(kind, device_counts: dict) -> int:
    if kind.unit == "axis":
        return 3
    return device_counts.get(kind.device, 0)


def read_entry(f, duration_s: float, device_counts: dict) -> Fault:
    """One [[faults]] table (a scenario _Section) -> Fault. device_counts: {device: units} of the scenario
    (star_tracker / gyro 1 when present, wheels and thrusters their number, link 1)."""
    kind_name = f.string("kind", choices=tuple(KINDS))
    kind = KINDS[kind_name]
    f.only(BASE_KEYS + tuple(p.key for p in kind.params))
    if not device_counts.get(kind.device):
        what = {STAR_TRACKER: "a [sensors.star_tracker]", GYRO: "a [sensors.gyro]", WHEELS: "a [wheels] array",
                THRUSTERS: "a [thrusters] section", LINK: "a link"}[kind.device]
        f.fail(f.key("kind"), f"{kind_name} needs {what}, the scenario has none")
    unit = None
    if kind.unit is not None:
        unit = f.integer("unit", minimum=0)
        n = _units(kind, device_counts)
        if unit >= n:
            f.fail(f.key("unit"), f"{kind.unit} {unit} does not exist ({kind.unit}s 0 to {n - 1})")
    elif f.has("unit"):
        f.fail(f.key("unit"), f"{kind_name} takes no unit (its device has one)")
    t0 = f.number("start_s", nonneg=True)
    if t0 >= duration_s:
        f.fail(f.key("start_s"), f"{t0:g} s is not inside the run (duration_s = {duration_s:g})")
    t1 = f.number("end_s", required=False, default=duration_s, positive=True)
    if not t1 > t0:
        f.fail(f.key("end_s"), f"must be after start_s ({t1:g} <= {t0:g})")
    params = []
    for p in kind.params:
        if not f.has(p.key):
            if p.default is None:
                f.fail(f.key(p.key), f"missing required key ({p.meaning})")
            params.append((p.key, None if p.default == OPTIONAL else p.default))
            continue
        raw, _ = f._pop(p.key, True, None)
        params.append((p.key, check_param(p, raw, lambda what, k=p.key: f.fail(f.key(k), what))))
    f.done()
    return Fault(kind_name, unit, t0, t1, tuple(params))


def device_counts(sensor_config, effector_configs: dict) -> dict:
    """{device: number of units} the scenario has (0 / absent: none)."""
    names = set(getattr(sensor_config, "sensors", {}) or {})
    w = effector_configs.get("wheels")
    th = effector_configs.get("thrusters")
    return {STAR_TRACKER: int("star_tracker" in names), GYRO: int("gyro" in names),
            WHEELS: w.n if w is not None and getattr(w, "enabled", True) else 0,
            THRUSTERS: th.n if th is not None and getattr(th, "enabled", True) else 0, LINK: 1}


def read(root, duration_s: float, sensor_config, effector_configs: dict) -> tuple:
    """Every [[faults]] entry of the scenario root, in the file's order."""
    counts = device_counts(sensor_config, effector_configs)
    return tuple(read_entry(f, duration_s, counts) for f in root.table_list("faults"))
