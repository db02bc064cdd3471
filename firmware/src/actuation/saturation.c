/*
 * Body-torque saturation of the actuation stage (aocs/actuation/actuation.h),
 * shared by every actuator path: the last line of defence, whatever a law or
 * an input did, the command that leaves the executive is finite and within
 * every enabled limit.
 */
#include <stddef.h>

#include "aocs/control/saturate.h"
#include "aocs/executive.h"

static int axis_limits_enabled(const aocs_act_limits_t *lim)
{
    const aocs_vec3_t l = lim->u_max_axis;
    return ((l.v[0] > AOCS_R(0.0)) && (l.v[1] > AOCS_R(0.0)) && (l.v[2] > AOCS_R(0.0))) ? 1 : 0;
}

/* 1 when a set limit lies in the accepted range [AOCS_EXEC_U_LIMIT_MIN, AOCS_EXEC_U_LIMIT_MAX] (aocs/exec/config.h) */
static int limit_in_range(real_t lim)
{
    return ((lim >= AOCS_EXEC_U_LIMIT_MIN) && (lim <= AOCS_EXEC_U_LIMIT_MAX)) ? 1 : 0;
}

aocs_status_t aocs_act_limits_check(const aocs_act_limits_t *lim)
{
    aocs_status_t st = AOCS_OK;
    int n_pos = 0;
    int n_zero = 0;
    if (lim == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((aocs_vec3_is_finite(lim->u_max_axis) == 0) || !AOCS_IS_FINITE(lim->u_max_norm)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else {
        for (int i = 0; i < 3; ++i) {
            if (lim->u_max_axis.v[i] > AOCS_R(0.0)) {
                n_pos++;
                if (limit_in_range(lim->u_max_axis.v[i]) == 0) {
                    st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
                }
            } else if (lim->u_max_axis.v[i] < AOCS_R(0.0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else {
                n_zero++;
            }
        }
        if (st == AOCS_OK) {
            /* per-axis: all three set or none; at least one kind of limit set; each set one in range */
            if ((n_pos != 3) && (n_zero != 3)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if (lim->u_max_norm < AOCS_R(0.0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if ((n_pos != 3) && !(lim->u_max_norm > AOCS_R(0.0))) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if ((lim->u_max_norm > AOCS_R(0.0)) && (limit_in_range(lim->u_max_norm) == 0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else {
                st = AOCS_OK;
            }
        }
    }
    return st;
}

/* Exact per-axis guard: each component within [-lim_i, lim_i], compared directly (independent of the helper). */
static aocs_vec3_t axis_guard(const aocs_act_limits_t *lim, aocs_vec3_t u, int *sat)
{
    aocs_vec3_t out = u;
    for (int i = 0; i < 3; ++i) {
        if (!(out.v[i] <= lim->u_max_axis.v[i])) {
            out.v[i] = lim->u_max_axis.v[i];
            *sat = 1;
        } else if (!(out.v[i] >= -lim->u_max_axis.v[i])) {
            out.v[i] = -lim->u_max_axis.v[i];
            *sat = 1;
        } else {
            /* within the limit */
        }
    }
    return out;
}

/*
 * Per-axis clip, then the norm scaling (saturate.h: scale-aware, exact norm
 * below the limit), then the per-axis guard again: the scaling multiplies
 * every component by max_norm / |u| < 1, but a component far below the
 * largest one is rounded in that product and could land an ulp above its
 * own (much smaller) limit. The guard only lowers magnitudes, so the norm
 * stays below its limit; the last check (never true for a scaled result) is
 * the independent line of defence.
 */
aocs_vec3_t aocs_act_saturate(const aocs_act_limits_t *lim, aocs_vec3_t u, int *saturated)
{
    aocs_vec3_t out = u;
    int sat = 0;
    int s = 0;
    if ((lim == NULL) || (aocs_vec3_is_finite(u) == 0)) {
        /* NaN or Inf from anywhere: the only command known to be safe is zero */
        out = aocs_vec3_zero();
        sat = 1;
    } else {
        const int axis = axis_limits_enabled(lim);
        if (axis != 0) {
            out = aocs_sat_clamp_per_axis(out, lim->u_max_axis, &s);
            sat |= s;
            out = axis_guard(lim, out, &sat);
        }
        if (lim->u_max_norm > AOCS_R(0.0)) {
            out = aocs_sat_scale_to_norm(out, lim->u_max_norm, &s);
            sat |= s;
            if (axis != 0) {
                out = axis_guard(lim, out, &sat);
            }
            if (aocs_sat_norm_above(out, lim->u_max_norm) != 0) {
                out = aocs_vec3_zero();
                sat = 1;
            }
        }
        if (aocs_vec3_is_finite(out) == 0) {
            out = aocs_vec3_zero();
            sat = 1;
        }
    }
    if (saturated != NULL) {
        *saturated = sat;
    }
    return out;
}
