"""The law registry of the flight software, as the build wrote it.

Every fact about a control law is a row of firmware/include/aocs/laws.def
(one row per law, one per configuration field), every gain table a row of
firmware/gains/gain_tables.def (written by `aocs gains`). The host build
expands them into <build>/registry/aocs_registry.json (tools/registry,
aocs_registry_dump, run on every `cmake --build`); this module is the one
place Python reads it. Law ids and names, which fields a law takes (fsw_node
keys, types, counts, rules, units, PIL ids), budgets, gain tables, status
and mode names, the layouts of the fixed PIL payloads: nothing of it is typed
again in Python.

The build directory is paths.build_dir() (AOCS_BUILD_DIR, default
build/host); the file is read once per path and cached. A missing file raises
paths.SetupError saying how to build it.
"""
from __future__ import annotations

import json
import math
from dataclasses import dataclass
from functools import lru_cache
from pathlib import Path

from . import paths

#: the registry file, relative to the build directory
JSON_PATH = Path("registry") / "aocs_registry.json"
#: the schema this module reads (aocs_registry_dump.c DUMP_SCHEMA)
SCHEMA = 3
#: the PIL targets' names in the registry's instruction budgets
TARGETS = ("cortex-m4f", "cortex-m7")
#: the plant's [wheels] key -> the configuration registry's field of the flight software's value of it
#: (config_fields.def; per wheel as wheel<i>.<field>, the others as they are): the plant's loader checks each
#: value against that row's range (aocs_plant.effectors.reaction_wheels) and the configuration writer gives the
#: flight software the plant's value under that key (aocs_flightcfg.fsw_config.wheel_keys)
WHEEL_REGISTRY_ROWS = {"spin_inertia_kg_m2": "js_kgm2", "torque_limit_nm": "u_max_nm",
                       "speed_limit_rad_s": "omega_max_radps", "viscous_nms": "viscous_nms",
                       "coulomb_nm": "coulomb_nm", "coulomb_width_rad_s": "coulomb_width_radps",
                       "null_speed_rad_s": "null_speed_radps", "null_gain_per_s": "wheels.null_gain"}


@dataclass(frozen=True)
class Field:
    """One configuration field of a law (an AOCS_LAW_FIELD_ROWS row)."""
    key: str              # fsw_node configuration key, "quat_pd.kp"
    name: str             # PIL field name, AOCS_PIL_CFG_<name>
    law: str              # the law whose config holds it (for a table: whose tables it takes)
    config: str           # that law's config member
    member: str           # path in the executive's law configs, "quat_pd.kp"
    type: str             # real, vec3, mat3, gain, table
    count: int            # values on the PIL wire (1 name for a table)
    rule: str             # any, pos, nonneg (the node's sign rule)
    unit: str             # unit and meaning (the node's error messages)
    pil_id: int           # CONFIG field id
    variant: str | None   # None: every variant of the config; else the one variant using it
    ref: str              # reference value in configuration-file syntax ("" = none)

    @property
    def param(self) -> str:
        """The field's name inside its law (the member without the config): the scenario parameter."""
        return self.member.split(".", 1)[1]


@dataclass(frozen=True)
class Law:
    """One control law (an AOCS_LAW_ROWS row), or "none" (STANDBY, id 0)."""
    id: int
    name: str
    input: str                    # attitude, orbit ("" for none)
    title: str                    # one line: spec section and what the law is
    config: str                   # config member ("" for none)
    variant: str | None           # the variant value the law id forces (an enum constant), None
    budget_ns: int                # declared host budget of one step
    budget_instructions: dict     # target -> instructions of one executive step
    reference_scenario: str       # sil/scenarios/<name>.toml ("" for none)
    field_keys: tuple[str, ...]   # the keys of the fields its config takes
    from_field: str | None = None  # laws.def FROM_FIELD: the member of another law's field copied in at init

    @property
    def is_orbit(self) -> bool:
        return self.input == "orbit"


@dataclass(frozen=True)
class GainTable:
    id: int
    name: str       # design name
    law: str        # the law whose gain layout it has


@dataclass(frozen=True)
class ExecField:
    """A PIL CONFIG field of the executive itself (AOCS_PIL_EXEC_FIELD_ROWS)."""
    name: str
    pil_id: int
    kind: str            # real, u64
    count: int
    key: str | None      # the fsw_node key the bridge takes it from


