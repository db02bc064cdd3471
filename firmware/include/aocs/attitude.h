/*
 * Attitude representations and kinematics, SPEC section 1 conventions:
 * quaternion scalar LAST q = [q1 q2 q3 q4], q4 = cos(phi/2); A(q) maps
 * N-components to B-components; product q (x) p is the Shuster product with
 * A(q (x) p) = A(q) A(p) (Markley & Crassidis 2014, eq. 2.82-2.85).
 */
#ifndef AOCS_ATTITUDE_H
#define AOCS_ATTITUDE_H

#include "aocs/math3.h"

typedef struct {
    real_t q[4]; /* q[0..2] vector part, q[3] scalar part */
} aocs_quat_t;

/* Euler 3-2-1 angles (yaw psi about z, then pitch theta about y', then roll phi about x''), rad */
typedef struct {
    real_t yaw;
    real_t pitch;
    real_t roll;
} aocs_euler321_t;

/* ---- quaternion (src/math/quat.c) ---- */
aocs_quat_t aocs_quat_identity(void);
aocs_quat_t aocs_quat_make(real_t q1, real_t q2, real_t q3, real_t q4);
aocs_vec3_t aocs_quat_vec(aocs_quat_t q);               /* [q1 q2 q3] */
aocs_quat_t aocs_quat_mul(aocs_quat_t q, aocs_quat_t p); /* q (x) p, SPEC 1 */
aocs_quat_t aocs_quat_conj(aocs_quat_t q);               /* inverse of a unit quaternion */
real_t aocs_quat_norm(aocs_quat_t q);
int aocs_quat_is_finite(aocs_quat_t q);
/* normalise; AOCS_ERR_QUAT_NOT_UNIT if the norm is ~0 or not finite */
aocs_status_t aocs_quat_normalize(aocs_quat_t q, aocs_quat_t *out);
aocs_mat3_t aocs_quat_to_dcm(aocs_quat_t q);             /* A(q) */
/* qe = q (x) qd^-1 (SPEC 1) */
aocs_quat_t aocs_quat_error(aocs_quat_t q, aocs_quat_t qd);
/* sign(q4) with sign(0) = +1, never 0 (SPEC 1 anti-unwinding) */
real_t aocs_quat_sign_q4(aocs_quat_t q);
/* qdot = 0.5 Xi(q) w (SPEC 1) */
aocs_quat_t aocs_quat_derivative(aocs_quat_t q, aocs_vec3_t w);
/* Xi(q) applied transposed: Xi(q)^T v4 (3-vector), used by laws and tests */
aocs_vec3_t aocs_quat_xi_transpose_mul(aocs_quat_t q, aocs_quat_t v);
/* true pointing angle 2 asin(|q_vec|) in rad, in [0, pi] */
real_t aocs_quat_angle(aocs_quat_t q);

/* ---- conversions (src/math/attitude.c) ---- */
aocs_quat_t aocs_dcm_to_quat(aocs_mat3_t a);   /* Shepperd's method, q4 >= 0 */
/*
 * Gibbs (CRP) rho = q_vec / q4. Uses the short-rotation representative
 * (flips q when q4 < 0). AOCS_ERR_CRP_SINGULAR when |q4| is so small that
 * rho is not representable (|q4| <= AOCS_CRP_Q4_MIN, documented in
 * docs/conventions.md), AOCS_ERR_INPUT_NOT_FINITE for NaN/Inf input,
 * AOCS_ERR_NULL_ARG for a NULL rho; out is untouched on every error.
 */
aocs_status_t aocs_quat_to_crp(aocs_quat_t q, aocs_vec3_t *rho);
aocs_quat_t aocs_crp_to_quat(aocs_vec3_t rho); /* [rho;1]/sqrt(1+|rho|^2) */
/* MRP sigma = q_vec / (1 + q4), always returns the set with |sigma| <= 1 */
aocs_vec3_t aocs_quat_to_mrp(aocs_quat_t q);
aocs_quat_t aocs_mrp_to_quat(aocs_vec3_t sigma);
/* shadow set -sigma / |sigma|^2 when |sigma| > 1, else sigma (SPEC 1) */
aocs_vec3_t aocs_mrp_shadow_if_needed(aocs_vec3_t sigma);
aocs_quat_t aocs_euler321_to_quat(aocs_euler321_t e);
aocs_euler321_t aocs_quat_to_euler321(aocs_quat_t q);
aocs_mat3_t aocs_euler321_to_dcm(aocs_euler321_t e);

/* ---- kinematics of the parameter sets (src/math/attitude.c) ---- */
/* rhodot = 0.5 (I + rho^x + rho rho^T) w (SPEC 1) */
aocs_vec3_t aocs_crp_derivative(aocs_vec3_t rho, aocs_vec3_t w);
/* G(sigma) = 0.25 ((1 - s.s) I + 2 sigma^x + 2 sigma sigma^T) (SPEC 1) */
aocs_mat3_t aocs_mrp_b_matrix(aocs_vec3_t sigma);
/* sigmadot = G(sigma) w */
aocs_vec3_t aocs_mrp_derivative(aocs_vec3_t sigma, aocs_vec3_t w);

/*
 * Below this |q4| the Gibbs vector is declared singular. Double: |rho| > ~1e8.
 * Float: a computed qe4 carries ~6e-8 of rounding, so the limit sits well
 * above it (|rho| > ~1e6) and the singular case is still detected.
 */
#if defined(AOCS_REAL_IS_FLOAT)
#define AOCS_CRP_Q4_MIN AOCS_R(1.0e-6)
#else
#define AOCS_CRP_Q4_MIN AOCS_R(1.0e-8)
#endif

#endif /* AOCS_ATTITUDE_H */
