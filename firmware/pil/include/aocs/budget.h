/*
 * Instruction budgets of one executive step per law and target core: the
 * timing budget of the flight code in the unit that is measured exactly in
 * the processor-in-the-loop image (QEMU -icount, docs/pil.md), independent
 * of the machine that runs the emulator.
 *
 * A budget covers one whole aocs_exec_step call with that law selected (input
 * checks, guidance, law, saturation, counters; in SAFE mode the law still
 * runs in the shadow, so the same budget applies). Each value is 1.4 times
 * the worst count measured over the reference scenarios of docs/pil.md
 * (plus a SAFE-mode step's extra), rounded up to 100; the PIL image flags a
 * step above it (reply `overrun`, counted in the bridge's n_overrun) and the
 * PIL tests fail on any.
 *
 * Microseconds on silicon are at least instructions / f_clk (one
 * instruction per cycle at best): divide by 168 (M4F at 168 MHz) or 216 (M7
 * at 216 MHz). Flash wait states, cache misses and the FPU's multi-cycle
 * operations (division, square root) only add to that.
 */
#ifndef AOCS_BUDGET_H
#define AOCS_BUDGET_H

#include <stdint.h>

#include "aocs/executive.h"

typedef enum {
    AOCS_BUDGET_TARGET_CORTEX_M4F = 0, /* float build, fpv4-sp-d16 */
    AOCS_BUDGET_TARGET_CORTEX_M7,      /* double build, fpv5-d16 */
    AOCS_BUDGET_TARGET_COUNT
} aocs_budget_target_t;

/* Nominal core clocks the microsecond figures of docs/pil.md use, Hz. */
#define AOCS_BUDGET_CLOCK_CORTEX_M4F_HZ 168000000UL
#define AOCS_BUDGET_CLOCK_CORTEX_M7_HZ 216000000UL

/*
 * STANDBY steps (AOCS_LAW_NONE, no law runs); the laws' budgets are the
 * INSTR_M4F / INSTR_M7 columns of their rows in aocs/laws.def.
 */
#define AOCS_BUDGET_STANDBY_INSTR_M4F 1600u /* measured worst 1102 */
#define AOCS_BUDGET_STANDBY_INSTR_M7 1900u  /* measured worst 1330 */

/*
 * Added to an attitude law's budget in guidance mode SLEW (executive.h): the
 * slew reference (profile, qd(t), rates into B) and the feedforward, and
 * once per target the planning. Measured (irassi_large, quat_pd, 1 N m per
 * axis, 200 s, `aocs run ... --target pil-m4f / pil-m7`, with and without
 * --guidance slew): worst step 5440 against 1783 (M4F), 7322 against 2037
 * (M7), the worst being the planning step (the other steps add a median
 * 1768 / 2930). The allowance is 1.4 x the worst difference, rounded up to 100.
 */
#define AOCS_BUDGET_SLEW_INSTR_M4F 5200u /* 1.4 x 3657 */
#define AOCS_BUDGET_SLEW_INSTR_M7 7400u  /* 1.4 x 5285 */

/*
 * Added to any step's budget when the executive flies a reaction wheel array
 * (cfg.wheels.n != 0; executive.h "Reaction wheels"): the allocation -Gs^+ u_c,
 * the friction feedforward (one tanh per wheel), the scale, the null-space
 * management (P_N, N x N) and the momentum (docs/spec.md 5.3.1, 5.3.2).
 * Measured (every IRASSI law, guidance SLEW, full 1000 s, `run_direct` of
 * aocs_pil.harness): irassi_rw (4 wheels, friction feedforward, null-space
 * management) and irassi_rw_failed (3 healthy) against irassi_large at
 * 0.5 N m per axis (no wheels). Worst step 8297 against 6149 (M4F), 10602
 * against 8356 (M7), both quat_pid on irassi_rw and both the planning step
 * (the wheel envelope of the guidance); the median step adds 1906 / 2021.
 * The largest array the flight software holds, six wheels (the same pyramid
 * with count 6, 300 s): worst 9083 (M4F) / 11392 (M7), quat_pid, i.e. 2934 /
 * 3036 more than without wheels. The allowance is 1.4 x that worst
 * difference, rounded up to 100. (Measured on 688f188; since the allocation
 * reports the delivered torque as s u_c, a wheel step is about 130
 * instructions shorter: irassi_rw quat_pd worst 7633 / 9674 on 1763ef3.)
 */
#define AOCS_BUDGET_WHEELS_INSTR_M4F 4200u /* 1.4 x 2934 */
#define AOCS_BUDGET_WHEELS_INSTR_M7 4300u  /* 1.4 x 3036 */

/*
 * Fault management (aocs/fdir/fdir.h, docs/spec.md 5.15), enabled (fdir.enabled, the default): the
 * instructions it adds to every step, its worst step included (the one that isolates a wheel re-initialises
 * the array: a pseudo-inverse and the null-space projector). Measured by tests/e2e/test_pil_fdir.py
 * (`pytest -s`): the same STEP sequence with fdir.enabled 1 and 0, four wheels, a wheel that stops answering
 * at step 10 (isolated at step 15); 1.4 x the worst difference, rounded up to 100. Measured: M4F 544 to
 * 6007 (the isolation step), M7 578 to 8601.
 */
#define AOCS_BUDGET_FDIR_INSTR_M4F 8500u  /* 1.4 x 6007 */
#define AOCS_BUDGET_FDIR_INSTR_M7 12100u  /* 1.4 x 8601 */

/* The fault-management allowance of `target` (above); 0 for an out-of-range target. Total. */
uint32_t aocs_budget_fdir_instructions(aocs_budget_target_t target);

/* The wheel array allowance of `target` (above); 0 for an out-of-range target. Total. */
uint32_t aocs_budget_wheels_instructions(aocs_budget_target_t target);

/* The SLEW allowance of `target` (above); 0 for an out-of-range target. Total. */
uint32_t aocs_budget_slew_instructions(aocs_budget_target_t target);

/*
 * The instructions a guidance mode adds to an attitude law's step (the
 * INSTR_M4F / INSTR_M7 columns of aocs/guidance/guidance_modes.def: SLEW =
 * aocs_budget_slew_instructions); 0 out of range. Total.
 */
uint32_t aocs_budget_guidance_instructions(aocs_guidance_id_t mode, aocs_budget_target_t target);

/* The instructions an estimator adds to every step (INSTR_M4F / INSTR_M7 of
 * aocs/estimation/determination.def); 0 out of range. Total. */
uint32_t aocs_budget_estimator_instructions(aocs_det_id_t estimator, aocs_budget_target_t target);

/* The instructions a momentum-management policy adds to every step (INSTR_M4F / INSTR_M7 of
 * aocs/momentum/momentum.def); 0 out of range. Total. */
uint32_t aocs_budget_momentum_instructions(aocs_mom_id_t policy, aocs_budget_target_t target);

/*
 * Instructions of one aocs_exec_step with `law` selected on `target`
 * (AOCS_LAW_NONE: a STANDBY step). 0 for an out-of-range law or target
 * (no budget known: every step would count as an overrun). Total.
 */
uint32_t aocs_budget_instructions(aocs_law_id_t law, aocs_budget_target_t target);

#endif /* AOCS_BUDGET_H */