@dataclass(frozen=True)
class ConfigField:
    """One row of the configuration registry (aocs/config_registry.h): a general, per-wheel or law field."""
    key: str              # configuration-file key; per-wheel: the field ("js_kgm2" of wheel<i>.js_kgm2); "" = adapter only
    pil_name: str         # AOCS_PIL_CFG_<pil_name> (per wheel: WHEEL<i>_<pil_name>)
    pil_id: int           # PIL CONFIG id (per wheel: of wheel 0)
    per_wheel: bool
    kind: str             # reals, inertia, u32, u64, ns, budget, law, enum, table
    count: int            # values on the wire
    rule: str             # any, pos, nonneg, or a physical range (config_fields.def AOCS_CONFIG_RULE_ROWS)
    names: tuple[str, ...]  # enum: its value names in order
    law: str | None       # a law field: the law
    status: str | None    # the aocs_exec_init status that names it
    help: str             # unit and meaning
    default: object = None  # aocs_exec_config_default's value: a list of reals, an integer (enum, law: its
    #                         index; ns), None for a table
    rule_lo: float = -math.inf     # the rule's range: [rule_lo, rule_hi] ((lo, hi] when rule_lo_open), or 0
    rule_lo_open: bool = False     # when rule_zero_ok
    rule_hi: float = math.inf
    rule_zero_ok: bool = False
    rule_text: str = "finite"      # the range as the flight software's messages say it

    def holds(self, x: float) -> bool:
        """The rule on one value, as the flight software's aocs_config_rule_holds applies it."""
        if not math.isfinite(x):
            return False
        if self.rule_zero_ok and x == 0.0:
            return True
        return (x > self.rule_lo if self.rule_lo_open else x >= self.rule_lo) and x <= self.rule_hi


@dataclass(frozen=True)
class PayloadField:
    """One row of a fixed PIL payload (pil_frame.h AOCS_PIL_<NAME>_ROWS), in wire order."""
    name: str             # the field's name on the host (the attribute of aocs_pil.frame's payload)
    kind: str             # u32, u64, status, law, mode, pil_err, real, vec3, quat, wheels, counters
    member: str           # the C struct member it travels in
    wire: str             # u32, i32, u64, f64 (little-endian; f64 binary64)
    count: int            # values on the wire


@dataclass(frozen=True)
class Payload:
    """A fixed-layout PIL payload (AOCS_PIL_PAYLOAD_ROWS): its rows and its size (AOCS_PIL_<NAME>_BYTES)."""
    name: str             # HELLO, STEP, STEP_REPLY, SELECT, ACK, BYE_REPLY, ERROR
    c_type: str
    bytes: int
    fields: tuple[PayloadField, ...]


@dataclass(frozen=True)
class Event:
    """One row of the fault-management event table (fdir/events.def)."""
    id: int
    name: str
    severity: str        # "info", "warning", "error", "critical"
    unit_kind: str       # "none", "star_tracker", "gyro", "wheel", "thruster", "magnetometer", "link"
    meaning: str


