"""Target passes of leo_day ([passes]; aocs_plant.target_passes, aocs_analysis.passes; docs/spec.md 5.11.4).

The geometry against an independent evaluation written here: the sub-satellite point from the circular orbit
written out (Vallado eq. 2-99) and the sidereal angle, the Earth central angle lambda to the target by the
haversine formula, and the off-nadir angle and elevation of the spherical-Earth triangle (Wertz and Larson,
SMAD sec. 5.2): tan eta = R sin lambda / (r - R cos lambda), tan eps = (cos lambda - R / r) / sin lambda. The
sidereal time against Meeus' example 12.a. The pass metrics against windows and sums written out here."""
from __future__ import annotations

import math

import numpy as np
import pytest

from aocs_analysis import passes as P
from aocs_plant import ScenarioError, load, target_passes
from aocs_plant.environment import Environment
from aocs_plant.environment.magnetic_field import gmst_rad

R_E = 6378137.0


def test_sidereal_time_against_meeus_example_12a():
    # 1987 April 10, 0h UT (JD 2446895.5): 13h 10m 46.3668s (Meeus, Astronomical Algorithms, example 12.a)
    want = (13 + 10 / 60 + 46.3668 / 3600) * 15.0
    assert math.degrees(gmst_rad(2446895.5)) == pytest.approx(want, abs=1e-6)


def _independent(sc, t, lat_deg, lon_deg):
    """(eta, eps) deg of one target at the times t, from the sub-satellite point and the central angle."""
    o = sc.environment.orbit
    mu, R = o.mu, o.radius_m
    n = math.sqrt(mu / R ** 3)
    u = math.radians(o.arg_latitude0_deg) + n * t
    i, om = math.radians(o.inclination_deg), math.radians(o.raan_deg)
    x = R * (np.cos(u) * math.cos(om) - np.sin(u) * math.cos(i) * math.sin(om))
    y = R * (np.cos(u) * math.sin(om) + np.sin(u) * math.cos(i) * math.cos(om))
    z = R * np.sin(u) * math.sin(i)
    env = Environment(sc.environment)
    th = np.array([gmst_rad(env.julian_date(tk)) for tk in t])
    lat_s = np.arcsin(z / R)
    lon_s = np.arctan2(y, x) - th                     # right ascension less the sidereal angle
    la, lo = math.radians(lat_deg), math.radians(lon_deg)
    hav = np.sin((lat_s - la) / 2) ** 2 + np.cos(lat_s) * math.cos(la) * np.sin((lon_s - lo) / 2) ** 2
    lam = 2.0 * np.arcsin(np.sqrt(hav))
    eta = np.degrees(np.arctan2(R_E * np.sin(lam), R - R_E * np.cos(lam)))
    eps = np.degrees(np.arctan2(np.cos(lam) - R_E / R, np.sin(lam)))
    return eta, eps


def test_off_nadir_and_elevation_against_the_central_angle():
    sc = load("leo_day")
    t = np.arange(0.0, 86400.0, 37.0)
    eta, eps = target_passes.geometry(sc.passes, Environment(sc.environment), t)
    for j, tg in enumerate(sc.passes.targets):
        e_eta, e_eps = _independent(sc, t, tg.lat_deg, tg.lon_deg)
        np.testing.assert_allclose(eta[j], e_eta, atol=1e-6)
        np.testing.assert_allclose(eps[j], e_eps, atol=1e-6)


def test_pass_windows_are_the_runs_of_ticks_in_view():
    sc = load("leo_day")
    t = np.arange(0.0, 86401.0)
    got = target_passes.windows(sc.passes, Environment(sc.environment), t)
    want = []
    for j, tg in enumerate(sc.passes.targets):
        eta, eps = _independent(sc, t, tg.lat_deg, tg.lon_deg)
        view = (eta <= 45.0) & (eps > 0.0)
        k = 0
        while k < t.size:
            if view[k]:
                k1 = k
                while k1 < t.size and view[k1]:
                    k1 += 1
                want.append((k, j, k1, float(eta[k:k1].min())))
                k = k1
            else:
                k += 1
    want.sort()
    assert [(p["i0"], p["target"], p["i1"]) for p in got] == [w[:3] for w in want]
    assert [p["min_off_nadir_deg"] for p in got] == pytest.approx([w[3] for w in want], abs=1e-6)
    assert len(got) == 26                                          # as leo_day's comment says
    # a 45 deg field of regard at 500 km: the longest pass is about 2 lambda / n (lambda = 4.69 deg)
    lam = math.radians(90.0 - 45.0) - math.acos(math.sin(math.radians(45.0)) * 6878137.0 / R_E)
    longest = 2.0 * lam / 1.1067834e-3
    assert max(p["i1"] - p["i0"] for p in got) == pytest.approx(longest, rel=0.05)


