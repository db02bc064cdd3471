"""Fault management on the PIL images (QEMU Cortex-M4F float, Cortex-M7 double): its instruction cost per step
and its allowance in aocs/budget.h (AOCS_BUDGET_FDIR_INSTR_*; issue 26, docs/spec.md 5.15).

The image is configured frame by frame (quat_pd, the four-wheel pyramid) and fed the same STEP sequence
twice, with fdir.enabled 1 and 0: from step 10 on the tachometers of wheel 1 stop moving while the law
commands torque (a wheel that no longer answers), so the enabled run isolates it at step 10 + persist and
re-initialises the array on the target. The difference of the exact instruction counts, step by step up to
and including that step, is the stage's cost (printed: `pytest -s tests/e2e/test_pil_fdir.py`); every whole
step stays within the budget the image reports, and the stage's cost within its allowance."""
from __future__ import annotations

import math

import pytest

from aocs_core import registry
from aocs_pil import frame
from pil_support import TARGETS, configure, start

STEPS = 24
DEAD = 1
FAIL_STEP = 10
PERSIST = 5
JS = 0.08
U_MAX = 0.25
#: the allowance (firmware/pil/include/aocs/budget.h AOCS_BUDGET_FDIR_INSTR_M4F / _M7), by hand on purpose
ALLOWANCE = {"pil-m4f": 8500, "pil-m7": 12100}


def _pyramid():
    beta = math.acos(1.0 / math.sqrt(3.0))
    return [[math.cos(beta), math.sin(beta) * math.cos(a), math.sin(beta) * math.sin(a)]
            for a in (0.0, 0.5 * math.pi, math.pi, 1.5 * math.pi)]


def _config(q, enabled: int):
    reg = registry.load()
    fields = dict(law=reg.law_ids()["quat_pd"], period_s=0.1, target_q=[0.0, 0.0, 0.0, 1.0], quat_pd_kp=40.0,
                  quat_pd_kd=80.0, u_max_norm=1.0, k_safe=2.0, wheels_count=4,
                  inertia=[2059.5, 0, 0, 0, 5954.2, 0, 0, 0, 5974.3], fdir_enabled=enabled)
    for i, g in enumerate(_pyramid()):
        fields.update({f"wheel{i}_axis": g, f"wheel{i}_js": JS, f"wheel{i}_u_max": U_MAX,
                       f"wheel{i}_omega_max": 600.0})
    return configure(q, **fields)


def _fly(target, enabled):
    q = start(target)
    try:
        ack = _config(q, enabled)
        assert (ack.pil_err, ack.status) == (0, 0), ack
        replies = []
        speeds = [50.0, -20.0, 10.0, 30.0]
        quat = [0.02, -0.01, 0.015, math.sqrt(1.0 - 0.02 ** 2 - 0.01 ** 2 - 0.015 ** 2)]
        for k in range(STEPS):
            p = frame.encode_step(k, (k + 1) * 100_000_000, 1 | 2, quat, [0.0, 0.0, 0.0], (0, 0, 0), (0, 0, 0),
                                  speeds + [0.0, 0.0])
            _, raw = q.request(frame.T_STEP, p, frame.T_STEP_REPLY)
            r = frame.StepReply.decode(raw)
            replies.append(r)
            # the wheels the test integrates: each takes its command, wheel DEAD none from FAIL_STEP on
            for i in range(4):
                if not (i == DEAD and k >= FAIL_STEP):
                    speeds[i] += 0.1 * r.u_wheels[i] / JS
        q.stop()
        return ack, replies
    finally:
        q.kill()


@pytest.mark.parametrize("target", TARGETS)
def test_fdir_within_its_instruction_allowance(target):
    ack_off, off = _fly(target, 0)
    ack_on, on = _fly(target, 1)
    assert all(r.exact == 1 for r in on + off)
    iso = FAIL_STEP + PERSIST           # the sample of step FAIL_STEP + 1 is the first to show it
    # the enabled run stops commanding the dead wheel after the isolation step; the disabled one never does
    assert all(abs(r.u_wheels[DEAD]) > 0.0 for r in on[:iso + 1])
    assert all(r.u_wheels[DEAD] == 0.0 for r in on[iso + 1:])
    assert all(abs(r.u_wheels[DEAD]) > 0.0 for r in off)
    cost = [a.instructions - b.instructions for a, b in zip(on[:iso + 1], off[:iso + 1])]
    print(f"\nfdir on {target}: cost per step min {min(cost)} max {max(cost)} (isolation step {cost[iso]}); "
          f"whole step max {max(r.instructions for r in on)}; budget {ack_on.budget} = off's {ack_off.budget} "
          f"+ {ALLOWANCE[target]}")
    assert ack_on.budget == ack_off.budget + ALLOWANCE[target]
    assert max(cost) <= ALLOWANCE[target]
    assert all(r.instructions <= r.budget and r.overrun == 0 for r in on)
