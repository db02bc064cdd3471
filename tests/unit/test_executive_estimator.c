/*
 * The executive with each estimator of estimation/determination.def
 * (docs/spec.md 5.6.11): lockstep, the POSIX HAL.
 *  - MEKF: a gyro + star-tracker stream: the law flies the filter's estimate
 *    (its command is the law's on q_BN_hat, w_hat), the estimate and its
 *    telemetry are in the output;
 *  - MEKF without a tracker sample yet: SAFE, damping on the gyro rate less
 *    the prior bias; NOMINAL after the recovery count once the filter holds
 *    an estimate;
 *  - MEKF: a hostile or gated tracker sample keeps NOMINAL (counted by the
 *    filter, not by the executive); no gyro, a NaN gyro or one beyond range
 *    is an invalid sample (SAFE, no rate to damp);
 *  - MEKF with the orbit law: the law runs on the acceptance's verdict (it
 *    uses no attitude);
 *  - MEKF: a gyro excluded whose switch to the gyroless model is refused
 *    latches SAFE;
 *  - passthrough: a gyro-only sample is invalid for it (its needs are
 *    ATT|RATE), its estimate telemetry is zero.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"

#define KP 1.0
#define KD 2.0
#define K_SAFE 3.0
#define LIM 0.5
#define M_GOOD 3u
#define PERIOD_NS 100000000ull

static void base_config(aocs_exec_config_t *cfg, aocs_det_id_t estimator)
{
    aocs_exec_config_default(cfg);
    cfg->period_s = AOCS_R(0.1);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(KP);
    cfg->laws.quat_pd.kd = AOCS_R(KD);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(LIM), AOCS_R(LIM), AOCS_R(LIM));
    cfg->k_safe = AOCS_R(K_SAFE);
    cfg->recover_good_samples = M_GOOD;
    cfg->determination.estimator = (uint32_t)estimator;
}

/* A body turning at a constant rate from a 10 deg offset (truth in double), as the gyro and the tracker see it. */
typedef struct {
    double q[4];
    double w[3];
} body_t;

static void body_init(body_t *b)
{
    const double h = 5.0 * 3.14159265358979323846 / 180.0;
    b->q[0] = 0.0;
    b->q[1] = 0.0;
    b->q[2] = sin(h);
    b->q[3] = cos(h);
    b->w[0] = 0.01;
    b->w[1] = -0.02;
    b->w[2] = 0.03;
}

static void body_step(body_t *t, double dt)
{
    const double r[3] = {t->w[0] * dt, t->w[1] * dt, t->w[2] * dt};
    const double th = sqrt((r[0] * r[0]) + (r[1] * r[1]) + (r[2] * r[2]));
    const double k = sin(0.5 * th) / th;
    const double a[4] = {k * r[0], k * r[1], k * r[2], cos(0.5 * th)};
    const double *b = t->q;
    double q[4];
    q[0] = ((a[3] * b[0]) + (b[3] * a[0])) - ((a[1] * b[2]) - (a[2] * b[1]));
    q[1] = ((a[3] * b[1]) + (b[3] * a[1])) - ((a[2] * b[0]) - (a[0] * b[2]));
    q[2] = ((a[3] * b[2]) + (b[3] * a[2])) - ((a[0] * b[1]) - (a[1] * b[0]));
    q[3] = (a[3] * b[3]) - ((a[0] * b[0]) + (a[1] * b[1]) + (a[2] * b[2]));
    for (int i = 0; i < 4; ++i) {
        t->q[i] = q[i];
    }
}

/* The MEKF's sample k: gyro (no bias) and, when st, a perfect tracker sample (identity mounting). */
static aocs_exec_input_t mekf_sample(const body_t *b, uint32_t k, int st)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = k;
    in.t_sensor_ns = (uint64_t)k * PERIOD_NS;
    in.valid = AOCS_EXEC_VALID_GYRO;
    in.gyro_w_B = aocs_vec3_make((real_t)b->w[0], (real_t)b->w[1], (real_t)b->w[2]);
    if (st != 0) {
        in.valid |= AOCS_EXEC_VALID_ST;
        in.st_q_SN = aocs_quat_make((real_t)b->q[0], (real_t)b->q[1], (real_t)b->q[2], (real_t)b->q[3]);
        in.st_t_meas_ns = in.t_sensor_ns;
    }
    return in;
}

