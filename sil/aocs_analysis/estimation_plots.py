"""Figures of the attitude filter's accuracy and consistency (issue 20; SPEC 5.7), in the house style of
plots.py (FIG_WIDTH_IN x DPI px wide, LEGEND_PT legends, units on every axis).

run_plots(series, out_dir, title) takes the series of estimation.analyse and writes

- knowledge_error.png: dth per axis of B (arcsec) with the filter's +-3 sigma envelope (from P) and the
  analytic steady-state +-3 sigma (Farrenkopf, after an update), the convergence time and the tested
  steady-state window; the vertical range is that of the window (the initial transient may be clipped:
  the figure says so);
- bias_estimate.png: the bias estimate against the truth per axis (deg/h), with the estimate's +-3 sigma;
- nees.png: the 6-dof and the attitude (3-dof) NEES per sample, the mean of each independent window, the
  window's 95 % chi-square band and the expected value (the degrees of freedom).
"""
from __future__ import annotations

from pathlib import Path

import numpy as np

from .plots import AXES, COLORS, FIG_WIDTH_IN, LABEL_PT, LEGEND_PT, NOTE_PT, TITLE_PT, save

#: NEES values below this are drawn at it (log axis), and the figure says so
NEES_FLOOR = 1e-3


def _stacked(title: str, n: int, height_in: float):
    """n axes sharing t, in the house style."""
    import matplotlib  # deferred: ~0.5 s, and the Agg backend must be chosen before pyplot loads (as plots.py)

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt  # deferred: see above

    fig, axes = plt.subplots(n, 1, figsize=(FIG_WIDTH_IN, height_in), sharex=True)
    axes = np.atleast_1d(axes)
    fig.suptitle(title, fontsize=TITLE_PT)
    for ax in axes:
        ax.tick_params(labelsize=LABEL_PT - 1)
        ax.grid(True, alpha=0.3)
    axes[-1].set_xlabel("t (s)", fontsize=LABEL_PT)
    return fig, axes


def _legend(ax):
    """Outside the axes, on the right: the traces stay visible."""
    ax.legend(fontsize=LEGEND_PT, loc="upper left", bbox_to_anchor=(1.01, 1.0), borderaxespad=0.0,
              framealpha=0.85)


def _window_span(ax, t, steady, label=True):
    if np.any(steady):
        ts = t[steady]
        ax.axvspan(ts[0], ts[-1], color="gray", alpha=0.08, label="tested window" if label else None)


def _note(ax, text):
    ax.annotate(text, xy=(1.0, 1.02), xycoords="axes fraction", ha="right", va="bottom",
                fontsize=NOTE_PT, color="dimgray")


def knowledge_error_plot(series: dict, path, title: str) -> Path:
    t, steady, valid = series["t"], series["steady"], series["valid"]
    e, s = series["knowledge_arcsec"], series["sigma_arcsec"]
    bound = series.get("bound_post_arcsec")
    conv = series.get("convergence_time_s")
    fig, axes = _stacked(f"{title}: attitude knowledge error dth = rotvec(q_true (x) q_est^-1), in B", 3, 7.5)
    for i, ax in enumerate(axes):
        ev = np.where(valid, e[:, i], np.nan)
        sv = np.where(valid, 3.0 * s[:, i], np.nan)
        ax.fill_between(t, -sv, sv, color=COLORS[i], alpha=0.18, lw=0, label="filter +-3 sigma (P)")
        ax.plot(t, ev, color=COLORS[i], lw=0.7, label=f"dth_{AXES[i]}")
        if bound is not None:
            ax.axhline(3.0 * bound[i], color="red", ls="--", lw=1.0,
                       label=f"analytic +-3 sigma\n({3.0 * bound[i]:.3g} arcsec)")
            ax.axhline(-3.0 * bound[i], color="red", ls="--", lw=1.0)
        if conv is not None:
            ax.axvline(conv, color="black", ls=":", lw=1.2, label=f"converged at {conv:.1f} s")
        _window_span(ax, t, steady)
        ax.set_ylabel(f"dth_{AXES[i]} (arcsec)", fontsize=LABEL_PT)
        if np.any(steady):
            lim = 1.3 * float(np.nanmax(np.concatenate([np.abs(ev[steady]), sv[steady],
                                                         [3.0 * bound[i]] if bound is not None else []])))
            if np.isfinite(lim) and lim > 0.0:
                clipped = bool(np.nanmax(np.abs(np.where(valid, e[:, i], 0.0))) > lim)
                ax.set_ylim(-lim, lim)
                if clipped:
                    _note(ax, "range of the tested window: the transient before it is clipped")
        _legend(ax)
    return save(fig, Path(path))


