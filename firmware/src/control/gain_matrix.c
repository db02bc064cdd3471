/* gain_matrix: validation and product of the 3x6 gain tables, see gain_matrix.h. */
#include "aocs/control/gain_matrix.h"

static int gain_matrix_all_finite(const real_t k[3][6])
{
    int ok = 1;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            if (!AOCS_IS_FINITE(k[i][j])) {
                ok = 0;
            }
        }
    }
    return ok;
}

static int gain_matrix_any_nonzero(const real_t k[3][6])
{
    int found = 0;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            if (AOCS_FABS(k[i][j]) > AOCS_R(0.0)) {
                found = 1;
            }
        }
    }
    return found;
}

/* 1 when k[i][col + i] > 0 for every row: the diagonal of the 3x3 block starting at column col */
static int gain_matrix_block_diag_positive(const real_t k[3][6], int col)
{
    int ok = 1;
    for (int i = 0; i < 3; ++i) {
        if (!(k[i][col + i] > AOCS_R(0.0))) {
            ok = 0;
        }
    }
    return ok;
}

aocs_status_t aocs_gain_matrix_check(const real_t k[3][6], aocs_gain_matrix_rule_t rule)
{
    aocs_status_t st = AOCS_OK;
    if (gain_matrix_all_finite(k) == 0) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (rule == AOCS_GAIN_MATRIX_ANY_NONZERO) {
        if (gain_matrix_any_nonzero(k) == 0) {
            st = AOCS_ERR_GAIN_TABLE_INVALID;
        }
    } else if (rule == AOCS_GAIN_MATRIX_POS_DIAG) {
        if (gain_matrix_block_diag_positive(k, 0) == 0) {
            st = AOCS_ERR_GAIN_TABLE_INVALID;
        }
    } else if (rule == AOCS_GAIN_MATRIX_POS_DIAGS) {
        if ((gain_matrix_block_diag_positive(k, 0) == 0) || (gain_matrix_block_diag_positive(k, 3) == 0)) {
            st = AOCS_ERR_GAIN_TABLE_INVALID;
        }
    } else {
        st = AOCS_ERR_GAIN_TABLE_INVALID; /* unknown rule: reject rather than accept unchecked */
    }
    return st;
}

aocs_vec3_t aocs_gain_matrix_mul(const real_t k[3][6], const real_t x[6], real_t sign)
{
    real_t y[3];
    for (int i = 0; i < 3; ++i) {
        real_t acc = AOCS_R(0.0);
        for (int j = 0; j < 6; ++j) {
            acc += k[i][j] * x[j];
        }
        y[i] = sign * acc;
    }
    return aocs_vec3_make(y[0], y[1], y[2]);
}
