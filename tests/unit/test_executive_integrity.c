/*
 * Frame acceptance of the executive (executive.h "Frame acceptance",
 * docs/wire-contract.md): no single sample, whatever its tick or time, can
 * keep the executive in SAFE. After any one bad sample the executive is
 * NOMINAL again at the latest with the (K - 1 + M)-th good sample
 * (K = AOCS_EXEC_RESYNC_FRAMES, M = recover_good_samples); a plant that really
 * jumps is followed after K consistent samples. Scripted HAL clock (this file
 * defines the HAL) for the real-time bounds.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"
#include "aocs/hal.h"

/* ---- scripted HAL ---- */
static uint64_t fake_now_ns;

uint64_t aocs_hal_time_ns(void)
{
    return fake_now_ns;
}

uint32_t aocs_hal_cycles(void)
{
    return 0u;
}

void aocs_hal_sleep_until_ns(uint64_t t_ns)
{
    if (t_ns > fake_now_ns) {
        fake_now_ns = t_ns;
    }
}

#define PERIOD_NS 100000000ull
#define M_GOOD 4u
#define K_RESYNC AOCS_EXEC_RESYNC_FRAMES
#define NS_PER_S 1000000000ull

static void base_config(aocs_exec_config_t *cfg, aocs_exec_clock_t clock)
{
    aocs_exec_config_default(cfg);
    cfg->period_s = AOCS_R(0.1);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(1.0);
    cfg->laws.quat_pd.kd = AOCS_R(2.0);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5));
    cfg->recover_good_samples = M_GOOD;
    cfg->missing_max_periods = 3u;
    cfg->stale_timeout_ns = 2u * PERIOD_NS;
    cfg->clock = clock;
}

static aocs_exec_input_t sample(uint32_t tick, uint64_t t_ns)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = t_ns;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0871557427), AOCS_R(0.9961946981));
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(-0.02), AOCS_R(0.03));
    return in;
}

/* the plant's sample of tick k: t = k T */
static aocs_exec_input_t good(uint32_t tick)
{
    return sample(tick, (uint64_t)tick * PERIOD_NS);
}

static aocs_exec_output_t step(aocs_exec_t *exec, aocs_exec_input_t in)
{
    aocs_exec_output_t out;
    assert_int_equal(aocs_exec_step(exec, &in, &out), AOCS_OK);
    for (int i = 0; i < 3; ++i) {
        assert_true(fabs((double)out.u_cmd.v[i]) <= 0.5);
    }
    return out;
}

/*
 * Plays good samples from tick `from` on (lockstep times k T) and returns how
 * many it took to be NOMINAL; fails when `bound` samples were not enough.
 */
static uint32_t good_until_nominal(aocs_exec_t *exec, uint32_t from, uint32_t bound)
{
    for (uint32_t n = 1u; n <= bound; ++n) {
        aocs_exec_output_t out = step(exec, good(from + n - 1u));
        if (out.mode == AOCS_EXEC_MODE_NOMINAL) {
            return n;
        }
    }
    print_error("still %s after %u good samples\n", aocs_exec_mode_name(exec->mode), bound);
    fail();
    return 0u;
}

static void init_running(aocs_exec_t *exec, aocs_exec_clock_t clock, uint32_t last_tick)
{
    aocs_exec_config_t cfg;
    base_config(&cfg, clock);
    assert_int_equal(aocs_exec_init(exec, &cfg), AOCS_OK);
    for (uint32_t k = 1u; k <= last_tick; ++k) {
        aocs_exec_output_t out = step(exec, good(k));
        assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    }
}

/* issue 11 item 1: one sample 1e9 s in the future latched SAFE for good */
static void test_future_time_does_not_latch(void **state)
{
    (void)state;
    aocs_exec_t exec;
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    aocs_exec_output_t out = step(&exec, sample(11u, 11u * PERIOD_NS + 1000000000u * NS_PER_S));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    /* the reference did not move: the plant's next samples are good at once */
    assert_true(good_until_nominal(&exec, 11u, M_GOOD) <= M_GOOD);
    assert_int_equal(exec.counters.stale, 1u);
    assert_int_equal(exec.accept.resyncs, 0u);
}

