"""`aocs compare SCENARIO`: every applicable law on the same scenario, side by side.

Each law (and each gain table of a table-based law: lqr_quat_ref and
lqr_quat_strong are two rows) runs in its own SIL run through real
processes (plant_node, fsw_node, the recorder; aocs_runner.cmd_run.execute),
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
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

EXIT_OK, EXIT_FAILED, EXIT_USAGE = 0, 1, 2


def add_arguments(p) -> None:
    p.add_argument("scenario", help="scenario id (aocs list) or path to a scenario file")
    p.add_argument("--laws", default="all", help="all (default) or a comma list, e.g. quat_pd,smc; "
                   "law:table selects one gain table, e.g. lqr_quat:lqr_quat_strong")
    p.add_argument("--limit", type=float, metavar="NM", help="per-axis actuator limit for every run (N m, or N)")
    p.add_argument("--duration", type=float, help="run length, s")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE",
                   help="scenario override for every run (repeatable)")
    p.add_argument("--json", help="also write the list of metrics here")
    p.add_argument("--out", help="output folder (default out/compare/<scenario>)")
    p.add_argument("--run-plots", action="store_true", help="also draw each run's own plots")
    p.add_argument("-q", "--quiet", action="store_true", help="no progress lines")


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
    from aocs_runner import lcmlog

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
             sets=(), run_plots=False, quiet=False, tag="") -> list[Row]:
    """One SIL run per row (must be called inside the private network namespace)."""
    from aocs_plant.scenario import load

    from aocs_runner.cmd_run import RunFailed, RunOptions, execute

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
        if not quiet:
            lim = "no limit" if limit is None else f"{limit:g} per axis"
            print(f"compare: {sc.id} {name} ({lim}{tag})", file=sys.stderr, flush=True)
        try:
            res = execute(RunOptions(scenario=scenario, law=None if law == "none" else law, limit=limit,
                                     duration=duration, sets=s, out=str(row.out_dir), label=table,
                                     plots=run_plots, quiet=True))
            row.metrics = res.metrics
            row.curves = curves_from_log(row.out_dir / "run.lcmlog", sc.kind, sc.dt)
        except RunFailed as exc:  # a process failed: record it, go on; RunAborted (a signal) stops everything
            row.error = str(exc)
            print(f"compare: {name}: FAILED: {exc}", file=sys.stderr)
        result.append(row)
    return result


# --------------------------------------------------------------------------- table
def _g(x, fmt=".3g"):
    return "-" if x is None else format(x, fmt)


def _vec(v, fmt=".3g"):
    return "-" if v is None else " ".join(format(x, fmt) for x in v)


def _yes(b):
    return "-" if b is None else ("yes" if b else "NO")


def table_rows(rows: list[Row], kind: str) -> tuple[list[str], list[list[str]]]:
    if kind == "attitude":
        head = ["law", "limit N m", "final max as", "per axis as", "qe_arcsec max", "0.3 as", "0.05 as",
                "settle s", "max abs u_i N m", "max norm u N m", "effort N m s", "sat s",
                "step ns med/p99/budget", "overruns"]
    else:
        head = ["law", "limit N", "pos err max m", "per axis m", "vel err max m/s", "settle s",
                "max abs F_i N", "max norm F N", "effort N s", "sat s", "step ns med/p99/budget", "overruns"]
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
            req = pe.get("final_max")
            body.append([r.name, limit, _g(req, ".4g"), _vec(pe.get("per_axis_final_max")),
                         _vec(pe.get("qe_arcsec_final_max")),
                         _yes(None if req is None else req <= 0.3), _yes(None if req is None else req <= 0.05),
                         settle, _vec(m["max_abs_torque_nm"]), _g(m["max_torque_norm_nm"], ".4g"),
                         _g(m["effort"], ".4g"), sat, timing, str(tm["overruns"])])
        else:
            pe = m["position_error_m"] or {}
            body.append([r.name, limit, _g(pe.get("final_max"), ".4g"), _vec(pe.get("per_axis_final_max")),
                         _g(pe.get("velocity_final_max_m_s"), ".3g"), settle, _vec(m["max_abs_force_n"]),
                         _g(m["max_force_norm_n"], ".4g"), _g(m["effort"], ".4g"), sat, timing,
                         str(tm["overruns"])])
    return head, body


def text_table(head, body) -> str:
    widths = [max(len(h), *(len(b[i]) for b in body)) if body else len(h) for i, h in enumerate(head)]
    fmt = lambda r: "  ".join(f"{c:<{w}}" for c, w in zip(r, widths)).rstrip()  # noqa: E731
    return "\n".join([fmt(head), fmt(["-" * w for w in widths])] + [fmt(b) for b in body])


def md_table(head, body) -> str:
    lines = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    lines += ["| " + " | ".join(b) + " |" for b in body]
    return "\n".join(lines)


# --------------------------------------------------------------------------- plots
def overlay_plots(rows: list[Row], out: Path, title: str, kind: str, prefix: str = "",
                  requirement=None, goal=None, limit=None) -> list[Path]:
    """Pointing (or position) error of every row on one log plot, and the command norms."""
    from aocs import plots as P

    plt = P._plt()
    out.mkdir(parents=True, exist_ok=True)
    ok = [r for r in rows if r.curves]
    files = []
    ylabel = "true angle 2 asin|qe_vec| (arcsec)" if kind == "attitude" else "max |position error| (m)"
    fig, ax = plt.subplots(figsize=(6.4, 3.4))
    for r in ok:
        ax.semilogy(r.curves["t"], np.maximum(r.curves["err"], 1e-9), lw=0.9, label=r.name)
    if requirement is not None:
        ax.axhline(requirement, color="red", ls="--", lw=0.8, label=f"requirement {requirement:g}")
    if goal is not None:
        ax.axhline(goal, color="green", ls="--", lw=0.8, label=f"goal {goal:g}")
    ax.set_title(f"{title}: {'pointing' if kind == 'attitude' else 'position'} error", fontsize=9)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel, fontsize=8)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, loc="upper right", ncol=2)
    files.append(_save(plt, fig, out / f"{prefix}{'pointing_error' if kind == 'attitude' else 'position_error'}.png"))

    fig, ax = plt.subplots(figsize=(6.4, 3.0))
    for r in ok:
        u = r.curves["u_norm"]
        if u.size:
            ax.semilogy(r.curves["t_cmd"], np.maximum(u, 1e-9), lw=0.8, label=r.name)
    if limit is not None:
        ax.axhline(limit * np.sqrt(3.0), color="red", ls=":", lw=0.8, label=f"sqrt(3) x axis limit {limit:g}")
    unit = "N m" if kind == "attitude" else "N"
    ax.set_title(f"{title}: commanded {'torque' if kind == 'attitude' else 'force'} norm", fontsize=9)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(f"|u| ({unit})", fontsize=8)
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=6, loc="upper right", ncol=2)
    files.append(_save(plt, fig, out / f"{prefix}{'torque_norm' if kind == 'attitude' else 'force_norm'}.png"))
    return files


def _save(plt, fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=72)
    plt.close(fig)
    return path


# --------------------------------------------------------------------------- report
def report_md(sc, rows: list[Row], plots: list[Path], limit=None, duration=None) -> str:
    head, body = table_rows(rows, sc.kind)
    lim = "reference actuator (no limit)" if limit is None else f"actuator limit {limit:g} per axis"
    dur = f"{duration:g} s" if duration else f"{sc.duration_s:g} s"
    parts = [f"# aocs compare: {sc.id}", "",
             f"{sc.description}", "", f"Reference: {sc.reference}", "",
             f"{len(rows)} SIL runs (each its own plant_node + fsw_node processes, lockstep), {lim}, {dur}, "
             f"{sc.control_rate_hz:g} Hz. Metrics from each run's LCM log (docs/sil.md).", "",
             md_table(head, body), ""]
    if sc.kind == "attitude":
        w = sc.metrics.window_s
        parts += [f"final max = max of the true pointing angle 2 asin|qe_vec| over the last {w:g} s; per axis = "
                  "max |2 qe_i|; qe_arcsec = max |qe_i| (the IRASSI report's figure, half the per-axis angle); "
                  "0.3 as / 0.05 as: final max within the IRASSI requirement / goal (true angle); "
                  "sat s = time the command was saturated; step time of the executive against the law's budget.",
                  ""]
    else:
        parts += [f"pos err max = max position error component over the last {sc.metrics.window_s:g} s.", ""]
    if sc.settle:
        crit = {k: v for k, v in vars(sc.settle).items() if v is not None} if hasattr(sc.settle, "__dict__") else {}
        if crit:
            parts += ["settled when " + ", ".join(f"{k} = {v:g}" for k, v in crit.items())
                      + " from then to the end of the run.", ""]
    from . import cmd_results

    parts += cmd_results.steady_state_section(sc, rows)
    for r in rows:
        if r.error:
            parts += [f"**{r.name} FAILED**: {r.error}", ""]
    for p in plots:
        parts += [f"![{p.stem}]({p.name})", ""]
    return "\n".join(parts)


def compare(scenario: str, out: Path, *, laws="all", limit=None, duration=None, sets=(), run_plots=False,
            quiet=False) -> tuple[object, list[Row], list[Path]]:
    from aocs_plant.scenario import load

    from aocs_runner import scenario_opts

    ov = scenario_opts.overrides(sets, None, None, limit)  # duration: per run (cmd_run adapts the window)
    sc = load(scenario, ov)
    rows = run_rows(scenario, variants(sc, laws), out, limit=limit, duration=duration, sets=sets,
                    run_plots=run_plots, quiet=quiet)
    plots = overlay_plots(rows, out, sc.id + ("" if limit is None else f", limit {limit:g}"), sc.kind,
                          requirement=sc.metrics.requirement_arcsec if sc.kind == "attitude" else None,
                          goal=sc.metrics.goal_arcsec if sc.kind == "attitude" else None, limit=limit)
    ms = [dict(r.metrics, row=r.name, table=r.table) if r.metrics else {"row": r.name, "error": r.error}
          for r in rows]
    (out / "compare.json").write_text(json.dumps(ms, indent=1) + "\n")
    (out / "report.md").write_text(report_md(sc, rows, plots, limit, duration))
    return sc, rows, plots


def run(args) -> int:
    from aocs_plant.scenario import ScenarioError

    from aocs_runner import fsw_config, netns, orchestrate, paths

    netns.reexec_in_netns(paths.self_argv())
    out = Path(args.out) if args.out else Path("out") / "compare" / Path(args.scenario).stem
    out.mkdir(parents=True, exist_ok=True)
    try:
        sc, rows, plots = compare(args.scenario, out, laws=args.laws, limit=args.limit, duration=args.duration,
                                  sets=args.set, run_plots=args.run_plots, quiet=args.quiet)
    except (ScenarioError, ValueError, fsw_config.ConfigError, paths.SetupError, netns.NetnsError) as exc:
        print(f"aocs compare: error: {exc}", file=sys.stderr)
        return EXIT_USAGE
    except orchestrate.RunAborted as exc:
        print(f"aocs compare: aborted: {exc}", file=sys.stderr)
        return EXIT_FAILED
    if args.json:
        Path(args.json).parent.mkdir(parents=True, exist_ok=True)
        Path(args.json).write_text((out / "compare.json").read_text())
    head, body = table_rows(rows, sc.kind)
    print(f"{sc.id}: {len(rows)} laws" + ("" if args.limit is None else f", limit {args.limit:g} per axis"))
    print(text_table(head, body))
    print(f"report: {out / 'report.md'}; plots: {', '.join(p.name for p in plots)}")
    return EXIT_FAILED if any(r.error for r in rows) else EXIT_OK
