/*
 * The momentum-management stage (aocs/momentum/momentum.h): names, init and
 * the dispatch to the selected policy, expanded from aocs/momentum/momentum.def;
 * policy NONE (no unloading).
 */
#include <stddef.h>

#include "aocs/executive.h"

#define MOM_NAME_ROW(ID, NAME, ...) (NAME),

static void mom_zero_output(aocs_mom_output_t *out)
{
    out->dipole_Am2 = aocs_vec3_zero();
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

aocs_status_t aocs_mom_init(aocs_mom_t *m, const aocs_mom_config_t *cfg)
{
    aocs_status_t st = AOCS_OK;
    if (m != NULL) {
        m->id = AOCS_MOM_NONE;
        mom_zero_output(&m->out);
        m->initialised = 0;
    }
    if ((m == NULL) || (cfg == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (cfg->policy >= (uint32_t)AOCS_MOM_COUNT) {
        st = AOCS_ERR_MOMENTUM_POLICY_UNKNOWN;
    } else {
        m->id = (aocs_mom_id_t)cfg->policy;
        m->initialised = 1;
    }
    return st;
}

#define MOM_STEP_CASE(ID, NAME, STEP) \
    case AOCS_MOM_##ID:               \
        st = STEP(m, h);              \
        break;

aocs_status_t aocs_mom_step(aocs_mom_t *m, const aocs_wheels_momentum_t *h)
{
    aocs_status_t st = AOCS_OK;
    if (m == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (m->initialised == 0) {
        st = AOCS_ERR_NOT_INITIALISED;
    } else {
        switch (m->id) {
        AOCS_MOMENTUM_ROWS(MOM_STEP_CASE)
        default:
            st = AOCS_ERR_MOMENTUM_POLICY_UNKNOWN;
            break;
        }
        if (st != AOCS_OK) {
            mom_zero_output(&m->out);
        }
    }
    return st;
}

aocs_mom_output_t aocs_mom_output(const aocs_mom_t *m)
{
    aocs_mom_output_t out;
    if ((m != NULL) && (m->initialised != 0)) {
        out = m->out;
    } else {
        mom_zero_output(&out);
    }
    return out;
}

aocs_status_t aocs_mom_none_step(aocs_mom_t *m, const aocs_wheels_momentum_t *h)
{
    /* no unloading: the zero commands of init stand */
    (void)m;
    (void)h;
    return AOCS_OK;
}
