"""The fsw_node configuration file, read exactly as fsw_node reads it.

Format and keys: docs/wire-contract.md, "Configuration file"; the reference
implementation is sil/fsw_node/node_config.c, which this module mirrors rule
for rule (same keys, value counts, sign rules, number syntax of strtod, error
messages with file, line and key), so a file fsw_node accepts the bridge
accepts with the same values, and a file it rejects the bridge rejects with
the same message. tests/python/aocs_pil/test_frame.py holds the two side by side.

The executive's own validation (aocs_exec_init: ordering rules, inertia,
limits, gain tables) is not repeated here: the image runs it on the CONFIG
frame and the bridge reports its status like fsw_node does.
"""
from __future__ import annotations

import math
import re
from dataclasses import dataclass, field
from pathlib import Path

from . import frame

#: law names in aocs_law_id_t order (executive.h, docs/wire-contract.md "Law ids")
LAW_NAMES = ("none", "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc", "lqr_quat", "hinf",
             "mrp_sat", "mrp_sat_tanh", "orbit_lqr")
LAW_IDS = {name: i for i, name in enumerate(LAW_NAMES)}

#: compiled gain tables in aocs_gain_table_id_t order: (design name, law)
GAIN_TABLES = (("lqr_quat_ref", "lqr_quat"), ("lqr_quat_strong", "lqr_quat"), ("hinf_min", "hinf"),
               ("hinf_regional", "hinf"), ("orbit_lqr_q1", "orbit_lqr"), ("orbit_lqr_q01", "orbit_lqr"),
               ("orbit_lqr_q10", "orbit_lqr"))

#: `<law>.table` key -> (law, the `<law>.k` key it excludes)
TABLE_KEYS = {"lqr_quat.table": ("lqr_quat", "lqr_quat.k"), "hinf.table": ("hinf", "hinf.k"),
              "orbit_lqr.table": ("orbit_lqr", "orbit_lqr.k")}

ANY, POS, NONNEG = "any", "pos", "nonneg"


@dataclass(frozen=True)
class Key:
    name: str
    kind: str        # real double u32 u64 seconds_ns law run_mode string inertia gain_table
    count: int
    rule: str
    help: str
    pil: str | None  # PIL CONFIG field (frame.CFG_FIELDS), None = bridge-only key


