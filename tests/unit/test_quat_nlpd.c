/*
 * quat_nlpd (SPEC 2.3): u = -kp sign(qe4) qe_vec - kd (1 -/+ qe_vec.qe_vec) we,
 * variants NEG (minus) and POS (plus).
 * Proves, for both variants: the torque equals the SPEC formula evaluated
 * independently in double (own Shuster product) at three states including
 * qe4 < 0 and qe4 = 0, and a state worked by hand where the two variants
 * differ by the expected factor; a positive error about +x gives u_x < 0;
 * q and -q (and qd, -qd) give the same torque; along a closed-loop RK4 run
 * with the IRASSI inertia and gains the SPEC Lyapunov function decreases
 * with Vdot = -0.5 kd (1 -/+ |qe_v|^2) |w|^2; every invalid config (including
 * an unknown variant -> AOCS_ERR_MODE_INVALID), every non-finite input field,
 * a non-unit quaternion, a bad dt, an overflowing torque and a step before
 * init are rejected with their own status and a zero torque.
 */
#include "law_test_support.h"
#include "aocs/control/quat_nlpd.h"

/* ---- law-specific reference ---- */

/* +1 for POS, -1 for NEG: the sign in (1 -/+ qe_v.qe_v) written as 1 + sv qq */
static double variant_sign(aocs_quat_nlpd_variant_t v)
{
    return (v == AOCS_QUAT_NLPD_POS) ? 1.0 : -1.0;
}

/* SPEC 2.3 in double on the values the firmware sees; returns the term scale */
static double nlpd_expected(const aocs_att_input_t *in, double kp, double kd, aocs_quat_nlpd_variant_t v,
                            double u[3])
{
    dq_t qe = dq_mul(dq_from_real(in->q_BN), dq_inv(dq_from_real(in->qd_DN)));
    double sgn = (qe.q[3] >= 0.0) ? 1.0 : -1.0;
    double qq = qe.q[0] * qe.q[0] + qe.q[1] * qe.q[1] + qe.q[2] * qe.q[2];
    double factor = 1.0 + variant_sign(v) * qq;
    double scale = 1.0;
    for (int i = 0; i < 3; ++i) {
        double we = (double)in->w_BN_B.v[i] - (double)in->wd_B.v[i];
        u[i] = -kp * sgn * qe.q[i] - kd * factor * we;
        double s = fabs(kp * qe.q[i]) + fabs(kd * factor * we);
        scale = (s > scale) ? s : scale;
    }
    return scale;
}

static aocs_quat_nlpd_t make_law(double kp, double kd, aocs_quat_nlpd_variant_t v)
{
    aocs_quat_nlpd_t law;
    aocs_quat_nlpd_config_t cfg = {(real_t)kp, (real_t)kd, v};
    memset(&law, 0, sizeof law);
    assert_int_equal(aocs_quat_nlpd_init(&law, &cfg), AOCS_OK);
    return law;
}

static const aocs_quat_nlpd_variant_t VARIANTS[2] = {AOCS_QUAT_NLPD_NEG, AOCS_QUAT_NLPD_POS};

static void check_state(double kp, double kd, aocs_att_input_t in)
{
    for (int k = 0; k < 2; ++k) {
        aocs_quat_nlpd_t law = make_law(kp, kd, VARIANTS[k]);
        aocs_vec3_t u = aocs_vec3_make(AOCS_R(123.0), AOCS_R(123.0), AOCS_R(123.0));
        double expected[3];
        double scale = nlpd_expected(&in, kp, kd, VARIANTS[k], expected);
        assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_OK);
        assert_vec3_close_scaled(u, expected, TOL_TIGHT, scale);
    }
}

