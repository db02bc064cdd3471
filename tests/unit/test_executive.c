/*
 * Executive mode logic, input checks, run-time selection and config
 * validation (SPEC 2-3, ARCHITECTURE.md data path). Lockstep mode with the
 * real POSIX HAL: nothing here depends on how long a step takes.
 * Expected torques are evaluated from the SPEC formulas in the test.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"

#define KP 1.0
#define KD 2.0
#define K_SAFE 3.0
#define LIM 0.5
#define M_GOOD 3u
#define N_MISS 2u
#define PERIOD_NS 100000000ull

/* 10 deg about z, and a small rate: a quat_pd torque well below LIM */
static aocs_quat_t q_test(void)
{
    double h = 5.0 * 3.14159265358979323846 / 180.0;
    return aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), (real_t)sin(h), (real_t)cos(h));
}

static aocs_vec3_t w_test(void)
{
    return aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
}

static void base_config(aocs_exec_config_t *cfg)
{
    aocs_exec_config_default(cfg);
    cfg->period_s = AOCS_R(0.1);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(KP);
    cfg->laws.quat_pd.kd = AOCS_R(KD);
    cfg->laws.crp_linear.k1 = AOCS_R(19.0);
    cfg->laws.crp_linear.k2 = AOCS_R(13.0);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(LIM), AOCS_R(LIM), AOCS_R(LIM));
    cfg->k_safe = AOCS_R(K_SAFE);
    cfg->recover_good_samples = M_GOOD;
    cfg->missing_max_periods = N_MISS;
}

static aocs_exec_input_t sample(uint32_t tick)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = (uint64_t)tick * PERIOD_NS;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = q_test();
    in.w_BN_B = w_test();
    return in;
}

/* SPEC 2.2 with qd = identity (qe = q): u = -kp sign(q4) q_vec - kd w */
static aocs_vec3_t pd_expected(aocs_quat_t q, aocs_vec3_t w)
{
    double sg = ((double)q.q[3] >= 0.0) ? 1.0 : -1.0;
    return aocs_vec3_make((real_t)(-KP * sg * (double)q.q[0] - KD * (double)w.v[0]),
                          (real_t)(-KP * sg * (double)q.q[1] - KD * (double)w.v[1]),
                          (real_t)(-KP * sg * (double)q.q[2] - KD * (double)w.v[2]));
}

static void assert_within_limits(const aocs_exec_output_t *out, double lim)
{
    for (int i = 0; i < 3; ++i) {
        assert_true(isfinite((double)out->u_cmd.v[i]));
        assert_true(fabs((double)out->u_cmd.v[i]) <= lim);
    }
}

static void init_ok(aocs_exec_t *exec, const aocs_exec_config_t *cfg)
{
    assert_int_equal(aocs_exec_init(exec, cfg), AOCS_OK);
}

static void step_ok(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_exec_output_t *out)
{
    assert_int_equal(aocs_exec_step(exec, in, out), AOCS_OK);
}

static void test_nominal_runs_selected_law(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(out.law, AOCS_LAW_QUAT_PD);
    assert_int_equal(out.law_status, AOCS_OK);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_vec3_close(out.u_cmd, pd_expected(in.q_BN, in.w_BN_B), TOL_TIGHT);
    assert_vec3_close(out.u_unsat, out.u_cmd, 0.0);
    assert_int_equal(out.saturated, 0);
    assert_int_equal(out.counters.steps, 1);
    assert_int_equal(out.counters.invalid + out.counters.stale + out.counters.missing + out.counters.law_error, 0);
}