def test_pass_metrics_by_hand():
    sc = load("leo_day", {"duration_s": 40000.0})
    t = np.arange(0.0, 40001.0)
    ang = 1.0 + 0.5 * np.sin(t / 7.0)
    ang[:600] = 500.0                                               # acquisition, outside the 60 arcsec band
    w = target_passes.windows(sc.passes, Environment(sc.environment), t)
    spike = w[1]["i0"] + 10
    ang[spike] = 40.0                                               # above the 36 arcsec requirement, settled
    late = w[2]["i0"] + 5
    ang[w[2]["i0"]:late] = 80.0                                     # pass 2 starts unsettled
    out = P.metrics(sc, {"t": t, "true_angle": ang}, ang < 60.0)
    assert len(out) == len(w) >= 4
    for p, win in zip(out, w):
        sel = ang[win["i0"]:win["i1"]]
        assert (p["start_s"], p["end_s"]) == (t[win["i0"]], t[win["i1"] - 1])
        assert p["target"]["name"] == sc.passes.targets[win["target"]].name
        assert p["pointing_max_arcsec"] == sel.max()
        assert p["pointing_rms_arcsec"] == pytest.approx(math.sqrt(float((sel ** 2).sum()) / sel.size), rel=1e-12)
    assert out[1]["settle_s"] == 0.0 and out[1]["meets_requirement"] is False
    assert out[2]["settle_s"] == 5.0 and out[2]["meets_requirement"] is False
    assert out[0]["meets_requirement"] is True and out[3]["meets_requirement"] is True
    assert all(p["complete"] for p in out)
    # a pass whose largest error is exactly the requirement meets it (at most the requirement)
    at = P.metrics(sc, {"t": t, "true_angle": ang}, ang < 60.0)
    req = at[0]["pointing_max_arcsec"]
    sc_req = load("leo_day", {"duration_s": 40000.0, "metrics.requirement_arcsec": req})
    assert P.metrics(sc_req, {"t": t, "true_angle": ang}, ang < 60.0)[0]["meets_requirement"] is True
    sc_below = load("leo_day", {"duration_s": 40000.0, "metrics.requirement_arcsec": float(np.nextafter(req, 0.0))})
    assert P.metrics(sc_below, {"t": t, "true_angle": ang}, ang < 60.0)[0]["meets_requirement"] is False
    # a run ending inside a pass: the pass is cut (complete false) and judged on what was flown
    cut = P.metrics(sc, {"t": t[:29951], "true_angle": ang[:29951]}, ang[:29951] < 60.0)
    assert cut[-1]["target"]["name"] == "Longyearbyen" and not cut[-1]["complete"] and cut[-1]["end_s"] == 29950.0
    rows = dict(P.table_rows(out, 36.0))
    assert rows["target passes"].startswith(f"{len(out)} passes") and len(rows) == 3
    missed = [v for k, v in rows.items() if k.startswith("pass ")]
    assert missed == ["MISSED: settled, max 40 arcsec", f"MISSED: not settled, max {out[2]['pointing_max_arcsec']:.3g} arcsec"]


def test_passes_section_errors_name_the_key():
    sc = load("leo_day")
    with pytest.raises(ScenarioError, match="max_off_nadir_deg"):
        load("leo_day", {"passes.max_off_nadir_deg": 95.0})
    with pytest.raises(ScenarioError, match="max_off_nadir_deg.*not below 90"):
        load("leo_day", {"passes.max_off_nadir_deg": 90.0})     # the horizon itself: no pass geometry
    with pytest.raises(ScenarioError, match="lat_deg"):
        load("leo_day", {"passes.targets": [{"name": "x", "lat_deg": 91.0, "lon_deg": 0.0}]})
    with pytest.raises(ScenarioError, match="given twice"):
        load("leo_day", {"passes.targets": [{"name": "x", "lat_deg": 1.0, "lon_deg": 0.0}] * 2})
    with pytest.raises(ScenarioError, match=r"environment\.orbit"):
        load("irassi_rw", {"passes": {"max_off_nadir_deg": 30.0,
                                      "targets": [{"name": "x", "lat_deg": 1.0, "lon_deg": 0.0}]}})
    assert sc.passes is not None and load("irassi_rw").passes is None


def test_the_day_timeline_shows_every_pass(tmp_path, monkeypatch):
    from aocs_analysis import day_timeline, plots
    sc = load("leo_day", {"duration_s": 40000.0})
    t = np.arange(0.0, 40001.0)
    ang = 1.0 + 0.5 * np.sin(t / 7.0)
    out = P.metrics(sc, {"t": t, "true_angle": ang}, ang < 60.0)
    out[1]["meets_requirement"] = False
    metrics = {"holds": None, "passes": out, "momentum": {"policy": "none"},
               "pointing_error_arcsec": {"requirement_arcsec": 36.0}}
    assert day_timeline.applies(metrics)
    series = {"t": t, "true_angle": ang, "t_cmd": t[:-1], "mode": np.ones(t.size - 1, int)}
    figs = []
    real_save = plots.save
    monkeypatch.setattr(plots, "save", lambda fig, path: (figs.append(fig), real_save(fig, path))[1])
    day_timeline.timeline(series, metrics, tmp_path / "day.png", "leo_day")
    ax = figs[0].axes[2]
    names = [x.get_text() for x in ax.texts if not x.get_text().startswith("log scale")]
    assert names == [p["target"]["name"] for p in out]
    assert [x.get_color() for x in ax.texts].count("red") == 1
    spans = [(round(p.get_x() * 3600.0, 6), round((p.get_x() + p.get_width()) * 3600.0, 6))
             for p in ax.patches if p.get_facecolor()[:3] == pytest.approx((0.58, 0.40, 0.74), abs=0.01)]
    assert spans == [(p["start_s"], p["end_s"]) for p in out]
