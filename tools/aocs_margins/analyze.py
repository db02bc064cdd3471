"""One law on one scenario: the margins predicted at its control rate, continuous, at lower rates, the
saturation check, and (optionally) measured in the SIL loop (docs/spec.md, "Stability margins")."""
from __future__ import annotations

import math
from pathlib import Path

import numpy as np

from . import law_models, loop_model, margins, measure

#: the requirements the verdict of the table is against
REQUIRED_GAIN_MARGIN_DB = 6.0
REQUIRED_PHASE_MARGIN_DEG = 30.0
REQUIRED_MODULUS_MARGIN = 0.5
#: the agreement asked of the measured loop (issue 22)
AGREE_DB, AGREE_DEG = 1.0, 5.0
#: the control rates searched for the lowest that keeps the margins, Hz
RATE_MIN_HZ, RATE_MAX_HZ = 0.05, 100.0


def meets(loops: dict) -> bool:
    """Every axis loop and the MIMO loop keep 6 dB and 30 deg (a missing gain margin: infinite)."""
    for m in loops.values():
        gm, pm = m["gain_margin_db"], m["phase_margin_deg"]
        if (gm is not None and gm < REQUIRED_GAIN_MARGIN_DB) or pm is None or pm < REQUIRED_PHASE_MARGIN_DEG:
            return False
        if m.get("gain_margin_low_db") is not None and m["gain_margin_low_db"] > -REQUIRED_GAIN_MARGIN_DB:
            return False
    return True


def build_loop(sc, law: law_models.LinearLaw, dt: float | None, delay: int):
    p = loop_model.plant(sc, law.output)
    return p, loop_model.loop(p, law, dt, delay)


def lowest_rate_hz(sc, law, delay: int) -> float | None:
    """The lowest control rate (Hz, to 1 %) at which the sampled loop with `delay` keeps 6 dB / 30 deg
    with the same gains (the margins fall as the rate falls; bisection in log rate)."""
    def ok(f):
        _, big_l = build_loop(sc, law, 1.0 / f, delay)
        return loop_model.is_stable(big_l) and meets(margins.loops(big_l, margins.grid(1.0 / f, n=800), disk=False))
    if not ok(RATE_MAX_HZ):
        return None
    lo, hi = RATE_MIN_HZ, RATE_MAX_HZ
    if ok(lo):
        return lo
    while hi / lo > 1.01:
        mid = math.sqrt(lo * hi)
        lo, hi = (lo, mid) if ok(mid) else (mid, hi)
    return hi


def describing_function(loops: dict, limit_nm: float | None) -> dict | None:
    """Saturation at the plant input (|u_i| <= limit): N(A) is real in (0, 1], so -1/N(A) covers the real
    axis left of -1; a limit cycle is predicted where an axis loop crosses the negative real axis beyond
    -1 (|l| > 1 at arg l = -180 deg: the lower gain margins), at the amplitude A with N(A) = 1/|l|:
    N(A) = (2/pi) (asin(r) + r sqrt(1 - r^2)), r = limit / A (Gelb and Vander Velde 1968)."""
    if limit_nm is None:
        return None
    out = {"limit_nm": limit_nm, "axes": {}}
    for ax in loop_model.AXES:
        g_low = loops[ax]["gain_margin_low_db"]
        if g_low is None:
            out["axes"][ax] = {"limit_cycle": False}
            continue
        n_a = 10 ** (g_low / 20.0)          # N(A) = 1 / |l| at the crossing
        r = _solve_saturation(n_a)
        out["axes"][ax] = {"limit_cycle": True, "n_of_a": n_a, "command_amplitude_nm": limit_nm / r}
    return out


def _solve_saturation(n: float) -> float:
    """r in (0, 1] with (2/pi)(asin r + r sqrt(1 - r^2)) = n."""
    lo, hi = 0.0, 1.0
    for _ in range(80):
        mid = 0.5 * (lo + hi)
        v = 2.0 / math.pi * (math.asin(mid) + mid * math.sqrt(1.0 - mid * mid))
        lo, hi = (mid, hi) if v < n else (lo, mid)
    return 0.5 * (lo + hi)