static void test_nan_sensor_enters_safe(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &out);

    /* NaN rate: no usable rate, so the safe command is zero */
    in = sample(2);
    in.w_BN_B.v[1] = (real_t)NAN;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(out.counters.invalid, 1);
    assert_int_equal(out.counters.mode_transitions, 1);
    assert_within_limits(&out, LIM);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);

    /* NaN attitude, good rate: rate damping u = -k_safe w (SPEC: safe mode) */
    in = sample(3);
    in.q_BN.q[0] = (real_t)NAN;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.counters.invalid, 2);
    assert_within_limits(&out, LIM);
    assert_vec3_close(out.u_cmd, aocs_vec3_make((real_t)(-K_SAFE * 0.01), (real_t)(K_SAFE * 0.02), (real_t)(-K_SAFE * 0.03)),
                      TOL_TIGHT);

    /* Inf rate, huge: still finite and within the limit */
    in = sample(4);
    in.w_BN_B.v[0] = (real_t)INFINITY;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.invalid, 3);
    assert_within_limits(&out, LIM);
}

static void test_safe_damping_is_saturated(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    in.q_BN.q[3] = (real_t)NAN;
    in.w_BN_B = aocs_vec3_make(AOCS_R(1.0), AOCS_R(-0.1), AOCS_R(0.0));
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    /* -k_safe w = (-3, 0.3, 0): x clamped to -LIM, y passes */
    assert_vec3_close(out.u_unsat, aocs_vec3_make(AOCS_R(-3.0), AOCS_R(0.3), AOCS_R(0.0)), TOL_TIGHT);
    assert_vec3_close(out.u_cmd, aocs_vec3_make(AOCS_R(-LIM), AOCS_R(0.3), AOCS_R(0.0)), TOL_TIGHT);
    assert_int_equal(out.saturated, 1);
    assert_int_equal(out.counters.saturated, 1);
}

static void test_validity_flags_and_non_unit_quaternion(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);

    aocs_exec_input_t in = sample(1);
    for (int i = 0; i < 4; ++i) {
        in.q_BN.q[i] = (real_t)(1.1 * (double)in.q_BN.q[i]); /* |q| = 1.1 */
    }
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.input_status, AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(out.counters.invalid, 1);
    assert_within_limits(&out, LIM);

    in = sample(2);
    in.valid = AOCS_EXEC_VALID_ATT; /* rate flagged invalid by the sensor */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_INVALID);
    assert_int_equal(out.counters.invalid, 2);
    /* the flagged rate must not be used for damping */
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);

    in = sample(3);
    in.valid = AOCS_EXEC_VALID_RATE; /* attitude flagged invalid, rate good */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.invalid, 3);
    assert_vec3_close(out.u_cmd, aocs_vec3_scale(w_test(), AOCS_R(-K_SAFE)), TOL_TIGHT);
}

static void test_stale_timestamp(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(5);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);

    /* next tick but the same sensor time: not advancing */
    in = sample(6);
    in.t_sensor_ns = 5u * PERIOD_NS;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.counters.stale, 1);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_within_limits(&out, LIM);

    /* older time */
    in = sample(7);
    in.t_sensor_ns = 4u * PERIOD_NS;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.stale, 2);

    /* repeated tick (duplicate frame) with a later time */
    in = sample(5);
    in.t_sensor_ns = 9u * PERIOD_NS;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.stale, 3);

    /* stale samples did not move the reference: tick 6 at its own time is fresh */
    in = sample(6);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.stale, 3);
    assert_int_equal(out.counters.invalid, 0);
}

static void test_missing_samples_counted(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg); /* N_MISS = 2 */
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(10);
    step_ok(&exec, &in, &out);

    in = sample(12); /* 1 missing < N: counted, tolerated */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.missing, 1);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(out.input_status, AOCS_OK);

    in = sample(15); /* 2 missing >= N: SAFE */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.counters.missing, 3);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_MISSING);
    assert_within_limits(&out, LIM);

    /* tick counter wrap is not a gap */
    base_config(&cfg);
    init_ok(&exec, &cfg);
    in = sample(0xFFFFFFFFu);
    step_ok(&exec, &in, &out);
    in = sample(0u);
    in.t_sensor_ns = 0x100000000ull * PERIOD_NS;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.missing, 0);
}

