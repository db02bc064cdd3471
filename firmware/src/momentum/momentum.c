/*
 * The momentum-management stage (aocs/momentum/momentum.h): names, init, the
 * trigger with hysteresis and the dispatch to the selected policy, expanded
 * from aocs/momentum/momentum.def; policy NONE (no unloading).
 */
#include <stddef.h>
#include <string.h>

#include "aocs/executive.h"

#define MOM_NAME_ROW(ID, NAME, ...) (NAME),
#define MOM_BUDGET_ROW(ID, NAME, INIT, STEP, BUDGET_NS, ...) (BUDGET_NS),

static void mom_zero_commands(aocs_mom_output_t *out)
{
    out->dipole_Am2 = aocs_vec3_zero();
    for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
        out->thruster_on_s[i] = AOCS_R(0.0);
    }
    out->u_unload_B_Nm = aocs_vec3_zero();
}

const char *aocs_mom_name(aocs_mom_id_t id)
{
    static const char *const mom_names[AOCS_MOM_COUNT] = {AOCS_MOMENTUM_ROWS(MOM_NAME_ROW)};
    const char *name = "unknown";
    if (((int)id >= 0) && (id < AOCS_MOM_COUNT)) {
        name = mom_names[id];
    }
    return name;
}

static int mom_nonneg(real_t x)
{
    return (AOCS_IS_FINITE(x) && (x >= AOCS_R(0.0))) ? 1 : 0;
}

/* The parameters every policy shares: trigger, target, thresholds. */
static aocs_status_t mom_common_check(const aocs_mom_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if ((cfg->trigger >= (uint32_t)AOCS_MOM_TRIGGER_COUNT) || (aocs_vec3_is_finite(cfg->h_target_B_Nms) == 0) ||
        (mom_nonneg(cfg->h_start_Nms) == 0) || (mom_nonneg(cfg->h_stop_Nms) == 0)) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID;
    } else if ((cfg->trigger == (uint32_t)AOCS_MOM_TRIGGER_THRESHOLD) && (cfg->policy != (uint32_t)AOCS_MOM_NONE) &&
               !(cfg->h_stop_Nms < cfg->h_start_Nms)) {
        st = AOCS_ERR_MOMENTUM_CONFIG_INVALID; /* hysteresis needs h_stop < h_start */
    } else {
        st = AOCS_OK;
    }
    return st;
}

#define MOM_INIT_CASE(ID, NAME, INIT, ...) \
    case AOCS_MOM_##ID:                    \
        st = INIT(m);                      \
        break;

