"""The fsw_node configuration file written from a scenario.

Format and keys: docs/wire-contract.md, "Configuration file" (flat
`key = value`, unknown keys are errors). Numbers are written with repr(), the
shortest decimal that reads back to the same double, so the node's strtod
gets exactly the scenario's values.

What comes from where (docs/sil.md):

- law, control period, target (`target_q`; a rotating target as
  `target_rotation_rate`, never `target_w`), inertia (used by smc);
- gains of EVERY law the scenario defines (so a command may switch law
  during the run): the keys are the law's field rows in the firmware's law
  registry (aocs_core.registry), valued from the scenario's parameters of the
  same names; design-based laws by table name (`<law>.table`): the compiled
  firmware tables fly, or by value (`<law>.k`) a gain the runner designed for
  the scenario at run start (aocs_runner.scenario_gains);
- limits: the scenario's `actuator.axis_limit` / `norm_limit`, or the
  runner's `--limit`; a scenario without a limit (the reference runs) gets
  UNLIMITED per axis, because the executive requires one limit;
- guidance: the scenario's [guidance] as the registry's guidance.* keys of
  the same names, only in slew mode (step mode, the default, writes none);
- the reaction wheel array, when the scenario has a [wheels] section: the
  same description that builds the plant's wheels (aocs_plant.effectors.
  reaction_wheels) gives `wheels.count`, `wheels.failed_mask` and per wheel
  `wheel<i>.axis_B` and the plant's spin inertia, torque and speed limits under
  their registry fields (aocs_core.registry.WHEEL_REGISTRY_ROWS), the friction
  model of the flight software's feedforward `wheel<i>.viscous_nms / coulomb_nm /
  coulomb_width_radps`
  (the plant's own friction coefficients, b and c times the [wheels] key
  `fsw_friction_scale`, 1 by default) and the null-space management
  `wheels.null_gain`, `wheel<i>.null_speed_radps`, so the two cannot disagree; the
  spacecraft inertia for the momentum is the `inertia` key;
- the attitude determination, from the scenario's [estimator] (docs/spec.md
  5.6.11): type "passthrough" (the default, every reference scenario)
  writes nothing; "mekf" writes `estimator = mekf` and the mekf.* keys: the
  sensor figures from the SAME [sensors.star_tracker] and [sensors.gyro]
  that build the plant's sensors (tracker mounting `mekf.st_q_SB`, its
  cross / about noise arcsec -> rad, the gyro's ARW and RRW), each noise
  times [estimator] noise_scale (1: the filter knows its sensors; else a
  mistuned filter), and the filter's tuning from [estimator] (gate, P0,
  max gap, bias prior, the start: `mekf.init_mode`, `mekf.init_q_BN`, and
  the gyroless model: `mekf.gyroless_*`, docs/spec.md 5.6.12);
- the momentum management, from the scenario's [momentum] (docs/spec.md 5.9):
  policy "none" (the default, every reference scenario) writes nothing; else
  `mom.policy`, `mom.trigger`, `mom.h_target_nms`, `mom.h_start_nms`,
  `mom.h_stop_nms` from [momentum], and the actuators' figures from the SAME
  sections that build the plant's: thrusters from [thrusters] (nominal
  geometry: no misalignment, no thrust noise; `mom.thr_arm_*_m` = r_i x d_i
  scaled by thrust_i / the largest thrust, `mom.thr_thrust_n` = that thrust,
  `mom.thr_min_on_s` = min_on_time_s, `mom.thr_quantum_s` =
  on_time_quantum_s, padded with zeros to 12) with [momentum] dump_torque_nm;
  magnetorquers from [magnetorquers] (`mom.mtq_axes`, `mom.mtq_max_dipole_am2`)
  with [momentum] k_mtq_per_s;
- k_safe: 0.1 * mean principal inertia (N m s/rad), i.e. a 10 s damping
  time constant in safe mode (attitude); orbit safe mode is zero force.
"""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from aocs_core import registry
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_core.limits import UNLIMITED

