"""The run JSON's `holds` section (docs/spec.md 5.11; docs/sil.md): one entry per observation of the scenario's
plan ([[plan]]) commanded inside the run, from the logged truth.

    metrics(scenario, series) -> [entry, ...] (None without a plan)

Observation i is commanded at T_i, held over [T_i + slew_s, T_i + slew_s + hold_s) (aocs_plant.observation_plan;
the hold cut at the run's end, `complete` false). Its entry: `target` (index, the quaternion q_DN and the
input as the file gave it), `slew_deg` (the eigenaxis angle from the previous target, or from the initial
attitude), `command_s`, `hold_start_s`, `hold_end_s`, `settle_s` (from T_i to the first sample after which
every [settle] criterion holds until the hold's end, against this observation's target; None: not settled),
`pointing_rms_arcsec` and `pointing_max_arcsec` (the true pointing angle of the truth samples inside the hold),
`meets_requirement` (settled before the hold starts, settle_s <= slew_s, and the hold's pointing within the
figure it is held to; None without one), `requirement` (that figure: {"basis", "on", "limit_arcsec"}).

The figure ([metrics] hold_requirement, docs/spec.md 5.11.6): "requirement" (default), the hold's max against
requirement_arcsec; "sensors" (a scenario flown on a star tracker and gyro through the MEKF), the hold's rms
against SENSOR_FACTOR times the steady-state knowledge rms sigma_k of those sensors (Farrenkopf 1978, the total
angle over the control periods: sqrt(sum_i log_rms_i^2) of estimation.steady_state_bounds), the pointing a loop
reaches on them (issue 20's rule for the integral laws, docs/results.md); the requirement_arcsec verdict of the
max is kept beside it (`requirement.meets_requirement_arcsec`).
"""
from __future__ import annotations

import math

import numpy as np

from . import estimation

#: a hold judged on its sensors: pointing rms within this many times the steady-state knowledge rms (issue 20's
#: rule for the integral laws, docs/results.md "The integral laws against 1.5 times the knowledge error")
SENSOR_FACTOR = 1.5


def _f(x):
    x = float(x)
    return x if math.isfinite(x) else None


def slew_angle_deg(q_from, q_to) -> float:
    """The eigenaxis angle between two attitudes (scalar last), deg: 2 atan2(|dq_v|, |dq_4|), dq = q_to q_from^-1."""
    a, b = np.asarray(q_from, float), np.asarray(q_to, float)
    c = abs(float(np.dot(a, b)))                 # |dq_4| = |<q_to, q_from>|
    s = math.sqrt(max(0.0, 1.0 - min(1.0, c) ** 2))
    return math.degrees(2.0 * math.atan2(s, c))


def metrics(scenario, series: dict, inside: np.ndarray) -> list[dict] | None:
    """One entry per commanded observation; series: run_metrics.attitude_series (true_angle against the plan's
    target at each t), inside: run_metrics.settle_mask of the same samples."""
    plan = getattr(scenario, "plan", None)
    if plan is None:
        return None
    t = np.asarray(series["t"], float)
    ang = np.asarray(series["true_angle"], float)
    t_end = float(t[-1]) if t.size else 0.0
    req = scenario.metrics.requirement_arcsec
    figure = requirement_figure(scenario)
    out = []
    prev = scenario.attitude.q0
    for i, (T, ob, (a, b)) in enumerate(zip(plan.command_times_s, plan.observations, plan.hold_windows_s())):
        if T >= t_end:
            break
        key, value = ob.target_input
        entry = {"target": {"index": i, "quaternion": [float(x) for x in ob.qd], key: [float(x) for x in value]},
                 "slew_deg": slew_angle_deg(prev, ob.qd), "command_s": float(T), "slew_s": ob.slew_s,
                 "hold_start_s": float(a), "hold_end_s": float(min(b, t_end)), "complete": bool(b <= t_end)}
        prev = ob.qd
        slot = (t >= T) & (t < b)
        entry["settle_s"] = _settle_from(t[slot], inside[slot], T)
        hold = (t >= a) & (t < b)
        if hold.any():
            e = ang[hold]
            entry["pointing_rms_arcsec"] = _f(np.sqrt(np.mean(e * e)))
            entry["pointing_max_arcsec"] = _f(np.max(e))
        else:
            entry["pointing_rms_arcsec"] = entry["pointing_max_arcsec"] = None
        entry["requirement"] = dict(figure) if figure is not None else None
        entry["meets_requirement"] = _judge(entry, ob.slew_s, figure, req)
        out.append(entry)
    return out


