"""PNG plots of one run (matplotlib, Agg backend, small files).

run_plots(series, out_dir, title) takes the series computed from the LCM log
by aocs_analysis.run_metrics.compute and writes:

- attitude: attitude_error.png (true angle 2 asin|qe_vec|, log scale, with
  the requirement and goal), rates.png (w - wd per axis), torques.png (the
  saturated command per axis with the saturation limit), step_time.png
  (executive step time against the step's budget);
- orbit: position_error.png, velocity_error.png, force.png, step_time.png.
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


def _save(fig, path: Path) -> Path:
    fig.tight_layout()
    fig.savefig(path, dpi=80)
    _plt().close(fig)
    return path


def _new(title, ylabel):
    plt = _plt()
    fig, ax = plt.subplots(figsize=(7.0, 3.6))
    ax.set_title(title, fontsize=10)
    ax.set_xlabel("t (s)")
    ax.set_ylabel(ylabel)
    ax.grid(True, alpha=0.3)
    return fig, ax


def _per_axis(ax, t, y, label):
    for i in range(3):
        ax.plot(t, y[:, i], color=COLORS[i], lw=1.0, label=f"{label} {AXES[i]}")


def _limit_lines(ax, lim, label):
    if lim is not None:
        ax.axhline(lim, color="red", ls="--", lw=1.0, label=label)
        ax.axhline(-lim, color="red", ls="--", lw=1.0)


def _step_time(series, path, title):
    fig, ax = _new(f"{title}: executive step time", "step time (ns)")
    t = series["t_cmd"]
    if t.size:
        ax.plot(t, series["step_ns"], ".", ms=2, color="tab:blue", label="step time")
        b = series["budget_ns"]
        if b.size:
            ax.step(t, b, where="post", color="red", lw=1.0, label="budget")
        ax.set_yscale("log")
    ax.legend(fontsize=8, loc="upper right")
    return _save(fig, path)


def run_plots(series: dict, out_dir, title: str, requirement=None, goal=None) -> list[Path]:
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    files = []
    t = series["t"]
    if series["kind"] == "attitude":
        fig, ax = _new(f"{title}: pointing error (true angle)", "2 asin|qe_vec| (arcsec)")
        y = np.maximum(series["true_angle"], 1e-12)
        ax.semilogy(t, y, lw=1.0, color="tab:blue", label="true angle")
        if requirement is not None:
            ax.axhline(requirement, color="red", ls="--", lw=1.0, label=f"requirement {requirement:g}")
        if goal is not None:
            ax.axhline(goal, color="green", ls="--", lw=1.0, label=f"goal {goal:g}")
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "attitude_error.png"))

        fig, ax = _new(f"{title}: body rate error", "w - wd (rad/s)")
        _per_axis(ax, t, series["we"], "w")
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "rates.png"))

        fig, ax = _new(f"{title}: commanded torque (after saturation)", "torque (N m)")
        if series["t_cmd"].size:
            for i in range(3):
                ax.step(series["t_cmd"], series["u_sat"][:, i], where="post", color=COLORS[i], lw=1.0,
                        label=f"u {AXES[i]}")
        _limit_lines(ax, series.get("axis_limit"), "axis limit")
        if series.get("norm_limit") is not None:
            ax.axhline(series["norm_limit"], color="purple", ls=":", lw=1.0, label="norm limit")
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "torques.png"))
    else:
        fig, ax = _new(f"{title}: position error", "[dx dy dz] (m)")
        _per_axis(ax, t, series["pos"], "d")
        ax.set_yscale("symlog", linthresh=0.1)
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "position_error.png"))

        fig, ax = _new(f"{title}: velocity error", "[du dv dw] (m/s)")
        for i, n in enumerate(("du", "dv", "dw")):
            ax.plot(t, series["vel"][:, i], color=COLORS[i], lw=1.0, label=n)
        ax.set_yscale("symlog", linthresh=0.01)
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "velocity_error.png"))

        fig, ax = _new(f"{title}: commanded force (after saturation)", "force (N)")
        if series["t_cmd"].size:
            for i in range(3):
                ax.step(series["t_cmd"], series["u_sat"][:, i], where="post", color=COLORS[i], lw=1.0,
                        label=f"F {AXES[i]}")
        _limit_lines(ax, series.get("axis_limit"), "axis limit")
        ax.legend(fontsize=8, loc="upper right")
        files.append(_save(fig, out / "force.png"))
    files.append(_step_time(series, out / "step_time.png", title))
    return files
