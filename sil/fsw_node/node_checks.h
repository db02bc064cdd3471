/*
 * Range checks of fsw_node's own settings, after the configuration file is
 * parsed (node_config.c checks count, finiteness and sign; the executive
 * checks its part in aocs_exec_init). Host code (SIL only).
 */
#ifndef AOCS_FSW_NODE_CHECKS_H
#define AOCS_FSW_NODE_CHECKS_H

#include <stddef.h>

#include "node_config.h"

/*
 * Plausible ranges of the node's timeouts, s (docs/wire-contract.md). The
 * node turns them into ns (node_wire.h aocs_node_seconds_to_ns): outside
 * these ranges a value would round to 0 ns or overflow the conversion, and
 * the node would end at once. Lower bounds: the node's loop waits in steps
 * of 1 ms, so a timeout below 10 ms (a heartbeat below 1 ms) is not one it
 * can keep. Upper bounds: an idle lockstep node waiting more than a day, a
 * run longer than 1e7 s (116 days) or a heartbeat rarer than once an hour is
 * a typo, not a setting.
 */
#define AOCS_NODE_IDLE_TIMEOUT_MIN_S 0.01
#define AOCS_NODE_IDLE_TIMEOUT_MAX_S 86400.0
#define AOCS_NODE_RUN_TIMEOUT_MIN_S 0.01   /* 0 = no limit is allowed as well */
#define AOCS_NODE_RUN_TIMEOUT_MAX_S 1.0e7
#define AOCS_NODE_STATUS_PERIOD_MIN_S 0.001
#define AOCS_NODE_STATUS_PERIOD_MAX_S 3600.0
/* wait_spin_us: up to 10 ms of polling per wait (a lockstep reply comes in tens of us; more is a typo) */
#define AOCS_NODE_WAIT_SPIN_MAX_US 10000.0

/*
 * 0 when idle_timeout_s, run_timeout_s, status_period_s and wait_spin_us are in range;
 * otherwise 1 with one line in err naming the key, its value and the range.
 */
int aocs_node_timeouts_check(const aocs_node_config_t *cfg, char *err, size_t err_size);

#endif /* AOCS_FSW_NODE_CHECKS_H */
