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
    /* IRASSI large slew geometry with non-zero rates */
    const double w1[3] = {0.01, -0.02, 0.03};
    const double wd1[3] = {0.001, 0.0, -0.002};
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    check_state(4000.0, 8000.0, make_input(dq_euler321_deg(14.0, 14.0, 14.0), w1, qd, wd1, ZERO3, 0.1));

    /* error of 250 deg: qe4 < 0, the law must use sign(qe4) = -1 */
    dq_t q2 = dq_mul(dq_axis_angle(1.0, -2.0, 0.5, 250.0 * 3.14159265358979323846 / 180.0), qd);
    dq_t qe2 = dq_mul(q2, dq_inv(qd));
    assert_true(qe2.q[3] < -0.5);
    const double w2[3] = {-0.1, 0.05, 0.2};
    check_state(4000.0, 8000.0, make_input(q2, w2, qd, ZERO3, ZERO3, 0.1));

    /* exactly 180 deg about x: qe4 = 0, sign(0) = +1, so u = [-kp, 0, -kd w3] */
    dq_t q3 = {{1.0, 0.0, 0.0, 0.0}};
    dq_t id = {{0.0, 0.0, 0.0, 1.0}};
    const double w3[3] = {0.0, 0.0, 0.5};
    aocs_att_input_t in3 = make_input(q3, w3, id, ZERO3, ZERO3, 0.1);
    check_state(4000.0, 8000.0, in3);
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
    aocs_vec3_t u;
    assert_int_equal(aocs_quat_pd_step(&law, &in3, &u), AOCS_OK);
    const double by_hand3[3] = {-4000.0, 0.0, -4000.0};
    assert_vec3_close_scaled(u, by_hand3, TOL_TIGHT, 4000.0);
}

static void test_by_hand(void **state)
{
    (void)state;
    /* 60 deg about x: qe = [0.5 0 0 cos 30]; kp = 2, kd = 3, w = [0.1 0 0]:
       u = [-2 * 0.5 - 3 * 0.1, 0, 0] = [-1.3, 0, 0] */
    aocs_quat_pd_t law = make_law(2.0, 3.0);
    aocs_att_input_t in;
    in.q_BN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.86602540378443865));
    in.qd_DN = aocs_quat_identity();
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0));
    in.wd_B = aocs_vec3_zero();
    in.wd_dot_B = aocs_vec3_zero();
    in.dt_s = AOCS_R(0.1);
    aocs_vec3_t u;
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_OK);
    const double expected[3] = {-1.3, 0.0, 0.0};
    assert_vec3_close_scaled(u, expected, TOL_TIGHT, 1.3);
}

static void test_sign_convention(void **state)
{
    (void)state;
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double angles_deg[3] = {0.1, 10.0, 170.0};
    for (int k = 0; k < 3; ++k) {
        /* body rotated by a positive angle about +x from the target */
        dq_t q = dq_mul(dq_axis_angle(1.0, 0.0, 0.0, angles_deg[k] * 3.14159265358979323846 / 180.0), qd);
        aocs_att_input_t in = make_input(q, ZERO3, qd, ZERO3, ZERO3, 0.1);
        aocs_vec3_t u;
        assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_OK);
        assert_true(u.v[0] < AOCS_R(0.0));
        assert_true(fabs((double)u.v[1]) <= 1e-3 * fabs((double)u.v[0]));
        assert_true(fabs((double)u.v[2]) <= 1e-3 * fabs((double)u.v[0]));
    }
}

static void test_q_and_minus_q_same_torque(void **state)
{
    (void)state;
    aocs_quat_pd_t law = make_law(4000.0, 8000.0);
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
        assert_int_equal(aocs_quat_pd_step(&law, &in, &u_ref), AOCS_OK);
        /* u is odd in the sign of qe4 only through sign(qe4) qe_vec: same torque */
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
            assert_int_equal(aocs_quat_pd_step(&law, &in2, &u2), AOCS_OK);
            assert_vec3_close(u2, u_ref, TOL_TIGHT * 4000.0);
        }
    }
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
    aocs_att_input_t in = make_input(q, w, c->qd, ZERO3, ZERO3, 0.01);
    aocs_vec3_t uv;
    aocs_status_t st = aocs_quat_pd_step(&c->law, &in, &uv);
    dv_from_real(uv, u);
    return st;
}

/*
 * SPEC 2.3 Lyapunov function with |qe4| (anti-unwinding):
 * V = 0.25 w^T J w + 0.5 kp qe_v.qe_v + 0.5 kp (1 - |qe4|)^2 = 0.25 w^T J w + kp (1 - |qe4|).
 * With wd = 0: Vdot = 0.5 w^T u + 0.5 kp sign(qe4) qe_v.w = -0.5 kd |w|^2
 * (the 0.25 on the kinetic term makes the SPEC V consistent with these gains).
 */
