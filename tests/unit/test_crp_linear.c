/*
 * crp_linear (SPEC 2.1, Rotea-Tsiotras-Corless 1998): u = -k1 we - k2 rho(qe).
 * Proves: the torque equals the formula at the rtc_ex2a state (rho given, so
 * also checkable by hand), at a state with qe4 < 0 and a non-identity target
 * (rho = qe_v / qe4 evaluated independently), at |rho| = 200 (rtc level) and
 * at |qe4| = 10 AOCS_CRP_Q4_MIN, just above the singular threshold; qe4 = 0, +-1e-12 give
 * AOCS_ERR_CRP_SINGULAR with a zero torque and no NaN; a positive error
 * about +x gives u_x < 0; q and -q give the same torque; along RK4
 * closed-loop runs of rtc_ex2a and rtc_ex3a (J = I3) the SPEC Lyapunov
 * function V = 0.5 w^T J w + k2 ln(1 + |rho|^2) decreases with
 * Vdot = -k1 |w|^2 (central differences); every invalid config, every
 * non-finite input field, a non-unit quaternion, a bad dt, an overflowing
 * torque and a step before init are rejected with their own status.
 */
#include "law_test_support.h"
#include "aocs/control/crp_linear.h"

/* ---- law-specific reference ---- */
static const dmat_t J_UNIT = {{{1.0, 0.0, 0.0}, {0.0, 1.0, 0.0}, {0.0, 0.0, 1.0}}};

/* q = [rho; 1] / sqrt(1 + |rho|^2) (SPEC 4 initial attitude) */
static dq_t dq_from_rho(const double rho[3])
{
    double n = sqrt(1.0 + dv_dot(rho, rho));
    dq_t q = {{rho[0] / n, rho[1] / n, rho[2] / n, 1.0 / n}};
    return q;
}

/* SPEC 2.1 in double on the values the firmware sees; returns the term scale */
static double crp_expected(const aocs_att_input_t *in, double k1, double k2, double u[3])
{
    dq_t qe = dq_mul(dq_from_real(in->q_BN), dq_inv(dq_from_real(in->qd_DN)));
    double scale = 1.0;
    for (int i = 0; i < 3; ++i) {
        double we = (double)in->w_BN_B.v[i] - (double)in->wd_B.v[i];
        double rho = qe.q[i] / qe.q[3]; /* same for qe and -qe */
        u[i] = -k1 * we - k2 * rho;
        double s = fabs(k1 * we) + fabs(k2 * rho);
        scale = (s > scale) ? s : scale;
    }
    return scale;
}

static aocs_crp_linear_t make_law(double k1, double k2)
{
    aocs_crp_linear_t law;
    aocs_crp_linear_config_t cfg = {(real_t)k1, (real_t)k2};
    memset(&law, 0, sizeof law);
    assert_int_equal(aocs_crp_linear_init(&law, &cfg), AOCS_OK);
    return law;
}

static aocs_status_t crp_step(void *law, const aocs_att_input_t *in, aocs_vec3_t *u_out)
{
    return aocs_crp_linear_step((aocs_crp_linear_t *)law, in, u_out);
}

static aocs_status_t crp_init_gains(void *law, real_t k1, real_t k2)
{
    aocs_crp_linear_config_t cfg = {k1, k2};
    return aocs_crp_linear_init((aocs_crp_linear_t *)law, &cfg);
}

static void check_state(double k1, double k2, aocs_att_input_t in, double tol)
{
    aocs_crp_linear_t law = make_law(k1, k2);
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(123.0), AOCS_R(123.0), AOCS_R(123.0));
    double expected[3];
    double scale = crp_expected(&in, k1, k2, expected);
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_OK);
    assert_vec3_close_scaled(u, expected, tol, scale);
}

