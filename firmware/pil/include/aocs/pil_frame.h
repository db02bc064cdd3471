/*
 * Processor-in-the-loop link: the versioned request/reply frames between the
 * host bridge (sil/pil, aocs_pil.bridge) and the flight image on the target
 * (firmware/port/cortex-m/pil_main.c). Portable C: no I/O, no allocation;
 * the same code is unit-tested on the host (tests/unit/test_pil_frame.c) and
 * linked into the image. docs/pil.md describes the protocol.
 *
 * Frame (all integers little-endian, reals IEEE-754 binary64 on the wire in
 * both precisions):
 *
 *   offset  size  field
 *   0       4     magic   AOCS_PIL_MAGIC (the bytes 'A' 'P' 'I' 'L')
 *   4       1     version AOCS_PIL_VERSION
 *   5       1     type    aocs_pil_type_t
 *   6       2     length  payload bytes, <= AOCS_PIL_PAYLOAD_MAX
 *   8       4     seq     request: sender's counter; reply: the request's seq
 *   12      n     payload (layout per type below)
 *   12+n    4     crc     CRC-32/ISO-HDLC (zlib's crc32) of bytes 0 .. 12+n-1
 *
 * A real_t is widened to binary64 when encoded and a binary64 is converted to
 * real_t when decoded, exactly as the SIL node converts the LCM doubles
 * (sil/fsw_node/node_wire.c), so the float image sees the same inputs as a
 * float build of the node would.
 */
#ifndef AOCS_PIL_FRAME_H
#define AOCS_PIL_FRAME_H

#include <stdint.h>

#include "aocs/config_registry.h"
#include "aocs/executive.h"
#include "aocs/types.h"

#define AOCS_PIL_MAGIC 0x4C495041UL   /* "APIL" read as a little-endian uint32 */
#define AOCS_PIL_VERSION 5U   /* 5: the thruster latch valves (STEP_REPLY thruster_latch_closed); 4: magnetometer, momentum management; 3: star tracker, gyro, estimate; 2: the wheel array (CONFIG fields 65-67 and 100-147,
                                * tachometers, wheel torques) */
#define AOCS_PIL_HEADER_BYTES 12U
#define AOCS_PIL_CRC_BYTES 4U
#define AOCS_PIL_PAYLOAD_MAX 1024U
#define AOCS_PIL_FRAME_MAX (AOCS_PIL_HEADER_BYTES + AOCS_PIL_PAYLOAD_MAX + AOCS_PIL_CRC_BYTES)

/*
 * QEMU runs the image with `-icount shift=AOCS_PIL_ICOUNT_SHIFT`: one guest
 * instruction advances the virtual clock by 2^7 ns, so the 25 MHz SysTick of
 * the MPS2 boards (40 ns) advances 3.2 ticks per instruction and a tick
 * difference converts to an exact instruction count (docs/pil.md).
 */
#define AOCS_PIL_ICOUNT_SHIFT 7U

/* Longest gain-table design name in a CONFIG frame (without the NUL). */
#define AOCS_PIL_TABLE_NAME_MAX AOCS_CONFIG_TABLE_NAME_MAX

/* Target ids of the HELLO frame. */
#define AOCS_PIL_TARGET_HOST 0U
#define AOCS_PIL_TARGET_CORTEX_M4F 1U
#define AOCS_PIL_TARGET_CORTEX_M7 2U

/* Payload sizes of the fixed-layout frames (the sums of their rows below, which the encoders check). */
#define AOCS_PIL_HELLO_BYTES 28U
#define AOCS_PIL_STEP_BYTES 256U
#define AOCS_PIL_STEP_REPLY_BYTES 736U
#define AOCS_PIL_SELECT_BYTES 64U
#define AOCS_PIL_ACK_BYTES 36U
#define AOCS_PIL_BYE_REPLY_BYTES 16U
#define AOCS_PIL_ERROR_BYTES 16U