/* SPEC 2.2 with qd = identity: u = -kp sign(q4) q_vec - kd w */
static aocs_vec3_t pd_expected(aocs_quat_t q, aocs_vec3_t w)
{
    double sg = ((double)q.q[3] >= 0.0) ? 1.0 : -1.0;
    return aocs_vec3_make((real_t)(-KP * sg * (double)q.q[0] - KD * (double)w.v[0]),
                          (real_t)(-KP * sg * (double)q.q[1] - KD * (double)w.v[1]),
                          (real_t)(-KP * sg * (double)q.q[2] - KD * (double)w.v[2]));
}

static void assert_vec_near(aocs_vec3_t a, aocs_vec3_t b, double tol)
{
    for (int i = 0; i < 3; ++i) {
        if (!(fabs((double)a.v[i] - (double)b.v[i]) <= tol)) {
            print_error("axis %d: %.9g vs %.9g (tol %.3g)\n", i, (double)a.v[i], (double)b.v[i], tol);
        }
        assert_true(fabs((double)a.v[i] - (double)b.v[i]) <= tol);
    }
}

static void test_mekf_law_flies_the_estimate(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    body_t b;
    base_config(&cfg, AOCS_DET_MEKF);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(exec.accept.needs, AOCS_EXEC_VALID_GYRO);
    body_init(&b);
    for (uint32_t k = 0u; k < 100u; ++k) {
        /* the tracker every 5th period; the commanded body is not moved (open loop) */
        aocs_exec_input_t in = mekf_sample(&b, k, ((k % 5u) == 0u) ? 1 : 0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        assert_int_equal(out.law_status, AOCS_OK);
        assert_int_equal(out.estimate.status, AOCS_OK);
        assert_int_equal(out.estimate.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
        /* the law's command is the law on the estimate (the estimate, not a measured q, drives it) */
        assert_vec_near(out.u_unsat, pd_expected(out.estimate.q_BN, out.estimate.w_BN_B), 1.0e-6);
        /* ... which is the truth within the filter's accuracy */
        assert_vec_near(out.estimate.w_BN_B, aocs_vec3_make((real_t)b.w[0], (real_t)b.w[1], (real_t)b.w[2]), 1.0e-5);
        assert_true(fabs((double)out.estimate.q_BN.q[2] - b.q[2]) < 1.0e-4);
        body_step(&b, 0.1);
    }
    assert_int_equal(out.estimate.n_st_used, 19u); /* 20 samples: the first started the filter */
    assert_int_equal(out.estimate.st_status, AOCS_ERR_INPUT_MISSING);
    assert_true(out.estimate.p_upper[0] > AOCS_R(0.0));
    assert_int_equal(out.counters.invalid, 0u);
    assert_int_equal(out.counters.mode_transitions, 0u);
}

static void test_mekf_waits_in_safe_damping_the_gyro_rate(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    body_t b;
    uint32_t k;
    base_config(&cfg, AOCS_DET_MEKF);
    cfg.determination.mekf.bias0_B_radps = aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(0.0), AOCS_R(-1.0e-3));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    body_init(&b);
    for (k = 0u; k < 4u; ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, 0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK); /* the sample is good: the filter has no attitude yet */
        assert_int_equal(out.estimate.status, AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        /* u = -k_safe (gyro - bias prior) */
        assert_vec_near(out.u_unsat, aocs_vec3_scale(aocs_vec3_sub(in.gyro_w_B, cfg.determination.mekf.bias0_B_radps),
                                                     -AOCS_R(K_SAFE)),
                        1.0e-6);
        body_step(&b, 0.1);
    }
    /* the first tracker sample: an estimate, then M good samples back to NOMINAL */
    for (uint32_t n = 1u; n <= M_GOOD; ++n, ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, (n == 1u) ? 1 : 0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.estimate.status, AOCS_OK);
        assert_int_equal(out.mode, (n < M_GOOD) ? AOCS_EXEC_MODE_SAFE : AOCS_EXEC_MODE_NOMINAL);
        body_step(&b, 0.1);
    }
    assert_int_equal(out.counters.invalid, 0u);
}

