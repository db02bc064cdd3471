/*
 * aocs_registry_dump: the registry of this build as JSON, for Python.
 *
 *   aocs_registry_dump [--out FILE]        the registry (default: stdout)
 *   aocs_registry_dump --pil-decode FILE   decode a PIL CONFIG payload
 *
 * Registry mode (run at build time: build/<preset>/registry/aocs_registry.json,
 * tools/registry/CMakeLists.txt): the laws of firmware/include/aocs/laws.def
 * (id, names, input kind, budgets, variant, the keys of the fields their
 * config takes), every config field (key, member, type, count, rule, unit,
 * PIL id, variant, reference value), the gain tables of
 * firmware/gains/gain_tables.def, the status codes and executive modes with
 * their names (aocs/status.def), and the PIL ids of the executive's own CONFIG fields. Python
 * reads this file instead of keeping copies (sil/aocs_core/registry.py).
 *
 * Decode mode (a test hook: Python encodes, the C codec decodes): FILE holds
 * the payload of one CONFIG frame; it is applied to aocs_exec_config_default()
 * by aocs_pil_config_decode and the result printed as one JSON object:
 * {"pil_err", "field", "status", "budget_instr", "values": {NAME: [...]}},
 * where NAME is every PIL field name (AOCS_PIL_CFG_<NAME>) and the values
 * are what the config holds afterwards (a TABLE field's values are its gain).
 *
 * Host tool: stdio allowed, no dynamic memory all the same.
 */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/budget.h"
#include "aocs/pil_frame.h"
#include "aocs_registry.h"

#if defined(AOCS_REAL_IS_FLOAT)
#define DUMP_REAL_NAME "float"
#else
#define DUMP_REAL_NAME "double"
#endif

#define DUMP_SCHEMA 2

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
    (void)fputs("],\n  \"pil_exec_fields\": [\n", f);
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

