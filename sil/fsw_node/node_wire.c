/* Wire checks of fsw_node (node_wire.h). */
#include "node_wire.h"

#include <math.h>
#include <string.h>

/* half the counter range: a difference at or above it is a frame behind (two's complement view) */
#define SEQ_BEHIND 0x8000000000000000ull

uint64_t aocs_node_add_sat(uint64_t a, uint64_t b)
{
    return (UINT64_MAX - a < b) ? UINT64_MAX : (a + b);
}

/* ---- payload decoding ----------------------------------------------------- */
aocs_node_decode_t aocs_node_decode_sensors(const void *data, uint32_t size, aocs_lcm_sensors_t *msg)
{
    aocs_node_decode_t r = AOCS_NODE_DECODE_MALFORMED;
    int used;
    if ((data == NULL) || (msg == NULL) || (size > (uint32_t)INT32_MAX)) {
        return AOCS_NODE_DECODE_MALFORMED;
    }
    used = aocs_lcm_sensors_t_decode(data, 0, (int)size, msg);
    if (used < 0) {
        r = AOCS_NODE_DECODE_MALFORMED;
    } else if (used != (int)size) {
        /* trailing bytes: not the message it claims to be */
        (void)aocs_lcm_sensors_t_decode_cleanup(msg);
        r = AOCS_NODE_DECODE_MALFORMED;
    } else if (msg->protocol_version != AOCS_LCM_SENSORS_T_PROTOCOL_VERSION) {
        (void)aocs_lcm_sensors_t_decode_cleanup(msg);
        r = AOCS_NODE_DECODE_FOREIGN;
    } else {
        r = AOCS_NODE_DECODE_OK;
    }
    return r;
}

aocs_node_decode_t aocs_node_decode_command(const void *data, uint32_t size, aocs_lcm_command_t *msg)
{
    aocs_node_decode_t r = AOCS_NODE_DECODE_MALFORMED;
    int used;
    if ((data == NULL) || (msg == NULL) || (size > (uint32_t)INT32_MAX)) {
        return AOCS_NODE_DECODE_MALFORMED;
    }
    used = aocs_lcm_command_t_decode(data, 0, (int)size, msg);
    if (used < 0) {
        r = AOCS_NODE_DECODE_MALFORMED;
    } else if (used != (int)size) {
        (void)aocs_lcm_command_t_decode_cleanup(msg);
        r = AOCS_NODE_DECODE_MALFORMED;
    } else if (msg->protocol_version != AOCS_LCM_COMMAND_T_PROTOCOL_VERSION) {
        (void)aocs_lcm_command_t_decode_cleanup(msg);
        r = AOCS_NODE_DECODE_FOREIGN;
    } else {
        r = AOCS_NODE_DECODE_OK;
    }
    return r;
}

/* ---- frame counter sequence ------------------------------------------------- */
void aocs_node_seq_reset(aocs_node_seq_t *seq)
{
    memset(seq, 0, sizeof(*seq));
}

int aocs_node_seq_accepted(aocs_node_seq_result_t r)
{
    return ((r == AOCS_NODE_SEQ_OK) || (r == AOCS_NODE_SEQ_GAP) || (r == AOCS_NODE_SEQ_RESYNC)) ? 1 : 0;
}

/* 1 when counter b is 1..W after counter a (modulo 2^64) */
static int seq_continues(uint64_t a, uint64_t b)
{
    const uint64_t d = b - a;
    return ((d >= 1u) && (d <= (uint64_t)AOCS_NODE_SEQ_WINDOW)) ? 1 : 0;
}

