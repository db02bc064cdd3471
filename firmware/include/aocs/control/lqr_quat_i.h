/*
 * lqr_quat_i: LQR with integral action on the reduced-quaternion error model
 * (SPEC 5.2; the model of SPEC 2.5 augmented with the integral of the error,
 * Markley & Crassidis 2014; Wie, Space Vehicle Dynamics and Control).
 *
 * Model linearised at qe_vec = 0, w = 0: x = [z; qe_vec; we], z' = qe_vec,
 * qe_vec' = 0.5 we, J we' = u:
 *     A = [[0, I, 0], [0, 0, 0.5 I], [0, 0, 0]],  B = [[0], [0], [J^-1]],
 * cost 0.5 int (x'Qx + u'Ru) dt, K = R^-1 B^T S (3x9) from the continuous
 * ARE, designed by `aocs gains` (tools/gains.toml kind lqr_quat_i: closed
 * loop stable, Riccati residual) and compiled as a constant table
 * (gains/aocs_gains.h, aocs_gains_<design>_K[3][9]). Law:
 *     u = -K [z; s qe_vec; we],   z(k+1) = z(k) + dt s qe_vec,   s = sign(qe4),
 * sign(0) = +1 (SPEC 1: q and -q give the same torque), with the same
 * conditional integration and clamp |z_i| <= z_max as quat_pid
 * (control/integral.h; the sensitivity of u to z is -K_z, the first three
 * columns, so an integral component that moves several axes is frozen when
 * it grows any saturated one). init resets z = 0 (the executive re-runs it on
 * target and mode changes). The stability of the gain is the design's
 * (checked by the tool); init checks what every stabilising K of this model
 * has: each 3x3 block diagonal of K positive.
 */
#ifndef AOCS_CONTROL_LQR_QUAT_I_H
#define AOCS_CONTROL_LQR_QUAT_I_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t k[3][9]; /* columns: z (N m per unit of z_i, z in s), qe_vec (N m), we (N m s/rad) */
    real_t z_max;   /* clamp of each |z_i|, s, > 0 */
} aocs_lqr_quat_i_config_t;

typedef struct {
    aocs_lqr_quat_i_config_t cfg; /* validated copy */
    aocs_vec3_t z;                /* integral of s qe_vec, s (reset by init) */
    int initialised;
} aocs_lqr_quat_i_t;

/*
 * Validates and copies cfg, resets z = 0; first failure wins: NULL ->
 * AOCS_ERR_NULL_ARG; an entry of K NaN/Inf -> AOCS_ERR_PARAM_NOT_FINITE; a
 * block diagonal of K <= 0 -> AOCS_ERR_GAIN_TABLE_INVALID; z_max NaN/Inf ->
 * AOCS_ERR_PARAM_NOT_FINITE; z_max <= 0 -> AOCS_ERR_INTEGRAL_LIMIT_NOT_POSITIVE.
 */
aocs_status_t aocs_lqr_quat_i_init(aocs_lqr_quat_i_t *law, const aocs_lqr_quat_i_config_t *cfg);

/*
 * u_out = -K [z; s qe_vec; we], then z advanced. Input checked by
 * aocs_att_input_check; on any error *u_out = 0, z unchanged and the status
 * is returned; a non-finite result gives AOCS_ERR_OUTPUT_NOT_FINITE.
 */
aocs_status_t aocs_lqr_quat_i_step(aocs_lqr_quat_i_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_LQR_QUAT_I_H */
