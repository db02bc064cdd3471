"""Scenario files (sil/scenarios/<id>.toml): strict loader and validation.

load(path_or_id, overrides=None) -> Scenario (frozen dataclasses, tuples for
vectors). Anything unexpected raises ScenarioError("<file>: <dotted.key>:
<what is wrong>"): unknown or missing keys, wrong types, non-finite numbers,
non-positive or non-symmetric inertia, unknown law names and inconsistent
content. The file format, every key, unit and default: docs/scenarios.md.
The effector sections ([disturbances.<kind>], [actuator]), the sensors' keys
([sensors]) and [environment] are read and validated by their own modules
(aocs_plant.effectors, aocs_plant.sensors, aocs_plant.environment) through
the same section reader.
"""
from __future__ import annotations

import copy
import difflib
import math
import tomllib
from dataclasses import dataclass, field
from pathlib import Path
from types import MappingProxyType
from typing import Any, Mapping

import numpy as np

from aocs_core import limits, paths, registry
from aocs_core.conventions import (
    crp_to_quat,
    euler321_deg_to_quat,
    mrp_to_quat,
    quat_from_rotvec,
    quat_mul,
    quat_normalize,
)

from . import effectors, environment, faults, sensors, target_passes
from .effectors.actuator import ActuatorConfig
from .environment import EnvironmentConfig
from .observation_plan import Observation, ObservationPlan
from .orbit import MU_EARTH, mean_motion
from .sensors import SensorsConfig

SCENARIO_DIR = Path(__file__).resolve().parent.parent / "scenarios"

KINDS = ("attitude", "orbit")
ATTITUDE_INPUTS = ("euler321_deg", "rho", "sigma", "quaternion")


#: integration error above which a run warns (aocs_plant.integration_error): 1e-3 arcsec is 1/50 of
#: the finest pointing figure of the reference scenarios (IRASSI goal 0.05 arcsec); 1e-3 m is 1/100
#: of the Landsat settle band (0.1 m)
INTEGRATION_TOLERANCE_DEFAULT = {"tolerance_arcsec": 1e-3, "tolerance_m": 1e-3}


class ScenarioError(ValueError):
    """A scenario file is malformed or inconsistent; the message names file and key."""


# --------------------------------------------------------------------------- data


@dataclass(frozen=True)
class LawConfig:
    name: str
    params: Mapping[str, Any]            # validated scalars / 3-tuples
    table: str | None = None             # selected gain table (design-based laws)
    tables: Mapping[str, Mapping[str, Any]] = field(default_factory=lambda: MappingProxyType({}))


@dataclass(frozen=True)
class ControlConfig:
    enabled: bool
    law: str
    laws: Mapping[str, LawConfig]


@dataclass(frozen=True)
class AttitudePlantConfig:
    inertia: tuple                       # 3x3 tuple of tuples, kg m^2
    q0: tuple                            # unit quaternion, scalar last
    w0: tuple                            # rad/s, body
    initial_input: tuple                 # (key, value) as written in the file


@dataclass(frozen=True)
class OrbitPlantConfig:
    model: str                           # "linear" | "nonlinear"
    mass_kg: float
    orbit_radius_m: float
    mu: float
    x0: tuple                            # [du dv dw dx dy dz], SPEC 2.8

    @property
    def n(self) -> float:
        return mean_motion(self.mu, self.orbit_radius_m)


@dataclass(frozen=True)
class TargetConfig:
    qd0: tuple                           # target quaternion at t = 0
    wd: tuple                            # constant target rate, rad/s, target frame
    target_input: tuple


class Disturbances(Mapping):
    """The [disturbances.<kind>] configs, in the file's order (each validated by its effector
    module, aocs_plant.effectors): sc.disturbances.constant_torque is that config, or None when
    the file has no such section; an unknown kind is an AttributeError."""

    def __init__(self, configs: Mapping[str, Any] | None = None):
        object.__setattr__(self, "_configs", MappingProxyType(dict(configs or {})))

    def __getattr__(self, name: str):
        if name.startswith("_"):
            raise AttributeError(name)
        if name in self._configs:
            return self._configs[name]
        if name in effectors.disturbance_kinds():
            return None
        raise AttributeError(f"no disturbance kind {name!r}")

    def __setattr__(self, name, value):
        raise AttributeError("Disturbances is read-only")

    def __getitem__(self, name: str):
        return self._configs[name]

    def __iter__(self):
        return iter(self._configs)

    def __len__(self) -> int:
        return len(self._configs)

    def active(self, name: str):
        d = getattr(self, name)
        return d if (d is not None and d.enabled) else None


@dataclass(frozen=True)
class SettleConfig:
    rho_norm_max: float | None = None
    w_norm_max_rad_s: float | None = None
    pointing_arcsec_max: float | None = None
    angle_abs_max_rad: float | None = None
    rate_abs_max_rad_s: float | None = None
    sigma_norm_max: float | None = None
    pos_abs_max_m: float | None = None
    vel_abs_max_m_s: float | None = None


@dataclass(frozen=True)
class MetricsConfig:
    window_s: float
    requirement_arcsec: float | None = None
    goal_arcsec: float | None = None
    # what the holds of a [[plan]] are judged against (docs/spec.md 5.11.6): "requirement" (requirement_arcsec)
    # or "sensors" (1.5 x the steady-state knowledge rms of the MEKF's star tracker and gyro)
    hold_requirement: str = "requirement"
    #: the pointing a fault recovery is judged against (arcsec; docs/spec.md 5.14.7), when the scenario's sensors
    #: cannot reach the requirement; None: the requirement
    recovery_arcsec: float | None = None


#: [guidance]'s keys are the flight software's guidance.* keys (the configuration registry), without the prefix
GUIDANCE_PREFIX = "guidance."


@dataclass(frozen=True)
class GuidanceConfig:
    """[guidance]: the flight software's slew guidance (docs/spec.md "Slew guidance", fsw_node keys
    guidance.*). mode "step" (default) is the reference papers' behaviour: the law sees the final target
    at once. "slew": a rest-to-rest eigenaxis slew from the attitude at the command."""
    mode: str = "step"
    profile: str = "bang_coast_bang"
    margin: float = 0.8
    rate_limit_radps: float = 0.0
    jerk_time_s: float = 0.0


#: [estimator]'s tuning keys are the flight software's mekf.* keys (the configuration registry) without the
#: prefix; the sensor figures the filter uses are not among them: they come from [sensors.star_tracker] and
#: [sensors.gyro] (aocs_flightcfg.fsw_config), the same description that builds the plant's sensors
MEKF_PREFIX = "mekf."
#: the fault-management keys of the configuration registry (config_fields.def FDIR_*), read from [fdir]
FDIR_PREFIX = "fdir."
U32_MAX = 2 ** 32 - 1
ESTIMATOR_TUNING_KEYS = ("gate_chi2", "p0_att_sigma_rad", "p0_bias_sigma_radps", "max_gap_s", "bias0_radps",
                         "init_mode", "init_q_BN", "gyroless_torque_sigma_nm", "gyroless_p0_rate_sigma_radps",
                         "gyroless_rate_sigma_radps")
