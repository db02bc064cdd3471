/*
 * Guidance stage alone (firmware/src/guidance/guidance.c, rotating.c,
 * slew_mode.c; aocs/guidance/guidance.h), against independent double
 * models (law_test_support.h), without the executive:
 *  - the table: every row of guidance_modes.def has a distinct name; the
 *    configuration resolves to STEP, ROTATING or SLEW; OWN_RATES, PLANNED,
 *    FEEDFORWARD and BUDGET_NS as documented;
 *  - the checks: guidance.mode out of range, a slew of a moving target, a
 *    bad slew configuration;
 *  - STEP gives the commanded target bit for bit;
 *  - ROTATING: qd(t) = dq(w (t - t0)) (x) qd0 and wd_B = A(qe) w,
 *    wd_dot_B = wd_B x w; zero rates on an unusable estimate; a command
 *    moves t0 to the last sample;
 *  - SLEW: planned at the first usable estimate with a law selected, from
 *    that attitude (qd(0) = q0), ending at the target; the feedforward
 *    J wd_dot + wd x (J wd + h).
 */
#include "law_test_support.h"

#include <string.h>

#include "aocs/executive.h"

#define NS_PER_S 1000000000ull

#if defined(AOCS_REAL_IS_FLOAT)
#define TOL_Q 2.0e-6
#else
#define TOL_Q 1.0e-12
#endif

static aocs_exec_target_t fixed_target(dq_t qd)
{
    aocs_exec_target_t t;
    (void)memset(&t, 0, sizeof(t));
    t.qd_DN = dq_to_real(qd);
    return t;
}

static aocs_exec_guidance_config_t gcfg_of(aocs_guidance_mode_t mode)
{
    aocs_exec_guidance_config_t g;
    (void)memset(&g, 0, sizeof(g));
    g.mode = mode;
    g.slew.profile = AOCS_SLEW_PROFILE_BANG_COAST_BANG;
    g.slew.margin = AOCS_R(0.8);
    g.slew.inertia_kgm2 = aocs_mat3_diag(aocs_vec3_make(AOCS_R(10.0), AOCS_R(12.0), AOCS_R(15.0)));
    return g;
}

static aocs_det_output_t estimate(dq_t q, const double w[3])
{
    aocs_det_output_t e;
    e.q_BN = dq_to_real(q);
    e.w_BN_B = dv_to_real(w);
    e.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    e.status = AOCS_OK;
    return e;
}

static aocs_guidance_input_t gin_of(uint64_t t_ns, const aocs_det_output_t *est)
{
    aocs_guidance_input_t in;
    in.t_ns = t_ns;
    in.est = est;
    in.usable = (est->status == AOCS_OK) ? 1 : 0;
    in.law_active = 1;
    in.wheels = NULL;
    return in;
}

static void test_table_and_resolution(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_STEP);
    const aocs_vec3_t zero = aocs_vec3_zero();
    const aocs_vec3_t w = aocs_vec3_make(AOCS_R(0.0), AOCS_R(-1.0e-3), AOCS_R(0.0));
    for (int i = 0; i < (int)AOCS_GUIDANCE_COUNT; ++i) {
        const char *name = aocs_guidance_name((aocs_guidance_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_guidance_name((aocs_guidance_id_t)j));
        }
    }
    assert_string_equal(aocs_guidance_name(AOCS_GUIDANCE_COUNT), "unknown");
    assert_int_equal(aocs_guidance_resolve(&g, zero), AOCS_GUIDANCE_STEP);
    assert_int_equal(aocs_guidance_resolve(&g, w), AOCS_GUIDANCE_ROTATING);
    g.mode = AOCS_GUIDANCE_MODE_SLEW;
    assert_int_equal(aocs_guidance_resolve(&g, zero), AOCS_GUIDANCE_SLEW);

    /* the columns */
    aocs_guidance_t st;
    aocs_exec_target_t t = fixed_target(dq_axis_angle(0.0, 0.0, 1.0, 0.0));
    const aocs_guidance_id_t ids[3] = {AOCS_GUIDANCE_STEP, AOCS_GUIDANCE_ROTATING, AOCS_GUIDANCE_SLEW};
    const int own[3] = {0, 1, 1};
    const int ff[3] = {0, 0, 1};
    const int planned[3] = {0, 0, 1};
    const uint64_t budget[3] = {0u, 0u, (uint64_t)AOCS_EXEC_SLEW_BUDGET_NS};
    for (int i = 0; i < 3; ++i) {
        aocs_exec_guidance_config_t gi = gcfg_of((ids[i] == AOCS_GUIDANCE_SLEW) ? AOCS_GUIDANCE_MODE_SLEW
                                                                                : AOCS_GUIDANCE_MODE_STEP);
        aocs_guidance_init(&st, &gi, &t, (ids[i] == AOCS_GUIDANCE_ROTATING) ? w : zero, 0u, aocs_vec3_zero(),
                           AOCS_R(1.0));
        assert_int_equal(st.id, ids[i]);
        assert_int_equal(aocs_guidance_owns_rates(&st), own[i]);
        assert_int_equal(aocs_guidance_has_feedforward(&st), ff[i]);
        assert_int_equal(st.slew_pending, planned[i]);
        assert_int_equal(aocs_guidance_budget_ns(&st), budget[i]);
    }
    assert_int_equal(aocs_guidance_budget_ns(NULL), 0u);
    assert_int_equal(aocs_guidance_owns_rates(NULL), 0);
}

