"""The momentum-management stage on the PIL images (QEMU Cortex-M4F float, Cortex-M7 double): its instruction
cost per step and the budget of momentum.def (issue 21).

The image is configured frame by frame (quat_pd, three wheels, a momentum policy) and fed the same STEP
sequence twice, with the policy and with policy none: the wheels hold momentum above the start threshold,
so every step of the first run unloads. The difference of the exact instruction counts, step by step, is the
stage's cost (printed: `pytest -s tests/e2e/test_pil_momentum.py`); every whole step stays within the budget
the image reports (the law's + the wheels' + the policy's), and the policy's cost within its momentum.def
column. The commands themselves are checked against the host build's unit tests (tests/unit/test_momentum.c);
here: the on-times are within the period and the dipole is perpendicular to the field."""
from __future__ import annotations

import math
import random

import pytest

from aocs_core import registry
from aocs_pil import frame
from pil_support import TARGETS, configure, start
from thruster_layout import arms as thruster_arms
from thruster_layout import couples

QD = (0.0, 0.0, 0.0, 1.0)
STEPS = 40


def _config(q, policy: int):
    reg = registry.load()
    arms = thruster_arms(*couples(1.2, 0.3, 8.0))   # canted 8 deg, as tests/unit/test_momentum.c
    fields = dict(law=reg.law_ids()["quat_pd"], period_s=0.1, target_q=list(QD), quat_pd_kp=4.0, quat_pd_kd=8.0,
                  u_max_axis=[2.0, 2.0, 2.0], k_safe=2.0, wheels_count=3, inertia=[10.0, 0, 0, 0, 10.0, 0, 0, 0, 10.0],
                  # the tachometer speeds below are drawn at random, not integrated from the commands: fault
                  # management would rightly find every wheel's residual high (and, with three wheels, latch
                  # SAFE); its own cost is measured in test_pil_fdir.py
                  fdir_enabled=0)
    for i in range(3):
        fields.update({f"wheel{i}_axis": [1.0 if c == i else 0.0 for c in range(3)], f"wheel{i}_js": 0.1,
                       f"wheel{i}_u_max": 2.0, f"wheel{i}_omega_max": 600.0})
    fields.update(mom_policy=policy, mom_trigger=0, mom_h_start=5.0, mom_h_stop=1.0, mom_k_mtq=0.01,
                  mom_mtq_max_dipole=[50.0, 50.0, 50.0], mom_dump_torque=0.8, mom_thr_count=12, mom_thr_thrust=1.0,
                  mom_thr_min_on=0.01, mom_thr_quantum=0.001, mom_thr_arm_x=[a[0] for a in arms],
                  mom_thr_arm_y=[a[1] for a in arms], mom_thr_arm_z=[a[2] for a in arms])
    return configure(q, **fields)


def _inputs():
    rng = random.Random(21)
    out = []
    for k in range(STEPS):
        quat = [QD[i] + 0.01 * rng.uniform(-1, 1) for i in range(4)]
        n = math.sqrt(sum(x * x for x in quat))
        speeds = [100.0 + 10 * rng.uniform(-1, 1), -60.0 + 10 * rng.uniform(-1, 1), 40.0 + 10 * rng.uniform(-1, 1)]
        mag = [3e-5 * rng.uniform(-1, 1) for _ in range(3)]
        out.append(([x / n for x in quat], [1e-3 * rng.uniform(-1, 1) for _ in range(3)], speeds, mag))
    return out


def _fly(target, policy):
    q = start(target)
    try:
        ack = _config(q, policy)
        assert (ack.pil_err, ack.status) == (0, 0), ack
        replies = []
        for k, (quat, w, speeds, mag) in enumerate(_inputs()):
            p = frame.encode_step(k, (k + 1) * 100_000_000, 1 | 2 | 32, quat, w, (0, 0, 0), (0, 0, 0), speeds,
                                  mag_b_t=mag)
            _, raw = q.request(frame.T_STEP, p, frame.T_STEP_REPLY)
            replies.append(frame.StepReply.decode(raw))
        q.stop()
        return ack, replies
    finally:
        q.kill()


@pytest.mark.parametrize("target", TARGETS)
@pytest.mark.parametrize("policy", ["magnetorquers", "thrusters"])
def test_momentum_policy_within_its_instruction_budget(target, policy):
    reg = registry.load()
    pid = [n for n in reg.momentum_policies].index(policy)
    row = reg.momentum_policies[policy][1]["cortex-m4f" if target == "pil-m4f" else "cortex-m7"]
    _, base = _fly(target, 0)
    ack, rs = _fly(target, pid)
    assert all(r.exact == 1 and b.exact == 1 for r, b in zip(rs, base))
    assert all(r.mode == 1 and r.mom_policy == pid and r.unloading == 1 and r.mom_status == 0 for r in rs)
    cost = [r.instructions - b.instructions for r, b in zip(rs, base)]
    print(f"\n{policy} on {target}: stage cost per step min {min(cost)} max {max(cost)} instructions; whole step "
          f"max {max(r.instructions for r in rs)} (policy none: {max(b.instructions for b in base)}); budget "
          f"{rs[0].budget} = none's {base[0].budget} + momentum.def {row}")
    assert rs[0].budget == base[0].budget + row == ack.budget
    assert max(cost) <= row, f"{policy} on {target}: the stage costs {max(cost)} instructions > {row}"
    assert all(r.instructions <= r.budget and r.overrun == 0 for r in rs)
    if policy == "thrusters":
        assert all(0.0 <= t <= 0.1 for r in rs for t in r.thruster_on_s)
        assert any(t > 0.0 for r in rs for t in r.thruster_on_s)
    else:
        tol = 1e-5 if target == "pil-m4f" else 1e-12
        for r, (_, _, _, mag) in zip(rs, _inputs()):
            m = r.dipole_am2
            dot = sum(a * b for a, b in zip(m, mag))
            assert abs(dot) <= tol * math.sqrt(sum(a * a for a in m) * sum(b * b for b in mag))