#: the mekf.* keys written from the sensor sections, never from [estimator]
ESTIMATOR_SENSOR_KEYS = ("st_q_SB", "st_sigma_cross_rad", "st_sigma_about_rad", "gyro_arw_radpsqrts",
                         "gyro_rrw_radps1p5")


@dataclass(frozen=True)
class EstimatorConfig:
    """[estimator]: the flight software's attitude determination (docs/spec.md 5.6.11, fsw_node key
    `estimator` and the mekf.* keys). type "passthrough" (default) flies the sensor's q and w as they
    are (every reference scenario); "mekf" the gyro and star-tracker filter, its sensor figures from
    [sensors.star_tracker] and [sensors.gyro] (times noise_scale: a mistuned filter), its tuning here."""
    type: str = "passthrough"
    gate_chi2: float = 16.266236196238129
    p0_att_sigma_rad: float = 0.017453292519943295
    p0_bias_sigma_radps: float = 4.84813681109536e-06
    max_gap_s: float = 10.0
    bias0_radps: tuple = (0.0, 0.0, 0.0)
    noise_scale: float = 1.0     # the filter's sensor noise figures = the sensors' x this
    # how the filter starts (docs/spec.md 5.6.10): "first_star_tracker" (its first valid sample) or
    # "configured" (at init_q_BN, given as it is or as the plant's initial attitude turned by init_error_deg)
    init_mode: str = "first_star_tracker"
    init_q_BN: tuple = (0.0, 0.0, 0.0, 1.0)
    init_error_deg: tuple | None = None   # the knowledge error dth at the start, deg, B (when given)
    # the gyroless model flown once fault management excludes the gyro (docs/spec.md 5.6.12; 0 = none)
    gyroless_torque_sigma_nm: float = 1.0e-2
    gyroless_p0_rate_sigma_radps: float = 1.0e-2
    gyroless_rate_sigma_radps: float = 1.0e-5


@dataclass(frozen=True)
class MomentumConfig:
    """[momentum]: the flight software's momentum management (docs/spec.md 5.9; fsw_node's mom.* keys). The
    actuators' figures come from [thrusters] / [magnetorquers], the sections that build the plant's (one
    description, both sides); here only the policy and its tuning. policy "none" (default) unloads nothing."""
    policy: str = "none"                 # none | thrusters | magnetorquers (momentum.def rows)
    trigger: str = "threshold"           # threshold (hysteresis) | continuous
    h_target_nms: tuple = (0.0, 0.0, 0.0)
    h_start_nms: float = 0.0             # threshold: start when |h_wheels - h_target| exceeds this
    h_stop_nms: float = 0.0              # threshold: stop below this (< h_start_nms)
    k_mtq_per_s: float = 0.0             # magnetorquers: m = k (dh x B) / |B|^2
    dump_torque_nm: float = 0.0          # thrusters: dumping torque magnitude


@dataclass(frozen=True)
class Scenario:
    id: str
    description: str
    reference: str
    kind: str
    control_rate_hz: float
    duration_s: float
    seed: int
    substeps: int
    control: ControlConfig
    attitude: AttitudePlantConfig | None
    orbit: OrbitPlantConfig | None
    target: TargetConfig | None
    disturbances: Disturbances
    actuator: ActuatorConfig
    sensors: SensorsConfig
    settle: SettleConfig
    metrics: MetricsConfig
    path: str
    # every effector section (the disturbances and [actuator]), kind -> config, in the file's order
    effectors: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))
    # integration error above which a run warns: arcsec (attitude) or m (orbit); aocs_plant.integration_error
    integrator_tolerance: float | None = None
    guidance: GuidanceConfig = GuidanceConfig()
    # [environment]: epoch, the spacecraft's orbit (attitude scenarios too), magnetic field model
    environment: EnvironmentConfig = EnvironmentConfig()
    # [estimator]: the flight software's attitude determination (passthrough unless the scenario says)
    estimator: EstimatorConfig = EstimatorConfig()
    # [momentum]: the flight software's momentum management (none unless the scenario says)
    momentum: MomentumConfig = MomentumConfig()
    # [[plan]]: the observation plan (None: the one [target]); observation_plan.py
    plan: ObservationPlan | None = None
    # [[faults]]: the injected faults (aocs_plant.faults; aocs run --fault appends to them)
    faults: tuple = ()
    # [passes]: ground targets imaged in nadir pointing (None: none); target_passes.py
    passes: target_passes.PassesConfig | None = None
    # [fdir]: the flight software's fault-management values the scenario gives (registry key without "fdir."
    # -> value); the others keep the flight software's defaults (docs/spec.md 5.15)
    fdir: Mapping[str, Any] = field(default_factory=lambda: MappingProxyType({}))

    @property
    def dt(self) -> float:
        return 1.0 / self.control_rate_hz

    @property
    def n_steps(self) -> int:
        return int(round(self.duration_s * self.control_rate_hz))

    @property
    def law(self) -> LawConfig:
        return self.control.laws[self.control.law]


# --------------------------------------------------------------------------- reader