static void pd_lyap(void *vctx, dq_t q, const double w[3], double *v, double *vdot)
{
    pd_ctx_t *c = (pd_ctx_t *)vctx;
    dq_t qe = dq_mul(q, dq_inv(c->qd));
    double qv[3] = {qe.q[0], qe.q[1], qe.q[2]};
    double h[3];
    dm_mul_vec(&c->j, w, h);
    double a = 1.0 - fabs(qe.q[3]);
    *v = 0.25 * dv_dot(w, h) + 0.5 * c->kp * dv_dot(qv, qv) + 0.5 * c->kp * a * a;
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
    dq_t q0 = dq_mul(dq_axis_angle(0.3, 1.0, -0.2, 200.0 * 3.14159265358979323846 / 180.0), ctx.qd);
    ratio = check_lyapunov(&plant, pd_torque, pd_lyap, &ctx, q0, w0, 0.01, 1000, 2e-3);
    assert_true(ratio < 0.9);
}

/* ---- rejection paths ---- */
static void test_invalid_config(void **state)
{
    (void)state;
    const double bad_nf[3] = {NAN, INFINITY, -INFINITY};
    const double bad_np[3] = {0.0, -0.0, -1.0};
    for (int which = 0; which < 2; ++which) {
        for (int b = 0; b < 3; ++b) {
            aocs_quat_pd_config_t cfg = {AOCS_R(4000.0), AOCS_R(8000.0)};
            aocs_quat_pd_t law = make_law(1.0, 1.0);
            if (which == 0) {
                cfg.kp = (real_t)bad_nf[b];
            } else {
                cfg.kd = (real_t)bad_nf[b];
            }
            assert_int_equal(aocs_quat_pd_init(&law, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
            /* a failed init leaves the law unusable even after a good one */
            aocs_att_input_t in = make_input(dq_euler321_deg(1, 2, 3), ZERO3, dq_euler321_deg(0, 0, 0), ZERO3,
                                             ZERO3, 0.1);
            aocs_vec3_t u = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
            assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_NOT_INITIALISED);
            assert_vec3_is_zero(u);

            cfg.kp = AOCS_R(4000.0);
            cfg.kd = AOCS_R(8000.0);
            if (which == 0) {
                cfg.kp = (real_t)bad_np[b];
            } else {
                cfg.kd = (real_t)bad_np[b];
            }
            law = make_law(1.0, 1.0);
            assert_int_equal(aocs_quat_pd_init(&law, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
            assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_NOT_INITIALISED);
        }
    }
    aocs_quat_pd_config_t cfg = {AOCS_R(1.0), AOCS_R(1.0)};
    aocs_quat_pd_t law;
    assert_int_equal(aocs_quat_pd_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_quat_pd_init(&law, NULL), AOCS_ERR_NULL_ARG);
}

static void test_step_rejections(void **state)
{
    (void)state;
    dq_t qd = dq_euler321_deg(30.0, -20.0, 1.0);
    const double w[3] = {0.01, 0.02, 0.03};
    aocs_att_input_t good = make_input(dq_euler321_deg(14.0, 14.0, 14.0), w, qd, ZERO3, ZERO3, 0.1);
    aocs_vec3_t u;

    /* before init: zeroed and garbage structs */
    aocs_quat_pd_t law;
    memset(&law, 0, sizeof law);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_quat_pd_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);
    memset(&law, 0xA5, sizeof law);
    assert_int_equal(aocs_quat_pd_step(&law, &good, &u), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_is_zero(u);

    law = make_law(4000.0, 8000.0);
    assert_int_equal(aocs_quat_pd_step(NULL, &good, &u), AOCS_ERR_NULL_ARG);
    u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
    assert_int_equal(aocs_quat_pd_step(&law, NULL, &u), AOCS_ERR_NULL_ARG);
    assert_vec3_is_zero(u);
    assert_int_equal(aocs_quat_pd_step(&law, &good, NULL), AOCS_ERR_NULL_ARG);

    /* NaN / +Inf / -Inf in every field */
    const double bad[3] = {NAN, INFINITY, -INFINITY};
    for (int k = 0; k < N_INPUT_FIELDS; ++k) {
        for (int b = 0; b < 3; ++b) {
            aocs_att_input_t in = good;
            *input_field(&in, k) = (real_t)bad[b];
            u = aocs_vec3_make(AOCS_R(5.0), AOCS_R(5.0), AOCS_R(5.0));
            aocs_status_t expected = (k == N_INPUT_FIELDS - 1) ? AOCS_ERR_DT_INVALID : AOCS_ERR_INPUT_NOT_FINITE;
            assert_int_equal(aocs_quat_pd_step(&law, &in, &u), expected);
            assert_vec3_is_zero(u);
        }
    }
    /* non-unit quaternions */
    aocs_att_input_t in = good;
    in.q_BN.q[3] *= AOCS_R(1.1);
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    in = good;
    in.qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_QUAT_NOT_UNIT);
    assert_vec3_is_zero(u);
    /* dt <= 0 */
    in = good;
    in.dt_s = AOCS_R(0.0);
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    in.dt_s = AOCS_R(-0.1);
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_DT_INVALID);
    assert_vec3_is_zero(u);
    /* finite inputs whose torque overflows: error, never Inf */
    in = good;
    in.w_BN_B = aocs_vec3_make(AOCS_REAL_MAX / AOCS_R(2.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_quat_pd_step(&law, &in, &u), AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_vec3_is_zero(u);
    /* the law still works after rejections (no sticky state) */
    assert_int_equal(aocs_quat_pd_step(&law, &good, &u), AOCS_OK);
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
