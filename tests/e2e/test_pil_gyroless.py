"""The MEKF without its gyro on the PIL images (docs/spec.md 5.6.12; QEMU Cortex-M4F float, Cortex-M7 double):
irassi_rw_mekf's slew flown on the image in the closed loop of the in-process plant (aocs_pil.harness
.run_direct), the gyro's x axis stuck from 60 s. On the target the fault management names it within a
second, the filter goes on without it on the rigid-body dynamics, the executive passes through SAFE while the
rate converges and flies NOMINAL again: the image ends in NOMINAL. Every step's instruction count is exact and
within the budget the image reports (the gyroless propagation and update included); the counts before and
after the switch are printed (`pytest -s tests/e2e/test_pil_gyroless.py`)."""
from __future__ import annotations

import statistics

import pytest

from aocs_core.modes import mode_value
from aocs_pil import harness
from pil_support import TARGETS

FAULT_S = 60.0
DURATION_S = 90.0
PERIOD_S = 0.1


@pytest.mark.parametrize("target", TARGETS)
def test_the_image_flies_on_without_its_gyro_within_its_budget(target):
    r = harness.run_direct("irassi_rw_mekf", "quat_pd", target, duration_s=DURATION_S,
                           overrides={"faults": [{"kind": "gyro_stuck_axis", "unit": 0, "start_s": FAULT_S}]})
    modes = [x.mode for x in r.replies]
    k_fault = int(round(FAULT_S / PERIOD_S))
    safe, nominal = mode_value("safe"), mode_value("nominal")
    assert nominal == modes[k_fault - 1] == modes[-1]
    k_safe = modes.index(safe, k_fault)
    assert k_safe <= k_fault + 20                       # the 10th identical sample, then SAFE
    assert safe not in modes[k_safe + 100:]             # back to NOMINAL within 10 s, for good
    ins = r.instructions
    budget = r.replies[-1].budget
    before, after = ins[k_fault - 300:k_fault], ins[k_safe + 100:]
    print(f"\n{target}: gyro MEKF step median {statistics.median(before):.0f} max {max(before)}; "
          f"gyroless median {statistics.median(after):.0f} max {max(after)}; switch steps "
          f"{ins[k_safe - 2:k_safe + 3]}; budget {budget}")
    assert all(x.exact for x in r.replies)
    assert r.replies[-1].pil_overruns == 0
    assert max(ins) <= budget
