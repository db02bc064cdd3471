/*
 * The executive proper (part of aocs/executive.h): it sequences the stages of
 * one control period, owns the modes and times the step (ARCHITECTURE.md
 * "The flight pipeline"):
 *
 *   accept input      aocs/exec/acceptance.h        frame acceptance, validity
 *   determine att.    aocs/estimation/determination.h (determination.def; key "estimator")
 *   guide             aocs/guidance/guidance.h      (guidance_modes.def; guidance.mode)
 *   control law       aocs/exec/law_dispatch.h      (laws.def; key "law")
 *   actuate           aocs/actuation/actuation.h    (actuation.def; wheels.count)
 *   manage momentum   aocs/momentum/momentum.h      (momentum.def; "none")
 *   manage faults     aocs/fdir/fdir.h              (events.def; fdir.enabled): residual tests, the
 *                     event log, wheel isolation (the allocation re-initialised, the slew replanned),
 *                     star-tracker exclusion (applied to the next step's determination), the gyro's
 *                     exclusion (the estimator goes gyroless, 5.6.12), SAFE latched when an isolation is
 *                     refused or the gyro is excluded with no gyroless estimator (docs/spec.md 5.15)
 *
 * The step is timed (aocs/exec/timing.h) from determination to the end of
 * actuation. Modes: STANDBY (zero command), NOMINAL (the law's command plus
 * the guidance feedforward), SAFE (attitude: rate damping on the estimate,
 * mode.c, within the limits; orbit: zero force). SAFE is entered on a sample the
 * acceptance or the determination rejects, a missing sample or a law error,
 * and left for the requested mode after M consecutive good samples
 * (exec/config.h) (valid, fresh, no gap, and the law evaluates without error:
 * in SAFE the law runs in the shadow to know that).
 */
#ifndef AOCS_EXEC_PIPELINE_H
#define AOCS_EXEC_PIPELINE_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/exec/law_dispatch.h"
#include "aocs/exec/modes.h"
#include "aocs/exec/io.h"
#include "aocs/exec/config.h"
#include "aocs/exec/acceptance.h"
#include "aocs/estimation/determination.h"
#include "aocs/guidance/guidance.h"
#include "aocs/actuation/actuation.h"
#include "aocs/momentum/momentum.h"
#include "aocs/fdir/fdir.h"

typedef struct {
    /* cached configuration */
    aocs_exec_config_t cfg;
    uint64_t period_ns;
    /* the stages, in pipeline order */
    aocs_accept_t accept;         /* input acceptance: tick/time reference, resynchronisation */
    aocs_det_t det;               /* attitude determination */
    aocs_guidance_t guidance;     /* guidance: target, rotating target, slew */
    aocs_exec_law_states_t states; /* control law: one state per law (laws.def) */
    aocs_law_id_t law;            /* selected law */
    aocs_act_t act;               /* actuation: saturation, wheel array */
    aocs_mom_t momentum;          /* momentum management */
    aocs_fdir_t fdir;             /* fault management: monitors, event log, isolation decisions */
    /* modes */
    aocs_exec_mode_t mode;        /* actual mode */
    aocs_exec_mode_t requested;   /* STANDBY or NOMINAL, what SAFE returns to */
    uint32_t good_run;            /* consecutive good samples while in SAFE */
    aocs_vec3_t last_u_cmd;       /* held by step_no_input below the missing threshold */
    int gyroless_capable;         /* 1: the estimator has a gyroless model and the configured inertia is one
                                     (docs/spec.md 5.6.12): an excluded gyro does not latch SAFE */
    aocs_exec_counters_t counters;
    int initialised;
} aocs_exec_t;

