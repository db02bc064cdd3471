/*
 * Input-acceptance stage alone (firmware/src/acceptance/acceptance.c,
 * aocs/exec/acceptance.h), without the executive:
 *  - frame acceptance: the first sample is the reference; a continuing one
 *    is fresh; a tick gap counts the missing samples (less those already
 *    counted by aocs_accept_no_sample) and is AOCS_ERR_INPUT_MISSING from N;
 *    a sample that does not continue is stale and leaves the reference;
 *    K = AOCS_EXEC_RESYNC_FRAMES consecutive candidates resynchronise; the
 *    lockstep time tolerance T / 4; real time: a sample off the HAL clock is stale;
 *  - the rows of acceptance.def (the clock's time rules) alone: names, the
 *    lockstep tolerance, the real-time HAL window;
 *  - validity for attitude laws, orbit laws and STANDBY (either rule);
 *  - the needs of each estimator (determination.def NEEDS): passthrough
 *    ATT|RATE (a unit q, a finite w), MEKF the gyro alone (flag, finite,
 *    range); a star-tracker sample is never a need, good or bad;
 *  - NULL arguments.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"
#include "aocs/hal.h"

#define T_NS 100000000ull /* 0.1 s */
/* the estimators' needs, from their rows (determination.def NEEDS) */
#define PT_NEEDS aocs_det_needs(AOCS_DET_PASSTHROUGH)
#define MEKF_NEEDS aocs_det_needs(AOCS_DET_MEKF)

static aocs_exec_input_t att_sample(uint32_t tick, uint64_t t_ns)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = t_ns;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = aocs_quat_identity();
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(-0.02));
    return in;
}

static void lockstep(aocs_accept_t *acc)
{
    aocs_accept_init(acc, AOCS_EXEC_CLOCK_LOCKSTEP, T_NS, 2u * T_NS, 3u, PT_NEEDS);
}

static aocs_status_t feed(aocs_accept_t *acc, uint32_t tick, uint64_t t_ns, uint32_t *missing)
{
    aocs_exec_input_t in = att_sample(tick, t_ns);
    aocs_status_t st = aocs_accept_sample(acc, AOCS_LAW_QUAT_PD, &in, missing);
    aocs_accept_done(acc, st);
    return st;
}

static void test_first_and_continuing_samples_are_fresh(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 99u;
    lockstep(&acc);
    assert_int_equal(acc.have_sample, 0);
    /* any first sample is the reference */
    assert_int_equal(feed(&acc, 1000u, 77u * T_NS, &missing), AOCS_OK);
    assert_int_equal(missing, 0u);
    assert_int_equal(acc.last_tick, 1000u);
    assert_int_equal(feed(&acc, 1001u, 78u * T_NS, &missing), AOCS_OK);
    /* within T / 4 of the expected time: fresh; beyond: stale */
    assert_int_equal(feed(&acc, 1002u, 79u * T_NS + T_NS / 4u, &missing), AOCS_OK);
    assert_int_equal(feed(&acc, 1003u, 80u * T_NS + T_NS / 4u + T_NS / 4u + 1u, &missing), AOCS_ERR_INPUT_STALE);
    assert_int_equal(acc.last_tick, 1002u); /* the reference did not move */
    /* the tick counter may wrap */
    lockstep(&acc);
    assert_int_equal(feed(&acc, UINT32_MAX, T_NS, &missing), AOCS_OK);
    assert_int_equal(feed(&acc, 0u, 2u * T_NS, &missing), AOCS_OK);
}

