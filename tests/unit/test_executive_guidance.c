/*
 * Executive guidance: a target frame D rotating at a constant rate w (in D).
 * Proves, against an independent double-precision model (law_test_support.h,
 * no firmware math):
 *  - qd(t) = dq(w (t - t0)) (x) qd0 at several sensor times, for the geo_hinf
 *    rate (0, -w0, 0) over a whole orbit and for a general rate, including a
 *    time so short that the small-angle branch is taken;
 *  - that path solves qd' = 0.5 Xi(qd) w (central differences of the
 *    executive's own outputs), i.e. w is in D as in the plant's Plant.target;
 *  - wd_B = A(qe) w and wd_dot_B = wd_B x w_BN_B reach the output, wd_dot_B is
 *    the time derivative of wd_B (central differences along a motion), and both reach the
 *    laws: quat_pd matches its formula with those rates, smc matches a direct
 *    call with them, hinf gives zero when the body follows the rotating frame;
 *  - a zero rate reproduces the fixed-target behaviour bit for bit;
 *  - select with a target restarts t0 at the last sample (without a target
 *    the phase is kept; before any sample t0 is kept), target_t0_ns and
 *    aocs_exec_set_target_epoch shift the phase;
 *  - a rotating target with a fixed wd/wd_dot, or a non-finite rate, is
 *    rejected (init and select), and an invalid sample still reports qd(t)
 *    with zero rates;
 *  - a law output that overflows from finite inputs (AOCS_ERR_OUTPUT_NOT_FINITE)
 *    is a law error: SAFE, finite saturated command; the new status names.
 */
#include "law_test_support.h"

#include "aocs/executive.h"

#define W0_GEO 7.292115e-5 /* rad/s, SPEC 2.6 */
#define NS_PER_S 1000000000ull

#if defined(AOCS_REAL_IS_FLOAT)
/* qd from float time and rate: ~1e-7 per component after a handful of operations */
#define TOL_QD 2.0e-6
#define TOL_FD 1.0e-4
#else
#define TOL_QD 1.0e-12
#define TOL_FD 2.0e-6
#endif

static const aocs_vec3_t LIMIT_AXIS = {{AOCS_R(100.0), AOCS_R(100.0), AOCS_R(100.0)}};

static aocs_exec_config_t base_config(aocs_law_id_t law, const double w_D[3], dq_t qd0)
{
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    cfg.law = law;
    cfg.u_max_axis = LIMIT_AXIS;
    cfg.target.qd_DN = dq_to_real(qd0);
    cfg.target_rotation_rate_D = dv_to_real(w_D);
    cfg.laws.quat_pd.kp = AOCS_R(4.0);
    cfg.laws.quat_pd.kd = AOCS_R(8.0);
    cfg.laws.crp_linear.k1 = AOCS_R(19.0);
    cfg.laws.crp_linear.k2 = AOCS_R(13.0);
    cfg.laws.smc.inertia = aocs_mat3_diag(aocs_vec3_make(AOCS_R(10.0), AOCS_R(12.0), AOCS_R(15.0)));
    cfg.laws.smc.inertia.m[0][1] = AOCS_R(0.5);
    cfg.laws.smc.inertia.m[1][0] = AOCS_R(0.5);
    cfg.laws.smc.lambda = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.laws.smc.g = aocs_vec3_make(AOCS_R(0.05), AOCS_R(0.05), AOCS_R(0.05));
    cfg.laws.smc.eps = aocs_vec3_make(AOCS_R(0.02), AOCS_R(0.02), AOCS_R(0.02));
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            cfg.laws.hinf.k[i][j] = AOCS_R(0.0);
        }
        cfg.laws.hinf.k[i][i] = AOCS_R(-50.0);
        cfg.laws.hinf.k[i][3 + i] = AOCS_R(-900.0);
    }
    return cfg;
}

/* ---- independent reference (double) ---- */

