"""The loop transfer measured in the SIL loop by input injection (docs/spec.md, "Stability margins").

Per axis i, one SIL run (plant_node, fsw_node, LCM, lockstep; aocs_runner.run) starts at the hold (on the
target, at its rate) with the actuator delayed by the modelled computation delay ([actuator]
delay_periods) and a multisine d(k) e_i held at the plant input ([disturbances.input_injection]). The
plant input is e(k) = u_applied(k) + d(k); u_applied(k) is the torque the plant applied over period k
(truth_t.torque_applied of tick k + 1), d(k) the injection (the same multisine function as the plant's).
After the closed loop's transient (5 time constants of its slowest pole, at least one window), every
tone's phasor of u_applied,i and of e_i is fitted by least squares over whole windows T = 2 pi / w0,
the tones being integer multiples of w0 (no leakage between tones), with a constant and a trend for the
constant disturbance and the integrators' slow drift; the measured loop is

    l_i(e^{j w dt}) = -U_applied,i(w) / E_i(w),

the same loop-at-a-time transfer as loop_model.loop_at (the other axes closed). The amplitude keeps the
predicted attitude excursion near 2e-5 rad per tone: well inside every law's linear region (the smc
boundary layer, the integrator clamps).
"""
from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import control
import numpy as np

from aocs_analysis import metrics as M
from aocs_analysis.run_metrics import attitude_series, target_quat
from aocs_core import conventions as C
from aocs_plant.effectors.input_injection import InputInjectionConfig, multisine, schroeder_phases
from aocs_runner.run import RunOptions, execute
from aocs_wire import lcmlog

from .law_models import LinearLaw
from .loop_model import AXES, closed_loop_poles, loop_at, response

#: tones as multiples of the axis loop's crossover frequency, from below to above it
TONE_FACTORS = (0.4, 0.6, 0.8, 1.0, 1.25, 1.6, 2.0)
#: the fundamental of the tone grid as a fraction of the crossover: window T = 2 pi / (FUNDAMENTAL w_c)
FUNDAMENTAL = 0.05
#: predicted attitude excursion per tone, rad
EXCURSION_RAD = 2e-5
WINDOWS = 2


@dataclass
class Plan:
    axis: int
    tones: tuple            # rad/s
    w0: float               # fundamental, rad/s
    amplitude_nm: float     # per tone
    settle_s: float
    duration_s: float


def slowest_decay(big_l, dt: float) -> float:
    """1/s: the decay rate of the slowest closed-loop pole."""
    r = float(np.max(np.abs(closed_loop_poles(big_l))))
    return -math.log(r) / dt


def plan(big_l, plant_model, axis: int, w_c: float, dt: float) -> Plan:
    nyq = math.pi / dt
    n_w = max(1, int(round(2.0 * math.pi / (FUNDAMENTAL * w_c) / dt)))
    w0 = 2.0 * math.pi / (n_w * dt)          # a whole number of samples per window
    tones = sorted({max(1, int(round(f * w_c / w0))) for f in TONE_FACTORS})
    tones = tuple(k * w0 for k in tones if k * w0 < 0.9 * nyq)
    # attitude i per unit torque at the plant input i, the loop closed: P_theta (1 + l)^-1
    pd = control.c2d(control.ss(plant_model.a, plant_model.b, np.eye(6), np.zeros((6, 3))), dt, "zoh")
    li = loop_at(big_l, axis)
    pt = response(pd, tones)[axis, axis]
    s = 1.0 / (1.0 + response(li, tones)[0, 0])
    amp = EXCURSION_RAD / float(np.max(np.abs(pt * s)))
    settle = max(5.0 / slowest_decay(big_l, dt), n_w * dt)
    duration = dt * math.ceil((settle + WINDOWS * n_w * dt) / dt)
    return Plan(axis, tones, w0, amp, settle, duration)


def hold_sets(sc, offset_rad=(0.0, 0.0, 0.0)) -> list[str]:
    """Scenario overrides that start the plant at the hold: on the target attitude (turned by the small
    rotation vector offset_rad, body axes) at its rate, in the representation the scenario's [plant]
    gives its attitude in (a second key would conflict with it)."""
    q = C.quat_mul(C.quat_from_rotvec(offset_rad), tuple(sc.target.qd0))     # q_BN = q_BT (x) q_TN
    key = sc.attitude.initial_input[0]
    value = {"euler321_deg": lambda: [math.degrees(a) for a in C.quat_to_euler321(q)],
             "rho": lambda: list(C.quat_to_crp(q)), "sigma": lambda: list(C.quat_to_mrp(q)),
             "quaternion": lambda: list(q)}[key]()
    return [f"plant.{key}={[float(x) for x in value]}", f"plant.w0={[float(x) for x in sc.target.wd]}"]


def injection_sets(p: Plan, sc, delay: int) -> list[str]:
    e = [0.0, 0.0, 0.0]
    e[p.axis] = 1.0
    return [f"actuator.delay_periods={delay}", "disturbances.input_injection.enabled=true",
            f"disturbances.input_injection.amplitude_nm={p.amplitude_nm!r}",
            f"disturbances.input_injection.frequency_rad_s={[float(w) for w in p.tones]}",
            f"disturbances.input_injection.direction={e}", *hold_sets(sc)]


