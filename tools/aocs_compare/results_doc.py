"""`aocs results [--out docs] [--quick]`: regenerate docs/results.md and docs/results/*.png.

Runs every reference scenario of SPEC 4 with its laws and reference gains
(each law in its own SIL run through real processes, lockstep, in a private
network namespace; aocs_compare.compare), plus irassi_large with
realistic reaction-wheel limits (1, 0.5 and 0.2 N m per axis, 3000 s so the
slow ones can finish; --quick: 500 s), the same with the slew guidance
(`--guidance slew`, 1000 s), the IRASSI scenarios on a star tracker and a gyro
through the MEKF (results_estimation), the H-infinity disturbance-to-output
gain measured from a run, and writes the tables, the figures and a short
discussion. Run logs go to --runs (default out/results), never into docs.
"""
from __future__ import annotations

import math
import sys
import time
from pathlib import Path

import numpy as np

from aocs_analysis.run_metrics import hinf_measured_gain
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_margins import results as margins_results
from aocs_plant.scenario import load
from aocs_report import markdown
from aocs_report.document import BulletList, Document, Figure, Paragraph, Section, Table
from aocs_wire import lcmlog

from . import compare as C
from . import results_estimation
from . import results_notes as notes
from . import sweep as S
from .compare import IRASSI_DIST_NM, designed_gamma, gain_matrix, steady_error_arcsec

RTC = ("rtc_ex1a", "rtc_ex1b", "rtc_ex2a", "rtc_ex2b", "rtc_ex3a", "rtc_ex3b")
LANDSAT_Q = ("landsat8_q10", "landsat8_q1", "landsat8_q01")
LANDSAT_DIST = ("landsat8_srp", "landsat8_debris")
#: per-axis limits of the realistic-wheel runs, N m (0.5: the README's `aocs run irassi_large --limit 0.5`)
LIMITS = (1.0, 0.5, 0.2)
LIMIT_DURATION_S = 3000.0
#: the guided runs (SPEC 5.1 slew guidance, `--guidance slew`): 1000 s, the last 100 s the window
GUIDED_DURATION_S = 1000.0
#: geo_hinf with zero initial attitude and rate errors about LVLH: only the disturbance drives z
HINF_ZERO_IC = ("plant.euler321_deg=[0.0, 0.0, 0.0]", "plant.w0=[0.0, -7.292115e-05, 0.0]")


# --------------------------------------------------------------------------- gains provenance


# --------------------------------------------------------------------------- H-infinity measured gain
# --------------------------------------------------------------------------- helpers
def first_time_below_for_good(t, err, level):
    """First time after which err stays <= level to the end (None if never)."""
    above = np.nonzero(err > level)[0]
    if above.size == 0:
        return float(t[0])
    k = above[-1] + 1
    return float(t[k]) if k < t.size else None


def rebound(t, err, band=10.0):
    """Max error after the error first entered the band (arcsec): > band means it left it again (overshoot)."""
    inside = np.nonzero(err < band)[0]
    if inside.size == 0:
        return None
    return float(np.max(err[inside[0]:]))


def rebound_factor(err) -> float:
    """max over t of err(t) / min_{s <= t} err(s): 1 for an error that only decreases; > 1 when the
    attitude runs past the target and the error grows again (overshoot / oscillation)."""
    e = np.maximum(np.asarray(err, float), 1e-12)
    return float(np.max(e / np.minimum.accumulate(e)))


def _rel(p: Path, base: Path) -> str:
    return str(p.relative_to(base))


def _clock(s: float) -> str:
    s = max(0, int(round(s)))
    return f"{s // 60}:{s % 60:02d}" if s < 3600 else f"{s // 3600}:{s // 60 % 60:02d}:{s % 60:02d}"


class Progress:
    """One readable line per run with the simulated time done and an ETA (make results).
    The ETA scales the wall time so far by the simulated steps still to run (the plan)."""

    def __init__(self, total_steps: int, quiet: bool):
        self.total, self.done, self.quiet, self.t0, self.n = max(total_steps, 1), 0, quiet, time.monotonic(), 0

    def start(self, what: str, steps: int) -> None:
        self.n += 1
        if not self.quiet:
            el = time.monotonic() - self.t0
            eta = "estimating" if self.done == 0 else _clock(el / self.done * (self.total - self.done))
            print(f"results: run {self.n}: {what} ({steps} steps); {100 * self.done / self.total:.0f} % of the "
                  f"simulation done, {_clock(el)} elapsed, ETA {eta}", file=sys.stderr, flush=True)
        self.done += steps


