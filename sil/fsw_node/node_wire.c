/* Wire checks of fsw_node (node_wire.h). */
#include "node_wire.h"

#include <math.h>
#include <string.h>

void aocs_node_seq_reset(aocs_node_seq_t *seq)
{
    memset(seq, 0, sizeof(*seq));
}

aocs_node_seq_result_t aocs_node_seq_check(aocs_node_seq_t *seq, int64_t frame)
{
    aocs_node_seq_result_t r = AOCS_NODE_SEQ_OK;
    if (seq->have_last == 0) {
        seq->have_last = 1;
        seq->last = frame;
    } else if (frame <= seq->last) {
        seq->duplicate++;
        r = AOCS_NODE_SEQ_DUPLICATE;
    } else {
        if (frame > seq->last + 1) {
            seq->lost += (uint64_t)(frame - seq->last - 1);
            r = AOCS_NODE_SEQ_GAP;
        }
        seq->last = frame;
    }
    return r;
}

uint64_t aocs_node_seconds_to_ns(double t_s)
{
    uint64_t ns = 0u;
    if (isfinite(t_s) && (t_s > 0.0) && (t_s < 1.8e10)) {
        ns = (uint64_t)llround(t_s * 1.0e9);
    }
    return ns;
}

void aocs_node_sensors_to_input(const aocs_lcm_sensors_t *msg, uint64_t t_sensor_ns, aocs_exec_input_t *in)
{
    int i;
    memset(in, 0, sizeof(*in));
    in->tick = (uint32_t)((uint64_t)msg->tick & 0xFFFFFFFFu);
    in->t_sensor_ns = t_sensor_ns;
    if ((msg->valid & AOCS_LCM_SENSORS_T_VALID_ATTITUDE) != 0) {
        in->valid |= AOCS_EXEC_VALID_ATT;
    }
    if ((msg->valid & AOCS_LCM_SENSORS_T_VALID_RATE) != 0) {
        in->valid |= AOCS_EXEC_VALID_RATE;
    }
    if (((msg->valid & AOCS_LCM_SENSORS_T_VALID_POSITION) != 0) &&
        ((msg->valid & AOCS_LCM_SENSORS_T_VALID_VELOCITY) != 0)) {
        in->valid |= AOCS_EXEC_VALID_ORBIT;
    }
    for (i = 0; i < 4; ++i) {
        in->q_BN.q[i] = (real_t)msg->q[i];
    }
    for (i = 0; i < 3; ++i) {
        in->w_BN_B.v[i] = (real_t)msg->w[i];
        in->pos_m.v[i] = (real_t)msg->pos[i];
        in->vel_mps.v[i] = (real_t)msg->vel[i];
    }
}
