/*
 * vec3 / mat3: hand-computed values, the skew <-> cross identity, the
 * scale-aware inverse, and the inertia check's distinct rejection codes.
 */
#include "test_support.h"

#include <string.h>

static aocs_mat3_t mat_from(const double v[3][3])
{
    aocs_mat3_t a;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            a.m[i][j] = (real_t)v[i][j];
        }
    }
    return a;
}

static void assert_mat_close(aocs_mat3_t a, const double e[3][3], double tol)
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(a.m[i][j], e[i][j], tol);
        }
    }
}

/* SPEC 4, gao_mrp */
static const double J_GAO[3][3] = {{42.0, 1.8, -1.5}, {1.8, 25.0, -1.2}, {-1.5, -1.2, 61.8}};

static void test_vec3_basic_values(void **state)
{
    (void)state;
    aocs_vec3_t a = aocs_vec3_make(AOCS_R(1.0), AOCS_R(-2.0), AOCS_R(3.0));
    aocs_vec3_t b = aocs_vec3_make(AOCS_R(4.0), AOCS_R(5.0), AOCS_R(-6.0));
    assert_vec3_close(aocs_vec3_add(a, b), aocs_vec3_make(5, 3, -3), TOL_TIGHT);
    assert_vec3_close(aocs_vec3_sub(a, b), aocs_vec3_make(-3, -7, 9), TOL_TIGHT);
    assert_vec3_close(aocs_vec3_scale(a, AOCS_R(-0.5)), aocs_vec3_make(-0.5, 1.0, -1.5), TOL_TIGHT);
    assert_vec3_close(aocs_vec3_neg(a), aocs_vec3_make(-1, 2, -3), TOL_TIGHT);
    assert_vec3_close(aocs_vec3_hadamard(a, b), aocs_vec3_make(4, -10, -18), TOL_TIGHT);
    assert_close(aocs_vec3_dot(a, b), 1.0 * 4.0 - 2.0 * 5.0 - 3.0 * 6.0, TOL_TIGHT);
    /* (-2*-6 - 3*5, 3*4 - 1*-6, 1*5 - -2*4) */
    assert_vec3_close(aocs_vec3_cross(a, b), aocs_vec3_make(-3, 18, 13), TOL_TIGHT);
    assert_vec3_close(aocs_vec3_zero(), aocs_vec3_make(0, 0, 0), 0.0);
    assert_close(aocs_vec3_norm(aocs_vec3_make(3, 4, 12)), 13.0, TOL_TIGHT);
    assert_close(aocs_vec3_norm_sq(aocs_vec3_make(3, 4, 12)), 169.0, TOL_TIGHT);
    assert_close(aocs_vec3_norm_inf(aocs_vec3_make(2, -7, 3)), 7.0, 0.0);
    assert_close(aocs_vec3_norm_inf(aocs_vec3_make(2, 3, -7)), 7.0, 0.0);
}

static void test_vec3_cross_right_handed(void **state)
{
    (void)state;
    aocs_vec3_t ex = aocs_vec3_make(1, 0, 0);
    aocs_vec3_t ey = aocs_vec3_make(0, 1, 0);
    aocs_vec3_t ez = aocs_vec3_make(0, 0, 1);
    assert_vec3_close(aocs_vec3_cross(ex, ey), ez, 0.0);
    assert_vec3_close(aocs_vec3_cross(ey, ez), ex, 0.0);
    assert_vec3_close(aocs_vec3_cross(ez, ex), ey, 0.0);
}

static void test_vec3_non_finite(void **state)
{
    (void)state;
    real_t nan_v = (real_t)NAN;
    real_t inf_v = (real_t)INFINITY;
    assert_int_equal(aocs_vec3_is_finite(aocs_vec3_make(1, 2, 3)), 1);
    assert_int_equal(aocs_vec3_is_finite(aocs_vec3_make(1, nan_v, 3)), 0);
    assert_int_equal(aocs_vec3_is_finite(aocs_vec3_make(1, 2, -inf_v)), 0);
    /* a NaN anywhere must not hide behind a finite maximum */
    assert_true(isnan(aocs_vec3_norm_inf(aocs_vec3_make(nan_v, 5, 1))));
    assert_true(isnan(aocs_vec3_norm_inf(aocs_vec3_make(5, nan_v, 1))));
    assert_true(isnan(aocs_vec3_norm_inf(aocs_vec3_make(5, 1, nan_v))));
}

