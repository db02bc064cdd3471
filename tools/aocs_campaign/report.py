"""A campaign's results: the per-run table (Parquet and CSV), the campaign JSON (statistics and
requirement pass fractions, SPEC 5.4), the plots and report.md.

Table: one row per run, columns
    index, status (passed | failed | error), error, repeat_command,
    in.<dispersed scalar>            the drawn values (dispersions.sample)
    m.<metric path>                  every number of the run's metrics JSON, flattened
                                     (pointing_error_arcsec.final_max, max_abs_torque_nm[2], ...)
Requirements (pass = True per run; a run with no metrics does not pass):
    settled           a settle time exists (aocs_analysis.run_metrics: inside every settle
                      criterion from then to the end)
    requirement       pointing_error_arcsec.final_max <= the scenario's requirement_arcsec
    goal              pointing_error_arcsec.final_max <= the scenario's goal_arcsec
    limits            no command beyond the flight software's limits and none non-finite
                      (limits.commands_over_limit == limits.commands_not_finite == 0)
    verdict           the run's own verdict (aocs_analysis.verdict) passed
    no_false_alarm    no fault-management alarm before the run's first injected fault (every alarm of a
                      nominal run: events_false_alarms == 0); campaign.json's false_alarms has the total
"""
from __future__ import annotations

import json
import math
import time
from pathlib import Path

from aocs_plant.scenario import load
from aocs_report import markdown
from aocs_report.document import BulletList, CodeBlock, Document, Figure, Figures, Paragraph, Section, Table

from . import plots as plotmod
from . import stats

#: metrics shown in report.md and plotted (column, label with unit); the JSON summarises every column
KEY_METRICS = (
    ("m.pointing_error_arcsec.final_max", "pointing error, max over the window (arcsec)"),
    ("m.pointing_error_arcsec.final_rms", "pointing error, RMS over the window (arcsec)"),
    ("m.settle_time_s", "settle time (s)"),
    ("m.max_torque_norm_nm", "max torque command norm (N m)"),
    ("m.effort", "effort, integral of the squared command norm (N^2 m^2 s)"),
    ("m.timing.step_ns_p99", "executive step time p99 (ns)"),
)
#: metrics JSON sections that are no run figure (paths, lists of records, the run's plots)
SKIP_SECTIONS = ("log.path", "commands", "plots", "fsw_node", "settle_criterion.criteria")


def flatten(d, prefix="") -> dict:
    """Numbers and booleans of a nested dict/list as {dotted.path[i]: value} (strings and None dropped)."""
    out = {}
    if isinstance(d, dict):
        for k, v in d.items():
            p = f"{prefix}.{k}" if prefix else str(k)
            if p in SKIP_SECTIONS:
                continue
            out.update(flatten(v, p))
    elif isinstance(d, (list, tuple)):
        if all(isinstance(x, (int, float)) and not isinstance(x, bool) for x in d):
            for i, x in enumerate(d):
                out[f"{prefix}[{i}]"] = float(x)
    elif isinstance(d, bool):
        out[prefix] = d
    elif isinstance(d, (int, float)):
        out[prefix] = float(d)
    return out


def table_rows(rows: list[dict]) -> list[dict]:
    out = []
    for r in rows:
        t = {"index": int(r["index"]), "status": r["status"], "error": r.get("error"),
             "wall_s": r.get("wall_s"), "repeat_command": r.get("repeat_command")}
        for k, v in (r.get("inputs") or {}).items():
            t[f"in.{k}"] = float(v)
        if r.get("metrics"):
            for k, v in flatten(r["metrics"]).items():
                t[f"m.{k}"] = v
        out.append(t)
    return out


def requirements(rows: list[dict], requirement: float | None, goal: float | None) -> dict:
    def pe(r):
        m = r.get("metrics") or {}
        return (m.get("pointing_error_arcsec") or {}).get("final_max")

    def lim_ok(r):
        m = r.get("metrics")
        if not m:
            return None
        lim = m.get("limits") or {}
        return lim.get("commands_over_limit") == 0 and lim.get("commands_not_finite") == 0

    flags = {
        "settled": [bool(r.get("metrics")) and r["metrics"].get("settle_time_s") is not None for r in rows],
        "limits": [lim_ok(r) is True for r in rows],
        "verdict": [bool(r.get("metrics")) and bool(r["metrics"]["verdict"]["passed"]) for r in rows],
        "no_false_alarm": [_false_alarms(r) == 0 for r in rows],
    }
    desc = {"settled": "settled (inside every settle criterion to the end)",
            "limits": "limits respected (no command beyond the limits, none non-finite)",
            "verdict": "run verdict passed (log complete, counters, limits)",
            "no_false_alarm": "no fault-management alarm before the first injected fault (none in a nominal run)"}
    if requirement is not None:
        flags["requirement"] = [pe(r) is not None and pe(r) <= requirement for r in rows]
        desc["requirement"] = f"pointing error max over the window <= {requirement:g} arcsec (requirement)"
    if goal is not None:
        flags["goal"] = [pe(r) is not None and pe(r) <= goal for r in rows]
        desc["goal"] = f"pointing error max over the window <= {goal:g} arcsec (goal)"
    return {k: {"what": desc[k], **stats.pass_fraction(v)} for k, v in flags.items()}


