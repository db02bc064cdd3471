/*
 * quat_pd (SPEC 2.2): u = -kp sign(qe4) qe_vec - kd we.
 * Proves: the torque equals the SPEC formula evaluated independently in
 * double (own Shuster product, no firmware math) at three states including
 * qe4 < 0 and qe4 = 0, plus one state worked by hand; a positive error about
 * +x gives a restoring u_x < 0; q and -q (and qd, -qd) give the same torque;
 * along a closed-loop RK4 run with the IRASSI inertia and gains the SPEC
 * Lyapunov function decreases and its derivative equals -0.5 kd |w|^2; every
 * invalid config, every non-finite input field, a non-unit quaternion, a bad
 * dt, an overflowing torque and a step before init are rejected with their
 * own status and a zero torque.
 */
#include "law_test_support.h"
#include "aocs/control/quat_pd.h"

/* ---- law-specific reference ---- */

/* SPEC 2.2 in double on the values the firmware sees; returns the term scale */
static double pd_expected(const aocs_att_input_t *in, double kp, double kd, double u[3])
{
    dq_t qe = dq_mul(dq_from_real(in->q_BN), dq_inv(dq_from_real(in->qd_DN)));
    double sgn = (qe.q[3] >= 0.0) ? 1.0 : -1.0;
    double scale = 1.0;
    for (int i = 0; i < 3; ++i) {
        double we = (double)in->w_BN_B.v[i] - (double)in->wd_B.v[i];
        u[i] = -kp * sgn * qe.q[i] - kd * we;
        double s = fabs(kp * qe.q[i]) + fabs(kd * we);
        scale = (s > scale) ? s : scale;
    }
    return scale;
}

static aocs_quat_pd_t make_law(double kp, double kd)
{
    aocs_quat_pd_t law;
    aocs_quat_pd_config_t cfg = {(real_t)kp, (real_t)kd};
    memset(&law, 0, sizeof law);
    assert_int_equal(aocs_quat_pd_init(&law, &cfg), AOCS_OK);
    return law;
}

static aocs_status_t pd_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_quat_pd_step((aocs_quat_pd_t *)law, in, u_out);
}

static aocs_status_t pd_init_gains(void *law, real_t kp, real_t kd)
{
    aocs_quat_pd_config_t cfg = {kp, kd};
    return aocs_quat_pd_init((aocs_quat_pd_t *)law, &cfg);
}

static void check_state(double kp, double kd, aocs_att_input_t in)
{
    aocs_quat_pd_t law = make_law(kp, kd);
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(123.0), AOCS_R(123.0), AOCS_R(123.0));
    double expected[3];
    double scale = pd_expected(&in, kp, kd, expected);
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_OK);
    assert_vec3_close_scaled(u, expected, TOL_TIGHT, scale);
}

static void test_known_states(void **state)
{
    (void)state;
    /* IRASSI slew, 250 deg (sign(qe4) = -1), 180 deg (qe4 = 0): law_test_support.h */
    aocs_att_input_t in[N_PD_REFERENCE_STATES];
    pd_reference_states(in);
    for (int k = 0; k < N_PD_REFERENCE_STATES; ++k) {
        check_state(4000.0, 8000.0, in[k]);
    }
    /* 180 deg about x: sign(0) = +1, so u = [-kp, 0, -kd w3] */
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
    aocs_vec3_t u;
    assert_int_equal(aocs_quat_pd_step(&law, &in[2], &u), AOCS_OK);
    const double by_hand3[3] = {-4000.0, 0.0, -4000.0};
    assert_vec3_close_scaled(u, by_hand3, TOL_TIGHT, 4000.0);
}

static void test_by_hand(void **state)
{
    (void)state;
    /* 60 deg about x: qe = [0.5 0 0 cos 30]; kp = 2, kd = 3, w = [0.1 0 0]:
       u = [-2 * 0.5 - 3 * 0.1, 0, 0] = [-1.3, 0, 0] */
    aocs_quat_pd_t law = make_law(2.0, 3.0);
    aocs_att_input_t in = make_input_60deg_about_x(0.1);
    aocs_vec3_t u;
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_OK);
    const double expected[3] = {-1.3, 0.0, 0.0};
    assert_vec3_close_scaled(u, expected, TOL_TIGHT, 1.3);
}

static void test_sign_convention(void **state)
{
    (void)state;
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
    check_restoring_torque_about_x(pd_step, &law);
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
    /* u is odd in the sign of qe4 only through sign(qe4) qe_vec: same torque */
    const sign_sweep_t sweep = {.w_scale = 0.1, .wd_scale = 0.01, .tol = TOL_TIGHT * 4000.0};
    assert_int_equal(check_q_sign_invariance(pd_step, &law, &sweep), 200);
}

/* ---- Lyapunov ---- */
typedef struct {
    aocs_quat_pd_t law;
    dq_t qd;
    double kp;
    double kd;
    dmat_t j;
} pd_ctx_t;

static aocs_status_t pd_torque(void *vctx, dq_t q, const double w[3], double u[3])
{
    pd_ctx_t *c = (pd_ctx_t *)vctx;
    return law_torque(pd_step, &c->law, q, w, c->qd, u);
}

/*
 * SPEC 2.3 Lyapunov function with |qe4| (pd_lyapunov_v, law_test_support.h).
 * With wd = 0: Vdot = 0.5 w^T u + 0.5 kp sign(qe4) qe_v.w = -0.5 kd |w|^2.
 */
static void pd_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    pd_ctx_t *c = (pd_ctx_t *)vctx;
    *v = pd_lyapunov_v(&c->j, c->kp, c->qd, q, w);
    *vdot = -0.5 * c->kd * dv_dot(w, w);
}

static void test_lyapunov_irassi(void **state)
{
    (void)state;
    static pd_ctx_t ctx;
    plant_t plant;
    plant_init(&plant, &J_IRASSI);
    ctx.law = make_law(4000.0, 8000.0);
    ctx.kp = 4000.0;
    ctx.kd = 8000.0;
    ctx.j = J_IRASSI;
    ctx.qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double w0[3] = {0.01, -0.02, 0.015};
    /* 10 s at h = 0.01 s; central-difference error ~ (h / 0.27 s)^2 / 6 */
    double ratio = check_lyapunov(&plant, pd_torque, pd_lyap, &ctx, dq_euler321_deg(14.0, 14.0, 14.0), w0,
                                  0.01, 1000, 2e-3);
    assert_true(ratio < 0.5);
    /* a second start beyond 180 deg error: converges the short way, V still decreasing */
    dq_t q0 = dq_mul(dq_axis_angle(0.3, 1.0, -0.2, 200.0 * PI / 180.0), ctx.qd);
    ratio = check_lyapunov(&plant, pd_torque, pd_lyap, &ctx, q0, w0, 0.01, 1000, 2e-3);
    assert_true(ratio < 0.9);
}

/* ---- rejection paths (law_test_support.h) ---- */
static void test_invalid_config(void **state)
{
    (void)state;
    aocs_quat_pd_t law;
    check_gain_pair_rejections(pd_init_gains, pd_step, &law, 4000.0, 8000.0);
    aocs_quat_pd_config_t cfg = {AOCS_R(1.0), AOCS_R(1.0)};
    assert_int_equal(aocs_quat_pd_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_quat_pd_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_quat_pd_t law;
    check_step_before_init(pd_step, &law, sizeof law);
    law = make_law(4000.0, 8000.0);
    aocs_att_input_t good = law_test_input();
    check_step_rejections(pd_step, &law, &good);
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
