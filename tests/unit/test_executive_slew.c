/*
 * Executive in guidance mode SLEW (executive.h "Slew guidance"):
 *  - each invalid guidance config its own status at init; STEP mode ignores the slew fields;
 *  - the first good sample starts the slew from its attitude: the law sees
 *    qd(t) of aocs_slew_plan/eval from that attitude (compared with a slew
 *    planned here), wd_B = A(qe) wd_D, and the command before saturation is
 *    the law's own output plus J wd_dot_B + wd_B x J wd_B (recomputed here in
 *    double) for quat_pd, and the law's output alone for smc (its formula has it);
 *  - a new target by select starts a new slew from the next sample's attitude;
 *  - STEP mode: the law sees the commanded target, no feedforward;
 *  - the selected law's state is reset (init re-run) on a target change and on
 *    the return to NOMINAL, not on a select without a target (a corrupted state
 *    makes that visible: the law step fails until the init runs again).
 */
#include "law_test_support.h"

#include <string.h>

#include "aocs/executive.h"

#define NS_PER_S 1000000000ull
#define PERIOD_NS 100000000ull

#if defined(AOCS_REAL_IS_FLOAT)
#define TOL_FF 1.0e-4
#else
#define TOL_FF 1.0e-10
#endif

static aocs_exec_config_t slew_config(aocs_law_id_t law)
{
    aocs_exec_config_t cfg;
    aocs_exec_config_default(&cfg);
    cfg.law = law;
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.target.qd_DN = dq_to_real(dq_euler321_deg(30.0, -20.0, 1.0));
    cfg.laws.quat_pd.kp = AOCS_R(40.0);
    cfg.laws.quat_pd.kd = AOCS_R(800.0);
    cfg.laws.smc.inertia = aocs_mat3_diag(aocs_vec3_make(AOCS_R(2059.5), AOCS_R(5954.2), AOCS_R(5974.3)));
    cfg.laws.smc.inertia.m[0][1] = AOCS_R(30.0);
    cfg.laws.smc.inertia.m[1][0] = AOCS_R(30.0);
    cfg.laws.smc.lambda = aocs_vec3_make(AOCS_R(1.0), AOCS_R(1.0), AOCS_R(1.0));
    cfg.laws.smc.g = aocs_vec3_make(AOCS_R(0.05), AOCS_R(0.05), AOCS_R(0.05));
    cfg.laws.smc.eps = aocs_vec3_make(AOCS_R(0.02), AOCS_R(0.02), AOCS_R(0.02));
    cfg.guidance.mode = AOCS_GUIDANCE_MODE_SLEW;
    cfg.guidance.slew.margin = AOCS_R(0.8);
    cfg.guidance.slew.inertia_kgm2 = cfg.laws.smc.inertia;
    return cfg;
}

static aocs_exec_input_t sample_at(uint32_t tick, aocs_quat_t q, aocs_vec3_t w)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = (uint64_t)tick * PERIOD_NS;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = q;
    in.w_BN_B = w;
    return in;
}

static void invalid_guidance_configs(void **state)
{
    (void)state;
    aocs_exec_t exec;
    aocs_exec_config_t c = slew_config(AOCS_LAW_QUAT_PD);
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_OK);
    c.guidance.mode = AOCS_GUIDANCE_MODE_COUNT;
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_MODE_INVALID);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.target_rotation_rate_D = aocs_vec3_make(AOCS_R(0.0), AOCS_R(1e-4), AOCS_R(0.0));
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_TARGET_MOVING);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.target.wd_B = aocs_vec3_make(AOCS_R(0.001), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_TARGET_MOVING);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.guidance.slew.margin = AOCS_R(1.5);
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_MARGIN_INVALID);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.guidance.slew.profile = AOCS_SLEW_PROFILE_COUNT;
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_PROFILE_INVALID);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.guidance.slew.rate_limit_radps = AOCS_R(-1.0);
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_RATE_LIMIT_INVALID);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.guidance.slew.profile = AOCS_SLEW_PROFILE_JERK_LIMITED;
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_ERR_GUIDANCE_JERK_TIME_INVALID);
    c = slew_config(AOCS_LAW_QUAT_PD);
    c.guidance.slew.inertia_kgm2 = aocs_mat3_zero();
    assert_true(aocs_exec_init(&exec, &c) != AOCS_OK);
    /* STEP mode: the slew fields are not looked at */
    c.guidance.mode = AOCS_GUIDANCE_MODE_STEP;
    c.guidance.slew.margin = AOCS_R(-3.0);
    c.target_rotation_rate_D = aocs_vec3_make(AOCS_R(0.0), AOCS_R(1e-4), AOCS_R(0.0));
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_OK);
    /* SLEW: a select with a moving target is rejected */
    c = slew_config(AOCS_LAW_QUAT_PD);
    assert_int_equal(aocs_exec_init(&exec, &c), AOCS_OK);
    {
        aocs_exec_target_t t = c.target;
        t.wd_dot_B = aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1e-6));
        assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &t), AOCS_ERR_TARGET_INVALID);
    }
}