static void test_mekf_bad_tracker_sample_keeps_nominal_bad_gyro_does_not(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    body_t b;
    uint32_t k;
    const real_t nan_value = (real_t)NAN;
    base_config(&cfg, AOCS_DET_MEKF);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    body_init(&b);
    for (k = 0u; k < 20u; ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, ((k % 5u) == 0u) ? 1 : 0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        body_step(&b, 0.1);
    }
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    /* hostile tracker samples: NaN, non-unit, from the future; then a well-formed wrong one (gated) */
    for (uint32_t c = 0u; c < 4u; ++c, ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, 1);
        if (c == 0u) {
            in.st_q_SN.q[0] = nan_value;
        } else if (c == 1u) {
            in.st_q_SN.q[3] = AOCS_R(2.0);
        } else if (c == 2u) {
            in.st_t_meas_ns = in.t_sensor_ns + PERIOD_NS;
        } else {
            in.st_q_SN = aocs_quat_mul(aocs_quat_make(AOCS_R(0.0871557427), AOCS_R(0.0), AOCS_R(0.0),
                                                      AOCS_R(0.9961946981)), in.st_q_SN);
        }
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        assert_int_not_equal(out.estimate.st_status, AOCS_OK);
        assert_int_equal(out.estimate.n_st_hostile, (c < 3u) ? (c + 1u) : 3u);
        assert_int_equal(out.estimate.n_st_gated, (c < 3u) ? 0u : 1u);
        body_step(&b, 0.1);
    }
    assert_int_equal(out.counters.invalid, 0u);
    /* no gyro: an invalid sample, SAFE with no rate to damp */
    {
        aocs_exec_input_t in = mekf_sample(&b, k, 1);
        in.valid = AOCS_EXEC_VALID_ST | AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        in.q_BN = aocs_quat_identity();
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_INVALID);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        assert_vec_near(out.u_unsat, aocs_vec3_zero(), 0.0);
        assert_int_equal(out.counters.invalid, 1u);
        ++k;
        body_step(&b, 0.1);
    }
    /* a NaN gyro, a gyro beyond range */
    {
        aocs_exec_input_t in = mekf_sample(&b, k, 0);
        in.gyro_w_B.v[1] = nan_value;
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_NOT_FINITE);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
        assert_true(aocs_vec3_is_finite(out.u_cmd) != 0);
        ++k;
        body_step(&b, 0.1);
        in = mekf_sample(&b, k, 0);
        in.gyro_w_B.v[0] = AOCS_R(200.0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_ERR_GYRO_RANGE);
        assert_int_equal(out.counters.invalid, 3u);
        ++k;
        body_step(&b, 0.1);
    }
    /* good samples again: the filter kept its estimate, NOMINAL after the recovery count */
    for (uint32_t n = 1u; n <= M_GOOD; ++n, ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, 0);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.estimate.status, AOCS_OK);
        body_step(&b, 0.1);
    }
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
}

/* docs/spec.md 5.6.12: the estimator may go on without the gyro only when the MEKF has a gyroless model
 * (mekf.gyroless_torque_sigma_nm > 0) and the configured inertia is one; else a gyro exclusion is SAFE. */
