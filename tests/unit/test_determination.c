/*
 * Attitude-determination stage alone (firmware/src/estimation/determination.c,
 * passthrough.c; aocs/estimation/determination.h):
 *  - every row of determination.def has a distinct non-empty name, inits from
 *    its configuration fields' defaults and resets; an estimator out of range
 *    is AOCS_ERR_ESTIMATOR_UNKNOWN;
 *  - PASSTHROUGH gives the measured q and w bit for bit, the attitude and rate
 *    flags of the sample, and the acceptance's verdict as its status (the
 *    measured values stay: SAFE damps with the rate of a stale sample);
 *  - MEKF (mekf_stage.c): inits from the configuration fields' defaults,
 *    which are aocs_mekf_config_default's; waits for its first tracker
 *    sample (AOCS_ERR_MEKF_NO_ATTITUDE, the gyro rate less the prior bias
 *    for SAFE); on a constant-rate truth with a perfect tracker the estimate
 *    converges (attitude, rate, bias) and the telemetry is the filter's (P's
 *    upper triangle, counts); a hostile tracker sample (NaN, non-unit,
 *    future, stale, too old) is counted and the estimate stays usable; no
 *    NaN or Inf out whatever comes in (NaN/Inf gyro and tracker, non-unit,
 *    times out of order, rejected samples);
 *  - not initialised / NULL arguments: an error and an unusable output.
 */
#include "test_support.h"

#include <math.h>
#include <string.h>

#include "aocs/executive.h"

static aocs_exec_input_t sample(void)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = 7u;
    in.t_sensor_ns = 800000000u;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ORBIT;
    in.q_BN = aocs_quat_make(AOCS_R(0.1), AOCS_R(-0.2), AOCS_R(0.3), AOCS_SQRT(AOCS_R(1.0) - AOCS_R(0.14)));
    in.w_BN_B = aocs_vec3_make(AOCS_R(1.0e-3), AOCS_R(-2.5e-4), AOCS_R(7.0e-5));
    return in;
}

/* The stage's configuration with every field at its DEFAULT (config_fields.def) and the given estimator. */
static aocs_det_config_t default_config(uint32_t estimator)
{
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    ecfg.determination.estimator = estimator;
    return ecfg.determination;
}

static void test_every_row_has_a_name_and_inits(void **state)
{
    (void)state;
    for (int i = 0; i < (int)AOCS_DET_COUNT; ++i) {
        aocs_det_t det;
        /* every estimator inits from its configuration fields' defaults */
        aocs_det_config_t cfg = default_config((uint32_t)i);
        const char *name = aocs_det_name((aocs_det_id_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_det_name((aocs_det_id_t)j));
        }
        assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
        assert_int_equal((int)det.id, i);
        assert_int_equal(aocs_det_reset(&det), AOCS_OK);
    }
    assert_string_equal(aocs_det_name(AOCS_DET_PASSTHROUGH), "passthrough");
    assert_string_equal(aocs_det_name(AOCS_DET_COUNT), "unknown");
}

static void test_unknown_estimator_is_refused(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_COUNT);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_ERR_ESTIMATOR_UNKNOWN);
    assert_int_equal(det.initialised, 0);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(out.status, AOCS_ERR_NOT_INITIALISED);
    assert_int_equal(out.valid, 0u);
    assert_int_equal(aocs_det_reset(&det), AOCS_ERR_NOT_INITIALISED);
    /* the default configuration is the pass-through */
    aocs_exec_config_t ecfg;
    aocs_exec_config_default(&ecfg);
    assert_int_equal(ecfg.determination.estimator, (uint32_t)AOCS_DET_PASSTHROUGH);
}