aocs_status_t aocs_mom_init(aocs_mom_t *m, const aocs_mom_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (m != NULL) {
        (void)memset(m, 0, sizeof(*m));
        m->id = AOCS_MOM_NONE;
        mom_zero_commands(&m->out);
        m->out.status = AOCS_OK;
        m->initialised = 0;
    }
    if ((m == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (cfg->policy >= (uint32_t)AOCS_MOM_COUNT) {
        st = AOCS_ERR_MOMENTUM_POLICY_UNKNOWN;
    } else {
        st = mom_common_check(cfg);
        if (st == AOCS_OK) {
            m->cfg = *cfg;
            m->id = (aocs_mom_id_t)cfg->policy;
            switch (m->id) {
            AOCS_MOMENTUM_ROWS(MOM_INIT_CASE)
            default:
                st = AOCS_ERR_MOMENTUM_POLICY_UNKNOWN;
                break;
            }
        }
        if (st == AOCS_OK) {
            m->initialised = 1;
        } else {
            (void)memset(m, 0, sizeof(*m));
            m->id = AOCS_MOM_NONE;
        }
    }
    return st;
}

int aocs_mom_trigger(const aocs_mom_config_t *cfg, int unloading, real_t dh_norm_Nms)
{
    int next = 0;
    if ((cfg != NULL) && AOCS_IS_FINITE(dh_norm_Nms)) {
        if (cfg->trigger == (uint32_t)AOCS_MOM_TRIGGER_CONTINUOUS) {
            next = 1;
        } else if (unloading != 0) {
            if (!(dh_norm_Nms < cfg->h_stop_Nms)) { /* on until |dh| falls below the stop threshold */
                next = 1;
            }
        } else if (dh_norm_Nms > cfg->h_start_Nms) { /* off until |dh| exceeds the start threshold */
            next = 1;
        } else {
            next = 0;
        }
    }
    return next;
}

#define MOM_STEP_CASE(ID, NAME, INIT, STEP, ...) \
    case AOCS_MOM_##ID:                          \
        st = STEP(m, in);                        \
        break;

aocs_status_t aocs_mom_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    aocs_status_t st = AOCS_OK;
    if ((m == NULL) || (in == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (m->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        aocs_mom_output_t *out = &m->out;
        int next = 0;
        mom_zero_commands(out);
        out->h_wheels_B_Nms = aocs_vec3_zero();
        out->dh_B_Nms = aocs_vec3_zero();
        if ((in->h_valid != 0) && (aocs_vec3_is_finite(in->h_wheels_B_Nms) != 0)) {
            out->h_wheels_B_Nms = in->h_wheels_B_Nms;
            out->dh_B_Nms = aocs_vec3_sub(in->h_wheels_B_Nms, m->cfg.h_target_B_Nms);
            if ((in->enabled != 0) && (m->id != AOCS_MOM_NONE) && AOCS_IS_FINITE(in->dt_s) &&
                (in->dt_s > AOCS_R(0.0))) {
                next = aocs_mom_trigger(&m->cfg, out->unloading, aocs_vec3_norm(out->dh_B_Nms));
            }
        } else if (m->id != AOCS_MOM_NONE) {
            st = AOCS_ERR_INPUT_MISSING; /* no wheel momentum: nothing to unload against */
        } else {
            st = AOCS_OK;
        }
        if ((next != 0) && (out->unloading == 0) && (out->n_events < UINT32_MAX)) {
            out->n_events += 1u;
        }
        out->unloading = next;
        if (next == 0) {
            for (uint32_t i = 0u; i < AOCS_MOM_THRUSTERS_MAX; ++i) {
                m->thr_residual_s[i] = AOCS_R(0.0); /* an unload that ended owes nothing */
            }
        }
        if ((st == AOCS_OK) && (next != 0)) {
            switch (m->id) {
            AOCS_MOMENTUM_ROWS(MOM_STEP_CASE)
            default:
                st = AOCS_ERR_MOMENTUM_POLICY_UNKNOWN;
                break;
            }
        }
        if (st != AOCS_OK) {
            mom_zero_commands(out);
        }
        out->status = st;
    }
    return st;
}

aocs_mom_output_t aocs_mom_output(const aocs_mom_t *m)
{
    aocs_mom_output_t out;
    if ((m != NULL) && (m->initialised != 0)) {
        out = m->out;
    } else {
        (void)memset(&out, 0, sizeof(out));
        mom_zero_commands(&out);
    }
    return out;
}

uint64_t aocs_mom_budget_ns(const aocs_mom_t *m)
{
    static const uint64_t budgets[AOCS_MOM_COUNT] = {AOCS_MOMENTUM_ROWS(MOM_BUDGET_ROW)};
    uint64_t b = 0u;
    if ((m != NULL) && ((int)m->id >= 0) && (m->id < AOCS_MOM_COUNT)) {
        b = budgets[m->id];
    }
    return b;
}

aocs_status_t aocs_mom_none_init(aocs_mom_t *m)
{
    (void)m;
    return AOCS_OK;
}

aocs_status_t aocs_mom_none_step(aocs_mom_t *m, const aocs_mom_input_t *in)
{
    /* no unloading: the zero commands stand */
    (void)m;
    (void)in;
    return AOCS_OK;
}
