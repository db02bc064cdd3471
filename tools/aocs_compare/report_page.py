"""The comparison's interactive page (`aocs compare --html FILE`, `aocs report COMPARE_FOLDER --html FILE`), built
from the folder the comparison left (compare-plan.json, compare.json, each law's run folder with its
telemetry.parquet): report.md's content (the table, the steady state, the failures) with every law overlaid on one
time axis instead of the PNG figures (pointing error with the requirement, goal and settle threshold; with a filter
the control error; the torque command norm with the limit; with wheels the largest wheel speed and the total
momentum), then the command that repeats the comparison and each law's own repeat command.
"""
from __future__ import annotations

import shlex
from pathlib import Path

import numpy as np

from aocs_plant.scenario import load
from aocs_report import run_report
from aocs_report.document import Chart, CodeBlock, Document, Level, Panel, Paragraph, Section, Table, Trace
from aocs_runner import scenario_opts

from .compare import PLAN_FILE, Row, known_norm_bounds, report_document, settle_line


def read_rows(folder: Path) -> tuple[dict, list[Row]]:
    folder = Path(folder)
    plan = run_report.read_json(folder / PLAN_FILE)
    ms = {m["row"]: m for m in run_report.read_json(folder / "compare.json")}
    rows = []
    for r in plan["rows"]:
        m = ms.get(r["row"]) or {}
        metrics = None if "error" in m and len(m) <= 2 else m
        err = m.get("error") if metrics is None else None
        if metrics is not None and not metrics.get("verdict", {}).get("passed", True):
            err = "verdict: FAILED"
        rows.append(Row(name=r["row"], law=r["law"], table=r["table"], metrics=metrics, error=err,
                        out_dir=folder / r["row"]))
    return plan, rows


def repeat_command(plan: dict) -> str:
    words = ["aocs", "compare", plan["scenario"]]
    if plan.get("laws") not in (None, "all"):
        words += ["--laws", plan["laws"]]
    for opt in ("limit", "duration", "guidance"):
        if plan.get(opt) is not None:
            words += [f"--{opt}", str(plan[opt])]
    for s in plan.get("sets") or []:
        words += ["--set", s]
    return shlex.join(words)


def overlay_chart(sc, rows: list[Row], runs: dict, limit, max_points: int = run_report.MAX_POINTS) -> Chart:
    """Every law's series on one time axis."""
    attitude = sc.kind == "attitude"
    err_levels = []
    if attitude and sc.metrics.requirement_arcsec is not None:
        err_levels.append(Level(sc.metrics.requirement_arcsec, f"requirement {sc.metrics.requirement_arcsec:g} arcsec"))
    if attitude and sc.metrics.goal_arcsec is not None:
        err_levels.append(Level(sc.metrics.goal_arcsec, f"goal {sc.metrics.goal_arcsec:g} arcsec"))
    st = settle_line(sc)
    if st is not None:
        err_levels.append(Level(*st))
    unit = "N m" if attitude else "N"
    u_levels = [Level(limit * np.sqrt(3.0), f"sqrt(3) x axis limit {limit:g} {unit}")] if limit is not None else []
    u_levels += [Level(v, lab) for v, lab in known_norm_bounds(sc, rows)]
    panels = [Panel("pointing error (arcsec)" if attitude else "max |position error| (m)", log_y=True,
                    levels=err_levels)]
    estimator = any("control_err_arcsec" in r.telemetry for r in runs.values())
    if estimator:
        panels.append(Panel("control error (arcsec)", log_y=True))
    panels.append(Panel(f"|{'torque' if attitude else 'force'} command| ({unit})", log_y=True, levels=u_levels))
    wheels = any(any(c.startswith("wheel_speed_true_") for c in r.telemetry.columns) for r in runs.values())
    if wheels:
        w = sc.effectors.get("wheels")
        sl = w.speed_limit_rad_s[0] if w is not None else None
        panels += [Panel("max |wheel speed| (rad/s)", levels=[Level(sl, f"speed limit {sl:g} rad/s")] if sl else []),
                   Panel("|H| total (N m s)")]
    traces = []
    for i, (name, run) in enumerate(runs.items()):
        df = run.telemetry
        k = run_report.stride(len(df), max_points)
        t = run_report.col(df, "t_s", k)
        color = _color(i)
        if attitude:
            err = run_report.col(df, "pointing_err_arcsec", k)
        else:
            err = np.max(np.abs(np.stack([run_report.col(df, f"pos_true_{a}_m", k) for a in "xyz"], 1)), axis=1)
        traces.append(Trace(name, t, err, 0, group=name, color=color))
        p = 1
        if estimator:
            if "control_err_arcsec" in df:
                traces.append(Trace(f"{name} control error", t, run_report.col(df, "control_err_arcsec", k), p,
                                    group=name, color=color))
            p += 1
        u = np.stack([run_report.col(df, f"{'torque_cmd' if attitude else 'force_cmd'}_{a}_{'nm' if attitude else 'n'}", k)
                      for a in "xyz"], 1)
        traces.append(Trace(f"{name} |u|", t, np.linalg.norm(u, axis=1), p, group=name, color=color))
        if wheels:
            ws = [c for c in df.columns if c.startswith("wheel_speed_true_")]
            if ws:
                sp = np.max(np.abs(np.stack([run_report.col(df, c, k) for c in ws], 1)), axis=1)
                h = np.stack([run_report.col(df, f"h_total_true_{a}_nms", k) for a in "xyz"], 1)
                traces += [Trace(f"{name} max |wheel speed|", t, sp, p + 1, group=name, color=color),
                           Trace(f"{name} |H|", t, np.linalg.norm(h, axis=1), p + 2, group=name, color=color)]
    return Chart(f"{sc.id}: every law", "t (s)", panels, traces,
                 note="Click a law in the legend to hide or show all its traces; drag to zoom, every panel follows.")


_PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b", "#e377c2", "#7f7f7f", "#bcbd22",
            "#17becf", "#393b79", "#637939")


def _color(i: int) -> str:
    return _PALETTE[i % len(_PALETTE)]


def compare_document(folder: Path, max_points: int = run_report.MAX_POINTS) -> Document:
    folder = Path(folder)
    plan, rows = read_rows(folder)
    ov = scenario_opts.overrides(plan.get("sets"), None, None, plan.get("limit"), plan.get("guidance"))
    sc = load(plan["scenario"], ov)
    runs = {}
    for r in rows:
        if r.metrics is not None and (r.out_dir / "run.json").is_file():
            try:
                runs[r.name] = run_report.read_run(r.out_dir)
            except run_report.ReportError:   # a run of an older version (no telemetry.parquet): in the table only
                continue
    doc = report_document(sc, rows, [], plan.get("limit"), plan.get("duration"), bound=plan.get("guidance") == "slew")
    at = next(i for i, b in enumerate(doc.blocks) if isinstance(b, Table)) + 1   # after the comparison table
    doc.blocks.insert(at, overlay_chart(sc, rows, runs, plan.get("limit"), max_points))
    cmds = [[r.name, f"`{runs[r.name].meta.get('repeat_command', '')}`" if r.name in runs else "-"] for r in rows]
    doc.add(Section("Repeat").add(Paragraph("The comparison:"), CodeBlock(repeat_command(plan), "sh"),
                                  Paragraph("Each law's run alone (each folder has its own page: `aocs report "
                                            f"{folder}/LAW --html FILE`):"),
                                  Table(["law", "repeat command"], cmds)))
    return doc
