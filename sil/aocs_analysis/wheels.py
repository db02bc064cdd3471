"""Reaction wheel figures of a run (SPEC 5.3; docs/spec.md 5.3), from the truth and command logs.

    metrics(log, scenario) -> the run JSON's "wheels" section (None without a [wheels] array)
    envelope(scenario)     -> the wheel envelope along the slew's eigenaxis and its bang-bang bound

Per wheel: peak |speed| against its limit, peak |motor torque| against its limit, the time its
command sat at the torque limit, the time its motor was cut at the speed limit (truth_t
wheel_at_limit bits, one control period each: time_speed_cut_s) and the time it spent at the speed limit
(time_at_speed_limit_s: periods ending with the motor cut or the speed within SPEED_LIMIT_REL of the
limit, where the flight software's allocation holds a saturated wheel; also as one list per wheel,
wheels.time_at_speed_limit_s); the total momentum H = J w + sum Js g Omega (true,
truth_t h_total: peak and final |H|), the wheels' own share |sum Js g Omega| (what they must store),
the flight software's smallest speed margin (actuator_cmd_t wheel_speed_margin), and which wheels
the scenario declared failed (removed from the allocation).

The eigenaxis bound (docs/spec.md 5.1) for the wheel envelope alone: slew_bound.py's eigenaxis and
alpha_max with the wheels (min_i u_s,max,i / |(Gs^+ J e)_i| over the healthy wheels, the flight
software's aocs_wheels_alpha_max computed independently with numpy), 2 sqrt(theta_f / alpha).
"""
from __future__ import annotations

import math

import numpy as np

from .slew_bound import alpha_max, eigenaxis

#: a wheel within this fraction of its speed limit is at the limit (time_at_speed_limit_s)
SPEED_LIMIT_REL = 1e-6


def _f(x):
    return None if x is None else float(x)


def envelope(scenario) -> dict | None:
    """alpha_max of the wheels alone along the slew's eigenaxis and the eigenaxis bound (slew_bound.py), or None."""
    w = scenario.effectors.get("wheels")
    if w is None or scenario.kind != "attitude":
        return None
    theta, e = eigenaxis(scenario.attitude.q0, scenario.target.qd0)
    if not theta > 0.0:
        return {"theta_f_deg": 0.0, "alpha_max_radps2": None, "eigenaxis_bound_s": 0.0}
    alpha = alpha_max(scenario.attitude.inertia, e, None, None, w)
    return {"theta_f_deg": math.degrees(theta), "axis_B": [float(x) for x in e], "alpha_max_radps2": alpha,
            "eigenaxis_bound_s": 2.0 * math.sqrt(theta / alpha),
            "healthy_wheels": [i for i in range(w.n) if i not in w.failed]}


