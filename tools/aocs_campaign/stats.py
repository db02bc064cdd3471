"""Statistics of a campaign (SPEC 5.4): per metric min / median / p95 / p99 / max, and per requirement
the pass fraction with its 95 % Wilson score interval.

Wilson interval (E. B. Wilson, "Probable inference, the law of succession, and statistical
inference", JASA 22 (1927) 209-212; Agresti and Coull, Am. Stat. 52 (1998) 119-126), for k passes
in n trials, p = k / n and z the two-sided normal quantile (1.959963984540054 for 95 %):

    centre    = (p + z^2 / (2 n)) / (1 + z^2 / n)
    half      = z / (1 + z^2 / n) * sqrt(p (1 - p) / n + z^2 / (4 n^2))
    interval  = [centre - half, centre + half]

It stays inside [0, 1] and is not degenerate at k = 0 or k = n (where the normal approximation
p +- z sqrt(p (1 - p) / n) collapses to a point).
"""
from __future__ import annotations

import math

import numpy as np

#: two-sided 95 % quantile of the standard normal, Phi^-1(0.975)
Z95 = 1.959963984540054
#: the percentiles of a metric's summary, in the order of the JSON
PERCENTILES = (("median", 50.0), ("p95", 95.0), ("p99", 99.0))


def wilson(k: int, n: int, z: float = Z95) -> tuple[float, float]:
    """95 % Wilson score interval of a binomial proportion k / n (formula in the module docstring)."""
    if n <= 0:
        raise ValueError(f"wilson: n = {n}: needs at least one trial")
    if not 0 <= k <= n:
        raise ValueError(f"wilson: k = {k} outside [0, n = {n}]")
    p = k / n
    z2 = z * z
    denom = 1.0 + z2 / n
    centre = (p + z2 / (2.0 * n)) / denom
    half = z / denom * math.sqrt(p * (1.0 - p) / n + z2 / (4.0 * n * n))
    return max(0.0, centre - half), min(1.0, centre + half)


def summary(values) -> dict:
    """min, median, p95, p99, max (linear interpolation between order statistics, numpy's default) and the
    count of finite values; None for each figure when there is none."""
    a = np.asarray([v for v in values if v is not None], dtype=float)
    a = a[np.isfinite(a)]
    out = {"n": int(a.size)}
    if a.size == 0:
        out.update({"min": None, **{k: None for k, _ in PERCENTILES}, "max": None})
        return out
    out["min"] = float(np.min(a))
    for k, q in PERCENTILES:
        out[k] = float(np.percentile(a, q))
    out["max"] = float(np.max(a))
    return out


def pass_fraction(flags) -> dict:
    """{passed, n, fraction, wilson95: [lo, hi]} of a list of booleans (None: the run gave no answer,
    counted as a failure: a run that crashed did not meet the requirement)."""
    n = len(flags)
    k = sum(1 for f in flags if f is True)
    if n == 0:
        return {"passed": 0, "n": 0, "fraction": None, "wilson95": None}
    lo, hi = wilson(k, n)
    return {"passed": k, "n": n, "fraction": k / n, "wilson95": [lo, hi]}
