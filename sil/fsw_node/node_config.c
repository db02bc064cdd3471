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
    NODE_DOUBLE,   /* double, within the key's rule */
    NODE_RUN_MODE, /* lockstep | realtime */
    NODE_STRING    /* char[AOCS_NODE_URL_MAX] */
} node_kind_t;

typedef struct {
    const char *name;
    node_kind_t kind;
    aocs_config_rule_t rule;
    size_t offset;
    const char *help;
} node_key_t;

#define NODE_OFF(member) offsetof(aocs_node_config_t, member)
static const node_key_t NODE_KEYS[] = {
    {"mode", NODE_RUN_MODE, AOCS_CONFIG_RULE_ANY, NODE_OFF(run_mode), "lockstep | realtime"},
    {"idle_timeout_s", NODE_DOUBLE, AOCS_CONFIG_RULE_POS, NODE_OFF(idle_timeout_s), "s"},
    {"run_timeout_s", NODE_DOUBLE, AOCS_CONFIG_RULE_NONNEG, NODE_OFF(run_timeout_s), "s, 0 = none"},
    {"status_period_s", NODE_DOUBLE, AOCS_CONFIG_RULE_POS, NODE_OFF(status_period_s), "s"},
    {"lcm_url", NODE_STRING, AOCS_CONFIG_RULE_ANY, NODE_OFF(lcm_url), "LCM provider URL"},
    {"wait_spin_us", NODE_DOUBLE, AOCS_CONFIG_RULE_NONNEG, NODE_OFF(wait_spin_us),
     "us a lockstep wait polls before it sleeps, 0 = sleeps at once"},
};
#define NODE_KEY_COUNT (sizeof(NODE_KEYS) / sizeof(NODE_KEYS[0]))
typedef char node_own_keys_counted[(NODE_KEY_COUNT == AOCS_NODE_OWN_KEYS) ? 1 : -1];

/* The message into err (when there is one); returns 1, so that `return fail(...)` ends a step in error. */
static int fail(char *err, size_t err_size, const char *fmt, ...)
{
    va_list ap;
    if ((err != NULL) && (err_size > 0u)) {
        va_start(ap, fmt);
        (void)vsnprintf(err, err_size, fmt, ap);
        va_end(ap);
    }
    return 1;
}

