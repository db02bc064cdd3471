/*
 * Timing of the step (part of aocs/executive.h; timing.c): the real-time
 * period timer, the period conversion and the host budgets of the steps
 * without a law and of the slew guidance.
 */
#ifndef AOCS_EXEC_TIMING_H
#define AOCS_EXEC_TIMING_H

#include <stdint.h>

#include "aocs/types.h"

/* ---- real-time period timer (timing.c), pure integer arithmetic ---- */
typedef struct {
    uint64_t period_ns;
    uint64_t t0_ns;               /* ideal start of period 0 */
    uint64_t k;                   /* index of the next period to start */
    uint64_t periods;             /* periods started */
    uint64_t slips;               /* periods skipped because the start came a period or more late */
    int64_t jitter_last_ns;       /* actual start - ideal start of the last period */
    uint64_t jitter_max_abs_ns;
    real_t jitter_ms_ns2;         /* running mean of jitter^2, ns^2 */
} aocs_exec_timer_t;

/*
 * Ideal start of period k is t0 + k * period (absolute: no drift).
 * AOCS_ERR_NULL_ARG, AOCS_ERR_RATE_INVALID when period_ns == 0.
 */
aocs_status_t aocs_exec_timer_init(aocs_exec_timer_t *tmr, uint64_t period_ns, uint64_t t0_ns);

/*
 * Records that a period started at now_ns: jitter = now - ideal start; when
 * now is one or more whole periods late those periods are counted as slips
 * and skipped (the phase is kept). Writes the absolute deadline of the next
 * period start (t0 + (k+1) * period) to *next_deadline_ns.
 */
aocs_status_t aocs_exec_timer_period_start(aocs_exec_timer_t *tmr, uint64_t now_ns, uint64_t *next_deadline_ns);

/* RMS of the recorded jitter, ns (0 before the first period). Total. */
real_t aocs_exec_timer_jitter_rms_ns(const aocs_exec_timer_t *tmr);

/* Period in ns from seconds, rounded to whole microseconds; AOCS_ERR_RATE_INVALID when out of [1 us, 1000 s]. */
aocs_status_t aocs_exec_period_to_ns(real_t period_s, uint64_t *period_ns);

/* Host budget of safe/standby steps (no law), ns. */
#define AOCS_EXEC_SAFE_BUDGET_NS 2000u

/* Host budget the fault-management stage adds to every step when enabled (fdir.enabled), ns: an allowance
 * above its cost (a few hundred ns on this machine: a loop over the wheels, a chi-square comparison). */
#define AOCS_EXEC_FDIR_BUDGET_NS 2000u

/*
 * Host budget added to an attitude law's step in guidance mode SLEW, ns: the
 * slew reference (closed-form profile, qd(t), the rotation of the rates into
 * B) and the feedforward. Measured with callgrind on the host (double,
 * irassi_large quat_pd, 13000 steps): +1870 instructions per step over the
 * same step in STEP mode (3390 against 1520), i.e. more than a whole quat_pd
 * step, whose budget is 2000 ns; the allowance is that budget again.
 */
#define AOCS_EXEC_SLEW_BUDGET_NS 2000u

#endif /* AOCS_EXEC_TIMING_H */