def metrics(log, scenario) -> tuple[dict | None, dict]:
    """(the "wheels" section, plot series) of a run; (None, {}) without a wheel array."""
    w = scenario.effectors.get("wheels")
    if w is None:
        return None, {}
    tr, cmd, n, dt = log.truth, log.cmd, w.n, scenario.dt
    speed = np.asarray(tr["wheel_speed"])[:, :n]
    torque = np.asarray(tr["wheel_torque"])[:, :n]
    bits = np.asarray(tr["wheel_at_limit"]).astype(np.int64)
    H = np.asarray(tr["h_total"])
    Hn = np.linalg.norm(H, axis=1)
    G = np.array(w.axes).T
    js = np.array(w.spin_inertia_kg_m2)
    h_w = np.linalg.norm((G @ (speed * js).T).T, axis=1)     # |sum Js g Omega|
    # truth sample k reports the period before it: every sample after the first is one period, (samples - 1, n),
    # bit i (at the torque limit) and bit 8 + i (speed cut) of wheel i
    at_t = (bits[1:, None] >> np.arange(n)) & 1
    at_s = (bits[1:, None] >> (8 + np.arange(n))) & 1
    wmax = np.asarray(w.speed_limit_rad_s, float)
    at_end = np.abs(speed[1:]) >= wmax[None, :] * (1.0 - SPEED_LIMIT_REL)
    per = []
    for i in range(n):
        per.append({
            "wheel": i, "failed": i in w.failed,
            "peak_speed_rad_s": _f(np.max(np.abs(speed[:, i]))) if speed.size else None,
            "speed_limit_rad_s": w.speed_limit_rad_s[i],
            "peak_motor_torque_nm": _f(np.max(np.abs(torque[:, i]))) if torque.size else None,
            "torque_limit_nm": w.torque_limit_nm[i],
            "time_at_torque_limit_s": _f(at_t[:, i].sum() * dt),
            # periods that end with the wheel at its limit: the plant cut its motor, or the flight software holds
            # it within SPEED_LIMIT_REL of the limit (its allocation scales the command down rather than cross it)
            "time_at_speed_limit_s": _f(np.count_nonzero(at_s[:, i].astype(bool) | at_end[:, i]) * dt),
            "time_speed_cut_s": _f(at_s[:, i].sum() * dt),
        })
    tol = 1e-9
    within = all(p["peak_motor_torque_nm"] is None or p["peak_motor_torque_nm"] <= p["torque_limit_nm"] * (1 + tol)
                 for p in per) and all(p["peak_speed_rad_s"] is None or
                                       p["peak_speed_rad_s"] <= p["speed_limit_rad_s"] * (1 + 1e-3) for p in per)
    # every wheel torque command (actuator_cmd_t.u_wheels) against that wheel's limit, and finite
    uw = np.asarray(cmd["u_wheels"], float)[:, :n] if cmd["tick"].size else np.zeros((0, n))
    umax = np.asarray(w.torque_limit_nm, float)
    with np.errstate(invalid="ignore"):
        over = int(np.count_nonzero(np.any(np.abs(uw) > umax * (1 + tol), axis=1))) if uw.size else 0
    nan = int(np.count_nonzero(~np.all(np.isfinite(uw), axis=1))) if uw.size else 0
    margin = np.asarray(cmd["wheel_speed_margin"]) if cmd["tick"].size else np.zeros(0)
    scale = np.asarray(cmd["wheel_scale"]) if cmd["tick"].size else np.zeros(0)
    out = {
        "count": n, "removed": list(w.failed),
        "per_wheel": per,
        "total_momentum_nms": {"peak": _f(Hn.max()) if Hn.size else None, "final": _f(Hn[-1]) if Hn.size else None},
        "wheel_momentum_nms": {"peak": _f(h_w.max()) if h_w.size else None, "final": _f(h_w[-1]) if h_w.size else None,
                               "capacity_per_wheel": [float(c) for c in w.momentum_capacity_nms()]},
        # per wheel, the name (the same figures as per_wheel[i]["time_at_speed_limit_s"])
        "time_at_speed_limit_s": [p["time_at_speed_limit_s"] for p in per],
        "min_speed_margin": _f(margin.min()) if margin.size else None,
        "time_scaled_s": _f(np.count_nonzero(scale < 1.0) * dt) if scale.size else 0.0,
        "within_limits": bool(within),
        "commands_over_limit": over, "commands_not_finite": nan,
        "envelope": envelope(scenario),
    }
    series = {"t": np.asarray(tr["t_s"]), "speed": speed, "speed_limit": list(w.speed_limit_rad_s),
              "H_norm": Hn, "h_wheels_norm": h_w, "failed": list(w.failed), "n": n}
    return out, series


def table_rows(m: dict) -> list[tuple[str, str]]:
    """Summary lines of the wheels section."""
    rows = []
    peaks = " ".join(f"{p['peak_speed_rad_s']:.4g}" for p in m["per_wheel"])
    rows.append(("wheels", f"{m['count']} wheels, removed: "
                 + (", ".join(f"wheel {i}" for i in m["removed"]) if m["removed"] else "none")
                 + ("" if m["within_limits"] else "; A LIMIT WAS EXCEEDED")))
    rows.append(("peak wheel speed", f"[{peaks}] rad/s (limit {m['per_wheel'][0]['speed_limit_rad_s']:g})"))
    rows.append(("time at torque limit", "[" + " ".join(f"{p['time_at_torque_limit_s']:g}" for p in m["per_wheel"])
                 + "] s per wheel"))
    rows.append(("time at speed limit", "[" + " ".join(f"{p['time_at_speed_limit_s']:g}" for p in m["per_wheel"])
                 + "] s per wheel"))
    hm, hw = m["total_momentum_nms"], m["wheel_momentum_nms"]
    rows.append(("total momentum |H|", f"peak {hm['peak']:.4g} N m s, final {hm['final']:.4g} N m s; wheels' "
                 f"share peak {hw['peak']:.4g} N m s ({hw['capacity_per_wheel'][0]:g} N m s per wheel)"))
    if m["min_speed_margin"] is not None:
        rows.append(("speed margin", f"min {m['min_speed_margin']:.3g} (1 - |Omega| / Omega_max), "
                     f"allocation scaled {m['time_scaled_s']:g} s"))
    env = m.get("envelope")
    if env and env.get("alpha_max_radps2"):
        rows.append(("wheel envelope", f"alpha_max {env['alpha_max_radps2']:.4g} rad/s^2 along the "
                     f"{env['theta_f_deg']:.4g} deg eigenaxis: bang-bang bound {env['eigenaxis_bound_s']:.4g} s"))
    return rows