def _steps(sc, duration=None) -> int:
    return int(round((duration or sc.duration_s) / sc.dt))


def plan_steps(quick: bool) -> int:
    """Simulated steps of every run build() makes, for the ETA (the same scenarios and durations)."""
    lim_dur = 500.0 if quick else LIMIT_DURATION_S
    n = 0
    for sid in ("irassi_small", "irassi_large", *RTC, *LANDSAT_Q, "geo_hinf", "gao_mrp"):
        sc = load(sid)
        n += len(C.variants(sc, "all")) * _steps(sc)
    n += len(C.variants(load("geo_hinf"), "all")) * _steps(load("geo_hinf"))      # zero initial errors
    n += len(LIMITS) * len(C.variants(load("irassi_large"), "all")) * _steps(load("irassi_large"), lim_dur)
    n += len(LIMITS) * len(C.variants(load("irassi_large"), "all")) * _steps(load("irassi_large"), GUIDED_DURATION_S)
    n += sum(2 * _steps(load(sid)) for sid in LANDSAT_DIST)
    g = load("geo_hinf")
    n += sum(_steps(g, S.sweep_duration(g, S.slowest_pole(g), w)) for w in S.FREQUENCIES)
    n += results_estimation.plan_steps(_steps)
    return n


class Results:
    def __init__(self, out: Path, runs: Path, quiet: bool, progress: Progress | None = None, reuse=False):
        self.reuse = reuse
        self.docs = out
        self.fig = out / "results"
        self.runs = runs
        self.quiet = quiet
        self.progress = progress or Progress(1, True)
        self.failed = 0
        self.fig.mkdir(parents=True, exist_ok=True)

    def rows(self, scenario, rows=None, *, limit=None, duration=None, sets=(), prefix=True, tag="ref",
             guidance=None):
        sc = load(scenario)
        rows = rows if rows is not None else C.variants(sc, "all")
        steps = _steps(sc, duration)
        res = C.run_rows(scenario, rows, self.runs / f"{scenario}-{tag}", limit=limit, duration=duration,
                         sets=sets, quiet=True, tag=f", {tag}", reuse=self.reuse, guidance=guidance,
                         progress=lambda name: self.progress.start(
                             f"{sc.id} {name}" + (f", limit {limit:g} per axis" if limit is not None
                                                  else "" if tag == "ref" else f", {tag}"), steps))
        for r in res:
            if prefix:
                r.name = f"{sc.id} {r.name}"
            self.failed += bool(r.error)
        return sc, res

    @staticmethod
    def table(rows, kind, sc=None, bound=False) -> Table:
        """sc: the scenario whose requirement and goal columns (IRASSI) the table shows; no host timing
        columns (they change at every run, so regenerating the page would churn). bound: the slew bound
        and settle / bound columns (guided runs)."""
        if sc is not None:
            return C.comparison_table_for(sc, rows, timing=False, bound=bound)
        return C.comparison_table(rows, kind, timing=False)

    def plots(self, rows, kind, title, prefix, *, torque=True, requirement=None, goal=None, limit=None,
              sc=None) -> list[Figure]:
        """sc: the scenario, to draw its settle threshold and the laws' known |u| bounds."""
        files = C.overlay_plots(rows, self.fig, title, kind, prefix=prefix, requirement=requirement, goal=goal,
                                limit=limit, norm_bounds=C.known_norm_bounds(sc, rows) if sc else (),
                                settle=C.settle_line(sc) if sc else None)
        if not torque:
            files[1].unlink()
            files = files[:1]
        return [Figure(_rel(f, self.docs), f.stem) for f in files]


TITLE = "Results: every reference scenario, every law, the same plant"
INTRO = ("Generated by `aocs results` (tools/aocs_compare/results_doc.py); do not edit by hand. "
         "Every row is its own software-in-the-loop run: plant_node (Python plant) and fsw_node (the C flight "
         "software, double precision, host build) as separate processes exchanging LCM messages in lockstep "
         "inside a private network namespace; every figure is computed from the run's LCM log "
         "(docs/sil.md). Reference gains are those of the scenario files (sil/scenarios/) and of the compiled "
         "gain tables (firmware/gains, docs/gains/report.md). One scenario: `aocs compare SCENARIO`.")
