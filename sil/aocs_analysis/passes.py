"""The run JSON's `passes` section (docs/spec.md 5.11.4; docs/sil.md): one entry per target pass of the
scenario's [passes] inside the run, from the logged truth.

    metrics(scenario, series, inside) -> [entry, ...] (None without [passes])

A pass is a maximal run of control ticks in which a ground target is in the imager's field of regard about
nadir (the scenario's passes.windows_at: aocs_plant.target_passes, on the truth samples' times). Its entry: `target` (index, name,
lat_deg, lon_deg), `start_s`, `end_s` (the first and last sample in view), `duration_s` (samples x dt),
`closest_s` and `min_off_nadir_deg` (the least off-nadir angle), `max_elevation_deg`, `complete` (not cut by
the run's start or end), `settle_s` (from the pass's start to the first sample after which every [settle]
criterion holds to its end: 0 when settled throughout, None when not at its end), `pointing_rms_arcsec`,
`pointing_max_arcsec` (the true pointing angle against the scenario's target, nadir, over the pass), and
`meets_requirement` (settled over the whole pass, settle_s == 0, and its max within [metrics]
requirement_arcsec; None without a requirement).
"""
from __future__ import annotations

import math

import numpy as np


def _f(x):
    x = float(x)
    return x if math.isfinite(x) else None


def metrics(scenario, series: dict, inside: np.ndarray) -> list[dict] | None:
    """series: run_metrics.attitude_series (t, true_angle against the target), inside: run_metrics.settle_mask."""
    cfg = getattr(scenario, "passes", None)
    if cfg is None:
        return None
    t = np.asarray(series["t"], float)
    ang = np.asarray(series["true_angle"], float)
    inside = np.asarray(inside, bool)
    req = scenario.metrics.requirement_arcsec
    out = []
    for w in cfg.windows_at(t):
        tg = cfg.targets[w["target"]]
        i0, i1 = w["i0"], w["i1"]
        e = ang[i0:i1]
        settle = _settle(t[i0:i1], inside[i0:i1])
        mx = _f(np.max(e))
        entry = {"target": {"index": w["target"], "name": tg.name, "lat_deg": tg.lat_deg, "lon_deg": tg.lon_deg},
                 "start_s": float(t[i0]), "end_s": float(t[i1 - 1]), "duration_s": float((i1 - i0) * scenario.dt),
                 "closest_s": float(t[w["closest_i"]]), "min_off_nadir_deg": w["min_off_nadir_deg"],
                 "max_elevation_deg": w["max_elevation_deg"], "complete": bool(i0 > 0 and i1 < t.size),
                 "settle_s": settle, "pointing_rms_arcsec": _f(np.sqrt(np.mean(e * e))), "pointing_max_arcsec": mx}
        entry["meets_requirement"] = (None if req is None or mx is None else
                                      bool(settle == 0.0 and mx <= req))
        out.append(entry)
    return out


def _settle(t: np.ndarray, inside: np.ndarray):
    """From t[0] to the first sample after which every one is inside (None: the last one is not)."""
    if not inside[-1]:
        return None
    out = np.flatnonzero(~inside)
    return 0.0 if not out.size else float(t[int(out[-1]) + 1] - t[0])


def table_rows(passes: list[dict], requirement) -> list[tuple[str, str]]:
    """One summary line, and one per pass that misses the requirement."""
    if not passes:
        return [("target passes", "none in the run")]
    met = sum(1 for p in passes if p["meets_requirement"])
    worst = max(p["pointing_max_arcsec"] for p in passes if p["pointing_max_arcsec"] is not None)
    rows = [("target passes", f"{len(passes)} passes of {len({p['target']['name'] for p in passes})} targets, "
             f"{met} meet the requirement" + (f" ({requirement:g} arcsec)" if requirement is not None else "")
             + f"; worst pass max {worst:.3g} arcsec")]
    for p in passes:
        if p["meets_requirement"] is False:
            rows.append((f"pass {p['target']['name']} {p['start_s']:.0f} s",
                         "MISSED: " + ("not settled" if p["settle_s"] != 0.0 else "settled")
                         + f", max {p['pointing_max_arcsec']:.3g} arcsec"))
    return rows
