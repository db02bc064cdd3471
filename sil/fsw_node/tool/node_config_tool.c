/*
 * aocs_node_config: the fsw_node configuration file read by fsw_node's own
 * parser (node_config.c), for the host tools that drive a flight computer
 * without being one: the PIL bridge turns it into the CONFIG frame of the
 * emulated MCU, so a file is parsed once, by one parser, whoever flies it.
 *
 *   aocs_node_config FILE [--pil-clock-hz HZ]   the configuration as JSON on stdout
 *   aocs_node_config --hint STATUS LAW          the keys to check for an aocs_exec_init status
 *
 * JSON: law, mode, period_s, idle_timeout_s, run_timeout_s, status_period_s,
 * lcm_url, budget_ns, stale_timeout_ns, n_wheels, guidance_mode, lines (key ->
 * line of the file), and with --pil-clock-hz the CONFIG payload as hex
 * (pil_config): every key the file gives, in the file's order, from the
 * parsed configuration (a gain table by its name; the ns budget as an
 * instruction budget at HZ, one instruction per cycle; the stale timeout
 * last, as the node computed it). A file fsw_node refuses gives fsw_node's
 * message on stderr and exit 2, nothing on stdout. Host tool (stdio).
 */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "aocs/config_registry.h"
#include "aocs/pil_frame.h"
#include "node_checks.h"
#include "node_config.h"
#include "node_hints.h"

#define EXIT_USAGE 2

static void put_str(const char *s)
{
    (void)putchar('"');
    for (const char *p = s; *p != '\0'; ++p) {
        const unsigned char c = (unsigned char)*p;
        if ((c == '"') || (c == '\\')) {
            (void)printf("\\%c", c);
        } else if (c < 0x20u) {
            (void)printf("\\u%04x", (unsigned)c);
        } else {
            (void)putchar((int)c);
        }
    }
    (void)putchar('"');
}

/* The key of a registry field as the file names it ("wheel2.js_kgm2" for a per-wheel one). */
static void field_key(aocs_config_ref_t ref, char *buf, size_t size)
{
    if (aocs_config_field_is_per_wheel(ref.field) != 0) {
        (void)snprintf(buf, size, "%s%u.%s", AOCS_CONFIG_WHEEL_KEY_PREFIX, (unsigned)ref.wheel, ref.field->key);
    } else {
        (void)snprintf(buf, size, "%s", ref.field->key);
    }
}

/* One given field as a CONFIG entry; the stale timeout and a zero budget are left out (see above). */
static aocs_pil_err_t put_entry(const aocs_node_config_t *cfg, aocs_config_ref_t ref, double clock_hz, uint8_t *out,
                                uint32_t cap, uint32_t *pos)
{
    const aocs_config_field_t *f = ref.field;
    const aocs_pil_cfg_field_t id = (aocs_pil_cfg_field_t)aocs_config_pil_id(ref);
    aocs_pil_err_t err = AOCS_PIL_OK;
    if ((f->kind == AOCS_CONFIG_KIND_REALS) || (f->kind == AOCS_CONFIG_KIND_INERTIA)) {
        double v[AOCS_CONFIG_VALUES_MAX];
        real_t r[AOCS_CONFIG_VALUES_MAX];
        const uint32_t n = aocs_config_get_reals(&cfg->exec, ref, v, AOCS_CONFIG_VALUES_MAX);
        for (uint32_t i = 0u; i < n; ++i) {
            r[i] = (real_t)v[i];
        }
        err = aocs_pil_config_put_reals(out, cap, pos, id, r, n);
    } else if (f->kind == AOCS_CONFIG_KIND_TABLE) {
        const size_t row = (size_t)(f - aocs_config_field_at(0u));
        err = aocs_pil_config_put_name(out, cap, pos, id, aocs_gain_table_name(cfg->table_of[row]));
    } else if (f->kind == AOCS_CONFIG_KIND_BUDGET) {
        const uint64_t ns = aocs_config_get_uint(&cfg->exec, ref);
        if (ns > 0u) {
            /* a ns budget at the target's nominal clock, one instruction per cycle */
            err = aocs_pil_config_put_u64(out, cap, pos, id, (uint64_t)ceil((double)ns * clock_hz / 1e9));
        }
    } else if (f->kind != AOCS_CONFIG_KIND_NS) {
        err = aocs_pil_config_put_u64(out, cap, pos, id, aocs_config_get_uint(&cfg->exec, ref));
    } else {
        err = AOCS_PIL_OK; /* the stale timeout goes last */
    }
    return err;
}

/* The CONFIG payload of the keys given, in the file's order; 0, or 1 when it does not fit a frame. */
static int pil_payload(const aocs_node_config_t *cfg, double clock_hz, uint8_t *out, uint32_t *len)
{
    uint32_t pos = 0u;
    unsigned line = 0u;
    aocs_pil_err_t err = AOCS_PIL_OK;
    for (;;) {
        /* the next line that gave a key (lines are unique: one key per line) */
        unsigned next = 0u;
        size_t next_slot = 0u;
        for (size_t s = 0u; s < AOCS_NODE_KEY_SLOTS; ++s) {
            if ((cfg->line_of[s] > line) && ((next == 0u) || (cfg->line_of[s] < next))) {
                next = cfg->line_of[s];
                next_slot = s;
            }
        }
        if ((next == 0u) || (err != AOCS_PIL_OK)) {
            break;
        }
        {
            aocs_config_ref_t ref = {NULL, 0u};
            const char *own = NULL;
            if (aocs_node_config_slot(next_slot, &ref, &own) == 1) {
                err = put_entry(cfg, ref, clock_hz, out, AOCS_PIL_PAYLOAD_MAX, &pos);
            }
        }
        line = next;
    }
    if (err == AOCS_PIL_OK) {
        aocs_config_ref_t stale = {NULL, 0u};
        (void)aocs_config_find_pil((uint32_t)AOCS_PIL_CFG_STALE_TIMEOUT_NS, &stale);
        err = aocs_pil_config_put_u64(out, AOCS_PIL_PAYLOAD_MAX, &pos, AOCS_PIL_CFG_STALE_TIMEOUT_NS,
                                      aocs_config_get_uint(&cfg->exec, stale));
    }
    *len = pos;
    return (err == AOCS_PIL_OK) ? 0 : 1;
}

