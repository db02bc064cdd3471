"""`aocs compare SCENARIO`: every applicable law on the same scenario, side by side.

Each law (and each gain table of a table-based law: lqr_quat_ref and
lqr_quat_strong are two rows) runs in its own SIL run through real
processes (plant_node, fsw_node, the recorder; aocs_runner.run.execute),
in lockstep, inside a private network namespace. The metrics come from each
run's LCM log (docs/sil.md). Written to OUT (default out/compare/<scenario>):

- OUT/<law>[-<table>]/      each run's log, metrics.json, config
- OUT/compare.json          the list of metrics (also --json FILE)
- OUT/pointing_error.png    true pointing angle of every law, log scale (attitude)
  OUT/torque_norm.png       |u| of every law (attitude)
  OUT/position_error.png, OUT/force_norm.png (orbit scenarios)
- OUT/report.md             the table, the requirement check, the plots
"""
from __future__ import annotations

import json
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

from aocs_analysis import plots as P
from aocs_analysis import verdict
from aocs_analysis.gain_tables import GAINS_C, designed_gamma, gain_matrix  # noqa: F401 (re-exported)
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_plant.scenario import load
from aocs_report import markdown
from aocs_report.document import Column, Document, Figure, Paragraph, Section, Table
from aocs_runner import scenario_opts
from aocs_runner.run import RunFailed, RunOptions, execute, planned_record
from aocs_runner.transport import check_transport
from aocs_wire import lcmlog

REPO = Path(__file__).resolve().parents[2]
#: what the comparison was asked (scenario, laws, options): `aocs report` rebuilds the page from it
PLAN_FILE = "compare-plan.json"
#: SPEC 4 irassi_*: constant disturbance torque per axis, N m
IRASSI_DIST_NM = 1.18e-3



# --------------------------------------------------------------------------- runs
@dataclass
class Row:
    """One SIL run of the comparison."""

    name: str                      # law or law-table, the row label
    law: str
    table: str | None
    metrics: dict | None = None
    curves: dict = field(default_factory=dict)
    error: str | None = None
    out_dir: Path | None = None


def variants(sc, laws: str | None = "all") -> list[tuple[str, str | None]]:
    """(law, gain table or None) per row: every applicable law, every table of table-based laws."""
    all_rows = []
    for law, lc in sc.control.laws.items():
        tables = list(getattr(lc, "tables", None) or [])
        all_rows += [(law, t) for t in tables] if tables else [(law, None)]
    if laws in (None, "", "all"):
        return all_rows
    out = []
    for item in laws.split(","):
        item = item.strip()
        law, _, table = item.partition(":")
        if law == "none":
            out.append(("none", None))
            continue
        if law not in sc.control.laws:
            raise ValueError(f"--laws {item}: scenario {sc.id} has no gains for {law} "
                             f"(applicable: {', '.join(sc.control.laws)})")
        rows = [r for r in all_rows if r[0] == law and (not table or r[1] == table)]
        if not rows:
            raise ValueError(f"--laws {item}: law {law} has no gain table {table!r}")
        out += rows
    return out


def row_name(law: str, table: str | None) -> str:
    return f"{law}-{table}" if table else law


def curves_from_log(log_path: Path, kind: str, dt: float) -> dict:
    """Time series for the overlay plots, read back from the run's LCM log."""
    log = lcmlog.read(log_path)
    tr, cmd = log.truth, log.cmd
    c = {"t": tr["t_s"], "t_cmd": cmd["tick"] * dt}
    if kind == "attitude":
        c["err"] = tr["pointing_err_arcsec"]
        c["u_norm"] = np.linalg.norm(cmd["u_sat"], axis=1) if cmd["tick"].size else np.zeros(0)
    else:
        c["err"] = np.max(np.abs(tr["pos"]), axis=1)
        c["u_norm"] = np.linalg.norm(cmd["u_sat"], axis=1) if cmd["tick"].size else np.zeros(0)
    return c