static void test_recovery_after_m_good_samples(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg); /* M_GOOD = 3 */
    init_ok(&exec, &cfg);
    uint32_t t = 1u;
    aocs_exec_input_t in = sample(t++);
    in.w_BN_B.v[2] = (real_t)NAN;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);

    /* M-1 good samples: still SAFE, command is the damping one */
    for (uint32_t i = 0u; i < M_GOOD - 1u; ++i) {
        in = sample(t++);
        step_ok(&exec, &in, &out);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        assert_vec3_close(out.u_cmd, aocs_vec3_scale(w_test(), AOCS_R(-K_SAFE)), TOL_TIGHT);
    }
    /* a bad sample restarts the count */
    in = sample(t++);
    in.valid = 0u;
    step_ok(&exec, &in, &out);
    for (uint32_t i = 0u; i < M_GOOD - 1u; ++i) {
        in = sample(t++);
        step_ok(&exec, &in, &out);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    }
    /* M-th consecutive good sample: NOMINAL with the law's torque */
    in = sample(t++);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_vec3_close(out.u_cmd, pd_expected(in.q_BN, in.w_BN_B), TOL_TIGHT);
    assert_int_equal(out.counters.mode_transitions, 2);
}

static void test_select_in_safe_restarts_recovery(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg); /* M_GOOD = 3 */
    init_ok(&exec, &cfg);
    uint32_t t = 1u;
    aocs_exec_input_t in = sample(t++);
    in.valid = 0u;
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    for (uint32_t i = 0u; i < M_GOOD - 1u; ++i) {
        in = sample(t++);
        step_ok(&exec, &in, &out);
    }
    /* a new law while recovering: it stays SAFE and needs its own M good samples */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_CRP_LINEAR, NULL), AOCS_OK);
    for (uint32_t i = 0u; i < M_GOOD - 1u; ++i) {
        in = sample(t++);
        step_ok(&exec, &in, &out);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        assert_int_equal(out.law, AOCS_LAW_CRP_LINEAR);
    }
    in = sample(t++);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(out.law_status, AOCS_OK);
}

static void test_select_unknown_law_rejected(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t before;
    aocs_exec_output_t after;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &before);

    aocs_exec_target_t tgt = {aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.6), AOCS_R(0.8)), aocs_vec3_zero(),
                              aocs_vec3_zero()};
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_COUNT, &tgt), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(aocs_exec_select(&exec, (aocs_law_id_t)99, NULL), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(aocs_exec_select(&exec, (aocs_law_id_t)-1, NULL), AOCS_ERR_UNKNOWN_LAW);

    in = sample(2);
    step_ok(&exec, &in, &after);
    assert_int_equal(after.law, AOCS_LAW_QUAT_PD);
    assert_int_equal(after.mode, AOCS_EXEC_MODE_NOMINAL);
    /* the target of the rejected select was not taken either */
    assert_vec3_close(after.u_cmd, before.u_cmd, 0.0);
    assert_int_equal(after.counters.select_rejected, 3);
    assert_int_equal(after.counters.select_accepted, 0);
    assert_int_equal(after.counters.mode_transitions, 0);
}

static void test_select_invalid_target_rejected(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t before;
    aocs_exec_output_t after;
    base_config(&cfg);
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &before);

    aocs_exec_target_t bad[4];
    for (int i = 0; i < 4; ++i) {
        bad[i].qd_DN = aocs_quat_identity();
        bad[i].wd_B = aocs_vec3_zero();
        bad[i].wd_dot_B = aocs_vec3_zero();
    }
    bad[0].qd_DN.q[1] = (real_t)NAN;
    bad[1].qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.9), AOCS_R(1.2)); /* |q| = 1.5 */
    bad[2].wd_B.v[0] = (real_t)INFINITY;
    bad[3].wd_dot_B.v[2] = (real_t)NAN;
    for (int i = 0; i < 4; ++i) {
        /* also with a different (valid) law: nothing may change */
        assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_CRP_LINEAR, &bad[i]), AOCS_ERR_TARGET_INVALID);
    }
    in = sample(2);
    step_ok(&exec, &in, &after);
    assert_int_equal(after.law, AOCS_LAW_QUAT_PD);
    assert_vec3_close(after.u_cmd, before.u_cmd, 0.0);
    assert_int_equal(after.counters.select_rejected, 4);
}

