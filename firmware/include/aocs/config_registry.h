/*
 * The configuration registry at run time: one table of every configuration
 * field of the flight software, expanded from the rows of config_fields.def
 * (the executive, guidance, wheel array) and laws.def (AOCS_LAW_FIELD_ROWS,
 * the laws), and the setters that apply each row's rule. Every reader of a
 * configuration goes through it: the fsw_node configuration file, the PIL
 * CONFIG frame, the registry dump that tells Python the fields. A value that
 * breaks its rule is refused here, with the same status whoever read it.
 *
 * A field is named by a reference (aocs_config_ref_t): its row, and for a
 * per-wheel row the wheel. Lookups by configuration key ("control_period_s",
 * "wheel2.js", "quat_pd.kp") and by PIL CONFIG id.
 */
#ifndef AOCS_CONFIG_REGISTRY_H
#define AOCS_CONFIG_REGISTRY_H

#include <float.h>
#include <stddef.h>
#include <stdint.h>

#include "aocs/types.h"
#include "aocs/executive.h"
#include "aocs/config_fields.def"

/* How a field's value is held and written (the KIND / TYPE columns of the rows). */
typedef enum {
    AOCS_CONFIG_KIND_REALS = 0, /* count real_t, contiguous (real, vec3, quat, a 3xn gain, a wheel's value) */
    AOCS_CONFIG_KIND_INERTIA,   /* aocs_mat3_t: 9 reals row-major (a file may give the 3 diagonal ones) */
    AOCS_CONFIG_KIND_U32,       /* uint32_t */
    AOCS_CONFIG_KIND_U64,       /* uint64_t */
    AOCS_CONFIG_KIND_NS,        /* uint64_t ns; seconds in a configuration file */
    AOCS_CONFIG_KIND_BUDGET,    /* uint64_t step budget, ns; the PIL image takes instructions */
    AOCS_CONFIG_KIND_LAW,       /* aocs_law_id_t, by law name in a file */
    AOCS_CONFIG_KIND_ENUM,      /* an enum, by one of the row's names in a file */
    AOCS_CONFIG_KIND_TABLE      /* a compiled gain table's design name, copied into the law's gain */
} aocs_config_kind_t;

/* The rule of a value (RULE column, the rows of AOCS_CONFIG_RULE_ROWS in config_fields.def): every
 * component finite and within the rule's range (ANY: nothing more, POS: > 0, NONNEG: >= 0, the others a
 * physical range). */
#define AOCS_CONFIG_RULE_ENUM(NAME, ...) AOCS_CONFIG_RULE_##NAME,
typedef enum { AOCS_CONFIG_RULE_ROWS(AOCS_CONFIG_RULE_ENUM) AOCS_CONFIG_RULE_COUNT } aocs_config_rule_t;

typedef struct {
    const char *name; /* the row's NAME */
    double lo;        /* lowest value (excluded when lo_open) */
    int lo_open;
    double hi;        /* highest value */
    int zero_ok;      /* 0 is also allowed (the row's "none") */
    const char *text; /* the range as the error messages say it ("in [0.01, 1]") */
} aocs_config_rule_info_t;

/* The enumerated kinds: their C type, number of values, and value names in enum order. */
#define AOCS_CONFIG_ENUM_GUIDANCE_MODE_T aocs_guidance_mode_t
#define AOCS_CONFIG_ENUM_GUIDANCE_MODE_NAMES "step,slew"
#define AOCS_CONFIG_ENUM_SLEW_PROFILE_T aocs_slew_profile_t
#define AOCS_CONFIG_ENUM_SLEW_PROFILE_NAMES "bang_coast_bang,jerk_limited"
/* the rows of estimation/determination.def, in id order (test_config_registry checks them against aocs_det_name) */
#define AOCS_CONFIG_ENUM_ESTIMATOR_T uint32_t
#define AOCS_CONFIG_ENUM_ESTIMATOR_NAMES "passthrough,mekf"
#define AOCS_CONFIG_ENUM_MEKF_INIT_MODE_T uint32_t
#define AOCS_CONFIG_ENUM_MEKF_INIT_MODE_NAMES "first_star_tracker,configured"
/* the rows of momentum/momentum.def, in id order (test_config_registry checks them against aocs_mom_name) */
#define AOCS_CONFIG_ENUM_MOM_POLICY_T uint32_t
#define AOCS_CONFIG_ENUM_MOM_POLICY_NAMES "none,magnetorquers,thrusters"
/* AOCS_MOM_TRIGGER_* (momentum.h), in value order */
#define AOCS_CONFIG_ENUM_MOM_TRIGGER_T uint32_t
#define AOCS_CONFIG_ENUM_MOM_TRIGGER_NAMES "threshold,continuous"