typedef enum {
    AOCS_PIL_T_HELLO = 1,        /* image -> host, once at boot */
    AOCS_PIL_T_CONFIG = 2,       /* host -> image: executive configuration (field list) */
    AOCS_PIL_T_CONFIG_ACK = 3,   /* image -> host: aocs_pil_ack_t */
    AOCS_PIL_T_STEP = 4,         /* host -> image: one sensor sample */
    AOCS_PIL_T_STEP_REPLY = 5,   /* image -> host: aocs_pil_step_reply_t */
    AOCS_PIL_T_SELECT = 6,       /* host -> image: run-time law / target command */
    AOCS_PIL_T_SELECT_ACK = 7,   /* image -> host: aocs_pil_ack_t */
    AOCS_PIL_T_BYE = 8,          /* host -> image: end (empty); image -> host: aocs_pil_bye_t, then exit 0 */
    AOCS_PIL_T_ERROR = 9         /* image -> host: aocs_pil_error_t, a frame it could not use */
} aocs_pil_type_t;

/* Codec and link errors (the ERROR frame carries one). */
typedef enum {
    AOCS_PIL_OK = 0,
    AOCS_PIL_ERR_NULL_ARG = 1,
    AOCS_PIL_ERR_MAGIC = 2,      /* the first 4 bytes are not AOCS_PIL_MAGIC */
    AOCS_PIL_ERR_VERSION = 3,    /* another protocol version */
    AOCS_PIL_ERR_LENGTH = 4,     /* payload length above AOCS_PIL_PAYLOAD_MAX or frame shorter than stated */
    AOCS_PIL_ERR_CRC = 5,        /* CRC mismatch: the frame was corrupted */
    AOCS_PIL_ERR_TYPE = 6,       /* unknown type, or a type the receiver does not accept */
    AOCS_PIL_ERR_PAYLOAD = 7,    /* payload size wrong for the type, or truncated field list */
    AOCS_PIL_ERR_BUFFER = 8,     /* output buffer too small */
    AOCS_PIL_ERR_FIELD = 9,      /* CONFIG: unknown field id, wrong value count or out-of-range value */
    AOCS_PIL_ERR_STATE = 10,     /* STEP or SELECT before a successful CONFIG */
    AOCS_PIL_ERR_COUNT
} aocs_pil_err_t;

/*
 * CONFIG fields: every field of the configuration registry
 * (aocs/config_registry.h: config_fields.def and the laws' rows of laws.def),
 * by its PIL id (AOCS_PIL_CFG_<NAME>; per wheel AOCS_PIL_CFG_WHEEL_BASE + i *
 * AOCS_PIL_WHEEL_STRIDE + index). The node-only keys (mode, timeouts,
 * lcm_url) stay in the bridge. Entry layout: u8 field, u8 count, then count
 * binary64 values (a REALS or INERTIA field, 9 row-major for an inertia),
 * one uint64 (an integer field: U32, U64, NS in ns, LAW / ENUM by value; the
 * BUDGET field is the instruction budget override of the image), or count
 * bytes (the design name of a gain table). Fields not given keep
 * aocs_exec_config_default(). The ids are wire values: never renumber
 * (tests/unit/test_registry.c pins them).
 */

/* Decoded header (magic and CRC are checked, not kept). */
typedef struct {
    uint8_t version;
    uint8_t type;      /* aocs_pil_type_t value as received */
    uint16_t length;   /* payload bytes */
    uint32_t seq;
} aocs_pil_header_t;

/* HELLO: what the image is and whether its instruction counter is exact. */
typedef struct {
    uint32_t target;          /* AOCS_PIL_TARGET_* */
    uint32_t real_bytes;      /* sizeof(real_t): 4 (float) or 8 (double) */
    uint32_t icount_shift;    /* the shift the image converts ticks with */
    uint32_t calib_ok;        /* 1 when the calibration loop measured exactly */
    uint32_t calib_measured;  /* instructions measured for the calibration difference */
    uint32_t calib_expected;  /* instructions that difference executes by construction */
    uint32_t overhead;        /* instructions of an empty measurement, subtracted from every count */
} aocs_pil_hello_t;

