/*
 * hinf (SPEC 2.6): u = +K x, x = [phi theta psi phidot thetadot psidot] of
 * the body relative to the target frame. States are built here from chosen
 * Euler angles and Euler rates (forward 3-2-1 relations), so the law's
 * inverse conversions are checked against independent data; the forward
 * body-rate relation itself was checked against finite differences of the
 * quaternion path (p = phidot - psidot sin theta, ...).
 */
#include "law_test_support.h"

#include "aocs/control/hinf.h"

#if defined(AOCS_REAL_IS_FLOAT)
/* float: Euler extraction (asin / atan2 of float products) ~1e-6 rad abs */
#define LAW_REL_TOL 5.0e-5
#define ANGLE_ABS_TOL 2.0e-6
#else
#define LAW_REL_TOL 1.0e-10
#define ANGLE_ABS_TOL 1.0e-12
#endif

static aocs_status_t hinf_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_hinf_step((aocs_hinf_t *)law, in, u_out);
}

/* quaternion reference (dq_t, Shuster product, 3-2-1 quaternions): law_test_support.h */

/* A(qe) = R1(phi) R2(theta) R3(psi) from e = [phi theta psi] */
static dq_t dq_321(double phi, double theta, double psi)
{
    return dq_euler321(psi, theta, phi);
}

/* body rate of B relative to D from Euler angles and rates (3-2-1 forward relation) */
static void body_rate_from_euler(const double e[3], const double ed[3], double w[3])
{
    const double phi = e[0], theta = e[1];
    w[0] = ed[0] - ed[2] * sin(theta);
    w[1] = ed[1] * cos(phi) + ed[2] * sin(phi) * cos(theta);
    w[2] = -ed[1] * sin(phi) + ed[2] * cos(phi) * cos(theta);
}

/* input for relative Euler state (e, ed) w.r.t. target qd rotating with wd */
static aocs_att_input_t make_state(const double e[3], const double ed[3], dq_t qd, const double wd[3])
{
    aocs_att_input_t in;
    double w[3];
    body_rate_from_euler(e, ed, w);
    for (int i = 0; i < 3; ++i) {
        w[i] += wd[i];
    }
    /* qe = q (x) qd^-1 */
    in = make_input_real(dq_to_real(dq_mul(dq_321(e[0], e[1], e[2]), qd)), dv_to_real(w), dq_to_real(qd),
                         dv_to_real(wd));
    return in;
}

static aocs_hinf_config_t random_config(test_rng_t *rng)
{
    aocs_hinf_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = (real_t)test_rng_uniform(rng, -1000.0, 1000.0);
        }
    }
    return cfg;
}

static void check_random_states(double angle_max, double rate_max, unsigned seed)
{
    test_rng_t rng = {seed};
    aocs_hinf_t law;
    const aocs_hinf_config_t cfg = random_config(&rng);
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    for (int k = 0; k < 2000; ++k) {
        double x[6];
        for (int i = 0; i < 3; ++i) {
            x[i] = test_rng_uniform(&rng, -angle_max, angle_max);
            x[3 + i] = test_rng_uniform(&rng, -rate_max, rate_max);
        }
        double wd[3] = {test_rng_uniform(&rng, -1e-3, 1e-3), test_rng_uniform(&rng, -1e-3, 1e-3),
                        test_rng_uniform(&rng, -1e-3, 1e-3)};
        aocs_att_input_t in = make_state(&x[0], &x[3], dq_from_real(test_random_quat(&rng)), wd);
        aocs_vec3_t u;
        assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
        /* u = +K x; the law's Euler angles carry up to ANGLE_ABS_TOL of rounding */
        assert_gain_product(cfg.k, x, 1.0, u, LAW_REL_TOL, ANGLE_ABS_TOL, 0.0);
    }
}

static void test_small_angle_states(void **state)
{
    (void)state;
    check_random_states(0.05, 1e-3, 0x77u); /* the regime of the linear model */
}

static void test_large_angle_exact_kinematics(void **state)
{
    (void)state;
    /* up to 60 deg: Euler rates differ clearly from we, the exact relation is needed */
    check_random_states(1.05, 0.05, 0x99u);
}

static void test_identity_error_gives_zero(void **state)
{
    (void)state;
    test_rng_t rng = {0x31u};
    aocs_hinf_t law;
    aocs_hinf_config_t cfg = random_config(&rng);
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    for (int k = 0; k < 100; ++k) {
        const aocs_quat_t q = test_random_quat(&rng);
        const aocs_vec3_t w = test_random_vec3(&rng, 0.01);
        aocs_att_input_t in = make_input_real(q, w, q, w);
        aocs_vec3_t u;
        assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
        /* x = 0 up to the rounding of qe4 ~ 1, qe_vec ~ eps */
        assert_true(aocs_vec3_norm_inf(u) <= AOCS_R(6000.0) * AOCS_R(8.0) * AOCS_REAL_EPS);
    }
}