aocs_node_seq_result_t aocs_node_seq_check(aocs_node_seq_t *seq, int64_t frame)
{
    /* the two's complement bits of the counter: every difference below is modulo 2^64 */
    const uint64_t f = (uint64_t)frame;
    aocs_node_seq_result_t r = AOCS_NODE_SEQ_OK;
    if (seq->have_last == 0) {
        seq->have_last = 1;
        seq->last = f;
        seq->cand_run = 0u;
    } else if (seq_continues(seq->last, f) != 0) {
        const uint64_t d = f - seq->last;
        if (d > 1u) {
            seq->lost = aocs_node_add_sat(seq->lost, d - 1u);
            r = AOCS_NODE_SEQ_GAP;
        }
        seq->last = f;
        seq->cand_run = 0u;
    } else {
        /* dropped; a resynchronisation candidate */
        const uint64_t d = f - seq->last;
        if ((seq->cand_run > 0u) && (seq_continues(seq->cand_last, f) != 0)) {
            seq->cand_run += 1u;
        } else {
            seq->cand_run = 1u;
        }
        seq->cand_last = f;
        if (seq->cand_run >= AOCS_NODE_SEQ_RESYNC_FRAMES) {
            seq->last = f;
            seq->cand_run = 0u;
            seq->resyncs = aocs_node_add_sat(seq->resyncs, 1u);
            r = AOCS_NODE_SEQ_RESYNC;
        } else if ((d == 0u) || (d >= SEQ_BEHIND)) {
            seq->duplicate = aocs_node_add_sat(seq->duplicate, 1u);
            r = AOCS_NODE_SEQ_DUPLICATE;
        } else {
            seq->jump = aocs_node_add_sat(seq->jump, 1u);
            r = AOCS_NODE_SEQ_JUMP;
        }
    }
    return r;
}

/* ---- conversions --------------------------------------------------------------- */
uint64_t aocs_node_seconds_to_ns(double t_s)
{
    uint64_t ns = 0u;
    if (isfinite(t_s) && (t_s > 0.0) && (t_s < AOCS_NODE_SECONDS_MAX)) {
        /* x < 1.8e19 < 2^64: the floor is exactly representable in uint64_t */
        const double x = t_s * 1.0e9;
        const double r = floor(x);
        ns = (uint64_t)r;
        if ((x - r) >= 0.5) {
            ns += 1u; /* half away from zero, as llround and the PIL bridge's mirror */
        }
    }
    return ns;
}

uint64_t aocs_node_meas_time_ns(uint64_t t_sensor_ns, double t_s, double t_meas_s)
{
    const uint64_t t = aocs_node_seconds_to_ns(t_s);
    const uint64_t m = aocs_node_seconds_to_ns(t_meas_s);
    uint64_t r = 0u;
    if ((m == 0u) || ((t == 0u) && (t_sensor_ns != 0u))) {
        r = 0u; /* no time: the measurement's own, or (real time) the sample's, so its age is unknown */
    } else if (m <= t) {
        const uint64_t age = t - m;
        r = (age < t_sensor_ns) ? (t_sensor_ns - age) : 0u;
    } else {
        r = aocs_node_add_sat(t_sensor_ns, m - t); /* measured after the sample's time: left to the estimator */
    }
    return r;
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
    if ((msg->valid & AOCS_LCM_SENSORS_T_VALID_STAR_TRACKER) != 0) {
        in->valid |= AOCS_EXEC_VALID_ST;
    }
    if ((msg->valid & AOCS_LCM_SENSORS_T_VALID_GYRO) != 0) {
        in->valid |= AOCS_EXEC_VALID_GYRO;
    }
    if ((msg->valid & AOCS_LCM_SENSORS_T_VALID_MAGNETOMETER) != 0) {
        in->valid |= AOCS_EXEC_VALID_MAG;
    }
    for (i = 0; i < 4; ++i) {
        in->q_BN.q[i] = (real_t)msg->q[i];
    }
    for (i = 0; i < 3; ++i) {
        in->w_BN_B.v[i] = (real_t)msg->w[i];
        in->pos_m.v[i] = (real_t)msg->pos[i];
        in->vel_mps.v[i] = (real_t)msg->vel[i];
    }
    /* star tracker (the last sample taken; a new one when VALID_ST is set) and gyro */
    for (i = 0; i < 4; ++i) {
        in->st_q_SN.q[i] = (real_t)msg->st_q[i];
    }
    in->st_t_meas_ns = aocs_node_meas_time_ns(t_sensor_ns, msg->t_s, msg->st_t_meas_s);
    for (i = 0; i < 3; ++i) {
        in->gyro_w_B.v[i] = (real_t)msg->gyro_w[i];
        in->mag_B_T.v[i] = (real_t)msg->mag_b_t[i]; /* magnetometer (VALID_MAG), unchecked */
    }
    /* tachometers: a wheel the message does not measure (flag off, beyond n_wheels) reads NaN, so an
     * executive with a wheel array gives a zero wheel command rather than act on a made-up speed */
    for (i = 0; i < (int)AOCS_WHEELS_MAX; ++i) {
        int usable = ((msg->valid & AOCS_LCM_SENSORS_T_VALID_WHEELS) != 0) && (i < (int)msg->n_wheels) &&
                     (i < AOCS_LCM_SENSORS_T_MAX_WHEELS);
        in->wheel_speed_radps[i] = usable ? (real_t)msg->wheel_speed[i] : (real_t)NAN;
    }
}