/* qd(t) = dq(w dt) (x) qd0, dq the rotation by |w| dt about w/|w| */
static dq_t ref_qd(const double w[3], double dt, dq_t qd0)
{
    const double n = sqrt(dv_dot(w, w));
    return dq_mul(dq_axis_angle(w[0], w[1], w[2], n * dt), qd0);
}

/* A(q) = (q4^2 - |qv|^2) I + 2 qv qv^T - 2 q4 qv^x (SPEC 1) applied to v */
static void ref_rotate(dq_t q, const double v[3], double out[3])
{
    const double qv[3] = {q.q[0], q.q[1], q.q[2]};
    const double s = q.q[3] * q.q[3] - dv_dot(qv, qv);
    const double d = 2.0 * dv_dot(qv, v);
    double qxv[3];
    dv_cross(qv, v, qxv);
    for (int i = 0; i < 3; ++i) {
        out[i] = s * v[i] + d * qv[i] - 2.0 * q.q[3] * qxv[i];
    }
}

/* wd_B = A(q (x) qd^-1) w, wd_dot_B = wd_B x w_B */
static void ref_rates(dq_t q, dq_t qd, const double w_D[3], const double w_B[3], double wd[3], double wd_dot[3])
{
    const dq_t qe = dq_normalize(dq_mul(q, dq_inv(qd)));
    ref_rotate(qe, w_D, wd);
    dv_cross(wd, w_B, wd_dot);
}

/* the reference inputs of a law at time t: the values the firmware saw, qd(t), wd_B, wd_dot_B */
typedef struct {
    dq_t q;
    double w[3];
    dq_t qd;
    double wd[3];
    double wd_dot[3];
} ref_input_t;

static ref_input_t ref_input(const double w_D[3], dq_t qd0, double t, dq_t q, const double w_B[3])
{
    ref_input_t r;
    r.q = dq_from_real(dq_to_real(q));
    dv_from_real(dv_to_real(w_B), r.w);
    r.qd = ref_qd(w_D, t, qd0);
    ref_rates(r.q, r.qd, w_D, r.w, r.wd, r.wd_dot);
    return r;
}

static aocs_exec_input_t sample(uint32_t tick, uint64_t t_ns, aocs_quat_t q, aocs_vec3_t w)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = t_ns;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = q;
    in.w_BN_B = w;
    return in;
}

static void assert_quat_close_d(aocs_quat_t got, dq_t want, double tol)
{
    for (int i = 0; i < 4; ++i) {
        assert_close(got.q[i], want.q[i], tol);
    }
}

static void assert_vec_close_d(aocs_vec3_t got, const double want[3], double tol)
{
    for (int i = 0; i < 3; ++i) {
        assert_close(got.v[i], want[i], tol);
    }
}

/* one step at t, body at q, w; checks qd(t), wd_B and wd_dot_B of the output */
static void check_step(aocs_exec_t *exec, uint32_t tick, double t_s, const double w_D[3], dq_t qd0, double t0_s,
                       dq_t q, const double w_B[3], aocs_exec_output_t *out)
{
    const uint64_t t_ns = (uint64_t)llround(t_s * 1e9);
    aocs_exec_input_t in = sample(tick, t_ns, dq_to_real(q), dv_to_real(w_B));
    assert_int_equal(aocs_exec_step(exec, &in, out), AOCS_OK);
    assert_int_equal(out->input_status, AOCS_OK);
    dq_t qd = ref_qd(w_D, t_s - t0_s, qd0);
    assert_quat_close_d(out->target.qd_DN, qd, TOL_QD);
    /* the rates from the values the firmware saw */
    double wd[3];
    double wd_dot[3];
    double w_seen[3];
    dv_from_real(in.w_BN_B, w_seen);
    ref_rates(dq_from_real(in.q_BN), dq_from_real(out->target.qd_DN), w_D, w_seen, wd, wd_dot);
    assert_vec_close_d(out->target.wd_B, wd, TOL_QD);
    assert_vec_close_d(out->target.wd_dot_B, wd_dot, TOL_QD);
}

