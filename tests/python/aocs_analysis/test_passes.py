"""The run JSON's `passes` section (aocs_analysis.passes, docs/spec.md 5.11.4) on passes laid out by hand: a
stand-in scenario whose passes.windows_at returns the windows the test chooses (the geometry is
tests/python/aocs_plant/test_target_passes.py's), so each entry's figures are known exactly."""
from __future__ import annotations

import math
import types

import numpy as np
import pytest

from aocs_analysis import passes as P

DT = 1.0


def _scenario(requirement, windows):
    targets = [types.SimpleNamespace(name=f"target {k}", lat_deg=10.0 * k, lon_deg=-5.0 * k) for k in range(3)]
    cfg = types.SimpleNamespace(targets=targets, windows_at=lambda t: windows)
    return types.SimpleNamespace(passes=cfg, dt=DT, metrics=types.SimpleNamespace(requirement_arcsec=requirement))


def _window(target, i0, i1):
    return {"target": target, "i0": i0, "i1": i1, "closest_i": (i0 + i1) // 2, "min_off_nadir_deg": 3.0,
            "max_elevation_deg": 80.0}


def test_meets_requirement_is_none_without_a_requirement_or_a_finite_max_and_judged_otherwise():
    t = np.arange(100) * DT
    ang = np.full(t.size, 20.0)
    ang[40:45] = 50.0                       # pass 1 (samples 30..59) goes over 36 arcsec for 5 s
    ang[72] = math.nan                      # pass 2 (samples 70..79) has no finite maximum
    inside = np.ones(t.size, bool)
    inside[10:13] = False                   # pass 0 (samples 5..24) settles at sample 13: 8 s after its start
    wins = [_window(0, 5, 25), _window(1, 30, 60), _window(2, 70, 80), _window(0, 85, 95)]
    # without a requirement nothing is judged, whatever the pass
    free = P.metrics(_scenario(None, wins), {"t": t, "true_angle": ang}, inside)
    assert [p["meets_requirement"] for p in free] == [None] * 4
    assert [p["settle_s"] for p in free] == [8.0, 0.0, 0.0, 0.0]
    assert [p["pointing_max_arcsec"] for p in free] == [20.0, 50.0, None, 20.0]
    # 36 arcsec: pass 0 not settled throughout, pass 1 over it, pass 2 undefined, pass 3 met
    judged = P.metrics(_scenario(36.0, wins), {"t": t, "true_angle": ang}, inside)
    assert [p["meets_requirement"] for p in judged] == [False, False, None, True]
    assert judged[1]["pointing_rms_arcsec"] == pytest.approx(math.sqrt((25 * 20.0 ** 2 + 5 * 50.0 ** 2) / 30))
    assert [(p["start_s"], p["end_s"], p["duration_s"]) for p in judged] == [
        (5.0, 24.0, 20.0), (30.0, 59.0, 30.0), (70.0, 79.0, 10.0), (85.0, 94.0, 10.0)]
    assert [p["complete"] for p in judged] == [True] * 4
    # a pass cut by the run's start (from sample 0) or its end (to the last sample) is not complete
    cut = P.metrics(_scenario(36.0, [_window(0, 0, 10), _window(1, 90, 100), _window(2, 1, 99)]),
                    {"t": t, "true_angle": ang}, inside)
    assert [p["complete"] for p in cut] == [False, False, True]
    # a pass whose largest error is exactly the requirement meets it (at most the requirement), a hair above not
    assert P.metrics(_scenario(20.0, wins), {"t": t, "true_angle": ang}, inside)[3]["meets_requirement"] is True
    below = P.metrics(_scenario(math.nextafter(20.0, 0.0), wins), {"t": t, "true_angle": ang}, inside)
    assert below[3]["meets_requirement"] is False
    # the table's line of each missed pass says whether it had settled
    rows = dict(P.table_rows(judged, 36.0))
    assert rows["pass target 0 5 s"] == "MISSED: not settled, max 20 arcsec"
    assert rows["pass target 1 30 s"] == "MISSED: settled, max 50 arcsec"
