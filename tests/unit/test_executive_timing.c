/*
 * Executive timing with a scripted HAL clock (this file defines the HAL, so
 * the POSIX port's object is not linked in): overrun detection against the
 * budget, max step time, real-time staleness against the HAL clock, periods
 * without a sample, and the absolute-deadline timer (next deadline =
 * t0 + k period, slips, jitter max and RMS) with synthetic times computed
 * by hand. No assertion depends on how fast this machine is.
 */
#include "test_support.h"

#include <string.h>

#include "aocs/executive.h"
#include "aocs/hal.h"

/* ---- scripted HAL: every time read advances the clock by fake_tick_ns ---- */
static uint64_t fake_now_ns;
static uint64_t fake_tick_ns;

uint64_t aocs_hal_time_ns(void)
{
    uint64_t t = fake_now_ns;
    fake_now_ns += fake_tick_ns;
    return t;
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

static void pd_config(aocs_exec_config_t *cfg)
{
    aocs_exec_config_default(cfg);
    cfg->law = AOCS_LAW_QUAT_PD;
    cfg->laws.quat_pd.kp = AOCS_R(1.0);
    cfg->laws.quat_pd.kd = AOCS_R(2.0);
    cfg->u_max_axis = aocs_vec3_make(AOCS_R(0.5), AOCS_R(0.5), AOCS_R(0.5));
    cfg->missing_max_periods = 2u;
    cfg->recover_good_samples = 2u;
}

static aocs_exec_input_t sample(uint32_t tick, uint64_t t_ns)
{
    aocs_exec_input_t in;
    memset(&in, 0, sizeof(in));
    in.tick = tick;
    in.t_sensor_ns = t_ns;
    in.valid = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    in.q_BN = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.6), AOCS_R(0.0), AOCS_R(0.8));
    in.w_BN_B = aocs_vec3_make(AOCS_R(0.01), AOCS_R(0.0), AOCS_R(-0.02));
    return in;
}

static void test_overrun_with_tiny_budget(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    pd_config(&cfg);
    cfg.budget_ns = 1u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_now_ns = 1000u;
    fake_tick_ns = 700u; /* each clock read 700 ns later: any timed step takes >= 700 ns */
    for (uint32_t k = 1u; k <= 5u; ++k) {
        aocs_exec_input_t in = sample(k, k * PERIOD_NS);
        assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
        assert_int_equal(out.budget_ns, 1u);
        assert_true(out.step_time_ns >= 700u);
        assert_int_equal(out.overrun, 1);
        assert_int_equal(out.counters.overrun, k);
    }
    assert_true(out.counters.step_time_max_ns >= 700u);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL); /* an overrun is reported, not a fault */

    /* a frozen clock: zero step time, no overrun even with the 1 ns budget */
    fake_tick_ns = 0u;
    aocs_exec_input_t in = sample(6u, 6u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.step_time_ns, 0u);
    assert_int_equal(out.overrun, 0);
    assert_int_equal(out.counters.overrun, 5u);
}

