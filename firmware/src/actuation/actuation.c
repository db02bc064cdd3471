/*
 * The actuation stage (aocs/actuation/actuation.h): the body-torque
 * saturation every path shares (saturation.c), then the selected path of
 * aocs/actuation/actuation.def: BODY (the saturated body torque) or WHEELS
 * (its allocation to the reaction wheel array, wheel_array.c).
 */
#include <stddef.h>

#include "aocs/executive.h"

#define ACT_NAME_ROW(ID, NAME, ...) (NAME),

const char *aocs_act_name(aocs_act_id_t id)
{
    static const char *const act_names[AOCS_ACT_COUNT] = {AOCS_ACTUATION_ROWS(ACT_NAME_ROW)};
    const char *name = "unknown";
    if (((int)id >= 0) && (id < AOCS_ACT_COUNT)) {
        name = act_names[id];
    }
    return name;
}

aocs_status_t aocs_act_init(aocs_act_t *act, const aocs_exec_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((act == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        act->limits.u_max_axis = cfg->u_max_axis;
        act->limits.u_max_norm = cfg->u_max_norm;
        act->id = AOCS_ACT_BODY;
        if (cfg->wheels.n != 0u) {
            aocs_wheels_config_t w = cfg->wheels;
            w.period_s = cfg->period_s; /* the speed protection's horizon is the control period */
            st = aocs_wheels_init(&act->wheels, &w);
            act->id = AOCS_ACT_WHEELS;
        }
    }
    return st;
}

int aocs_act_has_wheels(const aocs_act_t *act)
{
    return ((act != NULL) && (act->id == AOCS_ACT_WHEELS) && (act->wheels.initialised != 0)) ? 1 : 0;
}

const aocs_wheels_t *aocs_act_wheels(const aocs_act_t *act)
{
    const aocs_wheels_t *w = NULL;
    if (aocs_act_has_wheels(act) != 0) {
        w = &act->wheels;
    }
    return w;
}

aocs_status_t aocs_act_check_sample(const aocs_act_t *act, const real_t *omega_radps)
{
    aocs_status_t st = AOCS_OK;
    if ((act == NULL) || (omega_radps == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (aocs_act_has_wheels(act) != 0) {
        st = aocs_wheels_check_speeds(&act->wheels, omega_radps);
    } else {
        st = AOCS_OK;
    }
    return st;
}

#define ACT_APPLY_CASE(ID, NAME, APPLY)                                  \
    case AOCS_ACT_##ID:                                                  \
        APPLY(act, standby, omega_radps, w_BN_B, out, saturated);        \
        break;

void aocs_act_step(aocs_act_t *act, int standby, aocs_vec3_t u_unsat, const real_t *omega_radps,
                   aocs_vec3_t w_BN_B, aocs_exec_output_t *out, int *saturated)
{
    if ((act != NULL) && (omega_radps != NULL) && (out != NULL) && (saturated != NULL)) {
        out->u_cmd = aocs_act_saturate(&act->limits, u_unsat, saturated);
        switch (act->id) {
        AOCS_ACTUATION_ROWS(ACT_APPLY_CASE)
        default:
            /* not reachable: set by aocs_act_init; the saturated body torque stands */
            break;
        }
    }
}

void aocs_act_step_held(aocs_act_t *act, int standby, aocs_vec3_t u_unsat, aocs_exec_output_t *out,
                        int *saturated)
{
    if (act != NULL) {
        aocs_act_step(act, standby, u_unsat, act->wheel_speed_last, act->w_last_B, out, saturated);
    }
}

void aocs_act_body_apply(aocs_act_t *act, int standby, const real_t *omega_radps, aocs_vec3_t w_BN_B,
                         aocs_exec_output_t *out, int *saturated)
{
    /* the saturated body torque is the command */
    (void)act;
    (void)standby;
    (void)omega_radps;
    (void)w_BN_B;
    (void)out;
    (void)saturated;
}

/* The output guard of the wheel path (docs/spec.md 5.3.3): every motor command finite and within exactly
 * +-u_s,max and the body torque finite, else the whole allocation is replaced by zero and reported
 * (AOCS_ERR_WHEEL_CMD_INVALID). The allocation builds them so; this is the independent check. */
static void act_wheels_guard(const aocs_wheels_t *wa, aocs_exec_output_t *out)
{
    int ok = aocs_vec3_is_finite(out->wheels.u_body_B_nm);
    for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
        const real_t lim = (i < wa->cfg.n) ? wa->cfg.u_max_nm[i] : AOCS_R(0.0);
        if (!(AOCS_FABS(out->wheels.u_s_nm[i]) <= lim)) {
            ok = 0; /* also a NaN */
        }
    }
    if (ok == 0) {
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            out->wheels.u_s_nm[i] = AOCS_R(0.0);
            out->wheels.friction_nm[i] = AOCS_R(0.0);
            out->wheels.null_nm[i] = AOCS_R(0.0);
        }
        out->wheels.u_body_B_nm = aocs_vec3_zero();
        out->wheels.scale = AOCS_R(0.0);
        out->wheels.null_scale = AOCS_R(0.0);
        out->wheels_status = AOCS_ERR_WHEEL_CMD_INVALID;
    }
}

void aocs_act_wheels_apply(aocs_act_t *act, int standby, const real_t *omega_radps, aocs_vec3_t w_BN_B,
                           aocs_exec_output_t *out, int *saturated)
{
    if (act->wheels.initialised != 0) {
        out->wheels_status = aocs_wheels_allocate(&act->wheels, out->u_cmd, omega_radps, &out->wheels);
        if (standby != 0) {
            /* STANDBY commands nothing: no motor torque at all, so neither the friction feedforward nor the
             * null-space management (they act while a law or the safe damping flies; docs/spec.md 5.3.2) */
            for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
                out->wheels.u_s_nm[i] = AOCS_R(0.0);
                out->wheels.friction_nm[i] = AOCS_R(0.0);
                out->wheels.null_nm[i] = AOCS_R(0.0);
            }
        }
        act_wheels_guard(&act->wheels, out);
        /* what the wheels deliver: u_cmd scaled (same direction), zero when the allocation failed */
        out->u_cmd = out->wheels.u_body_B_nm;
        if ((out->wheels_status != AOCS_OK) || (out->wheels.scale < AOCS_R(1.0))) {
            *saturated = 1;
        }
        if (aocs_vec3_is_finite(w_BN_B) != 0) {
            (void)aocs_wheels_momentum(&act->wheels, w_BN_B, omega_radps, &out->momentum);
        }
        /* kept for step_no_input (which passes these same arrays back: copying onto itself is a no-op) */
        for (uint32_t i = 0u; i < AOCS_WHEELS_MAX; ++i) {
            act->wheel_speed_last[i] = omega_radps[i];
        }
        act->w_last_B = w_BN_B;
    }
}