static void test_gyroless_capable_only_with_a_model_and_an_inertia(void **state)
{
    (void)state;
    static const aocs_det_id_t est[4] = {AOCS_DET_MEKF, AOCS_DET_MEKF, AOCS_DET_MEKF, AOCS_DET_PASSTHROUGH};
    static const double sigma_nm[4] = {0.0, 1.0e-4, 1.0e-4, 1.0e-4};
    static const int with_inertia[4] = {1, 1, 0, 1};
    static const int capable[4] = {0, 1, 0, 0}; /* no model; both; no inertia (zero); the model is the MEKF's */
    for (int c = 0; c < 4; ++c) {
        aocs_exec_config_t cfg;
        aocs_exec_t exec;
        base_config(&cfg, est[c]);
        cfg.determination.mekf.gyroless_torque_sigma_nm = (real_t)sigma_nm[c];
        (void)memset(&cfg.guidance.slew.inertia_kgm2, 0, sizeof(cfg.guidance.slew.inertia_kgm2));
        if (with_inertia[c] != 0) {
            for (int i = 0; i < 3; ++i) {
                cfg.guidance.slew.inertia_kgm2.m[i][i] = (real_t)(10.0 * (double)(i + 1));
            }
        }
        assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
        if (exec.gyroless_capable != capable[c]) {
            print_error("case %d: gyroless_capable %d\n", c, exec.gyroless_capable);
        }
        assert_int_equal(exec.gyroless_capable, capable[c]);
    }
}

/* docs/spec.md 5.6.12: a gyro excluded when the estimator was to go on without it, but whose switch to the
 * gyroless model the estimator refuses, latches SAFE (nothing is left to propagate on, as with no gyroless
 * model at all). aocs_exec_init cannot produce that refusal: it sets gyroless_capable only when the MEKF has a
 * gyroless model and the inertia is one, the two things aocs_det_set_gyroless checks. So the test breaks that
 * promise by hand, the one way into the guard: a MEKF without a gyroless model (gyroless_torque_sigma_nm 0)
 * and gyroless_capable forced to 1. Samples of a gyro with noise on every axis (1e-6 rad/s) keep NOMINAL; then
 * its y axis sticks: the 10th identical y sample (fdir.gyro_stuck_samples) raises gyro_stuck and
 * gyro_excluded (axis 1) and estimator_gyroless (fault management was told the estimator could go on), the
 * switch fails, and from the next step the executive is in SAFE and stays there over 20 samples (beyond the
 * recovery count of 3) though the samples and the filter's estimate are good: safe_entered (value AOCS_OK:
 * neither the input nor the estimator failed) and no safe_left. */
static void test_a_refused_switch_to_gyroless_latches_safe(void **state)
{
    (void)state;
    static const aocs_evt_id_t expected[4] = {AOCS_EVT_GYRO_STUCK, AOCS_EVT_GYRO_EXCLUDED,
                                              AOCS_EVT_ESTIMATOR_GYROLESS, AOCS_EVT_SAFE_ENTERED};
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    test_rng_t rng = {2718u};
    body_t b;
    uint32_t k = 0u;
    uint32_t k_excluded = 0u;
    real_t y_stuck = AOCS_R(0.0);
    base_config(&cfg, AOCS_DET_MEKF);
    cfg.determination.mekf.gyroless_torque_sigma_nm = AOCS_R(0.0);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(exec.gyroless_capable, 0);
    exec.gyroless_capable = 1; /* the broken promise */
    body_init(&b);
    for (; k < 30u; ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, ((k % 5u) == 0u) ? 1 : 0);
        in.gyro_w_B = aocs_vec3_add(in.gyro_w_B, test_random_vec3(&rng, 1.0e-6));
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
        body_step(&b, 0.1);
    }
    assert_int_equal(aocs_evlog_count(aocs_exec_events(&exec)), 0u);
    /* y stuck from the first of these samples: the 10th is the 10th identical one */
    for (uint32_t n = 1u; n <= 30u; ++n, ++k) {
        aocs_exec_input_t in = mekf_sample(&b, k, ((k % 5u) == 0u) ? 1 : 0);
        in.gyro_w_B = aocs_vec3_add(in.gyro_w_B, test_random_vec3(&rng, 1.0e-6));
        if (n == 1u) {
            y_stuck = in.gyro_w_B.v[1];
        }
        in.gyro_w_B.v[1] = y_stuck;
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK);
        assert_int_equal(out.estimate.status, AOCS_OK);
        if (n == 10u) {
            k_excluded = k;
        }
        /* the latch holds the mode from the step after the exclusion */
        assert_int_equal(out.mode, (n <= 10u) ? AOCS_EXEC_MODE_NOMINAL : AOCS_EXEC_MODE_SAFE);
        body_step(&b, 0.1);
    }
    {
        const aocs_evlog_t *log = aocs_exec_events(&exec);
        aocs_event_t e;
        uint32_t seq = 0u;
        assert_int_equal(aocs_evlog_count(log), 4u);
        for (uint32_t i = 0u; i < 4u; ++i) {
            assert_int_equal(aocs_evlog_next(log, seq, &e, NULL), AOCS_OK);
            assert_int_equal(e.id, expected[i]);
            assert_int_equal(e.t_ns, (uint64_t)((i < 3u) ? k_excluded : (k_excluded + 1u)) * PERIOD_NS);
            if (i < 2u) {
                assert_int_equal(e.unit, 1);
            }
            seq = e.seq;
        }
        assert_close(e.value, (double)AOCS_OK, 0.0); /* safe_entered: no input or estimator fault */
    }
}

