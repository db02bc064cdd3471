"""PNG plots of one run (matplotlib, Agg backend), legible at full size.

run_plots(series, out_dir, title) takes the series computed from the LCM log
by aocs_analysis.run_metrics.compute and writes:

- attitude: attitude_error.png (true angle 2 asin|qe_vec|, log scale, with
  the requirement, the goal, the settle threshold and the settle time),
  rates.png (w - wd per axis), torques.png (the saturated command per axis
  with the saturation limits), step_time.png (executive step time against
  the step's budget);
- orbit: position_error.png, velocity_error.png (with the settle
  thresholds), force.png, step_time.png;
- with a reaction wheel array: wheel_speeds.png (with the speed limits) and
  momentum.png (wheel_plots; the figures in aocs_analysis.wheels).

Every figure: FIG_WIDTH_IN x DPI = 1280 px wide, legends of LEGEND_PT, units
on every axis, and where a log scale clips small values the clip is stated.
The same style serves the comparison plots (aocs_compare).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

AXES = ("x", "y", "z")
COLORS = ("tab:blue", "tab:orange", "tab:green")


def _plt():
    import matplotlib  # deferred: ~0.5 s, and the Agg backend must be chosen before pyplot loads

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: see above

    return plt


FIG_WIDTH_IN = 8.0     # x DPI = 1280 px
DPI = 160
LEGEND_PT = 9
#: notes on a figure (a clip, the tested window, a target's name): a point below the legend, read as annotations
NOTE_PT = LEGEND_PT - 1
LABEL_PT = 10
TITLE_PT = 11
#: smallest value a log-scale error plot draws (smaller values are drawn at it, and the axis says so)
LOG_FLOOR = 1e-12


def save(fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=DPI)
    _plt().close(fig)
    return path


def new_axes(title: str, ylabel: str, height_in: float = 4.0, xlabel: str = "t (s)"):
    """A figure in the house style: title, labelled axes with units, light grid."""
    plt = _plt()
    fig, ax = plt.subplots(figsize=(FIG_WIDTH_IN, height_in))
    ax.set_title(title, fontsize=TITLE_PT)
    ax.set_xlabel(xlabel, fontsize=LABEL_PT)
    ax.set_ylabel(ylabel, fontsize=LABEL_PT)
    ax.tick_params(labelsize=LABEL_PT - 1)
    ax.grid(True, alpha=0.3)
    return fig, ax


def clip_note(ax, floor: float = LOG_FLOOR) -> None:
    """States, on the figure, that a log axis draws values below floor at floor."""
    ax.annotate(f"log scale: values below {floor:g} are drawn at {floor:g}", xy=(1.0, -0.16),
                xycoords="axes fraction", ha="right", va="top", fontsize=NOTE_PT, color="dimgray")


def legend(ax, ncol: int = 1) -> None:
    ax.legend(fontsize=LEGEND_PT, loc="best", ncol=ncol, framealpha=0.85)


def settle_marks(ax, settle_time_s, label_threshold=None, threshold=None, symmetric=False) -> None:
    """The settle threshold (dashed) and the settle time (dotted vertical line) of a run."""
    if threshold is not None:
        ax.axhline(threshold, color="black", ls="-.", lw=1.0, label=label_threshold or f"settle {threshold:g}")
        if symmetric:
            ax.axhline(-threshold, color="black", ls="-.", lw=1.0)
    if settle_time_s is not None:
        ax.axvline(settle_time_s, color="gray", ls=":", lw=1.2, label=f"settled at {settle_time_s:.1f} s")


def _per_axis(ax, t, y, label):
    for i in range(3):
        ax.plot(t, y[:, i], color=COLORS[i], lw=1.0, label=f"{label} {AXES[i]}")


def _limit_lines(ax, lim, label):
    if lim is not None:
        ax.axhline(lim, color="red", ls="--", lw=1.0, label=label)
        ax.axhline(-lim, color="red", ls="--", lw=1.0)


def _step_time(series, path, title):
    fig, ax = new_axes(f"{title}: executive step time", "step time (ns)")
    t = series["t_cmd"]
    if t.size:
        ax.plot(t, series["step_ns"], ".", ms=2, color="tab:blue", label="step time")
        b = series["budget_ns"]
        if b.size:
            ax.step(t, b, where="post", color="red", lw=1.0, label="budget")
        ax.set_yscale("log")
    legend(ax)
    return save(fig, path)


def _command_plot(series: dict, path: Path, title: str, ylabel: str, symbol: str) -> Path:
    """The saturated command per axis (zero-order hold) with the limits the flight software applied."""
    fig, ax = new_axes(title, ylabel)
    if series["t_cmd"].size:
        for i in range(3):
            ax.step(series["t_cmd"], series["u_sat"][:, i], where="post", color=COLORS[i], lw=1.0,
                    label=f"{symbol} {AXES[i]}")
    _limit_lines(ax, series.get("axis_limit"), "axis limit")
    if series.get("norm_limit") is not None:
        ax.axhline(series["norm_limit"], color="purple", ls=":", lw=1.0, label="norm limit")
    legend(ax)
    return save(fig, path)


def fault_marks(ax, faults) -> None:
    """The injected faults (metrics `faults`) on a time axis: each one's interval shaded, its detection (when
    there was one) a dotted line."""
    for i, f in enumerate(faults or ()):
        ax.axvspan(f["start_s"], f["end_s"], color="tab:red", alpha=0.08, lw=0,
                   label="injected fault" if i == 0 else None)
        if f.get("detected_s") is not None:
            ax.axvline(f["detected_s"], color="tab:red", ls=":", lw=1.0, label="detected" if i == 0 else None)


def run_plots(series: dict, out_dir, title: str, requirement=None, goal=None, settle: dict | None = None,
              settle_time_s: float | None = None, faults=None) -> list[Path]:
    """settle: the settle criteria used (metrics settle_criterion.criteria), drawn where they apply; faults: the
    run's injected faults (metrics `faults`), shaded on the pointing error."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    t = series["t"]
    if series["kind"] == "attitude":
        settle = settle or {}
        fig, ax = new_axes(f"{title}: pointing error (true angle)", "2 asin|qe_vec| (arcsec)")
        clip_note(ax)
        y = np.maximum(series["true_angle"], LOG_FLOOR)
        ax.semilogy(t, y, lw=1.0, color="tab:blue", label="true angle")
        if requirement is not None:
            ax.axhline(requirement, color="red", ls="--", lw=1.0, label=f"requirement {requirement:g} arcsec")
        if goal is not None:
            ax.axhline(goal, color="green", ls="--", lw=1.0, label=f"goal {goal:g} arcsec")
        settle_marks(ax, settle_time_s, f"settle threshold {settle.get('pointing_arcsec_max', 0):g} arcsec",
                     settle.get("pointing_arcsec_max"))
        fault_marks(ax, faults)
        legend(ax)
        files.append(save(fig, out / "attitude_error.png"))

        fig, ax = new_axes(f"{title}: body rate error", "w - wd (rad/s)")
        _per_axis(ax, t, series["we"], "w")
        legend(ax)
        files.append(save(fig, out / "rates.png"))

        files.append(_command_plot(series, out / "torques.png", f"{title}: commanded torque (after saturation)",
                                   "torque (N m)", "u"))
    else:
        settle = settle or {}
        fig, ax = new_axes(f"{title}: position error", "[dx dy dz] (m, symlog: linear below 0.1)")
        _per_axis(ax, t, series["pos"], "d")
        ax.set_yscale("symlog", linthresh=0.1)
        settle_marks(ax, settle_time_s, f"settle +-{settle.get('pos_abs_max_m', 0):g} m", settle.get("pos_abs_max_m"),
                     symmetric=True)
        legend(ax)
        files.append(save(fig, out / "position_error.png"))

        fig, ax = new_axes(f"{title}: velocity error", "[du dv dw] (m/s, symlog: linear below 0.01)")
        for i, n in enumerate(("du", "dv", "dw")):
            ax.plot(t, series["vel"][:, i], color=COLORS[i], lw=1.0, label=n)
        ax.set_yscale("symlog", linthresh=0.01)
        settle_marks(ax, settle_time_s, f"settle +-{settle.get('vel_abs_max_m_s', 0):g} m/s",
                     settle.get("vel_abs_max_m_s"), symmetric=True)
        legend(ax)
        files.append(save(fig, out / "velocity_error.png"))

        files.append(_command_plot(series, out / "force.png", f"{title}: commanded force (after saturation)",
                                   "force (N)", "F"))
    files.append(_step_time(series, out / "step_time.png", title))
    files += wheel_plots(series.get("wheels") or {}, out, title)
    return files


