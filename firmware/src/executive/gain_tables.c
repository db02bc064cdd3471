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
#include "aocs/control/gain_matrix.h"

typedef struct {
    const char *name;         /* design name */
    aocs_law_id_t law;        /* the law whose gain layout the table has */
    aocs_gain_rows_t k;       /* the generated 3 x cols table (3x6, or 3x9 for lqr_quat_i), by rows */
} gain_table_t;

/* columns of a 3 x n gain array (a table of aocs_gains.h, or the gain member of a law config) */
#define GAIN_COLS(K) ((uint32_t)(sizeof((K)[0]) / sizeof((K)[0][0])))
#define GAIN_TABLE_ROW(ID, NAME, LAW, SYMBOL) \
    {(NAME), AOCS_LAW_##LAW, {{(SYMBOL)[0], (SYMBOL)[1], (SYMBOL)[2]}, GAIN_COLS(SYMBOL)}},

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

static void copy_row(real_t *dst, const real_t *src, uint32_t cols)
{
    for (uint32_t j = 0U; j < cols; ++j) {
        dst[j] = src[j];
    }
}

/* the table's rows into the rows of a law's gain of cols columns; a shape mismatch copies nothing */
static aocs_status_t copy_gain(const aocs_gain_rows_t *src, real_t *d0, real_t *d1, real_t *d2, uint32_t cols)
{
    aocs_status_t st = AOCS_ERR_GAIN_TABLE_WRONG_LAW;
    if (src->cols == cols) {
        copy_row(d0, src->row[0], cols);
        copy_row(d1, src->row[1], cols);
        copy_row(d2, src->row[2], cols);
        st = AOCS_OK;
    }
    return st;
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
#define GAIN_DEST_TABLE(LAW, MEMBER)                                                                   \
    case AOCS_LAW_##LAW:                                                                              \
        st = copy_gain(&gain_tables[table].k, cfgs->MEMBER[0], cfgs->MEMBER[1], cfgs->MEMBER[2],      \
                       GAIN_COLS(cfgs->MEMBER));                                                      \
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
