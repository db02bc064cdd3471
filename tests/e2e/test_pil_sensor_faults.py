"""Sensor faults handled on the PIL images (QEMU Cortex-M4F float, Cortex-M7 double).

The MEKF without its gyro (docs/spec.md 5.6.12):
irassi_rw_mekf's slew flown on the image in the closed loop of the in-process plant (aocs_pil.harness
.run_direct), the gyro's x axis stuck from 60 s. On the target the fault management names it within a
second, the filter goes on without it on the rigid-body dynamics, the executive passes through SAFE while the
rate converges and flies NOMINAL again: the image ends in NOMINAL. Every step's instruction count is exact and
within the budget the image reports (the gyroless propagation and update included); the counts before and
after the switch are printed (`pytest -s tests/e2e/test_pil_sensor_faults.py`).

The star tracker's noise adaptation (5.15.3): the same slew with the tracker 10 times noisier from 60 s. On
the target the tracker is excluded by its innovations, then re-admitted with its noise model scaled (the
filter uses its samples again: the estimate's st_status back to used), with no SAFE; every step within the
budget."""
from __future__ import annotations

import statistics

import pytest

from aocs_core.modes import mode_value
from aocs_core.registry import status_code
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


@pytest.mark.parametrize("target", TARGETS)
def test_the_image_readmits_a_noisier_tracker_within_its_budget(target):
    r = harness.run_direct("irassi_rw_mekf", "quat_pd", target, duration_s=DURATION_S,
                           overrides={"faults": [{"kind": "st_noise_increase", "factor": 10.0,
                                                  "start_s": FAULT_S}]})
    k_fault = int(round(FAULT_S / PERIOD_S))
    st = [e.st_status for e in r.estimates]
    # refused from the first noisy sample (the MEKF's gate, then the exclusion: gated before tested-excluded)
    refused = {status_code("AOCS_ERR_MEKF_GATED"), status_code("AOCS_ERR_MEKF_ST_EXCLUDED")}
    first = next(k for k in range(k_fault, len(st)) if st[k] != 0)
    assert first <= k_fault + 2 and st[first] in refused
    used_again = next(k for k in range(first, len(st)) if st[k] == 0)
    assert first + 20 <= used_again <= first + 30         # the 5 of the exclusion and a window of 20 samples
    assert st[used_again:].count(0) >= 0.95 * len(st[used_again:])   # used from then on
    assert mode_value("safe") not in [x.mode for x in r.replies]
    ins = r.instructions
    print(f"\n{target}: excluded at step {first}, used again at {used_again}; step median "
          f"{statistics.median(ins[k_fault:]):.0f} max {max(ins[k_fault:])}; budget {r.replies[-1].budget}")
    assert all(x.exact for x in r.replies)
    assert r.replies[-1].pil_overruns == 0
    assert max(ins) <= r.replies[-1].budget
