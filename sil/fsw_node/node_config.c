/*
 * fsw_node configuration parser (docs/wire-contract.md). Table driven: each
 * key names a field of aocs_node_config_t, how many numbers it takes and the
 * sign rule checked here, so an error message can always name the key. The
 * executive's own init still validates everything (ordering rules, inertia).
 * The node's and the executive's general keys are listed here; the keys of
 * the laws are the config field rows of the law registry
 * (AOCS_LAW_FIELD_ROWS, firmware/include/aocs/laws.def), expanded below.
 */
#include "node_config.h"

#include "aocs/control/gain_matrix.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef enum {
    KIND_REAL,     /* n real_t values at offset */
    KIND_DOUBLE,   /* one double at offset (node settings) */
    KIND_U32,      /* one uint32_t */
    KIND_U64,      /* one uint64_t */
    KIND_SECONDS_NS, /* seconds given, uint64_t ns stored */
    KIND_LAW,      /* law name -> aocs_law_id_t */
    KIND_RUN_MODE, /* lockstep | realtime */
    KIND_STRING,   /* char[AOCS_NODE_URL_MAX] */
    KIND_INERTIA,  /* 3 (diagonal) or 9 (row-major) values */
    KIND_GAIN_TABLE, /* design name of a compiled gain table (TABLE_KEYS) */
    KIND_GUIDANCE_MODE, /* step | slew */
    KIND_SLEW_PROFILE   /* bang_coast_bang | jerk_limited */
} key_kind_t;

typedef enum {
    RULE_ANY,      /* finite */
    RULE_POS,      /* finite and > 0 */
    RULE_NONNEG    /* finite and >= 0 */
} key_rule_t;

typedef struct {
    const char *name;
    key_kind_t kind;
    size_t offset;
    unsigned count;    /* values for KIND_REAL */
    key_rule_t rule;
    const char *help;  /* shown in errors: unit / meaning */
    aocs_law_id_t law; /* KIND_GAIN_TABLE: the law whose gain tables the key takes */
} key_def_t;

#define OFF(member) offsetof(aocs_node_config_t, member)

/*
 * A law field's row of laws.def as a key: REAL, VEC3 and GAIN are COUNT
 * real_t values at MEMBER; a MAT3 is an inertia (3 or 9 values); a TABLE is
 * a gain-table design name, copied into MEMBER (the law's gain matrix) for
 * the law LAW.
 */
