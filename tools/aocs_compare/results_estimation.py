"""docs/results.md, the IRASSI scenarios flown on a realistic sensor suite through the MEKF (issue 20).

Every law of irassi_hold_mekf and of the slew and wheel scenarios with the same suite (irassi_small_mekf,
irassi_large_mekf, irassi_rw_mekf, irassi_rw_failed_mekf): the comparison table, and the knowledge,
control and pointing error over the last 100 s (`aocs compare SCENARIO` prints the same). Then, from the
hold's runs, what the 0.3 arcsec requirement gets with this suite, and where the integral laws' pointing
error comes from (aocs_analysis.noise_paths: the attitude knowledge error through T(s) and the gyro's rate
noise through the derivative gain, checked against the logged pointing).
"""
from __future__ import annotations

import dataclasses
import math

import numpy as np

from aocs_analysis import estimation as E
from aocs_analysis import noise_paths as NP
from aocs_analysis.gain_tables import gain_matrix
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_plant.scenario import load
from aocs_report.document import Paragraph, Section, Table
from aocs_wire import lcmlog

from . import compare as C

#: the realistic-suite scenarios, the hold first (the IRASSI pointing figure)
SCENARIOS = ("irassi_hold_mekf", "irassi_small_mekf", "irassi_large_mekf", "irassi_rw_mekf", "irassi_rw_failed_mekf")
HOLD = SCENARIOS[0]
#: quat_pid with the reference scenarios' gains (half the suite's kp and ki, kd the same): what gains sized for a
#: perfect rate give on this suite (the 1.5 factor is a matter of gains against the sensors' noise)
REFERENCE_PID = ("laws.quat_pid.kp=400.0", "laws.quat_pid.ki=12.0")


def plan_steps(steps) -> int:
    """Simulated steps of the runs `section` makes (steps(sc): one run's steps)."""
    return sum(len(C.variants(load(s), "all")) * steps(load(s)) for s in SCENARIOS) + steps(load(HOLD))


