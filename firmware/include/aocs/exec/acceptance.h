/*
 * The input-acceptance stage (part of aocs/executive.h; src/acceptance/):
 * whether a sensor sample may drive the pipeline, with the reason when not.
 * Its time rules are the rows of aocs/exec/acceptance.def (LOCKSTEP,
 * REALTIME), selected by the executive's clock. Two checks, in this order:
 *   - frame acceptance (below): the sample continues the tick/time
 *     reference (fresh), or it is stale; tick gaps count missing samples;
 *   - validity for the selected law: an attitude law needs the flags of the
 *     selected estimator (`needs`, the NEEDS column of
 *     estimation/determination.def, aocs_det_needs): ATT|RATE (passthrough)
 *     a finite q with |q| = 1 within AOCS_QUAT_UNIT_TOL and a finite w; GYRO
 *     (MEKF) a finite gyro rate within AOCS_EXEC_GYRO_RATE_MAX_RADPS per axis.
 *     A star-tracker sample (VALID_ST) is never a need: the estimator judges
 *     it (the MEKF rejects and counts a bad one), so it cannot send the
 *     executive to SAFE. Orbit laws need the orbit flag and finite pos/vel;
 *     STANDBY reports the attitude verdict, or the orbit one for an
 *     orbit-only sample.
 *
 *   aocs_accept_init(&acc, clock, period_ns, stale_timeout_ns, missing_max_periods, needs)
 *   loop: st = aocs_accept_sample(&acc, law, &in, &missing)   missing: samples newly found missing
 *         aocs_accept_done(&acc, st)                          after the step
 *   no sample in a period: aocs_accept_no_sample(&acc)
 */
#ifndef AOCS_EXEC_ACCEPTANCE_H
#define AOCS_EXEC_ACCEPTANCE_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/exec/law_dispatch.h"
#include "aocs/exec/modes.h"
#include "aocs/exec/io.h"

/*
 * ---- Frame acceptance (executive.c; docs/wire-contract.md "Frame acceptance") ----
 * No single sample can move the tick/time reference of aocs_exec_step far.
 * With T the period, K = AOCS_EXEC_RESYNC_FRAMES, G = AOCS_EXEC_TICK_JUMP_MAX,
 * a sample b continues a sample a when
 *     g = b.tick - a.tick (modulo 2^32) is in [1, G], and
 *     lockstep:  |(b.t - a.t) - g T| <= T / AOCS_EXEC_LOCKSTEP_TOL_DIV
 *                (sensor time advances by the ticks' periods, within T / 4),
 *     real time: b.t > a.t.
 * Real time only: every sample must also lie on the HAL clock within
 * [now - stale_timeout_ns, now + T]; one outside is stale and nothing else.
 *
 * A sample that continues the reference (the last accepted sample) is
 * accepted and becomes the reference (a gap g > 1 counts g - 1 missing). The
 * first sample after init is accepted as it is. Any other sample is stale
 * (counted, SAFE, reference untouched) and a resynchronisation candidate:
 * K consecutive candidates, each continuing the one before, resynchronise;
 * the K-th becomes the reference and is treated as accepted (no missing
 * counted for the jump; exec.resyncs counts them). An accepted sample drops
 * the candidates. So one bad sample (any tick, any time, first one or not)
 * costs itself and at most K - 1 later good samples: the executive is
 * NOMINAL again at the latest with the (K - 1 + M)-th good sample after it
 * (M of exec/config.h), and with the M-th when the bad sample did not
 * continue the reference.
 *
 * K = 3: one bad sample can never resynchronise, two forged samples that
 * agree with each other cannot either, and a plant that really restarts its
 * tick or time is followed after 3 samples (0.3 s at 10 Hz).
 */
#define AOCS_EXEC_RESYNC_FRAMES 3u
/* Largest tick step that continues the reference: 1024 periods (102 s at 10 Hz),
 * far beyond any real loss burst (N missing samples already enter SAFE). */
#define AOCS_EXEC_TICK_JUMP_MAX 1024u
/* Lockstep: sensor time must advance by g periods within T / 4. Any tolerance
 * below T / 2 keeps tick and time unambiguous; T / 4 leaves room for the
 * plant's rounding (t_s = k dt in double, ns rounding) and nothing else. */