def run_rows(scenario: str, rows: list[tuple[str, str | None]], out: Path, *, limit=None, duration=None,
             sets=(), run_plots=False, quiet=False, tag="", guidance=None, progress=None,
             reuse=False, telemetry_decimate: int = 1, transport: str = "lcm") -> list[Row]:
    """One SIL run per row (must be called inside the private network namespace).
    progress: called with the row name before each run (instead of the 'compare:' line).
    reuse: a row whose folder already holds a passed run of the same configuration (run.json's
    overrides and fsw_node configuration equal to this row's) is read back instead of run again."""
    sc = load(scenario)
    result = []
    for law, table in rows:
        name = row_name(law, table)
        row = Row(name=name, law=law, table=table, out_dir=out / name)
        s = list(sets)
        if table:
            s.append(f'laws.{law}.table="{table}"')
        if law == "none":
            s.append("control.enabled=false")
        curves = (curves_from_log(row.out_dir / "run.lcmlog", sc.kind, sc.dt)
                  if reuse and _reusable(row.out_dir, scenario, law, limit, duration, s, guidance) else None)
        # reused only when this build's wire types decode the log (one of an older wire version reads empty)
        if curves is not None and curves["t"].size:
            row.metrics = json.loads((row.out_dir / "metrics.json").read_text())
            row.curves = curves
            result.append(row)
            if progress is not None:
                progress(name + " (reused)")
            continue
        if progress is not None:
            progress(name)
        elif not quiet:
            lim = "no limit" if limit is None else f"{limit:g} per axis"
            gd = "" if guidance is None else f", guidance {guidance}"
            print(f"compare: {sc.id} {name} ({lim}{gd}{tag})", file=sys.stderr, flush=True)
        try:
            res = execute(RunOptions(scenario=scenario, law=None if law == "none" else law, limit=limit,
                                     duration=duration, sets=s, out=str(row.out_dir), label=table,
                                     plots=run_plots, quiet=True, guidance=guidance,
                                     telemetry_decimate=telemetry_decimate, transport=transport))
            row.metrics = res.metrics
            row.curves = curves_from_log(row.out_dir / "run.lcmlog", sc.kind, sc.dt)
            if not res.metrics["verdict"]["passed"]:  # the run ended, but did not do what was asked
                row.error = "verdict: " + verdict.summary(res.metrics["verdict"])
                print(f"compare: {name}: FAILED: {row.error}", file=sys.stderr)
        except RunFailed as exc:  # a process failed: record it, go on; RunAborted (a signal) stops everything
            row.error = str(exc)
            print(f"compare: {name}: FAILED: {exc}", file=sys.stderr)
        result.append(row)
    return result


def _reusable(out_dir: Path, scenario, law, limit, duration, sets, guidance=None) -> bool:
    """A finished, passed run in out_dir with the overrides this row would give, of the same scenario file
    (its SHA-256) and the same flight configuration (aocs results --reuse)."""
    try:
        meta = json.loads((out_dir / "run.json").read_text())
        m = json.loads((out_dir / "metrics.json").read_text())
    except (OSError, ValueError):
        return False
    ov = scenario_opts.overrides(sets, duration, None, limit, guidance)
    if not (m.get("verdict", {}).get("passed") is True and meta.get("overrides") == ov
            and meta.get("law") == ("none" if law == "none" else law) and (out_dir / "run.lcmlog").is_file()):
        return False
    now = planned_record(RunOptions(scenario=scenario, law=None if law == "none" else law, limit=limit,
                                    duration=duration, sets=sets, guidance=guidance))
    return (meta.get("scenario_sha256") == now["scenario_sha256"]
            and meta.get("fsw_config") == json.loads(json.dumps(now["fsw_config"])))


# --------------------------------------------------------------------------- table
def _g(x, fmt=".3g"):
    return "-" if x is None else format(x, fmt)


def _vec(v, fmt=".3g"):
    return "-" if v is None else " ".join(format(x, fmt) for x in v)


def _yes(b):
    return "-" if b is None else ("yes" if b else "NO")


def settle_over_bound(m: dict) -> float | None:
    """settle time / eigenaxis bang-bang bound (slew_bound_s, SPEC 5.1); None when either is missing."""
    b = m.get("slew_bound_s")
    if m.get("settle_time_s") is None or b is None or not b > 0.0:
        return None
    return m["settle_time_s"] / b


#: the wheel columns of a run on a wheel array (SPEC 5.3): the removed (failed) wheels, the largest peak
#: speed and motor torque over the wheels as a fraction of their limits, the longest time a wheel spent at
#: a limit, and whether every wheel stayed within its limits
WHEEL_COLUMNS = (Column("removed"), Column("peak speed/max"), Column("peak u_s/max"), Column("at limit", "s"),
                 Column("wheel limits"))


