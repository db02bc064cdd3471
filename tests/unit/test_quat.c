/*
 * Quaternion algebra (SPEC 1): Shuster product, passive A(q) N -> B,
 * normalisation errors, error quaternion, sign(q4), pointing angle, Xi(q).
 * Reference values are hand-derived or evaluated here in double from the
 * SPEC formulas, never taken from the implementation.
 */
#include "test_support.h"

#define D(x) ((double)(x))
#define ARCSEC_PER_RAD 206264.806
#define PI 3.14159265358979323846

/* ref_dcm, A(q) of SPEC 1 in double: test_support.h */

static void ref_matmul(double a[3][3], double b[3][3], double c[3][3])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            c[i][j] = a[i][0] * b[0][j] + a[i][1] * b[1][j] + a[i][2] * b[2][j];
        }
    }
}

static void assert_quat_close(aocs_quat_t a, const double e[4], double tol)
{
    for (int i = 0; i < 4; ++i) {
        assert_close(a.q[i], e[i], tol);
    }
}

static void test_passive_convention_90deg_about_z(void **state)
{
    (void)state;
    /*
     * B is N turned +90 deg about z. A(q) = (q4^2-|qv|^2) I + 2 qv qv^T - 2 q4 [qv x]
     * with qv = (0,0,s), q4 = c, s = c = 1/sqrt2: the first term vanishes,
     * 2 qv qv^T = diag(0,0,1), -2 q4 [qv x] = [[0,1,0],[-1,0,0],[0,0,0]].
     * So N's x axis has B components (0,-1,0) and N's y axis (1,0,0).
     */
    const double h = 0.70710678118654752;
    aocs_quat_t q = aocs_quat_make((real_t)0.0, (real_t)0.0, (real_t)h, (real_t)h);
    aocs_mat3_t a = aocs_quat_to_dcm(q);
    const double e[3][3] = {{0, 1, 0}, {-1, 0, 0}, {0, 0, 1}};
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) {
            assert_close(a.m[i][j], e[i][j], TOL_TIGHT);
        }
    }
    assert_vec3_close(aocs_mat3_mul_vec(a, aocs_vec3_make(1, 0, 0)), aocs_vec3_make(0, -1, 0), TOL_TIGHT);
    assert_vec3_close(aocs_mat3_mul_vec(a, aocs_vec3_make(0, 1, 0)), aocs_vec3_make(1, 0, 0), TOL_TIGHT);

    /* 90 deg about x: N's y axis is B's -z, N's z axis is B's +y */
    aocs_mat3_t ax = aocs_quat_to_dcm(aocs_quat_make((real_t)h, 0, 0, (real_t)h));
    assert_vec3_close(aocs_mat3_mul_vec(ax, aocs_vec3_make(0, 1, 0)), aocs_vec3_make(0, 0, -1), TOL_TIGHT);
    assert_vec3_close(aocs_mat3_mul_vec(ax, aocs_vec3_make(0, 0, 1)), aocs_vec3_make(0, 1, 0), TOL_TIGHT);
}

static void test_product_by_hand_is_shuster(void **state)
{
    (void)state;
    /*
     * q = [1 2 3 4], p = [5 6 7 8]:
     * q4 pv = (20,24,28), p4 qv = (8,16,24), qv x pv = (-4,8,-4)
     * vector = (20+8+4, 24+16-8, 28+24+4) = (32,32,56); scalar = 32 - 38 = -6.
     * (Hamilton's order, +qv x pv, would give (24,48,48).)
     */
    const double e[4] = {32, 32, 56, -6};
    aocs_quat_t r = aocs_quat_mul(aocs_quat_make(1, 2, 3, 4), aocs_quat_make(5, 6, 7, 8));
    assert_quat_close(r, e, TOL_TIGHT);
    const double id[4] = {1, 2, 3, 4};
    assert_quat_close(aocs_quat_mul(aocs_quat_identity(), aocs_quat_make(1, 2, 3, 4)), id, 0.0);
    assert_quat_close(aocs_quat_mul(aocs_quat_make(1, 2, 3, 4), aocs_quat_identity()), id, 0.0);
    aocs_vec3_t v = aocs_quat_vec(aocs_quat_make(1, 2, 3, 4));
    assert_vec3_close(v, aocs_vec3_make(1, 2, 3), 0.0);
}