COLUMNS = ("Columns: final max = max true pointing angle 2 asin|qe_vec| over the scenario's metric window "
           "(IRASSI: last 100 s); per axis = max |2 qe_i|; qe_arcsec = max |qe_i| (the IRASSI report's figure, "
           "half the per-axis angle; never mixed up with the true angle); 0.3 as / 0.05 as = requirement / goal "
           "met by the true angle (IRASSI tables only); settle s = SPEC 4 criterion entered for good; max abs u_i / "
           "max norm u = saturated command; effort = integral of |u|_1; sat s = time saturated. Host step times "
           "are not in this page (they change from run to run on a shared machine): docs/benchmarks.md has "
           "the law timings, docs/pil.md the instruction counts on the targets.")


def build(out: Path, runs: Path, quick: bool, quiet: bool, reuse: bool = False) -> tuple[str, int]:
    R = Results(out, runs, quiet, Progress(plan_steps(quick), quiet), reuse=reuse)
    lim_dur = 500.0 if quick else LIMIT_DURATION_S
    doc = Document(TITLE).add(Paragraph(INTRO), Paragraph(COLUMNS))

    # ---- IRASSI reference
    irassi = {}
    for sid in ("irassi_small", "irassi_large"):
        sc, rows = R.rows(sid, prefix=False)
        irassi[sid] = (sc, rows)
        doc.add(Section(f"{sid}: reference gains, reference actuator (no limit)").add(
            Paragraph(sc.description), R.table(rows, "attitude", sc),
            *R.plots(rows, "attitude", f"{sid}, no limit", f"{sid}_", requirement=0.3, goal=0.05, sc=sc)))

    # ---- IRASSI realistic limits
    limited = {}
    for lim in LIMITS:
        sc, rows = R.rows("irassi_large", limit=lim, duration=lim_dur, prefix=False, tag=f"limit{lim:g}")
        limited[lim] = (sc, rows)
        doc.add(Section(f"irassi_large with reaction wheels: {lim:g} N m per axis, {lim_dur:g} s").add(
            Paragraph(f"Same gains, actuator and flight-software saturation at {lim:g} N m per axis; the run is "
                      f"extended from 500 s to {lim_dur:g} s to show how long each law needs. Final max is over "
                      "the last 100 s."),
            R.table(rows, "attitude", sc), settling_table(rows),
            *R.plots(rows, "attitude", f"irassi_large, {lim:g} N m", f"irassi_large_limit{lim:g}_",
                     requirement=0.3, goal=0.05, limit=lim)))

    # ---- IRASSI with slew guidance (SPEC 5.1)
    guided = {}
    for lim in LIMITS:
        sc, rows = R.rows("irassi_large", limit=lim, duration=GUIDED_DURATION_S, prefix=False,
                          tag=f"limit{lim:g}-slew", guidance="slew")
        guided[lim] = rows
        sec = Section(f"irassi_large with slew guidance: {lim:g} N m per axis, {GUIDED_DURATION_S:g} s").add(
            Paragraph("`aocs compare irassi_large --limit {0:g} --guidance slew --duration {1:g}`: the same laws "
                      "and gains, tracking the on-board rest-to-rest eigenaxis slew (docs/spec.md 5.1.1, margin "
                      "0.8, bang-coast-bang) with the feedforward; bound = the eigenaxis bang-bang time for this "
                      "slew and envelope (SPEC 5.1, margin 1). Final max is over the last 100 s.".format(
                          lim, GUIDED_DURATION_S)),
            R.table(rows, "attitude", sc, bound=True),
            *R.plots(rows, "attitude", f"irassi_large, {lim:g} N m, slew guidance", f"irassi_large_slew{lim:g}_",
                     requirement=0.3, goal=0.05, limit=lim))
        doc.add(sec)
    sec.add(guidance_summary(limited, guided, lim_dur))   # after the last guided table, about all of them

    # ---- IRASSI on a star tracker and a gyro through the MEKF (issue 20)
    doc.add(results_estimation.section(R))

    # ---- rtc
    rtc_rows = []
    for sid in RTC:
        rtc_rows += R.rows(sid)[1]
    doc.add(notes.section("rtc").add(
        R.table(rtc_rows, "attitude"), *R.plots(rtc_rows, "attitude", "rtc examples, crp_linear", "rtc_", torque=False)))

    # ---- landsat
    lq_rows = []
    for sid in LANDSAT_Q:
        lq_rows += R.rows(sid)[1]
    doc.add(notes.section("landsat8_q").add(
        R.table(lq_rows, "orbit"),
        *R.plots(lq_rows, "orbit", "landsat8, Q = 10 I / I / 0.1 I", "landsat8_q_", torque=False)))
    ld_rows = []
    for sid in LANDSAT_DIST:
        ld_rows += R.rows(sid, [("orbit_lqr", "orbit_lqr_q1"), ("none", None)])[1]
    doc.add(notes.section("landsat8_dist").add(
        R.table(ld_rows, "orbit"), *R.plots(ld_rows, "orbit", "landsat8 SRP / debris", "landsat8_dist_", torque=False)))

    # ---- geo_hinf
    sc_g, g_rows = R.rows("geo_hinf", prefix=False)
    sec = notes.section("geo_hinf").add(
        Paragraph(sc_g.description), R.table(g_rows, "attitude", sc_g),
        *R.plots(g_rows, "attitude", "geo_hinf", "geo_hinf_", torque=False))
    _, g0_rows = R.rows("geo_hinf", sets=HINF_ZERO_IC, prefix=False, tag="zero_ic")
    table = measured_hinf_gains(g0_rows, sc_g)
    sec.add(Paragraph(HINF_MEASURED), table)
    sweep_pts, sweep_sum = S.sweep(runs / "geo_hinf-sweep", progress=R.progress.start, quiet=quiet)
    R.failed += sweep_sum["failed"]
    doc.add(sec.add(sweep_section(sweep_pts, sweep_sum, R)))

    # ---- gao_mrp
    sc_m, m_rows = R.rows("gao_mrp", prefix=False)
    doc.add(notes.section("gao_mrp").add(
        Paragraph(sc_m.description), R.table(m_rows, "attitude", sc_m),
        *R.plots(m_rows, "attitude", "gao_mrp", "gao_mrp_", sc=sc_m)))

    # ---- stability margins (issue 22): every analysed law, predicted and measured in the loop
    margins_sec, margins_failed = margins_results.section(out, runs, progress=R.progress.start)
    R.failed += margins_failed
    doc.add(margins_sec)

    # ---- discussion
    doc.add(discussion(irassi, limited, lim_dur, [r for r in g0_rows if not r.error], m_rows).add(
        Paragraph(f"Run logs in the `--runs` folder (default `out/results`, not committed)"
                  f"{' (--quick)' if quick else ''}; regenerate with `make results`.")))
    return markdown.render(doc), R.failed


