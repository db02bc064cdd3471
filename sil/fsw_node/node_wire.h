/*
 * Wire checks of fsw_node (docs/wire-contract.md, "Frame checks" and "Frame
 * acceptance"): payload decoding, the frame counter sequence (lost,
 * duplicated and implausibly far frames), the conversion of an aocs_lcm
 * sensors_t into an executive input, the mapping of a command_t onto
 * aocs_exec_select, and the real-time epoch of a rotating target.
 * Host code (SIL only); no signed overflow anywhere: counters are unsigned
 * and saturate, frame counters are compared modulo 2^64.
 */
#ifndef AOCS_FSW_NODE_WIRE_H
#define AOCS_FSW_NODE_WIRE_H

#include <stdint.h>

#include "aocs/executive.h"
#include "aocs_lcm_actuator_cmd_t.h"
#include "aocs_lcm_command_t.h"
#include "aocs_lcm_event_t.h"
#include "aocs_lcm_sensors_t.h"

/* ---- payload decoding ----------------------------------------------------- */
typedef enum {
    AOCS_NODE_DECODE_OK = 0,   /* decoded, protocol version matches: the caller owns msg (decode_cleanup) */
    AOCS_NODE_DECODE_MALFORMED,/* wrong fingerprint, truncated, trailing bytes, or larger than INT32_MAX */
    AOCS_NODE_DECODE_FOREIGN   /* decoded, but another protocol_version */
} aocs_node_decode_t;

/* Decodes one AOCS_SENSORS payload into *msg; on anything but OK nothing needs cleaning up. Total. */
aocs_node_decode_t aocs_node_decode_sensors(const void *data, uint32_t size, aocs_lcm_sensors_t *msg);

/* Decodes one AOCS_COMMAND payload into *msg; on anything but OK nothing needs cleaning up. Total. */
aocs_node_decode_t aocs_node_decode_command(const void *data, uint32_t size, aocs_lcm_command_t *msg);

/* ---- frame counter sequence (AOCS_SENSORS) ---------------------------------- */
/*
 * With W = AOCS_NODE_SEQ_WINDOW and K = AOCS_NODE_SEQ_RESYNC_FRAMES, d = frame - last
 * (modulo 2^64, last = the last accepted counter):
 *   - the first frame is accepted;
 *   - 1 <= d <= W: accepted, d - 1 frames counted lost;
 *   - d = 0 or frame behind last (a replay, d >= 2^63): dropped, duplicate;
 *   - W < d < 2^63 (implausibly far ahead): dropped, jump.
 * A dropped frame never moves the reference on its own word: K consecutive
 * dropped frames whose counters each advance by 1..W over the one before
 * resynchronise: the K-th is accepted (result RESYNC, no frames counted lost)
 * and is the new reference. An accepted frame clears the candidates.
 */
#define AOCS_NODE_SEQ_WINDOW 1024u
#define AOCS_NODE_SEQ_RESYNC_FRAMES 3u

typedef struct {
    int have_last;      /* a frame was accepted before */
    uint64_t last;      /* counter of the last accepted frame (the int64 read modulo 2^64) */
    uint64_t lost;      /* counters skipped (gaps); saturates */
    uint64_t duplicate; /* frames not ahead of the last accepted one, dropped; saturates */
    uint64_t jump;      /* frames more than W ahead, dropped; saturates */
    uint64_t resyncs;   /* resynchronisations; saturates */
    uint32_t cand_run;  /* consecutive dropped frames, each 1..W after the one before (< K) */
    uint64_t cand_last; /* counter of the last of them */
} aocs_node_seq_t;

typedef enum {
    AOCS_NODE_SEQ_OK = 0,      /* next expected frame (or the first): process */
    AOCS_NODE_SEQ_GAP,         /* process; frames before it were lost */
    AOCS_NODE_SEQ_RESYNC,      /* process; the K-th consistent frame after a jump: new reference */
    AOCS_NODE_SEQ_DUPLICATE,   /* not newer than the last accepted frame: drop */
    AOCS_NODE_SEQ_JUMP         /* implausibly far ahead: drop */
} aocs_node_seq_result_t;

void aocs_node_seq_reset(aocs_node_seq_t *seq);
aocs_node_seq_result_t aocs_node_seq_check(aocs_node_seq_t *seq, int64_t frame);
/* 1 for OK, GAP and RESYNC (the frame is processed), 0 for DUPLICATE and JUMP. Total. */
int aocs_node_seq_accepted(aocs_node_seq_result_t r);

/* ---- sensors_t -> executive input ------------------------------------------- */
/*
 * Validity bits map VALID_ATTITUDE -> AOCS_EXEC_VALID_ATT, VALID_RATE ->
 * AOCS_EXEC_VALID_RATE, POSITION and VELOCITY both set -> AOCS_EXEC_VALID_ORBIT,
 * VALID_STAR_TRACKER -> AOCS_EXEC_VALID_ST, VALID_GYRO -> AOCS_EXEC_VALID_GYRO,
 * VALID_MAGNETOMETER -> AOCS_EXEC_VALID_MAG (mag_b_t -> mag_B_T).
 * tick is the int64 modulo 2^32. t_sensor_ns is given by the caller
 * (lockstep: from t_s; realtime: reception time on the HAL clock); the star
 * tracker's st_t_meas_ns is aocs_node_meas_time_ns(t_sensor_ns, t_s,
 * st_t_meas_s), on the same clock. Values are passed through unchecked (NaN
 * included): the executive decides.
 */
void aocs_node_sensors_to_input(const aocs_lcm_sensors_t *msg, uint64_t t_sensor_ns, aocs_exec_input_t *in);

/* Lockstep: the executive input of a sample, t_sensor_ns = aocs_node_seconds_to_ns(t_s) (what fsw_node steps
 * on, and what the host tool aocs_node_input prints for a log). */