static void test_default_budget_is_the_law_budget(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    pd_config(&cfg);
    cfg.budget_ns = 0u;
    cfg.fdir.enabled = 0u; /* its allowance: test_fdir_budget_is_added */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_now_ns = 0u;
    fake_tick_ns = 1u; /* far below any budget */
    aocs_exec_input_t in = sample(1u, PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    /* the BUDGET_NS column of the law's laws.def row (test_registry checks every row) */
    assert_int_equal(out.budget_ns, aocs_law_budget_ns(AOCS_LAW_QUAT_PD));
    assert_int_equal(out.budget_ns, 2000u);
    assert_int_equal(out.overrun, 0);
    assert_int_equal(aocs_law_budget_ns(AOCS_LAW_SMC), 5000u);
    assert_int_equal(aocs_law_budget_ns(AOCS_LAW_ORBIT_LQR), 1000u);
    /* a clock step larger than the law budget: overrun */
    fake_tick_ns = aocs_law_budget_ns(AOCS_LAW_QUAT_PD) + 1u;
    in = sample(2u, 2u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.overrun, 1);
    assert_int_equal(out.counters.overrun, 1u);
}

/* guidance mode SLEW adds its BUDGET_NS (guidance_modes.def) to the attitude law's; a step of exactly the budget
   is not an overrun (io.h: overrun when step_time_ns > budget_ns), one nanosecond more is */
static void test_slew_mode_step_budget_and_its_edge(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    pd_config(&cfg);
    cfg.budget_ns = 0u;
    cfg.guidance.mode = AOCS_GUIDANCE_MODE_SLEW;
    cfg.guidance.slew.margin = AOCS_R(0.8);
    cfg.guidance.slew.inertia_kgm2 = aocs_mat3_diag(aocs_vec3_make(AOCS_R(10.0), AOCS_R(12.0), AOCS_R(14.0)));
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_now_ns = 0u;
    fake_tick_ns = 1u;
    aocs_exec_input_t in = sample(1u, PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    /* quat_pd 2000 ns + slew 2000 ns (timing.h) + the estimator's and the momentum stage's, both 0 here, + fault
     * management's 2000 ns (enabled by default, timing.h) */
    const uint64_t expected = 2000u + 2000u + aocs_det_budget_ns(&exec.det) + aocs_mom_budget_ns(&exec.momentum) +
                              2000u;
    assert_int_equal(AOCS_EXEC_FDIR_BUDGET_NS, 2000u);
    assert_int_equal(AOCS_EXEC_SLEW_BUDGET_NS, 2000u);
    assert_int_equal(aocs_det_budget_ns(&exec.det), 0u);
    assert_int_equal(aocs_mom_budget_ns(&exec.momentum), 0u);
    assert_int_equal(out.budget_ns, expected);
    /* a step of exactly the budget: no overrun */
    fake_tick_ns = expected;
    in = sample(2u, 2u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.step_time_ns, expected);
    assert_int_equal(out.budget_ns, expected);
    assert_int_equal(out.overrun, 0);
    assert_int_equal(out.counters.overrun, 0u);
    /* one nanosecond over it: overrun */
    fake_tick_ns = expected + 1u;
    in = sample(3u, 3u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.overrun, 1);
    assert_int_equal(out.counters.overrun, 1u);
    /* the same law in mode STEP: the law's budget alone */
    cfg.guidance.mode = AOCS_GUIDANCE_MODE_STEP;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_tick_ns = 1u;
    in = sample(1u, PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.budget_ns, 2000u + aocs_det_budget_ns(&exec.det) + aocs_mom_budget_ns(&exec.momentum) +
                                         2000u);
    /* fault management off: its allowance is not added */
    cfg.fdir.enabled = 0u;
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    in = sample(1u, PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.budget_ns, 2000u + aocs_det_budget_ns(&exec.det) + aocs_mom_budget_ns(&exec.momentum));
}

static void test_realtime_stale_against_hal_clock(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    pd_config(&cfg);
    cfg.clock = AOCS_EXEC_CLOCK_REALTIME;
    cfg.stale_timeout_ns = 50000000u; /* 50 ms */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_tick_ns = 0u;

    fake_now_ns = 1000000000u;
    aocs_exec_input_t in = sample(1u, fake_now_ns - 10000000u); /* 10 ms old */
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);

    fake_now_ns = 1100000000u;
    in = sample(2u, fake_now_ns - 60000000u); /* advancing, but 60 ms old */
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_STALE);
    assert_int_equal(out.counters.stale, 1u);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);

    in = sample(2u, fake_now_ns - 50000000u); /* exactly at the timeout: accepted */
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_OK);
    assert_int_equal(out.counters.stale, 1u);
}

static void test_periods_without_sample(void **state)
{
    (void)state;
    aocs_exec_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;
    aocs_exec_output_t first;
    pd_config(&cfg); /* N = 2, M = 2 */
    assert_int_equal(aocs_exec_init(&exec, &cfg), AOCS_OK);
    fake_now_ns = 0u;
    fake_tick_ns = 1u;
    aocs_exec_input_t in = sample(1u, PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &first), AOCS_OK);

    /* 1 missing period < N: the last command is held */
    assert_int_equal(aocs_exec_step_no_input(&exec, &out), AOCS_OK);
    assert_int_equal(out.input_status, AOCS_ERR_INPUT_MISSING);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_vec3_close(out.u_cmd, first.u_cmd, 0.0);
    assert_int_equal(out.counters.missing, 1u);

    /* N missing periods: SAFE, zero command */
    assert_int_equal(aocs_exec_step_no_input(&exec, &out), AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    assert_vec3_close(out.u_cmd, aocs_vec3_zero(), 0.0);
    assert_int_equal(out.counters.missing, 2u);

    /* the sample after the gap: its 2 missed ticks were already counted */
    in = sample(4u, 4u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.counters.missing, 2u);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_SAFE);
    /* M = 2 good samples bring NOMINAL back */
    in = sample(5u, 5u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    in = sample(6u, 6u * PERIOD_NS);
    assert_int_equal(aocs_exec_step(&exec, &in, &out), AOCS_OK);
    assert_int_equal(out.mode, AOCS_EXEC_MODE_NOMINAL);
    assert_int_equal(out.counters.steps, 6u);
}

