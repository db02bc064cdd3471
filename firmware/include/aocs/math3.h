/*
 * 3-vectors and 3x3 matrices. Value semantics: small structs passed and
 * returned by value; every function is total (no status) unless it can fail,
 * in which case it returns aocs_status_t and writes through a pointer.
 */
#ifndef AOCS_MATH3_H
#define AOCS_MATH3_H

#include "aocs/types.h"

typedef struct {
    real_t v[3];
} aocs_vec3_t;

typedef struct {
    real_t m[3][3]; /* row-major: m[row][col] */
} aocs_mat3_t;

/* ---- vec3 (src/math/vec3.c) ---- */
aocs_vec3_t aocs_vec3_make(real_t x, real_t y, real_t z);
aocs_vec3_t aocs_vec3_zero(void);
aocs_vec3_t aocs_vec3_add(aocs_vec3_t a, aocs_vec3_t b);
aocs_vec3_t aocs_vec3_sub(aocs_vec3_t a, aocs_vec3_t b);
aocs_vec3_t aocs_vec3_scale(aocs_vec3_t a, real_t s);
aocs_vec3_t aocs_vec3_neg(aocs_vec3_t a);
aocs_vec3_t aocs_vec3_hadamard(aocs_vec3_t a, aocs_vec3_t b); /* element-wise product */
real_t aocs_vec3_dot(aocs_vec3_t a, aocs_vec3_t b);
aocs_vec3_t aocs_vec3_cross(aocs_vec3_t a, aocs_vec3_t b);
real_t aocs_vec3_norm(aocs_vec3_t a);
real_t aocs_vec3_norm_sq(aocs_vec3_t a);
real_t aocs_vec3_norm_inf(aocs_vec3_t a);       /* max |a_i| */
int aocs_vec3_is_finite(aocs_vec3_t a);          /* 1 when every element is finite */

/* ---- mat3 (src/math/mat3.c) ---- */
aocs_mat3_t aocs_mat3_identity(void);
aocs_mat3_t aocs_mat3_zero(void);
aocs_mat3_t aocs_mat3_diag(aocs_vec3_t d);
aocs_mat3_t aocs_mat3_add(aocs_mat3_t a, aocs_mat3_t b);
aocs_mat3_t aocs_mat3_scale(aocs_mat3_t a, real_t s);
aocs_mat3_t aocs_mat3_mul(aocs_mat3_t a, aocs_mat3_t b);
aocs_mat3_t aocs_mat3_transpose(aocs_mat3_t a);
aocs_vec3_t aocs_mat3_mul_vec(aocs_mat3_t a, aocs_vec3_t x);
aocs_vec3_t aocs_mat3_tmul_vec(aocs_mat3_t a, aocs_vec3_t x);   /* a^T x */
aocs_mat3_t aocs_mat3_skew(aocs_vec3_t a);                       /* a^x, SPEC 1 */
aocs_mat3_t aocs_mat3_outer(aocs_vec3_t a, aocs_vec3_t b);       /* a b^T */
real_t aocs_mat3_det(aocs_mat3_t a);
int aocs_mat3_is_finite(aocs_mat3_t a);
/*
 * Inverse by adjugate after scaling each row by its largest element.
 * AOCS_ERR_INERTIA_SINGULAR when |det| <= 1e3 eps * (product of the scaled
 * row norms) (a unit-free test from Hadamard's inequality),
 * AOCS_ERR_PARAM_NOT_FINITE for NaN/Inf input, AOCS_ERR_NULL_ARG for a NULL
 * out; out untouched on error (docs/conventions.md).
 */
aocs_status_t aocs_mat3_inverse(aocs_mat3_t a, aocs_mat3_t *out);
/*
 * Checks an inertia matrix: finite (AOCS_ERR_PARAM_NOT_FINITE), symmetric to
 * a relative tolerance (AOCS_ERR_INERTIA_NOT_SYMMETRIC), positive definite by
 * Sylvester's leading minors (AOCS_ERR_INERTIA_NOT_POS_DEF), invertible
 * (AOCS_ERR_INERTIA_SINGULAR). Triangle inequalities of a physical body are
 * not required (test inertias such as I3 must pass).
 */
aocs_status_t aocs_mat3_check_inertia(aocs_mat3_t j);

#endif /* AOCS_MATH3_H */
