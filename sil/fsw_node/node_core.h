/*
 * The node logic of the SIL flight computer, whatever carries its messages:
 * the configuration handed to the executive, the AOCS_SENSORS payload ->
 * executive step -> actuator_cmd_t of one lockstep tick, the AOCS_COMMAND
 * payload -> executive selection, the status_t and the exit summary.
 *
 * Two callers share it, so the LCM path and the in-process path run one
 * function from the received bytes to the reply (docs/sil.md, "Transports"):
 *   - fsw_node (fsw_node.c): LCM callbacks, the loops and their timeouts;
 *   - the in-process node (direct/aocs_node_direct.c): the same calls through
 *     a C ABI from the plant's process, no LCM.
 * Host code (SIL only), no allocation: a node is one static aocs_node_core_t.
 */
#ifndef AOCS_FSW_NODE_CORE_H
#define AOCS_FSW_NODE_CORE_H

#include <stddef.h>
#include <stdint.h>

#include "aocs/executive.h"
#include "aocs_lcm_actuator_cmd_t.h"
#include "aocs_lcm_sensors_t.h"
#include "aocs_lcm_status_t.h"
#include "node_config.h"
#include "node_stats.h"
#include "node_wire.h"

typedef struct {
    aocs_node_config_t cfg;
    aocs_exec_t exec;
    aocs_exec_output_t out;       /* last executive output */
    int have_out;
    aocs_node_seq_t seq;          /* AOCS_SENSORS frame sequence */
    uint64_t frame_cmd;           /* our counters on AOCS_ACTUATOR_CMD / AOCS_STATUS (sent modulo 2^63) */
    uint64_t frame_status;
    uint64_t frame_event;         /* our counter on AOCS_EVENTS */
    uint32_t event_seq_sent;      /* seq of the last event handed out by aocs_node_core_event */
    uint64_t sensor_frames;       /* AOCS_SENSORS messages received (any content) */
    uint64_t n_foreign;
    uint64_t n_malformed;
    uint64_t n_cmd_accepted;
    uint64_t n_cmd_rejected;
    int64_t last_request;
    int32_t last_request_status;
    aocs_law_id_t nominal_law;    /* law NOMINAL returns to after STANDBY */
    aocs_exec_timer_t timer;      /* real time: the period timer (its slips count as overruns) */
    aocs_node_stats_t stats;      /* step times of the accepted steps */
    uint64_t scratch[AOCS_NODE_STATS_WINDOW];
} aocs_node_core_t;

/* What became of one AOCS_SENSORS payload. */
typedef enum {
    AOCS_NODE_RX_ACCEPTED = 0,    /* decoded, in sequence: the caller owns the message (decode_cleanup) */
    AOCS_NODE_RX_DROPPED,         /* duplicate or implausible jump (counted in seq) */
    AOCS_NODE_RX_MALFORMED,       /* counted in n_malformed */
    AOCS_NODE_RX_FOREIGN          /* counted in n_foreign */
} aocs_node_rx_t;

/* Zeroes the node (counters, sequence, statistics); then fill cfg and call aocs_node_core_configure. */
void aocs_node_core_reset(aocs_node_core_t *n);

/*
 * After cfg is read (node_config.h): the timeout ranges, the executive's clock
 * from the run mode, aocs_exec_init and the nominal law. 0, or 1 with one
 * line in err naming `name` (the file) and what was refused.
 */
int aocs_node_core_configure(aocs_node_core_t *n, const char *name, char *err, size_t err_size);

/* Counts, decodes and sequence-checks one AOCS_SENSORS payload into *msg (owned by the caller on ACCEPTED). */
aocs_node_rx_t aocs_node_core_receive(aocs_node_core_t *n, const void *data, uint32_t size,
                                      aocs_lcm_sensors_t *msg);

/*
 * Lockstep, bytes in -> reply out: aocs_node_core_receive, then for an
 * accepted frame the executive step on aocs_node_lockstep_input and the
 * actuator_cmd_t of it in *reply (tick and utime of the sample). Returns 1
 * when *reply is filled, 0 when the payload got no reply (dropped, malformed,
 * foreign). fsw_node publishes *reply; the in-process node encodes it.
 */
int aocs_node_core_lockstep(aocs_node_core_t *n, const void *data, uint32_t size, aocs_lcm_actuator_cmd_t *reply);

/* One executive step's bookkeeping: the output kept, its step time in the statistics when rc is OK. */
void aocs_node_core_record(aocs_node_core_t *n, aocs_status_t rc);

/* The actuator_cmd_t of the last step (status: the first thing that went wrong, docs/wire-contract.md). */
void aocs_node_core_actuator(aocs_node_core_t *n, aocs_status_t step_rc, int64_t tick, int64_t utime,
                             int deadline_missed, aocs_lcm_actuator_cmd_t *m);

/*
 * Applies one AOCS_COMMAND payload: returns 1 when it decoded (last_request and its status set, the
 * accepted / rejected counts moved; the caller acknowledges with a status_t), 0 when it was malformed or
 * foreign (counted).
 */
int aocs_node_core_command(aocs_node_core_t *n, const void *data, uint32_t size);

/* The status_t of the node now (utime_us: the sender's clock). */
void aocs_node_core_status(aocs_node_core_t *n, int exiting, int64_t utime_us, aocs_lcm_status_t *m);

/*
 * The next event of the executive's log not yet handed out (after each step, until it returns 0): 1 and
 * *m (event_t), 0 when there is none. fsw_node publishes each on AOCS_EVENTS; the in-process node
 * returns their bytes (aocs_direct_event), so both transports deliver the same events.
 */
int aocs_node_core_event(aocs_node_core_t *n, aocs_lcm_event_t *m);

/* Overruns reported: the executive's plus the timer's slips. */
uint64_t aocs_node_core_overruns(const aocs_node_core_t *n);

/*
 * The exit summary, one JSON object {"fsw_node": {...}} without a newline (docs/sil.md): reason, run
 * mode, law, mode, step statistics, frame and command counts, guidance. Returns snprintf's length.
 */
int aocs_node_core_report_json(aocs_node_core_t *n, const char *reason, char *buf, size_t size);

/* int64 of a uint64 counter, saturating at INT64_MAX. */
int64_t aocs_node_to_i64(uint64_t x);

#endif /* AOCS_FSW_NODE_CORE_H */
