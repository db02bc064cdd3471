/* gain_matrix: validation and product of the 3x6 and 3x9 gain tables, see gain_matrix.h. */
#include <stddef.h>

#include "aocs/control/gain_matrix.h"

static int gain_shape_ok(aocs_gain_rows_t k)
{
    return ((k.cols >= 3U) && (k.cols <= AOCS_GAIN_COLS_MAX) && ((k.cols % 3U) == 0U) && (k.row[0] != NULL) &&
            (k.row[1] != NULL) && (k.row[2] != NULL))
               ? 1
               : 0;
}

static int gain_all_finite(aocs_gain_rows_t k)
{
    int ok = 1;
    for (uint32_t i = 0U; i < 3U; ++i) {
        for (uint32_t j = 0U; j < k.cols; ++j) {
            if (!AOCS_IS_FINITE(k.row[i][j])) {
                ok = 0;
            }
        }
    }
    return ok;
}

static int gain_any_nonzero(aocs_gain_rows_t k)
{
    int found = 0;
    for (uint32_t i = 0U; i < 3U; ++i) {
        for (uint32_t j = 0U; j < k.cols; ++j) {
            if (AOCS_FABS(k.row[i][j]) > AOCS_R(0.0)) {
                found = 1;
            }
        }
    }
    return found;
}

/* 1 when k[i][col + i] > 0 for every row: the diagonal of the 3x3 block starting at column col */
static int gain_block_diag_positive(aocs_gain_rows_t k, uint32_t col)
{
    int ok = 1;
    for (uint32_t i = 0U; i < 3U; ++i) {
        if (!(k.row[i][col + i] > AOCS_R(0.0))) {
            ok = 0;
        }
    }
    return ok;
}

aocs_status_t aocs_gain_rows_check(aocs_gain_rows_t k, aocs_gain_matrix_rule_t rule)
{
    aocs_status_t st = AOCS_OK;
    if (gain_shape_ok(k) == 0) {
        st = AOCS_ERR_GAIN_TABLE_INVALID;
    } else if (gain_all_finite(k) == 0) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else if (rule == AOCS_GAIN_MATRIX_ANY_NONZERO) {
        if (gain_any_nonzero(k) == 0) {
            st = AOCS_ERR_GAIN_TABLE_INVALID;
        }
    } else if (rule == AOCS_GAIN_MATRIX_POS_DIAG) {
        if (gain_block_diag_positive(k, 0U) == 0) {
            st = AOCS_ERR_GAIN_TABLE_INVALID;
        }
    } else if (rule == AOCS_GAIN_MATRIX_POS_DIAGS) {
        for (uint32_t col = 0U; col < k.cols; col += 3U) {
            if (gain_block_diag_positive(k, col) == 0) {
                st = AOCS_ERR_GAIN_TABLE_INVALID;
            }
        }
    } else {
        st = AOCS_ERR_GAIN_TABLE_INVALID; /* unknown rule: reject rather than accept unchecked */
    }
    return st;
}

aocs_vec3_t aocs_gain_rows_mul(aocs_gain_rows_t k, const real_t *x, real_t sign)
{
    real_t y[3] = {AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0)};
    if ((gain_shape_ok(k) != 0) && (x != NULL)) {
        for (uint32_t i = 0U; i < 3U; ++i) {
            real_t acc = AOCS_R(0.0);
            for (uint32_t j = 0U; j < k.cols; ++j) {
                acc += k.row[i][j] * x[j];
            }
            y[i] = sign * acc;
        }
    }
    return aocs_vec3_make(y[0], y[1], y[2]);
}

static aocs_gain_rows_t rows6(const real_t k[3][6])
{
    aocs_gain_rows_t r = {{k[0], k[1], k[2]}, 6U};
    return r;
}

static aocs_gain_rows_t rows9(const real_t k[3][9])
{
    aocs_gain_rows_t r = {{k[0], k[1], k[2]}, 9U};
    return r;
}

aocs_status_t aocs_gain_matrix_check(const real_t k[3][6], aocs_gain_matrix_rule_t rule)
{
    return aocs_gain_rows_check(rows6(k), rule);
}

aocs_status_t aocs_gain_matrix9_check(const real_t k[3][9], aocs_gain_matrix_rule_t rule)
{
    return aocs_gain_rows_check(rows9(k), rule);
}

aocs_vec3_t aocs_gain_matrix_mul(const real_t k[3][6], const real_t x[6], real_t sign)
{
    return aocs_gain_rows_mul(rows6(k), x, sign);
}

aocs_vec3_t aocs_gain_matrix9_mul(const real_t k[3][9], const real_t x[9], real_t sign)
{
    return aocs_gain_rows_mul(rows9(k), x, sign);
}
