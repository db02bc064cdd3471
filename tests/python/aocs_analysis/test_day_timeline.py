"""The mission-day timeline (aocs_analysis.day_timeline, docs/spec.md 5.11): every threshold the module
docstring lists is on its panel at its value, and every trace named in a legend is drawn."""
from __future__ import annotations

import types

import numpy as np
import pytest

from aocs_analysis import day_timeline, plots
from aocs_plant.scenario import load
from figure_checks import x_extent


def _visible(line) -> bool:
    """A Line2D that puts ink on the figure: a line of positive width and a real style, or a marker."""
    drawn = line.get_linewidth() > 0.0 and line.get_linestyle() not in ("None", "", " ")
    return drawn or line.get_marker() not in (None, "None", "", " ")


def _horizontal_at(ax, label):
    """The y of the horizontal line labelled `label` on ax (axhline: ydata [y, y])."""
    ys = [ln.get_ydata() for ln in ax.lines if ln.get_label() == label]
    assert len(ys) == 1, (label, [ln.get_label() for ln in ax.lines])
    y = np.asarray(ys[0], float)
    assert y.size == 2 and y[0] == y[1]
    return float(y[0])


#: ten hours at 10 s, hours on the axis
T = np.round(np.arange(0, 3601) * 10.0, 6)
METRICS = {"holds": None, "passes": None,
           "momentum": {"policy": "thrusters", "h_start_nms": 20.0, "h_stop_nms": 3.0, "capacity_nms": [48.0] * 4},
           "pointing_error_arcsec": {"requirement_arcsec": 0.3}}


def _series(speed, angle, flag) -> dict:
    """The timeline's series over T: wheel speeds (n, 4), the pointing angle, the unloading flag per command."""
    return {"t": T, "true_angle": angle, "t_cmd": T[:-1], "mode": np.ones(T.size - 1, int),
            "wheels": {"t": T, "n": 4, "speed": speed, "speed_limit": [600.0] * 4,
                       "h_wheels_norm": np.abs(speed).sum(axis=1) * 0.08},
            "unloading": {"t": T[:-1], "flag": flag, "cumulative": np.cumsum(flag) * 1e-4,
                          "cumulative_label": "propellant used (kg)"}}


def _figure(series, tmp_path, monkeypatch, metrics=None):
    """The figure day_timeline.timeline saves (written as it would be, and kept); METRICS unless given."""
    figs = []
    real_save = plots.save
    monkeypatch.setattr(plots, "save", lambda fig, path: (figs.append(fig), real_save(fig, path))[1])
    day_timeline.timeline(series, METRICS if metrics is None else metrics, tmp_path / "day.png", "test")
    fig, = figs
    return fig


def _steady_day(tmp_path, monkeypatch, metrics=None, flag=None):
    """The figure of a day at rest (every wheel at 100 rad/s, the pointing at 0.1 arcsec), unloading where flag
    says (none by default), with METRICS or the given metrics."""
    flag = np.zeros(T.size - 1, bool) if flag is None else flag
    return _figure(_series(np.stack([100 + 0 * T] * 4, axis=1), 0.1 + 0 * T, flag), tmp_path, monkeypatch, metrics)


def test_the_timeline_draws_every_threshold_at_its_value_and_every_legend_trace(tmp_path, monkeypatch):
    t = T
    speed = np.stack([100 + 0.01 * t, -100 - 0.01 * t, 50 + 0 * t, -50 + 0 * t], axis=1)
    flag = (t[:-1] > 7200.0) & (t[:-1] < 9000.0)
    fig = _figure(_series(speed, 0.1 + 0.05 * np.sin(t / 600.0), flag), tmp_path, monkeypatch)
    speeds, momentum, pointing, mode = fig.axes[:4]
    # the thresholds at their values (docstring panels 1 to 3)
    assert _horizontal_at(speeds, "speed limit +-600 rad/s") == 600.0
    assert _horizontal_at(momentum, "start unloading 20 N m s") == 20.0
    assert _horizontal_at(momentum, "stop 3 N m s") == 3.0
    assert _horizontal_at(momentum, "one wheel's capacity 48 N m s") == 48.0
    assert _horizontal_at(pointing, "requirement 0.3 arcsec") == pytest.approx(0.3)
    # the pointing angle over the run in hours; the dump's start at 2 h
    true = next(ln for ln in pointing.lines if ln.get_label() == "true pointing angle")
    assert np.asarray(true.get_xdata(), float) == pytest.approx(t / 3600.0)
    start = next(ln for ln in momentum.lines if ln.get_label() == "dump start")
    assert float(np.asarray(start.get_xdata(), float)[0]) == pytest.approx(7210.0 / 3600.0)
    # every trace named in a legend is drawn: a line of width 0 is in the legend but not on the figure
    for ax in fig.axes:
        handles, labels = ax.get_legend_handles_labels()
        invisible = [lab for h, lab in zip(handles, labels) if hasattr(h, "get_linewidth")
                     and hasattr(h, "get_marker") and not _visible(h)]
        assert not invisible, invisible


