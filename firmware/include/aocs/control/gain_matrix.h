/*
 * 3x6 state-feedback gain matrices of the table-driven laws: lqr_quat
 * (SPEC 2.5, u = -K x), hinf (SPEC 2.6, u = +K x) and orbit_lqr (SPEC 2.8,
 * F = -K x). The tables come from gains/aocs_gains.h; this module holds the
 * validation each law applies to its K at init and the product K x of its
 * step, so the three laws share one implementation of both.
 */
#ifndef AOCS_CONTROL_GAIN_MATRIX_H
#define AOCS_CONTROL_GAIN_MATRIX_H

#include "aocs/math3.h"

/* What a law requires of its K besides every entry being finite. */
typedef enum {
    AOCS_GAIN_MATRIX_ANY_NONZERO = 0, /* at least one nonzero entry, any signs (hinf) */
    AOCS_GAIN_MATRIX_POS_DIAG = 1,    /* k[i][i] > 0: the diagonal of the first 3x3 block (orbit_lqr) */
    AOCS_GAIN_MATRIX_POS_DIAGS = 2    /* k[i][i] > 0 and k[i][3+i] > 0: both block diagonals (lqr_quat) */
} aocs_gain_matrix_rule_t;

/*
 * Validation of a gain table, first failure wins:
 *   any entry NaN/Inf (all 18 checked)            AOCS_ERR_PARAM_NOT_FINITE
 *   rule not met, or rule unknown                 AOCS_ERR_GAIN_TABLE_INVALID
 * else AOCS_OK.
 */
aocs_status_t aocs_gain_matrix_check(const real_t k[3][6], aocs_gain_matrix_rule_t rule);

/*
 * y = sign K x, y_i = sign * (sum_j k[i][j] x[j]) with the sum accumulated in
 * the order j = 0..5; sign = -1 for u = -K x (lqr_quat, orbit_lqr), +1 for
 * u = +K x (hinf); a product by +-1 is exact. Not checked: the law passes
 * the result to aocs_law_set_output, which rejects a non-finite one.
 */
aocs_vec3_t aocs_gain_matrix_mul(const real_t k[3][6], const real_t x[6], real_t sign);

#endif /* AOCS_CONTROL_GAIN_MATRIX_H */
