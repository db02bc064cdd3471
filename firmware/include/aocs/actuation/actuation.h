/*
 * The actuation stage (ARCHITECTURE.md "The flight pipeline"): the body
 * command of the mode (law + feedforward, safe damping, or zero) becomes
 * actuator commands. Every path first saturates the body torque to the
 * executive's limits (aocs_act_saturate: never beyond them, NaN/Inf from
 * anywhere gives zero); then the path of aocs/actuation/actuation.def:
 *
 *   BODY    the saturated body command as it is (u_cmd);
 *   WHEELS  allocated to the reaction wheel array (aocs/actuation/wheel_array.h:
 *           minimum norm, one uniform scale, speed protection from the
 *           tachometers, friction feedforward and null-space management,
 *           docs/spec.md 5.3.2); u_cmd is then the body torque the wheels
 *           deliver (the same direction), out->wheels the motor torques,
 *           out->momentum the total momentum and the speed margin. STANDBY
 *           commands no motor torque at all. Non-finite tachometer speeds give
 *           a zero wheel command (out->wheels_status says why).
 *
 *   aocs_act_limits_check(u_max_axis, u_max_norm)     at init
 *   aocs_act_init(&act, &cfg)                          selects the path
 *   loop: aocs_act_step(&act, standby, u_unsat, omega, w, &out)
 */
#ifndef AOCS_ACTUATION_ACTUATION_H
#define AOCS_ACTUATION_ACTUATION_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/actuation/actuation.def"
#include "aocs/exec/io.h"
#include "aocs/exec/config.h"

#define AOCS_ACT_ENUM_ROW(ID, ...) AOCS_ACT_##ID,
typedef enum {
    AOCS_ACTUATION_ROWS(AOCS_ACT_ENUM_ROW)
    AOCS_ACT_COUNT
} aocs_act_id_t;

/* The body-torque limits (aocs_exec_config_t.u_max_axis, u_max_norm; see aocs_exec_init). */
typedef struct {
    aocs_vec3_t u_max_axis;       /* per-axis limit, N m (N); all 0 = unused */
    real_t u_max_norm;            /* limit of |u|_2; 0 = unused */
} aocs_act_limits_t;

typedef struct {
    aocs_act_id_t id;             /* the selected path */
    aocs_act_limits_t limits;
    aocs_wheels_t wheels;         /* WHEELS: the array (initialised only on that path) */
    real_t wheel_speed_last[AOCS_WHEELS_MAX]; /* tachometer speeds of the last sample (step_no_input) */
    aocs_vec3_t w_last_B;         /* body rate of the last sample (momentum in step_no_input) */
} aocs_act_t;

/* Name of a path ("body", "wheels"); "unknown" out of range. Total. */
const char *aocs_act_name(aocs_act_id_t id);

/*
 * Limit check (aocs_exec_init): AOCS_ERR_PARAM_NOT_FINITE; AOCS_ERR_SAT_LIMIT_NOT_POSITIVE
 * (negative limit, mixed zero and non-zero per-axis limits, no limit set, or a set limit
 * outside [AOCS_EXEC_U_LIMIT_MIN, AOCS_EXEC_U_LIMIT_MAX]).
 */
aocs_status_t aocs_act_limits_check(const aocs_act_limits_t *lim);

/*
 * Apply the limits; the result is finite and within every enabled limit,
 * also when u is NaN/Inf (then zero). *saturated = 1 when changed (may be NULL).
 * A NULL lim gives zero. Total.
 */
aocs_vec3_t aocs_act_saturate(const aocs_act_limits_t *lim, aocs_vec3_t u, int *saturated);

/*
 * Selects and initialises the path from the configuration: WHEELS when
 * cfg->wheels.n != 0 (its period_s set from cfg->period_s), else BODY; the
 * limits are taken as they are (checked before). AOCS_ERR_NULL_ARG, or the
 * wheel array's own status (aocs_wheels_init).
 */
aocs_status_t aocs_act_init(aocs_act_t *act, const aocs_exec_config_t *cfg);

/* 1 when the WHEELS path is flown. Total. */
int aocs_act_has_wheels(const aocs_act_t *act);

/* The array (for the slew envelope), NULL on another path. Total. */
const aocs_wheels_t *aocs_act_wheels(const aocs_act_t *act);

/*
 * The actuators' own sensors in a sample, checked like the other inputs
 * (input acceptance): on the WHEELS path the tachometers
 * (aocs_wheels_check_speeds: AOCS_ERR_INPUT_NOT_FINITE,
 * AOCS_ERR_WHEEL_SPEED_RANGE); AOCS_OK on a path without any;
 * AOCS_ERR_NULL_ARG.
 */
aocs_status_t aocs_act_check_sample(const aocs_act_t *act, const real_t *omega_radps);

/*
 * One step: out->u_cmd = the saturated u_unsat, then the path's APPLY
 * (standby: STANDBY mode; omega_radps: tachometer speeds, AOCS_WHEELS_MAX of
 * them; w_BN_B: body rate for the momentum). *saturated = 1 when anything
 * limited the command. Total.
 */
void aocs_act_step(aocs_act_t *act, int standby, aocs_vec3_t u_unsat, const real_t *omega_radps,
                   aocs_vec3_t w_BN_B, aocs_exec_output_t *out, int *saturated);

/* step_no_input: the same on the speeds and rate of the last sample. Total. */
void aocs_act_step_held(aocs_act_t *act, int standby, aocs_vec3_t u_unsat, aocs_exec_output_t *out,
                        int *saturated);

/* ---- the rows' functions (actuation.def), declared from the rows ---- */
#define AOCS_ACT_PROTOTYPES(ID, NAME, APPLY)                                                                  \
    void APPLY(aocs_act_t *act, int standby, const real_t *omega_radps, aocs_vec3_t w_BN_B,                   \
               aocs_exec_output_t *out, int *saturated);
AOCS_ACTUATION_ROWS(AOCS_ACT_PROTOTYPES)

#endif /* AOCS_ACTUATION_ACTUATION_H */