static void test_mat3_products_by_hand(void **state)
{
    (void)state;
    const double a_v[3][3] = {{1, 2, 3}, {4, 5, 6}, {7, 8, 10}};
    const double b_v[3][3] = {{2, 0, 1}, {-1, 3, 0}, {0, 1, -2}};
    /* a b, row by column, by hand */
    const double ab[3][3] = {{0, 9, -5}, {3, 21, -8}, {6, 34, -13}};
    const double at[3][3] = {{1, 4, 7}, {2, 5, 8}, {3, 6, 10}};
    aocs_mat3_t a = mat_from(a_v);
    aocs_mat3_t b = mat_from(b_v);
    aocs_vec3_t x = aocs_vec3_make(1, -1, 2);

    assert_mat_close(aocs_mat3_mul(a, b), ab, TOL_TIGHT);
    assert_mat_close(aocs_mat3_transpose(a), at, 0.0);
    assert_vec3_close(aocs_mat3_mul_vec(a, x), aocs_vec3_make(5, 11, 19), TOL_TIGHT);
    /* a^T x = (1-4+14, 2-5+16, 3-6+20) */
    assert_vec3_close(aocs_mat3_tmul_vec(a, x), aocs_vec3_make(11, 13, 17), TOL_TIGHT);
    /* det by the rule of Sarrus: 50+84+96-105-48-80 */
    assert_close(aocs_mat3_det(a), -3.0, TOL_TIGHT);
    assert_close(aocs_mat3_det(aocs_mat3_identity()), 1.0, 0.0);

    const double sum[3][3] = {{3, 2, 4}, {3, 8, 6}, {7, 9, 8}};
    assert_mat_close(aocs_mat3_add(a, b), sum, TOL_TIGHT);
    const double twice[3][3] = {{2, 4, 6}, {8, 10, 12}, {14, 16, 20}};
    assert_mat_close(aocs_mat3_scale(a, AOCS_R(2.0)), twice, TOL_TIGHT);
    const double dg[3][3] = {{1, 0, 0}, {0, -2, 0}, {0, 0, 3}};
    assert_mat_close(aocs_mat3_diag(aocs_vec3_make(1, -2, 3)), dg, 0.0);
    const double z[3][3] = {{0, 0, 0}, {0, 0, 0}, {0, 0, 0}};
    assert_mat_close(aocs_mat3_zero(), z, 0.0);
    const double outer[3][3] = {{1, -1, 2}, {2, -2, 4}, {3, -3, 6}};
    assert_mat_close(aocs_mat3_outer(aocs_vec3_make(1, 2, 3), x), outer, TOL_TIGHT);
}

static void test_mat3_skew_is_cross(void **state)
{
    (void)state;
    const double sk[3][3] = {{0, -3, 2}, {3, 0, -1}, {-2, 1, 0}}; /* SPEC 1 layout for a = (1,2,3) */
    assert_mat_close(aocs_mat3_skew(aocs_vec3_make(1, 2, 3)), sk, 0.0);
    test_rng_t rng = {0x1234567ULL};
    for (int k = 0; k < 200; ++k) {
        aocs_vec3_t a = test_random_vec3(&rng, 5.0);
        aocs_vec3_t b = test_random_vec3(&rng, 5.0);
        /* cross product written out independently in double */
        double e0 = (double)a.v[1] * (double)b.v[2] - (double)a.v[2] * (double)b.v[1];
        double e1 = (double)a.v[2] * (double)b.v[0] - (double)a.v[0] * (double)b.v[2];
        double e2 = (double)a.v[0] * (double)b.v[1] - (double)a.v[1] * (double)b.v[0];
        aocs_vec3_t s = aocs_mat3_mul_vec(aocs_mat3_skew(a), b);
        assert_close(s.v[0], e0, 25.0 * TOL_TIGHT);
        assert_close(s.v[1], e1, 25.0 * TOL_TIGHT);
        assert_close(s.v[2], e2, 25.0 * TOL_TIGHT);
    }
}

