/*
 * fsw_node configuration parser (docs/wire-contract.md). The flight
 * software's keys are the configuration registry's fields
 * (aocs/config_registry.h: config_fields.def and the laws' rows of laws.def),
 * set through its setters, so the file, the PIL CONFIG frame and the
 * registry's JSON cannot disagree on a key, a count or a rule. Only the
 * node's own transport settings (NODE_KEYS) are listed here. Every error
 * names the key; the executive's own init still validates the whole
 * (ordering rules, inertia, a spanning wheel array), and node_hints.c names
 * the keys to check when it refuses.
 */
#include "node_config.h"

#include "aocs/config_registry.h"
#include "node_hints.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* The node's own settings: not flight software configuration, so not registry rows. */
typedef enum {
    NODE_DOUBLE_POS,    /* double > 0 */
    NODE_DOUBLE_NONNEG, /* double >= 0 */
    NODE_RUN_MODE,      /* lockstep | realtime */
    NODE_STRING         /* char[AOCS_NODE_URL_MAX] */
} node_kind_t;

typedef struct {
    const char *name;
    node_kind_t kind;
    size_t offset;
    const char *help;
} node_key_t;

#define NODE_OFF(member) offsetof(aocs_node_config_t, member)
static const node_key_t NODE_KEYS[] = {
    {"mode", NODE_RUN_MODE, NODE_OFF(run_mode), "lockstep | realtime"},
    {"idle_timeout_s", NODE_DOUBLE_POS, NODE_OFF(idle_timeout_s), "s"},
    {"run_timeout_s", NODE_DOUBLE_NONNEG, NODE_OFF(run_timeout_s), "s, 0 = none"},
    {"status_period_s", NODE_DOUBLE_POS, NODE_OFF(status_period_s), "s"},
    {"lcm_url", NODE_STRING, NODE_OFF(lcm_url), "LCM provider URL"},
};
#define NODE_KEY_COUNT (sizeof(NODE_KEYS) / sizeof(NODE_KEYS[0]))
typedef char node_own_keys_counted[(NODE_KEY_COUNT == AOCS_NODE_OWN_KEYS) ? 1 : -1];

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

