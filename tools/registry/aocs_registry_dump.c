/*
 * aocs_registry_dump: the registry of this build as JSON, for Python.
 *
 *   aocs_registry_dump [--out FILE]        the registry (default: stdout)
 *   aocs_registry_dump --pil-decode FILE   decode a PIL CONFIG payload
 *   aocs_registry_dump --pil-payload NAME FILE   decode a fixed PIL payload
 *
 * Registry mode (run at build time: build/<preset>/registry/aocs_registry.json,
 * tools/registry/CMakeLists.txt): the laws of firmware/include/aocs/laws.def
 * (id, names, input kind, budgets, variant, the keys of the fields their
 * config takes), every config field (key, member, type, count, rule, unit,
 * PIL id, variant, reference value), the gain tables of
 * firmware/gains/gain_tables.def, the status codes and executive modes with
 * their names (aocs/status.def), the PIL ids of the executive's own CONFIG fields, and the
 * rows of every fixed PIL payload (pil_frame.h AOCS_PIL_PAYLOAD_ROWS: name, kind, member, wire
 * type and count of each field, in wire order; "pil_counters" the rows of the counters). Python
 * reads this file instead of keeping copies (sil/aocs_core/registry.py, aocs_pil.frame).
 *
 * Decode mode (a test hook: Python encodes, the C codec decodes): FILE holds
 * the payload of one CONFIG frame; it is applied to aocs_exec_config_default()
 * by aocs_pil_config_decode and the result printed as one JSON object:
 * {"pil_err", "field", "status", "budget_instr", "values": {NAME: [...]}},
 * where NAME is every PIL field name (AOCS_PIL_CFG_<NAME>) and the values
 * are what the config holds afterwards (a TABLE field's values are its gain).
 *
 * Payload mode (the same kind of hook for the fixed payloads): FILE holds the
 * payload of NAME (HELLO, STEP, STEP_REPLY, SELECT, ACK, BYE_REPLY, ERROR),
 * decoded by its C decoder and printed as {"pil_err", "fields": {FIELD:
 * [values]}, "encoded": hex}: every row's values by the row's name (the
 * counters as their ten values), and the C encoder's bytes of the result.
 *
 * Host tool: stdio allowed, no dynamic memory all the same.
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/budget.h"
#include "aocs/estimation/determination.h"
#include "aocs/config_registry.h"
#include "aocs/pil_frame.h"
#include "aocs_registry.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define DUMP_REAL_NAME "float"
#else
#define DUMP_REAL_NAME "double"
#endif

#define DUMP_SCHEMA 3

static void put_str(FILE *f, const char *s)
{
    if (s == NULL) {
        (void)fputs("null", f);
        return;
    }
    (void)fputc('"', f);
    for (const char *p = s; *p != '\0'; ++p) {
        if ((*p == '"') || (*p == '\\')) {
            (void)fputc('\\', f);
            (void)fputc(*p, f);
        } else if ((unsigned char)*p < 0x20u) {
            (void)fprintf(f, "\\u%04x", (unsigned)(unsigned char)*p);
        } else {
            (void)fputc(*p, f);
        }
    }
    (void)fputc('"', f);
}

static void put_key(FILE *f, const char *key)
{
    put_str(f, key);
    (void)fputs(": ", f);
}

static void dump_law_fields(FILE *f, const aocs_registry_law_t *law)
{
    int first = 1;
    (void)fputc('[', f);
    for (size_t i = 0u; i < aocs_registry_field_count; ++i) {
        if (aocs_registry_field_applies(&aocs_registry_fields[i], law) != 0) {
            (void)fputs(first ? "" : ", ", f);
            put_str(f, aocs_registry_fields[i].key);
            first = 0;
        }
    }
    (void)fputc(']', f);
}

static void dump_laws(FILE *f)
{
    (void)fputs("  \"none\": {", f);
    (void)fprintf(f, "\"id\": %d, ", (int)AOCS_LAW_NONE);
    put_key(f, "name");
    put_str(f, aocs_law_name(AOCS_LAW_NONE));
    (void)fprintf(f, ", \"budget_ns\": %llu, \"budget_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}},\n",
                  (unsigned long long)aocs_law_budget_ns(AOCS_LAW_NONE),
                  (unsigned)aocs_budget_instructions(AOCS_LAW_NONE, AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_instructions(AOCS_LAW_NONE, AOCS_BUDGET_TARGET_CORTEX_M7));
    (void)fputs("  \"laws\": [\n", f);
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        const aocs_registry_law_t *l = &aocs_registry_laws[i];
        (void)fprintf(f, "    {\"id\": %d, ", (int)l->id);
        put_key(f, "name");
        put_str(f, l->name);
        (void)fputs(", ", f);
        put_key(f, "enum");
        put_str(f, l->enum_name);
        (void)fputs(", ", f);
        put_key(f, "input");
        put_str(f, l->input);
        (void)fputs(", ", f);
        put_key(f, "title");
        put_str(f, l->title);
        (void)fputs(", ", f);
        put_key(f, "state");
        put_str(f, l->state);
        (void)fputs(", ", f);
        put_key(f, "state_type");
        put_str(f, l->state_type);
        (void)fputs(", ", f);
        put_key(f, "config");
        put_str(f, l->config);
        (void)fputs(", ", f);
        put_key(f, "config_type");
        put_str(f, l->config_type);
        (void)fprintf(f, ", \"config_owner\": %s, ", l->config_owner ? "true" : "false");
        put_key(f, "init");
        put_str(f, l->init);
        (void)fputs(", ", f);
        put_key(f, "step");
        put_str(f, l->step);
        (void)fputs(", \"variant\": ", f);
        if (l->variant_value == NULL) {
            (void)fputs("null", f);
        } else {
            (void)fputs("{\"member\": ", f);
            put_str(f, l->variant_member);
            (void)fputs(", \"value\": ", f);
            put_str(f, l->variant_value);
            (void)fprintf(f, ", \"number\": %d}", l->variant_number);
        }
        (void)fputs(", \"from_field\": ", f);
        if (l->from_field == NULL) {
            (void)fputs("null", f);
        } else {
            (void)fputs("{\"member\": ", f);
            put_str(f, l->from_member);
            (void)fputs(", \"field\": ", f);
            put_str(f, l->from_field);
            (void)fputs("}", f);
        }
        (void)fprintf(f, ", \"budget_ns\": %llu, \"budget_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}, ",
                      (unsigned long long)l->budget_ns, (unsigned)l->instr_m4f, (unsigned)l->instr_m7);
        put_key(f, "reference_scenario");
        put_str(f, l->reference_scenario);
        (void)fputs(", \"fields\": ", f);
        dump_law_fields(f, l);
        (void)fprintf(f, "}%s\n", ((i + 1u) < aocs_registry_law_count) ? "," : "");
    }
    (void)fputs("  ],\n", f);
}

static void dump_fields(FILE *f)
{
    (void)fputs("  \"fields\": [\n", f);
    for (size_t i = 0u; i < aocs_registry_field_count; ++i) {
        const aocs_registry_field_t *x = &aocs_registry_fields[i];
        const aocs_registry_law_t *owner = aocs_registry_law(x->law);
        (void)fputs("    {", f);
        put_key(f, "key");
        put_str(f, x->key);
        (void)fputs(", ", f);
        put_key(f, "name");
        put_str(f, x->name);
        (void)fputs(", ", f);
        put_key(f, "law");
        put_str(f, aocs_law_name(x->law));
        (void)fputs(", ", f);
        put_key(f, "config");
        put_str(f, (owner != NULL) ? owner->config : NULL);
        (void)fputs(", ", f);
        put_key(f, "member");
        put_str(f, x->member);
        (void)fputs(", ", f);
        put_key(f, "type");
        put_str(f, x->type);
        (void)fprintf(f, ", \"count\": %u, ", (unsigned)x->count);
        put_key(f, "rule");
        put_str(f, x->rule);
        (void)fputs(", ", f);
        put_key(f, "unit");
        put_str(f, x->help);
        (void)fprintf(f, ", \"pil_id\": %u, ", (unsigned)x->pil_id);
        put_key(f, "variant");
        put_str(f, (strcmp(x->variant, "ALL") == 0) ? NULL : x->variant);
        (void)fputs(", ", f);
        put_key(f, "ref");
        put_str(f, x->ref);
        (void)fprintf(f, "}%s\n", ((i + 1u) < aocs_registry_field_count) ? "," : "");
    }
    (void)fputs("  ],\n", f);
}

static void dump_tables(FILE *f)
{
    (void)fputs("  \"gain_tables\": [\n", f);
    for (size_t i = 0u; i < aocs_registry_table_count; ++i) {
        const aocs_registry_table_t *t = &aocs_registry_tables[i];
        (void)fprintf(f, "    {\"id\": %d, ", (int)t->id);
        put_key(f, "name");
        put_str(f, t->name);
        (void)fputs(", ", f);
        put_key(f, "law");
        put_str(f, aocs_law_name(t->law));
        (void)fputs(", ", f);
        put_key(f, "symbol");
        put_str(f, t->symbol);
        (void)fprintf(f, "}%s\n", ((i + 1u) < aocs_registry_table_count) ? "," : "");
    }
    (void)fputs("  ],\n", f);
}

#define DUMP_DET_BUDGET_NS(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, ...) (BUDGET_NS),
#define DUMP_DET_INSTR_M4F(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, M4F, ...) (M4F),
#define DUMP_DET_INSTR_M7(ID, NAME, STATE, STATE_T, CFG_USE, CFG, CFG_T, INIT, STEP, BUDGET_NS, M4F, M7, ...) (M7),
static const unsigned long long det_budget_ns[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DUMP_DET_BUDGET_NS)};
static const unsigned det_instr_m4f[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DUMP_DET_INSTR_M4F)};
#define DUMP_MOM_ROW(ID, NAME, INIT, STEP, BUDGET_NS, INSTR_M4F, INSTR_M7) {NAME, (BUDGET_NS), (INSTR_M4F), (INSTR_M7)},
static const struct {
    const char *name;
    unsigned long long budget_ns;
    unsigned m4f;
    unsigned m7;
} mom_rows[AOCS_MOM_COUNT] = {AOCS_MOMENTUM_ROWS(DUMP_MOM_ROW)};
static const unsigned det_instr_m7[AOCS_DET_COUNT] = {AOCS_DETERMINATION_ROWS(DUMP_DET_INSTR_M7)};

#define DUMP_EVT_MEANING(ID, NAME, SEV, UNIT, MEANING) MEANING,
static const char *const evt_meanings[AOCS_EVT_COUNT] = {AOCS_FDIR_EVENT_ROWS(DUMP_EVT_MEANING)};

static void dump_enums(FILE *f)
{
    (void)fputs("  \"status\": [\n", f);
    for (size_t i = 0u; i < aocs_registry_status_count; ++i) {
        const aocs_registry_status_t *x = &aocs_registry_statuses[i];
        (void)fprintf(f, "    {\"value\": %d, \"name\": ", (int)x->value);
        put_str(f, aocs_status_name(x->value)); /* the firmware's own name function */
        (void)fputs(", \"meaning\": ", f);
        put_str(f, x->meaning);
        (void)fprintf(f, "}%s\n", ((i + 1u) < aocs_registry_status_count) ? "," : "");
    }
    (void)fputs("  ", f);
    (void)fputs("],\n  \"modes\": [", f);
    for (int i = 0; i < (int)AOCS_EXEC_MODE_COUNT; ++i) {
        (void)fprintf(f, "%s{\"value\": %d, \"name\": ", (i > 0) ? ", " : "", i);
        put_str(f, aocs_exec_mode_name((aocs_exec_mode_t)i));
        (void)fputc('}', f);
    }
    /* the attitude-determination rows (estimation/determination.def): the budget each adds to every step */
    (void)fputs("],\n  \"estimators\": [", f);
    for (int i = 0; i < (int)AOCS_DET_COUNT; ++i) {
        (void)fprintf(f, "%s{\"value\": %d, \"name\": ", (i > 0) ? ", " : "", i);
        put_str(f, aocs_det_name((aocs_det_id_t)i));
        (void)fprintf(f, ", \"budget_ns\": %llu, \"budget_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}}",
                      (unsigned long long)det_budget_ns[i], (unsigned)det_instr_m4f[i], (unsigned)det_instr_m7[i]);
    }
    /* the momentum-management rows (momentum/momentum.def): the budget each adds to every step */
    (void)fputs("],\n  \"momentum_policies\": [", f);
    for (int i = 0; i < (int)AOCS_MOM_COUNT; ++i) {
        (void)fprintf(f, "%s{\"value\": %d, \"name\": ", (i > 0) ? ", " : "", i);
        put_str(f, mom_rows[i].name);
        (void)fprintf(f, ", \"budget_ns\": %llu, \"budget_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}}",
                      mom_rows[i].budget_ns, mom_rows[i].m4f, mom_rows[i].m7);
    }
    /* the fault-management event table (fdir/events.def): ids from 1, severities and unit kinds by name */
    (void)fputs("],\n  \"event_severities\": [", f);
    for (int i = 0; i < (int)AOCS_SEV_COUNT; ++i) {
        (void)fprintf(f, "%s{\"value\": %d, \"name\": ", (i > 0) ? ", " : "", i);
        put_str(f, aocs_evt_severity_name((aocs_evt_severity_t)i));
        (void)fputc('}', f);
    }
    (void)fputs("],\n  \"event_unit_kinds\": [", f);
    for (int i = 0; i < (int)AOCS_UNIT_KIND_COUNT; ++i) {
        (void)fprintf(f, "%s{\"value\": %d, \"name\": ", (i > 0) ? ", " : "", i);
        put_str(f, aocs_evt_unit_kind_name((aocs_evt_unit_kind_t)i));
        (void)fputc('}', f);
    }
    (void)fputs("],\n  \"events\": [\n", f);
    for (uint32_t i = 1u; i <= AOCS_EVT_COUNT; ++i) {
        const aocs_evt_id_t id = (aocs_evt_id_t)i;
        (void)fprintf(f, "    {\"id\": %u, \"name\": ", (unsigned)i);
        put_str(f, aocs_evt_name(id));
        (void)fputs(", \"severity\": ", f);
        put_str(f, aocs_evt_severity_name(aocs_evt_severity(id)));
        (void)fputs(", \"unit_kind\": ", f);
        put_str(f, aocs_evt_unit_kind_name(aocs_evt_unit_kind(id)));
        (void)fputs(", \"meaning\": ", f);
        put_str(f, evt_meanings[i - 1u]);
        (void)fprintf(f, "}%s\n", (i < AOCS_EVT_COUNT) ? "," : "");
    }
    (void)fputs("  ],\n  \"pil_exec_fields\": [\n", f);
    for (size_t i = 0u; i < aocs_registry_exec_field_count; ++i) {
        const aocs_registry_exec_field_t *x = &aocs_registry_exec_fields[i];
        (void)fputs("    {", f);
        put_key(f, "name");
        put_str(f, x->name);
        (void)fprintf(f, ", \"pil_id\": %u, ", (unsigned)x->pil_id);
        put_key(f, "kind");
        put_str(f, x->kind);
        (void)fprintf(f, ", \"count\": %u, ", (unsigned)x->count);
        put_key(f, "key");
        put_str(f, (x->key[0] != '\0') ? x->key : NULL);
        (void)fprintf(f, "}%s\n", ((i + 1u) < aocs_registry_exec_field_count) ? "," : "");
    }
    (void)fputs("  ],\n", f);
}

