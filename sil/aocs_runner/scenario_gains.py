"""Gains designed for the scenario (issue 10 item 6): which gain each table law flies.

A table law (a law with a TABLE field in firmware/include/aocs/laws.def: lqr_quat, hinf,
orbit_lqr, ...) names a compiled table, `[laws.<law>] table = "<name>"`, designed by `aocs gains`
from tools/gains.toml for that file's plant. The scenario's `[laws.<law>.tables.<name>]` entry
decides what flies:

- with design weights (`q` and `r`, the LQR kinds): K is designed at run start for the
  scenario's plant (inertia or mass) and those weights by the same code as the compiled tables
  (aocs_design.designs.design_one, with the same checks), and passed to the flight software as the
  explicit gain (`<law>.k`). When plant and weights equal the compiled table's design, the
  compiled table flies by name instead (bit-identical to a run without this step);
- without weights (or a hinf `variant`, which only names the design): the compiled table flies
  as it is; on a scenario whose plant differs from the table's design plant a warning names both.

Layering: the runner sits above aocs_design (pyproject.toml), so it calls the design tools here,
once per run, before any process starts; a design that fails its checks is a bad input (the run
does not start).
"""
from __future__ import annotations

import tomllib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aocs_core import paths, registry
from aocs_design import designs
from aocs_design.errors import DesignError

GAINS_TOML = paths.REPO / "tools" / "gains.toml"


class GainDesignError(ValueError):
    """A gain asked for by the scenario cannot be designed (one line naming the scenario key)."""


@dataclass
class GainChoice:
    law: str
    table: str                    # the compiled table the scenario names
    source: str                   # "compiled" (the table flies by name) or "designed" (K at run start)
    k: np.ndarray | None = None   # designed K (3x6), None for a compiled table
    design_plant: str = ""        # the compiled table's design plant, in words
    scenario_plant: str = ""      # the scenario's plant, in words
    weights: str = ""             # the weights flown, in words
    table_weights: str = ""       # the compiled table's design weights, in words
    warnings: list = field(default_factory=list)
    design: object = None         # the aocs_design result (checks, poles) of a designed K

    def to_json(self) -> dict:
        out = {"law": self.law, "table": self.table, "source": self.source, "weights": self.weights,
               "design_plant": self.design_plant, "scenario_plant": self.scenario_plant,
               "warnings": list(self.warnings), "summary": self.summary()}
        if self.k is not None:
            out["K"] = self.k.tolist()
            out["slowest_pole_re"] = self.design.slowest_pole_re
        return out

    def summary(self) -> str:
        if self.source == "designed":
            return (f"{self.law} K designed at run start for {self.scenario_plant}, {self.weights} "
                    f"(slowest closed-loop pole {self.design.slowest_pole_re:.4g} 1/s), instead of the "
                    f"compiled table {self.table} ({self.table_weights}, {self.design_plant})")
        return f"{self.law} gain: compiled table {self.table} ({self.weights}, designed for {self.design_plant})"


_CONFIG: dict[Path, dict] = {}


def design_config(path: Path = GAINS_TOML) -> dict:
    if path not in _CONFIG:
        try:
            with open(path, "rb") as f:
                _CONFIG[path] = tomllib.load(f)
        except (OSError, tomllib.TOMLDecodeError) as exc:
            raise GainDesignError(f"{path}: cannot read the gain design configuration ({exc})") from None
    return _CONFIG[path]


def _scenario_plant(sc, kind: str, design_plant: dict) -> dict:
    """The design plant of `kind` with the scenario's own inertia (attitude) or mass and orbit (orbit)."""
    p = dict(design_plant)
    if kind == "orbit_lqr":
        p.update(mass=sc.orbit.mass_kg, radius=sc.orbit.orbit_radius_m, mu=sc.orbit.mu)
    else:
        p.pop("inertia_diag", None)
        p["inertia"] = np.asarray(sc.attitude.inertia, dtype=float).tolist()
    return p


