"""Run metrics shared by `aocs run`, `aocs compare` and the benchmarks.

Everything is computed from the logged truth and command histories (numpy
arrays, one row per control period), never from the flight software's own
view, so a wrong sign or frame in the firmware shows up here.

Pointing errors follow SPEC section 1: the true angle 2 asin(|qe_vec|), the
per-axis error 2 qe_i, and the IRASSI report's figure |qe_i| ("qe_arcsec",
half the angle), always labelled separately.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from aocs_core.conventions import ARCSEC_PER_RAD, quat_conj_rows, quat_error_rows, quat_mul_rows

#: the row forms under the names the analysis has always used
quat_mul, quat_conj, error_quaternion = quat_mul_rows, quat_conj_rows, quat_error_rows


def pointing_errors_arcsec(q: np.ndarray, qd: np.ndarray) -> dict[str, np.ndarray]:
    """True angle, per-axis 2 qe_i and the reference's |qe_i|, all in arcsec."""
    qe = error_quaternion(q, qd)
    vec_norm = np.clip(np.linalg.norm(qe[..., :3], axis=-1), 0.0, 1.0)
    return {
        "true_angle": 2.0 * np.arcsin(vec_norm) * ARCSEC_PER_RAD,
        "per_axis": 2.0 * qe[..., :3] * ARCSEC_PER_RAD,
        "qe_arcsec": np.abs(qe[..., :3]) * ARCSEC_PER_RAD,
    }


def settle_time(t: np.ndarray, inside: np.ndarray) -> float | None:
    """First time after which the criterion holds until the end of the run.

    SPEC 4: settled = enters the criterion and stays in it until the end.
    None if the last sample is outside (never settled).
    """
    inside = np.asarray(inside, dtype=bool)
    if inside.size == 0 or not inside[-1]:
        return None
    outside = np.flatnonzero(~inside)
    first = 0 if outside.size == 0 else int(outside[-1]) + 1
    return float(t[first])


def window_mask(t: np.ndarray, window_s: float | None) -> np.ndarray:
    """Samples in the last window_s seconds of the run (all when None)."""
    t = np.asarray(t, float)
    if window_s is None or t.size == 0:
        return np.ones(t.shape, dtype=bool)
    return t >= t[-1] - window_s


def effort(t: np.ndarray, command: np.ndarray) -> float:
    """Integral of the command 1-norm over the run (ZOH: each command held for its period)."""
    t = np.asarray(t, float)
    if t.size < 2:
        return 0.0
    dt = np.diff(t)
    one_norm = np.sum(np.abs(command[:-1]), axis=-1)
    return float(np.sum(one_norm * dt))


def time_in_saturation(t: np.ndarray, saturated: np.ndarray) -> float:
    t = np.asarray(t, float)
    if t.size < 2:
        return 0.0
    return float(np.sum(np.diff(t) * np.asarray(saturated[:-1], bool)))


@dataclass(frozen=True)
class TimingSummary:
    step_ns_median: float
    step_ns_p99: float
    step_ns_max: float
    budget_ns: float
    overruns: int

    def as_dict(self) -> dict:
        return {
            "step_ns_median": self.step_ns_median,
            "step_ns_p99": self.step_ns_p99,
            "step_ns_max": self.step_ns_max,
            "budget_ns": self.budget_ns,
            "overruns": self.overruns,
        }


def timing_summary(step_ns: np.ndarray, budget_ns: float, overrun: np.ndarray) -> TimingSummary:
    step_ns = np.asarray(step_ns, float)
    if step_ns.size == 0:
        return TimingSummary(0.0, 0.0, 0.0, float(budget_ns), 0)
    return TimingSummary(
        step_ns_median=float(np.median(step_ns)),
        step_ns_p99=float(np.percentile(step_ns, 99)),
        step_ns_max=float(np.max(step_ns)),
        budget_ns=float(budget_ns),
        overruns=int(np.count_nonzero(overrun)),
    )
