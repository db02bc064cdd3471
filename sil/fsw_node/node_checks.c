/* Range checks of fsw_node's own settings (node_checks.h). */
#include "node_checks.h"

#include <math.h>
#include <stdio.h>

/* 1 when lo <= x <= hi (NaN is never in range) */
static int in_range(double x, double lo, double hi)
{
    return ((x >= lo) && (x <= hi)) ? 1 : 0;
}

int aocs_node_timeouts_check(const aocs_node_config_t *cfg, char *err, size_t err_size)
{
    const char *key = NULL;
    double value = 0.0;
    double lo = 0.0;
    double hi = 0.0;
    const char *extra = "";
    const char *unit = "s";
    if (cfg == NULL) {
        return 1;
    }
    if (in_range(cfg->idle_timeout_s, AOCS_NODE_IDLE_TIMEOUT_MIN_S, AOCS_NODE_IDLE_TIMEOUT_MAX_S) == 0) {
        key = "idle_timeout_s";
        value = cfg->idle_timeout_s;
        lo = AOCS_NODE_IDLE_TIMEOUT_MIN_S;
        hi = AOCS_NODE_IDLE_TIMEOUT_MAX_S;
    } else if ((in_range(cfg->run_timeout_s, 0.0, 0.0) == 0) &&
               (in_range(cfg->run_timeout_s, AOCS_NODE_RUN_TIMEOUT_MIN_S, AOCS_NODE_RUN_TIMEOUT_MAX_S) == 0)) {
        key = "run_timeout_s";
        value = cfg->run_timeout_s;
        lo = AOCS_NODE_RUN_TIMEOUT_MIN_S;
        hi = AOCS_NODE_RUN_TIMEOUT_MAX_S;
        extra = " or 0 (no limit)";
    } else if (in_range(cfg->status_period_s, AOCS_NODE_STATUS_PERIOD_MIN_S, AOCS_NODE_STATUS_PERIOD_MAX_S) == 0) {
        key = "status_period_s";
        value = cfg->status_period_s;
        lo = AOCS_NODE_STATUS_PERIOD_MIN_S;
        hi = AOCS_NODE_STATUS_PERIOD_MAX_S;
    } else if (in_range(cfg->wait_spin_us, 0.0, AOCS_NODE_WAIT_SPIN_MAX_US) == 0) {
        key = "wait_spin_us";
        value = cfg->wait_spin_us;
        lo = 0.0;
        hi = AOCS_NODE_WAIT_SPIN_MAX_US;
        unit = "us";
    } else {
        key = NULL;
    }
    if (key == NULL) {
        return 0;
    }
    if ((err != NULL) && (err_size > 0u)) {
        (void)snprintf(err, err_size, "key '%s': %g %s is outside [%g, %g] %s%s", key, value, unit, lo, hi, unit,
                       extra);
    }
    return 1;
}