class _Section:
    """A table being read: take keys one by one, then done() rejects leftovers."""

    def __init__(self, file: str, path: str, data: Any):
        self.file = file
        self.path = path
        if not isinstance(data, dict):
            self.fail(path or "<root>", f"must be a table, got {_tname(data)}")
        self.data = dict(data)

    def key(self, k: str) -> str:
        return f"{self.path}.{k}" if self.path else k

    def fail(self, key: str, what: str):
        # one line whatever the key or value holds: control characters are shown escaped
        key = key if key.isprintable() else repr(key)
        what = what if what.isprintable() else what.encode("unicode_escape").decode("ascii")
        raise ScenarioError(f"{self.file}: {key}: {what}")

    def has(self, k: str) -> bool:
        return k in self.data

    def _pop(self, k, required, default):
        if k not in self.data:
            if required:
                self.fail(self.key(k), "missing required key")
            return default, False
        return self.data.pop(k), True

    def string(self, k, required=True, default=None, choices=None):
        v, present = self._pop(k, required, default)
        if not present:
            return v
        if not isinstance(v, str):
            self.fail(self.key(k), f"expected a string, got {_tname(v)}")
        if choices is not None and v not in choices:
            self.fail(self.key(k), f"unknown value {v!r}, expected one of {', '.join(choices)}")
        return v

    def boolean(self, k, required=True, default=None):
        v, present = self._pop(k, required, default)
        if present and not isinstance(v, bool):
            self.fail(self.key(k), f"expected true or false, got {_tname(v)}")
        return v

    def integer(self, k, required=True, default=None, minimum=None):
        v, present = self._pop(k, required, default)
        if not present:
            return v
        if isinstance(v, bool) or not isinstance(v, int):
            self.fail(self.key(k), f"expected an integer, got {_tname(v)}")
        if not -2 ** 63 <= v < 2 ** 63:
            self.fail(self.key(k), f"an integer of {len(str(abs(v)))} digits is beyond the range of a 64-bit integer")
        if minimum is not None and v < minimum:
            self.fail(self.key(k), f"must be >= {minimum}, got {v}")
        return v

    def number(self, k, required=True, default=None, positive=False, nonneg=False):
        v, present = self._pop(k, required, default)
        if not present:
            return v
        return self._check_number(self.key(k), v, positive, nonneg)

    def _check_number(self, key, v, positive=False, nonneg=False):
        if isinstance(v, bool) or not isinstance(v, (int, float)):
            self.fail(key, f"expected a number, got {_tname(v)}")
        if isinstance(v, int) and abs(v) > 2 ** 1023:
            self.fail(key, f"an integer of {len(str(abs(v)))} digits is beyond the range of a double")
        v = float(v)
        if not math.isfinite(v):
            self.fail(key, f"must be finite, got {v}")
        if positive and not v > 0.0:
            self.fail(key, f"must be > 0, got {v}")
        if nonneg and v < 0.0:
            self.fail(key, f"must be >= 0, got {v}")
        return v

    def vector(self, k, n=3, required=True, default=None, positive=False, nonneg=False):
        v, present = self._pop(k, required, default)
        if not present:
            return v
        return self._check_vector(self.key(k), v, n, positive, nonneg)

    def _check_vector(self, key, v, n, positive=False, nonneg=False):
        if not isinstance(v, list):
            self.fail(key, f"expected an array of {n} numbers, got {_tname(v)}")
        if len(v) != n:
            self.fail(key, f"expected {n} numbers, got {len(v)}")
        return tuple(self._check_number(f"{key}[{i}]", x, positive, nonneg) for i, x in enumerate(v))

    def array(self, k, max_len=64, positive=False, nonneg=False):
        """An array of 1 to max_len numbers (required)."""
        v, _ = self._pop(k, True, None)
        n = len(v) if isinstance(v, list) else 0
        if not 1 <= n <= max_len:
            self.fail(self.key(k), f"expected an array of 1 to {max_len} numbers, got {_tname(v) if n == 0 else n}")
        return self._check_vector(self.key(k), v, n, positive, nonneg)

    def scalar_or_vector(self, k, n=3, required=True, default=None, positive=False):
        """A number (meaning that value on every axis) or an array of n numbers."""
        v, present = self._pop(k, required, default)
        if not present:
            return v
        if isinstance(v, list):
            return self._check_vector(self.key(k), v, n, positive)
        x = self._check_number(self.key(k), v, positive)
        return (x,) * n

    def matrix3(self, k):
        v, _ = self._pop(k, True, None)
        key = self.key(k)
        if not isinstance(v, list) or len(v) != 3:
            self.fail(key, "expected a 3x3 array of numbers (three rows of three)")
        return tuple(self._check_vector(f"{key}[{i}]", row, 3) for i, row in enumerate(v))

    def table(self, k, required=True):
        v, present = self._pop(k, required, None)
        if not present:
            return None
        return _Section(self.file, self.key(k), v)

    def table_list(self, k):
        v, present = self._pop(k, False, None)
        if not present:
            return []
        if not isinstance(v, list):
            self.fail(self.key(k), f"expected an array of tables, got {_tname(v)}")
        return [_Section(self.file, f"{self.key(k)}[{i}]", x) for i, x in enumerate(v)]

    def remaining(self):
        return list(self.data.keys())

    def only(self, known) -> None:
        """Refuse, before anything is read, a key the section cannot have (named, with the known ones)."""
        unknown = sorted(k for k in self.data if k not in known)
        if unknown:
            close = difflib.get_close_matches(unknown[0], known, n=1, cutoff=0.5)
            self.fail(self.key(unknown[0]), "unknown key" + (f" (did you mean {close[0]!r}?)" if close else "")
                      + f"; known: {', '.join(known)}")

    def done(self):
        if self.data:
            k = sorted(self.data)[0]
            self.fail(self.key(k), "unknown key" + (f" (also unknown: {', '.join(sorted(self.data)[1:])})"
                                                    if len(self.data) > 1 else ""))


def _tname(v) -> str:
    if isinstance(v, bool):
        return "a boolean"
    if isinstance(v, int):
        return "an integer"
    if isinstance(v, float):
        return "a number"
    if isinstance(v, str):
        return "a string"
    if isinstance(v, list):
        return "an array"
    if isinstance(v, dict):
        return "a table"
    return type(v).__name__


# --------------------------------------------------------------------------- sections


def _read_attitude_input(sec: _Section, what: str):
    """Exactly one of euler321_deg | rho | sigma | quaternion -> (q, (key, value))."""
    present = [k for k in ATTITUDE_INPUTS if sec.has(k)]
    if len(present) != 1:
        sec.fail(sec.path, f"give exactly one {what} among {', '.join(ATTITUDE_INPUTS)}"
                 + (f" (found {', '.join(present)})" if present else ""))
    k = present[0]
    if k == "quaternion":
        v = sec.vector(k, 4)
        n = math.sqrt(sum(x * x for x in v))
        if abs(n - 1.0) > 1e-6:
            sec.fail(sec.key(k), f"quaternion norm must be 1 (within 1e-6), got {n!r}")
        q = tuple(x / n for x in v)
    else:
        v = sec.vector(k, 3)
        q = {"euler321_deg": euler321_deg_to_quat, "rho": crp_to_quat, "sigma": mrp_to_quat}[k](v)
        if k == "sigma" and sum(x * x for x in v) > 1.0:
            sec.fail(sec.key(k), "use the MRP set with |sigma| <= 1")
    return q, (k, v)


def law_names(kind: str | None = None) -> tuple[str, ...]:
    """The laws a scenario may configure (the flight software's law registry, aocs_core.registry),
    in wire-id order; only those of one kind (attitude, orbit) when given."""
    reg = registry.load()
    return tuple(law.name for law in reg.laws if kind is None or law.input == kind)


def _gao_bound(p) -> float:
    """(2/sqrt 3) uM: the largest M2 that keeps |u| <= uM (SPEC 2.7)."""
    return 2.0 * p["u_max"] / math.sqrt(3.0)