static void test_product_composes_attitude_matrices(void **state)
{
    (void)state;
    test_rng_t rng = {0x9E3779B97F4A7C15ULL};
    for (int k = 0; k < 2000; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        aocs_quat_t p = test_random_quat(&rng);
        double aq[3][3], ap[3][3], aqp[3][3], prod[3][3];
        ref_dcm(q, aq);
        ref_dcm(p, ap);
        ref_matmul(aq, ap, prod);
        ref_dcm(aocs_quat_mul(q, p), aqp);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(aqp[i][j], prod[i][j], 4.0 * TOL_TIGHT);
            }
        }
    }
}

static void test_to_dcm_matches_spec_and_is_rotation(void **state)
{
    (void)state;
    test_rng_t rng = {42ULL};
    for (int k = 0; k < 1000; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        aocs_mat3_t a = aocs_quat_to_dcm(q);
        double e[3][3];
        ref_dcm(q, e);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(a.m[i][j], e[i][j], TOL_TIGHT);
            }
        }
        /* orthonormal rows, det +1 (a proper rotation) */
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                double dot = D(a.m[i][0]) * D(a.m[j][0]) + D(a.m[i][1]) * D(a.m[j][1]) +
                             D(a.m[i][2]) * D(a.m[j][2]);
                assert_close(dot, (i == j) ? 1.0 : 0.0, 4.0 * TOL_TIGHT);
            }
        }
        assert_close(aocs_mat3_det(a), 1.0, 4.0 * TOL_TIGHT);
        /* q and -q are the same attitude */
        aocs_mat3_t an = aocs_quat_to_dcm(aocs_quat_make(-q.q[0], -q.q[1], -q.q[2], -q.q[3]));
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(an.m[i][j], a.m[i][j], 0.0);
            }
        }
    }
}

static void test_inverse_and_error_quaternion(void **state)
{
    (void)state;
    test_rng_t rng = {7ULL};
    const double id[4] = {0, 0, 0, 1};
    for (int k = 0; k < 1000; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        aocs_quat_t qi = aocs_quat_conj(q);
        assert_close(qi.q[0], -D(q.q[0]), 0.0);
        assert_close(qi.q[3], D(q.q[3]), 0.0);
        assert_quat_close(aocs_quat_mul(q, qi), id, 2.0 * TOL_TIGHT);
        assert_quat_close(aocs_quat_mul(qi, q), id, 2.0 * TOL_TIGHT);
        assert_quat_close(aocs_quat_error(q, q), id, 2.0 * TOL_TIGHT);

        /* A(qe) = A(q) A(qd)^T: attitude of B relative to the target frame D */
        aocs_quat_t qd = test_random_quat(&rng);
        double aq[3][3], ad[3][3], adt[3][3], e[3][3], ae[3][3];
        ref_dcm(q, aq);
        ref_dcm(qd, ad);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                adt[i][j] = ad[j][i];
            }
        }
        ref_matmul(aq, adt, e);
        ref_dcm(aocs_quat_error(q, qd), ae);
        for (int i = 0; i < 3; ++i) {
            for (int j = 0; j < 3; ++j) {
                assert_close(ae[i][j], e[i][j], 4.0 * TOL_TIGHT);
            }
        }
    }
}