/* STEP_REPLY: the executive output plus the PIL measurement of the step. */
typedef struct {
    uint32_t tick;            /* tick of the sample */
    aocs_status_t step_status;/* return value of aocs_exec_step */
    aocs_law_id_t law;        /* out.law */
    aocs_exec_mode_t mode;    /* out.mode */
    aocs_status_t law_status;
    aocs_status_t input_status;
    aocs_vec3_t u_cmd;
    aocs_vec3_t u_unsat;
    uint32_t saturated;       /* out.saturated != 0 */
    uint32_t overrun;         /* instructions > budget */
    uint32_t exact;           /* 1 when the count is exact (no SysTick wrap inside the window) */
    uint32_t instructions;    /* aocs_exec_step, whole call */
    uint32_t law_instructions;/* the executive's own window (guidance + law + saturation) */
    uint32_t budget;          /* instruction budget of this step's law on this target */
    aocs_exec_counters_t counters; /* steps .. select_rejected (step_time_max_ns not sent) */
    uint32_t pil_overruns;    /* steps over the instruction budget so far */
    aocs_law_id_t exec_law;   /* selected law after the step */
    aocs_exec_mode_t exec_mode;
    /* the wheel array (all zero without one), as fsw_node publishes them in actuator_cmd_t */
    real_t u_wheels_nm[AOCS_WHEELS_MAX]; /* out.wheels.u_s_nm */
    real_t wheel_scale;       /* out.wheels.scale */
    uint32_t wheel_limited;   /* torque_limited_mask | speed_limited_mask << 8 */
    aocs_status_t wheels_status;
    aocs_vec3_t h_total_B_Nms;/* out.momentum.h_total_B_Nms */
    real_t speed_margin;      /* out.momentum.speed_margin */
    /* the attitude-determination stage's estimate, as fsw_node publishes it in actuator_cmd_t (valid not sent) */
    uint32_t estimator;       /* the executive's cfg.determination.estimator (estimation/determination.def) */
    aocs_det_output_t estimate; /* out.estimate */
    /* the momentum-management stage, as fsw_node publishes it in actuator_cmd_t (node_wire.c) */
    uint32_t mom_policy;      /* the executive's cfg.momentum.policy (momentum/momentum.def) */
    uint32_t n_thrusters;     /* cfg.momentum.thr_count with the thrusters policy, else 0 */
    uint32_t unloading;       /* mom.unloading != 0 */
    aocs_mom_output_t mom;    /* aocs_exec_momentum() after the step */
} aocs_pil_step_reply_t;

/* SELECT: the run-time command (aocs_exec_select). */
typedef struct {
    aocs_law_id_t law;
    uint32_t has_target;      /* 1: target below is given, 0: keep the current one */
    aocs_exec_target_t target;/* wd_dot_B is not sent (zero), as fsw_node does */
} aocs_pil_select_t;

/* CONFIG_ACK and SELECT_ACK. */
typedef struct {
    aocs_pil_err_t pil_err;   /* AOCS_PIL_OK, or why the field list was refused */
    aocs_status_t status;     /* aocs_exec_init / aocs_exec_select / gain-table status */
    uint32_t field;           /* CONFIG: the offending field id, 0 if none */
    aocs_law_id_t exec_law;   /* selected law afterwards */
    aocs_exec_mode_t exec_mode;
    uint32_t select_accepted;
    uint32_t select_rejected;
    uint32_t budget;          /* instruction budget of the selected law */
    uint32_t reserved;
} aocs_pil_ack_t;

/* BYE reply: end-of-run figures of the image. */
typedef struct {
    uint32_t stack_bytes;     /* main stack high-water mark since reset */
    uint32_t steps;           /* STEP frames answered */
    uint32_t instructions_max;/* largest whole-step count */
    uint32_t frame_errors;    /* ERROR frames sent */
} aocs_pil_bye_t;

/* ERROR: a frame the image could not use (it stays in its loop). */
typedef struct {
    aocs_pil_err_t pil_err;
    uint32_t type;            /* type byte received (0 if the header was unusable) */
    uint32_t seq;             /* seq received (0 if unusable) */
    uint32_t detail;          /* e.g. the received length or field id */
} aocs_pil_error_t;

