"""Run plots are legible: at least 1200 px wide at 150 dpi or more, with the thresholds drawn."""
from __future__ import annotations

import struct

import numpy as np

from aocs_analysis import plots


def _png_size_and_dpi(path):
    data = path.read_bytes()
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    w, h = struct.unpack(">II", data[16:24])
    dpi = None
    off = 8
    while off < len(data):
        n, kind = struct.unpack(">I4s", data[off:off + 8])
        if kind == b"pHYs":
            ppm_x, _, unit = struct.unpack(">IIB", data[off + 8:off + 17])
            dpi = ppm_x * 0.0254 if unit == 1 else None
        off += 12 + n
    return w, h, dpi


def _attitude_series(n=200):
    t = np.arange(n) * 0.1
    return {"kind": "attitude", "t": t, "true_angle": np.geomspace(1e5, 1e-14, n),
            "we": np.zeros((n, 3)), "t_cmd": t[:-1], "u_sat": np.full((n - 1, 3), 0.5),
            "u_unsat": np.ones((n - 1, 3)), "mode": np.ones(n - 1, int), "step_ns": np.full(n - 1, 900.0),
            "budget_ns": np.full(n - 1, 2000.0), "axis_limit": 0.5, "norm_limit": None}


def test_run_plots_are_large_enough_to_read(tmp_path):
    files = plots.run_plots(_attitude_series(), tmp_path, "test", 0.3, 0.05,
                            settle={"pointing_arcsec_max": 10.0}, settle_time_s=12.3)
    assert [f.name for f in files] == ["attitude_error.png", "rates.png", "torques.png", "step_time.png"]
    for f in files:
        w, h, dpi = _png_size_and_dpi(f)
        assert w >= 1200 and h >= 500, (f.name, w, h)
        assert dpi is not None and dpi >= 150, (f.name, dpi)
    assert plots.LEGEND_PT >= 8
    # notes read as annotations, below the legend, and stay legible at the figure's dpi
    assert 7 <= plots.NOTE_PT < plots.LEGEND_PT


def test_thresholds_settle_time_and_clip_are_drawn(tmp_path, monkeypatch):
    seen = []
    real_save = plots.save

    lines = {}
    budget = {}
    drawn = {}

    def spy(fig, path):
        ax = fig.axes[0]
        seen.append((path.name, [t.get_text() for t in ax.get_legend().get_texts()],
                     [t.get_text() for t in ax.texts]))
        lines[path.name] = [(tuple(ln.get_ydata()), ln.get_linewidth()) for ln in ax.get_lines()
                            if ln.get_linestyle() == "--" and ln.get_color() == "red"]
        budget[path.name] = [(set(ln.get_ydata()), ln.get_linewidth()) for ln in ax.get_lines()
                             if ln.get_label() == "budget"]
        drawn[path.name] = {ln.get_label(): ln.get_linewidth() for ln in ax.get_lines()}
        return real_save(fig, path)

    monkeypatch.setattr(plots, "save", spy)
    plots.run_plots(_attitude_series(), tmp_path, "test", 0.3, 0.05, settle={"pointing_arcsec_max": 10.0},
                    settle_time_s=12.3)
    name, labels, notes = seen[0]
    assert name == "attitude_error.png"
    assert {"requirement 0.3 arcsec", "goal 0.05 arcsec", "settle threshold 10 arcsec",
            "settled at 12.3 s"} <= set(labels)
    assert any("drawn at 1e-12" in n for n in notes)
    labels = dict((n, lb) for n, lb, _ in seen)["torques.png"]
    assert "axis limit" in labels
    # the axis limit at +lim and -lim, both visible
    limit = [(y[0], lw) for y, lw in lines["torques.png"] if len(set(y)) == 1]
    ys = sorted(y for y, _ in limit)
    assert len(ys) == 2 and ys[0] == -ys[1] < 0 and all(lw > 0 for _, lw in limit)
    # the step time's budget: one visible line at its value, named in the legend
    assert "budget" in dict((n, lb) for n, lb, _ in seen)["step_time.png"]
    assert [(y, lw > 0) for y, lw in budget["step_time.png"]] == [({2000.0}, True)]
    # the settle threshold and the requirement drawn visibly, not only named
    assert drawn["attitude_error.png"]["settle threshold 10 arcsec"] > 0
    assert drawn["attitude_error.png"]["requirement 0.3 arcsec"] > 0
    # the rate error: one visible line per axis, each named in the legend
    assert {k: lw > 0 for k, lw in drawn["rates.png"].items()} == {"w x": True, "w y": True, "w z": True}
    assert set(dict((n, lb) for n, lb, _ in seen)["rates.png"]) == {"w x", "w y", "w z"}