def wheel_cells(w: dict | None) -> list[str]:
    if not w:
        return ["-"] * len(WHEEL_COLUMNS)
    live = [x for x in w["per_wheel"] if not x["failed"]]
    speed = max((x["peak_speed_rad_s"] / x["speed_limit_rad_s"] for x in live), default=None)
    torque = max((x["peak_motor_torque_nm"] / x["torque_limit_nm"] for x in live), default=None)
    at_limit = max((max(x["time_at_torque_limit_s"], x["time_at_speed_limit_s"]) for x in live), default=None)
    removed = ",".join(str(i) for i in w["removed"]) or "none"
    return [removed, _g(speed, ".3f"), _g(torque, ".3f"), _g(at_limit, "g"),
            "within" if w["within_limits"] else "EXCEEDED"]


def comparison_table(rows: list[Row], kind: str, *, requirement=None, goal=None,
                     timing: bool = True, bound: bool = False) -> Table:
    """The comparison table. requirement / goal (arcsec): the scenario's pointing requirement and
    goal (IRASSI); without them the IRASSI columns (qe_arcsec, met requirement / goal) are left out.
    timing=False leaves out the host step-time columns (docs/results.md: they change at every run).
    bound: add the slew bound, settle / bound and profile end columns (--guidance slew)."""
    irassi = kind == "attitude" and requirement is not None
    show_timing = timing
    wheels = any(r.metrics is not None and r.metrics.get("wheels") for r in rows)
    if kind == "attitude":
        head = [Column("law"), Column("limit", "N m"), Column("final max", "as"), Column("per axis", "as")]
        if irassi:
            head += [Column("qe_arcsec max"), Column(f"{requirement:g}", "as")]
            head += [Column(f"{goal:g}", "as")] if goal is not None else []
        head += [Column("settle", "s")]
        head += [Column("bound", "s"), Column("settle/bound"), Column("profile end", "s")] if bound else []
        head += [Column("max abs u_i", "N m"), Column("max norm u", "N m"), Column("effort", "N m s"),
                 Column("sat", "s")]
        if wheels:
            head += WHEEL_COLUMNS
    else:
        head = [Column("law"), Column("limit", "N"), Column("pos err max", "m"), Column("per axis", "m"),
                Column("vel err max", "m/s"), Column("settle", "s"), Column("max abs F_i", "N"),
                Column("max norm F", "N"), Column("effort", "N s"), Column("sat", "s")]
    if timing:
        head += [Column("step ns med/p99/budget"), Column("overruns")]
    body = []
    for r in rows:
        m = r.metrics
        if m is None:
            body.append([r.name, "FAILED"] + ["-"] * (len(head) - 2))
            continue
        lim = m["limits"]
        limit = "none" if lim["unlimited"] or lim["axis"] is None else f"{lim['axis']:g}"
        settle = "never" if m["settle_time_s"] is None else f"{m['settle_time_s']:.1f}"
        tm = m["timing"]
        timing = f"{tm['step_ns_median']:.0f} / {tm['step_ns_p99']:.0f} / {tm['budget_ns']:.0f}"
        sat = f"{m['counters']['time_in_saturation_s']:g}"
        if kind == "attitude":
            pe = m["pointing_error_arcsec"] or {}
            fin = pe.get("final_max")
            row = [r.name, limit, _g(fin, ".4g"), _vec(pe.get("per_axis_final_max"))]
            if irassi:
                row += [_vec(pe.get("qe_arcsec_final_max")), _yes(None if fin is None else fin <= requirement)]
                row += [_yes(None if fin is None else fin <= goal)] if goal is not None else []
            row += [settle]
            if bound:
                row += [_g(m.get("slew_bound_s"), ".1f"), _g(settle_over_bound(m), ".3f"),
                        _g((m.get("guidance") or {}).get("profile_end_s"), ".1f")]
            row += [_vec(m["max_abs_torque_nm"]), _g(m["max_torque_norm_nm"], ".4g"),
                    _g(m["effort"], ".4g"), sat]
            if wheels:
                row += wheel_cells(m.get("wheels"))
        else:
            pe = m["position_error_m"] or {}
            row = [r.name, limit, _g(pe.get("final_max"), ".4g"), _vec(pe.get("per_axis_final_max")),
                   _g(pe.get("velocity_final_max_m_s"), ".3g"), settle, _vec(m["max_abs_force_n"]),
                   _g(m["max_force_norm_n"], ".4g"), _g(m["effort"], ".4g"), sat]
        body.append(row + ([timing, str(tm["overruns"])] if show_timing else []))
    return Table(head, body)