def phasors(t: np.ndarray, x: np.ndarray, tones) -> np.ndarray:
    """Least-squares phasors (a + j b for a sin + b cos) of x at the tones, with a constant and a trend."""
    cols = [np.ones_like(t), t - t.mean()]
    for w in tones:
        cols += [np.sin(w * t), np.cos(w * t)]
    coef, *_ = np.linalg.lstsq(np.column_stack(cols), x, rcond=None)
    return np.array([coef[2 + 2 * k] + 1j * coef[3 + 2 * k] for k in range(len(tones))])


def estimate(log, p: Plan, sc, config: InputInjectionConfig) -> np.ndarray:
    """Measured l_i at the plan's tones (complex) from one run's log."""
    dt = sc.dt
    tick = np.asarray(log.truth["tick"])
    applied = np.asarray(log.truth["torque_applied"])[1:, p.axis]     # over period k = tick - 1
    k = tick[1:] - 1
    t = k * dt
    d = np.array([multisine(config, float(x)) for x in t])
    e = applied + d
    n_w = int(round(2.0 * math.pi / p.w0 / dt))
    m = t >= t[-1] + dt - WINDOWS * n_w * dt - 1e-9
    return -phasors(t[m], applied[m], p.tones) / phasors(t[m], e[m], p.tones)


def law_residual(log, sc, law: LinearLaw) -> float:
    """The linear law against the real C law: the model's command from the logged states (the true attitude
    and rate at each tick, what the perfect sensors gave the law), its integrator started at zero like the
    law's, minus the command the flight software logged; max |difference| over the peak-to-peak of the
    logged command (the expansion's second-order terms, the float formatting)."""
    s = attitude_series(sc, log)
    n = log.cmd["tick"].size
    if law.output == "euler":
        y = np.hstack([s["euler_err"][:n, ::-1], s["we"][:n]])       # [roll pitch yaw], rates (1st order)
    else:
        # theta = 2 qe_vec: the law reads qe_vec, the model theta / 2 of it (law_models)
        qe = M.error_quaternion(np.asarray(log.truth["q"][:n]), target_quat(sc, log.truth["t_s"][:n]))
        y = np.hstack([2.0 * qe[:, :3], s["we"][:n]])
    z = np.zeros(law.states)
    u_model = np.empty((n, 3))
    for k in range(n):
        u_model[k] = law.cc @ z + law.dc @ y[k]
        z = z + sc.dt * (law.bc @ y[k])
    u_log = np.asarray(log.cmd["u_sat"])[:n]
    span = float(np.max(np.ptp(u_log, axis=0)))
    return float(np.max(np.abs(u_model - u_log)) / span) if span > 0 else math.inf


def measure_axis(scenario: str, sc, law: LinearLaw, big_l, plant_model, axis: int, w_c: float, delay: int, out: Path,
                 progress=None) -> tuple[float, list[dict]]:
    """One SIL run injecting at `axis`: the law residual (law_residual) and [{frequency_rad_s, gain_db,
    phase_deg, predicted_gain_db, predicted_phase_deg}] per tone."""
    p = plan(big_l, plant_model, axis, w_c, sc.dt)
    sets = injection_sets(p, sc, delay)
    if law.table:
        sets.append(f'laws.{law.law}.table="{law.table}"')
    run_dir = out / f"inject-{AXES[axis]}"
    if progress:
        progress(f"{sc.id} {law.law} axis {AXES[axis]}: {len(p.tones)} tones {p.tones[0]:.3g}..{p.tones[-1]:.3g} "
                 f"rad/s, {p.duration_s:g} s", int(round(p.duration_s / sc.dt)))
    res = execute(RunOptions(scenario=scenario, law=law.law,
                             duration=p.duration_s, sets=sets, out=str(run_dir), plots=False, quiet=True,
                             label=f"{law.law} inject {AXES[axis]}"))
    if not res.metrics["verdict"]["passed"]:
        raise RuntimeError("; ".join(f["reason"] for f in res.metrics["verdict"]["failures"]))
    cfg = InputInjectionConfig(True, 1.0, p.amplitude_nm, p.tones, schroeder_phases(len(p.tones)),
                               tuple(1.0 if i == axis else 0.0 for i in range(3)))
    log = lcmlog.read(run_dir / "run.lcmlog")
    meas = estimate(log, p, sc, cfg)
    pred = response(loop_at(big_l, axis), p.tones)[0, 0]
    residual = law_residual(log, sc, law)
    return residual, [{"frequency_rad_s": float(w), "gain_db": float(20 * np.log10(abs(m))),
             "phase_deg": float(np.degrees(np.angle(m))),
             "predicted_gain_db": float(20 * np.log10(abs(q))), "predicted_phase_deg": float(np.degrees(np.angle(q))),
             "amplitude_nm": p.amplitude_nm}
            for w, m, q in zip(p.tones, meas, pred)]
