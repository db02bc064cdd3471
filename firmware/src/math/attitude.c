/*
 * Attitude parameter conversions and kinematics (SPEC 1). Conventions are
 * written down in docs/conventions.md; this file implements them.
 */
#include <stddef.h>

#include "aocs/attitude.h"

/*
 * Shepperd's method in Markley's column form: the four diagonal values
 * d_i = 4 q_i^2 are formed from A; the column of the symmetric 4x4 matrix
 * 4 q q^T with the largest d_i is divided by its norm. sum(d_i) = 4 for any A,
 * so the chosen column has norm >= 1: no division by ~0, exact at 180 deg.
 * Off-diagonal sums/differences from A(q) of SPEC 1:
 *   4 q1 q4 = A23 - A32, 4 q2 q4 = A31 - A13, 4 q3 q4 = A12 - A21,
 *   4 q1 q2 = A12 + A21, 4 q1 q3 = A13 + A31, 4 q2 q3 = A23 + A32.
 */
aocs_quat_t aocs_dcm_to_quat(aocs_mat3_t a)
{
    real_t tr = a.m[0][0] + a.m[1][1] + a.m[2][2];
    real_t d[4];
    real_t c[4];
    real_t n;
    int k = 3;
    int i;

    d[0] = AOCS_R(1.0) + (AOCS_R(2.0) * a.m[0][0]) - tr;
    d[1] = AOCS_R(1.0) + (AOCS_R(2.0) * a.m[1][1]) - tr;
    d[2] = AOCS_R(1.0) + (AOCS_R(2.0) * a.m[2][2]) - tr;
    d[3] = AOCS_R(1.0) + tr;
    for (i = 0; i < 3; ++i) {
        if (d[i] > d[k]) {
            k = i;
        }
    }
    if (k == 0) {
        c[0] = d[0];
        c[1] = a.m[0][1] + a.m[1][0];
        c[2] = a.m[0][2] + a.m[2][0];
        c[3] = a.m[1][2] - a.m[2][1];
    } else if (k == 1) {
        c[0] = a.m[0][1] + a.m[1][0];
        c[1] = d[1];
        c[2] = a.m[1][2] + a.m[2][1];
        c[3] = a.m[2][0] - a.m[0][2];
    } else if (k == 2) {
        c[0] = a.m[0][2] + a.m[2][0];
        c[1] = a.m[1][2] + a.m[2][1];
        c[2] = d[2];
        c[3] = a.m[0][1] - a.m[1][0];
    } else {
        c[0] = a.m[1][2] - a.m[2][1];
        c[1] = a.m[2][0] - a.m[0][2];
        c[2] = a.m[0][1] - a.m[1][0];
        c[3] = d[3];
    }
    n = AOCS_SQRT((c[0] * c[0]) + (c[1] * c[1]) + (c[2] * c[2]) + (c[3] * c[3]));
    if (c[3] < AOCS_R(0.0)) {
        n = -n; /* representative with q4 >= 0 */
    }
    return aocs_quat_make(c[0] / n, c[1] / n, c[2] / n, c[3] / n);
}

/*
 * rho = q_v / q4 on the short-rotation representative (q4 >= 0)
 * (SPEC 2.1, docs/conventions.md "CRP"). q is used as given (rho is
 * invariant to the scale of q; AOCS_CRP_Q4_MIN assumes a unit q).
 */
aocs_status_t aocs_quat_to_crp(aocs_quat_t q, aocs_vec3_t *rho)
{
    aocs_status_t st = AOCS_OK;
    real_t q4 = AOCS_FABS(q.q[3]);
    aocs_vec3_t qv = aocs_vec3_scale(aocs_quat_vec(q), aocs_quat_sign_q4(q));
    aocs_vec3_t r;

    if (rho == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_quat_is_finite(q) == 0) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (!(q4 > AOCS_CRP_Q4_MIN)) {
        st = AOCS_ERR_CRP_SINGULAR;
    } else {
        r = aocs_vec3_scale(qv, AOCS_R(1.0) / q4);
        if (aocs_vec3_is_finite(r) == 0) {
            st = AOCS_ERR_CRP_SINGULAR;
        } else {
            *rho = r;
        }
    }
    return st;
}

/*
 * q = [rho; 1] / sqrt(1 + |rho|^2), evaluated as [rho/m; 1/m] / sqrt(1/m^2 +
 * |rho/m|^2) with m = max(1, |rho|_inf) so that |rho|^2 cannot overflow.
 * Non-finite rho gives a non-finite q (callers check with aocs_quat_is_finite).
 */