def bias_plot(series: dict, path, title: str) -> Path:
    t, valid = series["t"], series["valid"]
    est, true, s = series["bias_est_deg_h"], series["bias_true_deg_h"], series["sigma_bias_deg_h"]
    fig, axes = _stacked(f"{title}: gyro bias, estimate against truth (B)", 3, 7.5)
    for i, ax in enumerate(axes):
        ev = np.where(valid, est[:, i], np.nan)
        sv = np.where(valid, 3.0 * s[:, i], np.nan)
        ax.fill_between(t, ev - sv, ev + sv, color=COLORS[i], alpha=0.18, lw=0, label="estimate +-3 sigma (P)")
        ax.plot(t, ev, color=COLORS[i], lw=1.0, label=f"estimate b_{AXES[i]}")
        ax.plot(t, true[:, i], color="black", ls="--", lw=1.0, label=f"truth b_{AXES[i]}")
        _window_span(ax, t, series["steady"])
        ax.set_ylabel(f"b_{AXES[i]} (deg/h)", fontsize=LABEL_PT)
        _legend(ax)
    return save(fig, Path(path))


def nees_plot(series: dict, path, title: str) -> Path:
    t, steady = series["t"], series["steady"]
    fig, axes = _stacked(f"{title}: normalised estimation error squared (NEES)", 2, 7.0)
    for ax, key, tkey, name in ((axes[0], "nees", "nees_test", "[dth; db]"),
                                (axes[1], "nees_attitude", "nees_attitude_test", "dth")):
        eps, test = series[key], series[tkey]
        ax.semilogy(t, np.maximum(eps, NEES_FLOOR), ",", color="tab:blue", alpha=0.5)
        ax.plot([], [], ".", color="tab:blue", label=f"NEES of {name}\nper sample")
        if test.window_mean.size:
            ax.semilogy(test.window_t_s, test.window_mean, "o", ms=4, color="tab:orange",
                        label=f"window mean ({test.samples_per_window} samples\n{test.spacing_s:.3g} s apart)")
        lo, hi = test.band
        ax.axhline(hi, color="red", ls="--", lw=1.0, label=f"95 % band of the mean\n[{lo:.3g}, {hi:.3g}]")
        ax.axhline(lo, color="red", ls="--", lw=1.0)
        ax.axhline(test.dof, color="black", ls="-.", lw=1.0, label=f"expected {test.dof} (dof)")
        _window_span(ax, t, steady)
        frac = "none" if test.in_band_fraction is None else f"{test.in_band_fraction:.3f}"
        _note(ax, f"{test.dof} dof: {frac} of {test.windows} windows in band (all phases; the {test.independent_windows} disjoint ones drawn); "
                  f"values below {NEES_FLOOR:g} drawn at {NEES_FLOOR:g}")
        ax.set_ylabel(f"NEES, {test.dof} dof (-)", fontsize=LABEL_PT)
        _legend(ax)
    return save(fig, Path(path))


def run_plots(series: dict, out_dir, title: str) -> list[Path]:
    """knowledge_error.png, bias_estimate.png, nees.png in out_dir (module docstring)."""
    out = Path(out_dir)
    out.mkdir(parents=True, exist_ok=True)
    return [knowledge_error_plot(series, out / "knowledge_error.png", title),
            bias_plot(series, out / "bias_estimate.png", title),
            nees_plot(series, out / "nees.png", title)]
