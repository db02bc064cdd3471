"""One run's page (`aocs run --html FILE`, `aocs report RUN_FOLDER --html FILE`): built from what the run left in
its folder (run.json, metrics.json, telemetry.parquet), so a run can be reported again at any time.

    doc = run_document(Path("out/irassi_rw-quat_pid"))
    Path("r.html").write_text(html.render(doc))

The page: the verdict and every metric (aocs_analysis.run_metrics.table_rows, the table `aocs run` prints),
one interactive chart on the run's time axis (pointing error, and with a filter the control error and the
knowledge error with the filter's 3 sigma; body torques, wheel torques, wheel speeds and momentum with their
limits; modes, with the run's events and its settle time marked), the scenario file with its overrides and the
command that repeats the run. The chart shows at most MAX_POINTS samples per series (every k-th tick, said
under it); telemetry.parquet has them all.
"""
from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aocs_analysis import run_metrics, telemetry, verdict
from aocs_plant.scenario import ScenarioError, load

from .document import Chart, CodeBlock, Document, Level, Mark, Panel, Paragraph, Section, Table, Trace

#: samples per series drawn (the chart's decimation; a 1000 s run at 10 Hz is drawn every 4th tick)
MAX_POINTS = 2500
AXES = ("x", "y", "z")


class ReportError(ValueError):
    """A folder that is not a run, compare or campaign folder, or misses a file: one line naming it."""


@dataclass
class RunFolder:
    """What a run left: run.json, metrics.json and the telemetry table."""
    path: Path
    meta: dict
    metrics: dict
    telemetry: object        # pandas.DataFrame

    @property
    def title(self) -> str:
        m = self.metrics
        return f"{m['scenario']} / {m['law']}" + (f" ({m['label']})" if m.get("label") else "")


def read_json(path: Path) -> dict:
    try:
        return json.loads(path.read_text())
    except FileNotFoundError:
        raise ReportError(f"{path}: missing") from None
    except (OSError, ValueError) as exc:
        raise ReportError(f"{path}: not readable JSON ({exc})") from None


def read_run(folder: Path) -> RunFolder:
    folder = Path(folder)
    meta = read_json(folder / "run.json")
    metrics = read_json(folder / "metrics.json")
    tel = folder / meta.get("telemetry", "telemetry.parquet")
    if not tel.is_file():
        raise ReportError(f"{tel}: missing (a run of this version writes it beside run.lcmlog)")
    try:
        df = telemetry.read(tel)
    except Exception as exc:  # noqa: BLE001 - pyarrow's errors for a damaged file are many
        raise ReportError(f"{tel}: not a readable Parquet table ({type(exc).__name__}: {exc})") from None
    return RunFolder(folder, meta, metrics, df)


def scenario_of(run: RunFolder):
    """The scenario as flown (its file and the run's overrides), or None when the file is gone."""
    try:
        return load(run.meta["scenario_path"], run.meta.get("overrides") or {})
    except (ScenarioError, OSError, KeyError, ValueError):
        return None


def stride(n: int, max_points: int = MAX_POINTS) -> int:
    return max(1, int(np.ceil(n / max_points)))


def col(df, name: str, k: int) -> np.ndarray:
    return np.asarray(df[name].to_numpy(dtype=float))[::k]


def events(meta: dict) -> list[Mark]:
    """The run's scheduled events (--event T:WHAT) as marks."""
    out = []
    for e in meta.get("events") or []:
        t, _, what = str(e).partition(":")
        try:
            out.append(Mark(float(t), f"event {what}"))
        except ValueError:
            continue
    return out


def marks(run: RunFolder) -> list[Mark]:
    m = run.metrics
    out = events(run.meta)
    if m.get("settle_time_s") is not None:
        out.append(Mark(m["settle_time_s"], f"settled {m['settle_time_s']:.1f} s"))
    g = m.get("guidance") or {}
    if g.get("profile_end_s") is not None:
        out.append(Mark(g["profile_end_s"], f"slew profile end {g['profile_end_s']:.1f} s"))
    return out


def _sym(value, label: str) -> list[Level]:
    return [Level(value, f"+{label}"), Level(-value, f"-{label}")]


