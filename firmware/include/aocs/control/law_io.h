/*
 * Inputs shared by every law (SPEC 2: "every law takes the same inputs"),
 * and the checks every law shares (implemented in src/control/law_io.c).
 * Each law module exposes:
 *   aocs_status_t aocs_<law>_init(aocs_<law>_t *law, const aocs_<law>_config_t *cfg);
 *       validates every config value (own status per failure), copies it,
 *       resets the law's state; on failure the law stays unusable
 *       (step returns AOCS_ERR_NOT_INITIALISED).
 *   aocs_status_t aocs_<law>_step(aocs_<law>_t *law, const aocs_att_input_t *in,
 *                                 aocs_vec3_t *u_out);
 *       pure apart from the law's own state; on any error *u_out is set to
 *       zero and a status is returned, so the output is never NaN.
 * and is registered by its row in aocs/laws.def (name, id, budgets, config
 * fields), from which the executive and every tool know it.
 */
#ifndef AOCS_CONTROL_LAW_IO_H
#define AOCS_CONTROL_LAW_IO_H

#include "aocs/attitude.h"

/* Attitude laws. Frames: q_BN body w.r.t. inertial; rates in B. */
typedef struct {
    aocs_quat_t q_BN;      /* estimated attitude */
    aocs_vec3_t w_BN_B;    /* estimated body rate, rad/s */
    aocs_quat_t qd_DN;     /* target attitude */
    aocs_vec3_t wd_B;      /* target rate in B, rad/s (we = w - wd, SPEC 1) */
    aocs_vec3_t wd_dot_B;  /* target angular acceleration in B, rad/s^2 */
    real_t dt_s;           /* control period, s (> 0) */
    /* The limits the executive will saturate this step's command to (aocs_exec_config_t
     * u_max_axis, u_max_norm; 0 = that limit unused). Laws with integral action read them
     * for anti-windup (SPEC 5.2); the other laws ignore them. */
    aocs_vec3_t u_max_axis; /* per-axis limit, N m; all 0 = unused */
    real_t u_max_norm;      /* limit of |u|_2, N m; 0 = unused */
} aocs_att_input_t;

/* Orbit (station keeping) laws, SPEC 2.8 state order. */
typedef struct {
    aocs_vec3_t vel_mps;   /* [du dv dw] inertial velocity in rotating frame, m/s */
    aocs_vec3_t pos_m;     /* [dx dy dz] position error, m */
    real_t dt_s;
} aocs_orbit_input_t;

/*
 * Common input validation for attitude laws: finite everywhere
 * (AOCS_ERR_INPUT_NOT_FINITE), dt > 0 (AOCS_ERR_DT_INVALID), both
 * quaternions of unit norm within AOCS_QUAT_UNIT_TOL (AOCS_ERR_QUAT_NOT_UNIT).
 * Implemented in src/control/law_io.c.
 */
aocs_status_t aocs_att_input_check(const aocs_att_input_t *in);
aocs_status_t aocs_orbit_input_check(const aocs_orbit_input_t *in);

#define AOCS_QUAT_UNIT_TOL AOCS_R(1.0e-3)

/*
 * Config check of the laws with two scalar gains (crp_linear k1 k2,
 * quat_pd and quat_nlpd kp kd), first failure wins: either gain NaN/Inf
 * (AOCS_ERR_PARAM_NOT_FINITE), either gain <= 0 (AOCS_ERR_GAIN_NOT_POSITIVE);
 * else AOCS_OK.
 */
aocs_status_t aocs_law_check_gains(real_t g1, real_t g2);

/*
 * Last statement of every law step, so the contract above holds in one place:
 * a non-finite u with st == AOCS_OK (finite inputs whose result overflowed)
 * becomes AOCS_ERR_OUTPUT_NOT_FINITE; *u_out, when not NULL, receives u on
 * success and zero on any error. Returns the final status.
 */
aocs_status_t aocs_law_set_output(aocs_status_t st, aocs_vec3_t u, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_LAW_IO_H */