static void test_gaps_count_missing_samples(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    lockstep(&acc);
    assert_int_equal(feed(&acc, 0u, T_NS, &missing), AOCS_OK);
    /* gap 2: one missing, below N = 3 */
    assert_int_equal(feed(&acc, 2u, 3u * T_NS, &missing), AOCS_OK);
    assert_int_equal(missing, 1u);
    /* gap 4: three missing, >= N */
    assert_int_equal(feed(&acc, 6u, 7u * T_NS, &missing), AOCS_ERR_INPUT_MISSING);
    assert_int_equal(missing, 3u);
    assert_int_equal(acc.last_tick, 6u); /* a gap moves the reference */
    /* periods already reported by no_sample are not counted again */
    assert_int_equal(aocs_accept_no_sample(&acc), 1u);
    assert_int_equal(aocs_accept_no_sample(&acc), 2u);
    assert_int_equal(feed(&acc, 9u, 10u * T_NS, &missing), AOCS_OK);
    assert_int_equal(missing, 0u);
    assert_int_equal(acc.missing_run, 0u); /* done with a fresh sample ends the run */
    /* a stale sample does not end it */
    assert_int_equal(aocs_accept_no_sample(&acc), 1u);
    assert_int_equal(feed(&acc, 9u, 10u * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    assert_int_equal(acc.missing_run, 1u);
}

/* the edge of the tick rule (acceptance.h): a jump of exactly G = AOCS_EXEC_TICK_JUMP_MAX continues the
   reference (its G - 1 missing samples counted), G + 1 does not (stale, the reference kept) */
static void test_a_tick_jump_of_exactly_g_continues(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    const uint32_t g = AOCS_EXEC_TICK_JUMP_MAX;
    lockstep(&acc);
    assert_int_equal(feed(&acc, 5u, T_NS, &missing), AOCS_OK);
    assert_int_equal(feed(&acc, 5u + g, (1u + (uint64_t)g) * T_NS, &missing), AOCS_ERR_INPUT_MISSING);
    assert_int_equal(missing, g - 1u);
    assert_int_equal(acc.last_tick, 5u + g);
    lockstep(&acc);
    assert_int_equal(feed(&acc, 5u, T_NS, &missing), AOCS_OK);
    assert_int_equal(feed(&acc, 5u + g + 1u, (2u + (uint64_t)g) * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    assert_int_equal(missing, 0u);
    assert_int_equal(acc.last_tick, 5u);
    /* across the wrap of the counter: the same edge */
    lockstep(&acc);
    assert_int_equal(feed(&acc, UINT32_MAX - 3u, T_NS, &missing), AOCS_OK);
    assert_int_equal(feed(&acc, g - 4u, (1u + (uint64_t)g) * T_NS, &missing), AOCS_ERR_INPUT_MISSING);
    assert_int_equal(acc.last_tick, g - 4u);
}

static void test_k_consecutive_candidates_resynchronise(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    lockstep(&acc);
    assert_int_equal(feed(&acc, 10u, 11u * T_NS, &missing), AOCS_OK);
    /* the plant restarts: tick 0 at time 0.1 s, then continues */
    for (uint32_t k = 0u; k + 1u < AOCS_EXEC_RESYNC_FRAMES; ++k) {
        assert_int_equal(feed(&acc, k, (uint64_t)(k + 1u) * T_NS, &missing), AOCS_ERR_INPUT_STALE);
        assert_int_equal(acc.last_tick, 10u);
    }
    assert_int_equal(feed(&acc, AOCS_EXEC_RESYNC_FRAMES - 1u, (uint64_t)AOCS_EXEC_RESYNC_FRAMES * T_NS, &missing),
                     AOCS_OK);
    assert_int_equal(acc.resyncs, 1u);
    assert_int_equal(acc.last_tick, AOCS_EXEC_RESYNC_FRAMES - 1u);
    assert_int_equal(missing, 0u);
    /* one forged sample between good ones: stale, and the good ones stay fresh */
    assert_int_equal(feed(&acc, 500u, 900u * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    assert_int_equal(feed(&acc, AOCS_EXEC_RESYNC_FRAMES, (uint64_t)(AOCS_EXEC_RESYNC_FRAMES + 1u) * T_NS, &missing),
                     AOCS_OK);
    assert_int_equal(acc.resyncs, 1u);
}

static void test_real_time_sample_off_the_hal_clock_is_stale(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    const uint64_t now = aocs_hal_time_ns();
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_REALTIME, T_NS, 2u * T_NS, 3u, PT_NEEDS);
    /* far in the future (> T ahead) and far in the past (> the timeout) */
    assert_int_equal(feed(&acc, 0u, now + 100u * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    assert_int_equal(acc.have_sample, 0);
    if (now > 100u * T_NS) {
        assert_int_equal(feed(&acc, 0u, now - 100u * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    }
    assert_int_equal(feed(&acc, 0u, aocs_hal_time_ns(), &missing), AOCS_OK);
    /* real time: any later time continues (no period tolerance) */
    assert_int_equal(feed(&acc, 1u, aocs_hal_time_ns() + 1u, &missing), AOCS_OK);
}

static void test_validity_for_each_kind_of_law(void **state)
{
    (void)state;
    aocs_exec_input_t in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_OK);
    in.valid = AOCS_EXEC_VALID_ATT;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
    in = att_sample(0u, T_NS);
    in.w_BN_B.v[1] = (real_t)NAN;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in = att_sample(0u, T_NS);
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.1));
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_ERR_QUAT_NOT_UNIT);
    /* the orbit law needs the orbit flag and finite pos/vel, nothing of the attitude */
    in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, PT_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
    in.valid = AOCS_EXEC_VALID_ORBIT;
    in.q_BN.q[3] = (real_t)NAN;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, PT_NEEDS, &in), AOCS_OK);
    in.vel_mps.v[2] = (real_t)INFINITY;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, PT_NEEDS, &in), AOCS_ERR_INPUT_NOT_FINITE);
    /* STANDBY: either rule; an orbit-only sample reports the orbit verdict */
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, PT_NEEDS, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in.vel_mps.v[2] = AOCS_R(0.0);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, PT_NEEDS, &in), AOCS_OK);
    in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, PT_NEEDS, &in), AOCS_OK);
    in.valid = 0u;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, PT_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
}