/*
 * The fixed payloads as rows, in wire order: X(NAME, KIND, MEMBER). NAME is
 * the field's name on the host (aocs_pil.frame, the registry JSON), MEMBER
 * the member of the payload's struct it travels in, KIND its C type and its
 * wire form (AOCS_PIL_WIRE_<KIND>: wire type, value count):
 *
 *   KIND      member                    wire
 *   u32       uint32_t                  u32
 *   u64       uint64_t                  u64
 *   status    aocs_status_t             i32 (two's complement)
 *   law       aocs_law_id_t             i32
 *   mode      aocs_exec_mode_t          i32
 *   pil_err   aocs_pil_err_t            i32
 *   real      real_t                    f64 (binary64 in both precisions)
 *   vec3      aocs_vec3_t               3 f64
 *   quat      aocs_quat_t               4 f64, scalar last
 *   wheels    real_t[AOCS_WHEELS_MAX]   AOCS_WHEELS_MAX f64
 *   cov       real_t[AOCS_EST_P_UPPER_COUNT]  AOCS_EST_P_UPPER_COUNT f64 (a covariance's upper triangle, estimate.h)
 *   thrusters real_t[AOCS_MOM_THRUSTERS_MAX] AOCS_MOM_THRUSTERS_MAX f64 (thruster on-times, momentum.h)
 *   counters  aocs_exec_counters_t      the AOCS_PIL_COUNTER_ROWS (step_time_max_ns is not sent)
 *
 * pil_frame.c expands each payload's rows into its encoder and decoder (a
 * decoded member that is not on the wire reads 0), tools/registry writes
 * them into the registry JSON, and the Python codec (aocs_pil.frame) derives
 * its struct formats, sizes and field names from that. The rows are the
 * wire: never reorder or retype one without a new AOCS_PIL_VERSION.
 */
#define AOCS_PIL_WIRE_u32 "u32", 1U
#define AOCS_PIL_WIRE_u64 "u64", 1U
#define AOCS_PIL_WIRE_status "i32", 1U
#define AOCS_PIL_WIRE_law "i32", 1U
#define AOCS_PIL_WIRE_mode "i32", 1U
#define AOCS_PIL_WIRE_pil_err "i32", 1U
#define AOCS_PIL_WIRE_real "f64", 1U
#define AOCS_PIL_WIRE_vec3 "f64", 3U
#define AOCS_PIL_WIRE_quat "f64", 4U
#define AOCS_PIL_WIRE_wheels "f64", AOCS_WHEELS_MAX
#define AOCS_PIL_WIRE_cov "f64", AOCS_EST_P_UPPER_COUNT
#define AOCS_PIL_WIRE_thrusters "f64", AOCS_MOM_THRUSTERS_MAX
#define AOCS_PIL_WIRE_counters "u32", AOCS_PIL_COUNTERS

/* The executive counters of a STEP_REPLY (aocs_exec_counters_t). */
#define AOCS_PIL_COUNTERS 10U
#define AOCS_PIL_COUNTER_ROWS(X)                     \
    X(steps, u32, steps)                             \
    X(invalid, u32, invalid)                         \
    X(stale, u32, stale)                             \
    X(missing, u32, missing)                         \
    X(law_error, u32, law_error)                     \
    X(overrun, u32, overrun)                         \
    X(mode_transitions, u32, mode_transitions)       \
    X(saturated, u32, saturated)                     \
    X(select_accepted, u32, select_accepted)         \
    X(select_rejected, u32, select_rejected)

#define AOCS_PIL_HELLO_ROWS(X)                       \
    X(target, u32, target)                           \
    X(real_bytes, u32, real_bytes)                   \
    X(icount_shift, u32, icount_shift)               \
    X(calib_ok, u32, calib_ok)                       \
    X(calib_measured, u32, calib_measured)           \
    X(calib_expected, u32, calib_expected)           \
    X(overhead, u32, overhead)