aocs_quat_t aocs_crp_to_quat(aocs_vec3_t rho)
{
    real_t m = aocs_vec3_norm_inf(rho);
    real_t inv_m;
    real_t n;
    aocs_vec3_t rs;

    if (!(m > AOCS_R(1.0))) {
        m = AOCS_R(1.0);
    }
    inv_m = AOCS_R(1.0) / m;
    rs = aocs_vec3_scale(rho, inv_m);
    n = AOCS_SQRT((inv_m * inv_m) + aocs_vec3_norm_sq(rs));
    return aocs_quat_make(rs.v[0] / n, rs.v[1] / n, rs.v[2] / n, inv_m / n);
}

/*
 * sigma = q_v / (1 + q4) with the sign of q chosen so that q4 >= 0, hence
 * 1 + q4 >= 1 and |sigma| <= 1 for a unit q (SPEC 1, docs/conventions.md).
 */
aocs_vec3_t aocs_quat_to_mrp(aocs_quat_t q)
{
    real_t s = aocs_quat_sign_q4(q);
    return aocs_vec3_scale(aocs_quat_vec(q), s / (AOCS_R(1.0) + (s * q.q[3])));
}

/*
 * q = [2 sigma; 1 - s2] / (1 + s2), s2 = |sigma|^2 (standard inverse; q4 < 0
 * when |sigma| > 1). For |sigma| > 1 it is evaluated through the shadow set
 * (whose quaternion is exactly -q) so that a huge sigma cannot overflow s2.
 */
aocs_quat_t aocs_mrp_to_quat(aocs_vec3_t sigma)
{
    real_t s2 = aocs_vec3_norm_sq(sigma);
    real_t sign = AOCS_R(1.0);
    aocs_vec3_t sv = sigma;
    real_t den;
    aocs_vec3_t v;

    if (s2 > AOCS_R(1.0)) {
        sv = aocs_vec3_scale(sigma, AOCS_R(-1.0) / s2);
        s2 = aocs_vec3_norm_sq(sv);
        sign = AOCS_R(-1.0);
    }
    den = AOCS_R(1.0) + s2;
    v = aocs_vec3_scale(sv, (AOCS_R(2.0) * sign) / den);
    return aocs_quat_make(v.v[0], v.v[1], v.v[2], (sign * (AOCS_R(1.0) - s2)) / den);
}

/* shadow set -sigma / |sigma|^2 when |sigma| > 1 (SPEC 1) */
aocs_vec3_t aocs_mrp_shadow_if_needed(aocs_vec3_t sigma)
{
    real_t s2 = aocs_vec3_norm_sq(sigma);
    aocs_vec3_t r = sigma;
    if (s2 > AOCS_R(1.0)) {
        r = aocs_vec3_scale(sigma, AOCS_R(-1.0) / s2);
    }
    return r;
}

/*
 * 3-2-1: A = R1(roll) R2(pitch) R3(yaw) (passive, N -> B), hence
 * q = q1(roll) (x) q2(pitch) (x) q3(yaw) with A(q (x) p) = A(q) A(p), where
 * the elementary quaternion about axis e is [e sin(a/2); cos(a/2)].
 */
aocs_quat_t aocs_euler321_to_quat(aocs_euler321_t e)
{
    real_t hy = AOCS_R(0.5) * e.yaw;
    real_t hp = AOCS_R(0.5) * e.pitch;
    real_t hr = AOCS_R(0.5) * e.roll;
    aocs_quat_t qz = aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_SIN(hy), AOCS_COS(hy));
    aocs_quat_t qy = aocs_quat_make(AOCS_R(0.0), AOCS_SIN(hp), AOCS_R(0.0), AOCS_COS(hp));
    aocs_quat_t qx = aocs_quat_make(AOCS_SIN(hr), AOCS_R(0.0), AOCS_R(0.0), AOCS_COS(hr));
    return aocs_quat_mul(qx, aocs_quat_mul(qy, qz));
}

/* wrap an angle in (-2 pi, 2 pi] to (-pi, pi] */
static real_t wrap_pi(real_t x)
{
    const real_t pi = AOCS_R(3.14159265358979323846);
    real_t r = x;
    if (r > pi) {
        r -= AOCS_R(2.0) * pi;
    } else if (!(r > -pi)) {
        r += AOCS_R(2.0) * pi;
    } else {
        /* already in (-pi, pi] */
    }
    return r;
}

/*
 * Inverse of the 3-2-1 sequence straight from q (Bernardes & Viollet 2022,
 * direct method). Expanding q = qx(r) (x) qy(p) (x) qz(y) with half angles:
 *   q3 + q1 = (c(p/2) - s(p/2)) sin((y+r)/2),  q4 - q2 = (c(p/2) - s(p/2)) cos((y+r)/2)
 *   q3 - q1 = (c(p/2) + s(p/2)) sin((y-r)/2),  q4 + q2 = (c(p/2) + s(p/2)) cos((y-r)/2)
 * and both factors are >= 0 for |p| <= 90 deg. With n_minus, n_plus the
 * norms of those pairs: cos p = n_minus n_plus, sin p = 2 (q2 q4 - q1 q3),
 * so pitch comes from atan2 (no asin, never NaN, also for a non-unit q).
 * (y+r)/2 and (y-r)/2 each come from their own atan2; an error in the one
 * whose factor is ~0 near a lock multiplies that small factor when the
 * attitude is rebuilt, so the angles always reproduce A(q) to rounding.
 * Gimbal lock (docs/conventions.md "Euler 3-2-1"): when a factor is below
 * 16 eps |q|, only y - r (pitch +90) or y + r (pitch -90) is defined;
 * roll = 0 and yaw takes the whole defined combination.
 */