def analyse(sc, law_name: str, table: str | None, *, delay: int = 1, rates: bool = True) -> tuple[dict, object]:
    """The prediction of one law (no SIL run); returns (the JSON dict, the discrete MIMO loop)."""
    law = law_models.linear_law(sc, law_name, table)
    _, big_l = build_loop(sc, law, sc.dt, delay)
    loops = margins.loops(big_l)
    _, big_c = build_loop(sc, law, None, 0)
    cont = margins.loops(big_c, margins.grid(None, w_max=10.0 * math.pi / sc.dt))
    limit = sc.actuator.axis_limit if getattr(sc, "actuator", None) and sc.actuator.axis_limit else \
        getattr(sc.actuator, "realistic_axis_limit", None) if getattr(sc, "actuator", None) else None
    out = {
        "scenario": sc.id, "law": law_name, "table": law.table, "control_rate_hz": 1.0 / sc.dt, "dt_s": sc.dt,
        "delay_periods": delay, "linear_region": law.region,
        "loops": loops,
        "continuous": {k: {f: v[f] for f in ("gain_margin_db", "phase_margin_deg", "delay_margin_s",
                                             "modulus_margin", "crossover_rad_s")} for k, v in cont.items()},
        "requirements": {"gain_margin_db": REQUIRED_GAIN_MARGIN_DB, "phase_margin_deg": REQUIRED_PHASE_MARGIN_DEG,
                         "modulus_margin": REQUIRED_MODULUS_MARGIN},
        "meets_requirements": meets(loops) and all(m["modulus_margin"] >= REQUIRED_MODULUS_MARGIN
                                                   for m in loops.values()),
        "describing_function": describing_function(loops, limit),
    }
    out["sampled_loss"] = {k: {"phase_margin_deg": _diff(cont[k]["phase_margin_deg"], loops[k]["phase_margin_deg"]),
                               "gain_margin_db": _diff(cont[k]["gain_margin_db"], loops[k]["gain_margin_db"])}
                           for k in loops}
    if rates:
        out["lowest_rate_hz"] = lowest_rate_hz(sc, law, delay)
    return out, big_l


def _diff(a, b):
    if a is None and b is None:
        return 0.0
    if a is None:
        return math.inf if b is not None else None
    return None if b is None else float(a - b)


def measured(scenario: str, sc, result: dict, big_l, out: Path, progress=None) -> None:
    """Adds `measured` to each axis loop of `result` (one SIL run per axis) and the agreement summary."""
    law = law_models.linear_law(sc, result["law"], result["table"])
    p = loop_model.plant(sc, law.output)
    worst_db = worst_deg = 0.0
    for i, ax in enumerate(loop_model.AXES):
        w_c = result["loops"][ax]["crossover_rad_s"] or result["loops"]["mimo"]["crossover_rad_s"]
        res, pts = measure.measure_axis(scenario, sc, law, big_l, p, i, w_c, result["delay_periods"], out, progress)
        result["loops"][ax]["measured"] = pts
        result["loops"][ax]["law_residual"] = res
        for q in pts:
            worst_db = max(worst_db, abs(q["gain_db"] - q["predicted_gain_db"]))
            worst_deg = max(worst_deg, abs((q["phase_deg"] - q["predicted_phase_deg"] + 180.0) % 360.0 - 180.0))
    result["agreement"] = {"worst_gain_db": worst_db, "worst_phase_deg": worst_deg,
                           "worst_law_residual": max(result["loops"][a]["law_residual"] for a in loop_model.AXES),
                           "within": bool(worst_db <= AGREE_DB and worst_deg <= AGREE_DEG),
                           "required_db": AGREE_DB, "required_deg": AGREE_DEG}


def summary_rows(result: dict) -> list[list[str]]:
    rows = []
    for k, m in result["loops"].items():
        rows.append([k, _f(m["gain_margin_db"], ".2f"), _f(m["phase_margin_deg"], ".1f"),
                     _f(m["delay_margin_s"], ".3f"), _f(m["modulus_margin"], ".3f"), _f(m["crossover_rad_s"], ".3g"),
                     _f(m.get("disk_margin"), ".3f")])
    return rows