static void test_select_invalid_law_config_rejected(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    cfg.laws.crp_linear.k1 = AOCS_R(-1.0);
    init_ok(&exec, &cfg); /* only the selected law (quat_pd) must be valid */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_CRP_LINEAR, NULL), AOCS_ERR_GAIN_NOT_POSITIVE);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.law, AOCS_LAW_QUAT_PD);
    assert_vec3_close(out.u_cmd, pd_expected(in.q_BN, in.w_BN_B), TOL_TIGHT);
    assert_int_equal(out.counters.select_rejected, 1);
}

static void test_select_changes_law_target_and_mode(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    init_ok(&exec, &cfg);

    /* target = current attitude, wd given: qe = identity, u = -k1 (w - wd) (SPEC 2.1, rho = 0) */
    aocs_exec_target_t tgt = {q_test(), aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(0.0)), aocs_vec3_zero()};
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_CRP_LINEAR, &tgt), AOCS_OK);
    aocs_exec_input_t in = sample(1);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.law, AOCS_LAW_CRP_LINEAR);
    assert_vec3_close(out.u_unsat, aocs_vec3_make(AOCS_R(0.0), AOCS_R(19.0 * 0.02), AOCS_R(-19.0 * 0.03)), TOL_TIGHT);
    /* 19 * 0.03 = 0.57 > LIM on z */
    assert_vec3_close(out.u_cmd, aocs_vec3_make(AOCS_R(0.0), AOCS_R(19.0 * 0.02), AOCS_R(-LIM)), TOL_TIGHT);
    assert_int_equal(out.saturated, 1);

    /* NONE: STANDBY, zero command even with good inputs, and no law run (no law error counted) */
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_NONE, NULL), AOCS_OK);
    in = sample(2);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_STANDBY);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    assert_int_equal(out.law_status, AOCS_OK);
    assert_int_equal(out.counters.law_error, 0u);

    /* back to quat_pd with the identity target: NOMINAL at once from STANDBY */
    aocs_exec_target_t id = {aocs_quat_identity(), aocs_vec3_zero(), aocs_vec3_zero()};
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, &id), AOCS_OK);
    in = sample(3);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_vec3_close(out.u_cmd, pd_expected(in.q_BN, in.w_BN_B), TOL_TIGHT);
    assert_int_equal(out.counters.select_accepted, 3);
    assert_int_equal(out.counters.mode_transitions, 2);
}

static void test_crp_singular_goes_safe(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    cfg.law = AOCS_LAW_CRP_LINEAR;
    init_ok(&exec, &cfg);
    aocs_exec_input_t in = sample(1);
    in.q_BN = aocs_quat_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0)); /* 180 deg: qe4 = 0 */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.law_status, AOCS_ERR_CRP_SINGULAR);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(out.counters.law_error, 1);
    assert_within_limits(&out, LIM);
    assert_vec3_close(out.u_cmd, aocs_vec3_scale(w_test(), AOCS_R(-K_SAFE)), TOL_TIGHT);

    /* still singular: stays SAFE (the law is evaluated in the shadow) */
    for (uint32_t k = 2u; k < 2u + 2u * M_GOOD; ++k) {
        in = sample(k);
        in.q_BN = aocs_quat_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
        step_ok(&exec, &in, &out);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    }
    assert_int_equal(out.counters.law_error, 1u + 2u * M_GOOD);
}

