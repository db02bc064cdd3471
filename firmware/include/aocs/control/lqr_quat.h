/*
 * lqr_quat: LQR on the reduced-quaternion error model (SPEC 2.5, Bhatia 2018).
 *
 * Model linearised at qe_vec = 0, w = 0: x = [qe_vec; we],
 * A = [[0, 0.5 I], [0, 0]], B = [[0], [J^-1]], cost 0.5 int (x'Qx + u'Ru) dt,
 * K = R^-1 B^T S from the continuous ARE. Law:
 *     u = -K [sign(qe4) qe_vec; we],   sign(0) = +1 (SPEC 1 anti-unwinding).
 * K is designed by the tools and compiled in as a constant table
 * (gains/aocs_gains.h, aocs_gains_<design>_K); the config only carries it.
 * qe is renormalised before use (the inputs are unit only to
 * AOCS_QUAT_UNIT_TOL).
 */
#ifndef AOCS_CONTROL_LQR_QUAT_H
#define AOCS_CONTROL_LQR_QUAT_H

#include "aocs/control/law_io.h"

typedef struct {
    real_t k[3][6]; /* columns: qe_vec (N m per unit of qe_i), then we (N m s/rad) */
} aocs_lqr_quat_config_t;

typedef struct {
    aocs_lqr_quat_config_t cfg;
    int initialised;
} aocs_lqr_quat_t;

/*
 * Validates and copies cfg: every entry finite (AOCS_ERR_PARAM_NOT_FINITE);
 * the diagonals of the attitude block k[i][i] and of the rate block
 * k[i][3+i] strictly positive, which every stabilising LQR gain of this model
 * has (AOCS_ERR_GAIN_TABLE_INVALID). NULL -> AOCS_ERR_NULL_ARG.
 */
aocs_status_t aocs_lqr_quat_init(aocs_lqr_quat_t *law, const aocs_lqr_quat_config_t *cfg);

/*
 * u_out = -K [sign(qe4) qe_vec; we]. Input checked by aocs_att_input_check;
 * on any error *u_out = 0 and the status is returned; a non-finite result
 * (input magnitudes near REAL_MAX) gives AOCS_ERR_OUTPUT_NOT_FINITE.
 */
aocs_status_t aocs_lqr_quat_step(aocs_lqr_quat_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_LQR_QUAT_H */
