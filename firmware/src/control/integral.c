/* integral: conditional integration and clamp of the integral laws, SPEC 5.2, see integral.h. */
#include "aocs/control/integral.h"

/* 1 when |u|_2 is at or above a norm limit in use (computed once per step: one square root) */
static int at_norm_limit(aocs_vec3_t u, real_t u_max_norm)
{
    return ((u_max_norm > AOCS_R(0.0)) && (aocs_vec3_norm(u) >= u_max_norm)) ? 1 : 0;
}

/* the two rules of integral.h, with the norm test already made */
static int grows(aocs_vec3_t u, aocs_vec3_t du, aocs_vec3_t u_max_axis, int norm_saturated)
{
    int g = 0;
    for (int i = 0; i < 3; ++i) {
        const real_t lim = u_max_axis.v[i];
        if ((lim > AOCS_R(0.0)) && (AOCS_FABS(u.v[i]) >= lim) && ((u.v[i] * du.v[i]) > AOCS_R(0.0))) {
            g = 1;
        }
    }
    if ((norm_saturated != 0) && (aocs_vec3_dot(u, du) > AOCS_R(0.0))) {
        g = 1;
    }
    return g;
}

int aocs_integral_grows_saturation(aocs_vec3_t u, aocs_vec3_t du, aocs_vec3_t u_max_axis, real_t u_max_norm)
{
    return grows(u, du, u_max_axis, at_norm_limit(u, u_max_norm));
}

aocs_vec3_t aocs_integral_update(aocs_vec3_t z, aocs_vec3_t e, real_t dt_s, aocs_mat3_t sens, aocs_vec3_t u,
                                 aocs_vec3_t u_max_axis, real_t u_max_norm, real_t z_max)
{
    aocs_vec3_t out = z;
    const int norm_saturated = at_norm_limit(u, u_max_norm);
    for (int j = 0; j < 3; ++j) {
        const real_t dz = dt_s * e.v[j];
        const aocs_vec3_t du = aocs_vec3_make(sens.m[0][j] * dz, sens.m[1][j] * dz, sens.m[2][j] * dz);
        real_t zj = z.v[j];
        if (grows(u, du, u_max_axis, norm_saturated) == 0) {
            zj += dz;
        }
        if (!AOCS_IS_FINITE(zj)) {
            zj = z.v[j];
        }
        /* |z_j| <= z_max; a NaN z_max (never past init) leaves 0 */
        if (zj > z_max) {
            zj = z_max;
        } else if (zj < -z_max) {
            zj = -z_max;
        } else if (!(AOCS_FABS(zj) <= z_max)) {
            zj = AOCS_R(0.0);
        } else {
            /* within the clamp */
        }
        out.v[j] = zj;
    }
    return out;
}