@pytest.mark.parametrize("runs", [1, 3])
def test_the_dumps_are_shaded_and_named_once(tmp_path, monkeypatch, runs):
    """However many dumps the day holds (one, three), each is shaded on the momentum panel and the legend
    names them once."""
    tc = T[:-1]
    flag = np.zeros(tc.size, bool)
    for k in range(runs):
        flag |= (tc > 3000.0 + 8000.0 * k) & (tc < 4000.0 + 8000.0 * k)
    fig = _steady_day(tmp_path, monkeypatch, flag=flag)
    momentum = fig.axes[1]
    assert momentum.get_legend_handles_labels()[1].count("unloading") == 1
    assert len(momentum.patches) == runs
    assert all(p.get_linewidth() == 0.0 for p in momentum.patches)   # shading only: no edge line reads as a limit


@pytest.mark.parametrize("holds", [1, 3])
def test_the_holds_are_shaded_and_named_once(tmp_path, monkeypatch, holds):
    """However many holds the day has (one, three), each is shaded (no edge) on the pointing panel with its maximum
    drawn over it, and the legend names the shading and the maxima once each."""
    hs = [{"hold_start_s": 3000.0 + 8000.0 * k, "hold_end_s": 6000.0 + 8000.0 * k, "pointing_max_arcsec": 0.2,
           "pointing_rms_arcsec": 0.1, "meets_requirement": True} for k in range(holds)]
    fig = _steady_day(tmp_path, monkeypatch, {**METRICS, "holds": hs})
    pointing = fig.axes[2]
    labels = pointing.get_legend_handles_labels()[1]
    assert labels.count("hold") == 1 and labels.count("hold max") == 1
    assert len(pointing.patches) == holds
    assert all(p.get_linewidth() == 0.0 for p in pointing.patches)   # shading only: no edge line reads as a limit
    maxima = [ln for ln in pointing.lines if len(ln.get_xdata()) == 2 and ln.get_ydata()[0] == 0.2]
    assert sorted(float(ln.get_xdata()[0]) for ln in maxima) == pytest.approx([h["hold_start_s"] / 3600.0
                                                                               for h in hs])


def test_the_dipole_integral_counts_each_rod_within_its_limit():
    """leo_day's rods (0.2 A m^2 each, 1 s period): the cumulative dipole integral sums |m_i| dt per rod, a
    commanded dipole beyond a rod's limit counted at the limit (what the rod can give), by hand."""
    sc = load("leo_day")
    assert sc.momentum.policy == "magnetorquers" and sc.effectors["magnetorquers"].max_dipole_am2 == (0.2,) * 3
    cmd = {"tick": np.arange(3), "unloading": np.array([1, 1, 0]),
           "dipole_am2": np.array([[0.1, -0.05, 0.0], [-0.5, 0.2, 0.3], [0.0, 0.0, -0.01]])}
    out = day_timeline.unloading_series(types.SimpleNamespace(cmd=cmd), sc)
    assert out["flag"].tolist() == [True, True, False]
    np.testing.assert_allclose(out["cumulative"], [0.15, 0.15 + 0.6, 0.75 + 0.01], rtol=1e-12)
    assert out["cumulative_label"] == "dipole integral (A m^2 s)"


