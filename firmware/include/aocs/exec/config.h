/*
 * The executive's configuration (part of aocs/executive.h): one struct with
 * the configuration of every stage; its fields are the rows of
 * aocs/config_fields.def and aocs/laws.def (aocs/config_registry.h).
 */
#ifndef AOCS_EXEC_CONFIG_H
#define AOCS_EXEC_CONFIG_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"
#include "aocs/actuation/wheel_array.h"
#include "aocs/exec/law_dispatch.h"
#include "aocs/exec/modes.h"
#include "aocs/exec/io.h"
#include "aocs/guidance/guidance.h"
#include "aocs/estimation/determination.h"
#include "aocs/momentum/momentum.h"
#include "aocs/fdir/fdir.h"

typedef struct {
    real_t period_s;              /* control period, s; rounded to whole us (>= 1 us, <= 1000 s) */
    aocs_law_id_t law;            /* initial law; AOCS_LAW_NONE starts in STANDBY */
    aocs_exec_target_t target;    /* initial target; qd0 of a rotating target */
    aocs_vec3_t target_rotation_rate_D; /* rad/s, constant rate of D w.r.t. N in D; 0 = fixed target.
                                     * When non-zero, target.wd_B and target.wd_dot_B must be 0 (guidance computes them). */
    uint64_t target_t0_ns;        /* sensor time at which a rotating target equals target.qd_DN (lockstep: 0 = sim start) */
    aocs_exec_law_configs_t laws;
    aocs_vec3_t u_max_axis;       /* per-axis limit, N m (N); all 0 = unused, else all > 0 */
    real_t u_max_norm;            /* limit of |u|_2; 0 = unused. At least one limit must be set. */
    real_t k_safe;                /* safe-mode damping gain, N m s/rad, > 0 */
    uint32_t recover_good_samples;/* M: consecutive good samples to leave SAFE, >= 1 */
    uint32_t missing_max_periods; /* N: a gap of >= N missed samples enters SAFE, >= 1 */
    uint64_t stale_timeout_ns;    /* real-time mode: max age (HAL now - sensor time), > 0 there */
    uint64_t budget_ns;           /* step budget override; 0 = the law's BUDGET_NS (laws.def) */
    aocs_exec_clock_t clock;
    aocs_exec_guidance_config_t guidance; /* default: STEP mode */
    aocs_wheels_config_t wheels;  /* reaction wheel array; wheels.n = 0: none. Its period_s is set from
                                   * period_s at init (one source) */
    aocs_det_config_t determination; /* attitude determination; default: passthrough */
    aocs_mom_config_t momentum;   /* momentum management; default: none */
    aocs_fdir_config_t fdir;      /* fault management (docs/spec.md 5.15); default: enabled, the spec's thresholds */
} aocs_exec_config_t;

/*
 * Defaults: period 0.1 s, AOCS_LAW_NONE, identity target, no limits set
 * (the caller must set one), k_safe 1, M = 10, N = 3, stale timeout
 * 2 periods, no budget override, lockstep. Law configs zeroed (invalid).
 * No wheel array (wheels.n = 0) with the array's own defaults
 * (aocs_wheels_config_default: no friction model, no null-space management).
 * Total (no-op on NULL).
 */
void aocs_exec_config_default(aocs_exec_config_t *cfg);

/*
 * Accepted range of every actuator limit (u_max_axis components and
 * u_max_norm when set), N m for torque and N for force; aocs_exec_init gives
 * AOCS_ERR_SAT_LIMIT_NOT_POSITIVE for a limit outside it. 1e-9 is three orders
 * below the smallest actuator a spacecraft flies (micro-thrusters and
 * magnetorquers of 1e-6 N or N m): a smaller limit is a unit mistake. 1e9 is
 * the project's "effectively unlimited" value (aocs_core.limits.UNLIMITED,
 * written when a scenario sets no limit) and six orders above the largest
 * attitude actuators (CMGs of ~1e3 N m). Inside this range every square and
 * sum of squares the saturation forms is a normal number in float and in
 * double (1e-18 >> FLT_MIN, 3e18 << FLT_MAX), so the limiting is exact.
 */
#define AOCS_EXEC_U_LIMIT_MIN AOCS_R(1.0e-9)
#define AOCS_EXEC_U_LIMIT_MAX AOCS_R(1.0e9)

/*
 * Accepted control period, whole microseconds (aocs_exec_period_to_ns):
 * 1 us (a 1 MHz loop, far above any attitude loop) to 1000 s (slower is not
 * a control loop). The scenario loader reads both from the build's registry
 * (tools/registry), so it cannot accept a rate the executive refuses.
 */
#define AOCS_EXEC_PERIOD_MIN_US AOCS_R(1.0)
#define AOCS_EXEC_PERIOD_MAX_US AOCS_R(1.0e9)

#endif /* AOCS_EXEC_CONFIG_H */
