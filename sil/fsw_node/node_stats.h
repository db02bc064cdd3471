/*
 * Step-time statistics of fsw_node: the last AOCS_NODE_STATS_WINDOW step
 * times in a fixed ring (no allocation), median / p99 by nearest rank over
 * that window, max over the whole run. Host code (SIL only).
 */
#ifndef AOCS_FSW_NODE_STATS_H
#define AOCS_FSW_NODE_STATS_H

#include <stdint.h>

#define AOCS_NODE_STATS_WINDOW 65536u

typedef struct {
    uint64_t ring[AOCS_NODE_STATS_WINDOW];
    uint64_t count;   /* samples recorded since reset */
    uint64_t max;     /* over the whole run */
} aocs_node_stats_t;

typedef struct {
    uint64_t n;       /* samples in the window */
    uint64_t median;
    uint64_t p99;
    uint64_t max;
} aocs_node_stats_summary_t;

void aocs_node_stats_reset(aocs_node_stats_t *st);
void aocs_node_stats_add(aocs_node_stats_t *st, uint64_t value);
/* nearest-rank percentiles of the window (0 when empty); scratch holds a sorted copy */
aocs_node_stats_summary_t aocs_node_stats_summary(const aocs_node_stats_t *st, uint64_t *scratch);

#endif /* AOCS_FSW_NODE_STATS_H */