def settling_table(rows) -> Table:
    """When each law of a limited run enters 0.3 and 0.05 arcsec for good, and how far it rebounds."""
    def f(x):
        return "never" if x is None else f"{x:.0f}"

    body = []
    for r in rows:
        if not r.curves:
            continue
        t, e = r.curves["t"], r.curves["err"]
        rb = rebound(t, e)
        body.append([r.name, f(first_time_below_for_good(t, e, 0.3)), f(first_time_below_for_good(t, e, 0.05)),
                     "-" if rb is None else f"{rb:.3g}", f"{rebound_factor(e):.3g}"])
    return Table(["law", "time to stay within 0.3 as (s)", "time to stay within 0.05 as (s)",
                  "max error after first entering 10 as (as)", "rebound factor max err(t) / min err(s<=t)"], body)


HINF_MEASURED = (
    "Measured disturbance-to-output gain: the same scenario started exactly on the LVLH frame "
    "(`--set plant.euler321_deg=[0,0,0] --set plant.w0=[0,-7.292115e-05,0]`), so the disturbance "
    "alone drives the output. z = 1e-3 M q'' (SPEC 2.6; q = [phi theta psi] the 3-2-1 angles of the error "
    "quaternion about LVLH, q'' by central second differences of the logged truth), d = the logged "
    "disturbance torque (1e-4 N m per axis constant plus gravity gradient); measured gain = "
    "||z||_2 / ||d||_2 over the run. The designed gamma is the table's provenance "
    "(firmware/gains/aocs_gains.c).")


