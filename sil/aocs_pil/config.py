"""The fsw_node configuration file, read exactly as fsw_node reads it.

Format and keys: docs/wire-contract.md, "Configuration file"; the reference
implementation is sil/fsw_node/node_config.c, which this module mirrors rule
for rule (same keys, value counts, sign rules, number syntax of strtod, error
messages with file, line and key), so a file fsw_node accepts the bridge
accepts with the same values, and a file it rejects the bridge rejects with
the same message. tests/python/aocs_pil/test_frame.py holds the two side by side.
The general keys are listed here as in node_config.c; the law keys, their
PIL fields and the gain tables come from the build's law registry
(aocs_core.registry), as node_config.c expands them from laws.def.

The executive's own validation (aocs_exec_init: ordering rules, inertia,
limits, gain tables) is not repeated here: the image runs it on the CONFIG
frame and the bridge reports its status like fsw_node does.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path

from aocs_core import paths, registry

from . import frame

ANY, POS, NONNEG = "any", "pos", "nonneg"


@dataclass(frozen=True)
class Key:
    name: str
    kind: str        # real double u32 u64 seconds_ns law run_mode string inertia gain_table
    count: int
    rule: str
    help: str
    pil: str | None  # PIL CONFIG field (frame.cfg_fields()), None = bridge-only key
    law: str | None = None   # gain_table keys: the law whose gain tables the key takes


#: node_config.c's general KEYS (the node's and the executive's own keys), in its order:
#: (name, kind, count, rule, help). Their PIL fields are the registry's executive fields
#: of the same key; the law keys after them are the registry's field rows (keys()).
_GENERAL = (
    ("law", "law", 1, ANY, "law name (executive.h), none = standby"),
    ("mode", "run_mode", 1, ANY, "lockstep | realtime"),
    ("control_period_s", "real", 1, POS, "s"),
    ("target_q", "real", 4, ANY, "4 numbers, scalar last, unit"),
    ("target_w", "real", 3, ANY, "rad/s, 3 numbers"),
    ("target_w_dot", "real", 3, ANY, "rad/s^2, 3 numbers"),
    ("target_rotation_rate", "real", 3, ANY,
     "rad/s, 3 numbers: constant rate of the target frame w.r.t. N, in the target frame"),
    ("u_max_axis", "real", 3, NONNEG, "N m (N) per axis, 3 numbers"),
    ("u_max_norm", "real", 1, NONNEG, "N m (N), 0 = unused"),
    ("k_safe", "real", 1, POS, "N m s/rad"),
    ("recover_good_samples", "u32", 1, POS, "count >= 1"),
    ("missing_max_periods", "u32", 1, POS, "count >= 1"),
    ("stale_timeout_s", "seconds_ns", 1, POS, "s"),
    ("budget_ns", "u64", 1, NONNEG, "ns, 0 = the law's budget"),
    ("idle_timeout_s", "double", 1, POS, "s"),
    ("run_timeout_s", "double", 1, NONNEG, "s, 0 = none"),
    ("status_period_s", "double", 1, POS, "s"),
    ("lcm_url", "string", 1, ANY, "LCM provider URL"),
    ("guidance.mode", "guidance_mode", 1, ANY, "step | slew"),
    ("guidance.profile", "slew_profile", 1, ANY, "bang_coast_bang | jerk_limited"),
    ("guidance.margin", "real", 1, POS, "fraction of the torque envelope the slew reference may use, in (0, 1]"),
    ("guidance.rate_limit", "real", 1, NONNEG, "rad/s, 0 = none"),
    ("guidance.jerk_time", "real", 1, NONNEG, "s, ramp time of the jerk_limited profile, 0 with bang_coast_bang"),
    ("wheels.count", "u32", 1, POS, "reaction wheels, 3 to 6 (absent: none)"),
    ("wheels.failed_mask", "u32", 1, NONNEG, "bit i set: wheel i declared failed"),
    ("wheels.null_gain", "real", 1, NONNEG, "null-space wheel speed management gain k_n, 1/s, 0 = none"),
) + tuple((f"wheel{i}.{field}", kind, count, rule, help_) for i in range(6)
          for field, kind, count, rule, help_ in (
    # node_config.c WHEEL_KEYS: the per-wheel keys wheel<i>.<field>, in its order
    ("axis", "real", 3, ANY, "unit spin axis g in B, 3 numbers"),
    ("js", "real", 1, POS, "spin inertia Js, kg m^2"),
    ("u_max", "real", 1, POS, "motor torque limit, N m"),
    ("omega_max", "real", 1, POS, "speed limit, rad/s"),
    ("viscous", "real", 1, NONNEG, "viscous friction b of the friction feedforward, N m s/rad"),
    ("coulomb", "real", 1, NONNEG, "Coulomb friction c of the friction feedforward, N m"),
    ("coulomb_width", "real", 1, POS, "width of the Coulomb term's tanh, rad/s"),
    ("null_speed", "real", 1, ANY, "target speed of the null-space management, rad/s")))

#: the enumerated guidance keys: value -> the firmware's enum value (aocs_guidance_mode_t,
#: aocs_slew_profile_t, executive.h and guidance/slew.h order), and the words of fsw_node's message
_ENUMS = {"guidance_mode": ({"step": 0, "slew": 1}, "is neither step nor slew"),
          "slew_profile": ({"bang_coast_bang": 0, "jerk_limited": 1}, "is neither bang_coast_bang nor jerk_limited")}

#: how node_config.c's LAW_KEY_ROW reads a field of each registry type: (kind, count or None = the field's)
_LAW_KEY_KIND = {"real": ("real", None), "vec3": ("real", None), "gain": ("real", None),
                 "mat3": ("inertia", 1), "table": ("gain_table", 1)}


@lru_cache(maxsize=None)
def _keys(reg: registry.Registry) -> tuple[Key, ...]:
    out = []
    for name, kind, count, rule, help_ in _GENERAL:
        x = reg.exec_field_of_key(name)
        out.append(Key(name, kind, count, rule, help_, x.name if x is not None else None))
    for f in reg.fields:
        kind, count = _LAW_KEY_KIND[f.type]
        out.append(Key(f.key, kind, count if count is not None else f.count, f.rule, f.unit, f.name,
                       f.law if f.type == "table" else None))
    return tuple(out)


def keys() -> tuple[Key, ...]:
    """node_config.c KEYS, in the same order: the general keys, then every law field of the registry."""
    return _keys(registry.load())


def key_by_name() -> dict[str, Key]:
    return {k.name: k for k in keys()}


def _table_exclusions(reg: registry.Registry) -> list[tuple[str, str]]:
    """(`<law>.table` key, the `<law>.k` key it excludes) for every TABLE field."""
    return [(f.key, reg.gain_field_of(f).key) for f in reg.fields if f.type == "table"]


LINE_MAX = 1022          # fgets buffer of 1024: 1022 characters + newline + NUL
URL_MAX = 255            # AOCS_NODE_URL_MAX - 1
_SPACE = " \t\n\v\f\r"   # C isspace() in the C locale
_DBL_MIN = 2.2250738585072014e-308

_HEX = re.compile(r"[+-]?0[xX](?:[0-9a-fA-F]+\.?[0-9a-fA-F]*|\.[0-9a-fA-F]+)(?:[pP][+-]?[0-9]+)?")
_DEC = re.compile(r"[+-]?(?:[0-9]+\.?[0-9]*|\.[0-9]+)(?:[eE][+-]?[0-9]+)?")
_SPECIAL = re.compile(r"[+-]?(?:infinity|inf|nan(?:\([0-9A-Za-z_]*\))?)", re.I)


class ConfigError(ValueError):
    """A configuration fsw_node would reject; str() is fsw_node's message."""


