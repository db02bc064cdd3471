/*
 * fsw_node configuration: a flat `key = value` text file written by the
 * runner from a scenario (format and keys: docs/wire-contract.md,
 * "fsw_node configuration"). Host code (SIL only), not firmware.
 */
#ifndef AOCS_FSW_NODE_CONFIG_H
#define AOCS_FSW_NODE_CONFIG_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "aocs/config_registry.h"
#include "aocs/executive.h"

typedef enum {
    AOCS_NODE_RUN_LOCKSTEP = 0, /* each AOCS_SENSORS message is one tick */
    AOCS_NODE_RUN_REALTIME = 1  /* absolute-deadline loop at the control rate */
} aocs_node_run_mode_t;

#define AOCS_NODE_URL_MAX 256u
#define AOCS_NODE_ERR_MAX 512u
/* The node's own keys (mode, timeouts, lcm_url): not flight software configuration. */
#define AOCS_NODE_OWN_KEYS 6u
/* Rows of the configuration registry the node can track (a static check in node_config.c). */
#define AOCS_NODE_CONFIG_ROWS_MAX 128u
/* One slot per key a file can give: the node's own, then one per registry row and wheel. */
#define AOCS_NODE_KEY_SLOTS (AOCS_NODE_OWN_KEYS + (AOCS_NODE_CONFIG_ROWS_MAX * (size_t)AOCS_WHEELS_MAX))

typedef struct {
    aocs_exec_config_t exec;      /* executive config (law, gains, limits, period) */
    aocs_node_run_mode_t run_mode;
    double idle_timeout_s;        /* lockstep: exit after this long without sensor frames, > 0 */
    double run_timeout_s;         /* whole run limit, s; 0 = none */
    double status_period_s;       /* heartbeat period on AOCS_STATUS, > 0 */
    double wait_spin_us;          /* lockstep over udpm: a wait polls this long before it sleeps, us (node_udpm.h) */
    char lcm_url[AOCS_NODE_URL_MAX]; /* empty = LCM default (udpm, ttl=0) */
    unsigned line_of[AOCS_NODE_KEY_SLOTS]; /* the file's line of each key given (0 = not given), by slot */
    aocs_gain_table_id_t table_of[AOCS_NODE_CONFIG_ROWS_MAX]; /* the gain table a TABLE row was given */
} aocs_node_config_t;

/*
 * The key of a slot of line_of: a registry field (*ref, return 1), or one of
 * the node's own keys (*own_key, return 2); 0 for a slot of no key.
 */
int aocs_node_config_slot(size_t slot, aocs_config_ref_t *ref, const char **own_key);

/*
 * Fills defaults (docs/wire-contract.md), then reads `path`. Returns 0 on
 * success; otherwise non-zero with a message naming the file, line and key
 * in err (size AOCS_NODE_ERR_MAX).
 */
int aocs_node_config_load(const char *path, aocs_node_config_t *cfg, char *err, size_t err_size);

/*
 * aocs_node_config_load's reading of an open stream (a file, or the configuration text of the in-process
 * node, sil/fsw_node/direct): `path` names it in the messages. The stream is not closed.
 */
int aocs_node_config_read(FILE *f, const char *path, aocs_node_config_t *cfg, char *err, size_t err_size);

/*
 * Parses one `key = value` line into cfg (exposed for the loader and tests).
 * Returns 0, or non-zero with a message in err.
 */
int aocs_node_config_set(aocs_node_config_t *cfg, const char *key, const char *value, char *err,
                         size_t err_size);

#endif /* AOCS_FSW_NODE_CONFIG_H */
