"""Run metrics from the LCM log (truth + commands), the JSON and the printed table.

Everything here is computed from what the log recorded, with
aocs_analysis.metrics, never from the plant's or the flight software's
in-memory view: the true attitude of truth_t against the scenario's target
(qd(t) = dq(wd t) (x) qd0, recomputed here), the saturated commands of
actuator_cmd_t, the counters the node put on the wire. The keys are listed
in docs/sil.md.
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from aocs_core import paths, registry
from aocs_core.conventions import quat_from_rotvec_rows as quat_from_rotvec
from aocs_core.limits import UNLIMITED
from aocs_core.modes import mode_value
from aocs_core.ticks import first_tick

from . import estimation as E
from . import events, faults, holds, momentum, passes, wheels
from . import metrics as M
from .gain_tables import designed_gamma
from .slew_bound import scenario_slew_bound_s

RAD2AS = M.ARCSEC_PER_RAD


# --------------------------------------------------------------------------- attitude helpers
def target_quat(scenario, t: np.ndarray) -> np.ndarray:
    """qd(t) = dq(wd t) (x) qd0 (docs/scenarios.md [target]), (n, 4); with an observation plan ([[plan]]) the
    target of the observation commanded at t."""
    t = np.asarray(t, float)
    plan = getattr(scenario, "plan", None)
    if plan is not None:
        qds = np.array([ob.qd for ob in plan.observations], float)
        return qds[plan_index(plan, t, scenario.dt)]
    qd0 = np.asarray(scenario.target.qd0, float)
    wd = np.asarray(scenario.target.wd, float)
    if not np.any(wd):
        return np.broadcast_to(qd0, (t.size, 4)).copy()
    dq = quat_from_rotvec(t[:, None] * wd[None, :])
    return M.quat_mul(dq, np.broadcast_to(qd0, dq.shape))


def plan_index(plan, t: np.ndarray, dt: float) -> np.ndarray:
    """The observation commanded at each time t (ObservationPlan.index_at, vectorised): its command acts from
    the first tick with t_k >= T_i."""
    first = np.array([first_tick(T, dt) for T in plan.command_times_s])
    k = np.rint(np.asarray(t, float) / dt).astype(np.int64)
    return np.maximum(np.searchsorted(first, k, side="right") - 1, 0)


def dcm(q: np.ndarray) -> np.ndarray:
    """A(q) row-wise (n, 3, 3): (q4^2 - |v|^2) I + 2 v v^T - 2 q4 v^x (SPEC 1)."""
    v, s = q[:, :3], q[:, 3]
    n = q.shape[0]
    a = np.empty((n, 3, 3))
    ss = s * s - np.sum(v * v, axis=1)
    for i in range(3):
        for j in range(3):
            a[:, i, j] = 2.0 * v[:, i] * v[:, j] + (ss if i == j else 0.0)
    x, y, z = v[:, 0], v[:, 1], v[:, 2]
    a[:, 0, 1] += 2 * s * z
    a[:, 0, 2] -= 2 * s * y
    a[:, 1, 0] -= 2 * s * z
    a[:, 1, 2] += 2 * s * x
    a[:, 2, 0] += 2 * s * y
    a[:, 2, 1] -= 2 * s * x
    return a


def euler321(q: np.ndarray) -> np.ndarray:
    """[yaw psi, pitch theta, roll phi] of A(q) = R1(phi) R2(theta) R3(psi), (n, 3) rad."""
    a = dcm(q)
    yaw = np.arctan2(a[:, 0, 1], a[:, 0, 0])
    pitch = -np.arcsin(np.clip(a[:, 0, 2], -1.0, 1.0))
    roll = np.arctan2(a[:, 1, 2], a[:, 2, 2])
    return np.stack([yaw, pitch, roll], axis=1)


# --------------------------------------------------------------------------- series
def attitude_series(scenario, log) -> dict:
    tr = log.truth
    t = tr["t_s"]
    q = tr["q"]
    qd = target_quat(scenario, t)
    err = M.pointing_errors_arcsec(q, qd)
    qe = M.error_quaternion(q, qd)                      # qe4 >= 0
    wd_b = np.einsum("nij,j->ni", dcm(qe), np.asarray(scenario.target.wd, float))
    we = tr["w"] - wd_b
    q4 = qe[:, 3]
    with np.errstate(divide="ignore", invalid="ignore"):
        rho = qe[:, :3] / q4[:, None]
    sigma = qe[:, :3] / (1.0 + q4[:, None])
    return {"t": t, "true_angle": err["true_angle"], "per_axis": err["per_axis"], "qe_arcsec": err["qe_arcsec"],
            "we": we, "w": tr["w"], "rho": rho, "sigma": sigma, "euler_err": euler321(qe)}


def settle_mask(scenario, s: dict) -> tuple[np.ndarray, dict]:
    """Samples inside every criterion of [settle], and the criteria used."""
    st = scenario.settle
    inside = np.ones(s["t"].shape, bool)
    used = {}

    def add(name, value, ok):
        nonlocal inside
        if value is not None:
            inside &= ok
            used[name] = value

    if scenario.kind == "attitude":
        add("rho_norm_max", st.rho_norm_max,
            None if st.rho_norm_max is None else np.nan_to_num(np.linalg.norm(s["rho"], axis=1), nan=np.inf)
            < st.rho_norm_max)
        add("w_norm_max_rad_s", st.w_norm_max_rad_s,
            None if st.w_norm_max_rad_s is None else np.linalg.norm(s["we"], axis=1) < st.w_norm_max_rad_s)
        add("pointing_arcsec_max", st.pointing_arcsec_max,
            None if st.pointing_arcsec_max is None else s["true_angle"] < st.pointing_arcsec_max)
        add("angle_abs_max_rad", st.angle_abs_max_rad,
            None if st.angle_abs_max_rad is None else np.all(np.abs(s["euler_err"]) < st.angle_abs_max_rad, axis=1))
        add("rate_abs_max_rad_s", st.rate_abs_max_rad_s,
            None if st.rate_abs_max_rad_s is None else np.all(np.abs(s["we"]) < st.rate_abs_max_rad_s, axis=1))
        add("sigma_norm_max", st.sigma_norm_max,
            None if st.sigma_norm_max is None else np.linalg.norm(s["sigma"], axis=1) < st.sigma_norm_max)
    else:
        add("pos_abs_max_m", st.pos_abs_max_m,
            None if st.pos_abs_max_m is None else np.all(np.abs(s["pos"]) < st.pos_abs_max_m, axis=1))
        add("vel_abs_max_m_s", st.vel_abs_max_m_s,
            None if st.vel_abs_max_m_s is None else np.all(np.abs(s["vel"]) < st.vel_abs_max_m_s, axis=1))
    return inside, used


def meets_limit(final_max: float | None, limit: float) -> bool:
    """A pointing requirement or goal is met when the final error is at most the limit (equality meets it);
    an undefined error (None: not finite) never meets it."""
    return bool(final_max is not None and final_max <= limit)


def _f(x):
    """JSON-safe float (None for NaN / inf)."""
    x = float(x)
    return x if math.isfinite(x) else None


def _fo(x):
    """_f, with None kept (a value that may be absent)."""
    return None if x is None else _f(x)


def _fl(a):
    return [_f(x) for x in np.asarray(a, float).ravel()]


# --------------------------------------------------------------------------- metrics
def hinf_measured_gain(log, sc, t_from: float = 0.0) -> dict:
    """||z||_2 / ||d||_2 from t_from to the end of the run, from the logged truth.

    z = 1e-3 M q'' (SPEC 2.6), q = [phi theta psi] the 3-2-1 angles of the error
    quaternion about the (rotating) LVLH target, q'' by central second differences
    of the logged samples (dt = control period); d = the logged disturbance torque
    (constant torque plus gravity gradient)."""
    s = attitude_series(sc, log)
    ang = s["euler_err"][:, ::-1]            # [yaw, pitch, roll] -> [phi, theta, psi]
    dt = sc.dt
    qdd = (ang[2:] - 2.0 * ang[1:-1] + ang[:-2]) / dt ** 2
    m = np.diag(np.asarray(sc.attitude.inertia, float))
    z = 1e-3 * qdd * m[None, :]
    d = log.truth["torque_dist"][1:-1]
    keep = log.truth["t_s"][1:-1] >= t_from
    z, d = z[keep], d[keep]
    nz, nd = float(np.sqrt(np.sum(z ** 2) * dt)), float(np.sqrt(np.sum(d ** 2) * dt))
    return {"z_l2": nz, "d_l2": nd, "gain": nz / nd, "z_peak": float(np.max(np.linalg.norm(z, axis=1)))}


def compute(log, scenario, meta: dict, *, wall_s: float | None = None, plant: dict | None = None,
            fsw: dict | None = None) -> tuple[dict, dict]:
    """(metrics dict for the JSON, series dict for the plots): one section per concern, in the
    order of the JSON (docs/sil.md lists every key)."""
    sc = scenario
    t = log.truth["t_s"]
    if t.size == 0:
        raise ValueError(f"{log.path}: no truth_t messages in the log")
    out: dict = {"scenario": sc.id, "law": meta["law"], "kind": sc.kind,
                 "duration_s": _f(t[-1] - t[0]), "control_rate_hz": _f(sc.control_rate_hz)}
    series: dict = {"t": t, "kind": sc.kind}
    _accuracy(out, series, log, sc)
    _guidance(out, sc, fsw)
    u = _commands(out, series, log, sc)
    cfg = meta.get("fsw_config", {})
    _limits(out, series, u, cfg, sc)
    _timing(out, series, log.cmd, meta, cfg, fsw)
    _counters(out, log, sc.dt)
    _hinf(out, log, sc, cfg)
    tr = log.truth
    qw = [np.asarray(tr[k], float).reshape(len(tr["t_s"]), -1) for k in ("q", "w", "pos", "vel") if k in tr]
    out["truth_not_finite"] = (int(np.count_nonzero(~np.all(np.isfinite(np.hstack(qw)), axis=1)))
                               if qw and len(tr["t_s"]) else 0)
    out["wheels"], series["wheels"] = wheels.metrics(log, sc)   # None / {} without a [wheels] array
    plan = getattr(sc, "plan", None)
    out["holds"] = (holds.metrics(sc, series, series["settle_inside"]) if sc.kind == "attitude" else None)
    out["passes"] = (passes.metrics(sc, series, series["settle_inside"]) if sc.kind == "attitude" else None)
    out["momentum"] = momentum.metrics(log, sc, series["wheels"], plant,
                                       plan.hold_windows_s() if plan is not None else None)
    out["events"] = events.events(log)                 # fault management's event log (docs/spec.md 5.15)
    out["estimation"], series["estimation"] = _estimation(log, sc, out["events"])   # None / None without a filter
    out["events_alarms"] = events.alarms(out["events"])  # of them, severity warning or above
    out["events_false_alarms"] = events.false_alarms(   # of those, raised before any injected fault
        out["events"], [f.start_s for f in getattr(sc, "faults", ())])
    _run_info(out, log, meta, sc.dt, wall_s=wall_s, plant=plant, fsw=fsw)
    _faults(out, series, sc)
    return out, series


def _faults(out: dict, series: dict, sc) -> None:
    """The `faults` section (aocs_analysis.faults): each injected fault joined with the event log (`events`,
    empty without one) and the true pointing error; absent from a run without injected faults."""
    injected = getattr(sc, "faults", ())
    if not injected:
        return
    pointing = series.get("true_angle") if sc.kind == "attitude" else None
    t = series["t"] if pointing is not None else []
    out["faults"] = faults.entries(injected, out.get("events") or [], t, pointing if pointing is not None else [],
                                   faults.requirement_of(sc) if pointing is not None else None, sc.metrics.window_s)


def _estimation(log, sc, evs=()) -> tuple[dict | None, dict | None]:
    """The `estimation` section (docs/spec.md 5.7) of a run whose flight software flew a filter
    ([estimator] type other than passthrough): the estimate of actuator_cmd_t against the truth of the same
    tick (truth_t: the state at t_k the tick's sensors measured), the reference qd(t_k), the filter's own
    covariance, the sensor figures of the scenario's [sensors.star_tracker] and [sensors.gyro].
    Once the filter flies without its gyro (the event estimator_gyroless, docs/spec.md 5.6.12) its state and
    covariance hold the rate where the bias was: the filter's statistics are taken over the run before
    that (the metric window's attitude errors over all of it), and `gyroless_from_s` says when it began
    (None when it never did)."""
    est = getattr(sc, "estimator", None)
    if est is None or est.type == "passthrough" or sc.kind != "attitude":
        return None, None
    tr, cmd = log.truth, log.cmd
    it, ic, held = _estimate_rows(tr["tick"], cmd["tick"])
    if it.size == 0:
        return None, None
    t = tr["t_s"][it]
    names = sc.sensors.sensors
    sensors = (E.SensorSet.from_configs(names["star_tracker"], names["gyro"])
               if "star_tracker" in names and "gyro" in names else None)
    outages = getattr(names.get("star_tracker"), "outages", ()) or ()
    qd, valid = target_quat(sc, t), (cmd["est_status"][ic] == 0) & ~held
    gyroless_from = next((e["t_s"] for e in evs if e.get("name") == "estimator_gyroless"), None)
    with_gyro = valid if gyroless_from is None else valid & (t < gyroless_from)
    section, series = E.analyse(t, tr["q"][it], cmd["q_est"][ic], cmd["bias_est"][ic], tr["gyro_bias"][it],
                                cmd["est_p"][ic], qd=qd, valid=with_gyro, sensors=sensors,
                                control_rate_hz=sc.control_rate_hz, outages=outages,
                                start=_filter_start(sc, tr["q"][it][0], tr["gyro_bias"][it][0]))
    # steady state: the last half of the run; the same three errors over the run's metric window (the last
    # 100 s of an IRASSI run), as `aocs compare` and docs/results.md report them beside the pointing figures
    section["metric_window"] = E.window_errors(t, tr["q"][it], cmd["q_est"][ic], qd, valid,
                                               window_s=sc.metrics.window_s)
    section["gyroless_from_s"] = gyroless_from
    return section, series


def _estimate_rows(truth_ticks, cmd_ticks) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(truth rows, reply rows, held) on the uniform grid of the truth ticks from the first answered tick to
    the last: a tick without a reply (its sensor frame dropped: --event drop, an injected link_drop_burst) takes
    the previous reply's row, flagged held (not a valid estimate of that tick), so the series stays one sample
    per control step."""
    reply = {int(k): j for j, k in enumerate(cmd_ticks)}
    rows = [(i, reply.get(int(k))) for i, k in enumerate(truth_ticks)]
    answered = [n for n, (_, j) in enumerate(rows) if j is not None]
    if not answered:
        z = np.zeros(0, np.int64)
        return z, z, np.zeros(0, bool)
    it, ic, held = [], [], []
    last = None
    for i, j in rows[answered[0]:answered[-1] + 1]:
        it.append(i)
        held.append(j is None)
        last = j if j is not None else last
        ic.append(last)
    return np.asarray(it, np.int64), np.asarray(ic, np.int64), np.asarray(held, bool)


def _filter_start(sc, q_true0, bias_true0) -> dict | None:
    """The configured start of the filter (init_mode "configured", docs/spec.md 5.6.10): its P0 and its
    initial errors, truth minus estimate (the knowledge error of the configured q0_BN against the first
    logged truth, the true bias less the prior bias0); None for a start from the star tracker."""
    est = sc.estimator
    if getattr(est, "init_mode", "first_star_tracker") != "configured":
        return None
    e0 = E.knowledge_error_rad(np.asarray(q_true0, float)[None, :], np.asarray(est.init_q_BN, float)[None, :])[0]
    return {"p0_att_rad": est.p0_att_sigma_rad, "p0_bias_radps": est.p0_bias_sigma_radps,
            "e0_att_B_rad": e0, "e0_bias_B_radps": np.asarray(bias_true0, float) - np.asarray(est.bias0_radps, float)}


def _guidance(out: dict, sc, fsw: dict | None) -> None:
    """slew_bound_s: the eigenaxis bang-bang bound of this slew and envelope (slew_bound.py, SPEC 5.1),
    computed here from the scenario; guidance: the mode, and in slew mode the profile and its end time
    as the flight software planned it (fsw_node's exit summary; None where the flight computer does not
    report it, e.g. PIL). The settle time and the pointing error stay measured against the final target."""
    out["slew_bound_s"] = _fo(scenario_slew_bound_s(sc))
    g = getattr(sc, "guidance", None)
    if sc.kind != "attitude" or g is None:
        out["guidance"] = None
        return
    rep = ((fsw or {}).get("guidance") or {})
    # the scenario's [guidance] keys as it gives them (the registry's guidance.* fields); the slew's only in slew mode
    settings = {k: (v if k == "mode" or g.mode == "slew" else None) for k, v in dataclasses.asdict(g).items()}
    out["guidance"] = {**settings, "slew_start_s": _fo(rep.get("slew_start_s")),
                       "profile_end_s": _fo(rep.get("profile_end_s"))}


def _accuracy(out: dict, series: dict, log, sc) -> None:
    """Settle time and the final pointing (attitude) or position (orbit) error over the metric window."""
    tr = log.truth
    t = tr["t_s"]
    window = sc.metrics.window_s
    wmask = M.window_mask(t, window)
    if sc.kind == "attitude":
        s = attitude_series(sc, log)
        series.update(s)
        inside, used = settle_mask(sc, s)
        series["settle_inside"] = inside
        out["settle_time_s"] = M.settle_time(t, inside)
        out["pointing_error_arcsec"] = {
            "initial": _f(s["true_angle"][0]),
            "final_max": _f(np.max(s["true_angle"][wmask])),
            "per_axis_final_max": _fl(np.max(np.abs(s["per_axis"][wmask]), axis=0)),
            "qe_arcsec_final_max": _fl(np.max(s["qe_arcsec"][wmask], axis=0)),
            "final_rms": _f(np.sqrt(np.mean(s["true_angle"][wmask] ** 2))),
            "window_s": _f(window),
            "requirement_arcsec": sc.metrics.requirement_arcsec,
            "goal_arcsec": sc.metrics.goal_arcsec,
        }
        pe = out["pointing_error_arcsec"]
        if sc.metrics.requirement_arcsec is not None:
            pe["meets_requirement"] = meets_limit(pe["final_max"], sc.metrics.requirement_arcsec)
        if sc.metrics.goal_arcsec is not None:
            pe["meets_goal"] = meets_limit(pe["final_max"], sc.metrics.goal_arcsec)
        out["position_error_m"] = None
    else:
        s = {"pos": tr["pos"], "vel": tr["vel"]}
        series.update(s)
        inside, used = settle_mask(sc, {"t": t, **s})
        out["settle_time_s"] = M.settle_time(t, inside)
        out["pointing_error_arcsec"] = None
        out["position_error_m"] = {
            "initial": _f(np.max(np.abs(s["pos"][0]))),
            "final_max": _f(np.max(np.abs(s["pos"][wmask]))),
            "per_axis_final_max": _fl(np.max(np.abs(s["pos"][wmask]), axis=0)),
            "velocity_final_max_m_s": _f(np.max(np.abs(s["vel"][wmask]))),
            "window_s": _f(window),
        }
    out["settle_criterion"] = {"criteria": used, "rule": "inside every criterion from settle_time_s to the end",
                               "window_s": _f(window)}


def _commands(out: dict, series: dict, log, sc) -> np.ndarray:
    """What the flight software commanded (after its saturation) and what the plant applied; returns u_sat."""
    tr, cmd, dt = log.truth, log.cmd, sc.dt
    u = cmd["u_sat"] if cmd["tick"].size else np.zeros((0, 3))
    tc = cmd["tick"] * dt
    series.update(t_cmd=tc, u_sat=u, u_unsat=cmd["u_unsat"], mode=cmd["mode"], step_ns=cmd["step_ns"],
                  applied=tr["force_applied"] if sc.kind == "orbit" else tr["torque_applied"])
    if u.shape[0]:
        max_abs = np.max(np.abs(u), axis=0)
        max_norm = float(np.max(np.linalg.norm(u, axis=1)))
        # each command is held for one period (ZOH): append the end of its period
        eff = M.effort(np.append(tc, tc[-1] + dt), np.vstack([u, np.zeros((1, 3))]))
    else:
        max_abs, max_norm, eff = np.zeros(3), 0.0, 0.0
    if sc.kind == "attitude":
        out["max_abs_torque_nm"] = _fl(max_abs)
        out["max_torque_norm_nm"] = _f(max_norm)
        out["max_abs_force_n"] = None
        out["max_force_norm_n"] = None
    else:
        out["max_abs_torque_nm"] = None
        out["max_torque_norm_nm"] = None
        out["max_abs_force_n"] = _fl(max_abs)
        out["max_force_norm_n"] = _f(max_norm)
    out["effort"] = _f(eff)
    applied = series["applied"]
    out["max_abs_applied"] = _fl(np.max(np.abs(applied), axis=0)) if applied.shape[0] else [0.0] * 3
    return u


def _limits(out: dict, series: dict, u: np.ndarray, cfg: dict, sc) -> None:
    """The flight software's saturation limits, the plant's actuator, and every command beyond them."""
    axis_cfg = cfg.get("u_max_axis")
    axis_lim = float(axis_cfg.split()[0]) if axis_cfg else None
    norm_lim = float(cfg["u_max_norm"]) if cfg.get("u_max_norm") else None
    unlimited = axis_lim is not None and axis_lim >= UNLIMITED
    tol = 1e-12
    viol = 0
    if u.shape[0]:
        if axis_lim is not None:
            viol += int(np.count_nonzero(np.any(np.abs(u) > axis_lim * (1 + tol), axis=1)))
        if norm_lim is not None:
            viol += int(np.count_nonzero(np.linalg.norm(u, axis=1) > norm_lim * (1 + tol)))
    nonfinite = int(np.count_nonzero(~np.all(np.isfinite(u), axis=1))) if u.shape[0] else 0
    out["limits"] = {"axis": None if unlimited else axis_lim, "norm": norm_lim, "unlimited": unlimited,
                     "plant_axis": sc.actuator.axis_limit, "plant_norm": sc.actuator.norm_limit,
                     "plant_slew_rate_limit_per_s": sc.actuator.slew_rate_limit_per_s, "plant_lag_tau_s": sc.actuator.lag_tau_s,
                     "commands_over_limit": viol, "commands_not_finite": nonfinite}
    series["axis_limit"] = None if unlimited else axis_lim
    series["norm_limit"] = norm_lim


def _law_or_none(law_id: int) -> str:
    """The name of a wire law id; "none" (the standby budget) for an id the registry does not know."""
    law = registry.load().law_by_id(law_id)
    return law.name if law is not None else "none"


def _timing(out: dict, series: dict, cmd, meta: dict, cfg: dict, fsw: dict | None) -> None:
    """Step times against the budget of each step's law and mode (and PIL instruction counts)."""
    law_nominal = meta["law"]
    override = int(float(cfg.get("budget_ns", "0")))
    # guidance mode slew: the executive adds its slew allowance to an attitude law's NOMINAL budget
    # (aocs/exec/timing.h AOCS_EXEC_SLEW_BUDGET_NS; the orbit law takes no guidance)
    slew_ns = (int(paths.header_number("firmware/include/aocs/exec/timing.h", "AOCS_EXEC_SLEW_BUDGET_NS"))
               if cfg.get("guidance.mode") == "slew" else 0)

    # the estimator runs in every mode: its budget is added to every step's (executive.c step_budget)
    det_ns = registry.estimator_budget_ns(str(cfg.get("estimator", "passthrough")))

    def nominal(law: str) -> int:
        b = registry.law_budget_ns(law) + det_ns
        attitude = law in registry.load().laws_of_input("attitude")
        return b + slew_ns if attitude else b

    if cmd["tick"].size:
        # one registry look-up per distinct (law, mode) pair, not per step (it reads the build's registry)
        pairs, inverse = _distinct_pairs(cmd["law_id"], cmd["mode"])
        nominal_mode = mode_value("nominal")
        per_pair = np.array([override or (nominal(_law_or_none(lid))
                                          if m == nominal_mode else registry.law_budget_ns("none") + det_ns)
                             for lid, m in pairs], dtype=float)
        budgets = per_pair[inverse]
    else:
        budgets = np.zeros(0)
    budget_nominal = override or nominal(law_nominal if law_nominal in registry.law_ids() else "none")
    ts = M.timing_summary(cmd["step_ns"], budget_nominal, cmd["overrun"].astype(bool))
    out["timing"] = ts.as_dict()
    out["timing"]["steps"] = int(cmd["tick"].size)
    out["timing"]["over_step_budget"] = int(np.count_nonzero(cmd["step_ns"] > budgets)) if budgets.size else 0
    series["budget_ns"] = budgets
    target = meta.get("target", "host")
    if str(target).startswith("pil-"):
        pil_timing(out["timing"], series, cmd, target, fsw)


def _distinct_pairs(a, b) -> tuple[list, np.ndarray]:
    """The distinct (a[i], b[i]) pairs of two integer columns, in order of first appearance, and each row's index
    into them. By runs of equal rows (a law and a mode hold for many steps): np.unique(axis=0) sorted the rows as
    opaque records, a tenth of a campaign worker's time."""
    a = np.asarray(a, dtype=np.int64)
    b = np.asarray(b, dtype=np.int64)
    if a.size == 0:
        return [], np.zeros(0, dtype=np.int64)
    starts = np.flatnonzero(np.concatenate(([True], (a[1:] != a[:-1]) | (b[1:] != b[:-1]))))
    index: dict = {}
    of_run = np.array([index.setdefault(p, len(index)) for p in zip(a[starts].tolist(), b[starts].tolist())],
                      dtype=np.int64)
    return list(index), np.repeat(of_run, np.diff(np.append(starts, a.size)))


def _counters(out: dict, log, dt: float) -> None:
    """The flight computer's cumulative counters (last command, last status), modes, statuses, commands."""
    cmd = log.cmd
    last = {k: int(cmd[k][-1]) if cmd["tick"].size else 0 for k in
            ("n_invalid", "n_stale", "n_missing", "n_law_error", "n_overrun", "n_lost", "n_duplicate",
             "n_foreign", "n_malformed", "n_cmd_accepted", "n_cmd_rejected")}
    stt = log.status
    if stt["steps"].size:
        # the node's last word (exiting status) may count frames after the last command
        for key in ("n_foreign", "n_malformed", "n_cmd_accepted", "n_cmd_rejected", "n_overrun"):
            last[key] = max(last[key], int(np.max(stt[key])))
    modes = cmd["mode"]
    transitions = int(np.count_nonzero(np.diff(modes))) if modes.size > 1 else 0
    in_safe = modes == mode_value("safe")
    safe_entries = int(np.count_nonzero(in_safe[1:] & ~in_safe[:-1]) + (1 if in_safe.size and in_safe[0] else 0))
    status_counts: dict[str, int] = {}
    for code, n in zip(*np.unique(cmd["status"], return_counts=True)):
        if int(code) != 0:
            status_counts[registry.status_name(int(code))] = int(n)
    sent = np.unique(log.sensors["tick"][log.sensors["protocol_version"] == paths_version()])
    answered = np.isin(sent, cmd["tick"])
    ticks_sent, ticks_answered = set(sent.tolist()), set(cmd["tick"].tolist())
    out["counters"] = {
        "invalid": last["n_invalid"], "stale": last["n_stale"], "missing": last["n_missing"],
        "law_error": last["n_law_error"], "lost": last["n_lost"], "duplicate": last["n_duplicate"],
        "foreign": last["n_foreign"], "malformed": last["n_malformed"], "overruns": last["n_overrun"],
        "cmd_accepted": last["n_cmd_accepted"], "cmd_rejected": last["n_cmd_rejected"],
        "mode_changes": transitions, "safe_entries": safe_entries,
        "time_in_safe_mode_s": _f(np.count_nonzero(in_safe) * dt),
        "time_in_saturation_s": _f(np.count_nonzero(cmd["saturated"]) * dt),
        "steps_saturated": int(np.count_nonzero(cmd["saturated"])),
        "status": status_counts,
        "sensor_ticks_unanswered": len(ticks_sent - ticks_answered),
        "longest_unanswered_run": _longest_false_run(answered),
    }
    out["commands"] = [{"request": int(r), "law_id": int(lid), "mode": int(m), "set_target": bool(st),
                        "mode_name": registry.mode_name(int(m)) if int(m) >= 0 else None}
                       for r, lid, m, st in zip(log.command["request"], log.command["law_id"],
                                                log.command["mode"], log.command["set_target"])]
    if stt["steps"].size:
        acks = {int(r): int(s) for r, s in zip(stt["last_request"], stt["last_request_status"]) if r >= 0}
        for c in out["commands"]:
            if c["request"] in acks:
                c["status"] = registry.status_name(acks[c["request"]])
    out["final_mode"] = registry.mode_name(int(modes[-1])) if modes.size else None


def _hinf(out: dict, log, sc, cfg: dict) -> None:
    """H-infinity runs: the gamma of the flown K and the measured ||z||_2 / ||d||_2 over the metric window
    (SPEC 2.6), after the response to the initial errors, which is not driven by d, has died out. A
    constant disturbance is rejected by the loop, so the ratio sits far below gamma; `aocs compare
    geo_hinf --sweep` measures the gain across frequencies."""
    table = cfg.get("hinf.table")
    if out["law"] != "hinf" or not table:
        return
    t = log.truth["t_s"]
    t_from = float(t[-1] - sc.metrics.window_s) if t.size else 0.0
    out["hinf"] = {"table": table, "gamma": designed_gamma(table), "window_s": sc.metrics.window_s,
                   "measured": hinf_measured_gain(log, sc, t_from)}


def _longest_false_run(flags: np.ndarray) -> int:
    """Length of the longest run of consecutive False values."""
    best = run = 0
    for f in flags.tolist():
        run = 0 if f else run + 1
        best = max(best, run)
    return best


def _run_info(out: dict, log, meta: dict, dt: float, *, wall_s, plant, fsw) -> None:
    """The log, the run mode and the processes' own figures (lockstep speed, jitter)."""
    stt = log.status
    out["log"] = {"path": str(log.path), "messages": dict(sorted(log.counts.items())),
                  "truth_samples": int(log.truth["t_s"].size), "commands": int(log.cmd["tick"].size)}
    run_mode = meta.get("mode", "lockstep")
    out["run_mode"] = run_mode
    if run_mode == "realtime":
        jit = int(np.max(stt["jitter_ns_max"])) if stt["steps"].size else None
        out["realtime"] = {"jitter_ns_max": jit,
                           "plant_wake_jitter_ns_max": (plant or {}).get("wake_jitter_ns_max")}
    out["target"] = meta.get("target", "host")
    out["transport"] = meta.get("transport", "lcm")   # lcm | direct (docs/sil.md, Transports)
    if plant:
        loop = plant.get("loop_s") or 0.0
        out["lockstep" if run_mode == "lockstep" else "loop"] = {
            "loop_s": _f(loop), "startup_s": _f(plant.get("startup_s", 0.0)),
            "realtime_factor": _f((plant.get("steps", 0) * dt) / loop) if loop > 0 else None,
            "roundtrip_ns": plant.get("roundtrip_ns"),
        }
    # the plant's own estimate (aocs_plant.integration_error), None when the plant did not report
    out["integration_error"] = (plant or {}).get("integration_error")
    # the plant's udpm reader: fragments, garbage and the partial messages it dropped (udpm.Udpm.counters)
    out["udpm"] = (plant or {}).get("udpm")
    if fsw:
        out["fsw_node"] = fsw
    out["wall_s"] = _f(wall_s) if wall_s is not None else None


def pil_timing(timing: dict, series: dict, cmd, target: str, fsw: dict | None) -> None:
    """Timing of a processor-in-the-loop run (docs/pil.md), in place.

    The bridge's step_ns is an instruction count over the target's nominal
    clock, and its `overrun` flag means "above the instruction budget of the
    law" (firmware budget.h), so the host nanosecond budgets do not apply:
    `overruns` and `over_step_budget` both count the bridge's own flags, and
    `budget_ns` is the instruction budget at the nominal clock. The
    instruction figures come from the bridge's final JSON (`instructions`):
    instructions_median / _p99 (nearest rank over the bridge's statistics
    window, as fsw_node's step_ns), instructions_max (whole run),
    instructions_budget, instruction_overruns (the image's count), plus
    target and clock_hz. None when the bridge wrote no summary."""
    ins = (fsw or {}).get("instructions") or {}
    clock = (fsw or {}).get("clock_hz")
    flagged = int(np.count_nonzero(cmd["overrun"])) if cmd["tick"].size else 0
    budget = ins.get("budget")
    timing["target"] = target
    timing["precision"] = (fsw or {}).get("precision")
    timing["clock_hz"] = _f(clock) if clock is not None else None
    timing["budget_ns"] = _f(budget * 1e9 / clock) if (budget and clock) else timing["budget_ns"]
    timing["overruns"] = flagged
    timing["over_step_budget"] = flagged
    timing["instructions_median"] = ins.get("median")
    timing["instructions_p99"] = ins.get("p99")
    timing["instructions_max"] = ins.get("max")
    timing["instructions_budget"] = budget
    timing["instruction_overruns"] = ins.get("overruns")
    timing["instructions_inexact"] = ins.get("inexact")
    law_ins = (fsw or {}).get("law_instructions") or {}
    timing["law_instructions_median"] = law_ins.get("median")
    timing["law_instructions_max"] = law_ins.get("max")
    if timing["budget_ns"] is not None and cmd["tick"].size:
        series["budget_ns"] = np.full(cmd["tick"].size, float(timing["budget_ns"]))


def paths_version() -> int:
    """PROTOCOL_VERSION of the wire contract (from the generated bindings)."""
    return int(paths.import_bindings().sensors_t.PROTOCOL_VERSION)


# --------------------------------------------------------------------------- table
def _fmt(x, spec=".3g"):
    if x is None:
        return "-"
    if isinstance(x, (list, tuple)):
        return "[" + " ".join(_fmt(v, spec) for v in x) + "]"
    return format(x, spec)


def _run_text(m: dict) -> str:
    """'lockstep on host', or for a PIL target its precision and clock:
    'lockstep on pil-m4f (float, Cortex-M4F image under QEMU, instructions at 168 MHz)'."""
    tm = m.get("timing") or {}
    target = m["target"]
    if str(target).startswith("pil-"):
        bits = [b for b in (tm.get("precision"), "image under QEMU",
                            f"step time from instructions at {tm['clock_hz'] / 1e6:g} MHz" if tm.get("clock_hz") else None)
                if b]
        return f"{m['run_mode']} on {target} ({', '.join(bits)})"
    return f"{m['run_mode']} on {target} (double)"


def limit_text(m: dict) -> str:
    """The actuator limits in words: what the flight software saturates to, what the plant's actuator
    adds (rate limit, lag), and how many commands went beyond the limit."""
    lim = m["limits"]
    unit = "N m" if m.get("kind", "attitude") == "attitude" else "N"
    if lim["unlimited"] and lim.get("norm") is None:
        text = "none: the reference actuator (no saturation)"
    else:
        parts = []
        if lim["axis"] is not None:
            parts.append(f"|u_i| <= {lim['axis']:g} {unit} per axis")
        if lim.get("norm") is not None:
            parts.append(f"|u| <= {lim['norm']:g} {unit}")
        n = lim["commands_over_limit"]
        text = " and ".join(parts) + (f"; {n} command{'s' if n != 1 else ''} beyond it" if n
                                      else "; no command beyond it")
    extra = []
    if lim.get("plant_slew_rate_limit_per_s") is not None:
        extra.append(f"slew-rate limit {lim['plant_slew_rate_limit_per_s']:g} {unit}/s")
    if lim.get("plant_lag_tau_s") is not None:
        extra.append(f"first-order lag {lim['plant_lag_tau_s']:g} s")
    if extra:
        text += "; the plant's actuator adds a " + " and a ".join(extra)
    return text


def divergence(m: dict) -> str | None:
    """A run whose error ends above where it started and never settled is named as diverging."""
    if m.get("settle_time_s") is not None:
        return None
    pe = m.get("pointing_error_arcsec")
    if pe:
        start, end, unit = pe.get("initial"), pe.get("final_max"), "arcsec"
    else:
        po = m.get("position_error_m") or {}
        start, end, unit = po.get("initial"), po.get("final_max"), "m"
    if start is None or end is None or not end > start:
        return None
    return (f"the error grew from {start:.4g} {unit} at the start to {end:.4g} {unit} at the end and never "
            "settled: the loop diverges")


def table(m: dict) -> str:
    """The metrics table printed after a run."""
    rows = table_rows(m)
    w = max(len(k) for k, _ in rows)
    return "\n".join(f"  {k:<{w}}  {v}" for k, v in rows)


def table_rows(m: dict) -> list[tuple[str, str]]:
    """The metrics table's (what, value) lines (table(); the HTML run report's metrics table)."""
    rows = [("scenario", m["scenario"]), ("law", m["law"]), ("run", _run_text(m)),
            ("duration", f"{m['duration_s']:g} s at {m['control_rate_hz']:g} Hz"),
            ("settle time", "never" if m["settle_time_s"] is None else f"{m['settle_time_s']:.1f} s")]
    crit = ", ".join(f"{k} < {v:g}" for k, v in m["settle_criterion"]["criteria"].items())
    rows.append(("settle criterion", crit))
    if m.get("slew_bound_s") is not None:
        b = m["slew_bound_s"]
        ratio = "" if m["settle_time_s"] is None or b <= 0.0 else f" (settle / bound {m['settle_time_s'] / b:.3f})"
        rows.append(("slew bound (eigenaxis bang-bang)", f"{b:.1f} s{ratio}"))
    g = m.get("guidance")
    if g is not None:
        rows.append(("guidance", g["mode"] if g["mode"] != "slew" else
                     f"slew, {g['profile']}, margin {g['margin']:g}, profile end "
                     + ("unknown" if g["profile_end_s"] is None else f"{g['profile_end_s']:.1f} s")))
    if m.get("gain"):
        rows.append(("gain", m["gain"]["summary"]))
    if m["pointing_error_arcsec"]:
        pe = m["pointing_error_arcsec"]
        verdict = []
        if "meets_requirement" in pe:
            verdict.append(f"requirement {pe['requirement_arcsec']:g}: {'met' if pe['meets_requirement'] else 'MISSED'}")
        if "meets_goal" in pe:
            verdict.append(f"goal {pe['goal_arcsec']:g}: {'met' if pe['meets_goal'] else 'missed'}")
        rows.append(("initial pointing error", f"{_fmt(pe['initial'], '.5g')} arcsec "
                                               f"({pe['initial'] / 3600.0:.4g} deg)"))
        rows += [(f"pointing, last {pe['window_s']:g} s (true angle)", f"max {_fmt(pe['final_max'], '.4g')} arcsec"
                  + (f" ({'; '.join(verdict)})" if verdict else "")),
                 ("per-axis 2 qe_i max", _fmt(pe["per_axis_final_max"], ".4g") + " arcsec"),
                 ("|qe_i| max (IRASSI figure)", _fmt(pe["qe_arcsec_final_max"], ".4g") + " arcsec")]
        rows += [("max |torque| per axis", _fmt(m["max_abs_torque_nm"], ".4g") + " N m"),
                 ("max torque norm", _fmt(m["max_torque_norm_nm"], ".4g") + " N m"),
                 ("effort (int |u|_1 dt)", _fmt(m["effort"], ".4g") + " N m s")]
    else:
        pe = m["position_error_m"]
        rows += [(f"position error, last {pe['window_s']:g} s", f"max {_fmt(pe['final_max'], '.4g')} m"),
                 ("velocity error, same window", f"max {_fmt(pe['velocity_final_max_m_s'], '.4g')} m/s"),
                 ("max |force| per axis", _fmt(m["max_abs_force_n"], ".4g") + " N"),
                 ("effort (int |F|_1 dt)", _fmt(m["effort"], ".4g") + " N s")]
    rows.append(("limit", limit_text(m)))
    if m.get("wheels"):
        rows += wheels.table_rows(m["wheels"])
    if m.get("momentum"):
        rows += momentum.table_rows(m["momentum"])
    if m.get("holds") is not None:
        rows += holds.table_rows(m["holds"], (m.get("pointing_error_arcsec") or {}).get("requirement_arcsec"))
    if m.get("faults"):
        rows += faults.table_rows(m["faults"])
    if m.get("passes") is not None:
        rows += passes.table_rows(m["passes"], (m.get("pointing_error_arcsec") or {}).get("requirement_arcsec"))
    dv = divergence(m)
    if dv:
        rows.append(("DIVERGING", dv))
    tm = m["timing"]
    rows.append(("step time", f"median {tm['step_ns_median']:.0f} ns, p99 {tm['step_ns_p99']:.0f}, "
                 f"max {tm['step_ns_max']:.0f}, budget {tm['budget_ns']:.0f}, overruns {tm['overruns']}"))
    if tm.get("instructions_median") is not None:
        rows.append(("instructions", f"median {tm['instructions_median']}, p99 {tm['instructions_p99']}, "
                     f"max {tm['instructions_max']}, budget {tm['instructions_budget']}, overruns "
                     f"{tm['instruction_overruns']} ({tm['target']}, step time at {tm['clock_hz'] / 1e6:g} MHz)"))
    c = m["counters"]
    rows.append(("events", f"invalid {c['invalid']} stale {c['stale']} missing {c['missing']} "
                 f"law_error {c['law_error']} lost {c['lost']} dup {c['duplicate']} foreign {c['foreign']} "
                 f"malformed {c['malformed']} cmd ok/rejected {c['cmd_accepted']}/{c['cmd_rejected']}"))
    law_refusals = c["law_error"]
    if law_refusals:
        sing = c["status"].get("AOCS_ERR_CRP_SINGULAR", 0)
        if sing:
            rows.append(("law refused", f"{sing} samples at the Gibbs singularity: crp_linear cannot represent "
                                        "rho = q_vec / q4 within |q4| <= 1e-8 (1e-6 in float; near 180 deg, docs/conventions.md); "
                                        "safe mode damped the rate on those steps"))
        if law_refusals > sing:
            other = ", ".join(f"{k} {n}" for k, n in c["status"].items() if k != "AOCS_ERR_CRP_SINGULAR")
            rows.append(("law refused", f"{law_refusals - sing} samples ({other})"))
    rows.append(("modes", f"changes {c['mode_changes']}, safe {c['time_in_safe_mode_s']:g} s, "
                 f"saturated {c['time_in_saturation_s']:g} s, final {m['final_mode']}"))
    if "realtime" in m:
        rows.append(("real-time jitter", f"node max {_fmt(m['realtime']['jitter_ns_max'])} ns, plant wake max "
                     f"{_fmt(m['realtime']['plant_wake_jitter_ns_max'])} ns"))
    ls = m.get("lockstep")
    if ls and ls.get("realtime_factor"):
        rt = ls.get("roundtrip_ns") or {}
        rows.append(("lockstep speed", f"{ls['realtime_factor']:.0f}x real time, loop {ls['loop_s']:.3f} s, "
                     f"round trip median {rt.get('median', 0) / 1000:.1f} us p99 {rt.get('p99', 0) / 1000:.1f} us, "
                     f"startup {ls['startup_s']:.2f} s"))
    if m.get("wall_s") is not None:
        rows.append(("wall time", f"{m['wall_s']:.2f} s"))
    hi = m.get("hinf")
    if hi:
        rows.append(("H-infinity", f"gamma of K ({hi['table']}) {hi['gamma']:.4g}; measured ||z||_2 / ||d||_2 over the last "
                     f"{hi['window_s']:g} s {hi['measured']['gain']:.3g} (this disturbance; across frequencies: "
                     "aocs compare geo_hinf --sweep)"))
    ie = m.get("integration_error")
    if ie:
        key, unit = (("attitude_arcsec", "arcsec") if "attitude_arcsec_sum" in ie else ("position_m", "m"))
        rows.append(("integration error", f"{_fmt(ie[key + '_sum'], '.2g')} {unit} summed over the run, largest "
                     f"{_fmt(ie[key + '_local_max'], '.2g')} {unit} in one period (tolerance "
                     f"{_fmt(ie['tolerance_' + unit], '.2g')} {unit}"
                     + (": EXCEEDED, raise [integrator] substeps)" if ie["exceeds_tolerance"] else ")")))
    v = m.get("verdict")
    if v is not None:
        failed = "; ".join(f["reason"] for f in v["failures"])
        rows.append(("verdict", ("passed" if v["passed"] else f"FAILED: {failed}")
                     + (f" (allowed: {', '.join(v['allowed'])})" if v["allowed"] else "")))
    return rows


def comparison_table(ms: list[dict], bound: bool = False) -> str:
    """One line per run (for `make sil`); bound: the slew bound (slew_bound_s, SPEC 5.1) and
    settle / bound columns (guided runs)."""
    head = ("law", "limit", "settle s") + (("bound s", "settle/bound") if bound else ()) + (
            "final max as", "|qe_i| max as", "max |u| N m", "effort", "step ns p99", "safe s")
    lines = []
    for m in ms:
        pe = m.get("pointing_error_arcsec") or {}
        lim = m["limits"]
        b = m.get("slew_bound_s")
        ratio = None if (b is None or not b > 0.0 or m["settle_time_s"] is None) else m["settle_time_s"] / b
        lines.append((m["law"] + (f" ({m.get('label')})" if m.get("label") else ""),
                      "none" if lim["unlimited"] else f"{lim['axis']:g}",
                      "never" if m["settle_time_s"] is None else f"{m['settle_time_s']:.1f}")
                     + ((_fmt(b, ".1f"), _fmt(ratio, ".3f")) if bound else ())
                     + (_fmt(pe.get("final_max"), ".3g"),
                      _fmt(max(pe.get("qe_arcsec_final_max") or [0.0]), ".3g"),
                      _fmt(m.get("max_torque_norm_nm"), ".3g"), _fmt(m["effort"], ".3g"),
                      f"{m['timing']['step_ns_p99']:.0f}", f"{m['counters']['time_in_safe_mode_s']:g}"))
    widths = [max(len(h), *(len(r[i]) for r in lines)) for i, h in enumerate(head)]
    fmt = lambda r: "  ".join(f"{c:<{w}}" for c, w in zip(r, widths))  # noqa: E731
    return "\n".join([fmt(head), fmt(tuple("-" * w for w in widths))] + [fmt(r) for r in lines])
