"""H-infinity attenuation measured where it matters: a frequency sweep of the SIL loop.

For each frequency w a real SIL run of the H-infinity scenario (plant_node,
fsw_node, LCM; aocs_runner.run) starts at rest on the LVLH target with only a
sinusoidal disturbance torque d(t) = A e sin(w t) along a unit direction e
(`[disturbances.sinusoidal_torque]`); the constant torque is off, the Earth
gravity gradient stays (it is part of the linearised plant, SPEC 2.6). After
the closed loop's transient has died out (5 time constants of its slowest pole)
the performance output

    z = 1e-3 M q''   (SPEC 2.6, q = [phi theta psi] of the error quaternion)

is obtained from the logged attitude by second differences (as
aocs_analysis.run_metrics.hinf_measured_gain does), each component is fitted with
a sin(w t) + b cos(w t) + c over whole cycles, and the measured gain is
|Z| / A with |Z|^2 = sum_i (a_i^2 + b_i^2): the steady-state amplitude ratio of
the loop in direction e. It is compared with the design's own prediction
|Gzd(jw) e| from the linear model and the compiled K, below
sigma_max(Gzd(jw)) and gamma (docs/results.md plots all four).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from aocs_analysis import plots as P
from aocs_analysis import run_metrics as results
from aocs_design.lmi_hinf import closed_loop
from aocs_design.models import hinf_model
from aocs_plant.scenario import load
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog

from .compare import designed_gamma, gain_matrix

#: default sweep, rad/s: from below the loop's bandwidth (slowest closed-loop pole 0.05 /s for geo_hinf) to 1 rad/s
FREQUENCIES = (0.003, 0.01, 0.03, 0.1, 0.3, 1.0)
#: disturbance amplitude, N m: 10x the scenario's constant torque, small enough to stay linear
AMPLITUDE_NM = 1e-3
DIRECTION = (1.0 / math.sqrt(3.0),) * 3
CYCLES_MEASURED = 2
#: the initial state of every sweep run: on the LVLH target, at its rate (results_doc.HINF_ZERO_IC)
ZERO_IC = ("plant.euler321_deg=[0.0, 0.0, 0.0]", "plant.w0=[0.0, -7.292115e-05, 0.0]")


@dataclass
class SweepPoint:
    w_rad_s: float
    measured: float | None
    design: float           # |Gzd(jw) e|
    sigma_max: float        # sigma_max(Gzd(jw))
    duration_s: float
    error: str | None = None


def design_response(sc, table: str):
    """(A, B, C, D) of d -> z for the compiled K of `table`, from the design model of the scenario's data."""
    j = np.diag(np.asarray(sc.attitude.inertia, float))
    w0 = -float(sc.target.wd[1])              # the LVLH rate (0, -w0, 0)
    return closed_loop(hinf_model(j[0], j[1], j[2], w0), gain_matrix(table))


def gzd(resp, w: float) -> np.ndarray:
    a, b, c, d = resp
    return c @ np.linalg.solve(1j * w * np.eye(a.shape[0]) - a, b) + d


def measured_gain(log, sc, w: float, amplitude: float, t_from: float) -> float:
    """Steady-state |Z| / A of z = 1e-3 M q'' at w, fitted over whole cycles after t_from."""
    s = results.attitude_series(sc, log)
    ang = s["euler_err"][:, ::-1]            # [yaw, pitch, roll] -> [phi, theta, psi]
    dt = sc.dt
    t = log.truth["t_s"][1:-1]
    z = 1e-3 * (ang[2:] - 2.0 * ang[1:-1] + ang[:-2]) / dt ** 2 * np.diag(np.asarray(sc.attitude.inertia, float))
    period = 2.0 * math.pi / w
    t_end = t_from + math.floor((t[-1] - t_from) / period) * period
    m = (t >= t_from) & (t <= t_end)
    basis = np.column_stack([np.sin(w * t[m]), np.cos(w * t[m]), np.ones(np.count_nonzero(m))])
    coef, *_ = np.linalg.lstsq(basis, z[m], rcond=None)
    return float(math.sqrt(np.sum(coef[0] ** 2 + coef[1] ** 2))) / amplitude


def slowest_pole(sc, table: str | None = None) -> float:
    """|Re| of the slowest closed-loop pole of the design model with the table's K, 1/s."""
    resp = design_response(sc, table or sc.control.laws["hinf"].table)
    return float(-max(np.linalg.eigvals(resp[0]).real))


def sweep_duration(sc, slowest: float, w: float) -> float:
    """Simulated time of the run at w: 5 time constants of the slowest pole, then the measured cycles."""
    period = 2.0 * math.pi / w
    return sc.dt * math.ceil((5.0 / slowest + (CYCLES_MEASURED + 0.5) * period) / sc.dt)