def _false_alarms(r: dict) -> int | None:
    """The run's alarms before its first injected fault (run_metrics events_false_alarms), None without
    metrics (a run that did not complete does not pass the requirement)."""
    m = r.get("metrics")
    return None if not m else m.get("events_false_alarms")


def false_alarm_summary(rows: list[dict]) -> dict:
    """Over the runs with metrics: how many, the alarms raised before any fault in all of them, the runs
    with at least one, and those runs' indices (docs/spec.md 5.15.7)."""
    counted = [(r["index"], _false_alarms(r)) for r in rows if _false_alarms(r) is not None]
    return {"runs": len(counted), "alarms": int(sum(n for _, n in counted)),
            "runs_with_alarm": [int(i) for i, n in counted if n > 0]}


def build(out: Path, campaign, rows: list[dict], *, outcome=None, command: str | None = None,
          commit: str | None = None, plots: bool = True) -> dict:
    """Writes results.parquet, results.csv, campaign.json, the plots and report.md; returns the JSON."""
    import pyarrow as pa  # deferred: only the aggregation needs it
    import pyarrow.csv as pacsv  # deferred: see above
    import pyarrow.parquet as pq  # deferred: see above

    sc = load(campaign.scenario, _sets(campaign))
    req, goal = sc.metrics.requirement_arcsec, sc.metrics.goal_arcsec
    trows = table_rows(rows)
    cols = []
    for t in trows:
        for k in t:
            if k not in cols:
                cols.append(k)
    full = [{k: t.get(k) for k in cols} for t in trows]
    tab = pa.Table.from_pylist(full)
    pq.write_table(tab, out / "results.parquet")
    pacsv.write_csv(tab, out / "results.csv")
    numeric = [k for k in cols if k.startswith(("m.", "in.")) or k == "wall_s"]
    summ = {}
    for k in numeric:
        vals = [t.get(k) for t in trows]
        if any(isinstance(v, bool) for v in vals):
            continue
        summ[k] = stats.summary(vals)
    counts = {s: sum(1 for r in rows if r["status"] == s) for s in ("passed", "failed", "error")}
    doc = {
        "campaign": {"scenario": sc.id, "law": campaign.law or sc.control.law, "runs": campaign.runs,
                     "seed": campaign.seed, "sets": list(campaign.sets), "disperse": list(campaign.disperse),
                     "command": command, "commit": commit, "created": time.strftime("%Y-%m-%dT%H:%M:%S")},
        "rows": len(rows), "status": counts,
        "transport": getattr(campaign, "transport", "lcm"),
        "refly": refly_summary(rows),
        "complete": len(rows) == campaign.runs,
        "throughput": None if outcome is None else {
            "runs_this_call": outcome.finished, "wall_s": outcome.wall_s, "workers": outcome.workers,
            "runs_per_minute": (60.0 * outcome.finished / outcome.wall_s) if outcome.wall_s > 0 else None},
        "requirements": requirements(rows, req, goal),
        "false_alarms": false_alarm_summary(rows),
        "metrics": summ,
        "failed_runs": [{"index": r["index"], "status": r["status"], "error": r.get("error"),
                         "repeat_command": r.get("repeat_command")} for r in rows if r["status"] != "passed"],
        "plots": [],
    }
    if plots and rows:
        inputs = [k for k in cols if k.startswith("in.")]
        doc["plots"] = [p.name for p in plotmod.campaign_plots(out, trows, rows, KEY_METRICS, inputs, sc,
                                                               f"{sc.id} / {doc['campaign']['law']}")]
    (out / "campaign.json").write_text(json.dumps(doc, indent=1) + "\n")
    (out / "report.md").write_text(report_md(doc, sc))
    return doc


def refly_summary(rows: list[dict]) -> dict | None:
    """A direct campaign's LCM re-flights (worker.run_task): how many, how many identical, the runs that
    differ; None when no row was re-flown."""
    flown = [r for r in rows if r.get("refly")]
    if not flown:
        return None
    return {"sampled": len(flown), "identical": sum(1 for r in flown if r["refly"]["identical"]),
            "differ": [r["index"] for r in flown if not r["refly"]["identical"]]}


def _sets(campaign) -> dict:
    from aocs_runner import scenario_opts  # deferred: keeps this module's import light

    return scenario_opts.parse_sets(campaign.sets)