/* Largest number of values of one field: a 3 x AOCS_GAIN_COLS_MAX gain (lqr_quat_i.k, 27). */
#define AOCS_CONFIG_VALUES_MAX 27u
/* Longest gain-table design name (without the NUL). */
#define AOCS_CONFIG_TABLE_NAME_MAX 31u

typedef struct {
    const char *key;          /* configuration-file key; "" = no key (set by an adapter); per-wheel: the field */
    uint32_t pil_id;          /* PIL CONFIG id (per-wheel: of wheel 0) */
    const char *pil_name;     /* AOCS_PIL_CFG_<pil_name> (per-wheel: WHEEL<i>_<pil_name>) */
    aocs_config_kind_t kind;
    uint32_t count;           /* values on the wire: reals, 1 for an integer, name bytes at most for a table */
    aocs_config_rule_t rule;
    size_t offset;            /* of the value in aocs_exec_config_t (per-wheel: wheel 0's) */
    size_t stride;            /* per-wheel: bytes from one wheel's value to the next; 0 otherwise */
    uint32_t enum_count;      /* ENUM and LAW: number of values */
    const char *names;        /* ENUM: the value names, comma-separated, in enum order */
    aocs_law_id_t law;        /* a law field: the law (a table field: whose tables it takes); else NONE */
    aocs_status_t status;     /* what aocs_exec_init says when this field alone is wrong (AOCS_OK: none) */
    aocs_status_t also;       /* a status it takes part in with other fields (AOCS_OK: none) */
    const char *help;         /* unit and meaning */
} aocs_config_field_t;

/* A field of the configuration: its row, and for a per-wheel row the wheel (0 otherwise). */
typedef struct {
    const aocs_config_field_t *field;
    uint32_t wheel;
} aocs_config_ref_t;

/* The PIL CONFIG ids of the rows: AOCS_PIL_CFG_<NAME> (config_fields.def PIL_ID, laws.def PIL_ID). Wire values. */
#define AOCS_PIL_CFG_GENERAL_ENUM(NAME, KEY, MEMBER, KIND, RULE, DEFAULT, PIL_ID, ...) AOCS_PIL_CFG_##NAME = (PIL_ID),
#define AOCS_PIL_CFG_LAW_ENUM(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, PIL_ID, ...) \
    AOCS_PIL_CFG_##NAME = (PIL_ID),
typedef enum {
    AOCS_CONFIG_FIELD_ROWS(AOCS_PIL_CFG_GENERAL_ENUM)
    AOCS_LAW_FIELD_ROWS(AOCS_PIL_CFG_LAW_ENUM)
    AOCS_PIL_CFG_FIELD_MAX = 255 /* ids are one byte on the wire */
} aocs_pil_cfg_field_t;

/* Per-wheel ids: wheel i's field of INDEX is AOCS_PIL_CFG_WHEEL_BASE + i * AOCS_PIL_WHEEL_STRIDE + INDEX. */
#define AOCS_PIL_CFG_WHEEL_BASE 100u
#define AOCS_PIL_WHEEL_STRIDE 8u
/* Configuration-file key prefix of the per-wheel fields: "wheel<i>.<field>". */
#define AOCS_CONFIG_WHEEL_KEY_PREFIX "wheel"

