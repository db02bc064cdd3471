/*
 * Law table: CLI names, budgets and the dispatch to each law's init/step.
 * The two-variant laws (quat_nlpd, mrp_sat) share one config; the law id
 * decides the variant so a config can never disagree with the selection.
 */
#include <stddef.h>
#include <string.h>

#include "exec_internal.h"

static const char *const law_names[AOCS_LAW_COUNT] = {
    "none",          "crp_linear", "quat_pd", "quat_nlpd_neg", "quat_nlpd_pos", "smc",
    "lqr_quat",      "hinf",       "mrp_sat", "mrp_sat_tanh",  "orbit_lqr",
};

const char *aocs_law_name(aocs_law_id_t law)
{
    const char *name = "unknown";
    if (((int)law >= 0) && (law < AOCS_LAW_COUNT)) {
        name = law_names[law];
    }
    return name;
}

aocs_status_t aocs_law_from_name(const char *name, aocs_law_id_t *law)
{
    aocs_status_t st = AOCS_ERR_UNKNOWN_LAW;
    if ((name == NULL) || (law == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        for (int i = 0; i < (int)AOCS_LAW_COUNT; ++i) {
            if (strcmp(name, law_names[i]) == 0) {
                *law = (aocs_law_id_t)i;
                st = AOCS_OK;
                break;
            }
        }
    }
    return st;
}

int aocs_exec_law_is_valid(aocs_law_id_t law)
{
    return (((int)law > (int)AOCS_LAW_NONE) && (law < AOCS_LAW_COUNT)) ? 1 : 0;
}

int aocs_law_is_orbit(aocs_law_id_t law)
{
    return (law == AOCS_LAW_ORBIT_LQR) ? 1 : 0;
}

uint64_t aocs_law_budget_ns(aocs_law_id_t law)
{
    uint64_t budget = 0u;
    switch (law) {
    case AOCS_LAW_CRP_LINEAR:
        budget = (uint64_t)AOCS_CRP_LINEAR_BUDGET_NS;
        break;
    case AOCS_LAW_QUAT_PD:
        budget = (uint64_t)AOCS_QUAT_PD_BUDGET_NS;
        break;
    case AOCS_LAW_QUAT_NLPD_NEG:
    case AOCS_LAW_QUAT_NLPD_POS:
        budget = (uint64_t)AOCS_QUAT_NLPD_BUDGET_NS;
        break;
    case AOCS_LAW_SMC:
        budget = (uint64_t)AOCS_SMC_BUDGET_NS;
        break;
    case AOCS_LAW_LQR_QUAT:
        budget = (uint64_t)AOCS_LQR_QUAT_BUDGET_NS;
        break;
    case AOCS_LAW_HINF:
        budget = (uint64_t)AOCS_HINF_BUDGET_NS;
        break;
    case AOCS_LAW_MRP_SAT_LINEAR:
    case AOCS_LAW_MRP_SAT_TANH:
        budget = (uint64_t)AOCS_MRP_SAT_BUDGET_NS;
        break;
    case AOCS_LAW_ORBIT_LQR:
        budget = (uint64_t)AOCS_ORBIT_LQR_BUDGET_NS;
        break;
    default:
        budget = (uint64_t)AOCS_EXEC_SAFE_BUDGET_NS;
        break;
    }
    return budget;
}

aocs_status_t aocs_exec_law_init(aocs_exec_law_states_t *states, const aocs_exec_law_configs_t *cfgs,
                                 aocs_law_id_t law)
{
    aocs_status_t st = AOCS_ERR_UNKNOWN_LAW;
    aocs_quat_nlpd_config_t nlpd;
    aocs_mrp_sat_config_t mrp;
    aocs_law_id_t id = law;
    if ((states == NULL) || (cfgs == NULL)) {
        id = AOCS_LAW_COUNT; /* falls to the default branch */
        st = AOCS_ERR_NULL_ARG;
    }
    switch (id) {
    case AOCS_LAW_CRP_LINEAR:
        st = aocs_crp_linear_init(&states->crp_linear, &cfgs->crp_linear);
        break;
    case AOCS_LAW_QUAT_PD:
        st = aocs_quat_pd_init(&states->quat_pd, &cfgs->quat_pd);
        break;
    case AOCS_LAW_QUAT_NLPD_NEG:
        nlpd = cfgs->quat_nlpd;
        nlpd.variant = AOCS_QUAT_NLPD_NEG;
        st = aocs_quat_nlpd_init(&states->quat_nlpd_neg, &nlpd);
        break;
    case AOCS_LAW_QUAT_NLPD_POS:
        nlpd = cfgs->quat_nlpd;
        nlpd.variant = AOCS_QUAT_NLPD_POS;
        st = aocs_quat_nlpd_init(&states->quat_nlpd_pos, &nlpd);
        break;
    case AOCS_LAW_SMC:
        st = aocs_smc_init(&states->smc, &cfgs->smc);
        break;
    case AOCS_LAW_LQR_QUAT:
        st = aocs_lqr_quat_init(&states->lqr_quat, &cfgs->lqr_quat);
        break;
    case AOCS_LAW_HINF:
        st = aocs_hinf_init(&states->hinf, &cfgs->hinf);
        break;
    case AOCS_LAW_MRP_SAT_LINEAR:
        mrp = cfgs->mrp_sat;
        mrp.variant = AOCS_MRP_SAT_LINEAR;
        st = aocs_mrp_sat_init(&states->mrp_sat_linear, &mrp);
        break;
    case AOCS_LAW_MRP_SAT_TANH:
        mrp = cfgs->mrp_sat;
        mrp.variant = AOCS_MRP_SAT_TANH;
        st = aocs_mrp_sat_init(&states->mrp_sat_tanh, &mrp);
        break;
    case AOCS_LAW_ORBIT_LQR:
        st = aocs_orbit_lqr_init(&states->orbit_lqr, &cfgs->orbit_lqr);
        break;
    default:
        if (st != AOCS_ERR_NULL_ARG) {
            st = AOCS_ERR_UNKNOWN_LAW;
        }
        break;
    }
    return st;
}

aocs_status_t aocs_exec_law_step(aocs_exec_law_states_t *states, aocs_law_id_t law,
                                 const aocs_att_input_t *att, const aocs_orbit_input_t *orbit,
                                 aocs_vec3_t *u)
{
    aocs_status_t st = AOCS_ERR_UNKNOWN_LAW;
    aocs_vec3_t u_law = aocs_vec3_zero();
    aocs_law_id_t id = law;
    if ((states == NULL) || (att == NULL) || (orbit == NULL) || (u == NULL)) {
        id = AOCS_LAW_COUNT; /* falls to the default branch */
        st = AOCS_ERR_NULL_ARG;
    }
    switch (id) {
    case AOCS_LAW_CRP_LINEAR:
        st = aocs_crp_linear_step(&states->crp_linear, att, &u_law);
        break;
    case AOCS_LAW_QUAT_PD:
        st = aocs_quat_pd_step(&states->quat_pd, att, &u_law);
        break;
    case AOCS_LAW_QUAT_NLPD_NEG:
        st = aocs_quat_nlpd_step(&states->quat_nlpd_neg, att, &u_law);
        break;
    case AOCS_LAW_QUAT_NLPD_POS:
        st = aocs_quat_nlpd_step(&states->quat_nlpd_pos, att, &u_law);
        break;
    case AOCS_LAW_SMC:
        st = aocs_smc_step(&states->smc, att, &u_law);
        break;
    case AOCS_LAW_LQR_QUAT:
        st = aocs_lqr_quat_step(&states->lqr_quat, att, &u_law);
        break;
    case AOCS_LAW_HINF:
        st = aocs_hinf_step(&states->hinf, att, &u_law);
        break;
    case AOCS_LAW_MRP_SAT_LINEAR:
        st = aocs_mrp_sat_step(&states->mrp_sat_linear, att, &u_law);
        break;
    case AOCS_LAW_MRP_SAT_TANH:
        st = aocs_mrp_sat_step(&states->mrp_sat_tanh, att, &u_law);
        break;
    case AOCS_LAW_ORBIT_LQR:
        st = aocs_orbit_lqr_step(&states->orbit_lqr, orbit, &u_law);
        break;
    default:
        if (st != AOCS_ERR_NULL_ARG) {
            st = AOCS_ERR_UNKNOWN_LAW;
        }
        break;
    }
    if (u != NULL) {
        /* law_io.h promises a zero output on error; the executive does not rely on it */
        *u = (st == AOCS_OK) ? u_law : aocs_vec3_zero();
    }
    return st;
}
