"""The timeline of a mission day (docs/spec.md 5.11): one PNG, day_timeline.png, four panels over the run in hours.

1. wheel speeds with their limits (rad/s);
2. the wheels' stored momentum |h_w| (N m s) with the unloading thresholds and one wheel's capacity, the
   periods of unloading shaded and each dump's start marked;
3. the true pointing angle (arcsec, log scale) with every hold and every target pass shaded, each one's
   maximum drawn across it (green: met, red: missed; holds judged on the sensors' figure also their rms,
   dotted, and the figure; a pass's bar widened to 0.1 h to be seen on a day's
   axis, the target's name above it) and the requirement;
4. the flight software's mode, and the unloading's cumulative propellant (kg) or dipole integral (A m^2 s).

    timeline(series, metrics, out_path, title)          from run_metrics.compute's (metrics, series)
    python -m aocs_runner.day_timeline OUT_DIR           redraws OUT_DIR/day_timeline.png from its log

DPI and sizes: plots.py's house style at 160 dpi.
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from . import plots

FILE = "day_timeline.png"
HOURS = 3600.0


def applies(metrics: dict) -> bool:
    """A run with an observation plan, target passes or momentum management gets the timeline."""
    mom = metrics.get("momentum") or {}
    return (metrics.get("holds") is not None or metrics.get("passes") is not None
            or mom.get("policy", "none") != "none")


def timeline(series: dict, metrics: dict, out_path: Path, title: str) -> Path:
    plt = plots._plt()
    fig, axes = plt.subplots(4, 1, figsize=(plots.FIG_WIDTH_IN * 1.5, 11.0), sharex=True)
    w = series.get("wheels") or {}
    th = np.asarray(series["t"], float) / HOURS
    ax = axes[0]
    if w:
        tw = np.asarray(w["t"], float) / HOURS
        for i in range(w["n"]):
            ax.plot(tw, w["speed"][:, i], lw=0.8, label=f"wheel {i}")
        lim = max(w["speed_limit"])
        ax.axhline(lim, color="red", ls="--", lw=1.0, label=f"speed limit +-{lim:g} rad/s")
        ax.axhline(-lim, color="red", ls="--", lw=1.0)
    ax.set_ylabel("wheel speed (rad/s)", fontsize=plots.LABEL_PT)
    ax.set_title(f"{title}: the day", fontsize=plots.TITLE_PT)
    plots.legend(ax, ncol=3)

    ax = axes[1]
    mom = metrics.get("momentum") or {}
    if w:
        ax.plot(tw, w["h_wheels_norm"], lw=1.0, color="tab:blue", label="|h_w| = |sum Js g Omega|")
        if mom.get("h_start_nms") is not None:
            ax.axhline(mom["h_start_nms"], color="tab:orange", ls="--", lw=1.0,
                       label=f"start unloading {mom['h_start_nms']:g} N m s")
            ax.axhline(mom["h_stop_nms"], color="tab:green", ls="--", lw=1.0,
                       label=f"stop {mom['h_stop_nms']:g} N m s")
        cap = (mom.get("capacity_nms") or [None])[0]
        if cap is not None:
            ax.axhline(cap, color="red", ls="--", lw=1.0, label=f"one wheel's capacity {cap:g} N m s")
    un = series.get("unloading")
    if un is not None:
        tu, flag = np.asarray(un["t"], float) / HOURS, np.asarray(un["flag"], bool)
        _shade(ax, tu, flag, "tab:orange", "unloading")
        starts = tu[np.flatnonzero(flag & ~np.concatenate([[False], flag[:-1]]))]
        for k, s in enumerate(starts):
            ax.axvline(s, color="tab:orange", lw=0.8, label="dump start" if k == 0 else None)
    ax.set_ylabel("momentum (N m s)", fontsize=plots.LABEL_PT)
    plots.legend(ax, ncol=2)

    ax = axes[2]
    ang = np.maximum(np.asarray(series["true_angle"], float), plots.LOG_FLOOR)
    ax.semilogy(th, ang, lw=0.6, color="tab:blue", label="true pointing angle")
    req = (metrics.get("pointing_error_arcsec") or {}).get("requirement_arcsec")
    for k, h in enumerate(metrics.get("holds") or []):
        a, b = h["hold_start_s"] / HOURS, h["hold_end_s"] / HOURS
        ax.axvspan(a, b, color="tab:green", alpha=0.12, lw=0, label="hold" if k == 0 else None)
        if h["pointing_max_arcsec"] is not None:
            ok = h["meets_requirement"] is not False
            on_rms = (h.get("requirement") or {}).get("on") == "rms"
            ax.plot([a, b], [max(h["pointing_max_arcsec"], plots.LOG_FLOOR)] * 2, lw=2.0,
                    color="tab:green" if ok or on_rms else "red", label="hold max" if k == 0 else None)
            if on_rms:      # judged on the rms (the sensors' figure): its bar in the verdict's colour
                ax.plot([a, b], [max(h["pointing_rms_arcsec"], plots.LOG_FLOOR)] * 2, lw=2.0, ls=":",
                        color="tab:olive" if ok else "red", label="hold rms" if k == 0 else None)
    held_to = next((h["requirement"] for h in metrics.get("holds") or [] if h.get("requirement")), None)
    if held_to is not None and held_to["basis"] == "sensors":
        ax.axhline(held_to["limit_arcsec"], color="tab:olive", ls="--", lw=1.0,
                   label=f"sensors' figure (rms) {held_to['limit_arcsec']:.3g} arcsec")
    _draw_passes(ax, metrics.get("passes") or [])
    if req is not None:
        ax.axhline(req, color="red", ls="--", lw=1.0, label=f"requirement {req:g} arcsec")
    ax.set_ylabel("pointing (arcsec)", fontsize=plots.LABEL_PT)
    plots.clip_note(ax)
    plots.legend(ax, ncol=2)

    ax = axes[3]
    tc = np.asarray(series["t_cmd"], float) / HOURS
    ax.step(tc, np.asarray(series["mode"]), where="post", lw=1.0, color="tab:gray", label="mode")
    ax.set_yticks([0, 1, 2], ["standby", "nominal", "safe"])
    ax.set_ylabel("mode", fontsize=plots.LABEL_PT)
    if un is not None and un.get("cumulative") is not None:
        ax2 = ax.twinx()
        ax2.plot(tu, un["cumulative"], lw=1.2, color="tab:orange", label=un["cumulative_label"])
        ax2.set_ylabel(un["cumulative_label"], fontsize=plots.LABEL_PT)
        ax2.legend(fontsize=plots.LEGEND_PT, loc="lower right")
    ax.set_xlabel("t (h)", fontsize=plots.LABEL_PT)
    plots.legend(ax)
    for a in axes:
        a.grid(True, alpha=0.3)
    return plots.save(fig, Path(out_path))


#: the least width a pass is drawn with on the timeline (h): a two-minute pass is a hair on a day's axis
PASS_MIN_WIDTH_H = 0.1


def _draw_passes(ax, passes: list[dict]) -> None:
    """Each target pass shaded, its maximum as a bar (green met, red missed), the target's name above it."""
    for k, p in enumerate(passes):
        a, b = p["start_s"] / HOURS, p["end_s"] / HOURS
        mid, half = 0.5 * (a + b), 0.5 * max(b - a, PASS_MIN_WIDTH_H)
        ax.axvspan(a, b, color="tab:purple", alpha=0.25, lw=0, label="target pass" if k == 0 else None)
        if p["pointing_max_arcsec"] is None:
            continue
        y = max(p["pointing_max_arcsec"], plots.LOG_FLOOR)
        ok = p["meets_requirement"] is not False
        ax.plot([mid - half, mid + half], [y, y], lw=2.5, color="tab:purple" if ok else "red",
                label="pass max" if k == 0 else None)
        ax.annotate(p["target"]["name"], (mid, y), textcoords="offset points", xytext=(0, 3 + 7 * (k % 2)),
                    ha="center", fontsize=plots.NOTE_PT, color="tab:purple" if ok else "red")


