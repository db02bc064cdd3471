/*
 * The input-acceptance stage (aocs/exec/acceptance.h): frame acceptance
 * (docs/wire-contract.md "Frame acceptance") and the validity of a sample
 * for the selected law.
 */
#include <stddef.h>

#include "aocs/executive.h"
#include "aocs/hal.h"

/* Counter increment that sticks at the maximum instead of wrapping. */
static void accept_count(uint32_t *counter, uint32_t n)
{
    if ((UINT32_MAX - *counter) < n) {
        *counter = UINT32_MAX;
    } else {
        *counter += n;
    }
}

void aocs_accept_init(aocs_accept_t *acc, aocs_exec_clock_t clock, uint64_t period_ns, uint64_t stale_timeout_ns,
                      uint32_t missing_max_periods, uint32_t needs)
{
    if (acc != NULL) {
        acc->clock = clock;
        acc->needs = needs;
        acc->period_ns = period_ns;
        acc->stale_timeout_ns = stale_timeout_ns;
        acc->missing_max_periods = missing_max_periods;
        acc->have_sample = 0;
        acc->last_tick = 0u;
        acc->last_t_sensor_ns = 0u;
        acc->missing_run = 0u;
        acc->resync_run = 0u;
        acc->resync_tick = 0u;
        acc->resync_t_ns = 0u;
        acc->resyncs = 0u;
    }
}

#define ACCEPT_NAME_ROW(ID, NAME, ...) (NAME),

const char *aocs_accept_name(aocs_exec_clock_t clock)
{
    static const char *const accept_names[AOCS_EXEC_CLOCK_COUNT] = {AOCS_ACCEPTANCE_ROWS(ACCEPT_NAME_ROW)};
    const char *name = "unknown";
    if (((int)clock >= 0) && (clock < AOCS_EXEC_CLOCK_COUNT)) {
        name = accept_names[clock];
    }
    return name;
}

/* ---- time rule LOCKSTEP: the sample is the tick ---- */

int aocs_accept_lockstep_on_clock(const aocs_accept_t *acc, uint64_t t_ns)
{
    /* no clock but the samples' own: every sample may be considered */
    (void)acc;
    (void)t_ns;
    return 1;
}

/* Sensor time advances by g periods within T / AOCS_EXEC_LOCKSTEP_TOL_DIV. Unsigned: g T <= 1024 * 1e12 ns. */
int aocs_accept_lockstep_continues(const aocs_accept_t *acc, uint64_t ref_t_ns, uint64_t t_ns, uint32_t gap)
{
    int ok = 0;
    const uint64_t dt = t_ns - ref_t_ns;
    const uint64_t expected = (uint64_t)gap * acc->period_ns;
    const uint64_t tol = acc->period_ns / (uint64_t)AOCS_EXEC_LOCKSTEP_TOL_DIV;
    uint64_t err = 0u;
    if (dt >= expected) {
        err = dt - expected;
    } else {
        err = expected - dt;
    }
    if (err <= tol) {
        ok = 1;
    }
    return ok;
}

/* ---- time rule REALTIME: the HAL clock is the authority ---- */

/* 1 when t lies on the HAL clock within [now - stale_timeout, now + T]. */
int aocs_accept_realtime_on_clock(const aocs_accept_t *acc, uint64_t t_ns)
{
    const uint64_t now = aocs_hal_time_ns();
    int ok = 1;
    if ((now > t_ns) && ((now - t_ns) > acc->stale_timeout_ns)) {
        ok = 0; /* too old */
    } else if ((t_ns > now) && ((t_ns - now) > acc->period_ns)) {
        ok = 0; /* from the future: no clock the adapter reads runs ahead of ours by a period */
    } else {
        ok = 1;
    }
    return ok;
}

/* Any later time continues (the HAL window above bounds it). */
int aocs_accept_realtime_continues(const aocs_accept_t *acc, uint64_t ref_t_ns, uint64_t t_ns, uint32_t gap)
{
    (void)acc;
    (void)ref_t_ns;
    (void)t_ns;
    (void)gap;
    return 1;
}

/* ---- the dispatch to the selected row ---- */

#define ACCEPT_ON_CLOCK_CASE(ID, NAME, ON_CLOCK, CONTINUES) \
    case AOCS_EXEC_CLOCK_##ID:                               \
        ok = ON_CLOCK(acc, t_ns);                            \
        break;