aocs_euler321_t aocs_quat_to_euler321(aocs_quat_t q)
{
    real_t sp_re = q.q[3] - q.q[1];
    real_t sp_im = q.q[2] + q.q[0];
    real_t dp_re = q.q[3] + q.q[1];
    real_t dp_im = q.q[2] - q.q[0];
    real_t n_minus = AOCS_SQRT((sp_re * sp_re) + (sp_im * sp_im));
    real_t n_plus = AOCS_SQRT((dp_re * dp_re) + (dp_im * dp_im));
    real_t lock_tol = AOCS_R(16.0) * AOCS_REAL_EPS * (n_minus + n_plus);
    real_t half_sum = AOCS_ATAN2(sp_im, sp_re);  /* (yaw + roll) / 2 */
    real_t half_diff = AOCS_ATAN2(dp_im, dp_re); /* (yaw - roll) / 2 */
    aocs_euler321_t e;

    e.pitch = AOCS_ATAN2(AOCS_R(2.0) * ((q.q[1] * q.q[3]) - (q.q[0] * q.q[2])), n_minus * n_plus);
    if (n_minus <= lock_tol) {
        e.yaw = wrap_pi(AOCS_R(2.0) * half_diff);
        e.roll = AOCS_R(0.0);
    } else if (n_plus <= lock_tol) {
        e.yaw = wrap_pi(AOCS_R(2.0) * half_sum);
        e.roll = AOCS_R(0.0);
    } else {
        e.yaw = wrap_pi(half_sum + half_diff);
        e.roll = wrap_pi(half_sum - half_diff);
    }
    return e;
}

/* A = R1(roll) R2(pitch) R3(yaw), passive elementary rotations */
aocs_mat3_t aocs_euler321_to_dcm(aocs_euler321_t e)
{
    real_t cy = AOCS_COS(e.yaw);
    real_t sy = AOCS_SIN(e.yaw);
    real_t cp = AOCS_COS(e.pitch);
    real_t sp = AOCS_SIN(e.pitch);
    real_t cr = AOCS_COS(e.roll);
    real_t sr = AOCS_SIN(e.roll);
    aocs_mat3_t a;

    a.m[0][0] = cp * cy;
    a.m[0][1] = cp * sy;
    a.m[0][2] = -sp;
    a.m[1][0] = (sr * sp * cy) - (cr * sy);
    a.m[1][1] = (sr * sp * sy) + (cr * cy);
    a.m[1][2] = sr * cp;
    a.m[2][0] = (cr * sp * cy) + (sr * sy);
    a.m[2][1] = (cr * sp * sy) - (sr * cy);
    a.m[2][2] = cr * cp;
    return a;
}

/* rhodot = 0.5 (I + rho^x + rho rho^T) w (SPEC 1) */
aocs_vec3_t aocs_crp_derivative(aocs_vec3_t rho, aocs_vec3_t w)
{
    aocs_vec3_t v = aocs_vec3_add(aocs_vec3_add(w, aocs_vec3_cross(rho, w)),
                                  aocs_vec3_scale(rho, aocs_vec3_dot(rho, w)));
    return aocs_vec3_scale(v, AOCS_R(0.5));
}

/* G(sigma) = 0.25 ((1 - s.s) I + 2 sigma^x + 2 sigma sigma^T) (SPEC 1) */
aocs_mat3_t aocs_mrp_b_matrix(aocs_vec3_t sigma)
{
    aocs_mat3_t g = aocs_mat3_scale(aocs_mat3_identity(), AOCS_R(1.0) - aocs_vec3_norm_sq(sigma));
    g = aocs_mat3_add(g, aocs_mat3_scale(aocs_mat3_skew(sigma), AOCS_R(2.0)));
    g = aocs_mat3_add(g, aocs_mat3_scale(aocs_mat3_outer(sigma, sigma), AOCS_R(2.0)));
    return aocs_mat3_scale(g, AOCS_R(0.25));
}

/* sigmadot = G(sigma) w (SPEC 1) */
aocs_vec3_t aocs_mrp_derivative(aocs_vec3_t sigma, aocs_vec3_t w)
{
    return aocs_mat3_mul_vec(aocs_mrp_b_matrix(sigma), w);
}
