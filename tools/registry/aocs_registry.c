/*
 * Host descriptor tables of the registry (aocs_registry.h), expanded from
 * the rows of aocs/laws.def, aocs/status.def, gains/gain_tables.def and aocs/config_fields.def,
 * and the reference configuration built from the REF column.
 */
#include "aocs_registry.h"

#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/pil_frame.h"

/* ---- status codes ---- */
#define REG_STATUS_ROW(ID, MEANING) {AOCS_##ID, "AOCS_" #ID, MEANING},

const aocs_registry_status_t aocs_registry_statuses[] = {AOCS_STATUS_ROWS(REG_STATUS_ROW)};
const size_t aocs_registry_status_count = sizeof(aocs_registry_statuses) / sizeof(aocs_registry_statuses[0]);

/* ---- laws ---- */
#define REG_INPUT_ATTITUDE "attitude"
#define REG_INPUT_ORBIT "orbit"
#define REG_OWNER_CFG_OWN 1
#define REG_OWNER_CFG_SHARED 0
/* variant member, value, number; then the FROM_FIELD member and the field member it is copied from */
#define REG_VARIANT_NO_VARIANT(MEMBER, VALUE) NULL, NULL, -1, NULL, NULL
#define REG_VARIANT_VARIANT(MEMBER, VALUE) #MEMBER, #VALUE, (int)(VALUE), NULL, NULL
#define REG_VARIANT_FROM_FIELD(MEMBER, PATH) NULL, NULL, -1, #MEMBER, #PATH
#define REG_LAW_ROW(ID, NAME, INPUT, TITLE, STATE, STATE_T, CFG, CFG_T, CFG_USE, INIT, STEP, VARIANT, VMEMBER, VVALUE,   \
                    BUDGET_NS, M4F, M7, REF)                                                                       \
    {AOCS_LAW_##ID, "AOCS_LAW_" #ID, NAME, REG_INPUT_##INPUT, TITLE, #STATE, #STATE_T, #CFG, #CFG_T, REG_OWNER_##CFG_USE, \
     #INIT, #STEP, REG_VARIANT_##VARIANT(VMEMBER, VVALUE), (uint64_t)(BUDGET_NS), (uint32_t)(M4F), (uint32_t)(M7), REF},

const aocs_registry_law_t aocs_registry_laws[] = {AOCS_LAW_ROWS(REG_LAW_ROW)};
const size_t aocs_registry_law_count = sizeof(aocs_registry_laws) / sizeof(aocs_registry_laws[0]);

/* ---- law fields ---- */
#define REG_TYPE_REAL "real"
#define REG_TYPE_VEC3 "vec3"
#define REG_TYPE_MAT3 "mat3"
#define REG_TYPE_GAIN "gain"
#define REG_TYPE_TABLE "table"
#define REG_RULE_ANY "any"
#define REG_RULE_POS "pos"
#define REG_RULE_NONNEG "nonneg"
#define REG_FIELD_ROW(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, PIL_ID, FOR, REF) \
    {#NAME, AOCS_LAW_##LAW, KEY, #MEMBER, REG_TYPE_##TYPE, (uint32_t)(COUNT), REG_RULE_##RULE, HELP,   \
     (uint32_t)(PIL_ID), #FOR, REF},

const aocs_registry_field_t aocs_registry_fields[] = {AOCS_LAW_FIELD_ROWS(REG_FIELD_ROW)};
const size_t aocs_registry_field_count = sizeof(aocs_registry_fields) / sizeof(aocs_registry_fields[0]);

/* ---- gain tables ---- */
#define REG_TABLE_ROW(ID, NAME, LAW, SYMBOL) {AOCS_GAIN_TABLE_##ID, NAME, AOCS_LAW_##LAW, #SYMBOL},

const aocs_registry_table_t aocs_registry_tables[] = {AOCS_GAIN_TABLE_ROWS(REG_TABLE_ROW)};
const size_t aocs_registry_table_count = sizeof(aocs_registry_tables) / sizeof(aocs_registry_tables[0]);

/* ---- the PIL fields of the configuration registry's general and per-wheel rows (config_fields.def) ---- */
#define REG_KIND_REAL "real", 1u
#define REG_KIND_VEC3 "real", 3u
#define REG_KIND_QUAT "real", 4u
#define REG_KIND_U32 "u64", 1u
#define REG_KIND_U64 "u64", 1u
#define REG_KIND_NS "u64", 1u
#define REG_KIND_BUDGET "u64", 1u
#define REG_KIND_LAW "u64", 1u
#define REG_KIND_ENUM_GUIDANCE_MODE "u64", 1u
#define REG_KIND_ENUM_SLEW_PROFILE "u64", 1u
#define REG_KIND_ENUM_ESTIMATOR "u64", 1u
#define REG_KIND_ENUM_MEKF_INIT_MODE "u64", 1u
#define REG_KIND_ENUM_MOM_POLICY "u64", 1u
#define REG_KIND_ENUM_MOM_TRIGGER "u64", 1u
#define REG_KIND_MAT3 "real", 9u
#define REG_KIND_THR "real", AOCS_MOM_THRUSTERS_MAX
#define REG_EXEC_ROW(NAME, KEY, MEMBER, KIND, RULE, DEFAULT, PIL_ID, ...) {#NAME, (uint32_t)(PIL_ID), REG_KIND_##KIND, KEY},

/* wheel by wheel after the general rows: name WHEEL<i>_<NAME>, id AOCS_PIL_CFG_WHEEL_BASE + i *
 * AOCS_PIL_WHEEL_STRIDE + INDEX, key "wheel<i>.<MEMBER>" */
#define REG_WHEEL_ROW(W, NAME, INDEX, COUNT, KEY)                                                                 \
    {"WHEEL" #W "_" #NAME, (uint32_t)(AOCS_PIL_CFG_WHEEL_BASE + ((W) * AOCS_PIL_WHEEL_STRIDE) + (INDEX)), "real", \
     (uint32_t)(COUNT), "wheel" #W "." KEY},
#define REG_WHEEL_ROW_0(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(0, NAME, INDEX, COUNT, #MEMBER)
#define REG_WHEEL_ROW_1(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(1, NAME, INDEX, COUNT, #MEMBER)
#define REG_WHEEL_ROW_2(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(2, NAME, INDEX, COUNT, #MEMBER)
#define REG_WHEEL_ROW_3(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(3, NAME, INDEX, COUNT, #MEMBER)
#define REG_WHEEL_ROW_4(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(4, NAME, INDEX, COUNT, #MEMBER)
#define REG_WHEEL_ROW_5(NAME, MEMBER, COUNT, RULE, INDEX, ...) REG_WHEEL_ROW(5, NAME, INDEX, COUNT, #MEMBER)
#if AOCS_WHEELS_MAX != 6
#error "one REG_WHEEL_ROW_<i> per wheel of AOCS_WHEELS_MAX"
#endif

const aocs_registry_exec_field_t aocs_registry_exec_fields[] = {
    AOCS_CONFIG_FIELD_ROWS(REG_EXEC_ROW)
    AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_0) AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_1)
    AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_2) AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_3)
    AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_4) AOCS_CONFIG_WHEEL_FIELD_ROWS(REG_WHEEL_ROW_5)
};
const size_t aocs_registry_exec_field_count =
    sizeof(aocs_registry_exec_fields) / sizeof(aocs_registry_exec_fields[0]);

