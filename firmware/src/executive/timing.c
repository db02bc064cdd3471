/*
 * Real-time period timer: absolute deadlines t0 + k * period (no drift from
 * accumulating sleep errors), cycle slips, jitter statistics. Pure integer
 * time arithmetic; only the RMS accumulator is real_t. Wrap rule: times are
 * uint64_t ns of the HAL clock and wrap modulo 2^64 (after 584 years of
 * uptime); the signed jitter saturates at +-INT64_MAX (jitter_signed).
 */
#include <stddef.h>

#include "aocs/executive.h"

/* Periods outside [1 us, 1000 s] are not a control rate this firmware serves (executive.h). */
#define PERIOD_MIN_US AOCS_EXEC_PERIOD_MIN_US
#define PERIOD_MAX_US AOCS_EXEC_PERIOD_MAX_US

aocs_status_t aocs_exec_period_to_ns(real_t period_s, uint64_t *period_ns)
{
    aocs_status_t st = AOCS_OK;
    if (period_ns == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (!AOCS_IS_FINITE(period_s)) {
        st = AOCS_ERR_RATE_INVALID;
    } else {
        /*
         * Whole microseconds: a float period such as 0.1f is 0.100000001 s,
         * rounding to ns would make the deadlines drift 10 ns/s.
         */
        real_t us = period_s * AOCS_R(1.0e6);
        if ((us < (PERIOD_MIN_US - AOCS_R(0.5))) || (us > PERIOD_MAX_US)) {
            st = AOCS_ERR_RATE_INVALID;
        } else {
            uint64_t whole_us = (uint64_t)(us + AOCS_R(0.5));
            if (whole_us == 0u) {
                st = AOCS_ERR_RATE_INVALID;
            } else {
                *period_ns = whole_us * 1000u;
            }
        }
    }
    return st;
}

/*
 * +-abs as int64_t without signed overflow: magnitudes above INT64_MAX (a
 * clock 292 years off) saturate, so negating never meets INT64_MIN.
 */
static int64_t jitter_signed(uint64_t abs_ns, int negative)
{
    const int64_t mag = (abs_ns > (uint64_t)INT64_MAX) ? INT64_MAX : (int64_t)abs_ns;
    return (negative != 0) ? -mag : mag;
}

aocs_status_t aocs_exec_timer_init(aocs_exec_timer_t *tmr, uint64_t period_ns, uint64_t t0_ns)
{
    aocs_status_t st = AOCS_OK;
    if (tmr == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (period_ns == 0u) {
        st = AOCS_ERR_RATE_INVALID;
    } else {
        tmr->period_ns = period_ns;
        tmr->t0_ns = t0_ns;
        tmr->k = 0u;
        tmr->periods = 0u;
        tmr->slips = 0u;
        tmr->jitter_last_ns = 0;
        tmr->jitter_max_abs_ns = 0u;
        tmr->jitter_ms_ns2 = AOCS_R(0.0);
    }
    return st;
}

aocs_status_t aocs_exec_timer_period_start(aocs_exec_timer_t *tmr, uint64_t now_ns, uint64_t *next_deadline_ns)
{
    aocs_status_t st = AOCS_OK;
    if ((tmr == NULL) || (next_deadline_ns == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (tmr->period_ns == 0u) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        uint64_t ideal = tmr->t0_ns + (tmr->k * tmr->period_ns);
        uint64_t abs_jitter;
        int64_t jitter;
        real_t jr;
        if (now_ns >= ideal) {
            uint64_t late = now_ns - ideal;
            /* a start one or more whole periods late skipped those periods (F Prime cycle slip) */
            uint64_t skipped = late / tmr->period_ns;
            tmr->slips += skipped;
            tmr->k += skipped;
            ideal += skipped * tmr->period_ns;
            abs_jitter = now_ns - ideal;
            jitter = jitter_signed(abs_jitter, 0);
        } else {
            /* woke early (a sleep that returned before its deadline) */
            abs_jitter = ideal - now_ns;
            jitter = jitter_signed(abs_jitter, 1);
        }
        tmr->jitter_last_ns = jitter;
        if (abs_jitter > tmr->jitter_max_abs_ns) {
            tmr->jitter_max_abs_ns = abs_jitter;
        }
        tmr->periods += 1u;
        /* running mean of squares: no overflow however long the run */
        jr = (real_t)abs_jitter;
        tmr->jitter_ms_ns2 += ((jr * jr) - tmr->jitter_ms_ns2) / (real_t)tmr->periods;
        tmr->k += 1u;
        *next_deadline_ns = tmr->t0_ns + (tmr->k * tmr->period_ns);
    }
    return st;
}

real_t aocs_exec_timer_jitter_rms_ns(const aocs_exec_timer_t *tmr)
{
    real_t rms = AOCS_R(0.0);
    if ((tmr != NULL) && (tmr->periods > 0u) && (tmr->jitter_ms_ns2 > AOCS_R(0.0))) {
        rms = AOCS_SQRT(tmr->jitter_ms_ns2);
    }
    return rms;
}
