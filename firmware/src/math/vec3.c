/*
 * 3-vector helpers (math3.h). All functions are total: no status, no
 * division. Value semantics: small structs in and out by value.
 */
#include "aocs/math3.h"

aocs_vec3_t aocs_vec3_make(real_t x, real_t y, real_t z)
{
    aocs_vec3_t r;
    r.v[0] = x;
    r.v[1] = y;
    r.v[2] = z;
    return r;
}

aocs_vec3_t aocs_vec3_zero(void)
{
    return aocs_vec3_make(AOCS_R(0.0), AOCS_R(0.0), AOCS_R(0.0));
}

aocs_vec3_t aocs_vec3_add(aocs_vec3_t a, aocs_vec3_t b)
{
    return aocs_vec3_make(a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2]);
}

aocs_vec3_t aocs_vec3_sub(aocs_vec3_t a, aocs_vec3_t b)
{
    return aocs_vec3_make(a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2]);
}

aocs_vec3_t aocs_vec3_scale(aocs_vec3_t a, real_t s)
{
    return aocs_vec3_make(a.v[0] * s, a.v[1] * s, a.v[2] * s);
}

aocs_vec3_t aocs_vec3_neg(aocs_vec3_t a)
{
    return aocs_vec3_make(-a.v[0], -a.v[1], -a.v[2]);
}

aocs_vec3_t aocs_vec3_hadamard(aocs_vec3_t a, aocs_vec3_t b)
{
    return aocs_vec3_make(a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2]);
}

real_t aocs_vec3_dot(aocs_vec3_t a, aocs_vec3_t b)
{
    return (a.v[0] * b.v[0]) + (a.v[1] * b.v[1]) + (a.v[2] * b.v[2]);
}

aocs_vec3_t aocs_vec3_cross(aocs_vec3_t a, aocs_vec3_t b)
{
    return aocs_vec3_make((a.v[1] * b.v[2]) - (a.v[2] * b.v[1]),
                          (a.v[2] * b.v[0]) - (a.v[0] * b.v[2]),
                          (a.v[0] * b.v[1]) - (a.v[1] * b.v[0]));
}

real_t aocs_vec3_norm_sq(aocs_vec3_t a)
{
    return aocs_vec3_dot(a, a);
}

real_t aocs_vec3_norm(aocs_vec3_t a)
{
    return AOCS_SQRT(aocs_vec3_norm_sq(a));
}

/* a NaN element makes the result NaN (never hidden behind a finite max) */
real_t aocs_vec3_norm_inf(aocs_vec3_t a)
{
    real_t m = AOCS_FABS(a.v[0]);
    int i;
    for (i = 1; i < 3; ++i) {
        real_t x = AOCS_FABS(a.v[i]);
        if ((isnan(x) != 0) || (x > m)) {
            m = x;
        }
    }
    return m;
}

int aocs_vec3_is_finite(aocs_vec3_t a)
{
    return (AOCS_IS_FINITE(a.v[0]) && AOCS_IS_FINITE(a.v[1]) && AOCS_IS_FINITE(a.v[2])) ? 1 : 0;
}