static void dump_registry(FILE *f)
{
    (void)fprintf(f, "{\n  \"schema\": %d,\n  \"real_t\": \"%s\",\n", DUMP_SCHEMA, DUMP_REAL_NAME);
    (void)fprintf(f, "  \"pil\": {\"version\": %u, \"table_name_max\": %u, ", (unsigned)AOCS_PIL_VERSION,
                  (unsigned)AOCS_PIL_TABLE_NAME_MAX);
    /* the allowances added to a step's instruction budget (aocs/budget.h): slew guidance, wheel array */
    (void)fprintf(f, "\"slew_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}, ",
                  (unsigned)aocs_budget_slew_instructions(AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_slew_instructions(AOCS_BUDGET_TARGET_CORTEX_M7));
    (void)fprintf(f, "\"wheels_instructions\": {\"cortex-m4f\": %u, \"cortex-m7\": %u}},\n",
                  (unsigned)aocs_budget_wheels_instructions(AOCS_BUDGET_TARGET_CORTEX_M4F),
                  (unsigned)aocs_budget_wheels_instructions(AOCS_BUDGET_TARGET_CORTEX_M7));
    /* the executive's accepted ranges: the scenario loader applies the same ones (aocs_core.registry) */
    (void)fprintf(f, "  \"limits\": {\"u_limit_min\": %.17g, \"u_limit_max\": %.17g, "
                     "\"period_min_s\": %.17g, \"period_max_s\": %.17g},\n",
                  (double)AOCS_EXEC_U_LIMIT_MIN, (double)AOCS_EXEC_U_LIMIT_MAX,
                  (double)AOCS_EXEC_PERIOD_MIN_US * 1e-6, (double)AOCS_EXEC_PERIOD_MAX_US * 1e-6);
    dump_laws(f);
    dump_fields(f);
    dump_tables(f);
    dump_enums(f);
    (void)fputs("  \"generated_by\": \"tools/registry/aocs_registry_dump.c from firmware/include/aocs/laws.def, "
                "firmware/gains/gain_tables.def, firmware/pil/include/aocs/pil_frame.h\"\n}\n",
                f);
}

/* ---- decode mode ---- */
static void put_reals(FILE *f, const real_t *x, int n)
{
    (void)fputc('[', f);
    for (int i = 0; i < n; ++i) {
        (void)fprintf(f, "%s%.17g", (i > 0) ? ", " : "", (double)x[i]);
    }
    (void)fputc(']', f);
}

static void put_value(FILE *f, int *first, const char *name, const real_t *x, int n)
{
    (void)fputs(*first ? "" : ", ", f);
    put_key(f, name);
    put_reals(f, x, n);
    *first = 0;
}

static void put_u64_value(FILE *f, int *first, const char *name, uint64_t v)
{
    (void)fputs(*first ? "" : ", ", f);
    put_key(f, name);
    (void)fprintf(f, "[%llu]", (unsigned long long)v);
    *first = 0;
}

#define DECODED_REAL(NAME, MEMBER) put_value(f, &first, #NAME, &cfg->laws.MEMBER, 1);
#define DECODED_VEC3(NAME, MEMBER) put_value(f, &first, #NAME, cfg->laws.MEMBER.v, 3);
#define DECODED_MAT3(NAME, MEMBER) put_value(f, &first, #NAME, &cfg->laws.MEMBER.m[0][0], 9);
/* a gain, 3x6 or 3x9, as its row-major values */
#define DECODED_GAIN_COUNT(MEMBER) ((int)(sizeof(cfg->laws.MEMBER) / sizeof(cfg->laws.MEMBER[0][0])))
#define DECODED_GAIN(NAME, MEMBER) put_value(f, &first, #NAME, &cfg->laws.MEMBER[0][0], DECODED_GAIN_COUNT(MEMBER));
#define DECODED_TABLE(NAME, MEMBER) put_value(f, &first, #NAME, &cfg->laws.MEMBER[0][0], DECODED_GAIN_COUNT(MEMBER));
#define DECODED_FIELD(NAME, LAW, KEY, MEMBER, TYPE, ...) DECODED_##TYPE(NAME, MEMBER)

static void dump_decoded(FILE *f, const aocs_exec_config_t *cfg, uint64_t budget_instr)
{
    int first = 1;
    /* the executive's fields (AOCS_PIL_EXEC_FIELD_ROWS), by hand: each has its own member and type */
    put_u64_value(f, &first, "LAW", (uint64_t)cfg->law);
    put_value(f, &first, "PERIOD_S", &cfg->period_s, 1);
    put_value(f, &first, "TARGET_Q", cfg->target.qd_DN.q, 4);
    put_value(f, &first, "TARGET_W", cfg->target.wd_B.v, 3);
    put_value(f, &first, "TARGET_W_DOT", cfg->target.wd_dot_B.v, 3);
    put_value(f, &first, "TARGET_ROTATION_RATE", cfg->target_rotation_rate_D.v, 3);
    put_u64_value(f, &first, "TARGET_T0_NS", cfg->target_t0_ns);
    put_value(f, &first, "U_MAX_AXIS", cfg->u_max_axis.v, 3);
    put_value(f, &first, "U_MAX_NORM", &cfg->u_max_norm, 1);
    put_value(f, &first, "K_SAFE", &cfg->k_safe, 1);
    put_u64_value(f, &first, "RECOVER_GOOD_SAMPLES", (uint64_t)cfg->recover_good_samples);
    put_u64_value(f, &first, "MISSING_MAX_PERIODS", (uint64_t)cfg->missing_max_periods);
    put_u64_value(f, &first, "STALE_TIMEOUT_NS", cfg->stale_timeout_ns);
    put_u64_value(f, &first, "BUDGET_INSTR", budget_instr);
    AOCS_LAW_FIELD_ROWS(DECODED_FIELD)
}

static int pil_decode(const char *path)
{
    static uint8_t payload[AOCS_PIL_PAYLOAD_MAX + 1u];
    aocs_exec_config_t cfg;
    uint64_t budget_instr = 0u;
    uint32_t field = 0u;
    aocs_status_t status = AOCS_OK;
    aocs_pil_err_t err;
    size_t n;
    FILE *in = fopen(path, "rb");
    if (in == NULL) {
        (void)fprintf(stderr, "aocs_registry_dump: cannot open %s\n", path);
        return 2;
    }
    n = fread(payload, 1u, sizeof(payload), in);
    (void)fclose(in);
    if (n > AOCS_PIL_PAYLOAD_MAX) {
        (void)fprintf(stderr, "aocs_registry_dump: %s is longer than a CONFIG payload\n", path);
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
    if (argc == 1) {
        return write_registry(NULL);
    }
    (void)fprintf(stderr, "usage: aocs_registry_dump [--out FILE] | --pil-decode FILE\n");
    return 2;
}