static void test_geo_rate_closed_form(void **state)
{
    (void)state;
    const double w_D[3] = {0.0, -W0_GEO, 0.0};
    const dq_t qd0 = dq_euler321_deg(10.0, -20.0, 30.0); /* does not commute with a pitch rotation */
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    /* 0.1 s, the 1200 s of geo_hinf, a quarter orbit and one full orbit (2 pi / w0) */
    const double times[5] = {0.1, 600.0, 1200.0, 0.25 * 2.0 * PI / W0_GEO, 2.0 * PI / W0_GEO};
    const double w_B[3] = {1e-5, -6.3e-5, -1e-5};
    for (uint32_t k = 0; k < 5u; ++k) {
        /* the body a little off the rotating target; each time a first sample (fresh init): the
         * times jump by far more than one sample may move the frame reference (executive.h) */
        dq_t q = dq_mul(dq_euler321_deg(0.5, -0.5, 0.5), ref_qd(w_D, times[k], qd0));
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
        check_step(&exec, k + 1u, times[k], w_D, qd0, 0.0, q, w_B, &out);
    }
    /* after one orbit the target is back at qd0 (up to the sign of the quaternion: 360 deg = -q) */
    for (int i = 0; i < 4; ++i) {
        assert_close(out.target.qd_DN.q[i], -qd0.q[i], 1e3 * TOL_QD);
    }
}

static void test_general_rate_closed_form(void **state)
{
    (void)state;
    const double w_D[3] = {0.3, -0.2, 0.5};
    const dq_t qd0 = dq_axis_angle(1.0, 2.0, -0.5, 2.5);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    /* 1e-5 s: |theta| = 6e-6 rad, the small-angle branch; then beyond 2 pi */
    const double times[5] = {1e-5, 0.1, 3.7, 10.0, 123.456};
    const double w_B[3] = {0.2, 0.1, -0.3};
    for (uint32_t k = 0; k < 5u; ++k) {
        dq_t q = dq_axis_angle(0.3, -1.0, 0.2, 0.7 + 0.1 * (double)k);
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK); /* irregular times: each a first sample */
        check_step(&exec, k + 1u, times[k], w_D, qd0, 0.0, q, w_B, &out);
    }
}

/*
 * Relative accuracy of the vector part of dq near the small-angle switch
 * (|theta| = 1e-4 rad) and far below it: the series branch must be as
 * accurate as sin(|theta|/2)/|theta| itself (qd0 = identity, so qd = dq).
 */
static void test_small_angle_relative_accuracy(void **state)
{
    (void)state;
    const double w_D[3] = {2.0, -1.0, 2.0}; /* |w| = 3 rad/s */
    const dq_t ident = {{0.0, 0.0, 0.0, 1.0}};
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, ident);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    cfg.period_s = AOCS_R(1.0e-6); /* ticks 0, 33, 34 of 1 us: the times advance by whole periods */
    cfg.missing_max_periods = 64u;  /* the 32 ticks skipped on the way are no fault here */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    /* |theta| = 3 t: 3e-9, 9.9e-5 (series), 1.02e-4 (sin) rad; t in whole ns */
    const uint64_t t_ns[3] = {1u, 33000u, 34000u};
    const uint32_t ticks[3] = {0u, 33u, 34u};
#if defined(AOCS_REAL_IS_FLOAT)
    const double rel_tol = 1.0e-6;
#else
    const double rel_tol = 1.0e-14;
#endif
    for (uint32_t k = 0; k < 3u; ++k) {
        aocs_exec_input_t in = sample(ticks[k], t_ns[k], aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK);
        dq_t ref = ref_qd(w_D, (double)t_ns[k] * 1e-9, ident);
        for (int i = 0; i < 3; ++i) {
            double got = (double)out.target.qd_DN.q[i];
            if (!(fabs(got - ref.q[i]) <= rel_tol * fabs(ref.q[i]))) {
                print_error("t = %llu ns, q[%d] = %.17g, expected %.17g\n", (unsigned long long)t_ns[k], i, got,
                            ref.q[i]);
                fail();
            }
        }
    }
}