static void test_checks(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_STEP);
    aocs_exec_target_t t = fixed_target(dq_axis_angle(1.0, 0.0, 0.0, 0.3));
    const aocs_vec3_t w = aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_guidance_check(&g, &t, aocs_vec3_zero()), AOCS_OK);
    assert_int_equal(aocs_guidance_check(&g, &t, w), AOCS_OK);
    g.mode = AOCS_GUIDANCE_MODE_COUNT;
    assert_int_equal(aocs_guidance_check(&g, &t, aocs_vec3_zero()), AOCS_ERR_GUIDANCE_MODE_INVALID);
    g = gcfg_of(AOCS_GUIDANCE_MODE_SLEW);
    assert_int_equal(aocs_guidance_check(&g, &t, aocs_vec3_zero()), AOCS_OK);
    assert_int_equal(aocs_guidance_check(&g, &t, w), AOCS_ERR_GUIDANCE_TARGET_MOVING);
    t.wd_dot_B.v[2] = AOCS_R(1.0e-6);
    assert_int_equal(aocs_guidance_check(&g, &t, aocs_vec3_zero()), AOCS_ERR_GUIDANCE_TARGET_MOVING);
    t.wd_dot_B.v[2] = AOCS_R(0.0);
    g.slew.margin = AOCS_R(1.5);
    assert_int_equal(aocs_guidance_check(&g, &t, aocs_vec3_zero()), AOCS_ERR_GUIDANCE_MARGIN_INVALID);
    assert_int_equal(aocs_guidance_check(NULL, &t, aocs_vec3_zero()), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_guidance_check(&g, NULL, aocs_vec3_zero()), AOCS_ERR_NULL_ARG);
}

static void test_step_gives_the_commanded_target(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_STEP);
    aocs_exec_target_t t = fixed_target(dq_axis_angle(1.0, 2.0, -0.5, 0.7));
    const double w[3] = {0.01, -0.02, 0.005};
    aocs_det_output_t est = estimate(dq_axis_angle(0.0, 1.0, 0.0, 0.1), w);
    aocs_guidance_t st;
    t.wd_B = aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(2.0e-3), AOCS_R(3.0e-3));
    t.wd_dot_B = aocs_vec3_make(AOCS_R(-1.0e-5), AOCS_R(0.0), AOCS_R(2.0e-5));
    aocs_guidance_init(&st, &g, &t, aocs_vec3_zero(), 0u, aocs_vec3_zero(), AOCS_R(1.0));
    aocs_guidance_input_t in = gin_of(123u * NS_PER_S, &est);
    aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
    assert_memory_equal(&out, &t, sizeof(t));
    /* a new command replaces it */
    aocs_exec_target_t t2 = fixed_target(dq_axis_angle(0.0, 0.0, 1.0, -0.2));
    aocs_guidance_command(&st, &t2, 1, 5u * NS_PER_S);
    aocs_guidance_step(&st, &in, &out);
    assert_memory_equal(&out, &t2, sizeof(t2));
}

