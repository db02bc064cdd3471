"""Where a law's pointing error comes from when it flies the filter's estimate (issue 20; docs/spec.md 5.7.2).

A law of the PID family (quat_pd, quat_pid, lqr_quat_i; SPEC 2.1, 5.2) acts on the estimated attitude error
e = qe_vec(q_est, qd) and on the estimated rate w_est = gyro - b_hat; its integral state obeys z' = e:

    u_i = -kq_i e_i - kw_i w_est_i - kz_i z_i.

Near the target, per body axis with small angles (theta the true angle error, 2 qe_i), the attitude noise
n_th = estimate - truth (the knowledge error with its sign turned) and the rate noise n_w = w_est - w_true
(what the gyro's angle random walk leaves in the estimated rate, white: the MEKF does not filter the rate),
the rigid body J_i theta'' = u_i + d_i (d a constant disturbance torque) closes to

    D(s) theta = -(kq/2 s + kz/2) n_th - kw s n_w + s d,     D(s) = J s^3 + kw s^2 + kq/2 s + kz/2,

so the pointing error is the sum of linear paths: the attitude knowledge error through
T(s) = (kq/2 s + kz/2) / D(s), which is 1 at low frequency (a loop cannot point better than it knows where it
points) and peaks above 1 near the closed-loop poles; the gyro's rate noise through the derivative gain,
kw s / D(s); and the constant torque, which a law with integral action rejects and one without holds at
theta = d / (kq/2). `paths` drives them with a run's own logged noises (scipy.signal.lsim), so their sum can
be checked against the logged pointing error sample by sample; the gyroscopic, gravity-gradient and
cross-axis terms it leaves out are small in a hold.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import signal

from aocs_core.conventions import ARCSEC_PER_RAD

from . import estimation as E
from . import metrics as M
from .run_metrics import target_quat


@dataclass(frozen=True)
class AxisGains:
    """Per-axis gains of u = -kq e - kw w - kz z (N m per unit qe_vec, N m s/rad, N m/s per unit z)."""
    kq: float
    kw: float
    kz: float = 0.0


def closed_loop(j_kg_m2: float, g: AxisGains) -> tuple[tuple, tuple, tuple]:
    """(attitude-noise path, rate-noise path, disturbance-torque path) as (num, den) of s, with the pole at 0
    of a law without integral action cancelled."""
    if g.kz == 0.0:
        den = [j_kg_m2, g.kw, g.kq / 2.0]
        return ([-g.kq / 2.0], den), ([-g.kw], den), ([1.0], den)
    den = [j_kg_m2, g.kw, g.kq / 2.0, g.kz / 2.0]
    return ([-g.kq / 2.0, -g.kz / 2.0], den), ([-g.kw, 0.0], den), ([1.0, 0.0], den)


def t_peak(j_kg_m2: float, g: AxisGains) -> tuple[float, float]:
    """max |T(jw)| of the attitude-noise path and the w (rad/s) where it is."""
    (num, den), _, _ = closed_loop(j_kg_m2, g)
    w = np.logspace(-4, 2, 4000)
    _, h = signal.freqs(num, den, w)
    k = int(np.argmax(np.abs(h)))
    return float(np.abs(h[k])), float(w[k])


def paths(t_s, n_att_rad, n_rate_radps, j_diag, gains: list[AxisGains], d_nm=(0.0, 0.0, 0.0)) -> dict:
    """The paths driven by the logged noises and a constant disturbance torque d_nm (N m, B). t_s (n,);
    n_att_rad, n_rate_radps (n, 3) in B; j_diag the principal inertias (kg m^2); gains per axis. Returns per
    axis the pointing (rad) of each path and of their sum, as (n, 3) arrays, all from rest at t_s[0]:
    {"attitude": .., "rate": .., "disturbance": .., "total": ..}."""
    t = np.asarray(t_s, float)
    out = {k: np.zeros((t.size, 3)) for k in ("attitude", "rate", "disturbance")}
    for i in range(3):
        pa, pr, pd = closed_loop(float(j_diag[i]), gains[i])
        out["attitude"][:, i] = signal.lsim(pa, np.asarray(n_att_rad, float)[:, i], t)[1]
        out["rate"][:, i] = signal.lsim(pr, np.asarray(n_rate_radps, float)[:, i], t)[1]
        out["disturbance"][:, i] = signal.lsim(pd, np.full(t.size, float(d_nm[i])), t)[1]
    out["total"] = out["attitude"] + out["rate"] + out["disturbance"]
    return out


def noises_from_log(log, sc) -> dict:
    """From a run's LCM log (aocs_wire.lcmlog.read) of a scenario that flew a filter, the ticks both sides
    logged: t (n,), n_att_rad = -(knowledge error) (estimate - truth, B), n_rate_radps = w_est - w_true (B),
    pointing_rad = 2 qe_i of the truth against the reference (the per-axis pointing, SPEC 1.7)."""
    tr, cmd = log.truth, log.cmd
    rows = {int(k): i for i, k in enumerate(tr["tick"])}
    pairs = [(rows[int(k)], j) for j, k in enumerate(cmd["tick"]) if int(k) in rows]
    it, ic = (np.asarray(x, dtype=np.int64) for x in zip(*pairs))
    t = tr["t_s"][it]
    q_true = tr["q"][it]
    return {"t": t, "n_att_rad": -E.knowledge_error_rad(q_true, cmd["q_est"][ic]),
            "n_rate_radps": cmd["w_est"][ic] - tr["w"][it],
            "pointing_rad": M.pointing_errors_arcsec(q_true, target_quat(sc, t))["per_axis"] / ARCSEC_PER_RAD}