/* qd(t) from the executive solves qd' = 0.5 Xi(qd) w with w in D (SPEC 1 kinematics) */
static void test_path_solves_target_kinematics(void **state)
{
    (void)state;
    const double w_D[3] = {0.3, -0.2, 0.5};
    const dq_t qd0 = dq_euler321_deg(40.0, 25.0, -60.0);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out[3];
    const double h = 0.01;
    cfg.period_s = (real_t)h; /* the samples are one period apart */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    const double t_mid = 2.0;
    for (uint32_t k = 0; k < 3u; ++k) {
        double t = t_mid + h * ((double)k - 1.0);
        aocs_exec_input_t in =
            sample(k + 1u, (uint64_t)llround(t * 1e9), aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out[k]), AOCS_OK);
        assert_int_equal(out[k].input_status, AOCS_OK);
    }
    dq_t qd = dq_from_real(out[1].target.qd_DN);
    /* Xi(qd) w = [q4 w + qv x w; -qv . w] */
    const double qv[3] = {qd.q[0], qd.q[1], qd.q[2]};
    double qxw[3];
    dv_cross(qv, w_D, qxw);
    double expect[4];
    for (int i = 0; i < 3; ++i) {
        expect[i] = 0.5 * (qd.q[3] * w_D[i] + qxw[i]);
    }
    expect[3] = -0.5 * dv_dot(qv, w_D);
    for (int i = 0; i < 4; ++i) {
        double num = ((double)out[2].target.qd_DN.q[i] - (double)out[0].target.qd_DN.q[i]) / (2.0 * h);
        assert_close(num, expect[i], TOL_FD);
    }
    /* the other ordering, qd0 (x) dq (w in N), would differ here by far more than the tolerance */
    dq_t wrong = dq_mul(qd0, dq_axis_angle(w_D[0], w_D[1], w_D[2], sqrt(dv_dot(w_D, w_D)) * t_mid));
    double diff = 0.0;
    for (int i = 0; i < 4; ++i) {
        diff += fabs(wrong.q[i] - qd.q[i]);
    }
    assert_true(diff > 0.1);
}

/*
 * wd_dot_B is the time derivative of wd_B along a motion: the body turns at
 * a constant w_B (q(t) = dq(w_B t) (x) q0, body kinematics), the target at w;
 * the central difference of the executive's wd_B equals its wd_dot_B. This
 * checks the derivation in src/guidance/rotating.c, not just the formula.
 */
static void test_wd_dot_is_derivative_of_wd(void **state)
{
    (void)state;
    const double w_D[3] = {0.3, -0.2, 0.5};
    const double w_B[3] = {-0.4, 0.25, 0.1};
    const dq_t qd0 = dq_euler321_deg(40.0, 25.0, -60.0);
    const dq_t q0 = dq_euler321_deg(-10.0, 70.0, 20.0);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out[3];
    const double h = 1e-3;
    cfg.period_s = (real_t)h; /* the samples are one period apart */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    const double t_mid = 1.5;
    for (uint32_t k = 0; k < 3u; ++k) {
        double t = t_mid + h * ((double)k - 1.0);
        dq_t q = dq_mul(dq_axis_angle(w_B[0], w_B[1], w_B[2], sqrt(dv_dot(w_B, w_B)) * t), q0);
        aocs_exec_input_t in = sample(k + 1u, (uint64_t)llround(t * 1e9), dq_to_real(q), dv_to_real(w_B));
        assert_int_equal(aocs_exec_step(&exec, &in, &out[k]), AOCS_OK);
    }
    double num[3];
    for (int i = 0; i < 3; ++i) {
        num[i] = ((double)out[2].target.wd_B.v[i] - (double)out[0].target.wd_B.v[i]) / (2.0 * h);
    }
    assert_vec_close_d(out[1].target.wd_dot_B, num, TOL_FD);
    /* not a trivially small quantity: |wd x w_B| ~ 0.2 rad/s^2 */
    assert_true(aocs_vec3_norm(out[1].target.wd_dot_B) > AOCS_R(0.05));
}

