/*
 * Host view of the law registry (firmware/include/aocs/laws.def), the gain
 * table registration (firmware/gains/gain_tables.def), the PIL executive
 * fields (aocs/pil_frame.h) and the status codes (aocs/status.def): plain descriptor tables
 * with every column as text or number, expanded from the same rows the
 * firmware expands, for the host programs that need to look at the registry
 * as data: aocs_registry_dump (the JSON Python reads), the bench and the
 * registry unit test. Host only (stdio, strtod); never linked into an image.
 */
#ifndef AOCS_REGISTRY_H
#define AOCS_REGISTRY_H

#include <stddef.h>
#include <stdint.h>

#include "aocs/executive.h"

typedef struct {
    aocs_law_id_t id;
    const char *enum_name;          /* "AOCS_LAW_QUAT_PD" */
    const char *name;               /* CLI name */
    const char *input;              /* "attitude" or "orbit" */
    const char *title;              /* one line: spec section and what the law is */
    const char *state;              /* member of aocs_exec_law_states_t */
    const char *state_type;
    const char *config;             /* member of aocs_exec_law_configs_t */
    const char *config_type;
    int config_owner;               /* 1: CFG_OWN, 0: CFG_SHARED */
    const char *init;               /* function names */
    const char *step;
    const char *variant_member;     /* NULL without a variant */
    const char *variant_value;      /* enum constant name, NULL without a variant */
    int variant_number;             /* its value, -1 without a variant */
    const char *from_member;        /* FROM_FIELD: the member of its config set at init, else NULL */
    const char *from_field;         /* ... from this field member of another law ("smc.inertia"), else NULL */
    uint64_t budget_ns;             /* host budget of one law step */
    uint32_t instr_m4f;             /* instruction budgets of one executive step */
    uint32_t instr_m7;
    const char *reference_scenario; /* sil/scenarios/<name>.toml */
} aocs_registry_law_t;

typedef struct {
    const char *name;    /* PIL field name suffix: AOCS_PIL_CFG_<name> */
    aocs_law_id_t law;   /* owner of the config (TABLE: the law whose tables it takes) */
    const char *key;     /* fsw_node configuration key */
    const char *member;  /* path in aocs_exec_law_configs_t */
    const char *type;    /* "real" "vec3" "mat3" "gain" "table" */
    uint32_t count;      /* values on the PIL wire (1 name for a table) */
    const char *rule;    /* "any" "pos" "nonneg" */
    const char *help;    /* unit / meaning */
    uint32_t pil_id;     /* CONFIG field id */
    const char *variant; /* "ALL" or the variant value (enum constant) that uses it */
    const char *ref;     /* reference value, configuration-file syntax; "" = none */
} aocs_registry_field_t;

typedef struct {
    aocs_gain_table_id_t id;
    const char *name;    /* design name */
    aocs_law_id_t law;
    const char *symbol;  /* the table in gains/aocs_gains.h */
} aocs_registry_table_t;

typedef struct {
    const char *name;    /* AOCS_PIL_CFG_<name> */
    uint32_t pil_id;
    const char *kind;    /* "real" or "u64" */
    uint32_t count;
    const char *key;     /* fsw_node key the bridge takes it from, "" = none */
} aocs_registry_exec_field_t;

typedef struct {
    aocs_status_t value;
    const char *name;    /* "AOCS_ERR_NULL_ARG" */
    const char *meaning; /* what the code says (status.def) */
} aocs_registry_status_t;

extern const aocs_registry_status_t aocs_registry_statuses[]; /* value order */
extern const size_t aocs_registry_status_count;
extern const aocs_registry_law_t aocs_registry_laws[];       /* row order = id order, no NONE */
extern const size_t aocs_registry_law_count;
extern const aocs_registry_field_t aocs_registry_fields[];   /* laws.def field row order */
extern const size_t aocs_registry_field_count;
extern const aocs_registry_table_t aocs_registry_tables[];   /* id order */
extern const size_t aocs_registry_table_count;
extern const aocs_registry_exec_field_t aocs_registry_exec_fields[];
extern const size_t aocs_registry_exec_field_count;

/* The registry row of a law id, NULL for NONE / out of range. */
const aocs_registry_law_t *aocs_registry_law(aocs_law_id_t id);

/*
 * 1 when `field` belongs to the configuration `law` uses: the field's law has
 * the same config member, and the field is for every variant or for the
 * law's own variant; or the field is the one a FROM_FIELD row copies in.
 */
int aocs_registry_field_applies(const aocs_registry_field_t *field, const aocs_registry_law_t *law);

/*
 * Zeroes *c, then writes the REF value of every field that has one
 * (numbers as strtod reads them, a MAT3 given as 3 numbers is a diagonal; a
 * TABLE copies the compiled table through aocs_gain_table_apply). Returns 0,
 * or -1 with a message naming the key in err.
 */
int aocs_registry_reference_configs(aocs_exec_law_configs_t *c, char *err, size_t err_size);

#endif /* AOCS_REGISTRY_H */
