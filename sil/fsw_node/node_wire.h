/*
 * Wire checks of fsw_node (docs/wire-contract.md, "Frame checks"): frame
 * counter sequence (lost / duplicated frames) and the conversion of an
 * aocs_lcm sensors_t into an executive input. Host code (SIL only).
 */
#ifndef AOCS_FSW_NODE_WIRE_H
#define AOCS_FSW_NODE_WIRE_H

#include <stdint.h>

#include "aocs/executive.h"
#include "aocs_lcm_sensors_t.h"

typedef struct {
    int have_last;     /* a frame was accepted before */
    int64_t last;      /* counter of the last accepted frame */
    uint64_t lost;     /* counters skipped (gaps) */
    uint64_t duplicate;/* frames with counter <= last, dropped */
} aocs_node_seq_t;

typedef enum {
    AOCS_NODE_SEQ_OK = 0,      /* next expected frame (or the first) */
    AOCS_NODE_SEQ_GAP,         /* accepted, frames before it were lost */
    AOCS_NODE_SEQ_DUPLICATE    /* not newer than the last accepted frame: drop */
} aocs_node_seq_result_t;

void aocs_node_seq_reset(aocs_node_seq_t *seq);
aocs_node_seq_result_t aocs_node_seq_check(aocs_node_seq_t *seq, int64_t frame);

/*
 * sensors_t -> executive input. Validity bits map VALID_ATTITUDE ->
 * AOCS_EXEC_VALID_ATT, VALID_RATE -> AOCS_EXEC_VALID_RATE, POSITION and
 * VELOCITY both set -> AOCS_EXEC_VALID_ORBIT. t_sensor_ns is given by the
 * caller (lockstep: from t_s; realtime: reception time on the HAL clock).
 * Values are passed through unchecked (NaN included): the executive decides.
 */
void aocs_node_sensors_to_input(const aocs_lcm_sensors_t *msg, uint64_t t_sensor_ns, aocs_exec_input_t *in);

/* sim time in s -> ns for the executive (negative or non-finite -> 0) */
uint64_t aocs_node_seconds_to_ns(double t_s);

#endif /* AOCS_FSW_NODE_WIRE_H */