/* quat_pd formula (SPEC 2.2) with the guidance target and rates */
static void test_laws_see_guidance_rates(void **state)
{
    (void)state;
    const double w_D[3] = {0.01, -0.02, 0.015};
    const dq_t qd0 = dq_euler321_deg(30.0, -20.0, 1.0);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    cfg.period_s = AOCS_R(7.0); /* samples 7 s apart: one period each (no law here uses dt) */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    const double w_B[3] = {0.004, -0.003, 0.02};
    for (uint32_t k = 0; k < 4u; ++k) {
        double t = 5.0 + 7.0 * (double)k;
        dq_t q = dq_mul(dq_axis_angle(1.0, -1.0, 0.5, 0.2), ref_qd(w_D, t, qd0));
        check_step(&exec, k + 1u, t, w_D, qd0, 0.0, q, w_B, &out);
        /* u = -kp sign(qe4) qe_vec - kd (w - wd_B), everything from the reference */
        const ref_input_t r = ref_input(w_D, qd0, t, q, w_B);
        dq_t qe = dq_mul(r.q, dq_inv(r.qd));
        double sgn = (qe.q[3] < 0.0) ? -1.0 : 1.0;
        double u[3];
        double d = 0.0;
        for (int i = 0; i < 3; ++i) {
            u[i] = -4.0 * sgn * qe.q[i] - 8.0 * (r.w[i] - r.wd[i]);
            /* the rate term really changed the torque: kd |wd_B| ~ 0.2 N m */
            d += fabs((double)out.u_unsat.v[i] - (u[i] - 8.0 * r.wd[i]));
        }
        assert_vec3_close_scaled(out.u_unsat, u, TOL_QD, 4.0);
        assert_true(d > 1e-2);
    }

    /* smc: the executive's torque equals a direct call with the reference qd(t), wd_B, wd_dot_B */
    cfg = base_config(AOCS_LAW_SMC, w_D, qd0);
    cfg.period_s = AOCS_R(11.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_smc_t smc;
    assert_int_equal(aocs_smc_init(&smc, &cfg.laws.smc), AOCS_OK);
    for (uint32_t k = 0; k < 4u; ++k) {
        double t = 3.0 + 11.0 * (double)k;
        dq_t q = dq_mul(dq_axis_angle(0.2, 1.0, -0.4, 0.01), ref_qd(w_D, t, qd0));
        check_step(&exec, k + 1u, t, w_D, qd0, 0.0, q, w_B, &out);
        const ref_input_t r = ref_input(w_D, qd0, t, q, w_B);
        aocs_att_input_t att = make_input(r.q, r.w, r.qd, r.wd, r.wd_dot, 0.1);
        aocs_vec3_t u_direct;
        assert_int_equal(aocs_smc_step(&smc, &att, &u_direct), AOCS_OK);
        double ud[3];
        dv_from_real(u_direct, ud);
        /* J ~ 15, gains ~ 1: torque terms of order 1 */
        assert_vec3_close_scaled(out.u_unsat, ud, 10.0 * TOL_QD, 15.0);
        /* wd_dot matters here: the direct call without it differs */
        att.wd_dot_B = aocs_vec3_zero();
        assert_int_equal(aocs_smc_step(&smc, &att, &u_direct), AOCS_OK);
        double d = 0.0;
        for (int i = 0; i < 3; ++i) {
            d += fabs((double)u_direct.v[i] - (double)out.u_unsat.v[i]);
        }
        assert_true(d > 1e-4);
    }

    /* hinf on the geo rate: the body riding the rotating target exactly gives u = 0 */
    const double w_geo[3] = {0.0, -W0_GEO, 0.0};
    cfg = base_config(AOCS_LAW_HINF, w_geo, qd0);
    cfg.period_s = AOCS_R(400.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    for (uint32_t k = 0; k < 3u; ++k) {
        double t = 400.0 * (double)(k + 1u);
        dq_t qd = ref_qd(w_geo, t, qd0);
        double w_body[3];
        ref_rotate(dq_mul(qd, dq_inv(qd)), w_geo, w_body); /* A(identity) w = w */
        aocs_exec_input_t in = sample(k + 1u, (uint64_t)llround(t * 1e9), dq_to_real(qd), dv_to_real(w_body));
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        /* rounding only: angles ~1e-16 (float 1e-7) times 50, rates ~1e-20 times 900 */
        assert_true(aocs_vec3_norm_inf(out.u_unsat) <= AOCS_R(50.0) * AOCS_R(100.0) * AOCS_REAL_EPS);
    }
    /* the same states with a fixed target: a clearly non-zero torque (pitch error w0 t) */
    double zero_w[3] = {0.0, 0.0, 0.0};
    cfg = base_config(AOCS_LAW_HINF, zero_w, qd0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    dq_t qd1200 = ref_qd(w_geo, 1200.0, qd0);
    aocs_exec_input_t in = sample(1u, 1200u * NS_PER_S, dq_to_real(qd1200), aocs_vec3_make(AOCS_R(0.0), (real_t)-W0_GEO, AOCS_R(0.0)));
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_true(fabs((double)out.u_unsat.v[1]) > 50.0 * 0.5 * W0_GEO * 1200.0);
}

/* zero rate: the law sees exactly the configured target, bit for bit */
static void test_zero_rate_bit_for_bit(void **state)
{
    (void)state;
    const double zero_w[3] = {0.0, 0.0, 0.0};
    const dq_t qd0 = dq_euler321_deg(30.0, -20.0, 1.0);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_SMC, zero_w, qd0);
    cfg.target.wd_B = aocs_vec3_make(AOCS_R(0.001), AOCS_R(-0.002), AOCS_R(0.0005));
    cfg.target.wd_dot_B = aocs_vec3_make(AOCS_R(1e-5), AOCS_R(0.0), AOCS_R(-2e-5));
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_smc_t smc;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_smc_init(&smc, &cfg.laws.smc), AOCS_OK);
    test_rng_t rng = {0x5eedu};
    for (uint32_t k = 0; k < 50u; ++k) {
        aocs_exec_input_t in = sample(k + 1u, (uint64_t)(k + 1u) * 100000000ull, test_random_quat(&rng),
                                      test_random_vec3(&rng, 0.05));
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        assert_memory_equal(&out.target, &cfg.target, sizeof(cfg.target));
        aocs_att_input_t att;
        att.q_BN = in.q_BN;
        att.w_BN_B = in.w_BN_B;
        att.qd_DN = cfg.target.qd_DN;
        att.wd_B = cfg.target.wd_B;
        att.wd_dot_B = cfg.target.wd_dot_B;
        att.dt_s = cfg.period_s;
        att.u_max_axis = aocs_vec3_zero();
        att.u_max_norm = AOCS_R(0.0);
        aocs_vec3_t u;
        assert_int_equal(aocs_smc_step(&smc, &att, &u), AOCS_OK);
        assert_memory_equal(&out.u_unsat, &u, sizeof(u));
    }
}

static void test_select_restarts_t0(void **state)
{
    (void)state;
    const double w_D[3] = {0.02, 0.05, -0.03};
    const dq_t qd0 = dq_euler321_deg(10.0, 20.0, 30.0);
    const dq_t qd1 = dq_euler321_deg(-50.0, 5.0, 80.0);
    const double w_B[3] = {0.0, 0.0, 0.0};
    const dq_t q = dq_axis_angle(0.0, 0.0, 1.0, 0.3);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_target_t tgt;
    memset(&tgt, 0, sizeof(tgt));
    tgt.qd_DN = dq_to_real(qd1);
    cfg.period_s = AOCS_R(0.5); /* tick = t / 0.5 s below: the times advance by whole periods */

    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    check_step(&exec, 2u, 1.0, w_D, qd0, 0.0, q, w_B, &out);
    check_step(&exec, 4u, 2.0, w_D, qd0, 0.0, q, w_B, &out);
    /* a new target at the last sample (t = 2 s) is qd0 from then on */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &tgt), AOCS_OK);
    check_step(&exec, 6u, 3.0, w_D, qd1, 2.0, q, w_B, &out);
    /* a law change without a target keeps the phase */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_CRP_LINEAR, NULL), AOCS_OK);
    check_step(&exec, 9u, 4.5, w_D, qd1, 2.0, q, w_B, &out);

    /* before any sample t0 stays the configured one */
    cfg.target_t0_ns = 500000000u; /* 0.5 s */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &tgt), AOCS_OK);
    check_step(&exec, 1u, 1.5, w_D, qd1, 0.5, q, w_B, &out);

    /* sensor time before t0: the target rotates backwards */
    cfg.target_t0_ns = 10u * NS_PER_S;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    check_step(&exec, 1u, 4.0, w_D, qd0, 10.0, q, w_B, &out);

    /* the epoch set at run time (real-time adapters) */
    assert_int_equal(aocs_exec_set_target_epoch(&exec, 3u * NS_PER_S), AOCS_OK);
    check_step(&exec, 3u, 5.0, w_D, qd0, 3.0, q, w_B, &out); /* two periods on: one missing, tolerated */
    assert_int_equal(aocs_exec_set_target_epoch(NULL, 0u), AOCS_ERR_NULL_ARG);
    aocs_exec_t fresh;
    memset(&fresh, 0, sizeof(fresh));
    assert_int_equal(aocs_exec_set_target_epoch(&fresh, 0u), AOCS_ERR_NOT_INITIALISED);
}