#define AOCS_EXEC_LOCKSTEP_TOL_DIV 4u
/* Largest gyro rate component an attitude sample may carry when its estimator needs the gyro, rad/s
 * (AOCS_ERR_GYRO_RANGE beyond): the MEKF's own bound AOCS_MEKF_RATE_MAX_RADPS (test_acceptance checks they
 * agree), 100 rad/s, far beyond any spacecraft's body rate and any gyro's range. */
#define AOCS_EXEC_GYRO_RATE_MAX_RADPS AOCS_R(100.0)

/* The state of the stage: the tick/time reference and the resynchronisation candidates. */
typedef struct {
    aocs_exec_clock_t clock;
    uint32_t needs;               /* AOCS_EXEC_VALID_* flags an attitude sample must carry (the estimator's) */
    uint64_t period_ns;
    uint64_t stale_timeout_ns;    /* real time: max age of a sample on the HAL clock */
    uint32_t missing_max_periods; /* N: a gap of >= N missed samples is AOCS_ERR_INPUT_MISSING */
    int have_sample;              /* a previous sample exists (tick/time reference valid) */
    uint32_t last_tick;
    uint64_t last_t_sensor_ns;
    uint32_t missing_run;         /* consecutive periods without a sample (aocs_accept_no_sample) */
    uint32_t resync_run;          /* consecutive rejected samples, each continuing the one before (< K) */
    uint32_t resync_tick;         /* tick and sensor time of the last of them */
    uint64_t resync_t_ns;
    uint32_t resyncs;             /* resynchronisations so far (saturates at UINT32_MAX) */
} aocs_accept_t;

/* Initialises the stage (no sample yet). Values as checked by aocs_exec_init; needs: the selected
 * estimator's (aocs_det_needs). Total (no-op on NULL). */
void aocs_accept_init(aocs_accept_t *acc, aocs_exec_clock_t clock, uint64_t period_ns, uint64_t stale_timeout_ns,
                      uint32_t missing_max_periods, uint32_t needs);

/*
 * The verdict on one sample for law: AOCS_OK, AOCS_ERR_INPUT_STALE,
 * AOCS_ERR_INPUT_MISSING (a gap of N or more), AOCS_ERR_INPUT_INVALID (flag
 * off), AOCS_ERR_INPUT_NOT_FINITE, AOCS_ERR_QUAT_NOT_UNIT, AOCS_ERR_GYRO_RANGE;
 * AOCS_ERR_NULL_ARG.
 * *missing_out = samples newly known missing (a tick gap, less those already
 * counted by aocs_accept_no_sample).
 */
aocs_status_t aocs_accept_sample(aocs_accept_t *acc, aocs_law_id_t law, const aocs_exec_input_t *in,
                                 uint32_t *missing_out);

/* End of a step with a sample of verdict st: the missing-period run ends unless it was stale. Total. */
void aocs_accept_done(aocs_accept_t *acc, aocs_status_t st);

/* A period without a sample: one more missing period; returns the run so far. Total (0 on NULL). */
uint32_t aocs_accept_no_sample(aocs_accept_t *acc);

/* Validity of a sample for law with an estimator that needs the flags `needs` (the second check above).
 * AOCS_ERR_NULL_ARG on NULL. */
aocs_status_t aocs_accept_validity(aocs_law_id_t law, uint32_t needs, const aocs_exec_input_t *in);

/* Name of a time rule ("lockstep", "realtime"); "unknown" out of range. Total. */
const char *aocs_accept_name(aocs_exec_clock_t clock);

/* ---- the rows' functions (acceptance.def), declared from the rows ---- */
#define AOCS_ACCEPT_PROTOTYPES(ID, NAME, ON_CLOCK, CONTINUES)                                                 \
    int ON_CLOCK(const aocs_accept_t *acc, uint64_t t_ns);                                                    \
    int CONTINUES(const aocs_accept_t *acc, uint64_t ref_t_ns, uint64_t t_ns, uint32_t gap);
AOCS_ACCEPTANCE_ROWS(AOCS_ACCEPT_PROTOTYPES)

#endif /* AOCS_EXEC_ACCEPTANCE_H */