static void test_init_validation(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in = sample(1);

    assert_int_equal(aocs_exec_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    base_config(&cfg);
    assert_int_equal(aocs_exec_init(&exec, NULL), AOCS_ERR_NULL_ARG);
    /* not initialised: error and a zero command */
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_ERR_NOT_INITIALISED);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    assert_int_equal(aocs_exec_select(&exec, AOCS_LAW_QUAT_PD, NULL), AOCS_ERR_NOT_INITIALISED);

    base_config(&cfg);
    cfg.period_s = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_RATE_INVALID);
    cfg.period_s = (real_t)NAN;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_RATE_INVALID);
    cfg.period_s = AOCS_R(-0.1);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_RATE_INVALID);

    base_config(&cfg);
    cfg.law = (aocs_law_id_t)42;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_UNKNOWN_LAW);

    base_config(&cfg);
    cfg.u_max_axis = aocs_vec3_zero();
    cfg.u_max_norm = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE); /* no limit at all */
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(0.0), AOCS_R(1.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE); /* mixed */
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), AOCS_R(-1.0), AOCS_R(1.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE);
    cfg.u_max_axis = aocs_vec3_make(AOCS_R(1.0), (real_t)NAN, AOCS_R(1.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg.u_max_axis = aocs_vec3_zero();
    cfg.u_max_norm = AOCS_R(-1.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_SAT_LIMIT_NOT_POSITIVE);
    cfg.u_max_norm = (real_t)INFINITY;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    cfg.u_max_norm = AOCS_R(2.0); /* norm limit only: valid */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);

    base_config(&cfg);
    cfg.k_safe = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
    cfg.k_safe = (real_t)NAN;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_PARAM_NOT_FINITE);
    base_config(&cfg);
    cfg.recover_good_samples = 0u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
    base_config(&cfg);
    cfg.missing_max_periods = 0u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
    base_config(&cfg);
    cfg.clock = AOCS_EXEC_CLOCK_REALTIME;
    cfg.stale_timeout_ns = 0u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
    base_config(&cfg);
    cfg.clock = (aocs_exec_clock_t)7;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_MODE_INVALID);

    base_config(&cfg);
    cfg.target.qd_DN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(2.0));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_TARGET_INVALID);

    /* the selected law's own init status */
    base_config(&cfg);
    cfg.laws.quat_pd.kp = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_GAIN_NOT_POSITIVE);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_ERR_NOT_INITIALISED);
    cfg.laws.quat_pd.kp = (real_t)NAN;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_ERR_PARAM_NOT_FINITE);

    /* law NONE needs no law config and starts in STANDBY */
    base_config(&cfg);
    cfg.law = AOCS_LAW_NONE;
    cfg.laws.quat_pd.kp = AOCS_R(0.0);
    init_ok(&exec, &cfg);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_STANDBY);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
}

/* An orbit sample as the SIL node fills it: only the orbit flag, no attitude (q zeroed). */
static aocs_exec_input_t orbit_sample(uint32_t tick)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = (uint64_t)tick * PERIOD_NS;
    in.valid = AOCS_EXEC_VALID_ORBIT;
    in.pos_m = aocs_vec3_make(AOCS_R(12.0), AOCS_R(-3.0), AOCS_R(0.5));
    in.vel_mps = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(-0.02));
    return in;
}

/*
 * Law none (STANDBY, control disabled): the executive does not know whether
 * it is fed attitude or orbit samples, so a sample valid under either rule
 * is good; one valid under neither is counted invalid with the verdict of
 * the rule it claims (orbit flag alone: orbit rule, else attitude rule).
 * With a law selected, the law's own rule alone applies (unchanged).
 */