def _check_gao(sec: _Section, p):
    """Gao, Lu, Wang 2010: L1 = M1 < L2 <= M2 <= (2/sqrt 3) uM on every axis (SPEC 2.7)."""
    tol = 1e-12
    bound = _gao_bound(p)
    for l1, m1, l2, m2 in zip(p["l1"], p["m1"], p["l2"], p["m2"]):
        if abs(l1 - m1) > tol * max(1.0, abs(m1)):
            sec.fail(sec.key("m1"), f"violates L1 = M1 (L1 = {l1}, M1 = {m1})")
        if not m1 < l2:
            sec.fail(sec.key("l2"), f"violates M1 < L2 (M1 = {m1}, L2 = {l2})")
        if not l2 <= m2:
            sec.fail(sec.key("m2"), f"violates L2 <= M2 (L2 = {l2}, M2 = {m2})")
        if m2 > bound * (1.0 + tol):
            sec.fail(sec.key("m2"), f"violates M2 <= (2/sqrt 3) uM = {bound!r} (M2 = {m2})")


def _tanh_extra(sec: _Section, p):
    """SPEC 2.7 generalised saturation: M3 (default uM). The flight software's tanh variant uses
    M3 = u_max (mrp_sat.h), so another value cannot fly."""
    p["m3"] = sec.number("m3", required=False, default=p["u_max"], positive=True)
    if abs(p["m3"] - p["u_max"]) > 1e-12 * p["u_max"]:
        sec.fail(sec.key("m3"), f"m3 = {p['m3']} but the flight software's tanh variant uses M3 = u_max = "
                                f"{p['u_max']}")


#: keys a law section may hold beyond its registry fields (read by the law's check below)
_LAW_EXTRA_KEYS = {"mrp_sat_tanh": ("m3",)}

#: What a scenario says about a law beyond its registry fields (the paper's rules, SPEC 2.7):
#: law -> ({field: its default computed from the fields read before}, check(sec, params) or None).
#: L2 = M2 = 2 uM / sqrt 3 when absent; the tanh variant's M3.
_LAW_RULES = {
    "mrp_sat": ({"l2": lambda p: (_gao_bound(p),) * 3, "m2": lambda p: p["l2"]}, _check_gao),
    "mrp_sat_tanh": ({}, _tanh_extra),
}


def _read_law(sec: _Section, name: str, kind: str) -> LawConfig:
    """A law's parameters are the fields of its registry row (aocs_core.registry): one number per
    real field, a number (every axis) or an array per vec3 field, with the field's sign rule; a law
    with a gain-table field names its compiled table (`table`, defined under `tables`). The inertia
    (mat3) is the plant's; a gain matrix (gain) is given by its table."""
    reg = registry.load()
    fields = [f for f in reg.fields_of(name) if f.type in ("real", "vec3")]
    known = ([f.param for f in fields] + list(_LAW_EXTRA_KEYS.get(name, ()))
             + (["table", "tables"] if reg.table_field(name) is not None else []))
    sec.only(known)  # a misspelt key is named as such, not reported as the key it was meant to be
    optional, check = _LAW_RULES.get(name, ({}, None))
    params: dict[str, Any] = {}
    for f in fields:
        if f.param not in optional:
            params[f.param] = _read_field(sec, f)
    for f in fields:
        if f.param in optional:
            value = _read_field(sec, f, required=False)
            params[f.param] = optional[f.param](params) if value is None else value
    if check is not None:
        check(sec, params)
    table = None
    tables: dict[str, Mapping] = {}
    tfield = reg.table_field(name)
    if tfield is not None:
        compiled = reg.tables_for(name)
        table = sec.string("table")
        tsec = sec.table("tables")
        for tname in list(tsec.remaining()):
            t = tsec.table(tname)
            if tname not in compiled:
                t.fail(t.path, f"{tname!r} is not a compiled gain table of {name} "
                               f"(firmware/gains, `aocs gains`: {', '.join(compiled)})")
            if name == "hinf":
                entry = {"variant": t.string("variant", choices=("min", "regional", "bounded"))}
            else:
                # design weights (Q, R diagonals): Q on the law's state (the columns of its gain: 6, or 9
                # for lqr_quat_i), R on the torque / force. With them the runner designs K for this
                # scenario's plant (the compiled table when plant and weights are its design's); without
                # them the compiled table flies as it is (aocs_runner.scenario_gains)
                if t.has("q") != t.has("r"):
                    t.fail(t.key("r" if t.has("q") else "q"), "missing: give both design weights q and r, or neither")
                n_state = reg.gain_field_of(tfield).count // 3
                entry = ({"q": t.scalar_or_vector("q", n=n_state, positive=True),
                          "r": t.scalar_or_vector("r", n=3, positive=True)} if t.has("q") else {})
            t.done()
            tables[tname] = MappingProxyType(entry)
        tsec.done()
        if not tables:
            sec.fail(sec.key("tables"), "at least one gain table is required")
        if table not in tables:
            sec.fail(sec.key("table"), f"table {table!r} is not defined under {sec.key('tables')}")
    sec.done()
    return LawConfig(name, MappingProxyType(params), table, MappingProxyType(tables))


#: a law parameter flies in double (host, M7) and in float (M4F): a non-zero one must be a normal
#: number in both, or fsw_node (strtod underflow) or the float image (a zero gain) refuses it
FLOAT_NORMAL_MIN, FLOAT_MAX = 1.1754943508222875e-38, 3.4028234663852886e38


def _read_field(sec: _Section, f, required: bool = True):
    """One registry field as a scenario parameter (vec3: a number meaning every axis, or 3 numbers)."""
    pos, nonneg = f.rule == "pos", f.rule == "nonneg"
    if f.type == "vec3":
        if not required and not sec.has(f.param):
            return None
        value = sec.scalar_or_vector(f.param, n=f.count, positive=pos)
    else:
        value = sec.number(f.param, required=required, default=None, positive=pos, nonneg=nonneg)
    for x in (value if isinstance(value, tuple) else () if value is None else (value,)):
        if x != 0.0 and not FLOAT_NORMAL_MIN <= abs(x) <= FLOAT_MAX:
            sec.fail(sec.key(f.param), f"{x:g} is outside the magnitudes both precisions of the flight software "
                                       f"represent ([{FLOAT_NORMAL_MIN:.4g}, {FLOAT_MAX:.4g}], or 0)")
    return value


def _read_control(root: _Section, kind: str):
    csec = root.table("control")
    enabled = csec.boolean("enabled", required=False, default=True)
    law = csec.string("law")
    csec.done()
    lsec = root.table("laws")
    laws = {}
    every, allowed = law_names(), law_names(kind)
    for name in lsec.remaining():
        key = lsec.key(name)
        if name not in every:
            lsec.fail(key, f"unknown law {name!r}, expected one of {', '.join(every)}")
        if name not in allowed:
            lsec.fail(key, f"law {name!r} does not apply to a {kind} scenario")
        laws[name] = _read_law(lsec.table(name), name, kind)
    lsec.done()
    if not laws:
        lsec.fail(lsec.path, "at least one law is required")
    if law not in every:
        csec.fail("control.law", f"unknown law {law!r}, expected one of {', '.join(every)}")
    if law not in laws:
        csec.fail("control.law", f"law {law!r} has no gains under [laws.{law}]")
    return ControlConfig(enabled, law, MappingProxyType(laws))