def axis_gains(sc, row) -> list[NP.AxisGains] | None:
    """Per-axis gains (kq, kw, kz) of a PID-family row (quat_pd, quat_nlpd_*, quat_pid, lqr_quat, lqr_quat_i)
    as the scenario and the compiled tables give them; None for other laws (smc)."""
    p = sc.control.laws[row.law].params
    if row.law in ("quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "quat_pid"):
        g = NP.AxisGains(float(p["kp"]), float(p["kd"]), float(p.get("ki", 0.0)))
        return [g] * 3
    if row.law == "lqr_quat" and row.table:
        k = gain_matrix(row.table)
        return [NP.AxisGains(k[i, i], k[i, 3 + i]) for i in range(3)]
    if row.law == "lqr_quat_i" and row.table:
        k = gain_matrix(row.table, cols=9)
        return [NP.AxisGains(k[i, 3 + i], k[i, 6 + i], k[i, i]) for i in range(3)]
    return None


def decomposition(sc, row) -> dict | None:
    """The noise paths of a row's run over the last half (the estimation section's window): angle rms
    (arcsec) of the knowledge error, of each path, of their sum and of the logged pointing; the largest
    per-axis |T| peak."""
    gains = axis_gains(sc, row)
    if gains is None or row.out_dir is None:
        return None
    d = NP.noises_from_log(lcmlog.read(row.out_dir / "run.lcmlog"), sc)
    j = np.diag(np.asarray(sc.attitude.inertia, float))
    ct = sc.disturbances.constant_torque
    dist = np.asarray(ct.torque_nm, float) * ct.scale if ct is not None and ct.enabled else np.zeros(3)
    p = NP.paths(d["t"], d["n_att_rad"], d["n_rate_radps"], j, gains, dist)
    half = d["t"] >= d["t"][-1] - 0.5 * (d["t"][-1] - d["t"][0])

    def rms(a):
        return math.sqrt(float(np.mean(np.sum(a[half] ** 2, axis=1)))) * ARCSEC_PER_RAD
    return {"knowledge": rms(d["n_att_rad"]), "attitude_path": rms(p["attitude"]), "rate_path": rms(p["rate"]),
            "model": rms(p["total"]), "logged": rms(d["pointing_rad"]),
            "model_error": rms(p["total"] - d["pointing_rad"]),
            "rate_rms_radps": float(np.sqrt(np.mean(d["n_rate_radps"][half] ** 2))),
            "t_peak": max(NP.t_peak(j[i], gains[i])[0] for i in range(3))}


def tracker_factor_for(sc, knowledge_rms_arcsec: float, level_arcsec: float) -> float | None:
    """The factor f by which both star-tracker noises would have to shrink (the gyro kept) for the analytic
    knowledge angle rms to come down to level_arcsec (bisection on the Farrenkopf bound); None without sensors."""
    names = sc.sensors.sensors
    if "star_tracker" not in names or "gyro" not in names:
        return None
    base = E.SensorSet.from_configs(names["star_tracker"], names["gyro"])

    def angle(f):
        s = dataclasses.replace(base, noise_cross_arcsec=base.noise_cross_arcsec / f,
                                noise_about_arcsec=base.noise_about_arcsec / f)
        return float(np.linalg.norm(E.steady_state_bounds(s, sc.control_rate_hz)["log_rms_arcsec"]))
    lo, hi = 1.0, 1.0
    while angle(hi) > level_arcsec and hi < 1e4:
        hi *= 2.0
    for _ in range(60):
        mid = math.sqrt(lo * hi)
        lo, hi = (mid, hi) if angle(mid) > level_arcsec else (lo, mid)
    return hi


def section(R) -> Section:
    """The runs and the discussion (R: results_doc.Results)."""
    sec = Section("IRASSI on a realistic sensor suite: star tracker and gyro through the MEKF").add(Paragraph(
        "The scenarios above fly the true attitude and rate. These fly the same problems on the sensor suite of "
        "irassi_hold_mekf (stated in each scenario file): a star tracker of 1 arcsec cross-boresight and 8 arcsec "
        "about its boresight (+z_B), 1-sigma white, at 10 Hz, and a navigation-grade gyro (angle random walk "
        "1.45e-6 rad/s^0.5, rate random walk 1e-10 rad/s^1.5, a 0.1 deg/h bias the filter has to find), fused by "
        "the flight software's MEKF (docs/spec.md 5.6); every law flies the estimate. The reference gains are "
        "the reference scenarios' own. One scenario: `aocs compare irassi_hold_mekf` (the same tables)."))
    runs = {}
    for sid in SCENARIOS:
        sc, rows = R.rows(sid, prefix=False)
        runs[sid] = (sc, rows)
        sub = Section(f"{sid}: every law on the realistic suite").add(
            Paragraph(sc.description), R.table(rows, "attitude", sc),
            C.estimation_table(rows, sc.metrics.requirement_arcsec))
        if sid == HOLD:
            sub.add(Paragraph(C.ESTIMATION_COLUMNS),
                    *R.plots(rows, "attitude", f"{sid}", f"{sid}_", requirement=0.3, goal=0.05, sc=sc))
        sec.add(sub)
    sc, rows = runs[HOLD]
    _, reference = R.rows(HOLD, [("quat_pid", None)], sets=REFERENCE_PID, prefix=False, tag="quat_pid_kp400")
    sec.add(requirement_statement(sc, rows), integral_laws(sc, rows, reference))
    return sec


def _mw(r):
    return ((r.metrics or {}).get("estimation") or {}).get("metric_window")


def requirement_statement(sc, rows) -> Section:
    """What the 0.3 arcsec requirement gets with this suite, from the hold's runs."""
    ok = [r for r in rows if _mw(r)]
    req = sc.metrics.requirement_arcsec
    if not ok:
        return Section("What the IRASSI requirement gets with this suite").add(Paragraph("No run of the hold passed."))
    k = _mw(ok[0])["knowledge_arcsec"]
    bound = C.knowledge_bound_angle_arcsec(ok[0].metrics["estimation"])
    best = min(ok, key=lambda r: _mw(r)["pointing_arcsec"]["rms"])
    bp = _mw(best)["pointing_arcsec"]
    meets = [r.name for r in ok if _mw(r)["pointing_arcsec"]["max"] <= req]
    max_over_rms = k["max"] / k["rms"]
    f = tracker_factor_for(sc, k["rms"], req / max_over_rms)
    return Section("What the IRASSI requirement gets with this suite").add(Paragraph(
        f"Over the last {_mw(ok[0])['window_s']:g} s of the {sc.duration_s:g} s hold the filter knows the attitude "
        f"to {k['rms']:.3g} arcsec rms and {k['max']:.3g} arcsec max (true angle; the analytic steady state of these "
        f"sensors is {bound:.3g} arcsec rms, dominated by the 8 arcsec about-boresight axis), the same for every law. "
        "A loop cannot point better than it knows where it points: at low frequency the true attitude follows the "
        "estimate (the attitude-noise path T(s) below is 1 at s = 0), so the knowledge error is a floor under the "
        f"pointing error. The best law here, {best.name}, points to {bp['rms']:.3g} arcsec rms and {bp['max']:.3g} "
        f"arcsec max; **{'no law' if not meets else ', '.join(meets)} meets the {req:g} arcsec requirement** "
        "(max of the true angle over the last 100 s), and none comes near the 0.05 arcsec goal. The 2.95e-12 arcsec "
        "of the reference tables is the double-precision floor of a loop fed the true attitude, not a pointing "
        f"capability. With the max at {max_over_rms:.2f} times the rms as measured here, a {req:g} arcsec max needs "
        f"a knowledge rms of about {req / max_over_rms:.3g} arcsec: with the same gyro, a star tracker about "
        f"{f:.2g} times better on both axes (the Farrenkopf bound of estimation_bounds solved for the tracker noise; "
        "the bound falls more slowly than the tracker noise once the gyro's random walk between samples matters), "
        "or a second tracker head across the first so that no axis is seen only about a boresight, and that before "
        "the control loop adds its own share (below)."))


def integral_laws(sc, rows, reference) -> Section:
    """The integral laws' pointing rms against 1.5 times the knowledge rms, and where the excess comes from."""
    body = []
    for r in rows:
        mw = _mw(r)
        if not mw:
            continue
        d = decomposition(sc, r)
        ratio = C.pointing_over_knowledge(r)
        body.append([r.name, f"{mw['knowledge_arcsec']['rms']:.3g}", f"{mw['pointing_arcsec']['rms']:.3g}",
                     f"{ratio:.2f}", "-" if d is None else f"{d['knowledge']:.3g}",
                     "-" if d is None else f"{d['attitude_path']:.3g}", "-" if d is None else f"{d['rate_path']:.3g}",
                     "-" if d is None else f"{d['model']:.3g}", "-" if d is None else f"{d['logged']:.3g}",
                     "-" if d is None else f"{d['model_error']:.2g}", "-" if d is None else f"{d['t_peak']:.3f}"])
    integ = {r.name: C.pointing_over_knowledge(r) for r in rows if r.law in C.INTEGRAL_LAWS and _mw(r)}
    over = {n: x for n, x in integ.items() if x is not None and x > C.POINTING_OVER_KNOWLEDGE_MAX}
    s = reference[0] if reference and _mw(reference[0]) else None
    s_ratio = None if s is None else C.pointing_over_knowledge(s)
    verdict = (f"**Integral laws above it with this suite's gains: pointing rms / knowledge rms = "
               + ", ".join(f"{n} {x:.2f}" for n, x in over.items()) + "**." if over else
               "With this suite's gains (quat_pid kp 800 N m, ki 24 N m/s, kd 2000 N m s/rad; lqr_quat_i table "
               "lqr_quat_i_suite, tools/gains.toml) every integral law is within it: "
               + ", ".join(f"{n} {x:.2f}" for n, x in integ.items()) + ".")
    rate = next((d["rate_rms_radps"] for r in rows if (d := decomposition(sc, r)) is not None), None)
    text = [Paragraph(
        f"Issue 20 asks the integral laws (quat_pid, lqr_quat_i) to point within {C.POINTING_OVER_KNOWLEDGE_MAX:g} "
        "times their knowledge rms over the last 100 s. " + verdict)]
    text.append(Paragraph(
        "Where the pointing error comes from (aocs_analysis.noise_paths, docs/spec.md 5.7.2): near the target each "
        "body axis of a PID-family law closes to D(s) theta = -(kq/2 s + kz/2) n_th - kw s n_w, D(s) = J s^3 + kw s^2 "
        "+ kq/2 s + kz/2, with n_th the attitude knowledge error and n_w = w_est - w_true the rate error the law "
        "sees. Driven by each run's own logged n_th and n_w, the two paths add up to the logged pointing error "
        "(table: model against logged, over the last half of the run, angles; model error = rms of their "
        "difference). The attitude path alone stays near the knowledge error (T(s) is 1 at low frequency and peaks "
        "at the |T| shown near the closed-loop poles); the rest is the gyro's rate noise"
        + (f" ({rate:.3g} rad/s rms per axis: the MEKF's rate is the gyro less its bias estimate, white)"
           if rate is not None else "")
        + " through the derivative gain kw, which gains sized for a perfect rate (the reference scenarios') make "
        "large against the stiffness kq: on the two cross-boresight axes, where the knowledge error is smallest, it "
        "is then most of the pointing error. So the factor is a matter of gains against the sensors' noise, not of the "
        "filter: the loop must be stiff (kq) against its damping (kw) so that the rate noise it injects stays "
        "small, without pushing T's peak into the band where the knowledge error has its power."))
    text.append(Table(["law", "knowledge rms, last 100 s (as)", "pointing rms, last 100 s (as)",
                       "pointing / knowledge", "knowledge rms, last half (as)", "attitude path (as)",
                       "rate path (as)", "model total (as)", "logged pointing (as)", "model error (as)",
                       "max abs T"], body))
    if s is not None:
        mw = _mw(s)
        text.append(Paragraph(
            f"Against: quat_pid with the reference scenarios' gains (`aocs run irassi_hold_mekf --law quat_pid --set "
            f"{' --set '.join(REFERENCE_PID)}`, kd the same) points to {mw['pointing_arcsec']['rms']:.3g} arcsec rms "
            f"against {mw['knowledge_arcsec']['rms']:.3g} arcsec knowledge over the last 100 s: {s_ratio:.2f} times, "
            f"{'within' if s_ratio <= C.POINTING_OVER_KNOWLEDGE_MAX else 'above'} {C.POINTING_OVER_KNOWLEDGE_MAX:g}. "
            "The reference scenarios keep the reference gains (their figures are the papers'); the realistic-suite "
            "scenarios carry gains chosen for their sensors."))
    return Section(f"The integral laws against {C.POINTING_OVER_KNOWLEDGE_MAX:g} times the knowledge error").add(*text)
