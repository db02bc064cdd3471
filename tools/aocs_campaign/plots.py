"""Campaign plots in the house style of aocs_analysis.plots (1280 px wide at 160 dpi, legends of 9 pt,
units on every axis, the requirement, goal and limit drawn where they apply):

- cdf_<metric>.png: the empirical CDF of each key metric over the runs, with the requirement and goal
  (pointing error) or the actuator limit (torque) as vertical lines;
- scatter_<metric>.png: the metric against each dispersed input, one panel per input;
- pointing_overlay.png: every run's pointing error against time (decimated to <= 500 points per run,
  log scale), the requirement and the goal, the metric window shaded.
"""
from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np

from aocs_analysis import plots as house

#: most runs drawn in the overlay (a random-free choice: the first ones by index)
OVERLAY_MAX = 1000


def _slug(col: str) -> str:
    return re.sub(r"[^A-Za-z0-9]+", "_", col.removeprefix("m.")).strip("_")


def _lines(ax, col: str, sc, vertical: bool) -> None:
    draw = ax.axvline if vertical else ax.axhline
    if col.startswith("m.pointing_error_arcsec"):
        if sc.metrics.requirement_arcsec is not None:
            draw(sc.metrics.requirement_arcsec, color="tab:red", ls="--", lw=1.2,
                 label=f"requirement {sc.metrics.requirement_arcsec:g} arcsec")
        if sc.metrics.goal_arcsec is not None:
            draw(sc.metrics.goal_arcsec, color="tab:green", ls="--", lw=1.2,
                 label=f"goal {sc.metrics.goal_arcsec:g} arcsec")
    if col in ("m.max_torque_norm_nm",) and sc.actuator.axis_limit is not None:
        lim = sc.actuator.axis_limit
        draw(lim, color="black", ls="-.", lw=1.0, label=f"axis limit {lim:g} N m")
        draw(lim * math.sqrt(3.0), color="dimgray", ls=":", lw=1.0, label=f"sqrt(3) x axis limit {lim * 3 ** 0.5:.3g} N m")


def _values(trows, col):
    v = np.array([t.get(col) if isinstance(t.get(col), float) else np.nan for t in trows], float)
    return v


def _log_ok(v) -> bool:
    f = v[np.isfinite(v)]
    return f.size > 1 and np.all(f > 0) and f.max() / f.min() > 100.0


def campaign_plots(out: Path, trows, rows, key_metrics, inputs, sc, title: str) -> list[Path]:
    paths = []
    for col, label in key_metrics:
        v = _values(trows, col)
        f = np.sort(v[np.isfinite(v)])
        if f.size == 0:
            continue
        fig, ax = house.new_axes(f"{title}: {label}, empirical CDF over {f.size} runs", "fraction of runs (-)",
                                 xlabel=label)
        ax.step(f, np.arange(1, f.size + 1) / f.size, where="post", color="tab:blue", lw=1.5,
                label=f"{f.size} runs")
        _lines(ax, col, sc, vertical=True)
        if _log_ok(f):
            ax.set_xscale("log")
        ax.set_ylim(0.0, 1.02)
        house.legend(ax)
        paths.append(house.save(fig, out / f"cdf_{_slug(col)}.png"))
        if inputs:
            paths.append(_scatter(out, trows, col, label, v, inputs, sc, title))
    p = _overlay(out, rows, sc, title)
    if p is not None:
        paths.append(p)
    return paths


def _exponent(x: np.ndarray) -> int:
    """0 for values whose largest magnitude lies in [1e-3, 1e4) (or none), else its power of ten."""
    big = float(np.max(np.abs(x))) if x.size else 0.0
    if big == 0.0 or 1e-3 <= big < 1e4:
        return 0
    return int(math.floor(math.log10(big)))