/* u_ff = J wd_dot + wd x (J wd) in double */
static void ref_ff(const aocs_mat3_t *j, aocs_vec3_t wd_r, aocs_vec3_t wdd_r, double u[3])
{
    dmat_t jd;
    double wd[3];
    double wdd[3];
    double jw[3];
    double jwd[3];
    double cr[3];
    for (int i = 0; i < 3; ++i) {
        for (int k = 0; k < 3; ++k) {
            jd.m[i][k] = (double)j->m[i][k];
        }
    }
    dv_from_real(wd_r, wd);
    dv_from_real(wdd_r, wdd);
    dm_mul_vec(&jd, wd, jw);
    dm_mul_vec(&jd, wdd, jwd);
    dv_cross(wd, jw, cr);
    for (int i = 0; i < 3; ++i) {
        u[i] = jwd[i] + cr[i];
    }
}

static void check_tracking(aocs_law_id_t law, int ff_expected)
{
    aocs_exec_config_t cfg = slew_config(law);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_slew_t s;
    aocs_slew_envelope_t env;
    const aocs_quat_t q0 = dq_to_real(dq_euler321_deg(14.0, 14.0, 14.0));
    test_rng_t r = {0x4242ULL};
    env.u_max_axis_Nm = cfg.u_max_axis;
    env.u_max_norm_Nm = AOCS_R(0.0);
    env.wheels = NULL;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(aocs_slew_plan(&s, &cfg.guidance.slew, &env, q0, cfg.target.qd_DN), AOCS_OK);
    /* first sample (t = 0.1 s) at q0: the slew starts there */
    for (uint32_t tick = 1u; tick < 1500u; ++tick) {
        /* a body a little off the reference, with some rate */
        aocs_slew_ref_t ref;
        aocs_quat_t q;
        aocs_vec3_t w;
        aocs_exec_law_states_t states;
        aocs_att_input_t att;
        aocs_vec3_t u_law;
        aocs_orbit_input_t orbit;
        double u_ff[3];
        aocs_slew_eval(&s, (real_t)((double)(tick - 1u) * 0.1), &ref);
        if (tick == 1u) {
            q = q0;
            w = aocs_vec3_zero();
        } else {
            dq_t d = dq_axis_angle(test_rng_uniform(&r, -1, 1), test_rng_uniform(&r, -1, 1),
                                   test_rng_uniform(&r, -1, 1), 1e-3);
            q = dq_to_real(dq_normalize(dq_mul(d, dq_from_real(ref.qd_DN))));
            w = aocs_vec3_add(ref.wd_D, test_random_vec3(&r, 1e-4));
        }
        {
            aocs_exec_input_t in = sample_at(tick, q, w);
            assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        }
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        for (int i = 0; i < 4; ++i) {
            assert_close(out.target.qd_DN.q[i], ref.qd_DN.q[i], TOL_TIGHT * 10.0);
        }
        {
            /* wd_B = A(qe) wd_D, qe = q (x) qd^-1 (independent DCM) */
            double a[3][3];
            double wd_d[3];
            dv_from_real(ref.wd_D, wd_d);
            ref_dcm(dq_to_real(dq_normalize(dq_mul(dq_from_real(q), dq_inv(dq_from_real(out.target.qd_DN))))), a);
            for (int i = 0; i < 3; ++i) {
                double x = a[i][0] * wd_d[0] + a[i][1] * wd_d[1] + a[i][2] * wd_d[2];
                assert_true(fabs((double)out.target.wd_B.v[i] - x) <= TOL_FF * 1e-2 + 1e-6 * fabs(x));
            }
        }
        /* the law alone, on the same inputs */
        att.q_BN = q;
        att.w_BN_B = w;
        att.qd_DN = out.target.qd_DN;
        att.wd_B = out.target.wd_B;
        att.wd_dot_B = out.target.wd_dot_B;
        att.dt_s = cfg.period_s;
        att.u_max_axis = cfg.u_max_axis;
        att.u_max_norm = cfg.u_max_norm;
        memset(&orbit, 0, sizeof(orbit));
        orbit.dt_s = cfg.period_s;
        assert_int_equal(aocs_exec_law_init(&states, &cfg.laws, law), AOCS_OK);
        assert_int_equal(aocs_exec_law_step(&states, law, &att, &orbit, &u_law), AOCS_OK);
        ref_ff(&cfg.guidance.slew.inertia_kgm2, out.target.wd_B, out.target.wd_dot_B, u_ff);
        for (int i = 0; i < 3; ++i) {
            double expect = (double)u_law.v[i] + ((ff_expected != 0) ? u_ff[i] : 0.0);
            assert_true(fabs((double)out.u_unsat.v[i] - expect) <= TOL_FF * (1.0 + fabs(expect)));
            assert_true(fabs((double)out.u_ff.v[i] - ((ff_expected != 0) ? u_ff[i] : 0.0)) <= TOL_FF);
            assert_true(fabs((double)out.u_cmd.v[i]) <= 1.0);
        }
    }
}