#: the flight software's guidance keys: guidance.<name of the scenario's [guidance] value>
GUIDANCE_PREFIX = "guidance."


class ConfigError(ValueError):
    """The scenario cannot be expressed as an fsw_node configuration."""


def _num(x: float) -> str:
    x = float(x)
    if not math.isfinite(x):
        raise ConfigError(f"non-finite value {x!r}")
    return repr(x)


def _vec(v) -> str:
    return " ".join(_num(x) for x in v)


def _law_keys(law_cfg, gain=None) -> dict[str, str]:
    """The keys of one law: every field its registry row takes (aocs_core.registry), valued from the
    scenario's parameter of the same name (a scalar fills every component of a vector field); a
    table-based law's gain by table name, so the compiled firmware table flies, or, when `gain`
    (3x6) is given (designed for the scenario at run start, aocs_runner.scenario_gains), by value
    in the gain field the table field fills (`<law>.k`, row-major). The inertia field (mat3) is the
    plant's, written by node_config() for every attitude law."""
    reg = registry.load()
    out: dict[str, str] = {}
    for f in reg.fields_of(law_cfg.name):
        if f.type == "table":
            if gain is None:
                out[f.key] = law_cfg.table
            else:
                k = np.asarray(gain, dtype=float)
                gf = reg.gain_field_of(f)
                if k.size != gf.count:
                    raise ConfigError(f"{gf.key}: {k.size} gain entries, the flight software takes {gf.count}")
                out[gf.key] = _vec(k.ravel())
        elif f.type in ("real", "vec3"):
            v = law_cfg.params[f.param]
            if f.type == "real":
                out[f.key] = _num(v)
            else:
                out[f.key] = _vec(v if isinstance(v, (tuple, list)) else (v,) * f.count)
        # mat3: the plant's inertia (node_config); gain: given by the TABLE field of the same member
    return out


def wheel_keys(scenario) -> dict[str, str]:
    """fsw_node's wheel array keys from the scenario's [wheels] section (empty without one)."""
    w = scenario.effectors.get("wheels")
    if w is None:
        return {}
    out = {"wheels.count": str(w.n)}
    if w.failed:
        out["wheels.failed_mask"] = str(sum(1 << i for i in w.failed))
    row = registry.WHEEL_REGISTRY_ROWS   # the plant's [wheels] key -> the flight software's registry field
    for i in range(w.n):
        # the flight software's model of wheel i: its registry fields (wheel<i>.<member of aocs_wheels_config_t>)
        out[f"wheel{i}.axis_B"] = _vec(w.axes[i])
        for key in ("spin_inertia_kg_m2", "torque_limit_nm", "speed_limit_rad_s"):
            out[f"wheel{i}.{row[key]}"] = _num(getattr(w, key)[i])
        # the friction feedforward models the plant's bearing friction (docs/spec.md 5.3.2), times
        # fsw_friction_scale (1: exactly the plant's; a model error otherwise)
        out[f"wheel{i}.{row['viscous_nms']}"] = _num(w.fsw_friction_scale * w.viscous_nms)
        out[f"wheel{i}.{row['coulomb_nm']}"] = _num(w.fsw_friction_scale * w.coulomb_nm)
        out[f"wheel{i}.{row['coulomb_width_rad_s']}"] = _num(w.coulomb_width_rad_s)
        if w.null_gain_per_s > 0.0:
            out[f"wheel{i}.{row['null_speed_rad_s']}"] = _num(w.null_speed_rad_s[i])
    if w.null_gain_per_s > 0.0:
        out[row["null_gain_per_s"]] = _num(w.null_gain_per_s)
    return out


