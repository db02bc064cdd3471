/*
 * Law table: CLI names, input kinds, budgets and the dispatch to each law's
 * init/step, all expanded from the rows of aocs/laws.def (nothing here
 * names a law). The two-variant laws (quat_nlpd, mrp_sat) share one config;
 * the law id decides the variant (VARIANT column) so a config can never
 * disagree with the selection.
 */
#include <stddef.h>
#include <string.h>

#include "exec_internal.h"

/* What the executive needs to know of a law besides its functions. */
typedef struct {
    const char *name;   /* CLI name */
    int is_orbit;       /* 1: orbit input, force output */
    uint64_t budget_ns; /* declared host budget of one step */
} law_info_t;

#define LAW_IS_ORBIT_ATTITUDE 0
#define LAW_IS_ORBIT_ORBIT 1
#define LAW_INFO_ROW(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, VARIANT, VMEMBER, VVALUE, \
                     BUDGET_NS, ...)                                                                              \
    {(NAME), LAW_IS_ORBIT_##INPUT, (uint64_t)(BUDGET_NS)},

/* indexed by aocs_law_id_t: NONE first, then the rows in id order */
static const law_info_t law_info[AOCS_LAW_COUNT] = {
    {"none", 0, (uint64_t)AOCS_EXEC_SAFE_BUDGET_NS},
    AOCS_LAW_ROWS(LAW_INFO_ROW)
};

static int law_in_range(aocs_law_id_t law)
{
    return (((int)law >= 0) && (law < AOCS_LAW_COUNT)) ? 1 : 0;
}

const char *aocs_law_name(aocs_law_id_t law)
{
    const char *name = "unknown";
    if (law_in_range(law) != 0) {
        name = law_info[law].name;
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
            if (strcmp(name, law_info[i].name) == 0) {
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

/* The laws whose formula includes the slew feedforward (AOCS_LAW_FEEDFORWARD_IN_FORMULA, laws.def). */
#define AOCS_LAW_FF_ROW(ID) AOCS_LAW_##ID,

int aocs_law_has_feedforward(aocs_law_id_t law)
{
    static const aocs_law_id_t LAW_FEEDFORWARD_IN_FORMULA[] = {AOCS_LAW_FEEDFORWARD_IN_FORMULA(AOCS_LAW_FF_ROW)};
    int has = 0;
    for (size_t i = 0u; i < (sizeof(LAW_FEEDFORWARD_IN_FORMULA) / sizeof(LAW_FEEDFORWARD_IN_FORMULA[0])); ++i) {
        if (LAW_FEEDFORWARD_IN_FORMULA[i] == law) {
            has = 1;
        }
    }
    return has;
}

int aocs_law_is_orbit(aocs_law_id_t law)
{
    int orbit = 0;
    if (law_in_range(law) != 0) {
        orbit = law_info[law].is_orbit;
    }
    return orbit;
}

uint64_t aocs_law_budget_ns(aocs_law_id_t law)
{
    uint64_t budget = (uint64_t)AOCS_EXEC_SAFE_BUDGET_NS;
    if (law_in_range(law) != 0) {
        budget = law_info[law].budget_ns;
    }
    return budget;
}

/*
 * init of one row: a copy of the stored config with the variant forced
 * (VARIANT: law_cfg.VMEMBER = VVALUE; NO_VARIANT: as stored).
 */
#define LAW_SET_NO_VARIANT(MEMBER, VALUE)
#define LAW_SET_VARIANT(MEMBER, VALUE) law_cfg.MEMBER = (VALUE);
#define LAW_INIT_CASE(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, VARIANT, VMEMBER, VVALUE, \
                      ...)                                                                                      \
    case AOCS_LAW_##ID: {                                                                               \
        CFG_T law_cfg = cfgs->CFG;                                                                      \
        LAW_SET_##VARIANT(VMEMBER, VVALUE)                                                                \
        st = INIT(&states->STATE, &law_cfg);                                                              \
    }                                                                                                   \
        break;

aocs_status_t aocs_exec_law_init(aocs_exec_law_states_t *states, const aocs_exec_law_configs_t *cfgs,
                                 aocs_law_id_t law)
{
    aocs_status_t st = AOCS_ERR_UNKNOWN_LAW;
    aocs_law_id_t id = law;
    if ((states == NULL) || (cfgs == NULL)) {
        id = AOCS_LAW_COUNT; /* falls to the default branch */
        st = AOCS_ERR_NULL_ARG;
    }
    switch (id) {
    AOCS_LAW_ROWS(LAW_INIT_CASE)
    default:
        if (st != AOCS_ERR_NULL_ARG) {
            st = AOCS_ERR_UNKNOWN_LAW;
        }
        break;
    }
    return st;
}

/* step of one row: the attitude or the orbit input, by the INPUT column */
#define LAW_INPUT_ATTITUDE att
#define LAW_INPUT_ORBIT orbit
#define LAW_STEP_CASE(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, ...) \
    case AOCS_LAW_##ID:                                                                      \
        st = STEP(&states->STATE, LAW_INPUT_##INPUT, &u_law);                                \
        break;

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
    AOCS_LAW_ROWS(LAW_STEP_CASE)
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