def measured_hinf_gains(rows, sc) -> Table:
    """Designed gamma against the measured gain of the runs started on LVLH."""
    body = []
    for r in rows:
        if r.error:
            continue
        g = designed_gamma(r.table)
        mg = hinf_measured_gain(lcmlog.read(r.out_dir / "run.lcmlog"), sc)
        body.append([r.table, f"{g:.6g}", f"{mg['gain']:.4g}", f"{mg['z_l2']:.4g}", f"{mg['d_l2']:.4g}",
                     f"{mg['z_peak']:.3g}", "yes" if mg["gain"] < g else "NO"])
    return Table(["table", "designed gamma", "measured L2(z) / L2(d)", "L2(z)", "L2(d)", "peak norm z",
                        "below gamma"], body)


def sweep_section(points, summary, R) -> Section:
    """The geo_hinf frequency sweep (aocs_compare.sweep, `aocs compare geo_hinf --sweep`): table and plot."""
    body = []
    for p in points:
        if p.measured is None:
            body.append([f"{p.w_rad_s:g}", f"FAILED: {p.error}", f"{p.design:.4g}", f"{p.sigma_max:.4g}", "-"])
        else:
            body.append([f"{p.w_rad_s:g}", f"{p.measured:.4g}", f"{p.design:.4g}", f"{p.sigma_max:.4g}",
                         f"{p.measured / p.design:.3f}"])
    sec = Section("Disturbance-to-output gain across frequency (the sweep)").add(
        Paragraph(f"`aocs compare geo_hinf --sweep`: one SIL run per frequency, started on the LVLH target, with "
                  f"only a sinusoidal disturbance torque of {summary['amplitude_nm']:g} N m along e = "
                  f"[{' '.join(f'{x:.4g}' for x in summary['direction'])}] (the constant torque off, the gravity "
                  "gradient on); after 5 time constants of the slowest pole the steady amplitude of z = 1e-3 M q'' "
                  "is fitted over whole cycles. Measured |z| / |d| against the design's |Gzd(jw) e| and "
                  f"sigma_max(Gzd(jw)) for {summary['table']}, and gamma of K."),
        Table(["w (rad/s)", "measured", "design abs(Gzd e)", "sigma_max", "measured / design"], body),
        Paragraph(f"Within a factor 2 of the design at every frequency: "
                  f"{'yes' if summary['within_factor_2'] else 'NO'}; never above gamma = {summary['gamma']:.6g}: "
                  f"{'yes' if summary['below_gamma'] else 'NO'}."))
    if any(p.measured is not None for p in points):
        f = S.plot(points, summary, R.fig / "geo_hinf_sweep.png")
        sec.add(Figure(_rel(f, R.docs), "geo_hinf sweep"))
    return sec


def guidance_summary(limited, guided, lim_dur) -> Section:
    """Settle time per law and limit without and with slew guidance, over the bound, from the runs."""
    def f(x, spec):
        return "never" if x is None else format(x, spec)

    body, ratios = [], []
    for lim, rows in guided.items():
        step = {r.name: r for r in limited[lim][1]}
        for r in rows:
            if not r.metrics:
                body.append([r.name, f"{lim:g}", "-", "-", "FAILED", "-", "-"])
                continue
            m = r.metrics
            s0 = step.get(r.name)
            s0 = None if s0 is None or not s0.metrics else s0.metrics["settle_time_s"]
            ratio = C.settle_over_bound(m)
            ratios.append(ratio)
            body.append([r.name, f"{lim:g}", f(m.get("slew_bound_s"), ".1f"), f(s0, ".1f"),
                         f(m["settle_time_s"], ".1f"), f(ratio, ".3f"),
                         f"{m['pointing_error_arcsec']['final_max']:.3g}"])
    done = [x for x in ratios if x is not None]
    summary = ("" if not done else
               (f"With guidance every run settles, at {min(done):.3f} to {max(done):.3f} times the bound. "
                if len(done) == len(ratios) else
                f"With guidance {len(done)} of {len(ratios)} runs settle, at {min(done):.3f} to {max(done):.3f} "
                "times the bound. "))
    return Section("Slew guidance against the step command").add(
        Paragraph(f"Settle time (10 arcsec, stays) without guidance ({lim_dur:g} s runs) and with it "
                  f"({GUIDED_DURATION_S:g} s runs), settle / bound, and the max error over the last 100 s with "
                  "guidance."),
        Table(["law", "limit N m", "bound s", "settle, step command s", "settle, guided s", "guided / bound",
               "guided final max as"], body),
        Paragraph(summary + "The reference gains were sized for unlimited torque; commanded a step of 39 deg, each "
                  "law saturates for most of the slew and arrives with a rate error the gains cannot brake within "
                  "the limit, so it overshoots and may never settle. The guidance instead plans a slew the envelope "
                  "can fly with 20 % left for feedback (margin 0.8) and gives the law the reference attitude, "
                  "rate and feedforward torque, so the tracking error stays small and the feedback never saturates "
                  "the actuator. Settle / bound is close to 1 / sqrt(0.8) = 1.118 plus the allowance for the "
                  "gyroscopic torque and the final approach. The P-type laws then come to rest at d / kp as without "
                  "guidance; quat_pid and lqr_quat_i (SPEC 5.2) integrate the error away and reach the goal."))