/* The duplicate-check slot of a registry field: after the node's own keys, one per row and wheel. */
static size_t field_slot(const aocs_config_field_t *f, uint32_t wheel)
{
    return NODE_KEY_COUNT + ((size_t)(f - aocs_config_field_at(0u)) * (size_t)AOCS_WHEELS_MAX) + (size_t)wheel;
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
        *slot = field_slot(ref->field, ref->wheel);
        return (*slot < AOCS_NODE_KEY_SLOTS) ? 0 : 1; /* a row below AOCS_NODE_CONFIG_ROWS_MAX */
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

/* want values of key into vals (an inertia: 3 = the diagonal, or 9), each within rule; 0, or 1 with err set. */
static int read_numbers(const char *key, const char *help, const char *value, unsigned want, int inertia,
                        aocs_config_rule_t rule, double *vals, char *err, size_t err_size)
{
    const char *bad = NULL;
    int n = parse_numbers(value, vals, want, &bad);
    unsigned i;
    if (n == -1) {
        return fail(err, err_size, "key '%s': '%s' is not a finite number (%s)", key, bad, help);
    }
    if (n == -2) {
        return fail(err, err_size, "key '%s': too many values (%s)", key, help);
    }
    if ((inertia != 0) && (n == 3)) {
        double d[3] = {vals[0], vals[1], vals[2]};
        for (i = 0u; i < 9u; ++i) {
            vals[i] = ((i % 4u) == 0u) ? d[i / 4u] : 0.0;
        }
        n = 9;
    }
    if ((inertia != 0) && (n != 9)) {
        return fail(err, err_size, "key '%s': %d values given (%s)", key, n, help);
    }
    if ((unsigned)n != want) {
        return fail(err, err_size, "key '%s': %d value(s) given, %u expected (%s)", key, n, want, help);
    }
    for (i = 0u; i < want; ++i) {
        if (aocs_config_rule_holds(rule, vals[i]) == 0) { /* the registry's rule: sign or physical range */
            return fail(err, err_size, "key '%s': value %g must be %s (%s)", key, vals[i],
                        aocs_config_rule_info(rule)->text, help);
        }
    }
    return 0;
}

/* A registry field from its text: numbers, a whole number, a name of the row's enum or a gain table. */
static int set_field(aocs_node_config_t *cfg, const char *key, aocs_config_ref_t ref, const char *value, char *err,
                     size_t err_size)
{
    const aocs_config_field_t *f = ref.field;
    const int inertia = (f->kind == AOCS_CONFIG_KIND_INERTIA) ? 1 : 0;
    const int reals = (f->kind == AOCS_CONFIG_KIND_REALS) || (inertia != 0);
    double vals[AOCS_CONFIG_VALUES_MAX];
    aocs_status_t st;
    uint64_t u = 0u;
    if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        const size_t row = (size_t)(f - aocs_config_field_at(0u));
        aocs_gain_table_id_t t = AOCS_GAIN_TABLE_COUNT;
        char valid[256];
        st = aocs_config_set_table(&cfg->exec, ref, value);
        (void)aocs_gain_table_find(value, &t);
        if (st == AOCS_OK) {
            cfg->table_of[(row < AOCS_NODE_CONFIG_ROWS_MAX) ? row : 0u] = t;
            return 0;
        }
        aocs_node_config_table_names(f->law, valid, sizeof(valid));
        if (st == AOCS_ERR_GAIN_TABLE_WRONG_LAW) {
            return fail(err, err_size, "key '%s': gain table '%s' was designed for law %s, not %s (valid names: %s)",
                        key, value, aocs_law_name(aocs_gain_table_law(t)), aocs_law_name(f->law), valid);
        }
        return fail(err, err_size, "key '%s': unknown gain table '%s' (valid names: %s)", key, value, valid);
    }
    if ((f->kind == AOCS_CONFIG_KIND_LAW) || (f->kind == AOCS_CONFIG_KIND_ENUM)) {
        if (aocs_config_enum_value(f, value, &u) == 0) {
            return (f->kind == AOCS_CONFIG_KIND_LAW)
                       ? fail(err, err_size, "key '%s': unknown law '%s'", key, value)
                       : fail(err, err_size, "key '%s': '%s' is not one of %s", key, value, f->names);
        }
        (void)aocs_config_set_uint(&cfg->exec, ref, u);
        return 0;
    }
    if (read_numbers(key, f->help, value, reals ? f->count : 1u, inertia, f->rule, vals, err, err_size) != 0) {
        return 1;
    }
    if (reals) {
        st = aocs_config_set_reals(&cfg->exec, ref, vals, f->count);
    } else if (f->kind == AOCS_CONFIG_KIND_NS) {
        if (vals[0] > 1.0e9) {
            return fail(err, err_size, "key '%s': %g s is out of range (%s)", key, vals[0], f->help);
        }
        st = aocs_config_set_uint(&cfg->exec, ref, (uint64_t)(vals[0] * 1.0e9 + 0.5));
    } else {
        const double top = (f->kind == AOCS_CONFIG_KIND_U32) ? 4294967295.0 : 1.8e19;
        if ((vals[0] > top) || (floor(vals[0]) < vals[0])) {
            return fail(err, err_size, "key '%s': %g is not a whole number in range (%s)", key, vals[0], f->help);
        }
        st = aocs_config_set_uint(&cfg->exec, ref, (uint64_t)vals[0]);
    }
    return (st == AOCS_OK) ? 0 : fail(err, err_size, "key '%s': %s (%s)", key, aocs_status_name(st), f->help);
}

static int set_node_key(aocs_node_config_t *cfg, const node_key_t *k, const char *value, char *err, size_t err_size)
{
    double x[1];
    if (k->kind == NODE_RUN_MODE) {
        if (strcmp(value, "lockstep") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_LOCKSTEP;
        } else if (strcmp(value, "realtime") == 0) {
            cfg->run_mode = AOCS_NODE_RUN_REALTIME;
        } else {
            return fail(err, err_size, "key 'mode': '%s' is neither lockstep nor realtime", value);
        }
        return 0;
    }
    if (k->kind == NODE_STRING) {
        if (strlen(value) >= AOCS_NODE_URL_MAX) {
            return fail(err, err_size, "key '%s': longer than %u characters", k->name, AOCS_NODE_URL_MAX - 1u);
        }
        (void)snprintf(cfg->lcm_url, sizeof(cfg->lcm_url), "%s", value);
        return 0;
    }
    if (read_numbers(k->name, k->help, value, 1u, 0, k->rule, x, err, err_size) != 0) {
        return 1;
    }
    memcpy((unsigned char *)cfg + k->offset, &x[0], sizeof(double));
    return 0;
}

int aocs_node_config_set(aocs_node_config_t *cfg, const char *key, const char *value, char *err,
                         size_t err_size)
{
    const node_key_t *node = NULL;
    aocs_config_ref_t ref = {NULL, 0u};
    size_t slot = 0u;
    if (resolve_key(key, &node, &ref, &slot) != 0) {
        return fail(err, err_size, "unknown key '%s'", key);
    }
    if (value[0] == '\0') {
        return fail(err, err_size, "key '%s': empty value (%s)", key, (node != NULL) ? node->help : ref.field->help);
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
    cfg->wait_spin_us = 0.0;
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
    }
    return kind;
}