static void put_lines(const aocs_node_config_t *cfg)
{
    int first = 1;
    (void)fputs("\"lines\": {", stdout);
    for (size_t s = 0u; s < AOCS_NODE_KEY_SLOTS; ++s) {
        aocs_config_ref_t ref = {NULL, 0u};
        const char *own = NULL;
        const int kind = (cfg->line_of[s] != 0u) ? aocs_node_config_slot(s, &ref, &own) : 0;
        if (kind != 0) {
            char key[64];
            if (kind == 1) {
                field_key(ref, key, sizeof(key));
            } else {
                (void)snprintf(key, sizeof(key), "%s", own);
            }
            (void)fputs(first ? "" : ", ", stdout);
            put_str(key);
            (void)printf(": %u", cfg->line_of[s]);
            first = 0;
        }
    }
    (void)fputs("}", stdout);
}

static int describe(const char *path, const char *clock_arg)
{
    static aocs_node_config_t cfg;
    static uint8_t payload[AOCS_PIL_PAYLOAD_MAX];
    char err[AOCS_NODE_ERR_MAX];
    uint32_t len = 0u;
    if (aocs_node_config_load(path, &cfg, err, sizeof(err)) != 0) {
        (void)fprintf(stderr, "%s\n", err);
        return EXIT_USAGE;
    }
    if (aocs_node_timeouts_check(&cfg, err, sizeof(err)) != 0) {
        (void)fprintf(stderr, "%s: %s\n", path, err);
        return EXIT_USAGE;
    }
    if (clock_arg != NULL) {
        char *end = NULL;
        const double hz = strtod(clock_arg, &end);
        if ((end == clock_arg) || (*end != '\0') || !(hz > 0.0) || !(hz < 1e12)) {
            (void)fprintf(stderr, "aocs_node_config: --pil-clock-hz %s is not a clock rate in (0, 1e12) Hz\n",
                          clock_arg);
            return EXIT_USAGE;
        }
        if (pil_payload(&cfg, hz, payload, &len) != 0) {
            (void)fprintf(stderr, "%s: the configuration does not fit one PIL CONFIG frame (%u bytes)\n", path,
                          (unsigned)AOCS_PIL_PAYLOAD_MAX);
            return EXIT_USAGE;
        }
    }
    (void)fputs("{\"law\": ", stdout);
    put_str(aocs_law_name(cfg.exec.law));
    (void)printf(", \"mode\": \"%s\", \"period_s\": %.17g, \"idle_timeout_s\": %.17g, \"run_timeout_s\": %.17g, "
                 "\"status_period_s\": %.17g, \"lcm_url\": ",
                 (cfg.run_mode == AOCS_NODE_RUN_REALTIME) ? "realtime" : "lockstep", (double)cfg.exec.period_s,
                 cfg.idle_timeout_s, cfg.run_timeout_s, cfg.status_period_s);
    put_str(cfg.lcm_url);
    (void)printf(", \"budget_ns\": %llu, \"stale_timeout_ns\": %llu, \"n_wheels\": %u, \"guidance_mode\": \"%s\", ",
                 (unsigned long long)cfg.exec.budget_ns, (unsigned long long)cfg.exec.stale_timeout_ns,
                 (unsigned)cfg.exec.wheels.n, (cfg.exec.guidance.mode == AOCS_GUIDANCE_MODE_SLEW) ? "slew" : "step");
    put_lines(&cfg);
    if (clock_arg != NULL) {
        (void)fputs(", \"pil_config\": \"", stdout);
        for (uint32_t i = 0u; i < len; ++i) {
            (void)printf("%02x", (unsigned)payload[i]);
        }
        (void)putchar('"');
    }
    (void)fputs("}\n", stdout);
    return 0;
}

static int hint(const char *status_name, const char *law_name)
{
    char buf[AOCS_NODE_ERR_MAX];
    aocs_law_id_t law = AOCS_LAW_NONE;
    aocs_status_t st = AOCS_OK;
    int found = 0;
    for (int i = 0; (found == 0) && (i < (int)AOCS_STATUS_COUNT); ++i) {
        const char *name = aocs_status_name((aocs_status_t)i);
        if (strcmp(name, status_name) == 0) {
            st = (aocs_status_t)i;
            found = 1;
        }
    }
    (void)aocs_law_from_name(law_name, &law);
    (void)printf("%s\n", aocs_node_config_status_hint(st, law, buf, sizeof(buf)));
    return 0;
}

int main(int argc, char **argv)
{
    int rc = EXIT_USAGE;
    if (argc == 2) {
        rc = describe(argv[1], NULL);
    } else if ((argc == 4) && (strcmp(argv[2], "--pil-clock-hz") == 0)) {
        rc = describe(argv[1], argv[3]);
    } else if ((argc == 4) && (strcmp(argv[1], "--hint") == 0)) {
        rc = hint(argv[2], argv[3]);
    } else {
        (void)fprintf(stderr, "usage: aocs_node_config FILE [--pil-clock-hz HZ] | --hint STATUS LAW\n");
    }
    return rc;
}