static void test_rotating_target(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_STEP);
    const dq_t qd0 = dq_axis_angle(1.0, -1.0, 0.5, 0.4);
    const double w_D[3] = {0.002, -0.003, 0.001};
    const double w_B[3] = {0.004, 0.001, -0.002};
    const dq_t q = dq_axis_angle(0.3, 0.2, 1.0, 0.9);
    aocs_exec_target_t t = fixed_target(qd0);
    aocs_det_output_t est = estimate(q, w_B);
    aocs_guidance_t st;
    const uint64_t t0 = 3u * NS_PER_S;
    aocs_guidance_init(&st, &g, &t, dv_to_real(w_D), t0, aocs_vec3_zero(), AOCS_R(1.0));
    assert_int_equal(st.id, AOCS_GUIDANCE_ROTATING);
    for (int k = 0; k < 3; ++k) {
        const double dt = (k == 0) ? 1.0e-3 : ((k == 1) ? 17.5 : 400.0);
        const uint64_t t_ns = t0 + (uint64_t)(dt * 1.0e9);
        aocs_guidance_input_t in = gin_of(t_ns, &est);
        aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
        /* reference: dq(w dt) (x) qd0 */
        const double n = sqrt(dv_dot(w_D, w_D));
        const dq_t dq = dq_axis_angle(w_D[0], w_D[1], w_D[2], n * dt);
        const dq_t qd = dq_mul(dq, qd0);
        const dq_t qd_got = dq_from_real(out.qd_DN);
        for (int i = 0; i < 4; ++i) {
            assert_close(qd_got.q[i], qd.q[i], TOL_Q);
        }
        /* wd_B = A(qe) w_D with qe = q (x) qd^-1; wd_dot_B = wd_B x w */
        {
            const dq_t qe = dq_normalize(dq_mul(q, dq_inv(qd)));
            double a[3][3];
            double wd[3];
            double wd_dot[3];
            double got[3];
            ref_dcm(dq_to_real(qe), a);
            for (int r = 0; r < 3; ++r) {
                wd[r] = a[r][0] * w_D[0] + a[r][1] * w_D[1] + a[r][2] * w_D[2];
            }
            dv_cross(wd, w_B, wd_dot);
            dv_from_real(out.wd_B, got);
            for (int r = 0; r < 3; ++r) {
                assert_close(got[r], wd[r], 1.0e3 * TOL_Q * 1.0e-3);
            }
            dv_from_real(out.wd_dot_B, got);
            for (int r = 0; r < 3; ++r) {
                assert_close(got[r], wd_dot[r], 1.0e3 * TOL_Q * 1.0e-3);
            }
        }
    }
    /* an unusable estimate: qd(t) still, zero rates */
    est.status = AOCS_ERR_INPUT_STALE;
    {
        aocs_guidance_input_t in = gin_of(t0 + NS_PER_S, &est);
        aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
        assert_vec3_close(out.wd_B, aocs_vec3_zero(), 0.0);
        assert_vec3_close(out.wd_dot_B, aocs_vec3_zero(), 0.0);
        /* a command moves qd0's epoch to the last sample; without one the epoch is kept */
        aocs_guidance_command(&st, &t, 0, 99u * NS_PER_S);
        assert_true(st.target_t0_ns == t0);
        aocs_guidance_command(&st, &t, 1, 99u * NS_PER_S);
        assert_true(st.target_t0_ns == 99u * NS_PER_S);
        aocs_guidance_set_epoch(&st, 7u);
        assert_true(st.target_t0_ns == 7u);
    }
    /* at t0 the target is qd0 itself */
    {
        est.status = AOCS_OK;
        aocs_guidance_set_epoch(&st, t0);
        aocs_guidance_input_t in = gin_of(t0, &est);
        aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
        const dq_t got = dq_from_real(out.qd_DN);
        for (int i = 0; i < 4; ++i) {
            assert_close(got.q[i], qd0.q[i], TOL_Q);
        }
    }
}