def requirement_figure(scenario) -> dict | None:
    """What every hold of the scenario is held to: {"basis": "requirement", "on": "max", "limit_arcsec"}, or
    {"basis": "sensors", "on": "rms", "limit_arcsec", "knowledge_rms_arcsec", "knowledge_rms_per_axis_arcsec",
    "factor", "requirement_arcsec"}; None without a requirement."""
    m = scenario.metrics
    if getattr(m, "hold_requirement", "requirement") != "sensors":
        return None if m.requirement_arcsec is None else {"basis": "requirement", "on": "max",
                                                          "limit_arcsec": m.requirement_arcsec}
    names = scenario.sensors.sensors
    bounds = estimation.steady_state_bounds(
        estimation.SensorSet.from_configs(names["star_tracker"], names["gyro"]), scenario.control_rate_hz)
    if bounds is None:
        return None
    per = [float(x) for x in bounds["log_rms_arcsec"]]
    k = math.sqrt(sum(x * x for x in per))
    return {"basis": "sensors", "on": "rms", "limit_arcsec": SENSOR_FACTOR * k, "knowledge_rms_arcsec": k,
            "knowledge_rms_per_axis_arcsec": per, "factor": SENSOR_FACTOR, "requirement_arcsec": m.requirement_arcsec}


def _judge(entry: dict, slew_s: float, figure: dict | None, req) -> bool | None:
    """Settled within the slew allowance and the hold's max (or rms) within the figure; with the sensors'
    figure also the max against requirement_arcsec, kept in entry["requirement"]."""
    mx, rms, settle = entry["pointing_max_arcsec"], entry["pointing_rms_arcsec"], entry["settle_s"]
    if figure is None or mx is None:
        return None
    settled = settle is not None and settle <= slew_s
    if figure["basis"] == "sensors" and req is not None:
        entry["requirement"]["meets_requirement_arcsec"] = bool(settled and mx <= req)
    value = mx if figure["on"] == "max" else rms
    return bool(settled and value is not None and value <= figure["limit_arcsec"])


def _settle_from(t: np.ndarray, inside: np.ndarray, t0: float):
    """Time from t0 to the first sample after which every sample is inside (None: the last one is not)."""
    if not t.size or not inside[-1]:
        return None
    out = np.flatnonzero(~inside)
    k = 0 if not out.size else int(out[-1]) + 1
    return float(t[k] - t0)


def table_rows(holds: list[dict], requirement) -> list[tuple[str, str]]:
    """One summary line, and one per hold that misses the requirement."""
    if not holds:
        return [("holds", "none commanded")]
    done = [h for h in holds if h["pointing_max_arcsec"] is not None]
    worst = max((h["pointing_max_arcsec"] for h in done), default=None)
    met = sum(1 for h in holds if h["meets_requirement"])
    fig = next((h.get("requirement") for h in holds if h.get("requirement")), None)
    if fig is not None and fig["basis"] == "sensors":
        met_req = sum(1 for h in holds if fig and (h.get("requirement") or {}).get("meets_requirement_arcsec"))
        text = (f"{len(holds)} observations, {met} meet the sensors' figure (rms <= {fig['factor']:g} x "
                f"{fig['knowledge_rms_arcsec']:.3g} = {fig['limit_arcsec']:.3g} arcsec), {met_req} the requirement"
                + (f" ({requirement:g} arcsec max)" if requirement is not None else ""))
    else:
        text = f"{len(holds)} observations, {met} meet the requirement" + (
            f" ({requirement:g} arcsec)" if requirement is not None else "")
    if worst is not None:
        text += f"; worst hold max {worst:.3g} arcsec, settle max " + (
            "never" if any(h["settle_s"] is None for h in holds)
            else f"{max(h['settle_s'] for h in holds):.0f} s")
    rows = [("holds", text)]
    for h in holds:
        if h["meets_requirement"] is False:
            rows.append((f"hold {h['target']['index']}", f"MISSED: settle "
                         + ("never" if h["settle_s"] is None else f"{h['settle_s']:.0f} s") + ", max "
                         + ("-" if h["pointing_max_arcsec"] is None else f"{h['pointing_max_arcsec']:.3g} arcsec")
                         + ("" if h["pointing_rms_arcsec"] is None else f", rms {h['pointing_rms_arcsec']:.3g} arcsec")))
    return rows
