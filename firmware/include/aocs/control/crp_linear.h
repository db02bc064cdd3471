/*
 * crp_linear: linear feedback on Cayley-Rodrigues (Gibbs) parameters,
 * SPEC 2.1 (Rotea, Tsiotras, Corless 1998):
 *     u = -k1 we - k2 rho(qe),   k1, k2 > 0,
 * with qe = q (x) qd^-1, we = w - wd (SPEC 1) and rho = qe_vec / qe4 of the
 * short-rotation representative (qe4 >= 0; rho is the same for qe and -qe).
 * Lyapunov function V = 0.5 w^T J w + k2 ln(1 + |rho|^2), Vdot = -k1 w^T w.
 *
 * Singularity at 180 deg: when |qe4| <= AOCS_CRP_Q4_MIN (attitude.h) the
 * Gibbs vector is not representable; the step then returns
 * AOCS_ERR_CRP_SINGULAR with u = 0 and never divides by ~0. The executive
 * treats this like any other law error and goes to safe mode (the law is
 * unusable there by construction, not by accident).
 */
#ifndef AOCS_CONTROL_CRP_LINEAR_H
#define AOCS_CONTROL_CRP_LINEAR_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t k1; /* rate gain, N m s/rad, > 0 */
    real_t k2; /* Gibbs-vector gain, N m, > 0 */
} aocs_crp_linear_config_t;

typedef struct {
    aocs_crp_linear_config_t cfg; /* validated copy */
    int initialised;              /* set by a successful init only */
} aocs_crp_linear_t;

/*
 * NULL -> AOCS_ERR_NULL_ARG; NaN/Inf gain -> AOCS_ERR_PARAM_NOT_FINITE;
 * gain <= 0 -> AOCS_ERR_GAIN_NOT_POSITIVE. On failure law is left not
 * initialised (when law itself is not NULL).
 */
aocs_status_t aocs_crp_linear_init(aocs_crp_linear_t *law, const aocs_crp_linear_config_t *cfg);

/*
 * Commanded torque in B, N m. Errors (u_out zeroed when not NULL):
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, the codes of
 * aocs_att_input_check, AOCS_ERR_CRP_SINGULAR (|qe4| <= AOCS_CRP_Q4_MIN),
 * AOCS_ERR_OUTPUT_NOT_FINITE when finite inputs overflow the torque.
 */
aocs_status_t aocs_crp_linear_step(aocs_crp_linear_t *law, const aocs_att_input_t *in,
                                   aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_CRP_LINEAR_H */