#: node_config.c KEYS, in the same order
KEYS = (
    Key("law", "law", 1, ANY, "law name (executive.h), none = standby", "LAW"),
    Key("mode", "run_mode", 1, ANY, "lockstep | realtime", None),
    Key("control_period_s", "real", 1, POS, "s", "PERIOD_S"),
    Key("target_q", "real", 4, ANY, "4 numbers, scalar last, unit", "TARGET_Q"),
    Key("target_w", "real", 3, ANY, "rad/s, 3 numbers", "TARGET_W"),
    Key("target_w_dot", "real", 3, ANY, "rad/s^2, 3 numbers", "TARGET_W_DOT"),
    Key("target_rotation_rate", "real", 3, ANY,
        "rad/s, 3 numbers: constant rate of the target frame w.r.t. N, in the target frame",
        "TARGET_ROTATION_RATE"),
    Key("u_max_axis", "real", 3, NONNEG, "N m (N) per axis, 3 numbers", "U_MAX_AXIS"),
    Key("u_max_norm", "real", 1, NONNEG, "N m (N), 0 = unused", "U_MAX_NORM"),
    Key("k_safe", "real", 1, POS, "N m s/rad", "K_SAFE"),
    Key("recover_good_samples", "u32", 1, POS, "count >= 1", "RECOVER_GOOD_SAMPLES"),
    Key("missing_max_periods", "u32", 1, POS, "count >= 1", "MISSING_MAX_PERIODS"),
    Key("stale_timeout_s", "seconds_ns", 1, POS, "s", "STALE_TIMEOUT_NS"),
    Key("budget_ns", "u64", 1, NONNEG, "ns, 0 = the law's budget", "BUDGET_INSTR"),
    Key("idle_timeout_s", "double", 1, POS, "s", None),
    Key("run_timeout_s", "double", 1, NONNEG, "s, 0 = none", None),
    Key("status_period_s", "double", 1, POS, "s", None),
    Key("lcm_url", "string", 1, ANY, "LCM provider URL", None),
    Key("inertia", "inertia", 1, ANY, "kg m^2: 3 numbers (diagonal) or 9 (row-major)", "INERTIA"),
    Key("crp_linear.k1", "real", 1, POS, "N m s/rad", "CRP_K1"),
    Key("crp_linear.k2", "real", 1, POS, "N m", "CRP_K2"),
    Key("quat_pd.kp", "real", 1, POS, "N m", "QUAT_PD_KP"),
    Key("quat_pd.kd", "real", 1, POS, "N m s/rad", "QUAT_PD_KD"),
    Key("quat_nlpd.kp", "real", 1, POS, "N m", "QUAT_NLPD_KP"),
    Key("quat_nlpd.kd", "real", 1, POS, "N m s/rad", "QUAT_NLPD_KD"),
    Key("smc.lambda", "real", 3, POS, "diagonal of Lambda, 3 numbers", "SMC_LAMBDA"),
    Key("smc.g", "real", 3, POS, "diagonal of G, 3 numbers", "SMC_G"),
    Key("smc.eps", "real", 3, POS, "boundary layers, 3 numbers", "SMC_EPS"),
    Key("lqr_quat.k", "real", 18, ANY, "3x6 gain, 18 numbers row-major, columns qe_vec then we", "LQR_QUAT_K"),
    Key("lqr_quat.table", "gain_table", 1, ANY, "gain table design name", "LQR_QUAT_TABLE"),
    Key("hinf.k", "real", 18, ANY, "3x6 gain u = K x, 18 numbers row-major, columns phi theta psi then rates",
        "HINF_K"),
    Key("hinf.table", "gain_table", 1, ANY, "gain table design name", "HINF_TABLE"),
    Key("mrp_sat.k", "real", 1, POS, "N m s", "MRP_K"),
    Key("mrp_sat.lambda", "real", 1, POS, "attitude gain", "MRP_LAMBDA"),
    Key("mrp_sat.u_max", "real", 1, POS, "N m, bound on |u|_2", "MRP_U_MAX"),
    Key("mrp_sat.l1", "real", 3, POS, "S1 linear zone, 3 numbers", "MRP_L1"),
    Key("mrp_sat.m1", "real", 3, POS, "S1 bound, 3 numbers", "MRP_M1"),
    Key("mrp_sat.l2", "real", 3, POS, "S2 linear zone, 3 numbers", "MRP_L2"),
    Key("mrp_sat.m2", "real", 3, POS, "S2 bound, 3 numbers", "MRP_M2"),
    Key("orbit_lqr.k", "real", 18, ANY,
        "3x6 gain F = -K x, 18 numbers row-major, columns du dv dw then dx dy dz", "ORBIT_K"),
    Key("orbit_lqr.table", "gain_table", 1, ANY, "gain table design name", "ORBIT_TABLE"),
)
KEY_BY_NAME = {k.name: k for k in KEYS}

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
        for name, value in self.values:
            key = KEY_BY_NAME[name]
            if name == "budget_ns":
                if value > 0:
                    # a ns budget at the target's nominal clock, one instruction per cycle
                    out.add("BUDGET_INSTR", int(math.ceil(value * clock_hz / 1e9)))
                continue
            if name == "stale_timeout_s":
                continue
            if name == "law":
                out.add("LAW", LAW_IDS[value])
            elif key.kind == "inertia":
                if len(value) == 3:
                    value = [value[0], 0.0, 0.0, 0.0, value[1], 0.0, 0.0, 0.0, value[2]]
                out.add("INERTIA", value)
            elif key.kind == "gain_table":
                out.add(key.pil, value)
            elif key.kind == "u32":
                out.add(key.pil, int(value))
            else:
                out.add(key.pil, value)
        out.add("STALE_TIMEOUT_NS", self.stale_timeout_ns or 0)
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
    return ", ".join(name for name, tlaw in GAIN_TABLES if tlaw == law)


def _set(cfg: NodeConfig, key: Key, value: str) -> None:
    """aocs_node_config_set: raise ConfigError(message without file/line)."""
    if value == "":
        raise ConfigError(f"key '{key.name}': empty value ({key.help})")
    if key.kind == "law":
        if value not in LAW_IDS:
            raise ConfigError(f"key 'law': unknown law '{value}'")
        cfg.law = value
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
        law = TABLE_KEYS[key.name][0]
        valid = table_names(law)
        names = dict(GAIN_TABLES)
        if value not in names:
            raise ConfigError(f"key '{key.name}': unknown gain table '{value}' (valid names: {valid})")
        if names[value] != law:
            raise ConfigError(f"key '{key.name}': gain table '{value}' was designed for law {names[value]}, "
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
        key = KEY_BY_NAME.get(k)
        if key is not None and k in seen:
            raise ConfigError(f"{path}:{lineno}: key '{k}' given twice")
        if key is None:
            raise ConfigError(f"{path}:{lineno}: unknown key '{k}'")
        try:
            _set(cfg, key, v)
        except ConfigError as exc:
            raise ConfigError(f"{path}:{lineno}: {exc}") from None
        seen[k] = lineno
    for tkey, (_, kkey) in TABLE_KEYS.items():
        lt, lk = seen.get(tkey, 0), seen.get(kkey, 0)
        if lt and lk:
            raise ConfigError(f"{path}:{max(lt, lk)}: keys '{tkey}' (line {lt}) and '{kkey}' (line {lk}) are "
                              "mutually exclusive: give the gain by table name or by value, not both")
    if "stale_timeout_s" not in seen:
        p = cfg.period_s
        cfg.stale_timeout_ns = int(2.0e9 * p + 0.5) if 0.0 < p < 1.0e6 else 0
    cfg.lines = seen
    return cfg


def status_hint(status_name: str, law: str) -> str:
    """fsw_node's status_keys(): which keys to check for an aocs_exec_init status."""
    gain = {"lqr_quat": "lqr_quat.k / lqr_quat.table", "hinf": "hinf.k / hinf.table",
            "orbit_lqr": "orbit_lqr.k / orbit_lqr.table"}.get(law, "the gains of the selected law")
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
    }.get(status_name, "the keys of the selected law")