/* issue 11 item 1: a tick far ahead (with a time that agrees with it) latched SAFE */
static void test_tick_far_ahead_does_not_latch(void **state)
{
    (void)state;
    aocs_exec_t exec;
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    const uint32_t far = 10u + 0x40000000u;
    aocs_exec_output_t out = step(&exec, good(far));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(exec.counters.missing, 0u); /* not counted as 2^30 missing samples either */
    assert_true(good_until_nominal(&exec, 11u, M_GOOD) <= M_GOOD);
    /* just beyond the largest accepted jump: the same */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    out = step(&exec, good(10u + AOCS_EXEC_TICK_JUMP_MAX + 1u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_true(good_until_nominal(&exec, 11u, M_GOOD) <= M_GOOD);
    /* a tick behind (the counter went backwards) and a repeated tick: stale, reference kept */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    out = step(&exec, good(3u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    out = step(&exec, sample(10u, 10u * PERIOD_NS + 1u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_true(good_until_nominal(&exec, 11u, M_GOOD) <= M_GOOD);
}

/* lockstep: the time must advance by the ticks' periods within T / 4 */
static void test_lockstep_time_follows_ticks(void **state)
{
    (void)state;
    aocs_exec_t exec;
    const uint64_t tol = PERIOD_NS / AOCS_EXEC_LOCKSTEP_TOL_DIV;
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    /* edges of the tolerance, each against the last accepted sample */
    aocs_exec_output_t out = step(&exec, sample(11u, 11u * PERIOD_NS + tol));
    assert_int_equal(out.input_status, AOCS_OK);
    out = step(&exec, sample(12u, 11u * PERIOD_NS + tol + PERIOD_NS - tol));
    assert_int_equal(out.input_status, AOCS_OK);
    out = step(&exec, sample(13u, 13u * PERIOD_NS + tol + 1u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    out = step(&exec, sample(13u, 13u * PERIOD_NS - tol - 1u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    /* a gap of 2 ticks needs 2 periods: lost samples, not a time jump */
    out = step(&exec, good(14u));
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(exec.counters.missing, 1u);
    /* the time of two ticks on with the tick of one: stale */
    out = step(&exec, sample(15u, 16u * PERIOD_NS));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    /* the plant's stale-time fault (the time of the previous tick): stale, as before */
    out = step(&exec, sample(15u, 14u * PERIOD_NS));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    out = step(&exec, good(15u));
    assert_int_equal(out.input_status, AOCS_OK);
}

/*
 * The bound of executive.h for ANY single bad sample: after it, NOMINAL by
 * the (K - 1 + M)-th good sample. Bad samples tried: every kind of tick jump
 * (behind, equal, small and huge ahead) times every kind of time (past,
 * equal, consistent, inconsistent, far future), invalid values, a first
 * sample that is bad.
 */
static void test_any_single_bad_sample_recovers_within_bound(void **state)
{
    (void)state;
    const uint32_t bound = K_RESYNC - 1u + M_GOOD;
    const int64_t dticks[] = {-1000000, -5, -1, 0, 1, 2, 3, 4, 7, 1023, 1024, 1025, 100000, 0x7fffffff};
    const int64_t dts[] = {-1000, -1, 0, 1, 2, 3, 5, 1024, 1000000, 0x7fffffff};
    uint32_t worst = 0u;
    for (size_t a = 0; a < sizeof(dticks) / sizeof(dticks[0]); ++a) {
        for (size_t b = 0; b < sizeof(dts) / sizeof(dts[0]); ++b) {
            for (int consistent = 0; consistent < 2; ++consistent) {
                aocs_exec_t exec;
                init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 100u);
                /* tick 100 + dtick (mod 2^32), time (100 + dt) T, or matching the tick */
                uint32_t tick = (uint32_t)(100u + (uint32_t)dticks[a]);
                int64_t periods = (consistent != 0) ? (100 + dticks[a]) : (100 + dts[b]);
                uint64_t t = (periods > 0) ? ((uint64_t)periods * PERIOD_NS) : 0u;
                (void)step(&exec, sample(tick, t));
                uint32_t n = good_until_nominal(&exec, 101u, bound);
                if (n > worst) {
                    worst = n;
                }
            }
        }
    }
    assert_true(worst <= bound);
    assert_true(worst > M_GOOD); /* the bound is reached: a sample that took the next slots costs K - 1 */

    /* the first sample after init is bad (far future): the plant's own samples resynchronise */
    aocs_exec_t exec;
    aocs_exec_config_t cfg;
    base_config(&cfg, AOCS_EXEC_CLOCK_LOCKSTEP);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    (void)step(&exec, sample(5000000u, 1000000u * NS_PER_S));
    assert_true(good_until_nominal(&exec, 1u, bound) <= bound);
    assert_int_equal(exec.accept.resyncs, 1u);

    /* invalid values in an otherwise well-timed sample: M good samples */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    aocs_exec_input_t bad = good(11u);
    bad.w_BN_B.v[1] = (real_t)NAN;
    aocs_exec_output_t out = step(&exec, bad);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_int_equal(good_until_nominal(&exec, 12u, M_GOOD), M_GOOD);
}

/* a plant that really jumps (restart, time re-based) is followed after K consistent samples */
static void test_resync_after_k_consistent_samples(void **state)
{
    (void)state;
    aocs_exec_t exec;
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 50u);
    aocs_exec_output_t out;
    /* the plant restarts at tick 0, time 0 */
    for (uint32_t k = 0u; k + 1u < K_RESYNC; ++k) {
        out = step(&exec, good(k));
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    }
    out = step(&exec, good(K_RESYNC - 1u));
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(exec.accept.resyncs, 1u);
    assert_int_equal(exec.counters.missing, 0u);
    assert_true(good_until_nominal(&exec, K_RESYNC, M_GOOD) == M_GOOD - 1u);

    /* K - 1 forged samples consistent with each other: no resynchronisation */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    for (uint32_t k = 0u; k + 1u < K_RESYNC; ++k) {
        out = step(&exec, good(1000000u + k));
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    }
    out = step(&exec, good(11u));
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(exec.accept.resyncs, 0u);

    /* candidates that do not continue each other (the same forged sample repeated) never resynchronise */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    for (uint32_t k = 0u; k < 3u * K_RESYNC; ++k) {
        out = step(&exec, good(5000u));
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    }
    assert_int_equal(exec.accept.resyncs, 0u);
    out = step(&exec, good(11u));
    assert_int_equal(out.input_status, AOCS_OK);

    /* an accepted sample drops the candidates: interleaved forged samples never add up to K */
    init_running(&exec, AOCS_EXEC_CLOCK_LOCKSTEP, 10u);
    for (uint32_t k = 0u; k < 3u * K_RESYNC; ++k) {
        out = step(&exec, good(500000u + k));
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
        out = step(&exec, good(11u + k));
        assert_int_equal(out.input_status, AOCS_OK);
    }
    assert_int_equal(exec.accept.resyncs, 0u);
}

/* tick wrap modulo 2^32 is still a step of one */
static void test_tick_wrap(void **state)
{
    (void)state;
    aocs_exec_t exec;
    aocs_exec_config_t cfg;
    base_config(&cfg, AOCS_EXEC_CLOCK_LOCKSTEP);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    aocs_exec_output_t out = step(&exec, sample(0xFFFFFFFFu, 7u * PERIOD_NS));
    out = step(&exec, sample(0u, 8u * PERIOD_NS));
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.missing, 0u);
}

/* real time: the sample time must lie on the HAL clock in [now - stale_timeout, now + T] */
static void test_realtime_bounds_of_hal_clock(void **state)
{
    (void)state;
    aocs_exec_t exec;
    aocs_exec_config_t cfg;
    base_config(&cfg, AOCS_EXEC_CLOCK_REALTIME);
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_now_ns = 1000u * NS_PER_S;
    aocs_exec_output_t out = step(&exec, sample(1u, fake_now_ns - 1000u));
    assert_int_equal(out.input_status, AOCS_OK);
    /* one sample stamped 1e9 s ahead of the clock (a forged or broken time) */
    fake_now_ns += PERIOD_NS;
    out = step(&exec, sample(2u, fake_now_ns + 1000000000u * NS_PER_S));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    /* one period ahead is still accepted; more is not */
    out = step(&exec, sample(2u, fake_now_ns + PERIOD_NS + 1u));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    out = step(&exec, sample(2u, fake_now_ns + PERIOD_NS));
    assert_int_equal(out.input_status, AOCS_OK);
    /* the following samples (reception times on the clock) are good: no latch */
    for (uint32_t k = 3u; k < 3u + M_GOOD; ++k) {
        fake_now_ns += 2u * PERIOD_NS;
        out = step(&exec, sample(k, fake_now_ns));
        assert_int_equal(out.input_status, AOCS_OK);
    }
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);

    /* a tick far ahead in real time: stale, the next real one is good */
    fake_now_ns += PERIOD_NS;
    out = step(&exec, sample(0x70000000u, fake_now_ns));
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    fake_now_ns += PERIOD_NS;
    out = step(&exec, sample(3u + M_GOOD, fake_now_ns));
    assert_int_equal(out.input_status, AOCS_OK);
    /* too old: stale, and no resynchronisation candidate either (the clock is the authority) */
    for (uint32_t k = 0u; k < 2u * K_RESYNC; ++k) {
        fake_now_ns += PERIOD_NS;
        out = step(&exec, sample(100u + k, fake_now_ns - 3u * PERIOD_NS));
        assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    }
    assert_int_equal(exec.accept.resyncs, 0u);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_future_time_does_not_latch),
        cmocka_unit_test(test_tick_far_ahead_does_not_latch),
        cmocka_unit_test(test_lockstep_time_follows_ticks),
        cmocka_unit_test(test_any_single_bad_sample_recovers_within_bound),
        cmocka_unit_test(test_resync_after_k_consistent_samples),
        cmocka_unit_test(test_tick_wrap),
        cmocka_unit_test(test_realtime_bounds_of_hal_clock),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