@dataclass
class NodeConfig:
    path: str
    law: str = "none"
    run_mode: str = "lockstep"
    period_s: float = 0.1
    idle_timeout_s: float = 5.0
    run_timeout_s: float = 0.0
    status_period_s: float = 1.0
    lcm_url: str = ""
    budget_ns: int = 0
    stale_timeout_ns: int | None = None
    #: (key name, parsed value) in file order, executive keys only
    values: list = field(default_factory=list)
    lines: dict = field(default_factory=dict)

    def pil_fields(self, clock_hz: float) -> frame.ConfigFields:
        """The CONFIG field list the image applies (aocs_pil_config_decode)."""
        out = frame.ConfigFields()
        by_name = key_by_name()
        for name, value in self.values:
            key = by_name[name]
            if name == "budget_ns":
                if value > 0:
                    # a ns budget at the target's nominal clock, one instruction per cycle
                    out.add(key.pil, int(math.ceil(value * clock_hz / 1e9)))
                continue
            if name == "stale_timeout_s":
                continue
            if name == "law":
                out.add(key.pil, registry.law_ids()[value])
            elif key.kind in _ENUMS:
                out.add(key.pil, _ENUMS[key.kind][0][value])
            elif key.kind == "inertia":
                if len(value) == 3:
                    value = [value[0], 0.0, 0.0, 0.0, value[1], 0.0, 0.0, 0.0, value[2]]
                out.add(key.pil, value)
            elif key.kind == "gain_table":
                out.add(key.pil, value)
            elif key.kind == "u32":
                out.add(key.pil, int(value))
            else:
                out.add(key.pil, value)
        out.add(key_by_name()["stale_timeout_s"].pil, self.stale_timeout_ns or 0)
        return out