#: an integral law's pointing rms may exceed its knowledge rms by at most this factor (issue 20's acceptance: the
#: loop adds little to what the filter knows)
POINTING_OVER_KNOWLEDGE_MAX = 1.5
#: laws with integral action (SPEC 5.2): the ones the factor above is stated for
INTEGRAL_LAWS = ("quat_pid", "lqr_quat_i")


def knowledge_bound_angle_arcsec(est: dict) -> float | None:
    """The analytic rms knowledge angle the run's sensors allow: sqrt(sum_i b_i^2) of the per-axis
    Farrenkopf bound of the logged estimate (estimation.steady_state_bound_log_rms_arcsec)."""
    b = est.get("steady_state_bound_log_rms_arcsec")
    return None if not b or any(x is None for x in b) else math.sqrt(sum(x * x for x in b))


def estimation_table(rows: list[Row], requirement: float | None = None) -> Table | None:
    """Rows that flew a filter (metrics["estimation"]): knowledge (truth against estimate), control (estimate
    against the reference) and pointing (truth against the reference) error, true angles, rms and max over the
    run's metric window (the last 100 s of an IRASSI run), pointing rms / knowledge rms, the analytic knowledge
    bound of the sensors, the fraction inside the filter's own 3 sigma; None when no row has a filter."""
    flown = [r for r in rows if r.metrics is not None and (r.metrics.get("estimation") or {}).get("metric_window")]
    if not flown:
        return None
    w = flown[0].metrics["estimation"]["metric_window"]["window_s"]
    head = [Column("law"), Column(f"knowledge rms, last {w:g} s", "as"), Column("knowledge max", "as"),
            Column("control rms", "as"), Column("control max", "as"), Column("pointing rms", "as"),
            Column("pointing max", "as"), Column("pointing rms / knowledge rms"),
            Column("analytic knowledge rms", "as"), Column("in 3 sigma")]
    if requirement is not None:
        head.append(Column(f"pointing max <= {requirement:g} as"))
    body = []
    for r in rows:
        est = (r.metrics or {}).get("estimation") or {}
        mw = est.get("metric_window")
        if not mw:
            body.append([r.name, "FAILED" if r.metrics is None else "no filter"] + ["-"] * (len(head) - 2))
            continue
        k, c, p = mw["knowledge_arcsec"], mw["control_arcsec"], mw["pointing_arcsec"]
        ratio = None if not k["rms"] or p["rms"] is None else p["rms"] / k["rms"]
        row = [r.name, _g(k["rms"], ".3g"), _g(k["max"], ".3g"), _g(c["rms"], ".3g"), _g(c["max"], ".3g"),
               _g(p["rms"], ".3g"), _g(p["max"], ".3g"), _g(ratio, ".2f"), _g(knowledge_bound_angle_arcsec(est), ".3g"),
               _g(est.get("three_sigma_fraction"), ".4f")]
        if requirement is not None:
            row.append(_yes(None if p["max"] is None else p["max"] <= requirement))
        body.append(row)
    return Table(head, body)


def pointing_over_knowledge(r: Row) -> float | None:
    """pointing rms / knowledge rms over the metric window of a row that flew a filter (None otherwise)."""
    mw = ((r.metrics or {}).get("estimation") or {}).get("metric_window")
    if not mw or not mw["knowledge_arcsec"]["rms"] or mw["pointing_arcsec"]["rms"] is None:
        return None
    return mw["pointing_arcsec"]["rms"] / mw["knowledge_arcsec"]["rms"]


ESTIMATION_COLUMNS = (
    "Knowledge = the true attitude against the flight software's estimate, control = the estimate against the "
    "reference (what the law acts on), pointing = the true attitude against the reference (what the mission "
    "gets); all true angles 2 asin|qe_vec|, over the metric window. Analytic knowledge rms = sqrt(sum of the "
    "squared per-axis Farrenkopf steady-state values of the run's sensors, docs/spec.md 5.7); in 3 sigma = "
    "fraction of the filter's samples inside its own +/-3 sigma over the last half of the run.")