static void test_known_states(void **state)
{
    (void)state;
    const double w1[3] = {0.01, -0.02, 0.03};
    const double wd1[3] = {0.001, 0.0, -0.002};
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    check_state(4000.0, 8000.0, make_input(dq_euler321_deg(14.0, 14.0, 14.0), w1, qd, wd1, ZERO3, 0.1));

    /* error of 250 deg: qe4 < 0 and |qe_v|^2 ~ 0.67, so the variants differ strongly */
    dq_t q2 = dq_mul(dq_axis_angle(1.0, -2.0, 0.5, 250.0 * PI / 180.0), qd);
    dq_t qe2 = dq_mul(q2, dq_inv(qd));
    assert_true(qe2.q[3] < -0.5);
    const double w2[3] = {-0.1, 0.05, 0.2};
    check_state(4000.0, 8000.0, make_input(q2, w2, qd, ZERO3, ZERO3, 0.1));

    /* exactly 180 deg about x, qe4 = 0, sign(0) = +1 */
    dq_t q3 = {{1.0, 0.0, 0.0, 0.0}};
    dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    const double w3[3] = {0.0, 0.0, 0.5};
    check_state(4000.0, 8000.0, make_input(q3, w3, id, ZERO3, ZERO3, 0.1));
}

static void test_by_hand(void **state)
{
    (void)state;
    /* 60 deg about x: qe = [0.5 0 0 cos 30], |qe_v|^2 = 0.25; kp = 2, kd = 3, w = [0.1 0 0]
       NEG: u_x = -2 * 0.5 - 3 * 0.75 * 0.1 = -1.225; POS: -1 - 3 * 1.25 * 0.1 = -1.375 */
    const double by_hand[2] = {-1.225, -1.375};
    for (int k = 0; k < 2; ++k) {
        aocs_quat_nlpd_t law = make_law(2.0, 3.0, VARIANTS[k]);
        aocs_att_input_t in;
        in.q_BN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.86602540378443865));
        in.qd_DN = aocs_quat_identity();
        in.w_BN_B = aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0));
        in.wd_B = aocs_vec3_zero();
        in.wd_dot_B = aocs_vec3_zero();
        in.dt_s = AOCS_R(0.1);
        aocs_vec3_t u;
        assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_OK);
        const double expected[3] = {by_hand[k], 0.0, 0.0};
        assert_vec3_close_scaled(u, expected, TOL_TIGHT, 1.4);
    }
}

static void test_sign_convention(void **state)
{
    (void)state;
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double angles_deg[3] = {0.1, 10.0, 170.0};
    for (int v = 0; v < 2; ++v) {
        aocs_quat_nlpd_t law = make_law(4000.0, 8000.0, VARIANTS[v]);
        for (int k = 0; k < 3; ++k) {
            dq_t q = dq_mul(dq_axis_angle(1.0, 0.0, 0.0, angles_deg[k] * PI / 180.0), qd);
            aocs_att_input_t in = make_input(q, ZERO3, qd, ZERO3, ZERO3, 0.1);
            aocs_vec3_t u;
            assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_OK);
            assert_true(u.v[0] < AOCS_R(0.0));
            assert_true(fabs((double)u.v[1]) <= 1e-3 * fabs((double)u.v[0]));
            assert_true(fabs((double)u.v[2]) <= 1e-3 * fabs((double)u.v[0]));
        }
    }
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    for (int v = 0; v < 2; ++v) {
        aocs_quat_nlpd_t law = make_law(4000.0, 8000.0, VARIANTS[v]);
        test_rng_t rng = {0x9E3779B97F4A7C15ULL};
        for (int k = 0; k < 200; ++k) {
            aocs_att_input_t in;
            in.q_BN = test_random_quat(&rng);
            in.qd_DN = test_random_quat(&rng);
            in.w_BN_B = test_random_vec3(&rng, 0.1);
            in.wd_B = test_random_vec3(&rng, 0.01);
            in.wd_dot_B = aocs_vec3_zero();
            in.dt_s = AOCS_R(0.1);
            aocs_vec3_t u_ref;
            assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u_ref), AOCS_OK);
            for (int flip = 1; flip < 4; ++flip) {
                aocs_att_input_t in2 = in;
                for (int i = 0; i < 4; ++i) {
                    if ((flip & 1) != 0) {
                        in2.q_BN.q[i] = -in.q_BN.q[i];
                    }
                    if ((flip & 2) != 0) {
                        in2.qd_DN.q[i] = -in.qd_DN.q[i];
                    }
                }
                aocs_vec3_t u2;
                assert_int_equal(aocs_quat_nlpd_step(&law, &in2, &u2), AOCS_OK);
                assert_vec3_close(u2, u_ref, TOL_TIGHT * 4000.0);
            }
        }
    }
}