static void test_passthrough_gives_the_measurement_bit_for_bit(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_PASSTHROUGH);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_OK);
    assert_memory_equal(&out.q_BN, &in.q_BN, sizeof(in.q_BN));
    assert_memory_equal(&out.w_BN_B, &in.w_BN_B, sizeof(in.w_BN_B));
    assert_int_equal(out.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE); /* no orbit flag: not its estimate */
    assert_int_equal(out.status, AOCS_OK);
    /* a rejected sample: its verdict, the measured values kept */
    in.valid = AOCS_EXEC_VALID_RATE;
    assert_int_equal(aocs_det_step(&det, &in, AOCS_ERR_INPUT_STALE, AOCS_R(0.1), &out), AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.valid, AOCS_EXEC_VALID_RATE);
    assert_memory_equal(&out.w_BN_B, &in.w_BN_B, sizeof(in.w_BN_B));
    assert_int_equal(det.states.passthrough.steps, 2u);
    assert_int_equal(aocs_det_reset(&det), AOCS_OK);
    assert_int_equal(det.states.passthrough.steps, 0u);
}

/* ---- MEKF ---- */

#define MK_T_NS 100000000ull /* 0.1 s */
#define MK_DT AOCS_R(0.1)
#define MK_RAD_TO_ARCSEC 206264.80624709636

/* A constant-rate truth (double in both builds): q(t_k + dt) = dq(w dt) (x) q(t_k), the filter's convention. */
typedef struct {
    double q[4];
    double w[3];
    double bias[3];
} mk_truth_t;

static void mk_truth_init(mk_truth_t *t)
{
    const double n = sqrt(0.04 + 0.09 + 0.01 + 0.86);
    t->q[0] = 0.2 / n;
    t->q[1] = -0.3 / n;
    t->q[2] = 0.1 / n;
    t->q[3] = sqrt(0.86) / n;
    t->w[0] = 1.0e-3;
    t->w[1] = -2.0e-3;
    t->w[2] = 5.0e-4;
    t->bias[0] = 3.0e-6;
    t->bias[1] = -2.0e-6;
    t->bias[2] = 4.0e-6;
}

static void mk_truth_step(mk_truth_t *t, double dt)
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

static aocs_quat_t mk_truth_q(const mk_truth_t *t)
{
    return aocs_quat_make((real_t)t->q[0], (real_t)t->q[1], (real_t)t->q[2], (real_t)t->q[3]);
}

/* Sample k of the stream: the gyro (truth + bias), a perfect tracker sample when st (identity mounting). */
static aocs_exec_input_t mk_sample(const mk_truth_t *t, uint32_t k, int st)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = k;
    in.t_sensor_ns = (uint64_t)k * MK_T_NS;
    in.valid = AOCS_EXEC_VALID_GYRO;
    in.gyro_w_B = aocs_vec3_make((real_t)(t->w[0] + t->bias[0]), (real_t)(t->w[1] + t->bias[1]),
                                 (real_t)(t->w[2] + t->bias[2]));
    if (st != 0) {
        in.valid |= AOCS_EXEC_VALID_ST;
        in.st_q_SN = mk_truth_q(t);
        in.st_t_meas_ns = in.t_sensor_ns;
    }
    return in;
}

static double mk_angle_arcsec(aocs_quat_t a, const mk_truth_t *t)
{
    const aocs_quat_t e = aocs_quat_mul(a, aocs_quat_conj(mk_truth_q(t)));
    const double v = sqrt((double)((e.q[0] * e.q[0]) + (e.q[1] * e.q[1]) + (e.q[2] * e.q[2])));
    return 2.0 * asin(v < 1.0 ? v : 1.0) * MK_RAD_TO_ARCSEC;
}

/* Every real of the output finite. */
static int mk_output_finite(const aocs_det_output_t *out)
{
    int ok = (aocs_quat_is_finite(out->q_BN) != 0) && (aocs_vec3_is_finite(out->w_BN_B) != 0) &&
             (aocs_vec3_is_finite(out->bias_B_radps) != 0);
    for (uint32_t i = 0u; i < AOCS_EST_P_UPPER_COUNT; ++i) {
        ok = ok && AOCS_IS_FINITE(out->p_upper[i]);
    }
    return ok;
}

static void mk_init(aocs_det_t *det)
{
    aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_MEKF);
    assert_int_equal(aocs_det_init(det, &cfg), AOCS_OK);
}

