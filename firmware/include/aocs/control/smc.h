/*
 * smc: sliding mode control with a boundary layer, SPEC 2.4 (Crassidis,
 * Vadali, Markley 2000):
 *     s = we + Lambda sign(qe4) qe_vec
 *     u = J (-Lambda sign(qe4) d/dt(qe_vec) + wd_dot) + w x (J w) - J G sat(s, eps)
 *     d/dt(qe_vec) = 0.5 (qe4 I + qe_vec^x) we
 *     sat(s_i, eps_i) = s_i / eps_i for |s_i| <= eps_i, sign(s_i) outside
 * Lambda, G diagonal and positive, given by their diagonals; J a full
 * symmetric positive definite inertia. With this u the closed loop obeys
 * sdot_i = -G_i sat(s_i, eps_i), so V = 0.5 s^T s decreases outside the layer.
 */
#ifndef AOCS_CONTROL_SMC_H
#define AOCS_CONTROL_SMC_H

#include "aocs/control/law_io.h"

typedef struct {
    aocs_mat3_t inertia; /* J, kg m^2, symmetric positive definite */
    aocs_vec3_t lambda;  /* diagonal of Lambda, rad/s per unit qe_vec, > 0 */
    aocs_vec3_t g;       /* diagonal of G, rad/s^2, > 0 */
    aocs_vec3_t eps;     /* boundary layer widths, rad/s, > 0 */
} aocs_smc_config_t;

typedef struct {
    aocs_smc_config_t cfg; /* validated copy */
    int initialised;       /* set by a successful init only */
} aocs_smc_t;

/*
 * NULL -> AOCS_ERR_NULL_ARG; inertia codes of aocs_mat3_check_inertia
 * (NaN/Inf in J -> AOCS_ERR_PARAM_NOT_FINITE); NaN/Inf in lambda, g, eps ->
 * AOCS_ERR_PARAM_NOT_FINITE; lambda_i or g_i <= 0 ->
 * AOCS_ERR_GAIN_NOT_POSITIVE; eps_i <= 0 ->
 * AOCS_ERR_BOUNDARY_LAYER_NOT_POSITIVE. Law left not initialised on failure.
 */
aocs_status_t aocs_smc_init(aocs_smc_t *law, const aocs_smc_config_t *cfg);

/*
 * Commanded torque in B, N m. Errors (u_out zeroed when not NULL):
 * AOCS_ERR_NULL_ARG, AOCS_ERR_NOT_INITIALISED, the codes of
 * aocs_att_input_check, AOCS_ERR_OUTPUT_NOT_FINITE when finite inputs
 * overflow the torque.
 */
aocs_status_t aocs_smc_step(aocs_smc_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_SMC_H */