def _fmt(v) -> str:
    if v is None:
        return "-"
    if isinstance(v, float) and (v == 0 or 1e-3 <= abs(v) < 1e5):
        return f"{v:.4g}"
    return f"{v:.3e}" if isinstance(v, float) else str(v)


def report_md(doc: dict, sc) -> str:
    return markdown.render(report_document(doc, sc))


def report_document(doc: dict, sc) -> Document:
    """report.md's content, from the campaign JSON and the scenario."""
    c = doc["campaign"]
    rep = Document(f"Monte Carlo campaign: {c['scenario']} with {c['law']}")
    rep.add(Paragraph(f"{doc['rows']} of {c['runs']} runs recorded ({doc['status']['passed']} passed, "
                      f"{doc['status']['failed']} failed their verdict, {doc['status']['error']} did not complete)"
                      + ("" if doc["complete"] else "; the campaign is INCOMPLETE (interrupted: rerun the same "
                                                    "command to finish it)") + "."))
    if c.get("command"):
        rep.add(Paragraph("Command" + (f" (commit {c['commit']})" if c.get("commit") else "") + ":"),
                CodeBlock(c["command"]))
    rep.add(Paragraph(f"Scenario: {sc.description}"),
            Paragraph(f"Seed {c['seed']}; fixed overrides: " + (", ".join(f"`{s}`" for s in c["sets"]) or "none")
                      + "; dispersions:"),
            BulletList([f"`{d}`" for d in c["disperse"]] or ["none"]),
            Paragraph("Each run's values are a function of (seed, run index) alone; `results.csv` / "
                      "`results.parquet` hold, per run, the drawn values (`in.*`), every metric (`m.*`), the status, "
                      "the error and the `aocs run` command that repeats that run bit for bit."))
    t = doc.get("throughput")
    if t and t.get("runs_per_minute"):
        rep.add(Paragraph(f"Throughput of this call: {t['runs_this_call']} runs in {t['wall_s']:.1f} s on "
                          f"{t['workers']} workers = {t['runs_per_minute']:.1f} runs per minute."))
    rep.add(_requirements_section(doc), _metrics_section(doc))
    fa = doc.get("false_alarms")
    if fa:
        rep.add(Paragraph(f"False alarms (fault management's warnings and above before any injected fault): "
                          f"{fa['alarms']} over {fa['runs']} runs, in {len(fa['runs_with_alarm'])} runs."))
    if doc["failed_runs"]:
        rep.add(_failed_runs_section(doc["failed_runs"]))
    if doc["plots"]:
        rep.add(Section("Plots").add(Figures([Figure(p, p) for p in doc["plots"]])))
    return rep


def _requirements_section(doc: dict) -> Section:
    rows = []
    for r in doc["requirements"].values():
        w = r["wilson95"]
        rows.append([r["what"], f"{r['passed']} / {r['n']}", _fmt(r["fraction"]),
                     f"[{w[0]:.4f}, {w[1]:.4f}]" if w else "-"])
    return Section("Requirements").add(
        Paragraph("Pass fraction over all recorded runs (a run that did not complete does not pass), with its "
                  "95 % Wilson score interval."),
        Table(["requirement", "passed", "fraction", "95 % interval"], rows))


def _metrics_section(doc: dict) -> Section:
    sec = Section("Metrics").add(Paragraph("Over the runs that produced metrics (percentiles by linear "
                                           "interpolation); `campaign.json` has every metric."))
    rows = []
    for k, label in KEY_METRICS:
        s = doc["metrics"].get(k)
        if s:
            rows.append([label, str(s["n"]), *(_fmt(s[x]) for x in ("min", "median", "p95", "p99", "max"))])
    sec.add(Table(["metric", "n", "min", "median", "p95", "p99", "max"], rows))
    ins = [k for k in doc["metrics"] if k.startswith("in.")]
    if ins:
        s = doc["metrics"]
        sec.add(Paragraph("Dispersed inputs:"),
                Table(["input", "min", "median", "max"],
                      [[f"`{k[3:]}`", _fmt(s[k]["min"]), _fmt(s[k]["median"]), _fmt(s[k]["max"])] for k in ins]))
    return sec


#: failed runs listed in report.md (campaign.json lists them all)
FAILED_LISTED = 20


def _failed_runs_section(failed: list[dict]) -> Section:
    items = []
    for f in failed[:FAILED_LISTED]:
        err = str(f["error"]).splitlines()[0] if f["error"] else ""
        items.append(f"run {f['index']} ({f['status']}): {err}\nrepeat: `{f['repeat_command']}`")
    return Section("Runs that did not pass").add(
        Paragraph(f"{len(failed)} runs (logs kept in `runs/NNNNNN/`; the first {FAILED_LISTED} listed):"),
        BulletList(items))


def finite(v) -> bool:
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)
