/*
 * Name / id lookup of the gain tables compiled from `aocs gains`
 * (gains/aocs_gains.h). The id enum lets an image without string parsing
 * (the PIL target) pick a design; the names are the design names of
 * tools/gains.toml and the scenario files (`[laws.hinf] table = ...`).
 * A design added to the generator must be added here too: the unit test
 * test_executive_laws checks AOCS_GAIN_TABLE_COUNT == AOCS_GAINS_TABLE_COUNT.
 */
#include <stddef.h>
#include <string.h>

#include "gains/aocs_gains.h"
#include "exec_internal.h"

typedef struct {
    const char *name;         /* design name */
    aocs_law_id_t law;        /* the law whose gain layout the table has */
    const real_t (*k)[6];     /* the generated 3x6 table */
} gain_table_t;

static const gain_table_t gain_tables[AOCS_GAIN_TABLE_COUNT] = {
    {"lqr_quat_ref", AOCS_LAW_LQR_QUAT, aocs_gains_lqr_quat_ref_K},
    {"lqr_quat_strong", AOCS_LAW_LQR_QUAT, aocs_gains_lqr_quat_strong_K},
    {"hinf_min", AOCS_LAW_HINF, aocs_gains_hinf_min_K},
    {"hinf_regional", AOCS_LAW_HINF, aocs_gains_hinf_regional_K},
    {"orbit_lqr_q1", AOCS_LAW_ORBIT_LQR, aocs_gains_orbit_lqr_q1_K},
    {"orbit_lqr_q01", AOCS_LAW_ORBIT_LQR, aocs_gains_orbit_lqr_q01_K},
    {"orbit_lqr_q10", AOCS_LAW_ORBIT_LQR, aocs_gains_orbit_lqr_q10_K},
};

static int table_is_valid(aocs_gain_table_id_t table)
{
    return (((int)table >= 0) && (table < AOCS_GAIN_TABLE_COUNT)) ? 1 : 0;
}

const char *aocs_gain_table_name(aocs_gain_table_id_t table)
{
    const char *name = "unknown";
    if (table_is_valid(table) != 0) {
        name = gain_tables[table].name;
    }
    return name;
}

aocs_law_id_t aocs_gain_table_law(aocs_gain_table_id_t table)
{
    aocs_law_id_t law = AOCS_LAW_NONE;
    if (table_is_valid(table) != 0) {
        law = gain_tables[table].law;
    }
    return law;
}

aocs_status_t aocs_gain_table_find(const char *name, aocs_gain_table_id_t *table)
{
    aocs_status_t st = AOCS_ERR_GAIN_TABLE_UNKNOWN;
    if ((name == NULL) || (table == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        for (int i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
            if (strcmp(name, gain_tables[i].name) == 0) {
                *table = (aocs_gain_table_id_t)i;
                st = AOCS_OK;
                break;
            }
        }
    }
    return st;
}

static void copy_gain(real_t dst[3][6], const real_t (*src)[6])
{
    for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 6; ++j) {
            dst[i][j] = src[i][j];
        }
    }
}

aocs_status_t aocs_gain_table_apply(aocs_gain_table_id_t table, aocs_law_id_t law, aocs_exec_law_configs_t *cfgs)
{
    aocs_status_t st = AOCS_OK;
    if (cfgs == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (table_is_valid(table) == 0) {
        st = AOCS_ERR_GAIN_TABLE_UNKNOWN;
    } else if (gain_tables[table].law != law) {
        st = AOCS_ERR_GAIN_TABLE_WRONG_LAW;
    } else if (law == AOCS_LAW_LQR_QUAT) {
        copy_gain(cfgs->lqr_quat.k, gain_tables[table].k);
    } else if (law == AOCS_LAW_HINF) {
        copy_gain(cfgs->hinf.k, gain_tables[table].k);
    } else {
        /* the table's law is one of the three: here ORBIT_LQR */
        copy_gain(cfgs->orbit_lqr.k, gain_tables[table].k);
    }
    return st;
}