static aocs_exec_input_t gyro_sample(uint32_t tick, uint64_t t_ns)
{
    aocs_exec_input_t in;
    (void)memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = t_ns;
    in.valid = AOCS_EXEC_VALID_GYRO;
    in.gyro_w_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(-0.02));
    return in;
}

static void test_needs_of_each_estimator(void **state)
{
    (void)state;
    aocs_exec_input_t in = gyro_sample(0u, T_NS);
    const real_t nan_value = (real_t)NAN;
    assert_int_equal(PT_NEEDS, AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    assert_int_equal(MEKF_NEEDS, AOCS_EXEC_VALID_GYRO);
    assert_int_equal(aocs_det_needs(AOCS_DET_COUNT), AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE);
    /* the acceptance's gyro bound is the MEKF's own */
    assert_true(!(AOCS_EXEC_GYRO_RATE_MAX_RADPS < AOCS_MEKF_RATE_MAX_RADPS) &&
                !(AOCS_EXEC_GYRO_RATE_MAX_RADPS > AOCS_MEKF_RATE_MAX_RADPS));
    /* MEKF: the gyro alone; q and w are not looked at */
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_OK);
    in.q_BN.q[0] = nan_value;
    in.w_BN_B.v[0] = nan_value;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_OK);
    /* a hostile or absent star-tracker sample is the MEKF's business, never the acceptance's */
    in.valid |= AOCS_EXEC_VALID_ST;
    in.st_q_SN = aocs_quat_make(nan_value, AOCS_R(3.0), AOCS_R(0.0), AOCS_R(0.0));
    in.st_t_meas_ns = 99u * T_NS; /* from the future */
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_OK);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, MEKF_NEEDS, &in), AOCS_OK);
    /* ... but the gyro is needed: flag, finite, range */
    in = gyro_sample(0u, T_NS);
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE | AOCS_EXEC_VALID_ST;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
    in = gyro_sample(0u, T_NS);
    in.gyro_w_B.v[2] = (real_t)INFINITY;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in.gyro_w_B.v[2] = nan_value;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in.gyro_w_B.v[2] = AOCS_EXEC_GYRO_RATE_MAX_RADPS;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_OK);
    in.gyro_w_B.v[2] = -AOCS_R(1.01) * AOCS_EXEC_GYRO_RATE_MAX_RADPS;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_ERR_GYRO_RANGE);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, MEKF_NEEDS, &in), AOCS_ERR_GYRO_RANGE);
    /* the orbit law keeps its own rule whatever the estimator */
    in.valid = AOCS_EXEC_VALID_ORBIT;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, MEKF_NEEDS, &in), AOCS_OK);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, MEKF_NEEDS, &in), AOCS_OK);
    /* passthrough: a gyro-only sample is not enough, a good q and w without a gyro is */
    in = gyro_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
    in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, &in), AOCS_OK);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, MEKF_NEEDS, &in), AOCS_ERR_INPUT_INVALID);
}

/* The stage keeps the needs it was given: a sample stream for the MEKF passes on the gyro alone. */
static void test_stage_applies_its_needs(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    aocs_exec_input_t in = gyro_sample(0u, T_NS);
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_LOCKSTEP, T_NS, 2u * T_NS, 3u, MEKF_NEEDS);
    assert_int_equal(acc.needs, AOCS_EXEC_VALID_GYRO);
    assert_int_equal(aocs_accept_sample(&acc, AOCS_LAW_QUAT_PD, &in, &missing), AOCS_OK);
    in = gyro_sample(1u, 2u * T_NS);
    in.valid = 0u;
    assert_int_equal(aocs_accept_sample(&acc, AOCS_LAW_QUAT_PD, &in, &missing), AOCS_ERR_INPUT_INVALID);
}