/* ---- Lyapunov ---- */
typedef struct {
    aocs_quat_nlpd_t law;
    dq_t qd;
    double kp;
    double kd;
    double sv; /* variant_sign */
    dmat_t j;
} nlpd_ctx_t;

static aocs_status_t nlpd_torque(void *vctx, dq_t q, const double w[3], double u[3])
{
    nlpd_ctx_t *c = (nlpd_ctx_t *)vctx;
    aocs_att_input_t in = make_input(q, w, c->qd, ZERO3, ZERO3, 0.01);
    aocs_vec3_t uv;
    aocs_status_t st = aocs_quat_nlpd_step(&c->law, &in, &uv);
    dv_from_real(uv, u);
    return st;
}

/*
 * SPEC 2.3 Lyapunov function with |qe4| (anti-unwinding):
 * V = 0.25 w^T J w + 0.5 kp qe_v.qe_v + 0.5 kp (1 - |qe4|)^2 = 0.25 w^T J w + kp (1 - |qe4|);
 * with wd = 0, Vdot = 0.5 w^T u + 0.5 kp sign(qe4) qe_v.w = -0.5 kd (1 -/+ qe_v.qe_v) |w|^2 <= 0
 * (NEG: 1 - |qe_v|^2 = qe4^2 >= 0).
 */
static void nlpd_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    nlpd_ctx_t *c = (nlpd_ctx_t *)vctx;
    dq_t qe = dq_mul(q, dq_inv(c->qd));
    double qv[3] = {qe.q[0], qe.q[1], qe.q[2]};
    double h[3];
    dm_mul_vec(&c->j, w, h);
    double a = 1.0 - fabs(qe.q[3]);
    double qq = dv_dot(qv, qv);
    *v = 0.25 * dv_dot(w, h) + 0.5 * c->kp * qq + 0.5 * c->kp * a * a;
    *vdot = -0.5 * c->kd * (1.0 + c->sv * qq) * dv_dot(w, w);
}

static void test_lyapunov_irassi(void **state)
{
    (void)state;
    static nlpd_ctx_t ctx;
    plant_t plant;
    plant_init(&plant, &J_IRASSI);
    const double w0[3] = {0.01, -0.02, 0.015};
    for (int v = 0; v < 2; ++v) {
        ctx.law = make_law(4000.0, 8000.0, VARIANTS[v]);
        ctx.kp = 4000.0;
        ctx.kd = 8000.0;
        ctx.sv = variant_sign(VARIANTS[v]);
        ctx.j = J_IRASSI;
        ctx.qd = dq_euler321_deg(30.0, -20.0, 1.0);
        double ratio = check_lyapunov(&plant, nlpd_torque, nlpd_lyap, &ctx, dq_euler321_deg(14.0, 14.0, 14.0),
                                      w0, 0.01, 1000, 2e-3);
        assert_true(ratio < 0.5);
        /* start beyond 180 deg: short-way convergence, V still decreasing */
        dq_t q0 = dq_mul(dq_axis_angle(0.3, 1.0, -0.2, 200.0 * PI / 180.0), ctx.qd);
        ratio = check_lyapunov(&plant, nlpd_torque, nlpd_lyap, &ctx, q0, w0, 0.01, 1000, 2e-3);
        assert_true(ratio < 0.9);
    }
}

/* ---- rejection paths ---- */
static aocs_att_input_t some_input(void)
{
    const double w[3] = {0.01, 0.02, 0.03};
    return make_input(dq_euler321_deg(14.0, 14.0, 14.0), w, dq_euler321_deg(30.0, -20.0, 1.0), ZERO3, ZERO3, 0.1);
}