/* A key: a node setting (*node) or a registry field (*ref), and its duplicate-check slot. 0 when known. */
static int resolve_key(const char *key, const node_key_t **node, aocs_config_ref_t *ref, size_t *slot)
{
    size_t i;
    *node = NULL;
    for (i = 0u; i < NODE_KEY_COUNT; ++i) {
        if (strcmp(NODE_KEYS[i].name, key) == 0) {
            *node = &NODE_KEYS[i];
            *slot = i;
            return 0;
        }
    }
    if (aocs_config_find_key(key, ref) != 0) {
        size_t row = (size_t)(ref->field - aocs_config_field_at(0u));
        *slot = NODE_KEY_COUNT + (row * (size_t)AOCS_WHEELS_MAX) + (size_t)ref->wheel;
        return (row < AOCS_NODE_CONFIG_ROWS_MAX) ? 0 : 1;
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

/* The rule's words for an error message. */
static const char *rule_words(aocs_config_rule_t rule)
{
    return (rule == AOCS_CONFIG_RULE_POS) ? "must be > 0" : "must be >= 0";
}

/* want values of key into vals (an inertia: 3 = the diagonal, or 9); the count or -1 with err set. */
static int read_numbers(const char *key, const char *help, const char *value, unsigned want, int inertia,
                        double *vals, char *err, size_t err_size)
{
    const char *bad = NULL;
    int n = parse_numbers(value, vals, want, &bad);
    if (n == -1) {
        set_err(err, err_size, "key '%s': '%s' is not a finite number (%s)", key, bad, help);
        return -1;
    }
    if (n == -2) {
        set_err(err, err_size, "key '%s': too many values (%s)", key, help);
        return -1;
    }
    if ((inertia != 0) && (n == 3)) {
        double d[3] = {vals[0], vals[1], vals[2]};
        unsigned i;
        for (i = 0u; i < 9u; ++i) {
            vals[i] = ((i % 4u) == 0u) ? d[i / 4u] : 0.0;
        }
        n = 9;
    }
    if ((inertia != 0) && (n != 9)) {
        set_err(err, err_size, "key '%s': %d values given (%s)", key, n, help);
        return -1;
    }
    if ((unsigned)n != want) {
        set_err(err, err_size, "key '%s': %d value(s) given, %u expected (%s)", key, n, want, help);
        return -1;
    }
    return n;
}

/* A registry field from its text: numbers, a whole number, a name of the row's enum or a gain table. */
static int set_field(aocs_node_config_t *cfg, const char *key, aocs_config_ref_t ref, const char *value, char *err,
                     size_t err_size)
{
    const aocs_config_field_t *f = ref.field;
    double vals[AOCS_CONFIG_VALUES_MAX];
    aocs_status_t st = AOCS_OK;
    uint64_t u = 0u;
    if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        char valid[256];
        aocs_node_config_table_names(f->law, valid, sizeof(valid));
        st = aocs_config_set_table(&cfg->exec, ref, value);
        if (st == AOCS_OK) {
            size_t row = (size_t)(f - aocs_config_field_at(0u));
            (void)aocs_gain_table_find(value, &cfg->table_of[(row < AOCS_NODE_CONFIG_ROWS_MAX) ? row : 0u]);
        }
        if (st == AOCS_ERR_GAIN_TABLE_WRONG_LAW) {
            aocs_gain_table_id_t t = AOCS_GAIN_TABLE_COUNT;
            (void)aocs_gain_table_find(value, &t);
            set_err(err, err_size, "key '%s': gain table '%s' was designed for law %s, not %s (valid names: %s)", key,
                    value, aocs_law_name(aocs_gain_table_law(t)), aocs_law_name(f->law), valid);
        } else if (st != AOCS_OK) {
            set_err(err, err_size, "key '%s': unknown gain table '%s' (valid names: %s)", key, value, valid);
        }
        return (st == AOCS_OK) ? 0 : 1;
    }
    if ((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM)) {
        if (aocs_config_enum_value(f, value, &u) == 0) {
            if (f->kind == AOCS_CONFIG_KIND_LAW) {
                set_err(err, err_size, "key '%s': unknown law '%s'", key, value);
            } else {
                set_err(err, err_size, "key '%s': '%s' is not one of %s", key, value, f->names);
            }
            return 1;
        }
        (void)aocs_config_set_uint(&cfg->exec, ref, u);
        return 0;
    }
    {
        const int inertia = (f->kind == AOCS_CONFIG_KIND_INERTIA) ? 1 : 0;
        const unsigned want = (f->kind == AOCS_CONFIG_KIND_REALS) || (inertia != 0) ? f->count : 1u;
        unsigned i;
        if (read_numbers(key, f->help, value, want, inertia, vals, err, err_size) < 0) {
            return 1;
        }
        for (i = 0u; i < want; ++i) {
            if ((f->rule != AOCS_CONFIG_RULE_ANY) &&
                !((f->rule == AOCS_CONFIG_RULE_POS) ? (vals[i] > 0.0) : (vals[i] >= 0.0))) {
                set_err(err, err_size, "key '%s': value %g %s (%s)", key, vals[i], rule_words(f->rule), f->help);
                return 1;
            }
        }
    }
    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
        st = aocs_config_set_reals(&cfg->exec, ref, vals, f->count);
    } else if (f->kind == AOCS_CONFIG_KIND_NS) {
        if (vals[0] > 1.0e9) {
            set_err(err, err_size, "key '%s': %g s is out of range (%s)", key, vals[0], f->help);
            return 1;
        }
        st = aocs_config_set_uint(&cfg->exec, ref, (uint64_t)(vals[0] * 1.0e9 + 0.5));
    } else {
        const double top = (f->kind == AOCS_CONFIG_KIND_U32) ? 4294967295.0 : 1.8e19;
        if ((vals[0] > top) || (floor(vals[0]) < vals[0])) {
            set_err(err, err_size, "key '%s': %g is not a whole number in range (%s)", key, vals[0], f->help);
            return 1;
        }
        st = aocs_config_set_uint(&cfg->exec, ref, (uint64_t)vals[0]);
    }
    if (st != AOCS_OK) {
        set_err(err, err_size, "key '%s': %s (%s)", key, aocs_status_name(st), f->help);
        return 1;
    }
    return 0;
}

static int set_node_key(aocs_node_config_t *cfg, const node_key_t *k, const char *value, char *err, size_t err_size)
{
    unsigned char *base = (unsigned char *)cfg + k->offset;
    double x[1];
    if (k->kind == NODE_RUN_MODE) {
        if (strcmp(value, "lockstep") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_LOCKSTEP;
        } else if (strcmp(value, "realtime") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_REALTIME;
        } else {
            set_err(err, err_size, "key 'mode': '%s' is neither lockstep nor realtime", value);
            return 1;
        }
        return 0;
    }
    if (k->kind == NODE_STRING) {
        if (strlen(value) >= AOCS_NODE_URL_MAX) {
            set_err(err, err_size, "key '%s': longer than %u characters", k->name, AOCS_NODE_URL_MAX - 1u);
            return 1;
        }
        (void)snprintf(cfg->lcm_url, sizeof(cfg->lcm_url), "%s", value);
        return 0;
    }
    if (read_numbers(k->name, k->help, value, 1u, 0, x, err, err_size) < 0) {
        return 1;
    }
    if ((k->kind == NODE_DOUBLE_POS) ? !(x[0] > 0.0) : !(x[0] >= 0.0)) {
        set_err(err, err_size, "key '%s': value %g %s (%s)", k->name, x[0],
                rule_words((k->kind == NODE_DOUBLE_POS) ? AOCS_CONFIG_RULE_POS : AOCS_CONFIG_RULE_NONNEG), k->help);
        return 1;
    }
    memcpy(base, &x[0], sizeof(double));
    return 0;
}