static void test_mat3_inverse_exact_integer(void **state)
{
    (void)state;
    /* det = 1, inverse known in closed form */
    const double a_v[3][3] = {{1, 2, 3}, {0, 1, 4}, {5, 6, 0}};
    const double inv_v[3][3] = {{-24, 18, 5}, {20, -15, -4}, {-5, 4, 1}};
    aocs_mat3_t inv;
    assert_int_equal(aocs_mat3_inverse(mat_from(a_v), &inv), AOCS_OK);
    assert_mat_close(inv, inv_v, 50.0 * TOL_TIGHT);
}

static void test_mat3_inverse_gao_inertia(void **state)
{
    (void)state;
    aocs_mat3_t j = mat_from(J_GAO);
    aocs_mat3_t inv;
    const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    assert_int_equal(aocs_mat3_inverse(j, &inv), AOCS_OK);
    assert_mat_close(aocs_mat3_mul(inv, j), id, 10.0 * TOL_TIGHT);
    assert_mat_close(aocs_mat3_mul(j, inv), id, 10.0 * TOL_TIGHT);
    /* the inverse of a symmetric matrix is symmetric */
    for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) {
            assert_close(inv.m[r][c], inv.m[c][r], TOL_TIGHT);
        }
    }
}

/* the singularity test is relative: scaling a matrix never changes the verdict */
static void test_mat3_inverse_scale_aware(void **state)
{
    (void)state;
    const double scales[4] = {1e-12, 1e-6, 1e6, 1e12};
    const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const double sing_v[3][3] = {{1, 2, 3}, {4, 5, 6}, {7, 8, 9}}; /* row3 = 2 row2 - row1 */
    for (int k = 0; k < 4; ++k) {
        aocs_mat3_t j = aocs_mat3_scale(mat_from(J_GAO), (real_t)scales[k]);
        aocs_mat3_t inv;
        assert_int_equal(aocs_mat3_inverse(j, &inv), AOCS_OK);
        assert_mat_close(aocs_mat3_mul(inv, j), id, 10.0 * TOL_TIGHT);

        aocs_mat3_t s = aocs_mat3_scale(mat_from(sing_v), (real_t)scales[k]);
        aocs_mat3_t sentinel = aocs_mat3_identity();
        assert_int_equal(aocs_mat3_inverse(s, &sentinel), AOCS_ERR_INERTIA_SINGULAR);
        assert_mat_close(sentinel, id, 0.0); /* untouched on error */
    }
    /* rows of very different magnitude, still well conditioned after row scaling */
    const double mixed[3][3] = {{1e-9, 0, 0}, {0, 1.0, 0.5}, {0, 0.5, 1e3}};
    aocs_mat3_t inv;
    assert_int_equal(aocs_mat3_inverse(mat_from(mixed), &inv), AOCS_OK);
    assert_mat_close(aocs_mat3_mul(inv, mat_from(mixed)), id, 10.0 * TOL_TIGHT);
}

/* The singularity bound |det(As)| <= 1e3 eps |r1| |r2| |r3| at both sides, with rows whose only or dominant
 * entry is in the middle column (each row norm takes all three columns): rows (0, 1, 0), (d, 1, 0),
 * (0, 0, 1) have det -d and row norms ~1; d = 500 eps is singular, d = 2000 eps is not. */
