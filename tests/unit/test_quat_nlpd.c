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

static aocs_status_t nlpd_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_quat_nlpd_step((aocs_quat_nlpd_t *)law, in, u_out);
}

/* the gain checks do not depend on the variant: POS here */
static aocs_status_t nlpd_init_gains(void *law, real_t kp, real_t kd)
{
    aocs_quat_nlpd_config_t cfg = {kp, kd, AOCS_QUAT_NLPD_POS};
    return aocs_quat_nlpd_init((aocs_quat_nlpd_t *)law, &cfg);
}

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
    /* IRASSI slew, 250 deg (sign(qe4) = -1 and |qe_v|^2 ~ 0.67, so the variants
     * differ strongly), 180 deg (qe4 = 0): law_test_support.h */
    aocs_att_input_t in[N_PD_REFERENCE_STATES];
    pd_reference_states(in);
    for (int k = 0; k < N_PD_REFERENCE_STATES; ++k) {
        check_state(4000.0, 8000.0, in[k]);
    }
}

static void test_by_hand(void **state)
{
    (void)state;
    /* 60 deg about x: qe = [0.5 0 0 cos 30], |qe_v|^2 = 0.25; kp = 2, kd = 3, w = [0.1 0 0]
       NEG: u_x = -2 * 0.5 - 3 * 0.75 * 0.1 = -1.225; POS: -1 - 3 * 1.25 * 0.1 = -1.375 */
    const double by_hand[2] = {-1.225, -1.375};
    for (int k = 0; k < 2; ++k) {
        aocs_quat_nlpd_t law = make_law(2.0, 3.0, VARIANTS[k]);
        aocs_att_input_t in = make_input_60deg_about_x(0.1);
        aocs_vec3_t u;
        assert_int_equal(aocs_quat_nlpd_step(&law, &in, &u), AOCS_OK);
        const double expected[3] = {by_hand[k], 0.0, 0.0};
        assert_vec3_close_scaled(u, expected, TOL_TIGHT, 1.4);
    }
}

static void test_sign_convention(void **state)
{
    (void)state;
    for (int v = 0; v < 2; ++v) {
        aocs_quat_nlpd_t law = make_law(4000.0, 8000.0, VARIANTS[v]);
        check_restoring_torque_about_x(nlpd_step, &law);
    }
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    const sign_sweep_t sweep = {.w_scale = 0.1, .wd_scale = 0.01, .tol = TOL_TIGHT * 4000.0};
    for (int v = 0; v < 2; ++v) {
        aocs_quat_nlpd_t law = make_law(4000.0, 8000.0, VARIANTS[v]);
        assert_int_equal(check_q_sign_invariance(nlpd_step, &law, &sweep), 200);
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
    return law_torque(nlpd_step, &c->law, q, w, c->qd, u);
}

/*
 * SPEC 2.3 Lyapunov function with |qe4| (pd_lyapunov_v, law_test_support.h);
 * with wd = 0, Vdot = 0.5 w^T u + 0.5 kp sign(qe4) qe_v.w = -0.5 kd (1 -/+ qe_v.qe_v) |w|^2 <= 0
 * (NEG: 1 - |qe_v|^2 = qe4^2 >= 0).
 */
static void nlpd_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    nlpd_ctx_t *c = (nlpd_ctx_t *)vctx;
    dq_t qe = dq_mul(q, dq_inv(c->qd));
    double qq = qe.q[0] * qe.q[0] + qe.q[1] * qe.q[1] + qe.q[2] * qe.q[2];
    *v = pd_lyapunov_v(&c->j, c->kp, c->qd, q, w);
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

/* ---- rejection paths (law_test_support.h) ---- */
static void expect_init_fails(aocs_quat_nlpd_config_t cfg, aocs_status_t expected)
{
    aocs_quat_nlpd_t law = make_law(1.0, 1.0, AOCS_QUAT_NLPD_NEG);
    assert_int_equal(aocs_quat_nlpd_init(&law, &cfg), expected);
    /* a failed init leaves the law unusable even after a good one */
    assert_step_not_initialised(nlpd_step, &law);
}

static void test_invalid_config(void **state)
{
    (void)state;
    aocs_quat_nlpd_t law;
    check_gain_pair_rejections(nlpd_init_gains, nlpd_step, &law, 4000.0, 8000.0);
    aocs_quat_nlpd_config_t cfg = {AOCS_R(4000.0), AOCS_R(8000.0), (aocs_quat_nlpd_variant_t)2};
    expect_init_fails(cfg, AOCS_ERR_MODE_INVALID);
    cfg.variant = (aocs_quat_nlpd_variant_t)-1;
    expect_init_fails(cfg, AOCS_ERR_MODE_INVALID);
    cfg.variant = AOCS_QUAT_NLPD_NEG;
    assert_int_equal(aocs_quat_nlpd_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_quat_nlpd_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_quat_nlpd_t law;
    check_step_before_init(nlpd_step, &law, sizeof law);
    law = make_law(4000.0, 8000.0, AOCS_QUAT_NLPD_NEG);
    aocs_att_input_t good = law_test_input();
    check_step_rejections(nlpd_step, &law, &good);
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