static void test_pure_axis_errors(void **state)
{
    (void)state;
    aocs_hinf_t law;
    aocs_hinf_config_t cfg;
    /* K = [I 0]: u = [phi theta psi] */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = (i == j) ? AOCS_R(1.0) : AOCS_R(0.0);
        }
    }
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    const double a = 0.01;
    dq_t qd = dq_321(0.3, -0.2, 1.0); /* any target */
    for (int axis = 0; axis < 3; ++axis) {
        aocs_att_input_t in = make_input_real(dq_to_real(dq_mul(dq_axis_angle(axis == 0, axis == 1, axis == 2, a), qd)),
                                              aocs_vec3_zero(), dq_to_real(qd), aocs_vec3_zero());
        aocs_vec3_t u;
        assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
        for (int i = 0; i < 3; ++i) {
            double expect = (i == axis) ? a : 0.0; /* roll about x is phi, pitch y theta, yaw z psi */
            assert_true(fabs((double)u.v[i] - expect) <= 100.0 * ANGLE_ABS_TOL + 1e-15);
        }
    }
    /* K = [0 I]: u = Euler rates; pure roll rate with zero angles gives phidot = p */
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = (j == 3 + i) ? AOCS_R(1.0) : AOCS_R(0.0);
        }
    }
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    double e[3] = {0.0, 0.0, 0.0};
    double ed[3] = {2e-3, 0.0, 0.0};
    double wd[3] = {0.0, 0.0, 7.292115e-5}; /* orbit rate of the target frame */
    aocs_att_input_t in = make_state(e, ed, qd, wd);
    aocs_vec3_t u;
    assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
    assert_close(u.v[0], 2e-3, TOL_TIGHT);
    assert_true(fabs((double)u.v[1]) <= 1e-9 && fabs((double)u.v[2]) <= 1e-9);
}

static void test_gimbal_lock_finite(void **state)
{
    (void)state;
    test_rng_t rng = {0x55u};
    aocs_hinf_t law;
    aocs_hinf_config_t cfg = random_config(&rng);
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    dq_t ident = {{0.0, 0.0, 0.0, 1.0}};
    double e[3] = {0.0, 1.5707963267948966, 0.0}; /* theta = 90 deg */
    double ed[3] = {0.0, 0.0, 0.0};
    double wd[3] = {0.0, 0.0, 0.0};
    aocs_att_input_t in = make_state(e, ed, ident, wd);
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
    aocs_vec3_t u;
    assert_int_equal(aocs_hinf_step(&law, &in, &u), AOCS_OK);
    assert_true(aocs_vec3_is_finite(u) != 0);
}

static void test_config_validation(void **state)
{
    (void)state;
    aocs_hinf_t law;
    aocs_hinf_config_t cfg;
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.k[i][j] = AOCS_R(0.0);
        }
    }
    assert_int_equal(aocs_hinf_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_hinf_init(&law, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_ERR_GAIN_TABLE_INVALID); /* all zero */
    cfg.k[2][4] = AOCS_R(-3.0); /* one nonzero, negative: accepted (u = +K x) */
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    cfg.k[0][0] = (real_t)NAN;
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg.k[0][0] = (real_t)INFINITY;
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    assert_step_not_initialised(hinf_step, &law);
}

static void test_invalid_inputs_zero_output(void **state)
{
    (void)state;
    test_rng_t rng = {0x66u};
    aocs_hinf_t law;
    check_step_before_init(hinf_step, &law, sizeof law);
    aocs_hinf_config_t cfg = random_config(&rng);
    assert_int_equal(aocs_hinf_init(&law, &cfg), AOCS_OK);
    aocs_att_input_t good = make_input_real(aocs_quat_identity(), aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(0.0)),
                                            aocs_quat_identity(), aocs_vec3_zero());
    /* every rejection of the law_io.h contract (law_test_support.h) */
    check_step_rejections(hinf_step, &law, &good);
    aocs_att_input_t in = good;
    in.qd_DN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.5));
    assert_step_rejects(hinf_step, &law, &in, AOCS_ERR_QUAT_NOT_UNIT);
    in = good;
    in.w_BN_B.v[0] = AOCS_REAL_MAX;
    in.wd_B.v[0] = -AOCS_REAL_MAX; /* we overflows */
    assert_step_rejects(hinf_step, &law, &in, AOCS_ERR_OUTPUT_NOT_FINITE);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_small_angle_states),
        cmocka_unit_test(test_large_angle_exact_kinematics),
        cmocka_unit_test(test_identity_error_gives_zero),
        cmocka_unit_test(test_pure_axis_errors),
        cmocka_unit_test(test_gimbal_lock_finite),
        cmocka_unit_test(test_config_validation),
        cmocka_unit_test(test_invalid_inputs_zero_output),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
