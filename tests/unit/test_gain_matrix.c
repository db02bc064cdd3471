/*
 * gain_matrix (the 3x6 gain tables of lqr_quat, hinf and orbit_lqr):
 * Proves: a NaN / +Inf / -Inf entry anywhere gives AOCS_ERR_PARAM_NOT_FINITE
 * under every rule, also when the rule would fail too (finiteness first);
 * ANY_NONZERO rejects only the all-zero table (one entry of either sign
 * passes); POS_DIAG needs k[i][i] > 0 on every row (0, -0 and negative
 * rejected, other entries of any sign allowed); POS_DIAGS needs that and
 * k[i][3+i] > 0; an unknown rule rejects even a good table; a malformed
 * shape (cols 0, 4, 5, 12 or a NULL row) is rejected under every rule; the product is
 * sign * K x with hand-computed values, sign -1 is the exact negation of
 * sign +1 bit for bit (a zero row gives -0.0, as -acc did in the laws).
 */
#include <string.h>

#include "test_support.h"
#include "aocs/control/gain_matrix.h"

static const aocs_gain_matrix_rule_t RULES[3] = {AOCS_GAIN_MATRIX_ANY_NONZERO, AOCS_GAIN_MATRIX_POS_DIAG,
                                                 AOCS_GAIN_MATRIX_POS_DIAGS};

/* a table every rule accepts: both block diagonals positive, couplings of both signs */
static void good_table(real_t k[3][6])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            k[i][j] = (real_t)(0.25 * (double)((i + j) % 3) - 0.25); /* -0.25, 0, 0.25 */
        }
        k[i][i] = (real_t)(10.0 + i);
        k[i][3 + i] = (real_t)(20.0 + i);
    }
}

static void test_good_table_passes_every_rule(void **state)
{
    (void)state;
    real_t k[3][6];
    good_table(k);
    for (int r = 0; r < 3; ++r) {
        assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, RULES[r]), AOCS_OK);
    }
}

static void test_non_finite_first(void **state)
{
    (void)state;
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            for (int b = 0; b < 3; ++b) {
                for (int r = 0; r < 3; ++r) {
                    real_t k[3][6];
                    good_table(k);
                    k[i][j] = (real_t)bad[b];
                    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, RULES[r]),
                                     AOCS_ERR_PARAM_NOT_FINITE);
                    /* also when the rest of the table breaks the rule */
                    memset(k, 0, sizeof k);
                    k[i][j] = (real_t)bad[b];
                    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, RULES[r]),
                                     AOCS_ERR_PARAM_NOT_FINITE);
                }
            }
        }
    }
}

static void test_any_nonzero(void **state)
{
    (void)state;
    real_t k[3][6];
    memset(k, 0, sizeof k);
    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_ANY_NONZERO),
                     AOCS_ERR_GAIN_TABLE_INVALID);
    k[1][1] = -AOCS_R(0.0); /* still all zero */
    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_ANY_NONZERO),
                     AOCS_ERR_GAIN_TABLE_INVALID);
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            for (int s = 0; s < 2; ++s) {
                memset(k, 0, sizeof k);
                k[i][j] = (s == 0) ? AOCS_R(1e-30) : AOCS_R(-3.0);
                assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_ANY_NONZERO),
                                 AOCS_OK);
            }
        }
    }
}

static void test_positive_diagonals(void **state)
{
    (void)state;
    const real_t not_positive[3] = {AOCS_R(0.0), -AOCS_R(0.0), AOCS_R(-1.0)};
    for (int i = 0; i < 3; ++i) {
        for (int b = 0; b < 3; ++b) {
            real_t k[3][6];
            /* first block: both rules that need it reject */
            good_table(k);
            k[i][i] = not_positive[b];
            assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_POS_DIAG),
                             AOCS_ERR_GAIN_TABLE_INVALID);
            assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_POS_DIAGS),
                             AOCS_ERR_GAIN_TABLE_INVALID);
            assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_ANY_NONZERO), AOCS_OK);
            /* second block: only POS_DIAGS looks at it */
            good_table(k);
            k[i][3 + i] = not_positive[b];
            assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_POS_DIAG), AOCS_OK);
            assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, AOCS_GAIN_MATRIX_POS_DIAGS),
                             AOCS_ERR_GAIN_TABLE_INVALID);
        }
    }
}

static void test_unknown_rule_rejects(void **state)
{
    (void)state;
    real_t k[3][6];
    good_table(k);
    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, (aocs_gain_matrix_rule_t)3),
                     AOCS_ERR_GAIN_TABLE_INVALID);
    assert_int_equal(aocs_gain_matrix_check((const real_t(*)[6])k, (aocs_gain_matrix_rule_t)-1),
                     AOCS_ERR_GAIN_TABLE_INVALID);
}