def _strtod_token(text: str, i: int) -> tuple[float | None, int]:
    """strtod at text[i:]: (value, end) or (None, i) when nothing parses."""
    for rx in (_HEX, _DEC, _SPECIAL):
        m = rx.match(text, i)
        if m:
            tok = m.group(0)
            if rx is _HEX:
                sign = -1.0 if tok.startswith("-") else 1.0
                body = tok.lstrip("+-")
                if "p" not in body.lower():
                    body += "p0"
                return sign * float.fromhex(body), m.end()
            if rx is _SPECIAL:
                low = tok.lower().lstrip("+-")
                neg = tok.startswith("-")
                return (float("nan") if low.startswith("nan") else (-math.inf if neg else math.inf)), m.end()
            return float(tok), m.end()
    return None, i


def _erange(tok: str, x: float) -> bool:
    """strtod's ERANGE: overflow to infinity, or a non-zero number that underflows."""
    if math.isinf(x) and "inf" not in tok.lower():
        return True
    digits = re.sub(r"[eEpP].*$", "", tok.lower().replace("0x", ""))
    nonzero = any(c not in "0.+-" for c in digits)
    return nonzero and abs(x) < _DBL_MIN


def parse_numbers(value: str, maximum: int) -> list[float]:
    """node_config.c parse_numbers: blank- or comma-separated finite numbers.

    Raises ValueError(('bad', rest_of_value)) for a bad token, ValueError(('many', ...)) past maximum.
    """
    out: list[float] = []
    i, n = 0, len(value)
    while True:
        while i < n and (value[i] in _SPACE or value[i] == ","):
            i += 1
        if i >= n:
            return out
        x, end = _strtod_token(value, i)
        if x is None or end == i or _erange(value[i:end], x) or not math.isfinite(x) or \
                (end < n and value[end] not in _SPACE and value[end] != ","):
            raise ValueError(("bad", value[i:]))
        if len(out) >= maximum:
            raise ValueError(("many", value[i:]))
        out.append(x)
        i = end


def _g(x: float) -> str:
    return "%g" % x


def table_names(law: str) -> str:
    return ", ".join(registry.load().tables_for(law))


def _set(cfg: NodeConfig, key: Key, value: str) -> None:
    """aocs_node_config_set: raise ConfigError(message without file/line)."""
    if value == "":
        raise ConfigError(f"key '{key.name}': empty value ({key.help})")
    if key.kind == "law":
        if value not in registry.law_ids():
            raise ConfigError(f"key 'law': unknown law '{value}'")
        cfg.law = value
        cfg.values.append((key.name, value))
        return
    if key.kind in _ENUMS:
        names, words = _ENUMS[key.kind]
        if value not in names:
            raise ConfigError(f"key '{key.name}': '{value}' {words}")
        cfg.values.append((key.name, value))
        return
    if key.kind == "run_mode":
        if value not in ("lockstep", "realtime"):
            raise ConfigError(f"key 'mode': '{value}' is neither lockstep nor realtime")
        cfg.run_mode = value
        return
    if key.kind == "string":
        if len(value.encode()) > URL_MAX:
            raise ConfigError(f"key '{key.name}': longer than {URL_MAX} characters")
        cfg.lcm_url = value
        return
    if key.kind == "gain_table":
        law = key.law
        valid = table_names(law)
        table = registry.load().table(value)
        if table is None:
            raise ConfigError(f"key '{key.name}': unknown gain table '{value}' (valid names: {valid})")
        if table.law != law:
            raise ConfigError(f"key '{key.name}': gain table '{value}' was designed for law {table.law}, "
                              f"not {law} (valid names: {valid})")
        cfg.values.append((key.name, value))
        return
    want = key.count if key.kind == "real" else (9 if key.kind == "inertia" else 1)
    try:
        vals = parse_numbers(value, want)
    except ValueError as exc:
        what, rest = exc.args[0]
        if what == "bad":
            raise ConfigError(f"key '{key.name}': '{rest}' is not a finite number ({key.help})") from None
        raise ConfigError(f"key '{key.name}': too many values ({key.help})") from None
    if key.kind == "inertia":
        if len(vals) not in (3, 9):
            raise ConfigError(f"key '{key.name}': {len(vals)} values given ({key.help})")
        cfg.values.append((key.name, vals))
        return
    if len(vals) != want:
        raise ConfigError(f"key '{key.name}': {len(vals)} value(s) given, {want} expected ({key.help})")
    for x in vals:
        if key.rule == POS and not x > 0.0:
            raise ConfigError(f"key '{key.name}': value {_g(x)} must be > 0 ({key.help})")
        if key.rule == NONNEG and not x >= 0.0:
            raise ConfigError(f"key '{key.name}': value {_g(x)} must be >= 0 ({key.help})")
    x = vals[0]
    if key.kind == "real":
        if key.name == "control_period_s":
            cfg.period_s = x
        cfg.values.append((key.name, vals if want > 1 else x))
    elif key.kind == "double":
        setattr(cfg, key.name, x)
    elif key.kind == "u32":
        if x > 4294967295.0 or math.floor(x) < x:
            raise ConfigError(f"key '{key.name}': {_g(x)} is not a whole number in range ({key.help})")
        cfg.values.append((key.name, int(x)))
    elif key.kind == "u64":
        if x > 1.8e19 or math.floor(x) < x:
            raise ConfigError(f"key '{key.name}': {_g(x)} is not a whole number in range ({key.help})")
        cfg.budget_ns = int(x)
        cfg.values.append((key.name, int(x)))
    elif key.kind == "seconds_ns":
        if x > 1.0e9:
            raise ConfigError(f"key '{key.name}': {_g(x)} s is out of range ({key.help})")
        cfg.stale_timeout_ns = int(x * 1.0e9 + 0.5)
        cfg.values.append((key.name, cfg.stale_timeout_ns))
    else:  # pragma: no cover - every kind is handled above
        raise ConfigError(f"key '{key.name}': internal error (kind)")