/* "reals", "inertia", ...: a configuration field's kind (aocs_config_kind_t) as the JSON names it */
static const char *kind_name(aocs_config_kind_t kind)
{
    static const char *const names[] = {"reals", "inertia", "u32", "u64", "ns", "budget", "law", "enum", "table"};
    return ((unsigned)kind < (sizeof(names) / sizeof(names[0]))) ? names[kind] : "unknown";
}

/* "rule": the rule's name in lower case, then its range (config_fields.def AOCS_CONFIG_RULE_ROWS):
 * "rule_lo", "rule_lo_open", "rule_hi", "rule_zero_ok", "rule_text". */
static void put_rule(FILE *f, aocs_config_rule_t rule)
{
    const aocs_config_rule_info_t *r = aocs_config_rule_info(rule);
    char name[32];
    size_t i = 0u;
    for (; (r->name[i] != '\0') && (i + 1u < sizeof(name)); ++i) {
        const char c = r->name[i];
        name[i] = ((c >= 'A') && (c <= 'Z')) ? (char)(c - 'A' + 'a') : c;
    }
    name[i] = '\0';
    put_key(f, "rule");
    put_str(f, name);
    (void)fprintf(f, ", \"rule_lo\": %.17g, \"rule_lo_open\": %s, \"rule_hi\": %.17g, \"rule_zero_ok\": %s, ",
                  r->lo, (r->lo_open != 0) ? "true" : "false", r->hi, (r->zero_ok != 0) ? "true" : "false");
    put_key(f, "rule_text");
    put_str(f, r->text);
}