static void expect_init_fails(aocs_quat_nlpd_config_t cfg, aocs_status_t expected)
{
    aocs_quat_nlpd_t law = make_law(1.0, 1.0, AOCS_QUAT_NLPD_NEG);
    aocs_att_input_t in = some_input();
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    assert_int_equal(aocs_quat_nlpd_init(&law, &cfg), expected);
    /* a failed init leaves the law unusable even after a good one */
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);
}

static void test_invalid_config(void **state)
{
    (void)state;
    const double bad_nf[3] = {NAN, INFINITY, -INFINITY};
    const double bad_np[3] = {0.0, -0.0, -1.0};
    for (int which = 0; which < 2; ++which) {
        for (int b = 0; b < 3; ++b) {
            aocs_quat_nlpd_config_t cfg = {AOCS_R(4000.0), AOCS_R(8000.0), AOCS_QUAT_NLPD_POS};
            if (which == 0) {
                cfg.kp = (real_t)bad_nf[b];
            } else {
                cfg.kd = (real_t)bad_nf[b];
            }
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);
            cfg.kp = AOCS_R(4000.0);
            cfg.kd = AOCS_R(8000.0);
            if (which == 0) {
                cfg.kp = (real_t)bad_np[b];
            } else {
                cfg.kd = (real_t)bad_np[b];
            }
            expect_init_fails(cfg, AOCS_ERR_GAIN_NOT_POSITIVE);
        }
    }
    aocs_quat_nlpd_config_t cfg = {AOCS_R(4000.0), AOCS_R(8000.0), (aocs_quat_nlpd_variant_t)2};
    expect_init_fails(cfg, AOCS_ERR_MODE_INVALID);
    cfg.variant = (aocs_quat_nlpd_variant_t)-1;
    expect_init_fails(cfg, AOCS_ERR_MODE_INVALID);
    aocs_quat_nlpd_t law;
    cfg.variant = AOCS_QUAT_NLPD_NEG;
    assert_int_equal(aocs_quat_nlpd_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_quat_nlpd_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_att_input_t good = some_input();
    aocs_vec3_t u;

    aocs_quat_nlpd_t law;
    memset(&law, 0, sizeof law);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_quat_nlpd_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);
    memset(&law, 0xA5, sizeof law);
    assert_int_equal(aocs_quat_nlpd_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);

    law = make_law(4000.0, 8000.0, AOCS_QUAT_NLPD_NEG);
    assert_int_equal(aocs_quat_nlpd_step(NULL, &good, &u), AOCS_ERR_NULL_ARG);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_quat_nlpd_step(&law, NULL, &u), AOCS_ERR_NULL_ARG);
    assert_vec3_is_zero(u);
    assert_int_equal(aocs_quat_nlpd_step(&law, &good, NULL), AOCS_ERR_NULL_ARG);

    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < N_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            aocs_att_input_t in = good;
            *input_field(&in, k) = (real_t)bad[b];
            u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
            aocs_status_t expected = (k == N_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE;
            assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), expected);
            assert_vec3_is_zero(u);
        }
    }
    aocs_att_input_t in = good;
    in.q_BN.q[3] *= AOCS_R(1.1);
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    in = good;
    in.qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    in = good;
    in.dt_s = AOCS_R(0.0);
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(-0.1);
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    assert_vec3_is_zero(u);
    in = good;
    in.w_BN_B = aocs_vec3_make(AOCS_REAL_MAX / AOCS_R(2.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_vec3_is_zero(u);
    assert_int_equal(aocs_quat_nlpd_step(&law, &good, &u), AOCS_OK);
    assert_true(aocs_vec3_is_finite(u) != 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_states),
        cmocka_unit_test(test_by_hand),
        cmocka_unit_test(test_sign_convention),
        cmocka_unit_test(test_q_and_minus_q_same_torque),
        cmocka_unit_test(test_lyapunov_irassi),
        cmocka_unit_test(test_invalid_config),
        cmocka_unit_test(test_step_rejections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