/* STEP: the executive input (tachometers: NaN for a wheel the sensor message does not measure; the star
 * tracker's last sample, new when valid has AOCS_EXEC_VALID_ST, and its time of measurement on the clock of
 * t_sensor_ns; the gyro's rate) */
#define AOCS_PIL_STEP_ROWS(X)                        \
    X(tick, u32, tick)                               \
    X(t_sensor_ns, u64, t_sensor_ns)                 \
    X(valid, u32, valid)                             \
    X(q, quat, q_BN)                                 \
    X(w, vec3, w_BN_B)                               \
    X(pos, vec3, pos_m)                              \
    X(vel, vec3, vel_mps)                            \
    X(wheel_speed, wheels, wheel_speed_radps)        \
    X(st_q, quat, st_q_SN)                           \
    X(st_t_meas_ns, u64, st_t_meas_ns)               \
    X(gyro_w, vec3, gyro_w_B)                        \
    X(mag_b_t, vec3, mag_B_T)

#define AOCS_PIL_STEP_REPLY_ROWS(X)                  \
    X(tick, u32, tick)                               \
    X(step_status, status, step_status)              \
    X(law, law, law)                                 \
    X(mode, mode, mode)                              \
    X(law_status, status, law_status)                \
    X(input_status, status, input_status)            \
    X(u_cmd, vec3, u_cmd)                            \
    X(u_unsat, vec3, u_unsat)                        \
    X(saturated, u32, saturated)                     \
    X(overrun, u32, overrun)                         \
    X(exact, u32, exact)                             \
    X(instructions, u32, instructions)               \
    X(law_instructions, u32, law_instructions)       \
    X(budget, u32, budget)                           \
    X(counters, counters, counters)                  \
    X(pil_overruns, u32, pil_overruns)               \
    X(exec_law, law, exec_law)                       \
    X(exec_mode, mode, exec_mode)                    \
    X(u_wheels, wheels, u_wheels_nm)                 \
    X(wheel_scale, real, wheel_scale)                \
    X(wheel_limited, u32, wheel_limited)             \
    X(wheel_status, status, wheels_status)           \
    X(h_total, vec3, h_total_B_Nms)                  \
    X(speed_margin, real, speed_margin)              \
    X(estimator, u32, estimator)                     \
    X(est_status, status, estimate.status)           \
    X(q_est, quat, estimate.q_BN)                    \
    X(w_est, vec3, estimate.w_BN_B)                  \
    X(bias_est, vec3, estimate.bias_B_radps)         \
    X(est_p, cov, estimate.p_upper)                  \
    X(st_status, status, estimate.st_status)         \
    X(n_st_used, u32, estimate.n_st_used)            \
    X(n_st_gated, u32, estimate.n_st_gated)          \
    X(n_st_hostile, u32, estimate.n_st_hostile)      \
    X(n_est_restarts, u32, estimate.n_restarts)      \
    X(mom_policy, u32, mom_policy)                   \
    X(mom_status, status, mom.status)                \
    X(n_thrusters, u32, n_thrusters)                 \
    X(thruster_on_s, thrusters, mom.thruster_on_s)   \
    X(dipole_am2, vec3, mom.dipole_Am2)              \
    X(u_unload, vec3, mom.u_unload_B_Nm)             \
    X(h_wheels, vec3, mom.h_wheels_B_Nms)            \
    X(dh, vec3, mom.dh_B_Nms)                        \
    X(unloading, u32, unloading)                     \
    X(n_unload_events, u32, mom.n_events)            \
    X(thruster_latch_closed, u32, mom.latch_closed_mask)

/* SELECT: target.wd_dot_B is not sent (it decodes as zero, as fsw_node sets it) */
#define AOCS_PIL_SELECT_ROWS(X)                      \
    X(law, law, law)                                 \
    X(has_target, u32, has_target)                   \
    X(qd, quat, target.qd_DN)                        \
    X(wd, vec3, target.wd_B)