void aocs_node_lockstep_input(const aocs_lcm_sensors_t *msg, aocs_exec_input_t *in);

/*
 * A sensor's time of measurement t_meas_s (sim time, s) on the clock of
 * t_sensor_ns, the sample's sensor time: t_sensor_ns - (ns(t_s) - ns(t_meas_s)),
 * ns() = aocs_node_seconds_to_ns, formed in uint64_t without wrapping (a
 * time before the clock's 0 is 0, one beyond 2^64 - 1 ns is UINT64_MAX).
 * Lockstep, where t_sensor_ns = ns(t_s), that is ns(t_meas_s) exactly: the
 * measurement time converted as t_s is. 0 ("no time") when t_meas_s is out
 * of the range of t_s (NaN, Inf, <= 0, >= AOCS_NODE_SECONDS_MAX) and, when
 * t_sensor_ns is not ns(t_s) (real time), when t_s is: the age is then
 * unknown. Total.
 */
uint64_t aocs_node_meas_time_ns(uint64_t t_sensor_ns, double t_s, double t_meas_s);

/*
 * Sim time in s -> ns for the executive: round half away from zero of
 * t_s * 1e9 for 0 < t_s < AOCS_NODE_SECONDS_MAX, else 0 (negative, NaN,
 * Inf, or too large: an out-of-range time is "no time", which the frame
 * acceptance treats as not advancing). No llround: 1.8e19 ns < 2^64 but
 * > INT64_MAX, so the result is formed in uint64_t from floor(). Total.
 */
#define AOCS_NODE_SECONDS_MAX 1.8e10
uint64_t aocs_node_seconds_to_ns(double t_s);

/* ---- the estimate -> actuator_cmd_t ----------------------------------------------- */
/*
 * The attitude-determination stage's estimate of one step (aocs_exec_output_t.estimate)
 * into the estimate fields of *m (telemetry, docs/wire-contract.md): estimator = the
 * selected row of estimation/determination.def (the executive's
 * cfg.determination.estimator; above INT8_MAX reads INT8_MAX), est_status, q_est,
 * w_est, bias_est, est_p (the covariance's upper triangle as estimate.h orders it),
 * st_status and the star-tracker and restart counts. The other fields of *m are left
 * as they are. Total (nothing on NULL).
 */
void aocs_node_estimate_to_cmd(const aocs_det_output_t *est, uint32_t estimator, aocs_lcm_actuator_cmd_t *m);

/* ---- the momentum-management stage -> actuator_cmd_t ------------------------------ */
/*
 * The stage's output of one step (aocs_exec_output_t.mom) and its configuration into the
 * momentum fields of *m (protocol version 4, docs/wire-contract.md): mom_policy (the
 * momentum.def row, above INT8_MAX reads INT8_MAX), mom_status, n_thrusters (mom.thr_count
 * with the thrusters policy, else 0), thruster_on_s, dipole_am2, u_unload, h_wheels, dh,
 * unloading, n_unload_events. The other fields of *m are left as they are. Total.
 */
void aocs_node_momentum_to_cmd(const aocs_mom_output_t *mom, const aocs_mom_config_t *cfg, aocs_lcm_actuator_cmd_t *m);

/* ---- the event log -> event_t --------------------------------------------------------- */
/*
 * One event of the flight software's log (aocs/fdir/event_log.h) into *m (protocol version 5,
 * docs/wire-contract.md; frame and utime 0, the sender's): seq, t_s (t_ns / 1e9), id, severity, unit_kind, unit (clamped to int16),
 * value, threshold, n_lost (events the ring overwrote before this one was read). Total.
 */
void aocs_node_event_to_msg(const aocs_event_t *e, uint32_t lost, aocs_lcm_event_t *m);

/* ---- command_t -> aocs_exec_select ------------------------------------------- */
/*
 * Applies one decoded command (docs/wire-contract.md, command_t): STANDBY
 * selects law none; NOMINAL re-selects the given law, else the current one,
 * else *nominal_law; SAFE or an unknown mode is refused
 * (AOCS_ERR_MODE_INVALID); a law id out of range is AOCS_ERR_UNKNOWN_LAW.
 * Nothing asked (LAW_KEEP, MODE_KEEP, no target) is AOCS_OK and changes
 * nothing. On success *nominal_law follows a selected law.
 */
aocs_status_t aocs_node_command_apply(aocs_exec_t *exec, aocs_law_id_t *nominal_law, const aocs_lcm_command_t *c);

/* ---- real-time epoch of a rotating target ------------------------------------ */
/*
 * Real time: sim time 0 of the plant mapped onto the HAL clock, e = rx time -
 * t_s of a sample. The first sample sets it; later samples whose e differs
 * from it by more than tol_ns are candidates, and only K =
 * AOCS_NODE_SEQ_RESYNC_FRAMES consecutive candidates within tol_ns of each other
 * move it (to the last one's e): one forged t_s cannot shift the target.
 */
typedef struct {
    int have;           /* epoch set */
    uint64_t t0_ns;     /* the epoch */
    uint32_t cand_run;  /* consecutive disagreeing samples agreeing with each other */
    uint64_t cand_ns;   /* e of the last of them */
} aocs_node_epoch_t;

/* Feeds one sample (rx_ns, its t_s as ns); returns 1 when t0_ns was (re)set. Total. */
int aocs_node_epoch_update(aocs_node_epoch_t *ep, uint64_t rx_ns, uint64_t t_sim_ns, uint64_t tol_ns);

/* Saturating uint64 addition (counters). Total. */
uint64_t aocs_node_add_sat(uint64_t a, uint64_t b);

#endif /* AOCS_FSW_NODE_WIRE_H */