def _read_plant(root: _Section, kind: str):
    sec = root.table("plant")
    att = orb = None
    if kind == "attitude":
        J = sec.matrix3("inertia")
        a = np.array(J)
        if not np.allclose(a, a.T, rtol=1e-12, atol=0.0):
            sec.fail(sec.key("inertia"), "must be symmetric (J[i][j] = J[j][i])")
        eig = np.linalg.eigvalsh(a)
        if not eig[0] > 0.0:
            sec.fail(sec.key("inertia"), f"must be positive definite (eigenvalues {eig.tolist()})")
        # a physical body also satisfies the triangle inequality of principal moments
        if eig[0] + eig[1] < eig[2] * (1.0 - 1e-12):
            sec.fail(sec.key("inertia"), f"principal moments {eig.tolist()} violate J1 + J2 >= J3")
        q0, src = _read_attitude_input(sec, "initial attitude")
        w0 = sec.vector("w0")
        att = AttitudePlantConfig(J, q0, w0, src)
    else:
        model = sec.string("model", choices=("linear", "nonlinear"))
        mass = sec.number("mass_kg", positive=True)
        radius = sec.number("orbit_radius_m", positive=True)
        mu = sec.number("mu", required=False, default=MU_EARTH, positive=True)
        x0 = sec.vector("x0", n=6)
        orb = OrbitPlantConfig(model, mass, radius, mu, x0)
    sec.done()
    return att, orb


def _read_target(root: _Section, kind: str, plan: ObservationPlan | None = None):
    if kind == "orbit":
        if root.has("target"):
            root.fail("target", "an orbit scenario has no [target] (the reference point is the origin)")
        return None
    if plan is not None:
        if root.has("target"):
            root.fail("target", "give the first target as the first [[plan]] entry, not also as [target]")
        first = plan.observations[0]
        return TargetConfig(first.qd, (0.0, 0.0, 0.0), first.target_input)
    sec = root.table("target")
    qd, src = _read_attitude_input(sec, "target attitude")
    wd = sec.vector("wd", required=False, default=(0.0, 0.0, 0.0))
    sec.done()
    return TargetConfig(qd, wd, src)


def _read_plan(root: _Section, kind: str) -> ObservationPlan | None:
    """[[plan]]: the observation plan (observation_plan.py): each entry one target (exactly one of the
    attitude inputs), slew_s and hold_s > 0. A run shorter than the plan (--duration) flies the observations
    commanded before its end."""
    secs = root.table_list("plan")
    if not secs:
        return None
    if kind != "attitude":
        root.fail("plan", "an observation plan applies to attitude scenarios only")
    obs = []
    for sec in secs:
        if not isinstance(sec.data, dict):
            sec.fail(sec.path, f"expected a table, got {_tname(sec.data)}")
        qd, src = _read_attitude_input(sec, "target attitude")
        slew = sec.number("slew_s", positive=True)
        hold = sec.number("hold_s", positive=True)
        sec.done()
        obs.append(Observation(qd, slew, hold, src))
    return ObservationPlan(tuple(obs))


# the firmware's bound on the jerk ramp (aocs/guidance/slew.h), read from the header: one source
def _jerk_time_max_s() -> float:
    return paths.header_number("firmware/include/aocs/guidance/slew.h", "AOCS_SLEW_JERK_TIME_MAX_S")


# a rate limit above this is no limit a spacecraft flies (rad/s; 10 rad/s ~ 570 deg/s): a unit mistake
GUIDANCE_RATE_LIMIT_MAX_RADPS = 10.0


def _read_fdir(root: _Section) -> Mapping[str, Any]:
    """[fdir]: any fault-management key of the configuration registry (fdir.<key>, config_fields.def), each
    checked by its registry rule as fsw_node checks it (integers for the counts); the rules across keys
    (aocs_fdir_config_check: a fraction at most 1, repeat counts of 2 or more) are the flight software's, which
    refuses the run at its start naming the fdir keys."""
    sec = root.table("fdir", required=False)
    if sec is None:
        return MappingProxyType({})
    fields = {f.key[len(FDIR_PREFIX):]: f for f in registry.load().config_fields if f.key.startswith(FDIR_PREFIX)}
    out: dict[str, Any] = {}
    for name in list(sec.data):
        f = fields.get(name)
        if f is None:
            sec.fail(sec.key(name), f"is not a fault-management key (one of {', '.join(sorted(fields))})")
        v = sec.integer(name, minimum=0) if f.kind == "u32" else sec.number(name)
        if f.kind == "u32" and v > U32_MAX:
            sec.fail(sec.key(name), f"{v} is beyond a 32-bit count ({U32_MAX})")
        if not f.holds(float(v)):
            sec.fail(sec.key(name), f"{v!r} must be {f.rule_text} (the flight software's range, configuration "
                                    f"registry row {f.key})")
        out[name] = v
    sec.done()
    return MappingProxyType(out)


def _read_guidance(root: _Section, kind: str, target) -> GuidanceConfig:
    """[guidance], bounded as fsw_node and the executive bound it (aocs_exec_init, slew.h)."""
    sec = root.table("guidance", required=False)
    if sec is None:
        return GuidanceConfig()
    if kind != "attitude":
        sec.fail(sec.path, "slew guidance applies to attitude scenarios only")
    fields = {f.key[len(GUIDANCE_PREFIX):]: f for f in registry.load().config_fields
              if f.key.startswith(GUIDANCE_PREFIX)}
    # the enumerated keys take the registry's names, the first the default (the flight software's enum 0)
    mode = sec.string("mode", required=False, default=fields["mode"].names[0], choices=fields["mode"].names)
    profile = sec.string("profile", required=False, default=fields["profile"].names[0],
                         choices=fields["profile"].names)
    def number(name: str) -> float:   # a real-valued key: the registry's default and sign rule
        f = fields[name]
        return sec.number(name, required=False, default=f.default[0], positive=f.rule == "pos",
                          nonneg=f.rule == "nonneg")

    margin = number("margin")
    if margin > 1.0:
        sec.fail(sec.key("margin"), f"{margin:g} is above 1 (the fraction of the torque envelope, in (0, 1])")
    rate = number("rate_limit_radps")
    if rate > GUIDANCE_RATE_LIMIT_MAX_RADPS:
        sec.fail(sec.key("rate_limit_radps"), f"{rate:g} rad/s is above {GUIDANCE_RATE_LIMIT_MAX_RADPS:g} rad/s "
                                              "(0 = no limit)")
    jerk = number("jerk_time_s")
    jmax = _jerk_time_max_s()
    if jerk > jmax:
        sec.fail(sec.key("jerk_time_s"), f"{jerk:g} s is above {jmax:g} s")
    if profile == "jerk_limited" and not jerk > 0.0:
        sec.fail(sec.key("jerk_time_s"), "profile jerk_limited needs a ramp time > 0 s")
    if profile == "bang_coast_bang" and jerk > 0.0:
        sec.fail(sec.key("jerk_time_s"), "must be 0 with profile bang_coast_bang (or set profile = \"jerk_limited\")")
    for name, v in (("margin", margin), ("rate_limit_radps", rate), ("jerk_time_s", jerk)):
        if not fields[name].holds(v):     # the registry's range, as fsw_node applies it (config_fields.def)
            sec.fail(sec.key(name), f"{v!r} must be {fields[name].rule_text} (the flight software's range, "
                                    f"configuration registry row {fields[name].key})")
    sec.done()
    if mode == "slew" and target is not None and any(x != 0.0 for x in target.wd):
        root.fail("guidance.mode", "a slew needs a fixed target: [target] wd must be 0")
    return GuidanceConfig(mode, profile, margin, rate, jerk)


