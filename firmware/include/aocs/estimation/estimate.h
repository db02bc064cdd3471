/*
 * The estimate of one step of the attitude-determination stage
 * (aocs/estimation/determination.h), as the guidance, the law and the SAFE
 * mode read it, and its telemetry (the executive's output, the wire).
 *
 * The error state of a filter is x = [dth; db] (dth the attitude error's
 * rotation vector in B, rad; db the gyro-bias error, rad/s; docs/spec.md
 * 5.6); its covariance P (6x6) is sent as the upper triangle, row by row:
 * p_upper = P00 P01 P02 P03 P04 P05 P11 P12 ... P55 (21 values). An
 * estimator without a covariance (passthrough) sends zeros.
 */
#ifndef AOCS_ESTIMATION_ESTIMATE_H
#define AOCS_ESTIMATION_ESTIMATE_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/math3.h"

/* values of the 6x6 covariance's upper triangle */
#define AOCS_EST_P_UPPER_COUNT 21u

typedef struct {
    aocs_quat_t q_BN;             /* attitude estimate */
    aocs_vec3_t w_BN_B;           /* body rate estimate, rad/s */
    uint32_t valid;               /* AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE of the estimate */
    aocs_status_t status;         /* AOCS_OK: usable for the law this step; else why not */
    /* telemetry of a filter (zero for passthrough) */
    aocs_vec3_t bias_B_radps;     /* gyro bias estimate in B, rad/s */
    real_t p_upper[AOCS_EST_P_UPPER_COUNT]; /* covariance of [dth (rad); db (rad/s)], upper triangle row-major */
    aocs_status_t st_status;      /* this step's star-tracker sample: AOCS_OK used, AOCS_ERR_INPUT_MISSING none,
                                   * else why it was rejected (gated, hostile) */
    uint32_t n_st_used;           /* star-tracker samples used since the filter started */
    uint32_t n_st_gated;          /* rejected by the innovation gate */
    uint32_t n_st_hostile;        /* rejected as malformed (NaN, non-unit, stale, future, too old) */
    uint32_t n_restarts;          /* times the filter went back to waiting (gap, covariance failure, reset) */
    real_t innovation_chi2;       /* d^2 = y^T S^-1 y of this step's tracker sample when one was tested (st_status
                                   * AOCS_OK, AOCS_ERR_MEKF_GATED or AOCS_ERR_MEKF_ST_EXCLUDED), else 0 */
    aocs_vec3_t innovation_white; /* that sample's whitened innovation z = L^-1 y (S = L L^T): |z|^2 = d^2, N(0, I)
                                   * under the filter's model (the tracker's noise adaptation, spec 5.15.3); else 0 */
} aocs_det_output_t;

#endif /* AOCS_ESTIMATION_ESTIMATE_H */