static void test_slew_plans_from_the_first_usable_estimate(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_SLEW);
    const dq_t q0 = dq_axis_angle(0.0, 0.0, 1.0, 0.0);
    const dq_t qf = dq_axis_angle(0.0, 0.0, 1.0, 0.5);
    const double w0[3] = {0.0, 0.0, 0.0};
    aocs_exec_target_t t = fixed_target(qf);
    aocs_det_output_t est = estimate(q0, w0);
    aocs_guidance_t st;
    aocs_guidance_init(&st, &g, &t, aocs_vec3_zero(), 0u, aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5)),
                       AOCS_R(0.0));
    assert_int_equal(st.slew_pending, 1);
    /* no law selected, or an unusable estimate: not planned yet */
    {
        aocs_guidance_input_t in = gin_of(NS_PER_S, &est);
        in.law_active = 0;
        {
            aocs_exec_target_t out;
            aocs_guidance_step(&st, &in, &out);
        }
        assert_int_equal(st.slew_pending, 1);
        in.law_active = 1;
        in.usable = 0;
        {
            aocs_exec_target_t out;
            aocs_guidance_step(&st, &in, &out);
        }
        assert_int_equal(st.slew_pending, 1);
    }
    {
        aocs_guidance_input_t in = gin_of(2u * NS_PER_S, &est);
        aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
        const dq_t got = dq_from_real(out.qd_DN);
        assert_int_equal(st.slew_pending, 0);
        assert_true(st.slew_t0_ns == 2u * NS_PER_S);
        assert_true(st.slew.t_end_s > AOCS_R(0.0));
        for (int i = 0; i < 4; ++i) {
            assert_close(got.q[i], q0.q[i], TOL_Q); /* qd(0) = the attitude it starts from */
        }
    }
    {
        const uint64_t t_end_ns = 2u * NS_PER_S + (uint64_t)((double)st.slew.t_end_s * 1.0e9) + NS_PER_S;
        aocs_guidance_input_t in = gin_of(t_end_ns, &est);
        aocs_exec_target_t out;
        aocs_guidance_step(&st, &in, &out);
        const dq_t got = dq_from_real(out.qd_DN);
        double fp = 0.0;
        for (int i = 0; i < 4; ++i) {
            fp += got.q[i] * qf.q[i];
        }
        assert_close(fabs(fp), 1.0, 1.0e3 * TOL_Q); /* at rest on the target */
        assert_vec3_close(out.wd_B, aocs_vec3_zero(), 1.0e3 * TOL_Q);
    }
    /* a new command is planned again from the next usable estimate */
    aocs_guidance_command(&st, &t, 1, 50u * NS_PER_S);
    assert_int_equal(st.slew_pending, 1);
}

/* the slew's angle about z of a target qd (the test's slews are about z from the identity) */
static double angle_about_z(aocs_quat_t qd)
{
    return 2.0 * atan2((double)qd.q[2], (double)qd.q[3]);
}

/* aocs_guidance_slow_down (docs/spec.md 5.15.2): after the switch at t_s the reference is the profile at
 * tau = tau(t_s) + k (t - t_s); its rate, measured here by finite differences of the reference attitude, is
 * k times the profile's rate; twice in a row multiplies the factors; a new command plans on its own clock */
