"""The campaign's interactive page (`aocs campaign --html FILE`, `aocs report CAMPAIGN_FOLDER --html FILE`), built from
the folder (campaign.json, results.parquet, runs/NNNNNN.json): report.md's statistics (requirements with their
Wilson intervals, the metrics' percentiles, the runs that did not pass) and, instead of the PNG plots, interactive
figures: the empirical CDF of each key metric (the requirement and goal marked), each key metric against each
dispersed input, and the pointing error's envelope over the runs in time. Every point of a CDF or a scatter plot
is a run: hovering shows its index, clicking shows the `aocs run` command that repeats it.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from aocs_plant.scenario import load
from aocs_report import run_report
from aocs_report.document import Chart, Document, Level, Mark, Panel, Section, Trace

from . import execute
from .plan import Campaign
from .report import KEY_METRICS, _sets, report_document

#: dispersed inputs drawn against the key metrics (the first ones of the campaign)
SCATTER_INPUTS_MAX = 6
#: key metrics drawn against the inputs
SCATTER_METRICS = ("m.pointing_error_arcsec.final_max", "m.settle_time_s")
#: grid of the pointing-error envelope, points
ENVELOPE_POINTS = 500


def read_table(folder: Path):
    import pyarrow.parquet as pq  # deferred: only a campaign page needs it

    f = folder / "results.parquet"
    if not f.is_file():
        raise run_report.ReportError(f"{f}: missing (aocs campaign writes it)")
    return pq.read_table(f).to_pandas()


def links(df) -> list[str]:
    """The repeat command of each run, indexed by the run's index."""
    n = int(df["index"].max()) + 1 if len(df) else 0
    out = [""] * n
    for i, c in zip(df["index"], df["repeat_command"]):
        out[int(i)] = str(c or "")
    return out


def _label(col: str) -> str:
    return dict(KEY_METRICS).get(col, col[3:] if col.startswith(("m.", "in.")) else col)


def cdf_chart(df, col: str, sc, commands: list[str]) -> Chart | None:
    if col not in df:
        return None
    v = df[col].to_numpy(dtype=float)
    ok = np.isfinite(v)
    if not ok.any():
        return None
    order = np.argsort(v[ok], kind="stable")
    x = v[ok][order]
    ids = df["index"].to_numpy()[ok][order]
    y = np.arange(1, x.size + 1) / x.size
    marks = []
    if col.startswith("m.pointing_error_arcsec"):
        if sc.metrics.requirement_arcsec is not None:
            marks.append(Mark(sc.metrics.requirement_arcsec, f"requirement {sc.metrics.requirement_arcsec:g}"))
        if sc.metrics.goal_arcsec is not None:
            marks.append(Mark(sc.metrics.goal_arcsec, f"goal {sc.metrics.goal_arcsec:g}"))
    return Chart(f"CDF: {_label(col)}", _label(col), [Panel("fraction of runs <= x")],
                 [Trace(f"{x.size} runs", x, y, style="markers", ids=ids)], marks, links=commands,
                 note=f"{int((~ok).sum())} runs without this figure." if (~ok).any() else "")


def scatter_chart(df, metric: str, inp: str, commands: list[str]) -> Chart | None:
    if metric not in df or inp not in df:
        return None
    traces = []
    for status in ("passed", "failed", "error"):
        sel = (df["status"] == status).to_numpy()
        if sel.any():
            traces.append(Trace(f"{status} runs", df[inp].to_numpy(dtype=float)[sel],
                                df[metric].to_numpy(dtype=float)[sel], style="markers",
                                ids=df["index"].to_numpy()[sel]))
    if not traces:
        return None
    return Chart(f"{_label(metric)} against {inp[3:]}", inp[3:], [Panel(_label(metric))], traces, links=commands)


def envelope_chart(rows: list[dict], sc) -> Chart | None:
    """min, median, 95th percentile and max over the runs of the pointing error at each time (each run's
    decimated history, runs/NNNNNN.json "series", interpolated onto one grid)."""
    series = [r["series"] for r in rows if r.get("series")]
    if not series:
        return None
    t_end = min(s["t_s"][-1] for s in series)
    grid = np.linspace(0.0, t_end, ENVELOPE_POINTS)
    e = np.stack([np.interp(grid, s["t_s"], s["pointing_error_arcsec"]) for s in series])
    traces = [Trace(name, grid, f(e), dash=d) for name, f, d in (
        ("max over runs", lambda a: a.max(axis=0), "dot"), ("95th percentile", lambda a: np.percentile(a, 95, axis=0), "dash"),
        ("median", lambda a: np.median(a, axis=0), "solid"), ("min over runs", lambda a: a.min(axis=0), "dot"))]
    lv = []
    if sc.metrics.requirement_arcsec is not None:
        lv.append(Level(sc.metrics.requirement_arcsec, f"requirement {sc.metrics.requirement_arcsec:g} arcsec"))
    if sc.metrics.goal_arcsec is not None:
        lv.append(Level(sc.metrics.goal_arcsec, f"goal {sc.metrics.goal_arcsec:g} arcsec"))
    return Chart(f"pointing error over {len(series)} runs", "t (s)", [Panel("pointing error (arcsec)", True, lv)],
                 traces, note=f"Each run's history decimated to at most 500 points, then interpolated onto "
                              f"{ENVELOPE_POINTS} times.")


def campaign_document(folder: Path) -> Document:
    folder = Path(folder)
    doc = run_report.read_json(folder / "campaign.json")
    c = doc["campaign"]
    camp = Campaign(c["scenario"], c["law"], c["runs"], c["seed"], c["sets"], c["disperse"])
    sc = load(c["scenario"], _sets(camp))
    df = read_table(folder)
    page = report_document(doc, sc)
    page.blocks = [b for b in page.blocks if not (isinstance(b, Section) and b.title == "Plots")]
    commands = links(df)
    charts = [cdf_chart(df, col, sc, commands) for col, _ in KEY_METRICS]
    inputs = [k for k in df.columns if k.startswith("in.")][:SCATTER_INPUTS_MAX]
    charts += [scatter_chart(df, m, i, commands) for m in SCATTER_METRICS for i in inputs]
    charts.append(envelope_chart(execute.read_rows(folder, c["runs"]), sc))
    page.add(Section("Interactive figures").add(*(ch for ch in charts if ch is not None)))
    return page