/* the shape (gain_matrix.h): 3 rows, none NULL, cols a multiple of 3 in [3, AOCS_GAIN_COLS_MAX]; any other is
   AOCS_ERR_GAIN_TABLE_INVALID under every rule, before its entries are read */
static void test_a_malformed_shape_rejects(void **state)
{
    (void)state;
    real_t k[3][6];
    good_table(k);
    const real_t big[3][12] = {{1.0}, {0.0, 1.0}, {0.0, 0.0, 1.0}};
    for (int r = 0; r < 3; ++r) {
        aocs_gain_rows_t g = {{k[0], k[1], k[2]}, 6U};
        assert_int_equal(aocs_gain_rows_check(g, RULES[r]), AOCS_OK);
        const uint32_t bad_cols[4] = {0U, 4U, 12U, 5U};
        for (int c = 0; c < 4; ++c) {
            g.cols = bad_cols[c];
            g.row[0] = (bad_cols[c] > 6U) ? big[0] : k[0];
            g.row[1] = (bad_cols[c] > 6U) ? big[1] : k[1];
            g.row[2] = (bad_cols[c] > 6U) ? big[2] : k[2];
            assert_int_equal(aocs_gain_rows_check(g, RULES[r]), AOCS_ERR_GAIN_TABLE_INVALID);
        }
        for (int missing = 0; missing < 3; ++missing) {
            aocs_gain_rows_t h = {{k[0], k[1], k[2]}, 6U};
            h.row[missing] = NULL;
            assert_int_equal(aocs_gain_rows_check(h, RULES[r]), AOCS_ERR_GAIN_TABLE_INVALID);
        }
    }
}

static void test_product(void **state)
{
    (void)state;
    /* rows [1 2 3 4 5 6], [-1 0 1 0 -1 0], 0; x = [1 -1 2 0.5 -2 4]:
       y1 = 1 - 2 + 6 + 2 - 10 + 24 = 21, y2 = -1 + 2 + 2 = 3, y3 = 0 (all exact in float) */
    const real_t k[3][6] = {{1, 2, 3, 4, 5, 6}, {-1, 0, 1, 0, -1, 0}, {0, 0, 0, 0, 0, 0}};
    const real_t x[6] = {AOCS_R(1.0), AOCS_R(-1.0), AOCS_R(2.0), AOCS_R(0.5), AOCS_R(-2.0), AOCS_R(4.0)};
    aocs_vec3_t yp = aocs_gain_matrix_mul(k, x, AOCS_R(1.0));
    aocs_vec3_t yn = aocs_gain_matrix_mul(k, x, AOCS_R(-1.0));
    assert_close(yp.v[0], 21.0, 0.0);
    assert_close(yp.v[1], 3.0, 0.0);
    assert_true(fabs((double)yp.v[2]) <= 0.0 && !signbit((double)yp.v[2]));
    for (int i = 0; i < 3; ++i) {
        real_t neg = -yp.v[i];
        assert_memory_equal(&neg, &yn.v[i], sizeof neg); /* bit for bit, -0.0 included */
    }
    assert_true(signbit((double)yn.v[2]));
    /* random tables: sign -1 is the exact negation of sign +1 */
    test_rng_t rng = {0xC0FFEEu};
    for (int n = 0; n < 1000; ++n) {
        real_t kr[3][6];
        real_t xr[6];
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 6; ++j) {
                kr[i][j] = (real_t)test_rng_uniform(&rng, -1e3, 1e3);
            }
        }
        for (int j = 0; j < 6; ++j) {
            xr[j] = (real_t)test_rng_uniform(&rng, -1.0, 1.0);
        }
        aocs_vec3_t a = aocs_gain_matrix_mul((const real_t(*)[6])kr, xr, AOCS_R(1.0));
        aocs_vec3_t b = aocs_gain_matrix_mul((const real_t(*)[6])kr, xr, AOCS_R(-1.0));
        for (int i = 0; i < 3; ++i) {
            real_t neg = -a.v[i];
            assert_memory_equal(&neg, &b.v[i], sizeof neg);
            double ref = 0.0;
            double scale = 0.0;
            for (int j = 0; j < 6; ++j) {
                ref += (double)kr[i][j] * (double)xr[j];
                scale += fabs((double)kr[i][j] * (double)xr[j]);
            }
            assert_true(fabs((double)a.v[i] - ref) <= TOL_TIGHT * scale);
        }
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_good_table_passes_every_rule),
        cmocka_unit_test(test_non_finite_first),
        cmocka_unit_test(test_any_nonzero),
        cmocka_unit_test(test_positive_diagonals),
        cmocka_unit_test(test_unknown_rule_rejects),
        cmocka_unit_test(test_a_malformed_shape_rejects),
        cmocka_unit_test(test_product),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