static void test_rotating_target_validation(void **state)
{
    (void)state;
    const double w_D[3] = {0.0, -W0_GEO, 0.0};
    const dq_t qd0 = dq_euler321_deg(1.0, 2.0, 3.0);
    aocs_exec_t exec;
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_config_t bad = cfg;
    bad.target.wd_B.v[2] = AOCS_R(1e-6); /* a fixed rate as well: ambiguous */
    assert_int_equal(aocs_exec_init(&exec, &bad), AOCS_ERR_TARGET_INVALID);
    bad = cfg;
    bad.target.wd_dot_B.v[0] = AOCS_R(-1e-9);
    assert_int_equal(aocs_exec_init(&exec, &bad), AOCS_ERR_TARGET_INVALID);
    bad = cfg;
    bad.target_rotation_rate_D.v[1] = (real_t)NAN;
    assert_int_equal(aocs_exec_init(&exec, &bad), AOCS_ERR_TARGET_INVALID);
    bad.target_rotation_rate_D.v[1] = (real_t)INFINITY;
    assert_int_equal(aocs_exec_init(&exec, &bad), AOCS_ERR_TARGET_INVALID);

    /* select: the same rule, nothing changed on rejection */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_exec_target_t tgt;
    memset(&tgt, 0, sizeof(tgt));
    tgt.qd_DN = aocs_quat_identity();
    tgt.wd_B.v[0] = AOCS_R(0.01);
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &tgt), AOCS_ERR_TARGET_INVALID);
    assert_int_equal(exec.counters.select_rejected, 1u);
    assert_memory_equal(&exec.guidance.target, &cfg.target, sizeof(cfg.target));
    tgt.wd_B.v[0] = AOCS_R(0.0);
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &tgt), AOCS_OK);

    /* a fixed target accepts the same wd */
    const double zero_w[3] = {0.0, 0.0, 0.0};
    cfg = base_config(AOCS_LAW_QUAT_PD, zero_w, qd0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    tgt.wd_B.v[0] = AOCS_R(0.01);
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &tgt), AOCS_OK);
}