static void test_standby_accepts_attitude_or_orbit_samples(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    base_config(&cfg);
    cfg.law = AOCS_LAW_NONE;
    init_ok(&exec, &cfg);

    aocs_exec_input_t in = orbit_sample(1);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_STANDBY);
    assert_int_equal(out.counters.invalid, 0);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);

    in = sample(2); /* an attitude sample is still good */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.invalid, 0);

    in = orbit_sample(3);
    in.vel_mps.v[1] = (real_t)NAN; /* claims orbit, not finite: the orbit rule's verdict */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_NOT_FINITE);
    assert_int_equal(out.counters.invalid, 1);

    in = orbit_sample(4);
    in.valid = 0u; /* no flag at all */
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_INVALID);
    assert_int_equal(out.counters.invalid, 2);

    in = sample(5);
    for (int i = 0; i < 4; ++i) {
        in.q_BN.q[i] = (real_t)(1.1 * (double)in.q_BN.q[i]); /* attitude flags, |q| = 1.1: attitude verdict */
    }
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_QUAT_NOT_UNIT);
    assert_int_equal(out.counters.invalid, 3);

    in = sample(6); /* non-unit q but a good orbit part with the orbit flag: valid as an orbit sample */
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
    in.pos_m = aocs_vec3_make(AOCS_R(1.0), AOCS_R(2.0), AOCS_R(3.0));
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.invalid, 3);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_STANDBY);

    /* an attitude law keeps the attitude rule: the orbit sample is invalid and goes SAFE */
    base_config(&cfg);
    init_ok(&exec, &cfg);
    in = orbit_sample(1);
    step_ok(&exec, &in, &out);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_INVALID);
    assert_int_equal(out.counters.invalid, 1);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
}

static void test_law_names(void **state)
{
    (void)state;
    /* by hand on purpose (docs/extending.md): a new row of laws.def must be added here too */
    static const char *const expected[] = {
        "none", "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc",
        "lqr_quat", "hinf", "mrp_sat", "mrp_sat_tanh", "orbit_lqr", "quat_pid", "lqr_quat_i",
    };
    const int listed = (int)(sizeof(expected) / sizeof(expected[0]));
    if (listed != (int)AOCS_LAW_COUNT) {
        fail_msg("laws.def has %d laws (with none), test_law_names lists %d: add the new law's name in id order",
                 (int)AOCS_LAW_COUNT, listed);
    }
    for (int i = 0; (i < (int)AOCS_LAW_COUNT) && (i < listed); ++i) {
        aocs_law_id_t id = AOCS_LAW_COUNT;
        assert_string_equal(aocs_law_name((aocs_law_id_t)i), expected[i]);
        assert_int_equal(aocs_law_from_name(expected[i], &id), AOCS_OK);
        assert_int_equal((int)id, i);
    }
    aocs_law_id_t id = AOCS_LAW_QUAT_PD;
    assert_int_equal(aocs_law_from_name("QUAT_PD", &id), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(aocs_law_from_name("quat_nlpd", &id), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(aocs_law_from_name("", &id), AOCS_ERR_UNKNOWN_LAW);
    assert_int_equal(id, AOCS_LAW_QUAT_PD); /* untouched */
    assert_int_equal(aocs_law_from_name(NULL, &id), AOCS_ERR_NULL_ARG);
    assert_string_equal(aocs_law_name(AOCS_LAW_COUNT), "unknown");
    assert_string_equal(aocs_exec_mode_name(AOCS_EXEC_MODE_SAFE), "safe");
    assert_int_equal(aocs_law_is_orbit(AOCS_LAW_ORBIT_LQR), 1);
    assert_int_equal(aocs_law_is_orbit(AOCS_LAW_QUAT_PD), 0);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_nominal_runs_selected_law),
        cmocka_unit_test(test_nan_sensor_enters_safe),
        cmocka_unit_test(test_safe_damping_is_saturated),
        cmocka_unit_test(test_validity_flags_and_non_unit_quaternion),
        cmocka_unit_test(test_stale_timestamp),
        cmocka_unit_test(test_missing_samples_counted),
        cmocka_unit_test(test_recovery_after_m_good_samples),
        cmocka_unit_test(test_select_in_safe_restarts_recovery),
        cmocka_unit_test(test_select_unknown_law_rejected),
        cmocka_unit_test(test_select_invalid_target_rejected),
        cmocka_unit_test(test_select_invalid_law_config_rejected),
        cmocka_unit_test(test_select_changes_law_target_and_mode),
        cmocka_unit_test(test_crp_singular_goes_safe),
        cmocka_unit_test(test_init_validation),
        cmocka_unit_test(test_standby_accepts_attitude_or_orbit_samples),
        cmocka_unit_test(test_law_names),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