def time_chart(run: RunFolder, sc, max_points: int = MAX_POINTS) -> Chart:
    """Every series of the run on one time axis (module docstring)."""
    df, m = run.telemetry, run.metrics
    k = stride(len(df), max_points)
    t = col(df, "t_s", k)
    panels: list[Panel] = []
    traces: list[Trace] = []

    def panel(p: Panel) -> int:
        panels.append(p)
        return len(panels) - 1

    if m["kind"] == "attitude":
        pe = m.get("pointing_error_arcsec") or {}
        lv = []
        if pe.get("requirement_arcsec") is not None:
            lv.append(Level(pe["requirement_arcsec"], f"requirement {pe['requirement_arcsec']:g} arcsec"))
        if pe.get("goal_arcsec") is not None:
            lv.append(Level(pe["goal_arcsec"], f"goal {pe['goal_arcsec']:g} arcsec"))
        st = (m.get("settle_criterion") or {}).get("criteria") or {}
        if st.get("pointing_arcsec_max") is not None:
            lv.append(Level(st["pointing_arcsec_max"], f"settle threshold {st['pointing_arcsec_max']:g} arcsec"))
        p = panel(Panel("error (arcsec)", log_y=True, levels=lv))
        traces.append(Trace("pointing error (true vs target)", t, col(df, "pointing_err_arcsec", k), p))
        if "control_err_arcsec" in df:
            traces.append(Trace("control error (estimate vs target)", t, col(df, "control_err_arcsec", k), p))
            p = panel(Panel("knowledge error (arcsec)", y_range=steady_range(df, k)))
            for i, a in enumerate(AXES):
                s = col(df, f"est_sigma_att_{a}_arcsec", k)
                traces += [Trace(f"knowledge error {a}", t, col(df, f"knowledge_err_{a}_arcsec", k), p, group=a,
                                 color=COLORS[i]),
                           Trace(f"+3 sigma {a} (filter)", t, 3.0 * s, p, dash="dash", group=a, color=COLORS[i]),
                           Trace(f"-3 sigma {a} (filter)", t, -3.0 * s, p, dash="dash", group=a, color=COLORS[i])]
        lim = m.get("limits") or {}
        p = panel(Panel("body torque command (N m)",
                        levels=_sym(lim["axis"], f"axis limit {lim['axis']:g} N m") if lim.get("axis") else ()))
        traces += [Trace(f"torque command {a}", t, col(df, f"torque_cmd_{a}_nm", k), p) for a in AXES]
    else:
        p = panel(Panel("position error (m)"))
        traces += [Trace(f"position {a}", t, col(df, f"pos_true_{a}_m", k), p) for a in AXES]
        lim = m.get("limits") or {}
        p = panel(Panel("force command (N)",
                        levels=_sym(lim["axis"], f"axis limit {lim['axis']:g} N") if lim.get("axis") else ()))
        traces += [Trace(f"force command {a}", t, col(df, f"force_cmd_{a}_n", k), p) for a in AXES]
    wheels = sc.effectors.get("wheels") if sc is not None else None
    n_w = sum(1 for c in df.columns if c.startswith("wheel_speed_true_"))
    if n_w:
        tl = wheels.torque_limit_nm[0] if wheels is not None else None
        sl = wheels.speed_limit_rad_s[0] if wheels is not None else None
        p = panel(Panel("wheel motor torque command (N m)", levels=_sym(tl, f"torque limit {tl:g} N m") if tl else ()))
        traces += [Trace(f"wheel {i} torque command", t, col(df, f"wheel_torque_cmd_{i}_nm", k), p)
                   for i in range(1, n_w + 1)]
        p = panel(Panel("wheel speed (rad/s)", levels=_sym(sl, f"speed limit {sl:g} rad/s") if sl else ()))
        traces += [Trace(f"wheel {i} speed", t, col(df, f"wheel_speed_true_{i}_rad_s", k), p)
                   for i in range(1, n_w + 1)]
        cap = wheels.momentum_capacity_nms()[0] if wheels is not None else None
        p = panel(Panel("momentum (N m s)", levels=[Level(cap, f"capacity of one wheel {cap:g} N m s")] if cap else ()))
        h = np.stack([col(df, f"h_total_true_{a}_nms", k) for a in AXES], axis=1)
        traces.append(Trace("|H| total (body + wheels)", t, np.linalg.norm(h, axis=1), p))
        traces += [Trace(f"wheel {i} momentum", t, col(df, f"wheel_momentum_true_{i}_nms", k), p, dash="dot")
                   for i in range(1, n_w + 1)]
    p = panel(Panel("mode / flags"))
    traces += [Trace("mode (0 standby, 1 nominal, 2 safe)", t, col(df, "mode", k), p, style="steps"),
               Trace("saturated (1 = yes)", t, col(df, "saturated", k), p, style="steps", dash="dot")]
    note = ((f"Every {k}-th control tick drawn" if k > 1 else "Every control tick drawn")
            + f" ({len(t)} of {len(df)} rows of telemetry.parquet"
            + (f", itself every {run.meta.get('telemetry_decimate')}-th tick" if (run.meta.get('telemetry_decimate') or 1) > 1
               else "") + "). Drag to zoom (every panel follows), double-click to reset; click a legend entry to "
            "hide it." + (" The knowledge error is first shown over the range of the last half of the run (the "
                          "filter's start is larger): the autoscale button shows all." if "control_err_arcsec" in df
                          else ""))
    return Chart(f"{run.title}: time series", "t (s)", panels, traces, marks(run), note=note)