void aocs_node_lockstep_input(const aocs_lcm_sensors_t *msg, aocs_exec_input_t *in)
{
    aocs_node_sensors_to_input(msg, aocs_node_seconds_to_ns(msg->t_s), in);
}

/* ---- the estimate ---------------------------------------------------------------- */
/* the wire's est_p is the covariance's upper triangle of estimate.h (a compile-time check) */
typedef char aocs_node_est_p_matches[((sizeof(((aocs_lcm_actuator_cmd_t *)NULL)->est_p) / sizeof(double)) ==
                                      (size_t)AOCS_EST_P_UPPER_COUNT) ? 1 : -1];

void aocs_node_estimate_to_cmd(const aocs_det_output_t *est, uint32_t estimator, aocs_lcm_actuator_cmd_t *m)
{
    int i;
    if ((est == NULL) || (m == NULL)) {
        return;
    }
    m->estimator = (estimator > (uint32_t)INT8_MAX) ? INT8_MAX : (int8_t)estimator;
    m->est_status = (int32_t)est->status;
    for (i = 0; i < 4; ++i) {
        m->q_est[i] = (double)est->q_BN.q[i];
    }
    for (i = 0; i < 3; ++i) {
        m->w_est[i] = (double)est->w_BN_B.v[i];
        m->bias_est[i] = (double)est->bias_B_radps.v[i];
    }
    for (i = 0; i < (int)AOCS_EST_P_UPPER_COUNT; ++i) {
        m->est_p[i] = (double)est->p_upper[i];
    }
    m->st_status = (int32_t)est->st_status;
    m->n_st_used = (int64_t)est->n_st_used;
    m->n_st_gated = (int64_t)est->n_st_gated;
    m->n_st_hostile = (int64_t)est->n_st_hostile;
    m->n_est_restarts = (int64_t)est->n_restarts;
}

/* ---- the momentum-management stage ------------------------------------------------ */
/* the wire's thruster array is the stage's (a compile-time check) */
typedef char aocs_node_thrusters_match[((sizeof(((aocs_lcm_actuator_cmd_t *)NULL)->thruster_on_s) / sizeof(double)) ==
                                        (size_t)AOCS_MOM_THRUSTERS_MAX) ? 1 : -1];

void aocs_node_momentum_to_cmd(const aocs_mom_output_t *mom, const aocs_mom_config_t *cfg, aocs_lcm_actuator_cmd_t *m)
{
    int i;
    if ((mom == NULL) || (cfg == NULL) || (m == NULL)) {
        return;
    }
    m->mom_policy = (cfg->policy > (uint32_t)INT8_MAX) ? INT8_MAX : (int8_t)cfg->policy;
    m->mom_status = (int32_t)mom->status;
    m->n_thrusters = 0;
    if ((cfg->policy == (uint32_t)AOCS_MOM_THRUSTERS) && (cfg->thr_count <= AOCS_MOM_THRUSTERS_MAX)) {
        m->n_thrusters = (int8_t)cfg->thr_count;
    }
    for (i = 0; i < (int)AOCS_MOM_THRUSTERS_MAX; ++i) {
        m->thruster_on_s[i] = (double)mom->thruster_on_s[i];
    }
    for (i = 0; i < 3; ++i) {
        m->dipole_am2[i] = (double)mom->dipole_Am2.v[i];
        m->u_unload[i] = (double)mom->u_unload_B_Nm.v[i];
        m->h_wheels[i] = (double)mom->h_wheels_B_Nms.v[i];
        m->dh[i] = (double)mom->dh_B_Nms.v[i];
    }
    m->unloading = (mom->unloading != 0) ? 1 : 0;
    m->n_unload_events = (int64_t)mom->n_events;
    m->thruster_latch_closed = (int8_t)(mom->latch_closed_mask & ((1u << AOCS_MOM_LATCH_BRANCHES) - 1u));
}