def _same_plant(kind: str, a: dict, b: dict) -> bool:
    if kind == "orbit_lqr":
        return all(float(a[k]) == float(b[k]) for k in ("mass", "radius", "mu"))
    return bool(np.array_equal(designs.inertia_of(a), designs.inertia_of(b)))


def _plant_text(kind: str, p: dict) -> str:
    if kind == "orbit_lqr":
        return f"m = {p['mass']:g} kg, R = {p['radius']:g} m"
    j = designs.inertia_of(p)
    if np.count_nonzero(j - np.diag(np.diag(j))) == 0:
        return "J = diag(" + ", ".join(f"{v:g}" for v in np.diag(j)) + ") kg m^2"
    return "J = [" + "; ".join(" ".join(f"{v:g}" for v in row) for row in j) + "] kg m^2"


def _weights_text(w: dict, n_state: int) -> str:
    return (f"Q = {designs.weight_text(_compact(w['q']), n_state)}, "
            f"R = {designs.weight_text(_compact(w['r']), 3)}")


def _compact(v):
    """A diagonal with every entry equal as that number (so it prints as 'q I6')."""
    a = np.atleast_1d(np.asarray(v, dtype=float))
    return float(a[0]) if np.all(a == a[0]) else a


def resolve(sc, config: Path = GAINS_TOML) -> dict[str, GainChoice]:
    """law -> GainChoice for every table law the scenario defines (its selected table)."""
    reg = registry.load()
    out: dict[str, GainChoice] = {}
    for law, lcfg in sc.control.laws.items():
        if reg.table_field(law) is None or lcfg.table is None:
            continue
        cfg = design_config(config)
        dcfg = cfg.get("designs", {}).get(lcfg.table)
        if dcfg is None:
            raise GainDesignError(f"{sc.path}: laws.{law}.table = {lcfg.table!r} has no design in {config}")
        kind = dcfg["kind"]
        dplant = cfg["plants"][dcfg["plant"]]
        splant = _scenario_plant(sc, kind, dplant)
        entry = lcfg.tables.get(lcfg.table, {})
        weights = {k: entry[k] for k in ("q", "r") if k in entry}
        choice = GainChoice(law, lcfg.table, "compiled", design_plant=_plant_text(kind, dplant),
                            scenario_plant=_plant_text(kind, splant),
                            table_weights=(_weights_text(dcfg, designs.state_count(kind)) if kind in designs.LQR_KINDS
                                           else f"design {lcfg.table}"))
        same_plant = _same_plant(kind, dplant, splant)
        if not weights or kind not in designs.LQR_KINDS:
            choice.weights = choice.table_weights
            if not same_plant:
                choice.warnings.append(
                    f"{law}: the compiled table {lcfg.table} was designed for {choice.design_plant}, "
                    f"this scenario's plant is {choice.scenario_plant}; give design weights under "
                    f"[laws.{law}.tables.{lcfg.table}] to fly a gain designed for it")
            out[law] = choice
            continue
        same_weights = all(np.array_equal(designs.weight_matrix(weights[k], n), designs.weight_matrix(dcfg[k], n))
                           for k, n in (("q", designs.state_count(kind)), ("r", 3)))
        choice.weights = _weights_text(weights, designs.state_count(kind))
        if same_plant and same_weights:
            out[law] = choice
            continue
        d = dict(dcfg, q=list(weights["q"]), r=list(weights["r"]))
        name = f"{lcfg.table}@{sc.id}"
        try:
            res = designs.design_one(name, d, splant, cfg.get("hinf", {}))
        except DesignError as exc:
            raise GainDesignError(f"{sc.path}: laws.{law}.tables.{lcfg.table}: no gain for this scenario: "
                                  f"{exc}") from None
        choice.source, choice.k, choice.design = "designed", np.asarray(res.k, dtype=float), res
        out[law] = choice
    return out