def comparison_table_for(sc, rows: list[Row], *, timing: bool = True, bound: bool = False) -> Table:
    """comparison_table with the scenario's own requirement and goal (IRASSI columns only where they exist)."""
    req = sc.metrics.requirement_arcsec if sc.kind == "attitude" else None
    goal = sc.metrics.goal_arcsec if sc.kind == "attitude" else None
    return comparison_table(rows, sc.kind, requirement=req, goal=goal, timing=timing, bound=bound)


# --------------------------------------------------------------------------- plots
def overlay_plots(rows: list[Row], out: Path, title: str, kind: str, prefix: str = "",
                  requirement=None, goal=None, limit=None, norm_bounds=(), settle=None) -> list[Path]:
    """Pointing (or position) error of every row on one log plot, and the command norms, with the
    requirement, goal, settle threshold, actuator limit and any known bound of the laws
    (norm_bounds: (value, label) pairs, e.g. mrp_sat's uM) drawn."""
    out.mkdir(parents=True, exist_ok=True)
    ok = [r for r in rows if r.curves]
    files = []
    floor = P.LOG_FLOOR
    ylabel = "true angle 2 asin|qe_vec| (arcsec)" if kind == "attitude" else "max |position error| (m)"
    fig, ax = P.new_axes(f"{title}: {'pointing' if kind == 'attitude' else 'position'} error", ylabel, 4.5)
    P.clip_note(ax, floor)
    for r in ok:
        ax.semilogy(r.curves["t"], np.maximum(r.curves["err"], floor), lw=1.0, label=r.name)
    if requirement is not None:
        ax.axhline(requirement, color="red", ls="--", lw=1.0, label=f"requirement {requirement:g} arcsec")
    if goal is not None:
        ax.axhline(goal, color="green", ls="--", lw=1.0, label=f"goal {goal:g} arcsec")
    if settle is not None:
        value, label = settle
        ax.axhline(value, color="black", ls="-.", lw=1.0, label=label)
    P.legend(ax, ncol=2)
    files.append(P.save(fig, out / f"{prefix}{'pointing_error' if kind == 'attitude' else 'position_error'}.png"))

    unit = "N m" if kind == "attitude" else "N"
    fig, ax = P.new_axes(f"{title}: commanded {'torque' if kind == 'attitude' else 'force'} norm", f"|u| ({unit})",
                         4.0)
    P.clip_note(ax, floor)
    for r in ok:
        u = r.curves["u_norm"]
        if u.size:
            ax.semilogy(r.curves["t_cmd"], np.maximum(u, floor), lw=0.9, label=r.name)
    if limit is not None:
        ax.axhline(limit * np.sqrt(3.0), color="red", ls=":", lw=1.0,
                   label=f"sqrt(3) x axis limit {limit:g} {unit}")
    for value, label in norm_bounds:
        ax.axhline(value, color="purple", ls="--", lw=1.0, label=label)
    P.legend(ax, ncol=2)
    files.append(P.save(fig, out / f"{prefix}{'torque_norm' if kind == 'attitude' else 'force_norm'}.png"))
    return files


def known_norm_bounds(sc, rows: list[Row]) -> list[tuple[float, str]]:
    """Bounds on |u| a law guarantees by construction, to draw on the torque plot: a law whose
    parameters include u_max (mrp_sat and its tanh variant) keeps |u|_2 <= uM (SPEC 2.7)."""
    out = []
    for law in sorted({r.law for r in rows if r.law in sc.control.laws and "u_max" in sc.control.laws[r.law].params}):
        um = float(sc.control.laws[law].params["u_max"])
        if all(abs(um - v) > 1e-12 for v, _ in out):
            out.append((um, f"uM = {um:g} N m (|u| bound of mrp_sat, SPEC 2.7)"))
    return out


def settle_line(sc) -> tuple[float, str] | None:
    """The settle threshold that is drawn on an error plot of this scenario, if it is an error level."""
    st = sc.settle
    if sc.kind == "attitude" and st.pointing_arcsec_max is not None:
        return st.pointing_arcsec_max, f"settle threshold {st.pointing_arcsec_max:g} arcsec"
    if sc.kind == "orbit" and st.pos_abs_max_m is not None:
        return st.pos_abs_max_m, f"settle threshold {st.pos_abs_max_m:g} m"
    return None


# --------------------------------------------------------------------------- report
def report_md(sc, rows: list[Row], plots: list[Path], limit=None, duration=None, bound=False) -> str:
    return markdown.render(report_document(sc, rows, plots, limit, duration, bound))


