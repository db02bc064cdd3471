/*
 * The flight software's event log (issue 26; docs/spec.md 5.15.1): the ids,
 * severities and unit kinds of aocs/fdir/events.def, and a fixed-size ring of
 * the events raised, each with a sequence number (1, 2, ... never reused),
 * the sensor time of the step that raised it, its unit, the test statistic
 * and the threshold it crossed. Counts per severity since init. No dynamic
 * memory; a reader (the SIL node, a telemetry task) takes the events after
 * the last sequence number it has seen (aocs_evlog_next); an event the ring
 * overwrote before it was read is counted in `lost` of the reader's view.
 *
 *   aocs_evlog_init(&log);
 *   aocs_evlog_raise(&log, AOCS_EVT_WHEEL_ISOLATED, t_ns, 1, value, threshold);
 *   seq = 0; while (aocs_evlog_next(&log, seq, &e) == AOCS_OK) { send(e); seq = e.seq; }
 */
#ifndef AOCS_FDIR_EVENT_LOG_H
#define AOCS_FDIR_EVENT_LOG_H

#include <stdint.h>

#include "aocs/types.h"
#include "aocs/fdir/events.def"

#define AOCS_FDIR_SEV_ENUM_ROW(ID, NAME) AOCS_SEV_##ID,
typedef enum { AOCS_FDIR_SEVERITY_ROWS(AOCS_FDIR_SEV_ENUM_ROW) AOCS_SEV_COUNT } aocs_evt_severity_t;

#define AOCS_FDIR_UNIT_ENUM_ROW(ID, NAME) AOCS_UNIT_##ID,
typedef enum { AOCS_FDIR_UNIT_KIND_ROWS(AOCS_FDIR_UNIT_ENUM_ROW) AOCS_UNIT_KIND_COUNT } aocs_evt_unit_kind_t;

/* ids from 1 in row order (0: no event) */
#define AOCS_FDIR_EVT_ENUM_ROW(ID, NAME, SEV, UNIT, MEANING) AOCS_EVT_##ID,
typedef enum { AOCS_EVT_NONE = 0, AOCS_FDIR_EVENT_ROWS(AOCS_FDIR_EVT_ENUM_ROW) AOCS_EVT_END } aocs_evt_id_t;
#define AOCS_EVT_COUNT ((uint32_t)AOCS_EVT_END - 1u) /* rows of the table */

/* events kept for readers; a reader polling every step needs one slot per event of a step (a step raises
 * at most a handful: detection + isolation of one unit, a mode change) */
#define AOCS_EVLOG_LEN 32u

/* unit index of an event whose kind has one unit or none */
#define AOCS_EVT_UNIT_NONE (-1)

typedef struct {
    uint32_t seq;                 /* 1, 2, ...: the event's number since init */
    uint64_t t_ns;                /* sensor time of the step that raised it, ns */
    aocs_evt_id_t id;
    aocs_evt_severity_t severity; /* from the table */
    aocs_evt_unit_kind_t unit_kind; /* from the table */
    int32_t unit;                 /* index of the unit (wheel 0..), AOCS_EVT_UNIT_NONE */
    real_t value;                 /* the test statistic (its unit: the event's meaning) */
    real_t threshold;             /* the threshold it crossed */
} aocs_event_t;

typedef struct {
    aocs_event_t ring[AOCS_EVLOG_LEN];
    uint32_t seq_last;            /* seq of the newest event, 0 = none yet */
    uint32_t count_by_severity[AOCS_SEV_COUNT]; /* since init, saturating */
} aocs_evlog_t;

/* Name of an id ("wheel_isolated"), NULL out of range. Total. */
const char *aocs_evt_name(aocs_evt_id_t id);
/* Severity / unit kind of an id from the table; INFO / NONE out of range. Total. */
aocs_evt_severity_t aocs_evt_severity(aocs_evt_id_t id);
aocs_evt_unit_kind_t aocs_evt_unit_kind(aocs_evt_id_t id);
/* Names of a severity ("warning") and a unit kind ("wheel"); "unknown" out of range. Total. */
const char *aocs_evt_severity_name(aocs_evt_severity_t sev);
const char *aocs_evt_unit_kind_name(aocs_evt_unit_kind_t kind);

/* Empty log. No-op on NULL. */
void aocs_evlog_init(aocs_evlog_t *log);

/*
 * Appends event id at sensor time t_ns (seq = the previous + 1, severity and
 * unit kind from the table; a non-finite value or threshold is stored as the
 * largest real, so the log never holds a NaN). Returns the seq given, 0 when
 * log is NULL, id out of range or the sequence is exhausted (UINT32_MAX).
 */
uint32_t aocs_evlog_raise(aocs_evlog_t *log, aocs_evt_id_t id, uint64_t t_ns, int32_t unit, real_t value,
                          real_t threshold);

/*
 * The oldest event still held whose seq is greater than after_seq: AOCS_OK and
 * *e; AOCS_ERR_INPUT_MISSING when there is none; AOCS_ERR_NULL_ARG. When
 * events after after_seq were overwritten, *lost (may be NULL) is how many.
 */
aocs_status_t aocs_evlog_next(const aocs_evlog_t *log, uint32_t after_seq, aocs_event_t *e, uint32_t *lost);

/* Events raised since init (= seq of the newest), and those of severity >= sev. 0 on NULL. Total. */
uint32_t aocs_evlog_count(const aocs_evlog_t *log);
uint32_t aocs_evlog_count_at_least(const aocs_evlog_t *log, aocs_evt_severity_t sev);

#endif /* AOCS_FDIR_EVENT_LOG_H */