/* The rows: the general ones (config_fields.def), then the per-wheel ones, then the laws' (laws.def). Total. */
/* The rule's row (an out-of-range rule: ANY's). */
const aocs_config_rule_info_t *aocs_config_rule_info(aocs_config_rule_t rule);
/* 1 when x obeys the rule (finite, in its range or a permitted 0), else 0. */
int aocs_config_rule_holds(aocs_config_rule_t rule, double x);

uint32_t aocs_config_field_count(void);
/* Row i (NULL out of range). Total. */
const aocs_config_field_t *aocs_config_field_at(uint32_t i);
/* 1 for a per-wheel row. Total (0 for NULL). */
int aocs_config_field_is_per_wheel(const aocs_config_field_t *field);

/* The field of a configuration key; 1 when found (*ref set), 0 otherwise. Total. */
int aocs_config_find_key(const char *key, aocs_config_ref_t *ref);
/* The field of a PIL CONFIG id; 1 when found (*ref set), 0 otherwise. Total. */
int aocs_config_find_pil(uint32_t pil_id, aocs_config_ref_t *ref);
/* The PIL CONFIG id of a field (per-wheel: of its wheel). Total (0 for a NULL row). */
uint32_t aocs_config_pil_id(aocs_config_ref_t ref);

/*
 * Sets a REALS or INERTIA field from n values (its count: 9 for an inertia,
 * row-major): every value finite (AOCS_ERR_PARAM_NOT_FINITE) and within the
 * row's rule (AOCS_ERR_CONFIG_RULE); n != count or another kind:
 * AOCS_ERR_CONFIG_FIELD. On any error *cfg is unchanged.
 */
aocs_status_t aocs_config_set_reals(aocs_exec_config_t *cfg, aocs_config_ref_t ref, const double *values,
                                    uint32_t n);
/*
 * Sets an integer field (U32, U64, NS, BUDGET, LAW, ENUM): AOCS_ERR_CONFIG_RULE
 * when the value breaks the rule (POS: 0), does not fit a U32, or is not a
 * value of the LAW / ENUM; AOCS_ERR_CONFIG_FIELD for another kind.
 */
aocs_status_t aocs_config_set_uint(aocs_exec_config_t *cfg, aocs_config_ref_t ref, uint64_t value);
/* Sets a TABLE field: the compiled gain table of that design name into the row's law's gain
 * (AOCS_ERR_GAIN_TABLE_UNKNOWN, AOCS_ERR_GAIN_TABLE_WRONG_LAW; AOCS_ERR_CONFIG_FIELD for another kind). */
aocs_status_t aocs_config_set_table(aocs_exec_config_t *cfg, aocs_config_ref_t ref, const char *name);

/* The enum value of `name` for an ENUM or LAW field: 1 when it is one of its names (*value set), else 0. Total. */
int aocs_config_enum_value(const aocs_config_field_t *field, const char *name, uint64_t *value);

/* The values of a REALS / INERTIA field (count of them into out[0 .. cap)); 0 values for another kind. */
uint32_t aocs_config_get_reals(const aocs_exec_config_t *cfg, aocs_config_ref_t ref, double *out, uint32_t cap);
/* The value of an integer field (0 for another kind). Total. */
uint64_t aocs_config_get_uint(const aocs_exec_config_t *cfg, aocs_config_ref_t ref);

/* The defaults of the rows' DEFAULT column into *cfg (the rest untouched). Total (no-op on NULL). */
void aocs_config_apply_defaults(aocs_exec_config_t *cfg);

/* One inertia (key 'inertia', laws.smc.inertia, the plant's) copied to the members that need it too: the slew
 * guidance sizes its profile and feedforward with it, the wheel array's total momentum H = J w + h_w uses it.
 * Called once a whole configuration is read (fsw_node's file, the PIL CONFIG frame). Total (no-op on NULL). */
void aocs_config_share_inertia(aocs_exec_config_t *cfg);

#endif /* AOCS_CONFIG_REGISTRY_H */
