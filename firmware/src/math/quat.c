/*
 * Quaternions, scalar last (SPEC 1; Markley & Crassidis 2014, ch. 2).
 * q = [q_v; q4], A(q) maps N-components to B-components, and the product is
 * Shuster's, so A(q (x) p) = A(q) A(p).
 */
#include <stddef.h>

#include "aocs/attitude.h"

/* below this norm a quaternion carries no attitude (same in float) */
#define AOCS_QUAT_NORM_MIN AOCS_R(1.0e-6)

aocs_quat_t aocs_quat_make(real_t q1, real_t q2, real_t q3, real_t q4)
{
    aocs_quat_t r;
    r.q[0] = q1;
    r.q[1] = q2;
    r.q[2] = q3;
    r.q[3] = q4;
    return r;
}

aocs_quat_t aocs_quat_identity(void)
{
    return aocs_quat_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0), AOCS_R(1.0));
}

aocs_vec3_t aocs_quat_vec(aocs_quat_t q)
{
    return aocs_vec3_make(q.q[0], q.q[1], q.q[2]);
}

/* q (x) p = [q4 p_v + p4 q_v - q_v x p_v ; q4 p4 - q_v . p_v]  (SPEC 1, M&C eq. 2.82-2.85) */
aocs_quat_t aocs_quat_mul(aocs_quat_t q, aocs_quat_t p)
{
    aocs_vec3_t qv = aocs_quat_vec(q);
    aocs_vec3_t pv = aocs_quat_vec(p);
    aocs_vec3_t v = aocs_vec3_sub(aocs_vec3_add(aocs_vec3_scale(pv, q.q[3]), aocs_vec3_scale(qv, p.q[3])),
                                  aocs_vec3_cross(qv, pv));
    return aocs_quat_make(v.v[0], v.v[1], v.v[2], (q.q[3] * p.q[3]) - aocs_vec3_dot(qv, pv));
}

aocs_quat_t aocs_quat_conj(aocs_quat_t q)
{
    return aocs_quat_make(-q.q[0], -q.q[1], -q.q[2], q.q[3]);
}

real_t aocs_quat_norm(aocs_quat_t q)
{
    return AOCS_SQRT((q.q[0] * q.q[0]) + (q.q[1] * q.q[1]) + (q.q[2] * q.q[2]) + (q.q[3] * q.q[3]));
}

int aocs_quat_is_finite(aocs_quat_t q)
{
    return (AOCS_IS_FINITE(q.q[0]) && AOCS_IS_FINITE(q.q[1]) && AOCS_IS_FINITE(q.q[2]) &&
            AOCS_IS_FINITE(q.q[3]))
               ? 1
               : 0;
}

aocs_status_t aocs_quat_normalize(aocs_quat_t q, aocs_quat_t *out)
{
    aocs_status_t st = AOCS_OK;
    real_t n = aocs_quat_norm(q);
    if (out == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (!AOCS_IS_FINITE(n) || !(n >= AOCS_QUAT_NORM_MIN)) {
        st = AOCS_ERR_QUAT_NOT_UNIT;
    } else {
        *out = aocs_quat_make(q.q[0] / n, q.q[1] / n, q.q[2] / n, q.q[3] / n);
    }
    return st;
}

/*
 * A(q) = (q4^2 - |q_v|^2) I + 2 q_v q_v^T - 2 q4 [q_v x]  (SPEC 1).
 * Not normalised: a non-unit q gives |q|^2 times a rotation.
 */
aocs_mat3_t aocs_quat_to_dcm(aocs_quat_t q)
{
    aocs_vec3_t qv = aocs_quat_vec(q);
    real_t q4 = q.q[3];
    aocs_mat3_t a = aocs_mat3_scale(aocs_mat3_identity(), (q4 * q4) - aocs_vec3_norm_sq(qv));
    a = aocs_mat3_add(a, aocs_mat3_scale(aocs_mat3_outer(qv, qv), AOCS_R(2.0)));
    a = aocs_mat3_add(a, aocs_mat3_scale(aocs_mat3_skew(qv), AOCS_R(-2.0) * q4));
    return a;
}

/* qe = q (x) qd^-1 (SPEC 1); qd is unit so its inverse is its conjugate */
aocs_quat_t aocs_quat_error(aocs_quat_t q, aocs_quat_t qd)
{
    return aocs_quat_mul(q, aocs_quat_conj(qd));
}

/* sign(q4), sign(0) = +1 (SPEC 1 anti-unwinding); NaN also gives +1 */
real_t aocs_quat_sign_q4(aocs_quat_t q)
{
    return (q.q[3] < AOCS_R(0.0)) ? AOCS_R(-1.0) : AOCS_R(1.0);
}

/*
 * qdot = 0.5 Xi(q) w, Xi(q) = [q4 I + q_v^x ; -q_v^T]  (SPEC 1)
 */
aocs_quat_t aocs_quat_derivative(aocs_quat_t q, aocs_vec3_t w)
{
    aocs_vec3_t qv = aocs_quat_vec(q);
    aocs_vec3_t v = aocs_vec3_scale(aocs_vec3_add(aocs_vec3_scale(w, q.q[3]), aocs_vec3_cross(qv, w)),
                                    AOCS_R(0.5));
    return aocs_quat_make(v.v[0], v.v[1], v.v[2], AOCS_R(-0.5) * aocs_vec3_dot(qv, w));
}

/* Xi(q)^T v = q4 v_v - q_v x v_v - v4 q_v */
aocs_vec3_t aocs_quat_xi_transpose_mul(aocs_quat_t q, aocs_quat_t v)
{
    aocs_vec3_t qv = aocs_quat_vec(q);
    aocs_vec3_t vv = aocs_quat_vec(v);
    return aocs_vec3_sub(aocs_vec3_sub(aocs_vec3_scale(vv, q.q[3]), aocs_vec3_cross(qv, vv)),
                         aocs_vec3_scale(qv, v.q[3]));
}

/*
 * 2 asin(|q_v|) (SPEC 1), evaluated as 2 atan2(|q_v|, |q4|): identical for a
 * unit q, accurate near 0 and 180 deg where asin loses digits, never NaN for
 * a slightly non-unit q, and always in [0, pi] (short rotation).
 */
real_t aocs_quat_angle(aocs_quat_t q)
{
    return AOCS_R(2.0) * AOCS_ATAN2(aocs_vec3_norm(aocs_quat_vec(q)), AOCS_FABS(q.q[3]));
}