COLORS = ("#1f77b4", "#ff7f0e", "#2ca02c")


def steady_range(df, k: int) -> tuple[float, float] | None:
    """The knowledge panel's first range: +-1.2 x the largest |error| and 3 sigma over the last half of the run (as
    estimation_plots: the filter's start, with its initial sigma, would flatten the rest; autoscale shows it)."""
    half = len(df) // 2
    cols = [f"knowledge_err_{a}_arcsec" for a in AXES] + [f"est_sigma_att_{a}_arcsec" for a in AXES]
    v = np.array(df[cols].to_numpy(dtype=float)[half:])   # a copy: pandas hands out read-only views
    v[:, 3:] *= 3.0
    top = float(np.nanmax(np.abs(v))) if np.isfinite(v).any() else 0.0
    return (-1.2 * top, 1.2 * top) if top > 0.0 else None


def verdict_table(m: dict) -> Table:
    v = m.get("verdict") or {"passed": None, "failures": [], "allowed": []}
    failed = {f["check"]: f["reason"] for f in v.get("failures") or []}
    rows = []
    for c in verdict.CHECKS:
        if c in failed:
            rows.append([c, "allowed" if c in v.get("allowed", []) else "FAILED", failed[c]])
        else:
            rows.append([c, "passed", ""])
    return Table(["check", "result", "reason"], rows)


def scenario_section(run: RunFolder) -> Section:
    meta = run.meta
    sec = Section("Scenario")
    path = Path(meta.get("scenario_path", ""))
    ov = meta.get("overrides") or {}
    sec.add(Paragraph(f"`{meta.get('scenario')}` from `{path.name}`, law `{meta.get('law')}`, {meta.get('mode')}, "
                      f"flight computer `{meta.get('target')}`, {meta.get('n_steps')} steps of {meta.get('dt'):g} s."),
            Paragraph("Overrides: " + (", ".join(f"`{k} = {v}`" for k, v in ov.items()) or "none")
                      + "; events: " + (", ".join(f"`{e}`" for e in meta.get("events") or []) or "none") + "."))
    if path.is_file():
        sec.add(CodeBlock(path.read_text().rstrip("\n"), "toml"))
    return sec


def repeat_section(run: RunFolder) -> Section:
    meta = run.meta
    sec = Section("Repeat this run")
    cmd = meta.get("repeat_command")
    if cmd:
        sec.add(Paragraph("In lockstep the same command gives the same log and metrics:"), CodeBlock(cmd, "sh"))
    if meta.get("command") and meta.get("command") != cmd:
        sec.add(Paragraph("As it was started:"), CodeBlock(meta["command"], "sh"))
    sec.add(Paragraph(f"Files of the run in `{run.path}`: `{meta.get('log', 'run.lcmlog')}` (the LCM log), "
                      f"`metrics.json`, `run.json`, `{meta.get('telemetry', 'telemetry.parquet')}` (every decoded "
                      "series, units in the column names)."))
    return sec


def run_document(folder: Path, max_points: int = MAX_POINTS) -> Document:
    run = read_run(folder)
    sc = scenario_of(run)
    m = run.metrics
    v = m.get("verdict") or {}
    doc = Document(f"aocs run: {run.title}")
    if sc is not None:
        doc.add(Paragraph(sc.description))
    doc.add(Paragraph("**Verdict: " + ("passed" if v.get("passed") else "FAILED") + "**"
                      + (f" ({verdict.summary(v)})" if v and not v.get("passed") else "")))
    doc.add(time_chart(run, sc, max_points))
    doc.add(Section("Verdict").add(verdict_table(m)),
            Section("Metrics").add(Table(["metric", "value"], [list(r) for r in run_metrics.table_rows(m)])),
            scenario_section(run), repeat_section(run))
    return doc