def _scatter(out, trows, col, label, v, inputs, sc, title) -> Path:
    plt = house._plt()
    n = len(inputs)
    ncol = min(3, n)
    nrow = int(math.ceil(n / ncol))
    fig, axes = plt.subplots(nrow, ncol, figsize=(house.FIG_WIDTH_IN, 2.6 * nrow + 0.6), squeeze=False)
    fig.suptitle(f"{title}: {label}\nagainst each dispersed input ({int(np.isfinite(v).sum())} runs)",
                 fontsize=house.TITLE_PT)
    f = v[np.isfinite(v)]
    # the pointing error is positive and its requirement lines sit decades below a slew's error: log
    logy = _log_ok(v) or (col.startswith("m.pointing_error_arcsec") and f.size > 0 and bool(np.all(f > 0)))
    for k, inp in enumerate(inputs):
        ax = axes[k // ncol][k % ncol]
        x = _values(trows, inp)
        ok = np.isfinite(x) & np.isfinite(v)
        # very small or large inputs in units of a power of ten named in the label (matplotlib's own offset
        # text sits on the axis label)
        e = _exponent(x[ok])
        ax.scatter(x[ok] / 10.0 ** e, v[ok], s=6, alpha=0.6, color="tab:blue", label="run")
        _lines(ax, col, sc, vertical=False)
        ax.set_xlabel(f"{inp[3:]} ({'' if e == 0 else f'x 1e{e} '}{_unit(inp)})", fontsize=house.LABEL_PT - 1)
        if k % ncol == 0:   # the short name and its unit: "pointing error (arcsec)"
            unit = label[label.rfind("("):] if "(" in label else ""
            ax.set_ylabel(f"{label.split(',')[0].split(' (')[0]} {unit}", fontsize=house.LABEL_PT - 1)
        ax.tick_params(labelsize=house.LABEL_PT - 2)
        ax.ticklabel_format(axis="x", style="plain", useOffset=False)
        ax.grid(True, alpha=0.3)
        if logy:
            ax.set_yscale("log")
        if k == 0:
            ax.legend(fontsize=house.LEGEND_PT - 1, loc="best", framealpha=0.85)
    for k in range(n, nrow * ncol):
        axes[k // ncol][k % ncol].set_visible(False)
    fig.tight_layout(rect=(0, 0, 1, 1 - 0.5 / (2.6 * nrow + 0.6)))   # room for the two-line title
    path = out / f"scatter_{_slug(col)}.png"
    fig.savefig(path, dpi=house.DPI)
    plt.close(fig)
    return path


def _unit(inp: str) -> str:
    """Unit of a dispersed scenario key, from its name (docs/scenarios.md names keys with their units)."""
    k = inp[3:]
    for pat, unit in (("inertia", "kg m^2"), ("_deg", "deg"), ("w0", "rad/s"), ("torque_nm", "N m"),
                      ("axis_limit", "N m"), ("norm_limit", "N m"), ("scale", "-"), ("_arcsec", "arcsec"),
                      ("_s", "s"), ("_m", "m"), ("_n", "N")):
        if pat in k:
            return unit
    return "scenario units"


def _overlay(out, rows, sc, title) -> Path | None:
    have = [r for r in rows if r.get("series")][:OVERLAY_MAX]
    if not have:
        return None
    fig, ax = house.new_axes(f"{title}: pointing error of {len(have)} runs (decimated)",
                             "true pointing error 2 asin|qe_vec| (arcsec)", height_in=4.8)
    for i, r in enumerate(have):
        s = r["series"]
        e = np.maximum(np.asarray(s["pointing_error_arcsec"], float), house.LOG_FLOOR)
        ax.plot(s["t_s"], e, color="tab:blue", lw=0.5, alpha=max(0.05, min(0.6, 20.0 / len(have))),
                label="runs" if i == 0 else None)
    if sc.metrics.requirement_arcsec is not None:
        ax.axhline(sc.metrics.requirement_arcsec, color="tab:red", ls="--", lw=1.2,
                   label=f"requirement {sc.metrics.requirement_arcsec:g} arcsec")
    if sc.metrics.goal_arcsec is not None:
        ax.axhline(sc.metrics.goal_arcsec, color="tab:green", ls="--", lw=1.2,
                   label=f"goal {sc.metrics.goal_arcsec:g} arcsec")
    w = sc.metrics.window_s
    ax.axvspan(sc.duration_s - w, sc.duration_s, color="gray", alpha=0.12, label=f"metric window (last {w:g} s)")
    ax.set_yscale("log")
    house.clip_note(ax)
    house.legend(ax)
    return house.save(fig, out / "pointing_overlay.png")
