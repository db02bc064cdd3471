/*
 * The configuration registry's table and setters (aocs/config_registry.h):
 * every row of config_fields.def and of laws.def's AOCS_LAW_FIELD_ROWS,
 * expanded once into one constant table. A value reaches the struct only
 * through a setter that checks it against its row, so the fsw_node parser
 * and the PIL CONFIG decoder cannot apply different rules.
 *
 * Values are copied in and out with memcpy at the row's offset (the members
 * are real_t arrays or structs of them, and integers of the row's kind):
 * MISRA C:2012 11.5 / 21.15 are set aside for that in MISRA-DEVIATIONS.md.
 */
#include <math.h>
#include <string.h>

#include "aocs/config_registry.h"

#define CFG_OFF(member) offsetof(aocs_exec_config_t, member)

/* ---- general rows (config_fields.def): kind, count and enum facts of each KIND ---- */
#define CFG_KIND_REAL AOCS_CONFIG_KIND_REALS
#define CFG_KIND_VEC3 AOCS_CONFIG_KIND_REALS
#define CFG_KIND_QUAT AOCS_CONFIG_KIND_REALS
#define CFG_KIND_U32 AOCS_CONFIG_KIND_U32
#define CFG_KIND_U64 AOCS_CONFIG_KIND_U64
#define CFG_KIND_NS AOCS_CONFIG_KIND_NS
#define CFG_KIND_BUDGET AOCS_CONFIG_KIND_BUDGET
#define CFG_KIND_LAW AOCS_CONFIG_KIND_LAW
#define CFG_KIND_ENUM_GUIDANCE_MODE AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_ENUM_SLEW_PROFILE AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_ENUM_ESTIMATOR AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_ENUM_MEKF_INIT_MODE AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_ENUM_MOM_POLICY AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_ENUM_MOM_TRIGGER AOCS_CONFIG_KIND_ENUM
#define CFG_KIND_MAT3 AOCS_CONFIG_KIND_REALS
#define CFG_KIND_THR AOCS_CONFIG_KIND_REALS
#define CFG_COUNT_REAL 1u
#define CFG_COUNT_VEC3 3u
#define CFG_COUNT_QUAT 4u
#define CFG_COUNT_U32 1u
#define CFG_COUNT_U64 1u
#define CFG_COUNT_NS 1u
#define CFG_COUNT_BUDGET 1u
#define CFG_COUNT_LAW 1u
#define CFG_COUNT_ENUM_GUIDANCE_MODE 1u
#define CFG_COUNT_ENUM_SLEW_PROFILE 1u
#define CFG_COUNT_ENUM_ESTIMATOR 1u
#define CFG_COUNT_ENUM_MEKF_INIT_MODE 1u
#define CFG_COUNT_ENUM_MOM_POLICY 1u
#define CFG_COUNT_ENUM_MOM_TRIGGER 1u
#define CFG_COUNT_MAT3 9u
#define CFG_COUNT_THR AOCS_MOM_THRUSTERS_MAX
#define CFG_ENUMS_REAL 0u, NULL
#define CFG_ENUMS_VEC3 0u, NULL
#define CFG_ENUMS_QUAT 0u, NULL
#define CFG_ENUMS_U32 0u, NULL
#define CFG_ENUMS_U64 0u, NULL
#define CFG_ENUMS_NS 0u, NULL
#define CFG_ENUMS_BUDGET 0u, NULL
#define CFG_ENUMS_LAW (uint32_t)AOCS_LAW_COUNT, NULL
#define CFG_ENUMS_ENUM_GUIDANCE_MODE (uint32_t)AOCS_GUIDANCE_MODE_COUNT, AOCS_CONFIG_ENUM_GUIDANCE_MODE_NAMES
#define CFG_ENUMS_ENUM_SLEW_PROFILE (uint32_t)AOCS_SLEW_PROFILE_COUNT, AOCS_CONFIG_ENUM_SLEW_PROFILE_NAMES
#define CFG_ENUMS_ENUM_ESTIMATOR (uint32_t)AOCS_DET_COUNT, AOCS_CONFIG_ENUM_ESTIMATOR_NAMES
#define CFG_ENUMS_ENUM_MEKF_INIT_MODE (uint32_t)AOCS_MEKF_INIT_COUNT, AOCS_CONFIG_ENUM_MEKF_INIT_MODE_NAMES
#define CFG_ENUMS_ENUM_MOM_POLICY (uint32_t)AOCS_MOM_COUNT, AOCS_CONFIG_ENUM_MOM_POLICY_NAMES
#define CFG_ENUMS_ENUM_MOM_TRIGGER (uint32_t)AOCS_MOM_TRIGGER_COUNT, AOCS_CONFIG_ENUM_MOM_TRIGGER_NAMES
#define CFG_ENUMS_MAT3 0u, NULL
#define CFG_ENUMS_THR 0u, NULL