def estimator_keys(scenario) -> dict[str, str]:
    """fsw_node's attitude-determination keys from the scenario's [estimator] (empty for the passthrough)."""
    e = getattr(scenario, "estimator", None)
    if e is None or e.type == "passthrough":
        return {}
    if e.type != "mekf":
        raise ConfigError(f"estimator type {e.type!r}: no flight-software keys for it")
    st, gyro = scenario.sensors["star_tracker"], scenario.sensors["gyro"]
    k = e.noise_scale
    out = {
        "estimator": e.type,
        # the sensor figures: the plant's own sensors (one description), in the filter's units
        "mekf.st_q_SB": _vec(st.mounting_q),
        "mekf.st_sigma_cross_rad": _num(k * st.noise_cross_arcsec / ARCSEC_PER_RAD),
        "mekf.st_sigma_about_rad": _num(k * st.noise_about_arcsec / ARCSEC_PER_RAD),
        "mekf.gyro_arw_radpsqrts": _num(k * gyro.arw),
        "mekf.gyro_rrw_radps1p5": _num(k * gyro.rrw),
        # the filter's tuning
        "mekf.bias0_radps": _vec(e.bias0_radps),
        "mekf.p0_att_sigma_rad": _num(e.p0_att_sigma_rad),
        "mekf.p0_bias_sigma_radps": _num(e.p0_bias_sigma_radps),
        "mekf.gate_chi2": _num(e.gate_chi2),
        "mekf.max_gap_s": _num(e.max_gap_s),
        "mekf.init_mode": e.init_mode,
        "mekf.gyroless_torque_sigma_nm": _num(e.gyroless_torque_sigma_nm),
        "mekf.gyroless_p0_rate_sigma_radps": _num(e.gyroless_p0_rate_sigma_radps),
        "mekf.gyroless_rate_sigma_radps": _num(e.gyroless_rate_sigma_radps),
    }
    if e.init_mode == "configured":
        out["mekf.init_q_BN"] = _vec(e.init_q_BN)
    keys = {f.key for f in registry.load().config_fields}
    unknown = sorted(set(out) - keys)
    if unknown:
        raise ConfigError(f"the flight software has no key {unknown[0]!r} (the registry of this build)")
    return out


#: AOCS_MOM_THRUSTERS_MAX (momentum.h): the mom.thr_arm_*_m rows hold this many values
MOM_THRUSTERS_MAX = 12


def fdir_keys(scenario) -> dict[str, str]:
    """fsw_node's fault-management keys the scenario's [fdir] gives (the others: the flight software's
    defaults)."""
    out = {}
    for name, v in getattr(scenario, "fdir", {}).items():
        out[f"fdir.{name}"] = str(v) if isinstance(v, int) else _num(v)
    return out


def momentum_keys(scenario) -> dict[str, str]:
    """fsw_node's momentum-management keys from the scenario's [momentum] and the actuator sections (empty for
    policy none)."""
    m = getattr(scenario, "momentum", None)
    if m is None or m.policy == "none":
        return {}
    out = {"mom.policy": m.policy, "mom.trigger": m.trigger, "mom.h_target_nms": _vec(m.h_target_nms),
           "mom.h_start_nms": _num(m.h_start_nms), "mom.h_stop_nms": _num(m.h_stop_nms)}
    if m.policy == "thrusters":
        t = scenario.effectors["thrusters"]
        n = len(t.positions_m)
        if n > MOM_THRUSTERS_MAX:
            raise ConfigError(f"{n} thrusters: the flight software allocates at most {MOM_THRUSTERS_MAX}")
        thrust = tuple(t.thrust_n) if isinstance(t.thrust_n, (tuple, list)) else (t.thrust_n,) * n
        f_max = max(thrust)
        arms = []
        for r, d, f in zip(t.positions_m, t.directions, thrust):
            c = np.cross(np.asarray(r, float), np.asarray(d, float)) * (f / f_max)   # nominal geometry
            arms.append(tuple(float(x) for x in c))
        arms += [(0.0, 0.0, 0.0)] * (MOM_THRUSTERS_MAX - n)
        # bit i set: thruster i is fed through latch valve B (clear: A), the plant's [thrusters] latch_branch
        b_mask = sum(1 << i for i, b in enumerate(getattr(t, "latch_branch", ())) if b == 1)
        out.update({"mom.thr_count": str(n), "mom.thr_thrust_n": _num(f_max),
                    "mom.thr_min_on_s": _num(t.min_on_time_s), "mom.thr_quantum_s": _num(t.on_time_quantum_s),
                    "mom.dump_torque_nm": _num(m.dump_torque_nm), "mom.thr_latch_b_mask": str(b_mask)})
        for c, axis in enumerate("xyz"):
            out[f"mom.thr_arm_{axis}_m"] = _vec([a[c] for a in arms])
    elif m.policy == "magnetorquers":
        g = scenario.effectors["magnetorquers"]
        out.update({"mom.k_mtq_per_s": _num(m.k_mtq_per_s),
                    "mom.mtq_axes": _vec([x for axis in g.axes for x in axis]),
                    "mom.mtq_max_dipole_am2": _vec(g.max_dipole_am2)})
    else:
        raise ConfigError(f"momentum policy {m.policy!r}: no flight-software keys for it")
    keys = {f.key for f in registry.load().config_fields}
    unknown = sorted(set(out) - keys)
    if unknown:
        raise ConfigError(f"the flight software has no key {unknown[0]!r} (the registry of this build)")
    return out


