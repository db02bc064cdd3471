/*
 * Compiled gain tables (part of aocs/executive.h; gain_tables.c): the designs
 * of gains/aocs_gains.h by name or id.
 */
#ifndef AOCS_EXEC_GAIN_TABLES_H
#define AOCS_EXEC_GAIN_TABLES_H

#include "aocs/exec/law_dispatch.h"
#include "gains/gain_tables.def"

/*
 * ---- compiled gain tables (gains/gain_tables.def, gain_tables.c) ----
 * One id per row of the registration that `aocs gains` writes next to the
 * tables (design order of tools/gains.toml), then AOCS_GAIN_TABLE_COUNT.
 */
#define AOCS_GAIN_TABLE_ENUM_ROW(ID, ...) AOCS_GAIN_TABLE_##ID,
typedef enum {
    AOCS_GAIN_TABLE_ROWS(AOCS_GAIN_TABLE_ENUM_ROW)
    AOCS_GAIN_TABLE_COUNT
} aocs_gain_table_id_t;

/* Design name of a table (its tools/gains.toml section); "unknown" when out of range. Total. */
const char *aocs_gain_table_name(aocs_gain_table_id_t table);

/* The law a table was designed for (LQR_QUAT, HINF or ORBIT_LQR); AOCS_LAW_NONE when out of range. Total. */
aocs_law_id_t aocs_gain_table_law(aocs_gain_table_id_t table);

/*
 * Table id from its design name (exact, case-sensitive).
 * AOCS_ERR_GAIN_TABLE_UNKNOWN (and *table untouched) for any other string,
 * AOCS_ERR_NULL_ARG for NULL pointers.
 */
aocs_status_t aocs_gain_table_find(const char *name, aocs_gain_table_id_t *table);

/*
 * Copies the 3x6 gain of `table` into the config of `law` in *cfgs: the
 * MEMBER of the law's TABLE field in laws.def (lqr_quat.k, hinf.k,
 * orbit_lqr.k); nothing else changes.
 * AOCS_ERR_NULL_ARG; AOCS_ERR_GAIN_TABLE_UNKNOWN (table out of range);
 * AOCS_ERR_GAIN_TABLE_WRONG_LAW (the table was designed for another law,
 * *cfgs untouched). The law's init still validates the gain.
 */
aocs_status_t aocs_gain_table_apply(aocs_gain_table_id_t table, aocs_law_id_t law,
                                    aocs_exec_law_configs_t *cfgs);

#endif /* AOCS_EXEC_GAIN_TABLES_H */
