/*
 * The human hints of fsw_node's configuration errors, from the rows of the
 * configuration registry: the keys to check when aocs_exec_init refuses a
 * configuration, the keys that give a law's gain, the gain tables a law
 * takes. Host code (SIL only), not firmware.
 */
#ifndef AOCS_FSW_NODE_HINTS_H
#define AOCS_FSW_NODE_HINTS_H

#include <stddef.h>

#include "aocs/config_registry.h"

/* "a, b, c": the design names of the compiled gain tables of `law`, written into buf. */
void aocs_node_config_table_names(aocs_law_id_t law, char *buf, size_t size);

/* The REALS field a TABLE field fills by name (same offset): the key giving the gain by value; NULL if none. */
const aocs_config_field_t *aocs_node_config_gain_field(const aocs_config_field_t *table);

/*
 * "<law>.k / <law>.table": the keys that give the 3x6 gain of `law` (by value,
 * by table name), written into buf; "the gains of the selected law" for a
 * law without a gain table. Returns the text.
 */
const char *aocs_node_config_gain_keys(aocs_law_id_t law, char *buf, size_t size);

/*
 * The keys to check when aocs_exec_init refuses a configuration with `st`:
 * every registry row that names st (STATUS / ALSO columns of
 * config_fields.def) with its unit, the gains of `law` for a gain status, the
 * inertia for an inertia status; written into buf. Returns the text.
 */
const char *aocs_node_config_status_hint(aocs_status_t st, aocs_law_id_t law, char *buf, size_t size);

#endif /* AOCS_FSW_NODE_HINTS_H */