class Registry:
    """The parsed registry JSON of one build."""

    def __init__(self, data: dict, path: Path):
        if data.get("schema") != SCHEMA:
            raise paths.SetupError(f"{path}: registry schema {data.get('schema')!r}, this code reads {SCHEMA}; "
                                   f"rebuild ({paths.BUILD_HINT})")
        self.path = path
        self.real_t: str = data["real_t"]
        self.table_name_max: int = data["pil"]["table_name_max"]
        #: per-wheel PIL ids: wheel i's field of index j is wheel_base + i * wheel_stride + j, i < wheels_max
        self.wheel_base: int = data["pil"]["wheel_base"]
        self.wheel_stride: int = data["pil"]["wheel_stride"]
        self.wheels_max: int = data["pil"]["wheels_max"]
        #: instruction allowances added to a step's budget (aocs/budget.h), per target ("cortex-m4f", "cortex-m7"):
        #: guidance mode SLEW, and a reaction wheel array
        self.slew_instructions: dict[str, int] = dict(data["pil"]["slew_instructions"])
        self.wheels_instructions: dict[str, int] = dict(data["pil"]["wheels_instructions"])
        #: fault management (fdir.enabled, on by default): added to every step's budget
        self.fdir_instructions: dict[str, int] = dict(data["pil"].get("fdir_instructions", {}))
        #: the attitude-determination rows: name -> (host budget ns, {target: instructions}) each adds to every step
        self.estimators: dict[str, tuple[int, dict[str, int]]] = {
            e["name"]: (e["budget_ns"], dict(e["budget_instructions"])) for e in data["estimators"]}
        #: momentum.def rows: name -> (host budget ns, {target: instructions}) each adds to every step
        self.momentum_policies: dict[str, tuple[int, dict[str, int]]] = {
            e["name"]: (e["budget_ns"], dict(e["budget_instructions"])) for e in data.get("momentum_policies", ())}
        self.fields: tuple[Field, ...] = tuple(
            Field(f["key"], f["name"], f["law"], f["config"], f["member"], f["type"], f["count"], f["rule"],
                  f["unit"], f["pil_id"], f["variant"], f["ref"]) for f in data["fields"])
        n = data["none"]
        self.none = Law(n["id"], n["name"], "", "standby: zero command", "", None, n["budget_ns"], dict(n["budget_instructions"]), "", ())
        self.laws: tuple[Law, ...] = tuple(
            Law(x["id"], x["name"], x["input"], x["title"], x["config"], (x["variant"] or {}).get("value"), x["budget_ns"],
                dict(x["budget_instructions"]), x["reference_scenario"], tuple(x["fields"]),
                (x.get("from_field") or {}).get("field")) for x in data["laws"])
        self.gain_tables: tuple[GainTable, ...] = tuple(GainTable(t["id"], t["name"], t["law"])
                                                        for t in data["gain_tables"])
        self.exec_fields: tuple[ExecField, ...] = tuple(
            ExecField(x["name"], x["pil_id"], x["kind"], x["count"], x["key"]) for x in data["pil_exec_fields"])
        self.config_fields: tuple[ConfigField, ...] = tuple(
            ConfigField(x["key"], x["pil_name"], x["pil_id"], x["per_wheel"], x["kind"], x["count"], x["rule"],
                        tuple((x["names"] or "").split(",")) if x["names"] else (), x["law"], x["status"], x["help"],
                        x["default"], x["rule_lo"], x["rule_lo_open"], x["rule_hi"], x["rule_zero_ok"],
                        x["rule_text"])
            for x in data["config_fields"])
        #: the fixed PIL payloads by name, and the counters of a STEP_REPLY (their rows, in wire order)
        self.pil_payloads: dict[str, Payload] = {
            x["name"]: Payload(x["name"], x["c_type"], x["bytes"], tuple(PayloadField(**f) for f in x["fields"]))
            for x in data["pil_payloads"]}
        self.pil_counters: tuple[PayloadField, ...] = tuple(PayloadField(**f) for f in data["pil_counters"])
        #: the executive's accepted ranges (executive.h): actuator limits (N m or N), control period (s)
        self.limits: dict[str, float] = {k: float(v) for k, v in data["limits"].items()}
        self.status_names: dict[int, str] = {s["value"]: s["name"] for s in data["status"]}
        self.mode_names: dict[int, str] = {m["value"]: m["name"] for m in data["modes"]}
        #: the fault-management event table (firmware/include/aocs/fdir/events.def): id -> Event; the severity
        #: and unit kind names by value (event_t.severity, event_t.unit_kind on the wire)
        self.events: dict[int, Event] = {
            e["id"]: Event(e["id"], e["name"], e["severity"], e["unit_kind"], e["meaning"])
            for e in data.get("events", ())}
        self.event_severities: dict[int, str] = {x["value"]: x["name"] for x in data.get("event_severities", ())}
        self.event_unit_kinds: dict[int, str] = {x["value"]: x["name"] for x in data.get("event_unit_kinds", ())}
        self._law = {law.name: law for law in (self.none, *self.laws)}
        self._field = {f.key: f for f in self.fields}

    # ---- laws ----
    def law_names(self) -> tuple[str, ...]:
        """Every law name in id order, "none" first (the wire's law_id is the index)."""
        return (self.none.name,) + tuple(law.name for law in self.laws)

    def law_ids(self) -> dict[str, int]:
        return {law.name: law.id for law in (self.none, *self.laws)}

    def law(self, name: str) -> Law:
        """The law of that name ("none" included); KeyError naming the valid ones."""
        try:
            return self._law[name]
        except KeyError:
            raise KeyError(f"unknown law {name!r} (laws: {', '.join(self.law_names())})") from None

    def law_by_id(self, law_id: int) -> Law | None:
        ids = {law.id: law for law in (self.none, *self.laws)}
        return ids.get(int(law_id))

    def laws_of_input(self, kind: str) -> tuple[str, ...]:
        """The law names of one input kind (attitude, orbit), in id order."""
        return tuple(law.name for law in self.laws if law.input == kind)

    # ---- fields ----
    def field(self, key: str) -> Field:
        return self._field[key]

    def fields_of(self, law: str) -> tuple[Field, ...]:
        """The fields law's config takes (its variant's), in registry order."""
        return tuple(self._field[k] for k in self.law(law).field_keys)

    def table_field(self, law: str) -> Field | None:
        """The law's TABLE field (a gain given by table name), None when it has none."""
        return next((f for f in self.fields_of(law) if f.type == "table"), None)

    def gain_field_of(self, table_field: Field) -> Field:
        """The GAIN field a TABLE field fills (same member): the key that gives the gain by value."""
        return next(f for f in self.fields if f.type == "gain" and f.member == table_field.member)

    # ---- gain tables ----
    def tables_for(self, law: str) -> tuple[str, ...]:
        """Design names of the compiled gain tables of a law, in table id order."""
        return tuple(t.name for t in self.gain_tables if t.law == law)

    def table(self, name: str) -> GainTable | None:
        return next((t for t in self.gain_tables if t.name == name), None)

    # ---- PIL ----
    def pil_fields(self) -> dict[str, tuple[int, str, int]]:
        """Every PIL CONFIG field: name -> (id, kind, count); kind 'f' binary64, 'u' uint64, 's' a name."""
        out = {x.name: (x.pil_id, "u" if x.kind == "u64" else "f", x.count) for x in self.exec_fields}
        for f in self.fields:
            out[f.name] = (f.pil_id, "s", 0) if f.type == "table" else (f.pil_id, "f", f.count)
        return out

    def config_field(self, key: str) -> ConfigField | None:
        """The configuration registry's row of a file key ("control_period_s", "wheel2.js_kgm2", "quat_pd.kp"); None if none."""
        if key.startswith("wheel") and len(key) > 7 and key[5].isdigit() and key[6] == ".":
            return next((f for f in self.config_fields if f.per_wheel and f.key == key[7:]), None)
        return next((f for f in self.config_fields if not f.per_wheel and f.key == key and key), None)

    def config_key_of_pil_id(self, pil_id: int) -> str | None:
        """The file key of a PIL CONFIG id (wheel<i>.<field> for a per-wheel one); None if none."""
        base, stride = self.wheel_base, self.wheel_stride
        if base <= pil_id < base + self.wheels_max * stride:
            i, j = divmod(pil_id - base, stride)
            f = next((f for f in self.config_fields if f.per_wheel and f.pil_id == base + j), None)
            return f"wheel{i}.{f.key}" if f is not None else None
        f = next((f for f in self.config_fields if not f.per_wheel and f.pil_id == pil_id), None)
        return (f.key or None) if f is not None else None

    def exec_field_of_key(self, key: str) -> ExecField | None:
        return next((x for x in self.exec_fields if x.key == key), None)


