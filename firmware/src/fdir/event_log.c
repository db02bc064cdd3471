/*
 * The event log (aocs/fdir/event_log.h; docs/spec.md 5.15.1): the table of
 * aocs/fdir/events.def as data, and the fixed-size ring with its sequence
 * numbers and counts per severity.
 */
#include <stddef.h>
#include <string.h>

#include "aocs/fdir/event_log.h"

typedef struct {
    const char *name;
    aocs_evt_severity_t severity;
    aocs_evt_unit_kind_t unit_kind;
} evt_info_t;

#define EVT_INFO_ROW(ID, NAME, SEV, UNIT, MEANING) {NAME, AOCS_SEV_##SEV, AOCS_UNIT_##UNIT},
static const evt_info_t evt_info[AOCS_EVT_COUNT] = {AOCS_FDIR_EVENT_ROWS(EVT_INFO_ROW)};

#define EVT_NAME_ROW(ID, NAME) NAME,

static int evt_id_valid(aocs_evt_id_t id)
{
    return (((int)id >= 1) && ((uint32_t)id <= AOCS_EVT_COUNT)) ? 1 : 0;
}

const char *aocs_evt_name(aocs_evt_id_t id)
{
    return (evt_id_valid(id) != 0) ? evt_info[(uint32_t)id - 1u].name : NULL;
}

aocs_evt_severity_t aocs_evt_severity(aocs_evt_id_t id)
{
    return (evt_id_valid(id) != 0) ? evt_info[(uint32_t)id - 1u].severity : AOCS_SEV_INFO;
}

aocs_evt_unit_kind_t aocs_evt_unit_kind(aocs_evt_id_t id)
{
    return (evt_id_valid(id) != 0) ? evt_info[(uint32_t)id - 1u].unit_kind : AOCS_UNIT_NONE;
}

const char *aocs_evt_severity_name(aocs_evt_severity_t sev)
{
    static const char *const sev_names[AOCS_SEV_COUNT] = {AOCS_FDIR_SEVERITY_ROWS(EVT_NAME_ROW)};
    return (((int)sev >= 0) && (sev < AOCS_SEV_COUNT)) ? sev_names[sev] : "unknown";
}

const char *aocs_evt_unit_kind_name(aocs_evt_unit_kind_t kind)
{
    static const char *const unit_kind_names[AOCS_UNIT_KIND_COUNT] = {AOCS_FDIR_UNIT_KIND_ROWS(EVT_NAME_ROW)};
    return (((int)kind >= 0) && (kind < AOCS_UNIT_KIND_COUNT)) ? unit_kind_names[kind] : "unknown";
}

void aocs_evlog_init(aocs_evlog_t *log)
{
    if (log != NULL) {
        (void)memset(log, 0, sizeof(*log));
    }
}

static real_t evlog_finite(real_t x)
{
    return AOCS_IS_FINITE(x) ? x : AOCS_REAL_MAX;
}

uint32_t aocs_evlog_raise(aocs_evlog_t *log, aocs_evt_id_t id, uint64_t t_ns, int32_t unit, real_t value,
                          real_t threshold)
{
    uint32_t seq = 0u;
    if ((log != NULL) && (evt_id_valid(id) != 0) && (log->seq_last < UINT32_MAX)) {
        aocs_event_t *e;
        seq = log->seq_last + 1u;
        e = &log->ring[seq % AOCS_EVLOG_LEN];
        e->seq = seq;
        e->t_ns = t_ns;
        e->id = id;
        e->severity = aocs_evt_severity(id);
        e->unit_kind = aocs_evt_unit_kind(id);
        e->unit = unit;
        e->value = evlog_finite(value);
        e->threshold = evlog_finite(threshold);
        log->seq_last = seq;
        if (log->count_by_severity[e->severity] < UINT32_MAX) {
            log->count_by_severity[e->severity] += 1u;
        }
    }
    return seq;
}

aocs_status_t aocs_evlog_next(const aocs_evlog_t *log, uint32_t after_seq, aocs_event_t *e, uint32_t *lost)
{
    aocs_status_t st = AOCS_ERR_INPUT_MISSING;
    if (lost != NULL) {
        *lost = 0u;
    }
    if ((log == NULL) || (e == NULL)) {
        st = AOCS_ERR_NULL_ARG;
    } else if (after_seq < log->seq_last) {
        /* the oldest still held: seq_last - LEN + 1 (or 1) */
        const uint32_t oldest = (log->seq_last > AOCS_EVLOG_LEN) ? (log->seq_last - AOCS_EVLOG_LEN + 1u) : 1u;
        uint32_t want = after_seq + 1u;
        if (want < oldest) {
            if (lost != NULL) {
                *lost = oldest - want;
            }
            want = oldest;
        }
        *e = log->ring[want % AOCS_EVLOG_LEN];
        st = AOCS_OK;
    } else {
        /* nothing newer */
    }
    return st;
}

uint32_t aocs_evlog_count(const aocs_evlog_t *log)
{
    return (log != NULL) ? log->seq_last : 0u;
}

uint32_t aocs_evlog_count_at_least(const aocs_evlog_t *log, aocs_evt_severity_t sev)
{
    uint32_t n = 0u;
    if (log != NULL) {
        for (int s = (int)sev; (s >= 0) && (s < (int)AOCS_SEV_COUNT); ++s) {
            const uint32_t c = log->count_by_severity[s];
            n = ((UINT32_MAX - n) < c) ? UINT32_MAX : (n + c);
        }
    }
    return n;
}