def report_document(sc, rows: list[Row], plots: list[Path], limit=None, duration=None, bound=False) -> Document:
    """report.md's content: the runs' table, what its columns mean, the steady state, failures, plots."""
    lim = "reference actuator (no limit)" if limit is None else f"actuator limit {limit:g} per axis"
    dur = f"{duration:g} s" if duration else f"{sc.duration_s:g} s"
    doc = Document(f"aocs compare: {sc.id}").add(
        Paragraph(f"{sc.description}"), Paragraph(f"Reference: {sc.reference}"),
        Paragraph(f"{len(rows)} SIL runs (each its own plant_node + fsw_node processes, lockstep), {lim}, {dur}, "
                  f"{sc.control_rate_hz:g} Hz. Metrics from each run's LCM log (docs/sil.md)."),
        comparison_table_for(sc, rows, bound=bound), Paragraph(columns_explained(sc)))
    est = estimation_table(rows, sc.metrics.requirement_arcsec if sc.kind == "attitude" else None)
    if est is not None:
        doc.add(Section("Attitude knowledge, control and pointing error (the laws fly the estimate)").add(
            est, Paragraph(ESTIMATION_COLUMNS)))
    if sc.settle:
        crit = {k: v for k, v in vars(sc.settle).items() if v is not None} if hasattr(sc.settle, "__dict__") else {}
        if crit:
            doc.add(Paragraph("settled when " + ", ".join(f"{k} = {v:g}" for k, v in crit.items())
                              + " from then to the end of the run."))
    steady = steady_state_section(sc, rows)
    if steady is not None:
        doc.add(steady)
    doc.add(*(Paragraph(f"**{r.name} FAILED**: {r.error}") for r in rows if r.error))
    doc.add(*(Figure(p.name, p.stem) for p in plots))
    return doc


def columns_explained(sc) -> str:
    """What the comparison table's columns mean, for this scenario's kind."""
    if sc.kind != "attitude":
        return f"pos err max = max position error component over the last {sc.metrics.window_s:g} s."
    req, goal = sc.metrics.requirement_arcsec, sc.metrics.goal_arcsec
    irassi = ("qe_arcsec = max |qe_i| (the IRASSI report's figure, half the per-axis angle); "
              f"{req:g} as / {goal:g} as: final max within the requirement / goal (true angle); "
              if req is not None and goal is not None else "")
    return (f"final max = max of the true pointing angle 2 asin|qe_vec| over the last {sc.metrics.window_s:g} s; "
            f"per axis = max |2 qe_i|; {irassi}"
            "sat s = time the command was saturated; step time of the executive against the law's budget.")


def compare(scenario: str, out: Path, *, laws="all", limit=None, duration=None, sets=(), run_plots=False,
            quiet=False, guidance=None, telemetry_decimate: int = 1,
            transport: str = "lcm") -> tuple[object, list[Row], list[Path]]:
    ov = scenario_opts.overrides(sets, None, None, limit, guidance)  # duration: per run (cmd_run adapts the window)
    check_transport(transport)
    sc = load(scenario, ov)
    rows = run_rows(scenario, variants(sc, laws), out, limit=limit, duration=duration, sets=sets,
                    run_plots=run_plots, quiet=quiet, guidance=guidance, telemetry_decimate=telemetry_decimate,
                    transport=transport)
    plots = overlay_plots(rows, out, sc.id + ("" if limit is None else f", limit {limit:g}"), sc.kind,
                          norm_bounds=known_norm_bounds(sc, rows), settle=settle_line(sc),
                          requirement=sc.metrics.requirement_arcsec if sc.kind == "attitude" else None,
                          goal=sc.metrics.goal_arcsec if sc.kind == "attitude" else None, limit=limit)
    ms = [dict(r.metrics, row=r.name, table=r.table) if r.metrics else {"row": r.name, "error": r.error}
          for r in rows]
    (out / "compare.json").write_text(json.dumps(ms, indent=1) + "\n")
    plan = {"scenario": scenario, "laws": laws, "limit": limit, "duration": duration, "sets": list(sets),
            "guidance": guidance, "transport": transport, "rows": [{"row": r.name, "law": r.law, "table": r.table} for r in rows]}
    (out / PLAN_FILE).write_text(json.dumps(plan, indent=1) + "\n")
    (out / "report.md").write_text(report_md(sc, rows, plots, limit, duration, bound=guidance == "slew"))
    return sc, rows, plots