/*
 * Validates the config and initialises the selected law with its config.
 * Status: AOCS_ERR_NULL_ARG; AOCS_ERR_RATE_INVALID (period not finite or out
 * of range); AOCS_ERR_UNKNOWN_LAW; AOCS_ERR_TARGET_INVALID (non-finite or
 * non-unit qd, non-finite wd/wd_dot, non-finite target_rotation_rate_D, or
 * a rotating target with a non-zero wd/wd_dot); AOCS_ERR_PARAM_NOT_FINITE (limit,
 * safe-mode gain); AOCS_ERR_SAT_LIMIT_NOT_POSITIVE (negative limit, mixed zero and
 * non-zero per-axis limits, or no limit set); AOCS_ERR_GAIN_NOT_POSITIVE
 * (safe-mode gain <= 0, M or N == 0, real-time stale timeout == 0);
 * AOCS_ERR_MODE_INVALID (clock out of range); AOCS_ERR_GUIDANCE_MODE_INVALID
 * (guidance.mode out of range); in SLEW mode AOCS_ERR_GUIDANCE_TARGET_MOVING
 * (rotating target or non-zero wd/wd_dot) and the slew config's codes
 * (aocs_slew_config_check: profile, margin, rate limit, jerk time, inertia);
 * AOCS_ERR_ESTIMATOR_UNKNOWN (estimator out of range, determination.h);
 * AOCS_ERR_MOMENTUM_POLICY_UNKNOWN (momentum.policy out of range);
 * the wheel array's own status (aocs_wheels_init) when cfg.wheels.n != 0;
 * else the law init's own status. The selected law's state is reset (its init
 * re-run from the cached config) on every target change (select with a
 * target) and on every change into NOMINAL, so integral states start at zero.
 * On any error exec is left not initialised (step returns
 * AOCS_ERR_NOT_INITIALISED with a zero command).
 */
aocs_status_t aocs_exec_init(aocs_exec_t *exec, const aocs_exec_config_t *cfg);

/*
 * Run-time command: select law (AOCS_LAW_NONE = STANDBY) and target (NULL
 * keeps the current target). A new law is (re)initialised from the stored
 * config. With a rotating target (cfg.target_rotation_rate_D != 0) the new
 * target is qd0 from the time of the last sample on (t0 = that sensor time;
 * before any sample t0 is kept), and its wd/wd_dot must be zero. Rejected,
 * counted in select_rejected, and nothing changed on:
 * AOCS_ERR_UNKNOWN_LAW, AOCS_ERR_TARGET_INVALID, or the law init's status.
 * Selecting a law requests NOMINAL; if the executive is in SAFE it stays
 * there until the recovery rule is met. Selecting NONE enters STANDBY at once.
 */
aocs_status_t aocs_exec_select(aocs_exec_t *exec, aocs_law_id_t law, const aocs_exec_target_t *target);

/*
 * One control step on a sensor sample. Returns AOCS_OK when a command was
 * produced (whatever the mode: a rejected input is reported in
 * out->input_status and handled by SAFE, not by an error return);
 * AOCS_ERR_NULL_ARG / AOCS_ERR_NOT_INITIALISED otherwise (then *out, if
 * given, holds a zero command).
 */
aocs_status_t aocs_exec_step(aocs_exec_t *exec, const aocs_exec_input_t *in, aocs_exec_output_t *out);

/*
 * Real-time mode: the period ended without a sample. Counts one missing
 * sample; below N consecutive missing periods the last command is held
 * (zero-order hold), from N on the executive is in SAFE with a zero command
 * (no fresh rate to damp). input_status = AOCS_ERR_INPUT_MISSING.
 */
aocs_status_t aocs_exec_step_no_input(aocs_exec_t *exec, aocs_exec_output_t *out);

/*
 * Sets t0 of a rotating target: the sensor time at which it equals its qd0
 * (real-time mode: the sensor time base is the HAL clock, so the adapter maps
 * the plant's time 0 onto it). AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED.
 */
aocs_status_t aocs_exec_set_target_epoch(aocs_exec_t *exec, uint64_t t0_ns);

/*
 * The momentum-management stage's commands and telemetry of the last step (docs/spec.md 5.9): its
 * u_unload_B_Nm was taken off that step's wheel command (out->u_cmd, what the wheels deliver, is the law's
 * torque minus it, before saturation). All zero with policy NONE, and for NULL or an executive not
 * initialised. Kept out of aocs_exec_output_t so a step without momentum management costs nothing more.
 * Total.
 */
aocs_mom_output_t aocs_exec_momentum(const aocs_exec_t *exec);

/* The fault-management stage's event log (aocs/fdir/event_log.h: read with aocs_evlog_next after the last seq
 * seen), NULL for NULL or an executive not initialised. Total. */
const aocs_evlog_t *aocs_exec_events(const aocs_exec_t *exec);

/* Counters so far (zeroed struct on NULL args). Total. */
aocs_exec_counters_t aocs_exec_counters(const aocs_exec_t *exec);

#endif /* AOCS_EXEC_PIPELINE_H */