static void test_known_states(void **state)
{
    (void)state;
    dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    /* rtc_ex2a: rho = [0.5 0.1 0.6], w = [0 0.9 -0.5], k1 = 19, k2 = 13:
       by hand u = -19 w - 13 rho = [-6.5, -18.4, 1.7] */
    const double rho1[3] = {0.5, 0.1, 0.6};
    const double w1[3] = {0.0, 0.9, -0.5};
    aocs_att_input_t in1 = make_input(dq_from_rho(rho1), w1, id, ZERO3, ZERO3, 0.01);
    check_state(19.0, 13.0, in1, TOL_TIGHT);
    aocs_crp_linear_t law = make_law(19.0, 13.0);
    aocs_vec3_t u;
    assert_int_equal(aocs_crp_linear_step(&law, &in1, &u), AOCS_OK);
    const double by_hand[3] = {-6.5, -18.4, 1.7};
    assert_vec3_close_scaled(u, by_hand, TOL_TIGHT, 20.0);

    /* non-identity target, error of 230 deg: qe4 < 0, short-rotation rho */
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    dq_t q2 = dq_mul(dq_axis_angle(1.0, -2.0, 0.5, 230.0 * PI / 180.0), qd);
    assert_true(dq_mul(q2, dq_inv(qd)).q[3] < -0.3);
    const double w2[3] = {-0.1, 0.05, 0.2};
    const double wd2[3] = {0.01, -0.02, 0.0};
    check_state(3.0, 2.0, make_input(q2, w2, qd, wd2, ZERO3, 0.01), TOL_TIGHT);

    /* |rho| = 200 along [1 -2 2] / 3 (rtc scenarios pass here): finite, equals the formula */
    const double rho3[3] = {200.0 / 3.0, -400.0 / 3.0, 400.0 / 3.0};
    const double w3[3] = {48.0, 30.0, -20.0};
    aocs_att_input_t in3 = make_input(dq_from_rho(rho3), w3, id, ZERO3, ZERO3, 0.01);
    check_state(19.0, 13.0, in3, TOL_TIGHT);
    assert_int_equal(aocs_crp_linear_step(&law, &in3, &u), AOCS_OK);
    const double by_hand3[3] = {-19.0 * 48.0 - 13.0 * rho3[0], -19.0 * 30.0 - 13.0 * rho3[1],
                                19.0 * 20.0 - 13.0 * rho3[2]};
    /* by hand from the unrounded rho: float rounds q4 = 1/sqrt(40001) first */
    assert_vec3_close_scaled(u, by_hand3, TOL_LOOSE, 2600.0);

    /* |qe4| ten times the singular threshold (1e-7 double, 1e-5 float): |rho| = 0.1 / AOCS_CRP_Q4_MIN,
       still finite and exact */
    dq_t q4 = {{0.0, 0.6, 0.8, 10.0 * (double)AOCS_CRP_Q4_MIN}};
    check_state(19.0, 13.0, make_input(q4, w1, id, ZERO3, ZERO3, 0.01), TOL_TIGHT);
}

static void test_singular(void **state)
{
    (void)state;
    aocs_crp_linear_t law = make_law(19.0, 13.0);
    dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    const double w[3] = {0.1, -0.2, 0.3};
    /* 180 deg exactly and within 1e-12 of it, both signs of qe4 */
    const dq_t qs[4] = {{{0.0, 0.0, 1.0, 0.0}}, {{0.6, 0.0, 0.8, 1e-12}}, {{0.6, 0.0, 0.8, -1e-12}},
                        {{-0.48, 0.6, 0.64, 0.0}}};
    for (int k = 0; k < 4; ++k) {
        aocs_att_input_t in = make_input(qs[k], w, id, ZERO3, ZERO3, 0.01);
        aocs_vec3_t u = aocs_vec3_make(AOCS_R(7.0), AOCS_R(7.0), AOCS_R(7.0));
        assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_CRP_SINGULAR);
        assert_vec3_is_zero(u);
        /* the law recovers on the next good input (no sticky state) */
        dq_t q_ok = {{0.6, 0.0, 0.0, 0.8}};
        in = make_input(q_ok, w, id, ZERO3, ZERO3, 0.01);
        assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_OK);
        double expected[3];
        double scale = crp_expected(&in, 19.0, 13.0, expected);
        assert_vec3_close_scaled(u, expected, TOL_TIGHT, scale);
    }
}

