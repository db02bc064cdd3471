/*
 * quat_pd: linear quaternion PD, SPEC 2.2:
 *     u = -kp sign(qe4) qe_vec - kd we,   kp, kd > 0,
 * qe = q (x) qd^-1, we = w - wd, sign(0) = +1 (SPEC 1 anti-unwinding: q and
 * -q give the same torque).
 */
#ifndef AOCS_CONTROL_QUAT_PD_H
#define AOCS_CONTROL_QUAT_PD_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t kp; /* attitude gain, N m, > 0 */
    real_t kd; /* rate gain, N m s/rad, > 0 */
} aocs_quat_pd_config_t;

typedef struct {
    aocs_quat_pd_config_t cfg; /* validated copy */
    int initialised;           /* set by a successful init only */
} aocs_quat_pd_t;

/*
 * NULL -> AOCS_ERR_NULL_ARG; NaN/Inf -> AOCS_ERR_PARAM_NOT_FINITE;
 * gain <= 0 -> AOCS_ERR_GAIN_NOT_POSITIVE; law left not initialised on failure.
 */
aocs_status_t aocs_quat_pd_init(aocs_quat_pd_t *law, const aocs_quat_pd_config_t *cfg);

/*
 * Commanded torque in B, N m. Errors (u_out zeroed when not NULL):
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, the codes of
 * aocs_att_input_check, AOCS_ERR_OUTPUT_NOT_FINITE when finite inputs
 * overflow the torque.
 */
aocs_status_t aocs_quat_pd_step(aocs_quat_pd_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_QUAT_PD_H */
