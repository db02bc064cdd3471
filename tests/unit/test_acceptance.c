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
 *  - NULL arguments.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"
#include "aocs/hal.h"

#define T_NS 100000000ull /* 0.1 s */

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
    aocs_accept_init(acc, AOCS_EXEC_CLOCK_LOCKSTEP, T_NS, 2u * T_NS, 3u);
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
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_REALTIME, T_NS, 2u * T_NS, 3u);
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
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, &in), AOCS_OK);
    in.valid = AOCS_EXEC_VALID_ATT;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, &in), AOCS_ERR_INPUT_INVALID);
    in = att_sample(0u, T_NS);
    in.w_BN_B.v[1] = (real_t)NAN;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in = att_sample(0u, T_NS);
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.1));
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, &in), AOCS_ERR_QUAT_NOT_UNIT);
    /* the orbit law needs the orbit flag and finite pos/vel, nothing of the attitude */
    in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, &in), AOCS_ERR_INPUT_INVALID);
    in.valid = AOCS_EXEC_VALID_ORBIT;
    in.q_BN.q[3] = (real_t)NAN;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, &in), AOCS_OK);
    in.vel_mps.v[2] = (real_t)INFINITY;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_ORBIT_LQR, &in), AOCS_ERR_INPUT_NOT_FINITE);
    /* STANDBY: either rule; an orbit-only sample reports the orbit verdict */
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, &in), AOCS_ERR_INPUT_NOT_FINITE);
    in.vel_mps.v[2] = AOCS_R(0.0);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, &in), AOCS_OK);
    in = att_sample(0u, T_NS);
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, &in), AOCS_OK);
    in.valid = 0u;
    assert_int_equal(aocs_accept_validity(AOCS_LAW_NONE, &in), AOCS_ERR_INPUT_INVALID);
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
    aocs_accept_init(&acc, AOCS_EXEC_CLOCK_REALTIME, T_NS, 2u * T_NS, 3u);
    assert_int_equal(aocs_accept_realtime_on_clock(&acc, now), 1);
    assert_int_equal(aocs_accept_realtime_on_clock(&acc, now + 10u * T_NS), 0);
    assert_int_equal(aocs_accept_realtime_continues(&acc, T_NS, 900u * T_NS, 1u), 1);
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
    assert_int_equal(aocs_accept_validity(AOCS_LAW_QUAT_PD, NULL), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_accept_no_sample(NULL), 0u);
    aocs_accept_done(NULL, AOCS_OK);
    aocs_accept_init(NULL, AOCS_EXEC_CLOCK_LOCKSTEP, T_NS, T_NS, 1u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_first_and_continuing_samples_are_fresh),
        cmocka_unit_test(test_gaps_count_missing_samples),
        cmocka_unit_test(test_k_consecutive_candidates_resynchronise),
        cmocka_unit_test(test_real_time_sample_off_the_hal_clock_is_stale),
        cmocka_unit_test(test_time_rule_rows),
        cmocka_unit_test(test_validity_for_each_kind_of_law),
        cmocka_unit_test(test_null_arguments),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