static void test_sign_convention(void **state)
{
    (void)state;
    aocs_crp_linear_t law = make_law(19.0, 13.0);
    check_restoring_torque_about_x(crp_step, &law);
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    aocs_crp_linear_t law = make_law(19.0, 13.0);
    /* keep away from 180 deg where rho is ill-conditioned in float */
    const sign_sweep_t sweep = {.w_scale = 1.0, .wd_scale = 0.1, .tol = TOL_TIGHT * 300.0, .min_abs_qe4 = 0.05};
    assert_true(check_q_sign_invariance(crp_step, &law, &sweep) > 150);
}

/* ---- Lyapunov ---- */
typedef struct {
    aocs_crp_linear_t law;
    double k1;
    double k2;
} crp_ctx_t;

static aocs_status_t crp_torque(void *vctx, dq_t q, const double w[3], double u[3])
{
    const dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    return law_torque(crp_step, &((crp_ctx_t *)vctx)->law, q, w, id, u);
}

/* SPEC 2.1: V = 0.5 w^T J w + k2 ln(1 + |rho|^2), Vdot = -k1 w^T w (J = I3 here) */
static void crp_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    crp_ctx_t *c = (crp_ctx_t *)vctx;
    double rho[3] = {q.q[0] / q.q[3], q.q[1] / q.q[3], q.q[2] / q.q[3]};
    *v = 0.5 * dv_dot(w, w) + c->k2 * log1p(dv_dot(rho, rho));
    *vdot = -c->k1 * dv_dot(w, w);
}

static void test_lyapunov_rtc(void **state)
{
    (void)state;
    static crp_ctx_t ctx;
    plant_t plant;
    plant_init(&plant, &J_UNIT);
    /* rtc_ex2a */
    ctx.law = make_law(19.0, 13.0);
    ctx.k1 = 19.0;
    ctx.k2 = 13.0;
    const double rho_a[3] = {0.5, 0.1, 0.6};
    const double w_a[3] = {0.0, 0.9, -0.5};
    double ratio = check_lyapunov(&plant, crp_torque, crp_lyap, &ctx, dq_from_rho(rho_a), w_a, 1e-3, 2000, 2e-3);
    assert_true(ratio < 0.2);
    /* rtc_ex3a: k1 = 3, k2 = 2, large rho and rates */
    ctx.law = make_law(3.0, 2.0);
    ctx.k1 = 3.0;
    ctx.k2 = 2.0;
    const double rho_b[3] = {15.0, -9.0, 1.0};
    const double w_b[3] = {-6.0, 4.0, -3.0};
    ratio = check_lyapunov(&plant, crp_torque, crp_lyap, &ctx, dq_from_rho(rho_b), w_b, 1e-3, 3000, 2e-3);
    assert_true(ratio < 0.9);
}

/* ---- rejection paths (law_test_support.h) ---- */
static void test_invalid_config(void **state)
{
    (void)state;
    aocs_crp_linear_t law;
    check_gain_pair_rejections(crp_init_gains, crp_step, &law, 19.0, 13.0);
    aocs_crp_linear_config_t cfg = {AOCS_R(19.0), AOCS_R(13.0)};
    assert_int_equal(aocs_crp_linear_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_crp_linear_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_crp_linear_t law;
    check_step_before_init(crp_step, &law, sizeof law);
    law = make_law(19.0, 13.0);
    aocs_att_input_t good = law_test_input();
    check_step_rejections(crp_step, &law, &good);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_known_states),
        cmocka_unit_test(test_singular),
        cmocka_unit_test(test_sign_convention),
        cmocka_unit_test(test_q_and_minus_q_same_torque),
        cmocka_unit_test(test_lyapunov_rtc),
        cmocka_unit_test(test_invalid_config),
        cmocka_unit_test(test_step_rejections),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