#define LAW_KEY_KIND_REAL KIND_REAL
#define LAW_KEY_KIND_VEC3 KIND_REAL
#define LAW_KEY_KIND_MAT3 KIND_INERTIA
#define LAW_KEY_KIND_GAIN KIND_REAL
#define LAW_KEY_KIND_TABLE KIND_GAIN_TABLE
#define LAW_KEY_COUNT_REAL(COUNT) (COUNT)
#define LAW_KEY_COUNT_VEC3(COUNT) (COUNT)
#define LAW_KEY_COUNT_MAT3(COUNT) 1u
#define LAW_KEY_COUNT_GAIN(COUNT) (COUNT)
#define LAW_KEY_COUNT_TABLE(COUNT) 1u
#define LAW_KEY_ROW(NAME, LAW, KEY, MEMBER, TYPE, COUNT, RULE, HELP, ...) \
    {KEY, LAW_KEY_KIND_##TYPE, OFF(exec.laws.MEMBER), LAW_KEY_COUNT_##TYPE(COUNT), RULE_##RULE, HELP, AOCS_LAW_##LAW},

static const key_def_t KEYS[] = {
    {"law", KIND_LAW, OFF(exec.law), 1u, RULE_ANY, "law name (executive.h), none = standby", AOCS_LAW_NONE},
    {"mode", KIND_RUN_MODE, OFF(run_mode), 1u, RULE_ANY, "lockstep | realtime", AOCS_LAW_NONE},
    {"control_period_s", KIND_REAL, OFF(exec.period_s), 1u, RULE_POS, "s", AOCS_LAW_NONE},
    {"target_q", KIND_REAL, OFF(exec.target.qd_DN), 4u, RULE_ANY, "4 numbers, scalar last, unit", AOCS_LAW_NONE},
    {"target_w", KIND_REAL, OFF(exec.target.wd_B), 3u, RULE_ANY, "rad/s, 3 numbers", AOCS_LAW_NONE},
    {"target_w_dot", KIND_REAL, OFF(exec.target.wd_dot_B), 3u, RULE_ANY, "rad/s^2, 3 numbers", AOCS_LAW_NONE},
    {"target_rotation_rate", KIND_REAL, OFF(exec.target_rotation_rate_D), 3u, RULE_ANY,
     "rad/s, 3 numbers: constant rate of the target frame w.r.t. N, in the target frame", AOCS_LAW_NONE},
    {"u_max_axis", KIND_REAL, OFF(exec.u_max_axis), 3u, RULE_NONNEG, "N m (N) per axis, 3 numbers", AOCS_LAW_NONE},
    {"u_max_norm", KIND_REAL, OFF(exec.u_max_norm), 1u, RULE_NONNEG, "N m (N), 0 = unused", AOCS_LAW_NONE},
    {"k_safe", KIND_REAL, OFF(exec.k_safe), 1u, RULE_POS, "N m s/rad", AOCS_LAW_NONE},
    {"recover_good_samples", KIND_U32, OFF(exec.recover_good_samples), 1u, RULE_POS, "count >= 1", AOCS_LAW_NONE},
    {"missing_max_periods", KIND_U32, OFF(exec.missing_max_periods), 1u, RULE_POS, "count >= 1", AOCS_LAW_NONE},
    {"stale_timeout_s", KIND_SECONDS_NS, OFF(exec.stale_timeout_ns), 1u, RULE_POS, "s", AOCS_LAW_NONE},
    {"budget_ns", KIND_U64, OFF(exec.budget_ns), 1u, RULE_NONNEG, "ns, 0 = the law's budget", AOCS_LAW_NONE},
    {"idle_timeout_s", KIND_DOUBLE, OFF(idle_timeout_s), 1u, RULE_POS, "s", AOCS_LAW_NONE},
    {"run_timeout_s", KIND_DOUBLE, OFF(run_timeout_s), 1u, RULE_NONNEG, "s, 0 = none", AOCS_LAW_NONE},
    {"status_period_s", KIND_DOUBLE, OFF(status_period_s), 1u, RULE_POS, "s", AOCS_LAW_NONE},
    {"lcm_url", KIND_STRING, OFF(lcm_url), 1u, RULE_ANY, "LCM provider URL", AOCS_LAW_NONE},
    {"guidance.mode", KIND_GUIDANCE_MODE, OFF(exec.guidance.mode), 1u, RULE_ANY, "step | slew", AOCS_LAW_NONE},
    {"guidance.profile", KIND_SLEW_PROFILE, OFF(exec.guidance.slew.profile), 1u, RULE_ANY,
     "bang_coast_bang | jerk_limited", AOCS_LAW_NONE},
    {"guidance.margin", KIND_REAL, OFF(exec.guidance.slew.margin), 1u, RULE_POS,
     "fraction of the torque envelope the slew reference may use, in (0, 1]", AOCS_LAW_NONE},
    {"guidance.rate_limit", KIND_REAL, OFF(exec.guidance.slew.rate_limit_radps), 1u, RULE_NONNEG,
     "rad/s, 0 = none", AOCS_LAW_NONE},
    {"guidance.jerk_time", KIND_REAL, OFF(exec.guidance.slew.jerk_time_s), 1u, RULE_NONNEG,
     "s, ramp time of the jerk_limited profile, 0 with bang_coast_bang", AOCS_LAW_NONE},
    {"wheels.count", KIND_U32, OFF(exec.wheels.n), 1u, RULE_POS, "reaction wheels, 3 to 6 (absent: none)",
     AOCS_LAW_NONE},
    {"wheels.failed_mask", KIND_U32, OFF(exec.wheels.failed_mask), 1u, RULE_NONNEG,
     "bit i set: wheel i declared failed", AOCS_LAW_NONE},
    {"wheels.null_gain", KIND_REAL, OFF(exec.wheels.null_gain_per_s), 1u, RULE_NONNEG,
     "null-space wheel speed management gain k_n, 1/s, 0 = none", AOCS_LAW_NONE},
    AOCS_LAW_FIELD_ROWS(LAW_KEY_ROW)
};

#define KEY_COUNT (sizeof(KEYS) / sizeof(KEYS[0]))

/*
 * The reaction wheel array's per-wheel keys, `wheel<i>.<field>` with i = 0 ..
 * AOCS_WHEELS_MAX - 1 (docs/wire-contract.md "Reaction wheels"; wheel_array.h):
 * one row per field, the wheel's value at offset + i * stride. wheels.count = 0
 * or absent is none; the executive validates the rest (unit axes, a spanning
 * array, the friction model below the motor limit). The spacecraft inertia for
 * the momentum is the `inertia` key (one source), copied after the file is read.
 */
typedef struct {
    const char *field;
    size_t offset;     /* of wheel 0's value */
    size_t stride;     /* bytes from one wheel's value to the next */
    unsigned count;
    key_rule_t rule;
    const char *help;
} wheel_key_def_t;

#define WOFF(member) OFF(exec.wheels.member)
static const wheel_key_def_t WHEEL_KEYS[] = {
    {"axis", WOFF(axis_B[0]), sizeof(aocs_vec3_t), 3u, RULE_ANY, "unit spin axis g in B, 3 numbers"},
    {"js", WOFF(js_kgm2[0]), sizeof(real_t), 1u, RULE_POS, "spin inertia Js, kg m^2"},
    {"u_max", WOFF(u_max_nm[0]), sizeof(real_t), 1u, RULE_POS, "motor torque limit, N m"},
    {"omega_max", WOFF(omega_max_radps[0]), sizeof(real_t), 1u, RULE_POS, "speed limit, rad/s"},
    {"viscous", WOFF(viscous_nms[0]), sizeof(real_t), 1u, RULE_NONNEG,
     "viscous friction b of the friction feedforward, N m s/rad"},
    {"coulomb", WOFF(coulomb_nm[0]), sizeof(real_t), 1u, RULE_NONNEG,
     "Coulomb friction c of the friction feedforward, N m"},
    {"coulomb_width", WOFF(coulomb_width_radps[0]), sizeof(real_t), 1u, RULE_POS,
     "width of the Coulomb term's tanh, rad/s"},
    {"null_speed", WOFF(null_speed_radps[0]), sizeof(real_t), 1u, RULE_ANY,
     "target speed of the null-space management, rad/s"},
};

#define WHEEL_KEY_COUNT (sizeof(WHEEL_KEYS) / sizeof(WHEEL_KEYS[0]))
#define WHEEL_KEY_PREFIX "wheel"
/* one slot per key for the loader's duplicate check: KEYS, then wheel i's field f at KEY_COUNT + i * F + f */
#define KEY_SLOTS (KEY_COUNT + ((size_t)AOCS_WHEELS_MAX * WHEEL_KEY_COUNT))


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

/* "a, b, c": the names of the compiled gain tables designed for law */
static void table_names(aocs_law_id_t law, char *buf, size_t size)
{
    size_t used = 0u;
    int i;
    buf[0] = '\0';
    for (i = 0; i < (int)AOCS_GAIN_TABLE_COUNT; ++i) {
        aocs_gain_table_id_t t = (aocs_gain_table_id_t)i;
        if ((aocs_gain_table_law(t) == law) && (used < size)) {
            int n = snprintf(buf + used, size - used, "%s%s", (used > 0u) ? ", " : "", aocs_gain_table_name(t));
            used += (n > 0) ? (size_t)n : 0u;
        }
    }
}

static int set_gain_table(aocs_node_config_t *cfg, const key_def_t *k, const char *value, char *err,
                          size_t err_size)
{
    aocs_gain_table_id_t table = AOCS_GAIN_TABLE_COUNT;
    char valid[256];
    table_names(k->law, valid, sizeof(valid));
    if (aocs_gain_table_find(value, &table) != AOCS_OK) {
        set_err(err, err_size, "key '%s': unknown gain table '%s' (valid names: %s)", k->name, value, valid);
        return 1;
    }
    if (aocs_gain_table_apply(table, k->law, &cfg->exec.laws) != AOCS_OK) {
        set_err(err, err_size, "key '%s': gain table '%s' was designed for law %s, not %s (valid names: %s)",
                k->name, value, aocs_law_name(aocs_gain_table_law(table)), aocs_law_name(k->law), valid);
        return 1;
    }
    return 0;
}

/* The key that gives by value the gain a KIND_GAIN_TABLE key gives by name (same offset); NULL if none. */
static const key_def_t *gain_key_of(const key_def_t *table_key)
{
    size_t i;
    for (i = 0u; i < KEY_COUNT; ++i) {
        if ((KEYS[i].kind == KIND_REAL) && (KEYS[i].offset == table_key->offset)) {
            return &KEYS[i];
        }
    }
    return NULL;
}

const char *aocs_node_config_gain_keys(aocs_law_id_t law, char *buf, size_t size)
{
    size_t i;
    for (i = 0u; i < KEY_COUNT; ++i) {
        const key_def_t *kk = (KEYS[i].kind == KIND_GAIN_TABLE) ? gain_key_of(&KEYS[i]) : NULL;
        if ((kk != NULL) && (KEYS[i].law == law) && (size > 0u)) {
            (void)snprintf(buf, size, "%s / %s", kk->name, KEYS[i].name);
            return buf;
        }
    }
    return "the gains of the selected law";
}

static const key_def_t *find_key(const char *key)
{
    size_t i;
    for (i = 0u; i < KEY_COUNT; ++i) {
        if (strcmp(KEYS[i].name, key) == 0) {
            return &KEYS[i];
        }
    }
    return NULL;
}

/*
 * The key definition of `key` in *out and its duplicate-check slot: a KEYS row
 * as it is, or a `wheel<i>.<field>` key (one digit i below AOCS_WHEELS_MAX, a
 * field of WHEEL_KEYS) as a row at wheel i's offset, named by `key` itself
 * (which must outlive *out). 0 when known, 1 otherwise.
 */
static int resolve_key(const char *key, key_def_t *out, size_t *slot)
{
    const key_def_t *k = find_key(key);
    const size_t plen = strlen(WHEEL_KEY_PREFIX);
    if (k != NULL) {
        *out = *k;
        *slot = (size_t)(k - KEYS);
        return 0;
    }
    if ((strncmp(key, WHEEL_KEY_PREFIX, plen) == 0) && isdigit((unsigned char)key[plen]) && (key[plen + 1u] == '.')) {
        unsigned wheel = (unsigned)(key[plen] - '0');
        size_t f;
        for (f = 0u; (wheel < AOCS_WHEELS_MAX) && (f < WHEEL_KEY_COUNT); ++f) {
            if (strcmp(&key[plen + 2u], WHEEL_KEYS[f].field) == 0) {
                const wheel_key_def_t *w = &WHEEL_KEYS[f];
                out->name = key;
                out->kind = KIND_REAL;
                out->offset = w->offset + ((size_t)wheel * w->stride);
                out->count = w->count;
                out->rule = w->rule;
                out->help = w->help;
                out->law = AOCS_LAW_NONE;
                *slot = KEY_COUNT + ((size_t)wheel * WHEEL_KEY_COUNT) + f;
                return 0;
            }
        }
    }
    return 1;
}

/* Splits value into up to max finite numbers; returns the count or -1 (bad token in *bad). */
static int parse_numbers(const char *value, double *out, unsigned max, const char **bad)
{
    const char *p = value;
    int n = 0;
    for (;;) {
        char *end = NULL;
        double x;
        while ((*p != '\0') && (isspace((unsigned char)*p) || (*p == ','))) {
            ++p;
        }
        if (*p == '\0') {
            break;
        }
        errno = 0;
        x = strtod(p, &end);
        if ((end == p) || (errno == ERANGE) || !isfinite(x) ||
            ((*end != '\0') && !isspace((unsigned char)*end) && (*end != ','))) {
            *bad = p;
            return -1;
        }
        if ((unsigned)n >= max) {
            *bad = p;
            return -2;
        }
        out[n] = x;
        ++n;
        p = end;
    }
    return n;
}

static int check_rule(const key_def_t *k, double x, char *err, size_t err_size)
{
    if ((k->rule == RULE_POS) && !(x > 0.0)) {
        set_err(err, err_size, "key '%s': value %g must be > 0 (%s)", k->name, x, k->help);
        return 1;
    }
    if ((k->rule == RULE_NONNEG) && !(x >= 0.0)) {
        set_err(err, err_size, "key '%s': value %g must be >= 0 (%s)", k->name, x, k->help);
        return 1;
    }
    return 0;
}

/* The longest list a key takes: a 3 x AOCS_GAIN_COLS_MAX gain (lqr_quat_i.k, 27 numbers). */
#define NODE_VALUES_MAX (3u * AOCS_GAIN_COLS_MAX)

static int set_numeric(aocs_node_config_t *cfg, const key_def_t *k, const char *value, char *err,
                       size_t err_size)
{
    double vals[NODE_VALUES_MAX];
    const char *bad = NULL;
    unsigned want = (k->kind == KIND_REAL) ? k->count : ((k->kind == KIND_INERTIA) ? 9u : 1u);
    int n;
    unsigned i;
    unsigned char *base = (unsigned char *)cfg + k->offset;

    if (want > NODE_VALUES_MAX) { /* a key table row beyond the buffer: refused, never written past it */
        set_err(err, err_size, "key '%s': takes %u values, more than this build reads (%u)", k->name, want,
                NODE_VALUES_MAX);
        return 1;
    }
    n = parse_numbers(value, vals, want, &bad);
    if (n == -1) {
        set_err(err, err_size, "key '%s': '%s' is not a finite number (%s)", k->name, bad, k->help);
        return 1;
    }
    if (n == -2) {
        set_err(err, err_size, "key '%s': too many values (%s)", k->name, k->help);
        return 1;
    }
    if (k->kind == KIND_INERTIA) {
        aocs_mat3_t j = aocs_mat3_zero();
        if (n == 3) {
            for (i = 0u; i < 3u; ++i) {
                j.m[i][i] = (real_t)vals[i];
            }
        } else if (n == 9) {
            for (i = 0u; i < 9u; ++i) {
                j.m[i / 3u][i % 3u] = (real_t)vals[i];
            }
        } else {
            set_err(err, err_size, "key '%s': %d values given (%s)", k->name, n, k->help);
            return 1;
        }
        memcpy(base, &j, sizeof(j));
        return 0;
    }
    if ((unsigned)n != want) {
        set_err(err, err_size, "key '%s': %d value(s) given, %u expected (%s)", k->name, n, want, k->help);
        return 1;
    }
    for (i = 0u; i < want; ++i) {
        if (check_rule(k, vals[i], err, err_size) != 0) {
            return 1;
        }
    }
    switch (k->kind) {
    case KIND_REAL:
        for (i = 0u; i < want; ++i) {
            real_t r = (real_t)vals[i];
            memcpy(base + (size_t)i * sizeof(real_t), &r, sizeof(r));
        }
        break;
    case KIND_DOUBLE:
        memcpy(base, &vals[0], sizeof(double));
        break;
    case KIND_U32: {
        uint32_t u;
        if ((vals[0] > 4294967295.0) || (floor(vals[0]) < vals[0])) {
            set_err(err, err_size, "key '%s': %g is not a whole number in range (%s)", k->name, vals[0], k->help);
            return 1;
        }
        u = (uint32_t)vals[0];
        memcpy(base, &u, sizeof(u));
        break;
    }
    case KIND_U64: {
        uint64_t u;
        if ((vals[0] > 1.8e19) || (floor(vals[0]) < vals[0])) {
            set_err(err, err_size, "key '%s': %g is not a whole number in range (%s)", k->name, vals[0], k->help);
            return 1;
        }
        u = (uint64_t)vals[0];
        memcpy(base, &u, sizeof(u));
        break;
    }
    case KIND_SECONDS_NS: {
        uint64_t u;
        if (vals[0] > 1.0e9) {
            set_err(err, err_size, "key '%s': %g s is out of range (%s)", k->name, vals[0], k->help);
            return 1;
        }
        u = (uint64_t)(vals[0] * 1.0e9 + 0.5);
        memcpy(base, &u, sizeof(u));
        break;
    }
    default:
        set_err(err, err_size, "key '%s': internal error (kind)", k->name);
        return 1;
    }
    return 0;
}

int aocs_node_config_set(aocs_node_config_t *cfg, const char *key, const char *value, char *err,
                         size_t err_size)
{
    key_def_t def;
    size_t slot = 0u;
    const key_def_t *k = &def;
    if (resolve_key(key, &def, &slot) != 0) {
        set_err(err, err_size, "unknown key '%s'", key);
        return 1;
    }
    if (value[0] == '\0') {
        set_err(err, err_size, "key '%s': empty value (%s)", key, k->help);
        return 1;
    }
    switch (k->kind) {
    case KIND_LAW: {
        aocs_law_id_t law = AOCS_LAW_NONE;
        if (aocs_law_from_name(value, &law) != AOCS_OK) {
            set_err(err, err_size, "key 'law': unknown law '%s'", value);
            return 1;
        }
        cfg->exec.law = law;
        return 0;
    }
    case KIND_RUN_MODE:
        if (strcmp(value, "lockstep") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_LOCKSTEP;
        } else if (strcmp(value, "realtime") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_REALTIME;
        } else {
            set_err(err, err_size, "key 'mode': '%s' is neither lockstep nor realtime", value);
            return 1;
        }
        return 0;
    case KIND_STRING:
        if (strlen(value) >= AOCS_NODE_URL_MAX) {
            set_err(err, err_size, "key '%s': longer than %u characters", key, AOCS_NODE_URL_MAX - 1u);
            return 1;
        }
        (void)snprintf(cfg->lcm_url, sizeof(cfg->lcm_url), "%s", value);
        return 0;
    case KIND_GAIN_TABLE:
        return set_gain_table(cfg, k, value, err, err_size);
    case KIND_GUIDANCE_MODE:
        if (strcmp(value, "step") == 0) {
            cfg->exec.guidance.mode = AOCS_GUIDANCE_MODE_STEP;
        } else if (strcmp(value, "slew") == 0) {
            cfg->exec.guidance.mode = AOCS_GUIDANCE_MODE_SLEW;
        } else {
            set_err(err, err_size, "key '%s': '%s' is neither step nor slew", key, value);
            return 1;
        }
        return 0;
    case KIND_SLEW_PROFILE:
        if (strcmp(value, "bang_coast_bang") == 0) {
            cfg->exec.guidance.slew.profile = AOCS_SLEW_PROFILE_BANG_COAST_BANG;
        } else if (strcmp(value, "jerk_limited") == 0) {
            cfg->exec.guidance.slew.profile = AOCS_SLEW_PROFILE_JERK_LIMITED;
        } else {
            set_err(err, err_size, "key '%s': '%s' is neither bang_coast_bang nor jerk_limited", key, value);
            return 1;
        }
        return 0;
    default:
        return set_numeric(cfg, k, value, err, err_size);
    }
}

static void config_defaults(aocs_node_config_t *cfg)
{
    memset(cfg, 0, sizeof(*cfg));
    aocs_exec_config_default(&cfg->exec);
    cfg->run_mode = AOCS_NODE_RUN_LOCKSTEP;
    cfg->idle_timeout_s = 5.0;
    cfg->run_timeout_s = 0.0;
    cfg->status_period_s = 1.0;
    cfg->lcm_url[0] = '\0';
}

/* strips leading/trailing blanks in place, returns the start */
static char *trim(char *s)
{
    char *end;
    while ((*s != '\0') && isspace((unsigned char)*s)) {
        ++s;
    }
    end = s + strlen(s);
    while ((end > s) && isspace((unsigned char)end[-1])) {
        --end;
    }
    *end = '\0';
    return s;
}

int aocs_node_config_load(const char *path, aocs_node_config_t *cfg, char *err, size_t err_size)
{
    FILE *f;
    char line[1024];
    char msg[AOCS_NODE_ERR_MAX];
    unsigned seen[KEY_SLOTS]; /* line of each key (resolve_key's slot), 0 = not given */
    unsigned lineno = 0u;
    int rc = 0;

    config_defaults(cfg);
    memset(seen, 0, sizeof(seen));
    f = fopen(path, "r");
    if (f == NULL) {
        set_err(err, err_size, "%s: cannot open: %s", path, strerror(errno));
        return 1;
    }
    while ((rc == 0) && (fgets(line, (int)sizeof(line), f) != NULL)) {
        char *s;
        char *eq;
        char *key;
        char *value;
        char *hash;
        key_def_t def;
        size_t slot = 0u;
        int known;
        ++lineno;
        if ((strchr(line, '\n') == NULL) && !feof(f)) {
            set_err(err, err_size, "%s:%u: line longer than %u characters", path, lineno,
                    (unsigned)sizeof(line) - 2u);
            rc = 1;
            break;
        }
        hash = strchr(line, '#');
        if (hash != NULL) {
            *hash = '\0';
        }
        s = trim(line);
        if (*s == '\0') {
            continue;
        }
        eq = strchr(s, '=');
        if (eq == NULL) {
            set_err(err, err_size, "%s:%u: expected 'key = value', got '%s'", path, lineno, s);
            rc = 1;
            break;
        }
        *eq = '\0';
        key = trim(s);
        value = trim(eq + 1);
        known = (resolve_key(key, &def, &slot) == 0);
        if (known && (seen[slot] != 0u)) {
            set_err(err, err_size, "%s:%u: key '%s' given twice", path, lineno, key);
            rc = 1;
            break;
        }
        if (aocs_node_config_set(cfg, key, value, msg, sizeof(msg)) != 0) {
            set_err(err, err_size, "%s:%u: %s", path, lineno, msg);
            rc = 1;
            break;
        }
        seen[slot] = lineno;
    }
    if ((rc == 0) && ferror(f)) {
        set_err(err, err_size, "%s: read error", path);
        rc = 1;
    }
    (void)fclose(f);
    if (rc == 0) {
        size_t i;
        for (i = 0u; (rc == 0) && (i < KEY_COUNT); ++i) {
            const key_def_t *kk = (KEYS[i].kind == KIND_GAIN_TABLE) ? gain_key_of(&KEYS[i]) : NULL;
            unsigned line_table = seen[i];
            unsigned line_k = (kk != NULL) ? seen[kk - KEYS] : 0u;
            if ((line_table != 0u) && (line_k != 0u)) {
                set_err(err, err_size,
                        "%s:%u: keys '%s' (line %u) and '%s' (line %u) are mutually exclusive: give the gain "
                        "by table name or by value, not both",
                        path, (line_table > line_k) ? line_table : line_k, KEYS[i].name, line_table, kk->name,
                        line_k);
                rc = 1;
            }
        }
    }
    if (rc == 0) {
        /* one inertia (the plant's, key 'inertia'): the slew guidance sizes its profile and feedforward with it */
        cfg->exec.guidance.slew.inertia_kgm2 = cfg->exec.laws.smc.inertia;
        /* the same inertia gives the wheel array's total momentum H = J w + sum Js g Omega */
        cfg->exec.wheels.inertia_B_kgm2 = cfg->exec.laws.smc.inertia;
    }
    if ((rc == 0) && (seen[find_key("stale_timeout_s") - KEYS] == 0u)) {
        /* default: a sample older than two control periods is stale */
        double p = (double)cfg->exec.period_s;
        cfg->exec.stale_timeout_ns = (p > 0.0) && (p < 1.0e6) ? (uint64_t)(2.0e9 * p + 0.5) : 0u;
    }
    return rc;
}
