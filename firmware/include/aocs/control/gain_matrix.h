/*
 * State-feedback gain matrices of the table-driven laws: 3x6 for lqr_quat
 * (SPEC 2.5, u = -K x), hinf (SPEC 2.6, u = +K x) and orbit_lqr (SPEC 2.8,
 * F = -K x), 3x9 for lqr_quat_i (SPEC 5.2, u = -K [z; qe_vec; we]). The
 * tables come from gains/aocs_gains.h; this module holds the validation each
 * law applies to its K at init and the product K x of its step. Both shapes
 * go through one implementation on the rows of K (aocs_gain_rows_t); the
 * 3x6 and 3x9 functions only say which shape.
 */
#ifndef AOCS_CONTROL_GAIN_MATRIX_H
#define AOCS_CONTROL_GAIN_MATRIX_H

#include "aocs/math3.h"

/* Widest gain (columns) of a table-driven law: the state of lqr_quat_i */
#define AOCS_GAIN_COLS_MAX 9U

/* What a law requires of its K besides every entry being finite. */
typedef enum {
    AOCS_GAIN_MATRIX_ANY_NONZERO = 0, /* at least one nonzero entry, any signs (hinf) */
    AOCS_GAIN_MATRIX_POS_DIAG = 1,    /* k[i][i] > 0: the diagonal of the first 3x3 block (orbit_lqr) */
    AOCS_GAIN_MATRIX_POS_DIAGS = 2    /* k[i][3b+i] > 0 for every 3x3 block b: every block diagonal
                                         (lqr_quat: 2 blocks, lqr_quat_i: 3) */
} aocs_gain_matrix_rule_t;

/* A 3 x cols gain by its rows (cols a multiple of 3, <= AOCS_GAIN_COLS_MAX). */
typedef struct {
    const real_t *row[3];
    uint32_t cols;
} aocs_gain_rows_t;

/*
 * Validation of a gain table, first failure wins:
 *   any entry NaN/Inf (all checked)               AOCS_ERR_PARAM_NOT_FINITE
 *   rule not met, or rule unknown, or a shape
 *   that is not 3 x 3n (n >= 1, <= the max)        AOCS_ERR_GAIN_TABLE_INVALID
 * else AOCS_OK.
 */
aocs_status_t aocs_gain_rows_check(aocs_gain_rows_t k, aocs_gain_matrix_rule_t rule);
aocs_status_t aocs_gain_matrix_check(const real_t k[3][6], aocs_gain_matrix_rule_t rule);
aocs_status_t aocs_gain_matrix9_check(const real_t k[3][9], aocs_gain_matrix_rule_t rule);

/*
 * y = sign K x, y_i = sign * (sum_j k[i][j] x[j]) with the sum accumulated in
 * the order j = 0..cols-1; sign = -1 for u = -K x (lqr_quat, orbit_lqr,
 * lqr_quat_i), +1 for u = +K x (hinf); a product by +-1 is exact. x has
 * cols entries. Not checked: the law passes the result to
 * aocs_law_set_output, which rejects a non-finite one.
 */
aocs_vec3_t aocs_gain_rows_mul(aocs_gain_rows_t k, const real_t *x, real_t sign);
aocs_vec3_t aocs_gain_matrix_mul(const real_t k[3][6], const real_t x[6], real_t sign);
aocs_vec3_t aocs_gain_matrix9_mul(const real_t k[3][9], const real_t x[9], real_t sign);

#endif /* AOCS_CONTROL_GAIN_MATRIX_H */
