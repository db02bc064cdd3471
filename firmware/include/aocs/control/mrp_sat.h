/*
 * mrp_sat: saturated, model-independent MRP regulator (SPEC 2.7, Gao, Lu,
 * Wang 2010). The law never reads the inertia.
 *
 * sigma = MRP of qe = q (x) qd^-1, taken with qe4 >= 0 so that |sigma| <= 1
 * (the shadow set -sigma/|sigma|^2 whenever the other set has |sigma| > 1);
 * sigmadot = G(sigma) we, G = 0.25 ((1 - s.s) I + 2 sigma^x + 2 sigma sigma^T).
 *
 * Variant AOCS_MRP_SAT_LINEAR:
 *     u = G(sigma)^T S2(-k sigmadot - S1(lambda sigma))
 *   S_j(x) = (phi_j1(x1), phi_j2(x2), phi_j3(x3)), phi_ji the linear saturation
 *   aocs_sat_linear(x, L_ji, M_ji) (identity up to L, bounded by M).
 * Variant AOCS_MRP_SAT_TANH (generalised saturation):
 *     u = -(2/sqrt 3) G(sigma)^T S3(k sigmadot + lambda sigma),
 *   phi(x) = M tanh(x / M) with M = u_max (aocs_sat_tanh); l1..m2 unused.
 *
 * Why |u|_2 <= uM (both variants). G G^T = (0.25 (1 + s.s))^2 I, i.e. G is
 * 0.25 (1 + s.s) times an orthogonal matrix, so for any y
 *     |G^T y| = 0.25 (1 + |sigma|^2) |y| <= 0.5 |y|      (|sigma| <= 1).
 * Linear: |y_i| <= M2i, so |y| <= sqrt 3 max M2i and the inequality chain
 *     L1i = M1i < L2i <= M2i <= (2/sqrt 3) uM
 * gives |u| <= 0.5 sqrt 3 M2 <= 0.5 sqrt 3 (2/sqrt 3) uM = uM.
 * (L1 = M1: S1 is a plain clamp; M1 < L2: the sigma term alone never
 * saturates S2, which Gao et al. need for global asymptotic stability;
 * L2 <= M2: S2 is a linear saturation; M2 <= (2/sqrt 3) uM: the bound.)
 * Tanh: |y_i| < uM, |y| < sqrt 3 uM, so |u| <= (2/sqrt 3)(0.5)(sqrt 3 uM) = uM.
 * The rates stay bounded, |w_i| <~ 4 M1i / k (SPEC 2.7).
 * In floating point the chain holds to a few ulps; a final guard
 * (aocs_sat_scale_to_norm to uM) makes |u| <= uM hold exactly as computed,
 * and counts the steps in which it acted (guard_count, rounding only).
 */
#ifndef AOCS_CONTROL_MRP_SAT_H
#define AOCS_CONTROL_MRP_SAT_H

#include <stdint.h>
#include "aocs/control/law_io.h"

typedef enum {
    AOCS_MRP_SAT_LINEAR = 0,
    AOCS_MRP_SAT_TANH = 1
} aocs_mrp_sat_variant_t;

typedef struct {
    aocs_mrp_sat_variant_t variant;
    real_t k;         /* rate gain, N m s (> 0) */
    real_t lambda;    /* attitude gain (> 0) */
    real_t u_max;     /* torque bound uM on |u|_2, N m (> 0) */
    aocs_vec3_t l1;   /* S1 linear zone, per axis (linear variant) */
    aocs_vec3_t m1;   /* S1 bound (= l1) */
    aocs_vec3_t l2;   /* S2 linear zone (> m1) */
    aocs_vec3_t m2;   /* S2 bound (>= l2, <= (2/sqrt 3) u_max) */
} aocs_mrp_sat_config_t;

typedef struct {
    aocs_mrp_sat_config_t cfg;
    int initialised;
    int shadow_used;       /* 1 when the last step used the shadow set (qe4 < 0) */
    uint32_t guard_count;  /* steps in which the final |u| <= uM guard acted */
} aocs_mrp_sat_t;

/*
 * Validates and copies cfg, resets the state. Checks, in this order:
 *   variant known                                  AOCS_ERR_MODE_INVALID
 *   every value finite (all fields)                AOCS_ERR_PARAM_NOT_FINITE
 *   k > 0, lambda > 0                              AOCS_ERR_GAIN_NOT_POSITIVE
 *   u_max > 0; linear: every l1,m1,l2,m2 > 0       AOCS_ERR_SAT_LIMIT_NOT_POSITIVE
 * linear variant only, per axis:
 *   L1 = M1 (relative tolerance 4 eps)             AOCS_ERR_SAT_L1_NOT_EQUAL_M1
 *   M1 < L2                                        AOCS_ERR_SAT_M1_NOT_BELOW_L2
 *   L2 <= M2                                       AOCS_ERR_SAT_L2_ABOVE_M2
 *   M2 <= (2/sqrt 3) uM (relative tolerance 8 eps, AOCS_ERR_SAT_M2_ABOVE_UMAX
 *       so M2 = 2 uM / sqrt 3 computed in real_t passes; the reference's
 *       M2 = 0.06 with uM = 0.05 is rejected)
 */
aocs_status_t aocs_mrp_sat_init(aocs_mrp_sat_t *law, const aocs_mrp_sat_config_t *cfg);

/*
 * u_out = the law above, |u_out|_2 <= u_max. Input checked by
 * aocs_att_input_check; finite w and wd whose difference overflows give
 * AOCS_ERR_OUTPUT_NOT_FINITE; on any error *u_out = 0 and the status is
 * returned.
 */
aocs_status_t aocs_mrp_sat_step(aocs_mrp_sat_t *law, const aocs_att_input_t *in, aocs_vec3_t *u_out);

#endif /* AOCS_CONTROL_MRP_SAT_H */