static void test_slow_down_after_an_actuator_loss(void **state)
{
    (void)state;
    /* the 0.5 rad slew about z from rest at the identity of test_slew_plans_from_the_first_usable_estimate */
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_SLEW);
    aocs_exec_target_t t = fixed_target(dq_axis_angle(0.0, 0.0, 1.0, 0.5));
    const double w0[3] = {0.0, 0.0, 0.0};
    aocs_det_output_t est = estimate(dq_axis_angle(0.0, 0.0, 1.0, 0.0), w0);
    aocs_guidance_t st;
    aocs_exec_target_t out;
    aocs_guidance_init(&st, &g, &t, aocs_vec3_zero(), 0u, aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5)),
                       AOCS_R(0.0));
    est.status = AOCS_ERR_INPUT_INVALID; /* usable = 0 below: only the reference attitude is compared */
    {
        aocs_guidance_input_t in = gin_of(NS_PER_S, &est);
        in.usable = 1;
        aocs_guidance_step(&st, &in, &out); /* planned at t = 1 s */
    }
    const double t_end = (double)st.slew.t_end_s;
    const uint64_t t_s_ns = NS_PER_S + (uint64_t)(0.3 * t_end * 1.0e9);
    const double k = 0.6;
    aocs_guidance_slow_down(&st, t_s_ns, AOCS_R(0.6));
    assert_int_equal(st.scaled, 1);
    for (int j = 1; j <= 5; ++j) {
        const uint64_t t_ns = t_s_ns + (uint64_t)j * (uint64_t)(0.1 * t_end * 1.0e9);
        const double tau = 0.3 * t_end + k * ((double)(t_ns - t_s_ns) * 1.0e-9);
        aocs_slew_ref_t ref;
        aocs_guidance_input_t in = gin_of(t_ns, &est);
        aocs_guidance_step(&st, &in, &out);
        aocs_slew_eval(&st.slew, (real_t)tau, &ref);
        assert_close(angle_about_z(out.qd_DN), (double)ref.theta_rad, 1.0e3 * TOL_Q);
        /* the rate of the reference: k theta_dot(tau), by a central difference over +-1 ms */
        {
            aocs_exec_target_t a;
            aocs_exec_target_t b;
            aocs_guidance_input_t ia = gin_of(t_ns - 1000000u, &est);
            aocs_guidance_input_t ib = gin_of(t_ns + 1000000u, &est);
            aocs_guidance_step(&st, &ia, &a);
            aocs_guidance_step(&st, &ib, &b);
#if defined(AOCS_REAL_IS_FLOAT)
            const double tol = 2.0e-2 * fabs((double)ref.theta_dot_radps) + 1.0e-4;
#else
            const double tol = 1.0e-6 * fabs((double)ref.theta_dot_radps) + 1.0e-9;
#endif
            assert_close((angle_about_z(b.qd_DN) - angle_about_z(a.qd_DN)) / 2.0e-3,
                         k * (double)ref.theta_dot_radps, tol);
        }
    }
    /* a second loss: the factors multiply */
    aocs_guidance_slow_down(&st, t_s_ns + NS_PER_S, AOCS_R(0.5));
    assert_close(st.time_scale, 0.3, TOL_Q);
    /* nothing in progress after the (slowed) end, and k outside (0, 1]: no-op */
    aocs_guidance_slow_down(&st, t_s_ns + (uint64_t)(10.0 * t_end * 1.0e9), AOCS_R(0.5));
    assert_close(st.time_scale, 0.3, TOL_Q);
    aocs_guidance_slow_down(&st, t_s_ns + NS_PER_S, AOCS_R(1.5));
    assert_close(st.time_scale, 0.3, TOL_Q);
    /* a new command: planned afresh, unscaled */
    aocs_guidance_command(&st, &t, 1, 900u * NS_PER_S);
    {
        aocs_guidance_input_t in = gin_of(901u * NS_PER_S, &est);
        in.usable = 1;
        aocs_guidance_step(&st, &in, &out);
    }
    assert_int_equal(st.scaled, 0);
    aocs_guidance_slow_down(NULL, 0u, AOCS_R(0.5)); /* total */
}

static void test_feedforward(void **state)
{
    (void)state;
    aocs_exec_guidance_config_t g = gcfg_of(AOCS_GUIDANCE_MODE_SLEW);
    aocs_guidance_t st;
    aocs_exec_target_t t = fixed_target(dq_axis_angle(0.0, 0.0, 1.0, 0.0));
    const double wd[3] = {0.01, -0.02, 0.03};
    const double wd_dot[3] = {1.0e-3, 2.0e-3, -1.0e-3};
    const double h[3] = {0.5, -0.2, 0.1};
    const double jd[3] = {10.0, 12.0, 15.0};
    double jw[3];
    double c[3];
    double got[3];
    aocs_guidance_init(&st, &g, &t, aocs_vec3_zero(), 0u, aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0)),
                       AOCS_R(0.0));
    t.wd_B = dv_to_real(wd);
    t.wd_dot_B = dv_to_real(wd_dot);
    dv_from_real(aocs_guidance_feedforward(&st, &t, dv_to_real(h)), got);
    for (int i = 0; i < 3; ++i) {
        jw[i] = jd[i] * wd[i] + h[i];
    }
    dv_cross(wd, jw, c);
    for (int i = 0; i < 3; ++i) {
        assert_close(got[i], jd[i] * wd_dot[i] + c[i], 1.0e2 * TOL_Q);
    }
    assert_vec3_close(aocs_guidance_feedforward(NULL, &t, dv_to_real(h)), aocs_vec3_zero(), 0.0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_table_and_resolution),
        cmocka_unit_test(test_checks),
        cmocka_unit_test(test_step_gives_the_commanded_target),
        cmocka_unit_test(test_rotating_target),
        cmocka_unit_test(test_slew_plans_from_the_first_usable_estimate),
        cmocka_unit_test(test_feedforward),
        cmocka_unit_test(test_slow_down_after_an_actuator_loss),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