int aocs_node_config_set(aocs_node_config_t *cfg, const char *key, const char *value, char *err,
                         size_t err_size)
{
    const node_key_t *node = NULL;
    aocs_config_ref_t ref = {NULL, 0u};
    size_t slot = 0u;
    if (resolve_key(key, &node, &ref, &slot) != 0) {
        set_err(err, err_size, "unknown key '%s'", key);
        return 1;
    }
    if (value[0] == '\0') {
        set_err(err, err_size, "key '%s': empty value (%s)", key, (node != NULL) ? node->help : ref.field->help);
        return 1;
    }
    return (node != NULL) ? set_node_key(cfg, node, value, err, err_size)
                          : set_field(cfg, key, ref, value, err, err_size);
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

int aocs_node_config_slot(size_t slot, aocs_config_ref_t *ref, const char **own_key)
{
    int kind = 0;
    if (slot < NODE_KEY_COUNT) {
        *own_key = NODE_KEYS[slot].name;
        kind = 2;
    } else if (slot < AOCS_NODE_KEY_SLOTS) {
        const uint32_t row = (uint32_t)((slot - NODE_KEY_COUNT) / (size_t)AOCS_WHEELS_MAX);
        const uint32_t wheel = (uint32_t)((slot - NODE_KEY_COUNT) % (size_t)AOCS_WHEELS_MAX);
        const aocs_config_field_t *f = aocs_config_field_at(row);
        if ((f != NULL) && ((wheel == 0u) || (aocs_config_field_is_per_wheel(f) != 0))) {
            ref->field = f;
            ref->wheel = wheel;
            kind = 1;
        }
    } else {
        kind = 0;
    }
    return kind;
}

/* The duplicate-check slot of a (non-wheel) registry field by its PIL id. */
static size_t slot_of_field(uint32_t pil_id)
{
    aocs_config_ref_t ref = {NULL, 0u};
    (void)aocs_config_find_pil(pil_id, &ref);
    return NODE_KEY_COUNT + ((size_t)(ref.field - aocs_config_field_at(0u)) * (size_t)AOCS_WHEELS_MAX);
}

/* A gain is given by table name or by value, not both: 0, or 1 with the two lines in err. */
static int exclusive_gain_keys(const char *path, const unsigned *seen, char *err, size_t err_size)
{
    uint32_t i;
    for (i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *t = aocs_config_field_at(i);
        const aocs_config_field_t *k = (t->kind == AOCS_CONFIG_KIND_TABLE) ? aocs_node_config_gain_field(t) : NULL;
        if (k != NULL) {
            const unsigned line_table = seen[NODE_KEY_COUNT + ((size_t)i * (size_t)AOCS_WHEELS_MAX)];
            const unsigned line_k =
                seen[NODE_KEY_COUNT + ((size_t)(k - aocs_config_field_at(0u)) * (size_t)AOCS_WHEELS_MAX)];
            if ((line_table != 0u) && (line_k != 0u)) {
                set_err(err, err_size,
                        "%s:%u: keys '%s' (line %u) and '%s' (line %u) are mutually exclusive: give the gain "
                        "by table name or by value, not both",
                        path, (line_table > line_k) ? line_table : line_k, t->key, line_table, k->key, line_k);
                return 1;
            }
        }
    }
    return 0;
}

int aocs_node_config_load(const char *path, aocs_node_config_t *cfg, char *err, size_t err_size)
{
    FILE *f;
    char line[1024];
    char msg[AOCS_NODE_ERR_MAX];
    unsigned *seen = cfg->line_of; /* line of each key (resolve_key's slot), 0 = not given */
    unsigned lineno = 0u;
    int rc = 0;

    config_defaults(cfg);
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
        const node_key_t *node = NULL;
        aocs_config_ref_t ref = {NULL, 0u};
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
        known = (resolve_key(key, &node, &ref, &slot) == 0);
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
        rc = exclusive_gain_keys(path, seen, err, err_size);
    }
    if (rc == 0) {
        /* one inertia (the plant's, key 'inertia'): the slew guidance sizes its profile and feedforward with it */
        cfg->exec.guidance.slew.inertia_kgm2 = cfg->exec.laws.smc.inertia;
        /* the same inertia gives the wheel array's total momentum H = J w + sum Js g Omega */
        cfg->exec.wheels.inertia_B_kgm2 = cfg->exec.laws.smc.inertia;
    }
    if ((rc == 0) && (seen[slot_of_field(AOCS_PIL_CFG_STALE_TIMEOUT_NS)] == 0u)) {
        /* default: a sample older than two control periods is stale */
        double p = (double)cfg->exec.period_s;
        cfg->exec.stale_timeout_ns = (p > 0.0) && (p < 1.0e6) ? (uint64_t)(2.0e9 * p + 0.5) : 0u;
    }
    return rc;
}
