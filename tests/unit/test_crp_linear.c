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
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double angles_deg[3] = {0.1, 10.0, 170.0};
    for (int k = 0; k < 3; ++k) {
        dq_t q = dq_mul(dq_axis_angle(1.0, 0.0, 0.0, angles_deg[k] * PI / 180.0), qd);
        aocs_att_input_t in = make_input(q, ZERO3, qd, ZERO3, ZERO3, 0.01);
        aocs_vec3_t u;
        assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_OK);
        assert_true(u.v[0] < AOCS_R(0.0));
        assert_true(fabs((double)u.v[1]) <= 1e-3 * fabs((double)u.v[0]));
        assert_true(fabs((double)u.v[2]) <= 1e-3 * fabs((double)u.v[0]));
    }
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    aocs_crp_linear_t law = make_law(19.0, 13.0);
    test_rng_t rng = {0x9E3779B97F4A7C15ULL};
    int tested = 0;
    for (int k = 0; k < 200; ++k) {
        aocs_att_input_t in;
        in.q_BN = test_random_quat(&rng);
        in.qd_DN = test_random_quat(&rng);
        in.w_BN_B = test_random_vec3(&rng, 1.0);
        in.wd_B = test_random_vec3(&rng, 0.1);
        in.wd_dot_B = aocs_vec3_zero();
        in.dt_s = AOCS_R(0.01);
        /* keep away from 180 deg where rho is ill-conditioned in float */
        if (fabs(dq_mul(dq_from_real(in.q_BN), dq_inv(dq_from_real(in.qd_DN))).q[3]) < 0.05) {
            continue;
        }
        ++tested;
        aocs_vec3_t u_ref;
        assert_int_equal(aocs_crp_linear_step(&law, &in, &u_ref), AOCS_OK);
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
            assert_int_equal(aocs_crp_linear_step(&law, &in2, &u2), AOCS_OK);
            assert_vec3_close(u2, u_ref, TOL_TIGHT * 300.0);
        }
    }
    assert_true(tested > 150);
}

/* ---- Lyapunov ---- */
typedef struct {
    aocs_crp_linear_t law;
    double k1;
    double k2;
} crp_ctx_t;

static aocs_status_t crp_torque(void *vctx, dq_t q, const double w[3], double u[3])
{
    crp_ctx_t *c = (crp_ctx_t *)vctx;
    dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    aocs_att_input_t in = make_input(q, w, id, ZERO3, ZERO3, 0.01);
    aocs_vec3_t uv;
    aocs_status_t st = aocs_crp_linear_step(&c->law, &in, &uv);
    dv_from_real(uv, u);
    return st;
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

/* ---- rejection paths ---- */
static aocs_att_input_t some_input(void)
{
    const double w[3] = {0.01, 0.02, 0.03};
    return make_input(dq_euler321_deg(14.0, 14.0, 14.0), w, dq_euler321_deg(30.0, -20.0, 1.0), ZERO3, ZERO3, 0.1);
}

static void expect_init_fails(aocs_crp_linear_config_t cfg, aocs_status_t expected)
{
    aocs_crp_linear_t law = make_law(1.0, 1.0);
    aocs_att_input_t in = some_input();
    aocs_vec3_t u = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    assert_int_equal(aocs_crp_linear_init(&law, &cfg), expected);
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);
}

static void test_invalid_config(void **state)
{
    (void)state;
    const double bad_nf[3] = {NAN, INFINITY, -INFINITY};
    const double bad_np[3] = {0.0, -0.0, -1.0};
    for (int which = 0; which < 2; ++which) {
        for (int b = 0; b < 3; ++b) {
            aocs_crp_linear_config_t cfg = {AOCS_R(19.0), AOCS_R(13.0)};
            if (which == 0) {
                cfg.k1 = (real_t)bad_nf[b];
            } else {
                cfg.k2 = (real_t)bad_nf[b];
            }
            expect_init_fails(cfg, AOCS_ERR_PARAM_NOT_FINITE);
            cfg.k1 = AOCS_R(19.0);
            cfg.k2 = AOCS_R(13.0);
            if (which == 0) {
                cfg.k1 = (real_t)bad_np[b];
            } else {
                cfg.k2 = (real_t)bad_np[b];
            }
            expect_init_fails(cfg, AOCS_ERR_GAIN_NOT_POSITIVE);
        }
    }
    aocs_crp_linear_config_t cfg = {AOCS_R(19.0), AOCS_R(13.0)};
    aocs_crp_linear_t law;
    assert_int_equal(aocs_crp_linear_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_crp_linear_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    aocs_att_input_t good = some_input();
    aocs_vec3_t u;

    aocs_crp_linear_t law;
    memset(&law, 0, sizeof law);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_crp_linear_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);
    memset(&law, 0xA5, sizeof law);
    assert_int_equal(aocs_crp_linear_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);

    law = make_law(19.0, 13.0);
    assert_int_equal(aocs_crp_linear_step(NULL, &good, &u), AOCS_ERR_NULL_ARG);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_crp_linear_step(&law, NULL, &u), AOCS_ERR_NULL_ARG);
    assert_vec3_is_zero(u);
    assert_int_equal(aocs_crp_linear_step(&law, &good, NULL), AOCS_ERR_NULL_ARG);

    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < N_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            aocs_att_input_t in = good;
            *input_field(&in, k) = (real_t)bad[b];
            u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
            aocs_status_t expected = (k == N_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE;
            assert_int_equal(aocs_crp_linear_step(&law, &in, &u), expected);
            assert_vec3_is_zero(u);
        }
    }
    aocs_att_input_t in = good;
    in.q_BN.q[3] *= AOCS_R(1.1);
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    in = good;
    in.qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    in = good;
    in.dt_s = AOCS_R(0.0);
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(-0.1);
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    assert_vec3_is_zero(u);
    in = good;
    in.w_BN_B = aocs_vec3_make(AOCS_REAL_MAX / AOCS_R(2.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_crp_linear_step(&law, &in, &u), AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_vec3_is_zero(u);
    assert_int_equal(aocs_crp_linear_step(&law, &good, &u), AOCS_OK);
    assert_true(aocs_vec3_is_finite(u) != 0);
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