const aocs_registry_law_t *aocs_registry_law(aocs_law_id_t id)
{
    for (size_t i = 0u; i < aocs_registry_law_count; ++i) {
        if (aocs_registry_laws[i].id == id) {
            return &aocs_registry_laws[i];
        }
    }
    return NULL;
}

int aocs_registry_field_applies(const aocs_registry_field_t *field, const aocs_registry_law_t *law)
{
    const aocs_registry_law_t *owner = aocs_registry_law(field->law);
    if ((owner != NULL) && (law != NULL) && (law->from_field != NULL) && (strcmp(field->member, law->from_field) == 0)) {
        return 1; /* FROM_FIELD: the law takes that field of another law (laws.def) */
    }
    if ((owner == NULL) || (law == NULL) || (strcmp(owner->config, law->config) != 0)) {
        return 0;
    }
    if (strcmp(field->variant, "ALL") == 0) {
        return 1;
    }
    return ((law->variant_value != NULL) && (strcmp(field->variant, law->variant_value) == 0)) ? 1 : 0;
}

/* ---- reference configuration ---- */
static void set_err(char *err, size_t err_size, const char *fmt, ...)
{
    va_list ap;
    if ((err == NULL) || (err_size == 0u)) {
        return;
    }
    va_start(ap, fmt);
    (void)vsnprintf(err, err_size, fmt, ap);
    va_end(ap);
}

/* blank- or comma-separated finite numbers, as the node's parser reads them; count or -1 */
static int ref_numbers(const char *key, const char *text, double *v, int max, char *err, size_t err_size)
{
    const char *p = text;
    int n = 0;
    for (;;) {
        char *end = NULL;
        double x;
        while ((*p == ' ') || (*p == '\t') || (*p == ',')) {
            ++p;
        }
        if (*p == '\0') {
            break;
        }
        errno = 0;
        x = strtod(p, &end);
        if ((end == p) || (errno == ERANGE) || !isfinite(x) || (n >= max)) {
            set_err(err, err_size, "%s: bad reference value '%s'", key, text);
            return -1;
        }
        v[n] = x;
        ++n;
        p = end;
    }
    return n;
}

