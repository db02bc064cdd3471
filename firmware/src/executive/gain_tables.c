/*
 * Name / id lookup of the gain tables compiled from `aocs gains`
 * (gains/aocs_gains.h). The id enum lets an image without string parsing
 * (the PIL target) pick a design; the names are the design names of
 * tools/gains.toml and the scenario files (`[laws.hinf] table = ...`).
 * Both the list (gains/gain_tables.def, written by `aocs gains` with the
 * tables) and where a table goes (the TABLE field of its law, laws.def) are
 * expanded here: a design added to tools/gains.toml needs no edit of C.
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

#define GAIN_TABLE_ROW(ID, NAME, LAW, SYMBOL) {(NAME), AOCS_LAW_##LAW, (SYMBOL)},

static const gain_table_t gain_tables[AOCS_GAIN_TABLE_COUNT] = {
    AOCS_GAIN_TABLE_ROWS(GAIN_TABLE_ROW)
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

/*
 * One case per TABLE field of laws.def: the law whose tables the field
 * accepts -> the gain matrix (MEMBER) the table is copied into. The other
 * field types expand to nothing.
 */
#define GAIN_DEST_REAL(LAW, MEMBER)
#define GAIN_DEST_VEC3(LAW, MEMBER)
#define GAIN_DEST_MAT3(LAW, MEMBER)
#define GAIN_DEST_GAIN(LAW, MEMBER)
#define GAIN_DEST_TABLE(LAW, MEMBER)                       \
    case AOCS_LAW_##LAW:                                  \
        copy_gain(cfgs->MEMBER, gain_tables[table].k);    \
        st = AOCS_OK;                                     \
        break;
#define GAIN_DEST_CASE(NAME, LAW, KEY, MEMBER, TYPE, ...) GAIN_DEST_##TYPE(LAW, MEMBER)

aocs_status_t aocs_gain_table_apply(aocs_gain_table_id_t table, aocs_law_id_t law, aocs_exec_law_configs_t *cfgs)
{
    aocs_status_t st = AOCS_OK;
    if (cfgs == NULL) {
        st = AOCS_ERR_NULL_ARG;
    } else if (table_is_valid(table) == 0) {
        st = AOCS_ERR_GAIN_TABLE_UNKNOWN;
    } else if (gain_tables[table].law != law) {
        st = AOCS_ERR_GAIN_TABLE_WRONG_LAW;
    } else {
        /* a table registered for a law without a TABLE field has nowhere to go */
        st = AOCS_ERR_GAIN_TABLE_WRONG_LAW;
        switch (law) {
        AOCS_LAW_FIELD_ROWS(GAIN_DEST_CASE)
        default:
            break;
        }
    }
    return st;
}
