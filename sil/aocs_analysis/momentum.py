"""The run JSON's `momentum` section (docs/spec.md 5.11; docs/sil.md): the wheels' stored momentum and what the
momentum-management stage did to it, from the log.

    metrics(log, scenario, wheel_series, plant) -> the section (None without a [wheels] array)

- `max_nms`, `final_nms`: the largest and the last |h_w|, h_w = sum_i Js_i g_i Omega_i (B), from the true wheel
  speeds of truth_t (aocs_analysis.wheels' series); `max_in_holds_nms` the largest inside the observation
  plan's holds (None without a plan); `capacity_nms` each wheel's Js Omega_max.
- `unloading`: the policy (docs/spec.md 5.9), `events` (actuator_cmd_t n_unload_events: unloads started),
  `time_s` (periods with an unload in progress); with thrusters `propellant_kg`, the propellant of the
  on-times the flight software commanded, sum_k sum_i F_i tau_ik / (Isp g0) over the scenario's [thrusters]
  (the plant fires the same on-times: they are already on its quantum and above its minimum), and
  `propellant_kg_per_day` (scaled to 86400 s); with magnetorquers `dipole_am2_s`, sum_k sum_i |m_ik| dt of the
  commanded rod dipoles clipped at their limits, per rod; `plant` the plant's own integrals at the end of the
  run (plant_node's summary: thrusters.propellant_kg, magnetorquers.dipole_s_am2s), None when it gave none.
"""
from __future__ import annotations

import numpy as np

#: standard gravity, m/s^2 (the thrusters' propellant: F tau / (Isp g0), docs/spec.md 5.8.1)
G0_M_S2 = 9.80665
SECONDS_PER_DAY = 86400.0


def _f(x):
    return None if x is None else float(x)


def metrics(log, scenario, wheel_series: dict, plant: dict | None = None, hold_windows=None) -> dict | None:
    """The `momentum` section; None without a wheel array. hold_windows: ((start, end), ...) of the plan's holds."""
    w = scenario.effectors.get("wheels")
    if w is None or not wheel_series:
        return None
    t = np.asarray(wheel_series["t"], float)
    h = np.asarray(wheel_series["h_wheels_norm"], float)
    in_holds = None
    if hold_windows:
        mask = np.zeros(t.shape, bool)
        for a, b in hold_windows:
            mask |= (t >= a) & (t < b)
        in_holds = _f(h[mask].max()) if mask.any() else None
    mom = scenario.momentum
    threshold = mom.policy != "none" and mom.trigger == "threshold"   # the thresholds mean something
    out = {"max_nms": _f(h.max()) if h.size else None, "final_nms": _f(h[-1]) if h.size else None,
           "max_in_holds_nms": in_holds,
           "capacity_nms": [float(c) for c in w.momentum_capacity_nms()],
           "policy": mom.policy, "trigger": mom.trigger if mom.policy != "none" else None,
           "h_start_nms": mom.h_start_nms if threshold else None,
           "h_stop_nms": mom.h_stop_nms if threshold else None,
           "unloading": unloading(log, scenario, plant)}
    return out


def unloading(log, scenario, plant: dict | None) -> dict:
    """The `unloading` part: events, time, and the propellant or the dipole integral of the policy."""
    cmd, dt = log.cmd, scenario.dt
    n = int(cmd["tick"].size)
    out = {"events": int(cmd["n_unload_events"][-1]) if n else 0,
           "time_s": float(np.count_nonzero(cmd["unloading"]) * dt) if n else 0.0,
           "plant": (plant or {}).get("unloading_actuators")}
    policy = scenario.momentum.policy
    if policy == "thrusters":
        thr = scenario.effectors["thrusters"]
        nt = thr.n
        on = np.asarray(cmd["thruster_on_s"], float)[:, :nt] if n else np.zeros((0, nt))
        thrust = np.broadcast_to(np.asarray(thr.thrust_n, float), (nt,))
        kg = float(np.sum(on * thrust[None, :]) / (thr.isp_s * G0_M_S2))
        dur = n * dt
        out["propellant_kg"] = kg
        out["propellant_kg_per_day"] = kg * SECONDS_PER_DAY / dur if dur > 0 else None
        out["pulses"] = int(np.count_nonzero(on > 0.0))
    elif policy == "magnetorquers":
        mtq = scenario.effectors["magnetorquers"]
        m = np.asarray(cmd["dipole_am2"], float) if n else np.zeros((0, 3))
        m = np.clip(m, -np.asarray(mtq.max_dipole_am2, float), np.asarray(mtq.max_dipole_am2, float))
        per_rod = np.sum(np.abs(m), axis=0) * dt
        out["dipole_am2_s"] = float(per_rod.sum())
        out["dipole_am2_s_per_rod"] = [float(x) for x in per_rod]
    return out


def table_rows(m: dict) -> list[tuple[str, str]]:
    """Summary lines of the momentum section."""
    u = m["unloading"]
    rows = [("wheel momentum |h_w|", f"max {m['max_nms']:.4g} N m s"
             + (f", max in holds {m['max_in_holds_nms']:.4g}" if m.get("max_in_holds_nms") is not None else "")
             + f", final {m['final_nms']:.4g} (capacity {m['capacity_nms'][0]:g} N m s per wheel)")]
    text = f"{m['policy']}: {u['events']} unloads, {u['time_s']:g} s unloading"
    if "propellant_kg" in u:
        per_day = u.get("propellant_kg_per_day")
        text += f", propellant {u['propellant_kg']:.4g} kg" + (f" ({per_day:.4g} kg/day)" if per_day else "")
    if "dipole_am2_s" in u:
        text += f", dipole integral {u['dipole_am2_s']:.4g} A m^2 s"
    rows.append(("momentum unloading", text))
    return rows