static void test_normalize(void **state)
{
    (void)state;
    aocs_quat_t out;
    const double s = 1.0 / sqrt(30.0);
    const double e[4] = {1 * s, 2 * s, 3 * s, 4 * s};
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(1, 2, 3, 4), &out), AOCS_OK);
    assert_quat_close(out, e, TOL_TIGHT);
    assert_close(aocs_quat_norm(aocs_quat_make(1, 2, 3, 4)), sqrt(30.0), TOL_TIGHT);
    /* 1e-5 still carries an attitude */
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(0, 0, AOCS_R(6e-6), AOCS_R(8e-6)), &out), AOCS_OK);
    assert_close(out.q[2], 0.6, TOL_TIGHT);
    assert_close(out.q[3], 0.8, TOL_TIGHT);

    const double sentinel[4] = {9, 9, 9, 9};
    out = aocs_quat_make(9, 9, 9, 9);
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(0, 0, 0, 0), &out), AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(0, 0, AOCS_R(6e-8), AOCS_R(8e-8)), &out),
                     AOCS_ERR_QUAT_NOT_UNIT); /* norm 1e-7 < 1e-6 */
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(0, (real_t)NAN, 0, 1), &out), AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(0, 0, 0, (real_t)INFINITY), &out),
                     AOCS_ERR_QUAT_NOT_UNIT);
    assert_quat_close(out, sentinel, 0.0);
    assert_int_equal(aocs_quat_normalize(aocs_quat_make(1, 2, 3, 4), NULL), AOCS_ERR_NULL_ARG);
}

static void test_is_finite(void **state)
{
    (void)state;
    assert_int_equal(aocs_quat_is_finite(aocs_quat_identity()), 1);
    for (int i = 0; i < 4; ++i) {
        aocs_quat_t q = aocs_quat_identity();
        q.q[i] = (real_t)NAN;
        assert_int_equal(aocs_quat_is_finite(q), 0);
        q.q[i] = (real_t)-INFINITY;
        assert_int_equal(aocs_quat_is_finite(q), 0);
    }
}

static void test_sign_q4(void **state)
{
    (void)state;
    assert_close(aocs_quat_sign_q4(aocs_quat_make(1, 0, 0, 0)), 1.0, 0.0); /* sign(0) = +1 */
    assert_close(aocs_quat_sign_q4(aocs_quat_make(1, 0, 0, AOCS_R(-0.0))), 1.0, 0.0);
    assert_close(aocs_quat_sign_q4(aocs_quat_make(0, 0, 0, AOCS_R(1e-30))), 1.0, 0.0);
    assert_close(aocs_quat_sign_q4(aocs_quat_make(0, 0, 0, AOCS_R(-1e-30))), -1.0, 0.0);
    assert_close(aocs_quat_sign_q4(aocs_quat_make(0, 0, 0, AOCS_R(-0.7))), -1.0, 0.0);
    assert_close(aocs_quat_sign_q4(aocs_quat_make(0, 0, 0, AOCS_R(0.7))), 1.0, 0.0);
}

static void test_angle(void **state)
{
    (void)state;
    /* 10 arcsec about a skew axis: q = [e sin(5"), cos(5")] */
    const double half = 5.0 / ARCSEC_PER_RAD;
    const double ax[3] = {1.0 / sqrt(14.0), -2.0 / sqrt(14.0), 3.0 / sqrt(14.0)};
    aocs_quat_t q = aocs_quat_make((real_t)(ax[0] * sin(half)), (real_t)(ax[1] * sin(half)),
                                   (real_t)(ax[2] * sin(half)), (real_t)cos(half));
    double ang_arcsec = D(aocs_quat_angle(q)) * ARCSEC_PER_RAD;
    /* relative, since the angle is tiny; float: inputs rounded to 6e-8 relative */
    assert_true(fabs(ang_arcsec - 10.0) <= 10.0 * 1e-6);
    /* both signs of q give the short angle */
    aocs_quat_t qn = aocs_quat_make(-q.q[0], -q.q[1], -q.q[2], -q.q[3]);
    assert_true(fabs(D(aocs_quat_angle(qn)) * ARCSEC_PER_RAD - 10.0) <= 10.0 * 1e-6);

    const double h = 0.70710678118654752;
    assert_close(aocs_quat_angle(aocs_quat_make(0, (real_t)h, 0, (real_t)h)), PI / 2.0, TOL_TIGHT);
    assert_close(aocs_quat_angle(aocs_quat_make(0, 0, 1, 0)), PI, TOL_TIGHT);
    assert_close(aocs_quat_angle(aocs_quat_identity()), 0.0, 0.0);
    /* a 190 deg rotation is a 170 deg one the other way */
    const double h190 = 0.5 * 190.0 * PI / 180.0;
    aocs_quat_t q190 = aocs_quat_make((real_t)sin(h190), 0, 0, (real_t)cos(h190));
    assert_close(aocs_quat_angle(q190), 170.0 * PI / 180.0, 4.0 * TOL_TIGHT);
}