def _f(x, fmt):
    return "inf" if x is None else format(x, fmt)


def finite_json(x):
    """Non-finite floats as None (JSON)."""
    if isinstance(x, dict):
        return {k: finite_json(v) for k, v in x.items()}
    if isinstance(x, (list, tuple)):
        return [finite_json(v) for v in x]
    if isinstance(x, (float, np.floating)):
        return float(x) if math.isfinite(x) else None
    if isinstance(x, np.bool_):
        return bool(x)
    return x


#: the loop gains of the two verification runs, as fractions of the predicted (uniform) gain margin
VERIFY_FACTORS = (0.9, 1.1)
#: predicted growth of the outside run over its duration, and the initial attitude offset about body x, deg
VERIFY_GROWTH = 1e6
VERIFY_OFFSET_DEG = 1e-3
#: a run diverged when its error at the end is this many times its error at the start
DIVERGED_RATIO = 100.0


def verify_gain_margin(scenario: str, sc, result: dict, big_l, out: Path, progress=None) -> dict:
    """Two SIL runs from a small offset of the hold with the delivered torque scaled by k ([actuator]
    scale_factor = a loop gain k at the plant input): k = 0.9 and 1.1 times the predicted uniform gain
    margin. The first must converge (error at the end below the start), the second diverge (error at the
    end > 100x the start, or the run's verdict fails as the plant diverges)."""
    from aocs_runner.run import RunFailed, RunOptions, execute  # deferred: the runner only for --verify
    from aocs_wire import lcmlog  # deferred: as above

    gm_db = result["loops"]["mimo"]["gain_margin_db"]
    if gm_db is None:
        return {"verified": None, "reason": "no finite gain margin"}
    k_gm = 10.0 ** (gm_db / 20.0)
    rho_out = float(np.max(np.abs(loop_model.closed_loop_poles(big_l, VERIFY_FACTORS[1] * k_gm))))
    steps = int(math.ceil(math.log(VERIFY_GROWTH) / math.log(rho_out)))
    duration = steps * sc.dt
    runs = []
    for f in VERIFY_FACTORS:
        k = f * k_gm
        sets = [f"actuator.delay_periods={result['delay_periods']}", f"actuator.scale_factor={k!r}",
                *measure.hold_sets(sc, (math.radians(VERIFY_OFFSET_DEG), 0.0, 0.0))]
        if result["table"]:
            sets.append(f'laws.{result["law"]}.table="{result["table"]}"')
        run_dir = out / f"gain-{f:g}"
        if progress:
            progress(f"{sc.id} {result['law']}: loop gain {k:.4g} ({f:g} x the gain margin), {duration:g} s", steps)
        rec = {"factor_of_margin": f, "loop_gain": k,
               "predicted_spectral_radius": float(np.max(np.abs(loop_model.closed_loop_poles(big_l, k))))}
        try:
            res = execute(RunOptions(scenario=scenario, law=result["law"], duration=duration, sets=sets,
                                     out=str(run_dir), plots=False, quiet=True, label=f"gain {f:g} x GM"))
            err = np.asarray(lcmlog.read(run_dir / "run.lcmlog").truth["pointing_err_arcsec"], float)
            n = max(1, err.size // 20)
            start, end = float(np.max(err[:n])), float(np.max(err[-n:]))
            rec.update(start_arcsec=start, end_arcsec=end, verdict_passed=res.metrics["verdict"]["passed"],
                       verdict_failures=[x["check"] for x in res.metrics["verdict"]["failures"]])
            rec["diverged"] = bool(not math.isfinite(end) or end > DIVERGED_RATIO * start
                                   or "non-finite" in rec["verdict_failures"])
            rec["converged"] = bool(math.isfinite(end) and end < start and res.metrics["verdict"]["passed"])
        except RunFailed as exc:
            rec.update(diverged=True, converged=False, run_failed=str(exc))
        runs.append(rec)
    return {"runs": runs, "duration_s": duration, "offset_deg": VERIFY_OFFSET_DEG,
            "verified": bool(runs[0]["converged"] and runs[1]["diverged"])}