#define AOCS_PIL_ACK_ROWS(X)                         \
    X(pil_err, pil_err, pil_err)                     \
    X(status, status, status)                        \
    X(field, u32, field)                             \
    X(exec_law, law, exec_law)                       \
    X(exec_mode, mode, exec_mode)                    \
    X(select_accepted, u32, select_accepted)         \
    X(select_rejected, u32, select_rejected)         \
    X(budget, u32, budget)                           \
    X(reserved, u32, reserved)

#define AOCS_PIL_BYE_REPLY_ROWS(X)                   \
    X(stack_bytes, u32, stack_bytes)                 \
    X(steps, u32, steps)                             \
    X(instructions_max, u32, instructions_max)       \
    X(frame_errors, u32, frame_errors)

#define AOCS_PIL_ERROR_ROWS(X)                       \
    X(pil_err, pil_err, pil_err)                     \
    X(type, u32, type)                               \
    X(seq, u32, seq)                                 \
    X(detail, u32, detail)

/*
 * Every fixed payload: X(NAME, FN, TYPE, ROWS, BYTES): aocs_pil_<FN>_encode
 * and aocs_pil_<FN>_decode (declared below) code a TYPE as ROWS, BYTES long.
 */
#define AOCS_PIL_PAYLOAD_ROWS(X)                                                                        \
    X(HELLO, hello, aocs_pil_hello_t, AOCS_PIL_HELLO_ROWS, AOCS_PIL_HELLO_BYTES)                        \
    X(STEP, step, aocs_exec_input_t, AOCS_PIL_STEP_ROWS, AOCS_PIL_STEP_BYTES)                           \
    X(STEP_REPLY, step_reply, aocs_pil_step_reply_t, AOCS_PIL_STEP_REPLY_ROWS, AOCS_PIL_STEP_REPLY_BYTES) \
    X(SELECT, select, aocs_pil_select_t, AOCS_PIL_SELECT_ROWS, AOCS_PIL_SELECT_BYTES)                   \
    X(ACK, ack, aocs_pil_ack_t, AOCS_PIL_ACK_ROWS, AOCS_PIL_ACK_BYTES)                                  \
    X(BYE_REPLY, bye, aocs_pil_bye_t, AOCS_PIL_BYE_REPLY_ROWS, AOCS_PIL_BYE_REPLY_BYTES)                \
    X(ERROR, error, aocs_pil_error_t, AOCS_PIL_ERROR_ROWS, AOCS_PIL_ERROR_BYTES)

/* CRC-32/ISO-HDLC (reflected 0x04C11DB7, init and final XOR 0xFFFFFFFF). Total (0 for NULL). */
uint32_t aocs_pil_crc32(const uint8_t *data, uint32_t len);

/*
 * Writes header + payload + CRC into out (cap bytes); *frame_len = total.
 * AOCS_PIL_ERR_NULL_ARG, AOCS_PIL_ERR_LENGTH (len > AOCS_PIL_PAYLOAD_MAX),
 * AOCS_PIL_ERR_BUFFER (cap too small). payload may be NULL when len == 0.
 */
aocs_pil_err_t aocs_pil_frame_encode(aocs_pil_type_t type, uint32_t seq, const uint8_t *payload, uint32_t len,
                                     uint8_t *out, uint32_t cap, uint32_t *frame_len);

/*
 * Decodes and checks the first AOCS_PIL_HEADER_BYTES of a frame: magic,
 * version, length <= AOCS_PIL_PAYLOAD_MAX (the type is not judged here).
 */
aocs_pil_err_t aocs_pil_header_decode(const uint8_t *buf, uint32_t len, aocs_pil_header_t *hdr);

/*
 * Checks a whole frame of len bytes: header as above, len equal to
 * header + payload + CRC, CRC. On success *hdr is filled and the payload
 * starts at buf + AOCS_PIL_HEADER_BYTES.
 */
aocs_pil_err_t aocs_pil_frame_check(const uint8_t *buf, uint32_t len, aocs_pil_header_t *hdr);

/* ---- payloads, from their rows (AOCS_PIL_PAYLOAD_ROWS): encode writes exactly AOCS_PIL_<X>_BYTES, decode
 * requires exactly that many ---- */
