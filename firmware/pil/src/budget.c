/*
 * Per-law instruction budgets (aocs/budget.h): the INSTR_M4F / INSTR_M7
 * columns of aocs/laws.def, set from the PIL runs of docs/pil.md
 * ("Instruction budgets"): budget = 1.4 x (worst whole-step count measured
 * over the full reference scenarios of the law + 80 for a SAFE-mode step,
 * which also runs the law in the shadow), rounded up to 100.
 */
#include "aocs/budget.h"

#define BUDGET_ROW(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, VARIANT, VMEMBER, VVALUE, \
                   BUDGET_NS, INSTR_M4F, INSTR_M7, ...)                                                          \
    {(INSTR_M4F), (INSTR_M7)},

uint32_t aocs_budget_instructions(aocs_law_id_t law, aocs_budget_target_t target)
{
    /* [law][target]: cortex-m4f (float), cortex-m7 (double) */
    static const uint32_t budget_table[AOCS_LAW_COUNT][AOCS_BUDGET_TARGET_COUNT] = {
        {AOCS_BUDGET_STANDBY_INSTR_M4F, AOCS_BUDGET_STANDBY_INSTR_M7}, /* none (STANDBY) */
        AOCS_LAW_ROWS(BUDGET_ROW)
    };
    uint32_t budget = 0U;
    if (((int32_t)law >= 0) && (law < AOCS_LAW_COUNT) && ((int32_t)target >= 0) &&
        (target < AOCS_BUDGET_TARGET_COUNT)) {
        budget = budget_table[law][target];
    }
    return budget;
}

/* An allowance given per target (the slew planning, the wheel array): its M4F or M7 figure, 0 for another. */
static uint32_t budget_per_target(aocs_budget_target_t target, uint32_t m4f, uint32_t m7)
{
    uint32_t budget = 0U;
    if (target == AOCS_BUDGET_TARGET_CORTEX_M4F) {
        budget = m4f;
    } else if (target == AOCS_BUDGET_TARGET_CORTEX_M7) {
        budget = m7;
    } else {
        budget = 0U;
    }
    return budget;
}

uint32_t aocs_budget_slew_instructions(aocs_budget_target_t target)
{
    return aocs_budget_guidance_instructions(AOCS_GUIDANCE_SLEW, target);
}

#define GUIDANCE_BUDGET_ROW(ID, NAME, CHECK, STEP, OWN_RATES, PLANNED, FEEDFORWARD, BUDGET_NS, INSTR_M4F, INSTR_M7) \
    {(INSTR_M4F), (INSTR_M7)},

uint32_t aocs_budget_guidance_instructions(aocs_guidance_id_t mode, aocs_budget_target_t target)
{
    static const uint32_t guidance_budget[AOCS_GUIDANCE_COUNT][AOCS_BUDGET_TARGET_COUNT] = {
        AOCS_GUIDANCE_ROWS(GUIDANCE_BUDGET_ROW)};
    uint32_t budget = 0U;
    if (((int32_t)mode >= 0) && (mode < AOCS_GUIDANCE_COUNT)) {
        budget = budget_per_target(target, guidance_budget[mode][AOCS_BUDGET_TARGET_CORTEX_M4F],
                                   guidance_budget[mode][AOCS_BUDGET_TARGET_CORTEX_M7]);
    }
    return budget;
}

#define ESTIMATOR_BUDGET_ROW(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, INSTR_M4F, \
                             INSTR_M7, ...)                                                                    \
    {(INSTR_M4F), (INSTR_M7)},

uint32_t aocs_budget_estimator_instructions(aocs_det_id_t estimator, aocs_budget_target_t target)
{
    static const uint32_t estimator_budget[AOCS_DET_COUNT][AOCS_BUDGET_TARGET_COUNT] = {
        AOCS_DETERMINATION_ROWS(ESTIMATOR_BUDGET_ROW)};
    uint32_t budget = 0U;
    if (((int32_t)estimator >= 0) && (estimator < AOCS_DET_COUNT)) {
        budget = budget_per_target(target, estimator_budget[estimator][AOCS_BUDGET_TARGET_CORTEX_M4F],
                                   estimator_budget[estimator][AOCS_BUDGET_TARGET_CORTEX_M7]);
    }
    return budget;
}

#define MOMENTUM_BUDGET_ROW(ID, NAME, INIT, STEP, BUDGET_NS, INSTR_M4F, INSTR_M7) {(INSTR_M4F), (INSTR_M7)},

uint32_t aocs_budget_momentum_instructions(aocs_mom_id_t policy, aocs_budget_target_t target)
{
    static const uint32_t momentum_budget[AOCS_MOM_COUNT][AOCS_BUDGET_TARGET_COUNT] = {
        AOCS_MOMENTUM_ROWS(MOMENTUM_BUDGET_ROW)};
    uint32_t budget = 0U;
    if (((int32_t)policy >= 0) && (policy < AOCS_MOM_COUNT)) {
        budget = budget_per_target(target, momentum_budget[policy][AOCS_BUDGET_TARGET_CORTEX_M4F],
                                   momentum_budget[policy][AOCS_BUDGET_TARGET_CORTEX_M7]);
    }
    return budget;
}

uint32_t aocs_budget_wheels_instructions(aocs_budget_target_t target)
{
    return budget_per_target(target, AOCS_BUDGET_WHEELS_INSTR_M4F, AOCS_BUDGET_WHEELS_INSTR_M7);
}

uint32_t aocs_budget_fdir_instructions(aocs_budget_target_t target)
{
    return budget_per_target(target, AOCS_BUDGET_FDIR_INSTR_M4F, AOCS_BUDGET_FDIR_INSTR_M7);
}