#: the sensor figures the MEKF takes, which must be > 0 (its noise model): section, key
_MEKF_SENSOR_FIGURES = (("star_tracker", "noise_cross_arcsec", "noise_cross_arcsec"),
                        ("star_tracker", "noise_about_arcsec", "noise_about_arcsec"),
                        ("gyro", "arw_rad_sqrt_s", "arw"), ("gyro", "rrw_rad_s_sqrt_s", "rrw"))


def _initial_estimate(sec: _Section, fields: dict, att: AttitudePlantConfig | None, mode: str):
    """(init_q_BN, init_error_deg) of [estimator]: init_q_BN as given (unit), or init_error_deg (deg, the
    knowledge error at the start, B): q0_BN = dq(-dth) (x) q_BN(0), so that q_BN(0) = dq(dth) (x) q0_BN, the
    knowledge error of aocs_analysis.estimation. Either only with init_mode = "configured"."""
    q0 = tuple(float(x) for x in fields["init_q_BN"].default)
    has_q, has_err = sec.has("init_q_BN"), sec.has("init_error_deg")
    for k, present in (("init_q_BN", has_q), ("init_error_deg", has_err)):
        if present and mode != "configured":
            sec.fail(sec.key(k), f'applies to init_mode = "configured" only (init_mode is "{mode}")')
    if has_q and has_err:
        sec.fail(sec.key("init_error_deg"), "give init_q_BN or init_error_deg, not both")
    if has_q:
        q0 = sec.vector("init_q_BN", n=4)
        tol = paths.header_number("firmware/include/aocs/estimation/mekf.h", "AOCS_MEKF_QUAT_UNIT_TOL")
        if not abs(math.sqrt(sum(x * x for x in q0)) - 1.0) <= tol:
            sec.fail(sec.key("init_q_BN"), f"is not a unit quaternion (|q| - 1 beyond {tol:g})")
        return q0, None
    if has_err:
        err = sec.vector("init_error_deg")
        if not math.sqrt(sum(x * x for x in err)) < 180.0:
            sec.fail(sec.key("init_error_deg"), "the error angle must be below 180 deg")
        q_true = att.q0 if att is not None else (0.0, 0.0, 0.0, 1.0)
        dq = quat_from_rotvec(tuple(-math.radians(x) for x in err))
        return tuple(float(x) for x in quat_normalize(quat_mul(dq, q_true))), err
    if mode == "configured":
        sec.fail(sec.key("init_mode"), '"configured" needs init_q_BN or init_error_deg')
    return q0, None


def _read_estimator(root: _Section, kind: str, sensor_config: SensorsConfig,
                    att: AttitudePlantConfig | None = None) -> EstimatorConfig:
    """[estimator], bounded as fsw_node and the MEKF's init bound it (the registry's rules; mekf.h)."""
    sec = root.table("estimator", required=False)
    if sec is None:
        return EstimatorConfig()
    est = next(f for f in registry.load().config_fields if f.key == "estimator")
    typ = sec.string("type", required=False, default=est.names[0], choices=est.names)
    fields = {f.key[len(MEKF_PREFIX):]: f for f in registry.load().config_fields if f.key.startswith(MEKF_PREFIX)}
    for k in sec.remaining():
        if k in ESTIMATOR_SENSOR_KEYS:
            sec.fail(sec.key(k), "is a sensor figure: it comes from [sensors.star_tracker] / [sensors.gyro]")
    if typ != "mekf":
        for k in sec.remaining():
            sec.fail(sec.key(k), f'applies to type = "mekf" only (type is "{typ}")')
        sec.done()
        return EstimatorConfig(type=typ)
    if kind != "attitude":
        sec.fail(sec.key("type"), "an attitude estimator applies to attitude scenarios only")

    def number(name: str) -> float:   # a real-valued key: the registry's default and sign rule
        f = fields[name]
        return sec.number(name, required=False, default=f.default[0], positive=f.rule == "pos",
                          nonneg=f.rule == "nonneg")

    gate, p0a, p0b, gap = (number(k) for k in ("gate_chi2", "p0_att_sigma_rad", "p0_bias_sigma_radps", "max_gap_s"))
    gap_max = paths.header_number("firmware/include/aocs/estimation/mekf.h", "AOCS_MEKF_MAX_GAP_LIMIT_S")
    if gap > gap_max:
        sec.fail(sec.key("max_gap_s"), f"{gap:g} s is above {gap_max:g} s")
    bias0 = sec.vector("bias0_radps", required=False, default=tuple(fields["bias0_radps"].default))
    scale = sec.number("noise_scale", required=False, default=1.0, positive=True)
    mode = sec.string("init_mode", required=False, default=fields["init_mode"].names[0],
                      choices=fields["init_mode"].names)
    q0, err0 = _initial_estimate(sec, fields, att, mode)
    gyroless = {k: number(k) for k in ("gyroless_torque_sigma_nm", "gyroless_p0_rate_sigma_radps",
                                       "gyroless_rate_sigma_radps")}
    sec.done()
    for name in ("star_tracker", "gyro"):
        if name not in sensor_config.sensors:
            root.fail("estimator.type", f'"mekf" needs [sensors.star_tracker] and [sensors.gyro] '
                                        f"(the filter's sensors; [sensors.{name}] is missing)")
    for name, key, attr in _MEKF_SENSOR_FIGURES:
        if not getattr(sensor_config[name], attr) > 0.0:
            root.fail(f"sensors.{name}.{key}", 'must be > 0 with estimator type "mekf" (the filter\'s noise model)')
    return EstimatorConfig(typ, gate, p0a, p0b, gap, tuple(bias0), scale, mode, q0, err0, **gyroless)