# --------------------------------------------------------------------------- gains and steady state
def steady_error_arcsec(kp_diag, d=IRASSI_DIST_NM) -> tuple[np.ndarray, float]:
    """Steady state of a law without integral action under a constant torque d per axis:
    kp_i qe_i = d_i, so qe_i = d_i / kp_i; per-axis angle 2 qe_i; true angle 2 asin|qe_vec| (arcsec)."""
    qe = d / np.asarray(kp_diag, float)
    as_ = ARCSEC_PER_RAD
    return 2.0 * qe * as_, 2.0 * math.asin(float(np.linalg.norm(qe))) * as_


def steady_state_section(sc, rows) -> Section | None:
    """For `aocs compare` reports: the no-integral-action steady-state estimate d / kp of every
    proportional law (quat_pd, quat_nlpd_*, lqr_quat tables) under the scenario's constant torque
    (None when the scenario has no constant torque or no such law ran)."""
    ct = sc.disturbances.constant_torque
    if sc.kind != "attitude" or ct is None or not ct.enabled:
        return None
    d = np.abs(np.asarray(ct.torque_nm, float)) * ct.scale
    req = sc.metrics.requirement_arcsec
    body = []
    n = unsettled = 0
    miss = []
    for r in rows:
        if r.metrics is None:
            continue
        kp = proportional_gain(sc, r)
        if kp is None:
            continue
        meas = r.metrics["pointing_error_arcsec"]["final_max"]
        meets = "-" if req is None else ("yes" if meas <= req else "NO")
        if r.metrics["settle_time_s"] is None:
            # still slewing (or never settled): there is no steady state to explain yet
            body.append([r.name, " ".join(f"{k:.6g}" for k in kp), "-", f"{meas:.4g}",
                         "not settled: the slew has not finished, no steady state", meets])
            unsettled += 1
            continue
        _, est = steady_error_arcsec(kp, d)
        body.append([r.name, " ".join(f"{k:.6g}" for k in kp), f"{est:.4g}", f"{meas:.4g}", f"{meas / est:.3f}",
                     meets])
        n += 1
        # the explanation holds where the steady error is the estimate (a settled run, ratio near 1)
        if r.law == "lqr_quat" and req is not None and meas > req and 0.5 <= meas / est <= 2.0:
            miss.append((r, kp))
    if not n and not unsettled:
        return None
    sec = Section("Steady-state error of the laws without integral action").add(
        Paragraph("quat_pd, quat_nlpd and lqr_quat have no integral action: under the constant disturbance torque "
                  f"d = [{' '.join(f'{x:g}' for x in d)}] N m they come to rest where the proportional term cancels "
                  "it, kp_i qe_i = d_i, so the steady error is the constant disturbance over the proportional gain: "
                  "qe_i = d_i / kp_i, true angle 2 asin|qe_vec|. kp from the scenario (PD laws) or the attitude "
                  "block of the K that flew (the compiled table, firmware/gains/aocs_gains.c, or the K designed "
                  "for the scenario). Only a run that has settled has a steady state to compare. Agreement is "
                  "stated as measured / estimate (the gravity gradient and the metric window's residual transient "
                  "make up the rest)."),
        Table(["law", "kp per axis", "estimate (true angle, arcsec)", "measured final max (arcsec)",
               "measured / estimate", f"meets {req:g}" if req is not None else "meets requirement"], body))
    for r, kp in miss:
        sec.add(Paragraph(f"{r.name} misses {req:g} arcsec because it has no integral action and its proportional "
                          f"gain K[i][i] = {kp[0]:.6g} N m is too small for the disturbance: steady error = constant "
                          f"disturbance / proportional gain = {d[0]:g} / {kp[0]:.6g} per axis."))
    return sec


def proportional_gain(sc, r: Row):
    """kp per axis of a proportional law of this row (None for other laws): the scenario's kp (PD laws),
    or the attitude block of the K that flew (lqr_quat: a K designed for the scenario, else its table)."""
    params = sc.control.laws[r.law].params
    if "kp" in params:   # the quaternion PD laws
        return np.full(3, float(params["kp"]))
    if r.law == "lqr_quat":
        g = (r.metrics or {}).get("gain") or {}
        k = np.asarray(g["K"]) if g.get("K") is not None else (gain_matrix(r.table) if r.table else None)
        return None if k is None else np.diag(k[:, :3])
    return None
