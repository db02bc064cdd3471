/*
 * quat_pid: quaternion PD plus the integral of the attitude error, SPEC 5.2
 * (Markley & Crassidis 2014, attitude control with integral action; Wie, Space Vehicle
 * Dynamics and Control):
 *     u = -kp s qe_vec - kd we - ki z,   z' = s qe_vec,   s = sign(qe4),
 * qe = q (x) qd^-1, we = w - wd, sign(0) = +1 (SPEC 1: q and -q give the same
 * torque). z (s) is integrated by forward Euler, z(k+1) = z(k) + dt s qe_vec,
 * with conditional integration against the executive's limits and the clamp
 * |z_i| <= z_max (control/integral.h states the discretisation and the rule).
 * init resets z = 0; the executive re-runs init on a target change and on a
 * mode change into NOMINAL, so the integral starts from zero each time.
 *
 * Gain condition (checked at init). Linearised about qe = 0, we = 0 with
 * qe_vec ~ theta / 2 and wd = 0: J theta'' = -(kp/2) theta - kd theta'
 * - (ki/2) int theta, i.e. J theta''' + kd theta'' + (kp/2) theta' + (ki/2)
 * theta = 0. With scalar gains it decouples along the principal axes of J;
 * per principal inertia lambda the cubic lambda s^3 + kd s^2 + (kp/2) s + ki/2
 * is Hurwitz (Routh) iff all coefficients are > 0 and kd (kp/2) > lambda
 * (ki/2), i.e.
 *     kd kp > lambda_max ki.
 * init checks it with lambda_max bounded by the Gershgorin row sums of J
 * (max_i J_ii + sum_j!=i |J_ij|, exact for a diagonal J), so an accepted
 * config is stable at every axis; the bound can refuse a marginal config of
 * a J with products of inertia.
 *
 * The inertia is the node's `inertia` key (laws.def: this row's FROM_FIELD
 * column copies the one inertia field into this config at init).
 */
#ifndef AOCS_CONTROL_QUAT_PID_H
#define AOCS_CONTROL_QUAT_PID_H

#include "aocs/control/law_io.h"

typedef struct {
    aocs_mat3_t inertia; /* J, kg m^2, of the gain condition (the scenario's plant inertia) */
    real_t kp;           /* attitude gain, N m, > 0 */
    real_t kd;           /* rate gain, N m s/rad, > 0 */
    real_t ki;           /* integral gain, N m/s, > 0 */
    real_t z_max;        /* clamp of each |z_i|, s, > 0 */
} aocs_quat_pid_config_t;

typedef struct {
    aocs_quat_pid_config_t cfg; /* validated copy */
    aocs_vec3_t z;              /* integral of s qe_vec, s (reset by init) */
    int initialised;            /* set by a successful init only */
} aocs_quat_pid_t;

/*
 * Validates and copies cfg, resets z = 0; first failure wins:
 * NULL -> AOCS_ERR_NULL_ARG; kp, kd, ki or z_max NaN/Inf ->
 * AOCS_ERR_PARAM_NOT_FINITE; kp, kd or ki <= 0 -> AOCS_ERR_GAIN_NOT_POSITIVE;
 * z_max <= 0 -> AOCS_ERR_INTEGRAL_LIMIT_NOT_POSITIVE; the inertia codes of
 * aocs_mat3_check_inertia; kd kp <= lambda_max ki -> AOCS_ERR_PID_NOT_HURWITZ.
 * The law is left not initialised on failure.
 */
aocs_status_t aocs_quat_pid_init(aocs_quat_pid_t *law, const aocs_quat_pid_config_t *cfg);

/*
 * Commanded torque in B, N m, then z advanced (conditional integration,
 * clamp). Errors (u_out zeroed when not NULL, z unchanged):
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, the codes of
 * aocs_att_input_check, AOCS_ERR_OUTPUT_NOT_FINITE when finite inputs
 * overflow the torque.
 */
aocs_status_t aocs_quat_pid_step(aocs_quat_pid_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

/*
 * The Gershgorin bound on the largest eigenvalue of a symmetric J used by the
 * gain conditions: max_i (J_ii + sum_{j != i} |J_ij|). Total.
 */
real_t aocs_quat_pid_inertia_bound(aocs_mat3_t j);

#endif /* AOCS_CONTROL_QUAT_PID_H */
