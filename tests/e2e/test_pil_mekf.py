"""The MEKF on the PIL images (issue 20), irassi_hold_mekf cut to 30 s (300 steps: the filter starts on its first
tracker sample and is at its steady state within a few seconds; the full 2000 s run is `make pil-mekf`, its
figures in docs/pil.md).

- The M4F (float) image fed the host's own sensor samples gives the host's (double) estimate to within
  aocs_pil.mekf_check.FLOAT_TOLERANCE_ARCSEC, a bound derived from binary32 quaternion rounding (two roundings
  of a unit quaternion, 2^-22 rad), recomputed here; a filter computing anything else (another gain, a lost
  update, a wrong reset) would part from the host's by the knowledge error itself, ~1 arcsec.
- Every step on both cores is within its budget (the law's row plus the MEKF's allowance of the registry,
  read here) and its count is exact: with the MEKF the image waits for a whole SysTick period before each
  step (pil_icount.h), so no reload falls inside a 20000-40000-instruction step."""
from __future__ import annotations

import os

import pytest

from aocs_core import registry
from aocs_core.conventions import ARCSEC_PER_RAD
from aocs_pil import mekf_check
from pil_support import TARGETS, image

DURATION_S = 30.0


@pytest.fixture(scope="module")
def result(aocs_build_dir, private_netns, aocs_lcm):
    os.environ["AOCS_BUILD_DIR"] = str(aocs_build_dir)
    for t in TARGETS:
        image(t)
    return mekf_check.check("quat_pid", DURATION_S, log=lambda s: None, split=False)


def test_the_float_image_estimates_as_the_double_host_to_float_rounding(result):
    assert mekf_check.FLOAT_TOLERANCE_ARCSEC == pytest.approx(2.0 * 2.0 * 2.0 * 2.0 ** -25 * ARCSEC_PER_RAD)
    s = result["same_samples"]
    assert s["steps_compared"] == int(DURATION_S * 10)
    assert s["estimate_diff_max_arcsec"] <= mekf_check.FLOAT_TOLERANCE_ARCSEC, s
    assert s["estimate_diff_max_arcsec"] > 0.0   # the float image does round: the comparison is not vacuous


def test_every_mekf_step_is_counted_exactly_within_its_budget(result):
    reg = registry.load()
    for row in result["instructions"]:
        core = {"pil-m4f": "cortex-m4f", "pil-m7": "cortex-m7"}[row["target"]]
        law = reg.law("quat_pid").budget_instructions[core]
        assert row["budget"] == law + mekf_allowance(reg, core) + reg.fdir_instructions[core]
        assert row["inexact"] == 0 and row["overruns"] == 0 and row["max"] <= row["budget"], row
        assert row["estimate_invalid_steps"] == 0
        # a step that skipped the filter costs at most the law's budget; the MEKF's steps cost several times that
        assert row["median"] > 3 * law, row


def mekf_allowance(reg, core) -> int:
    return reg.estimators["mekf"][1][core]