@pytest.mark.parametrize("n_passes", [1, 3])
def test_the_target_passes_are_shaded_and_named_once_with_their_maxima(tmp_path, monkeypatch, n_passes):
    """However many target passes the day has (one, three), each is shaded (no edge) with its maximum as a bar
    over it in the colour of its verdict, and the legend names the shading and the maxima once each."""
    ps = [{"start_s": 3000.0 + 8000.0 * k, "end_s": 3600.0 + 8000.0 * k, "pointing_max_arcsec": 0.2 + 0.1 * k,
           "meets_requirement": k != 1, "target": {"name": f"T{k}"}} for k in range(n_passes)]
    fig = _steady_day(tmp_path, monkeypatch, {**METRICS, "passes": ps})
    pointing = fig.axes[2]
    labels = pointing.get_legend_handles_labels()[1]
    assert labels.count("target pass") == 1 and labels.count("pass max") == 1
    assert len(pointing.patches) == n_passes
    assert all(p.get_linewidth() == 0.0 for p in pointing.patches)
    bars = [ln for ln in pointing.lines if len(ln.get_xdata()) == 2 and ln.get_linewidth() == 2.5]
    assert [float(ln.get_ydata()[0]) for ln in bars] == pytest.approx([p["pointing_max_arcsec"] for p in ps])
    assert [ln.get_color() for ln in bars] == ["tab:purple" if p["meets_requirement"] else "red" for p in ps]
    # each bar centred on its pass, as wide as the pass (or the smallest width drawn, for a short one)
    for ln, p in zip(bars, ps):
        a, b = p["start_s"] / 3600.0, p["end_s"] / 3600.0
        half = 0.5 * max(b - a, day_timeline.PASS_MIN_WIDTH_H)
        assert list(ln.get_xdata()) == pytest.approx([0.5 * (a + b) - half, 0.5 * (a + b) + half])
    names = [a.get_text() for a in pointing.texts]
    assert [p["target"]["name"] for p in ps] == [n for n in names if n.startswith("T")]
    # each name centred above its bar (no sideways offset), neighbours' names at alternating heights
    labels = [a for a in pointing.texts if a.get_text().startswith("T")]
    assert [tuple(a.xyann) for a in labels] == [(0.0, 3.0 + 7.0 * (k % 2)) for k in range(n_passes)]
    assert all(a.get_ha() == "center" for a in labels)


@pytest.mark.parametrize("basis,on", [("sensors", "rms"), ("requirement", "max")])
def test_the_sensors_figure_is_drawn_only_when_the_holds_are_held_to_it(tmp_path, monkeypatch, basis, on):
    """Holds held to the sensors' figure (rms): its limit drawn as its own threshold and each hold's rms bar in
    dotted line; held to the requirement (max): neither (the requirement's own line is the threshold)."""
    need = {"basis": basis, "on": on, "limit_arcsec": 0.45}
    hs = [{"hold_start_s": 3000.0, "hold_end_s": 6000.0, "pointing_max_arcsec": 0.6, "pointing_rms_arcsec": 0.2,
           "meets_requirement": True, "requirement": need}]
    fig = _steady_day(tmp_path, monkeypatch, {**METRICS, "holds": hs})
    pointing = fig.axes[2]
    labels = [ln.get_label() for ln in pointing.lines]
    if basis == "sensors":
        assert _horizontal_at(pointing, "sensors' figure (rms) 0.45 arcsec") == pytest.approx(0.45)
        assert labels.count("hold rms") == 1
    else:
        assert not any(lab.startswith("sensors' figure") for lab in labels) and "hold rms" not in labels


def test_a_dump_still_going_at_the_end_is_shaded_to_the_last_command(tmp_path, monkeypatch):
    """Unloading from 30000 s to the run's end: one shading from its first command to the last one's time."""
    tc = T[:-1]
    flag = tc >= 30000.0
    fig = _steady_day(tmp_path, monkeypatch, flag=flag)
    (patch,) = fig.axes[1].patches
    assert x_extent(patch) == pytest.approx((30000.0 / 3600.0, tc[-1] / 3600.0))