def node_config(scenario, law: str, *, mode: str = "lockstep", limit: float | None = None,
                idle_timeout_s: float = 5.0, run_timeout_s: float = 0.0,
                status_period_s: float | None = None, lcm_url: str | None = None,
                gains: dict | None = None, wait_spin_us: float = 0.0) -> dict[str, str]:
    """key -> value text of the fsw_node configuration for one run.

    law: a law of the scenario, or "none" (control disabled: STANDBY, zero command).
    limit: per-axis actuator limit override (N m or N), as `aocs run --limit`.
    gains: law -> explicit 3x6 gain flown instead of the law's compiled table (None: the tables).
    wait_spin_us: lockstep over udpm, how long the node's wait for a sensors_t polls before it sleeps (0: not
    written, the node's default 0).
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
        for f in registry.load().fields:
            if f.type == "mat3":   # the inertia a law models (smc): the plant's, as the scenario gives it
                cfg[f.key] = _vec(np.asarray(sc.attitude.inertia, float).ravel())
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
    g = getattr(sc, "guidance", None)
    if sc.kind == "attitude" and g is not None and g.mode != "step":
        # [guidance]: the registry's guidance.* keys, each the scenario's value of the same name (one
        # description). Step mode writes nothing: the reference runs' configuration stays as it was
        for f in registry.load().config_fields:
            if f.key.startswith(GUIDANCE_PREFIX):
                v = getattr(g, f.key[len(GUIDANCE_PREFIX):])
                cfg[f.key] = v if f.kind == "enum" else _num(v)
    cfg.update(wheel_keys(sc))
    if sc.kind == "attitude":
        cfg.update(estimator_keys(sc))
        cfg.update(momentum_keys(sc))
    cfg.update(fdir_keys(sc))
    # every law of the scenario; the selected one last so its shared keys win
    # (the variants of a law share its config, hence its keys: laws.def CFG_SHARED)
    order = [n for n in sc.control.laws if n != law] + ([law] if law in sc.control.laws else [])
    for name in order:
        cfg.update(_law_keys(sc.control.laws[name], (gains or {}).get(name)))
    cfg["idle_timeout_s"] = _num(idle_timeout_s)
    cfg["run_timeout_s"] = _num(run_timeout_s)
    if status_period_s is None:
        status_period_s = 0.05  # the plant starts on the first heartbeat
    cfg["status_period_s"] = _num(status_period_s)
    if lcm_url:
        cfg["lcm_url"] = lcm_url
    if wait_spin_us:
        cfg["wait_spin_us"] = _num(wait_spin_us)
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