static void test_mat3_inverse_bound_uses_whole_rows(void **state)
{
    (void)state;
    const real_t d_in[2] = {AOCS_R(500.0) * AOCS_REAL_EPS, AOCS_R(2000.0) * AOCS_REAL_EPS};
    const aocs_status_t expect[2] = {AOCS_ERR_INERTIA_SINGULAR, AOCS_OK};
    for (int k = 0; k < 2; ++k) {
        aocs_mat3_t a = aocs_mat3_identity();
        aocs_mat3_t inv = aocs_mat3_identity();
        a.m[0][0] = AOCS_R(0.0);
        a.m[0][1] = AOCS_R(1.0);
        a.m[1][0] = d_in[k];
        a.m[1][1] = AOCS_R(1.0);
        assert_int_equal(aocs_mat3_inverse(a, &inv), expect[k]);
    }
}

static void test_mat3_inverse_errors(void **state)
{
    (void)state;
    const double id[3][3] = {{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
    const double zero_row[3][3] = {{1, 2, 3}, {0, 0, 0}, {5, 6, 0}};
    /* exactly dependent rows: row2 = 2 row1 */
    const double dep[3][3] = {{42, 1.8, -1.5}, {84, 3.6, -3.0}, {-1.5, -1.2, 61.8}};
    aocs_mat3_t out = aocs_mat3_identity();
    assert_int_equal(aocs_mat3_inverse(mat_from(zero_row), &out), AOCS_ERR_INERTIA_SINGULAR);
    assert_int_equal(aocs_mat3_inverse(mat_from(dep), &out), AOCS_ERR_INERTIA_SINGULAR);
    assert_int_equal(aocs_mat3_inverse(aocs_mat3_zero(), &out), AOCS_ERR_INERTIA_SINGULAR);
    aocs_mat3_t bad = mat_from(J_GAO);
    bad.m[2][1] = (real_t)NAN;
    assert_int_equal(aocs_mat3_inverse(bad, &out), AOCS_ERR_PARAM_NOT_FINITE);
    bad.m[2][1] = (real_t)INFINITY;
    assert_int_equal(aocs_mat3_inverse(bad, &out), AOCS_ERR_PARAM_NOT_FINITE);
    assert_mat_close(out, id, 0.0);
    assert_int_equal(aocs_mat3_inverse(mat_from(J_GAO), NULL), AOCS_ERR_NULL_ARG);
}

static void test_mat3_is_finite(void **state)
{
    (void)state;
    aocs_mat3_t a = aocs_mat3_identity();
    assert_int_equal(aocs_mat3_is_finite(a), 1);
    a.m[1][2] = (real_t)NAN;
    assert_int_equal(aocs_mat3_is_finite(a), 0);
    a.m[1][2] = AOCS_R(0.0);
    a.m[2][2] = (real_t)-INFINITY;
    assert_int_equal(aocs_mat3_is_finite(a), 0);
}

static void test_inertia_accepts_valid(void **state)
{
    (void)state;
    const double irassi[3][3] = {{2059.5, 0, 0}, {0, 5954.2, 0}, {0, 0, 5974.3}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(J_GAO)), AOCS_OK);
    assert_int_equal(aocs_mat3_check_inertia(aocs_mat3_identity()), AOCS_OK); /* rtc_*: J = I3 */
    assert_int_equal(aocs_mat3_check_inertia(mat_from(irassi)), AOCS_OK);
    /* units do not matter (g mm^2 vs kg m^2) */
    assert_int_equal(aocs_mat3_check_inertia(aocs_mat3_scale(mat_from(J_GAO), AOCS_R(1.0e9))), AOCS_OK);
    assert_int_equal(aocs_mat3_check_inertia(aocs_mat3_scale(mat_from(J_GAO), AOCS_R(1.0e-9))), AOCS_OK);
    /* an asymmetry of 1e-8 relative is rounding, tolerated (tolerance 1e-6) */
    aocs_mat3_t j = mat_from(J_GAO);
    j.m[0][1] = (real_t)(1.8 + 61.8 * 1e-8);
    assert_int_equal(aocs_mat3_check_inertia(j), AOCS_OK);
}

static void test_inertia_rejects_each_with_own_code(void **state)
{
    (void)state;
    aocs_mat3_t j = mat_from(J_GAO);
    j.m[1][0] = AOCS_R(1.9); /* J12 = 1.8, J21 = 1.9 */
    assert_int_equal(aocs_mat3_check_inertia(j), AOCS_ERR_INERTIA_NOT_SYMMETRIC);
    /* just outside the 1e-6 relative tolerance */
    j = mat_from(J_GAO);
    j.m[0][1] = (real_t)(1.8 + 61.8 * 1e-5);
    assert_int_equal(aocs_mat3_check_inertia(j), AOCS_ERR_INERTIA_NOT_SYMMETRIC);

    const double neg_diag[3][3] = {{1, 0, 0}, {0, -1, 0}, {0, 0, 1}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(neg_diag)), AOCS_ERR_INERTIA_NOT_POS_DEF);
    /* positive diagonal but eigenvalues 3, -1, 1 */
    const double indef2[3][3] = {{1, 2, 0}, {2, 1, 0}, {0, 0, 1}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(indef2)), AOCS_ERR_INERTIA_NOT_POS_DEF);
    /* leading 2x2 minor 0.75 > 0, determinant 0.19 - 0.655 - 1.215 = -1.68 < 0 */
    const double indef3[3][3] = {{1, 0.5, 0.9}, {0.5, 1, -0.9}, {0.9, -0.9, 1}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(indef3)), AOCS_ERR_INERTIA_NOT_POS_DEF);
    assert_int_equal(aocs_mat3_check_inertia(aocs_mat3_zero()), AOCS_ERR_INERTIA_NOT_POS_DEF);
    /* two negative eigenvalues: the determinant 1 + 9 - 4 - 2.25 - 2.25 = 1.5 > 0 passes, the leading 2x2
     * minor 1 - 4 = -3 (a negative J12) alone refuses it (Sylvester's criterion needs every leading minor) */
    const double indef2neg[3][3] = {{1, -2, 1.5}, {-2, 1, -1.5}, {1.5, -1.5, 1}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(indef2neg)), AOCS_ERR_INERTIA_NOT_POS_DEF);

    /* positive semidefinite, rank 2: eigenvalues 0, 2, 1 */
    const double sing[3][3] = {{1, 1, 0}, {1, 1, 0}, {0, 0, 1}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(sing)), AOCS_ERR_INERTIA_SINGULAR);
    /* rank 2 with a non-zero 2x2 minor: J = v1 v1^T + v2 v2^T, v1 = (1,0,1), v2 = (0,1,1) */
    const double sing3[3][3] = {{1, 0, 1}, {0, 1, 1}, {1, 1, 2}};
    assert_int_equal(aocs_mat3_check_inertia(mat_from(sing3)), AOCS_ERR_INERTIA_SINGULAR);

    j = mat_from(J_GAO);
    j.m[2][2] = (real_t)NAN;
    assert_int_equal(aocs_mat3_check_inertia(j), AOCS_ERR_PARAM_NOT_FINITE);
    j.m[2][2] = (real_t)INFINITY;
    assert_int_equal(aocs_mat3_check_inertia(j), AOCS_ERR_PARAM_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_vec3_basic_values),
        cmocka_unit_test(test_vec3_cross_right_handed),
        cmocka_unit_test(test_vec3_non_finite),
        cmocka_unit_test(test_mat3_products_by_hand),
        cmocka_unit_test(test_mat3_skew_is_cross),
        cmocka_unit_test(test_mat3_inverse_exact_integer),
        cmocka_unit_test(test_mat3_inverse_gao_inertia),
        cmocka_unit_test(test_mat3_inverse_scale_aware),
        cmocka_unit_test(test_mat3_inverse_bound_uses_whole_rows),
        cmocka_unit_test(test_mat3_inverse_errors),
        cmocka_unit_test(test_mat3_is_finite),
        cmocka_unit_test(test_inertia_accepts_valid),
        cmocka_unit_test(test_inertia_rejects_each_with_own_code),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
