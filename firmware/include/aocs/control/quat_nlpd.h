/*
 * quat_nlpd: nonlinear quaternion PD, SPEC 2.3, both variants:
 *     u = -kp sign(qe4) qe_vec - kd (1 -/+ qe_vec^T qe_vec) we,   kp, kd > 0,
 * NEG uses the minus sign (rate gain kd qe4^2, fading near 180 deg), POS the
 * plus sign (rate gain growing to 2 kd near 180 deg). qe = q (x) qd^-1,
 * we = w - wd, sign(0) = +1 (SPEC 1).
 */
#ifndef AOCS_CONTROL_QUAT_NLPD_H
#define AOCS_CONTROL_QUAT_NLPD_H

#include "aocs/control/law_io.h"

typedef enum {
    AOCS_QUAT_NLPD_NEG = 0, /* kd (1 - qe_vec.qe_vec) */
    AOCS_QUAT_NLPD_POS = 1  /* kd (1 + qe_vec.qe_vec) */
} aocs_quat_nlpd_variant_t;

typedef struct {
    real_t kp; /* attitude gain, N m, > 0 */
    real_t kd; /* rate gain, N m s/rad, > 0 */
    aocs_quat_nlpd_variant_t variant;
} aocs_quat_nlpd_config_t;

typedef struct {
    aocs_quat_nlpd_config_t cfg; /* validated copy */
    int initialised;             /* set by a successful init only */
} aocs_quat_nlpd_t;

/*
 * NULL -> AOCS_ERR_NULL_ARG; NaN/Inf -> AOCS_ERR_PARAM_NOT_FINITE;
 * gain <= 0 -> AOCS_ERR_GAIN_NOT_POSITIVE; unknown variant ->
 * AOCS_ERR_MODE_INVALID; law left not initialised on failure.
 */
aocs_status_t aocs_quat_nlpd_init(aocs_quat_nlpd_t *law, const aocs_quat_nlpd_config_t *cfg);

/*
 * Commanded torque in B, N m. Errors (u_out zeroed when not NULL):
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, the codes of
 * aocs_att_input_check, AOCS_ERR_OUTPUT_NOT_FINITE when finite inputs
 * overflow the torque.
 */
aocs_status_t aocs_quat_nlpd_step(aocs_quat_nlpd_t *law, const aocs_att_input_t *in,
                                  aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_QUAT_NLPD_H */