def wheel_plots(series: dict, out_dir, title: str) -> list:
    """wheel_speeds.png (per wheel, with the speed limits) and momentum.png (|H| and the wheels' share)."""
    if not series:
        return []
    files = []
    fig, ax = new_axes(f"{title}: wheel speeds (relative to the body)", "Omega (rad/s)")
    colors = ("tab:blue", "tab:orange", "tab:green", "tab:purple", "tab:brown", "tab:olive")
    for i in range(series["n"]):
        lab = f"wheel {i}" + (" (failed)" if i in series["failed"] else "")
        ax.plot(series["t"], series["speed"][:, i], lw=1.0, color=colors[i], label=lab)
    lim = max(series["speed_limit"])
    ax.axhline(lim, color="red", ls="--", lw=1.0, label=f"speed limit +-{lim:g} rad/s")
    ax.axhline(-lim, color="red", ls="--", lw=1.0)
    legend(ax, ncol=2)
    files.append(save(fig, Path(out_dir) / "wheel_speeds.png"))
    fig, ax = new_axes(f"{title}: angular momentum", "momentum (N m s)")
    ax.plot(series["t"], series["H_norm"], lw=1.0, color="tab:blue", label="|H| total, J w + sum Js g Omega")
    ax.plot(series["t"], series["h_wheels_norm"], lw=1.0, color="tab:orange", label="|sum Js g Omega| (wheels)")
    legend(ax)
    files.append(save(fig, Path(out_dir) / "momentum.png"))
    return files