def half_newton_metre(rows, lim_dur) -> Section:
    """The 0.5 N m case (the README's `aocs run irassi_large --law smc --limit 0.5`), from its runs."""
    items = []
    for r in rows:
        if not r.curves:
            items.append(f"{r.name}: FAILED ({r.error})")
            continue
        t, e = r.curves["t"], r.curves["err"]
        t03 = first_time_below_for_good(t, e, 0.3)
        settle = r.metrics["settle_time_s"]
        fin = r.metrics["pointing_error_arcsec"]["final_max"]
        items.append(f"{r.name}: " + ("never settles (10 arcsec)" if settle is None else f"settles at {settle:.0f} s")
                     + f", final max {fin:.4g} arcsec, "
                     + ("never within 0.3 arcsec" if t03 is None else f"within 0.3 arcsec from {t03:.0f} s")
                     + f", saturated {r.metrics['counters']['time_in_saturation_s']:g} s, rebound factor "
                     f"{rebound_factor(e):.3g}.")
    return Section("irassi_large at 0.5 N m per axis").add(
        Paragraph("0.5 N m is the wheel limit of the README's example (`aocs run irassi_large --law smc --limit 0.5`) "
                  "and lies between the two other cases. The slew of irassi_large needs several hundred seconds at "
                  f"that torque, so the reference run of 500 s is too short. Over {lim_dur:g} s:"),
        BulletList(items),
        Paragraph("Once a law has settled, its final error is the unlimited case's (d / kp, see above). The limit "
                  "changes how long the slew takes and whether the law overshoots, not where it comes to rest."))


def _final(rows, name):
    r = next((r for r in rows if r.name == name and r.metrics), None)
    return None if r is None else r.metrics["pointing_error_arcsec"]["final_max"]