static void test_timer_deadlines_slips_jitter(void **state)
{
    (void)state;
    aocs_exec_timer_t tmr;
    uint64_t dl = 0u;
    assert_int_equal(aocs_exec_timer_init(&tmr, 100u, 1000u), AOCS_OK);
    assert_true((double)aocs_exec_timer_jitter_rms_ns(&tmr) <= 0.0);
    {
        /* after its first period alone the rms is that period's jitter (7 late) */
        aocs_exec_timer_t one = tmr;
        assert_int_equal(aocs_exec_timer_period_start(&one, 1007u, &dl), AOCS_OK);
        assert_close(aocs_exec_timer_jitter_rms_ns(&one), 7.0, TOL_TIGHT);
    }
    {
        /* below a nanosecond: 1 ns late once, then three periods on time: mean square 1/4 ns^2, rms 0.5 ns */
        aocs_exec_timer_t sub = tmr;
        const uint64_t starts[4] = {1001u, 1100u, 1200u, 1300u};
        for (int k = 0; k < 4; ++k) {
            assert_int_equal(aocs_exec_timer_period_start(&sub, starts[k], &dl), AOCS_OK);
        }
        assert_close(aocs_exec_timer_jitter_rms_ns(&sub), 0.5, TOL_TIGHT);
    }

    assert_int_equal(aocs_exec_timer_period_start(&tmr, 1000u, &dl), AOCS_OK); /* on time */
    assert_int_equal(dl, 1100u);
    assert_int_equal(tmr.jitter_last_ns, 0);
    assert_int_equal(aocs_exec_timer_period_start(&tmr, 1105u, &dl), AOCS_OK); /* 5 late */
    assert_int_equal(dl, 1200u); /* absolute: the lateness does not shift the next deadline */
    assert_int_equal(tmr.jitter_last_ns, 5);
    assert_int_equal(aocs_exec_timer_period_start(&tmr, 1190u, &dl), AOCS_OK); /* 10 early */
    assert_int_equal(dl, 1300u);
    assert_int_equal(tmr.jitter_last_ns, -10);
    /* ideal 1300, came at 1550: periods starting 1300 and 1400 slipped, this one is 1500 + 50 */
    assert_int_equal(aocs_exec_timer_period_start(&tmr, 1550u, &dl), AOCS_OK);
    assert_int_equal(tmr.slips, 2u);
    assert_int_equal(tmr.jitter_last_ns, 50);
    assert_int_equal(dl, 1600u);
    assert_int_equal(tmr.periods, 4u);
    assert_int_equal(tmr.jitter_max_abs_ns, 50u);
    /* RMS of (0, 5, -10, 50) = sqrt((0 + 25 + 100 + 2500) / 4) */
    assert_close(aocs_exec_timer_jitter_rms_ns(&tmr), sqrt(2625.0 / 4.0), TOL_TIGHT);

    /* exactly one period late is a slip too */
    assert_int_equal(aocs_exec_timer_period_start(&tmr, 1700u, &dl), AOCS_OK);
    assert_int_equal(tmr.slips, 3u);
    assert_int_equal(tmr.jitter_last_ns, 0);
    assert_int_equal(dl, 1800u);

    assert_int_equal(aocs_exec_timer_init(&tmr, 0u, 0u), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_timer_init(NULL, 1u, 0u), AOCS_ERR_NULL_ARG);
    assert_int_equal(aocs_exec_timer_period_start(&tmr, 0u, NULL), AOCS_ERR_NULL_ARG);
}

static void test_timer_no_drift_over_long_run(void **state)
{
    (void)state;
    aocs_exec_timer_t tmr;
    const uint64_t t0 = 123456789012345ull;
    const uint64_t n = 1000000u; /* 27.8 h at 10 Hz */
    uint64_t dl = t0;
    assert_int_equal(aocs_exec_timer_init(&tmr, PERIOD_NS, t0), AOCS_OK);
    for (uint64_t k = 0u; k < n; ++k) {
        /* each wake-up 3 ns late: a relative sleep would drift 3 ms over the run */
        assert_int_equal(aocs_exec_timer_period_start(&tmr, dl + 3u, &dl), AOCS_OK);
    }
    assert_int_equal(dl, t0 + n * PERIOD_NS); /* deadline of period n = t0 + n period, exactly */
    assert_int_equal(tmr.slips, 0u);
    assert_int_equal(tmr.jitter_max_abs_ns, 3u);
    assert_close(aocs_exec_timer_jitter_rms_ns(&tmr), 3.0, TOL_LOOSE);
}

static void test_period_to_ns(void **state)
{
    (void)state;
    uint64_t p = 0u;
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(0.1), &p), AOCS_OK);
    assert_int_equal(p, 100000000u); /* also in float, where 0.1f = 0.100000001 */
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(0.01), &p), AOCS_OK);
    assert_int_equal(p, 10000000u);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(1.0e-6), &p), AOCS_OK);
    assert_int_equal(p, 1000u);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(1.0e-7), &p), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(0.0), &p), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(-0.1), &p), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(2000.0), &p), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_period_to_ns((real_t)NAN, &p), AOCS_ERR_RATE_INVALID);
    assert_int_equal(aocs_exec_period_to_ns(AOCS_R(0.1), NULL), AOCS_ERR_NULL_ARG);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_overrun_with_tiny_budget),
        cmocka_unit_test(test_slew_mode_step_budget_and_its_edge),
        cmocka_unit_test(test_default_budget_is_the_law_budget),
        cmocka_unit_test(test_realtime_stale_against_hal_clock),
        cmocka_unit_test(test_periods_without_sample),
        cmocka_unit_test(test_timer_deadlines_slips_jitter),
        cmocka_unit_test(test_timer_no_drift_over_long_run),
        cmocka_unit_test(test_period_to_ns),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}
