/*
 * Per-law instruction budgets (aocs/budget.h). From the PIL runs of
 * docs/pil.md ("Instruction budgets"): budget = 1.4 x (worst whole-step count
 * measured over the full reference scenarios of the law + 80 for a SAFE-mode
 * step, which also runs the law in the shadow), rounded up to 100. The
 * comments give the measured worst NOMINAL counts (cortex-m4f, cortex-m7).
 */
#include "aocs/budget.h"

uint32_t aocs_budget_instructions(aocs_law_id_t law, aocs_budget_target_t target)
{
    /* [law][target]: cortex-m4f (float), cortex-m7 (double); comment: measured worst, same order */
    static const uint32_t budget_table[AOCS_LAW_COUNT][AOCS_BUDGET_TARGET_COUNT] = {
        {1600U, 1900U}, /* none (STANDBY): 1102, 1330 */
        {2700U, 3000U}, /* crp_linear: 1800, 2048 (rtc_ex1a/2a/3a) */
        {2500U, 2900U}, /* quat_pd: 1679, 1925 (irassi_small, irassi_large) */
        {2500U, 2900U}, /* quat_nlpd_neg: 1698, 1945 (irassi_small) */
        {2500U, 2900U}, /* quat_nlpd_pos: 1699, 1946 (irassi_small) */
        {3100U, 3400U}, /* smc: 2066, 2328 (irassi_small, irassi_large) */
        {2700U, 3100U}, /* lqr_quat: 1839, 2068 (irassi_small, irassi_large) */
        {5300U, 7000U}, /* hinf: 3636, 4895 (geo_hinf) */
        {4200U, 6000U}, /* mrp_sat: 2916, 4195 (gao_mrp) */
        {4500U, 6300U}, /* mrp_sat_tanh: 3095, 4392 (gao_mrp) */
        {2200U, 2500U}, /* orbit_lqr: 1421, 1656 (landsat8_q1, landsat8_debris) */
    };
    uint32_t budget = 0U;
    if (((int32_t)law >= 0) && (law < AOCS_LAW_COUNT) && ((int32_t)target >= 0) &&
        (target < AOCS_BUDGET_TARGET_COUNT)) {
        budget = budget_table[law][target];
    }
    return budget;
}