def discussion(irassi, limited, lim_dur, hinf_rows, m_rows) -> Section:
    sec = Section("Discussion: where a law differs from its reference, and why")
    sc, rows = irassi["irassi_small"]
    k_ref = np.diag(gain_matrix("lqr_quat_ref")[:, :3])
    k_str = np.diag(gain_matrix("lqr_quat_strong")[:, :3])
    kp_pd = float(sc.control.laws["quat_pd"].params["kp"])
    est_ref_axis, est_ref = steady_error_arcsec(k_ref)
    _, est_str = steady_error_arcsec(k_str)
    _, est_pd = steady_error_arcsec([kp_pd] * 3)
    meas_ref = _final(rows, "lqr_quat-lqr_quat_ref")
    meas_str = _final(rows, "lqr_quat-lqr_quat_strong")
    meas_pd = _final(rows, "quat_pd")
    f = lambda x: "-" if x is None else f"{x:.4g}"  # noqa: E731
    sec.add(Section("lqr_quat with Q = 200 I, R = 0.001 I misses 0.3 arcsec: no integral action").add(
        Paragraph("None of quat_pd, quat_nlpd, lqr_quat has an integral term. Under the constant disturbance "
                  f"d = {IRASSI_DIST_NM:g} N m per axis the closed loop comes to rest where the proportional term "
                  "cancels it: kp_i qe_i = d_i, so the steady error is the constant disturbance over the proportional "
                  "gain, qe_i = d_i / kp_i, per-axis angle 2 qe_i, true angle 2 asin|qe_vec| (the L2 gravity gradient, "
                  "~1e-9 N m here, is negligible)."),
        Paragraph(f"With the compiled table lqr_quat_ref the proportional gains are K[i][i] = "
                  f"{', '.join(f'{k:.6g}' for k in k_ref)} N m (firmware/gains/aocs_gains.c; sqrt(Q/R) = "
                  f"sqrt(200/0.001) = {math.sqrt(200 / 0.001):.6g}), so the steady-state estimate is "
                  f"qe_i = {IRASSI_DIST_NM:g} / {k_ref[0]:.6g} = {IRASSI_DIST_NM / k_ref[0]:.4g}, per axis "
                  f"{est_ref_axis[0]:.4g} arcsec, **true angle {est_ref:.4g} arcsec** (qe_arcsec figure "
                  f"{est_ref_axis[0] / 2:.4g}). Measured on irassi_small: **{f(meas_ref)} arcsec** "
                  f"(ratio measured / estimate {f(None if meas_ref is None else meas_ref / est_ref)}). It misses the "
                  "0.3 arcsec requirement in the true angle and in the report's |qe_i| figure alike."),
        Paragraph(f"The same formula predicts the other linear-P laws: quat_pd kp = {kp_pd:g}: estimate {est_pd:.4g}, "
                  f"measured {f(meas_pd)} arcsec (meets 0.3, misses 0.05); lqr_quat_strong (K[i][i] = {k_str[0]:.6g}): "
                  f"estimate {est_str:.4g}, measured {f(meas_str)} arcsec (meets 0.3; just above the 0.05 goal). "
                  "smc reaches a smaller error (its switching term inside the boundary layer acts as extra stiffness) "
                  "and the nonlinear PD variants end where quat_pd ends (qe_vec^T qe_vec ~ 1e-12 at rest). "
                  "Reaching the 0.05 arcsec goal with a PD/LQR structure needs kp > 2 sqrt(3) d / (0.05 arcsec in "
                  f"rad) = {2 * math.sqrt(3) * IRASSI_DIST_NM / (0.05 / ARCSEC_PER_RAD):.4g} N m, or integral "
                  "action.")))
    items = []
    for lim, (_, rows) in limited.items():
        parts = []
        for r in rows:
            if not r.curves:
                continue
            t, e = r.curves["t"], r.curves["err"]
            tr = first_time_below_for_good(t, e, 0.3)
            rb = rebound(t, e)
            parts.append(f"{r.name}: within 0.3 as after {'never' if tr is None else f'{tr:.0f} s'}, "
                         f"saturated {r.metrics['counters']['time_in_saturation_s']:g} s, "
                         f"rebound factor {rebound_factor(e):.3g}"
                         + (f", overshoot back to {rb:.3g} as after first entering 10 as" if rb and rb > 10 else ""))
        items.append(f"{lim:g} N m ({lim_dur:g} s): " + "; ".join(parts) + ".")
    sec.add(Section("High-gain laws under a realistic actuator limit").add(
        Paragraph("The reference runs command hundreds to thousands of N m (tables above). With reaction wheels "
                  "the slew of irassi_large is torque-limited: every law saturates for most of the slew and the "
                  "gains designed for the unlimited plant then act on a large rate error at the end of the "
                  "saturated arc."),
        BulletList(items, loose=True),
        Paragraph("A rebound factor well above 1 means the error fell and then grew again: the attitude ran past "
                  "the target (overshoot) and, with the wheel limit, the loop swings back and forth (see the "
                  "figures). An error back above 10 arcsec after first entering that band is the same effect near "
                  "the end: the derivative gain was sized for unlimited torque, so the braking demanded near the "
                  "target exceeds the wheel torque and the attitude runs through the target. The steady-state "
                  "error after settling is unchanged (it only depends on kp and d, see above), but the time to "
                  "reach it grows with the limit: the table above gives, per law, when it enters 0.3 and 0.05 "
                  "arcsec for good (never = not within the run).")))
    if 0.5 in limited:
        sec.add(half_newton_metre(limited[0.5][1], lim_dur))
    for key, rows in (("geo_hinf", hinf_rows), ("gao_mrp", m_rows)):
        law_notes = notes.discussion(key, rows)
        if law_notes is not None:
            sec.add(law_notes)
    return sec