static void test_mekf_inits_from_the_filter_defaults(void **state)
{
    (void)state;
    aocs_mekf_config_t ref;
    aocs_det_t det;
    const aocs_det_config_t cfg = default_config((uint32_t)AOCS_DET_MEKF);
    aocs_mekf_config_default(&ref);
    /* the DEFAULT column of the mekf.* rows (config_fields.def) is aocs_mekf_config_default, bit for bit */
    assert_memory_equal(&cfg.mekf, &ref, sizeof(ref));
    assert_string_equal(aocs_det_name(AOCS_DET_MEKF), "mekf");
    assert_int_equal(aocs_det_needs(AOCS_DET_MEKF), AOCS_EXEC_VALID_GYRO);
    assert_int_equal(aocs_det_needs(AOCS_DET_PASSTHROUGH), AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    mk_init(&det);
    assert_int_equal(det.id, AOCS_DET_MEKF);
    assert_int_equal(det.states.mekf.started, 0u);
    /* an invalid filter configuration is the filter's own status */
    {
        aocs_det_config_t bad = cfg;
        bad.mekf.gate_chi2 = AOCS_R(0.0);
        assert_int_equal(aocs_det_init(&det, &bad), AOCS_ERR_MEKF_GATE_INVALID);
        bad = cfg;
        bad.mekf.q_SB = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
        assert_int_equal(aocs_det_init(&det, &bad), AOCS_ERR_QUAT_NOT_UNIT);
    }
}

static void test_mekf_waits_for_a_tracker_sample_then_converges(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_output_t out;
    mk_truth_t truth;
    uint32_t used = 0u;
    uint32_t k;
    mk_truth_init(&truth);
    mk_init(&det);
    /* gyro only: no estimate yet, the rate (gyro less the prior bias, 0) for SAFE */
    for (k = 0u; k < 5u; ++k) {
        aocs_exec_input_t in = mk_sample(&truth, k, 0);
        assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_int_equal(out.status, AOCS_ERR_MEKF_NO_ATTITUDE);
        assert_int_equal(out.valid, AOCS_EXEC_VALID_RATE);
        assert_memory_equal(&out.w_BN_B, &in.gyro_w_B, sizeof(in.gyro_w_B));
        assert_int_equal(out.st_status, AOCS_ERR_INPUT_MISSING);
        assert_true(mk_output_finite(&out));
        mk_truth_step(&truth, 1.0e-1);
    }
    /* a tracker sample every second (1 Hz of a 10 Hz loop), 600 s; the first starts the filter, the others
     * update it (n_st_used counts the updates) */
    for (; k < 6005u; ++k) {
        const int st = ((k % 10u) == 5u) ? 1 : 0;
        aocs_exec_input_t in = mk_sample(&truth, k, st);
        assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
        assert_int_equal(out.status, AOCS_OK);
        assert_int_equal(out.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
        assert_int_equal(out.st_status, (st != 0) ? AOCS_OK : AOCS_ERR_INPUT_MISSING);
        if ((st != 0) && (k > 5u)) {
            ++used;
        }
        assert_int_equal(out.n_st_used, used);
        assert_true(mk_output_finite(&out));
        if (k < 6004u) {
            mk_truth_step(&truth, 1.0e-1);
        }
    }
    /* converged: attitude within 2 arcsec, rate and bias within 2e-7 rad/s (the truth bias 3e-6 .. 4e-6) */
    assert_true(mk_angle_arcsec(out.q_BN, &truth) < 2.0);
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs((double)out.w_BN_B.v[i] - truth.w[i]) < 2.0e-7);
        assert_true(fabs((double)out.bias_B_radps.v[i] - truth.bias[i]) < 2.0e-7);
    }
    /* the telemetry is the filter's covariance, upper triangle row by row */
    assert_true(out.p_upper[0] > AOCS_R(0.0));
    {
        const aocs_mekf_t *f = &det.states.mekf;
        uint32_t n = 0u;
        for (int i = 0; i < 6; ++i) {
            for (int j = i; j < 6; ++j) {
                assert_memory_equal(&out.p_upper[n], &f->P.m[i][j], sizeof(real_t));
                ++n;
            }
        }
        assert_int_equal(n, AOCS_EST_P_UPPER_COUNT);
    }
    assert_int_equal(out.n_st_gated, 0u);
    assert_int_equal(out.n_st_hostile, 0u);
    assert_int_equal(out.n_restarts, 0u);
}