/* Every row of the configuration registry (aocs/config_registry.h), in its order: how Python learns each key,
 * its kind, count, rule, unit, PIL id, enum names and the status that names it. */
/* A field's value in aocs_exec_config_default (a per-wheel field: wheel 0's), as JSON: numbers, or null. */
static void put_default(FILE *f, const aocs_config_field_t *x)
{
    static aocs_exec_config_t cfg;
    const aocs_config_ref_t ref = {x, 0u};
    double v[AOCS_CONFIG_VALUES_MAX];
    aocs_exec_config_default(&cfg);
    put_key(f, "default");
    if ((x->kind == AOCS_CONFIG_KIND_REALS) || (x->kind == AOCS_CONFIG_KIND_INERTIA)) {
        const uint32_t n = aocs_config_get_reals(&cfg, ref, v, AOCS_CONFIG_VALUES_MAX);
        (void)fputc('[', f);
        for (uint32_t i = 0u; i < n; ++i) {
            (void)fprintf(f, "%s%.17g", (i > 0u) ? ", " : "", v[i]);
        }
        (void)fputc(']', f);
    } else if (x->kind == AOCS_CONFIG_KIND_TABLE) {
        (void)fputs("null", f);
    } else {
        (void)fprintf(f, "%llu", (unsigned long long)aocs_config_get_uint(&cfg, ref));
    }
}