/* ---- commands -------------------------------------------------------------------- */
aocs_status_t aocs_node_command_apply(aocs_exec_t *exec, aocs_law_id_t *nominal_law, const aocs_lcm_command_t *c)
{
    aocs_law_id_t law;
    aocs_exec_target_t target;
    const aocs_exec_target_t *tp = NULL;
    aocs_status_t st;
    int i;

    if ((exec == NULL) || (nominal_law == NULL) || (c == NULL)) {
        return AOCS_ERR_NULL_ARG;
    }
    law = exec->law;
    if (c->law_id != AOCS_LCM_COMMAND_T_LAW_KEEP) {
        if ((c->law_id < 0) || (c->law_id >= (int16_t)AOCS_LAW_COUNT)) {
            return AOCS_ERR_UNKNOWN_LAW;
        }
        law = (aocs_law_id_t)c->law_id;
    }
    if (c->mode == AOCS_LCM_COMMAND_T_MODE_STANDBY) {
        law = AOCS_LAW_NONE;
    } else if (c->mode == AOCS_LCM_COMMAND_T_MODE_NOMINAL) {
        if (law == AOCS_LAW_NONE) {
            law = *nominal_law;
        }
        if (law == AOCS_LAW_NONE) {
            return AOCS_ERR_MODE_INVALID; /* no law known to be nominal with */
        }
    } else if (c->mode != AOCS_LCM_COMMAND_T_MODE_KEEP) {
        /* SAFE is entered by the executive's fault logic only */
        return AOCS_ERR_MODE_INVALID;
    } else {
        /* MODE_KEEP: the law (if any) decides */
    }
    if (c->set_target != 0) {
        for (i = 0; i < 4; ++i) {
            target.qd_DN.q[i] = (real_t)c->qd[i];
        }
        for (i = 0; i < 3; ++i) {
            target.wd_B.v[i] = (real_t)c->wd[i];
            target.wd_dot_B.v[i] = AOCS_R(0.0);
        }
        tp = &target;
    }
    if ((c->law_id == AOCS_LCM_COMMAND_T_LAW_KEEP) && (c->mode == AOCS_LCM_COMMAND_T_MODE_KEEP) && (tp == NULL)) {
        return AOCS_OK; /* nothing asked */
    }
    st = aocs_exec_select(exec, law, tp);
    if ((st == AOCS_OK) && (exec->law != AOCS_LAW_NONE)) {
        *nominal_law = exec->law;
    }
    return st;
}

/* ---- real-time epoch --------------------------------------------------------------- */
static uint64_t abs_diff(uint64_t a, uint64_t b)
{
    return (a >= b) ? (a - b) : (b - a);
}

int aocs_node_epoch_update(aocs_node_epoch_t *ep, uint64_t rx_ns, uint64_t t_sim_ns, uint64_t tol_ns)
{
    int set = 0;
    /* sim time 0 on the HAL clock; a sample from "before the clock started" maps to 0 */
    const uint64_t e = (rx_ns > t_sim_ns) ? (rx_ns - t_sim_ns) : 0u;
    if (ep == NULL) {
        return 0;
    }
    if (ep->have == 0) {
        ep->have = 1;
        ep->t0_ns = e;
        ep->cand_run = 0u;
        set = 1;
    } else if (abs_diff(e, ep->t0_ns) <= tol_ns) {
        ep->cand_run = 0u;
    } else {
        if ((ep->cand_run > 0u) && (abs_diff(e, ep->cand_ns) <= tol_ns)) {
            ep->cand_run += 1u;
        } else {
            ep->cand_run = 1u;
        }
        ep->cand_ns = e;
        if (ep->cand_run >= AOCS_NODE_SEQ_RESYNC_FRAMES) {
            ep->t0_ns = e;
            ep->cand_run = 0u;
            set = 1;
        }
    }
    return set;
}

void aocs_node_event_to_msg(const aocs_event_t *e, uint32_t lost, aocs_lcm_event_t *m)
{
    memset(m, 0, sizeof(*m));
    m->protocol_version = AOCS_LCM_EVENT_T_PROTOCOL_VERSION;
    m->seq = (int64_t)e->seq;
    m->t_s = (double)e->t_ns * 1e-9;
    m->id = (int16_t)e->id;
    m->severity = (int8_t)e->severity;
    m->unit_kind = (int8_t)e->unit_kind;
    m->unit = (int16_t)((e->unit < INT16_MIN) ? INT16_MIN : ((e->unit > INT16_MAX) ? INT16_MAX : e->unit));
    m->value = (double)e->value;
    m->threshold = (double)e->threshold;
    m->n_lost = (int64_t)lost;
}
