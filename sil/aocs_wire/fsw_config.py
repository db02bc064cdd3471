"""The fsw_node configuration file written from a scenario.

Format and keys: docs/wire-contract.md, "Configuration file" (flat
`key = value`, unknown keys are errors). Numbers are written with repr(), the
shortest decimal that reads back to the same double, so the node's strtod
gets exactly the scenario's values.

What comes from where (docs/sil.md):

- law, control period, target (`target_q`; a rotating target as
  `target_rotation_rate`, never `target_w`), inertia (used by smc);
- gains of EVERY law the scenario defines (so a command may switch law
  during the run); design-based laws by table name (`lqr_quat.table`,
  `hinf.table`, `orbit_lqr.table`): the compiled firmware tables fly;
- limits: the scenario's `actuator.axis_limit` / `norm_limit`, or the
  runner's `--limit`; a scenario without a limit (the reference runs) gets
  UNLIMITED per axis, because the executive requires one limit;
- k_safe: 0.1 * mean principal inertia (N m s/rad), i.e. a 10 s damping
  time constant in safe mode (attitude); orbit safe mode is zero force.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from aocs_core.limits import UNLIMITED


class ConfigError(ValueError):
    """The scenario cannot be expressed as an fsw_node configuration."""


def _num(x: float) -> str:
    x = float(x)
    if not math.isfinite(x):
        raise ConfigError(f"non-finite value {x!r}")
    return repr(x)


def _vec(v) -> str:
    return " ".join(_num(x) for x in v)


def _law_keys(law_cfg, scenario) -> dict[str, str]:
    name, p = law_cfg.name, law_cfg.params
    if name == "crp_linear":
        return {"crp_linear.k1": _num(p["k1"]), "crp_linear.k2": _num(p["k2"])}
    if name == "quat_pd":
        return {"quat_pd.kp": _num(p["kp"]), "quat_pd.kd": _num(p["kd"])}
    if name in ("quat_nlpd_neg", "quat_nlpd_pos"):
        return {"quat_nlpd.kp": _num(p["kp"]), "quat_nlpd.kd": _num(p["kd"])}
    if name == "smc":
        return {"smc.lambda": _vec(p["lambda"]), "smc.g": _vec(p["g"]), "smc.eps": _vec(p["eps"])}
    if name == "mrp_sat":
        out = {"mrp_sat.k": _num(p["k"]), "mrp_sat.lambda": _num(p["lambda"]),
               "mrp_sat.u_max": _num(p["u_max"])}
        for key in ("l1", "m1", "l2", "m2"):
            out[f"mrp_sat.{key}"] = _vec((p[key],) * 3)
        return out
    if name == "mrp_sat_tanh":
        # the firmware's tanh variant uses M = u_max (mrp_sat.h)
        if abs(p["m3"] - p["u_max"]) > 1e-12 * p["u_max"]:
            raise ConfigError(f"{scenario.path}: laws.mrp_sat_tanh.m3 = {p['m3']} but the flight "
                              f"software's tanh variant uses M3 = u_max = {p['u_max']}")
        return {"mrp_sat.k": _num(p["k"]), "mrp_sat.lambda": _num(p["lambda"]),
                "mrp_sat.u_max": _num(p["u_max"])}
    if name in ("lqr_quat", "hinf", "orbit_lqr"):
        return {f"{name}.table": law_cfg.table}
    raise ConfigError(f"law {name!r} has no fsw_node keys")  # pragma: no cover


def node_config(scenario, law: str, *, mode: str = "lockstep", limit: float | None = None,
                idle_timeout_s: float = 5.0, run_timeout_s: float = 0.0,
                status_period_s: float | None = None, lcm_url: str | None = None) -> dict[str, str]:
    """key -> value text of the fsw_node configuration for one run.

    law: a law of the scenario, or "none" (control disabled: STANDBY, zero command).
    limit: per-axis actuator limit override (N m or N), as `aocs run --limit`.
    """
    sc = scenario
    if mode not in ("lockstep", "realtime"):
        raise ConfigError(f"mode must be lockstep or realtime, got {mode!r}")
    if law != "none" and law not in sc.control.laws:
        raise ConfigError(f"{sc.path}: law {law!r} has no gains in this scenario "
                          f"(it defines {', '.join(sc.control.laws)})")
    cfg: dict[str, str] = {
        "law": law,
        "mode": mode,
        "control_period_s": _num(sc.dt),
    }
    if sc.kind == "attitude":
        cfg["target_q"] = _vec(sc.target.qd0)
        if any(x != 0.0 for x in sc.target.wd):
            cfg["target_rotation_rate"] = _vec(sc.target.wd)
        cfg["inertia"] = _vec(np.asarray(sc.attitude.inertia, float).ravel())
        jmean = float(np.mean(np.linalg.eigvalsh(np.asarray(sc.attitude.inertia, float))))
        cfg["k_safe"] = _num(0.1 * jmean)
    a = sc.actuator
    axis = limit if limit is not None else a.axis_limit
    if axis is not None:
        cfg["u_max_axis"] = _vec((axis,) * 3)
    if a.norm_limit is not None:
        cfg["u_max_norm"] = _num(a.norm_limit)
    if axis is None and a.norm_limit is None:
        cfg["u_max_axis"] = _vec((UNLIMITED,) * 3)
    # every law of the scenario; the selected one last so its shared keys win
    # (quat_nlpd_neg / _pos share quat_nlpd.*, mrp_sat / mrp_sat_tanh share mrp_sat.*)
    order = [n for n in sc.control.laws if n != law] + ([law] if law in sc.control.laws else [])
    for name in order:
        cfg.update(_law_keys(sc.control.laws[name], sc))
    cfg["idle_timeout_s"] = _num(idle_timeout_s)
    cfg["run_timeout_s"] = _num(run_timeout_s)
    if status_period_s is None:
        status_period_s = 0.05  # the plant starts on the first heartbeat
    cfg["status_period_s"] = _num(status_period_s)
    if lcm_url:
        cfg["lcm_url"] = lcm_url
    return cfg


def write(path: str | Path, cfg: dict[str, str], header: str = "") -> Path:
    path = Path(path)
    lines = ["# fsw_node configuration written by aocs run (docs/wire-contract.md)"]
    lines += [f"# {h}" for h in header.splitlines() if h]
    lines += [f"{k} = {v}" for k, v in cfg.items()]
    path.write_text("\n".join(lines) + "\n")
    return path


def read(path: str | Path) -> dict[str, str]:
    """Parse a configuration file back (comments and blank lines dropped)."""
    out: dict[str, str] = {}
    for line in Path(path).read_text().splitlines():
        line = line.split("#", 1)[0].strip()
        if not line:
            continue
        if "=" not in line:
            raise ConfigError(f"{path}: expected 'key = value', got {line!r}")
        k, v = line.split("=", 1)
        out[k.strip()] = v.strip()
    return out