static void dump_config_fields(FILE *f)
{
    const uint32_t n = aocs_config_field_count();
    (void)fputs("  \"config_fields\": [\n", f);
    for (uint32_t i = 0u; i < n; ++i) {
        const aocs_config_field_t *x = aocs_config_field_at(i);
        (void)fputs("    {", f);
        put_key(f, "key");
        put_str(f, x->key);
        (void)fputs(", ", f);
        put_key(f, "pil_name");
        put_str(f, x->pil_name);
        (void)fprintf(f, ", \"pil_id\": %u, \"per_wheel\": %s, ", (unsigned)x->pil_id,
                      (aocs_config_field_is_per_wheel(x) != 0) ? "true" : "false");
        put_key(f, "kind");
        put_str(f, kind_name(x->kind));
        (void)fprintf(f, ", \"count\": %u, ", (unsigned)x->count);
        put_rule(f, x->rule);
        (void)fputs(", ", f);
        put_key(f, "names");
        put_str(f, x->names);
        (void)fputs(", ", f);
        put_key(f, "law");
        put_str(f, (x->law != AOCS_LAW_NONE) ? aocs_law_name(x->law) : NULL);
        (void)fputs(", ", f);
        put_key(f, "status");
        put_str(f, (x->status != AOCS_OK) ? aocs_status_name(x->status) : NULL);
        (void)fputs(", ", f);
        put_key(f, "help");
        put_str(f, x->help);
        (void)fputs(", ", f);
        put_default(f, x);
        (void)fprintf(f, "}%s\n", ((i + 1u) < n) ? "," : "");
    }
    (void)fputs("  ],\n", f);
}