/* A converged filter (the sequence above, 120 s) for the tests below; the truth at the last sample. */
static uint32_t mk_converge(aocs_det_t *det, mk_truth_t *truth)
{
    aocs_det_output_t out;
    uint32_t k;
    mk_truth_init(truth);
    mk_init(det);
    for (k = 0u; k < 1200u; ++k) {
        aocs_exec_input_t in = mk_sample(truth, k, ((k % 10u) == 0u) ? 1 : 0);
        assert_int_equal(aocs_det_step(det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
        mk_truth_step(truth, 1.0e-1);
    }
    return k;
}

static void test_mekf_hostile_tracker_sample_is_counted_not_fatal(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_output_t out;
    mk_truth_t truth;
    uint32_t k = mk_converge(&det, &truth);
    const real_t nan_value = (real_t)NAN;
    const aocs_status_t expect[5] = {AOCS_ERR_INPUT_NOT_FINITE, AOCS_ERR_QUAT_NOT_UNIT, AOCS_ERR_MEKF_MEAS_FUTURE,
                                     AOCS_ERR_INPUT_STALE, AOCS_ERR_INPUT_STALE};
    for (uint32_t c = 0u; c < 5u; ++c) {
        aocs_exec_input_t in = mk_sample(&truth, k, 1);
        if (c == 0u) {
            in.st_q_SN.q[2] = nan_value;
        } else if (c == 1u) {
            in.st_q_SN = aocs_quat_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.9));
        } else if (c == 2u) {
            in.st_t_meas_ns = in.t_sensor_ns + 1u;
        } else if (c == 3u) {
            in.st_t_meas_ns = det.states.mekf.t_last_meas_ns; /* not after the last one used */
        } else {
            in.st_t_meas_ns = 0u; /* long ago (before the history too: the staleness is found first) */
        }
        assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
        assert_int_equal(out.status, AOCS_OK);
        assert_int_equal(out.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
        assert_int_equal(out.st_status, expect[c]);
        assert_int_equal(out.n_st_hostile, c + 1u);
        assert_true(mk_output_finite(&out));
        assert_true(mk_angle_arcsec(out.q_BN, &truth) < 5.0);
        mk_truth_step(&truth, 1.0e-1);
        ++k;
    }
    /* a wrong attitude, well formed: the gate rejects it, counted apart */
    {
        aocs_exec_input_t in = mk_sample(&truth, k, 1);
        in.st_q_SN = aocs_quat_mul(aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0871557427), AOCS_R(0.0), AOCS_R(0.9961946981)),
                                   in.st_q_SN); /* 10 deg off */
        assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
        assert_int_equal(out.st_status, AOCS_ERR_MEKF_GATED);
        assert_int_equal(out.n_st_gated, 1u);
        assert_int_equal(out.n_st_hostile, 5u);
        assert_true(mk_angle_arcsec(out.q_BN, &truth) < 5.0);
    }
}