def load(path: str | Path) -> NodeConfig:
    """aocs_node_config_load; ConfigError with fsw_node's message on any problem."""
    path = str(path)
    cfg = NodeConfig(path=path)
    try:
        raw = Path(path).read_bytes()
    except OSError as exc:
        raise ConfigError(f"{path}: cannot open: {exc.strerror}") from None
    text = raw.decode("latin-1")
    lines = text.split("\n")
    if lines and lines[-1] == "":
        lines.pop()   # the file ends with a newline
    seen: dict[str, int] = {}
    by_name = key_by_name()
    for lineno, line in enumerate(lines, start=1):
        last_without_newline = (lineno == len(lines)) and not text.endswith("\n")
        if len(line) > LINE_MAX and not (last_without_newline and len(line) == LINE_MAX + 1):
            raise ConfigError(f"{path}:{lineno}: line longer than {LINE_MAX} characters")
        line = line.split("#", 1)[0].strip(_SPACE)
        if not line:
            continue
        if "=" not in line:
            raise ConfigError(f"{path}:{lineno}: expected 'key = value', got '{line}'")
        k, v = line.split("=", 1)
        k, v = k.strip(_SPACE), v.strip(_SPACE)
        key = by_name.get(k)
        if key is not None and k in seen:
            raise ConfigError(f"{path}:{lineno}: key '{k}' given twice")
        if key is None:
            raise ConfigError(f"{path}:{lineno}: unknown key '{k}'")
        try:
            _set(cfg, key, v)
        except ConfigError as exc:
            raise ConfigError(f"{path}:{lineno}: {exc}") from None
        seen[k] = lineno
    for tkey, kkey in _table_exclusions(registry.load()):
        lt, lk = seen.get(tkey, 0), seen.get(kkey, 0)
        if lt and lk:
            raise ConfigError(f"{path}:{max(lt, lk)}: keys '{tkey}' (line {lt}) and '{kkey}' (line {lk}) are "
                              "mutually exclusive: give the gain by table name or by value, not both")
    problem = timeouts_problem(cfg)
    if problem:
        raise ConfigError(f"{path}: {problem}")
    if "stale_timeout_s" not in seen:
        p = cfg.period_s
        cfg.stale_timeout_ns = int(2.0e9 * p + 0.5) if 0.0 < p < 1.0e6 else 0
    cfg.lines = seen
    return cfg