static int ref_count(const char *key, const char *text, double *v, int want, char *err, size_t err_size)
{
    int n = ref_numbers(key, text, v, want, err, err_size);
    if ((n >= 0) && (n != want)) {
        set_err(err, err_size, "%s: reference '%s' has %d values, %d expected", key, text, n, want);
        n = -1;
    }
    return (n < 0) ? -1 : 0;
}

static int ref_real(const char *key, const char *text, real_t *x, char *err, size_t err_size)
{
    double v[1];
    int rc = ref_count(key, text, v, 1, err, err_size);
    if (rc == 0) {
        *x = (real_t)v[0];
    }
    return rc;
}

static int ref_vec3(const char *key, const char *text, aocs_vec3_t *x, char *err, size_t err_size)
{
    double v[3];
    int rc = ref_count(key, text, v, 3, err, err_size);
    if (rc == 0) {
        *x = aocs_vec3_make((real_t)v[0], (real_t)v[1], (real_t)v[2]);
    }
    return rc;
}

static int ref_mat3(const char *key, const char *text, aocs_mat3_t *m, char *err, size_t err_size)
{
    double v[9];
    int n = ref_numbers(key, text, v, 9, err, err_size);
    if (n == 3) {
        *m = aocs_mat3_diag(aocs_vec3_make((real_t)v[0], (real_t)v[1], (real_t)v[2]));
    } else if (n == 9) {
        for (int i = 0; i < 9; ++i) {
            m->m[i / 3][i % 3] = (real_t)v[i];
        }
    } else {
        if (n >= 0) {
            set_err(err, err_size, "%s: reference '%s' has %d values, 3 or 9 expected", key, text, n);
        }
        return -1;
    }
    return 0;
}

/* 3 x cols numbers, row-major, into the rows of a gain (3x6, or 3x9 for lqr_quat_i) */
static int ref_gain(const char *key, const char *text, real_t *k0, real_t *k1, real_t *k2, int cols, char *err,
                    size_t err_size)
{
    double v[27];
    real_t *const k[3] = {k0, k1, k2};
    int rc = ((cols > 0) && (cols <= 9)) ? ref_count(key, text, v, 3 * cols, err, err_size) : -1;
    if (rc == 0) {
        for (int i = 0; i < 3 * cols; ++i) {
            k[i / cols][i % cols] = (real_t)v[i];
        }
    }
    return rc;
}

static int ref_table(const char *key, const char *text, aocs_law_id_t law, aocs_exec_law_configs_t *c, char *err,
                     size_t err_size)
{
    aocs_gain_table_id_t table = AOCS_GAIN_TABLE_COUNT;
    aocs_status_t st = aocs_gain_table_find(text, &table);
    if (st == AOCS_OK) {
        st = aocs_gain_table_apply(table, law, c);
    }
    if (st != AOCS_OK) {
        set_err(err, err_size, "%s: reference table '%s': %s", key, text, aocs_status_name(st));
        return -1;
    }
    return 0;
}

#define REF_APPLY_REAL(LAW, KEY, MEMBER, REF) ref_real(KEY, REF, &c->MEMBER, err, err_size)
#define REF_APPLY_VEC3(LAW, KEY, MEMBER, REF) ref_vec3(KEY, REF, &c->MEMBER, err, err_size)
#define REF_APPLY_MAT3(LAW, KEY, MEMBER, REF) ref_mat3(KEY, REF, &c->MEMBER, err, err_size)
#define REF_APPLY_GAIN(LAW, KEY, MEMBER, REF) \
    ref_gain(KEY, REF, c->MEMBER[0], c->MEMBER[1], c->MEMBER[2], (int)(sizeof(c->MEMBER[0]) / sizeof(c->MEMBER[0][0])), err, err_size)
#define REF_APPLY_TABLE(LAW, KEY, MEMBER, REF) ref_table(KEY, REF, AOCS_LAW_##LAW, c, err, err_size)
#define REF_FIELD(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, PIL_ID, FOR, REF) \
    if ((rc == 0) && ((REF)[0] != '\0')) {                                            \
        rc = REF_APPLY_##TYPE(LAW, KEY, MEMBER, REF);                                 \
    }

int aocs_registry_reference_configs(aocs_exec_law_configs_t *c, char *err, size_t err_size)
{
    int rc = 0;
    (void)memset(c, 0, sizeof(*c));
    AOCS_LAW_FIELD_ROWS(REF_FIELD)
    return rc;
}