aocs_pil_err_t aocs_pil_hello_encode(const aocs_pil_hello_t *h, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_hello_decode(const uint8_t *p, uint32_t len, aocs_pil_hello_t *h);

/* STEP <-> executive input (tick, t_sensor_ns, valid flags, q, w, pos, vel, the AOCS_WHEELS_MAX tachometer
 * speeds: NaN for a wheel the sensor message does not measure, as fsw_node reads them; the star tracker's
 * st_q_SN and st_t_meas_ns, the gyro's gyro_w_B). */
aocs_pil_err_t aocs_pil_step_encode(const aocs_exec_input_t *in, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_step_decode(const uint8_t *p, uint32_t len, aocs_exec_input_t *in);

aocs_pil_err_t aocs_pil_step_reply_encode(const aocs_pil_step_reply_t *r, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_step_reply_decode(const uint8_t *p, uint32_t len, aocs_pil_step_reply_t *r);

aocs_pil_err_t aocs_pil_select_encode(const aocs_pil_select_t *s, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_select_decode(const uint8_t *p, uint32_t len, aocs_pil_select_t *s);

aocs_pil_err_t aocs_pil_ack_encode(const aocs_pil_ack_t *a, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_ack_decode(const uint8_t *p, uint32_t len, aocs_pil_ack_t *a);

aocs_pil_err_t aocs_pil_bye_encode(const aocs_pil_bye_t *b, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_bye_decode(const uint8_t *p, uint32_t len, aocs_pil_bye_t *b);

aocs_pil_err_t aocs_pil_error_encode(const aocs_pil_error_t *e, uint8_t *out, uint32_t cap);
aocs_pil_err_t aocs_pil_error_decode(const uint8_t *p, uint32_t len, aocs_pil_error_t *e);

/*
 * CONFIG field list writers (host side and tests): each appends one entry
 * at *pos of out (cap bytes). put_reals: count binary64 values (1..27);
 * put_u64: one integer; put_name: a gain-table design name
 * (1..AOCS_PIL_TABLE_NAME_MAX characters, NUL-terminated in name).
 * AOCS_PIL_ERR_BUFFER when it does not fit (out unchanged past *pos),
 * AOCS_PIL_ERR_FIELD for a count or name length out of range.
 */
aocs_pil_err_t aocs_pil_config_put_reals(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                         const real_t *values, uint32_t count);
aocs_pil_err_t aocs_pil_config_put_u64(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                       uint64_t value);
aocs_pil_err_t aocs_pil_config_put_name(uint8_t *out, uint32_t cap, uint32_t *pos, aocs_pil_cfg_field_t field,
                                        const char *name);

/*
 * Applies a CONFIG field list, in order, to *cfg (which the caller has
 * filled with aocs_exec_config_default) and *budget_instr (the override,
 * unchanged when the field is absent). A gain-table entry copies the
 * compiled table of that name (aocs_gain_table_find / aocs_gain_table_apply)
 * into the law's gain, as the fsw_node parser does for `<law>.table`.
 * Returns AOCS_PIL_OK; AOCS_PIL_ERR_PAYLOAD (truncated entry);
 * AOCS_PIL_ERR_FIELD with *field = the entry's id (unknown id, wrong count,
 * integer out of range, or a gain table that is unknown or of another law,
 * then *status says which: AOCS_ERR_GAIN_TABLE_UNKNOWN / _WRONG_LAW).
 * The executive's own checks are left to aocs_exec_init.
 */
aocs_pil_err_t aocs_pil_config_decode(const uint8_t *p, uint32_t len, aocs_exec_config_t *cfg,
                                      uint64_t *budget_instr, uint32_t *field, aocs_status_t *status);

/* "AOCS_PIL_ERR_CRC" etc.; "AOCS_PIL_ERR_UNKNOWN" out of range. Total. */
const char *aocs_pil_err_name(aocs_pil_err_t err);

#endif /* AOCS_PIL_FRAME_H */