static int sample_on_clock(const aocs_accept_t *acc, uint64_t t_ns)
{
    int ok = 0;
    switch (acc->clock) {
    AOCS_ACCEPTANCE_ROWS(ACCEPT_ON_CLOCK_CASE)
    default:
        ok = 0; /* not reachable: the clock was checked at init */
        break;
    }
    return ok;
}

#define ACCEPT_CONTINUES_CASE(ID, NAME, ON_CLOCK, CONTINUES) \
    case AOCS_EXEC_CLOCK_##ID:                                \
        ok = CONTINUES(acc, ref_t_ns, t_ns, gap);             \
        break;

/*
 * 1 when sample (tick, t) continues the sample (ref_tick, ref_t): the tick
 * advances by g in [1, G] (modulo 2^32: the counter may wrap), the time
 * advances, and the selected time rule agrees (acceptance.h, "Frame
 * acceptance"). *gap_out = g.
 */
static int sample_continues(const aocs_accept_t *acc, uint32_t ref_tick, uint64_t ref_t_ns, uint32_t tick,
                            uint64_t t_ns, uint32_t *gap_out)
{
    int ok = 0;
    const uint32_t gap = tick - ref_tick;
    *gap_out = gap;
    if ((gap >= 1u) && (gap <= AOCS_EXEC_TICK_JUMP_MAX) && (t_ns > ref_t_ns)) {
        switch (acc->clock) {
        AOCS_ACCEPTANCE_ROWS(ACCEPT_CONTINUES_CASE)
        default:
            ok = 0; /* not reachable: the clock was checked at init */
            break;
        }
    }
    return ok;
}

static void take_reference(aocs_accept_t *acc, const aocs_exec_input_t *in)
{
    acc->have_sample = 1;
    acc->last_tick = in->tick;
    acc->last_t_sensor_ns = in->t_sensor_ns;
    acc->resync_run = 0u;
}

/*
 * A sample that does not continue the reference: one more resynchronisation
 * candidate. Returns 1 when it completes K consecutive candidates (each
 * continuing the one before): the caller then takes it as the reference.
 */
static int resync_candidate(aocs_accept_t *acc, const aocs_exec_input_t *in)
{
    uint32_t gap = 0u;
    int resync = 0;
    if ((acc->resync_run > 0u) &&
        (sample_continues(acc, acc->resync_tick, acc->resync_t_ns, in->tick, in->t_sensor_ns, &gap) != 0)) {
        acc->resync_run += 1u;
    } else {
        acc->resync_run = 1u;
    }
    acc->resync_tick = in->tick;
    acc->resync_t_ns = in->t_sensor_ns;
    if (acc->resync_run >= AOCS_EXEC_RESYNC_FRAMES) {
        resync = 1;
    }
    return resync;
}

/*
 * Frame acceptance: a sample is fresh when it continues the tick/time
 * reference (a tick gap counts the samples that never came), or when it
 * completes a resynchronisation; otherwise it is stale and the reference does
 * not move, so no single sample, however far its tick or time, can make the
 * later good ones stale.
 */
static aocs_status_t sample_timing_check(aocs_accept_t *acc, const aocs_exec_input_t *in, uint32_t *missing)
{
    aocs_status_t st = AOCS_OK;
    uint32_t gap = 0u;
    if (sample_on_clock(acc, in->t_sensor_ns) == 0) {
        /* real time: the HAL clock is the authority, such a sample is no candidate either */
        st = AOCS_ERR_INPUT_STALE;
        acc->resync_run = 0u;
    } else if (acc->have_sample == 0) {
        take_reference(acc, in);
    } else if (sample_continues(acc, acc->last_tick, acc->last_t_sensor_ns, in->tick, in->t_sensor_ns, &gap) != 0) {
        if (gap > 1u) {
            /* periods already reported by aocs_accept_no_sample are not counted twice */
            if ((gap - 1u) > acc->missing_run) {
                *missing = (gap - 1u) - acc->missing_run;
            }
            if ((gap - 1u) >= acc->missing_max_periods) {
                st = AOCS_ERR_INPUT_MISSING;
            }
        }
        take_reference(acc, in);
    } else if (resync_candidate(acc, in) != 0) {
        take_reference(acc, in);
        accept_count(&acc->resyncs, 1u);
    } else {
        st = AOCS_ERR_INPUT_STALE;
    }
    return st;
}