/* The duplicate-check slot of a (non-wheel) registry field by its PIL id. */
static size_t slot_of_field(uint32_t pil_id)
{
    aocs_config_ref_t ref = {NULL, 0u};
    (void)aocs_config_find_pil(pil_id, &ref);
    return field_slot(ref.field, 0u);
}

/* A gain is given by table name or by value, not both: 0, or 1 with the two lines in err. */
static int exclusive_gain_keys(const char *path, const unsigned *seen, char *err, size_t err_size)
{
    uint32_t i;
    for (i = 0u; i < aocs_config_field_count(); ++i) {
        const aocs_config_field_t *t = aocs_config_field_at(i);
        const aocs_config_field_t *k = (t->kind == AOCS_CONFIG_KIND_TABLE) ? aocs_node_config_gain_field(t) : NULL;
        if (k != NULL) {
            const unsigned line_table = seen[field_slot(t, 0u)];
            const unsigned line_k = seen[field_slot(k, 0u)];
            if ((line_table != 0u) && (line_k != 0u)) {
                return fail(err, err_size,
                            "%s:%u: keys '%s' (line %u) and '%s' (line %u) are mutually exclusive: give the gain "
                            "by table name or by value, not both",
                            path, (line_table > line_k) ? line_table : line_k, t->key, line_table, k->key, line_k);
            }
        }
    }
    return 0;
}

/* One line of the file: blank or a comment, or `key = value` of a key not given before (its line noted). */
static int load_line(const char *path, unsigned lineno, char *line, aocs_node_config_t *cfg, char *err,
                     size_t err_size)
{
    char msg[AOCS_NODE_ERR_MAX];
    char *hash = strchr(line, '#');
    char *s;
    char *eq;
    char *key;
    const node_key_t *node = NULL;
    aocs_config_ref_t ref = {NULL, 0u};
    size_t slot = 0u;
    if (hash != NULL) {
        *hash = '\0';
    }
    s = trim(line);
    eq = strchr(s, '=');
    if (*s == '\0') {
        return 0;
    }
    if (eq == NULL) {
        return fail(err, err_size, "%s:%u: expected 'key = value', got '%s'", path, lineno, s);
    }
    *eq = '\0';
    key = trim(s);
    if ((resolve_key(key, &node, &ref, &slot) == 0) && (cfg->line_of[slot] != 0u)) {
        return fail(err, err_size, "%s:%u: key '%s' given twice", path, lineno, key);
    }
    if (aocs_node_config_set(cfg, key, trim(eq + 1), msg, sizeof(msg)) != 0) {
        return fail(err, err_size, "%s:%u: %s", path, lineno, msg);
    }
    cfg->line_of[slot] = lineno; /* resolve_key's slot; 0 = not given */
    return 0;
}

int aocs_node_config_read(FILE *f, const char *path, aocs_node_config_t *cfg, char *err, size_t err_size)
{
    char line[1024];
    unsigned lineno = 0u;
    int rc = 0;
    config_defaults(cfg);
    while ((rc == 0) && (fgets(line, (int)sizeof(line), f) != NULL)) {
        ++lineno;
        if ((strchr(line, '\n') == NULL) && !feof(f)) {
            rc = fail(err, err_size, "%s:%u: line longer than %u characters", path, lineno,
                      (unsigned)sizeof(line) - 2u);
        } else {
            rc = load_line(path, lineno, line, cfg, err, err_size);
        }
    }
    if ((rc == 0) && ferror(f)) {
        rc = fail(err, err_size, "%s: read error", path);
    }
    if (rc == 0) {
        rc = exclusive_gain_keys(path, cfg->line_of, err, err_size);
    }
    if (rc == 0) {
        aocs_config_share_inertia(&cfg->exec); /* one inertia: the slew guidance's and the wheel array's too */
    }
    if ((rc == 0) && (cfg->line_of[slot_of_field(AOCS_PIL_CFG_STALE_TIMEOUT_NS)] == 0u)) {
        /* default: a sample older than two control periods is stale */
        double p = (double)cfg->exec.period_s;
        cfg->exec.stale_timeout_ns = (p > 0.0) && (p < 1.0e6) ? (uint64_t)(2.0e9 * p + 0.5) : 0u;
    }
    return rc;
}

int aocs_node_config_load(const char *path, aocs_node_config_t *cfg, char *err, size_t err_size)
{
    int rc;
    FILE *f = fopen(path, "r");
    if (f == NULL) {
        config_defaults(cfg);
        return fail(err, err_size, "%s: cannot open: %s", path, strerror(errno));
    }
    rc = aocs_node_config_read(f, path, cfg, err, err_size);
    (void)fclose(f);
    return rc;
}