def _shade(ax, t, flag, color, label):
    """Shade the runs of flag (t, flag per sample)."""
    edges = np.flatnonzero(np.diff(np.concatenate([[0], flag.astype(np.int8), [0]])))
    for k, (a, b) in enumerate(zip(edges[::2], edges[1::2])):
        ax.axvspan(t[a], t[min(b, len(t) - 1)], color=color, alpha=0.15, lw=0, label=label if k == 0 else None)


def unloading_series(log, scenario) -> dict | None:
    """The unloading flag per command, and the cumulative propellant (thrusters) or dipole integral (rods)."""
    if scenario.momentum.policy == "none" or not log.cmd["tick"].size:
        return None
    cmd, dt = log.cmd, scenario.dt
    out = {"t": cmd["tick"] * dt, "flag": np.asarray(cmd["unloading"]) != 0, "cumulative": None}
    if scenario.momentum.policy == "thrusters":
        thr = scenario.effectors["thrusters"]
        on = np.asarray(cmd["thruster_on_s"], float)[:, :thr.n]
        thrust = np.broadcast_to(np.asarray(thr.thrust_n, float), (thr.n,))
        out["cumulative"] = np.cumsum(on @ thrust) / (thr.isp_s * 9.80665)
        out["cumulative_label"] = "propellant used (kg)"
    else:
        lim = np.asarray(scenario.effectors["magnetorquers"].max_dipole_am2, float)
        m = np.clip(np.asarray(cmd["dipole_am2"], float), -lim, lim)
        out["cumulative"] = np.cumsum(np.abs(m).sum(axis=1)) * dt
        out["cumulative_label"] = "dipole integral (A m^2 s)"
    return out
