"""Campaign statistics (aocs_campaign.stats): the 95 % Wilson score interval against values computed
independently (published tables and scipy's own implementation), and the metric summary."""
from __future__ import annotations

import numpy as np
import pytest
from scipy.stats import binomtest

from aocs_campaign import stats


# R. G. Newcombe, "Two-sided confidence intervals for the single proportion: comparison of seven
# methods", Statistics in Medicine 17 (1998) 857-872, Table II, method 3 (Wilson score, no continuity
# correction), to 4 decimals
@pytest.mark.parametrize("k,n,lo,hi", [
    (81, 263, 0.2553, 0.3662),
    (15, 148, 0.0624, 0.1605),
    (0, 20, 0.0000, 0.1611),
    (1, 29, 0.0061, 0.1718),
])
def test_wilson_matches_newcombe_table(k, n, lo, hi):
    got = stats.wilson(k, n)
    assert got[0] == pytest.approx(lo, abs=6e-5) and got[1] == pytest.approx(hi, abs=6e-5)


@pytest.mark.parametrize("k,n", [(0, 1), (1, 1), (3, 7), (500, 1000), (999, 1000), (1000, 1000), (17, 40)])
def test_wilson_matches_scipy(k, n):
    ci = binomtest(k, n).proportion_ci(confidence_level=0.95, method="wilson")
    got = stats.wilson(k, n)
    assert got[0] == pytest.approx(ci.low, abs=1e-12) and got[1] == pytest.approx(ci.high, abs=1e-12)


def test_wilson_refuses_impossible_counts():
    for k, n in ((1, 0), (-1, 5), (6, 5)):
        with pytest.raises(ValueError):
            stats.wilson(k, n)


def test_pass_fraction_counts_a_run_without_answer_as_not_passing():
    r = stats.pass_fraction([True, True, None, False])
    assert r["passed"] == 2 and r["n"] == 4 and r["fraction"] == 0.5
    assert r["wilson95"] == list(stats.wilson(2, 4))


def test_summary_percentiles_are_numpys_and_skip_missing_values():
    vals = [float(x) for x in np.arange(1, 101)] + [None, float("nan")]
    s = stats.summary(vals)
    a = np.arange(1, 101, dtype=float)
    assert s["n"] == 100 and s["min"] == 1.0 and s["max"] == 100.0
    assert s["median"] == np.percentile(a, 50) and s["p95"] == np.percentile(a, 95)
    assert s["p99"] == np.percentile(a, 99)
    assert stats.summary([None])["median"] is None