/* Xi(q) of SPEC 1 typed in as a matrix */
static void ref_xi(aocs_quat_t qr, double xi[4][3])
{
    double q1 = D(qr.q[0]), q2 = D(qr.q[1]), q3 = D(qr.q[2]), q4 = D(qr.q[3]);
    const double m[4][3] = {{q4, -q3, q2}, {q3, q4, -q1}, {-q2, q1, q4}, {-q1, -q2, -q3}};
    for (int i = 0; i < 4; ++i) {
        for (int j = 0; j < 3; ++j) {
            xi[i][j] = m[i][j];
        }
    }
}

static void test_derivative_and_xi_transpose(void **state)
{
    (void)state;
    test_rng_t rng = {0xABCDEFULL};
    for (int k = 0; k < 1000; ++k) {
        aocs_quat_t q = test_random_quat(&rng);
        aocs_vec3_t w = test_random_vec3(&rng, 2.0);
        aocs_quat_t v4 = aocs_quat_make((real_t)test_rng_uniform(&rng, -1, 1), (real_t)test_rng_uniform(&rng, -1, 1),
                                        (real_t)test_rng_uniform(&rng, -1, 1), (real_t)test_rng_uniform(&rng, -1, 1));
        double xi[4][3];
        ref_xi(q, xi);
        aocs_quat_t qd = aocs_quat_derivative(q, w);
        for (int i = 0; i < 4; ++i) {
            double e = 0.5 * (xi[i][0] * D(w.v[0]) + xi[i][1] * D(w.v[1]) + xi[i][2] * D(w.v[2]));
            assert_close(qd.q[i], e, 4.0 * TOL_TIGHT);
        }
        aocs_vec3_t xt = aocs_quat_xi_transpose_mul(q, v4);
        for (int j = 0; j < 3; ++j) {
            double e = 0.0;
            for (int i = 0; i < 4; ++i) {
                e += xi[i][j] * D(v4.q[i]);
            }
            assert_close(xt.v[j], e, 4.0 * TOL_TIGHT);
        }
        /* Xi(q)^T q = 0 and the derivative keeps |q| constant: q . qdot = 0 */
        assert_vec3_close(aocs_quat_xi_transpose_mul(q, q), aocs_vec3_zero(), 4.0 * TOL_TIGHT);
        double qdotq = D(q.q[0]) * D(qd.q[0]) + D(q.q[1]) * D(qd.q[1]) + D(q.q[2]) * D(qd.q[2]) +
                       D(q.q[3]) * D(qd.q[3]);
        assert_close(qdotq, 0.0, 4.0 * TOL_TIGHT);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_passive_convention_90deg_about_z),
        cmocka_unit_test(test_product_by_hand_is_shuster),
        cmocka_unit_test(test_product_composes_attitude_matrices),
        cmocka_unit_test(test_to_dcm_matches_spec_and_is_rotation),
        cmocka_unit_test(test_inverse_and_error_quaternion),
        cmocka_unit_test(test_normalize),
        cmocka_unit_test(test_is_finite),
        cmocka_unit_test(test_sign_q4),
        cmocka_unit_test(test_angle),
        cmocka_unit_test(test_derivative_and_xi_transpose),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