static void test_passthrough_needs_a_measured_attitude(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    body_t b;
    base_config(&cfg, AOCS_DET_PASSTHROUGH);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    assert_int_equal(exec.accept.needs, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    body_init(&b);
    {
        aocs_exec_input_t in = mekf_sample(&b, 0u, 1);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_INVALID);
        assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    }
    {
        aocs_exec_input_t in = mekf_sample(&b, 1u, 0);
        in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        in.q_BN = aocs_quat_make((real_t)b.q[0], (real_t)b.q[1], (real_t)b.q[2], (real_t)b.q[3]);
        in.w_BN_B = in.gyro_w_B;
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.input_status, AOCS_OK);
        assert_memory_equal(&out.estimate.q_BN, &in.q_BN, sizeof(in.q_BN));
        /* no filter: zero telemetry */
        for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
            assert_true(!(out.estimate.p_upper[i] < AOCS_R(0.0)) && !(out.estimate.p_upper[i] > AOCS_R(0.0)));
        }
        assert_int_equal(out.estimate.n_st_used, 0u);
        assert_int_equal(out.estimate.st_status, AOCS_ERR_INPUT_MISSING);
    }
}

static void test_orbit_law_runs_on_the_acceptance_verdict(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_input_t in;
    base_config(&cfg, AOCS_DET_MEKF);
    cfg.law = AOCS_LAW_ORBIT_LQR;
    for (uint32_t i = 0u; i < 3u; ++i) {
        cfg.laws.orbit_lqr.k[i][i] = AOCS_R(1.0e-1);
        cfg.laws.orbit_lqr.k[i][i + 3u] = AOCS_R(1.0e-3);
    }
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    memset(&in, 0, sizeof(in));
    in.valid = AOCS_EXEC_VALID_ORBIT;
    in.pos_m = aocs_vec3_make(AOCS_R(10.0), AOCS_R(0.0), AOCS_R(0.0));
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_not_equal(out.estimate.status, AOCS_OK); /* no gyro: the MEKF has nothing */
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(out.law_status, AOCS_OK);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_mekf_law_flies_the_estimate),
        cmocka_unit_test(test_mekf_waits_in_safe_damping_the_gyro_rate),
        cmocka_unit_test(test_mekf_bad_tracker_sample_keeps_nominal_bad_gyro_does_not),
        cmocka_unit_test(test_gyroless_capable_only_with_a_model_and_an_inertia),
        cmocka_unit_test(test_a_refused_switch_to_gyroless_latches_safe),
        cmocka_unit_test(test_passthrough_needs_a_measured_attitude),
        cmocka_unit_test(test_orbit_law_runs_on_the_acceptance_verdict),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