/* an invalid sample still reports qd(t) (time only); the rates need q and w: zero */
static void test_invalid_sample_keeps_qd(void **state)
{
    (void)state;
    const double w_D[3] = {0.1, 0.0, 0.2};
    const dq_t qd0 = dq_euler321_deg(5.0, 6.0, 7.0);
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, w_D, qd0);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_exec_input_t in = sample(1u, 2u * NS_PER_S, aocs_quat_identity(),
                                  aocs_vec3_make((real_t)NAN, AOCS_R(0.0), AOCS_R(0.0)));
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_quat_close_d(out.target.qd_DN, ref_qd(w_D, 2.0, qd0), TOL_QD);
    assert_true(aocs_vec3_norm_inf(out.target.wd_B) <= AOCS_R(0.0));
    assert_true(aocs_vec3_norm_inf(out.target.wd_dot_B) <= AOCS_R(0.0));
    /* no sample at all: nothing evaluated */
    assert_int_equal(aocs_exec_step_no_input(&exec, &out), AOCS_OK);
    assert_true(aocs_quat_norm(out.target.qd_DN) <= AOCS_R(0.0));
}

/* finite inputs whose torque overflows: a law error with its own status, SAFE, finite command */
static void test_output_overflow_is_law_error(void **state)
{
    (void)state;
    const double zero_w[3] = {0.0, 0.0, 0.0};
    aocs_exec_config_t cfg = base_config(AOCS_LAW_QUAT_PD, zero_w, dq_euler321_deg(0.0, 0.0, 0.0));
    aocs_exec_t exec;
    aocs_exec_output_t out;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_exec_input_t in = sample(1u, NS_PER_S, aocs_quat_identity(),
                                  aocs_vec3_make(AOCS_REAL_MAX / AOCS_R(2.0), AOCS_R(0.0), AOCS_R(0.0)));
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.law_status, AOCS_ERR_OUTPUT_NOT_FINITE);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.counters.law_error, 1u);
    assert_true(aocs_vec3_is_finite(out.u_cmd) != 0);
    assert_true(aocs_vec3_norm_inf(out.u_cmd) <= LIMIT_AXIS.v[0]);
    /* the status codes appended to types.h have their names; past the end: unknown */
    assert_string_equal(aocs_status_name(AOCS_ERR_OUTPUT_NOT_FINITE), "AOCS_ERR_OUTPUT_NOT_FINITE");
    assert_string_equal(aocs_status_name(AOCS_ERR_GAIN_TABLE_UNKNOWN), "AOCS_ERR_GAIN_TABLE_UNKNOWN");
    assert_string_equal(aocs_status_name(AOCS_ERR_GAIN_TABLE_WRONG_LAW), "AOCS_ERR_GAIN_TABLE_WRONG_LAW");
    assert_string_equal(aocs_status_name(AOCS_ERR_INPUT_INVALID), "AOCS_ERR_INPUT_INVALID");
    assert_string_equal(aocs_status_name(AOCS_STATUS_COUNT), "AOCS_STATUS_UNKNOWN");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_geo_rate_closed_form),
        cmocka_unit_test(test_general_rate_closed_form),
        cmocka_unit_test(test_small_angle_relative_accuracy),
        cmocka_unit_test(test_path_solves_target_kinematics),
        cmocka_unit_test(test_wd_dot_is_derivative_of_wd),
        cmocka_unit_test(test_laws_see_guidance_rates),
        cmocka_unit_test(test_zero_rate_bit_for_bit),
        cmocka_unit_test(test_select_restarts_t0),
        cmocka_unit_test(test_rotating_target_validation),
        cmocka_unit_test(test_invalid_sample_keeps_qd),
        cmocka_unit_test(test_output_overflow_is_law_error),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