def timeout_ranges() -> dict[str, tuple[float, float]]:
    """fsw_node's timeout ranges, s, read from sil/fsw_node/node_checks.h (their one definition)."""
    def macro(name):
        return paths.header_number("sil/fsw_node/node_checks.h", f"AOCS_NODE_{name}")
    return {"idle_timeout_s": (macro("IDLE_TIMEOUT_MIN_S"), macro("IDLE_TIMEOUT_MAX_S")),
            "run_timeout_s": (macro("RUN_TIMEOUT_MIN_S"), macro("RUN_TIMEOUT_MAX_S")),
            "status_period_s": (macro("STATUS_PERIOD_MIN_S"), macro("STATUS_PERIOD_MAX_S"))}


def timeouts_problem(cfg: NodeConfig) -> str | None:
    """node_checks.c aocs_node_timeouts_check: the first timeout out of its range, in fsw_node's words."""
    for key in ("idle_timeout_s", "run_timeout_s", "status_period_s"):
        lo, hi = timeout_ranges()[key]
        v = getattr(cfg, key)
        if key == "run_timeout_s" and v == 0.0:
            continue
        if not lo <= v <= hi:
            extra = " or 0 (no limit)" if key == "run_timeout_s" else ""
            return f"key '{key}': {_g(v)} s is outside [{_g(lo)}, {_g(hi)}] s{extra}"
    return None


def status_hint(status_name: str, law: str) -> str:
    """fsw_node's status_keys(): which keys to check for an aocs_exec_init status."""
    reg = registry.load()
    table = reg.table_field(law) if law in reg.law_ids() else None
    gain = f"{reg.gain_field_of(table).key} / {table.key}" if table is not None else "the gains of the selected law"
    return {
        "AOCS_ERR_RATE_INVALID": "control_period_s",
        "AOCS_ERR_TARGET_INVALID": "target_q / target_w / target_w_dot / target_rotation_rate (a rotating target "
                                   "needs target_w = target_w_dot = 0)",
        "AOCS_ERR_SAT_LIMIT_NOT_POSITIVE": "u_max_axis / u_max_norm (set at least one limit; per-axis all > 0)",
        "AOCS_ERR_GAIN_NOT_POSITIVE": "the gains of the selected law, k_safe, recover_good_samples, "
                                      "missing_max_periods, stale_timeout_s",
        "AOCS_ERR_INERTIA_NOT_SYMMETRIC": "inertia",
        "AOCS_ERR_INERTIA_NOT_POS_DEF": "inertia",
        "AOCS_ERR_INERTIA_SINGULAR": "inertia",
        "AOCS_ERR_GAIN_TABLE_INVALID": gain,
        "AOCS_ERR_PARAM_NOT_FINITE": "u_max_*, k_safe or a gain of the selected law",
        "AOCS_ERR_GUIDANCE_MODE_INVALID": "guidance.mode",
        "AOCS_ERR_GUIDANCE_PROFILE_INVALID": "guidance.profile",
        "AOCS_ERR_GUIDANCE_MARGIN_INVALID": "guidance.margin (in (0, 1])",
        "AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID": "guidance.rate_limit",
        "AOCS_ERR_GUIDANCE_JERK_TIME_INVALID": "guidance.jerk_time (> 0 and <= 1000 s with jerk_limited, 0 with "
                                               "bang_coast_bang)",
        "AOCS_ERR_GUIDANCE_TARGET_MOVING": "guidance.mode = slew needs target_w = target_w_dot = "
                                           "target_rotation_rate = 0",
        "AOCS_ERR_GUIDANCE_ENVELOPE_INVALID": "u_max_axis / u_max_norm",
        **{f"AOCS_ERR_{w}": "wheels.count / wheels.failed_mask / wheel<i>.axis, .js, .u_max, .omega_max"
           for w in ("WHEEL_COUNT", "WHEEL_FAILED_MASK", "WHEEL_AXIS_NOT_UNIT", "WHEEL_INERTIA_NOT_POSITIVE",
                     "WHEEL_LIMIT_NOT_POSITIVE", "WHEELS_NOT_SPANNING")},
        **{f"AOCS_ERR_{w}": "wheel<i>.viscous, .coulomb, .coulomb_width (b omega_max + c < u_max)"
           for w in ("WHEEL_FRICTION_NEGATIVE", "WHEEL_FRICTION_WIDTH_NOT_POSITIVE", "WHEEL_FRICTION_EXCEEDS_LIMIT")},
        "AOCS_ERR_WHEEL_NULL_GAIN_INVALID": "wheels.null_gain (>= 0, null_gain * control_period_s <= 1)",
        "AOCS_ERR_WHEEL_NULL_SPEED_INVALID": "wheel<i>.null_speed (|null_speed| < omega_max)",
    }.get(status_name, "the keys of the selected law")