static void test_mekf_rejected_sample_does_not_move_the_filter(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_output_t out;
    mk_truth_t truth;
    uint32_t k = mk_converge(&det, &truth);
    const uint64_t t_filter = det.states.mekf.t_ns;
    aocs_exec_input_t in = mk_sample(&truth, k, 1);
    /* the acceptance's verdict stands; the filter keeps its time; SAFE still gets the gyro less the bias */
    assert_int_equal(aocs_det_step(&det, &in, AOCS_ERR_INPUT_STALE, MK_DT, &out), AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.valid, AOCS_EXEC_VALID_RATE);
    assert_int_equal(out.st_status, AOCS_ERR_INPUT_STALE); /* offered, not looked at */
    assert_int_equal(det.states.mekf.t_ns, t_filter);
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs((double)out.w_BN_B.v[i] - truth.w[i]) < 2.0e-6);
    }
    /* no gyro: no rate at all */
    in.valid = AOCS_EXEC_VALID_ST;
    assert_int_equal(aocs_det_step(&det, &in, AOCS_ERR_INPUT_INVALID, MK_DT, &out), AOCS_ERR_INPUT_INVALID);
    assert_int_equal(out.valid, 0u);
    assert_true(mk_output_finite(&out));
    /* accepted without a gyro (an orbit law's sample): not the filter's */
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_ERR_INPUT_INVALID);
    assert_int_equal(det.states.mekf.t_ns, t_filter);
    /* the next good sample goes on */
    in = mk_sample(&truth, k, 0);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
    /* a clock that restarts (the acceptance resynchronised to it): the filter starts again from the sample */
    in = mk_sample(&truth, 3u, 1);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_OK);
    assert_int_equal(out.n_restarts, 1u);
    assert_int_equal(det.states.mekf.t_ns, 3u * MK_T_NS);
    assert_true(mk_angle_arcsec(out.q_BN, &truth) < 1.0);
    /* reset: waiting again */
    assert_int_equal(aocs_det_reset(&det), AOCS_OK);
    in = mk_sample(&truth, 4u, 0);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, MK_DT, &out), AOCS_ERR_MEKF_NO_ATTITUDE);
}

/* A deterministic generator of hostile inputs (LCG), both precisions. */
static uint32_t mk_lcg(uint32_t *s)
{
    *s = (*s * 1664525u) + 1013904223u;
    return *s >> 8;
}

static real_t mk_hostile_real(uint32_t *s)
{
    static const double pool[10] = {0.0, 1.0, -1.0, 1.0e-3, -0.5, 150.0, 1.0e30, -1.0e-30, 0.7071067811865476,
                                    2.0};
    const uint32_t r = mk_lcg(s) % 13u;
    real_t v = AOCS_R(0.0);
    if (r < 10u) {
        v = (real_t)pool[r];
    } else if (r == 10u) {
        v = (real_t)NAN;
    } else if (r == 11u) {
        v = (real_t)INFINITY;
    } else {
        v = -(real_t)INFINITY;
    }
    return v;
}