aocs_status_t aocs_accept_sample(aocs_accept_t *acc, aocs_law_id_t law, const aocs_exec_input_t *in,
                                 uint32_t *missing_out)
{
    aocs_status_t st = AOCS_OK;
    uint32_t missing = 0u;
    if ((acc == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        st = sample_timing_check(acc, in, &missing);
        if (st == AOCS_OK) {
            st = aocs_accept_validity(law, acc->needs, in);
        }
    }
    if (missing_out != NULL) {
        *missing_out = missing;
    }
    return st;
}

void aocs_accept_done(aocs_accept_t *acc, aocs_status_t st)
{
    if ((acc != NULL) && (st != AOCS_ERR_INPUT_STALE)) {
        acc->missing_run = 0u; /* the tick reference moved past the counted periods */
    }
}

uint32_t aocs_accept_no_sample(aocs_accept_t *acc)
{
    uint32_t run = 0u;
    if (acc != NULL) {
        accept_count(&acc->missing_run, 1u);
        run = acc->missing_run;
    }
    return run;
}

static int accept_quat_is_unit(aocs_quat_t q)
{
    real_t n = aocs_quat_norm(q);
    return (AOCS_IS_FINITE(n) && (AOCS_FABS(n - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL)) ? 1 : 0;
}

/* Orbit sample rule: the orbit flag set, r and v finite (SPEC: orbit_lqr state x = [r; v]). */
static aocs_status_t orbit_validity(const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if ((in->valid & AOCS_EXEC_VALID_ORBIT) == 0u) {
        st = AOCS_ERR_INPUT_INVALID;
    } else if ((aocs_vec3_is_finite(in->pos_m) == 0) || (aocs_vec3_is_finite(in->vel_mps) == 0)) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/*
 * Attitude sample rule, for an estimator that needs the flags `needs`
 * (estimation/determination.def NEEDS): those flags set, then the values
 * they stand for finite (q and w for ATT|RATE, the gyro rate for GYRO), then
 * |q| = 1 within AOCS_QUAT_UNIT_TOL (ATT), then the gyro within
 * AOCS_EXEC_GYRO_RATE_MAX_RADPS (GYRO). With needs ATT|RATE (passthrough)
 * this is the rule of every attitude law before the estimators had needs.
 */
static aocs_status_t attitude_validity(const aocs_exec_input_t *in, uint32_t needs)
{
    aocs_status_t st = AOCS_OK;
    const uint32_t need_att = needs & AOCS_EXEC_VALID_ATT;
    const uint32_t need_rate = needs & AOCS_EXEC_VALID_RATE;
    const uint32_t need_gyro = needs & AOCS_EXEC_VALID_GYRO;
    if ((in->valid & needs) != needs) {
        st = AOCS_ERR_INPUT_INVALID;
    } else if (((need_att != 0u) && (aocs_quat_is_finite(in->q_BN) == 0)) ||
               ((need_rate != 0u) && (aocs_vec3_is_finite(in->w_BN_B) == 0)) ||
               ((need_gyro != 0u) && (aocs_vec3_is_finite(in->gyro_w_B) == 0))) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if ((need_att != 0u) && (accept_quat_is_unit(in->q_BN) == 0)) {
        st = AOCS_ERR_QUAT_NOT_UNIT;
    } else if ((need_gyro != 0u) && (aocs_vec3_norm_inf(in->gyro_w_B) > AOCS_EXEC_GYRO_RATE_MAX_RADPS)) {
        st = AOCS_ERR_GYRO_RANGE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/*
 * An orbit law needs an orbit sample, an attitude law an attitude sample.
 * With no law (STANDBY, control disabled) the executive does not know which
 * kind of vehicle state it is fed, so a sample is good when it passes either
 * rule. A sample that passes neither reports the orbit rule's verdict when
 * it carries only the orbit flag (none of the estimator's: it claims to be an
 * orbit sample), else the attitude rule's verdict (the behaviour before orbit
 * samples were accepted).
 */
aocs_status_t aocs_accept_validity(aocs_law_id_t law, uint32_t needs, const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if (in == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_law_is_orbit(law) != 0) {
        st = orbit_validity(in);
    } else if (law != AOCS_LAW_NONE) {
        st = attitude_validity(in, needs);
    } else {
        const uint32_t att_flags = needs;
        st = attitude_validity(in, needs);
        if (st != AOCS_OK) {
            const aocs_status_t st_orbit = orbit_validity(in);
            if ((st_orbit == AOCS_OK) ||
                (((in->valid & AOCS_EXEC_VALID_ORBIT) != 0u) && ((in->valid & att_flags) == 0u))) {
                st = st_orbit;
            }
        }
    }
    return st;
}
