"""The eigenaxis bang-bang lower bound of a rest-to-rest slew (docs/spec.md "Slew guidance", SPEC 5.1).

For reporting only (the run JSON's `slew_bound_s`, `aocs compare --guidance slew`): from the scenario's
inertia J, initial attitude q0, target qd_f and actuator envelope,

    dq = qd_f (x) q0^-1 (short way),  theta_f = 2 atan2(|dq_vec|, |dq4|),  e = dq_vec / |dq_vec|,
    alpha = max{a : J a e inside the envelope}
          = min(min_i u_i / |(J e)_i|  (per-axis box),  u_norm / |J e|  (norm ball),
                min_i u_s,max,i / |(Gs^+ J e)_i| over the healthy wheels  (a [wheels] array, SPEC 5.3)),
    bound = 2 sqrt(theta_f / alpha)          (margin 1, no rate limit, no gyroscopic allowance).

It is the time of the eigenaxis bang-bang manoeuvre at the envelope's full acceleration along e
(B. Wie, Space Vehicle Dynamics and Control: time-optimal eigenaxis slews). The firmware's profile
(aocs/guidance/slew.h) is slower by its margin and the allowance it keeps for the gyroscopic torque.
"""
from __future__ import annotations

import math

import numpy as np

from aocs_core.conventions import quat_conj, quat_mul


def eigenaxis(q0, qf) -> tuple[float, np.ndarray]:
    """(theta_f rad in [0, pi], unit axis e) of the rotation qf (x) q0^-1, the short way."""
    dq = np.asarray(quat_mul(tuple(map(float, qf)), quat_conj(tuple(map(float, q0)))), float)
    if dq[3] < 0.0:
        dq = -dq
    s = float(np.linalg.norm(dq[:3]))
    if s == 0.0:
        return 0.0, np.array([1.0, 0.0, 0.0])
    return 2.0 * math.atan2(s, float(dq[3])), dq[:3] / s


def alpha_max(inertia, e, axis_limit: float | None, norm_limit: float | None, wheels=None) -> float:
    """Largest acceleration along e (rad/s^2) whose torque J alpha e lies inside the envelope; wheels: the
    scenario's [wheels] config (the minimum-norm allocation over the healthy wheels, unscaled)."""
    je = np.asarray(inertia, float) @ np.asarray(e, float)
    alpha = math.inf
    if wheels is not None:
        healthy = [i for i in range(wheels.n) if i not in wheels.failed]
        d = np.abs(np.linalg.pinv(np.array([wheels.axes[i] for i in healthy]).T) @ je)
        umax = np.array([wheels.torque_limit_nm[i] for i in healthy])
        alpha = min(alpha, float(np.min(umax[d > 0.0] / d[d > 0.0])))
    if axis_limit is not None:
        for x in je:
            if abs(x) > 0.0:
                alpha = min(alpha, float(axis_limit) / abs(float(x)))
    if norm_limit is not None:
        alpha = min(alpha, float(norm_limit) / float(np.linalg.norm(je)))
    return alpha


def slew_bound_s(inertia, q0, qf, axis_limit: float | None, norm_limit: float | None,
                 wheels=None) -> float | None:
    """2 sqrt(theta_f / alpha); None without any limit (no bound: unlimited torque), 0 for no rotation."""
    if axis_limit is None and norm_limit is None and wheels is None:
        return None
    theta, e = eigenaxis(q0, qf)
    if theta == 0.0:
        return 0.0
    return 2.0 * math.sqrt(theta / alpha_max(inertia, e, axis_limit, norm_limit, wheels))


def scenario_slew_bound_s(sc) -> float | None:
    """The bound for an attitude scenario (after its overrides, e.g. --limit), None for orbit scenarios
    or when no actuator limit is set."""
    if sc.kind != "attitude" or sc.attitude is None or sc.target is None:
        return None
    return slew_bound_s(sc.attitude.inertia, sc.attitude.q0, sc.target.qd0, sc.actuator.axis_limit,
                        sc.actuator.norm_limit, sc.effectors.get("wheels"))
