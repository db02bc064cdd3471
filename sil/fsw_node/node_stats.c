/* Step-time statistics of fsw_node (node_stats.h). */
#include "node_stats.h"

#include <stdlib.h>
#include <string.h>

void aocs_node_stats_reset(aocs_node_stats_t *st)
{
    st->count = 0u;
    st->max = 0u;
}

void aocs_node_stats_add(aocs_node_stats_t *st, uint64_t value)
{
    st->ring[st->count % AOCS_NODE_STATS_WINDOW] = value;
    st->count++;
    if (value > st->max) {
        st->max = value;
    }
}

static int cmp_u64(const void *a, const void *b)
{
    uint64_t x = *(const uint64_t *)a;
    uint64_t y = *(const uint64_t *)b;
    return (x > y) - (x < y);
}

/* nearest rank: the smallest value with at least p percent of the samples at or below it */
static uint64_t rank(const uint64_t *sorted, uint64_t n, unsigned percent)
{
    uint64_t r = (n * percent + 99u) / 100u;
    if (r == 0u) {
        r = 1u;
    }
    return sorted[r - 1u];
}

aocs_node_stats_summary_t aocs_node_stats_summary(const aocs_node_stats_t *st, uint64_t *scratch)
{
    aocs_node_stats_summary_t s;
    uint64_t n = (st->count < AOCS_NODE_STATS_WINDOW) ? st->count : (uint64_t)AOCS_NODE_STATS_WINDOW;
    memset(&s, 0, sizeof(s));
    s.n = n;
    s.max = st->max;
    if (n > 0u) {
        memcpy(scratch, st->ring, (size_t)n * sizeof(uint64_t));
        qsort(scratch, (size_t)n, sizeof(uint64_t), cmp_u64);
        s.median = rank(scratch, n, 50u);
        s.p99 = rank(scratch, n, 99u);
    }
    return s;
}
