/*
 * Input checks, safe-mode command and actuator saturation of the executive.
 * The saturation here is the last line of defence: whatever a law or an
 * input did, the command that leaves the executive is finite and within
 * every enabled limit.
 */
#include <stddef.h>

#include "aocs/control/saturate.h"
#include "exec_internal.h"

void aocs_exec_count(uint32_t *counter, uint32_t n)
{
    if (counter != NULL) {
        if ((UINT32_MAX - *counter) < n) {
            *counter = UINT32_MAX;
        } else {
            *counter += n;
        }
    }
}

static int quat_is_unit(aocs_quat_t q)
{
    real_t n = aocs_quat_norm(q);
    return (AOCS_IS_FINITE(n) && (AOCS_FABS(n - AOCS_R(1.0)) <= AOCS_QUAT_UNIT_TOL)) ? 1 : 0;
}

/* Orbit sample rule: the orbit flag set, r and v finite (SPEC: orbit_lqr state x = [r; v]). */
static aocs_status_t orbit_input_check(const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if ((in->valid & AOCS_EXEC_VALID_ORBIT) == 0u) {
        st = AOCS_ERR_INPUT_INVALID;
    } else if ((aocs_vec3_is_finite(in->pos_m) == 0) || (aocs_vec3_is_finite(in->vel_mps) == 0)) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/* Attitude sample rule: attitude and rate flags set, finite, |q| = 1 within AOCS_QUAT_UNIT_TOL. */
static aocs_status_t attitude_input_check(const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    const uint32_t need = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
    if ((in->valid & need) != need) {
        st = AOCS_ERR_INPUT_INVALID;
    } else if ((aocs_quat_is_finite(in->q_BN) == 0) || (aocs_vec3_is_finite(in->w_BN_B) == 0)) {
        st = AOCS_ERR_INPUT_NOT_FINITE;
    } else if (quat_is_unit(in->q_BN) == 0) {
        st = AOCS_ERR_QUAT_NOT_UNIT;
    } else {
        st = AOCS_OK;
    }
    return st;
}

/*
 * An orbit law needs an orbit sample, an attitude law an attitude sample.
 * With no law (STANDBY, control disabled) the executive does not know which
 * kind of vehicle state it is fed, so a sample is good when it passes either
 * rule. A sample that passes neither reports the orbit rule's verdict when
 * it carries only the orbit flag (it claims to be an orbit sample), else the
 * attitude rule's verdict (the behaviour before orbit samples were accepted).
 */
aocs_status_t aocs_exec_input_check(aocs_law_id_t law, const aocs_exec_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if (in == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_law_is_orbit(law) != 0) {
        st = orbit_input_check(in);
    } else if (law != AOCS_LAW_NONE) {
        st = attitude_input_check(in);
    } else {
        const uint32_t att_flags = AOCS_EXEC_VALID_ATT | AOCS_EXEC_VALID_RATE;
        st = attitude_input_check(in);
        if (st != AOCS_OK) {
            const aocs_status_t st_orbit = orbit_input_check(in);
            if ((st_orbit == AOCS_OK) ||
                (((in->valid & AOCS_EXEC_VALID_ORBIT) != 0u) && ((in->valid & att_flags) == 0u))) {
                st = st_orbit;
            }
        }
    }
    return st;
}

aocs_status_t aocs_exec_target_check(const aocs_exec_target_t *target)
{
    aocs_status_t st = AOCS_OK;
    if (target == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((aocs_quat_is_finite(target->qd_DN) == 0) || (quat_is_unit(target->qd_DN) == 0) ||
               (aocs_vec3_is_finite(target->wd_B) == 0) || (aocs_vec3_is_finite(target->wd_dot_B) == 0)) {
        st = AOCS_ERR_TARGET_INVALID;
    } else {
        st = AOCS_OK;
    }
    return st;
}

aocs_vec3_t aocs_exec_safe_command(const aocs_exec_config_t *cfg, aocs_law_id_t law,
                                   const aocs_exec_input_t *in)
{
    aocs_vec3_t u = aocs_vec3_zero();
    /* orbit: zero force (drifting is safe, thrusting on bad data is not) */
    if ((cfg != NULL) && (in != NULL) && (aocs_law_is_orbit(law) == 0) &&
        ((in->valid & AOCS_EXEC_VALID_RATE) != 0u) && (aocs_vec3_is_finite(in->w_BN_B) != 0)) {
        /* rate damping: d/dt(0.5 w^T J w) = -k_safe |w|^2 <= 0 without attitude knowledge */
        u = aocs_vec3_scale(in->w_BN_B, -cfg->k_safe);
    }
    return u;
}

static int axis_limits_enabled(const aocs_exec_config_t *cfg)
{
    const aocs_vec3_t l = cfg->u_max_axis;
    return ((l.v[0] > AOCS_R(0.0)) && (l.v[1] > AOCS_R(0.0)) && (l.v[2] > AOCS_R(0.0))) ? 1 : 0;
}

/* 1 when a set limit lies in the accepted range [AOCS_EXEC_U_LIMIT_MIN, AOCS_EXEC_U_LIMIT_MAX] (executive.h) */
static int limit_in_range(real_t lim)
{
    return ((lim >= AOCS_EXEC_U_LIMIT_MIN) && (lim <= AOCS_EXEC_U_LIMIT_MAX)) ? 1 : 0;
}

aocs_status_t aocs_exec_limits_check(const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    int n_pos = 0;
    int n_zero = 0;
    if (cfg == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if ((aocs_vec3_is_finite(cfg->u_max_axis) == 0) || !AOCS_IS_FINITE(cfg->u_max_norm)) {
        st = AOCS_ERR_PARAM_NOT_FINITE;
    } else {
        for (int i = 0; i < 3; ++i) {
            if (cfg->u_max_axis.v[i] > AOCS_R(0.0)) {
                n_pos++;
                if (limit_in_range(cfg->u_max_axis.v[i]) == 0) {
                    st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
                }
            } else if (cfg->u_max_axis.v[i] < AOCS_R(0.0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else {
                n_zero++;
            }
        }
        if (st == AOCS_OK) {
            /* per-axis: all three set or none; at least one kind of limit set; each set one in range */
            if ((n_pos != 3) && (n_zero != 3)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if (cfg->u_max_norm < AOCS_R(0.0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if ((n_pos != 3) && !(cfg->u_max_norm > AOCS_R(0.0))) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else if ((cfg->u_max_norm > AOCS_R(0.0)) && (limit_in_range(cfg->u_max_norm) == 0)) {
                st = AOCS_ERR_SAT_LIMIT_NOT_POSITIVE;
            } else {
                st = AOCS_OK;
            }
        }
    }
    return st;
}

/* Exact per-axis guard: each component within [-lim_i, lim_i], compared directly (independent of the helper). */
static aocs_vec3_t axis_guard(const aocs_exec_config_t *cfg, aocs_vec3_t u, int *sat)
{
    aocs_vec3_t out = u;
    for (int i = 0; i < 3; ++i) {
        if (!(out.v[i] <= cfg->u_max_axis.v[i])) {
            out.v[i] = cfg->u_max_axis.v[i];
            *sat = 1;
        } else if (!(out.v[i] >= -cfg->u_max_axis.v[i])) {
            out.v[i] = -cfg->u_max_axis.v[i];
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
aocs_vec3_t aocs_exec_saturate(const aocs_exec_config_t *cfg, aocs_vec3_t u, int *saturated)
{
    aocs_vec3_t out = u;
    int sat = 0;
    int s = 0;
    if ((cfg == NULL) || (aocs_vec3_is_finite(u) == 0)) {
        /* NaN or Inf from anywhere: the only command known to be safe is zero */
        out = aocs_vec3_zero();
        sat = 1;
    } else {
        const int axis = axis_limits_enabled(cfg);
        if (axis != 0) {
            out = aocs_sat_clamp_per_axis(out, cfg->u_max_axis, &s);
            sat |= s;
            out = axis_guard(cfg, out, &sat);
        }
        if (cfg->u_max_norm > AOCS_R(0.0)) {
            out = aocs_sat_scale_to_norm(out, cfg->u_max_norm, &s);
            sat |= s;
            if (axis != 0) {
                out = axis_guard(cfg, out, &sat);
            }
            if (aocs_sat_norm_above(out, cfg->u_max_norm) != 0) {
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