#define CFG_GENERAL_ROW(NAME, KEY, MEMBER, KIND, RULE, DEFAULT, PIL_ID, STATUS, ALSO, HELP)                 \
    {KEY, PIL_ID, #NAME, CFG_KIND_##KIND, CFG_COUNT_##KIND, AOCS_CONFIG_RULE_##RULE, CFG_OFF(MEMBER), 0u, \
     CFG_ENUMS_##KIND, AOCS_LAW_NONE, AOCS_##STATUS, AOCS_##ALSO, HELP},

/* ---- per-wheel rows: wheel 0's value, one wheel's value to the next ---- */
#define CFG_WHEEL_ROW(NAME, MEMBER, COUNT, RULE, INDEX, STATUS, ALSO, HELP)                                    \
    {#MEMBER, AOCS_PIL_CFG_WHEEL_BASE + (INDEX), #NAME, AOCS_CONFIG_KIND_REALS, COUNT, AOCS_CONFIG_RULE_##RULE, \
     CFG_OFF(wheels.MEMBER[0]), sizeof(((aocs_wheels_config_t *)NULL)->MEMBER[0]), 0u, NULL, AOCS_LAW_NONE,   \
     AOCS_##STATUS, AOCS_##ALSO, HELP},

/* ---- law rows (laws.def): a MAT3 is an inertia, a TABLE a name, the others contiguous reals ---- */
#define CFG_LAW_KIND_REAL AOCS_CONFIG_KIND_REALS
#define CFG_LAW_KIND_VEC3 AOCS_CONFIG_KIND_REALS
#define CFG_LAW_KIND_GAIN AOCS_CONFIG_KIND_REALS
#define CFG_LAW_KIND_MAT3 AOCS_CONFIG_KIND_INERTIA
#define CFG_LAW_KIND_TABLE AOCS_CONFIG_KIND_TABLE
#define CFG_LAW_COUNT_REAL(COUNT) (COUNT)
#define CFG_LAW_COUNT_VEC3(COUNT) (COUNT)
#define CFG_LAW_COUNT_GAIN(COUNT) (COUNT)
#define CFG_LAW_COUNT_MAT3(COUNT) (COUNT)
#define CFG_LAW_COUNT_TABLE(COUNT) AOCS_CONFIG_TABLE_NAME_MAX
#define CFG_LAW_ROW(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, PIL_ID, ...)                             \
    {KEY, PIL_ID, #NAME, CFG_LAW_KIND_##TYPE, CFG_LAW_COUNT_##TYPE(COUNT), AOCS_CONFIG_RULE_##RULE,           \
     CFG_OFF(laws.MEMBER), 0u, 0u, NULL, AOCS_LAW_##LAW, AOCS_OK, AOCS_OK, HELP},

static const aocs_config_field_t cfg_fields[] = {
    AOCS_CONFIG_FIELD_ROWS(CFG_GENERAL_ROW)
    AOCS_CONFIG_WHEEL_FIELD_ROWS(CFG_WHEEL_ROW)
    AOCS_LAW_FIELD_ROWS(CFG_LAW_ROW)
};

#define CFG_FIELD_COUNT ((uint32_t)(sizeof(cfg_fields) / sizeof(cfg_fields[0])))

uint32_t aocs_config_field_count(void)
{
    return CFG_FIELD_COUNT;
}

const aocs_config_field_t *aocs_config_field_at(uint32_t i)
{
    return (i < CFG_FIELD_COUNT) ? &cfg_fields[i] : NULL;
}

int aocs_config_field_is_per_wheel(const aocs_config_field_t *field)
{
    int per_wheel = 0;
    if ((field != NULL) && (field->stride > 0u)) {
        per_wheel = 1;
    }
    return per_wheel;
}

/* "wheel<i>.<field>" with one digit i: 1 with *wheel and *rest (the field name) set. */
static int split_wheel_key(const char *key, uint32_t *wheel, const char **rest)
{
    const size_t plen = sizeof(AOCS_CONFIG_WHEEL_KEY_PREFIX) - 1u;
    int ok = 0;
    if ((strncmp(key, AOCS_CONFIG_WHEEL_KEY_PREFIX, plen) == 0) && (key[plen] >= '0') && (key[plen] <= '9') &&
        (key[plen + 1u] == '.')) {
        const uint32_t digit = (uint32_t)(unsigned char)key[plen];
        *wheel = digit - (uint32_t)(unsigned char)'0';
        *rest = &key[plen + 2u];
        if (*wheel < AOCS_WHEELS_MAX) {
            ok = 1;
        }
    }
    return ok;
}

int aocs_config_find_key(const char *key, aocs_config_ref_t *ref)
{
    int found = 0;
    if ((key != NULL) && (ref != NULL) && (key[0] != '\0')) {
        uint32_t wheel = 0u;
        const char *rest = NULL;
        const int per_wheel = split_wheel_key(key, &wheel, &rest);
        for (uint32_t i = 0u; (found == 0) && (i < CFG_FIELD_COUNT); ++i) {
            const aocs_config_field_t *f = &cfg_fields[i];
            const int f_per_wheel = aocs_config_field_is_per_wheel(f);
            if ((f_per_wheel == per_wheel) && (strcmp(f->key, (per_wheel != 0) ? rest : key) == 0)) {
                ref->field = f;
                ref->wheel = (per_wheel != 0) ? wheel : 0u;
                found = 1;
            }
        }
    }
    return found;
}

int aocs_config_find_pil(uint32_t pil_id, aocs_config_ref_t *ref)
{
    int found = 0;
    if (ref != NULL) {
        uint32_t wheel = 0u;
        uint32_t id = pil_id;
        if ((pil_id >= AOCS_PIL_CFG_WHEEL_BASE) &&
            (pil_id < (AOCS_PIL_CFG_WHEEL_BASE + ((uint32_t)AOCS_WHEELS_MAX * AOCS_PIL_WHEEL_STRIDE)))) {
            wheel = (pil_id - AOCS_PIL_CFG_WHEEL_BASE) / AOCS_PIL_WHEEL_STRIDE;
            id = pil_id - (wheel * AOCS_PIL_WHEEL_STRIDE);
        }
        for (uint32_t i = 0u; (found == 0) && (i < CFG_FIELD_COUNT); ++i) {
            const aocs_config_field_t *f = &cfg_fields[i];
            if ((f->pil_id == id) && ((aocs_config_field_is_per_wheel(f) != 0) || (wheel == 0u))) {
                ref->field = f;
                ref->wheel = wheel;
                found = 1;
            }
        }
    }
    return found;
}

uint32_t aocs_config_pil_id(aocs_config_ref_t ref)
{
    uint32_t id = 0u;
    if (ref.field != NULL) {
        id = ref.field->pil_id + ((aocs_config_field_is_per_wheel(ref.field) != 0) ? (ref.wheel * AOCS_PIL_WHEEL_STRIDE) : 0u);
    }
    return id;
}

/* Where the value of ref lives in *cfg: its byte offset (the row's, plus the wheel's stride). */
static size_t value_offset(aocs_config_ref_t ref)
{
    return ref.field->offset + ((size_t)ref.wheel * ref.field->stride);
}

static unsigned char *value_at(aocs_exec_config_t *cfg, aocs_config_ref_t ref)
{
    unsigned char *bytes = (unsigned char *)cfg;
    return &bytes[value_offset(ref)];
}

static const unsigned char *value_at_const(const aocs_exec_config_t *cfg, aocs_config_ref_t ref)
{
    const unsigned char *bytes = (const unsigned char *)cfg;
    return &bytes[value_offset(ref)];
}

#define CFG_RULE_ROW(NAME, LO, LO_OPEN, HI, ZERO_OK, TEXT) {#NAME, (LO), (LO_OPEN), (HI), (ZERO_OK), TEXT},

const aocs_config_rule_info_t *aocs_config_rule_info(aocs_config_rule_t rule)
{
    static const aocs_config_rule_info_t k_rules[AOCS_CONFIG_RULE_COUNT] = {AOCS_CONFIG_RULE_ROWS(CFG_RULE_ROW)};
    return ((unsigned)rule < (unsigned)AOCS_CONFIG_RULE_COUNT) ? &k_rules[rule] : &k_rules[AOCS_CONFIG_RULE_ANY];
}

int aocs_config_rule_holds(aocs_config_rule_t rule, double x)
{
    const aocs_config_rule_info_t *r = aocs_config_rule_info(rule);
    int ok = 0;
    if (isfinite(x) == 0) {
        ok = 0;
    } else if ((r->zero_ok != 0) && !(x < 0.0) && !(x > 0.0)) { /* exactly 0 */
        ok = 1;
    } else if ((r->lo_open != 0) ? !(x > r->lo) : !(x >= r->lo)) {
        ok = 0;
    } else if (x <= r->hi) {
        ok = 1;
    } else {
        ok = 0;
    }
    return ok;
}

static int ref_usable(const aocs_exec_config_t *cfg, aocs_config_ref_t ref)
{
    return ((cfg != NULL) && (ref.field != NULL) && (ref.wheel < AOCS_WHEELS_MAX) &&
            ((ref.wheel == 0u) || (aocs_config_field_is_per_wheel(ref.field) != 0))) ? 1 : 0;
}

aocs_status_t aocs_config_set_reals(aocs_exec_config_t *cfg, aocs_config_ref_t ref, const double *values,
                                    uint32_t n)
{
    aocs_status_t st = AOCS_OK;
    if ((ref_usable(cfg, ref) == 0) || (values == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (((ref.field->kind != AOCS_CONFIG_KIND_REALS) && (ref.field->kind != AOCS_CONFIG_KIND_INERTIA)) ||
               (n != ref.field->count) || (n > AOCS_CONFIG_VALUES_MAX)) {
        st = AOCS_ERR_CONFIG_FIELD;
    } else {
        for (uint32_t i = 0u; (st == AOCS_OK) && (i < n); ++i) {
            if (isfinite(values[i]) == 0) {
                st = AOCS_ERR_PARAM_NOT_FINITE;
            } else if (aocs_config_rule_holds(ref.field->rule, values[i]) == 0) {
                st = AOCS_ERR_CONFIG_RULE;
            } else {
                st = AOCS_OK;
            }
        }
        if (st == AOCS_OK) {
            unsigned char *dst = value_at(cfg, ref);
            for (uint32_t i = 0u; i < n; ++i) {
                const real_t r = (real_t)values[i]; /* as the adapters convert a wire double */
                (void)memcpy(&dst[(size_t)i * sizeof(real_t)], &r, sizeof(r));
            }
        }
    }
    return st;
}

/* An enum member of a general row, written by its own type (an enum's size is the compiler's choice). */
#define CFG_ENUM_SET_REAL(MEMBER)
#define CFG_ENUM_SET_VEC3(MEMBER)
#define CFG_ENUM_SET_QUAT(MEMBER)
#define CFG_ENUM_SET_U32(MEMBER)
#define CFG_ENUM_SET_U64(MEMBER)
#define CFG_ENUM_SET_NS(MEMBER)
#define CFG_ENUM_SET_BUDGET(MEMBER)
#define CFG_ENUM_SET_LAW(MEMBER) cfg->MEMBER = (aocs_law_id_t)(int32_t)value;
#define CFG_ENUM_SET_ENUM_GUIDANCE_MODE(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_GUIDANCE_MODE_T)(int32_t)value;
#define CFG_ENUM_SET_ENUM_SLEW_PROFILE(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_SLEW_PROFILE_T)(int32_t)value;
#define CFG_ENUM_SET_ENUM_ESTIMATOR(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_ESTIMATOR_T)value;
#define CFG_ENUM_SET_ENUM_MEKF_INIT_MODE(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_MEKF_INIT_MODE_T)value;
#define CFG_ENUM_SET_ENUM_MOM_POLICY(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_MOM_POLICY_T)value;
#define CFG_ENUM_SET_ENUM_MOM_TRIGGER(MEMBER) cfg->MEMBER = (AOCS_CONFIG_ENUM_MOM_TRIGGER_T)value;
#define CFG_ENUM_SET_MAT3(MEMBER)
#define CFG_ENUM_SET_THR(MEMBER)
#define CFG_ENUM_SET_CASE(NAME, KEY, MEMBER, KIND, ...) \
    case (uint32_t)AOCS_PIL_CFG_##NAME:                            \
        CFG_ENUM_SET_##KIND(MEMBER) break;

#define CFG_ENUM_GET_REAL(MEMBER)
#define CFG_ENUM_GET_VEC3(MEMBER)
#define CFG_ENUM_GET_QUAT(MEMBER)
#define CFG_ENUM_GET_U32(MEMBER)
#define CFG_ENUM_GET_U64(MEMBER)
#define CFG_ENUM_GET_NS(MEMBER)
#define CFG_ENUM_GET_BUDGET(MEMBER)
#define CFG_ENUM_GET_LAW(MEMBER) value = (uint64_t)(uint32_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_GUIDANCE_MODE(MEMBER) value = (uint64_t)(uint32_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_SLEW_PROFILE(MEMBER) value = (uint64_t)(uint32_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_ESTIMATOR(MEMBER) value = (uint64_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_MEKF_INIT_MODE(MEMBER) value = (uint64_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_MOM_POLICY(MEMBER) value = (uint64_t)cfg->MEMBER;
#define CFG_ENUM_GET_ENUM_MOM_TRIGGER(MEMBER) value = (uint64_t)cfg->MEMBER;
#define CFG_ENUM_GET_MAT3(MEMBER)
#define CFG_ENUM_GET_THR(MEMBER)
#define CFG_ENUM_GET_CASE(NAME, KEY, MEMBER, KIND, ...) \
    case (uint32_t)AOCS_PIL_CFG_##NAME:                            \
        CFG_ENUM_GET_##KIND(MEMBER) break;

static void enum_set(aocs_exec_config_t *cfg, uint32_t pil_id, uint64_t value)
{
    switch (pil_id) {
    AOCS_CONFIG_FIELD_ROWS(CFG_ENUM_SET_CASE)
    default:
        /* only LAW and ENUM rows come here */
        break;
    }
}

static uint64_t enum_get(const aocs_exec_config_t *cfg, uint32_t pil_id)
{
    uint64_t value = 0u;
    switch (pil_id) {
    AOCS_CONFIG_FIELD_ROWS(CFG_ENUM_GET_CASE)
    default:
        value = 0u;
        break;
    }
    return value;
}

aocs_status_t aocs_config_set_uint(aocs_exec_config_t *cfg, aocs_config_ref_t ref, uint64_t value)
{
    aocs_status_t st = AOCS_OK;
    if (ref_usable(cfg, ref) == 0) {
        st = AOCS_ERR_NULL_ARG;
    } else {
        const aocs_config_field_t *f = ref.field;
        unsigned char *dst = value_at(cfg, ref);
        const double x = (double)value;
        if ((f->kind != AOCS_CONFIG_KIND_LAW) && (f->kind != AOCS_CONFIG_KIND_ENUM) &&
            (aocs_config_rule_holds(f->rule, x) == 0)) {
            st = AOCS_ERR_CONFIG_RULE; /* the row's rule, as for a real (POS: not 0; FLAG: 0 or 1; REPEATS: >= 2) */
        } else if ((f->kind == AOCS_CONFIG_KIND_U32) && (value > (uint64_t)UINT32_MAX)) {
            st = AOCS_ERR_CONFIG_RULE;
        } else if (((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM)) &&
                   (value >= (uint64_t)f->enum_count)) {
            st = AOCS_ERR_CONFIG_RULE;
        } else if (f->kind == AOCS_CONFIG_KIND_U32) {
            const uint32_t u = (uint32_t)value;
            (void)memcpy(dst, &u, sizeof(u));
        } else if ((f->kind == AOCS_CONFIG_KIND_U64) || (f->kind == AOCS_CONFIG_KIND_NS) ||
                   (f->kind == AOCS_CONFIG_KIND_BUDGET)) {
            (void)memcpy(dst, &value, sizeof(value));
        } else if ((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM)) {
            enum_set(cfg, f->pil_id, value);
        } else {
            st = AOCS_ERR_CONFIG_FIELD;
        }
    }
    return st;
}

aocs_status_t aocs_config_set_table(aocs_exec_config_t *cfg, aocs_config_ref_t ref, const char *name)
{
    aocs_status_t st = AOCS_OK;
    if ((ref_usable(cfg, ref) == 0) || (name == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (ref.field->kind != AOCS_CONFIG_KIND_TABLE) {
        st = AOCS_ERR_CONFIG_FIELD;
    } else {
        aocs_gain_table_id_t table = AOCS_GAIN_TABLE_COUNT;
        st = aocs_gain_table_find(name, &table);
        if (st == AOCS_OK) {
            st = aocs_gain_table_apply(table, ref.field->law, &cfg->laws);
        }
    }
    return st;
}

int aocs_config_enum_value(const aocs_config_field_t *field, const char *name, uint64_t *value)
{
    int found = 0;
    if ((field != NULL) && (name != NULL) && (value != NULL)) {
        if (field->kind == AOCS_CONFIG_KIND_LAW) {
            aocs_law_id_t law = AOCS_LAW_NONE;
            if (aocs_law_from_name(name, &law) == AOCS_OK) {
                *value = (uint64_t)(uint32_t)law;
                found = 1;
            }
        } else if ((field->kind == AOCS_CONFIG_KIND_ENUM) && (field->names != NULL)) {
            /* the names are comma-separated in enum order: compare name with each, by index */
            const char *names = field->names;
            const size_t len = strlen(name);
            size_t start = 0u;
            size_t i = 0u;
            uint64_t index = 0u;
            int more = 0;
            if (len > 0u) {
                more = 1;
            }
            while (more != 0) {
                if ((names[i] == ',') || (names[i] == '\0')) {
                    if (((i - start) == len) && (strncmp(&names[start], name, len) == 0)) {
                        *value = index;
                        found = 1;
                    }
                    if ((names[i] == '\0') || (found != 0)) {
                        more = 0;
                    }
                    start = i + 1u;
                    ++index;
                }
                ++i;
            }
        } else {
            found = 0;
        }
    }
    return found;
}

uint32_t aocs_config_get_reals(const aocs_exec_config_t *cfg, aocs_config_ref_t ref, double *out, uint32_t cap)
{
    uint32_t n = 0u;
    if ((ref_usable(cfg, ref) != 0) && (out != NULL) &&
        ((ref.field->kind == AOCS_CONFIG_KIND_REALS) || (ref.field->kind == AOCS_CONFIG_KIND_INERTIA)) &&
        (ref.field->count <= cap)) {
        const unsigned char *src = value_at_const(cfg, ref);
        for (n = 0u; n < ref.field->count; ++n) {
            real_t r;
            (void)memcpy(&r, &src[(size_t)n * sizeof(real_t)], sizeof(r));
            out[n] = (double)r;
        }
    }
    return n;
}

uint64_t aocs_config_get_uint(const aocs_exec_config_t *cfg, aocs_config_ref_t ref)
{
    uint64_t value = 0u;
    if (ref_usable(cfg, ref) != 0) {
        const aocs_config_field_t *f = ref.field;
        const unsigned char *src = value_at_const(cfg, ref);
        if (f->kind == AOCS_CONFIG_KIND_U32) {
            uint32_t u;
            (void)memcpy(&u, src, sizeof(u));
            value = (uint64_t)u;
        } else if ((f->kind == AOCS_CONFIG_KIND_U64) || (f->kind == AOCS_CONFIG_KIND_NS) ||
                   (f->kind == AOCS_CONFIG_KIND_BUDGET)) {
            (void)memcpy(&value, src, sizeof(value));
        } else if ((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM)) {
            value = enum_get(cfg, f->pil_id);
        } else {
            value = 0u;
        }
    }
    return value;
}

/* DEFAULT column: a REAL or integer row's value; the other kinds keep what the caller set */
#define CFG_DEF_REAL(MEMBER, DEFAULT) cfg->MEMBER = AOCS_R(DEFAULT);
#define CFG_DEF_VEC3(MEMBER, DEFAULT)
#define CFG_DEF_QUAT(MEMBER, DEFAULT) CFG_DEF_QUAT_##DEFAULT(MEMBER)
#define CFG_DEF_QUAT_0(MEMBER)
#define CFG_DEF_QUAT_IDENTITY(MEMBER) cfg->MEMBER = aocs_quat_identity();
#define CFG_DEF_U32(MEMBER, DEFAULT) cfg->MEMBER = (uint32_t)(DEFAULT);
#define CFG_DEF_U64(MEMBER, DEFAULT) cfg->MEMBER = (uint64_t)(DEFAULT);
#define CFG_DEF_NS(MEMBER, DEFAULT) cfg->MEMBER = (uint64_t)(DEFAULT);
#define CFG_DEF_BUDGET(MEMBER, DEFAULT) cfg->MEMBER = (uint64_t)(DEFAULT);
#define CFG_DEF_LAW(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_GUIDANCE_MODE(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_SLEW_PROFILE(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_ESTIMATOR(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_MEKF_INIT_MODE(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_MOM_POLICY(MEMBER, DEFAULT)
#define CFG_DEF_ENUM_MOM_TRIGGER(MEMBER, DEFAULT)
#define CFG_DEF_MAT3(MEMBER, DEFAULT) CFG_DEF_MAT3_##DEFAULT(MEMBER)
#define CFG_DEF_MAT3_IDENTITY(MEMBER) cfg->MEMBER = aocs_mat3_identity();
#define CFG_DEF_THR(MEMBER, DEFAULT)
#define CFG_DEFAULT_ROW(NAME, KEY, MEMBER, KIND, RULE, DEFAULT, ...) CFG_DEF_##KIND(MEMBER, DEFAULT)

void aocs_config_apply_defaults(aocs_exec_config_t *cfg)
{
    if (cfg != NULL) {
        AOCS_CONFIG_FIELD_ROWS(CFG_DEFAULT_ROW)
    }
}

void aocs_config_share_inertia(aocs_exec_config_t *cfg)
{
    if (cfg != NULL) {
        cfg->guidance.slew.inertia_kgm2 = cfg->laws.smc.inertia;
        cfg->wheels.inertia_B_kgm2 = cfg->laws.smc.inertia;
    }
}