def test_the_wheel_speed_plot_draws_both_speed_limits(tmp_path, monkeypatch):
    """wheel_speeds.png: each wheel's speed and the speed limits +-Omega_max as visible horizontal lines (a line
    of width 0 is not on the figure), |H| and the wheels' share on momentum.png."""
    figs = {}
    real_save = plots.save
    monkeypatch.setattr(plots, "save", lambda fig, path: (figs.__setitem__(path.name, fig), real_save(fig, path))[1])
    t = np.arange(50) * 0.1
    series = {"n": 3, "failed": (1,), "t": t, "speed": np.stack([10 * t, -20 * t, 5 * t], axis=1),
              "speed_limit": [600.0, 550.0, 600.0], "H_norm": 1.0 + 0 * t, "h_wheels_norm": 0.5 + 0 * t}
    files = plots.wheel_plots(series, tmp_path, "test")
    assert [f.name for f in files] == ["wheel_speeds.png", "momentum.png"]
    ax = figs["wheel_speeds.png"].axes[0]
    level = [float(ln.get_ydata()[0]) for ln in ax.lines
             if len(set(np.asarray(ln.get_ydata(), float))) == 1 and ln.get_linewidth() > 0.0
             and ln.get_linestyle() not in ("None", "", " ")]
    assert sorted(level) == [-600.0, 600.0]
    labels = [ln.get_label() for ln in ax.lines]
    assert labels[:3] == ["wheel 0", "wheel 1 (failed)", "wheel 2"]
    assert [ln.get_label() for ln in figs["momentum.png"].axes[0].lines] == [
        "|H| total, J w + sum Js g Omega", "|sum Js g Omega| (wheels)"]


def _visible(line) -> bool:
    """A Line2D that shows on the figure: a stroke of some width, or markers."""
    stroke = line.get_linewidth() > 0.0 and line.get_linestyle() not in ("None", "", " ")
    return stroke or line.get_marker() not in (None, "", " ", "None")


def test_every_line_of_every_run_plot_is_visible(tmp_path, monkeypatch):
    """A line of width 0 (or without a style and markers) is in the legend and nowhere else: every line of the
    attitude, orbit and wheel plots shows."""
    figs = {}
    real_save = plots.save
    monkeypatch.setattr(plots, "save", lambda fig, path: (figs.__setitem__(path.name, fig), real_save(fig, path))[1])
    plots.run_plots(_attitude_series(), tmp_path / "a", "test", 0.3, 0.05, settle={"pointing_arcsec_max": 10.0},
                    settle_time_s=12.3)
    n = 50
    t = np.arange(n) * 0.1
    orbit = {"kind": "orbit", "t": t, "pos": np.ones((n, 3)), "vel": np.ones((n, 3)), "t_cmd": t[:-1],
             "u_sat": np.full((n - 1, 3), 0.5), "u_unsat": np.ones((n - 1, 3)), "mode": np.ones(n - 1, int),
             "step_ns": np.full(n - 1, 900.0), "budget_ns": np.full(n - 1, 2000.0), "axis_limit": 0.5,
             "norm_limit": 1.0}
    plots.run_plots(orbit, tmp_path / "o", "test", settle={"pos_abs_max_m": 0.1, "vel_abs_max_m_s": 0.01},
                    settle_time_s=2.0)
    plots.wheel_plots({"n": 2, "failed": (), "t": t, "speed": np.ones((n, 2)), "speed_limit": [600.0, 600.0],
                       "H_norm": 1.0 + 0 * t, "h_wheels_norm": 0.5 + 0 * t}, tmp_path, "test")
    assert {"attitude_error.png", "rates.png", "torques.png", "step_time.png", "position_error.png",
            "velocity_error.png", "wheel_speeds.png", "momentum.png"} <= set(figs)
    for name, fig in figs.items():
        for ax in fig.axes:
            assert ax.lines, name
            for ln in ax.lines:
                assert _visible(ln), (name, ln.get_label())