#: the largest number of thrusters the flight software allocates (AOCS_MOM_THRUSTERS_MAX, momentum.h)
MOM_THRUSTERS_MAX = 12


def _read_momentum(root: _Section, kind: str, configs: Mapping[str, Any], sensor_config: SensorsConfig
                   ) -> MomentumConfig:
    """[momentum], bounded as the momentum stage's init bounds it (momentum.c; the registry's mom.* rules)."""
    sec = root.table("momentum", required=False)
    if sec is None:
        return MomentumConfig()
    fields = {f.key: f for f in registry.load().config_fields}
    policy = sec.string("policy", required=False, default="none", choices=fields["mom.policy"].names)
    trigger = sec.string("trigger", required=False, default="threshold", choices=fields["mom.trigger"].names)
    h_target = sec.vector("h_target_nms", required=False, default=(0.0, 0.0, 0.0))
    h_start = sec.number("h_start_nms", required=False, default=0.0, nonneg=True)
    h_stop = sec.number("h_stop_nms", required=False, default=0.0, nonneg=True)
    k_mtq = sec.number("k_mtq_per_s", required=False, default=0.0, nonneg=True)
    dump = sec.number("dump_torque_nm", required=False, default=0.0, nonneg=True)
    sec.done()
    if policy == "none":
        return MomentumConfig(policy, trigger, tuple(h_target), h_start, h_stop, k_mtq, dump)
    if kind != "attitude":
        sec.fail(sec.key("policy"), "momentum management applies to attitude scenarios only")
    if "wheels" not in configs:
        sec.fail(sec.key("policy"), f'"{policy}" unloads the reaction wheels: the scenario has no [wheels]')
    if policy == "magnetorquers":
        if "magnetorquers" not in configs:
            sec.fail(sec.key("policy"), '"magnetorquers" needs a [magnetorquers] section (the rods)')
        if "magnetometer" not in sensor_config.sensors:
            sec.fail(sec.key("policy"), '"magnetorquers" needs [sensors.magnetometer] (the field the law uses)')
        if not k_mtq > 0.0:
            sec.fail(sec.key("k_mtq_per_s"), 'must be > 0 with policy "magnetorquers"')
    if policy == "thrusters":
        thr = configs.get("thrusters")
        if thr is None:
            sec.fail(sec.key("policy"), '"thrusters" needs a [thrusters] section (the thrusters)')
        if len(thr.positions_m) > MOM_THRUSTERS_MAX:
            root.fail("thrusters.positions_m", f"{len(thr.positions_m)} thrusters: the flight software allocates "
                                               f"at most {MOM_THRUSTERS_MAX}")
        if not dump > 0.0:
            sec.fail(sec.key("dump_torque_nm"), 'must be > 0 with policy "thrusters"')
    if trigger == "threshold" and not h_stop < h_start:
        sec.fail(sec.key("h_stop_nms"), f"{h_stop:g} N m s is not below h_start_nms ({h_start:g}): the threshold "
                                        f"trigger's hysteresis needs h_stop_nms < h_start_nms")
    return MomentumConfig(policy, trigger, tuple(h_target), h_start, h_stop, k_mtq, dump)


def _read_effectors(root: _Section, kind: str, duration: float, rate: float, substeps: int, plant) -> dict:
    """[disturbances.<kind>] and [actuator]: each effector module reads its own section."""
    ctx = effectors.ReadContext(root.file, kind, duration, 1.0 / rate, substeps, plant)
    return effectors.read(root, ctx)


def _read_sensors(root: _Section, kind: str, duration: float, rate: float, configs: dict) -> SensorsConfig:
    """[sensors]: each sensor module reads its own keys (aocs_plant.sensors)."""
    return sensors.read(root, sensors.SensorReadContext(root.file, kind, duration, 1.0 / rate, configs))


SETTLE_KEYS = {
    "attitude": ("rho_norm_max", "w_norm_max_rad_s", "pointing_arcsec_max", "angle_abs_max_rad",
                 "rate_abs_max_rad_s", "sigma_norm_max"),
    "orbit": ("pos_abs_max_m", "vel_abs_max_m_s"),
}


def _read_settle(root: _Section, kind: str) -> SettleConfig:
    sec = root.table("settle")
    for k in sec.remaining():
        if k in SETTLE_KEYS["attitude"] + SETTLE_KEYS["orbit"] and k not in SETTLE_KEYS[kind]:
            sec.fail(sec.key(k), f"does not apply to a {kind} scenario")
    kw = {k: sec.number(k, required=False, positive=True) for k in SETTLE_KEYS[kind]}
    sec.done()
    if all(v is None for v in kw.values()):
        sec.fail(sec.path, f"give at least one criterion among {', '.join(SETTLE_KEYS[kind])}")
    return SettleConfig(**kw)


#: [metrics] hold_requirement: what a [[plan]] hold is judged against (docs/spec.md 5.11.6)
HOLD_REQUIREMENTS = ("requirement", "sensors")


def _read_metrics(root: _Section, kind: str, duration: float, estimator=None) -> MetricsConfig:
    sec = root.table("metrics", required=False)
    if sec is None:
        return MetricsConfig(window_s=duration)
    w = sec.number("window_s", required=False, default=duration, positive=True)
    if w > duration:
        sec.fail(sec.key("window_s"), f"metric window {w} s is longer than duration_s = {duration} s")
    req = goal = rec = None
    if kind == "attitude":
        req = sec.number("requirement_arcsec", required=False, positive=True)
        goal = sec.number("goal_arcsec", required=False, positive=True)
        rec = sec.number("recovery_arcsec", required=False, positive=True)
        if req is not None and goal is not None and goal > req:
            sec.fail(sec.key("goal_arcsec"), f"goal {goal} is looser than the requirement {req}")
    hold_req = sec.string("hold_requirement", required=False, default="requirement",
                          choices=HOLD_REQUIREMENTS)
    if hold_req == "sensors" and (estimator is None or estimator.type != "mekf"):
        sec.fail(sec.key("hold_requirement"), '"sensors" needs [estimator] type = "mekf" (the figure is its '
                                              "steady-state knowledge)")
    sec.done()
    return MetricsConfig(w, req, goal, hold_req, rec)


# --------------------------------------------------------------------------- API