/* One row of a fixed PIL payload: its name, kind, struct member, wire type and value count (AOCS_PIL_WIRE_<KIND>). */
static void put_payload_field(FILE *f, const char *sep, const char *name, const char *kind, const char *member,
                              const char *wire, unsigned count)
{
    (void)fprintf(f, "%s{\"name\": \"%s\", \"kind\": \"%s\", \"member\": \"%s\", \"wire\": \"%s\", \"count\": %u}", sep,
                  name, kind, member, wire, count);
}

#define DUMP_PIL_FIELD(NAME, KIND, MEMBER)                                               \
    put_payload_field(f, sep, #NAME, #KIND, #MEMBER, AOCS_PIL_WIRE_##KIND);              \
    sep = ", ";
#define DUMP_PIL_PAYLOAD(NAME, FN, TYPE, ROWS, BYTES)                                    \
    (void)fprintf(f, "%s    {\"name\": \"" #NAME "\", \"c_type\": \"" #TYPE "\", \"bytes\": %u, \"fields\": [", \
                  next, (unsigned)(BYTES));                                              \
    sep = "";                                                                            \
    ROWS(DUMP_PIL_FIELD)                                                                 \
    (void)fputs("]}", f);                                                                \
    next = ",\n";

/* The rows of every fixed payload (pil_frame.h), in wire order: how aocs_pil.frame learns each layout. */
static void dump_pil_payloads(FILE *f)
{
    const char *sep = "";
    const char *next = "";
    (void)fputs("  \"pil_payloads\": [\n", f);
    AOCS_PIL_PAYLOAD_ROWS(DUMP_PIL_PAYLOAD)
    (void)fputs("\n  ],\n  \"pil_counters\": [", f);
    sep = "";
    AOCS_PIL_COUNTER_ROWS(DUMP_PIL_FIELD)
    (void)fputs("],\n", f);
}

static void dump_registry(FILE *f)
{
    (void)fprintf(f, "{\n  \"schema\": %d,\n  \"real_t\": \"%s\",\n", DUMP_SCHEMA, DUMP_REAL_NAME);
    (void)fprintf(f, "  \"pil\": {\"version\": %u, \"table_name_max\": %u, ", (unsigned)AOCS_PIL_VERSION,
                  (unsigned)AOCS_PIL_TABLE_NAME_MAX);
    (void)fprintf(f, "\"wheel_base\": %u, \"wheel_stride\": %u, \"wheels_max\": %u, ", (unsigned)AOCS_PIL_CFG_WHEEL_BASE,
                  (unsigned)AOCS_PIL_WHEEL_STRIDE, (unsigned)AOCS_WHEELS_MAX);
    /* the allowances added to a step's instruction budget (aocs/budget.h): slew guidance, wheel array */
    (void)fprintf(f, "\"slew_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}, ",
                  (unsigned)aocs_budget_slew_instructions(AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_slew_instructions(AOCS_BUDGET_TARGET_CORTEX_M7));
    (void)fprintf(f, "\"wheels_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}, ",
                  (unsigned)aocs_budget_wheels_instructions(AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_wheels_instructions(AOCS_BUDGET_TARGET_CORTEX_M7));
    /* fault management, added to every step while fdir.enabled (the default) */
    (void)fprintf(f, "\"fdir_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}},\n",
                  (unsigned)aocs_budget_fdir_instructions(AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_fdir_instructions(AOCS_BUDGET_TARGET_CORTEX_M7));
    /* the executive's accepted ranges: the scenario loader applies the same ones (aocs_core.registry) */
    (void)fprintf(f, "  \"limits\": {\"u_limit_min\": %.17g, \"u_limit_max\": %.17g, "
                     "\"period_min_s\": %.17g, \"period_max_s\": %.17g},\n",
                  (double)AOCS_EXEC_U_LIMIT_MIN, (double)AOCS_EXEC_U_LIMIT_MAX,
                  (double)AOCS_EXEC_PERIOD_MIN_US * 1e-6, (double)AOCS_EXEC_PERIOD_MAX_US * 1e-6);
    dump_laws(f);
    dump_fields(f);
    dump_tables(f);
    dump_enums(f);
    dump_config_fields(f);
    dump_pil_payloads(f);
    (void)fputs("  \"generated_by\": \"tools/registry/aocs_registry_dump.c from firmware/include/aocs/laws.def, "
                "firmware/include/aocs/config_fields.def, firmware/gains/gain_tables.def, "
                "firmware/pil/include/aocs/pil_frame.h\"\n}\n",
                f);
}

/* ---- decode mode ---- */
/* The REALS row a TABLE row fills by name (same offset): its gain. */
static aocs_config_ref_t gain_of(aocs_config_ref_t table)
{
    aocs_config_ref_t ref = table;
    for (uint32_t i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *x = aocs_config_field_at(i);
        if ((x->kind == AOCS_CONFIG_KIND_REALS) && (x->offset == table.field->offset)) {
            ref.field = x;
        }
    }
    return ref;
}

/* One field's value as "NAME": [...] (a TABLE field: its gain; the BUDGET field: the image's instruction budget). */
static void put_decoded(FILE *f, int *first, const char *name, const aocs_exec_config_t *cfg, aocs_config_ref_t ref,
                        uint64_t budget_instr)
{
    double v[AOCS_CONFIG_VALUES_MAX];
    const aocs_config_kind_t kind = ref.field->kind;
    (void)fputs(*first ? "" : ", ", f);
    put_key(f, name);
    if ((kind == AOCS_CONFIG_KIND_REALS) || (kind == AOCS_CONFIG_KIND_INERTIA) || (kind == AOCS_CONFIG_KIND_TABLE)) {
        const uint32_t n = aocs_config_get_reals(cfg, (kind == AOCS_CONFIG_KIND_TABLE) ? gain_of(ref) : ref, v,
                                                 AOCS_CONFIG_VALUES_MAX);
        (void)fputc('[', f);
        for (uint32_t i = 0u; i < n; ++i) {
            (void)fprintf(f, "%s%.17g", (i > 0u) ? ", " : "", v[i]);
        }
        (void)fputc(']', f);
    } else {
        const uint64_t u = (kind == AOCS_CONFIG_KIND_BUDGET) ? budget_instr : aocs_config_get_uint(cfg, ref);
        (void)fprintf(f, "[%llu]", (unsigned long long)u);
    }
    *first = 0;
}

/* Every field of the registry by its PIL name (per wheel: WHEEL<i>_<NAME>), as the config holds it. */
static void dump_decoded(FILE *f, const aocs_exec_config_t *cfg, uint64_t budget_instr)
{
    int first = 1;
    for (uint32_t i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *x = aocs_config_field_at(i);
        const uint32_t units = (aocs_config_field_is_per_wheel(x) != 0) ? (uint32_t)AOCS_WHEELS_MAX : 1u;
        for (uint32_t w = 0u; w < units; ++w) {
            char name[64];
            const aocs_config_ref_t ref = {x, w};
            if (units > 1u) {
                (void)snprintf(name, sizeof(name), "WHEEL%u_%s", (unsigned)w, x->pil_name);
            } else {
                (void)snprintf(name, sizeof(name), "%s", x->pil_name);
            }
            put_decoded(f, &first, name, cfg, ref, budget_instr);
        }
    }
}

/* The payload in FILE into payload (AOCS_PIL_PAYLOAD_MAX + 1 bytes); 0, or 2 with a message. */
static int read_payload(const char *path, uint8_t *payload, size_t *n)
{
    FILE *in = fopen(path, "rb");
    if (in == NULL) {
        (void)fprintf(stderr, "aocs_registry_dump: cannot open %s\n", path);
        return 2;
    }
    *n = fread(payload, 1u, AOCS_PIL_PAYLOAD_MAX + 1u, in);
    (void)fclose(in);
    if (*n > AOCS_PIL_PAYLOAD_MAX) {
        (void)fprintf(stderr, "aocs_registry_dump: %s is longer than a payload\n", path);
        return 2;
    }
    return 0;
}

static int pil_decode(const char *path)
{
    static uint8_t payload[AOCS_PIL_PAYLOAD_MAX + 1u];
    aocs_exec_config_t cfg;
    uint64_t budget_instr = 0u;
    uint32_t field = 0u;
    aocs_status_t status = AOCS_OK;
    aocs_pil_err_t err;
    size_t n = 0u;
    if (read_payload(path, payload, &n) != 0) {
        return 2;
    }
    aocs_exec_config_default(&cfg);
    err = aocs_pil_config_decode(payload, (uint32_t)n, &cfg, &budget_instr, &field, &status);
    (void)printf("{\"pil_err\": ");
    put_str(stdout, aocs_pil_err_name(err));
    (void)printf(", \"field\": %u, \"status\": ", (unsigned)field);
    put_str(stdout, aocs_status_name(status));
    (void)printf(", \"budget_instr\": %llu, \"values\": {", (unsigned long long)budget_instr);
    dump_decoded(stdout, &cfg, budget_instr);
    (void)printf("}}\n");
    return 0;
}

/* ---- payload mode: each row's values as the C decoder read them, one printer per row kind ---- */
/* NaN and the infinities as Python's json reads them (a STEP frame's unmeasured wheels are NaN) */
static void show_reals(const real_t *x, unsigned n)
{
    for (unsigned i = 0u; i < n; ++i) {
        const double v = (double)x[i];
        (void)fputs((i > 0u) ? ", " : "", stdout);
        if (isnan(v)) {
            (void)fputs("NaN", stdout);
        } else if (isinf(v)) {
            (void)fputs((v > 0.0) ? "Infinity" : "-Infinity", stdout);
        } else {
            (void)printf("%.17g", v);
        }
    }
}

static void show_u32(const uint32_t *x) { (void)printf("%lu", (unsigned long)*x); }
static void show_u64(const uint64_t *x) { (void)printf("%llu", (unsigned long long)*x); }
static void show_status(const aocs_status_t *x) { (void)printf("%d", (int)*x); }
static void show_law(const aocs_law_id_t *x) { (void)printf("%d", (int)*x); }
static void show_mode(const aocs_exec_mode_t *x) { (void)printf("%d", (int)*x); }
static void show_pil_err(const aocs_pil_err_t *x) { (void)printf("%d", (int)*x); }
static void show_real(const real_t *x) { show_reals(x, 1u); }
static void show_vec3(const aocs_vec3_t *x) { show_reals(x->v, 3u); }
static void show_quat(const aocs_quat_t *x) { show_reals(x->q, 4u); }
static void show_wheels(const real_t (*x)[AOCS_WHEELS_MAX]) { show_reals(*x, AOCS_WHEELS_MAX); }
static void show_cov(const real_t (*x)[AOCS_EST_P_UPPER_COUNT]) { show_reals(*x, AOCS_EST_P_UPPER_COUNT); }
static void show_thrusters(const real_t (*x)[AOCS_MOM_THRUSTERS_MAX]) { show_reals(*x, AOCS_MOM_THRUSTERS_MAX); }

#define SHOW_COUNTER(NAME, KIND, MEMBER) \
    (void)fputs(sep, stdout);            \
    show_##KIND(&x->MEMBER);             \
    sep = ", ";

static void show_counters(const aocs_exec_counters_t *x)
{
    const char *sep = "";
    AOCS_PIL_COUNTER_ROWS(SHOW_COUNTER)
}

#define SHOW_FIELD(NAME, KIND, MEMBER)              \
    (void)printf("%s\"" #NAME "\": [", sep);         \
    show_##KIND(&x->MEMBER);                         \
    (void)fputc(']', stdout);                        \
    sep = ", ";
/* decode payload[0 .. n) as NAME; print the rows' values and the C encoder's bytes of them */
#define SHOW_PAYLOAD(NAME, FN, TYPE, ROWS, BYTES)                                               \
    if (strcmp(which, #NAME) == 0) {                                                            \
        TYPE v;                                                                                 \
        const TYPE *x = &v;                                                                     \
        const char *sep = "";                                                                   \
        const aocs_pil_err_t err = aocs_pil_##FN##_decode(payload, (uint32_t)n, &v);             \
        (void)printf("{\"pil_err\": \"%s\", \"fields\": {", aocs_pil_err_name(err));             \
        if (err == AOCS_PIL_OK) {                                                               \
            ROWS(SHOW_FIELD)                                                                    \
            (void)aocs_pil_##FN##_encode(&v, back, sizeof(back));                               \
        }                                                                                       \
        (void)fputs("}, \"encoded\": \"", stdout);                                              \
        for (unsigned i = 0u; (err == AOCS_PIL_OK) && (i < (unsigned)(BYTES)); ++i) {           \
            (void)printf("%02x", (unsigned)back[i]);                                            \
        }                                                                                       \
        (void)fputs("\"}\n", stdout);                                                           \
        return 0;                                                                               \
    }

static int pil_payload(const char *which, const char *path)
{
    static uint8_t payload[AOCS_PIL_PAYLOAD_MAX + 1u];
    static uint8_t back[AOCS_PIL_PAYLOAD_MAX];
    size_t n = 0u;
    if (read_payload(path, payload, &n) != 0) {
        return 2;
    }
    AOCS_PIL_PAYLOAD_ROWS(SHOW_PAYLOAD)
    (void)fprintf(stderr, "aocs_registry_dump: no fixed payload named %s\n", which);
    return 2;
}

static int write_registry(const char *out)
{
    FILE *f = stdout;
    char tmp[4096];
    if (out != NULL) {
        if ((size_t)snprintf(tmp, sizeof(tmp), "%s.tmp", out) >= sizeof(tmp)) {
            (void)fprintf(stderr, "aocs_registry_dump: path too long\n");
            return 2;
        }
        f = fopen(tmp, "w");
        if (f == NULL) {
            (void)fprintf(stderr, "aocs_registry_dump: cannot write %s\n", tmp);
            return 1;
        }
    }
    dump_registry(f);
    if (out != NULL) {
        if ((fclose(f) != 0) || (rename(tmp, out) != 0)) {
            (void)fprintf(stderr, "aocs_registry_dump: cannot write %s\n", out);
            return 1;
        }
    }
    return 0;
}

int main(int argc, char **argv)
{
    if ((argc == 3) && (strcmp(argv[1], "--out") == 0)) {
        return write_registry(argv[2]);
    }
    if ((argc == 3) && (strcmp(argv[1], "--pil-decode") == 0)) {
        return pil_decode(argv[2]);
    }
    if ((argc == 4) && (strcmp(argv[1], "--pil-payload") == 0)) {
        return pil_payload(argv[2], argv[3]);
    }
    if (argc == 1) {
        return write_registry(NULL);
    }
    (void)fprintf(stderr, "usage: aocs_registry_dump [--out FILE] | --pil-decode FILE | --pil-payload NAME FILE\n");
    return 2;
}