@lru_cache(maxsize=None)
def _load(path: Path) -> Registry:
    if not path.is_file():
        raise paths.SetupError(f"the law registry {path} is missing; {paths.BUILD_HINT}")
    return Registry(json.loads(path.read_text()), path)


def path() -> Path:
    return paths.build_dir() / JSON_PATH


def load() -> Registry:
    """The registry of the current build directory (cached per path)."""
    return _load(path())


# ---- the facts most callers need, by name ----
def law_ids() -> dict[str, int]:
    """Law name -> wire id ("none" = 0), id order."""
    return load().law_ids()


def law_names() -> tuple[str, ...]:
    """Law names in id order, "none" first."""
    return load().law_names()


def law_name(law_id: int) -> str:
    law = load().law_by_id(law_id)
    return law.name if law is not None else f"law {int(law_id)}"


def law_budget_ns(law: str) -> int:
    """Declared host step budget of a law (ns); the safe/standby budget for "none"."""
    return load().law(law).budget_ns


def estimator_budget_ns(estimator: str) -> int:
    """Host budget an estimator (the configuration key "estimator"; "passthrough" when absent) adds to every
    step, ns (estimation/determination.def)."""
    return load().estimators[estimator][0]


def status_name(code: int) -> str:
    """Name of an aocs_status_t value ("AOCS_ERR_GAIN_NOT_POSITIVE"), "status N" when out of range."""
    return load().status_names.get(int(code), f"status {int(code)}")


def status_code(name: str) -> int:
    """aocs_status_t value of a status name (KeyError when the firmware has no such status)."""
    for code, n in load().status_names.items():
        if n == name:
            return code
    raise KeyError(f"no aocs_status_t named {name}")


def mode_name(mode: int) -> str:
    """Name of an executive mode value ("standby", "nominal", "safe"), the number as text when unknown."""
    return load().mode_names.get(int(mode), str(int(mode)))


def events() -> dict[int, "Event"]:
    """The fault-management event table of the build, by id (firmware/include/aocs/fdir/events.def)."""
    return load().events


def event_severity_name(value: int) -> str:
    """Name of an event severity value ("warning"), the number as text when unknown."""
    return load().event_severities.get(int(value), str(int(value)))


def event_unit_kind_name(value: int) -> str:
    """Name of an event unit kind value ("wheel"), the number as text when unknown."""
    return load().event_unit_kinds.get(int(value), str(int(value)))