static void test_mekf_no_nan_out_for_any_input(void **state)
{
    (void)state;
    static const aocs_status_t verdicts[4] = {AOCS_OK, AOCS_OK, AOCS_ERR_INPUT_STALE, AOCS_ERR_INPUT_INVALID};
    aocs_det_t det;
    aocs_det_output_t out;
    mk_truth_t truth;
    uint32_t seed = 12345u;
    uint32_t k = mk_converge(&det, &truth);
    for (uint32_t n = 0u; n < 20000u; ++n) {
        aocs_exec_input_t in = mk_sample(&truth, k, 1);
        const uint32_t what = mk_lcg(&seed) % 8u;
        if ((what & 1u) != 0u) {
            in.gyro_w_B.v[mk_lcg(&seed) % 3u] = mk_hostile_real(&seed);
        }
        if ((what & 2u) != 0u) {
            in.st_q_SN.q[mk_lcg(&seed) % 4u] = mk_hostile_real(&seed);
        }
        if ((what & 4u) != 0u) {
            /* times out of order: the past, the future, a far jump */
            const uint32_t t = mk_lcg(&seed) % 4u;
            in.t_sensor_ns = (t == 0u) ? 0u : ((t == 1u) ? (in.t_sensor_ns + 3600000000000ull) : in.t_sensor_ns);
            in.st_t_meas_ns = (t == 2u) ? (in.t_sensor_ns + MK_T_NS) : (in.t_sensor_ns - (uint64_t)(t * MK_T_NS));
        }
        in.valid = mk_lcg(&seed) & 0x1Fu;
        {
            const aocs_status_t v = verdicts[mk_lcg(&seed) % 4u];
            const aocs_status_t st = aocs_det_step(&det, &in, v, MK_DT, &out);
            assert_int_equal(st, out.status);
            assert_true(mk_output_finite(&out));
            if (out.status == AOCS_OK) {
                assert_int_equal(out.valid, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
                assert_true(AOCS_FABS(aocs_quat_norm(out.q_BN) - AOCS_R(1.0)) < AOCS_R(1.0e-4));
            } else {
                assert_int_equal(out.valid & AOCS_EXEC_VALID_ATT, 0u);
            }
        }
        if ((n % 7u) == 0u) {
            mk_truth_step(&truth, 1.0e-1);
            ++k;
        }
    }
}

static void test_null_arguments(void **state)
{
    (void)state;
    aocs_det_t det;
    aocs_det_config_t cfg = default_config(0u);
    aocs_det_output_t out;
    aocs_exec_input_t in = sample();
    assert_int_equal(aocs_det_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_init(&det, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
    assert_int_equal(aocs_det_step(&det, NULL, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NULL_ARG);
    assert_int_equal(out.status, AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_step(NULL, &in, AOCS_OK, AOCS_R(0.1), &out), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_step(&det, &in, AOCS_OK, AOCS_R(0.1), NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_reset(NULL), AOCS_ERR_NULL_ARG);
    /* the rows' own init, called directly: either argument NULL is refused */
    aocs_det_passthrough_state_t pt;
    assert_int_equal(aocs_det_passthrough_init(NULL, &cfg), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_passthrough_init(&pt, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_det_passthrough_init(&pt, &cfg), AOCS_OK);
}

/* The fault-management entry points the header calls no-ops "on NULL and for an estimator without one": on
 * NULL nothing is dereferenced (the answers 0 / AOCS_ERR_NULL_ARG), and the pass-through estimator is left
 * byte for byte. */
static void test_fault_management_hooks_on_null_and_on_a_filterless_estimator(void **state)
{
    (void)state;
    const aocs_mat3_t j = aocs_mat3_identity();
    const aocs_vec3_t tau = aocs_vec3_make(AOCS_R(0.1), AOCS_R(0.0), AOCS_R(0.0));
    aocs_det_set_st_excluded(NULL, 1u);
    aocs_det_set_st_noise_scale(NULL, AOCS_R(4.0));
    aocs_det_reinflate_bias(NULL);
    aocs_det_set_torque(NULL, tau, tau);
    assert_true(aocs_det_gyro_rrw(NULL) <= AOCS_R(0.0));
    assert_int_equal(aocs_det_gyroless_capable(NULL), 0u);
    assert_int_equal(aocs_det_is_gyroless(NULL), 0u);
    assert_int_equal(aocs_det_set_gyroless(NULL, &j), AOCS_ERR_NULL_ARG);

    aocs_det_t det;
    aocs_det_config_t cfg = default_config(0u);
    (void)memset(&det, 0, sizeof(det));
    assert_int_equal(aocs_det_init(&det, &cfg), AOCS_OK);
    assert_int_not_equal(det.id, AOCS_DET_MEKF);
    aocs_det_t before;
    (void)memcpy(&before, &det, sizeof(det)); /* padding too: a struct assignment need not copy it */
    aocs_det_set_st_excluded(&det, 1u);
    aocs_det_set_st_noise_scale(&det, AOCS_R(4.0));
    aocs_det_reinflate_bias(&det);
    aocs_det_set_torque(&det, tau, tau);
    assert_memory_equal(&det, &before, sizeof(det));
    assert_int_equal(aocs_det_set_gyroless(&det, &j), AOCS_ERR_MEKF_NOISE_NOT_POSITIVE);
    assert_int_equal(aocs_det_is_gyroless(&det), 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_every_row_has_a_name_and_inits),
        cmocka_unit_test(test_unknown_estimator_is_refused),
        cmocka_unit_test(test_passthrough_gives_the_measurement_bit_for_bit),
        cmocka_unit_test(test_mekf_inits_from_the_filter_defaults),
        cmocka_unit_test(test_mekf_waits_for_a_tracker_sample_then_converges),
        cmocka_unit_test(test_mekf_hostile_tracker_sample_is_counted_not_fatal),
        cmocka_unit_test(test_mekf_rejected_sample_does_not_move_the_filter),
        cmocka_unit_test(test_mekf_no_nan_out_for_any_input),
        cmocka_unit_test(test_null_arguments),
        cmocka_unit_test(test_fault_management_hooks_on_null_and_on_a_filterless_estimator),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