static void quat_pd_gets_feedforward(void **state)
{
    (void)state;
    check_tracking(AOCS_LAW_QUAT_PD, 1);
}

static void smc_has_its_own(void **state)
{
    (void)state;
    check_tracking(AOCS_LAW_SMC, 0);
}

static void select_starts_new_slew_and_step_mode(void **state)
{
    (void)state;
    aocs_exec_config_t cfg = slew_config(AOCS_LAW_QUAT_PD);
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_target_t t;
    aocs_exec_input_t in;
    const aocs_quat_t q1 = dq_to_real(dq_euler321_deg(-5.0, 3.0, 8.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in = sample_at(1u, dq_to_real(dq_euler321_deg(14.0, 14.0, 14.0)), aocs_vec3_zero());
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    t = cfg.target;
    t.qd_DN = aocs_quat_identity();
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &t), AOCS_OK);
    in = sample_at(2u, q1, aocs_vec3_zero());
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_close(out.target.qd_DN.q[i], q1.q[i], TOL_TIGHT); /* theta = 0: the new start */
    }
    /* long after: the commanded target exactly */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    for (uint32_t tick = 1u; tick <= 2000u; ++tick) { /* 200 s: the slew (~133 s) is over */
        in = sample_at(tick, q1, aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    }
    assert_true(aocs_vec3_norm_inf(out.target.wd_B) < AOCS_R(1e-30));
    assert_int_equal(out.target.qd_DN.q[3] < cfg.target.qd_DN.q[3], 0); /* same value, no float == */
    assert_int_equal(out.target.qd_DN.q[3] > cfg.target.qd_DN.q[3], 0);
    /* STEP mode: the target at once, no feedforward */
    cfg.guidance.mode = AOCS_GUIDANCE_MODE_STEP;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in = sample_at(1u, q1, aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(0.0)));
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    for (int i = 0; i < 4; ++i) {
        assert_int_equal(out.target.qd_DN.q[i] < cfg.target.qd_DN.q[i], 0);
        assert_int_equal(out.target.qd_DN.q[i] > cfg.target.qd_DN.q[i], 0);
    }
    assert_true(aocs_vec3_norm_inf(out.u_ff) < AOCS_R(1e-30));
}

static void law_reset_on_target_and_nominal(void **state)
{
    (void)state;
    for (int mode = 0; mode < 2; ++mode) {
        aocs_exec_config_t cfg = slew_config(AOCS_LAW_QUAT_PD);
        aocs_exec_t exec;
        aocs_exec_output_t out;
        aocs_exec_input_t in;
        aocs_exec_target_t t;
        uint32_t tick = 1u;
        cfg.guidance.mode = (aocs_guidance_mode_t)mode;
        cfg.recover_good_samples = 3u;
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
        t = cfg.target;
        in = sample_at(tick, aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.law_status, AOCS_OK);
        /* a broken law state: the law fails (SAFE) ... */
        exec.states.quat_pd.initialised = 0;
        in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.law_status, AOCS_ERR_NOT_INITIALISED);
        /* ... a select without a target changes nothing ... */
        assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, NULL), AOCS_OK);
        in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.law_status, AOCS_ERR_NOT_INITIALISED);
        /* ... a new target re-runs the init */
        assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &t), AOCS_OK);
        in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.law_status, AOCS_OK);
        /* return to NOMINAL: SAFE after an invalid sample, the state broken meanwhile; the
         * recovering sample resets it, so the law works and the executive is NOMINAL again */
        while (out.mode != AOCS_EXEC_MODE_NOMINAL) {
            in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
            assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        }
        in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
        in.valid = 0u;
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        for (uint32_t k = 0u; k < 3u; ++k) {
            if (k == 2u) {
                exec.states.quat_pd.initialised = 0; /* broken just before the recovering sample */
            }
            in = sample_at(++tick, aocs_quat_identity(), aocs_vec3_zero());
            assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
            assert_int_equal(out.law_status, AOCS_OK);
        }
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    }
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(invalid_guidance_configs),
        cmocka_unit_test(quat_pd_gets_feedforward),
        cmocka_unit_test(smc_has_its_own),
        cmocka_unit_test(select_starts_new_slew_and_step_mode),
        cmocka_unit_test(law_reset_on_target_and_nominal),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