def validate(data: dict, file: str = "<memory>", expected_id: str | None = None) -> Scenario:
    """Validate a parsed TOML document; raise ScenarioError naming file and key."""
    root = _Section(file, "", data)
    sid = root.string("id")
    if expected_id is not None and sid != expected_id:
        root.fail("id", f"{sid!r} does not match the file name {expected_id!r}")
    description = root.string("description")
    reference = root.string("reference")
    kind = root.string("kind", choices=KINDS)
    rate = root.number("control_rate_hz", positive=True)
    lim = registry.load().limits   # the executive's own ranges, from the build (executive.h)
    rate_min, rate_max = 1.0 / lim["period_max_s"], 1.0 / lim["period_min_s"]
    if not rate_min <= rate <= rate_max:
        root.fail("control_rate_hz", f"{rate:g} Hz is outside [{rate_min:g}, {rate_max:g}] Hz (the flight "
                                     "software's period range, executive.h)")
    duration = root.number("duration_s", positive=True)
    if duration > limits.DURATION_S_MAX:
        root.fail("duration_s", f"{duration:g} s is longer than {limits.DURATION_S_MAX:g} s")
    steps = duration * rate
    if steps > limits.STEPS_MAX:
        root.fail("duration_s", f"{steps:.3g} control periods, more than {limits.STEPS_MAX:g}")
    if steps < 1.0 - 1e-6:
        root.fail("duration_s", f"{duration:g} s is shorter than one control period ({1.0 / rate:g} s)")
    if abs(steps - round(steps)) > 1e-6 * max(1.0, steps):
        root.fail("duration_s", f"must be a whole number of control periods ({steps} periods)")
    seed = root.integer("seed", required=False, default=0, minimum=0)
    isec = root.table("integrator", required=False)
    substeps = 1
    tol_key = "tolerance_arcsec" if kind == "attitude" else "tolerance_m"
    tolerance = INTEGRATION_TOLERANCE_DEFAULT[tol_key]
    if isec is not None:
        substeps = isec.integer("substeps", required=False, default=1, minimum=1)
        if substeps > limits.SUBSTEPS_MAX:
            isec.fail(isec.key("substeps"), f"{substeps} is more than {limits.SUBSTEPS_MAX}")
        tolerance = isec.number(tol_key, required=False, default=tolerance, positive=True)
        isec.done()
    control = _read_control(root, kind)
    att, orb = _read_plant(root, kind)
    plan = _read_plan(root, kind)
    target = _read_target(root, kind, plan)
    guidance = _read_guidance(root, kind, target)
    configs = _read_effectors(root, kind, duration, rate, substeps, att if kind == "attitude" else orb)
    disturbances = Disturbances({k: c for k, c in configs.items()
                                 if effectors.REGISTRY[k].group == "disturbances"})
    actuator = configs["actuator"]
    sensor_config = _read_sensors(root, kind, duration, rate, configs)
    estimator = _read_estimator(root, kind, sensor_config, att)
    momentum = _read_momentum(root, kind, configs, sensor_config)
    env = environment.read(root, kind, orb)
    passes = target_passes.read(root, kind, env)
    gge = configs.get("gravity_gradient_earth")
    if gge is not None and gge.orbit_rate_rad_s is None and env.orbit is None:
        root.fail("disturbances.gravity_gradient_earth.orbit_rate_rad_s",
                  "required without [environment.orbit] (the orbit whose nadir and rate it takes otherwise)")
    settle = _read_settle(root, kind)
    metrics = _read_metrics(root, kind, duration, estimator)
    injected = faults.read(root, duration, sensor_config, configs)
    fdir = _read_fdir(root)
    root.table("campaign", required=False)  # a Monte Carlo campaign's own table (aocs_campaign.plan)
    root.done()
    return Scenario(sid, description, reference, kind, rate, duration, seed, substeps, control,
                    att, orb, target, disturbances, actuator, sensor_config, settle, metrics, file,
                    effectors=MappingProxyType(configs), integrator_tolerance=tolerance, guidance=guidance,
                    environment=env, estimator=estimator, momentum=momentum, plan=plan, passes=passes,
                    faults=injected, fdir=fdir)


def _apply_overrides(data: dict, overrides: Mapping[str, Any], file: str) -> dict:
    data = copy.deepcopy(data)
    for dotted, value in overrides.items():
        parts = dotted.split(".")
        node = data
        for i, p in enumerate(parts[:-1]):
            nxt = node.setdefault(p, {})
            if not isinstance(nxt, dict):
                raise ScenarioError(f"{file}: {'.'.join(parts[:i + 1])}: override {dotted!r} "
                                    "goes through a value that is not a table")
            node = nxt
        if value is None:
            node.pop(parts[-1], None)
        else:
            node[parts[-1]] = value
    return data


def resolve(path_or_id: str | Path) -> Path:
    """A path when it looks like one (a .toml name, a folder in it, or an existing file), else the id of
    sil/scenarios/<id>.toml: a folder in the working directory named like an id does not shadow it."""
    p = Path(path_or_id)
    if p.suffix == ".toml" or len(p.parts) > 1 or p.is_file():
        return p
    return SCENARIO_DIR / f"{path_or_id}.toml"


def load(path_or_id: str | Path, overrides: Mapping[str, Any] | None = None) -> Scenario:
    """Load and validate a scenario by path or id (sil/scenarios/<id>.toml).

    overrides: {"dotted.key": value} applied to the document before validation
    (value None deletes the key), e.g. {"actuator.axis_limit": 0.5} for the
    realistic IRASSI runs or {"control.enabled": False} for open-loop runs.
    """
    p = resolve(path_or_id)
    return validate(document(p, overrides), str(p), expected_id=p.stem)


def document(path_or_id: str | Path, overrides: Mapping[str, Any] | None = None) -> dict:
    """The parsed TOML document of a scenario with the overrides applied, not validated (the nominal
    values that a Monte Carlo campaign disperses); ScenarioError when the file cannot be read."""
    p = resolve(path_or_id)
    file = str(p)
    try:
        with open(p, "rb") as fh:
            data = tomllib.load(fh)
    except FileNotFoundError:
        raise ScenarioError(f"{file}: <file>: no such scenario file "
                            f"(known ids: {', '.join(list_scenarios())})") from None
    except IsADirectoryError:
        raise ScenarioError(f"{file}: <file>: is a folder, not a scenario file") from None
    except PermissionError:
        raise ScenarioError(f"{file}: <file>: not readable (permission denied)") from None
    except UnicodeDecodeError as exc:
        raise ScenarioError(f"{file}: <file>: not UTF-8 text (byte {exc.start})") from None
    except RecursionError:
        raise ScenarioError(f"{file}: <syntax>: values nested too deeply") from None
    except tomllib.TOMLDecodeError as exc:
        raise ScenarioError(f"{file}: <syntax>: not valid TOML: {exc}") from None
    if overrides:
        data = _apply_overrides(data, overrides, file)
    return data


def list_scenarios(directory: str | Path | None = None) -> list[str]:
    """Ids of the scenario files, sorted (for `aocs list`)."""
    d = Path(directory) if directory is not None else SCENARIO_DIR
    return sorted(p.stem for p in d.glob("*.toml"))