def sweep(out: Path, *, scenario: str = "geo_hinf", table: str | None = None, freqs=FREQUENCIES,
          amplitude: float = AMPLITUDE_NM, direction=DIRECTION, quiet: bool = False,
          progress=None) -> tuple[list[SweepPoint], dict]:
    """One SIL run per frequency (inside the private network namespace); returns the points and a summary.
    progress: called with (label, steps) before each run instead of the 'sweep:' line."""
    sc = load(scenario)
    table = table or sc.control.laws["hinf"].table
    resp = design_response(sc, table)
    slowest = slowest_pole(sc, table)
    settle = 5.0 / slowest
    e = np.asarray(direction, float)
    e = e / np.linalg.norm(e)
    points = []
    for k, w in enumerate(freqs):
        duration = sweep_duration(sc, slowest, w)
        amp = [float(amplitude * abs(x)) for x in e]
        phase = [0.0 if x >= 0 else math.pi for x in e]
        sets = [*ZERO_IC, "disturbances.constant_torque.enabled=false",
                "disturbances.sinusoidal_torque.enabled=true", f"disturbances.sinusoidal_torque.amplitude_nm={amp}",
                f"disturbances.sinusoidal_torque.frequency_rad_s={[float(w)] * 3}",
                f"disturbances.sinusoidal_torque.phase_rad={phase}", f'laws.hinf.table="{table}"']
        g = gzd(resp, w)
        pt = SweepPoint(w, None, float(np.linalg.norm(g @ e)), float(np.linalg.svd(g, compute_uv=False)[0]), duration)
        if progress is not None:
            progress(f"{scenario} sweep {k + 1}/{len(freqs)}, w = {w:g} rad/s", int(round(duration / sc.dt)))
        elif not quiet:
            print(f"sweep: {k + 1}/{len(freqs)} w = {w:g} rad/s, {duration:g} s of simulation", flush=True)
        run_dir = out / f"w{w:g}"
        try:
            res = execute(RunOptions(scenario=scenario, law="hinf", duration=duration, sets=sets, out=str(run_dir),
                                     plots=False, quiet=True, label=f"w = {w:g} rad/s"))
            if not res.metrics["verdict"]["passed"]:
                pt.error = "; ".join(f["reason"] for f in res.metrics["verdict"]["failures"])
            else:
                pt.measured = measured_gain(lcmlog.read(run_dir / "run.lcmlog"), sc, w, amplitude, settle)
        except Exception as exc:  # noqa: BLE001 - a failed run is recorded with its reason, the sweep goes on
            pt.error = str(exc)
        points.append(pt)
    gamma = designed_gamma(table)
    ok = [p for p in points if p.measured is not None]
    summary = {"scenario": scenario, "table": table, "gamma": gamma, "amplitude_nm": amplitude,
               "direction": e.tolist(), "slowest_pole_re": -slowest,
               "points": [vars(p) for p in points],
               "within_factor_2": all(0.5 <= p.measured / p.design <= 2.0 for p in ok),
               "below_gamma": all(p.measured <= gamma for p in ok), "failed": len(points) - len(ok)}
    return points, summary


def plot(points: list[SweepPoint], summary: dict, path: Path) -> Path:
    resp_w = np.logspace(math.log10(min(p.w_rad_s for p in points)) - 0.5,
                         math.log10(max(p.w_rad_s for p in points)) + 0.5, 300)
    sc = load(summary["scenario"])
    resp = design_response(sc, summary["table"])
    e = np.asarray(summary["direction"])
    sig = [np.linalg.svd(gzd(resp, w), compute_uv=False)[0] for w in resp_w]
    dir_gain = [np.linalg.norm(gzd(resp, w) @ e) for w in resp_w]
    fig, ax = P.new_axes(f"{summary['scenario']} ({summary['table']}): disturbance-to-output gain of the SIL loop",
                         "gain |z| / |d| (z = 1e-3 M q'', d in N m)", 4.5, xlabel="frequency (rad/s)")
    ax.loglog(resp_w, sig, color="tab:blue", lw=1.2, label="design: sigma_max(Gzd(jw))")
    ax.loglog(resp_w, dir_gain, color="tab:orange", lw=1.2, ls="--", label="design: |Gzd(jw) e| (sweep direction)")
    ok = [p for p in points if p.measured is not None]
    ax.loglog([p.w_rad_s for p in ok], [p.measured for p in ok], "o", color="black", ms=6,
              label=f"measured in the SIL loop ({len(ok)} runs)")
    ax.axhline(summary["gamma"], color="red", ls=":", lw=1.2, label=f"gamma of K = {summary['gamma']:.4g}")
    P.legend(ax)
    return P.save(fig, path)