static void test_time_rule_rows(void **state)
{
    (void)state;
    aocs_accept_t acc;
    const uint64_t now = aocs_hal_time_ns();
    for (int i = 0; i < (int)AOCS_EXEC_CLOCK_COUNT; ++i) {
        const char *name = aocs_accept_name((aocs_exec_clock_t)i);
        assert_true(strlen(name) > 0u);
        assert_string_not_equal(name, "unknown");
        for (int j = 0; j < i; ++j) {
            assert_string_not_equal(name, aocs_accept_name((aocs_exec_clock_t)j));
        }
    }
    assert_string_equal(aocs_accept_name(AOCS_EXEC_CLOCK_LOCKSTEP), "lockstep");
    assert_string_equal(aocs_accept_name(AOCS_EXEC_CLOCK_COUNT), "unknown");
    lockstep(&acc);
    /* lockstep: any sample may be considered; g periods later within T / 4 */
    assert_int_equal(aocs_accept_lockstep_on_clock(&acc, 0u), 1);
    assert_int_equal(aocs_accept_lockstep_continues(&acc, T_NS, 3u * T_NS, 2u), 1);
    assert_int_equal(aocs_accept_lockstep_continues(&acc, T_NS, 3u * T_NS + T_NS / 4u, 2u), 1);
    assert_int_equal(aocs_accept_lockstep_continues(&acc, T_NS, 3u * T_NS + T_NS / 4u + 1u, 2u), 0);
    assert_int_equal(aocs_accept_lockstep_continues(&acc, T_NS, 3u * T_NS - T_NS / 4u - 1u, 2u), 0);
    /* real time: the HAL window [now - timeout, now + T], any later time continues */
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_REALTIME, T_NS, 2u * T_NS, 3u, PT_NEEDS);
    assert_int_equal(aocs_accept_realtime_on_clock(&acc, now), 1);
    assert_int_equal(aocs_accept_realtime_on_clock(&acc, now + 10u * T_NS), 0);
    assert_int_equal(aocs_accept_realtime_continues(&acc, T_NS, 900u * T_NS, 1u), 1);
}

/* A stage given a time rule out of the rows (aocs_exec_init never does: it checks the clock first) trusts no
 * sample's time: every sample is stale, none becomes the reference. */
static void test_a_time_rule_out_of_the_rows_accepts_no_sample(void **state)
{
    (void)state;
    aocs_accept_t acc;
    uint32_t missing = 0u;
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_COUNT, T_NS, 2u * T_NS, 3u, PT_NEEDS);
    for (uint32_t k = 1u; k <= 5u; ++k) {
        assert_int_equal(feed(&acc, k, (uint64_t)k * T_NS, &missing), AOCS_ERR_INPUT_STALE);
    }
    assert_int_equal(acc.have_sample, 0);
}

static void test_null_arguments(void **state)
{
    (void)state;
    aocs_accept_t acc;
    aocs_exec_input_t in = att_sample(0u, T_NS);
    uint32_t missing = 5u;
    lockstep(&acc);
    assert_int_equal(aocs_accept_sample(NULL, AOCS_LAW_QUAT_PD, &in, &missing), AOCS_ERR_NULL_ARG);
    assert_int_equal(missing, 0u);
    assert_int_equal(aocs_accept_sample(&acc, AOCS_LAW_QUAT_PD, NULL, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_accept_sample(&acc, AOCS_LAW_QUAT_PD, &in, NULL), AOCS_OK);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, PT_NEEDS, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_accept_no_sample(NULL), 0u);
    aocs_accept_done(NULL, AOCS_OK);
    aocs_accept_init(NULL, AOCS_EXEC_CLOCK_LOCKSTEP, T_NS, T_NS, 1u, PT_NEEDS);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_first_and_continuing_samples_are_fresh),
        cmocka_unit_test(test_gaps_count_missing_samples),
        cmocka_unit_test(test_a_tick_jump_of_exactly_g_continues),
        cmocka_unit_test(test_k_consecutive_candidates_resynchronise),
        cmocka_unit_test(test_real_time_sample_off_the_hal_clock_is_stale),
        cmocka_unit_test(test_time_rule_rows),
        cmocka_unit_test(test_validity_for_each_kind_of_law),
        cmocka_unit_test(test_needs_of_each_estimator),
        cmocka_unit_test(test_stage_applies_its_needs),
        cmocka_unit_test(test_a_time_rule_out_of_the_rows_accepts_no_sample),
        cmocka_unit_test(test_null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
